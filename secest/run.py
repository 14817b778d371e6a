"""Execute one notebook with papermill after validating its parameters.

Command line::

    python -m secest.run lee2020 -p mode fast -p seed 3 [--output out.ipynb]

Without ``--output`` the notebook is executed in place (what ``make figures``
does). Unknown parameter names are an error (papermill itself only warns).
Values are parsed as Python literals when possible (``3``, ``0.5``, ``[1, 2]``),
otherwise kept as strings.
"""

from __future__ import annotations

import argparse
import ast
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from secest.results import notebook_path, repo_root, validate_parameters

__all__ = ["KERNEL", "execute_notebook", "main"]

KERNEL = "python3"
"""Kernel name given to papermill; with JUPYTER_PREFER_ENV_PATH=1 it is the venv's."""


def execute_notebook(
    key: str, parameters: Mapping[str, Any] | None = None, output: str | Path | None = None
) -> Path:
    """Validate ``parameters`` and execute ``notebooks/<key>.ipynb`` with papermill.

    Parameters
    ----------
    key : paper key.
    parameters : values injected after the ``parameters`` cell.
    output : output notebook path; the input notebook itself when omitted.

    Returns
    -------
    Path of the executed notebook.
    """
    import papermill

    params = dict(parameters or {})
    validate_parameters(key, params)
    source = notebook_path(key)
    target = Path(output) if output is not None else source
    os.environ["JUPYTER_PREFER_ENV_PATH"] = "1"
    papermill.execute_notebook(
        str(source),
        str(target),
        parameters=params,
        kernel_name=KERNEL,
        cwd=str(repo_root()),
        progress_bar=False,
    )
    return target


def _literal(text: str) -> Any:
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


def main(argv: list[str] | None = None) -> None:
    """Command-line entry point (see the module docstring)."""
    parser = argparse.ArgumentParser(prog="python -m secest.run", description=__doc__)
    parser.add_argument("key", help="paper key, e.g. lee2020")
    parser.add_argument("-p", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"))
    parser.add_argument("--output", default=None, help="output notebook (default: in place)")
    args = parser.parse_args(argv)
    params = {name: _literal(value) for name, value in args.p}
    execute_notebook(args.key, params, args.output)


if __name__ == "__main__":
    main()
