"""The arena: the five papers' methods and the baselines raced on shared scenarios.

``scenarios``
   plants, networks and attacks as data (``cards.toml``), and the trials drawn from them
``estimators``
   the :class:`~secest.arena.estimators.Method` interface, the registry, the baselines, the scores
``matrix``
   the matrix of scenarios x methods and its tables

The arena uses the estimation library (:mod:`secest.core`) and the papers' methods
(:mod:`secest.methods`); neither of those imports it.
"""
