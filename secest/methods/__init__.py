"""The five papers' estimators, one module per paper key, as plain functions.

Each line carries the paper's equation number; the paper's notebook imports these functions
and shows their source where its derivation reaches them, and the arena
(:mod:`secest.arena.papers`) wraps the same functions. This package imports only
:mod:`secest.core` (ma2021's LMIs need the ``lmi`` extra).
"""
