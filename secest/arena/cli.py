"""The arena's command line ``python -m secest.arena``: a thin layer over
:func:`secest.arena.report.race`.

Race every registered method (and one's own) on the package's cards (and one's own), and write
the matrix into a folder::

    python -m secest.arena --cards my_cards.toml --method my_method.py:FixedGainKF \\
        --plants mynet --runs 10 --horizon 100 --out results/

``--list`` prints the cards and the registered methods (with ``--cards`` and ``--method``: one's
own too). Every argument is checked before any work starts; a bad one ends the program with a
one-line error and exit status 2.

``--workers N`` runs the scenarios as tasks on a Dask ``LocalCluster`` of N processes,
``--scheduler tcp://host:8786`` on a running cluster (:func:`secest.arena.matrix.run_matrix`);
the matrix is the same as in this process.
"""

from __future__ import annotations

import argparse
import hashlib
import importlib
import importlib.util
import sys
from collections.abc import Sequence
from pathlib import Path

from secest.arena import matrix, report, scenarios
from secest.arena.estimators import METHODS, Method, register
from secest.core.validation import ValidationError

__all__ = ["PROG", "list_text", "load_method", "main", "parser"]

PROG = "python -m secest.arena"


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (exit status 2) instead of the usage and the error."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def _count(minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected an integer >= {minimum}, found {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, found {value}")
        return value
    return parse


def _names(text: str) -> list[str]:
    names = [n.strip() for n in text.split(",")]
    if not text.strip() or not all(names):
        raise argparse.ArgumentTypeError(f"expected a comma-separated list of names, found {text!r}")
    return names


def parser() -> argparse.ArgumentParser:
    """The argument parser of :func:`main` (its ``--help`` is the reference of every option)."""
    p = _Parser(prog=PROG, description="Race estimators on the arena's scenarios and write the "
                "matrix (CSV, JSON), its heatmap and one table per plant.")
    p.add_argument("--cards", metavar="FILE", help="extra cards, a TOML file laid out like "
                   "secest/arena/cards.toml (its [matrix] networks and attacks extend the cross)")
    p.add_argument("--method", metavar="MOD:CLASS", action="append", default=[],
                   help="a Method subclass to register and race: MOD a dotted module name or a "
                   "path to a .py file (repeatable)")
    p.add_argument("--methods", type=_names, metavar="A,B,...",
                   help="methods to race (default every registered one; the oracle is always scored)")
    p.add_argument("--plants", type=_names, metavar="A,B,...",
                   help="network cards (each with its plant) to cross (default the [matrix] networks)")
    p.add_argument("--attacks", type=_names, metavar="A,B,...",
                   help="attack cards to cross (default the [matrix] attacks)")
    p.add_argument("--runs", type=_count(2), help="Monte Carlo runs per scenario (default [matrix])")
    p.add_argument("--horizon", type=_count(1), help="steps per run (default [matrix]: 20 time "
                   "constants of each plant; a shorter horizon needs --short)")
    p.add_argument("--short", action="store_true", help="smoke test: allow horizons without a "
                   "steady window (shorter than 20 time constants)")
    p.add_argument("--seed", type=_count(0), help="root seed of the runs (default [matrix])")
    p.add_argument("--out", metavar="DIR", help="folder to write matrix.csv, matrix.json, "
                   "heatmap.png and tables/<plant>.md into")
    p.add_argument("--list", action="store_true", help="print the cards and the registered methods")
    p.add_argument("--workers", type=_count(1), metavar="N", help="run the scenarios on a Dask "
                   "LocalCluster of N single-threaded processes (needs the sweep extra)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run the scenarios on the Dask cluster "
                   "at ADDRESS, e.g. tcp://127.0.0.1:8786 (its workers need secest and your modules)")
    return p


def _module(spec: str, where: str):
    """The module ``where`` names: a path to a ``.py`` file, or a dotted module name."""
    if where.endswith(".py"):
        path = Path(where).resolve()
        if not path.is_file():
            raise ValidationError(f"--method {spec}: no file {where!r}")
        name = matrix.USER_MODULE_PREFIX + hashlib.sha1(str(path).encode()).hexdigest()[:12]
        if name in sys.modules:  # the same file twice: one module, one class, one registration
            return sys.modules[name]
        loader = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(loader)
        sys.modules[name] = module
        try:
            loader.loader.exec_module(module)
        except Exception as exc:
            del sys.modules[name]
            raise ValidationError(f"--method {spec}: importing {where!r} raised "
                                  f"{type(exc).__name__}: {exc}") from exc
        return module
    try:
        return importlib.import_module(where)
    except Exception as exc:
        raise ValidationError(f"--method {spec}: cannot import module {where!r} "
                              f"({type(exc).__name__}: {exc})") from exc


def load_method(spec: str) -> str:
    """Import and register the :class:`~secest.arena.estimators.Method` subclass ``MOD:CLASS``.

    Parameters
    ----------
    spec : str
        ``MOD:CLASS``: ``MOD`` a dotted module name importable here or a path to a ``.py`` file,
        ``CLASS`` a :class:`~secest.arena.estimators.Method` subclass in it. A class the module
        registers itself (``@register``) is not registered twice.

    Returns
    -------
    str
        The method's name in the registry.
    """
    if not isinstance(spec, str):
        raise ValidationError(f"--method must be MOD:CLASS (a module or .py path, a class name), "
                              f"found {spec!r}")
    where, sep, cls_name = spec.rpartition(":")
    if not sep or not where or not cls_name.isidentifier():
        raise ValidationError(f"--method must be MOD:CLASS (a module or .py path, a class name), "
                              f"found {spec!r}")
    module = _module(spec, where)
    cls = getattr(module, cls_name, None)
    if not (isinstance(cls, type) and issubclass(cls, Method)):
        found = sorted(n for n, v in vars(module).items()
                       if isinstance(v, type) and issubclass(v, Method) and v is not Method)
        raise ValidationError(f"--method {spec}: {cls_name!r} is not a Method subclass of {where!r}; "
                              f"Method subclasses there: {found}")
    if type(METHODS.get(cls.name)) is not cls:
        register(cls)
    return cls.name


def list_text(cards: scenarios.Extra = None) -> str:
    """The cards (name, title; a network's plant and size) and the registered methods, as text.

    Parameters
    ----------
    cards : path or mapping, optional
        More cards (``--cards``), listed with the package's.
    """
    c = scenarios.cards(cards)
    lines = ["plants:"]
    lines += [f"  {n:18} {p.title}" for n, p in c["plant"].items()]
    lines.append("networks (--plants):")
    lines += [f"  {n:18} plant {net.plant}, N = {net.N}: {net.title}" for n, net in c["network"].items()]
    lines.append("attacks (--attacks):")
    lines += [f"  {n:18} {a.kind}: {a.title}" for n, a in c["attack"].items()]
    if c["scenario"]:
        lines.append("named scenarios:")
        lines += [f"  {n:18} {s['network']} / {s['attack']}" for n, s in c["scenario"].items()]
    m = c["matrix"]
    lines.append(f"matrix: networks {m['networks']} x attacks {m['attacks']}, "
                 f"{m['runs']} runs of {m['horizon']} steps, seed {m['seed']}")
    lines.append("methods (--methods):")
    lines += [f"  {n:18} {meth.kind}: {meth.title}" for n, meth in METHODS.items()]
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name (see :func:`parser`).

    Returns
    -------
    int
        0 on success, 2 after a one-line error on standard error (a bad argument, a card or
        method the arena refuses).
    """
    args = parser().parse_args(argv)
    try:
        if args.cards is not None and not Path(args.cards).is_file():
            raise ValidationError(f"--cards: no file {args.cards!r}")
        if args.cards is not None:  # every card checked before any method is imported
            try:
                scenarios.cards(args.cards)
            except ValidationError as exc:
                raise ValidationError(f"--cards {args.cards}: {exc}") from None
        for spec in args.method:
            load_method(spec)
        if args.list:
            print(list_text(args.cards))
            return 0
        if args.out is None:
            raise ValidationError("--out DIR is required to race (or --list to see the cards)")
        m = report.race(args.cards, args.methods, plants=args.plants, attacks=args.attacks,
                        runs=args.runs, horizon=args.horizon, seed=args.seed, out=args.out,
                        short=args.short, scheduler=args.scheduler, workers=args.workers)
    except ValidationError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    counts = {s: sum(c.status == s for c in m.cells.values()) for s in matrix.STATUSES}
    print(f"{len(m.scenarios)} scenarios x {len(m.methods)} methods: "
          + ", ".join(f"{n} {s}" for s, n in counts.items()) + f"; written to {args.out}")
    if not report.can_plot():
        print("heatmap.png not drawn: it needs matplotlib (pip install 'secest[notebooks]')")
    return 0
