"""The Python API of the crowd step keeps what does not change between calls (the
default parameters, the cut-off arrays): every call must still step exactly as the
kernel with a context built afresh, whatever came before it, and reject bad input."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

import srfm
from srfm.models import _kernels
from srfm.models._arrays import ForceContext
from srfm.models.forces import CELL_LIST_MIN_AGENTS, Cutoff, interaction_cutoffs, kernel_cutoffs

DT = 1.0 / 15.0
N = 40  # above CELL_LIST_MIN_AGENTS: "auto" takes the cut-off and the row list
WALLS = srfm.Obstacles.create(
    segments=[[0.0, 0.0, 8.0, 0.0], [4.0, 2.0, 4.0, 5.0]], circles=[[2.0, 3.0, 0.3]]
)
PILLARS = srfm.Obstacles.create(circles=[[6.0, 6.0, 0.5], [1.0, 7.0, 0.2]])
OTHER = srfm.SRFMParams(a_ped=5.0, b_ped=0.4, a_obs=10.0, b_obs=0.2, lambda_ped=0.7)


def crowd(n: int = N, seed: int = 0) -> srfm.CrowdState:
    rng = np.random.default_rng(seed)
    return srfm.CrowdState.create(
        pos=rng.uniform(0.5, 8.0, (n, 2)),
        goal=rng.uniform(0.5, 8.0, (n, 2)),
        vel=rng.uniform(-1.0, 1.0, (n, 2)),
        radius=rng.uniform(0.2, 0.35, n),
        v0=rng.uniform(0.8, 1.4, n),
    )


def kernel_step(
    c: srfm.CrowdState,
    params: srfm.SRFMParams,
    robot: srfm.RobotBody | None,
    obstacles: srfm.Obstacles | None,
    cutoff: Cutoff,
) -> None:
    """One step by the kernel itself, its context built here from nothing cached."""
    r_max = float(c.radius.max())
    if cutoff == "exact" or (cutoff == "auto" and c.n < CELL_LIST_MIN_AGENTS):
        cut = np.array([np.inf, np.inf])
    elif cutoff == "auto":
        cut = np.array(interaction_cutoffs(params, r_max))
    else:
        cut = np.array([float(cutoff), interaction_cutoffs(params, r_max)[1]])
    context = ForceContext(
        attrs.evolve(params).for_kernels(),  # a new instance: nothing kept on it
        np.zeros(5) if robot is None else robot.as_array(),
        robot is not None,
        (obstacles or srfm.Obstacles()).for_kernels(),
        cut,
    )
    kernel = _kernels.step_exact if math.isinf(cut[0]) else _kernels.step_serial
    kernel(c.for_kernels(), context, DT, np.empty_like(c.pos))


# (params, robot, obstacles, cutoff) of consecutive calls on one crowd: each changes
# something the API might have kept from the call before
CALLS: list[tuple[srfm.SRFMParams | None, srfm.RobotBody | None, srfm.Obstacles | None, Cutoff]] = [
    (None, None, None, "auto"),
    (OTHER, None, None, "auto"),
    (None, None, None, "auto"),
    (None, srfm.RobotBody(x=4.0, y=4.0), WALLS, "auto"),
    (None, srfm.RobotBody(x=4.5, y=3.5, vx=0.5), WALLS, "auto"),
    (None, None, WALLS, "auto"),
    (None, None, PILLARS, "auto"),
    (OTHER, None, PILLARS, 3.0),
    (OTHER, None, PILLARS, 3),
    (OTHER, srfm.RobotBody(x=2.0, y=2.0), None, "exact"),
    (srfm.SRFMParams(), None, WALLS, 5.5),
    (None, None, None, "exact"),
    (None, None, None, "auto"),
]


@pytest.mark.parametrize("n", [10, N])
def test_every_call_steps_as_the_kernel_with_a_fresh_context(n: int) -> None:
    api = crowd(n)
    ref = api.copy()
    for params, robot, obstacles, cutoff in CALLS:
        srfm.step_crowd(api, DT, params, robot, obstacles, cutoff=cutoff)
        kernel_step(ref, params or srfm.SRFMParams(), robot, obstacles, cutoff)
        np.testing.assert_array_equal(api.pos, ref.pos)
        np.testing.assert_array_equal(api.vel, ref.vel)
        assert np.any(api.vel != 0.0)


def test_params_a_then_b_is_b_fresh() -> None:
    start = crowd()
    assert (
        kernel_cutoffs("auto", OTHER, start.radius)[0]
        != kernel_cutoffs("auto", srfm.SRFMParams(), start.radius)[0]
    )
    fresh = start.copy()
    kernel_step(fresh, OTHER, None, None, "auto")
    after_a = start.copy()
    srfm.step_crowd(start.copy(), DT)  # the default parameters' cut-offs kept
    srfm.step_crowd(after_a, DT, OTHER)
    np.testing.assert_array_equal(after_a.pos, fresh.pos)
    np.testing.assert_array_equal(after_a.vel, fresh.vel)
    # and the other way round: B's cut-offs are not taken for the defaults
    default_fresh = start.copy()
    kernel_step(default_fresh, srfm.SRFMParams(), None, None, "auto")
    after_b = start.copy()
    srfm.step_crowd(after_b, DT)
    np.testing.assert_array_equal(after_b.pos, default_fresh.pos)


def test_a_radius_changed_in_place_changes_the_cut_off() -> None:
    api = crowd()
    ref = api.copy()
    before = kernel_cutoffs("auto", srfm.SRFMParams(), api.radius)
    for radius in (None, 0.6, 0.1, None):
        if radius is not None:
            api.radius[:] = radius
            ref.radius[:] = radius
        srfm.step_crowd(api, DT)
        kernel_step(ref, srfm.SRFMParams(), None, None, "auto")
        np.testing.assert_array_equal(api.pos, ref.pos)
        np.testing.assert_array_equal(api.vel, ref.vel)
    assert kernel_cutoffs("auto", srfm.SRFMParams(), api.radius)[0] != before[0]


def test_the_default_parameters_are_agrawal2024() -> None:
    a = crowd()
    b = a.copy()
    srfm.step_crowd(a, DT)
    srfm.step_crowd(b, DT, srfm.SRFMParams.preset("agrawal2024"))
    np.testing.assert_array_equal(a.pos, b.pos)


def test_kernel_cutoffs_hands_out_a_copy() -> None:
    c = crowd()
    cut = kernel_cutoffs("auto", srfm.SRFMParams(), c.radius)
    expected = cut.copy()
    cut[:] = 0.01  # the caller's array: the next calls must not see it
    assert kernel_cutoffs("auto", srfm.SRFMParams(), c.radius).tolist() == expected.tolist()
    api = c.copy()
    ref = c.copy()
    srfm.step_crowd(api, DT)
    kernel_step(ref, srfm.SRFMParams(), None, None, "auto")
    np.testing.assert_array_equal(api.pos, ref.pos)


@pytest.mark.parametrize(
    ("cutoff", "text"),
    [
        (True, "True"),
        (False, "False"),
        ("bogus", "bogus"),
        ([3.0], r"\[3.0\]"),
        (float("nan"), "nan"),
        (-1.0, "-1.0"),
        (0, "0"),
        (float("inf"), "inf"),
    ],
)
def test_bad_cutoffs_raise_after_good_calls(cutoff: object, text: str) -> None:
    c = crowd()
    srfm.step_crowd(c.copy(), DT, cutoff=1.0)  # 1.0 == True: must not be taken for it
    srfm.step_crowd(c.copy(), DT, cutoff="auto")
    before = c.copy()
    with pytest.raises(srfm.SimulationError, match=f"cutoff.*{text}"):
        srfm.step_crowd(c, DT, cutoff=cutoff)  # type: ignore[arg-type]
    with pytest.raises(srfm.SimulationError, match=f"cutoff.*{text}"):
        srfm.force_components(c, cutoff=cutoff)  # type: ignore[arg-type]
    np.testing.assert_array_equal(c.pos, before.pos)


@pytest.mark.parametrize("dt", [0.0, float("nan"), 2.0])
def test_bad_dt_raises_after_good_calls(dt: float) -> None:
    c = crowd()
    srfm.step_crowd(c, DT)
    with pytest.raises(srfm.SimulationError, match=rf"dt .*{dt!r}"):
        srfm.step_crowd(c, dt)


def test_crowds_either_side_of_the_cell_list_threshold() -> None:
    # the same radii (the same largest radius): only the crowd size tells the exact
    # kernel ("auto" below CELL_LIST_MIN_AGENTS) from the cut-off apart
    for sizes in ((10, N), (N, 10)):
        for n in sizes:
            api = crowd(n, seed=n)
            api.radius[:] = 0.3
            ref = api.copy()
            srfm.step_crowd(api, DT)
            kernel_step(ref, srfm.SRFMParams(), None, None, "auto")
            np.testing.assert_array_equal(api.pos, ref.pos)
