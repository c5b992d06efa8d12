"""How real people answer a robot (issue 28): model-free evidence from NavWareSet, and
prediction windows aligned to encounters checked on synthetic data.

    PYTHONPATH=. nice .venv/bin/python tools/fitting/real_encounters.py

(``PYTHONPATH=.``: part 2 re-simulates pedestrians with ``tests/datasets/_synthetic.py``.)
One command makes every figure and table of docs/real_encounters.md: it reads every
NavWareSet scene (``$SRFM_DATA_DIR/navwareset_quant``, default
``../shared/data/navwareset_quant``, both formats), measures how each pedestrian's
motion changes against the robot's distance, time to closest approach, predicted
distance at closest approach, bearing and relative speed, beside pedestrian-pedestrian
encounters and pedestrians with no one near (part 1); then fits a known robot response
back from synthetic pedestrians with encounter-aligned windows (part 2, which also
needs the 12-file excerpt ``navwareset/`` for the recorded robots). It writes the
figures (PNG), ``results.json`` and ``tables.md`` into ``docs/real_encounters/`` and
prints the tables. Deterministic: every random draw comes from ``--seed``; the plan it
follows (what is confirmatory, what exploratory) is the page's section "The plan".
"""

from __future__ import annotations

import argparse
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
from scipy.signal import savgol_filter

from srfm.datasets import PEDESTRIAN, Trajectories
from srfm.datasets.navwareset import condition_of, drop_supersets, read_navwareset
from srfm.fitting import holm

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tools.results.record import run_record, start  # noqa: E402

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# ---- the plan's constants (docs/real_encounters.md, "The plan") ----------------------
SG_WINDOW = 11  # Savitzky-Golay window (samples): 1 s at 10 Hz
SG_ORDER = 2
EDGE = SG_WINDOW // 2  # samples dropped at each segment end
MAX_GAP_FACTOR = 1.5  # an interval longer than this many dt breaks a track
WALK_MPS = 0.3  # a sample is used while the pedestrian walks at least this fast
NEAR_M = 4.0  # baseline: no known agent within this distance
PASS_MAX_M = 3.0  # an encounter passes within this centre distance
LEAD_S = 3.0  # t_ref = t_pass - LEAD_S
BEFORE_S = 4.0  # usable samples needed before the pass
AFTER_S = 1.0  # and after it
STRETCH_S = 3.0  # baseline stretches: 3 s long, one every 1 s
STRETCH_STEP_S = 1.0
N_BOOT = 2000
SEED = 2028
COLLISION_DSTAR_M = 1.0  # "on a collision course": d* <= 1 m
D_BINS = np.arange(0.0, 8.0 + 1e-9, 0.25)
T_BINS = np.arange(0.0, 8.0 + 1e-9, 0.25)
ONSET_STEP = 0.05
MIN_BIN_N = 30  # bins with fewer samples are not drawn and not a peak
MIN_SCENES_P = 5  # no p-value for a cell of fewer scenes (too few distinct resamples)
AVOID_TSTAR_MIN = 1.0  # exploratory: the avoidance phase is at t* >= 1 s
AVOID_D_MIN = 1.5  # and at d >= 1.5 m
SCENARIO_ORDER = (
    "frontal_approach",
    "pedestrian_obstruction",
    "blind_corner",
    "perpendicular_crossing",
    "circular_crossing",
)


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


# ======================================================================================
# Part 1: kinematics of every recording


class Recording(NamedTuple):
    """Smoothed states of every agent of one recording, NaN outside usable samples."""

    scene: int  # index of the recorded scene (group)
    rid: int  # index of the recording
    name: str
    t: FloatArray  # (F,) s since the first frame
    pos: FloatArray  # (F, A, 2) smoothed positions
    vel: FloatArray  # (F, A, 2)
    acc: FloatArray  # (F, A, 2)
    segment: IntArray  # (F, A) segment id of each usable sample, -1 elsewhere
    peds: tuple[int, ...]  # agent indices of the pedestrians
    robot: int
    dt: float


class SceneInfo(NamedTuple):
    key: str
    scenario: str
    robot: str
    compliant: bool
    fmt: str


def _runs(ok: NDArray[np.bool_], gap: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """[lo, hi) runs of consecutive True in ``ok`` not broken by ``gap`` (F-1,)."""
    runs: list[tuple[int, int]] = []
    lo = None
    for f in range(ok.shape[0]):
        if ok[f] and lo is not None and f > 0 and gap[f - 1]:
            runs.append((lo, f))
            lo = f
        elif ok[f] and lo is None:
            lo = f
        elif not ok[f] and lo is not None:
            runs.append((lo, f))
            lo = None
    if lo is not None:
        runs.append((lo, ok.shape[0]))
    return runs


def recording_states(scene: Trajectories, group: int, rid: int) -> Recording:
    """Savitzky-Golay positions, velocities and accelerations of every agent."""
    frames, times = scene.frames()
    t = (times - times[0]).astype(np.float64) * 1e-9
    n_f, n_a = frames.shape[0], scene.n_agents
    raw = np.full((n_f, n_a, 2), np.nan)
    raw[np.searchsorted(frames, scene.frame), scene.agent] = scene.xy
    dt = float(np.median(np.diff(t)))
    gap = np.diff(t) > MAX_GAP_FACTOR * dt
    pos = np.full_like(raw, np.nan)
    vel = np.full_like(raw, np.nan)
    acc = np.full_like(raw, np.nan)
    segment = np.full((n_f, n_a), -1, dtype=np.int64)
    for a in range(n_a):
        present = np.isfinite(raw[:, a, 0])
        for sid, (lo, hi) in enumerate(_runs(present, gap)):
            if hi - lo < SG_WINDOW + 2 * EDGE:
                continue
            xy = raw[lo:hi, a]
            s = [
                savgol_filter(xy, SG_WINDOW, SG_ORDER, deriv=k, delta=dt, axis=0) for k in range(3)
            ]
            keep = slice(lo + EDGE, hi - EDGE)
            inner = slice(EDGE, hi - lo - EDGE)
            pos[keep, a], vel[keep, a], acc[keep, a] = s[0][inner], s[1][inner], s[2][inner]
            segment[keep, a] = sid
    robot = scene.robot_index
    assert robot is not None
    peds = tuple(a for a, k in enumerate(scene.kinds) if k == PEDESTRIAN)
    return Recording(group, rid, scene.scene, t, pos, vel, acc, segment, peds, robot, dt)


class Relative(NamedTuple):
    """Relative geometry of a pedestrian (p, v) and another agent (q, u), per frame."""

    d: FloatArray
    tstar: FloatArray
    dstar: FloatArray
    bearing: FloatArray  # deg, 0 ahead, + left
    relspeed: FloatArray
    side: FloatArray  # s: +1 when "away" is to the pedestrian's left


def relative(p: FloatArray, v: FloatArray, q: FloatArray, u: FloatArray) -> Relative:
    dp = q - p
    dv = u - v
    dv2 = np.sum(dv * dv, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        tstar = np.where(dv2 > 1e-12, -np.sum(dp * dv, axis=-1) / dv2, 0.0)
    miss = dp + dv * np.maximum(tstar, 0.0)[..., None]
    heading = np.arctan2(v[..., 1], v[..., 0])
    bearing = np.degrees(_wrap(np.arctan2(dp[..., 1], dp[..., 0]) - heading))
    normal = np.stack([-v[..., 1], v[..., 0]], axis=-1)
    side = np.sign(np.sum(-miss * normal, axis=-1))
    return Relative(
        d=np.linalg.norm(dp, axis=-1),
        tstar=tstar,
        dstar=np.linalg.norm(miss, axis=-1),
        bearing=bearing,
        relspeed=np.sqrt(dv2),
        side=side,
    )


def _wrap(angle: FloatArray) -> FloatArray:
    return np.asarray((angle + np.pi) % (2 * np.pi) - np.pi)


def _unit_normal(v: FloatArray) -> FloatArray:
    speed = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.stack([-v[..., 1], v[..., 0]], axis=-1) / speed


def track_id(rec: Recording, agent: int) -> int:
    """A track's id over all recordings."""
    return rec.rid * 64 + agent


# Sample and event tables: dicts of equal-length arrays ("columns").
Table = dict[str, NDArray[Any]]


def _concat(parts: list[Table]) -> Table:
    if not parts:
        return {}
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def recording_samples(rec: Recording) -> dict[str, Table]:
    """Per walking sample of every pedestrian: its own motion, and its relation to the
    nearest known agent; split into robot, pedestrian and baseline samples."""
    out: dict[str, list[Table]] = {"robot": [], "pedestrian": [], "baseline": []}
    others_all = (*rec.peds, rec.robot)
    for i in rec.peds:
        p, v, a = rec.pos[:, i], rec.vel[:, i], rec.acc[:, i]
        speed = np.linalg.norm(v, axis=1)
        with np.errstate(invalid="ignore"):
            walking = np.isfinite(speed) & (speed >= WALK_MPS)
        if not np.any(walking):
            continue
        f = np.flatnonzero(walking)
        others = [o for o in others_all if o != i]
        dist = np.stack([np.linalg.norm(rec.pos[f, o] - p[f], axis=1) for o in others], axis=1)
        known = np.isfinite(dist)
        dist_k = np.where(known, dist, np.inf)
        nearest = np.argmin(dist_k, axis=1)
        nearest_d = dist_k[np.arange(f.size), nearest]
        normal = _unit_normal(v[f])
        a_n = np.sum(a[f] * normal, axis=1)
        a_t = np.sum(a[f] * v[f], axis=1) / speed[f]
        own = {
            "scene": np.full(f.size, rec.scene, dtype=np.int64),
            "track": np.full(f.size, track_id(rec, i), dtype=np.int64),
            "speed": speed[f],
            "a_n": a_n,
            "a_t": a_t,
            "omega": np.degrees(a_n / speed[f]),
        }
        base = nearest_d > NEAR_M
        if np.any(base):
            out["baseline"].append({k: val[base] for k, val in own.items()})
        for kind, is_kind in (
            ("robot", np.array([o == rec.robot for o in others])[nearest]),
            ("pedestrian", np.array([o != rec.robot for o in others])[nearest]),
        ):
            sel = is_kind & np.isfinite(nearest_d)
            if not np.any(sel):
                continue
            o_idx = np.array(others)[nearest[sel]]
            fs = f[sel]
            rel = relative(p[fs], v[fs], rec.pos[fs, o_idx], rec.vel[fs, o_idx])
            ok = np.isfinite(rel.tstar) & np.isfinite(rel.relspeed)
            cols = {k: val[sel][ok] for k, val in own.items()}
            cols.update({k: np.asarray(getattr(rel, k))[ok] for k in Relative._fields})
            cols["a_away"] = cols["side"] * cols["a_n"]
            cols["omega_away"] = cols["side"] * cols["omega"]
            out[kind].append(cols)
    return {k: _concat(v) for k, v in out.items()}


def _event(
    rec: Recording,
    i: int,
    o: int,
    k_pass: int,
    k_ref: int,
    n_before: int,
    n_after: int,
    lane: tuple[int, int],
) -> Table | None:
    """The event measures of pedestrian i's encounter with agent o (None when unusable).

    ``lane`` = the first and last walking sample of the track segment: the lane measures
    (added after the confirmatory results, see the page) take the pedestrian's lateral
    position from the line between them, signed away from the side of that line the
    other agent is on at t_ref."""
    p, v, a = rec.pos[:, i], rec.vel[:, i], rec.acc[:, i]
    if not (np.isfinite(rec.vel[k_ref, o, 0]) and np.isfinite(v[k_ref, 0])):
        return None
    if np.linalg.norm(v[k_ref]) < WALK_MPS:
        return None
    rel = relative(p[k_ref], v[k_ref], rec.pos[k_ref, o], rec.vel[k_ref, o])
    s = float(rel.side) if float(rel.side) != 0 else 1.0
    n_ref = _unit_normal(v[k_ref])
    th = np.arctan2(v[:, 1], v[:, 0])
    idx = np.arange(k_pass - n_before, k_pass + n_after + 1)
    lateral = s * ((p[idx] - p[k_ref]) @ n_ref)
    speed = np.linalg.norm(v[idx], axis=1)
    normals = _unit_normal(v[idx])
    a_away = s * np.sum(a[idx] * normals, axis=1)
    d_now = np.linalg.norm(rec.pos[:, o] - p, axis=1)
    span = slice(k_ref, k_pass + 1)
    start, end = p[lane[0]], p[lane[1]]
    chord = end - start
    n_lane = np.array([-chord[1], chord[0]]) / max(float(np.linalg.norm(chord)), 1e-9)
    y_other = float((rec.pos[k_ref, o] - start) @ n_lane)
    s_lane = -1.0 if y_other > 0 else 1.0
    y_ped = (p[idx] - start) @ n_lane
    return {
        "scene": np.array([rec.scene]),
        "track": np.array([track_id(rec, i)]),
        "d_pass": np.array([d_now[k_pass]]),
        "d_ref": np.array([float(rel.d)]),
        "tstar_ref": np.array([float(rel.tstar)]),
        "dstar_ref": np.array([float(rel.dstar)]),
        "relspeed_ref": np.array([float(rel.relspeed)]),
        "bearing_ref": np.array([float(rel.bearing)]),
        "offset": np.array([s * float((p[k_pass] - p[k_ref]) @ n_ref)]),
        "heading": np.array([s * math.degrees(float(_wrap(th[k_pass] - th[k_ref])))]),
        "speed_change": np.array([float(np.linalg.norm(v[k_pass]) / np.linalg.norm(v[k_ref]) - 1)]),
        "a_away_mean": np.array(
            [float(np.mean(s * np.sum(a[span] * _unit_normal(v[span]), axis=1)))]
        ),
        "lane_offset": np.array([s_lane * float((p[k_pass] - start) @ n_lane)]),
        "lane_other_ref": np.array([abs(y_other)]),
        "lane_length": np.array([float(np.linalg.norm(chord))]),
        "lane_course": (s_lane * y_ped)[None, :],
        "course_d": d_now[idx][None, :],
        "course_offset": lateral[None, :],
        "course_speed": (speed / np.linalg.norm(v[k_ref]))[None, :],
        "course_a_away": a_away[None, :],
    }


def recording_events(rec: Recording) -> dict[str, Table]:
    """Robot and pedestrian encounters, and baseline stretches, of one recording."""
    n_before = round(BEFORE_S / rec.dt)
    n_after = round(AFTER_S / rec.dt)
    n_lead = round(LEAD_S / rec.dt)
    out: dict[str, list[Table]] = {"robot": [], "pedestrian": [], "baseline": []}
    for i in rec.peds:
        seg = rec.segment[:, i]
        for sid in np.unique(seg[seg >= 0]):
            frames = np.flatnonzero(seg == sid)
            lo, hi = int(frames[0]), int(frames[-1]) + 1
            speed = np.linalg.norm(rec.vel[lo:hi, i], axis=1)
            walking = np.flatnonzero(speed >= WALK_MPS)
            if walking.size < 2:
                continue
            lane = (lo + int(walking[0]), lo + int(walking[-1]))
            others = [rec.robot] + [j for j in rec.peds if j != i]
            for o in others:
                d = np.linalg.norm(rec.pos[lo:hi, o] - rec.pos[lo:hi, i], axis=1)
                if not np.any(np.isfinite(d)):
                    continue
                k_pass = lo + int(np.nanargmin(d))
                if d[k_pass - lo] > PASS_MAX_M:
                    continue
                if k_pass - n_before < lo or k_pass + n_after >= hi:
                    continue
                ev = _event(rec, i, o, k_pass, k_pass - n_lead, n_before, n_after, lane)
                if ev is not None:
                    out["robot" if o == rec.robot else "pedestrian"].append(ev)
            out["baseline"].extend(_stretches(rec, i, lo, hi))
    return {k: _concat(v) for k, v in out.items()}


def _stretches(rec: Recording, i: int, lo: int, hi: int) -> list[Table]:
    """Baseline stretches of track segment [lo, hi): walking, no known agent within
    NEAR_M throughout; unsigned measures."""
    n = round(STRETCH_S / rec.dt)
    step = round(STRETCH_STEP_S / rec.dt)
    p, v = rec.pos[:, i], rec.vel[:, i]
    speed = np.linalg.norm(v, axis=1)
    others = [o for o in (*rec.peds, rec.robot) if o != i]
    near = np.zeros(rec.t.shape[0], dtype=bool)
    for o in others:
        d = np.linalg.norm(rec.pos[:, o] - p, axis=1)
        with np.errstate(invalid="ignore"):
            near |= d <= NEAR_M
    out: list[Table] = []
    for k in range(lo, hi - n, step):
        span = slice(k, k + n + 1)
        with np.errstate(invalid="ignore"):
            if near[span].any() or not np.all(speed[span] >= WALK_MPS):
                continue
        n_ref = _unit_normal(v[k])
        th0, th1 = math.atan2(v[k, 1], v[k, 0]), math.atan2(v[k + n, 1], v[k + n, 0])
        out.append(
            {
                "scene": np.array([rec.scene]),
                "track": np.array([track_id(rec, i)]),
                "offset_abs": np.array([abs(float((p[k + n] - p[k]) @ n_ref))]),
                "heading_abs": np.array([abs(math.degrees(float(_wrap(np.array(th1 - th0)))))]),
                "speed_change": np.array([float(speed[k + n] / speed[k] - 1)]),
            }
        )
    return out


# ======================================================================================
# Part 1: statistics (bootstrap over scenes)


class Boot:
    """Scene-resampling weights: (B, G) counts of each scene in each resample."""

    def __init__(self, n_groups: int, seed: int, n_boot: int = N_BOOT) -> None:
        self.n_groups = n_groups
        self.n_boot = n_boot
        self._rng = np.random.default_rng(seed)
        self.all = self.within([list(range(n_groups))])

    def within(self, pools: Sequence[Sequence[int]]) -> FloatArray:
        """Weights that resample each pool of scenes separately (stratified)."""
        w = np.zeros((self.n_boot, self.n_groups))
        for pool in pools:
            if not pool:
                continue
            draw = self._rng.choice(np.asarray(pool), size=(self.n_boot, len(pool)))
            for b in range(self.n_boot):
                w[b] += np.bincount(draw[b], minlength=self.n_groups)
        return w


def scene_sums(values: FloatArray, scene: IntArray, n_groups: int) -> tuple[FloatArray, FloatArray]:
    ok = np.isfinite(values)
    s = np.bincount(scene[ok], weights=values[ok], minlength=n_groups)
    n = np.bincount(scene[ok], minlength=n_groups).astype(np.float64)
    return s, n


def boot_mean(
    values: FloatArray,
    scene: IntArray,
    n_groups: int,
    w: FloatArray,
    mask: FloatArray | None = None,
) -> tuple[float, FloatArray]:
    """The mean over units and its resamples; ``mask`` (G,) zeroes scenes not in scope."""
    s, n = scene_sums(values, scene, n_groups)
    if mask is not None:
        s, n = s * mask, n * mask
    est = float(s.sum() / n.sum()) if n.sum() > 0 else math.nan
    with np.errstate(invalid="ignore", divide="ignore"):
        boot = (w @ s) / (w @ n)
    return est, boot


def binned(
    x: FloatArray, y: FloatArray, scene: IntArray, edges: FloatArray, n_groups: int
) -> tuple[FloatArray, FloatArray]:
    """Per-scene sums and counts of y in bins of x: each (G, nb)."""
    nb = edges.shape[0] - 1
    b = np.digitize(x, edges) - 1
    ok = (b >= 0) & (b < nb) & np.isfinite(y)
    idx = scene[ok] * nb + b[ok]
    s = np.bincount(idx, weights=y[ok], minlength=n_groups * nb).reshape(n_groups, nb)
    n = np.bincount(idx, minlength=n_groups * nb).reshape(n_groups, nb).astype(np.float64)
    return s, n


def curve(
    x: FloatArray, y: FloatArray, scene: IntArray, edges: FloatArray, n_groups: int, w: FloatArray
) -> dict[str, Any]:
    """Binned mean of y against x with its bootstrap interval and n per bin."""
    s, n = binned(x, y, scene, edges, n_groups)
    with np.errstate(invalid="ignore", divide="ignore"):
        est = s.sum(0) / n.sum(0)
        boot = (w @ s) / (w @ n)
    lo, hi = np.nanpercentile(boot, [2.5, 97.5], axis=0)
    return {
        "centre": ((edges[:-1] + edges[1:]) / 2).tolist(),
        "mean": est.tolist(),
        "lo": lo.tolist(),
        "hi": hi.tolist(),
        "n": n.sum(0).astype(int).tolist(),
        "scenes": (n > 0).sum(0).astype(int).tolist(),
        "_s": s,
        "_n": n,
    }


def hinge(
    centre: FloatArray, means: FloatArray, counts: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Onset x_on, slope b and level c of y = c + b max(0, x_on - x), weighted least
    squares over a grid of x_on; means/counts (B, nb) (one row per resample)."""
    grid = np.arange(centre[1], centre[-1] + 1e-9, ONSET_STEP)
    m = np.nan_to_num(means)
    wts = np.where(np.isfinite(means), counts, 0.0)
    sw = wts.sum(1, keepdims=True)
    mbar = (wts * m).sum(1, keepdims=True) / sw
    h = np.maximum(0.0, grid[:, None] - centre[None, :])  # (K, nb)
    hbar = (wts[:, None, :] * h[None]).sum(2) / sw  # (B, K)
    hc = h[None] - hbar[:, :, None]  # (B, K, nb)
    shh = (wts[:, None, :] * hc * hc).sum(2)
    shm = (wts[:, None, :] * hc * (m - mbar)[:, None, :]).sum(2)
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = np.where(shh > 1e-12, shm * shm / shh, -np.inf)
        best = np.argmax(gain, axis=1)
        rows = np.arange(means.shape[0])
        b = shm[rows, best] / shh[rows, best]
    c = mbar[:, 0] - b * hbar[rows, best]
    return grid[best], b, c


def onset(cv: dict[str, Any], w: FloatArray, x_min: float = -np.inf) -> dict[str, Any]:
    """The hinge onset of a curve (bins with centre >= ``x_min``), with bootstrap
    intervals of x_on and b."""
    keep = np.asarray(cv["centre"]) >= x_min
    s, n = cv["_s"][:, keep], cv["_n"][:, keep]
    centre = np.asarray(cv["centre"])[keep]
    with np.errstate(invalid="ignore", divide="ignore"):
        est_m = (s.sum(0) / n.sum(0))[None]
        boot_m = (w @ s) / (w @ n)
    x0, b0, c0 = hinge(centre, est_m, n.sum(0)[None])
    xb, bb, _ = hinge(centre, boot_m, w @ n)
    return {
        "x_on": float(x0[0]),
        "x_on_ci": np.nanpercentile(xb, [2.5, 97.5]).tolist(),
        "slope": float(b0[0]),
        "slope_ci": np.nanpercentile(bb, [2.5, 97.5]).tolist(),
        "slope_p": boot_p(bb),
        "level": float(c0[0]),
    }


def peak(cv: dict[str, Any], w: FloatArray, x_min: float) -> dict[str, Any]:
    """The largest bin mean at x >= ``x_min`` and where it is, with bootstrap intervals."""
    keep = np.asarray(cv["centre"]) >= x_min
    s, n = cv["_s"][:, keep], cv["_n"][:, keep]
    centre = np.asarray(cv["centre"])[keep]
    with np.errstate(invalid="ignore", divide="ignore"):
        est = np.where(n.sum(0) >= MIN_BIN_N, s.sum(0) / n.sum(0), -np.inf)
        boot = np.where((w @ n) >= MIN_BIN_N, (w @ s) / (w @ n), -np.inf)
    k = int(np.argmax(est))
    kb = np.argmax(boot, axis=1)
    vb = boot[np.arange(boot.shape[0]), kb]
    ok = np.isfinite(vb)  # a resample with no bin of MIN_BIN_N samples has no peak
    return {
        "value": float(est[k]),
        "value_ci": np.percentile(vb[ok], [2.5, 97.5]).tolist(),
        "at": float(centre[k]),
        "at_ci": np.percentile(centre[kb[ok]], [2.5, 97.5]).tolist(),
    }


def boot_p(boot: FloatArray) -> float:
    boot = boot[np.isfinite(boot)]
    if boot.size == 0:
        return math.nan
    below = (np.count_nonzero(boot <= 0) + 1) / (boot.size + 1)
    above = (np.count_nonzero(boot >= 0) + 1) / (boot.size + 1)
    return float(min(1.0, 2 * min(below, above)))


def summary(est: float, boot: FloatArray, n_scenes: int | None = None) -> dict[str, Any]:
    """Estimate, 95 % percentile interval and bootstrap p; with ``n_scenes`` below
    MIN_SCENES_P the p is NaN (a bootstrap over so few scenes has too few distinct
    resamples to test with)."""
    lo, hi = np.nanpercentile(boot, [2.5, 97.5])
    p = boot_p(boot) if n_scenes is None or n_scenes >= MIN_SCENES_P else math.nan
    return {"est": est, "ci": [float(lo), float(hi)], "p": p}


# ======================================================================================
# Part 1: the analysis


class Data(NamedTuple):
    info: list[SceneInfo]
    samples: dict[str, Table]
    events: dict[str, Table]
    n_recordings: int
    n_tracks: int


def load(root: Path) -> Data:
    scenes, dropped = drop_supersets(read_navwareset(root))
    log(f"{len(scenes)} recordings (dropped {', '.join(dropped) or 'none'})")
    keys: dict[str, int] = {}
    info: list[SceneInfo] = []
    samples: dict[str, list[Table]] = {"robot": [], "pedestrian": [], "baseline": []}
    events: dict[str, list[Table]] = {"robot": [], "pedestrian": [], "baseline": []}
    n_tracks = 0
    for rid, scene in enumerate(scenes):
        cond = condition_of(scene)
        key = scene.source["navwareset_scene"]
        if cond is None:
            raise SystemExit(f"{scene.scene}: scene {key} has no condition")
        if key not in keys:
            keys[key] = len(info)
            info.append(SceneInfo(key, cond[0], cond[1], cond[2], scene.source["format"]))
        rec = recording_states(scene, keys[key], rid)
        n_tracks += len(rec.peds)
        for k, tab in recording_samples(rec).items():
            if tab:
                samples[k].append(tab)
        for k, tab in recording_events(rec).items():
            if tab:
                events[k].append(tab)
    return Data(
        info=info,
        samples={k: _concat(v) for k, v in samples.items()},
        events={k: _concat(v) for k, v in events.items()},
        n_recordings=len(scenes),
        n_tracks=n_tracks,
    )


def _n(tab: Table, sel: NDArray[np.bool_] | None = None) -> dict[str, int]:
    """n of a selection: rows, tracks, scenes."""
    if sel is None:
        sel = np.ones(tab["scene"].shape[0], dtype=bool)
    return {
        "rows": int(np.count_nonzero(sel)),
        "tracks": int(np.unique(tab["track"][sel]).size),
        "scenes": int(np.unique(tab["scene"][sel]).size),
    }


class Weights(NamedTuple):
    all: FloatArray
    robot: FloatArray  # within HSR / within Jackal
    compliance: FloatArray  # within compliant / within non-compliant
    cell: FloatArray  # within robot x compliance
    scenario: FloatArray  # within scenario x robot
    circular: FloatArray  # the circular-crossing scenes only
    scenario_only: FloatArray  # within scenario (both robots)


def weights(info: list[SceneInfo], seed: int) -> Weights:
    g = len(info)
    boot = Boot(g, seed)

    def pools(key: Callable[[SceneInfo], object]) -> list[list[int]]:
        out: dict[object, list[int]] = {}
        for i, s in enumerate(info):
            out.setdefault(key(s), []).append(i)
        return list(out.values())

    return Weights(
        all=boot.all,
        robot=boot.within(pools(lambda s: s.robot)),
        compliance=boot.within(pools(lambda s: s.compliant)),
        cell=boot.within(pools(lambda s: (s.robot, s.compliant))),
        scenario=boot.within(pools(lambda s: (s.scenario, s.robot))),
        circular=boot.within([[i for i, s in enumerate(info) if s.fmt == "2"]]),
        scenario_only=boot.within(pools(lambda s: s.scenario)),
    )


def scene_mask(info: list[SceneInfo], pred: Callable[[SceneInfo], bool]) -> FloatArray:
    return np.array([1.0 if pred(s) else 0.0 for s in info])


def _sel(tab: Table, **ranges: tuple[float, float]) -> NDArray[np.bool_]:
    """Rows with lo < column <= hi for every given column."""
    ok = np.ones(tab["scene"].shape[0], dtype=bool)
    for col, (lo, hi) in ranges.items():
        with np.errstate(invalid="ignore"):
            ok &= (tab[col] > lo) & (tab[col] <= hi)
    return ok


def _masked(tab: Table, sel: NDArray[np.bool_]) -> Table:
    return {k: v[sel] for k, v in tab.items()}


def confirmatory(data: Data, w: Weights) -> dict[str, Any]:
    info, g = data.info, len(data.info)
    rob_s = data.samples["robot"]
    rob_e, ped_e = data.events["robot"], data.events["pedestrian"]
    rows: list[dict[str, Any]] = []

    def add(name: str, est: float, boot: FloatArray, n: dict[str, Any]) -> None:
        rows.append({"test": name, **summary(est, boot), "n": n})

    for col, label in (
        ("offset", "robot encounters: path offset at the pass (m)"),
        ("heading", "robot encounters: heading change (deg)"),
        ("speed_change", "robot encounters: speed change (ratio - 1)"),
    ):
        est, boot = boot_mean(rob_e[col], rob_e["scene"], g, w.all)
        add(label, est, boot, _n(rob_e))
    appr = _sel(rob_s, tstar=(0.0, np.inf))
    near = appr & _sel(rob_s, d=(-np.inf, 2.0))
    far = appr & _sel(rob_s, d=(4.0, 8.0))
    e1, b1 = boot_mean(rob_s["a_away"][near], rob_s["scene"][near], g, w.all)
    e2, b2 = boot_mean(rob_s["a_away"][far], rob_s["scene"][far], g, w.all)
    add(
        "robot samples, approaching: a_away at d <= 2 m minus 4 < d <= 8 m (m/s²)",
        e1 - e2,
        b1 - b2,
        {"near": _n(rob_s, near), "far": _n(rob_s, far)},
    )
    course = appr & _sel(rob_s, dstar=(-np.inf, COLLISION_DSTAR_M))
    near = course & _sel(rob_s, tstar=(0.0, 2.0))
    far = course & _sel(rob_s, tstar=(5.0, 8.0))
    e1, b1 = boot_mean(rob_s["a_away"][near], rob_s["scene"][near], g, w.all)
    e2, b2 = boot_mean(rob_s["a_away"][far], rob_s["scene"][far], g, w.all)
    add(
        "robot samples, d* <= 1 m: a_away at 0 < t* <= 2 s minus 5 < t* <= 8 s (m/s²)",
        e1 - e2,
        b1 - b2,
        {"near": _n(rob_s, near), "far": _n(rob_s, far)},
    )
    circ = scene_mask(info, lambda s: s.fmt == "2")
    e1, b1 = boot_mean(rob_e["offset"], rob_e["scene"], g, w.circular, circ)
    e2, b2 = boot_mean(ped_e["offset"], ped_e["scene"], g, w.circular, circ)
    in_circ = circ[rob_e["scene"]] > 0
    add(
        "path offset: robot minus pedestrian encounters, circular crossing (m)",
        e1 - e2,
        b1 - b2,
        {"robot": _n(rob_e, in_circ), "pedestrian": _n(ped_e)},
    )
    for label, wts, pred_a, pred_b in (
        (
            "path offset: HSR minus Jackal (m)",
            w.robot,
            lambda s: s.robot == "hsr",
            lambda s: s.robot == "jackal",
        ),
        (
            "path offset: compliant minus non-compliant (m)",
            w.compliance,
            lambda s: s.compliant,
            lambda s: not s.compliant,
        ),
    ):
        ma, mb = scene_mask(info, pred_a), scene_mask(info, pred_b)
        e1, b1 = boot_mean(rob_e["offset"], rob_e["scene"], g, wts, ma)
        e2, b2 = boot_mean(rob_e["offset"], rob_e["scene"], g, wts, mb)
        add(
            label,
            e1 - e2,
            b1 - b2,
            {"a": _n(rob_e, ma[rob_e["scene"]] > 0), "b": _n(rob_e, mb[rob_e["scene"]] > 0)},
        )
    for row, p in zip(rows, holm([r["p"] for r in rows]), strict=True):
        row["p_holm"] = p
    return {"tests": rows}


def curves(data: Data, w: Weights) -> dict[str, Any]:
    """Every binned curve (exploratory, except the two onsets of all robot samples)."""
    info, g = data.info, len(data.info)
    rob, ped = data.samples["robot"], data.samples["pedestrian"]
    subsets: dict[str, tuple[Table, FloatArray, Callable[[SceneInfo], bool]]] = {
        "robot": (rob, w.all, lambda s: True),
        "HSR": (rob, w.robot, lambda s: s.robot == "hsr"),
        "Jackal": (rob, w.robot, lambda s: s.robot == "jackal"),
        "compliant": (rob, w.compliance, lambda s: s.compliant),
        "non-compliant": (rob, w.compliance, lambda s: not s.compliant),
        "HSR compliant": (rob, w.cell, lambda s: s.robot == "hsr" and s.compliant),
        "HSR non-compliant": (rob, w.cell, lambda s: s.robot == "hsr" and not s.compliant),
        "Jackal compliant": (rob, w.cell, lambda s: s.robot == "jackal" and s.compliant),
        "Jackal non-compliant": (rob, w.cell, lambda s: s.robot == "jackal" and not s.compliant),
        "pedestrian": (ped, w.circular, lambda s: True),
    }
    for scenario in SCENARIO_ORDER:
        subsets[scenario] = (rob, w.scenario_only, lambda s, sc=scenario: s.scenario == sc)
    out: dict[str, Any] = {}
    for name, (tab, wts, pred) in subsets.items():
        mask = scene_mask(info, pred)
        keep = mask[tab["scene"]] > 0
        t = _masked(tab, keep)
        appr = _sel(t, tstar=(0.0, np.inf))
        course = appr & _sel(t, dstar=(-np.inf, COLLISION_DSTAR_M))
        soon = appr & _sel(t, tstar=(0.0, 3.0))
        ahead = appr & _sel(t, d=(-np.inf, 4.0))
        close = appr & _sel(t, d=(-np.inf, 3.0))
        c: dict[str, Any] = {}
        c["a_away~d"] = curve(t["d"][appr], t["a_away"][appr], t["scene"][appr], D_BINS, g, wts)
        c["omega_away~d"] = curve(
            t["d"][appr], t["omega_away"][appr], t["scene"][appr], D_BINS, g, wts
        )
        c["a_t~d"] = curve(t["d"][appr], t["a_t"][appr], t["scene"][appr], D_BINS, g, wts)
        c["abs_a_n~d"] = curve(
            t["d"][appr], np.abs(t["a_n"][appr]), t["scene"][appr], D_BINS, g, wts
        )
        c["a_away~tstar"] = curve(
            t["tstar"][course], t["a_away"][course], t["scene"][course], T_BINS, g, wts
        )
        c["a_t~tstar"] = curve(
            t["tstar"][course], t["a_t"][course], t["scene"][course], T_BINS, g, wts
        )
        c["a_away~dstar"] = curve(
            t["dstar"][soon], t["a_away"][soon], t["scene"][soon], np.arange(0, 3.01, 0.2), g, wts
        )
        c["a_away~bearing"] = curve(
            t["bearing"][ahead],
            t["a_away"][ahead],
            t["scene"][ahead],
            np.arange(-180, 181, 30.0),
            g,
            wts,
        )
        c["a_away~relspeed"] = curve(
            t["relspeed"][close],
            t["a_away"][close],
            t["scene"][close],
            np.arange(0, 2.61, 0.2),
            g,
            wts,
        )
        c["onset_d"] = onset(c["a_away~d"], wts)
        c["onset_tstar"] = onset(c["a_away~tstar"], wts)
        # exploratory, chosen after seeing the curves: the avoidance phase (t* >= 1 s,
        # before the return phase), the steering magnitude |a_n| against d and t*
        c["onset_tstar_avoid"] = onset(c["a_away~tstar"], wts, x_min=AVOID_TSTAR_MIN)
        c["onset_d_avoid"] = onset(c["a_away~d"], wts, x_min=AVOID_D_MIN)
        c["abs_a_n~tstar"] = curve(
            t["tstar"][course], np.abs(t["a_n"][course]), t["scene"][course], T_BINS, g, wts
        )
        c["onset_abs_a_n_d"] = onset(c["abs_a_n~d"], wts)
        c["onset_abs_a_n_tstar"] = onset(c["abs_a_n~tstar"], wts)
        c["peak_avoid"] = peak(c["a_away~tstar"], wts, AVOID_TSTAR_MIN)
        c["n_approaching"] = _n(t, appr)
        c["n_course"] = _n(t, course)
        out[name] = c
    return out


def event_table(data: Data, w: Weights) -> dict[str, Any]:
    """Event measures per robot x compliance and per scenario x robot (exploratory; Holm
    over every p of the table)."""
    info, g = data.info, len(data.info)
    rob_e, ped_e = data.events["robot"], data.events["pedestrian"]
    cells: list[tuple[str, Table, FloatArray, FloatArray]] = [
        ("robot, all", rob_e, w.all, scene_mask(info, lambda s: True))
    ]
    for robot in ("hsr", "jackal"):
        for comp in (True, False):
            cells.append(
                (
                    f"{robot} {'compliant' if comp else 'non-compliant'}",
                    rob_e,
                    w.cell,
                    scene_mask(info, lambda s, r=robot, c=comp: s.robot == r and s.compliant == c),
                )
            )
    scenarios = sorted({s.scenario for s in info}, key=[s.scenario for s in info].index)
    for scenario in scenarios:
        for robot in ("hsr", "jackal"):
            cells.append(
                (
                    f"{scenario.replace('_', ' ')} / {robot}",
                    rob_e,
                    w.scenario,
                    scene_mask(
                        info, lambda s, sc=scenario, r=robot: s.scenario == sc and s.robot == r
                    ),
                )
            )
    cells.append(
        (
            "pedestrian (circular crossing)",
            ped_e,
            w.circular,
            scene_mask(info, lambda s: s.fmt == "2"),
        )
    )
    rows: list[dict[str, Any]] = []
    for name, tab, wts, mask in cells:
        keep = mask[tab["scene"]] > 0
        row: dict[str, Any] = {"cell": name, "n": _n(tab, keep)}
        for col in ("offset", "heading", "speed_change", "a_away_mean", "d_pass", "dstar_ref"):
            est, boot = boot_mean(tab[col], tab["scene"], g, wts, mask)
            row[col] = summary(est, boot, row["n"]["scenes"])
        rows.append(row)
    tested = [(r, c) for r in rows for c in ("offset", "heading", "speed_change")]
    for (r, c), p in zip(tested, holm([r[c]["p"] for r, c in tested]), strict=True):
        r[c]["p_holm"] = p
    return {"rows": rows}


def magnitudes(data: Data, w: Weights) -> dict[str, Any]:
    """Unsigned sizes of motion change: robot near, pedestrian near, no one near."""
    g = len(data.info)
    out: dict[str, Any] = {}
    samples = {
        "robot within 2 m, approaching": (
            data.samples["robot"],
            _sel(data.samples["robot"], d=(-np.inf, 2.0), tstar=(0.0, np.inf)),
            w.all,
        ),
        "pedestrian within 2 m, approaching": (
            data.samples["pedestrian"],
            _sel(data.samples["pedestrian"], d=(-np.inf, 2.0), tstar=(0.0, np.inf)),
            w.circular,
        ),
        "no one within 4 m": (
            data.samples["baseline"],
            np.ones(data.samples["baseline"]["scene"].shape[0], dtype=bool),
            w.all,
        ),
    }
    for name, (tab, sel, wts) in samples.items():
        row: dict[str, Any] = {"n": _n(tab, sel)}
        for col, f in (
            ("abs_a_n", lambda t: np.abs(t["a_n"])),
            ("abs_omega", lambda t: np.abs(t["omega"])),
            ("a_t", lambda t: t["a_t"]),
            ("abs_a_t", lambda t: np.abs(t["a_t"])),
            ("speed", lambda t: t["speed"]),
        ):
            v = f(tab)[sel]
            est, boot = boot_mean(v, tab["scene"][sel], g, wts)
            row[col] = summary(est, boot)
        out[name] = row
    events = {
        "robot encounters": (data.events["robot"], w.all),
        "pedestrian encounters": (data.events["pedestrian"], w.circular),
        "no one within 4 m (3 s stretches)": (data.events["baseline"], w.all),
    }
    ev_out: dict[str, Any] = {}
    for name, (tab, wts) in events.items():
        row = {"n": _n(tab)}
        off = tab["offset_abs"] if "offset_abs" in tab else np.abs(tab["offset"])
        hd = tab["heading_abs"] if "heading_abs" in tab else np.abs(tab["heading"])
        for col, v in (
            ("abs_offset", off),
            ("abs_heading", hd),
            ("speed_change", tab["speed_change"]),
        ):
            est, boot = boot_mean(v, tab["scene"], g, wts)
            row[col] = summary(est, boot)
        ev_out[name] = row
    # the difference robot - baseline in |offset|, resampling all scenes
    r_off, r_b = boot_mean(
        np.abs(data.events["robot"]["offset"]), data.events["robot"]["scene"], g, w.all
    )
    b_off, b_b = boot_mean(
        data.events["baseline"]["offset_abs"], data.events["baseline"]["scene"], g, w.all
    )
    ev_out["robot minus no one near, |offset|"] = summary(r_off - b_off, r_b - b_b)
    return {"samples": out, "events": ev_out}


def time_courses(data: Data, w: Weights) -> dict[str, Any]:
    """Means over encounters of the offset, speed ratio and a_away against the time to
    the observed pass (-4 .. +1 s), with bootstrap bands."""
    info, g = data.info, len(data.info)
    out: dict[str, Any] = {}
    groups = {
        "HSR": (data.events["robot"], w.robot, lambda s: s.robot == "hsr"),
        "Jackal": (data.events["robot"], w.robot, lambda s: s.robot == "jackal"),
        "pedestrian": (data.events["pedestrian"], w.circular, lambda s: True),
    }
    for name, (tab, wts, pred) in groups.items():
        mask = scene_mask(info, pred)
        keep = mask[tab["scene"]] > 0
        entry: dict[str, Any] = {"n": _n(tab, keep)}
        for col in ("course_offset", "course_speed", "course_a_away"):
            x = tab[col][keep]
            sc = tab["scene"][keep]
            s = np.zeros((g, x.shape[1]))
            np.add.at(s, sc, x)
            n = np.bincount(sc, minlength=g).astype(np.float64)[:, None] * np.ones(x.shape[1])
            est = s.sum(0) / n.sum(0)
            with np.errstate(invalid="ignore", divide="ignore"):
                boot = (wts @ s) / (wts @ n)
            lo, hi = np.nanpercentile(boot, [2.5, 97.5], axis=0)
            entry[col] = {"mean": est.tolist(), "lo": lo.tolist(), "hi": hi.tolist()}
        out[name] = entry
    n_before = round(BEFORE_S / 0.1)
    out["tau"] = (np.arange(-n_before, round(AFTER_S / 0.1) + 1) * 0.1).tolist()
    return out


def tstar_dstar_map(data: Data) -> dict[str, Any]:
    """Mean a_away over a (t*, d*) grid of approaching robot samples (exploratory)."""
    t = data.samples["robot"]
    appr = _sel(t, tstar=(0.0, 6.0), dstar=(-np.inf, 3.0))
    te, de = np.arange(0, 6.01, 0.5), np.arange(0, 3.01, 0.25)
    s, _, _ = np.histogram2d(
        t["tstar"][appr], t["dstar"][appr], [te, de], weights=t["a_away"][appr]
    )
    n, _, _ = np.histogram2d(t["tstar"][appr], t["dstar"][appr], [te, de])
    with np.errstate(invalid="ignore", divide="ignore"):
        m = np.where(n >= 30, s / n, np.nan)
    return {
        "tstar_edges": te.tolist(),
        "dstar_edges": de.tolist(),
        "mean": m.tolist(),
        "n": n.tolist(),
    }


# Added after the confirmatory results (see the page): the lane frame.
LANE_SCENARIOS = ("frontal_approach", "perpendicular_crossing", "pedestrian_obstruction")


def lane_analysis(data: Data, w: Weights) -> dict[str, Any]:
    """Lateral offset from the lane (the line from a track's first to its last walking
    sample) at the pass, signed away from the robot's side of the lane 3 s before the
    pass; format-1 scenarios with straight lanes. Per cell: the mean (bootstrap over
    the cell's scenes), its time course and the hinge onset of that time course."""
    info, g = data.info, len(data.info)
    ev = data.events["robot"]
    tau = np.arange(-round(BEFORE_S / 0.1), round(AFTER_S / 0.1) + 1) * 0.1
    before = tau <= 1e-9
    straight = scene_mask(info, lambda s: s.scenario in LANE_SCENARIOS)
    cells: list[tuple[str, FloatArray, FloatArray]] = []
    for comp in (False, True):
        label = "compliant" if comp else "non-compliant"
        cells.append(
            (
                f"{label}, all",
                w.compliance,
                straight * scene_mask(info, lambda s, c=comp: s.compliant == c),
            )
        )
        for robot in ("hsr", "jackal"):
            cells.append(
                (
                    f"{label}, {robot}",
                    w.cell,
                    straight
                    * scene_mask(
                        info, lambda s, c=comp, r=robot: s.compliant == c and s.robot == r
                    ),
                )
            )
        for scenario in LANE_SCENARIOS:
            boot = Boot(g, SEED + 7 + len(cells))
            pool = [i for i, s in enumerate(info) if s.scenario == scenario and s.compliant == comp]
            cells.append(
                (
                    f"{label}, {scenario.replace('_', ' ')}",
                    boot.within([pool]),
                    scene_mask(
                        info, lambda s, c=comp, sc=scenario: s.compliant == c and s.scenario == sc
                    ),
                )
            )
    rows: list[dict[str, Any]] = []
    for name, wts, mask in cells:
        keep = mask[ev["scene"]] > 0
        row: dict[str, Any] = {"cell": name, "n": _n(ev, keep)}
        est, boot = boot_mean(ev["lane_offset"], ev["scene"], g, wts, mask)
        row["lane_offset"] = summary(est, boot, row["n"]["scenes"])
        est, boot = boot_mean(ev["lane_other_ref"], ev["scene"], g, wts, mask)
        row["robot_lane_ref"] = summary(est, boot)
        est, boot = boot_mean(ev["d_pass"], ev["scene"], g, wts, mask)
        row["d_pass"] = summary(est, boot)
        # time course and its onset (x = time before the pass)
        x = ev["lane_course"][keep]
        sc = ev["scene"][keep]
        s = np.zeros((g, x.shape[1]))
        np.add.at(s, sc, x)
        n = np.bincount(sc, minlength=g).astype(np.float64)[:, None] * np.ones(x.shape[1])
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = s.sum(0) / n.sum(0)
            bmean = (wts @ s) / (wts @ n)
        lo, hi = np.nanpercentile(bmean, [2.5, 97.5], axis=0)
        row["course"] = {"mean": mean.tolist(), "lo": lo.tolist(), "hi": hi.tolist()}
        if keep.sum() >= 5:
            xs = -tau[before][::-1]
            m0 = mean[before][::-1][None]
            mb = bmean[:, before][:, ::-1]
            ones = np.ones_like(m0)
            x0, b0, _ = hinge(xs, m0, ones)
            xb, bb, _ = hinge(xs, mb, np.ones_like(mb))
            d_at = ev["course_d"][keep]
            k_on = int(np.argmin(np.abs(tau + x0[0])))
            row["onset_s"] = {
                "x_on": float(x0[0]),
                "x_on_ci": np.nanpercentile(xb, [2.5, 97.5]).tolist(),
                "slope": float(b0[0]),
                "slope_ci": np.nanpercentile(bb, [2.5, 97.5]).tolist(),
                "slope_p": boot_p(bb) if row["n"]["scenes"] >= MIN_SCENES_P else math.nan,
                "d_at_onset_median": float(np.median(d_at[:, k_on])),
            }
        rows.append(row)
    for r, p in zip(rows, holm([r["lane_offset"]["p"] for r in rows]), strict=True):
        r["lane_offset"]["p_holm"] = p
    return {"rows": rows, "tau": tau.tolist()}


# ======================================================================================
# Part 2: encounter-aligned windows, a known response fitted back

# The known response (tests/datasets/test_protocol.py's TRUE): a pedestrian part that
# reaches its goal, an anisotropic robot part that is none of the presets.
KNOWN = {
    "a_ped": 2.0,
    "b_ped": 0.5,
    "lambda_ped": 0.4,
    "tau": 0.8,
    "a_robot": 3.0,
    "b_robot": 0.6,
    "lambda_robot": 0.4,
}
# tests/datasets/test_fitting.py's TRUE, for the fully synthetic streams
KNOWN_STREAMS = {**KNOWN, "tau": 0.6, "a_robot": 6.0, "b_robot": 0.8}
LEADS = (2.0, 3.0, 4.0)


def _window_choices() -> list[tuple[str, Any]]:
    from srfm.fitting import WindowConfig

    out: list[tuple[str, Any]] = [
        (
            "every 1.2 s, goal = track end (the current protocol)",
            WindowConfig(stride_s=1.2, min_start_speed_mps=0.3),
        )
    ]
    for goal in ("track_end", "heading"):
        for lead in LEADS:
            out.append(
                (
                    f"encounter, lead {lead:g} s, goal = {goal.replace('_', ' ')}",
                    WindowConfig(
                        align="encounter", lead_s=lead, goal=goal, min_start_speed_mps=0.3
                    ),
                )
            )
    return out


def _errors(windows: Any, sel: IntArray, params: Any, mode: str) -> dict[str, Any]:
    from srfm.fitting import pass_errors, predict, window_errors

    ade, fde = window_errors(windows, sel, params, mode)
    dist, off = pass_errors(windows, sel, predict(windows, params, sel, mode))
    return {
        "ade": float(ade.mean()),
        "fde": float(fde.mean()),
        "pass_distance_abs": float(np.nanmean(np.abs(dist))),
        "pass_distance_bias": float(np.nanmean(dist)),
        "path_offset_abs": float(np.nanmean(np.abs(off))),
    }


def recovery(scenes: Sequence[Trajectories], known: Any, label: str) -> list[dict[str, Any]]:
    """The robot part fitted back (pedestrian part known) with every window choice."""
    from srfm.fitting import build_windows, fit_robot_part
    from srfm.models import SRFMParams

    start = known.replace(
        a_robot=SRFMParams().a_robot, b_robot=SRFMParams().b_robot, lambda_robot=1.0
    )
    rows: list[dict[str, Any]] = []
    for name, config in _window_choices():
        windows = build_windows(scenes, config)
        sel = windows.select(True)
        row: dict[str, Any] = {
            "data": label,
            "windows": name,
            "n": int(sel.size),
            "tracks": int(np.unique(windows.track[sel]).size),
        }
        if sel.size:
            fitted = fit_robot_part(windows, start, multi_start=False)
            row["fitted"] = {f: getattr(fitted, f) for f in ("a_robot", "b_robot", "lambda_robot")}
            row["errors_fitted"] = _errors(windows, sel, fitted, "srfm")
            row["errors_known"] = _errors(windows, sel, known, "srfm")
            row["errors_ignored"] = _errors(windows, sel, known, "sfm")
        rows.append(row)
        log(f"recovery {label}: {name}: {row.get('fitted')}")
    return rows


def real_windows(scenes: Sequence[Trajectories]) -> list[dict[str, Any]]:
    """ADE, FDE, pass-distance and path-offset errors of the published parameter sets on
    the real NavWareSet encounter windows (lead 3 s; both goals)."""
    from srfm.fitting import WindowConfig, build_windows
    from srfm.models import SRFMParams

    agrawal = SRFMParams.preset("agrawal2024")
    nws = SRFMParams.preset("navwareset2025")
    models = [
        ("constant velocity", agrawal, "constant_velocity"),
        ("robot ignored (agrawal2024 pedestrian part)", agrawal, "sfm"),
        ("robot as pedestrian", agrawal, "robot_as_pedestrian"),
        ("SRFM agrawal2024", agrawal, "srfm"),
        (
            "SRFM navwareset2025 robot part",
            agrawal.replace(**{f: getattr(nws, f) for f in ("a_robot", "b_robot", "lambda_robot")}),
            "srfm",
        ),
    ]
    rows: list[dict[str, Any]] = []
    for goal in ("heading", "track_end"):
        config = WindowConfig(align="encounter", lead_s=LEAD_S, goal=goal, min_start_speed_mps=0.3)
        windows = build_windows(scenes, config)
        sel = windows.select(True)
        for robot in ("all", "hsr", "jackal"):
            pick = (
                sel
                if robot == "all"
                else sel[[scenes[i].source["robot"] == robot for i in windows.scene[sel]]]
            )
            n_scenes = len({scenes[i].source["navwareset_scene"] for i in windows.scene[pick]})
            for name, params, mode in models:
                rows.append(
                    {
                        "goal": goal,
                        "robot": robot,
                        "model": name,
                        "n": int(pick.size),
                        "tracks": int(np.unique(windows.track[pick]).size),
                        "scenes": n_scenes,
                        **_errors(windows, pick, params, mode),
                    }
                )
    return rows


def part2(data_root: Path) -> dict[str, Any]:
    from srfm.models import SRFMParams
    from tests.datasets._synthetic import resimulate_pedestrian, simulate_scene

    known = SRFMParams(**KNOWN)
    excerpt = read_navwareset(data_root / "navwareset")
    quant, _ = drop_supersets(read_navwareset(data_root / "navwareset_quant"))
    single = [s for s in quant if s.source["format"] == "1"]
    out: dict[str, Any] = {"known": KNOWN, "known_streams": KNOWN_STREAMS, "recovery": []}
    out["recovery"] += recovery(
        [resimulate_pedestrian(s, known) for s in excerpt],
        known,
        "12 recorded robots (the excerpt; the test of docs/fitting.md)",
    )
    resim = [resimulate_pedestrian(s, known) for s in single]
    out["recovery"] += recovery(
        resim, known, f"{len(single)} recorded robots (every format-1 recording)"
    )
    for scenario in SCENARIO_ORDER[:4]:
        part = [s for s in resim if s.source["scenario"] == scenario]
        out["recovery"] += recovery(
            part, known, f"{len(part)} recorded robots, {scenario.replace('_', ' ')}"
        )
    streams_known = SRFMParams(**KNOWN_STREAMS)
    streams = [simulate_scene(streams_known, s, name=f"r{s}", robot=True) for s in range(30, 36)]
    out["recovery"] += recovery(
        streams, streams_known, "6 synthetic scenes, two streams and a robot"
    )
    out["real"] = real_windows(quant)
    return out


def part2_tables(r: dict[str, Any]) -> str:
    k, ks = r["known"], r["known_streams"]
    out = [
        f"### Recovery of a known robot response (A_r = {k['a_robot']:g}, "
        f"B_r = {k['b_robot']:g} m, λ_r = {k['lambda_robot']:g}; the streams: "
        f"A_r = {ks['a_robot']:g}, B_r = {ks['b_robot']:g} m, λ_r = {ks['lambda_robot']:g}), "
        "pedestrian part known, goals and desired speeds estimated",
        "",
    ]
    rows = []
    for row in r["recovery"]:
        if "fitted" not in row:
            rows.append([row["data"], row["windows"], "0", *["–"] * 7])
            continue
        f, e, i = row["fitted"], row["errors_fitted"], row["errors_ignored"]
        rows.append(
            [
                row["data"],
                row["windows"],
                f"{row['n']} / {row['tracks']}",
                f"{f['a_robot']:.2f}",
                f"{f['b_robot']:.3f}",
                f"{f['lambda_robot']:.2f}",
                f"{e['ade']:.3f} / {e['fde']:.3f}",
                f"{e['pass_distance_abs']:.3f}",
                f"{e['path_offset_abs']:.3f}",
                f"{i['ade']:.3f}, {i['pass_distance_abs']:.3f}, {i['path_offset_abs']:.3f}",
            ]
        )
    out += _table(
        [
            "data",
            "windows",
            "n (windows / tracks)",
            "A_r",
            "B_r (m)",
            "λ_r",
            "ADE / FDE (m)",
            "\\|pass-distance error\\| (m)",
            "\\|path-offset error\\| (m)",
            "robot ignored: ADE, \\|pass\\|, \\|offset\\| (m)",
        ],
        rows,
    )
    out += ["### Real NavWareSet encounter windows (lead 3 s): the published parameter sets", ""]
    rows = [
        [
            row["goal"].replace("_", " "),
            row["robot"],
            row["model"],
            f"{row['n']} / {row['tracks']} / {row['scenes']}",
            f"{row['ade']:.3f}",
            f"{row['fde']:.3f}",
            f"{row['pass_distance_abs']:.3f}",
            f"{row['pass_distance_bias']:+.3f}",
            f"{row['path_offset_abs']:.3f}",
        ]
        for row in r["real"]
    ]
    out += _table(
        [
            "goal",
            "robot",
            "model",
            "n (windows / tracks / scenes)",
            "ADE (m)",
            "FDE (m)",
            "\\|pass-distance error\\| (m)",
            "pass-distance bias (m)",
            "\\|path-offset error\\| (m)",
        ],
        rows,
    )
    return "\n".join(out)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    """A Markdown table (and a blank line after it)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return [*lines, ""]


def _nn(n: dict[str, int]) -> str:
    return f"{n['rows']} / {n['tracks']} / {n['scenes']}"


def _onset(o: dict[str, Any], digits: int = 2) -> str:
    return f"{o['x_on']:.{digits}f} ({o['x_on_ci'][0]:.{digits}f}–{o['x_on_ci'][1]:.{digits}f})"


def _slope(o: dict[str, Any]) -> str:
    return (
        f"{o['slope']:+.3f} ({o['slope_ci'][0]:+.3f} to {o['slope_ci'][1]:+.3f}), "
        f"p {_p(o['slope_p'])}"
    )


# ======================================================================================
# Figures


def _band(ax: Any, cv: dict[str, Any], label: str, color: str) -> None:
    x = np.asarray(cv["centre"])
    ok = np.asarray(cv["n"]) >= MIN_BIN_N
    m, lo, hi = (np.asarray(cv[k], dtype=float) for k in ("mean", "lo", "hi"))
    ax.plot(x[ok], m[ok], "-", color=color, label=label, lw=1.5)
    ax.fill_between(x[ok], lo[ok], hi[ok], color=color, alpha=0.2, lw=0)


def _save(fig: Any, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})


COLORS = {
    "robot": "k",
    "HSR": "tab:blue",
    "Jackal": "tab:red",
    "pedestrian": "tab:green",
    "compliant": "tab:purple",
    "non-compliant": "tab:orange",
    "frontal_approach": "tab:blue",
    "pedestrian_obstruction": "tab:brown",
    "blind_corner": "tab:gray",
    "perpendicular_crossing": "tab:red",
    "circular_crossing": "tab:olive",
}


def figures(results: dict[str, Any], out: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = results["curves"]
    names: list[str] = []

    def panel(ax: Any, key: str, groups: Sequence[str], xlabel: str, ylabel: str) -> None:
        for gname in groups:
            _band(ax, c[gname][key], gname.replace("_", " "), COLORS.get(gname, "k"))
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)

    fig, axs = plt.subplots(2, 3, figsize=(14, 7.5))
    main = ("HSR", "Jackal", "pedestrian")
    panel(axs[0, 0], "a_away~d", main, "distance d (m), approaching", "a_away (m/s²)")
    panel(
        axs[0, 1],
        "a_away~tstar",
        main,
        "time to closest approach t* (s), d* ≤ 1 m",
        "a_away (m/s²)",
    )
    panel(axs[0, 2], "a_away~dstar", main, "predicted miss d* (m), 0 < t* ≤ 3 s", "a_away (m/s²)")
    panel(axs[1, 0], "a_t~d", main, "distance d (m), approaching", "a_t, speed change (m/s²)")
    panel(axs[1, 1], "a_t~tstar", main, "t* (s), d* ≤ 1 m", "a_t (m/s²)")
    panel(axs[1, 2], "abs_a_n~d", main, "distance d (m), approaching", "|a_n| (m/s²)")
    base = results["magnitudes"]["samples"]["no one within 4 m"]["abs_a_n"]
    axs[1, 2].axhline(base["est"], color="0.3", ls="--", lw=1, label="no one within 4 m")
    axs[1, 2].legend(fontsize=7)
    fig.suptitle(
        "Pedestrian response against the robot (HSR, Jackal) and another pedestrian: "
        f"bin means, 95 % bootstrap over scenes (bins with n ≥ {MIN_BIN_N})"
    )
    _save(fig, out / "response_curves.png")
    names.append("response_curves.png")

    fig, axs = plt.subplots(1, 3, figsize=(14, 4))
    panel(
        axs[0],
        "a_away~bearing",
        main,
        "bearing of the other (deg), d ≤ 4 m, approaching",
        "a_away (m/s²)",
    )
    panel(
        axs[1],
        "a_away~relspeed",
        main,
        "relative speed (m/s), d ≤ 3 m, approaching",
        "a_away (m/s²)",
    )
    m = results["tstar_dstar_map"]
    im = axs[2].imshow(
        np.asarray(m["mean"], dtype=float).T,
        origin="lower",
        aspect="auto",
        extent=(
            m["tstar_edges"][0],
            m["tstar_edges"][-1],
            m["dstar_edges"][0],
            m["dstar_edges"][-1],
        ),
        cmap="RdBu_r",
        vmin=-0.3,
        vmax=0.3,
    )
    fig.colorbar(im, ax=axs[2], label="a_away (m/s²), robot samples")
    axs[2].set_xlabel("t* (s)")
    axs[2].set_ylabel("d* (m)")
    _save(fig, out / "bearing_speed_map.png")
    names.append("bearing_speed_map.png")

    fig, axs = plt.subplots(1, 3, figsize=(14, 4))
    scen = SCENARIO_ORDER
    panel(axs[0], "a_away~d", scen, "distance d (m), approaching robot", "a_away (m/s²)")
    panel(axs[1], "a_away~tstar", scen, "t* (s), d* ≤ 1 m", "a_away (m/s²)")
    panel(axs[2], "a_t~tstar", scen, "t* (s), d* ≤ 1 m", "a_t (m/s²)")
    _save(fig, out / "by_scenario.png")
    names.append("by_scenario.png")

    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    comp = ("HSR compliant", "HSR non-compliant", "Jackal compliant", "Jackal non-compliant")
    cols = ("tab:blue", "tab:cyan", "tab:red", "tab:orange")
    for gname, col in zip(comp, cols, strict=True):
        _band(axs[0], c[gname]["a_away~d"], gname, col)
        _band(axs[1], c[gname]["a_t~d"], gname, col)
    for ax, lab in zip(axs, ("a_away (m/s²)", "a_t (m/s²)"), strict=True):
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_xlabel("distance d (m), approaching robot")
        ax.set_ylabel(lab)
        ax.legend(fontsize=7)
    _save(fig, out / "compliance.png")
    names.append("compliance.png")

    tc = results["time_courses"]
    tau = np.asarray(tc["tau"])
    fig, axs = plt.subplots(1, 3, figsize=(14, 4))
    for gname in ("HSR", "Jackal", "pedestrian"):
        for ax, col in zip(axs, ("course_offset", "course_speed", "course_a_away"), strict=True):
            e = tc[gname][col]
            ax.plot(
                tau, e["mean"], color=COLORS[gname], label=f"{gname} (n = {tc[gname]['n']['rows']})"
            )
            ax.fill_between(tau, e["lo"], e["hi"], color=COLORS[gname], alpha=0.2, lw=0)
    for ax, lab in zip(
        axs,
        (
            "offset from the t_ref line, signed away (m)",
            "speed / speed at t_ref",
            "a_away, sign of t_ref (m/s²)",
        ),
        strict=True,
    ):
        ax.axvline(-LEAD_S, color="0.5", ls=":", lw=1)
        ax.axvline(0, color="0.5", lw=0.8)
        ax.set_xlabel("time to the observed pass (s)")
        ax.set_ylabel(lab)
        ax.legend(fontsize=7)
    _save(fig, out / "time_courses.png")
    names.append("time_courses.png")
    plt.close("all")
    return names


# ======================================================================================
# Tables and main


def _strip(obj: Any) -> Any:
    """JSON-ready: drop the private (per-scene) arrays, floats rounded to 6 digits."""
    if isinstance(obj, dict):
        return {k: _strip(v) for k, v in obj.items() if not str(k).startswith("_")}
    if isinstance(obj, (list, tuple)):
        return [_strip(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return None if not math.isfinite(f) else float(f"{f:.6g}")
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def _ci(s: dict[str, Any], fmt: str = "{:+.3f}") -> str:
    return f"{fmt.format(s['est'])} ({fmt.format(s['ci'][0])} to {fmt.format(s['ci'][1])})"


def _p(p: float | None) -> str:
    if p is None or not math.isfinite(p):
        return "–"
    return f"{p:.2g}" if p >= 0.001 else "< 0.001"


def part1_tables(r: dict[str, Any]) -> str:
    out = ["### n", ""]
    out += _table(
        ["population", "rows", "tracks", "scenes"],
        [[k, str(v["rows"]), str(v["tracks"]), str(v["scenes"])] for k, v in r["n"].items()],
    )
    out += ["### Confirmatory tests (Holm over the 8)", ""]
    rows = []
    for i, t in enumerate(r["confirmatory"]["tests"], 1):
        n = t["n"]
        ns = _nn(n) if "rows" in n else "; ".join(f"{k}: {_nn(v)}" for k, v in n.items())
        rows.append([str(i), t["test"], _ci(t), ns, _p(t["p"]), _p(t["p_holm"])])
    out += _table(
        ["#", "test", "estimate (95 % CI)", "n (rows / tracks / scenes)", "p", "p (Holm)"], rows
    )
    out += ["### Onsets (hinge of a_away; those of all robot samples are confirmatory)", ""]
    rows = []
    for name, c in r["curves"].items():
        od, ot = c["onset_d"], c["onset_tstar"]
        rows.append(
            [
                name.replace("_", " "),
                _nn(c["n_approaching"]),
                _onset(od),
                _slope(od),
                _onset(ot),
                _slope(ot),
            ]
        )
    out += _table(
        [
            "samples",
            "n approaching (rows / tracks / scenes)",
            "d_on (m)",
            "slope below d_on (m/s² per m)",
            "t*_on (s), d* ≤ 1 m",
            "slope below t*_on (m/s² per s)",
        ],
        rows,
    )
    out += [
        "### The avoidance phase and the steering magnitude "
        "(exploratory, chosen after seeing the curves)",
        "",
    ]
    rows = []
    for name, c in r["curves"].items():
        pk = c["peak_avoid"]
        rows.append(
            [
                name.replace("_", " "),
                _nn(c["n_course"]),
                _onset(c["onset_tstar_avoid"]),
                _slope(c["onset_tstar_avoid"]),
                _onset(c["onset_d_avoid"]),
                _slope(c["onset_d_avoid"]),
                f"{pk['value']:+.3f} ({pk['value_ci'][0]:+.3f} to {pk['value_ci'][1]:+.3f})",
                f"{pk['at']:.2f} ({pk['at_ci'][0]:.2f}–{pk['at_ci'][1]:.2f})",
                f"{_onset(c['onset_abs_a_n_d'])}; {_slope(c['onset_abs_a_n_d'])}",
                f"{_onset(c['onset_abs_a_n_tstar'])}; {_slope(c['onset_abs_a_n_tstar'])}",
            ]
        )
    out += _table(
        [
            "samples",
            "n, d* ≤ 1 m (rows / tracks / scenes)",
            "avoidance onset t*_on (s), fit at t* ≥ 1 s",
            "its slope (m/s² per s)",
            "avoidance onset d_on (m), fit at d ≥ 1.5 m",
            "its slope (m/s² per m)",
            "peak a_away (m/s²)",
            "at t* (s)",
            "\\|a_n\\| onset d (m); slope",
            "\\|a_n\\| onset t* (s); slope",
        ],
        rows,
    )
    out += ["### Event measures per cell (exploratory; Holm over every p of the table)", ""]
    rows = []
    for row in r["event_table"]["rows"]:
        rows.append(
            [
                row["cell"],
                _nn(row["n"]),
                _ci(row["offset"]),
                _p(row["offset"].get("p_holm")),
                _ci(row["heading"], "{:+.1f}"),
                _p(row["heading"].get("p_holm")),
                _ci(row["speed_change"]),
                _p(row["speed_change"].get("p_holm")),
                f"{row['d_pass']['est']:.2f}",
                f"{row['dstar_ref']['est']:.2f}",
            ]
        )
    out += _table(
        [
            "cell",
            "n (enc. / tracks / scenes)",
            "path offset (m)",
            "p (Holm)",
            "heading change (deg)",
            "p (Holm)",
            "speed change",
            "p (Holm)",
            "pass distance (m)",
            "d*_ref (m)",
        ],
        rows,
    )
    out += ["### Magnitudes beside the no-one-near baseline (exploratory)", ""]
    rows = [
        [
            name,
            _nn(row["n"]),
            _ci(row["abs_a_n"]),
            _ci(row["abs_omega"], "{:.1f}"),
            _ci(row["a_t"]),
            _ci(row["abs_a_t"]),
            _ci(row["speed"]),
        ]
        for name, row in r["magnitudes"]["samples"].items()
    ]
    out += _table(
        [
            "samples",
            "n (rows / tracks / scenes)",
            "\\|a_n\\| (m/s²)",
            "\\|ω\\| (deg/s)",
            "a_t (m/s²)",
            "\\|a_t\\| (m/s²)",
            "speed (m/s)",
        ],
        rows,
    )
    rows = [
        [
            name,
            _nn(row["n"]),
            _ci(row["abs_offset"]),
            _ci(row["abs_heading"], "{:.1f}"),
            _ci(row["speed_change"]),
        ]
        for name, row in r["magnitudes"]["events"].items()
        if "n" in row
    ]
    out += _table(
        [
            "events",
            "n (rows / tracks / scenes)",
            "\\|path offset\\| (m)",
            "\\|heading change\\| (deg)",
            "speed change",
        ],
        rows,
    )
    out += [
        "### The lane frame (added after the confirmatory results; exploratory, Holm over "
        "the rows)",
        "",
    ]
    rows = []
    for row in r["lane"]["rows"]:
        o = row.get("onset_s")
        rows.append(
            [
                row["cell"],
                _nn(row["n"]),
                _ci(row["lane_offset"]),
                _p(row["lane_offset"].get("p_holm")),
                f"{row['robot_lane_ref']['est']:.2f}",
                _onset(o) if o else "–",
                _slope(o) if o else "–",
                f"{o['d_at_onset_median']:.2f}" if o else "–",
            ]
        )
    out += _table(
        [
            "cell",
            "n (enc. / tracks / scenes)",
            "lane offset at the pass, away from the robot's side at t_ref (m)",
            "p (Holm)",
            "robot's distance from the lane at t_ref (m)",
            "onset before the pass (s)",
            "slope (m/s)",
            "robot distance at onset (m, median)",
        ],
        rows,
    )
    return "\n".join(out)


def tables_text(saved: dict[str, Any]) -> str:
    """``tables.md``: the tables of the parts a saved ``results.json`` holds, from the
    numbers as saved (rounded by ``_strip``; its keys in the order they were computed,
    which is the tables' order), so that the committed page is what its data give
    (``make docs-tables`` rewrites it with this function)."""
    text = []
    if "part1" in saved:
        text.append("## Part 1\n\n" + part1_tables(saved["part1"]))
    if "part2" in saved:
        text.append("## Part 2\n\n" + part2_tables(saved["part2"]))
    return "\n".join(text)


def part1(root: Path, seed: int) -> dict[str, Any]:
    data = load(root)
    w = weights(data.info, seed)
    n = {f"{k} samples": _n(v) for k, v in data.samples.items()}
    n.update(
        {
            f"{k} encounters" if k != "baseline" else "baseline stretches (3 s)": _n(v)
            for k, v in data.events.items()
        }
    )
    n["all (rows: recordings)"] = {
        "rows": data.n_recordings,
        "tracks": data.n_tracks,
        "scenes": len(data.info),
    }
    log("confirmatory")
    results: dict[str, Any] = {
        "n": n,
        "scenes": [s._asdict() for s in data.info],
        "confirmatory": confirmatory(data, w),
    }
    log("curves")
    results["curves"] = curves(data, w)
    results["event_table"] = event_table(data, w)
    results["magnitudes"] = magnitudes(data, w)
    results["time_courses"] = time_courses(data, w)
    results["tstar_dstar_map"] = tstar_dstar_map(data)
    results["lane"] = lane_analysis(data, w)
    return results


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--data", type=Path, default=None, help="default $SRFM_DATA_DIR (../shared/data)"
    )
    ap.add_argument("--out", type=Path, default=REPO / "docs" / "real_encounters")
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--part", choices=("1", "2", "all"), default="all")
    args = ap.parse_args()
    root = args.data or Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))
    args.out.mkdir(parents=True, exist_ok=True)
    began = start()
    t0 = time.perf_counter()
    payload: dict[str, Any] = {}
    if args.part in ("1", "all"):
        r1 = part1(root / "navwareset_quant", args.seed)
        payload["part1"] = r1
        payload["part1_figures"] = figures(r1, args.out)
    if args.part in ("2", "all"):
        payload["part2"] = part2(root)
    payload["run"] = run_record(*began)
    saved = json.dumps(_strip(payload), indent=1) + "\n"
    tables = tables_text(json.loads(saved))
    print(tables)
    (args.out / "tables.md").write_text(tables)
    (args.out / "results.json").write_text(saved)
    log(f"done in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
