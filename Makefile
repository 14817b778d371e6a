# secest: every target builds the virtual environment first (python3 + make are all you need).
SHELL := /bin/bash
.DELETE_ON_ERROR:

# The interpreter: `make test PYTHON=python3.13`. Each minor version gets its own environment,
# .venv/py<major.minor>, built from the same lock (it pins every supported Python's wheels).
PYTHON ?= python3
PYVER  := $(shell $(PYTHON) -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)
SUPPORTED := 3.11 3.12 3.13
ifeq ($(PYVER),)
$(error PYTHON=$(PYTHON) does not run: name an interpreter, e.g. PYTHON=python3.13)
endif
ifeq ($(filter $(PYVER),$(SUPPORTED)),)
$(warning PYTHON=$(PYTHON) is Python $(PYVER), which this package is not tested on (tested: $(SUPPORTED)); \
  the lock may not install or the tests may fail)
endif
VENV   := .venv/py$(PYVER)
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.stamp
KEYS   := $(sort $(basename $(notdir $(wildcard notebooks/*.py))))
NB     ?= $(KEYS)
export JUPYTER_PREFER_ENV_PATH := 1
export OMP_NUM_THREADS := 1
export OPENBLAS_NUM_THREADS := 1
export MPLBACKEND := Agg
export PYDEVD_DISABLE_FILE_VALIDATION := 1

.PHONY: venv figures test verify lint bench lock html clean robustness arena-test shots $(addprefix figures-,$(KEYS))

venv: $(STAMP)

$(STAMP): environment.lock
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check --require-hashes -r environment.lock
	$(PY) -m pip install --quiet --disable-pip-version-check --no-deps --no-build-isolation -e .
	$(PY) -m ipykernel install --sys-prefix --name python3 --display-name "Python 3 (secest)" >/dev/null
	touch $@

## figures: build each notebook from its .py, execute it in place, strip metadata, check the manifest
figures: $(addprefix figures-,$(NB))
	$(PY) -m secest.repro.build manifest $(NB)

$(addprefix figures-,$(KEYS)): figures-%: $(STAMP)
	$(PY) -m secest.repro.build ipynb $*
	$(PY) -m secest.repro.build prepare $*
	$(PY) -m secest.repro.run $* --in-place
	$(PY) -m secest.repro.build strip $*

## test: unit tests + papermill-executed notebook tests (fast mode) + lint
test: $(STAMP)
	$(PY) -m ruff check secest tests notebooks benchmarks docs
	$(PY) -m pytest -n 2 --dist loadscope

## shots: build the site and save a full-page screenshot of every page in build/site-screenshots/
## (make test saves what a reader first sees of each page)
shots: $(STAMP)
	SECEST_SITE_SHOTS=full $(PY) -m pytest -q -p no:cacheprovider tests/test_site.py -k screenshot

## robustness: sweep each notebook's declared space on Dask (a LocalCluster sized to the machine;
## SCHEDULER=tcp://host:port sends it to an existing cluster). Writes figures/<key>/robustness.*
## For the arena (NB=arena) it runs the tuning searches of secest/arena/protocol.toml on the
## validation seeds instead (python -m secest.arena.tuning, every method with a search set on the
## cards' plants) and writes figures/arena/tuned.json: commit that file before `make arena-test`
WORKERS ?= $(shell nproc 2>/dev/null || echo 2)
DASK = $(if $(SCHEDULER),--scheduler $(SCHEDULER),--workers $(WORKERS))
SWEPT = $(filter-out arena,$(NB))
robustness: $(STAMP)
	$(if $(SWEPT),$(PY) -m secest.repro.sweep $(SWEPT) $(if $(SCHEDULER),--scheduler $(SCHEDULER)))
	$(if $(filter arena,$(NB)),$(PY) -m secest.arena.tuning $(DASK) --out figures/arena/tuned.json)

## arena-test: the arena's test stage (issue #28): every method printed and tuned (the committed
## figures/arena/tuned.json) on the test seeds of protocol.toml, every plant and attack; refuses a
## tuned.json that git does not track or that differs from its commit. Writes figures/arena/test.json
## (then `make figures NB=arena`). WORKERS=n or SCHEDULER=tcp://host:port as for robustness
arena-test: $(STAMP)
	$(PY) -m secest.arena.tuning test --tuned figures/arena/tuned.json $(DASK) --out figures/arena/test.json

## verify: execute the notebooks (paper mode) into build/verify/ and compare every committed number
## with its declared tolerance (report: build/verify.json). It forces no BLAS kernel or CPU feature:
## machines differ, and the tolerances say by how much results may.
verify: $(STAMP)
	$(PY) -m secest.repro.verify $(NB)

bench: $(STAMP)
	$(PY) benchmarks/bench.py

## lock: regenerate environment.lock (pinned with hashes) from pyproject.toml: one universal
## resolution for every Python from the oldest supported on (markers pick a version per Python)
lock:
	$(PYTHON) -m venv build/lockenv
	build/lockenv/bin/python -m pip install --quiet uv==0.13.9
	build/lockenv/bin/uv pip compile pyproject.toml --extra all --generate-hashes \
	    --universal --python-version $(firstword $(SUPPORTED)) --no-header -o environment.lock

## html: the site in build/html/ (Sphinx + myst-nb, renders the committed notebooks, executes nothing).
## Any warning fails it; a failed build drops Sphinx's cache so the next run reports every warning again.
SITE_SRC := build/site-src
html: $(STAMP)
	$(PY) -m secest.repro.site prepare $(SITE_SRC)
	$(PY) -m sphinx -W --keep-going -q -j auto -b html -c docs $(SITE_SRC) build/html \
	    || { rm -rf build/html/.doctrees; exit 1; }
	@echo "site: build/html/index.html (opens from disk, no network needed); 'make serve' serves it"

## serve: serve build/html/ on http://localhost:$(PORT) (Ctrl-C stops it)
PORT ?= 8000
.PHONY: serve
serve: html
	$(PY) -m http.server $(PORT) --bind 127.0.0.1 --directory build/html

clean:
	rm -rf .venv build .pytest_cache
