"""The study's policies (tools/rl/study.py) as planners for ``srfm benchmark``:

    PYTHONPATH=. srfm benchmark -p tools.rl.study_planners:k0_seed1 ...

``k<k2>_seed<s>`` loads the NumPy policy ``tools/rl/study/policies/k<k2>-seed<s>.json``
(the run's best checkpoint, exported by ``tools/rl/study.py collect``), named
``k<k2>-seed<s>``. Run from the repository root with it on the import path: the module is
imported by name in every worker.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from srfm.planners.td3 import TD3Planner

POLICIES = Path(__file__).resolve().parent / "study" / "policies"
_NAME = re.compile(r"k(\d+(?:\.\d+)?)_seed(\d+)")


def __getattr__(name: str) -> Callable[[], TD3Planner]:
    match = _NAME.fullmatch(name)
    if match is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    run = f"k{match[1]}-seed{match[2]}"

    def factory() -> TD3Planner:
        return TD3Planner(POLICIES / f"{run}.json", run)

    return factory
