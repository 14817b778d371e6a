"""secest: five published secure distributed estimators, reproduced, and an arena to race them.

The package has four layers; each imports only the layers before it:

:mod:`secest.core`
   the estimation library: graphs, channels, covariance, detectors, Monte Carlo, systems,
   unknown-input estimation, schedules, LMIs, validation, tolerances
:mod:`secest.methods`
   the five papers' estimators (one module per paper key), with the papers' equation numbers
:mod:`secest.arena`
   the papers' methods and the baselines raced on shared scenarios: ``scenarios`` (plants,
   networks and attacks as cards), ``estimators`` (the ``Method`` interface, the registry, the
   centralised baselines, the scores), ``baselines`` (the distributed baselines), ``papers`` (the
   five methods behind that interface), ``matrix`` (every
   method on every scenario, its tables), ``report`` (``race``: one's own cards and methods in one
   call, the matrix as files), ``cli`` (``python -m secest.arena``), ``protocol`` (the
   pre-registered protocol), ``tuning`` (its tuning rule on the validation seeds), ``testseeds``
   (the tuned and printed rows on the test seeds)
:mod:`secest.repro`
   the reproduction tooling: results and claims, plotting, notebook execution, declared
   spaces, sweeps on Dask, ``make verify`` and the site

Import the module you need, e.g. ``from secest.core import graphs``.
"""

from secest.core.validation import ValidationError

__all__ = ["ValidationError"]
__version__ = "0.1.0"
