"""Showing the library's code in a notebook, where the derivation reaches it.

The algorithm of each paper lives once, in :mod:`secest.methods` (or :mod:`secest.core`); the
notebook derives it and then shows the very source it runs, so every line can be checked
against its equation number.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from secest.core.validation import ValidationError

__all__ = ["show_source", "source_of"]


def source_of(obj: Callable[..., Any] | type, *, after: str | None = None) -> str:
    """The source of a function or class, from the first line containing ``after`` on.

    Parameters
    ----------
    obj : function or class
        What to show, e.g. ``guo2023.local_gains``.
    after : str, optional
        Start at the first line containing this text (e.g. ``"    if validate:"``, to skip a long
        docstring and the argument checks); None: the whole definition.

    Returns
    -------
    str
        The source text.

    Raises
    ------
    ValidationError
        If ``obj`` has no source or ``after`` is in none of its lines.
    """
    try:
        src = inspect.getsource(obj)
    except (TypeError, OSError) as exc:
        raise ValidationError(f"obj: expected a function or class with source, found {obj!r}") from exc
    if after is None:
        return src
    lines = src.splitlines(keepends=True)
    for i, line in enumerate(lines):
        if after in line:
            return "".join(lines[i:])
    raise ValidationError(f"after: {after!r} is in no line of {obj.__qualname__}")


def show_source(obj: Callable[..., Any] | type, *, after: str | None = None) -> None:
    """Display :func:`source_of` as a highlighted Python block, headed by the module it lives in.

    Parameters
    ----------
    obj : function or class
        What to show.
    after : str, optional
        As in :func:`source_of`.
    """
    from IPython.display import Markdown, display

    text = source_of(obj, after=after)
    display(Markdown(f"`{obj.__module__}.{obj.__qualname__}`:\n\n```python\n{text}```"))
