"""The canonical trajectory representation: sorting, invariants, errors."""

from __future__ import annotations

import numpy as np
import pytest

from srfm.datasets import PEDESTRIAN, ROBOT, Trajectories
from srfm.errors import DatasetError


def make(**changes: object) -> Trajectories:
    args: dict[str, object] = {
        "scene": "s",
        "agent_ids": ["a", "b", "robot"],
        "kinds": [PEDESTRIAN, PEDESTRIAN, ROBOT],
        "agent": [1, 0, 2, 0, 2],
        "frame": [5, 5, 5, 6, 6],
        "t_ns": [500, 500, 500, 600, 600],
        "xy": [[1.0, 1.0], [0.0, 0.0], [5.0, 5.0], [0.1, 0.0], [5.0, 4.9]],
    }
    args.update(changes)
    return Trajectories.from_samples(**args)  # type: ignore[arg-type]


def test_from_samples_sorts_by_frame_then_agent() -> None:
    t = make()
    assert t.agent.tolist() == [0, 1, 2, 0, 2]
    assert t.frame.tolist() == [5, 5, 5, 6, 6]
    assert t.xy[1].tolist() == [1.0, 1.0]
    assert t.robot_index == 2
    frames, times = t.frames()
    assert frames.tolist() == [5, 6]
    assert times.tolist() == [500, 600]
    f, ts, xy = t.track("a")
    assert ts.tolist() == [500, 600]
    assert f.tolist() == [5, 6]
    assert xy.tolist() == [[0.0, 0.0], [0.1, 0.0]]


def test_arrays_are_read_only() -> None:
    t = make()
    with pytest.raises(ValueError, match="read-only"):
        t.xy[0, 0] = 3.0


def test_summary_counts_and_speed() -> None:
    s = make().summary()
    assert (s["pedestrians"], s["robot"], s["frames"], s["samples"]) == (2, True, 2, 5)
    assert s["duration_s"] == pytest.approx(1e-7)
    # Pedestrian "a" moves 0.1 m in 100 ns: 1e6 m/s; "b" has a single sample.
    assert s["median_speed_mps"] == pytest.approx(1e6)


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"agent": [0, 0, 2, 0, 2]}, "agent 'a' appears twice in frame 5"),
        ({"kinds": [PEDESTRIAN, ROBOT, ROBOT]}, "at most one robot"),
        ({"kinds": [PEDESTRIAN, "cyclist", ROBOT]}, "kind 'cyclist'"),
        ({"agent_ids": ["a", "a", "robot"]}, "duplicate agent id 'a'"),
        ({"t_ns": [500, 500, 500, 400, 400]}, "timestamps go backwards"),
        ({"t_ns": [500, 501, 500, 600, 600]}, "frame 5 has two timestamps"),
        ({"t_ns": [-5, -5, -5, 600, 600]}, "negative timestamp"),
        ({"xy": [[1.0, np.nan], [0, 0], [5, 5], [0.1, 0], [5, 4.9]]}, "non-finite position"),
        ({"agent": [1, 0, 3, 0, 2]}, "agent index out of range"),
        ({"frame": [5.0, 5, 5, 6, 6]}, "frame must be a 1-D integer array"),
        ({"frame_of_reference": "map"}, "frame_of_reference must be one of"),
        ({"scene": ""}, "scene name must be a non-empty string"),
    ],
)
def test_invariants_raise_dataset_errors(changes: dict[str, object], match: str) -> None:
    with pytest.raises(DatasetError, match=match):
        make(**changes)


def test_constructor_rejects_unsorted_samples() -> None:
    t = make()
    with pytest.raises(DatasetError, match="not sorted"):
        Trajectories(
            scene="s",
            agent_ids=t.agent_ids,
            kinds=t.kinds,
            agent=t.agent[::-1].copy(),
            frame=t.frame[::-1].copy(),
            t_ns=t.t_ns[::-1].copy(),
            xy=t.xy[::-1].copy(),
        )


def test_dataset_error_is_a_value_error() -> None:
    with pytest.raises(ValueError, match="at most one robot"):
        make(kinds=[ROBOT, ROBOT, ROBOT])
