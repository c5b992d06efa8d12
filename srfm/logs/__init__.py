"""Run logs: Rerun recordings (.rrd), MCAP files, and re-scoring from MCAP alone.

The sinks work on a finished :class:`~srfm.sim.record.EpisodeRecord`, so the simulator
knows nothing of them and pays nothing when logging is off:

- :func:`write_rrd`: a Rerun recording with its own ``RecordingStream`` (never the
  global one) and a default blueprint; entity tree in :mod:`srfm.logs._rerun` and
  ``docs/logging.md``.
- :func:`write_episode_mcap`: an MCAP file written with the ``mcap`` library: versioned
  JSON-schema channels (exact arrays as NumPy ``.npy`` files) plus Foxglove scene
  messages built with the Foxglove SDK (``foxglove.SceneUpdate``, protobuf);
  :func:`load_episode` rebuilds the episode from it bit for bit, and refuses files of
  another log schema version naming it and the srfm that wrote them.
- :func:`score_logs` / :func:`write_score_reports`: every metric and the benchmark
  tables from MCAP files alone (``srfm score``).
- :class:`EpisodeLogger`: the benchmark's per-episode writer; :class:`LogOptions` says
  what to write, :func:`write_episode_logs` writes one episode's logs into a results
  folder (``OUT/logs/<scenario>/<planner>/seed-NNNNNN.{mcap,rrd}``).
"""

from srfm.logs._mcap import (
    PROFILES,
    LogFile,
    LoggedEpisode,
    Profile,
    load_episode,
    read_log,
    write_counterfactual_mcap,
    write_episode_mcap,
)
from srfm.logs._rerun import write_rrd
from srfm.logs._schemas import CHANNELS, SCHEMA_VERSION
from srfm.logs._writer import (
    LOGS_DIR,
    EpisodeLogger,
    LogOptions,
    counterfactual_log_path,
    episode_log_path,
    write_episode_logs,
)
from srfm.logs.score import (
    ScoredEpisode,
    ScoreResult,
    find_logs,
    metrics_identical,
    score_logs,
    write_score_reports,
)

__all__ = [
    "CHANNELS",
    "LOGS_DIR",
    "PROFILES",
    "SCHEMA_VERSION",
    "EpisodeLogger",
    "LogFile",
    "LogOptions",
    "LoggedEpisode",
    "Profile",
    "ScoreResult",
    "ScoredEpisode",
    "counterfactual_log_path",
    "episode_log_path",
    "find_logs",
    "load_episode",
    "metrics_identical",
    "read_log",
    "score_logs",
    "write_counterfactual_mcap",
    "write_episode_logs",
    "write_episode_mcap",
    "write_rrd",
    "write_score_reports",
]
