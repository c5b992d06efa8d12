"""Synthetic data for the dataset and fitting tests: JRDB-format files and SRFM-simulated scenes."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import srfm
from srfm.datasets import PEDESTRIAN, ROBOT, Trajectories
from srfm.fitting import WindowConfig, build_windows, predict

RATE_HZ = 15.0


# --------------------------------------------------------------------------------------
# JRDB: a robot that drives and turns, a pedestrian standing still, one walking.


def robot_poses(n_frames: int) -> NDArray[np.float64]:
    """(F, 3) robot poses (x, y, yaw) in the odometry frame: forward, turning left, back."""
    t = np.arange(n_frames) / RATE_HZ
    yaw = 0.3 + 0.8 * np.sin(0.35 * t) + 0.05 * t  # turns both ways, not periodic
    speed = 0.6
    # Integrate the unicycle exactly enough: small steps, then sample.
    x = 1.0 + np.concatenate([[0.0], np.cumsum(speed * np.cos(yaw[:-1]) / RATE_HZ)])
    y = -2.0 + np.concatenate([[0.0], np.cumsum(speed * np.sin(yaw[:-1]) / RATE_HZ)])
    return np.stack([x, y, yaw], axis=1)


STANDING_WORLD = (3.0, 2.0)


def walker_world(n_frames: int) -> NDArray[np.float64]:
    """(F, 2) world positions of a pedestrian walking at 1.1 m/s along a diagonal."""
    t = np.arange(n_frames) / RATE_HZ
    return np.stack([-1.0 + 0.9 * t, 4.0 - 0.63 * t], axis=1)


def to_robot_frame(world: NDArray[np.float64], pose: NDArray[np.float64]) -> NDArray[np.float64]:
    """World point(s) -> the robot frame (x forward, y left) of ``pose`` = (x, y, yaw)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    d = np.asarray(world, dtype=np.float64) - pose[:2]
    return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)


def quaternion_z(yaw: float) -> dict[str, float]:
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}


def write_jrdb(
    root: Path,
    sequence: str = "synthetic-lab-2024-01-01_0",
    n_frames: int = 90,
    *,
    first_frame: int = 0,
    t0_s: float = 1549578463.25,
    pose_layout: str = "quaternion",
) -> dict[str, object]:
    """Write one JRDB-format sequence under ``root``; return the ground truth.

    Layout: ``root/labels/labels_3d/<seq>.json``, ``root/timestamps/<seq>/frames_pc.json``
    and ``root/odometry/<seq>.json``. The standing pedestrian ("pedestrian:3") is
    absent from every 7th frame (occlusion) and the walker ("pedestrian:12") appears from
    frame 10 on, so frames, ids and gaps all have to round-trip.
    """
    poses = robot_poses(n_frames)
    walker = walker_world(n_frames)
    frames = list(range(first_frame, first_frame + n_frames))
    # Timestamps: 15 Hz with a little jitter, strictly increasing.
    jitter = 0.002 * np.sin(np.arange(n_frames) * 1.7)
    times = t0_s + np.arange(n_frames) / RATE_HZ + jitter
    labels: dict[str, list[dict[str, object]]] = {}
    for k, frame in enumerate(frames):
        name = f"{frame:06d}.pcd"
        items: list[dict[str, object]] = []
        if k % 7 != 3:
            sx, sy = to_robot_frame(np.array(STANDING_WORLD), poses[k])
            items.append(_label("pedestrian:3", float(sx), float(sy)))
        if k >= 10:
            wx, wy = to_robot_frame(walker[k], poses[k])
            items.append(_label("pedestrian:12", float(wx), float(wy)))
        labels[name] = items
    seq_labels = root / "labels" / "labels_3d" / f"{sequence}.json"
    seq_labels.parent.mkdir(parents=True, exist_ok=True)
    seq_labels.write_text(json.dumps({"labels": labels}, indent=1))
    ts_path = root / "timestamps" / sequence / "frames_pc.json"
    ts_path.parent.mkdir(parents=True, exist_ok=True)
    data = [
        {
            "frame_id": frame,
            "pointclouds": [
                {
                    "name": "lower_velodyne",
                    "url": f"pointclouds/lower_velodyne/{sequence}/{frame:06d}.pcd",
                    "timestamp": float(times[k]) + 0.01,
                },
                {
                    "name": "upper_velodyne",
                    "url": f"pointclouds/upper_velodyne/{sequence}/{frame:06d}.pcd",
                    "timestamp": float(times[k]),
                },
            ],
        }
        for k, frame in enumerate(frames)
    ]
    ts_path.write_text(json.dumps({"data": data}))
    odometry: dict[str, object] = {}
    for k, frame in enumerate(frames):
        x, y, yaw = poses[k]
        if pose_layout == "quaternion":
            odometry[f"{frame:06d}.pcd"] = {
                "position": {"x": float(x), "y": float(y), "z": 0.0},
                "orientation": quaternion_z(float(yaw)),
            }
        else:
            odometry[f"{frame:06d}.pcd"] = {"x": float(x), "y": float(y), "yaw": float(yaw)}
    odo_path = root / "odometry" / f"{sequence}.json"
    odo_path.parent.mkdir(parents=True, exist_ok=True)
    odo_path.write_text(json.dumps({"odometry": odometry}))
    return {
        "sequence": sequence,
        "labels": seq_labels,
        "timestamps": ts_path,
        "odometry": odo_path,
        "frames": np.array(frames),
        "t_ns": np.array([round(t * 1e9) for t in times.tolist()]),
        "poses": poses,
        "walker": walker,
    }


def _label(label_id: str, cx: float, cy: float) -> dict[str, object]:
    return {
        "label_id": label_id,
        "box": {"cx": cx, "cy": cy, "cz": -0.2, "l": 0.5, "w": 0.6, "h": 1.7, "rot_z": 0.1},
        "attributes": {"distance": math.hypot(cx, cy), "occlusion": "Fully_visible"},
    }


# --------------------------------------------------------------------------------------
# Scenes simulated with the SRFM itself (for fitting and identifiability).


def simulate_scene(
    params: srfm.SRFMParams,
    seed: int,
    *,
    name: str,
    n_per_side: int = 5,
    robot: bool = False,
    noise_m: float = 0.0,
    dt: float = 1.0 / RATE_HZ,
    max_steps: int = 600,
    truth: dict[str, NDArray[np.float64]] | None = None,
) -> Trajectories:
    """Two opposing streams of pedestrians cross a 16 m corridor (and meet the robot).

    Every pedestrian has its own desired speed v0 ~ U(1.0, 1.4) m/s and speed cap
    1.3 v0 (the fitting protocol's convention), walks about 12 m to its goal and is
    recorded at every step until all are within 0.1 m of their goals. With ``robot``, a robot
    drives against the +x stream along the corridor's centre line at 0.5 m/s. Gaussian
    noise of ``noise_m`` (m) is added to every recorded pedestrian position. If
    ``truth`` is a dict, the true goals (N, 2) and desired speeds (N,) are stored in it.
    """
    rng = np.random.default_rng(seed)
    n = 2 * n_per_side
    # Lanes 3 m apart; goals on a permutation of the lanes (so paths cross), far enough
    # apart that neighbours standing at their goals barely push each other.
    lanes = np.linspace(1.0, 13.0, n_per_side)
    y0 = np.concatenate([lanes + rng.uniform(-0.4, 0.4, n_per_side) for _ in range(2)])
    y1 = np.concatenate(
        [rng.permutation(lanes) + rng.uniform(-0.2, 0.2, n_per_side) for _ in range(2)]
    )
    x0 = np.concatenate([rng.uniform(0.0, 2.0, n_per_side), rng.uniform(14.0, 16.0, n_per_side)])
    x1 = np.concatenate([x0[:n_per_side] + 12.0, x0[n_per_side:] - 12.0])
    v0 = rng.uniform(1.0, 1.4, n)
    crowd = srfm.CrowdState.create(
        pos=np.stack([x0, y0], axis=1),
        goal=np.stack([x1, y1], axis=1),
        v0=v0,
        vmax=1.3 * v0,
    )
    if truth is not None:
        truth["goal"] = crowd.goal.copy()
        truth["v0"] = v0.copy()
    robot_xy = np.array([16.0, 7.0])
    robot_vel = np.array([-0.5, 0.0])
    rows_xy: list[NDArray[np.float64]] = []
    rows_robot: list[NDArray[np.float64]] = []
    for _ in range(max_steps):
        rows_xy.append(crowd.pos.copy())
        rows_robot.append(robot_xy.copy())
        if np.max(np.linalg.norm(crowd.pos - crowd.goal, axis=1)) < 0.1:
            break
        body = srfm.RobotBody(x=float(robot_xy[0]), y=float(robot_xy[1])) if robot else None
        srfm.step_crowd(crowd, dt, params, robot=body, parallel=False)
        robot_xy = robot_xy + robot_vel * dt
    n_frames = len(rows_xy)
    xy = np.stack(rows_xy)  # (F, N, 2)
    if noise_m > 0:
        xy = xy + rng.normal(0.0, noise_m, xy.shape)
    n_agents = n + (1 if robot else 0)
    samples = xy
    if robot:
        samples = np.concatenate([xy, np.stack(rows_robot)[:, None, :]], axis=1)
    frames = np.arange(n_frames, dtype=np.int64)
    t_ns = np.rint(frames * dt * 1e9).astype(np.int64)
    return Trajectories.from_samples(
        scene=name,
        agent_ids=[f"p{i}" for i in range(n)] + (["robot"] if robot else []),
        kinds=[PEDESTRIAN] * n + ([ROBOT] if robot else []),
        agent=np.tile(np.arange(n_agents), n_frames),
        frame=np.repeat(frames, n_agents),
        t_ns=np.repeat(t_ns, n_agents),
        xy=samples.reshape(-1, 2),
        source={"dataset": "synthetic", "seed": str(seed)},
    )


def resimulate_pedestrian(
    scene: Trajectories, params: srfm.SRFMParams, truth: dict[str, list[object]] | None = None
) -> Trajectories:
    """The scene with its one pedestrian replaced by an SRFM pedestrian around the
    *recorded* robot: from the observed state 0.4 s into the track toward the track's
    last observed position, with the fitting protocol's v0 (the replay kernel, one
    window spanning the whole track). The first 0.4 s stay as observed. If ``truth`` is
    a dict, the goal (2,) and desired speed used are appended to its "goal" and "v0"."""
    peds = [i for i, k in enumerate(scene.kinds) if k == PEDESTRIAN]
    assert len(peds) == 1, "format-1 scenes only (one pedestrian)"
    mask = scene.agent == peds[0]
    n = int(np.count_nonzero(mask))
    dt = float(np.median(np.diff(scene.t_ns[mask]))) * 1e-9
    m_v = max(1, round(0.4 / dt))
    horizon = n - m_v - 1
    config = WindowConfig(horizon_s=horizon * dt, stride_s=1000.0)
    windows = build_windows([scene], config)
    assert windows.n_windows == 1
    assert int(windows.steps[0]) == horizon
    simulated = predict(windows, params, np.array([0], dtype=np.int64), "srfm")
    if truth is not None:
        truth.setdefault("goal", []).append(windows.goal[0].copy())
        truth.setdefault("v0", []).append(float(windows.v0[0]))
    xy = scene.xy.copy()
    track_rows = np.flatnonzero(mask)
    xy[track_rows[m_v + 1 :]] = simulated
    return Trajectories.from_samples(
        scene=f"{scene.scene}-resimulated",
        agent_ids=scene.agent_ids,
        kinds=scene.kinds,
        agent=scene.agent,
        frame=scene.frame,
        t_ns=scene.t_ns,
        xy=xy,
        source=dict(scene.source),
    )
