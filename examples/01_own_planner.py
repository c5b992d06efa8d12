"""Your own planner in about 30 lines, registered and benchmarked against the shipped ones.

    python examples/01_own_planner.py          # the paper suite, every planner, seeds 0-2
    python examples/01_own_planner.py --fast   # seed 0, three planners, no figures

A planner is any object with ``name``, ``detection_range_m``, ``reset(context, rng)``
and ``act(observation)`` (docs/planners.md). This one drives straight at the goal like
the ``straight`` baseline, but slows down in proportion to how close the nearest person
ahead of it is. The results folder holds the paper's table (table.md) and a results
page (report.html) that opens offline in a browser.
"""

import math
import os
import sys
from pathlib import Path

import numpy as np

import srfm
from srfm.benchmark import BenchmarkRequest, run_benchmark
from srfm.planners import register_planner

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "01_own_planner"


class Cautious:
    """Head for the goal (unicycle: turn, then drive); slow down for people ahead."""

    name = "cautious"
    detection_range_m = 3.0  # the planner sees only people within 3 m (None: everyone)

    def reset(self, context, rng):
        self.robot = context.robot  # limits: max_speed_mps, max_angular_speed_radps

    def act(self, obs):
        r = obs.robot
        heading = math.atan2(obs.robot_goal[1] - r.y, obs.robot_goal[0] - r.x)
        error = math.remainder(heading - r.theta, 2 * math.pi)
        speed = self.robot.max_speed_mps * max(math.cos(error), 0.0)
        for pos in obs.ped_pos:  # (k, 2) positions (m) of the people in range
            dx, dy = pos[0] - r.x, pos[1] - r.y
            ahead = dx * math.cos(r.theta) + dy * math.sin(r.theta)
            if ahead > 0:  # only people in front of the robot slow it down
                speed *= min(1.0, max(0.0, (math.hypot(dx, dy) - 0.6) / 2.0))
        omega = float(np.clip(2.0 * error, -1, 1) * self.robot.max_angular_speed_radps)
        return np.array([speed, omega])  # (v m/s, ω rad/s)


# Registered, it is a planner name like the shipped ones (the benchmark's workers are
# forked, so they see the registry; from the command line use -p module:Cautious).
register_planner("cautious", Cautious, "straight to the goal, slowing down for people ahead")

if __name__ == "__main__":
    # One episode first: the record holds both crowds, the robot and the events.
    record = srfm.run_episode("crosswalk", seed=0, planner="cautious")
    print(
        f"crosswalk seed 0: {record.outcome} at step {record.end_step}, "
        f"largest deviation {record.twin_separation_m().max():.2f} m"
    )

    # Then the benchmark: the paper's five scenarios × planners × seeds. Every
    # registered planner by default, "cautious" included.
    request = BenchmarkRequest.create(
        planners=["cautious", "straight", "dwa"] if FAST else None,
        seeds=[0] if FAST else None,
        quick=True,  # seeds 0-2
    )
    summary = run_benchmark(request, OUT, jobs=2, figures=not FAST, force=True)
    print((OUT / "table.md").read_text(encoding="utf-8"))
    print(
        f"{summary.simulated} episodes in {summary.wall_time_s:.1f} s; open {OUT / 'report.html'}"
    )
