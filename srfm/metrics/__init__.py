"""Metrics: the exact Fréchet deviation, episode metrics, statistics and tables.

Definitions of every metric: :data:`EPISODE_METRICS`, :data:`PEDESTRIAN_METRICS` and
``docs/metrics.md``.
"""

from srfm.metrics.episode import (
    EPISODE_METRICS,
    METRIC_GROUPS,
    PEDESTRIAN_METRICS,
    EpisodeMetrics,
    MetricInfo,
    MetricParams,
    episode_metrics,
)
from srfm.metrics.frechet import frechet_distance, frechet_distances
from srfm.metrics.stats import (
    ALPHA,
    CORRECTIONS,
    Comparison,
    Summary,
    adjust_p_values,
    compare,
    summarize,
)
from srfm.metrics.tables import (
    EXTENDED_COLUMNS,
    OUTCOME_COLUMNS,
    TABLE_COLUMNS,
    BenchmarkTable,
    Cell,
    base_metric,
    benchmark_table,
    given_success,
    legend,
    min_n_for_best,
    summary_dict,
    to_latex,
    to_latex_extended,
    to_markdown,
    to_markdown_extended,
)

__all__ = [
    "ALPHA",
    "CORRECTIONS",
    "EPISODE_METRICS",
    "EXTENDED_COLUMNS",
    "METRIC_GROUPS",
    "OUTCOME_COLUMNS",
    "PEDESTRIAN_METRICS",
    "TABLE_COLUMNS",
    "BenchmarkTable",
    "Cell",
    "Comparison",
    "EpisodeMetrics",
    "MetricInfo",
    "MetricParams",
    "Summary",
    "adjust_p_values",
    "base_metric",
    "benchmark_table",
    "compare",
    "episode_metrics",
    "frechet_distance",
    "frechet_distances",
    "given_success",
    "legend",
    "min_n_for_best",
    "summarize",
    "summary_dict",
    "to_latex",
    "to_latex_extended",
    "to_markdown",
    "to_markdown_extended",
]
