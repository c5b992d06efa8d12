"""``srfm train``: a tiny real TD3 run, checkpoints, evaluation, resume."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import srfm
from srfm.cli import main
from srfm.errors import ParameterError
from srfm.rl.training import EvalResult, TrainConfig, evaluate_planner

pytest.importorskip("stable_baselines3")

TINY = [
    "--learning-starts",
    "50",
    "--buffer-size",
    "2000",
    "--batch-size",
    "32",
    "--eval-every",
    "100",
    "--eval-seeds",
    "1",
    "--checkpoint-every",
    "100",
]


def test_train_checkpoint_evaluate_and_resume(tmp_path: Path) -> None:
    run = tmp_path / "run"
    runner = CliRunner()
    result = runner.invoke(
        main,
        [
            "train",
            "--run-dir",
            str(run),
            "--steps",
            "200",
            "--k-div",
            "2.5",
            "--success-reward",
            "40",
            "--timeout-penalty",
            "30",
            "--no-progress",
            *TINY,
        ],
    )
    assert result.exit_code == 0, result.output
    assert "trained 200 steps" in result.output
    for name in ("latest.zip", "latest_replay_buffer.pkl", "best.zip", "config.json"):
        assert (run / name).is_file(), name
    assert (run / "checkpoints" / "step_000000100.zip").is_file()
    assert (run / "checkpoints" / "step_000000200.zip").is_file()
    meta = json.loads((run / "config.json").read_text())
    assert meta["env_config"]["k2"] == 2.5
    assert meta["env_config"]["success_reward"] == 40.0
    assert meta["env_config"]["timeout_penalty"] == 30.0
    assert meta["train_config"]["learning_rate"] == 1e-4
    assert meta["command"].startswith("srfm train --run-dir")
    assert "--k-div 2.5" in meta["command"]
    assert "--steps 200" in meta["command"]
    evals = [json.loads(line) for line in (run / "eval.jsonl").read_text().splitlines()]
    assert [e["steps"] for e in evals] == [100, 200]
    assert all(e["episodes"] == 5 for e in evals)
    assert json.loads((run / "state.json").read_text())["steps"] == 200

    # Resume to 450 steps, with the progress bar.
    result = runner.invoke(
        main,
        [
            "train",
            "--run-dir",
            str(run),
            "--steps",
            "300",
            "--k-div",
            "2.5",
            "--resume",
            str(run / "latest.zip"),
            *TINY,
        ],
    )
    assert result.exit_code == 0, result.output
    assert "resumed from" in result.output
    assert "with its replay buffer" in result.output
    assert "trained 300 steps" in result.output
    assert json.loads((run / "state.json").read_text())["steps"] == 300
    assert (run / "checkpoints" / "step_000000300.zip").is_file()

    # A run stopped at step 100 holds the same policy as the longer run's checkpoint.
    short = tmp_path / "short"
    result = runner.invoke(
        main,
        [
            "train",
            "--run-dir",
            str(short),
            "--steps",
            "100",
            "--k-div",
            "2.5",
            "--no-progress",
            *TINY,
        ],
    )
    assert result.exit_code == 0, result.output
    assert _weights(short / "checkpoints" / "step_000000100.zip") == _weights(
        run / "checkpoints" / "step_000000100.zip"
    )
    assert _weights(run / "checkpoints" / "step_000000100.zip") != _weights(
        run / "checkpoints" / "step_000000200.zip"
    )

    # A run started from another run's checkpoint (stage 2 of tools/rl/train_policies.sh)
    # records its own seed, in its checkpoints and in the policy file exported from them.
    from srfm.planners.td3 import load_checkpoint, load_numpy_policy
    from srfm.rl.training import export_policy

    second = tmp_path / "second"
    result = runner.invoke(
        main,
        [
            "train",
            "--run-dir",
            str(second),
            "--steps",
            "400",
            "--seed",
            "7",
            "--k-div",
            "1.0",
            "--no-progress",
            "--resume",
            str(short / "latest.zip"),
            *TINY,
        ],
    )
    assert result.exit_code == 0, result.output
    assert load_checkpoint(second / "latest.zip")[2]["seed"] == 7
    json_path, _ = export_policy(second / "latest.zip", tmp_path / "exported")
    training = load_numpy_policy(json_path).metadata["training"]
    assert training["seed"] == 7
    assert training["resume_config"]["train_config"]["seed"] == 7

    # The checkpoint runs as a planner.
    from srfm.planners.td3 import TD3Planner

    record = srfm.run_episode("concert", 0, TD3Planner(run / "latest.zip", "ckpt"))
    assert record.outcome in {"goal_reached", "collision", "out_of_bounds", "timeout"}


def _weights(path: Path) -> dict[str, bytes]:
    import io
    import zipfile

    import torch

    with zipfile.ZipFile(path) as z:
        state = torch.load(io.BytesIO(z.read("policy.pth")), weights_only=True)
    return {k: v.numpy().tobytes() for k, v in state.items()}


def test_train_rejects_bad_values(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["train", "--run-dir", str(tmp_path), "--k-div", "-1"])
    assert result.exit_code == 2
    with pytest.raises(ParameterError, match="gamma"):
        TrainConfig(gamma=1.5)
    with pytest.raises(ParameterError, match="net_arch"):
        TrainConfig(net_arch=(256, 0))


def test_paper_defaults() -> None:
    c = TrainConfig()
    assert (c.learning_rate, c.buffer_size, c.batch_size, c.learning_starts) == (
        1e-4,
        1_000_000,
        256,
        10_000,
    )
    assert (c.train_freq, c.gradient_steps, c.tau, c.gamma, c.policy_delay) == (
        5,
        5,
        0.005,
        0.99,
        2,
    )
    assert (c.target_policy_noise, c.target_noise_clip, c.action_noise_sigma) == (0.2, 0.5, 0.3)
    assert c.net_arch == (256, 256)
    assert c.total_steps == 2_000_000


def test_evaluate_planner_counts_outcomes() -> None:
    result = evaluate_planner(lambda: srfm.planners.make_planner("straight"), ["concert"], [0, 1])
    assert isinstance(result, EvalResult)
    assert result.episodes == 2
    total = result.success_rate + result.collision_rate + result.timeout_rate
    assert 0.0 <= total <= 1.0
    assert result.per_scenario["concert"]["mean_deviation_m"] == result.mean_deviation_m
    better = EvalResult(
        steps=0,
        episodes=2,
        success_rate=1.0,
        collision_rate=0.0,
        timeout_rate=0.0,
        mean_deviation_m=9.0,
        per_scenario={},
    )
    assert better.better_than(result) or result.success_rate == 1.0
    assert better.better_than(None)


def test_train_options_and_vectorised_envs(tmp_path: Path) -> None:
    run = tmp_path / "vec"
    args = ["train", "--run-dir", str(run), "--steps", "210", "--no-progress", *TINY]
    args += ["--net-arch", "16,8", "--n-envs", "3", "--train-freq", "2", "--gradient-steps", "3"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    meta = json.loads((run / "config.json").read_text())
    train_config = meta["train_config"]
    assert train_config["net_arch"] == [16, 8]
    assert (train_config["n_envs"], train_config["train_freq"]) == (3, 2)
    assert (train_config["gradient_steps"], train_config["backend"]) == (3, "sb3")
    assert "--net-arch 16,8" in meta["command"]
    assert "--n-envs 3" in meta["command"]
    # 3 steps per call: checkpoints when the count passes a multiple of 100
    assert (run / "checkpoints" / "step_000000102.zip").is_file()
    assert (run / "checkpoints" / "step_000000201.zip").is_file()
    assert (run / "1.monitor.csv").is_file()
    evals = [json.loads(line) for line in (run / "eval.jsonl").read_text().splitlines()]
    assert [e["steps"] for e in evals] == [102, 201]
    bad = CliRunner().invoke(main, ["train", "--run-dir", str(run), "--net-arch", "16,x"])
    assert bad.exit_code == 2
    assert "comma-separated list of positive integers" in bad.output
    with pytest.raises(ParameterError, match="backend"):
        TrainConfig(backend="jax")


def test_sbx_backend_trains_resumes_and_exports(tmp_path: Path) -> None:
    pytest.importorskip("sbx")
    import warnings

    import numpy as np

    from srfm.planners.td3 import load_numpy_policy
    from srfm.rl.training import export_policy, train

    run = tmp_path / "sbx"
    config = TrainConfig(
        total_steps=150,
        learning_starts=50,
        buffer_size=500,
        batch_size=16,
        net_arch=(16,),
        eval_every=100,
        eval_seeds=1,
        checkpoint_every=100,
        backend="sbx",
    )
    result = train(config, run)
    assert result.steps == 150
    assert result.best_eval is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        json_path, _ = export_policy(run / "checkpoints" / "step_000000100.zip", tmp_path / "e")
    policy = load_numpy_policy(json_path)
    assert policy.metadata["training"]["backend"] == "sbx"
    assert policy.metadata["training"]["steps"] == 100
    assert policy.metadata["training"]["run_config"]["train_config"]["backend"] == "sbx"
    assert policy.metadata["evaluation"]["periodic"]["steps"] == 100
    import sbx

    model = sbx.TD3.load(run / "checkpoints" / "step_000000100.zip", device="cpu")
    obs = np.random.default_rng(0).uniform(-1, 1, (256, policy.actor.obs_size))
    predicted, _ = model.predict(obs.astype(np.float32), deterministic=True)
    got = np.stack([policy.actor.forward(o) for o in obs.astype(np.float32)])
    assert np.abs(got - predicted).max() <= 1e-5
    more = train(attrs_evolve(config, total_steps=200), run, resume=run / "latest.zip")
    assert more.steps == 200
    with pytest.raises(srfm.SrfmError, match="written by the sbx backend"):
        train(attrs_evolve(config, backend="sb3"), run, resume=run / "latest.zip")


def attrs_evolve(config: TrainConfig, **changes: object) -> TrainConfig:
    import attrs

    return attrs.evolve(config, **changes)


def test_family_weights_option(tmp_path: Path) -> None:
    from srfm.rl import SocialNavEnv

    run = tmp_path / "weighted"
    args = ["train", "--run-dir", str(run), "--steps", "120", "--no-progress", *TINY]
    args += ["--scenario", "mixed", "--family-weights", "0,0,0,1,0", "--net-arch", "8"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    meta = json.loads((run / "config.json").read_text())
    assert meta["train_config"]["family_weights"] == [0.0, 0.0, 0.0, 1.0, 0.0]
    assert "--family-weights 0.0,0.0,0.0,1.0,0.0" in meta["command"]
    env = SocialNavEnv("mixed", family_weights=(0, 0, 0, 1, 0))
    for seed in range(5):
        env.reset(seed=seed)
        assert env.layout.name == "mixed/standing"
    bad = CliRunner().invoke(main, [*args[:3], str(tmp_path / "b"), "--family-weights", "1,2"])
    assert bad.exit_code == 2
    assert "need 5 values" in bad.output
    with pytest.raises(ParameterError, match="'mixed' scenario only"):
        SocialNavEnv("crosswalk", family_weights=(1, 1, 1, 1, 1))
    with pytest.raises(ParameterError, match="'circle' must be finite"):
        TrainConfig(family_weights=(1.0, 1.0, 1.0, 1.0, -2.0))


def test_walls_recipe_options(tmp_path: Path) -> None:
    """Range beams, a library share, validation scenarios and selection by outcome only
    reach the environment, the evaluations and the exported policy."""
    from srfm.planners.td3 import load_policy
    from srfm.rl.training import export_policy, selectable

    run = tmp_path / "walls"
    args = ["train", "--run-dir", str(run), "--steps", "200", "--no-progress", *TINY]
    args += ["--scenario", "mixed", "--net-arch", "8", "--range-beams", "8"]
    args += ["--library", "narrow_hallway,frontal_approach", "--library-share", "0.5"]
    args += ["--eval-scenarios", "mixed,narrow_hallway", "--select-by-outcome"]
    args += ["--k-div", "0", "--k-div-start", "100", "--k-div-ramp", "50"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    meta = json.loads((run / "config.json").read_text())
    assert meta["train_config"]["library"] == ["narrow_hallway", "frontal_approach"]
    assert meta["train_config"]["select_by_deviation"] is False
    assert meta["env_config"]["range_beams"] == 8
    evals = [json.loads(line) for line in (run / "eval.jsonl").read_text().splitlines()]
    assert [set(e["per_scenario"]) for e in evals] == [{"mixed", "narrow_hallway"}] * 2
    # k2 = 0 throughout, but only evaluations after the curriculum window may be the best
    assert [e["eligible"] for e in evals] == [False, True]
    json_path, _ = export_policy(run / "best.zip", tmp_path / "policy")
    _, config = load_policy(json_path)
    assert config.range_beams == 8
    assert config.obs_size == 9 + 6 * 10 + 8
    config_k2 = TrainConfig(k_div_start=100, k_div_ramp=50)
    assert [selectable(config_k2, s) for s in (149, 150)] == [False, True]
    bad = CliRunner().invoke(main, [*args[:3], str(tmp_path / "b"), "--library", "nowhere"])
    assert bad.exit_code == 2
    assert "nowhere" in bad.output
    with pytest.raises(ParameterError, match="nowhere"):
        TrainConfig(eval_scenarios=("crosswalk", "nowhere"))


def test_selection_by_outcome_ignores_deviation() -> None:
    def result(success: float, deviation: float) -> EvalResult:
        return EvalResult(
            steps=0,
            episodes=10,
            success_rate=success,
            collision_rate=0.0,
            timeout_rate=1.0 - success,
            mean_deviation_m=deviation,
            per_scenario={},
        )

    assert result(0.9, 0.1).better_than(result(0.9, 0.2))
    assert not result(0.9, 0.1).better_than(result(0.9, 0.2), by_deviation=False)
    assert result(1.0, 0.5).better_than(result(0.9, 0.2), by_deviation=False)
