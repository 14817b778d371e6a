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

Import the submodule you need, e.g. ``from secest import graphs``.
"""

from secest.validation import ValidationError

__all__ = ["ValidationError"]
__version__ = "0.1.0"
