"""Episode records: the arrays and events one twin episode produces."""

from __future__ import annotations

import math
from typing import Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.models.params import SRFMParams

__all__ = ["EVENT_KINDS", "ROBOT_OUTCOMES", "EpisodeRecord", "Event", "EventKind", "RobotOutcome"]

FloatArray = NDArray[np.float64]

EventKind = Literal[
    "robot_goal_reached",
    "robot_collision",
    "robot_out_of_bounds",
    "robot_timeout",
    "ped_arrival",
]
EVENT_KINDS: Final = (
    "robot_goal_reached",
    "robot_collision",
    "robot_out_of_bounds",
    "robot_timeout",
    "ped_arrival",
)
RobotOutcome = Literal["goal_reached", "collision", "out_of_bounds", "timeout", "planner_failed"]
# planner_failed: an external planner crashed, hung or answered garbage or a bad
# command (srfm.planners.external); no event of the world ended the episode.
ROBOT_OUTCOMES: Final = ("goal_reached", "collision", "out_of_bounds", "timeout", "planner_failed")


@attrs.frozen(kw_only=True)
class Event:
    """Something that happened at the end of step ``step`` (so at ``time_s``).

    Attributes:
        step: index of the sample at which it was detected (1..horizon).
        time_s: simulated time of that sample (s).
        kind: one of ``EVENT_KINDS``.
        agent: pedestrian index for ``ped_arrival`` and for a collision with a
            pedestrian; -1 otherwise (collisions with an obstacle, robot events).
        twin: ``"factual"`` or ``"counterfactual"`` for pedestrian arrivals, ``""`` for
            robot events (which belong to the factual world).
    """

    step: int
    time_s: float
    kind: EventKind
    agent: int = -1
    twin: str = ""


@attrs.frozen(kw_only=True, eq=False)
class EpisodeRecord:
    """Everything one twin episode produced; T = ``horizon_steps``, N pedestrians.

    Sample k is the state after k steps (sample 0 is the initial state), at
    ``time_s[k] = k * dt_s``. Both twins have exactly T + 1 samples.

    Attributes:
        scenario: scenario name.
        seed: episode seed.
        planner: planner registry name.
        params: the SRFM parameters the factual crowd used.
        dt_s: step (s).
        horizon_steps: T.
        time_s: (T + 1,) sample times (s).
        ped_radius: (N,) radii (m).
        factual_pos, factual_vel: (T + 1, N, 2) pedestrians that feel the robot.
        counterfactual_pos, counterfactual_vel: (T + 1, N, 2) the same pedestrians
            with the robot force switched off.
        factual_goal, counterfactual_goal: (T + 1, N, 2) each twin's current goals
            (they change only in scenarios that re-goal pedestrians).
        robot_pose: (T + 1, 3) x, y, theta.
        robot_vel: (T + 1, 2) world-frame velocity applied in the step that ended at
            each sample (0 at sample 0 and after the robot's episode ended).
        robot_cmd: (T, 2) the command the planner returned at each step, NaN once the
            robot's episode has ended.
        robot_active: (T + 1,) True while the robot's episode runs.
        robot_goal: (2,) goal (m).
        robot_radius: robot radius (m).
        robot_kinematics: ``"unicycle"`` or ``"holonomic"``.
        outcome: how the robot's episode ended.
        end_step: the sample at which it ended (T on timeout).
        events: every event, in time order.
        robot_goal_radius_m: the robot's goal counts as reached within this distance (m).
        ped_enter_step: (N,) the sample at which each pedestrian appears (scenarios
            with entering pedestrians; None: everyone from sample 0). Before it a
            pedestrian stands at its start in both twins with zero velocity and
            counts for no metric (:meth:`enter_steps`).
    """

    scenario: str
    seed: int
    planner: str
    params: SRFMParams
    dt_s: float
    horizon_steps: int
    time_s: FloatArray
    ped_radius: FloatArray
    factual_pos: FloatArray
    factual_vel: FloatArray
    counterfactual_pos: FloatArray
    counterfactual_vel: FloatArray
    factual_goal: FloatArray
    counterfactual_goal: FloatArray
    robot_pose: FloatArray
    robot_vel: FloatArray
    robot_cmd: FloatArray
    robot_active: NDArray[np.bool_]
    robot_goal: FloatArray
    robot_radius: float
    robot_kinematics: str
    outcome: RobotOutcome
    end_step: int
    events: tuple[Event, ...]
    robot_goal_radius_m: float = 0.5
    ped_enter_step: NDArray[np.int64] | None = None

    @property
    def n_pedestrians(self) -> int:
        """N."""
        return int(self.factual_pos.shape[1])

    def enter_steps(self) -> NDArray[np.int64]:
        """(N,) the sample at which each pedestrian appears (zeros without entries)."""
        if self.ped_enter_step is None:
            return np.zeros(self.n_pedestrians, dtype=np.int64)
        return np.asarray(self.ped_enter_step, dtype=np.int64)

    def present(self) -> NDArray[np.bool_]:
        """(T + 1, N) True where a pedestrian is there (at or after its entry sample)."""
        samples = np.arange(self.horizon_steps + 1)[:, None]
        return np.asarray(samples >= self.enter_steps()[None, :])

    def arrays(self) -> dict[str, NDArray[np.generic]]:
        """Every array field by name (for hashing, saving or comparing records)."""
        return {
            f.name: getattr(self, f.name)
            for f in attrs.fields(EpisodeRecord)
            if isinstance(getattr(self, f.name), np.ndarray)
        }

    def robot_path_length_m(self) -> float:
        """Length of the robot's path (m)."""
        return float(np.sum(np.linalg.norm(np.diff(self.robot_pose[:, :2], axis=0), axis=1)))

    def min_robot_distance_m(self) -> float:
        """Smallest centre distance between the robot and a factual pedestrian that is
        there (m); inf when nobody ever is."""
        d = np.linalg.norm(self.factual_pos - self.robot_pose[:, None, :2], axis=2)
        if self.ped_enter_step is not None:
            d = np.where(self.present(), d, np.inf)
        return float(d.min()) if d.size else math.inf

    def twin_separation_m(self) -> FloatArray:
        """(T + 1, N) distance between each pedestrian's factual and counterfactual twin."""
        return np.asarray(
            np.linalg.norm(self.factual_pos - self.counterfactual_pos, axis=2), dtype=np.float64
        )
