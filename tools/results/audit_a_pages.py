"""Run figures of docs/fitting.md, real_encounters.md, sensitivity.md and model.md that
were typed in their prose, now written from committed data (``make docs-tables``).

Each block reads a file that is already committed for its page:

- ``fitting-horizon-pass``: the robots' median driving speeds of
  ``docs/fitting_navwareset_facts.json`` (``tools/fitting/navwareset_facts.py``);
- ``encounters-track-end-cache``: the fits held by the caches of
  ``tools/fitting/fit_forms.py`` (``docs/real_encounters/forms_cache_*.json``);
- ``sensitivity-design``, ``sensitivity-pooled-n``, ``sensitivity-success-n``: the
  episodes of the sweep (``docs/sensitivity/episodes.csv.gz``, ``tools/results/sensitivity.py``);
- ``model-presets``: the shipped presets themselves (``srfm.models.params.PRESETS``, the
  parameter files of ``srfm/models/presets/``).

Nothing is computed but counts, a product of committed numbers and formatting.
"""

from __future__ import annotations

import csv
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, Final

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from srfm.models.params import PRESETS, SRFMParams
from tools.results import sensitivity
from tools.results.fitting_pages import DOCS, WORDS, MissingDataError, _json, prose

FACTS: Final = "fitting_navwareset_facts.json"
HORIZON_S: Final = 4.8
"""The NavWareSet protocol's horizon (``srfm fit --horizon``; docs/fitting.md)."""
WALKING_MPS: Final = 1.0
"""The walking speed of the head-on example (an assumption of the sentence, not data)."""
INTERACTION_M: Final = 3.0
"""The protocol's interaction radius (``--interaction-radius``)."""

CACHE: Final = "real_encounters/forms_cache_{goal}.json"
DECISIVE_FORMS: Final = ("exponential", "ttc", "collision_prediction")
"""The forms of part 4's decisive family (``tools/fitting/fit_forms.py``)."""
FORM_NAMES: Final = {
    "exponential": "exponential",
    "ttc": "time-to-collision",
    "collision_prediction": "collision-prediction",
    "elliptical": "elliptical",
}


# -- docs/fitting.md ------------------------------------------------------------------


def fitting_horizon_pass() -> str:
    """The protocol's horizon bullet: how far a person and each robot close in over the
    horizon, from the robots' median driving speeds in the data."""
    speed = _json(FACTS)["robot_speed_mps"]
    close = {r: (WALKING_MPS + float(speed[r])) * HORIZON_S for r in ("hsr", "jackal")}
    if min(close.values()) <= INTERACTION_M:
        raise SystemExit(
            "docs/fitting.md: a pass no longer fits in the horizon: rewrite the sentence"
        )
    return prose(
        f"- **Horizon {HORIZON_S:g} s** (48 samples at 10 Hz), as on ETH/UCY: long enough "
        f"to contain a pass (head-on, a person at {WALKING_MPS:g} m/s and the robot at its "
        f"median driving speed in the data, {float(speed['hsr']):.1f} m/s for the HSR and "
        f"{float(speed['jackal']):.1f} m/s for the Jackal, close about {close['hsr']:.0f} m "
        f"and {close['jackal']:.0f} m in {HORIZON_S:g} s, against the "
        f"{INTERACTION_M:g} m interaction radius), short enough that the goal estimate "
        "matters less than the dynamics."
    )


# -- docs/real_encounters.md ----------------------------------------------------------


def _fits(goal: str, form: str) -> set[str]:
    """The cached robot-part fits (all scenes and every held-out fold, no bootstrap
    resample) of ``form`` with the ``goal`` windows."""
    entries = _json(CACHE.format(goal=goal))["entries"]
    return {
        k.split("/", 1)[1] for k in entries if k.startswith(f"{goal}/{form}/") and "/boot/" not in k
    }


def encounters_track_end_cache() -> str:
    """How far the track-end run of part 4 got: its cache against the heading run's."""
    entries = _json(CACHE.format(goal="track_end"))["entries"]
    folds = sum(k.startswith("ped/without/") for k in entries)
    heading_folds = sum(
        k.startswith("ped/without/") for k in _json(CACHE.format(goal="heading"))["entries"]
    )
    done = {f: len(_fits("track_end", f)) for f in DECISIVE_FORMS}
    need = {f: len(_fits("heading", f)) for f in DECISIVE_FORMS}
    if all(done[f] >= need[f] for f in DECISIVE_FORMS):
        raise SystemExit(
            "docs/real_encounters.md: the track-end run is complete: report its results"
        )
    started = [f for f in DECISIVE_FORMS if done[f]]
    parts = [
        f"{done[f]} of the {FORM_NAMES[f]} form's {need[f]} fits (all scenes and the "
        "held-out folds)"
        for f in started
    ]
    rest = [FORM_NAMES[f] for f in DECISIVE_FORMS if not done[f]]
    ped = (
        "every held-out fold" if folds >= heading_folds else f"{folds} of the {heading_folds} folds"
    )
    return prose(
        "**The track-end goal** (secondary, exploratory; the goal can leak the avoidance, "
        "part 2) was not run to the end: its cache (`forms_cache_track_end.json`) holds the "
        f"pedestrian part of {ped} and "
        + "; ".join(parts)
        + (f", none of the {' or '.join(rest)} form's" if rest else "")
        + "; the second command above resumes it."
    )


# -- docs/sensitivity.md --------------------------------------------------------------


def _counts() -> dict[str, Any]:
    e = sensitivity.episodes()
    seeds = sorted(set(e["seed"].tolist()))
    return {
        "episodes": int(e["seed"].size),
        "seeds": seeds,
        "a": sensitivity.levels("a_robot"),
        "b": sensitivity.levels("b_robot"),
    }


def _per(mask: Any) -> int:
    """The number of episodes of one planner under ``mask`` (every planner the same)."""
    e = sensitivity.episodes()
    n = {int(np.sum(mask & (e["planner"] == p))) for p in sensitivity.planners()}
    if len(n) != 1:
        raise SystemExit(f"docs/sensitivity.md: planners differ in their episodes: {sorted(n)}")
    return n.pop()


def _values(xs: list[float]) -> str:
    return "{" + ", ".join(f"{x:g}" for x in xs) + "}"


def _times(x: float) -> str:
    return "twice" if x == 2 else f"{x:g} times"


def _word(n: int) -> str:
    return WORDS[n] if n < len(WORDS) else str(n)


def sensitivity_design() -> str:
    """The grid of the sweep as it ran: its levels, planners, scenarios, seeds and the
    number of twin episodes, from the committed episodes."""
    c = _counts()
    ref = sensitivity.REFERENCE
    a, b, seeds = c["a"], c["b"], c["seeds"]
    if seeds != list(range(seeds[0], seeds[-1] + 1)):
        raise SystemExit("docs/sensitivity.md: the seeds are not a range: rewrite the sentence")
    per_cell = c["episodes"] // (len(a) * len(b) * len(sensitivity.planners()))
    per_cell //= len(sensitivity.scenarios())
    lines = [
        f"[`docs/sweeps/sensitivity.toml`](sweeps/sensitivity.toml): a grid of {len(a)} × "
        f"{len(b)} = {len(a) * len(b)} cells,",
        "",
        f"- **A_r** ∈ {_values(a)} m/s² ({a[0]:g} to {_times(a[-1] / ref['a_robot'])} the "
        "paper's value),",
        f"- **B_r** ∈ {_values(b)} m (the paper's value "
        f"{'in the middle' if b[len(b) // 2] == ref['b_robot'] else 'among them'}),",
        "",
        prose(
            "every other parameter at the paper's preset (`agrawal2024`), × the paper's "
            f"planner suite ({', '.join(f'`{p}`' for p in sensitivity.planners())}: the "
            f"policies shipped with srfm) × the {_word(len(sensitivity.scenarios()))} evaluation "
            f"scenarios × seeds {seeds[0]}–{seeds[-1]}: {c['episodes']:,} twin episodes "
            f"({per_cell} seeds per cell and scenario, where the paper's table used 100)."
        ),
    ]
    return "\n".join(lines)


def sensitivity_pooled_n() -> str:
    """The caption of the pooled tables: their n per planner and level."""
    e = sensitivity.episodes()
    a, b = sensitivity.levels("a_robot"), sensitivity.levels("b_robot")
    n_a = {_per(e["a_robot"] == x) for x in a}
    n_b = {_per(e["b_robot"] == x) for x in b}
    if len(n_a) != 1 or len(n_b) != 1:
        raise SystemExit("docs/sensitivity.md: the levels hold different numbers of episodes")
    return prose(
        "Mean Fréchet deviation (m) ± the half-width of its 95 % confidence interval "
        "(Student's t), and the robot's success rate, the scenarios and the other factor "
        f"pooled ({n_a.pop():,} episodes per planner and value of A_r, {n_b.pop():,} per "
        "value of B_r; the bands of the pooled plots are mostly the spread between "
        "scenarios; no interval where every deviation is 0):"
    )


def sensitivity_success_n() -> str:
    """The caption of the success table: the cells with a robot force and their n."""
    e = sensitivity.episodes()
    forced = e["a_robot"] > 0
    cells = len({(x, y) for x, y in zip(e["a_robot"][forced], e["b_robot"][forced], strict=True)})
    n = {_per(forced & (e["scenario"] == s)) for s in sensitivity.scenarios()}
    if len(n) != 1:
        raise SystemExit("docs/sensitivity.md: scenarios hold different numbers of episodes")
    return prose(
        f"Success rate per scenario over the {cells} cells with A_r > 0 ({n.pop():,} "
        "episodes per planner and scenario):"
    )


# -- docs/metrics.md ------------------------------------------------------------------

CONVERGENCE: Final = DOCS / "convergence" / "frechet.csv"
ATTRIBUTION: Final = "attribution/paper.json"
STEPS: Final = {"frechet_sub1": "dt", "frechet_sub2": "dt/2", "frechet_sub4": "dt/4"}


def _seeds(seeds: list[int]) -> str:
    if seeds != list(range(seeds[0], seeds[-1] + 1)):
        raise SystemExit("docs/metrics.md: the seeds are not a range: rewrite the sentence")
    return f"{seeds[0]}–{seeds[-1]}"


def convergence_design() -> str:
    """What the convergence tables hold: the suite's seeds, planners and crowd steps, and
    the episodes per step (docs/convergence/frechet.csv, one row per episode)."""
    if not CONVERGENCE.is_file():
        raise MissingDataError("data file `docs/convergence/frechet.csv`")
    with CONVERGENCE.open(encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    steps = [STEPS[c] for c in rows[0] if c in STEPS]
    seeds = sorted({int(r["seed"]) for r in rows})
    planners = sorted({r["planner"] for r in rows})
    return prose(
        "Measured on the paper suite (when and on which commit: under the tables), seeds "
        f"{_seeds(seeds)}, the {_word(len(planners))} default planners, at "
        f"{', '.join(steps[:-1])} and {steps[-1]} ({len(steps)} × {len(rows):,} episodes; "
        "the relative change of a quantity q is (q(dt) − q(dt/4)) / |q(dt/4)|):"
    )


def attribution_design() -> str:
    """What the attribution tables hold (docs/attribution/paper.json)."""
    doc = _json(ATTRIBUTION)
    planners, seeds, scenarios = doc["planners"], doc["seeds"], doc["scenarios"]
    n = seeds[1] - seeds[0] + 1 if len(seeds) == 2 else len(seeds)
    extra = [p for p in planners if p in ("oracle", "stay")]
    default = len(planners) - len(extra)
    return prose(
        f"{_word(len(scenarios)).capitalize()} scenarios × {_word(len(planners))} planners "
        f"(the {_word(default)} default ones, `straight`'s reference partner `oracle`, and "
        f"`stay`) × {n} seeds, the default step; n = {n} seeds per cell, the floor once per "
        "(scenario, seed):"
    )


# -- docs/model.md --------------------------------------------------------------------

PRESET_COLUMNS: Final = (
    ("A_p", "a_ped"),
    ("B_p (m)", "b_ped"),
    ("λ", "lambda_ped"),
    ("τ (s)", "tau"),
    ("A_r", "a_robot"),
    ("B_r (m)", "b_robot"),
    ("λ_r", "lambda_robot"),
    ("A_o", "a_obs"),
    ("B_o (m)", "b_obs"),
)
"""The paper's nine fields, in the order of its Table 1 (strengths in m/s²)."""


def _form(p: SRFMParams) -> str:
    d = p.as_dict()
    if p.robot_form == "exponential":
        return "exponential"
    paper = set(dict(PRESET_COLUMNS).values()) | {"robot_form"}
    own = [f"`{k}` = {float(v):.3g}" for k, v in d.items() if k not in paper]
    return f"{p.robot_form} ({', '.join(own)})"


def model_presets() -> str:
    """The presets' parameters, read from the presets srfm ships."""
    default = SRFMParams()
    lines = [
        "| preset | " + " | ".join(h for h, _ in PRESET_COLUMNS) + " | robot force |",
        "|---|" + "--:|" * len(PRESET_COLUMNS) + "---|",
    ]
    for name, p in PRESETS.items():
        label = f"`{name}`" + (" (default)" if p == default else "")
        cells = [f"{float(getattr(p, f)):.3g}" for _, f in PRESET_COLUMNS]
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {_form(p)} |")
    return "\n".join(lines)


BLOCKS: dict[str, Callable[[], str]] = {
    "fitting-horizon-pass": fitting_horizon_pass,
    "encounters-track-end-cache": encounters_track_end_cache,
    "sensitivity-design": sensitivity_design,
    "sensitivity-pooled-n": sensitivity_pooled_n,
    "sensitivity-success-n": sensitivity_success_n,
    "model-presets": model_presets,
    "convergence-design": convergence_design,
    "attribution-design": attribution_design,
}
