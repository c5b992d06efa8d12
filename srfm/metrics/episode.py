"""Episode metrics: how much a robot disturbed each pedestrian, and how the robot did.

Every metric is defined once here (name, unit, direction, definition): the CSV columns,
the JSON files, the tables and ``docs/metrics.md`` follow these definitions.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.metrics.frechet import frechet_distances
from srfm.sim.record import EpisodeRecord

__all__ = [
    "EPISODE_METRICS",
    "PEDESTRIAN_METRICS",
    "EpisodeMetrics",
    "MetricInfo",
    "episode_metrics",
]

FloatArray = NDArray[np.float64]


@attrs.frozen
class MetricInfo:
    """One metric: its column name, unit, which way is better, and its definition."""

    name: str
    unit: str
    better: Literal["lower", "higher", ""]
    definition: str


PEDESTRIAN_METRICS: Final[tuple[MetricInfo, ...]] = (
    MetricInfo(
        "frechet_m",
        "m",
        "lower",
        "Discrete Fréchet distance between the pedestrian's factual and counterfactual "
        "trajectories over the whole horizon (T + 1 samples each): the deviation.",
    ),
    MetricInfo(
        "mean_separation_m",
        "m",
        "lower",
        "Mean over the T + 1 samples of the distance between the factual and the "
        "counterfactual twin at the same time.",
    ),
    MetricInfo(
        "max_separation_m",
        "m",
        "lower",
        "Largest distance between the factual and the counterfactual twin at the same "
        "time (an upper bound of the Fréchet distance).",
    ),
    MetricInfo(
        "min_robot_distance_m",
        "m",
        "higher",
        "Smallest centre-to-centre distance between the robot and the factual pedestrian "
        "over the robot's episode (samples 0 to end_step).",
    ),
    MetricInfo(
        "min_robot_clearance_m",
        "m",
        "higher",
        "min_robot_distance_m minus the robot's and the pedestrian's radii; negative "
        "means overlap.",
    ),
    MetricInfo(
        "path_length_m",
        "m",
        "lower",
        "Length of the factual trajectory over the whole horizon.",
    ),
    MetricInfo(
        "counterfactual_path_length_m",
        "m",
        "",
        "Length of the counterfactual trajectory over the whole horizon.",
    ),
    MetricInfo(
        "extra_length_m",
        "m",
        "lower",
        "path_length_m minus counterfactual_path_length_m: the detour the robot caused.",
    ),
    MetricInfo(
        "time_to_goal_s",
        "s",
        "lower",
        "Time of the factual pedestrian's first arrival within the goal radius (NaN if "
        "it never arrives). Standing pedestrians (goal = start) arrive at the first step.",
    ),
    MetricInfo(
        "counterfactual_time_to_goal_s",
        "s",
        "",
        "The same for the counterfactual twin.",
    ),
    MetricInfo(
        "delay_s",
        "s",
        "lower",
        "time_to_goal_s minus counterfactual_time_to_goal_s (NaN unless both arrive).",
    ),
)

EPISODE_METRICS: Final[tuple[MetricInfo, ...]] = (
    MetricInfo(
        "frechet_m",
        "m",
        "lower",
        "Mean over pedestrians of frechet_m: the benchmark's deviation (paper Table 3).",
    ),
    MetricInfo("mean_separation_m", "m", "lower", "Mean over pedestrians of mean_separation_m."),
    MetricInfo("max_separation_m", "m", "lower", "Mean over pedestrians of max_separation_m."),
    MetricInfo(
        "min_robot_distance_m",
        "m",
        "higher",
        "Smallest centre-to-centre distance between the robot and any factual pedestrian "
        "over the robot's episode (paper Table 3).",
    ),
    MetricInfo(
        "min_robot_clearance_m",
        "m",
        "higher",
        "Smallest clearance (centre distance minus both radii) to any pedestrian over the "
        "robot's episode.",
    ),
    MetricInfo(
        "path_length_m",
        "m",
        "lower",
        "Mean over pedestrians of the factual path length (paper Table 3, trajectory length).",
    ),
    MetricInfo("extra_length_m", "m", "lower", "Mean over pedestrians of extra_length_m."),
    MetricInfo(
        "time_to_goal_s",
        "s",
        "lower",
        "Mean over the pedestrians that arrive of time_to_goal_s (paper Table 3, time); "
        "NaN if none arrives.",
    ),
    MetricInfo(
        "delay_s",
        "s",
        "lower",
        "Mean over the pedestrians that arrive in both twins of delay_s; NaN if none.",
    ),
    MetricInfo(
        "arrived_fraction",
        "1",
        "higher",
        "Fraction of pedestrians whose factual twin reaches its goal within the horizon.",
    ),
    MetricInfo("robot_success", "1", "higher", "1 if the robot reached its goal, else 0."),
    MetricInfo(
        "robot_collision",
        "1",
        "lower",
        "1 if the robot's episode ended in a collision (centre distance below the sum of "
        "radii, or touching an obstacle), else 0.",
    ),
    MetricInfo("robot_out_of_bounds", "1", "lower", "1 if the robot left the world, else 0."),
    MetricInfo("robot_timeout", "1", "lower", "1 if the robot was still driving at the horizon."),
    MetricInfo(
        "robot_time_to_goal_s",
        "s",
        "lower",
        "Time at which the robot reached its goal; NaN unless it succeeded.",
    ),
    MetricInfo(
        "robot_path_length_m",
        "m",
        "",
        "Length of the robot's path over its episode.",
    ),
    MetricInfo(
        "robot_mean_speed_mps",
        "m/s",
        "",
        "robot_path_length_m divided by the duration of the robot's episode (0 if it "
        "ended at step 0).",
    ),
)


@attrs.frozen(kw_only=True, eq=False)
class EpisodeMetrics:
    """The metrics of one twin episode.

    Attributes:
        scenario: scenario name.
        planner: planner name.
        seed: episode seed.
        outcome: how the robot's episode ended.
        end_step: the sample at which it ended.
        values: every :data:`EPISODE_METRICS` entry by name (floats, NaN where undefined).
        pedestrians: every :data:`PEDESTRIAN_METRICS` entry by name, (N,) arrays.
    """

    scenario: str
    planner: str
    seed: int
    outcome: str
    end_step: int
    values: Mapping[str, float]
    pedestrians: Mapping[str, FloatArray]

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def to_document(self) -> dict[str, Any]:
        """Plain JSON-ready data: identity, ``metrics`` and ``pedestrians`` by name, NaN
        as None (floats round-trip exactly through ``json``)."""
        return {
            "scenario": self.scenario,
            "planner": self.planner,
            "seed": self.seed,
            "outcome": self.outcome,
            "end_step": self.end_step,
            "metrics": {m.name: _none_if_nan(self.values[m.name]) for m in EPISODE_METRICS},
            "pedestrians": {
                m.name: [_none_if_nan(v) for v in self.pedestrians[m.name].tolist()]
                for m in PEDESTRIAN_METRICS
            },
        }

    @classmethod
    def from_document(cls, doc: Mapping[str, Any]) -> EpisodeMetrics:
        """The inverse of :meth:`to_document` (extra keys are ignored).

        Raises:
            KeyError, TypeError, ValueError: a missing or malformed entry; callers turn
                these into an error that names their file.
        """
        return cls(
            scenario=str(doc["scenario"]),
            planner=str(doc["planner"]),
            seed=int(doc["seed"]),
            outcome=str(doc["outcome"]),
            end_step=int(doc["end_step"]),
            values={m.name: _nan_if_none(doc["metrics"][m.name]) for m in EPISODE_METRICS},
            pedestrians={
                m.name: np.array(
                    [_nan_if_none(v) for v in doc["pedestrians"][m.name]], dtype=np.float64
                )
                for m in PEDESTRIAN_METRICS
            },
        )


def _none_if_nan(x: float) -> float | None:
    return None if math.isnan(x) else float(x)


def _nan_if_none(x: Any) -> float:
    return math.nan if x is None else float(x)


def _path_lengths(pos: FloatArray) -> FloatArray:
    """(N,) length of each of the (T + 1, N, 2) trajectories."""
    return np.asarray(np.linalg.norm(np.diff(pos, axis=0), axis=2).sum(axis=0), dtype=np.float64)


def _first_arrival_s(record: EpisodeRecord, twin: str) -> FloatArray:
    times = np.full(record.n_pedestrians, np.nan)
    for event in record.events:  # in time order: keep the first per pedestrian
        if event.kind == "ped_arrival" and event.twin == twin and math.isnan(times[event.agent]):
            times[event.agent] = event.time_s
    return times


def _nanmean(x: FloatArray) -> float:
    finite = x[~np.isnan(x)]
    return float(finite.mean()) if finite.size else math.nan


def episode_metrics(record: EpisodeRecord) -> EpisodeMetrics:
    """Compute every metric of :data:`PEDESTRIAN_METRICS` and :data:`EPISODE_METRICS`.

    Args:
        record: a finished twin episode.

    Returns:
        The per-pedestrian arrays and the per-episode values; the same record always
        gives bit-identical numbers.
    """
    f_pos = record.factual_pos
    c_pos = record.counterfactual_pos
    end = record.end_step
    separation = record.twin_separation_m()
    robot_xy = record.robot_pose[: end + 1, None, :2]
    robot_dist = np.linalg.norm(f_pos[: end + 1] - robot_xy, axis=2).min(axis=0)
    f_len = _path_lengths(f_pos)
    c_len = _path_lengths(c_pos)
    f_time = _first_arrival_s(record, "factual")
    c_time = _first_arrival_s(record, "counterfactual")
    ped: dict[str, FloatArray] = {
        "frechet_m": frechet_distances(f_pos, c_pos),
        "mean_separation_m": separation.mean(axis=0),
        "max_separation_m": separation.max(axis=0),
        "min_robot_distance_m": robot_dist,
        "min_robot_clearance_m": robot_dist - record.ped_radius - record.robot_radius,
        "path_length_m": f_len,
        "counterfactual_path_length_m": c_len,
        "extra_length_m": f_len - c_len,
        "time_to_goal_s": f_time,
        "counterfactual_time_to_goal_s": c_time,
        "delay_s": f_time - c_time,
    }
    robot_len = float(
        np.linalg.norm(np.diff(record.robot_pose[: end + 1, :2], axis=0), axis=1).sum()
    )
    duration = end * record.dt_s
    n = record.n_pedestrians
    values: dict[str, float] = {
        "frechet_m": float(ped["frechet_m"].mean()),
        "mean_separation_m": float(ped["mean_separation_m"].mean()),
        "max_separation_m": float(ped["max_separation_m"].mean()),
        "min_robot_distance_m": float(robot_dist.min()),
        "min_robot_clearance_m": float(ped["min_robot_clearance_m"].min()),
        "path_length_m": float(f_len.mean()),
        "extra_length_m": float(ped["extra_length_m"].mean()),
        "time_to_goal_s": _nanmean(f_time),
        "delay_s": _nanmean(ped["delay_s"]),
        "arrived_fraction": float(np.count_nonzero(~np.isnan(f_time)) / n),
        "robot_success": float(record.outcome == "goal_reached"),
        "robot_collision": float(record.outcome == "collision"),
        "robot_out_of_bounds": float(record.outcome == "out_of_bounds"),
        "robot_timeout": float(record.outcome == "timeout"),
        "robot_time_to_goal_s": duration if record.outcome == "goal_reached" else math.nan,
        "robot_path_length_m": robot_len,
        "robot_mean_speed_mps": robot_len / duration if end > 0 else 0.0,
    }
    return EpisodeMetrics(
        scenario=record.scenario,
        planner=record.planner,
        seed=record.seed,
        outcome=record.outcome,
        end_step=end,
        values=values,
        pedestrians=ped,
    )
