"""Part 4 of issue 28: fit and test each robot-force form on real NavWareSet encounters.

The protocol is docs/real_encounters.md, "Part 4" (written before any held-out result):
leave one scene out, per robot (HSR, Jackal) and pooled, the pedestrian part fitted on
NavWareSet's own non-interaction windows, every form against "robot ignored" and
"robot as a pedestrian" on the encounter windows (lead 3 s, goal straight ahead).

    PYTHONPATH=. nice -n 5 .venv/bin/python tools/fitting/fit_forms.py               # primary
    PYTHONPATH=. nice -n 5 .venv/bin/python tools/fitting/fit_forms.py --goal track_end

Resumable: every fit (a fold's pedestrian part, a fold's robot part of a form and set,
a full fit, a bootstrap resample) is stored in ``--cache`` as it finishes (one JSON file,
rewritten atomically) and not recomputed by the next run; a cache made under another
protocol (data, windows, forms, seeds) is refused. Writes ``forms_<goal>.json`` (every
number, with its n) and ``forms_<goal>.md`` (the tables) into ``--out``, and prints the
tables. Deterministic: the bootstraps draw from fixed seeds.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from srfm._version import __version__
from srfm.datasets.navwareset import drop_supersets, read_navwareset
from srfm.fitting import (
    EVAL_WINDOWS,
    FIT_WINDOWS,
    ROBOT_FIELDS,
    SceneGroups,
    WindowConfig,
    Windows,
    build_windows,
    displacement_errors,
    fit_params,
    holm,
    paired_test,
    pass_errors,
    predict,
    scene_groups,
)
from srfm.models import SRFMParams, save_params
from srfm.models.params import FORM_FIELDS

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tools.results.record import run_record, start  # noqa: E402

PED_FIELDS = ("a_ped", "b_ped", "lambda_ped", "tau")
LEAD_S = 3.0
N_BOOT_ERR = 2000  # bootstrap of the held-out errors over scenes
SEED_ERR = 2028
N_BOOT_PAR = 100  # bootstrap of the parameters (one fit each)
SEED_PAR = 2029
SUCCESS = {"ade": 0.05, "pass": 0.10}  # the margins (relative improvement)


class Form(NamedTuple):
    """A robot-force form: what it sets in the parameters, what a fit varies, further
    starting points (changes to the form's defaults) and whether it is in the decisive
    family of the protocol."""

    changes: dict[str, Any]
    fields: tuple[str, ...]
    label: str
    starts: tuple[dict[str, float], ...] = ()
    decisive: bool = True


_DEFAULT = SRFMParams()
FORMS: dict[str, Form] = {
    "exponential": Form({}, ROBOT_FIELDS, "exponential distance (paper)"),
    "ttc": Form(
        {"robot_form": "ttc"},
        ("ttc_k", "ttc_tau0"),
        "time to collision (Karamouzas 2014)",
        starts=({"ttc_k": 0.1 * _DEFAULT.ttc_k},),
    ),
    "collision_prediction": Form(
        {"robot_form": "collision_prediction"},
        ("cp_a", "cp_b"),
        "collision prediction (Zanlungo 2011)",
        starts=({"cp_a": 0.1 * _DEFAULT.cp_a},),
    ),
    "elliptical": Form(
        {"robot_form": "elliptical"},
        ("ell_a", "ell_b", "ell_dt"),
        "elliptical (Johansson 2007; exploratory)",
        starts=({"ell_a": 0.1 * _DEFAULT.ell_a},),
        decisive=False,
    ),
}
SETS: dict[str, Callable[[str], bool]] = {
    "hsr": lambda robot: robot == "hsr",
    "jackal": lambda robot: robot == "jackal",
    "pooled": lambda robot: True,
}
FORCE_NAMES = {
    "exponential": "exponential distance",
    "ttc": "time-to-collision",
    "collision_prediction": "collision-prediction",
    "elliptical": "elliptical",
}
SET_LABELS = {"hsr": "HSR", "jackal": "Jackal", "pooled": "pooled"}
MEASURES = {
    "ade": "ADE",
    "fde": "FDE",
    "pass": "\\|pass-distance error\\|",
    "offset": "\\|path-offset error\\|",
}
BASELINES = {
    "constant_velocity": "constant velocity",
    "sfm": "robot ignored",
    "robot_as_pedestrian": "robot as pedestrian",
}

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def encounter_config(goal: str) -> WindowConfig:
    return WindowConfig(align="encounter", lead_s=LEAD_S, goal=goal, min_start_speed_mps=0.3)


# --------------------------------------------------------------------------------------
# The cache


class Cache:
    """Fit results by key, in one JSON file rewritten atomically after every put."""

    def __init__(self, path: Path, protocol: dict[str, Any]) -> None:
        self.path = path
        self.protocol = protocol
        self.entries: dict[str, Any] = {}
        if path.exists():
            data = json.loads(path.read_text())
            if data.get("protocol") != protocol:
                raise SystemExit(
                    f"{path} was made under another protocol; remove it or pass another "
                    f"--cache (cached: {data.get('protocol')}, now: {protocol})"
                )
            self.entries = data["entries"]
            log(f"cache {path}: {len(self.entries)} entries")

    def get(self, key: str, compute: Callable[[], Any]) -> Any:
        if key not in self.entries:
            t0 = time.perf_counter()
            value = compute()
            self.entries[key] = value
            self._write()
            log(f"{key}: {time.perf_counter() - t0:.1f} s")
        return self.entries[key]

    def _write(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_suffix(".tmp")
        payload = {"protocol": self.protocol, "entries": self.entries}
        tmp.write_text(json.dumps(payload, indent=0, sort_keys=True) + "\n")
        os.replace(tmp, self.path)


def params_of(d: dict[str, Any]) -> SRFMParams:
    return SRFMParams().replace(**d)


def as_dict(p: SRFMParams) -> dict[str, Any]:
    return {k: (float(v) if isinstance(v, float) else v) for k, v in p.as_dict().items()}


# --------------------------------------------------------------------------------------
# The fits


class Data(NamedTuple):
    ped: Windows  # non-interaction windows (pedestrian part)
    enc: Windows  # encounter windows
    g_ped: SceneGroups
    g_enc: SceneGroups
    tested: list[int]  # scenes with encounter windows
    sets: dict[str, list[int]]  # scenes of each robot set


def load(root: Path, goal: str) -> Data:
    scenes, dropped = drop_supersets(read_navwareset(root))
    log(f"{len(scenes)} recordings (dropped {', '.join(dropped) or 'none'})")
    ped = build_windows(scenes, FIT_WINDOWS)
    enc = build_windows(scenes, encounter_config(goal))
    g_ped, g_enc = scene_groups(ped, scenes), scene_groups(enc, scenes)
    if g_ped.keys != g_enc.keys:
        raise SystemExit("the two window sets group the scenes differently")
    tested = sorted({int(g) for g in g_enc.of_window})
    sets = {name: [g for g in tested if pred(g_enc.robot[g])] for name, pred in SETS.items()}
    log(
        f"{int((~ped.interaction).sum())} non-interaction windows; {enc.n_windows} encounter "
        f"windows in {len(tested)} scenes ({', '.join(f'{k} {len(v)}' for k, v in sets.items())})"
    )
    return Data(ped, enc, g_ped, g_enc, tested, sets)


def fit_pedestrian(data: Data, held: int | None) -> dict[str, Any]:
    keep = [g for g in range(data.g_ped.n_groups) if g != held]
    sel = data.g_ped.windows_of(keep)
    result = fit_params(
        data.ped, start=SRFMParams.preset("agrawal2024"), stages=("pedestrian",), subset=sel
    )
    stage = result.stages[0]
    return {
        "params": {f: getattr(result.params, f) for f in PED_FIELDS},
        "windows": stage.n_windows,
        "tracks": stage.n_tracks,
        "ade_m": stage.ade_m,
    }


def with_form(ped: dict[str, Any], form: Form) -> SRFMParams:
    return SRFMParams.preset("agrawal2024").replace(**ped["params"]).replace(**form.changes)


def fit_robot(data: Data, base: SRFMParams, form: Form, scenes: Sequence[int]) -> dict[str, Any]:
    result = fit_params(
        data.enc,
        start=base,
        stages=("robot",),
        fields={"robot": form.fields},
        subset=data.g_enc.windows_of(scenes),
        extra_starts=[base.replace(**start) for start in form.starts],
    )
    stage = result.stages[0]
    return {
        "fitted": stage.fitted,
        "windows": stage.n_windows,
        "tracks": stage.n_tracks,
        "ade_m": stage.ade_m,
        "success": stage.success,
    }


def run_fits(data: Data, cache: Cache, goal: str, n_boot: int) -> dict[str, Any]:
    """Every fit of the protocol, from the cache where it is there."""
    g_key = data.g_enc.keys
    ped_all = cache.get("ped/all", lambda: fit_pedestrian(data, None))
    ped_fold = {
        g: cache.get(f"ped/without/{g_key[g]}", lambda g=g: fit_pedestrian(data, g))
        for g in data.tested
    }
    robot: dict[str, Any] = {}
    for form_name, form in FORMS.items():
        spec = json.loads(json.dumps([form.changes, list(form.fields), list(form.starts)]))
        if cache.get(f"form/{form_name}", lambda spec=spec: spec) != spec:
            raise SystemExit(f"the cache holds another definition of the form {form_name}")
        for set_name, members in data.sets.items():
            prefix = f"{goal}/{form_name}/{set_name}"
            full = cache.get(
                f"{prefix}/all",
                lambda f=form, m=members: fit_robot(data, with_form(ped_all, f), f, m),
            )
            folds = {
                g: cache.get(
                    f"{prefix}/without/{g_key[g]}",
                    lambda f=form, m=members, g=g: fit_robot(
                        data, with_form(ped_fold[g], f), f, [x for x in m if x != g]
                    ),
                )
                for g in members
            }
            robot[f"{form_name}/{set_name}"] = {"all": full, "folds": folds}
    for form_name, form in FORMS.items():
        for si, (set_name, members) in enumerate(data.sets.items()):
            prefix = f"{goal}/{form_name}/{set_name}"
            full = robot[f"{form_name}/{set_name}"]["all"]
            start = with_form(ped_all, form).replace(**full["fitted"])
            rng = np.random.default_rng([SEED_PAR, si, list(FORMS).index(form_name)])
            draws = [rng.choice(members, size=len(members), replace=True) for _ in range(n_boot)]
            boot = []
            for b, draw in enumerate(draws):
                boot.append(
                    cache.get(
                        f"{prefix}/boot/{b}",
                        lambda f=form, s=start, d=draw: bootstrap_fit(data, s, f, d),
                    )
                )
            robot[f"{form_name}/{set_name}"]["boot"] = boot
    return {"ped_all": ped_all, "ped_fold": ped_fold, "robot": robot}


def bootstrap_fit(data: Data, start: SRFMParams, form: Form, draw: IntArray) -> dict[str, float]:
    result = fit_params(
        data.enc,
        start=start,
        stages=("robot",),
        fields={"robot": form.fields},
        subset=data.g_enc.windows_of([int(g) for g in draw]),
        multi_start=False,
        tolerance=1e-4,
    )
    return dict(result.stages[0].fitted)


# --------------------------------------------------------------------------------------
# Held-out errors and tests


def window_measures(
    w: Windows, sel: IntArray, params: SRFMParams, mode: Any
) -> dict[str, FloatArray]:
    predicted = predict(w, params, sel, mode)
    err = displacement_errors(w, sel, predicted)
    steps = w.steps[sel]
    ends = np.cumsum(steps)
    ade = np.add.reduceat(err, ends - steps) / steps
    distance, offset = pass_errors(w, sel, predicted)
    return {
        "ade": ade,
        "fde": err[ends - 1],
        "pass": np.abs(distance),
        "offset": np.abs(offset),
        "bias": distance,
    }


def heldout(data: Data, fits: dict[str, Any]) -> dict[str, dict[str, FloatArray]]:
    """Per-window held-out measures of every model, keyed "<baseline>" or
    "<form>/<set>" (NaN outside the set)."""
    w, groups = data.enc, data.g_enc
    out: dict[str, dict[str, FloatArray]] = {}

    def put(key: str, sel: IntArray, values: dict[str, FloatArray]) -> None:
        table = out.setdefault(key, {m: np.full(w.n_windows, np.nan) for m in values})
        for m, v in values.items():
            table[m][sel] = v

    for g in data.tested:
        sel = groups.windows_of([g])
        ped = with_form(fits["ped_fold"][g], FORMS["exponential"])
        for mode in BASELINES:
            put(mode, sel, window_measures(w, sel, ped, mode))
        for form_name, form in FORMS.items():
            for set_name, members in data.sets.items():
                if g not in members:
                    continue
                fold = fits["robot"][f"{form_name}/{set_name}"]["folds"][g]
                params = with_form(fits["ped_fold"][g], form).replace(**fold["fitted"])
                put(f"{form_name}/{set_name}", sel, window_measures(w, sel, params, "srfm"))
    return out


def scene_means(values: FloatArray, of_window: IntArray, scenes: Sequence[int]) -> FloatArray:
    return np.array([float(np.nanmean(values[of_window == g])) for g in scenes])


def compare(
    data: Data, model: FloatArray, base: FloatArray, scenes: Sequence[int], seed: int
) -> dict[str, Any]:
    """Relative change of mean(model) against mean(base) over the windows of ``scenes``,
    its bootstrap intervals over scenes and the Wilcoxon test over scene means."""
    of = data.g_enc.of_window
    ok = np.isfinite(model) & np.isfinite(base)
    sums = np.array([[model[ok & (of == g)].sum(), base[ok & (of == g)].sum()] for g in scenes])
    counts = np.array([np.count_nonzero(ok & (of == g)) for g in scenes])
    est = sums[:, 0].sum() / sums[:, 1].sum() - 1.0
    rng = np.random.default_rng(seed)
    draws = rng.multinomial(len(scenes), np.full(len(scenes), 1.0 / len(scenes)), size=N_BOOT_ERR)
    boot = (draws @ sums[:, 0]) / (draws @ sums[:, 1]) - 1.0
    test = paired_test(scene_means(base, of, scenes), scene_means(model, of, scenes))
    sel = np.flatnonzero(ok & np.isin(of, scenes))
    return {
        "model_m": float(model[sel].mean()),
        "base_m": float(base[sel].mean()),
        "rel": float(est),
        "ci95": np.percentile(boot, [2.5, 97.5]).tolist(),
        "ci90": np.percentile(boot, [5.0, 95.0]).tolist(),
        "p": test.p,
        "n_windows": int(sel.size),
        "n_tracks": int(np.unique(data.enc.track[sel]).size),
        "n_scenes": int(np.count_nonzero(counts)),
    }


def tests(data: Data, err: dict[str, dict[str, FloatArray]]) -> dict[str, Any]:
    decisive: list[dict[str, Any]] = []
    secondary: list[dict[str, Any]] = []
    seed = SEED_ERR
    for form_name in FORMS:
        for set_name, members in data.sets.items():
            model = err[f"{form_name}/{set_name}"]
            for against in ("sfm", "robot_as_pedestrian"):
                for measure in MEASURES:
                    row = {
                        "form": form_name,
                        "set": set_name,
                        "against": against,
                        "measure": measure,
                        **compare(data, model[measure], err[against][measure], members, seed),
                    }
                    seed += 1
                    if against == "sfm" and measure in SUCCESS and FORMS[form_name].decisive:
                        decisive.append(row)
                    else:
                        secondary.append(row)
    for family in (decisive, secondary):
        for row, p in zip(family, holm([r["p"] for r in family]), strict=True):
            row["p_holm"] = p
    for row in decisive:
        margin = SUCCESS[row["measure"]]
        row["success"] = bool(row["rel"] <= -margin and row["p_holm"] < 0.05)
        lo, hi = row["ci90"]
        row["equivalent"] = bool(-margin < lo and hi < margin)
    return {"decisive": decisive, "secondary": secondary}


def absolute(data: Data, err: dict[str, dict[str, FloatArray]]) -> list[dict[str, Any]]:
    """Mean of every measure of every model per set (and the signed pass bias)."""
    rows = []
    of = data.g_enc.of_window
    for set_name, members in data.sets.items():
        sel = np.flatnonzero(np.isin(of, members))
        keys = [*BASELINES, *(f"{f}/{set_name}" for f in FORMS)]
        for key in keys:
            row: dict[str, Any] = {"set": set_name, "model": key.split("/")[0]}
            for m in (*MEASURES, "bias"):
                row[m] = float(np.nanmean(err[key][m][sel]))
            row["n_windows"] = int(sel.size)
            row["n_tracks"] = int(np.unique(data.enc.track[sel]).size)
            row["n_scenes"] = len(members)
            rows.append(row)
    return rows


def parameters(data: Data, fits: dict[str, Any]) -> list[dict[str, Any]]:
    rows = []
    for form_name, form in FORMS.items():
        for set_name in data.sets:
            r = fits["robot"][f"{form_name}/{set_name}"]
            boot = np.array([[b[f] for f in form.fields] for b in r["boot"]])
            folds = np.array([[v["fitted"][f] for f in form.fields] for v in r["folds"].values()])
            rows.append(
                {
                    "form": form_name,
                    "set": set_name,
                    "fitted": r["all"]["fitted"],
                    "windows": r["all"]["windows"],
                    "tracks": r["all"]["tracks"],
                    "scenes": len(data.sets[set_name]),
                    "ci95": {
                        f: np.percentile(boot[:, i], [2.5, 97.5]).tolist()
                        for i, f in enumerate(form.fields)
                    }
                    if boot.size
                    else {},
                    "n_boot": len(r["boot"]),
                    "folds_min_median_max": {
                        f: np.percentile(folds[:, i], [0, 50, 100]).tolist()
                        for i, f in enumerate(form.fields)
                    },
                }
            )
    return rows


# --------------------------------------------------------------------------------------
# Tables


def _p(p: float) -> str:
    if not math.isfinite(p):
        return "–"
    return "< 0.001" if p < 0.001 else f"{p:.3f}" if p < 0.1 else f"{p:.2f}"


def _rel(row: dict[str, Any]) -> str:
    lo, hi = row["ci95"]
    return f"{100 * row['rel']:+.1f} % ({100 * lo:+.1f} to {100 * hi:+.1f})"


def _verdict(row: dict[str, Any]) -> str:
    if row["success"]:
        return "**success**"
    return "equivalent" if row["equivalent"] else "inconclusive"


def tables(payload: dict[str, Any]) -> str:
    lines: list[str] = []
    add = lines.append
    add(f"Goal: {payload['goal']}; windows: encounter, lead {LEAD_S:g} s, 4.8 s.")
    add("")
    add("Decisive table (held out, leave one scene out; against robot ignored; Holm over")
    add(f"its {len(payload['tests']['decisive'])} rows):")
    add("")
    add(
        "| form | robot | n (windows / tracks / scenes) | ADE form / ignored (m) "
        "| ADE change (95 % CI) | p | p Holm | \\|pass err\\| form / ignored (m) "
        "| pass change (95 % CI) | p | p Holm | verdict ADE / pass |"
    )
    add("|---|---|---|---|---|--:|--:|---|---|--:|--:|---|")
    rows = payload["tests"]["decisive"]
    for form in (f for f, spec in FORMS.items() if spec.decisive):
        for set_name in SETS:
            a = next(
                r for r in rows if (r["form"], r["set"], r["measure"]) == (form, set_name, "ade")
            )
            b = next(
                r for r in rows if (r["form"], r["set"], r["measure"]) == (form, set_name, "pass")
            )
            add(
                f"| {FORMS[form].label} | {SET_LABELS[set_name]} "
                f"| {a['n_windows']} / {a['n_tracks']} / {a['n_scenes']} "
                f"| {a['model_m']:.3f} / {a['base_m']:.3f} | {_rel(a)} | {_p(a['p'])} "
                f"| {_p(a['p_holm'])} | {b['model_m']:.3f} / {b['base_m']:.3f} | {_rel(b)} "
                f"| {_p(b['p'])} | {_p(b['p_holm'])} | {_verdict(a)} / {_verdict(b)} |"
            )
    add("")
    add("Mean held-out errors (m; bias = mean signed pass-distance error):")
    add("")
    add(
        "| robot | model | n (windows / tracks / scenes) | ADE | FDE | \\|pass err\\| "
        "| \\|offset err\\| | pass bias |"
    )
    add("|---|---|---|--:|--:|--:|--:|--:|")
    for r in payload["absolute"]:
        label = BASELINES.get(r["model"]) or FORMS[r["model"]].label
        add(
            f"| {SET_LABELS[r['set']]} | {label} | {r['n_windows']} / {r['n_tracks']} / "
            f"{r['n_scenes']} | {r['ade']:.3f} | {r['fde']:.3f} | {r['pass']:.3f} | "
            f"{r['offset']:.3f} | {r['bias']:+.3f} |"
        )
    add("")
    add("Secondary family (exploratory; Holm over its rows):")
    add("")
    add("| form | robot | against | measure | form / other (m) | change (95 % CI) | p | p Holm |")
    add("|---|---|---|---|---|---|--:|--:|")
    for r in payload["tests"]["secondary"]:
        add(
            f"| {FORMS[r['form']].label} | {SET_LABELS[r['set']]} | {BASELINES[r['against']]} "
            f"| {MEASURES[r['measure']]} | {r['model_m']:.3f} / {r['base_m']:.3f} | {_rel(r)} "
            f"| {_p(r['p'])} | {_p(r['p_holm'])} |"
        )
    add("")
    add("Fitted robot parts (all the set's scenes; 95 % bootstrap over scenes; held-out folds):")
    add("")
    add(
        "| form | robot | n (windows / tracks / scenes) | parameter | fit | 95 % CI "
        "| folds min / median / max |"
    )
    add("|---|---|---|---|--:|---|---|")
    for r in payload["parameters"]:
        for f, v in r["fitted"].items():
            ci = r["ci95"].get(f)
            fo = r["folds_min_median_max"][f]
            add(
                f"| {FORMS[r['form']].label} | {SET_LABELS[r['set']]} "
                f"| {r['windows']} / {r['tracks']} / {r['scenes']} | {f} | {v:.4g} "
                f"| {'–' if ci is None else f'{ci[0]:.3g}–{ci[1]:.3g}'} "
                f"| {fo[0]:.3g} / {fo[1]:.3g} / {fo[2]:.3g} |"
            )
    ped = payload["pedestrian_part"]
    add("")
    add(
        "Pedestrian part (non-interaction windows of all 32 scenes): "
        + ", ".join(f"{k} = {v:.4g}" for k, v in ped["params"].items())
        + f"; {ped['windows']} windows, {ped['tracks']} tracks, ADE {ped['ade_m']:.3f} m."
    )
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------------------


def round_sig(x: float, digits: int = 4) -> float:
    return float(f"{x:.{digits}g}")


def robot_part_label(
    form_name: str, form: Form, full: dict[str, Any], goal: str, set_name: str, data: Data
) -> str:
    """What the preset's robot part is: "fitted (...)" only when the fit moved it by more
    than 0.1 % from every starting point; otherwise "not fitted", naming the starting
    values (issue 40)."""
    windows = (
        f"the encounter windows (lead {LEAD_S:g} s, 4.8 s, goal {goal}, walking starts "
        f">= 0.3 m/s) of the {SET_LABELS[set_name]} scenes ({full['windows']} windows, "
        f"{full['tracks']} tracks, {len(data.sets[set_name])} scenes)"
    )
    default = with_form({"params": {}}, form)
    starts = [{f: getattr(default, f) for f in form.fields}]
    starts += [{**starts[0], **s} for s in form.starts]
    fitted = {f: float(full["fitted"][f]) for f in form.fields}
    if not any(
        all(math.isclose(fitted[f], s[f], rel_tol=1e-3) for f in form.fields) for s in starts
    ):
        return f"fitted ({', '.join(form.fields)}) on {windows}"
    values = []
    for f in (*form.fields, *(g for g in FORM_FIELDS[form_name] if g not in form.fields)):
        value, at = round_sig(getattr(default.replace(**fitted), f)), getattr(default, f)
        how = "the default" if math.isclose(value, at) else f"the default {at:g} divided by ten"
        if f not in form.fields:
            how += ", not varied by the fit"
        values.append(f"{f} = {value:g}, {how}")
    return (
        f"not fitted: the {FORCE_NAMES[form_name]} force at default parameters, chosen by a "
        "held-out test "
        f"({'; '.join(values)}); the least-squares fit on {windows} did not move it from "
        "these starting values (by more than 0.1 %)"
    )


def write_preset(
    path: Path,
    name: str,
    form_name: str,
    set_name: str,
    data: Data,
    fits: dict[str, Any],
    payload: dict[str, Any],
    folder: Path,
) -> None:
    """A parameter file of the pedestrian part of all 32 scenes and the ``form_name``
    robot part fitted on all scenes of ``set_name``, rounded to 4 digits, with the fit's
    provenance and the numbers a test recomputes (``check_*``) in its [meta]."""
    form = FORMS[form_name]
    full = fits["robot"][f"{form_name}/{set_name}"]["all"]
    params = with_form(fits["ped_all"], form).replace(**full["fitted"])
    params = params.replace(
        **{f: round_sig(getattr(params, f)) for f in (*PED_FIELDS, *form.fields)}
    )
    agrawal = SRFMParams.preset("agrawal2024")
    scenes, _ = drop_supersets(read_navwareset(folder))
    ev = build_windows(scenes, EVAL_WINDOWS)
    non = ev.select(False)
    enc_all = np.arange(data.enc.n_windows, dtype=np.int64)

    def ade(w: Windows, sel: IntArray, p: SRFMParams, mode: Any) -> float:
        return float(window_measures(w, sel, p, mode)["ade"].mean())

    decisive = {
        (r["set"], r["measure"]): r for r in payload["tests"]["decisive"] if r["form"] == form_name
    }
    goal = payload["goal"]
    meta: dict[str, Any] = {
        "name": name,
        "created_by": f"tools/fitting/fit_forms.py (srfm {__version__}), issue 28",
        "data": "NavWareSet-Quant: navwareset_quant/ of the shared data, 32 scenes, "
        f"435 recordings (sha256 of the CSV files {payload['protocol']['data']})",
        "pedestrian_part": "srfm fit --stage pedestrian on the non-interaction windows "
        "(every 1.2 s, 4.8 s, walking starts >= 0.3 m/s, goal = track end): "
        f"{fits['ped_all']['windows']} windows, {fits['ped_all']['tracks']} tracks",
        "robot_form": form_name,
        "robot_part": robot_part_label(form_name, form, full, goal, set_name, data),
        "heldout_ade_change_vs_robot_ignored": decisive[(set_name, "ade")]["rel"],
        "heldout_ade_p_holm": decisive[(set_name, "ade")]["p_holm"],
        "heldout_pass_error_change_vs_robot_ignored": decisive[(set_name, "pass")]["rel"],
        "heldout_pass_error_p_holm": decisive[(set_name, "pass")]["p_holm"],
        "docs": "docs/real_encounters.md, Part 4",
        "reproduce": "srfm data convert navwareset navwareset_quant nws.mcap; "
        "srfm fit nws.mcap --stage pedestrian --stride 1.2 --min-start-speed 0.3 "
        "-o ped.toml; srfm fit nws.mcap --stage robot --start ped.toml "
        f"--robot-force {form_name}"
        + (" --fit-lambda-robot" if "lambda_robot" in form.fields else "")
        + f" --align encounter --lead {LEAD_S:g} --goal {goal} "
        f"--min-start-speed 0.3 -o {name}.toml"
        + ("" if set_name == "pooled" else f" (on the {SET_LABELS[set_name]} scenes only)"),
        "check_nonint_windows": int(non.size),
        "check_nonint_ade_m": ade(ev, non, params, "sfm"),
        "check_agrawal2024_nonint_ade_m": ade(ev, non, agrawal, "sfm"),
        "check_encounter_goal": goal,
        "check_encounter_lead_s": LEAD_S,
        "check_encounter_windows": int(enc_all.size),
        "check_encounter_ade_m": ade(data.enc, enc_all, params, "srfm"),
        "check_encounter_robot_ignored_ade_m": ade(data.enc, enc_all, params, "sfm"),
    }
    save_params(params, path, meta=meta)
    log(f"wrote {path}")


def data_root(arg: str | None) -> Path:
    if arg:
        return Path(arg)
    return Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))


def fingerprint(folder: Path) -> str:
    h = hashlib.sha256()
    for path in sorted(folder.rglob("*.csv")):
        h.update(str(path.relative_to(folder)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--data", default=None, help="data root (default $SRFM_DATA_DIR)")
    ap.add_argument("--goal", choices=("heading", "track_end"), default="heading")
    ap.add_argument("--boot", type=int, default=N_BOOT_PAR, help="parameter bootstrap resamples")
    ap.add_argument(
        "--out", type=Path, default=REPO / "docs" / "real_encounters", help="output folder"
    )
    ap.add_argument("--cache", type=Path, default=None, help="cache file (default in --out)")
    ap.add_argument(
        "--write-preset",
        nargs=3,
        action="append",
        default=[],
        metavar=("NAME", "FORM", "SET"),
        help="write srfm/models/presets/NAME.toml: the FORM fitted on SET (hsr, jackal, pooled)",
    )
    args = ap.parse_args()
    began = start()
    t0 = time.perf_counter()
    folder = data_root(args.data) / "navwareset_quant"
    data = load(folder, args.goal)
    protocol = {
        "data": fingerprint(folder),
        "goal": args.goal,
        "lead_s": LEAD_S,
        "seed_par": SEED_PAR,
    }
    cache = Cache(args.cache or args.out / f"forms_cache_{args.goal}.json", protocol)
    fits = run_fits(data, cache, args.goal, args.boot)
    err = heldout(data, fits)
    payload = {
        "goal": args.goal,
        "protocol": protocol,
        "pedestrian_part": fits["ped_all"],
        "tests": tests(data, err),
        "absolute": absolute(data, err),
        "parameters": parameters(data, fits),
        "n": {
            "encounter_windows": data.enc.n_windows,
            "scenes": {k: len(v) for k, v in data.sets.items()},
            "non_interaction_windows": int((~data.ped.interaction).sum()),
        },
    }
    payload["run"] = run_record(*began)
    saved = json.dumps(payload, default=float, indent=1, sort_keys=True)
    payload = json.loads(saved)
    text = tables(payload)  # what the saved data give: make docs-tables
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / f"forms_{args.goal}.json").write_text(saved + "\n")
    (args.out / f"forms_{args.goal}.md").write_text(text)
    for name, form_name, set_name in args.write_preset:
        path = REPO / "srfm" / "models" / "presets" / f"{name}.toml"
        write_preset(path, name, form_name, set_name, data, fits, payload, folder)
    log(f"done in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
