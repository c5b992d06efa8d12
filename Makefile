# Quick start: `make benchmark` (set up, then run the main job) and `make test`
# (set up, then lint, type-check and run the test suite). Both create .venv and
# install the package on first use; constraints.txt keeps torch on the CPU build.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
PIP_INSTALL := $(BIN)/python -m pip install --disable-pip-version-check -q -c constraints.txt
STAMP := $(VENV)/.installed

.PHONY: setup benchmark benchmark-full test lint typecheck pytest bench-perf clean

setup: $(STAMP)

$(STAMP): pyproject.toml constraints.txt
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(PIP_INSTALL) -e '.[dev,rl,sbx,dask,sweep]'
	@touch $(STAMP)

# The main job: the benchmark on the built-in evaluation scenarios with every
# registered planner. --quick runs seeds 0-2 in seconds; `make benchmark-full` runs the
# paper's 100 seeds. Results (tables, CSV, figures) go to results/.
benchmark: $(STAMP)
	$(BIN)/srfm benchmark --quick --out results/quick

benchmark-full: $(STAMP)
	$(BIN)/srfm benchmark --out results/full

test: $(STAMP) lint typecheck pytest

lint: $(STAMP)
	$(BIN)/ruff check srfm tests tools
	$(BIN)/ruff format --check srfm tests tools

typecheck: $(STAMP)
	$(BIN)/mypy

pytest: $(STAMP)
	$(BIN)/pytest -q

# Performance measurements (docs/performance.md); needs the bench extra.
bench-perf: $(STAMP)
	$(PIP_INSTALL) -e '.[dev,bench]'
	$(BIN)/python tools/bench/bench_crowd_step.py
	$(BIN)/python tools/bench/bench_episode.py
	$(BIN)/python tools/bench/bench_frechet.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis
