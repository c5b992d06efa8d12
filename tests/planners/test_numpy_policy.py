"""NumPy policy files: save/load round trip, validation, shipped files (NumPy only)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import attrs
import numpy as np
import pytest

import srfm
from srfm.errors import PlannerError
from srfm.planners import make_planner
from srfm.planners._observation import EnvConfig, obs_size
from srfm.planners.td3 import (
    OBSERVATION_LAYOUT_VERSION,
    POLICY_FORMAT,
    SHIPPED_POLICIES,
    NumpyActor,
    TD3Planner,
    load_numpy_policy,
    load_policy,
    read_policy_config,
    save_numpy_policy,
    shipped_policy_path,
)

CONFIG = EnvConfig(kinematics="unicycle", k2=0.0)


def _actor(sizes: tuple[int, ...] = (16, 8), seed: int = 0) -> NumpyActor:
    rng = np.random.default_rng(seed)
    dims = (obs_size(CONFIG.max_pedestrians), *sizes, 2)
    weights = tuple(
        rng.normal(0, 0.3, (dims[k + 1], dims[k])).astype(np.float32) for k in range(len(dims) - 1)
    )
    biases = tuple(rng.normal(0, 0.1, dims[k + 1]).astype(np.float32) for k in range(len(dims) - 1))
    return NumpyActor(weights, biases)


@pytest.fixture
def saved(tmp_path: Path) -> Path:
    json_path, _ = save_numpy_policy(
        _actor(), CONFIG, tmp_path / "p", training={"seed": 3}, evaluation=None
    )
    return json_path


def _edit(path: Path, **changes: object) -> None:
    meta = json.loads(path.read_text())
    meta.update(changes)
    path.write_text(json.dumps(meta))


def test_round_trip_keeps_weights_config_and_metadata(saved: Path) -> None:
    policy = load_numpy_policy(saved)
    same = load_numpy_policy(saved.with_suffix(".npz"))  # either file names the policy
    original = _actor()
    for a, b in zip(policy.actor.weights, original.weights, strict=True):
        assert a.dtype == np.float32
        assert np.array_equal(a, b)
    assert policy.config == CONFIG == same.config
    assert policy.metadata["format"] == POLICY_FORMAT
    assert policy.metadata["observation_layout_version"] == OBSERVATION_LAYOUT_VERSION
    assert policy.metadata["kinematics"] == "unicycle"
    assert policy.metadata["training"] == {"seed": 3}
    assert policy.metadata["layers"] == [[16, 69], [8, 16], [2, 8]]
    assert read_policy_config(saved) == CONFIG
    actor, config = load_policy(saved)
    assert config == CONFIG
    obs = np.random.default_rng(1).uniform(-1, 1, (32, actor.obs_size)).astype(np.float32)
    for o in obs:
        np.testing.assert_array_equal(actor.forward(o), original.forward(o))
        np.testing.assert_allclose(actor.forward(o), actor.forward_numpy(o), atol=1e-6)


def test_npz_is_read_without_pickle(saved: Path) -> None:
    npz = saved.with_suffix(".npz")
    with np.load(npz, allow_pickle=False) as data:
        assert sorted(data.files) == [
            "bias_0",
            "bias_1",
            "bias_2",
            "weight_0",
            "weight_1",
            "weight_2",
        ]
    # an object array (which needs pickle) is refused
    arrays = dict(np.load(npz))
    arrays["weight_0"] = np.array([object()] * 3, dtype=object)
    np.savez(npz, **arrays)
    _edit(saved, weights_sha256=None)
    with pytest.raises(PlannerError, match="cannot read the weights"):
        load_numpy_policy(saved)


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"format": "something"}, "format is 'something'"),
        ({"format_version": 99}, "format_version 99"),
        ({"observation_layout_version": 0}, "observation_layout_version 0"),
        ({"kinematics": "holonomic"}, "kinematics 'holonomic'"),
        ({"env_config": {"k1": -1.0, "kinematics": "unicycle"}}, "bad environment configuration"),
        ({"env_config": None}, "no srfm environment configuration"),
        ({"obs_size": 10}, "obs_size 10 does not match"),
        ({"layers": [[16, 69], [2, 16]]}, "do not match the arrays"),
        ({"activations": ["relu", "relu", "relu"]}, "activations"),
        ({"weights_sha256": "0" * 64}, "SHA-256 differs"),
    ],
)
def test_bad_metadata_is_named(saved: Path, changes: dict[str, object], match: str) -> None:
    _edit(saved, **changes)
    with pytest.raises(PlannerError, match=match):
        load_numpy_policy(saved)


def test_bad_weights_are_named(saved: Path) -> None:
    npz = saved.with_suffix(".npz")
    arrays = dict(np.load(npz))

    def write(**changes: np.ndarray) -> None:
        np.savez(npz, **{**arrays, **changes})
        _edit(saved, weights_sha256=None)

    write(weight_1=arrays["weight_1"][:, :5])
    with pytest.raises(PlannerError, match=r"weight_1 has shape \(8, 5\), expected \(out, 16\)"):
        load_numpy_policy(saved)
    write(bias_2=np.zeros(3, np.float32))
    with pytest.raises(PlannerError, match=r"bias_2 has shape \(3,\), expected \(2,\)"):
        load_numpy_policy(saved)
    bad = arrays["weight_0"].copy()
    bad[0, 0] = np.nan
    write(weight_0=bad)
    with pytest.raises(PlannerError, match="weight_0 holds NaN"):
        load_numpy_policy(saved)
    write(weight_0=arrays["weight_0"].astype(np.int32))
    with pytest.raises(PlannerError, match="dtype int32"):
        load_numpy_policy(saved)
    np.savez(npz, weight_0=arrays["weight_0"])
    _edit(saved, weights_sha256=None)
    with pytest.raises(PlannerError, match="expected weight_0, bias_0"):
        load_numpy_policy(saved)


def test_missing_and_unreadable_files(tmp_path: Path, saved: Path) -> None:
    with pytest.raises(PlannerError, match="does not exist"):
        load_numpy_policy(tmp_path / "nope.json")
    saved.with_suffix(".npz").unlink()
    with pytest.raises(PlannerError, match=r"p\.npz' does not exist"):
        load_numpy_policy(saved)
    saved.write_text("{not json")
    with pytest.raises(PlannerError, match="not a JSON policy metadata file"):
        read_policy_config(saved)


def test_save_refuses_actor_that_does_not_fit(tmp_path: Path) -> None:
    with pytest.raises(PlannerError, match="must name its kinematics"):
        save_numpy_policy(_actor(), EnvConfig(), tmp_path / "p")
    with pytest.raises(PlannerError, match="expected \\(out, 39\\)"):
        save_numpy_policy(_actor(), CONFIG.replace(max_pedestrians=5), tmp_path / "p")


def test_numpy_policy_as_planner(saved: Path) -> None:
    planner = TD3Planner(saved, "mine")
    assert planner._inner is None
    assert planner.detection_range_m == CONFIG.social_zone_m
    record = srfm.run_episode("crosswalk", 0, planner)
    again = srfm.run_episode("crosswalk", 0, TD3Planner(saved.with_suffix(".npz"), "mine"))
    assert np.array_equal(record.robot_pose, again.robot_pose)


def test_planner_refuses_other_kinematics(tmp_path: Path) -> None:
    path, _ = save_numpy_policy(_actor(), CONFIG.replace(kinematics="holonomic"), tmp_path / "h")
    with pytest.raises(PlannerError, match="trained for a holonomic robot"):
        srfm.run_episode("crosswalk", 0, TD3Planner(path))


@pytest.mark.parametrize("name", sorted(SHIPPED_POLICIES))
def test_shipped_numpy_policies(name: str) -> None:
    path = shipped_policy_path(name)
    assert path.suffix == ".json"
    policy = load_numpy_policy(path)
    meta = policy.metadata
    assert (policy.config.k2 > 0.0) == (name == "td3-srfm")
    assert meta["kinematics"] == "unicycle"
    # the walls-aware recipe of docs/rl.md (tools/rl/study.py): SBX [64, 64] from
    # scratch, 24 range beams, actions held for 4 simulation steps, the progress term 10,
    # a checkpoint after the k2 curriculum (every 25,000 actions); the weights are those
    # of the study run the note names (its policy in tools/rl/study/policies/)
    assert meta["layers"] == [[64, 93], [64, 64], [2, 64]]
    assert meta["training"]["backend"] == "sbx"
    run = re.search(r"run (k[02]-seed(\d+)) of tools/rl/study.py", meta["training"]["note"])
    assert run is not None
    assert int(run[2]) == meta["training"]["seed"]
    study = Path(__file__).parents[2] / "tools" / "rl" / "study" / "policies" / f"{run[1]}.npz"
    assert path.with_suffix(".npz").read_bytes() == study.read_bytes()
    assert meta["training"]["steps"] % 25_000 == 0
    assert meta["training"]["steps"] >= 125_000
    assert policy.config.k_progress == 10.0
    assert policy.config.action_repeat == 4
    assert (policy.config.range_beams, policy.config.range_max_m) == (24, 4.0)
    assert meta["evaluation"]["at_export"]["episodes"] == 50
    planner = make_planner(name)
    record = srfm.run_episode("narrow_doorway", 1, planner)
    assert record.outcome in {"goal_reached", "collision", "out_of_bounds", "timeout"}
    assert attrs.asdict(policy.config) == meta["env_config"]


def test_policy_files_written_before_range_beams_load_without_them() -> None:
    """A file written before an option existed loads with its default (range beams:
    none): the first shipped policies, kept in tools/rl/policies/."""
    path = Path(__file__).parents[2] / "tools" / "rl" / "policies" / "td3_srfm_seed12.json"
    policy = load_numpy_policy(path)
    meta = policy.metadata
    loaded = attrs.asdict(policy.config)
    assert "range_beams" not in meta["env_config"]
    assert {k: loaded[k] for k in meta["env_config"]} == meta["env_config"]
    assert (policy.config.range_beams, policy.config.obs_size) == (0, 69)
    assert meta["layers"][0] == [64, 69]


@pytest.mark.parametrize("variant", ["srfm", "base"])
@pytest.mark.parametrize("seed", [11, 12, 13])
def test_per_seed_policies_load_and_drive(variant: str, seed: int) -> None:
    """The policy of every training seed (tools/rl/policies/, docs/rl.md) is a valid NumPy
    policy file of that run, and drives a robot."""
    from srfm.planners.td3 import TD3Planner, load_numpy_policy

    path = (
        Path(__file__).parents[2] / "tools" / "rl" / "policies" / f"td3_{variant}_seed{seed}.json"
    )
    policy = load_numpy_policy(path)
    training = policy.metadata["training"]
    assert training["seed"] == seed
    assert training["backend"] == "sbx"
    assert policy.config.k2 == (2.0 if variant == "srfm" else 0.0)
    assert policy.config.k_progress == 5.0  # stage 2
    assert policy.config.action_repeat == 4
    record = srfm.run_episode("crosswalk", 0, TD3Planner(path, f"td3-{variant}-seed{seed}"))
    moved = np.linalg.norm(record.robot_pose[-1, :2] - record.robot_pose[0, :2])
    assert moved > 1.0


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_stage1_policies_load_and_drive(seed: int) -> None:
    """The pre-training (stage 1) RL_base policy of every training seed
    (tools/rl/policies/stage1/, docs/rl.md) is a valid NumPy policy file with the paper's
    terminal rewards, and drives a robot."""
    from srfm.planners.td3 import TD3Planner, load_numpy_policy

    path = (
        Path(__file__).parents[2]
        / "tools"
        / "rl"
        / "policies"
        / "stage1"
        / f"td3_base_seed{seed}.json"
    )
    policy = load_numpy_policy(path)
    assert policy.metadata["training"]["seed"] == seed
    assert policy.config.k2 == 0.0
    assert policy.config.success_reward == 25.0
    assert policy.config.action_repeat == 4
    record = srfm.run_episode("crosswalk", 0, TD3Planner(path, f"stage1-seed{seed}"))
    moved = np.linalg.norm(record.robot_pose[-1, :2] - record.robot_pose[0, :2])
    assert moved > 1.0
