"""Scenario files and action policies shared by the environment tests."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from srfm.models.robot import RobotConfig, RobotState
from srfm.planners._observation import action_to_command


def fixed_scenario(
    path: Path,
    *,
    robot_start: tuple[float, float],
    robot_goal: tuple[float, float],
    starts: list[tuple[float, float]],
    goals: list[tuple[float, float]],
    horizon: int = 750,
    heading: float | None = None,
    kinematics: str = "unicycle",
    extra: str = "",
) -> Path:
    """A fixed scenario TOML without per-seed noise."""
    heading_line = "" if heading is None else f"heading_rad = {heading!r}\n"
    text = f"""schema_version = 1
name = "test"
description = "test scenario"
kind = "fixed"

[simulation]
horizon_steps = {horizon}

[robot]
start = [{robot_start[0]!r}, {robot_start[1]!r}]
goal = [{robot_goal[0]!r}, {robot_goal[1]!r}]
kinematics = "{kinematics}"
{heading_line}
[pedestrians]
noise_m = 0.0
starts = {[list(p) for p in starts]!r}
goals = {[list(p) for p in goals]!r}
{extra}
"""
    path.write_text(text, encoding="utf-8")
    return path


def seek_action(robot: RobotState, goal: np.ndarray, holonomic: bool) -> np.ndarray:
    """A simple goal-seeking action in [−1, 1]² (reaches goals, sometimes collides)."""
    dx = float(goal[0]) - robot.x
    dy = float(goal[1]) - robot.y
    error = math.remainder(math.atan2(dy, dx) - robot.theta, 2.0 * math.pi)
    if holonomic:
        return np.array([math.cos(error), math.sin(error)], dtype=np.float32)
    turn = max(-1.0, min(1.0, 2.0 * error / math.pi))
    return np.array([max(math.cos(error), 0.0), turn], dtype=np.float32)


def command_for(action: np.ndarray, robot: RobotState, holonomic: bool) -> np.ndarray:
    """The simulator command the environment applies for ``action`` (default limits)."""
    a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
    limits = RobotConfig(kinematics="holonomic" if holonomic else "unicycle").for_kernels()
    c0, c1 = action_to_command(float(a[0]), float(a[1]), robot.theta, limits)
    return np.array([c0, c1])
