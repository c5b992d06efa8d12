"""The generated blocks of the pages on real data: docs/robot_response.md,
docs/fitting.md, docs/real_encounters.md and docs/sensitivity.md.

Each block renders a table (or a sentence) from a committed data file that the page's
own command wrote (``tools/fitting/*.py``, ``srfm sweep``); nothing is computed here
but formatting, the selection of rows and, where said, a count or a mean over the
committed numbers. ``tools/results/generate.py`` registers them (``BLOCKS``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from decimal import ROUND_HALF_UP, Decimal
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from tools.fitting import cap_diagnostic, fit_navwareset, navwareset_compliance

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
MINUS = "\u2212"


@cache
def _json(rel: str) -> Any:
    """A committed JSON file under docs/."""
    return json.loads((DOCS / rel).read_text(encoding="utf-8"))


def signed(x: float, digits: int) -> str:
    """``x`` with its sign always written, the minus as U+2212: ``+0.12``, ``−0.05``."""
    return f"{x:+.{digits}f}".replace("-", MINUS)


def num(x: float, spec: str) -> str:
    """``x`` formatted by ``spec``, a negative sign as U+2212."""
    return format(x, spec).replace("-", MINUS)


def pct(rel: float, ci: Sequence[float], digits: int = 1) -> str:
    """A relative change and its interval in %: ``−6.6 % (−10.6 to −3.8)``."""
    lo, hi = ci
    return (
        f"{signed(100 * rel, digits)} % ({signed(100 * lo, digits)} to "
        f"{signed(100 * hi, digits)})"
    )


def p_value(p: float) -> str:
    """A p-value as the fitting pages write it: ``< 0.001``, else three decimals."""
    return "–" if not math.isfinite(p) else "< 0.001" if p < 0.001 else f"{p:.3f}"


# -- docs/robot_response.md (tools/fitting/fit_response.py --stage tests) ---------------

RESPONSE = "robot_response/results.json"
RESPONSE_SETS = {"hsr": "HSR", "jackal": "Jackal", "pooled": "pooled"}
RESPONSE_MODELS = {
    "sidestep": "**sidestep (fitted, held out)**",
    "robot_as_pedestrian": "robot as a pedestrian",
    "no_overlap": "no overlap (contact only)",
    "ttc": "time-to-collision force at defaults",
    "agrawal2024": "`agrawal2024` (the paper's preset)",
}


def _response_rows() -> dict[tuple[str, str, str], dict[str, Any]]:
    """Every test row of the response fit by (model, set, measure)."""
    t = _json(RESPONSE)["tests"]
    return {
        (r["model"], r["set"], r["measure"]): r
        for family in ("decisive", "ade", "secondary")
        for r in t[family]
    }


def response_decisive() -> str:
    """The decisive table and the baselines: every model against robot ignored."""
    rows = _response_rows()
    t = _json(RESPONSE)["tests"]
    lines = [
        "**The decisive table and the baselines** (held out: each scene predicted by the fit "
        "that did not see it, with the pedestrian part that did not see it; change = mean "
        "error of the model / robot ignored − 1, 95 % bootstrap interval over scenes; p: "
        "Wilcoxon signed-rank over the scenes' mean errors; the sidestep's p are Holm over "
        f"the decisive family's {len(t['decisive'])} rows, the others' Holm over the "
        f"secondary family's {len(t['secondary'])} rows):",
        "",
        "| model | robot | n (windows / tracks / scenes) | ADE (m) | ADE change | "
        "\\|pass-distance error\\| (m) | pass change | p (Holm) | \\|path-offset error\\| (m) "
        "| offset change | p (Holm) |",
        "|---|---|---|--:|---|--:|---|--:|--:|---|--:|",
    ]
    for s, label in RESPONSE_SETS.items():
        base = rows["sidestep", s, "ade"]
        n = f"{base['n_windows']} / {base['n_tracks']} / {base['n_scenes']}"
        ignored = [
            f"{rows['sidestep', s, m]['base_m']:.3f}" for m in ("ade", "pass", "offset")
        ]
        lines.append(
            f"| robot ignored | {label} | {n} | {ignored[0]} | – | {ignored[1]} | – | – "
            f"| {ignored[2]} | – | – |"
        )
        for model, name in RESPONSE_MODELS.items():
            a, ps, of = (rows[model, s, m] for m in ("ade", "pass", "offset"))
            lines.append(
                f"| {name} | {label} | {n} | {a['model_m']:.3f} | {pct(a['rel'], a['ci95'])} "
                f"| {ps['model_m']:.3f} | {pct(ps['rel'], ps['ci95'])} | "
                f"{p_value(ps['p_holm'])} | {of['model_m']:.3f} | {pct(of['rel'], of['ci95'])} "
                f"| {p_value(of['p_holm'])} |"
            )
    return "\n".join(lines)


def _rise(r: dict[str, Any]) -> tuple[float, float]:
    """The profile's cost above the minimum, lowest and highest, in % of the minimum."""
    rise = (np.asarray(r["costs"]) - r["min_cost"]) / r["min_cost"] * 100
    return float(rise.min()), float(rise.max())


def response_parameters() -> str:
    """The full fits' parameters, the ends of their starts and the profiles' verdicts."""
    lines = [
        "| robot | n (windows / scenes) | parameter | fit | status | ends of the 9 starts "
        "(min / median / max) | profile cost above the minimum |",
        "|---|---|---|--:|---|---|---|",
    ]
    for r in _json(RESPONSE)["parameters"]:
        ends = np.asarray(r["starts_end"])
        lo, hi = _rise(r)
        status = "**identified**" if r["status"] == "identified" else r["status"]
        lines.append(
            f"| {RESPONSE_SETS[r['set']]} | {r['n_windows']} / {r['n_scenes']} | "
            f"`{r['field']}` | {num(r['fitted'], '.3g')} | {status} | "
            f"{num(ends.min(), '.3g')} / {num(float(np.median(ends)), '.3g')} / "
            f"{num(ends.max(), '.3g')} | {lo:.2f}–{hi:.2f} % |"
        )
    return "\n".join(lines)


# -- docs/fitting.md (tools/fitting/fit_navwareset.py, navwareset_compliance.py) -------

NAVWARESET = "fitting_navwareset.json"
NAVWARESET_AGRAWAL = "fitting_navwareset_agrawal.json"
OVERALL = frozenset({"all", "hsr", "jackal", "compliant", "non-compliant"})


def fitting_conditions() -> str:
    """The robot part per condition, ETH/UCY pedestrian part held."""
    return "\n".join(fit_navwareset.conditions_lines(_json(NAVWARESET)))


def _scene_level_caption(payload: dict[str, Any]) -> str:
    n = {t["n"] for t in payload["scene_level"].values()}
    return (
        "Scene level (each scene's mean ADE over its interaction test windows; Wilcoxon "
        f"over the {', '.join(map(str, sorted(n)))} scenes):"
    )


def fitting_table2() -> str:
    """Table 2 on held-out scenes, its scene-level test and the folds' range."""
    payload = _json(NAVWARESET)
    return "\n\n".join(
        [
            "\n".join(fit_navwareset.table2_lines(payload)),
            _scene_level_caption(payload),
            "\n".join(fit_navwareset.scene_level_lines(payload)),
            "\n".join(fit_navwareset.folds_lines(payload)),
        ]
    )


def fitting_agrawal() -> str:
    """The same on top of agrawal2024's pedestrian part: Table 2's overall cells, the
    scene-level test and the per-condition fits."""
    payload = _json(NAVWARESET_AGRAWAL)
    return "\n\n".join(
        [
            "\n".join(fit_navwareset.table2_lines(payload, OVERALL)),
            "\n".join(fit_navwareset.scene_level_lines(payload)),
            "\n".join(fit_navwareset.conditions_lines(payload)),
        ]
    )


def fitting_compliance() -> str:
    """Compliant against non-compliant recordings, replayed from the walking start."""
    return "\n".join(navwareset_compliance.replay_lines(_json(COMPLIANCE)["rows"]))


def fitting_compliance_episodes() -> str:
    """The same through the benchmark's twin episode of each recording."""
    doc = _json(COMPLIANCE_EPISODES)
    return "\n".join(navwareset_compliance.episodes_lines(doc["episodes"]))


COMPLIANCE = "fitting_compliance.json"
COMPLIANCE_EPISODES = "fitting_compliance_episodes.json"

# -- docs/real_encounters.md (tools/fitting/real_encounters.py, fit_forms.py,
#    cap_diagnostic.py) ---------------------------------------------------------------

ENCOUNTERS = "real_encounters/results.json"
FORMS = "real_encounters/forms_heading.json"
CAP = "real_encounters/cap_diagnostic.json"


def fixed(x: float, digits: int, *, sign: bool = False) -> str:
    """``x`` rounded half up to ``digits`` decimals (the committed JSON keeps 6
    significant digits, so a tie there was above it before), minus as U+2212."""
    q = Decimal(repr(float(x))).quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_UP)
    text = f"{q:+f}" if sign else f"{q:f}"
    return text.replace("-", MINUS)


def _n3(n: dict[str, int]) -> str:
    return f"{n['rows']:,} / {n['tracks']:,} / {n['scenes']:,}"


def _est(s: dict[str, Any], digits: int = 3) -> str:
    """An estimate and its interval: ``−0.149 (−0.227 to −0.077)``."""
    lo, hi = s["ci"]
    return (
        f"{fixed(s['est'], digits, sign=True)} ({fixed(lo, digits, sign=True)} to "
        f"{fixed(hi, digits, sign=True)})"
    )


def _p2(p: float | None) -> str:
    """Two significant digits, ``< 0.001`` below it, ``–`` for none."""
    if p is None or not math.isfinite(p):
        return "–"
    return "< 0.001" if p < 0.001 else f"{p:.2g}"


def _range(o: dict[str, Any], digits: int = 2, key: str = "x_on") -> str:
    lo, hi = o[f"{key}_ci"]
    return f"{fixed(o[key], digits)} ({fixed(lo, digits)}–{fixed(hi, digits)})"


POPULATIONS = {
    "robot samples": "robot samples (walking, the robot the nearest known agent)",
    "pedestrian samples": "pedestrian samples (another participant the nearest)",
    "baseline samples": "baseline samples (no known agent within 4 m)",
    "robot encounters": "robot encounters",
    "pedestrian encounters": "pedestrian encounters (ordered pairs)",
    "baseline stretches (3 s)": "baseline stretches (3 s, no one within 4 m)",
}


def encounters_n() -> str:
    """How many samples, encounters, tracks and scenes each population has."""
    n = _json(ENCOUNTERS)["part1"]["n"]
    lines = ["| population | rows | tracks | scenes |", "|---|--:|--:|--:|"]
    for key, label in POPULATIONS.items():
        r = n[key]
        lines.append(f"| {label} | {r['rows']:,} | {r['tracks']:,} | {r['scenes']:,} |")
    r = n["all (rows: recordings)"]
    lines.append(f"| all: {r['rows']:,} recordings | | {r['tracks']:,} | {r['scenes']:,} |")
    return "\n".join(lines)


def _test_label(text: str) -> str:
    return text.replace("<=", "≤").replace("ratio - 1", "ratio − 1")


def encounters_confirmatory() -> str:
    """The confirmatory family (Holm over its 8 tests) and the confirmatory onsets."""
    part1 = _json(ENCOUNTERS)["part1"]
    lines = [
        "| # | test | estimate (95 % CI) | n (rows / tracks / scenes) | p | p (Holm) |",
        "|--:|---|---|---|--:|--:|",
    ]
    for i, t in enumerate(part1["confirmatory"]["tests"], 1):
        n = t["n"]
        ns = _n3(n) if "rows" in n else " and ".join(_n3(v) for v in n.values())
        digits = 1 if "(deg)" in t["test"] else 3
        lines.append(
            f"| {i} | {_test_label(t['test'])} | {_est(t, digits)} | {ns} | {_p2(t['p'])} "
            f"| {_p2(t['p_holm'])} |"
        )
    robot = part1["curves"]["robot"]
    od, ot = robot["onset_d"], robot["onset_tstar"]
    lines += [
        "",
        "Confirmatory onsets (hinge of a_away over all approaching robot samples): "
        f"d_on = {_range(od)} m, slope {fixed(od['slope'], 2)} m/s² per m; "
        f"t*_on = {_range(ot)} s on a collision course, slope {fixed(ot['slope'], 2)} m/s² "
        "per s; both the onset of the *return* phase (see the deviations).",
    ]
    return "\n".join(lines)


AWAY_ROWS = {
    "robot": "robot",
    "HSR": "HSR",
    "Jackal": "Jackal",
    "compliant": "compliant",
    "non-compliant": "non-compliant",
    "pedestrian": "pedestrian",
    "frontal_approach": "frontal approach",
    "perpendicular_crossing": "perpendicular crossing",
}


def encounters_away() -> str:
    """The away phase and the steering magnitude, the rows the page selects."""
    curves = _json(ENCOUNTERS)["part1"]["curves"]
    lines = [
        "| samples | n, d* ≤ 1 m (rows / tracks / scenes) | away phase: onset t* (s) | peak "
        "a_away (m/s²) | at t* (s) | \\|a_n\\| onset d (m) | \\|a_n\\| onset t* (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for key, label in AWAY_ROWS.items():
        c = curves[key]
        pk = c["peak_avoid"]
        lo, hi = pk["value_ci"]
        lines.append(
            f"| {label} | {_n3(c['n_course'])} | {_range(c['onset_tstar_avoid'])} | "
            f"{fixed(pk['value'], 3, sign=True)} ({fixed(lo, 3)}–{fixed(hi, 3)}) | "
            f"{_range(pk, key='at')} | {_range(c['onset_abs_a_n_d'])} | "
            f"{_range(c['onset_abs_a_n_tstar'])} |"
        )
    return "\n".join(lines)


EVENT_CELLS = {
    "robot, all": "robot, all",
    "hsr compliant": "HSR compliant",
    "hsr non-compliant": "HSR non-compliant",
    "jackal compliant": "Jackal compliant",
    "jackal non-compliant": "Jackal non-compliant",
    "frontal approach / hsr": "frontal approach / HSR",
    "frontal approach / jackal": "frontal approach / Jackal",
    "blind corner / hsr": "blind corner / HSR",
    "blind corner / jackal": "blind corner / Jackal",
    "perpendicular crossing / hsr": "perpendicular crossing / HSR",
    "circular crossing / hsr": "circular crossing / HSR",
    "circular crossing / jackal": "circular crossing / Jackal",
    "pedestrian (circular crossing)": "pedestrian (circular crossing)",
}


def encounters_events() -> str:
    """The event measures per cell (every cell but the small ones the page names)."""
    rows = {r["cell"]: r for r in _json(ENCOUNTERS)["part1"]["event_table"]["rows"]}
    lines = [
        "| cell | n (enc. / tracks / scenes) | path offset (m) | p (Holm) | heading change (deg) "
        "| p (Holm) | speed change | p (Holm) | pass distance (m) | d*_ref (m) |",
        "|---|---|---|--:|---|--:|---|--:|--:|--:|",
    ]
    for key, label in EVENT_CELLS.items():
        r = rows[key]
        lines.append(
            f"| {label} | {_n3(r['n'])} | {_est(r['offset'])} | "
            f"{_p2(r['offset'].get('p_holm'))} | {_est(r['heading'], 1)} | "
            f"{_p2(r['heading'].get('p_holm'))} | {_est(r['speed_change'])} | "
            f"{_p2(r['speed_change'].get('p_holm'))} | {fixed(r['d_pass']['est'], 2)} | "
            f"{fixed(r['dstar_ref']['est'], 2)} |"
        )
    return "\n".join(lines)


RECOVERY_DATA = {
    "12": "12 recorded robots (the excerpt; the test of docs/fitting.md)",
    "91": "91 recorded robots, frontal approach",
    "343": "343 recorded robots (every format-1 recording)",
    "6": "6 synthetic scenes, two streams and a robot",
}
CURRENT = "every 1.2 s, goal = track end (the current protocol)"
RECOVERY_ROWS = (
    ("12", CURRENT, "12 recorded robots (the test)", "every 1.2 s, goal = track end (current)"),
    ("12", "encounter, lead 3 s, goal = track end", "12 recorded robots", None),
    ("12", "encounter, lead 3 s, goal = heading", "12 recorded robots", "**"),
    ("91", CURRENT, "91 recorded robots, frontal approach", "every 1.2 s, goal = track end"),
    ("91", "encounter, lead 3 s, goal = track end", "91 recorded robots, frontal approach", None),
    ("91", "encounter, lead 3 s, goal = heading", "91 recorded robots, frontal approach", "**"),
    ("343", CURRENT, "343 recorded robots (every format-1 recording)", "every 1.2 s, goal = track end"),
    ("343", "encounter, lead 2 s, goal = heading", "343 recorded robots", None),
    ("343", "encounter, lead 3 s, goal = heading", "343 recorded robots", None),
    ("343", "encounter, lead 3 s, goal = track end", "343 recorded robots", None),
    ("6", CURRENT, "6 synthetic two-stream scenes", "every 1.2 s, goal = track end"),
    ("6", "encounter, lead 3 s, goal = heading", "6 synthetic two-stream scenes", None),
)
"""The rows of the recovery table the page shows: (data, windows, the page's data
label, the page's windows label, or None for the windows as recorded, or ``**`` for
them in bold with the fitted parameters)."""


def encounters_recovery() -> str:
    """Recovery of a known response: the selected rows of the 49."""
    part2 = _json(ENCOUNTERS)["part2"]
    rows = {(r["data"], r["windows"]): r for r in part2["recovery"]}
    lines = [
        "| data | windows | n (windows / tracks) | A_r | B_r (m) | λ_r | ADE / FDE (m) "
        "| \\|pass-distance error\\| (m) | \\|path-offset error\\| (m) | robot ignored: "
        "ADE, \\|pass\\|, \\|offset\\| (m) |",
        "|---|---|---|--:|--:|--:|---|--:|--:|---|",
    ]
    for data, windows, label, shown in RECOVERY_ROWS:
        r = rows[RECOVERY_DATA[data], windows]
        f, e, i = r["fitted"], r["errors_fitted"], r["errors_ignored"]
        bold = "**" if shown == "**" else ""
        w = f"**{windows}**" if bold else windows if shown is None else shown
        params = [fixed(f["a_robot"], 2), fixed(f["b_robot"], 3), fixed(f["lambda_robot"], 2)]
        lines.append(
            f"| {label} | {w} | {r['n']:,} / {r['tracks']:,} | "
            + " | ".join(f"{bold}{v}{bold}" for v in params)
            + f" | {fixed(e['ade'], 3)} / {fixed(e['fde'], 3)} | "
            f"{fixed(e['pass_distance_abs'], 3)} | {fixed(e['path_offset_abs'], 3)} | "
            f"{fixed(i['ade'], 3)}, {fixed(i['pass_distance_abs'], 3)}, "
            f"{fixed(i['path_offset_abs'], 3)} |"
        )
    return "\n".join(lines)


PUBLISHED_ROWS = (
    ("heading", "constant velocity", "constant velocity"),
    ("heading", "robot ignored (agrawal2024 pedestrian part)", "robot ignored"),
    ("heading", "robot as pedestrian", "robot as pedestrian"),
    ("heading", "SRFM agrawal2024", "SRFM `agrawal2024`"),
    ("heading", "SRFM navwareset2025 robot part", "SRFM, `navwareset2025` robot part"),
    ("track_end", "robot ignored (agrawal2024 pedestrian part)", "robot ignored"),
    ("track_end", "robot as pedestrian", "robot as pedestrian"),
    ("track_end", "SRFM agrawal2024", "SRFM `agrawal2024`"),
)


def encounters_published() -> str:
    """The published parameter sets on the real encounter windows (both robots)."""
    rows = {(r["goal"], r["model"]): r for r in _json(ENCOUNTERS)["part2"]["real"]
            if r["robot"] == "all"}
    lines = [
        "| goal | model | ADE (m) | FDE (m) | \\|pass-distance error\\| (m) | pass-distance "
        "bias (m) | \\|path-offset error\\| (m) |",
        "|---|---|--:|--:|--:|--:|--:|",
    ]
    for goal, model, label in PUBLISHED_ROWS:
        r = rows[goal, model]
        lines.append(
            f"| {goal.replace('_', ' ')} | {label} | {fixed(r['ade'], 3)} | {fixed(r['fde'], 3)} "
            f"| {fixed(r['pass_distance_abs'], 3)} | {fixed(r['pass_distance_bias'], 3, sign=True)} "
            f"| {fixed(r['path_offset_abs'], 3)} |"
        )
    return "\n".join(lines)


FORM_LABELS = {
    "exponential": "exponential (paper)",
    "ttc": "time to collision",
    "collision_prediction": "collision prediction",
}


def _verdict(ade: dict[str, Any], pass_: dict[str, Any]) -> str:
    won = [m for m, r in (("ADE", ade), ("pass", pass_)) if r["success"]]
    if won:
        return f"**success** ({', '.join(won)})"
    va, vp = (
        "equivalent" if r["equivalent"] else "inconclusive" for r in (ade, pass_)
    )
    return va if va == vp else f"ADE {va}, pass {vp}"


def _form_p(p: float) -> str:
    if not math.isfinite(p):
        return "–"
    return "< 0.001" if p < 0.001 else f"{p:.3f}" if p < 0.1 else f"{p:.2f}"


def forms_decisive() -> str:
    """The decisive table of part 4: each form against robot ignored, held out."""
    rows = {(r["form"], r["set"], r["measure"]): r for r in _json(FORMS)["tests"]["decisive"]}
    lines = [
        "| form | robot | n (windows / tracks / scenes) | ADE (m): form / robot ignored | ADE "
        "change | p (Holm) | \\|pass-distance error\\| (m): form / ignored | pass change | "
        "p (Holm) | verdict |",
        "|---|---|---|---|---|--:|---|---|--:|---|",
    ]
    for form, label in FORM_LABELS.items():
        for s, robot in RESPONSE_SETS.items():
            a, b = rows[form, s, "ade"], rows[form, s, "pass"]

            def cells(r: dict[str, Any]) -> tuple[str, str]:
                lo, hi = r["ci95"]
                change = f"{signed(100 * r['rel'], 1)} %"
                p = _form_p(r["p_holm"])
                if r["success"]:
                    change, p = f"**{change}**", f"**{p}**"
                return f"{change} ({signed(100 * lo, 1)} to {signed(100 * hi, 1)})", p

            (ca, pa), (cb, pb) = cells(a), cells(b)
            lines.append(
                f"| {label} | {robot} | {a['n_windows']} / {a['n_tracks']} / {a['n_scenes']} | "
                f"{a['model_m']:.3f} / {a['base_m']:.3f} | {ca} | {pa} | "
                f"{b['model_m']:.3f} / {b['base_m']:.3f} | {cb} | {pb} | {_verdict(a, b)} |"
            )
    return "\n".join(lines)


PARAMETER_NAMES = {
    "a_robot": ("A_r", "m/s²"),
    "b_robot": ("B_r", "m"),
    "lambda_robot": ("λ_r", ""),
    "ttc_k": ("k", "m²"),
    "ttc_tau0": ("τ0", "s"),
    "cp_a": ("A", ""),
    "cp_b": ("B", "m"),
}


def forms_parameters() -> str:
    """Each form's robot part fitted on all the set's scenes, with its bootstrap
    interval (100 resamples over scenes)."""
    lines = [
        "| form | robot | n (windows / tracks / scenes) | parameters (95 % interval) |",
        "|---|---|---|---|",
    ]
    for r in _json(FORMS)["parameters"]:
        if r["form"] not in FORM_LABELS:
            continue
        parts = []
        for f, v in r["fitted"].items():
            name, unit = PARAMETER_NAMES[f]
            lo, hi = r["ci95"][f]
            parts.append(
                f"{name} = {num(v, '.3g')}{' ' + unit if unit else ''} "
                f"({num(lo, '.2g')}–{num(hi, '.2g')})"
            )
        lines.append(
            f"| {FORM_LABELS[r['form']].removesuffix(' (paper)')} | {RESPONSE_SETS[r['set']]} | "
            f"{r['windows']} / {r['tracks']} / {r['scenes']} | {', '.join(parts)} |"
        )
    return "\n".join(lines)


def cap_diagnostic_block() -> str:
    """The cap diagnostic: every encounter window, k and the cap varied, in-sample."""
    return cap_diagnostic.table_text(_json(CAP)).strip()


BLOCKS: dict[str, Callable[[], str]] = {
    "encounters-n": encounters_n,
    "encounters-confirmatory": encounters_confirmatory,
    "encounters-away": encounters_away,
    "encounters-events": encounters_events,
    "encounters-recovery": encounters_recovery,
    "encounters-published": encounters_published,
    "forms-decisive": forms_decisive,
    "forms-parameters": forms_parameters,
    "cap-diagnostic": cap_diagnostic_block,
    "fitting-conditions": fitting_conditions,
    "fitting-table2": fitting_table2,
    "fitting-agrawal": fitting_agrawal,
    "fitting-compliance": fitting_compliance,
    "fitting-compliance-episodes": fitting_compliance_episodes,
    "response-decisive": response_decisive,
    "response-parameters": response_parameters,
}
