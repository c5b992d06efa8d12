"""Ctrl-C exits 130 with the ``interrupted`` message in every phase of a run: also after
the simulation (the reports, the printing of the results; it ended in click's
``Aborted!`` and exit 1) and while Python shuts down after the work (the process died
by the signal, status -2, with nothing printed). A Ctrl-C in the middle of the
simulation: ``tests/benchmark/test_runner.py::test_interrupted_run_resumes_to_the_same_tables``."""

from __future__ import annotations

import importlib
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import click
import pytest

from tests.conftest import REPO
from tests.reliability.conftest import cli


def _interrupt(*args: object, **kwargs: object) -> None:
    raise KeyboardInterrupt


def _module(name: str) -> object:
    """A command's module (``srfm.cli.benchmark`` as an attribute is the command)."""
    return importlib.import_module(f"srfm.cli.{name}")


def test_ctrl_c_after_the_simulation_exits_130_and_keeps_the_episodes(
    tiny: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The benchmark's last step (the line on its logs), after the reports."""
    monkeypatch.setattr(_module("benchmark"), "_logs_line", _interrupt)
    out = tmp_path / "out"
    res = cli("benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-2", "--out", str(out))
    assert res.exit_code == 130, res.output
    assert res.output.splitlines()[-1] == (
        f"interrupted: 3 finished episodes are kept in {out}; run the same command again to resume"
    )
    assert "Aborted" not in res.output


def test_ctrl_c_in_any_command_exits_130(tiny: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_module("simulate"), "format_summary", _interrupt)
    res = cli("simulate", "--scenario", str(tiny))
    assert res.exit_code == 130, res.output
    assert res.output.splitlines()[-1] == "interrupted"


def test_ctrl_c_after_a_sweep_exits_130(
    tiny: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'schema_version = 1\nscenarios = ["{tiny}"]\nplanners = ["straight"]\nseeds = "0-1"\n'
        '[design]\nkind = "grid"\n[design.factors]\na_robot = [1.0]\n',
        encoding="utf-8",
    )
    echo = click.echo

    def last_line_interrupted(message: object = None, *args: object, **kwargs: object) -> None:
        if str(message).startswith("simulated "):  # the sweep's last line
            raise KeyboardInterrupt
        echo(message, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(click, "echo", last_line_interrupted)
    res = cli("sweep", str(spec), "--out", str(tmp_path / "out"))
    assert res.exit_code == 130, res.output
    assert "interrupted: finished partitions are kept in" in res.output


def test_ctrl_c_while_python_shuts_down_is_ignored(tiny: Path, tmp_path: Path) -> None:
    """A SIGINT that arrives after the command's work, while the interpreter shuts down
    (its signal handlers already gone): an object deleted at shutdown sends it."""
    script = textwrap.dedent(
        f"""
        import os, signal, sys

        class Late:
            def __del__(self):
                os.kill(os.getpid(), signal.SIGINT)

        late = Late()
        from srfm.cli import main
        sys.argv = ["srfm", "benchmark", "-s", {str(tiny)!r}, "-p", "straight",
                    "--seeds", "0-1", "--out", {str(tmp_path / "out")!r}, "-j", "1",
                    "--no-logs", "--no-figures"]
        main()
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": str(REPO)},
        # as a terminal starts it: SIGINT at its default disposition (a shell starts
        # background jobs with it ignored, which would hide the difference)
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert proc.returncode == 0, (proc.returncode, proc.stderr)
    assert "simulated 2 of 2 episodes" in proc.stderr
