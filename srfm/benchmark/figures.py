"""Benchmark figures (matplotlib, PNG): top-down paths and the deviation chart."""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import atomic_write_bytes, write_file_set
from srfm.benchmark._request import BenchmarkRequest
from srfm.metrics import BenchmarkTable
from srfm.sim.episode import build_planner, run_episode
from srfm.sim.record import EpisodeRecord

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from srfm.models.state import Obstacles
    from srfm.scenarios import Scenario

__all__ = [
    "FigureEpisode",
    "deviation_figure",
    "figure_episode_path",
    "load_figure_episode",
    "metric_bars_figure",
    "paths_figure",
    "paths_figure_name",
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
    from matplotlib.patches import Circle

    x0, x1, y0, y1 = world
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], color="0.6", lw=0.8)
    if obstacles is not None:
        for sx0, sy0, sx1, sy1 in obstacles.segments:
            ax.plot([sx0, sx1], [sy0, sy1], color="0.25", lw=2.0, solid_capstyle="butt")
        for cx, cy, r in obstacles.circles:
            ax.add_patch(Circle((cx, cy), r, color="0.25"))
    colors = colormaps["tab10"](np.arange(record.n_pedestrians) % 10)
    for i in range(record.n_pedestrians):
        c = record.counterfactual_pos[:, i]
        f = record.factual_pos[:, i]
        ax.plot(c[:, 0], c[:, 1], ls="--", lw=0.9, color=colors[i], alpha=0.6)
        ax.plot(f[:, 0], f[:, 1], lw=1.2, color=colors[i])
        ax.plot(f[0, 0], f[0, 1], "o", ms=3, color=colors[i])
    robot = record.robot_pose[: record.end_step + 1, :2]
    ax.plot(robot[:, 0], robot[:, 1], color="black", lw=2.0)
    ax.plot(robot[0, 0], robot[0, 1], "s", color="black", ms=5)
    ax.plot(record.robot_goal[0], record.robot_goal[1], "*", color="black", ms=9)
    ax.set_aspect("equal")
    ax.set_xlim(x0 - 0.5, x1 + 0.5)
    ax.set_ylim(y0 - 0.5, y1 + 0.5)
    ax.set_title(f"{record.planner}: {record.outcome.replace('_', ' ')}", fontsize=9)
    ax.tick_params(labelsize=7)


def paths_figure(
    records: Sequence[FigureEpisode],
    world: Sequence[float],
    obstacles: Obstacles | None = None,
) -> Figure:
    """One panel per planner: walls and pillars (dark grey), factual paths (solid),
    counterfactual paths (dashed, same colour per pedestrian), the robot path (black,
    square start, star goal). A panel's height follows the world's aspect ratio."""
    from matplotlib.figure import Figure

    cols = min(len(records), 4)
    rows = -(-len(records) // cols)
    x0, x1, y0, y1 = world
    aspect = (y1 - y0 + 1.0) / (x1 - x0 + 1.0)  # the axes' limits add 0.5 m per side
    height = min(3.3, max(1.2, 3.0 * aspect + 0.5))
    fig = Figure(figsize=(3.2 * cols, height * rows), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax, record in zip(axes.flat, records, strict=False):
        _draw_episode(ax, record, world, obstacles)
    for ax in list(axes.flat)[len(records) :]:
        ax.set_axis_off()
    first = records[0]
    fig.suptitle(
        f"{first.scenario}, seed {first.seed}: factual (solid) vs counterfactual (dashed)",
        fontsize=10,
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


def metric_bars_figure(table: BenchmarkTable, metric: str, ylabel: str, title: str) -> Figure:
    """Grouped bars: the mean of ``metric`` per scenario and planner, ± sample std."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(max(6.0, 1.2 + 1.6 * len(table.scenarios)), 4.0), layout="constrained")
    ax = fig.subplots()
    n = len(table.planners)
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
    fig.legend(fontsize=8, ncols=min(n, 8), loc="outside lower center")  # 7 planners: one row
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
) -> dict[str, bytes]:
    """The PNG bytes of every figure by path relative to ``out`` (nothing written).

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
    return written
