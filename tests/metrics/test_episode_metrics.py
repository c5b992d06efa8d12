"""Episode metrics against their definitions, computed independently from the record."""

from __future__ import annotations

import math

import numpy as np
import pytest

from srfm import SRFMParams, run_episode
from srfm.metrics import (
    EPISODE_METRICS,
    METRIC_GROUPS,
    PEDESTRIAN_METRICS,
    MetricInfo,
    episode_metrics,
    frechet_distance,
)


@pytest.fixture(scope="module")
def crosswalk():  # type: ignore[no-untyped-def]
    record = run_episode("crosswalk", 1)
    return record, episode_metrics(record)


def test_every_defined_metric_is_computed(crosswalk) -> None:  # type: ignore[no-untyped-def]
    record, m = crosswalk
    assert set(m.values) == {x.name for x in EPISODE_METRICS}
    assert set(m.pedestrians) == {x.name for x in PEDESTRIAN_METRICS}
    for arr in m.pedestrians.values():
        assert arr.shape == (record.n_pedestrians,)
    for info in (*EPISODE_METRICS, *PEDESTRIAN_METRICS):
        assert info.unit
        assert info.definition


def test_deviation_definitions(crosswalk) -> None:  # type: ignore[no-untyped-def]
    record, m = crosswalk
    for i in range(record.n_pedestrians):
        f = record.factual_pos[:, i]
        c = record.counterfactual_pos[:, i]
        gap = np.hypot(*(f - c).T)
        assert m.pedestrians["frechet_m"][i] == frechet_distance(f, c)
        assert m.pedestrians["mean_separation_m"][i] == pytest.approx(gap.mean(), rel=1e-12)
        assert m.pedestrians["max_separation_m"][i] == pytest.approx(gap.max(), rel=1e-12)
        assert m.pedestrians["frechet_m"][i] <= m.pedestrians["max_separation_m"][i]
    assert m["frechet_m"] == pytest.approx(m.pedestrians["frechet_m"].mean())
    assert m["frechet_m"] > 0.1  # the robot does push people in this scenario


def test_robot_distance_is_over_the_robot_episode_only(crosswalk) -> None:  # type: ignore[no-untyped-def]
    record, m = crosswalk
    end = record.end_step
    assert end < record.horizon_steps
    best = math.inf
    for k in range(end + 1):
        for i in range(record.n_pedestrians):
            d = math.dist(record.factual_pos[k, i], record.robot_pose[k, :2])
            best = min(best, d)
    assert m["min_robot_distance_m"] == pytest.approx(best, rel=1e-12)
    clearance = best - record.robot_radius - record.ped_radius.max()
    assert m["min_robot_clearance_m"] == pytest.approx(clearance, rel=1e-12)


def test_lengths_times_and_robot_side(crosswalk) -> None:  # type: ignore[no-untyped-def]
    record, m = crosswalk
    f_len = np.linalg.norm(np.diff(record.factual_pos, axis=0), axis=2).sum(axis=0)
    c_len = np.linalg.norm(np.diff(record.counterfactual_pos, axis=0), axis=2).sum(axis=0)
    np.testing.assert_allclose(m.pedestrians["path_length_m"], f_len, rtol=1e-12)
    np.testing.assert_allclose(m.pedestrians["extra_length_m"], f_len - c_len, rtol=1e-9)
    for i in range(record.n_pedestrians):
        radius = 0.5
        gap = np.hypot(*(record.factual_pos[:, i] - record.factual_goal[:, i]).T)
        hits = np.flatnonzero(gap < radius)
        expected = record.time_s[hits[0]] if hits.size else math.nan
        got = m.pedestrians["time_to_goal_s"][i]
        assert (math.isnan(got) and math.isnan(expected)) or got == pytest.approx(expected)
    assert m.outcome == record.outcome == "goal_reached"
    assert m["robot_success"] == 1.0
    assert m["robot_collision"] == m["robot_timeout"] == m["robot_out_of_bounds"] == 0.0
    assert m["robot_time_to_goal_s"] == pytest.approx(record.end_step * record.dt_s)
    assert m["robot_path_length_m"] == pytest.approx(record.robot_path_length_m())
    assert 0.3 < m["robot_mean_speed_mps"] <= 0.5 + 1e-9


def test_no_robot_force_means_exactly_zero_deviation() -> None:
    record = run_episode("circle", 4, params=SRFMParams(a_robot=0.0))
    m = episode_metrics(record)
    for name in ("frechet_m", "mean_separation_m", "max_separation_m", "extra_length_m"):
        assert m[name] == 0.0
        assert not m.pedestrians[name].any()


def test_timeout_has_no_robot_time() -> None:
    from srfm.planners import make_planner

    class Stay:
        name = "stay"
        detection_range_m = 0.0

        def reset(self, context, rng):  # type: ignore[no-untyped-def]
            pass

        def act(self, observation):  # type: ignore[no-untyped-def]
            return np.zeros(2)

    assert make_planner("straight")  # registry intact
    m = episode_metrics(run_episode("concert", 0, Stay()))  # type: ignore[arg-type]
    assert m.outcome == "timeout"
    assert m["robot_timeout"] == 1.0
    assert math.isnan(m["robot_time_to_goal_s"])
    assert m["robot_path_length_m"] == 0.0


def test_same_record_same_numbers() -> None:
    a = episode_metrics(run_episode("footpath", 2))
    b = episode_metrics(run_episode("footpath", 2))
    assert a.values == b.values
    for name in a.pedestrians:
        np.testing.assert_array_equal(a.pedestrians[name], b.pedestrians[name])


def _doc_rows(text: str) -> list[list[str]]:
    """The rows of the metric tables of docs/metrics.md (those starting with a `name`)."""
    rows = []
    for line in text.splitlines():
        if line.startswith("| `"):
            cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
            if len(cells) == 5:
                rows.append(cells)
    return rows


def _code_rows(infos: tuple[MetricInfo, ...]) -> list[list[str]]:
    return [[f"`{m.name}`", m.unit, m.better or "–", m.definition, m.source] for m in infos]


def test_docs_list_exactly_the_metrics_of_the_registry() -> None:
    from tests.conftest import REPO

    text = (REPO / "docs" / "metrics.md").read_text(encoding="utf-8")
    per_pedestrian = text[text.index("## Per pedestrian") : text.index("## Per episode")]
    per_episode = text[text.index("## Per episode") : text.index("## Thresholds")]
    assert _doc_rows(per_pedestrian) == _code_rows(PEDESTRIAN_METRICS)
    grouped = tuple(m for g in METRIC_GROUPS for m in EPISODE_METRICS if m.group == g)
    assert _doc_rows(per_episode) == _code_rows(grouped)
    assert len(grouped) == len(EPISODE_METRICS)  # every episode metric has a group


def test_the_doc_check_can_fail() -> None:
    from tests.conftest import REPO

    text = (REPO / "docs" / "metrics.md").read_text(encoding="utf-8")
    edited = text.replace("| `delay_s` | s | lower |", "| `delay_s` | s | higher |", 1)
    assert _doc_rows(edited) != _doc_rows(text)
