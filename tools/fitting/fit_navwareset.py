"""The NavWareSet robot-force protocol of docs/fitting.md (issue 15): fit, bootstrap,
per-condition fits, scene-level cross-validation, the held-out Table 2 and the figure.

    srfm fit <ETH/UCY mcaps> --stage pedestrian -o ped.toml       # the pedestrian part
    nice .venv/bin/python tools/fitting/fit_navwareset.py --pedestrian ped.toml \\
        --out docs/fitting_navwareset.json --figure docs/fitting_navwareset.png

Reads the NavWareSet folder (``$SRFM_DATA_DIR/navwareset_quant``, default
``../shared/data/navwareset_quant``) directly from its CSV files, drops the full
scene-13 recording that its slices repeat, and prints the markdown tables of the docs.
Deterministic: the bootstrap draws from ``--seed``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from srfm.cli._common import load_params_option
from srfm.datasets.navwareset import SCENARIOS, drop_supersets, read_navwareset
from srfm.fitting import (
    EVAL_WINDOWS,
    FIT_WINDOWS,
    ROBOT_FIELDS,
    TABLE2_MODES,
    SceneGroups,
    Windows,
    bootstrap_robot_part,
    build_windows,
    fit_robot_part,
    heldout_errors,
    leave_one_scene_out,
    paired_test,
    predict,
    scene_groups,
)
from srfm.models import SRFMParams

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tools.results.record import run_record, start  # noqa: E402

LABELS = {
    "constant_velocity": "CV",
    "sfm": "SFM, robot ignored",
    "robot_as_pedestrian": "SFM, robot as pedestrian",
    "srfm": "SRFM (held-out fit)",
    "srfm_agrawal": "SRFM, agrawal2024 robot part",
}
CONDITIONS = {
    "all scenes": lambda s, r, c: True,
    "HSR": lambda s, r, c: r == "hsr",
    "Jackal": lambda s, r, c: r == "jackal",
    "compliant": lambda s, r, c: c,
    "non-compliant": lambda s, r, c: not c,
}


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def robot_dict(p: SRFMParams) -> dict[str, float]:
    return {f: getattr(p, f) for f in ROBOT_FIELDS}


def summarise(boot: np.ndarray) -> dict[str, list[float]]:
    return {
        f: [float(np.std(boot[:, i], ddof=1)), *np.percentile(boot[:, i], [2.5, 97.5]).tolist()]
        for i, f in enumerate(ROBOT_FIELDS)
    }


def fits(
    w: Windows, groups: SceneGroups, ped: SRFMParams, n_boot: int, n_boot_cond: int, seed: int
) -> tuple[SRFMParams, dict[str, Any]]:
    out: dict[str, Any] = {}
    full: SRFMParams | None = None
    for i, (name, pred) in enumerate(CONDITIONS.items()):
        among = groups.where(pred)
        t0 = time.perf_counter()
        p = fit_robot_part(w, ped, groups.windows_of(among))
        t_fit = time.perf_counter() - t0
        nb = n_boot if name == "all scenes" else n_boot_cond
        boot = bootstrap_robot_part(
            w, groups, ped, p, n_boot=nb, seed=seed + i, among=among, tolerance=1e-4
        )
        sel = groups.windows_of(among)
        out[name] = {
            "scenes": len(among),
            "interaction_windows": int(np.count_nonzero(w.interaction[sel])),
            "params": robot_dict(p),
            "bootstrap_n": nb,
            "bootstrap_sd_ci95": summarise(boot),
            "fit_time_s": round(t_fit, 1),
            "bootstrap_time_s": round(time.perf_counter() - t0 - t_fit, 1),
        }
        log(f"{name}: {robot_dict(p)} ({len(among)} scenes)")
        if name == "all scenes":
            full = p
    assert full is not None
    return full, out


def table2(
    w: Windows, groups: SceneGroups, ped: SRFMParams, per_group: list[SRFMParams]
) -> dict[str, Any]:
    err = heldout_errors(w, groups, ped, per_group)
    agrawal = [SRFMParams.preset("agrawal2024")] * groups.n_groups
    err["srfm_agrawal"] = heldout_errors(w, groups, ped, agrawal)["srfm"]
    cells: list[tuple[str, np.ndarray]] = [("all", np.arange(w.n_windows))]
    for robot in ("hsr", "jackal"):
        cells.append((robot, groups.windows_of(groups.where(lambda s, r, c, rb=robot: r == rb))))
    for scenario in SCENARIOS:
        for robot in ("hsr", "jackal"):
            g = groups.where(lambda s, r, c, sc=scenario, rb=robot: s == sc and r == rb)
            cells.append((f"{scenario} / {robot}", groups.windows_of(g)))
    for compliant in (True, False):
        g = groups.where(lambda s, r, c, cc=compliant: c == cc)
        cells.append(("compliant" if compliant else "non-compliant", groups.windows_of(g)))
    rows = []
    for name, sel in cells:
        for inter in (True, False):
            s = np.sort(sel[w.interaction[sel] == inter])
            row: dict[str, Any] = {
                "cell": name,
                "windows": "interaction" if inter else "non-interaction",
                "n": int(s.size),
                "scenes": int(np.unique(groups.of_window[s]).size),
                "tracks": int(np.unique(w.track[s]).size),
            }
            for mode, (ade, fde) in err.items():
                row[f"ade_{mode}"] = float(ade[s].mean()) if s.size else math.nan
                row[f"fde_{mode}"] = float(fde[s].mean()) if s.size else math.nan
            for other in ("robot_as_pedestrian", "sfm", "srfm_agrawal"):
                t = paired_test(err[other][0][s], err["srfm"][0][s])
                row[f"srfm_vs_{other}"] = {"median_diff": t.median_diff, "p": t.p, "n": t.n}
            rows.append(row)
    # Scene level: the mean over a scene's interaction windows, paired over scenes.
    inter = w.interaction
    scene_means = {
        mode: np.array(
            [
                float(np.mean(err[mode][0][s])) if s.size else math.nan
                for s in (
                    groups.windows_of([g])[inter[groups.windows_of([g])]]
                    for g in range(groups.n_groups)
                )
            ]
        )
        for mode in err
    }
    ok = np.isfinite(scene_means["srfm"])
    scene_test = {
        other: attrs.asdict(paired_test(scene_means[other][ok], scene_means["srfm"][ok]))
        for other in ("robot_as_pedestrian", "sfm", "srfm_agrawal")
    }
    return {"rows": rows, "scene_level": scene_test, "errors": err}


def table2_lines(payload: dict[str, Any], cells: frozenset[str] | None = None) -> list[str]:
    """Table 2 on held-out scenes (every cell, or those named in ``cells``)."""
    labels = [LABELS[m] for m in (*TABLE2_MODES, "srfm_agrawal")]
    lines = [
        "| cell | windows | n (scenes/tracks) | "
        + " | ".join(labels)
        + " | SRFM − robot as ped.: mean, median (mm), p | SRFM − SFM robot ignored |",
        "|" + "---|" * (4 + len(labels) + 1),
    ]
    for row in payload["table2"]:
        if cells is not None and row["cell"] not in cells:
            continue
        parts = [
            row["cell"].replace("_", " "),
            row["windows"],
            f"{row['n']} ({row['scenes']}/{row['tracks']})",
        ]
        for mode in (*TABLE2_MODES, "srfm_agrawal"):
            a, f = row[f"ade_{mode}"], row[f"fde_{mode}"]
            parts.append("–" if math.isnan(a) else f"{a:.3f} / {f:.3f}")
        for other in ("robot_as_pedestrian", "sfm"):
            t = row[f"srfm_vs_{other}"]
            mean = (row["ade_srfm"] - row[f"ade_{other}"]) * 1e3
            parts.append(
                "–"
                if math.isnan(t["p"])
                else f"{mean:+.2f}, {t['median_diff'] * 1e3:+.2f}, p = {t['p']:.2g}"
            )
        lines.append("| " + " | ".join(parts) + " |")
    return lines


def scene_level_lines(payload: dict[str, Any]) -> list[str]:
    """The scene-level test: each scene's mean ADE over its interaction windows."""
    lines = [
        "| SRFM against | scenes | other (m) | SRFM (m) | median difference (mm) | p |",
        "|---|---|---|---|---|---|",
    ]
    for other, t in payload["scene_level"].items():
        lines.append(
            f"| {LABELS[other]} | {t['n']} | {t['mean_a']:.4f} | {t['mean_b']:.4f} "
            f"| {t['median_diff'] * 1e3:+.2f} | {t['p']:.2g} |"
        )
    return lines


def conditions_lines(payload: dict[str, Any]) -> list[str]:
    """The robot part per condition with its bootstrap sd and interval."""
    lines = [
        "| condition | scenes | interaction windows | A_r (m/s²) | B_r (m) | λ_r "
        "| bootstrap resamples |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in CONDITIONS:
        c = payload["per_condition"][name]
        cols = []
        for f in ROBOT_FIELDS:
            sd, lo, hi = c["bootstrap_sd_ci95"][f]
            cols.append(f"{c['params'][f]:.3g} (sd {sd:.2g}; {lo:.3g}–{hi:.3g})")
        lines.append(
            f"| {name} | {c['scenes']} | {c['interaction_windows']} | "
            + " | ".join(cols)
            + f" | {c['bootstrap_n']} |"
        )
    return lines


def folds_lines(payload: dict[str, Any]) -> list[str]:
    """Min / median / max of the held-out fits' robot parameters."""
    folds = np.array([[v[f] for f in ROBOT_FIELDS] for v in payload["cross_validation"].values()])
    lines = [f"The {folds.shape[0]} leave-one-scene-out fits (min / median / max):"]
    for i, f in enumerate(ROBOT_FIELDS):
        lo, med, hi = np.percentile(folds[:, i], [0, 50, 100])
        lines.append(f"- {f}: {lo:.3g} / {med:.3g} / {hi:.3g}")
    return lines


def print_tables(payload: dict[str, Any]) -> None:
    """The markdown tables of docs/fitting.md, from the results payload."""
    print("\n".join(table2_lines(payload)))
    print()
    print("Scene level (mean ADE of each scene's interaction windows, Wilcoxon over scenes):")
    print()
    print("\n".join(scene_level_lines(payload)))
    print()
    print("\n".join(conditions_lines(payload)))
    print()
    print("\n".join(folds_lines(payload)))
    print()
    print("wall times (s):", payload["wall_times"])


def figure(
    path: Path, w: Windows, groups: SceneGroups, ped: SRFMParams, per_group: list[SRFMParams]
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(SCENARIOS), 2, figsize=(9.0, 4.0 * len(SCENARIOS)))
    for i, scenario in enumerate(SCENARIOS):
        for j, compliant in enumerate((True, False)):
            ax = axes[i, j]
            g_all = groups.where(lambda s, r, c, sc=scenario, cc=compliant: s == sc and c == cc)
            sel = groups.windows_of(g_all)
            sel = sel[w.interaction[sel]]
            # the two closest passes of the condition: the encounters that test the model most
            picks = sel[np.argsort(w.min_robot_distance[sel], kind="stable")[:2]]
            for k, win in enumerate(picks):
                g = int(groups.of_window[win])
                one = np.array([win], dtype=np.int64)
                rows = w.rows(one)
                obs = np.vstack([w.pos[win], w.observed[rows]])
                frames = w.frame0[win] + np.arange(w.steps[win] + 1)
                rb = w.rb_a[frames][w.rb_on[frames]]
                srfm = np.vstack(
                    [w.pos[win], predict(w, ped.replace(**robot_dict(per_group[g])), one, "srfm")]
                )
                rap = np.vstack([w.pos[win], predict(w, ped, one, "robot_as_pedestrian")])
                ax.plot(
                    rb[:, 0],
                    rb[:, 1],
                    color="tab:red",
                    lw=2,
                    label="robot (recorded)" if k == 0 else None,
                )
                if len(rb) > 1:
                    ax.annotate(
                        "", rb[-1], rb[-2], arrowprops={"arrowstyle": "-|>", "color": "tab:red"}
                    )
                ax.plot(
                    obs[:, 0],
                    obs[:, 1],
                    color="black",
                    lw=2,
                    label="pedestrian, observed" if k == 0 else None,
                )
                ax.plot(
                    srfm[:, 0],
                    srfm[:, 1],
                    "--",
                    color="tab:blue",
                    lw=1.5,
                    label="SRFM (held-out fit)" if k == 0 else None,
                )
                ax.plot(
                    rap[:, 0],
                    rap[:, 1],
                    ":",
                    color="tab:orange",
                    lw=1.5,
                    label="robot as pedestrian" if k == 0 else None,
                )
                ax.plot(obs[0, 0], obs[0, 1], "o", color="black", ms=4)
                ax.annotate(f"scene {groups.keys[g]}", obs[0], fontsize=7, color="0.3")
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_title(
                f"{scenario.replace('_', ' ')}, {'compliant' if compliant else 'non-compliant'}",
                fontsize=9,
            )
            ax.tick_params(labelsize=7)
            if i == 0 and j == 0:
                ax.legend(fontsize=7, loc="best")
    fig.suptitle(
        "NavWareSet: observed vs simulated 4.8 s windows (closest two passes per condition)",
        fontsize=10,
    )
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.985))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def figure_from_saved(payload: dict[str, Any], data: Path, path: Path) -> None:
    """The figure again from a saved run's fits (``--out`` JSON) and the NavWareSet folder
    ``data``: what ``--tables-from ... --figure`` and ``make docs-tables`` draw."""
    scenes, _ = drop_supersets(read_navwareset(data))
    w_eval = build_windows(scenes, EVAL_WINDOWS)
    g_eval = scene_groups(w_eval, scenes)
    ped = SRFMParams().replace(**payload["pedestrian_part"])
    cv = payload["cross_validation"]
    per_group = [ped.replace(**cv[key]) for key in g_eval.keys]
    figure(path, w_eval, g_eval, ped, per_group)


def data_folder(arg: str | None) -> Path:
    if arg:
        return Path(arg)
    root = Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))
    return root / "navwareset_quant"


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--pedestrian",
        default=None,
        help="pedestrian part: a parameter file (srfm fit --stage pedestrian) or a preset",
    )
    ap.add_argument(
        "--data", default=None, help="NavWareSet folder (default $SRFM_DATA_DIR/navwareset_quant)"
    )
    ap.add_argument("--boot", type=int, default=50, help="bootstrap resamples, all scenes")
    ap.add_argument(
        "--boot-condition", type=int, default=20, help="bootstrap resamples per condition"
    )
    ap.add_argument(
        "--folds",
        type=int,
        default=0,
        help="scene-level folds (scene g in fold g mod k); 0: leave one scene out",
    )
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    ap.add_argument("--figure", type=Path, default=None, help="PNG of observed vs simulated paths")
    ap.add_argument(
        "--tables-from", type=Path, default=None, help="only print the tables of a saved JSON"
    )
    args = ap.parse_args()
    if args.tables_from is not None:
        payload = json.loads(args.tables_from.read_text())
        print_tables(payload)
        if args.figure:  # the figure again, from the saved fits
            figure_from_saved(payload, data_folder(args.data), args.figure)
        return
    data = data_folder(args.data)
    if args.pedestrian is None:
        ap.error("--pedestrian is required (unless --tables-from)")
    t_start = time.perf_counter()
    began = start()
    ped = load_params_option(args.pedestrian)
    scenes, dropped = drop_supersets(read_navwareset(data))
    log(f"{len(scenes)} recordings (dropped {dropped})")
    w_fit = build_windows(scenes, FIT_WINDOWS)
    w_eval = build_windows(scenes, EVAL_WINDOWS)
    g_fit = scene_groups(w_fit, scenes)
    g_eval = scene_groups(w_eval, scenes)
    log(
        f"fit windows {w_fit.n_windows} ({int(w_fit.interaction.sum())} interaction); "
        f"test windows {w_eval.n_windows} ({int(w_eval.interaction.sum())} interaction); "
        f"{g_fit.n_groups} scenes"
    )
    t0 = time.perf_counter()
    full, per_condition = fits(w_fit, g_fit, ped, args.boot, args.boot_condition, args.seed)
    t_fits = time.perf_counter() - t0
    t0 = time.perf_counter()
    per_group = leave_one_scene_out(
        w_fit,
        g_fit,
        ped,
        n_folds=args.folds or None,
        start=full,
        multi_start=False,
        tolerance=1e-4,
        log=log,
    )
    t_cv = time.perf_counter() - t0
    assert g_fit.keys == g_eval.keys
    t0 = time.perf_counter()
    tab = table2(w_eval, g_eval, ped, per_group)
    t_tab = time.perf_counter() - t0
    if args.figure:
        figure(args.figure, w_eval, g_eval, ped, per_group)
    timing = {
        "fits_and_bootstrap_s": round(t_fits, 1),
        "cross_validation_s": round(t_cv, 1),
        "table2_s": round(t_tab, 1),
        "total_s": round(time.perf_counter() - t_start, 1),
    }
    payload = {
        "pedestrian_part": {f: getattr(ped, f) for f in ("a_ped", "b_ped", "lambda_ped", "tau")},
        "robot_part": robot_dict(full),
        "per_condition": per_condition,
        "cross_validation": {g_fit.keys[g]: robot_dict(p) for g, p in enumerate(per_group)},
        "folds": args.folds,
        "table2": tab["rows"],
        "scene_level": tab["scene_level"],
        "windows": {
            "fit": w_fit.n_windows,
            "fit_interaction": int(w_fit.interaction.sum()),
            "test": w_eval.n_windows,
            "test_interaction": int(w_eval.interaction.sum()),
        },
        "seed": args.seed,
        "wall_times": timing,
        "run": run_record(*began),
    }
    payload = json.loads(json.dumps(payload, default=float))
    print_tables(payload)
    if args.out:
        args.out.write_text(json.dumps(payload, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
