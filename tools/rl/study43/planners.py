"""The issue-43 study's policies as planners for ``srfm benchmark``:

    PYTHONPATH=. srfm benchmark -p tools.rl.study43.planners:k0_seed1 ...
    PYTHONPATH=. srfm benchmark -p tools.rl.study43.planners:k0_seed1_final ...

``k<k2>_seed<s>`` loads ``tools/rl/study43/policies/k<k2>-seed<s>.json`` (the run's
checkpoint chosen on the validation set), ``k<k2>_seed<s>_final`` the run's last
checkpoint (``k<k2>-seed<s>-final.json``); both are written by
``tools/rl/study43/finish.py``. Run from the repository root with it on the import path.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from srfm.planners.td3 import TD3Planner

POLICIES = Path(__file__).resolve().parent / "policies"
_NAME = re.compile(r"k(\d+(?:\.\d+)?)_seed(\d+)(_final)?")


def __getattr__(name: str) -> Callable[[], TD3Planner]:
    match = _NAME.fullmatch(name)
    if match is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    run = f"k{match[1]}-seed{match[2]}" + ("-final" if match[3] else "")

    def factory() -> TD3Planner:
        return TD3Planner(POLICIES / f"{run}.json", run)

    return factory
