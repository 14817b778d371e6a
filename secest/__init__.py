"""secest: the shared module behind five literate reproductions.

It holds the code the notebooks share with each other, the tests and the
benchmarks, each function citing the equation it implements (a notebook shows
it where its derivation reaches it), and the tooling that builds, runs, sweeps
and verifies the notebooks and generates the site.

Numerics:

``validation``
   shape / property checks raising :class:`ValidationError`
``graphs``
   communication graphs, weights, Laplacians (networkx)
``channels``
   Gilbert-Elliott and Bernoulli channel sequences
``covariance``
   symmetrisation, PSD checks, Joseph form, information fusion, CI
``detectors``
   chi-square thresholds and the normalised innovation squared
``montecarlo``
   seeded random generators and Monte Carlo statistics
``systems``
   observability matrices / subspaces, redundant observability (lee2020, guo2023),
   zero-order-hold discretisation, fixed-step integration of sign-driven linear
   systems (lee2020)
``estimation``
   SVD decoupling and constrained gains of unknown-input filters (guo2023)
``filters``
   the ding2020 secure filter step, vectorised and per node (benchmarked)
``schedules``
   the round-robin-like multichannel schedule RRL-MAP (li2025)
``lmi``
   cvxpy + CLARABEL LMI assembly and certified solves (ma2021)

Notebooks, results and tooling:

``plotting``
   house style and deterministic figure + data saving
``results``
   claims JSON, run manifests, papermill parameter validation
``spaces``
   declared parameters, their domains and declared spaces (``notebooks/<key>.toml``)
``run``, ``build``
   notebook execution (papermill) and build steps used by the Makefile
``sweep``
   robustness sweeps of each notebook's declared space on Dask (``make robustness``)
``verify``
   re-run in paper mode and compare every number within its tolerance (``make verify``)
``site``
   the Sphinx source tree of the site (``make html``)

Import the submodule you need, e.g. ``from secest import graphs``.
"""

from secest.validation import ValidationError

__all__ = ["ValidationError"]
__version__ = "0.1.0"
