"""TD3 policy planners: NumPy actor = torch actor, lazy loading, episodes, registry."""

from __future__ import annotations

import importlib
from pathlib import Path

import attrs
import numpy as np
import pytest

import srfm
from srfm.errors import PlannerError
from srfm.planners import available_planners, make_planner
from srfm.planners.td3 import (
    SHIPPED_POLICIES,
    NumpyActor,
    PolicyPlanner,
    TD3Planner,
    load_policy,
    shipped_policy_path,
)

pytestmark = pytest.mark.filterwarnings("ignore:.*unpickles:UserWarning")

sb3 = pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

from srfm.rl import EnvConfig, SocialNavEnv  # noqa: E402

# The SB3 checkpoints the shipped policies were exported from (kept out of the wheel).
CHECKPOINTS = Path(__file__).parents[2] / "tools" / "rl" / "policies"


@pytest.fixture(scope="module")
def policy_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small untrained TD3 policy saved the way ``srfm train`` saves it."""
    config = EnvConfig(kinematics="unicycle")
    env = SocialNavEnv("random", config)
    model = sb3.TD3("MlpPolicy", env, policy_kwargs={"net_arch": [32, 16]}, seed=0, device="cpu")
    model.srfm_env_config = attrs.asdict(config)
    path = tmp_path_factory.mktemp("policy") / "policy.zip"
    model.save(path)
    return path


def test_numpy_forward_equals_torch_forward(policy_file: Path) -> None:
    model = sb3.TD3.load(policy_file, device="cpu")
    actor = NumpyActor.from_sb3(model.actor)
    obs = np.random.default_rng(0).uniform(-1, 1, (64, actor.obs_size)).astype(np.float32)
    with torch.no_grad():
        expected = model.actor(torch.as_tensor(obs)).numpy()
    got = np.stack([actor.forward(o) for o in obs])
    assert got.dtype == np.float32
    np.testing.assert_allclose(got, expected, rtol=0, atol=2e-6)
    plain = np.stack([actor.forward_numpy(o) for o in obs])
    np.testing.assert_allclose(plain, expected, rtol=0, atol=2e-6)
    # zero inputs are skipped in the numba layers: still the same function
    sparse = obs.copy()
    sparse[:, ::2] = 0.0
    with torch.no_grad():
        expected_sparse = model.actor(torch.as_tensor(sparse)).numpy()
    got_sparse = np.stack([actor.forward(o) for o in sparse])
    np.testing.assert_allclose(got_sparse, expected_sparse, rtol=0, atol=2e-6)
    # and SB3's own predict (deterministic) agrees
    predicted, _ = model.predict(obs, deterministic=True)
    np.testing.assert_allclose(got, predicted, rtol=0, atol=2e-6)


def test_load_policy_returns_the_training_config(policy_file: Path) -> None:
    actor, config = load_policy(policy_file)
    assert config == EnvConfig(kinematics="unicycle")
    assert actor.obs_size == SocialNavEnv().observation_space.shape[0]


def test_planner_loads_lazily_and_completes_an_episode(policy_file: Path) -> None:
    planner = TD3Planner(policy_file, "mine")
    assert planner._inner is None  # nothing loaded before the first reset
    record = srfm.run_episode("crosswalk", 0, planner)
    assert planner._inner is not None
    assert record.planner == "mine"
    assert record.outcome in {"goal_reached", "collision", "out_of_bounds", "timeout"}
    assert planner.detection_range_m == 3.0
    again = srfm.run_episode("crosswalk", 0, TD3Planner(policy_file, "mine"))
    assert np.array_equal(again.robot_pose, record.robot_pose)


def test_detection_range_is_valid_from_construction(policy_file: Path, tmp_path: Path) -> None:
    # run_episode reads detection_range_m before the first reset.
    planner = TD3Planner(policy_file)
    assert planner._inner is None
    assert planner.detection_range_m == 3.0
    model = sb3.TD3.load(policy_file, device="cpu")
    model.srfm_env_config = attrs.asdict(EnvConfig(kinematics="unicycle", social_zone_m=2.5))
    narrow = tmp_path / "narrow.zip"
    model.save(narrow)
    planner = TD3Planner(narrow)
    assert planner.detection_range_m == 2.5
    assert planner._inner is None  # read without loading the policy
    srfm.run_episode("crosswalk", 0, planner)
    assert planner.detection_range_m == 2.5
    with pytest.raises(PlannerError, match="does not exist"):
        TD3Planner(tmp_path / "nope.zip")


def test_planner_refuses_other_kinematics(policy_file: Path, tmp_path: Path) -> None:
    from srfm.scenarios import load_scenario

    scenario = load_scenario("crosswalk")
    holo = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics="holonomic"))
    with pytest.raises(PlannerError, match="trained for a unicycle robot"):
        srfm.run_episode(holo, 0, TD3Planner(policy_file))


def test_missing_and_foreign_files(policy_file: Path, tmp_path: Path) -> None:
    with pytest.raises(PlannerError, match="does not exist"):
        load_policy(tmp_path / "nope.zip")
    bad = tmp_path / "bad.zip"
    bad.write_bytes(b"not a zip")
    with pytest.raises(PlannerError, match="cannot load a TD3 policy"):
        load_policy(bad)
    model = sb3.TD3.load(policy_file, device="cpu")
    del model.srfm_env_config
    plain = tmp_path / "plain.zip"
    model.save(plain)
    with pytest.raises(PlannerError, match="no srfm environment configuration"):
        load_policy(plain)


def test_act_before_reset_raises(policy_file: Path) -> None:
    actor, config = load_policy(policy_file)
    with pytest.raises(PlannerError, match="reset"):
        PolicyPlanner(actor, config).act(None)  # type: ignore[arg-type]


def test_shipped_policies_are_registered() -> None:
    names = {p.name for p in available_planners()}
    assert {"td3-srfm", "td3-base"} <= names
    for name in SHIPPED_POLICIES:
        assert shipped_policy_path(name).is_file()
        size = shipped_policy_path(name).stat().st_size
        assert size < 5_000_000


@pytest.mark.parametrize("name", ["td3-srfm", "td3-base"])
def test_shipped_planners_complete_an_episode(name: str) -> None:
    planner = make_planner(name)
    assert planner.name == name
    record = srfm.run_episode("footpath", 1, planner)
    assert record.outcome in {"goal_reached", "collision", "out_of_bounds", "timeout"}
    _, config = load_policy(shipped_policy_path(name))
    assert (config.k2 > 0.0) == (name == "td3-srfm")


def test_loading_a_checkpoint_warns_about_pickle(policy_file: Path) -> None:
    from srfm.planners.td3 import load_checkpoint

    with pytest.warns(UserWarning, match="unpickles"):
        _, _, info = load_checkpoint(policy_file)
    assert info["backend"] == "sb3"
    assert info["seed"] == 0


def test_export_round_trip_and_same_episodes(policy_file: Path, tmp_path: Path) -> None:
    from click.testing import CliRunner

    from srfm.cli import main
    from srfm.planners.td3 import load_numpy_policy

    result = CliRunner().invoke(
        main, ["export-policy", str(policy_file), str(tmp_path / "out"), "--note", "test"]
    )
    assert result.exit_code == 0, result.output
    policy = load_numpy_policy(tmp_path / "out.json")
    assert policy.config == EnvConfig(kinematics="unicycle")
    training = policy.metadata["training"]
    assert training["backend"] == "sb3"
    assert training["note"] == "test"
    assert training["checkpoint_hyperparameters"]["policy_kwargs"] == {"net_arch": [32, 16]}
    from_zip = srfm.run_episode("crosswalk", 2, TD3Planner(policy_file, "p"))
    from_npz = srfm.run_episode("crosswalk", 2, TD3Planner(tmp_path / "out.json", "p"))
    assert np.array_equal(from_zip.robot_pose, from_npz.robot_pose)
    assert from_zip.outcome == from_npz.outcome
    bad = CliRunner().invoke(main, ["export-policy", str(tmp_path / "out.json"), "x"])
    assert bad.exit_code == 2
    assert "cannot load a TD3 policy" in bad.output


def _observations(n_random: int, config: EnvConfig) -> np.ndarray:
    """Random observations in [−1, 1] and observations met in episodes (with walls)."""
    rng = np.random.default_rng(5)
    obs = [rng.uniform(-1, 1, (n_random, config.obs_size)).astype(np.float32)]
    sparse = obs[0].copy()
    sparse[rng.random(sparse.shape) < 0.5] = 0.0
    obs.append(sparse)
    for scenario in ("crosswalk", "concert", "random", "narrow_doorway"):
        env = SocialNavEnv(scenario, config.replace(kinematics="unicycle"))
        o, _ = env.reset(seed=1)
        for _ in range(300):
            obs.append(o[None])
            o, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                o, _ = env.reset()
    return np.concatenate(obs)


@pytest.mark.parametrize("name", sorted(SHIPPED_POLICIES))
def test_shipped_numpy_actor_matches_predict(name: str) -> None:
    from srfm.planners.td3 import checkpoint_backend, load_numpy_policy

    numpy_policy = load_numpy_policy(shipped_policy_path(name))
    checkpoint = CHECKPOINTS / shipped_policy_path(name).with_suffix(".zip").name
    # the shipped checkpoints were trained with SBX (docs/rl.md); make setup installs it
    library = importlib.import_module(
        checkpoint_backend(checkpoint).replace("sb3", "stable_baselines3")
    )
    model = library.TD3.load(checkpoint, device="cpu")
    assert numpy_policy.config == EnvConfig(**model.srfm_env_config)
    obs = _observations(2000, numpy_policy.config)
    predicted, _ = model.predict(obs, deterministic=True)
    got = np.stack([numpy_policy.actor.forward(o) for o in obs])
    # float32 sums in another order than XLA's: a few ulps of the pre-activations
    # (93 inputs), magnified where tanh is steep; measured at most 1.1e-5
    assert np.abs(got - predicted).max() <= 3e-5
