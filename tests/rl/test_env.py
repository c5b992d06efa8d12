"""srfm/SocialNav-v0: API checks, determinism, pickling, reward terms, observation."""

from __future__ import annotations

import math
import pickle
import subprocess
import sys
from pathlib import Path

import attrs
import gymnasium as gym
import numpy as np
import pytest

import srfm
import srfm.rl
from srfm._deps import MissingDependencyError, require
from srfm.errors import ParameterError, PlannerError, ScenarioError, SimulationError
from srfm.models._robot_kernels import robot_task
from srfm.planners import _observation as kern
from srfm.rl import EnvConfig, SocialNavEnv
from tests.rl._helpers import fixed_scenario


def _run(env: SocialNavEnv, actions: np.ndarray) -> list[tuple[bytes, float, bool, bool]]:
    out = []
    for a in actions:
        obs, r, te, tr, _ = env.step(a)
        out.append((obs.tobytes(), r, te, tr))
        if te or tr:
            break
    return out


def test_registered_with_gymnasium() -> None:
    env = gym.make("srfm/SocialNav-v0", scenario="crosswalk")
    assert isinstance(env.unwrapped, SocialNavEnv)
    assert env.unwrapped.scenario.name == "crosswalk"
    env.close()


# corridor_flow's horizon is 1200 steps: gym.make needs max_episode_steps for it (docs/rl.md).
@pytest.mark.parametrize(
    "name", [n for n in srfm.BUILTIN_SCENARIOS if n not in srfm.scenarios.FLOW_SCENARIOS]
)
def test_registered_max_episode_steps_is_the_horizon(name: str) -> None:
    env = gym.make("srfm/SocialNav-v0", scenario=name)
    assert env.spec is not None
    assert env.spec.max_episode_steps == srfm.rl.MAX_EPISODE_STEPS
    assert env.spec.max_episode_steps == env.unwrapped.scenario.horizon_steps  # type: ignore[attr-defined]
    env.close()


def test_time_limit_truncates_where_the_environment_does(tmp_path: Path) -> None:
    # The robot stands still far from everyone: a timeout at the horizon (750 steps).
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(12.0, 12.0)],
        goals=[(12.0, 1.0)],
    )
    made = gym.make("srfm/SocialNav-v0", scenario=path)
    plain = SocialNavEnv(path)
    runs = []
    for env in (made, plain):
        env.reset(seed=0)
        steps = []
        for _ in range(750):
            obs, reward, terminated, truncated, info = env.step(np.zeros(2, np.float32))
            steps.append((obs.tobytes(), reward, terminated, truncated))
        assert info["outcome"] == "timeout"
        runs.append(steps)
    assert runs[0] == runs[1]
    assert [s[2:] for s in runs[0]] == [(False, False)] * 749 + [(False, True)]


def test_module_path_form_of_make() -> None:
    env = gym.make("srfm.rl.env:srfm/SocialNav-v0")
    assert isinstance(env.unwrapped, SocialNavEnv)


def test_gymnasium_env_checker() -> None:
    from gymnasium.utils.env_checker import check_env

    check_env(SocialNavEnv("random"), skip_render_check=True)
    check_env(SocialNavEnv("footpath", EnvConfig(kinematics="holonomic")), skip_render_check=True)


def test_sb3_env_checker() -> None:
    from stable_baselines3.common.env_checker import check_env

    check_env(SocialNavEnv("random"), warn=True)


def test_spaces() -> None:
    env = SocialNavEnv(config=EnvConfig(max_pedestrians=4))
    assert env.observation_space.shape == (9 + 6 * 4,)
    assert env.observation_space.dtype == np.float32
    assert env.action_space.shape == (2,)
    assert np.all(env.action_space.low == -1.0)
    assert np.all(env.action_space.high == 1.0)
    obs, _ = env.reset(seed=0)
    assert obs.dtype == np.float32
    assert env.observation_space.contains(obs)


def test_same_seed_same_episode_and_no_leakage() -> None:
    actions = np.random.default_rng(0).uniform(-1, 1, (400, 2)).astype(np.float32)
    a = SocialNavEnv("random")
    a.reset(seed=11)
    first = _run(a, actions)
    b = SocialNavEnv("random")
    b.reset(seed=3)
    _run(b, actions[::-1])  # another episode first: nothing may carry over
    obs_b, _ = b.reset(seed=11)
    obs_a, _ = SocialNavEnv("random").reset(seed=11)
    assert obs_a.tobytes() == obs_b.tobytes()
    assert _run(b, actions) == first


def test_reset_without_seed_follows_the_seeded_stream() -> None:
    a = SocialNavEnv("random")
    b = SocialNavEnv("random")
    a.reset(seed=5)
    b.reset(seed=5)
    seeds_a = [a.reset()[1]["episode_seed"] for _ in range(3)]
    seeds_b = [b.reset()[1]["episode_seed"] for _ in range(3)]
    assert seeds_a == seeds_b
    assert len(set(seeds_a)) == 3
    _, info = a.reset(options={"episode_seed": 42})
    assert info["episode_seed"] == 42


def test_pickle_round_trip_continues_identically() -> None:
    env = SocialNavEnv("random")
    env.reset(seed=2)
    actions = np.random.default_rng(1).uniform(-1, 1, (300, 2)).astype(np.float32)
    _run(env, actions[:50])
    clone = pickle.loads(pickle.dumps(env))
    assert _run(clone, actions[50:]) == _run(env, actions[50:])


def test_step_before_reset_and_after_end_raise() -> None:
    env = SocialNavEnv("random")
    with pytest.raises(SimulationError, match="call reset"):
        env.step(np.zeros(2, np.float32))
    env.reset(seed=0)
    with pytest.raises(PlannerError, match="finite"):
        env.step(np.array([np.nan, 0.0], np.float32))
    with pytest.raises(PlannerError, match="two real numbers"):
        env.step(np.array([1.0], np.float32))


def test_bad_arguments() -> None:
    with pytest.raises(ParameterError, match="k2"):
        EnvConfig(k2=-1.0)
    with pytest.raises(ParameterError, match="max_pedestrians"):
        EnvConfig(max_pedestrians=-2)
    with pytest.raises(ParameterError, match="kinematics"):
        EnvConfig(kinematics="tank")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="render_mode"):
        SocialNavEnv(render_mode="human")
    with pytest.raises(ScenarioError, match="unknown scenario"):
        SocialNavEnv("nowhere")
    with pytest.raises(ScenarioError, match="seed"):
        SocialNavEnv().reset(options={"episode_seed": -1})


def test_collision_penalty_is_twice_the_timeout_penalty() -> None:
    assert EnvConfig().collision_penalty == 2.0 * EnvConfig().timeout_penalty
    assert (EnvConfig().success_reward, EnvConfig().timeout_penalty) == (25.0, 25.0)
    assert EnvConfig(timeout_penalty=7.5).collision_penalty == 15.0


def _no_robot_force() -> srfm.SRFMParams:
    return srfm.SRFMParams().replace(a_robot=0.0)


def test_collision_terminates_with_the_collision_penalty(tmp_path: Path) -> None:
    # A pedestrian stands 1.5 m ahead; with A_r = 0 it does not step aside.
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(3.5, 5.0)],
        goals=[(3.5, 5.0)],
    )
    config = EnvConfig(timeout_penalty=3.0)
    env = SocialNavEnv(path, config, _no_robot_force())
    env.reset(seed=0)
    for _ in range(200):
        _, reward, terminated, truncated, info = env.step(np.array([1.0, 0.0], np.float32))
        if terminated or truncated:
            break
    assert terminated
    assert not truncated
    assert info["outcome"] == "collision"
    assert info["is_success"] is False
    assert info["r_term"] == -6.0
    assert reward == pytest.approx(-6.0 - config.k1 * info["r_dist"])
    # Centre distance at the collision is below the radius sum 0.5 m, and was not before.
    robot = env.robot_state
    d = math.hypot(robot.x - 3.5, robot.y - 5.0)
    assert d < 0.5
    assert d > 0.5 - 0.5 / 15 - 1e-9


def test_timeout_is_a_truncation_at_the_horizon(tmp_path: Path) -> None:
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(12.0, 12.0)],
        goals=[(12.0, 1.0)],
        horizon=7,
    )
    env = SocialNavEnv(path, EnvConfig(timeout_penalty=4.0))
    env.reset(seed=0)
    flags = []
    for _ in range(7):
        obs, _reward, terminated, truncated, info = env.step(np.zeros(2, np.float32))
        flags.append((terminated, truncated))
    assert flags == [(False, False)] * 6 + [(False, True)]
    assert info["outcome"] == "timeout"
    assert info["r_term"] == -4.0
    assert obs[kern.OBS_FLAGS] == 0.0
    assert obs[kern.OBS_FLAGS + 1] == 1.0


def test_goal_terminates_with_the_success_reward(tmp_path: Path) -> None:
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(3.5, 5.0),
        starts=[(12.0, 12.0)],
        goals=[(12.0, 1.0)],
    )
    env = SocialNavEnv(path, EnvConfig(success_reward=12.0))
    env.reset(seed=0)
    for _ in range(100):
        obs, _reward, terminated, truncated, info = env.step(np.array([1.0, 0.0], np.float32))
        if terminated or truncated:
            break
    assert terminated
    assert not truncated
    assert info["is_success"]
    assert info["r_term"] == 12.0
    assert obs[kern.OBS_FLAGS] == 1.0
    assert obs[kern.OBS_FLAGS + 1] == 1.0
    assert info["r_dist"] == pytest.approx(math.hypot(env.robot_state.x - 3.5, 0.0) / 1.5)


def test_leaving_the_world_is_penalised_like_a_collision(tmp_path: Path) -> None:
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(0.3, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(12.0, 12.0)],
        goals=[(12.0, 1.0)],
        heading=math.pi,
    )
    env = SocialNavEnv(path, EnvConfig(timeout_penalty=2.0))
    env.reset(seed=0)
    for _ in range(100):
        _, _, terminated, truncated, info = env.step(np.array([1.0, 0.0], np.float32))
        assert info["r_dist"] == 1.0  # moving away from the goal: capped at 1
        if terminated or truncated:
            break
    assert terminated
    assert info["outcome"] == "out_of_bounds"
    assert info["r_term"] == -4.0


def test_robot_starting_in_collision_is_refused(tmp_path: Path) -> None:
    """A scenario file whose robot overlaps a pedestrian is refused when read (issue 33,
    either version); one built in code (or moved there by a seed's noise) is refused by
    the environment at reset."""
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(2.2, 5.0)],
        goals=[(2.2, 5.0)],
    )
    with pytest.raises(ScenarioError, match=r"pedestrians\.starts\[0\]: overlaps robot\.start"):
        SocialNavEnv(path)
    free = fixed_scenario(
        tmp_path / "free.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(4.0, 5.0)],
        goals=[(4.0, 5.0)],
    )
    scenario = srfm.load_scenario(free)
    onto_robot = np.array([[2.2, 5.0]])
    onto_robot.setflags(write=False)
    scenario = attrs.evolve(scenario, ped_starts=onto_robot, ped_goals=onto_robot)
    with pytest.raises(ScenarioError, match=r"ends at sample 0 \(collision\)"):
        SocialNavEnv(scenario).reset(seed=0)


def test_r_div_is_exactly_zero_without_robot_force() -> None:
    env = SocialNavEnv("random", EnvConfig(k2=3.0), _no_robot_force())
    env.reset(seed=4)
    rng = np.random.default_rng(0)
    for _ in range(750):
        _, reward, te, tr, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        assert info["r_div"] == 0.0
        assert reward == info["r_term"] - 0.1 * info["r_dist"]
        if te or tr:
            break


def _reference_r_div(env: SocialNavEnv, params: srfm.SRFMParams, zone: float) -> float:
    """r_div from the public force API: step each zone pedestrian with and without the
    robot force and sum the distances between the two predictions."""
    robot = env.robot_state
    pos = env.factual_pos
    vel = env.factual_vel
    crowd = srfm.CrowdState.create(pos=pos, vel=vel, goal=env.factual_goal)
    with_robot = srfm.force_components(
        crowd, params, srfm.RobotBody(x=robot.x, y=robot.y, radius=0.2)
    )
    dt = 1 / 15
    total = 0.0
    for i in range(pos.shape[0]):
        if math.hypot(*(pos[i] - [robot.x, robot.y])) >= zone:
            continue
        preds = []
        for force in (
            with_robot.total[i],
            with_robot.goal[i] + with_robot.pedestrians[i] + with_robot.obstacles[i],
        ):
            v = vel[i] + force * dt
            speed = np.linalg.norm(v)
            if speed > 1.25:
                v = v * (1.25 / speed)
            preds.append(pos[i] + v * dt)
        total += float(np.linalg.norm(preds[0] - preds[1]))
    return total


def test_r_div_matches_a_numpy_reference() -> None:
    params = srfm.SRFMParams()
    env = SocialNavEnv("random", EnvConfig(), params)
    env.reset(seed=9)
    rng = np.random.default_rng(2)
    positive = 0
    for _ in range(400):
        _, _, te, tr, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        if te or tr:
            break
        expected = _reference_r_div(env, params, 3.0)
        assert info["r_div"] == pytest.approx(expected, rel=1e-9, abs=1e-15)
        positive += info["r_div"] > 0.0
    assert positive > 10


def test_reward_combines_the_terms() -> None:
    config = EnvConfig(k1=0.3, k2=7.0)
    env = SocialNavEnv("random", config)
    env.reset(seed=1)
    rng = np.random.default_rng(5)
    for _ in range(100):
        _, reward, te, tr, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        assert reward == pytest.approx(
            info["r_term"] - 0.3 * info["r_dist"] - 7.0 * info["r_div"], abs=1e-12
        )
        if te or tr:
            break


def _observe(
    robot: tuple[float, float, float, float, float, float, float],
    peds: list[tuple[float, float, float, float]],
    goal: tuple[float, float],
    holonomic: bool = False,
    last_action: tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    world = srfm.scenarios.WorldBounds()
    limits = srfm.RobotConfig(kinematics="holonomic" if holonomic else "unicycle").for_kernels()
    arr = np.array(peds, dtype=np.float64).reshape(-1, 4)
    out = np.zeros(kern.obs_size(3), dtype=np.float32)
    kern.build_observation(
        np.ascontiguousarray(arr[:, :2]),
        np.ascontiguousarray(arr[:, 2:]),
        np.array(robot, dtype=np.float64),
        np.array(last_action),
        False,
        False,
        limits,
        robot_task(np.array(goal), world, 750),
        EnvConfig(max_pedestrians=3).observation_params(world),
        np.zeros((0, 4)),
        np.zeros((0, 3)),
        np.zeros(max(len(peds), 1)),
        np.zeros(max(len(peds), 1), dtype=np.int64),
        out,
    )
    return out


def test_observation_hand_built() -> None:
    diag = math.hypot(15.0, 15.0)
    # Robot at (5, 5) facing +y (θ = π/2), moving at 0.25 m/s, turning at π/2 rad/s.
    robot = (5.0, 5.0, math.pi / 2, 0.0, 0.25, 0.25, math.pi / 2)
    peds = [
        (7.9, 5.0, 0.0, 0.0),  # 2.9 m to the right: in the zone, third closest
        (5.0, 6.0, 0.0, -1.0),  # 1 m ahead, walking at the robot
        (3.5, 5.0, 0.0, 0.25),  # 1.5 m to the left, walking along
        (5.0, 8.0, 0.0, 0.0),  # 3 m ahead: on the zone's edge, outside (strict <)
        (9.0, 9.0, 0.0, 0.0),  # far away
    ]
    obs = _observe(robot, peds, goal=(5.0, 9.0), last_action=(0.5, -2.0))
    assert obs[0] == pytest.approx(4.0 / diag)
    assert obs[1:3] == pytest.approx([1.0, 0.0], abs=1e-7)  # goal straight ahead
    assert obs[3:5] == pytest.approx([0.5, 0.5])  # v / 0.5, ω / π
    assert obs[5:7] == pytest.approx([0.5, -1.0])  # last action, clipped
    assert obs[7:9].tolist() == [0.0, 0.0]
    slots = obs[9:].reshape(3, 6)
    # closest: 1 m ahead, relative velocity (0, −1.25) world = −1.25 forward -> /2
    assert slots[0] == pytest.approx([1.0, 1 / 3, 1.0, 0.0, -0.625, 0.0], abs=1e-7)
    # then 1.5 m to the left, moving with the robot: relative velocity 0
    assert slots[1] == pytest.approx([1.0, 0.5, 0.0, 1.0, 0.0, 0.0], abs=1e-7)
    # then 2.9 m to the right; relative velocity −0.25 forward
    assert slots[2] == pytest.approx([1.0, 2.9 / 3, 0.0, -1.0, -0.125, 0.0], abs=1e-6)


def test_observation_zero_padding_and_no_one_in_zone() -> None:
    robot = (5.0, 5.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    obs = _observe(robot, [(5.0, 6.0, 0.0, 0.0)], goal=(10.0, 5.0))
    assert obs[9:15].tolist()[0] == 1.0
    assert np.all(obs[15:] == 0.0)
    empty = _observe(robot, [(12.0, 12.0, 0.0, 0.0)], goal=(10.0, 5.0))
    assert np.all(empty[9:] == 0.0)


def test_observation_keeps_the_k_closest() -> None:
    robot = (5.0, 5.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    peds = [(5.0 + d, 5.0, 0.0, 0.0) for d in (2.0, 0.6, 1.0, 2.5, 0.8)]
    obs = _observe(robot, peds, goal=(10.0, 5.0))
    dists = obs[9:].reshape(3, 6)[:, 1] * 3.0
    assert dists == pytest.approx([0.6, 0.8, 1.0])


def test_holonomic_action_is_robot_frame() -> None:
    holonomic = srfm.RobotConfig(kinematics="holonomic").for_kernels()
    unicycle = srfm.RobotConfig(kinematics="unicycle").for_kernels()
    c0, c1 = kern.action_to_command(1.0, 0.0, math.pi / 2, holonomic)
    assert (c0, c1) == pytest.approx((0.0, 0.5), abs=1e-12)
    c0, c1 = kern.action_to_command(3.0, -3.0, 0.0, unicycle)
    assert (c0, c1) == (0.5, -math.pi)


def test_holonomic_observation_velocity_in_robot_frame() -> None:
    robot = (5.0, 5.0, math.pi / 2, 0.0, 0.5, 0.5, 0.0)
    obs = _observe(robot, [], goal=(10.0, 5.0), holonomic=True)
    assert obs[3:5] == pytest.approx([1.0, 0.0], abs=1e-7)


def test_full_twin_can_be_skipped() -> None:
    env = SocialNavEnv("crosswalk", EnvConfig(counterfactual_twin=False))
    env.reset(seed=0)
    start = env.counterfactual_pos
    with_twin = SocialNavEnv("crosswalk")
    with_twin.reset(seed=0)
    for _ in range(30):
        _, r1, *_ = env.step(np.array([1.0, 0.0], np.float32))
        _, r2, *_ = with_twin.step(np.array([1.0, 0.0], np.float32))
        assert r1 == r2
    assert np.array_equal(env.counterfactual_pos, start)
    assert np.array_equal(env.factual_pos, with_twin.factual_pos)
    assert not np.array_equal(with_twin.counterfactual_pos, start)


def test_import_srfm_does_not_import_rl_dependencies() -> None:
    code = (
        "import sys, srfm, srfm.cli; "
        "bad = [m for m in ('torch', 'gymnasium', 'stable_baselines3') if m in sys.modules]; "
        "print(bad); sys.exit(1 if bad else 0)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_missing_dependency_names_the_extra() -> None:
    with pytest.raises(
        MissingDependencyError, match=r"pip install 'social-robot-force-model\[rl\]' -c constraints"
    ):
        require("surely_not_an_installed_module_xyz")
    assert issubclass(MissingDependencyError, ImportError)
    with pytest.raises(ImportError) as info:
        require("surely_not_an_installed_module_xyz")
    assert srfm.rl.INSTALL_HINT in str(info.value)


def test_gym_make_by_package_path_registers_in_a_fresh_process() -> None:
    """``srfm.rl`` is light, yet ``gym.make("srfm.rl:...")`` still finds the environment."""
    code = (
        "import sys, gymnasium as gym; "
        "env = gym.make('srfm.rl:srfm/SocialNav-v0', scenario='crosswalk'); "
        "assert env.spec.max_episode_steps == 750; print('ok')"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip() == "ok"
