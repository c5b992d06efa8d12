"""Episode metrics (the exact Fréchet deviation, social-navigation metrics, statistics).

Empty until the metrics issue lands; :class:`srfm.EpisodeRecord` already carries the
arrays they are computed from.
"""

__all__: list[str] = []
