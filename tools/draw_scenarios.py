"""Draw the Francis scenarios into docs/scenarios/<name>.png (issue 17).

Walls in black, pedestrians' start -> goal in blue (seed 0), the robot's start -> goal
in red with the global router's waypoints (clearance = robot radius).

    .venv/bin/python tools/draw_scenarios.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from srfm.planners.routing import Router
from srfm.scenarios import FRANCIS_SCENARIOS, episode_setup, load_scenario

OUT = Path(__file__).resolve().parents[1] / "docs" / "scenarios"


def draw(name: str) -> Path:
    scenario = load_scenario(name)
    setup = episode_setup(scenario, 0)
    w = scenario.world
    fig, ax = plt.subplots(figsize=(6.0, 6.0 * (w.y_max - w.y_min) / (w.x_max - w.x_min) + 0.6))
    ax.plot(
        [w.x_min, w.x_max, w.x_max, w.x_min, w.x_min],
        [w.y_min, w.y_min, w.y_max, w.y_max, w.y_min],
        color="0.7",
        lw=0.8,
    )
    for x1, y1, x2, y2 in scenario.obstacles.segments:
        ax.plot([x1, x2], [y1, y2], color="black", lw=3)
    for (sx, sy), (gx, gy) in zip(setup.crowd.pos, setup.crowd.goal, strict=True):
        ax.annotate("", (gx, gy), (sx, sy), arrowprops={"arrowstyle": "->", "color": "tab:blue"})
        ax.plot(sx, sy, "o", color="tab:blue", ms=6)
    router = Router(scenario.obstacles, w, clearance_m=scenario.robot.radius_m)
    path = router.route(tuple(setup.robot_start), tuple(setup.robot_goal))
    xs = [setup.robot_start[0], *path[:, 0]]
    ys = [setup.robot_start[1], *path[:, 1]]
    ax.plot(xs, ys, "--", color="tab:red")
    ax.plot(*setup.robot_start, "s", color="tab:red", ms=7)
    ax.plot(*setup.robot_goal, "*", color="tab:red", ms=12)
    ax.set_aspect("equal")
    ax.set_title(f"{name}: {scenario.description}", fontsize=7, wrap=True)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    OUT.mkdir(parents=True, exist_ok=True)
    out = OUT / f"{name}.png"
    fig.savefig(out, dpi=80, bbox_inches="tight", metadata={"Software": None})
    plt.close(fig)
    return out


if __name__ == "__main__":
    for name in FRANCIS_SCENARIOS:
        print(draw(name))
