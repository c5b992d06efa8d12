# Quick start: `make benchmark` (set up, then run the main job) and `make test`
# (set up, then lint, type-check and run the test suite). Both create .venv and
# install the package on first use; constraints.txt keeps torch on the CPU build.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
PIP_INSTALL := $(BIN)/python -m pip install --disable-pip-version-check -q -c constraints.txt
STAMP := $(VENV)/.installed

.PHONY: setup benchmark test lint typecheck pytest bench-perf clean

setup: $(STAMP)

$(STAMP): pyproject.toml constraints.txt
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(PIP_INSTALL) -e '.[dev,rl]'
	@touch $(STAMP)

# The main job: every built-in evaluation scenario with every registered planner.
benchmark: $(STAMP)
	@for scenario in footpath crosswalk cross_footpath circle concert; do \
		for planner in $$($(BIN)/srfm planners | cut -d' ' -f1); do \
			$(BIN)/srfm simulate --scenario $$scenario --planner $$planner --seed 0 || exit 1; \
			echo; \
		done; \
	done

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
	$(BIN)/python tools/bench_crowd_step.py
	$(BIN)/python tools/bench_episode.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis
