"""Write the large-crowd built-in scenarios (issue 19) into srfm/scenarios/.

The two scenarios are plain ``kind = "fixed"`` TOML files; this script is how their
hundreds of starts and goals were made (seeded, so it rewrites the same files):

* ``concert_crowd``: 400 spectators stand still (goal = start) in a dense block of
  24 m × 14 m (1.2 people/m², jittered lattice) in a 30 m × 30 m hall; the robot must
  cross the block from the bottom to the top.
* ``station_concourse``: a 40 m × 24 m walled concourse with a 4 × 2 grid of pillars;
  300 pedestrians in three flows already under way (120 west → east, 120 east → west,
  60 south → north, each starting spread along its lane and heading for the lane's far
  end); the robot crosses the concourse diagonally through the flows.

Usage::

    .venv/bin/python tools/scenarios/make_large_scenarios.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

OUT = Path(__file__).resolve().parents[2] / "srfm" / "scenarios"
FloatArray = NDArray[np.float64]
CONCERT = (
    "Large crowd: 400 people stand still in a dense 24 m x 14 m block (1.2 per m2),"
    " as at a concert; the robot must cross the block."
)
STATION = (
    "Large crowd: a 40 m x 24 m station concourse with eight pillars and three flows of"
    " 300 people (west-east, east-west, south-north); the robot crosses diagonally."
)
WALLS = (
    "[[0.0, 0.0, 40.0, 0.0], [40.0, 0.0, 40.0, 24.0], [40.0, 24.0, 0.0, 24.0],"
    " [0.0, 24.0, 0.0, 0.0]]"
)


def _pairs(a: FloatArray) -> str:
    return "[" + ", ".join(f"[{x:.2f}, {y:.2f}]" for x, y in a) + "]"


def _write(name: str, header: str, starts: FloatArray, goals: FloatArray) -> None:
    text = header.rstrip() + f"\nstarts = {_pairs(starts)}\ngoals = {_pairs(goals)}\n"
    (OUT / f"{name}.toml").write_text(text)
    print(f"{name}: {starts.shape[0]} pedestrians -> {OUT / f'{name}.toml'}")


def concert_crowd() -> None:
    rng = np.random.default_rng(19)
    nx, ny = 29, 14  # 406 lattice points; 400 kept
    xs = 3.0 + (np.arange(nx) + 0.5) * 24.0 / nx
    ys = 8.0 + (np.arange(ny) + 0.5) * 14.0 / ny
    grid = np.array([[x, y] for y in ys for x in xs])
    keep = np.sort(rng.permutation(grid.shape[0])[:400])
    starts = grid[keep] + rng.uniform(-0.1, 0.1, (400, 2))
    header = f"""# srfm scenario, schema version 1 (see docs/scenarios.md).
# Large-crowd suite (issue 19); written by tools/scenarios/make_large_scenarios.py.
schema_version = 1
name = "concert_crowd"
description = "{CONCERT}"
kind = "fixed"

[simulation]
dt_s = 0.06666666666666667  # 1/15 s
horizon_steps = 900         # 60 s, both twins

[world]
x_min = 0.0
x_max = 30.0
y_min = 0.0
y_max = 30.0

[robot]
start = [15.0, 2.0]
goal = [15.0, 28.0]
kinematics = "unicycle"
radius_m = 0.2
max_speed_mps = 0.5
max_angular_speed_radps = 3.141592653589793

[pedestrians]
radius_m = 0.25
desired_speed_mps = 1.25
max_speed_mps = 1.25
goal_radius_m = 0.3
noise_m = 0.05
"""
    _write("concert_crowd", header, starts, starts)


def station_concourse() -> None:
    rng = np.random.default_rng(20)
    flows = []
    # west -> east and east -> west in two lane bands, south -> north in the middle
    for n, (x0, x1), (y_lo, y_hi) in (
        (120, (1.0, 39.0), (3.0, 11.0)),
        (120, (39.0, 1.0), (13.0, 21.0)),
    ):
        frac = rng.uniform(0.0, 0.8, n)
        y = rng.uniform(y_lo, y_hi, n)
        starts = np.stack([x0 + frac * (x1 - x0), y], axis=1)
        goals = np.stack([np.full(n, x1), rng.uniform(y_lo, y_hi, n)], axis=1)
        flows.append((starts, goals))
    n = 60
    frac = rng.uniform(0.0, 0.8, n)
    x = rng.uniform(16.0, 24.0, n)
    flows.append(
        (
            np.stack([x, 1.0 + frac * 22.0], axis=1),
            np.stack([rng.uniform(16.0, 24.0, n), np.full(n, 23.0)], axis=1),
        )
    )
    starts = np.vstack([f[0] for f in flows])
    goals = np.vstack([f[1] for f in flows])
    # keep starts off the pillars and apart from each other (resample the few that clash)
    pillars = np.array([[x, y, 0.4] for x in (8.0, 16.0, 24.0, 32.0) for y in (8.0, 16.0)])
    for i in range(starts.shape[0]):
        for _ in range(1000):
            near_pillar = np.any(np.hypot(*(starts[i] - pillars[:, :2]).T) < pillars[:, 2] + 0.5)
            near_ped = np.any(np.hypot(*(starts[i] - starts[:i]).T) < 0.7) if i else False
            if not (near_pillar or near_ped):
                break
            starts[i] += rng.uniform(-0.5, 0.5, 2)
            starts[i] = np.clip(starts[i], 0.6, [39.4, 23.4])
    pillar_text = ", ".join(f"[{x:.1f}, {y:.1f}, {r:.1f}]" for x, y, r in pillars)
    header = f"""# srfm scenario, schema version 1 (see docs/scenarios.md).
# Large-crowd suite (issue 19); written by tools/scenarios/make_large_scenarios.py.
schema_version = 1
name = "station_concourse"
description = "{STATION}"
kind = "fixed"

[simulation]
dt_s = 0.06666666666666667  # 1/15 s
horizon_steps = 1200        # 80 s, both twins

[world]
x_min = 0.0
x_max = 40.0
y_min = 0.0
y_max = 24.0

[robot]
start = [4.0, 2.0]
goal = [36.0, 22.0]
kinematics = "unicycle"
radius_m = 0.2
max_speed_mps = 0.5
max_angular_speed_radps = 3.141592653589793

[obstacles]
walls = {WALLS}
pillars = [{pillar_text}]

[pedestrians]
radius_m = 0.25
desired_speed_mps = 1.25
max_speed_mps = 1.25
goal_radius_m = 0.5
noise_m = 0.1
"""
    _write("station_concourse", header, starts, goals)


if __name__ == "__main__":
    concert_crowd()
    station_concourse()
