# Quick start: `make benchmark` (set up what the quick benchmark needs, then run it) and
# `make test` (set up everything, then lint, type-check, build the documentation and run
# the test suite). Both create .venv and install on first use; constraints.txt keeps
# torch on the CPU build.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
PIP_INSTALL := $(BIN)/python -m pip install --disable-pip-version-check -q -c constraints.txt
# The library alone (what `make benchmark` needs), and every extra (what `make test` needs).
RUN_STAMP := $(VENV)/.installed-run
DEV_STAMP := $(VENV)/.installed-dev
DEV_EXTRAS := dev,rl,sbx,dask,sweep,docs,release

.PHONY: setup system-deps benchmark benchmark-full test lint typecheck docs docs-tables results-set pytest dist bench-perf clean

setup: $(DEV_STAMP) system-deps

# The C++ client of the external planner protocol (clients/cpp), which the test suite
# builds: CMake, a C++ compiler and Debian's msgpack-cxx, installed with apt-get when
# missing and make runs as root (elsewhere it says what to install).
CPP_DEPS := cmake g++ libmsgpack-cxx-dev
system-deps:
	@if [ -f /usr/include/msgpack.hpp ] && command -v cmake >/dev/null && command -v c++ >/dev/null; then \
		:; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
		echo "make: installing Debian's $(CPP_DEPS) for the C++ client (clients/cpp)"; \
		DEBIAN_FRONTEND=noninteractive apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $(CPP_DEPS) >/dev/null; \
	else \
		echo "make: the C++ client (clients/cpp) needs $(CPP_DEPS): sudo apt-get install $(CPP_DEPS)" >&2; \
	fi

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(RUN_STAMP): pyproject.toml constraints.txt | $(BIN)/python
	$(PIP_INSTALL) -e .
	@touch $@

$(DEV_STAMP): pyproject.toml constraints.txt | $(BIN)/python
	$(PIP_INSTALL) -e '.[$(DEV_EXTRAS)]'
	@touch $@ $(RUN_STAMP)

# The main job: the benchmark on the built-in evaluation scenarios with every
# registered planner. --quick runs seeds 0-2 in seconds; `make benchmark-full` runs the
# paper's 100 seeds. Results (tables, CSV, figures, report.html) go to results/.
benchmark: $(RUN_STAMP)
	$(BIN)/srfm benchmark --quick --out results/quick

benchmark-full: $(RUN_STAMP)
	$(BIN)/srfm benchmark --out results/full

test: $(DEV_STAMP) system-deps lint typecheck docs pytest

lint: $(DEV_STAMP)
	$(BIN)/ruff check srfm tests tools examples
	$(BIN)/ruff format --check srfm tests tools examples

typecheck: $(DEV_STAMP)
	$(BIN)/mypy

# The documentation site (docs/*.md and the API reference) into site/; any warning
# (a broken link, a public name without a docstring) fails it.
docs: $(DEV_STAMP)
	$(BIN)/mkdocs build --strict --site-dir site

# Every generated table of the docs (between <!-- generated: NAME --> and <!-- end: NAME -->,
# and the whole files of tools/results/whole_files.py) from the committed data: reads data,
# simulates nothing (seconds); then every figure from its committed data
# (tools/results/figures.py, about 20 s). tests/docs/test_generated.py,
# test_whole_files.py and test_figures.py fail when a page, file or figure differs.
docs-tables: $(DEV_STAMP)
	$(BIN)/python tools/results/generate.py
	$(BIN)/python tools/results/figures.py

# Run one results set again from scratch into results/SET (interrupt and run again: the
# benchmark resumes), pack it into docs/results/SET, then `make docs-tables`.
# `make results-set SET=paper`; docs/results/index.md lists the sets and their times.
results-set: $(DEV_STAMP)
	$(BIN)/python tools/results/run.py $(SET)

pytest: $(DEV_STAMP) system-deps
	$(BIN)/pytest -q

# The release files: a wheel and an sdist in dist/, checked by twine.
dist: $(DEV_STAMP)
	rm -rf dist
	$(BIN)/python -m build --outdir dist
	$(BIN)/twine check --strict dist/*

# Performance measurements (docs/performance.md); needs the bench extra.
bench-perf: $(DEV_STAMP)
	$(PIP_INSTALL) -e '.[dev,bench]'
	$(BIN)/python tools/bench/bench_crowd_step.py
	$(BIN)/python tools/bench/bench_episode.py
	$(BIN)/python tools/bench/bench_frechet.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis site dist
