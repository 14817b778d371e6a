"""The arena: the five papers' methods and the baselines raced on shared scenarios.

``scenarios``
   plants, networks and attacks as data (``cards.toml``), and the trials drawn from them
``estimators``
   the :class:`~secest.arena.estimators.Method` interface, the registry, the baselines, the scores
``matrix``
   the matrix of scenarios x methods and its tables

Importing any module of the arena registers the baselines and the five papers' methods.
The arena uses the estimation library (:mod:`secest.core`) and the papers' methods
(:mod:`secest.methods`); neither of those imports it.
"""

# The five papers' methods are registered whenever the arena is used (not only after an explicit
# import of secest.arena.papers): a matrix never silently scores the baselines alone.
from secest.arena import papers  # noqa: E402, F401
