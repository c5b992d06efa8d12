"""The benchmark: scenarios × planners × seeds into a results folder of tables and figures."""

from srfm.benchmark._draws import (
    SENSITIVITY_RANGES,
    WIDE_RANGES,
    ParamDraws,
    RankTable,
    draw_params,
    rank_probabilities,
    rank_table,
)
from srfm.benchmark._html import REPORT, render_report, write_report
from srfm.benchmark._models import ResponseModels, Robustness, robustness
from srfm.benchmark._request import (
    MANIFEST,
    MAX_SEEDS,
    QUICK_SEEDS,
    BenchmarkRequest,
    default_planners,
)
from srfm.benchmark._results import episode_path, read_episode
from srfm.benchmark._runner import (
    BenchmarkSummary,
    EpisodeWriter,
    load_results,
    run_benchmark,
    write_reports,
)
from srfm.metrics.report import write_tables

__all__ = [
    "MANIFEST",
    "MAX_SEEDS",
    "QUICK_SEEDS",
    "REPORT",
    "SENSITIVITY_RANGES",
    "WIDE_RANGES",
    "BenchmarkRequest",
    "BenchmarkSummary",
    "EpisodeWriter",
    "ParamDraws",
    "RankTable",
    "ResponseModels",
    "Robustness",
    "default_planners",
    "draw_params",
    "episode_path",
    "load_results",
    "rank_probabilities",
    "rank_table",
    "read_episode",
    "render_report",
    "robustness",
    "run_benchmark",
    "write_report",
    "write_reports",
    "write_tables",
]
