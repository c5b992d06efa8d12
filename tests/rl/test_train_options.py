"""``srfm train`` builds one validated :class:`TrainOptions` and runs it (issue 39 part 5:
``_train`` took 37 parameters).

Behaviour is unchanged: the command line writes the same ``config.json`` as the
``srfm train`` of main before the change (``data/train_cli_golden.json``, written by it
with the arguments below; configuration and command do not depend on the machine), and
trains the same bits as the Python API given the same settings (checkpoints, replay
buffer, evaluations, monitor files; on one machine, as TD3 on a CPU is only bitwise
reproducible there). The same comparison against main's own run of the same command,
on one machine, is in the report of issue 39.
"""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from srfm.cli import main
from srfm.errors import ParameterError
from srfm.rl.training import TrainConfig, TrainOptions, train

pytest.importorskip("stable_baselines3")

GOLDEN = json.loads((Path(__file__).parent / "data" / "train_cli_golden.json").read_text())
ARGS = [
    "--steps", "120", "--learning-starts", "40", "--buffer-size", "500", "--batch-size", "16",
    "--net-arch", "8", "--eval-every", "60", "--eval-seeds", "1", "--checkpoint-every", "60",
    "--k-div", "1.5", "--k-div-start", "20", "--k-div-ramp", "40", "--scenario", "mixed",
    "--n-envs", "2", "--library", "narrow_hallway", "--library-share", "0.5",
    "--range-beams", "4", "--family-weights", "1,1,1,2,1", "--eval-scenarios",
    "crosswalk,mixed", "--select-by-outcome", "--no-twin", "--no-progress",
]  # fmt: skip
# What differs between two runs of the same training: clocks, and object reprs in SB3's
# "data" member.
_CLOCKS = {"start_time", "policy_class", "replay_buffer_class"}


def _comparable(path: Path) -> Any:
    """A run file's content less what a clock (or a memory address) writes into it."""
    data = path.read_bytes()
    if path.suffix == ".zip":
        members = {}
        archive = zipfile.ZipFile(io.BytesIO(data))
        for name in archive.namelist():
            if name == "system_info.txt":
                continue
            content: Any = archive.read(name)
            if name == "data":
                content = {k: v for k, v in json.loads(content).items() if k not in _CLOCKS}
            members[name] = content
        return members
    if path.name == "eval.jsonl":
        rows = [json.loads(line) for line in data.decode().splitlines()]
        return [{k: v for k, v in row.items() if k != "wall_time_s"} for row in rows]
    if path.name.endswith("monitor.csv"):  # less the start time and each episode's time
        return [line.rsplit(",", 1)[0] for line in data.decode().splitlines()[1:]]
    if path.name == "state.json":
        return {k: v for k, v in json.loads(data).items() if "wall" not in k}
    return data


def _subsequence(words: list[str], of: list[str]) -> bool:
    it = iter(of)
    return all(word in it for word in words)


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    run = tmp_path_factory.mktemp("train") / "cli"
    result = CliRunner().invoke(main, ["train", "--run-dir", str(run), *ARGS])
    assert result.exit_code == 0, result.output
    return run


def test_the_command_line_writes_mains_configuration(cli_run: Path) -> None:
    """Every field and option main wrote is there with the same value, in the same
    order (a training option added since, with its default, may come between)."""
    meta = json.loads((cli_run / "config.json").read_text())
    for section in ("train_config", "env_config"):
        golden = GOLDEN[section]
        assert {k: meta[section].get(k) for k in golden} == golden, section
    command = meta["command"].replace(str(cli_run), "RUN").split()
    assert _subsequence(GOLDEN["command"].split(), command)
    assert command[:4] == ["srfm", "train", "--run-dir", "RUN"]


def test_the_command_line_and_the_python_api_train_the_same_bits(
    cli_run: Path, tmp_path: Path
) -> None:
    settings = json.loads((cli_run / "config.json").read_text())["train_config"]
    options = TrainOptions.from_settings(run_dir=tmp_path / "api", progress=False, **settings)
    result = train(options.config, options.run_dir, resume=options.resume)
    assert result.steps == 120
    files = sorted(p.relative_to(cli_run) for p in cli_run.rglob("*") if p.is_file())
    names = [str(f) for f in files]
    assert "latest.zip" in names
    assert "checkpoints/step_000000060.zip" in names
    assert "eval.jsonl" in names
    assert sorted(p.relative_to(options.run_dir) for p in options.run_dir.rglob("*")) == sorted(
        p.relative_to(cli_run) for p in cli_run.rglob("*")
    )
    for name in files:
        if name.name == "config.json":  # the API records no command
            continue
        assert _comparable(cli_run / name) == _comparable(options.run_dir / name), name


def test_options_are_validated_with_clear_errors(tmp_path: Path) -> None:
    options = TrainOptions.from_settings(run_dir=str(tmp_path), net_arch=[16, 8], k_div=0.0)
    assert options.run_dir == tmp_path
    assert options.config == TrainConfig(net_arch=(16, 8), k_div=0.0)
    assert options.resume is None
    assert options.progress is True
    with pytest.raises(ParameterError, match=r"TrainConfig: unknown option 'k_dvi'; known: "):
        TrainOptions.from_settings(run_dir=tmp_path, k_dvi=1.0)
    with pytest.raises(ParameterError, match=r"train.k_div must be >= 0, got -1.0$"):
        TrainOptions.from_settings(run_dir=tmp_path, k_div=-1.0)
    with pytest.raises(ParameterError, match=r"train.run_dir must be a path, got 3$"):
        TrainOptions(run_dir=3)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"train.resume must be a path, got \[\]$"):
        TrainOptions(run_dir=tmp_path, resume=[])  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"train.progress must be true or false, got 1$"):
        TrainOptions(run_dir=tmp_path, progress=1)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"train.config must be a TrainConfig, got \{\}$"):
        TrainOptions(run_dir=tmp_path, config={})  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"TrainOptions: unknown option 'steps'"):
        TrainOptions(run_dir=tmp_path, steps=3)


def test_a_bad_option_is_one_line_before_anything_is_written(tmp_path: Path) -> None:
    run = tmp_path / "bad"
    result = CliRunner().invoke(main, ["train", "--run-dir", str(run), "--learning-rate", "-1"])
    assert result.exit_code == 2, result.output
    assert result.output == "Error: train.learning_rate must be > 0, got -1.0\n"
    assert not run.exists()


def test_the_progress_bar_opens_with_the_first_steps(monkeypatch: pytest.MonkeyPatch) -> None:
    """Nothing of the bar is shown before training reports its first steps: an error of
    the set-up (a bad checkpoint, a missing extra) is the only line."""
    import contextlib
    import importlib

    cli_train = importlib.import_module("srfm.cli.train")  # the module, not the command

    opened: list[int] = []
    updates: list[int] = []

    @contextlib.contextmanager
    def fake_bar(*, length: int, **options: Any) -> Any:
        opened.append(length)
        yield type("Bar", (), {"update": lambda self, n: updates.append(n)})()

    monkeypatch.setattr(cli_train, "progressbar", fake_bar)
    with cli_train._TrainingBar(300) as bar:
        assert opened == []
        bar.advance(100)
        bar.advance(100)
        bar.advance(250)
    assert opened == [300]
    assert updates == [100, 150]
