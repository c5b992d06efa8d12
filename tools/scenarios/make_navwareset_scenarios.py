"""Write the NavWareSet room scenarios (issue 17) into srfm/scenarios/navwareset_*.toml.

The room is scene 13's static map of the NavWareSet quantitative selection
(``../shared/data/navwareset_quant/13_occupancy_xy_points.json``, a list of occupied
points in metres). Its walls here are straight segments fitted by eye to that map
(the upper room's three sides, its lower-right wall, the table block on the left and
the passage to the south); the occupied points, thinned to one per 0.1 m cell, are kept
in each file's ``[map] points`` for drawing. The five layouts are the dataset's
(frontal approach, pedestrian obstruction, blind corner, perpendicular crossing,
circular crossing); robot and pedestrian starts and goals are rounded from the first
tracks of scenes 1, 2, 3, 5 and 13 (same world frame).

    .venv/bin/python tools/scenarios/make_navwareset_scenarios.py [DATA_DIR]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT.parent / "shared" / "data"
WORLD = (0.5, 12.0, -8.5, 2.0)
WALLS = [
    [1.0, 1.2, 11.4, 1.65],  # top
    [1.0, 1.2, 1.0, -3.3],  # left
    [11.4, 1.65, 11.6, -2.2],  # right
    [7.8, -2.3, 11.6, -2.2],  # lower right
    [1.0, -3.9, 4.35, -3.9, 1.2],  # the table block on the left (1.2 m deep)
    [4.35, -4.5, 4.35, -8.0],  # passage, west side
    [7.8, -2.3, 7.8, -8.0],  # passage, east side
    [4.35, -8.0, 7.8, -8.0],  # passage, south end
]
LAYOUTS = {
    "frontal_approach": (
        "a pedestrian walks head-on at the robot across the room (scene 1).",
        [3.0, -0.4],
        [9.6, -0.3],
        "starts = [[10.0, -0.2]]\ngoals = [[1.8, -0.4]]",
    ),
    "obstruction": (
        "a pedestrian stands in the robot's way in the room (scene 2).",
        [3.0, -0.4],
        [9.6, -0.3],
        "starts = []\ngoals = []\nstanding = [[6.3, -0.4]]",
    ),
    "blind_corner": (
        "the robot comes up the passage round a corner into a pedestrian (scene 3).",
        [6.8, -5.0],
        [9.3, -1.5],
        "starts = [[10.8, -1.3]]\ngoals = [[6.5, -6.8]]",
    ),
    "perpendicular_crossing": (
        "two pedestrians walk across the room in front of the robot (scene 5).",
        [6.0, -2.3],
        [6.2, 0.8],
        "starts = [[2.5, -0.6], [10.3, 0.2]]\ngoals = [[10.8, -0.6], [2.0, 0.2]]",
    ),
    "circular_crossing": (
        "five pedestrians cross the room to the opposite side as the robot does (scene 13).",
        [5.1, -4.2],
        [9.1, 0.7],
        "starts = [[3.1, 0.5], [2.1, -2.2], [10.3, -1.5], [10.2, 0.8], [7.1, -5.7]]\n"
        "goals = [[7.2, -5.1], [10.8, -1.4], [2.5, -2.4], [5.0, -5.7], [3.1, 0.5]]",
    ),
}


def map_points() -> list[list[float]]:
    """The occupied points inside the world, one per 0.1 m cell (sorted)."""
    raw = json.loads((DATA / "navwareset_quant" / "13_occupancy_xy_points.json").read_text())
    pts = np.array([[p["x"], p["y"]] for p in raw], dtype=np.float64)
    x0, x1, y0, y1 = WORLD
    inside = (pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)
    cells = np.unique(np.round(pts[inside] / 0.1).astype(np.int64), axis=0)
    return [[round(float(x) * 0.1, 1), round(float(y) * 0.1, 1)] for x, y in cells]


def scenario_text(key: str, points: list[list[float]]) -> str:
    what, start, goal, peds = LAYOUTS[key]
    x0, x1, y0, y1 = WORLD
    walls = ",\n    ".join(str(w) for w in WALLS)
    rows = ",\n    ".join(
        ", ".join(str(p) for p in points[i : i + 8]) for i in range(0, len(points), 8)
    )
    return f"""# srfm scenario, schema version 2 (see docs/scenarios.md). Written by
# tools/scenarios/make_navwareset_scenarios.py: the NavWareSet room (scene 13's map), {key} layout.
schema_version = 2
name = "navwareset_{key}"
description = "NavWareSet room: {what}"
kind = "fixed"

[simulation]
dt_s = 0.06666666666666667
horizon_steps = 750

[world]
x_min = {x0}
x_max = {x1}
y_min = {y0}
y_max = {y1}

[robot]
start = {start}
goal = {goal}
kinematics = "unicycle"
radius_m = 0.2
max_speed_mps = 0.5
max_angular_speed_radps = 3.141592653589793

[pedestrians]
radius_m = 0.3
desired_speed_mps = 1.0  # the dataset's median walking speed
max_speed_mps = 1.25
goal_radius_m = 0.5
noise_m = 0.15  # per seed, each pedestrian's start and goal move by one u ~ U(-noise, noise)^2
{peds}

[obstacles]
walls = [
    {walls},
]

[regions]
room = [1.0, -2.3, 11.4, 1.2]
passage = [4.35, -8.0, 7.8, -2.3]

[map]  # scene 13's occupied points (NavWareSet), one per 0.1 m cell, for drawing
points = [
    {rows},
]
"""


def main() -> None:
    points = map_points()
    for key in LAYOUTS:
        out = ROOT / "srfm" / "scenarios" / f"navwareset_{key}.toml"
        out.write_text(scenario_text(key, points), encoding="utf-8")
        print(out)


if __name__ == "__main__":
    main()
