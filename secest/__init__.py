"""secest: the thin shared module behind five literate reproductions.

Each submodule holds only what two or more notebooks use:

``validation``  shape / property checks raising :class:`ValidationError`
``graphs``      communication graphs, weights, Laplacians (networkx)
``channels``    Gilbert-Elliott and Bernoulli channel sequences
``covariance``  symmetrisation, PSD checks, Joseph form, information fusion, CI
``detectors``   chi-square thresholds and the normalised innovation squared
``montecarlo``  seeded random generators and Monte Carlo statistics
``plotting``    house style and deterministic figure + data saving
``results``     claims JSON, run manifests, papermill parameter validation
``run``, ``build``  notebook execution (papermill) and build steps used by the Makefile
``systems``     observability matrices / subspaces, redundant observability,
                fixed-step integration of sign-driven linear systems (lee2020, guo2023)
``estimation``  SVD decoupling and constrained gains of unknown-input filters (guo2023)
``filters``     the ding2020 secure filter step, vectorised and per node (benchmarked)
``schedules``   the round-robin-like multichannel schedule RRL-MAP (li2025)
``lmi``         cvxpy + CLARABEL LMI assembly and certified solves (ma2021)

Import the submodule you need, e.g. ``from secest import graphs``.
"""

from secest.validation import ValidationError

__all__ = ["ValidationError"]
__version__ = "0.1.0"
