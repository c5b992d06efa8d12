"""Draw the scenario library into docs/scenarios/<name>.png (issue 17).

Walls and pillars in black, map points (NavWareSet) in grey, named regions shaded;
each pedestrian's route from its start (seed 0) in blue (given or computed waypoints,
as the simulator uses them; a standing pedestrian is a ring); pedestrians who enter
during the run (seed 0's entries) in orange, dotted; the robot's start, goal and route
(srfm.sim.routes.RobotRoute) in red.

    .venv/bin/python tools/scenarios/draw_scenarios.py [NAME ...]

A NAME may be any scenario name, e.g. ``generated:door:1`` or a TOML path; the file is
named after the scenario (``generated_door_1.png``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import Circle, Rectangle

from srfm.scenarios import (
    FLOW_SCENARIOS,
    FRANCIS_SCENARIOS,
    NAVWARESET_SCENARIOS,
    episode_setup,
    load_scenario,
)
from srfm.sim.routes import RobotRoute, pedestrian_waypoints

OUT = Path(__file__).resolve().parents[2] / "docs" / "scenarios"


def draw(name: str, out_dir: Path = OUT) -> Path:
    """Draw scenario ``name`` into ``out_dir/<scenario name>.png``; return the path."""
    scenario = load_scenario(name)
    setup = episode_setup(scenario, 0)
    w = scenario.world
    aspect = (w.x_max - w.x_min) / (w.y_max - w.y_min)
    width = min(9.0, max(5.0, 1.5 * aspect))  # long corridors get a wider figure
    height = width / aspect
    fig, ax = plt.subplots(figsize=(width, height + 0.7))
    ax.plot(
        [w.x_min, w.x_max, w.x_max, w.x_min, w.x_min],
        [w.y_min, w.y_min, w.y_max, w.y_max, w.y_min],
        color="0.7",
        lw=0.8,
    )
    if scenario.map_points is not None:
        ax.plot(*scenario.map_points.T, ".", color="0.75", ms=1.5, zorder=0)
    for x0, y0, x1, y1 in scenario.regions.values():
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="tab:green", alpha=0.07))
    for x1, y1, x2, y2 in scenario.obstacles.segments:
        ax.plot([x1, x2], [y1, y2], color="black", lw=2.5, solid_capstyle="butt")
    for cx, cy, r in scenario.obstacles.circles:
        ax.add_patch(Circle((cx, cy), r, color="black"))
    enters = setup.ped_enter_step
    for i, path in enumerate(pedestrian_waypoints(setup)):
        sx, sy = setup.crowd.pos[i]
        later = enters is not None and enters[i] > 0
        colour = "tab:orange" if later else "tab:blue"
        if i in setup.ped_standing:
            ax.plot(sx, sy, "o", mfc="none", color=colour, ms=8)
            continue
        xs = [sx, *path[:, 0]]
        ys = [sy, *path[:, 1]]
        ax.plot(xs[:-1], ys[:-1], ":" if later else "-", color=colour, lw=0.8, alpha=0.7)
        ax.annotate(
            "",
            (xs[-1], ys[-1]),
            (xs[-2], ys[-2]),
            arrowprops={"arrowstyle": "->", "color": colour, "alpha": 0.5 if later else 1.0},
        )
        ax.plot(sx, sy, "o", color=colour, ms=5)
    route = RobotRoute(scenario, setup.robot_start, setup.robot_goal).waypoints
    ax.plot(
        [setup.robot_start[0], *route[:, 0]],
        [setup.robot_start[1], *route[:, 1]],
        "--",
        color="tab:red",
    )
    ax.plot(*setup.robot_start, "s", color="tab:red", ms=7)
    ax.plot(*setup.robot_goal, "*", color="tab:red", ms=12)
    ax.set_aspect("equal")
    ax.set_xlim(w.x_min - 0.2, w.x_max + 0.2)
    ax.set_ylim(w.y_min - 0.2, w.y_max + 0.2)
    ax.set_title(name, fontsize=9)
    ax.tick_params(labelsize=7)
    out_dir.mkdir(parents=True, exist_ok=True)
    out = out_dir / f"{scenario.name}.png"  # generated:door:1 -> generated_door_1.png
    fig.savefig(out, dpi=70, bbox_inches="tight", metadata={"Software": None})
    plt.close(fig)
    return out


if __name__ == "__main__":
    for name in sys.argv[1:] or [*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS]:
        print(draw(name))
