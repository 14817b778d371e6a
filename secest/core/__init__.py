"""The estimation library: building blocks that know nothing of the papers, the arena or the tooling.

``validation``
   shape / property checks raising :class:`ValidationError`
``tolerances``
   how closely a re-run must reproduce a number (:class:`Tolerance`)
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
   observability, redundant observability, zero-order hold, sign-driven integration
``estimation``
   SVD decoupling and constrained gains of unknown-input filters
``schedules``
   the round-robin-like multichannel schedule RRL-MAP
``lmi``
   cvxpy + CLARABEL LMI assembly and certified solves (extra ``lmi``)

Every module here imports only numpy, scipy, networkx (cvxpy for ``lmi``) and this package.
"""
