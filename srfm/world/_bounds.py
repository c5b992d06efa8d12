"""The world rectangle: where the robot may drive, and what routers are bounded by."""

from __future__ import annotations

import attrs

__all__ = ["WorldBounds"]


@attrs.frozen(kw_only=True)
class WorldBounds:
    """Axis-aligned world rectangle (m)."""

    x_min: float = 0.0
    x_max: float = 15.0
    y_min: float = 0.0
    y_max: float = 15.0

    def contains(self, x: float, y: float) -> bool:
        """True when (x, y) lies inside the rectangle (edges included)."""
        return self.x_min <= x <= self.x_max and self.y_min <= y <= self.y_max

    def grown(self, margin_m: float) -> WorldBounds:
        """The rectangle grown by ``margin_m`` on every side: the world's edge is no
        wall for pedestrians, so their routers use the world grown by their radius."""
        return WorldBounds(
            x_min=self.x_min - margin_m,
            x_max=self.x_max + margin_m,
            y_min=self.y_min - margin_m,
            y_max=self.y_max + margin_m,
        )
