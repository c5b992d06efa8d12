"""Whole recorded encounters replayed: the deviation the benchmark would attribute to a
real robot, and what the people observably did.

For one pedestrian of a recorded scene, the SRFM simulates it from its observed state
when it starts walking (the first sample whose 0.4 s velocity reaches
``min_start_speed_mps``) to the end of its track, toward its last observed position,
twice: with the robot force (*factual*) and without it (*counterfactual*), while the
recorded robot and every other pedestrian move exactly as recorded (the replay kernel of
:mod:`srfm.fitting`). The benchmark's deviation is the discrete Fréchet distance between
the two simulated paths. The observed track gives the measures of how much the person
yielded: closest centre distance to the robot, detour (path length over straight-line
distance, minus one) and slow-down (one minus the lowest 1 s speed while the robot is
within the interaction radius, over the desired speed). See ``docs/fitting.md``.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.datasets._trajectories import PEDESTRIAN, Trajectories
from srfm.errors import ParameterError
from srfm.fitting._predict import predict
from srfm.fitting._windows import WindowConfig, build_windows
from srfm.metrics.frechet import frechet_distance
from srfm.models.params import SRFMParams

__all__ = ["Encounter", "replay_encounter"]

FloatArray = NDArray[np.float64]


@attrs.frozen(kw_only=True, eq=False)
class Encounter:
    """One pedestrian's recorded encounter, replayed.

    Attributes:
        agent_id: the pedestrian.
        observed, factual, counterfactual: (n, 2) positions (m) from the walking start
            (first row) to the end of the track: as recorded, simulated with the robot
            force, simulated without it.
        robot: (n, 2) the recorded robot at the same instants (NaN where not recorded).
        deviation_m: Fréchet distance between factual and counterfactual (m).
        ade_factual_m: mean distance between factual and observed (m).
        min_distance_m: closest observed centre distance to the robot (m).
        detour: observed path length / straight-line distance − 1.
        slowdown: 1 − (lowest observed 1 s speed while the robot is within the
            interaction radius) / (desired speed v0), in [0, 1]; NaN if it never is.
    """

    agent_id: str
    observed: FloatArray
    factual: FloatArray
    counterfactual: FloatArray
    robot: FloatArray
    deviation_m: float
    ade_factual_m: float
    min_distance_m: float
    detour: float
    slowdown: float


def replay_encounter(
    scene: Trajectories,
    agent_id: str,
    params: SRFMParams,
    *,
    min_start_speed_mps: float = 0.3,
    config: WindowConfig | None = None,
) -> Encounter | None:
    """Replay one pedestrian's whole encounter (see the module docstring).

    Args:
        scene: a world-frame scene with a robot.
        agent_id: a pedestrian of ``scene``.
        params: SRFM parameters of both simulations.
        min_start_speed_mps: the walking start's speed threshold (m/s).
        config: radii, substep, velocity and speed spans (horizon and stride are set
            here); the defaults of :class:`WindowConfig` when omitted.

    Returns:
        The encounter, or None when the pedestrian never walks, or its track after the
        walking start is broken by a detection gap or shorter than 1 s.

    Raises:
        ParameterError: ``agent_id`` is not a pedestrian of the scene, or the scene has no
            robot.
    """
    config = config or WindowConfig()
    if agent_id not in scene.agent_ids or (
        scene.kinds[scene.agent_ids.index(agent_id)] != PEDESTRIAN
    ):
        raise ParameterError(f"{agent_id!r} is not a pedestrian of scene {scene.scene!r}")
    robot = scene.robot_index
    if robot is None:
        raise ParameterError(f"scene {scene.scene!r} has no robot")
    frames, times = scene.frames()
    if frames.shape[0] < 3:
        return None
    dt = float(np.median(np.diff(times))) * 1e-9
    m_v = max(1, round(config.velocity_span_s / dt))
    a = scene.agent_ids.index(agent_id)
    mask = scene.agent == a
    xy = scene.xy[mask]
    t = scene.t_ns[mask].astype(np.float64) * 1e-9
    fr = scene.frame[mask]
    if xy.shape[0] <= m_v + 1:
        return None
    speed = np.linalg.norm(xy[m_v:] - xy[:-m_v], axis=1) / (t[m_v:] - t[:-m_v])
    walking = np.flatnonzero(speed >= min_start_speed_mps)
    if walking.size == 0:
        return None
    k0 = int(walking[0]) + m_v  # the walking start, with m_v samples before it
    first_frame = fr[k0 - m_v]
    keep = scene.frame >= first_frame
    trimmed = Trajectories.from_samples(
        scene=scene.scene,
        agent_ids=scene.agent_ids,
        kinds=scene.kinds,
        agent=scene.agent[keep],
        frame=scene.frame[keep],
        t_ns=scene.t_ns[keep],
        xy=scene.xy[keep],
        source=dict(scene.source),
    )
    tr_frames, tr_times = trimmed.frames()
    dt_nom = float(np.median(np.diff(tr_times.astype(np.float64) * 1e-9)))
    horizon = xy.shape[0] - k0 - 1
    if horizon * dt_nom < 1.0:
        return None
    windows = build_windows(
        [trimmed],
        attrs.evolve(config, horizon_s=horizon * dt_nom, stride_s=86400.0, min_start_speed_mps=0.0),
    )
    mine = np.flatnonzero(
        (windows.agent == a) & (windows.frame0 == 0 + int(np.searchsorted(tr_frames, fr[k0])))
    )
    if mine.size != 1 or int(windows.steps[mine[0]]) != horizon:
        return None  # a detection gap breaks the track
    sel = mine.astype(np.int64)
    factual = np.vstack([xy[k0], predict(windows, params, sel, "srfm")])
    counterfactual = np.vstack([xy[k0], predict(windows, params, sel, "sfm")])
    observed = xy[k0:]
    # the recorded robot at the same frames
    rmask = scene.agent == robot
    r_fr = scene.frame[rmask]
    r_xy = scene.xy[rmask]
    idx = np.searchsorted(r_fr, fr[k0:])
    found = (idx < r_fr.shape[0]) & (r_fr[np.minimum(idx, r_fr.shape[0] - 1)] == fr[k0:])
    robot_xy = np.full_like(observed, np.nan)
    robot_xy[found] = r_xy[idx[found]]
    dist = np.linalg.norm(observed - robot_xy, axis=1)
    length = float(np.sum(np.linalg.norm(np.diff(observed, axis=0), axis=1)))
    chord = float(np.linalg.norm(observed[-1] - observed[0]))
    v0 = float(windows.v0[sel[0]])
    m_s = max(1, round(config.speed_span_s / dt_nom))
    tt = t[k0:]
    near = dist[:-m_s] <= config.interaction_radius_m if observed.shape[0] > m_s else None
    if near is not None and np.any(near) and v0 > 0:
        s = np.linalg.norm(observed[m_s:] - observed[:-m_s], axis=1) / (tt[m_s:] - tt[:-m_s])
        slowdown = float(np.clip(1.0 - s[near].min() / v0, 0.0, 1.0))
    else:
        slowdown = math.nan
    return Encounter(
        agent_id=agent_id,
        observed=observed,
        factual=factual,
        counterfactual=counterfactual,
        robot=robot_xy,
        deviation_m=frechet_distance(factual, counterfactual),
        ade_factual_m=float(np.mean(np.linalg.norm(factual - observed, axis=1))),
        min_distance_m=float(np.nanmin(dist)) if np.any(found) else math.inf,
        detour=length / chord - 1.0 if chord > 0 else math.nan,
        slowdown=slowdown,
    )
