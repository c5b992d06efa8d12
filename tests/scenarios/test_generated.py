"""Generated walled layouts (issue 43): determinism, validity, names, bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

import srfm
from srfm.errors import PlannerError
from srfm.scenarios import Scenario, episode_setup, load_scenario
from srfm.scenarios.generated import GENERATED_KINDS, generated_scenario
from srfm.sim.checks import check_scenario
from srfm.world import Router


def _fingerprint(scenario: Scenario) -> bytes:
    """Every drawn number of a layout, as bytes."""
    parts = [
        scenario.name.encode(),
        np.asarray(scenario.robot_start).tobytes(),
        np.asarray(scenario.robot_goal).tobytes(),
        np.float64(scenario.robot_heading_rad).tobytes(),
        np.asarray(scenario.ped_starts).tobytes(),
        np.asarray(scenario.ped_goals).tobytes(),
        np.asarray(scenario.ped_desired_speed_mps).tobytes(),
        scenario.obstacles.segments.tobytes(),
        scenario.obstacles.circles.tobytes(),
        repr(scenario.world).encode(),
        np.asarray(scenario.ped_enter_s if scenario.ped_enter_s is not None else []).tobytes(),
    ]
    return b"|".join(parts)


def test_the_same_seed_gives_the_same_layout_in_any_order_and_process() -> None:
    seeds = [0, 7, 123, 2**32 - 1]
    forward = [_fingerprint(generated_scenario(s)) for s in seeds]
    backward = [_fingerprint(generated_scenario(s)) for s in reversed(seeds)][::-1]
    assert forward == backward
    code = (
        "import sys; from tests.scenarios.test_generated import _fingerprint;"
        "from srfm.scenarios.generated import generated_scenario;"
        "sys.stdout.buffer.write(_fingerprint(generated_scenario(123)))"
    )
    root = Path(__file__).resolve().parents[2]
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, check=True, cwd=root
    ).stdout
    assert out == forward[2]
    assert len(set(forward)) == len(forward)  # different seeds, different layouts


def test_the_kind_is_the_first_draw() -> None:
    """generated:SEED is generated:KIND:SEED of the kind it draws; other kinds differ."""
    for seed in range(12):
        drawn = generated_scenario(seed)
        kind = drawn.name.split("_")[1]
        assert drawn.source == f"generated:{kind}:{seed}"
        assert _fingerprint(generated_scenario(seed, kind)) == _fingerprint(drawn)
        other = next(k for k in GENERATED_KINDS if k != kind)
        assert generated_scenario(seed, other).name == f"generated_{other}_{seed}"


def _passable_disc(scenario: Scenario, people: np.ndarray, clearance: float) -> bool:
    """Whether a disc of radius ``clearance`` goes from the robot's start to its goal
    among the walls, pillars and ``people`` (discs of the pedestrian radius)."""
    circles = [*scenario.obstacles.circles.tolist(), *[[x, y, 0.3] for x, y in people]]
    obstacles = srfm.Obstacles.create(segments=scenario.obstacles.segments, circles=circles)
    try:
        Router(obstacles, scenario.world, clearance_m=clearance).route(
            tuple(scenario.robot_start), tuple(scenario.robot_goal)
        )
    except PlannerError:
        return False
    return True


@pytest.mark.parametrize("kind", GENERATED_KINDS)
def test_many_layouts_of_every_kind_are_valid(kind: str) -> None:
    """Walls off the robot's start and goal, the goal reachable past the standing
    people, nobody overlapping at the start, everything inside the world, the robot
    and time step of the training scenario; the kind's walls are there."""
    base = load_scenario("random")
    for seed in range(25):
        sc = generated_scenario(seed, kind)
        assert sc.kind == "fixed"
        assert sc.schema_version == 2
        assert sc.robot == base.robot
        assert sc.dt_s == base.dt_s
        assert sc.horizon_steps == 750
        assert sc.obstacles.segments.shape[0] >= 1
        walls = shapely.union_all(
            [shapely.LineString([(a, b), (c, d)]) for a, b, c, d in sc.obstacles.segments]
            + [shapely.Point(x, y).buffer(r) for x, y, r in sc.obstacles.circles]
        )
        for point in (sc.robot_start, sc.robot_goal):
            assert shapely.distance(shapely.Point(*point), walls) >= 0.4
        assert np.linalg.norm(sc.robot_goal - sc.robot_start) >= 6.0
        standing = np.array([sc.ped_starts[i] for i in sc.ped_standing]).reshape(-1, 2)
        assert _passable_disc(sc, standing, 0.2)
        setup = episode_setup(sc, 0)
        there = setup.n_present(0)
        starts = np.vstack([sc.robot_start[None], setup.crowd.pos[:there]])
        radii = np.concatenate([[0.2], setup.crowd.radius[:there]])
        gap = np.linalg.norm(starts[:, None] - starts[None], axis=2) - radii[:, None] - radii
        np.fill_diagonal(gap, np.inf)
        assert gap.min() >= 0.0, (kind, seed)
        points = np.vstack([sc.ped_starts, sc.ped_goals, sc.robot_start, sc.robot_goal])
        w = sc.world
        assert (points[:, 0] >= w.x_min).all()
        assert (points[:, 0] <= w.x_max).all()
        assert (points[:, 1] >= w.y_min).all()
        assert (points[:, 1] <= w.y_max).all()


def test_layouts_hold_what_the_generator_promises() -> None:
    """Over 120 seeds: every kind, standing people, people entering during the run,
    walkers coming from the robot's goal side."""
    layouts = [generated_scenario(seed) for seed in range(120)]
    assert {sc.name.split("_")[1] for sc in layouts} == set(GENERATED_KINDS)
    assert sum(bool(sc.ped_standing) for sc in layouts) >= 30
    entering = [sc for sc in layouts if sc.ped_enter_s is not None and sc.ped_enter_s.max() > 0]
    assert len(entering) >= 30
    towards = 0
    for sc in layouts:
        heading = sc.robot_goal - sc.robot_start
        walkers = [i for i in range(sc.n_pedestrians) if i not in sc.ped_standing]
        towards += any(
            float(np.dot(sc.ped_goals[i] - sc.ped_starts[i], heading)) < 0 for i in walkers
        )
    assert towards >= 100


@pytest.mark.parametrize("kind", GENERATED_KINDS)
def test_a_classical_planner_reaches_the_goal(kind: str) -> None:
    """The simulated check of the library scenarios (srfm.sim.checks): DWA reaches the
    goal, nobody starts overlapping, no pedestrian ends up in a wall."""
    result = check_scenario(generated_scenario(3, kind), range(2), "dwa")
    assert result.robot_goals >= 1
    assert result.overlapping_starts == 0
    assert result.in_wall_samples == 0


def test_names_load_everywhere_a_scenario_is_named() -> None:
    assert load_scenario("generated:5").source.startswith("generated:")
    assert load_scenario("generated:door:5").name == "generated_door_5"
    record = srfm.run_episode("generated:bend:2", 0, "straight")
    assert record.outcome in ("goal_reached", "collision", "timeout", "out_of_bounds")


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("generated:", "bad generated scenario name 'generated:'"),
        ("generated:attic:3", "unknown generated layout kind 'attic'"),
        ("generated:door", "bad seed 'door'"),
        ("generated:-1", "bad seed '-1'"),
        ("generated:1.5", "bad seed '1.5'"),
        ("generated:door:3:4", "bad generated scenario name"),
        ("generated:4294967296", "4294967296"),
    ],
)
def test_bad_names_are_refused_clearly(name: str, message: str) -> None:
    with pytest.raises(srfm.ScenarioError, match=message.replace(".", r"\.")):
        load_scenario(name)


def test_bad_arguments_are_refused_clearly() -> None:
    with pytest.raises(srfm.ScenarioError, match="unknown generated layout kind 'attic'"):
        generated_scenario(1, "attic")
    with pytest.raises(srfm.ScenarioError, match="-3"):
        generated_scenario(-3)


def test_the_benchmark_runs_generated_layouts(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from srfm.cli import main

    out = f"{tmp_path}/bench"
    result = CliRunner().invoke(
        main,
        ["benchmark", "-s", "generated:door:4,generated:9", "-p", "straight", "--seeds", "0",
         "--out", out, "--no-logs", "--no-figures", "-j", "1"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    episodes = Path(out, "episodes.csv").read_text()
    assert "generated_door_4" in episodes
    assert "generated_" in episodes
    bad = CliRunner().invoke(main, ["benchmark", "-s", "generated:attic:1", "--quick"])
    assert bad.exit_code != 0
    assert "unknown generated layout kind 'attic'" in bad.output
