"""The arena: the five papers' methods and the baselines raced on shared scenarios.

``scenarios``
   plants, networks and attacks as data (``cards.toml``), and the trials drawn from them
``estimators``
   the :class:`~secest.arena.estimators.Method` interface, the registry, the centralised
   baselines, the scores
``baselines``
   the distributed baselines (local, consensus, diffusion, Kalman consensus, W-MSR filters)
``papers``
   the five papers' methods (:mod:`secest.methods`) behind the ``Method`` interface, registered
``matrix``
   the matrix of scenarios x methods and its tables
``report``
   :func:`race` (cards and methods of one's own in one call) and the matrix as files: CSV,
   JSON, heatmap, per-plant tables; the card schema as documentation
``cli``
   the command line ``python -m secest.arena`` over :func:`race`
``protocol``
   the pre-registered protocol of the arena (``protocol.toml``)
``tuning``
   the protocol's tuning rule: search grids, validation runs (validation seeds only), the choice,
   and the command line ``python -m secest.arena.tuning``
``testseeds``
   the test stage: the committed tuned constants (and the printed ones) on the test seeds, pooled
   over the seeds (``python -m secest.arena.tuning test``)

Importing any module of the arena registers the baselines and the five papers' methods.
The arena uses the estimation library (:mod:`secest.core`) and the papers' methods
(:mod:`secest.methods`); neither of those imports it.
"""

# The distributed baselines and the five papers' methods are registered whenever the arena is used
# (not only after an explicit import of secest.arena.papers): a matrix never silently scores the
# centralised baselines alone.
from secest.arena import baselines, papers  # noqa: E402, F401
from secest.arena.report import race

__all__ = ["race"]
