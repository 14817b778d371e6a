"""The five papers' estimators as arena methods, one module per paper key.

Importing this package registers each with :data:`secest.arena.estimators.METHODS`. Each module
wraps the paper's functions of :mod:`secest.methods` (what the notebook verified against the
paper) in a :class:`~secest.arena.estimators.Method` that checks the conditions of its theory
on a scenario first. ma2021 imports cvxpy only when it runs.
"""

from secest.arena.papers import ding2020, guo2023, lee2020, li2025, ma2021

__all__ = ["ding2020", "guo2023", "lee2020", "li2025", "ma2021"]
