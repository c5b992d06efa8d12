"""Every way an external planner process can fail ends only its own episode, with the
outcome planner_failed and one line naming the planner and what it did; the next episode
starts a new process. Real processes throughout (raw_planner.py)."""

from __future__ import annotations

import re
import uuid
import warnings

import numpy as np
import pytest

import srfm
from srfm.errors import PlannerError, PlannerFailureWarning
from srfm.metrics import episode_metrics
from srfm.planners.external import define_external
from tests.conftest import record_digest
from tests.external.conftest import raw_command

SCENARIO = "crosswalk"
STEP = 7


def _define(mode: str, **timeouts: float) -> str:
    return define_external(f"raw-{uuid.uuid4().hex[:8]}", raw_command(mode), **timeouts)


@pytest.fixture(scope="module")
def straight_records() -> dict[int, srfm.EpisodeRecord]:
    return {seed: srfm.run_episode(SCENARIO, seed, "straight") for seed in (0, 1)}


FAILURES = {
    "crash": r"crashed: its process exited with status 3",
    "segv": r"crashed: its process was killed by signal SIGSEGV",
    "hang": r"did not answer within its timeout \(0\.5 s per step\)",
    "garbage": r"answered garbage: sent 5 bytes that are not MessagePack",
    "length": r"answered garbage: announced a message of 4294967295 bytes",
    "wrongtype": r"answered garbage: expected a 'command' message, got type 'ready'",
    "nan": r"answered a non-finite command \[nan, 0\.0\]",
    "fast": r"answered the command \[5\.0, 0\.0\], outside the robot's limits "
    r"\(\|v\| <= 0\.5 m/s and \|omega\| <= 3\.14159\d* rad/s\)",
    "strings": r"answered a command that is not two numbers: \['a', 'b'\]",
    "error": r"reported an error: the map server is down",
    "close": r"closed its connection \(end of file\) but kept running",
}


@pytest.mark.parametrize("mode", sorted(FAILURES))
def test_a_failure_ends_only_its_episode(
    mode: str, straight_records: dict[int, srfm.EpisodeRecord]
) -> None:
    name = _define(f"{mode}@{STEP}", step_timeout_s=0.5)
    with pytest.warns(PlannerFailureWarning) as caught:
        failed = srfm.run_episode(SCENARIO, 0, name)
    (warning,) = caught
    line = str(warning.message)
    assert "\n" not in line
    assert line.startswith(f"planner {name!r} (")
    assert f"at step {STEP} (scenario {SCENARIO}, seed 0)" in line
    assert line.endswith("its episode ends with the outcome planner_failed")
    assert re.search(FAILURES[mode], line), line
    # The episode: the straight planner's up to the failure, then the robot at rest.
    reference = straight_records[0]
    assert failed.outcome == "planner_failed"
    assert failed.end_step == STEP
    assert failed.robot_active[:STEP].all()
    assert not failed.robot_active[STEP:].any()
    np.testing.assert_array_equal(failed.robot_pose[: STEP + 1], reference.robot_pose[: STEP + 1])
    np.testing.assert_array_equal(failed.factual_pos[: STEP + 1], reference.factual_pos[: STEP + 1])
    assert (failed.robot_pose[STEP:] == failed.robot_pose[STEP]).all()
    assert np.isnan(failed.robot_cmd[STEP:]).all()
    # Both twins go on to the horizon; the counterfactual one never saw the robot.
    np.testing.assert_array_equal(failed.counterfactual_pos, reference.counterfactual_pos)
    metrics = episode_metrics(failed)
    assert metrics.outcome == "planner_failed"
    # The next episode starts a new process and runs as the built-in planner does.
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlannerFailureWarning)
        after = srfm.run_episode(SCENARIO, 1, name)
    assert record_digest(after) == record_digest(straight_records[1])


def test_a_failed_reset_ends_the_episode_at_its_first_step(
    straight_records: dict[int, srfm.EpisodeRecord],
) -> None:
    name = _define("resetcrash")
    with pytest.warns(
        PlannerFailureWarning, match=r"crashed: its process exited with status 5 at reset"
    ):
        failed = srfm.run_episode(SCENARIO, 0, name)
    assert failed.outcome == "planner_failed"
    assert failed.end_step == 0
    assert not failed.robot_active.any()
    assert (failed.robot_pose == failed.robot_pose[0]).all()
    assert record_digest(srfm.run_episode(SCENARIO, 1, name)) == record_digest(straight_records[1])


@pytest.mark.parametrize(
    ("command", "match"),
    [
        (raw_command("version"), r"speaks protocol version 99, srfm speaks version 1"),
        (raw_command("noconnect"), r"exited with status 4 before connecting to srfm"),
        (["/nonexistent/planner-program"], r"cannot start '/nonexistent/planner-program'"),
    ],
    ids=["version", "noconnect", "missing"],
)
def test_a_planner_that_cannot_start_is_refused(command: list[str], match: str) -> None:
    name = define_external(f"bad-{uuid.uuid4().hex[:8]}", command)
    with pytest.raises(PlannerError, match=match):
        srfm.run_episode(SCENARIO, 0, name)


def test_nothing_listening_at_an_address_is_refused(tmp_path: object) -> None:
    name = define_external("nobody", address=f"unix:{tmp_path}/nothing.sock", start_timeout_s=1.0)
    with pytest.raises(PlannerError, match=r"cannot connect to unix:.*nothing\.sock"):
        srfm.run_episode(SCENARIO, 0, name)


def test_an_undefined_external_planner_says_how_to_define_it() -> None:
    with pytest.raises(
        PlannerError,
        match=r"'external:undefined' is not defined: give --external undefined=COMMAND",
    ):
        srfm.run_episode(SCENARIO, 0, "external:undefined")
