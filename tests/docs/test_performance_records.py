"""The records behind docs/performance.md's generated tables carry the run that wrote
them (tools/results/record.py): a hand-made or hand-edited file is refused."""

from __future__ import annotations

import copy
import json

import pytest

from tools.results import performance_pages as perf


@pytest.mark.parametrize("name", sorted(perf.COMMANDS))
def test_a_committed_record_is_what_its_command_wrote(name: str) -> None:
    doc = perf.record(name)  # checks it (check_record)
    run = doc["run"]
    assert run["command"] == perf.COMMANDS[name]
    assert run["command"].endswith(f"--json docs/results/performance/{name}")
    assert run["started"] < run["finished"]
    assert doc["machine"]["cores"] >= 1


def test_a_record_without_its_run_is_refused() -> None:
    name = "episodes.json"
    doc = json.loads((perf.FOLDER / name).read_text(encoding="utf-8"))
    perf.check_record(name, doc)
    bare = {k: v for k, v in doc.items() if k != "run"}
    with pytest.raises(perf.RecordError, match=r"episodes.json: no run record"):
        perf.check_record(name, bare)
    for key, value, message in (
        ("command", "python tools/bench/bench_episode.py", "not by the page's"),
        ("commit", "abc1234-dirty", "not a clean"),
        ("wall_s", 0.0, "wall 0.0 s"),
    ):
        edited = copy.deepcopy(doc)
        edited["run"][key] = value
        with pytest.raises(perf.RecordError, match=message):
            perf.check_record(name, edited)
    edited = copy.deepcopy(doc)
    del edited["run"]["machine"]
    with pytest.raises(perf.RecordError, match=r"lacks \['machine'\]"):
        perf.check_record(name, edited)
    with pytest.raises(perf.RecordError, match="no machine record"):
        perf.check_record(name, {k: v for k, v in doc.items() if k != "machine"})
