"""Issue 40, part 3: fit the sidestep robot response to NavWareSet's people and test it
on held-out scenes, by the protocol of docs/robot_response.md (``srfm.fitting.PROTOCOL``).

    SRFM_DATA_DIR=../shared/data nice -n 5 .venv/bin/python tools/fitting/fit_response.py \
        --stage full          # the full fits of the three sets (every start)
    ... --stage folds         # the held-out folds
    ... --stage profiles      # the profiles of the full fits
    ... --stage tests         # held-out errors, tests, tables (needs the three above)

Resumable: every fit is stored as it finishes in ``--out``/fits_<stage>.json (one file
per stage and, for the folds, per set, so that they can run side by side) and not
recomputed; a file made under another protocol is refused. The analysis is
``srfm.fitting`` (``fit_sidestep``, ``profile_costs``, ``identification``,
``relative_change``, ``success``); this script
only reads the data, runs it and writes ``results.json`` and ``tables.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.datasets.navwareset import drop_supersets, read_navwareset
from srfm.fitting import (
    PROTOCOL,
    SceneGroups,
    Windows,
    best_fit,
    build_windows,
    fit_sidestep,
    holm,
    identification,
    profile_costs,
    profile_grid,
    relative_change,
    scene_groups,
    success,
    window_metrics,
)
from srfm.fitting._response import StartFit
from srfm.models import SRFMParams

REPO = Path(__file__).resolve().parents[2]
PED_CACHE = REPO / "docs" / "real_encounters" / "forms_cache_heading.json"
SETS = ("hsr", "jackal", "pooled")
LABELS = {"hsr": "HSR", "jackal": "Jackal", "pooled": "pooled"}
MEASURES = {
    "ade": "ADE",
    "fde": "FDE",
    "pass": "\\|pass-distance error\\|",
    "offset": "\\|path-offset error\\|",
}
MODELS = {
    "sidestep": "sidestep (fitted, held out)",
    "sfm": "robot ignored",
    "robot_as_pedestrian": "robot as a pedestrian",
    "no_overlap": "no overlap (contact only)",
    "ttc": "time-to-collision force at defaults",
    "agrawal2024": "the paper's preset (agrawal2024)",
}
IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


class Store:
    """Results by key in one JSON file, rewritten atomically after every put."""

    def __init__(self, path: Path, protocol: Any) -> None:
        self.path, self.protocol = path, protocol
        self.entries: dict[str, Any] = {}
        if path.exists():
            data = json.loads(path.read_text())
            if data["protocol"] != protocol:
                raise SystemExit(f"{path} was made under another protocol")
            self.entries = data["entries"]

    def get(self, key: str, compute: Callable[[], Any]) -> Any:
        if key not in self.entries:
            t0 = time.perf_counter()
            self.entries[key] = json.loads(json.dumps(compute()))
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.path.with_suffix(".tmp")
            payload = {"protocol": self.protocol, "entries": self.entries}
            tmp.write_text(json.dumps(payload, indent=1, sort_keys=True) + "\n")
            os.replace(tmp, self.path)
            log(f"{key}: {time.perf_counter() - t0:.1f} s")
        return self.entries[key]


class Data(NamedTuple):
    enc: Windows
    groups: SceneGroups
    sets: dict[str, list[int]]
    ped_all: dict[str, float]
    ped_fold: dict[int, dict[str, float]]


def load(root: Path) -> Data:
    scenes, _ = drop_supersets(read_navwareset(root / "navwareset_quant"))
    enc = build_windows(scenes, PROTOCOL.windows)
    groups = scene_groups(enc, scenes)
    tested = sorted({int(g) for g in groups.of_window})
    sets = {
        "hsr": [g for g in tested if groups.robot[g] == "hsr"],
        "jackal": [g for g in tested if groups.robot[g] == "jackal"],
        "pooled": tested,
    }
    entries = json.loads(PED_CACHE.read_text())["entries"]
    ped_fold = {g: entries[f"ped/without/{groups.keys[g]}"]["params"] for g in tested}
    log(
        f"{enc.n_windows} encounter windows; " + ", ".join(f"{k} {len(v)}" for k, v in sets.items())
    )
    return Data(enc, groups, sets, entries["ped/all"]["params"], ped_fold)


def with_ped(ped: dict[str, float]) -> SRFMParams:
    return SRFMParams.preset("agrawal2024").replace(**ped)


def fits_as_json(fits: list[StartFit]) -> list[dict[str, Any]]:
    return [attrs.asdict(f) for f in fits]


def fits_from_json(rows: list[dict[str, Any]]) -> list[StartFit]:
    return [StartFit(**r) for r in rows]


def run_full(data: Data, store: Store) -> None:
    for s in SETS:
        sel = data.groups.windows_of(data.sets[s])
        store.get(
            f"full/{s}",
            lambda sel=sel: fits_as_json(
                fit_sidestep(data.enc, with_ped(data.ped_all), sel, full=True)
            ),
        )


def run_folds(data: Data, store: Store, s: str) -> None:
    for g in data.sets[s]:
        train = data.groups.windows_of([h for h in data.sets[s] if h != g])
        base = with_ped(data.ped_fold[g])
        store.get(
            f"fold/{s}/{data.groups.keys[g]}",
            lambda t=train, b=base: fits_as_json(fit_sidestep(data.enc, b, t, full=False)),
        )


def run_profiles(data: Data, store: Store, full: Store) -> None:
    for s in SETS:
        fitted = best_fit(fits_from_json(full.entries[f"full/{s}"])).end
        sel = data.groups.windows_of(data.sets[s])
        for field in PROTOCOL.fields:
            store.get(
                f"profile/{s}/{field}",
                lambda sel=sel, f=field, x=fitted: profile_costs(
                    data.enc, with_ped(data.ped_all), sel, x, f
                ).tolist(),
            )


def model_params(
    data: Data, g: int, model: str, fold: dict[str, float] | None
) -> tuple[SRFMParams, Any]:
    ped = with_ped(data.ped_fold[g])
    if model == "sidestep":
        assert fold is not None
        return ped.replace(robot_form="sidestep", **fold), "srfm"
    if model in ("sfm", "robot_as_pedestrian"):
        return ped, model
    if model == "no_overlap":
        a, b, lam = PROTOCOL.no_overlap
        return ped.replace(robot_form="exponential", a_robot=a, b_robot=b, lambda_robot=lam), "srfm"
    if model == "ttc":
        ttc = SRFMParams.preset("navwareset2026_ttc")
        return ped.replace(
            robot_form="ttc",
            ttc_k=ttc.ttc_k,
            ttc_tau0=ttc.ttc_tau0,
            robot_force_cap=ttc.robot_force_cap,
        ), "srfm"
    return SRFMParams.preset("agrawal2024"), "srfm"


def heldout(data: Data, folds: dict[str, Store]) -> dict[str, dict[str, FloatArray]]:
    """Per-window held-out errors, keyed by model (the sidestep per set: "sidestep/<set>")."""
    w = data.enc
    out: dict[str, dict[str, FloatArray]] = {}
    for g in data.sets["pooled"]:
        sel = data.groups.windows_of([g])
        keys: list[tuple[str, str, dict[str, float] | None]] = [
            (m, m, None) for m in MODELS if m != "sidestep"
        ]
        for s in SETS:
            if g in data.sets[s]:
                fold = best_fit(
                    fits_from_json(folds[s].entries[f"fold/{s}/{data.groups.keys[g]}"])
                ).end
                keys.append((f"sidestep/{s}", "sidestep", fold))
        for key, model, fold in keys:
            params, mode = model_params(data, g, model, fold)
            m = window_metrics(w, sel, params, mode)
            values = {
                "ade": m.ade,
                "fde": m.fde,
                "pass": np.abs(m.pass_distance),
                "offset": np.abs(m.path_offset),
                "bias": m.pass_distance,
            }
            table = out.setdefault(key, {k: np.full(w.n_windows, np.nan) for k in values})
            for k, v in values.items():
                table[k][sel] = v
    return out


def tests(data: Data, err: dict[str, dict[str, FloatArray]]) -> dict[str, Any]:
    of, track = data.groups.of_window, data.enc.track
    seed = PROTOCOL.boot_seed
    decisive, ade, secondary = [], [], []
    for s in SETS:
        for model in MODELS:
            if model == "sfm":
                continue
            key = f"sidestep/{s}" if model == "sidestep" else model
            for measure in MEASURES:
                row = {
                    "model": model,
                    "set": s,
                    "measure": measure,
                    **relative_change(
                        err[key][measure], err["sfm"][measure], of, track, data.sets[s], seed
                    ),
                }
                seed += 1
                if model == "sidestep" and measure in ("pass", "offset"):
                    decisive.append(row)
                elif model == "sidestep" and measure == "ade":
                    ade.append(row)
                else:
                    secondary.append(row)
    for family in (decisive, secondary):
        for row, p in zip(family, holm([r["p"] for r in family]), strict=True):
            row["p_holm"] = p
    verdict = {}
    for s in SETS:
        pick = {r["measure"]: r for r in decisive if r["set"] == s}
        a = next(r for r in ade if r["set"] == s)
        verdict[s] = success(pick["pass"], pick["offset"], a)
    return {"decisive": decisive, "ade": ade, "secondary": secondary, "success": verdict}


def parameters(data: Data, full: Store, profiles: Store) -> list[dict[str, Any]]:
    rows = []
    for s in SETS:
        fits = fits_from_json(full.entries[f"full/{s}"])
        best = best_fit(fits)
        for field in PROTOCOL.fields:
            costs = np.array(profiles.entries[f"profile/{s}/{field}"])
            grid = profile_grid(field)
            min_cost = float(min(best.cost, costs.min()))
            rows.append(
                {
                    "set": s,
                    "field": field,
                    "fitted": best.end[field],
                    "status": identification(field, best.end[field], grid, costs, min_cost),
                    "grid": grid.tolist(),
                    "costs": costs.tolist(),
                    "min_cost": min_cost,
                    "starts_end": [f.end[field] for f in fits],
                    "starts_cost": [f.cost for f in fits],
                    "n_windows": int(data.groups.windows_of(data.sets[s]).size),
                    "n_scenes": len(data.sets[s]),
                }
            )
    return rows


def _p(p: float) -> str:
    return "–" if not np.isfinite(p) else "< 0.001" if p < 0.001 else f"{p:.3f}"


def _rel(r: dict[str, Any]) -> str:
    lo, hi = r["ci95"]
    return f"{100 * r['rel']:+.1f} % ({100 * lo:+.1f} to {100 * hi:+.1f})"


def tables(payload: dict[str, Any]) -> str:
    t = payload["tests"]
    lines = [
        "Decisive table (held out, leave one scene out; change against robot ignored, 95 % "
        "bootstrap interval over scenes; p: Wilcoxon signed-rank over scenes, Holm over the "
        f"{len(t['decisive'])} pass/offset rows; ADE: 90 % interval for the ±2 % TOST):",
        "",
        "| form | robot | n (windows / tracks / scenes) | ADE (m) form / ignored | ADE change "
        "| ADE 90 % | \\|pass-distance error\\| (m) | pass change | p (Holm) "
        "| \\|path-offset error\\| (m) | offset change | p (Holm) | criterion |",
        "|---|---|---|---|---|---|---|---|--:|---|---|--:|---|",
    ]
    for s in SETS:
        a = next(r for r in t["ade"] if r["set"] == s)
        ps = next(r for r in t["decisive"] if r["set"] == s and r["measure"] == "pass")
        of = next(r for r in t["decisive"] if r["set"] == s and r["measure"] == "offset")
        v = t["success"][s]
        verdict = (
            "**met**"
            if v["met"]
            else "not met ("
            + ", ".join(k for k in ("pass", "offset", "ade") if not v[k])
            + " fail)"
        )
        lines.append(
            f"| sidestep | {LABELS[s]} | {a['n_windows']} / {a['n_tracks']} / {a['n_scenes']} "
            f"| {a['model_m']:.3f} / {a['base_m']:.3f} | {_rel(a)} "
            f"| {100 * a['ci90'][0]:+.1f} to {100 * a['ci90'][1]:+.1f} % "
            f"| {ps['model_m']:.3f} / {ps['base_m']:.3f} | {_rel(ps)} | {_p(ps['p_holm'])} "
            f"| {of['model_m']:.3f} / {of['base_m']:.3f} | {_rel(of)} | {_p(of['p_holm'])} "
            f"| {verdict} |"
        )
    lines += [
        "",
        "All models against robot ignored (secondary family, exploratory, Holm over its rows; "
        "the sidestep's pass and offset rows carry the decisive family's Holm p, its ADE row "
        "none: its test is the TOST above):",
        "",
        "| model | robot | measure | n (windows / tracks / scenes) | model / ignored (m) "
        "| change (95 % CI) | p | p (Holm) |",
        "|---|---|---|---|---|---|--:|--:|",
    ]
    every = sorted(
        [*t["decisive"], *t["ade"], *t["secondary"]],
        key=lambda r: (
            SETS.index(r["set"]),
            list(MODELS).index(r["model"]),
            list(MEASURES).index(r["measure"]),
        ),
    )
    for r in every:
        lines.append(
            f"| {MODELS[r['model']]} | {LABELS[r['set']]} | {MEASURES[r['measure']]} "
            f"| {r['n_windows']} / {r['n_tracks']} / {r['n_scenes']} "
            f"| {r['model_m']:.3f} / {r['base_m']:.3f} "
            f"| {_rel(r)} | {_p(r['p'])} | {_p(r.get('p_holm', float('nan')))} |"
        )
    lines += [
        "",
        "Parameters (full fit on all the set's scenes, the lowest-cost of 9 starts; the profile's "
        "verdict, 1 % rise rule):",
        "",
        "| robot | parameter | fit | status | ends of the 9 starts (min / median / max) "
        "| profile cost above the minimum |",
        "|---|---|--:|---|---|---|",
    ]
    for r in payload["parameters"]:
        ends = np.array(r["starts_end"])
        rise = np.array(r["costs"]) - r["min_cost"]
        lines.append(
            f"| {LABELS[r['set']]} | {r['field']} | {r['fitted']:.4g} | {r['status']} "
            f"| {ends.min():.3g} / {np.median(ends):.3g} / {ends.max():.3g} "
            f"| {100 * rise.min() / r['min_cost']:.2f}–{100 * rise.max() / r['min_cost']:.2f} % |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--stage", choices=("full", "folds", "profiles", "tests"), required=True)
    ap.add_argument(
        "--sets", nargs="+", choices=SETS, default=list(SETS), help="sets of --stage folds"
    )
    ap.add_argument("--data", type=Path, default=None, help="data root (default $SRFM_DATA_DIR)")
    ap.add_argument("--out", type=Path, default=REPO / "docs" / "robot_response")
    args = ap.parse_args()
    root = args.data or Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))
    data = load(root)
    protocol = json.loads(json.dumps(attrs.asdict(PROTOCOL), default=str))
    names = ("full", "profiles", *(f"folds_{s}" for s in SETS))
    store = {name: Store(args.out / f"fits_{name}.json", protocol) for name in names}
    if args.stage == "full":
        run_full(data, store["full"])
    elif args.stage == "folds":
        for s in args.sets:
            run_folds(data, store[f"folds_{s}"], s)
    elif args.stage == "profiles":
        run_profiles(data, store["profiles"], store["full"])
    else:
        err = heldout(data, {s: store[f"folds_{s}"] for s in SETS})
        payload = {
            "protocol": protocol,
            "tests": tests(data, err),
            "parameters": parameters(data, store["full"], store["profiles"]),
        }
        saved = json.dumps(payload, default=float, indent=1, sort_keys=True)
        text = tables(json.loads(saved))  # what the saved data give: make docs-tables
        print(text)
        (args.out / "results.json").write_text(saved + "\n")
        (args.out / "tables.md").write_text(text)


if __name__ == "__main__":
    main()
