"""The protocol's schema is the one definition of its messages: the docs' table is
generated from it, srfm's messages follow it, and bad definitions are refused with a
message naming the bad value."""

from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np
import pytest

import srfm
from srfm.errors import PlannerError
from srfm.planners import Observation, PlannerContext, StraightPlanner
from srfm.planners.external import (
    PROTOCOL_VERSION,
    SCHEMA_FILE,
    define_external,
    external_definition,
    field_table,
)
from srfm.planners.external._planner import (
    limit_problem,
    observe_message,
    parse_external_option,
    reset_message,
)
from srfm.planners.external._schema import message_problem, message_spec, messages
from srfm.planners.external._wire import parse_address
from tests.conftest import REPO

DOC = REPO / "docs" / "planners-any-language.md"
BEGIN = "<!-- protocol-table: generated from srfm/planners/external/protocol.toml -->"
END = "<!-- end protocol-table -->"


def test_the_docs_table_is_the_schema() -> None:
    text = DOC.read_text(encoding="utf-8")
    table = text.split(BEGIN, 1)[1].split(END, 1)[0]
    assert table.strip() == field_table().strip(), (
        "docs/planners-any-language.md is out of date: paste srfm.planners.external.field_table()"
    )
    assert f"version {PROTOCOL_VERSION}" in text


def test_the_schema_is_consistent() -> None:
    assert SCHEMA_FILE.name == "protocol.toml"
    types = {(m.type, m.sender) for m in messages()}
    for m in messages():
        assert m.sender in ("srfm", "planner")
        if m.answer:
            assert (m.answer, "planner") in types
        assert len({f.name for f in m.fields}) == len(m.fields)


class _Recorder(StraightPlanner):
    """The straight planner, keeping what srfm would send an external planner."""

    def __init__(self) -> None:
        super().__init__()
        self.sent: list[dict[str, Any]] = []

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.sent.append(reset_message(context))
        super().reset(context, rng)

    def act(self, observation: Observation) -> Any:
        self.sent.append(observe_message(observation))
        return super().act(observation)


@pytest.mark.parametrize("scenario", ["crosswalk", "narrow_doorway"])
def test_srfm_sends_what_the_schema_says(scenario: str) -> None:
    planner = _Recorder()
    planner.detection_range_m = None
    srfm.run_episode(scenario, 0, planner)
    reset, *steps = planner.sent
    assert message_problem(reset, message_spec("reset", "srfm")) is None
    assert set(reset) == {"type"} | {f.name for f in message_spec("reset", "srfm").fields}
    spec = message_spec("observe", "srfm")
    for message in steps:
        assert message_problem(message, spec) is None
        assert set(message) == {"type"} | {f.name for f in spec.fields}
    assert len(steps[0]["ped_ids"]) > 0
    if scenario == "narrow_doorway":
        assert len(reset["walls"]) > 0


@pytest.mark.parametrize(
    ("message", "problem"),
    [
        ([1, 2], "expected a map, got list"),
        ({"type": "ready"}, "expected a 'command' message, got type 'ready'"),
        ({"type": "command"}, "'command' message without 'command'"),
        ({"type": "command", "command": [1.0]}, "'command' must be a list of 2, got [1.0]"),
        ({"type": "command", "command": "ab"}, "'command' must be a list, got 'ab'"),
        ({"type": "command", "command": [1.0, math.inf]}, "a list of finite numbers"),
        ({"type": "command", "command": [True, 0.0]}, "a list of finite numbers"),
    ],
)
def test_message_problems_name_the_field(message: Any, problem: str) -> None:
    found = message_problem(message, message_spec("command", "planner"))
    assert found is not None
    assert problem in found


def test_hello_needs_a_number_or_nil_range() -> None:
    spec = message_spec("hello", "planner")
    assert (
        message_problem({"type": "hello", "protocol": 1, "detection_range_m": None}, spec) is None
    )
    found = message_problem({"type": "hello", "protocol": 1, "detection_range_m": "far"}, spec)
    assert found == "'hello' message: 'detection_range_m' must be a finite number, got 'far'"


def test_limits_per_kinematics() -> None:
    record_context = PlannerContext(
        scenario="s",
        seed=0,
        dt_s=0.1,
        horizon_steps=10,
        robot=srfm.RobotConfig(max_speed_mps=0.5, max_angular_speed_radps=1.0),
        robot_goal=np.zeros(2),
        world=srfm.load_scenario("crosswalk").world,
        obstacles=srfm.Obstacles(),
    )
    assert limit_problem(0.5, -1.0, record_context) is None
    assert limit_problem(-0.5, 1.0, record_context) is None
    assert limit_problem(0.5000001, 0.0, record_context) is not None
    assert limit_problem(0.0, 1.01, record_context) is not None
    import attrs

    holo = attrs.evolve(
        record_context,
        robot=srfm.RobotConfig(kinematics="holonomic", max_speed_mps=0.5),
    )
    assert limit_problem(0.3, 0.4, holo) is None
    assert limit_problem(0.4, 0.4, holo) == "the speed |(vx, vy)| <= 0.5 m/s"


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (("a b", "x"), {}, r"planner 'external:a b': an external planner's NAME must be"),
        (("ok",), {}, r"give either a command or an address"),
        (("ok", "x"), {"address": "unix:/tmp/x"}, r"give either a command or an address"),
        (("ok", ""), {}, r"the command is empty"),
        (("ok", "'unclosed"), {}, r"command \"'unclosed\": No closing quotation"),
        (("ok",), {"address": "udp:1"}, r"address 'udp:1' is neither unix:PATH nor tcp:HOST:PORT"),
        (("ok", "x"), {"step_timeout_s": 0}, r"the step timeout must be a number of seconds"),
        (("ok", "x"), {"step_timeout_s": math.nan}, r"got nan"),
    ],
)
def test_bad_definitions_are_refused(
    args: tuple[Any, ...], kwargs: dict[str, Any], match: str
) -> None:
    with pytest.raises(PlannerError, match=match):
        define_external(*args, **kwargs)


def test_a_definition_reaches_other_processes_through_the_environment() -> None:
    import subprocess

    label = define_external("envtest", "prog --flag 'two words'", step_timeout_s=0.25)
    assert label == "external:envtest"
    code = (
        "from srfm.planners.external import external_definition as d;"
        "e = d('external:envtest'); print(e.command, e.step_timeout_s)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "('prog', '--flag', 'two words') 0.25"
    assert external_definition("envtest").source == "prog --flag 'two words'"


def test_command_line_option_parsing() -> None:
    assert parse_external_option("cpp=./build/planner --fast") == ("cpp", "./build/planner --fast")
    assert parse_external_option("x=tcp:127.0.0.1:5555") == ("x", "tcp:127.0.0.1:5555")
    for bad in ("cpp", "=prog", "cpp="):
        with pytest.raises(PlannerError, match=r"--external must be NAME=COMMAND"):
            parse_external_option(bad)
    assert parse_address("tcp:localhost:80")[1] == ("localhost", 80)
    with pytest.raises(ValueError, match="tcp:host:99999"):
        parse_address("tcp:host:99999")
