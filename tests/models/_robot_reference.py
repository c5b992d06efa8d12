"""Plain-NumPy reference of the robot force's anticipatory forms (docs/model.md).

Written from the papers' equations, independently of ``srfm.models._robot_forces``:
vectorised over all pedestrians, each force in the form its paper prints it. Only the
tests use it. ``p`` is the relative position x_i − x_r, ``w`` the relative velocity
v_i − v_r (N, 2), ``r`` the radius sums (N,).

- Time to collision (Karamouzas, Skinner, Guy 2014, PRL 113, 238701): with
  a = |w|², b = p·w, c = |p|² − r², D = b² − a c and τ = (−b − √D) / a,

      F = −(k e^(−τ/τ0) / (a τ²)) (2/τ + 1/τ0) [w − (a p − b w) / √D]

  (the paper's force on i, in its own notation). No force unless b < 0, a > 0 and
  D > 0; overlapping discs (c < 0) are pushed apart at the cap; capped at ``cap``.
- Collision prediction (Zanlungo, Ikeda, Kanda 2011, EPL 93, 68005): t = min(−b / a,
  t_max), p' = p + w t, F = A |v_i| / max(t, t_min) e^(−(|p'| − r)/B) p'/|p'| for
  b < 0 (p' = 0 exactly: along p); capped.
- Elliptical specification II (Johansson, Helbing, Shukla 2007): y = (v_r − v_i) Δt,
  2β = √((|p| + |p − y|)² − |y|²), F = A_e e^((r − β)/B_e) ψ (|p| + |p − y|)/(2β)
  (p̂ + (p − y)^)/2; capped.
- Sidestep (srfm, issue 40): with t* = −(p·w)/|w|² and m = p + w t*, for p·w < 0,
  t* < T and |m| < d_on, |F| = A (1 − |m|/d_on)(1 − t*/T) e^(γ(|v_r| − 1)), pointing
  along the component of m perpendicular to the heading (to the heading's right when
  that component is 0), along m (else p) without a heading; capped.

Degenerate cases use the kernel's documented conventions (the EPS thresholds of
``srfm.models._primitives``), so that the branches agree; everything else is computed
differently (other formulas, whole-array operations).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

import srfm

FloatArray = NDArray[np.float64]
EPS = 1e-12
TTC_MIN_TAU_S = 1e-6


def _cap(f: FloatArray, cap: float) -> FloatArray:
    norm = np.linalg.norm(f, axis=1)
    scale = np.where(norm > cap, cap / np.where(norm > 0.0, norm, 1.0), 1.0)
    return f * scale[:, None]


def _dot(u: FloatArray, v: FloatArray) -> FloatArray:
    return np.einsum("ij,ij->i", u, v)


def ttc(
    p: FloatArray, w: FloatArray, r: FloatArray, k: float, tau0: float, cap: float
) -> FloatArray:
    """The time-to-collision force (N, 2)."""
    a = _dot(w, w)
    b = _dot(p, w)
    c = _dot(p, p) - r * r
    d = b * b - a * c
    ok = (c >= 0.0) & (b < 0.0) & (a >= EPS) & (d > EPS)
    a_ = np.where(ok, a, 1.0)
    sd = np.sqrt(np.where(ok, d, 1.0))
    tau = np.maximum((-b - sd) / a_, TTC_MIN_TAU_S)
    tau = np.where(ok, tau, 1.0)
    scale = -(k * np.exp(-tau / tau0) / (a_ * tau**2)) * (2.0 / tau + 1.0 / tau0)
    bracket = w - (a_[:, None] * p - b[:, None] * w) / sd[:, None]
    f = np.where(ok[:, None], scale[:, None] * bracket, 0.0)
    dist = np.linalg.norm(p, axis=1)
    overlap = (c < 0.0) & (dist >= EPS)
    push = cap * p / np.where(dist > 0.0, dist, 1.0)[:, None]
    f = np.where(overlap[:, None], push, f)
    return _cap(f, cap)


def collision_prediction(
    p: FloatArray,
    w: FloatArray,
    v: FloatArray,
    r: FloatArray,
    a: float,
    b: float,
    t_min: float,
    t_max: float,
    cap: float,
) -> FloatArray:
    """The collision-prediction force (N, 2); ``v`` the pedestrians' own velocities."""
    s = _dot(p, w)
    w2 = _dot(w, w)
    ok = (s < 0.0) & (w2 >= EPS)
    t = np.minimum(-s / np.where(ok, w2, 1.0), t_max)
    q = p + w * t[:, None]
    qn = np.linalg.norm(q, axis=1)
    course = qn < EPS  # an exact collision course: along p, predicted distance 0
    q = np.where(course[:, None], p, q)
    dist = np.where(course, 0.0, qn) - r
    qn = np.linalg.norm(q, axis=1)
    ok &= qn >= EPS
    unit = q / np.where(ok, qn, 1.0)[:, None]
    speed = np.linalg.norm(v, axis=1)
    mag = a * speed / np.maximum(t, t_min) * np.exp(np.minimum(-dist / b, 60.0))
    f = np.where(ok[:, None], mag[:, None] * unit, 0.0)
    return _cap(f, cap)


def elliptical(
    p: FloatArray,
    v: FloatArray,
    robot_v: FloatArray,
    r: FloatArray,
    heading: FloatArray,
    has_heading: NDArray[np.bool_],
    a: float,
    b: float,
    dt: float,
    lam: float,
    cap: float,
) -> FloatArray:
    """The elliptical force (N, 2); ``heading`` unit headings (N, 2)."""
    y = (robot_v[None, :] - v) * dt
    e = p - y
    pn = np.linalg.norm(p, axis=1)
    en = np.linalg.norm(e, axis=1)
    ok = pn >= EPS
    p_hat = p / np.where(ok, pn, 1.0)[:, None]
    e_hat = np.where((en >= EPS)[:, None], e / np.where(en >= EPS, en, 1.0)[:, None], 0.0)
    beta = 0.5 * np.sqrt(np.maximum((pn + en) ** 2 - _dot(y, y), 0.0))
    beta = np.maximum(beta, EPS)
    cos_phi = _dot(heading, -p_hat)
    psi = np.where(has_heading, lam + (1.0 - lam) * (1.0 + cos_phi) / 2.0, 1.0)
    grad = (pn + en)[:, None] / (4.0 * beta[:, None]) * (p_hat + e_hat)
    mag = a * np.exp(np.minimum((r - beta) / b, 60.0)) * psi
    f = np.where(ok[:, None], mag[:, None] * grad, 0.0)
    return _cap(f, cap)


def sidestep(
    p: FloatArray,
    w: FloatArray,
    robot_v: FloatArray,
    heading: FloatArray,
    has_heading: NDArray[np.bool_],
    a: float,
    onset: float,
    horizon: float,
    gain: float,
    cap: float,
) -> FloatArray:
    """The sidestep force (N, 2): the heading's perpendicular component of the
    predicted miss gives the side, projected with the heading's rejection."""
    s = _dot(p, w)
    w2 = _dot(w, w)
    t = -s / np.where(w2 >= EPS, w2, 1.0)
    m = p + w * t[:, None]
    miss = np.linalg.norm(m, axis=1)
    ok = (s < 0.0) & (w2 >= EPS) & (t < horizon) & (miss < onset)
    ok &= np.linalg.norm(p, axis=1) >= EPS
    speed = float(np.hypot(robot_v[0], robot_v[1]))
    mag = a * (1.0 - miss / onset) * (1.0 - t / horizon) * np.exp(min(gain * (speed - 1.0), 60.0))
    # the side: m minus its part along the heading; its sign along the left normal
    lateral = m - _dot(m, heading)[:, None] * heading
    left = np.stack([-heading[:, 1], heading[:, 0]], axis=1)
    side = np.where(_dot(lateral, left) > 0.0, 1.0, -1.0)
    with_heading = side[:, None] * left
    far = np.where((miss >= EPS)[:, None], m, p)
    far_n = np.linalg.norm(far, axis=1)
    without = far / np.where(far_n >= EPS, far_n, 1.0)[:, None]
    without = np.where((far_n >= EPS)[:, None], without, 0.0)
    unit = np.where(has_heading[:, None], with_heading, without)
    f = np.where(ok[:, None], mag[:, None] * unit, 0.0)
    return _cap(f, cap)


def robot_force(
    crowd: srfm.CrowdState,
    params: srfm.SRFMParams,
    robot: srfm.RobotBody,
    heading: FloatArray,
    has_heading: NDArray[np.bool_],
) -> FloatArray:
    """f_robot on every pedestrian in the form ``params.robot_form`` (not exponential)."""
    rpos = np.array([robot.x, robot.y])
    rvel = np.array([robot.vx, robot.vy])
    p = crowd.pos - rpos
    w = crowd.vel - rvel
    r = crowd.radius + robot.radius
    cap = params.robot_force_cap
    if params.robot_form == "ttc":
        if params.ttc_k == 0.0:
            return np.zeros_like(p)
        return ttc(p, w, r, params.ttc_k, params.ttc_tau0, cap)
    if params.robot_form == "collision_prediction":
        if params.cp_a == 0.0:
            return np.zeros_like(p)
        return collision_prediction(
            p, w, crowd.vel, r, params.cp_a, params.cp_b, params.cp_t_min, params.cp_t_max, cap
        )
    if params.robot_form == "sidestep":
        if params.ss_a == 0.0:
            return np.zeros_like(p)
        return sidestep(
            p,
            w,
            rvel,
            heading,
            has_heading,
            params.ss_a,
            params.ss_miss,
            params.ss_horizon,
            params.ss_speed_gain,
            cap,
        )
    assert params.robot_form == "elliptical"
    if params.ell_a == 0.0:
        return np.zeros_like(p)
    return elliptical(
        p,
        crowd.vel,
        rvel,
        r,
        heading,
        has_heading,
        params.ell_a,
        params.ell_b,
        params.ell_dt,
        params.lambda_robot,
        cap,
    )
