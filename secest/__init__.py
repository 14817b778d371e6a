"""secest: five published secure distributed estimators, reproduced, and an arena to race them.

The package has four layers; each imports only the layers before it:

:mod:`secest.core`
   the estimation library: graphs, channels, covariance, detectors, Monte Carlo, systems,
   unknown-input estimation, schedules, LMIs, validation, tolerances
:mod:`secest.methods`
   the five papers' estimators (one module per paper key), with the papers' equation numbers
:mod:`secest.arena`
   scenarios (cards), the ``Method`` interface and baselines, scores and the matrix
:mod:`secest.repro`
   the reproduction tooling: results and claims, plotting, notebook execution, declared
   spaces, sweeps on Dask, ``make verify`` and the site

Import the module you need, e.g. ``from secest.core import graphs``.
"""

from secest.core.validation import ValidationError

__all__ = ["ValidationError"]
__version__ = "0.1.0"
