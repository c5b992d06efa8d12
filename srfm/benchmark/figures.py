"""Benchmark figures (matplotlib, PNG): top-down paths and the deviation chart."""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import atomic_write_bytes, write_file_set
from srfm.benchmark._request import BenchmarkRequest
from srfm.metrics import BenchmarkTable
from srfm.metrics.suite import SuiteStats
from srfm.sim.episode import build_planner, run_episode
from srfm.sim.record import EpisodeRecord

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from srfm.models.state import Obstacles
    from srfm.scenarios import Scenario

__all__ = [
    "PROFILES",
    "FigureEpisode",
    "deviation_figure",
    "figure_episode_path",
    "load_figure_episode",
    "metric_bars_figure",
    "paths_figure",
    "paths_figure_name",
    "profiles_figure",
    "render_figures",
    "render_paths_figure",
    "save_figure_episode",
    "write_figures",
]

_DPI = 110

FloatArray = NDArray[np.float64]


def _png(fig: Figure) -> bytes:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=_DPI, metadata={"Software": None})
    return buf.getvalue()


@attrs.frozen(kw_only=True, eq=False)
class FigureEpisode:
    """What a path figure needs of an episode (a record's arrays, without the rest)."""

    scenario: str
    seed: int
    planner: str
    outcome: str
    end_step: int
    factual_pos: FloatArray
    counterfactual_pos: FloatArray
    robot_pose: FloatArray
    robot_goal: FloatArray

    @property
    def n_pedestrians(self) -> int:
        """N."""
        return int(self.factual_pos.shape[1])


def figure_episode_path(out: Path, scenario: str, planner: str) -> Path:
    """Where a worker leaves the trajectories of the figure seed's episode."""
    return out / "figures" / "episodes" / scenario / f"{planner}.npz"


_SAVED_ARRAYS = ("factual_pos", "counterfactual_pos", "robot_pose", "robot_goal")


def _figure_episode(record: EpisodeRecord) -> FigureEpisode:
    return FigureEpisode(
        scenario=record.scenario,
        seed=record.seed,
        planner=record.planner,
        outcome=record.outcome,
        end_step=record.end_step,
        **{name: getattr(record, name) for name in _SAVED_ARRAYS},
    )


def save_figure_episode(out: Path, record: EpisodeRecord) -> None:
    """Keep what the path figure needs of ``record`` (called in the worker that ran it,
    so that drawing the figures does not simulate anything again)."""
    episode = _figure_episode(record)
    buf = io.BytesIO()
    np.savez(
        buf,
        seed=episode.seed,
        end_step=episode.end_step,
        outcome=episode.outcome,
        **{name: getattr(episode, name) for name in _SAVED_ARRAYS},
    )
    atomic_write_bytes(figure_episode_path(out, record.scenario, record.planner), buf.getvalue())


def load_figure_episode(out: Path, scenario: str, planner: str, seed: int) -> FigureEpisode | None:
    """The saved figure episode of (scenario, planner), or None if absent, of another
    seed, or damaged (then the figure's episode is simulated again: same figure)."""
    path = figure_episode_path(out, scenario, planner)
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if int(data["seed"]) != seed:
                return None
            episode = FigureEpisode(
                scenario=scenario,
                seed=seed,
                planner=planner,
                outcome=str(data["outcome"]),
                end_step=int(data["end_step"]),
                **{name: np.array(data[name], dtype=np.float64) for name in _SAVED_ARRAYS},
            )
    except Exception:  # any damage (zip, zlib, format, missing key): simulate again
        return None
    n_steps = episode.robot_pose.shape[0]
    shapes_ok = (
        episode.factual_pos.ndim == 3
        and episode.factual_pos.shape == episode.counterfactual_pos.shape
        and episode.factual_pos.shape[0] == n_steps
        and episode.factual_pos.shape[2] == 2
        and episode.robot_pose.shape == (n_steps, 3)
        and episode.robot_goal.shape == (2,)
        and 0 <= episode.end_step < n_steps
    )
    return episode if shapes_ok else None


def _draw_episode(
    ax: Axes, record: FigureEpisode, world: Sequence[float], obstacles: Obstacles | None
) -> None:
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Circle

    x0, x1, y0, y1 = world
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], color="0.6", lw=0.8)
    if obstacles is not None and obstacles.segments.shape[0] > 0:
        walls = list(obstacles.segments.reshape(-1, 2, 2))
        ax.add_collection(
            LineCollection(walls, colors="0.25", linewidths=2.0, capstyle="butt"), autolim=False
        )
    if obstacles is not None:
        for cx, cy, r in obstacles.circles:
            ax.add_patch(Circle((cx, cy), r, color="0.25"))
    n = record.n_pedestrians
    colors = colormaps["tab10"](np.arange(n) % 10)
    # one collection per kind of path (each pedestrian its colour): a Line2D per path
    # costs more to build than the whole figure's drawing
    counterfactual = list(np.moveaxis(record.counterfactual_pos, 1, 0))
    factual = list(np.moveaxis(record.factual_pos, 1, 0))
    ax.add_collection(
        LineCollection(counterfactual, colors=colors, linewidths=0.9, linestyles="--", alpha=0.6),
        autolim=False,
    )
    ax.add_collection(LineCollection(factual, colors=colors, linewidths=1.2), autolim=False)
    starts = record.factual_pos[0]
    ax.scatter(starts[:, 0], starts[:, 1], s=16, c=colors, marker="o", linewidths=0)
    robot = record.robot_pose[: record.end_step + 1, :2]
    ax.plot(robot[:, 0], robot[:, 1], color="black", lw=2.0)
    ax.plot(robot[0, 0], robot[0, 1], "s", color="black", ms=5)
    ax.plot(record.robot_goal[0], record.robot_goal[1], "*", color="black", ms=9)
    ax.set_title(f"{record.planner}: {record.outcome.replace('_', ' ')}", fontsize=9, y=1.0)


# A path figure's fixed layout, in inches (matplotlib's constrained layout measured every
# tick label twice and was most of a figure's CPU time): the y tick labels on the left of
# the figure, a gap between columns, below each panel its x tick labels (kept only where
# no panel is below: the panels share their axes) and above it its title; the figure's
# title has a band at the top.
_PANEL_WIDTH = 3.2
_LEFT, _RIGHT, _GAP = 0.42, 0.1, 0.16
_PANEL_BOTTOM, _PANEL_TOP, _SUPTITLE = 0.26, 0.24, 0.26


def paths_figure(
    records: Sequence[FigureEpisode],
    world: Sequence[float],
    obstacles: Obstacles | None = None,
) -> Figure:
    """One panel per planner: walls and pillars (dark grey), factual paths (solid),
    counterfactual paths (dashed, same colour per pedestrian), the robot path (black,
    square start, star goal). A panel's height follows the world's aspect ratio; the
    panels share their axes (the same world), labelled on the outer panels."""
    from matplotlib.figure import Figure

    n = len(records)
    cols = min(n, 4)
    rows = -(-n // cols)
    x0, x1, y0, y1 = world
    aspect = (y1 - y0 + 1.0) / (x1 - x0 + 1.0)  # the axes' limits add 0.5 m per side
    height = min(3.3, max(1.2, 3.0 * aspect + 0.5))
    width, total = _PANEL_WIDTH * cols, height * rows
    panel = (width - _LEFT - _RIGHT - (cols - 1) * _GAP) / cols
    cell = (total - _SUPTITLE) / rows
    fig = Figure(figsize=(width, total))
    first: Axes | None = None
    for k, record in enumerate(records):
        row, col = divmod(k, cols)
        rect = (
            (_LEFT + col * (panel + _GAP)) / width,
            (total - _SUPTITLE - (row + 1) * cell + _PANEL_BOTTOM) / total,
            panel / width,
            (cell - _PANEL_BOTTOM - _PANEL_TOP) / total,
        )
        ax = fig.add_axes(rect, sharex=first, sharey=first)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7, labelleft=col == 0, labelbottom=k + cols >= n)
        if first is None:
            first = ax
            ax.set_xlim(x0 - 0.5, x1 + 0.5)
            ax.set_ylim(y0 - 0.5, y1 + 0.5)
        _draw_episode(ax, record, world, obstacles)
    fig.suptitle(
        f"{records[0].scenario}, seed {records[0].seed}: factual (solid) vs counterfactual"
        " (dashed)",
        fontsize=10,
        y=1.0 - 0.06 / total,
        va="top",
    )
    return fig


def deviation_figure(table: BenchmarkTable) -> Figure:
    """Grouped bars: mean Fréchet deviation per scenario and planner, ± sample std."""
    return metric_bars_figure(
        table,
        "frechet_m",
        "Fréchet deviation (m)",
        "Pedestrian deviation caused by the robot (mean ± std over seeds)",
    )


# A bar chart's margins, in inches: the y label and tick labels on the left, the x tick
# labels below the axes and a legend row per eight planners below them, the title above.
_BARS_LEFT, _BARS_RIGHT, _BARS_TOP, _BARS_TICKS = 0.72, 0.12, 0.3, 0.3
_BARS_LEGEND_ROW, _BARS_LEGEND_COLUMNS = 0.3, 8


def metric_bars_figure(table: BenchmarkTable, metric: str, ylabel: str, title: str) -> Figure:
    """Grouped bars: the mean of ``metric`` per scenario and planner, ± sample std."""
    from matplotlib.figure import Figure

    n = len(table.planners)
    width, height = max(6.0, 1.2 + 1.6 * len(table.scenarios)), 4.0
    bottom = _BARS_TICKS + _BARS_LEGEND_ROW * -(-n // _BARS_LEGEND_COLUMNS)  # the legend below
    fig = Figure(figsize=(width, height))  # a fixed layout, in inches (as the path figures')
    ax = fig.add_axes(
        (
            _BARS_LEFT / width,
            bottom / height,
            1.0 - (_BARS_LEFT + _BARS_RIGHT) / width,
            1.0 - (bottom + _BARS_TOP) / height,
        )
    )
    width = 0.8 / n
    x = np.arange(len(table.scenarios))
    for k, planner in enumerate(table.planners):
        cells = [table.cells[(s, planner)][metric].summary for s in table.scenarios]
        means = [c.mean for c in cells]
        stds = [0.0 if np.isnan(c.std) else c.std for c in cells]
        ax.bar(x - 0.4 + width * (k + 0.5), means, width, yerr=stds, capsize=2, label=planner)
    ax.set_xticks(x, list(table.scenarios), fontsize=8)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    fig.legend(
        fontsize=8,
        ncols=min(n, _BARS_LEGEND_COLUMNS),  # 7 planners: one row
        loc="lower center",
        bbox_to_anchor=(0.5, 0.02 / height),
    )
    return fig


PROFILES: Final = "figures/profiles.png"
"""The performance profiles figure of a run."""


def profiles_figure(stats: SuiteStats) -> Figure:
    """Performance profiles: per planner, the share of its episodes (every scenario and
    seed) whose Fréchet deviation is at most τ, against τ (log scale)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.0))
    ax = fig.add_axes((0.11, 0.13, 0.6, 0.78))
    for planner in stats.planners:
        ax.step(stats.taus, stats.profiles[planner], where="post", label=planner)
    if stats.taus.size and stats.taus[0] > 0.0:
        ax.set_xscale("log")
    ax.set_ylim(0.0, 1.02)
    ax.set_xlabel("τ: Fréchet deviation of an episode (m)")
    ax.set_ylabel("share of episodes with deviation ≤ τ")
    ax.set_title("Performance profiles (higher and further left: gentler)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    fig.legend(fontsize=8, loc="center right", bbox_to_anchor=(0.99, 0.5))
    return fig


def write_figures(
    out: Path,
    request: BenchmarkRequest,
    table: BenchmarkTable,
    extended: BenchmarkTable | None = None,
) -> list[str]:
    """Draw ``figures/paths_<scenario>.png`` (one seed, every planner),
    ``figures/deviation.png`` and, given the extended table, ``figures/social_work.png``
    as a whole; return their paths relative to ``out``."""
    files = render_figures(out, request, table, extended)
    write_file_set(out, files)
    return list(files)


def paths_figure_name(scenario: str) -> str:
    """The path of a scenario's path figure, relative to the results folder."""
    return f"figures/paths_{scenario}.png"


def render_paths_figure(out: Path, request: BenchmarkRequest, scenario: Scenario) -> bytes:
    """The PNG bytes of ``scenario``'s path figure: the drawn seed's episode of every
    planner, as the workers saved it (simulated again where it is missing)."""
    seed = request.drawn_seed
    records = []
    for p in request.planners:
        saved = load_figure_episode(out, scenario.name, p, seed)
        if saved is None:  # a folder from before figures were kept: simulate again
            record = run_episode(scenario, seed, build_planner(p), request.params, parallel=False)
            saved = _figure_episode(record)
        records.append(saved)
    w = scenario.world
    return _png(paths_figure(records, (w.x_min, w.x_max, w.y_min, w.y_max), scenario.obstacles))


def render_figures(
    out: Path,
    request: BenchmarkRequest,
    table: BenchmarkTable,
    extended: BenchmarkTable | None = None,
    *,
    drawn: Mapping[str, bytes] | None = None,
    suite: SuiteStats | None = None,
) -> dict[str, bytes]:
    """The PNG bytes of every figure by path relative to ``out`` (nothing written);
    with ``suite``, the performance profiles too (:data:`PROFILES`).

    ``drawn``: path figures already rendered (:func:`render_paths_figure`, by
    :func:`paths_figure_name`), e.g. while the other episodes ran; the rest are drawn
    here. The same bytes either way."""
    drawn = drawn or {}
    written: dict[str, bytes] = {}
    for scenario in request.scenarios:
        name = paths_figure_name(scenario.name)
        png = drawn.get(name)
        written[name] = render_paths_figure(out, request, scenario) if png is None else png
    written["figures/deviation.png"] = _png(deviation_figure(table))
    if extended is not None:
        written["figures/social_work.png"] = _png(
            metric_bars_figure(
                extended,
                "social_work_m2ps2",
                "social work (m²/s²)",
                "Robot force integrated along each pedestrian's path (mean ± std over seeds)",
            )
        )
    if suite is not None and suite.taus.size:
        written[PROFILES] = _png(profiles_figure(suite))
    return written
