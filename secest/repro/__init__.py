"""The reproduction tooling: what builds, runs, sweeps and verifies the notebooks and makes the site.

``results``
   claims JSON, run manifests, papermill parameter validation
``plotting``
   house style and deterministic figure + data saving
``spaces``
   declared parameters, their domains and declared spaces (``notebooks/<key>.toml``)
``run``, ``build``
   notebook execution (papermill) and the build steps of the Makefile
``sweep``
   robustness sweeps of each notebook's declared space on Dask (``make robustness``)
``verify``
   re-run in paper mode and compare every number within its tolerance (``make verify``)
``site``
   the Sphinx source tree of the site (``make html``)

The tooling may import every other layer; nothing outside it imports it.
"""
