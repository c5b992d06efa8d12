"""Fixtures for the dataset and fitting tests: the real data folder, synthetic scenes."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.conftest import REPO


def data_dir() -> Path:
    """``$SRFM_DATA_DIR`` when set, else ``<repo>/../shared/data``."""
    env = os.environ.get("SRFM_DATA_DIR")
    return Path(env) if env else REPO.parent / "shared" / "data"


@pytest.fixture
def real_data() -> Path:
    """The real data folder; the test is skipped, saying why, when it is absent."""
    root = data_dir()
    if not (root / "eth_ucy").is_dir() or not (root / "navwareset").is_dir():
        pytest.skip(
            f"real trajectory data not found at {root} (needs eth_ucy/ and navwareset/); "
            "set SRFM_DATA_DIR to the shared data folder to run this test"
        )
    return root
