"""The benchmark's path figures draw the scenario's walls and pillars and follow the
world's shape."""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection

import srfm
from srfm.benchmark.figures import _figure_episode, paths_figure
from srfm.scenarios import load_scenario


def _world(scenario: srfm.Scenario) -> tuple[float, float, float, float]:
    w = scenario.world
    return (w.x_min, w.x_max, w.y_min, w.y_max)


def test_walls_and_pillars_are_drawn_in_every_panel(tmp_path) -> None:  # type: ignore[no-untyped-def]
    scenario = load_scenario("narrow_doorway")
    records = [_figure_episode(srfm.run_episode(scenario, 0, p)) for p in ("straight", "dwa")]
    fig = paths_figure(records, _world(scenario), scenario.obstacles)
    segments = scenario.obstacles.segments
    assert segments.shape[0] > 0
    assert len(fig.axes) == len(records)
    for ax in fig.axes:
        drawn = {
            tuple(np.round(np.ravel(segment), 9))
            for collection in ax.collections
            if isinstance(collection, LineCollection)
            for segment in collection.get_segments()
            if len(segment) == 2
        }
        for x0, y0, x1, y1 in segments:
            assert (round(x0, 9), round(y0, 9), round(x1, 9), round(y1, 9)) in drawn
    without = paths_figure(records, _world(scenario))
    assert sum(len(ax.collections) for ax in without.axes) < sum(
        len(ax.collections) for ax in fig.axes
    )
    concourse = load_scenario("station_concourse")  # 8 pillars
    record = _figure_episode(srfm.run_episode(concourse, 0, "straight"))
    fig = paths_figure([record], _world(concourse), concourse.obstacles)
    assert len(fig.axes[0].patches) == concourse.obstacles.circles.shape[0] == 8


def test_a_long_world_gets_flat_panels() -> None:
    flow = load_scenario("corridor_flow")
    square = load_scenario("crosswalk")
    flat = paths_figure([_figure_episode(srfm.run_episode(flow, 0, "straight"))], _world(flow))
    tall = paths_figure([_figure_episode(srfm.run_episode(square, 0, "straight"))], _world(square))
    assert flat.get_size_inches()[1] < 0.5 * tall.get_size_inches()[1]
    assert tall.get_size_inches()[1] == 3.3  # the paper's scenarios keep their panels
