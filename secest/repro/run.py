"""Execute one notebook with papermill after checking its parameters.

Command line::

    python -m secest.repro.run lee2020 -p gamma_ex 3.0 -p T_ex 60   # -> build/run/lee2020/
    python -m secest.repro.run ding2020 --list                       # every parameter, its domain, tag
    python -m secest.repro.run lee2020 --in-place                    # what `make figures` does

Every ``-p NAME VALUE`` is parsed by the declared type of NAME (booleans accept
true/false, yes/no, 1/0; ``None`` is None) and checked against its domain in
``notebooks/<key>.toml`` before any kernel starts: an unknown name, a value of
the wrong type or outside its range stops with one line naming the parameter.

Without ``--in-place`` the executed notebook, its figures and its claims go to
``build/run/<key>/`` (or next to ``--output``), never over the committed files,
unless ``fig_dir`` / ``results_path`` are given explicitly.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import tempfile
import uuid
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from secest.core.validation import ValidationError
from secest.repro import spaces
from secest.repro.results import notebook_path, repo_root

__all__ = ["KERNEL", "execute_notebook", "list_parameters", "main", "safe_outputs"]

KERNEL = "python3"
"""Kernel name given to papermill; with JUPYTER_PREFER_ENV_PATH=1 it is the venv's."""


@functools.cache
def _kernel_manager_class() -> type:
    """jupyter_client's ``KernelManager``, its kernel listening on Unix sockets (POSIX).

    Over TCP (jupyter_client's default) every kernel takes five free ports on 127.0.0.1
    chosen before it binds them, so two kernels started at once by different processes (the
    two pytest workers, the Dask workers of a sweep) can pick the same port: the kernel dies
    with "Address already in use" before it answers (seen once in a clean-clone CI run).
    Unix sockets are files with names of their own. They are placed in the temporary folder
    under a short random name (a socket path may not exceed 107 bytes; jupyter_client would
    put them beside the connection file, deep in the Jupyter runtime folder) and removed when
    the kernel stops. On Windows, where ZeroMQ has no such sockets, TCP stays.
    """
    from jupyter_client.manager import KernelManager

    class UnixSocketKernelManager(KernelManager):
        def __init__(self, **kwargs: Any) -> None:
            super().__init__(**kwargs)
            if os.name == "posix":
                self.transport = "ipc"
                self.ip = os.path.join(tempfile.gettempdir(), f"secest-kernel-{uuid.uuid4().hex[:12]}")

    return UnixSocketKernelManager


def execute_notebook(
    key: str,
    parameters: Mapping[str, Any] | None = None,
    output: str | Path | None = None,
    *,
    source: str | Path | None = None,
    root: str | Path | None = None,
) -> Path:
    """Check ``parameters`` and execute ``notebooks/<key>.ipynb`` with papermill.

    Parameters
    ----------
    key : str
        Paper key.
    parameters : mapping, optional
        Values injected after the ``parameters`` cell; names and values are
        checked against ``notebooks/<key>.toml`` first (:func:`secest.repro.spaces.validate`).
    output : str or Path, optional
        Output notebook path; the input notebook itself when omitted.
    source : str or Path, optional
        Notebook to execute instead of ``notebooks/<key>.ipynb`` (e.g. one freshly
        built from the ``.py`` by a sweep).
    root : str or Path, optional
        Folder laid out like this repository (``notebooks/<key>.py``, its ``.toml``);
        the kernel runs there. Default: this repository.

    Returns
    -------
    Path
        The executed notebook.

    Notes
    -----
    The executed notebook is written once, when the execution ends, and also when a
    cell raises (papermill writes it, error included, before it re-raises). Papermill's
    default rewrite of the whole notebook before and after every cell is turned off: it
    cost about a fifth of a fast-mode execution (13.7 s against 11.3 s for ding2020).
    The kernel is stopped at once when the last cell has run (or one has raised): its
    outputs are all received by then and it holds nothing to save. A graceful shutdown
    instead stalled for 3.3 s in about one execution of five (a one-cell notebook: 0.7 s
    or 4.0 s).
    The kernel talks over Unix sockets, not TCP ports (see :func:`_kernel_manager_class`).
    """
    import papermill

    top = Path(root) if root is not None else repo_root()
    params = spaces.validate(spaces.load(key, top), dict(parameters or {}))
    src = Path(source) if source is not None else notebook_path(key, top)
    target = Path(output) if output is not None else src
    target.parent.mkdir(parents=True, exist_ok=True)
    os.environ["JUPYTER_PREFER_ENV_PATH"] = "1"
    papermill.execute_notebook(
        str(src),
        str(target),
        parameters=params,
        kernel_name=KERNEL,
        cwd=str(top),
        progress_bar=False,
        request_save_on_cell_execute=False,
        shutdown_kernel="immediate",
        kernel_manager_class=_kernel_manager_class(),
    )
    return target


def safe_outputs(key: str, params: Mapping[str, Any], output: str | Path | None) -> tuple[Path, dict]:
    """Where a run that is not ``--in-place`` writes: never over the committed outputs.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``; names the default output folder.
    params : mapping
        Parameter values of the run (already checked); not modified.
    output : str or Path or None
        Output notebook path; None means ``build/run/<key>/<key>.ipynb`` under the
        repository root.

    Returns
    -------
    output : Path
        The output notebook path.
    params : dict
        A copy of ``params`` completed with ``fig_dir`` (``<folder>/figures``) and
        ``results_path`` (``<folder>/claims.json``), ``<folder>`` being the output
        notebook's folder, unless the caller gave them.
    """
    out = Path(output) if output is not None else repo_root() / "build" / "run" / key / f"{key}.ipynb"
    folder = out.resolve().parent
    completed = dict(params)
    completed.setdefault("fig_dir", str(folder / "figures"))
    completed.setdefault("results_path", str(folder / "claims.json"))
    return out, completed


def list_parameters(key: str) -> str:
    """One line per parameter: name, default, admissible values, tag, declared space, comment.

    What ``python -m secest.repro.run KEY --list`` prints.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"ding2020"``.

    Returns
    -------
    str
        A header line and one line per parameter of the notebook's ``parameters``
        cell, in its order, the first five columns aligned.

    Raises
    ------
    ValidationError
        If ``key`` names no notebook or its ``notebooks/<key>.toml`` is invalid
        (see :func:`secest.repro.spaces.load`).
    """
    space = spaces.load(key)
    rows = [("name", "default", "admissible", "tag", "declared space", "comment")]
    for p in space.parameters.values():
        rows.append(
            (
                p.name,
                spaces.format_value(p.default),
                p.domain_text(),
                p.tag or "-",
                p.space_text(),
                p.comment,
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(5)]
    return "\n".join(
        "  ".join(cell.ljust(w) for cell, w in zip(r[:5], widths, strict=True)) + "  " + r[5]
        for r in rows
    )


def _parse(key: str, pairs: list[list[str]]) -> dict[str, Any]:
    space = spaces.load(key)
    params: dict[str, Any] = {}
    for name, text in pairs:
        if name not in space.parameters:
            raise ValidationError(
                f"parameter {name!r} is not declared by notebook {key!r}; "
                f"declared: {', '.join(space.parameters)}"
            )
        params[name] = spaces.parse_value(space.parameters[name], text)
    return params


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point (see the module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name (``KEY [-p NAME VALUE]... [--output PATH |
        --in-place] [--list]``). Default: ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 on success, 2 when a key or parameter is invalid (one line
        naming it is printed to stderr). argparse exits with status 2 on malformed
        arguments; an error raised inside the notebook propagates
        (``papermill.PapermillExecutionError``).
    """
    parser = argparse.ArgumentParser(
        prog="python -m secest.repro.run",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("key", help="paper key, e.g. lee2020")
    parser.add_argument("-p", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"))
    where = parser.add_mutually_exclusive_group()
    where.add_argument(
        "--output", default=None, help="output notebook (default build/run/<key>/<key>.ipynb)"
    )
    where.add_argument("--in-place", action="store_true", help="execute notebooks/<key>.ipynb in place")
    parser.add_argument("--list", action="store_true", help="list the parameters and exit")
    args = parser.parse_args(argv)
    try:
        if args.list:
            print(list_parameters(args.key))
            return 0
        params = _parse(args.key, args.p)
        if args.in_place:
            target = execute_notebook(args.key, params)
        else:
            out, params = safe_outputs(args.key, params, args.output)
            target = execute_notebook(args.key, params, out)
            print(f"executed notebook: {target}")
            print(f"figures: {params['fig_dir']}\nclaims: {params['results_path']}")
    except ValidationError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
