"""The five papers' estimators as arena methods (one module per paper key).

Importing this package registers every method with :data:`secest.estimators.METHODS`.
Each module holds the estimator the paper notebook derives, as plain functions the
notebook calls, and a :class:`secest.estimators.Method` that runs it on a shared scenario
after checking the conditions of its theory. Modules that need optional dependencies
(ma2021: cvxpy) import them only when the method runs.
"""

from secest.methods import ding2020, guo2023, lee2020, li2025, ma2021

__all__ = ["ding2020", "guo2023", "lee2020", "li2025", "ma2021"]
