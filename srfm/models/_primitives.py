"""Force primitives shared by the SRFM crowd kernels and the social-force planner.

Small ``inline="always"`` numba functions over floats, so that every caller compiles
the same floating-point operations in the same order (results stay bit for bit what
they were when each caller carried its own copy):

- :func:`desired_velocity`: the velocity an agent wants, (g − x) capped at its desired
  speed v0 (the goal force is (v_des − v) / τ, paper Eq. 3);
- :func:`capped_exp`: the exponential of a repulsion, its argument capped at
  ``EXP_ARG_MAX`` (e^60 ≈ 1e26, far beyond any force that changes a step, so extreme but
  valid inputs give huge finite forces instead of inf and NaN);
- :func:`anisotropy`: ψ(φ; λ) = λ + (1 − λ)(1 + cos φ)/2 (SRFM paper Eq. 5);
- :func:`closest_on_segment`: the point of a wall segment closest to a position;
- :func:`disc_repulsion`: the anisotropic exponential push of a disc (a pedestrian, the
  robot) on an agent, A exp((r_i + r_j − d) / B) ψ n (paper Eq. 4 with Eq. 5).

``ZERO``, ``TRUE`` and ``FALSE`` are 0, True and False as plain numba types, for
constant arguments of kernel-to-kernel calls and counters started at 0: numba types
a bare constant such as ``0`` or ``True`` as a literal and compiles the callee once per
literal value, sometimes once more for the literal it sees before the loop's counter
is typed as ``int64`` (seconds of compilation on a first run for the crowd step and
ORCA's linear programs); a global NumPy scalar is typed as ``int64`` / ``bool``.

``EPS`` is the explicit epsilon below which a distance or length counts as zero (no
``fastmath``; the direction of a zero vector is undefined).

numba's on-disk cache of a kernel is keyed on the kernel's own file: after a change
here, clear the cache (the ``*.nbi``/``*.nbc`` files in ``__pycache__``) so that the
kernels inlining these functions are compiled again.
"""

from __future__ import annotations

import math
from typing import Final, cast

import numpy as np
from numba import njit

__all__ = [
    "EPS",
    "EXP_ARG_MAX",
    "FALSE",
    "TRUE",
    "ZERO",
    "anisotropy",
    "capped_exp",
    "closest_on_segment",
    "desired_velocity",
    "disc_repulsion",
]

EPS = 1e-12
EXP_ARG_MAX = 60.0
ZERO: Final = cast(int, np.int64(0))
TRUE: Final = cast(bool, np.bool_(True))
FALSE: Final = cast(bool, np.bool_(False))


@njit(cache=True, inline="always")
def desired_velocity(x: float, y: float, gx: float, gy: float, v0: float) -> tuple[float, float]:
    """(g − x) capped at the desired speed v0: walk at v0, slow down within v0·1 s of the goal.

    Computed as ``(dx * s, dy * s)`` with ``s = v0 / |g − x|`` when |g − x| > v0 (the same
    as ``dx *= v0 / dist; dy *= v0 / dist``), else (dx, dy) unchanged.

    Args:
        x: x of the agent (m).
        y: y of the agent (m).
        gx: x of its goal (m).
        gy: y of its goal (m).
        v0: desired speed (m/s).

    Returns:
        (vx, vy), the desired velocity (m/s).
    """
    dx = gx - x
    dy = gy - y
    dist = math.sqrt(dx * dx + dy * dy)
    if dist > v0:
        scale = v0 / dist
        return dx * scale, dy * scale
    return dx, dy


@njit(cache=True, inline="always")
def capped_exp(arg: float) -> float:
    """exp(min(arg, EXP_ARG_MAX)).

    Args:
        arg: the exponent (dimensionless), e.g. (r_i + r_j − d_ij) / B.

    Returns:
        e^arg, with arg capped at ``EXP_ARG_MAX``.
    """
    return math.exp(min(arg, EXP_ARG_MAX))


@njit(cache=True, inline="always")
def anisotropy(hx: float, hy: float, has_heading: bool, ux: float, uy: float, lam: float) -> float:
    """ψ(φ; λ) = λ + (1 − λ)(1 + cos φ)/2 (paper Eq. 5).

    Computed as ``lam + (1.0 - lam) * (1.0 + cos_phi) * 0.5`` with
    ``cos_phi = hx * ux + hy * uy``. A caller holding the unit vector n from the source
    to the agent passes (ux, uy) = (−nx, −ny); this equals bit for bit the form
    ``(1.0 - (hx * nx + hy * ny))`` (negation is exact and rounding is symmetric).

    Args:
        hx: x of the agent's unit heading e.
        hy: y of the agent's unit heading e.
        has_heading: False when the agent has no heading (at rest, no desired
            direction); then ψ = 1 (isotropic).
        ux: x of the unit vector u from the agent to the force's source.
        uy: y of the unit vector u.
        lam: λ in [0, 1]; 1 is isotropic, 0 ignores a source straight behind.

    Returns:
        ψ in [λ, 1] (dimensionless), φ the angle between e and u.
    """
    if not has_heading:
        return 1.0
    cos_phi = hx * ux + hy * uy
    return lam + (1.0 - lam) * (1.0 + cos_phi) * 0.5


@njit(cache=True, inline="always")
def closest_on_segment(
    x: float, y: float, x1: float, y1: float, x2: float, y2: float
) -> tuple[float, float]:
    """The point of segment (x1, y1)–(x2, y2) closest to (x, y).

    With s = (x2 − x1, y2 − y1): t = clip(((x, y) − (x1, y1)) · s / |s|², 0, 1), the point
    (x1, y1) + t s; a segment shorter than √EPS counts as its first end (t = 0).

    Args:
        x: x of the position (m).
        y: y of the position (m).
        x1: x of the segment's first end (m).
        y1: y of the segment's first end (m).
        x2: x of the segment's second end (m).
        y2: y of the segment's second end (m).

    Returns:
        (cx, cy), the closest point (m).
    """
    sx = x2 - x1
    sy = y2 - y1
    len2 = sx * sx + sy * sy
    t = 0.0
    if len2 > EPS:
        t = min(1.0, max(0.0, ((x - x1) * sx + (y - y1) * sy) / len2))
    return x1 + t * sx, y1 + t * sy


@njit(cache=True, inline="always")
def disc_repulsion(
    x: float,
    y: float,
    sx: float,
    sy: float,
    r_sum: float,
    a: float,
    b: float,
    hx: float,
    hy: float,
    has_heading: bool,
    lam: float,
) -> tuple[float, float]:
    """The push A exp((r_sum − d) / B) ψ(φ; λ) n of a disc centred at (sx, sy) on (x, y).

    n is the unit vector from the source to the agent, d their centre distance, φ the
    angle between the agent's heading and −n (:func:`anisotropy`). A source closer than
    ``EPS`` exerts no force (the direction is undefined): (0.0, 0.0), which added to a
    running sum started at +0.0 leaves it bit for bit as skipping the source would.

    Args:
        x: x of the agent (m).
        y: y of the agent (m).
        sx: x of the source's centre (m).
        sy: y of the source's centre (m).
        r_sum: r_i + r_j, the sum of the two radii (m).
        a: A, the strength (m/s²).
        b: B, the range (m).
        hx: x of the agent's unit heading.
        hy: y of the agent's unit heading.
        has_heading: False for an agent without heading (then ψ = 1).
        lam: λ, the anisotropy in [0, 1].

    Returns:
        (fx, fy), the acceleration (m/s²) on the agent.
    """
    dx = x - sx
    dy = y - sy
    d = math.sqrt(dx * dx + dy * dy)
    if d < EPS:
        return 0.0, 0.0
    nx = dx / d
    ny = dy / d
    psi = anisotropy(hx, hy, has_heading, -nx, -ny, lam)
    mag = a * capped_exp((r_sum - d) / b) * psi
    return mag * nx, mag * ny
