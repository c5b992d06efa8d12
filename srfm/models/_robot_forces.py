"""The robot's force on a pedestrian, in each of its forms (numba kernels).

The one definition of the robot term f_robot(i) of the SRFM force (docs/model.md, "The
robot's force: five forms"): the crowd step, the fitting predictor and the
environment's one-step deviation all reach it through :func:`robot_force`, which picks
the form the parameter set names (``SRFMKernelParams.robot_form``, a ``FORM_*`` code):

- ``FORM_EXPONENTIAL``, the paper's force (Agrawal, Dengler, Bennewitz 2024):
  A_r exp((r_i + r_r − d) / B_r) ψ(φ; λ_r) n, :func:`~srfm.models._primitives.disc_repulsion`;
- ``FORM_TTC``, the anticipatory time-to-collision force (Karamouzas, Skinner, Guy 2014,
  PRL 113, 238701): :func:`ttc_force`;
- ``FORM_COLLISION_PREDICTION``, the collision-prediction social force (Zanlungo, Ikeda,
  Kanda 2011, EPL 93, 68005): :func:`collision_prediction_force`;
- ``FORM_ELLIPTICAL``, the velocity-dependent elliptical force (Johansson, Helbing,
  Shukla 2007, Adv. Complex Syst. 10, 271): :func:`elliptical_force`;
- ``FORM_SIDESTEP``, srfm's sideways response to a predicted near miss, with the onset,
  amplitude, horizon and robot-speed dependence that NavWareSet's encounters show
  (docs/real_encounters.md, issue 40): :func:`sidestep_force`.

Each form is zero when its strength is zero (the twin guarantee: a crowd that feels a
robot of zero strength moves bit for bit as its blind twin). The anticipatory forms
read both velocities: the pedestrian's (the crowd's state) and the robot's
(``robot[3:5]``). Their singularities (a time to collision or of closest approach near
0, a grazing course, a degenerate ellipse) are bounded by ``robot_force_cap``: a force
longer than the cap is scaled down to it, so that every input within the parameter and
state bounds gives a finite force, never inf or NaN. Like every kernel here: no
``fastmath``; zero lengths use the explicit epsilon ``EPS``; no division by a number
that can be zero.

Shapes: ``robot`` (5,) = (x, y, radius, vx, vy), m and m/s. Forces are accelerations
(m/s², unit mass).

numba's on-disk cache of a kernel is keyed on the kernel's own file: after a change
here, clear the cache (``*.nbi``/``*.nbc`` in ``__pycache__``) so that the kernels
inlining these functions are compiled again.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numba import njit

from srfm.models._primitives import EPS, anisotropy, capped_exp, disc_repulsion
from srfm.models.params import SRFMKernelParams

__all__ = [
    "FORM_COLLISION_PREDICTION",
    "FORM_ELLIPTICAL",
    "FORM_EXPONENTIAL",
    "FORM_SIDESTEP",
    "FORM_TTC",
    "SIDESTEP_REF_SPEED_MPS",
    "TTC_MIN_TAU_S",
    "collision_prediction_force",
    "elliptical_force",
    "robot_force",
    "robot_strength",
    "sidestep_force",
    "ttc_force",
]

# The forms' codes in SRFMKernelParams.robot_form (the order of srfm.models.params.ROBOT_FORMS).
FORM_EXPONENTIAL: Final = 0
FORM_TTC: Final = 1
FORM_COLLISION_PREDICTION: Final = 2
FORM_ELLIPTICAL: Final = 3
FORM_SIDESTEP: Final = 4

SIDESTEP_REF_SPEED_MPS: Final = 1.0
"""The robot speed at which the sidestep force's amplitude is ``ss_a`` (m/s)."""

TTC_MIN_TAU_S: Final = 1e-6
"""Floor of the time to collision τ (s) in the TTC force: keeps τ⁻³ finite (the cap
binds long before: k τ⁻³ at τ = 1e-6 s is 1e18 k)."""


@njit(cache=True, inline="always")
def _capped(fx: float, fy: float, cap: float) -> tuple[float, float]:
    """(fx, fy) scaled down to length ``cap`` when longer (the direction kept)."""
    f = math.sqrt(fx * fx + fy * fy)
    if f > cap:
        s = cap / f
        return fx * s, fy * s
    return fx, fy


@njit(cache=True, inline="always")
def ttc_force(
    x: float,
    y: float,
    vx: float,
    vy: float,
    sx: float,
    sy: float,
    svx: float,
    svy: float,
    r_sum: float,
    k: float,
    tau0: float,
    cap: float,
) -> tuple[float, float]:
    """The time-to-collision force on an agent (Karamouzas, Skinner, Guy 2014).

    The interaction energy is a power law of the predicted time to collision τ with an
    exponential cut-off, E(τ) = k τ⁻² exp(−τ/τ0), and the force is its negative
    gradient in the relative position p = x_i − x_s (relative velocity w = v_i − v_s,
    r = r_sum): τ is the smaller root of |p + w τ| = r,

        τ = c / (−b + √D),  b = p·w, c = |p|² − r², D = b² − |w|² c,

    and f = −dE/dτ ∇_p τ = k e^(−τ/τ0) τ⁻² (2/τ + 1/τ0) (p + w τ) / √D (the paper's
    force, written with ∇_p τ = (p + w τ)/√D; p + w τ, of length r, points from the
    source to the agent at contact).

    Settled cases: no force when the two do not close in (b ≥ 0), when no collision lies
    ahead (D ≤ EPS, a miss or a graze) or when their relative speed is below √EPS; two
    discs already overlapping (c < 0) push apart at the cap along p (no force when the
    centres coincide); τ is floored at ``TTC_MIN_TAU_S``; the force is capped at
    ``cap``.

    Args:
        x, y: the agent's position (m).
        vx, vy: the agent's velocity (m/s).
        sx, sy: the source's position (m).
        svx, svy: the source's velocity (m/s).
        r_sum: r_i + r_s, the sum of the radii (m).
        k: k, the strength (m², per unit mass).
        tau0: τ0, the cut-off time (s), > 0.
        cap: the largest force (m/s²), > 0.

    Returns:
        (fx, fy), the acceleration (m/s²) on the agent.
    """
    px = x - sx
    py = y - sy
    wx = vx - svx
    wy = vy - svy
    c = px * px + py * py - r_sum * r_sum
    if c < 0.0:
        d = math.sqrt(px * px + py * py)
        if d < EPS:
            return 0.0, 0.0
        return cap * px / d, cap * py / d
    b = px * wx + py * wy
    a = wx * wx + wy * wy
    if b >= 0.0 or a < EPS:
        return 0.0, 0.0
    disc = b * b - a * c
    if disc <= EPS:
        return 0.0, 0.0
    root = math.sqrt(disc)
    tau = max(c / (root - b), TTC_MIN_TAU_S)
    mag = k * math.exp(-tau / tau0) / (tau * tau) * (2.0 / tau + 1.0 / tau0) / root
    return _capped(mag * (px + wx * tau), mag * (py + wy * tau), cap)


@njit(cache=True, inline="always")
def collision_prediction_force(
    x: float,
    y: float,
    vx: float,
    vy: float,
    sx: float,
    sy: float,
    svx: float,
    svy: float,
    r_sum: float,
    a: float,
    b: float,
    t_min: float,
    t_max: float,
    cap: float,
) -> tuple[float, float]:
    """The collision-prediction force on an agent (Zanlungo, Ikeda, Kanda 2011).

    The agent predicts, from both current velocities, the time of closest approach
    t_ca = −(p·w)/|w|² (p = x_i − x_s, w = v_i − v_s), and feels a circular exponential
    force of the situation then: with t* = min(t_ca, t_max), the predicted relative
    position p' = p + w t* and d' = |p'| − r_sum,

        f = A (|v_i| / max(t*, t_min)) exp(−d' / B) p'/|p'|,

    |v_i| / t* being the deceleration that would stop the agent before the closest
    approach. Settled cases: no force when the two do not close in (p·w ≥ 0, which
    includes a source at rest beside a pedestrian at rest) or when their relative speed
    is below √EPS; on an exact collision course (|p'| < EPS) the force points along p,
    and not at all when the centres coincide; the force is capped at ``cap``.

    Args:
        x, y: the agent's position (m).
        vx, vy: the agent's velocity (m/s).
        sx, sy: the source's position (m).
        svx, svy: the source's velocity (m/s).
        r_sum: r_i + r_s (m).
        a: A, the strength (dimensionless).
        b: B, the range (m), > 0.
        t_min: the shortest time in the 1/t factor (s), > 0.
        t_max: the longest prediction time (s), >= t_min.
        cap: the largest force (m/s²), > 0.

    Returns:
        (fx, fy), the acceleration (m/s²) on the agent.
    """
    px = x - sx
    py = y - sy
    wx = vx - svx
    wy = vy - svy
    s = px * wx + py * wy
    w2 = wx * wx + wy * wy
    if s >= 0.0 or w2 < EPS:
        return 0.0, 0.0
    t = min(-s / w2, t_max)
    qx = px + wx * t
    qy = py + wy * t
    q = math.sqrt(qx * qx + qy * qy)
    if q < EPS:
        q = math.sqrt(px * px + py * py)
        if q < EPS:
            return 0.0, 0.0
        qx = px
        qy = py
        dist = -r_sum  # the predicted distance of a collision course is 0
    else:
        dist = q - r_sum
    speed = math.sqrt(vx * vx + vy * vy)
    mag = a * speed / max(t, t_min) * capped_exp(-dist / b) / q
    return _capped(mag * qx, mag * qy, cap)


@njit(cache=True, inline="always")
def elliptical_force(
    x: float,
    y: float,
    vx: float,
    vy: float,
    sx: float,
    sy: float,
    svx: float,
    svy: float,
    r_sum: float,
    a: float,
    b: float,
    dt: float,
    hx: float,
    hy: float,
    has_heading: bool,
    lam: float,
    cap: float,
) -> tuple[float, float]:
    """The elliptical, velocity-dependent force on an agent (Johansson, Helbing, Shukla
    2007, "elliptical specification II").

    With p = x_i − x_s and the source's displacement relative to the agent within Δt,
    y = (v_s − v_i) Δt, the potential A B exp((r_sum − β)/B) depends on the semi-minor
    axis β of the ellipse through the agent with foci at the source now and after Δt:

        2β = √((|p| + |p − y|)² − |y|²),
        f = A exp((r_sum − β)/B) ψ(φ; λ) (|p| + |p − y|) / (2β) · (p̂ + (p − y)^) / 2

    (the potential's negative gradient in p, times the anisotropy ψ of the paper's
    force). At equal velocities (y = 0) β = |p| and f is the paper's exponential force.
    The radius sum r_sum in the exponent, as in the paper's force, scales A only.
    Settled cases: coincident centres give no force; (p − y)^ is taken as 0 when
    |p − y| < EPS; β is floored at EPS; the force is capped at ``cap``.

    Args:
        x, y: the agent's position (m).
        vx, vy: the agent's velocity (m/s).
        sx, sy: the source's position (m).
        svx, svy: the source's velocity (m/s).
        r_sum: r_i + r_s (m).
        a: A, the strength (m/s²).
        b: B, the range (m), > 0.
        dt: Δt, the prediction time (s), >= 0.
        hx, hy: the agent's unit heading.
        has_heading: False for an agent without heading (ψ = 1).
        lam: λ, the anisotropy in [0, 1].
        cap: the largest force (m/s²), > 0.

    Returns:
        (fx, fy), the acceleration (m/s²) on the agent.
    """
    px = x - sx
    py = y - sy
    d = math.sqrt(px * px + py * py)
    if d < EPS:
        return 0.0, 0.0
    nx = px / d
    ny = py / d
    yx = (svx - vx) * dt
    yy = (svy - vy) * dt
    ex = px - yx
    ey = py - yy
    e = math.sqrt(ex * ex + ey * ey)
    if e < EPS:
        ux = 0.0
        uy = 0.0
    else:
        ux = ex / e
        uy = ey / e
    span = d + e
    beta = 0.5 * math.sqrt(max(span * span - (yx * yx + yy * yy), 0.0))
    beta = max(beta, EPS)
    psi = anisotropy(hx, hy, has_heading, -nx, -ny, lam)
    mag = a * capped_exp((r_sum - beta) / b) * psi * span / (2.0 * beta) * 0.5
    return _capped(mag * (nx + ux), mag * (ny + uy), cap)


@njit(cache=True, inline="always")
def sidestep_force(
    x: float,
    y: float,
    vx: float,
    vy: float,
    sx: float,
    sy: float,
    svx: float,
    svy: float,
    hx: float,
    hy: float,
    has_heading: bool,
    amplitude: float,
    onset: float,
    horizon: float,
    speed_gain: float,
    cap: float,
) -> tuple[float, float]:
    """The sidestep force on an agent: a sideways step away from the predicted side of
    a near miss (srfm, issue 40; docs/model.md).

    Both moving at constant velocity (p = x_i − x_s, w = v_i − v_s), the closest
    approach is at t* = −(p·w)/|w|², at the predicted miss vector m = p + w t* (from the
    source to the agent), of length d* (centre distance). The agent reacts only while
    the two close in (p·w < 0), the closest approach lies within the horizon
    (t* < T) and the predicted miss is below the onset (d* < d_on):

        |f| = A (1 − d*/d_on) (1 − t*/T) exp(γ (|v_s| − v_ref)),

    v_ref = :data:`SIDESTEP_REF_SPEED_MPS`: the amplitude A is the force at a predicted
    collision course, now, of a source at v_ref; γ (s/m) is the dependence on the
    source's speed (0: none; the exponent capped as everywhere). The direction is
    sideways to the agent's heading h, n = h turned by +90°, toward the side of m:
    +n when m·n > 0, −n when m·n < 0, and −n (to the right) on an exact collision
    course (m·n = 0). An agent without heading steps along m (along p when m = 0).
    No force when the centres coincide (|p| < EPS) or the relative speed is below
    √EPS. The force is capped at ``cap``; the step ends when the source has passed
    (p·w ≥ 0).

    Args:
        x, y: the agent's position (m).
        vx, vy: the agent's velocity (m/s).
        sx, sy: the source's position (m).
        svx, svy: the source's velocity (m/s).
        hx, hy: the agent's unit heading.
        has_heading: False for an agent without heading.
        amplitude: A (m/s²), >= 0.
        onset: d_on, the predicted miss below which the agent reacts (m), > 0.
        horizon: T, the longest time ahead at which it reacts (s), > 0.
        speed_gain: γ (s/m).
        cap: the largest force (m/s²), > 0.

    Returns:
        (fx, fy), the acceleration (m/s²) on the agent.
    """
    px = x - sx
    py = y - sy
    wx = vx - svx
    wy = vy - svy
    s = px * wx + py * wy
    w2 = wx * wx + wy * wy
    if s >= 0.0 or w2 < EPS or math.sqrt(px * px + py * py) < EPS:
        return 0.0, 0.0
    t = -s / w2
    if t >= horizon:
        return 0.0, 0.0
    mx = px + wx * t
    my = py + wy * t
    miss = math.sqrt(mx * mx + my * my)
    if miss >= onset:
        return 0.0, 0.0
    speed = math.sqrt(svx * svx + svy * svy)
    mag = (
        amplitude
        * (1.0 - miss / onset)
        * (1.0 - t / horizon)
        * capped_exp(speed_gain * (speed - SIDESTEP_REF_SPEED_MPS))
    )
    if has_heading:
        nx = -hy
        ny = hx
        if mx * nx + my * ny > 0.0:
            return _capped(mag * nx, mag * ny, cap)
        return _capped(-mag * nx, -mag * ny, cap)
    if miss < EPS:
        mx = px
        my = py
        miss = math.sqrt(px * px + py * py)
        if miss < EPS:
            return 0.0, 0.0
    return _capped(mag * mx / miss, mag * my / miss, cap)


@njit(cache=True, inline="always")
def robot_strength(params: SRFMKernelParams) -> float:
    """The strength of the parameter set's robot form (A_r, k, A, A_e or the sidestep's
    A): 0 switches the robot off."""
    form = params.robot_form
    if form == FORM_SIDESTEP:
        return params.ss_a
    if form == FORM_TTC:
        return params.ttc_k
    if form == FORM_COLLISION_PREDICTION:
        return params.cp_a
    if form == FORM_ELLIPTICAL:
        return params.ell_a
    return params.a_robot


# Compiled apart, not inline="always": see the comment above step_exact in
# srfm/models/_kernels.py.
@njit(cache=True)
def robot_force(
    x: float,
    y: float,
    vx: float,
    vy: float,
    radius: float,
    hx: float,
    hy: float,
    has_heading: bool,
    robot: np.ndarray,
    params: SRFMKernelParams,
) -> tuple[float, float]:
    """f_robot on a pedestrian at (x, y) with velocity (vx, vy), radius ``radius`` and
    heading (hx, hy) (``has_heading`` False: none), from the robot ``robot`` (5,) =
    (x, y, radius, vx, vy), in the form ``params.robot_form``; (0.0, 0.0) when the
    form's strength is 0 (:func:`robot_strength`).
    """
    form = params.robot_form
    r_sum = radius + robot[2]
    if form == FORM_SIDESTEP:
        if params.ss_a == 0.0:
            return 0.0, 0.0
        return sidestep_force(
            x,
            y,
            vx,
            vy,
            robot[0],
            robot[1],
            robot[3],
            robot[4],
            hx,
            hy,
            has_heading,
            params.ss_a,
            params.ss_miss,
            params.ss_horizon,
            params.ss_speed_gain,
            params.robot_force_cap,
        )
    if form == FORM_TTC:
        if params.ttc_k == 0.0:
            return 0.0, 0.0
        return ttc_force(
            x,
            y,
            vx,
            vy,
            robot[0],
            robot[1],
            robot[3],
            robot[4],
            r_sum,
            params.ttc_k,
            params.ttc_tau0,
            params.robot_force_cap,
        )
    if form == FORM_COLLISION_PREDICTION:
        if params.cp_a == 0.0:
            return 0.0, 0.0
        return collision_prediction_force(
            x,
            y,
            vx,
            vy,
            robot[0],
            robot[1],
            robot[3],
            robot[4],
            r_sum,
            params.cp_a,
            params.cp_b,
            params.cp_t_min,
            params.cp_t_max,
            params.robot_force_cap,
        )
    if form == FORM_ELLIPTICAL:
        if params.ell_a == 0.0:
            return 0.0, 0.0
        return elliptical_force(
            x,
            y,
            vx,
            vy,
            robot[0],
            robot[1],
            robot[3],
            robot[4],
            r_sum,
            params.ell_a,
            params.ell_b,
            params.ell_dt,
            hx,
            hy,
            has_heading,
            params.lambda_robot,
            params.robot_force_cap,
        )
    if params.a_robot == 0.0:
        return 0.0, 0.0
    return disc_repulsion(
        x,
        y,
        robot[0],
        robot[1],
        r_sum,
        params.a_robot,
        params.b_robot,
        hx,
        hy,
        has_heading,
        params.lambda_robot,
    )
