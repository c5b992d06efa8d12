"""Episode metrics: how much a robot disturbed each pedestrian, how close it came to
people, and how the robot itself did.

Every metric is defined once here (name, unit, direction, definition, source): the
CSV and Parquet columns, the JSON files, the tables and ``docs/metrics.md`` follow these
definitions (a test checks that the page lists exactly these rows). Each is computed
from the episode record alone (:class:`srfm.sim.record.EpisodeRecord`), with the named
thresholds of :class:`MetricParams`, so that ``srfm score`` recomputes it bit for bit
from an MCAP log.

Pedestrians entering during the run (``EpisodeRecord.ped_enter_step``) count from their
entry sample on: before it they are nowhere, for the robot and for every metric.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import MetricError
from srfm.metrics._social_kernels import (
    force_exposure,
    min_time_to_collision,
    near_miss_entries,
    stopped_samples,
)
from srfm.metrics.frechet import frechet_distances
from srfm.sim.record import EpisodeRecord

__all__ = [
    "EPISODE_METRICS",
    "METRIC_GROUPS",
    "PEDESTRIAN_METRICS",
    "EpisodeMetrics",
    "MetricInfo",
    "MetricParams",
    "episode_metrics",
]

FloatArray = NDArray[np.float64]

Group = Literal["pedestrian", "social", "robot"]
METRIC_GROUPS: Final[dict[str, str]] = {
    "pedestrian": "Pedestrian side: what the robot did to each pedestrian (its twin as baseline)",
    "social": "Social: how close the robot came to people",
    "robot": "Robot: outcome, efficiency and motion quality",
}
"""The groups of :data:`EPISODE_METRICS`, with a title, in table order."""

# Sources, cited by key in MetricInfo.source and in docs/metrics.md.
_PAPER = "Agrawal et al. 2024"
_FRANCIS = "Francis et al. 2023, Table 1"
_SPL = "Anderson et al. 2018"
_GUZZI = "Guzzi et al. 2013"
_HALL = "Hall 1966; Francis et al. 2023"
_SRFM = "this project (SRFM robot term, Agrawal et al. 2024 Eq. 4)"
_OWN = "this project"


def _finite_positive(inst: Any, attribute: attrs.Attribute[float], value: float) -> None:
    if not (isinstance(value, float) and math.isfinite(value) and value > 0.0):
        raise MetricError(f"{attribute.name} must be a finite number > 0, got {plain(value)}")


def _to_float(value: Any) -> Any:
    if isinstance(value, bool):
        return value  # refused by the validator, not turned into 1.0
    try:
        return float(value)
    except (TypeError, ValueError):
        return value


@attrs.frozen(kw_only=True)
class MetricParams:
    """The named thresholds of the social and robot metrics.

    Attributes:
        intimate_m: clearance (m) inside which a pedestrian is in the robot's intimate
            space (Hall's intimate zone, 0.45 m).
        personal_m: clearance (m) inside which a pedestrian is in the robot's personal
            space (Hall's personal zone, 1.2 m).
        near_miss_m: clearance (m) below which an approach counts as a near miss.
        ped_stop_speed_mps: step speed (m/s) below which a pedestrian stands.
        ped_stop_min_s: how long (s) a pedestrian must stand, while its twin walks, to
            count as brought to a stop.
        robot_stall_speed_mps: step speed (m/s) below which the robot is stalled.
        progress_window_s: the window (s) of the failure-to-progress test.
        progress_min_m: the least progress (m) towards the goal over one window.
    """

    intimate_m: float = attrs.field(default=0.45, converter=_to_float, validator=_finite_positive)
    personal_m: float = attrs.field(default=1.2, converter=_to_float, validator=_finite_positive)
    near_miss_m: float = attrs.field(default=0.2, converter=_to_float, validator=_finite_positive)
    ped_stop_speed_mps: float = attrs.field(
        default=0.2, converter=_to_float, validator=_finite_positive
    )
    ped_stop_min_s: float = attrs.field(
        default=0.5, converter=_to_float, validator=_finite_positive
    )
    robot_stall_speed_mps: float = attrs.field(
        default=0.05, converter=_to_float, validator=_finite_positive
    )
    progress_window_s: float = attrs.field(
        default=5.0, converter=_to_float, validator=_finite_positive
    )
    progress_min_m: float = attrs.field(
        default=0.5, converter=_to_float, validator=_finite_positive
    )

    def __attrs_post_init__(self) -> None:
        if self.intimate_m >= self.personal_m:
            raise MetricError(
                f"intimate_m ({self.intimate_m}) must be smaller than personal_m "
                f"({self.personal_m})"
            )

    def as_dict(self) -> dict[str, float]:
        """Every threshold by name (for the manifest and the results page)."""
        return attrs.asdict(self)


@attrs.frozen
class MetricInfo:
    """One metric: its column name, unit, which way is better, its definition, where it
    comes from, and its group (episode metrics only)."""

    name: str
    unit: str
    better: Literal["lower", "higher", ""]
    definition: str
    source: str = _OWN
    group: Group | Literal[""] = ""


PEDESTRIAN_METRICS: Final[tuple[MetricInfo, ...]] = (
    MetricInfo(
        "frechet_m",
        "m",
        "lower",
        "Discrete Fréchet distance between the pedestrian's factual and counterfactual "
        "trajectories over the whole horizon (T + 1 samples each): the deviation.",
        _PAPER,
    ),
    MetricInfo(
        "mean_separation_m",
        "m",
        "lower",
        "Mean over the T + 1 samples (from its entry on, for a pedestrian entering during "
        "the run) of the distance between the factual and the counterfactual twin at the "
        "same time.",
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
        "over the robot's episode (samples 0 to end_step; from its entry on, NaN if it "
        "enters after that).",
        _PAPER,
    ),
    MetricInfo(
        "min_robot_clearance_m",
        "m",
        "higher",
        "min_robot_distance_m minus the robot's and the pedestrian's radii; negative "
        "means overlap.",
        _FRANCIS,
    ),
    MetricInfo(
        "path_length_m",
        "m",
        "lower",
        "Length of the factual trajectory over the whole horizon.",
        _PAPER,
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
        "it never arrives), from its entry (0 unless it enters during the run). Standing "
        "pedestrians (goal = start) arrive at the first step.",
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
    MetricInfo(
        "robot_force_mean_mps2",
        "m/s²",
        "lower",
        "Mean over the steps k = 0..T − 1 of the magnitude of the SRFM robot term on the "
        "factual pedestrian, A_r exp((r_i + r_r − d) / B_r) ψ_r, in the state the step "
        "starts from (heading: the direction of the step velocity, else of the goal).",
        _SRFM,
    ),
    MetricInfo(
        "robot_force_max_mps2",
        "m/s²",
        "lower",
        "Largest magnitude of the robot term over the steps k = 0..T − 1.",
        _SRFM,
    ),
    MetricInfo(
        "robot_force_p95_mps2",
        "m/s²",
        "lower",
        "95th percentile (linear interpolation) of the magnitude of the robot term over "
        "the steps k = 0..T − 1.",
        _SRFM,
    ),
    MetricInfo(
        "social_work_m2ps2",
        "m²/s²",
        "lower",
        "Social work: the robot term's magnitude integrated along the factual path, "
        "Σ_k |f_robot(k)| |x(k+1) − x(k)| over the whole horizon (J per kg).",
        _SRFM,
    ),
    MetricInfo(
        "stopped_time_s",
        "s",
        "lower",
        "Time before the pedestrian's first arrival during which its factual step speed "
        "was below ped_stop_speed_mps while its counterfactual twin's was not.",
        _OWN,
    ),
    MetricInfo(
        "stopped_by_robot",
        "1",
        "lower",
        "1 if stopped_time_s is at least ped_stop_min_s: the robot brought the pedestrian "
        "to a stop its twin did not make; else 0.",
        _OWN,
    ),
    MetricInfo(
        "min_ttc_s",
        "s",
        "higher",
        "Smallest constant-velocity time to collision between the robot and the "
        "pedestrian over the robot's episode (step velocities; 0 while overlapping); NaN "
        "when they were never on a collision course.",
        _FRANCIS,
    ),
    MetricInfo(
        "near_misses",
        "count",
        "lower",
        "Times the clearance to the robot went below near_miss_m during the robot's "
        "episode (entries into that zone), without the entry that ended in a collision "
        "with this pedestrian.",
        _FRANCIS,
    ),
)

EPISODE_METRICS: Final[tuple[MetricInfo, ...]] = (
    # Pedestrian side.
    MetricInfo(
        "frechet_m",
        "m",
        "lower",
        "Mean over pedestrians of frechet_m: the benchmark's deviation (paper Table 3).",
        _PAPER,
        "pedestrian",
    ),
    MetricInfo(
        "mean_separation_m",
        "m",
        "lower",
        "Mean over pedestrians of mean_separation_m.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "max_separation_m",
        "m",
        "lower",
        "Mean over pedestrians of max_separation_m.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "path_length_m",
        "m",
        "lower",
        "Mean over pedestrians of the factual path length (paper Table 3, trajectory length).",
        _PAPER,
        "pedestrian",
    ),
    MetricInfo(
        "extra_length_m",
        "m",
        "lower",
        "Mean over pedestrians of extra_length_m.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "time_to_goal_s",
        "s",
        "lower",
        "Mean over the pedestrians that arrive of time_to_goal_s (the pedestrians' time "
        "to goal; not the paper's Time column, which is robot_duration_s); NaN if none "
        "arrives.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "delay_s",
        "s",
        "lower",
        "Mean over the pedestrians that arrive in both twins of delay_s; NaN if none.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "arrived_fraction",
        "1",
        "higher",
        "Fraction of pedestrians whose factual twin reaches its goal within the horizon.",
        _OWN,
        "pedestrian",
    ),
    MetricInfo(
        "robot_force_mean_mps2",
        "m/s²",
        "lower",
        "Mean over pedestrians of robot_force_mean_mps2.",
        _SRFM,
        "pedestrian",
    ),
    MetricInfo(
        "robot_force_max_mps2",
        "m/s²",
        "lower",
        "Mean over pedestrians of robot_force_max_mps2.",
        _SRFM,
        "pedestrian",
    ),
    MetricInfo(
        "robot_force_p95_mps2",
        "m/s²",
        "lower",
        "Mean over pedestrians of robot_force_p95_mps2.",
        _SRFM,
        "pedestrian",
    ),
    MetricInfo(
        "social_work_m2ps2",
        "m²/s²",
        "lower",
        "Mean over pedestrians of social_work_m2ps2.",
        _SRFM,
        "pedestrian",
    ),
    MetricInfo(
        "pedestrians_stopped",
        "count",
        "lower",
        "Number of pedestrians the robot brought to a stop (stopped_by_robot = 1).",
        _OWN,
        "pedestrian",
    ),
    # Social.
    MetricInfo(
        "min_robot_distance_m",
        "m",
        "higher",
        "Smallest centre-to-centre distance between the robot and any factual pedestrian "
        "over the robot's episode (paper Table 3).",
        _PAPER,
        "social",
    ),
    MetricInfo(
        "min_robot_clearance_m",
        "m",
        "higher",
        "Smallest clearance (centre distance minus both radii) to any pedestrian over the "
        "robot's episode.",
        _FRANCIS,
        "social",
    ),
    MetricInfo(
        "mean_robot_clearance_m",
        "m",
        "higher",
        "Mean over the samples 0..end_step of the clearance to the closest pedestrian.",
        _FRANCIS,
        "social",
    ),
    MetricInfo(
        "intimate_space_compliance",
        "1",
        "higher",
        "Share of the samples 0..end_step at which no pedestrian's clearance is below "
        "intimate_m (0.45 m).",
        _HALL,
        "social",
    ),
    MetricInfo(
        "personal_space_compliance",
        "1",
        "higher",
        "Share of the samples 0..end_step at which no pedestrian's clearance is below "
        "personal_m (1.2 m).",
        _HALL,
        "social",
    ),
    MetricInfo(
        "intimate_space_time_s",
        "s",
        "lower",
        "dt times the number of samples 0..end_step with a pedestrian's clearance below "
        "intimate_m.",
        _HALL,
        "social",
    ),
    MetricInfo(
        "personal_space_time_s",
        "s",
        "lower",
        "dt times the number of samples 0..end_step with a pedestrian's clearance below "
        "personal_m: the time in personal space.",
        _HALL,
        "social",
    ),
    MetricInfo(
        "min_ttc_s",
        "s",
        "higher",
        "Smallest min_ttc_s over pedestrians; NaN when no pedestrian was ever on a "
        "collision course with the robot.",
        _FRANCIS,
        "social",
    ),
    MetricInfo(
        "near_misses",
        "count",
        "lower",
        "Sum over pedestrians of near_misses.",
        _FRANCIS,
        "social",
    ),
    # Robot.
    MetricInfo(
        "robot_success",
        "1",
        "higher",
        "1 if the robot reached its goal, else 0.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_collision",
        "1",
        "lower",
        "1 if the robot's episode ended in a collision (centre distance below the sum of "
        "radii, or touching an obstacle), else 0.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_out_of_bounds",
        "1",
        "lower",
        "1 if the robot left the world, else 0.",
        _OWN,
        "robot",
    ),
    MetricInfo(
        "robot_timeout",
        "1",
        "lower",
        "1 if the robot was still driving at the horizon.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_duration_s",
        "s",
        "lower",
        "Duration of the robot's run, end_step × dt, whatever its outcome (the horizon on "
        "a timeout): what the paper's Table 3 Time column measured.",
        _PAPER,
        "robot",
    ),
    MetricInfo(
        "robot_time_to_goal_s",
        "s",
        "lower",
        "Time at which the robot reached its goal; NaN unless it succeeded.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_path_length_m",
        "m",
        "",
        "Length of the robot's path over its episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_path_ratio",
        "1",
        "lower",
        "robot_path_length_m divided by ℓ = |goal − start| − goal radius, the shortest "
        "way into the goal disc in free space; NaN unless it succeeded (or ℓ = 0).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_spl",
        "1",
        "higher",
        "Success weighted by path length: success × ℓ / max(p, ℓ), ℓ as in "
        "robot_path_ratio, p robot_path_length_m (1 on success when ℓ = 0).",
        _SPL,
        "robot",
    ),
    MetricInfo(
        "robot_failure_to_progress",
        "1",
        "lower",
        "1 if at some sample of the robot's episode its distance to the goal had shrunk "
        "by less than progress_min_m (0.5 m) over the last progress_window_s (5 s), else 0.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_stalled_time_s",
        "s",
        "lower",
        "dt times the number of steps of the robot's episode with a step speed below "
        "robot_stall_speed_mps (0.05 m/s).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_min_speed_mps",
        "m/s",
        "",
        "Smallest step speed |x(k) − x(k−1)| / dt over the robot's episode (k = 1..end_step).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_mean_speed_mps",
        "m/s",
        "",
        "robot_path_length_m divided by the duration of the robot's episode (the mean step "
        "speed; 0 if it ended at step 0).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_max_speed_mps",
        "m/s",
        "",
        "Largest step speed over the robot's episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_min_accel_mps2",
        "m/s²",
        "",
        "Smallest |v(k) − v(k−1)| / dt, v the step velocities (k = 2..end_step).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_mean_accel_mps2",
        "m/s²",
        "lower",
        "Mean of |v(k) − v(k−1)| / dt over the robot's episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_max_accel_mps2",
        "m/s²",
        "lower",
        "Largest |v(k) − v(k−1)| / dt over the robot's episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_min_jerk_mps3",
        "m/s³",
        "",
        "Smallest |a(k) − a(k−1)| / dt, a the step accelerations (k = 3..end_step).",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_mean_jerk_mps3",
        "m/s³",
        "lower",
        "Mean of |a(k) − a(k−1)| / dt over the robot's episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_max_jerk_mps3",
        "m/s³",
        "lower",
        "Largest |a(k) − a(k−1)| / dt over the robot's episode.",
        _FRANCIS,
        "robot",
    ),
    MetricInfo(
        "robot_path_irregularity_radpm",
        "rad/m",
        "lower",
        "Path irregularity: the summed absolute change of the direction of travel between "
        "consecutive moving steps, divided by robot_path_length_m; NaN if it did not move.",
        _GUZZI,
        "robot",
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


def _first_arrivals(record: EpisodeRecord, twin: str) -> tuple[FloatArray, NDArray[np.int64]]:
    """(N,) time (NaN if never) and sample (T + 1 if never) of each pedestrian's first
    arrival in ``twin``."""
    times = np.full(record.n_pedestrians, np.nan)
    steps = np.full(record.n_pedestrians, record.horizon_steps + 1, dtype=np.int64)
    for event in record.events:  # in time order: keep the first per pedestrian
        if event.kind == "ped_arrival" and event.twin == twin and math.isnan(times[event.agent]):
            times[event.agent] = event.time_s
            steps[event.agent] = event.step
    return times, steps


def _finite_mean(x: FloatArray) -> float:
    """Mean of the finite entries of ``x`` (NaN when there are none)."""
    finite = x[np.isfinite(x)]
    return float(finite.mean()) if finite.size else math.nan


def _finite_min(x: FloatArray) -> float:
    """Smallest non-NaN entry of ``x`` (NaN when there is none)."""
    kept = x[~np.isnan(x)]
    return float(kept.min()) if kept.size else math.nan


def _nanmean(x: FloatArray) -> float:
    finite = x[~np.isnan(x)]
    return float(finite.mean()) if finite.size else math.nan


def _stats(x: FloatArray) -> tuple[float, float, float]:
    """min, mean, max of ``x``; NaN for an empty array."""
    if not x.size:
        return math.nan, math.nan, math.nan
    return float(x.min()), float(x.mean()), float(x.max())


def _pedestrian_side(
    record: EpisodeRecord, params: MetricParams, f_arrival_step: NDArray[np.int64]
) -> dict[str, FloatArray]:
    """Robot-force exposure, social work and stops of every pedestrian."""
    pos = np.ascontiguousarray(record.factual_pos)
    n = record.n_pedestrians
    steps = record.horizon_steps
    robot_xy = np.ascontiguousarray(record.robot_pose[:, :2])
    magnitude = np.empty((steps, n))
    work = np.empty(n)
    p = record.params
    enter = record.enter_steps()
    force_exposure(
        pos,
        np.ascontiguousarray(record.factual_goal),
        np.ascontiguousarray(record.ped_radius),
        robot_xy,
        float(record.robot_radius),
        np.ascontiguousarray(record.robot_active),
        p.for_kernels(),
        float(record.dt_s),
        enter,
        magnitude,
        work,
    )
    stopped = np.empty(n)
    stopped_samples(
        pos,
        np.ascontiguousarray(record.counterfactual_pos),
        f_arrival_step,
        float(record.dt_s),
        params.ped_stop_speed_mps,
        stopped,
    )
    min_samples = max(1, math.ceil(round(params.ped_stop_min_s / record.dt_s, 9)))
    if not steps:
        f_mean = f_max = f_p95 = np.full(n, np.nan)
    elif record.ped_enter_step is None:
        f_mean = magnitude.mean(axis=0)
        f_max = magnitude.max(axis=0)
        f_p95 = np.percentile(magnitude, 95.0, axis=0)
    else:  # over the steps each pedestrian is there for (it enters before the horizon)
        f_mean = np.array([magnitude[e:, i].mean() for i, e in enumerate(enter)])
        f_max = np.array([magnitude[e:, i].max() for i, e in enumerate(enter)])
        f_p95 = np.array([np.percentile(magnitude[e:, i], 95.0) for i, e in enumerate(enter)])
    return {
        "robot_force_mean_mps2": f_mean,
        "robot_force_max_mps2": f_max,
        "robot_force_p95_mps2": np.asarray(f_p95, dtype=np.float64),
        "social_work_m2ps2": work,
        "stopped_time_s": stopped * record.dt_s,
        "stopped_by_robot": (stopped >= min_samples).astype(np.float64),
    }


def _social(
    record: EpisodeRecord, params: MetricParams
) -> tuple[dict[str, FloatArray], dict[str, float]]:
    """Clearance, personal space, time to collision and near misses over the robot's
    episode; per pedestrian and per episode."""
    end = record.end_step
    pos = np.ascontiguousarray(record.factual_pos[: end + 1])
    robot_xy = np.ascontiguousarray(record.robot_pose[: end + 1, :2])
    radius = np.ascontiguousarray(record.ped_radius)
    n = record.n_pedestrians
    enter = record.enter_steps()
    ttc = np.empty(n)
    min_time_to_collision(
        pos, radius, robot_xy, float(record.robot_radius), end, record.dt_s, enter, ttc
    )
    near = np.empty(n)
    near_miss_entries(
        pos, radius, robot_xy, float(record.robot_radius), end, params.near_miss_m, enter, near
    )
    if record.outcome == "collision":
        hit = next((e.agent for e in record.events if e.kind == "robot_collision"), -1)
        if hit >= 0 and near[hit] > 0:
            near[hit] -= 1.0  # that entry ended in the collision: not a near miss
    ttc[np.isinf(ttc)] = np.nan
    centres = np.linalg.norm(pos - robot_xy[:, None, :], axis=2)
    gaps = centres - radius[None, :] - record.robot_radius
    if record.ped_enter_step is not None:  # nobody there: no clearance at that sample
        gaps = np.where(record.present()[: end + 1], gaps, np.inf)
    clearance = gaps.min(axis=1) if n else np.full(end + 1, np.inf)
    samples = end + 1
    inside_intimate = int(np.count_nonzero(clearance < params.intimate_m))
    inside_personal = int(np.count_nonzero(clearance < params.personal_m))
    per_ped = {"min_ttc_s": ttc, "near_misses": near}
    finite_ttc = ttc[~np.isnan(ttc)]
    values = {
        "mean_robot_clearance_m": _finite_mean(clearance),
        "intimate_space_compliance": 1.0 - inside_intimate / samples,
        "personal_space_compliance": 1.0 - inside_personal / samples,
        "intimate_space_time_s": inside_intimate * record.dt_s,
        "personal_space_time_s": inside_personal * record.dt_s,
        "min_ttc_s": float(finite_ttc.min()) if finite_ttc.size else math.nan,
        "near_misses": float(near.sum()),
    }
    return per_ped, values


def _robot_motion(
    record: EpisodeRecord, params: MetricParams, robot_len: float
) -> dict[str, float]:
    """Path ratio, SPL, progress, stalls, speed, acceleration, jerk and irregularity."""
    end = record.end_step
    dt = record.dt_s
    xy = record.robot_pose[: end + 1, :2]
    disp = np.diff(xy, axis=0)
    step_len = np.linalg.norm(disp, axis=1)
    vel = disp / dt
    acc = np.diff(vel, axis=0) / dt
    jerk = np.diff(acc, axis=0) / dt
    speed_min, _, speed_max = _stats(step_len / dt)
    acc_stats = _stats(np.linalg.norm(acc, axis=1))
    jerk_stats = _stats(np.linalg.norm(jerk, axis=1))
    success = record.outcome == "goal_reached"
    straight = max(
        float(np.linalg.norm(record.robot_goal - record.robot_pose[0, :2]))
        - record.robot_goal_radius_m,
        0.0,
    )
    ratio = robot_len / straight if success and straight > 0.0 else math.nan
    if not success:
        spl = 0.0
    elif straight > 0.0:
        spl = straight / max(robot_len, straight)
    else:
        spl = 1.0
    window = max(1, round(params.progress_window_s / dt))
    goal_dist = np.linalg.norm(record.robot_goal[None, :] - xy, axis=1)
    progress = goal_dist[:-window] - goal_dist[window:] if end >= window else np.zeros(0)
    stall = int(np.count_nonzero(step_len < params.robot_stall_speed_mps * dt))
    moving = step_len > 1e-12
    heading = np.arctan2(disp[moving, 1], disp[moving, 0])
    turn = np.diff(heading)
    turn = (turn + np.pi) % (2.0 * np.pi) - np.pi
    irregularity = float(np.abs(turn).sum()) / robot_len if robot_len > 0.0 else math.nan
    return {
        "robot_duration_s": end * dt,
        "robot_path_ratio": ratio,
        "robot_spl": spl,
        "robot_failure_to_progress": float(bool((progress < params.progress_min_m).any())),
        "robot_stalled_time_s": stall * dt,
        "robot_min_speed_mps": speed_min,
        "robot_max_speed_mps": speed_max,
        "robot_min_accel_mps2": acc_stats[0],
        "robot_mean_accel_mps2": acc_stats[1],
        "robot_max_accel_mps2": acc_stats[2],
        "robot_min_jerk_mps3": jerk_stats[0],
        "robot_mean_jerk_mps3": jerk_stats[1],
        "robot_max_jerk_mps3": jerk_stats[2],
        "robot_path_irregularity_radpm": irregularity,
    }


def episode_metrics(record: EpisodeRecord, params: MetricParams | None = None) -> EpisodeMetrics:
    """Compute every metric of :data:`PEDESTRIAN_METRICS` and :data:`EPISODE_METRICS`.

    Args:
        record: a finished twin episode.
        params: the thresholds (default: :class:`MetricParams`'s defaults).

    Returns:
        The per-pedestrian arrays and the per-episode values; the same record always
        gives bit-identical numbers.
    """
    params = MetricParams() if params is None else params
    f_pos = record.factual_pos
    c_pos = record.counterfactual_pos
    end = record.end_step
    separation = record.twin_separation_m()
    robot_xy = record.robot_pose[: end + 1, None, :2]
    robot_gap = np.linalg.norm(f_pos[: end + 1] - robot_xy, axis=2)
    f_len = _path_lengths(f_pos)
    c_len = _path_lengths(c_pos)
    f_time, f_step = _first_arrivals(record, "factual")
    c_time, _ = _first_arrivals(record, "counterfactual")
    if record.ped_enter_step is None:
        robot_dist = robot_gap.min(axis=0)
        mean_separation = separation.mean(axis=0)
    else:
        # Entering pedestrians: only the samples from each one's entry on count; one
        # that enters after the robot's episode has no distance to it (NaN); times to
        # the goal run from the entry.
        enter = record.enter_steps()
        robot_gap = np.where(record.present()[: end + 1], robot_gap, np.inf)
        robot_dist = robot_gap.min(axis=0)
        robot_dist[np.isinf(robot_dist)] = np.nan
        mean_separation = separation.sum(axis=0) / (record.horizon_steps + 1 - enter)
        f_time = f_time - enter * record.dt_s
        c_time = c_time - enter * record.dt_s
    social_ped, social_values = _social(record, params)
    ped: dict[str, FloatArray] = {
        "frechet_m": frechet_distances(f_pos, c_pos),
        "mean_separation_m": mean_separation,
        "max_separation_m": separation.max(axis=0),
        "min_robot_distance_m": robot_dist,
        "min_robot_clearance_m": robot_dist - record.ped_radius - record.robot_radius,
        "path_length_m": f_len,
        "counterfactual_path_length_m": c_len,
        "extra_length_m": f_len - c_len,
        "time_to_goal_s": f_time,
        "counterfactual_time_to_goal_s": c_time,
        "delay_s": f_time - c_time,
        **_pedestrian_side(record, params, f_step),
        **social_ped,
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
        "path_length_m": float(f_len.mean()),
        "extra_length_m": float(ped["extra_length_m"].mean()),
        "time_to_goal_s": _nanmean(f_time),
        "delay_s": _nanmean(ped["delay_s"]),
        "arrived_fraction": float(np.count_nonzero(~np.isnan(f_time)) / n),
        "robot_force_mean_mps2": float(ped["robot_force_mean_mps2"].mean()),
        "robot_force_max_mps2": float(ped["robot_force_max_mps2"].mean()),
        "robot_force_p95_mps2": float(ped["robot_force_p95_mps2"].mean()),
        "social_work_m2ps2": float(ped["social_work_m2ps2"].mean()),
        "pedestrians_stopped": float(ped["stopped_by_robot"].sum()),
        "min_robot_distance_m": _finite_min(robot_dist),
        "min_robot_clearance_m": _finite_min(ped["min_robot_clearance_m"]),
        **social_values,
        "robot_success": float(record.outcome == "goal_reached"),
        "robot_collision": float(record.outcome == "collision"),
        "robot_out_of_bounds": float(record.outcome == "out_of_bounds"),
        "robot_timeout": float(record.outcome == "timeout"),
        "robot_time_to_goal_s": duration if record.outcome == "goal_reached" else math.nan,
        "robot_path_length_m": robot_len,
        "robot_mean_speed_mps": robot_len / duration if end > 0 else 0.0,
        **_robot_motion(record, params, robot_len),
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
