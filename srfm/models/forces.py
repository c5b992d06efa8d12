"""Python API over the force kernels: inspect force components, step a crowd."""

from __future__ import annotations

import math
from typing import Any, Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._jit import specialize_once
from srfm._text import plain
from srfm._validate import MAX_SPEED_MPS
from srfm.errors import SimulationError
from srfm.models import _kernels
from srfm.models._arrays import ForceContext
from srfm.models.params import SRFMParams
from srfm.models.state import CrowdState, Obstacles

__all__ = [
    "CELL_LIST_MIN_AGENTS",
    "FORCE_TOLERANCE_MPS2",
    "Cutoff",
    "ForceComponents",
    "RobotBody",
    "force_components",
    "interaction_cutoffs",
    "kernel_cutoffs",
    "step_crowd",
]

# The serial kernel is the default at every crowd size: with the other core busy the
# threaded kernel ran 0.002-0.5x as fast as the serial one up to N = 1000 and 1.0x at
# N = 10,000 (docs/performance.md, "Threading under load"). parallel=True asks for it
# where cores are known to be idle.

# The interaction cut-off (docs/performance.md, "Neighbour search"). Beyond
#   d_ped = 2 r_max + B_p ln(A_p / tol)   (pedestrians; r_max the largest radius)
#   d_obs = r_max + B_o ln(A_o / tol)     (walls and pillars, distance to the surface)
# every pairwise term A exp((r_i + r_j - d) / B) ψ (ψ <= 1) is below tol; those terms are
# left out. With the agrawal2024 preset, r = 0.3 m and tol = 1e-6 m/s²: d_ped = 13.5 m,
# d_obs = 1.66 m. The robot's single term is always computed.
FORCE_TOLERANCE_MPS2: Final = 1e-6
# "auto" (the default) uses the cut-off and a cell list from this many pedestrians on,
# and the exact kernel (every pair, in index order) below: the paper's 10-pedestrian
# scenarios (every built-in scenario but the large ones has 10 or fewer) stay bit for
# bit what they were. From about 30 pedestrians on the vectorised cell-list pass is the
# faster one (docs/performance.md).
CELL_LIST_MIN_AGENTS: Final = 32
# A cut-off: "auto", "exact" (no cut-off), or the pedestrian cut-off distance in m.
Cutoff = float | Literal["auto", "exact"]

# Largest step (s): with the speed bounds of CrowdState it keeps positions finite.
MAX_DT_S: Final = 1.0

_NO_OBSTACLES: Final = Obstacles()
# The parameters when none are given: the agrawal2024 preset (frozen, so one instance
# serves every call and its kernel tuple is built once).
_DEFAULT_PARAMS: Final = SRFMParams()
# The kernels' robot argument when there is no robot (never read then, never written).
_NO_ROBOT: Final = np.zeros(5)


@attrs.frozen(kw_only=True)
class RobotBody:
    """What the pedestrians perceive of the robot: a disc at ``(x, y)`` of ``radius`` (m)
    moving with velocity ``(vx, vy)`` (m/s; the paper's exponential force ignores it, the
    anticipatory forms of ``SRFMParams.robot_form`` read it)."""

    x: float
    y: float
    radius: float = 0.2
    vx: float = 0.0
    vy: float = 0.0

    def as_array(self) -> NDArray[np.float64]:
        """(5,) = (x, y, radius, vx, vy), the kernels' layout."""
        return np.array([self.x, self.y, self.radius, self.vx, self.vy], dtype=np.float64)


@attrs.frozen(kw_only=True, eq=False)
class ForceComponents:
    """The SRFM force components on each pedestrian, (N, 2) each, in m/s² (unit mass)."""

    goal: NDArray[np.float64]
    pedestrians: NDArray[np.float64]
    robot: NDArray[np.float64]
    obstacles: NDArray[np.float64]

    @property
    def total(self) -> NDArray[np.float64]:
        """Sum of the four components, in the order the step kernel adds them."""
        return self.goal + self.pedestrians + self.robot + self.obstacles


def _robot_args(robot: RobotBody | None) -> tuple[NDArray[np.float64], bool]:
    if robot is None:
        return _NO_ROBOT, False
    arr = robot.as_array()
    if not np.all(np.isfinite(arr)) or arr[2] < 0.0 or math.hypot(arr[3], arr[4]) > MAX_SPEED_MPS:
        raise SimulationError(
            f"robot body must be finite with radius >= 0 and speed <= {MAX_SPEED_MPS:g} m/s, "
            f"got {plain(robot)}"
        )
    return arr, True


def interaction_cutoffs(
    params: SRFMParams, max_radius: float, tolerance: float = FORCE_TOLERANCE_MPS2
) -> tuple[float, float]:
    """(pedestrian, obstacle) cut-off distances (m) beyond which every pairwise term
    is below ``tolerance`` (m/s²), for pedestrians of radius at most ``max_radius``.

    The pedestrian cut-off is a centre distance, the obstacle cut-off a distance to the
    wall or the pillar's surface; see ``FORCE_TOLERANCE_MPS2`` for the formulas.
    """
    if not tolerance > 0.0 or not math.isfinite(tolerance):
        raise SimulationError(f"force tolerance must be finite and > 0, got {plain(tolerance)}")
    r = max(float(max_radius), 0.0)
    ped = (
        2.0 * r + params.b_ped * max(math.log(params.a_ped / tolerance), 0.0)
        if params.a_ped
        else 0.0
    )
    obs = r + params.b_obs * max(math.log(params.a_obs / tolerance), 0.0) if params.a_obs else 0.0
    # a zero strength has no term at all: any cut-off will do (the kernel skips the sum)
    return max(ped, 2.0 * r) or 1.0, max(obs, r) or 1.0


def kernel_cutoffs(
    cutoff: Cutoff, params: SRFMParams, radius: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The kernels' ``cut`` argument (2,) for a crowd with radii ``radius``.

    Args:
        cutoff: "exact": no cut-off (every pair, in index order); "auto": the cut-offs
            of :func:`interaction_cutoffs` with a cell list from ``CELL_LIST_MIN_AGENTS``
            pedestrians on, exact below; a number: that pedestrian cut-off (m, > 0) with
            a cell list at any crowd size, obstacles cut as in "auto".

    Raises:
        SimulationError: an unknown mode or a cut-off that is not a positive number.
    """
    return _shared_cut(cutoff, params, radius).copy()


def _cut(cutoff: Cutoff, params: SRFMParams, r_max: float, n: int) -> NDArray[np.float64]:
    """:func:`kernel_cutoffs` for ``n`` pedestrians of largest radius ``r_max``."""
    if isinstance(cutoff, str):
        if cutoff == "exact" or (cutoff == "auto" and n < CELL_LIST_MIN_AGENTS):
            return np.array([np.inf, np.inf])
        if cutoff == "auto":
            return np.array(interaction_cutoffs(params, r_max))
        raise SimulationError(
            f"cutoff must be 'auto', 'exact' or a distance in m, got {plain(cutoff)}"
        )
    if isinstance(cutoff, bool) or not isinstance(cutoff, int | float | np.floating | np.integer):
        raise SimulationError(
            f"cutoff must be 'auto', 'exact' or a distance in m, got {plain(cutoff)}"
        )
    value = float(cutoff)
    if not (value > 0.0 and math.isfinite(value)):
        raise SimulationError(f"cutoff must be a finite distance > 0 m, got {plain(cutoff)}")
    return np.array([value, interaction_cutoffs(params, r_max)[1]])


# The cut arrays of the calls so far, by what they are computed from: the cut-off mode
# or distance, the parameters (their kernel tuple: equal values, equal cut-offs), the
# largest radius and whether the crowd is below CELL_LIST_MIN_AGENTS. Shared by the
# calls (the kernels only read ``cut``), never handed out (kernel_cutoffs copies);
# emptied when full.
_CUTS: dict[tuple[Any, ...], NDArray[np.float64]] = {}
_MAX_CUTS: Final = 256


def _shared_cut(
    cutoff: Cutoff, params: SRFMParams, radius: NDArray[np.float64]
) -> NDArray[np.float64]:
    """:func:`kernel_cutoffs`, computed once per distinct input: the array is shared,
    read it only."""
    n = radius.shape[0]
    r_max = float(radius.max()) if n else 0.0
    if isinstance(cutoff, str):
        mode: Any = cutoff
    elif isinstance(cutoff, bool) or not isinstance(cutoff, int | float | np.floating | np.integer):
        mode = None  # an error: _cut raises it
    else:
        mode = float(cutoff)
    key = (mode, params.for_kernels(), r_max, n < CELL_LIST_MIN_AGENTS)
    cut = _CUTS.get(key) if mode is not None else None
    if cut is None:
        cut = _cut(cutoff, params, r_max, n)
        if len(_CUTS) >= _MAX_CUTS:
            _CUTS.clear()
        _CUTS[key] = cut
    return cut


def force_components(
    crowd: CrowdState,
    params: SRFMParams | None = None,
    robot: RobotBody | None = None,
    obstacles: Obstacles | None = None,
    *,
    cutoff: Cutoff = "auto",
) -> ForceComponents:
    """Compute each SRFM force component for the current crowd state.

    Args:
        crowd: the pedestrians.
        params: model parameters; the ``agrawal2024`` preset when omitted.
        robot: the robot as the pedestrians perceive it; None for no robot.
        obstacles: walls and pillars; none when omitted.
        cutoff: interaction cut-off, see :func:`kernel_cutoffs`.

    Returns:
        The goal, pedestrian, robot and obstacle components, each (N, 2) in m/s².
    """
    params = _DEFAULT_PARAMS if params is None else params
    obstacles = _NO_OBSTACLES if obstacles is None else obstacles
    robot_arr, robot_on = _robot_args(robot)
    cut = _shared_cut(cutoff, params, crowd.radius)
    out = np.zeros((4, crowd.n, 2))
    context = ForceContext(params.for_kernels(), robot_arr, robot_on, obstacles.for_kernels(), cut)
    args = (crowd.for_kernels(), context, out)
    specialize_once(_kernels.force_components_kernel, *args)(*args)
    return ForceComponents(goal=out[0], pedestrians=out[1], robot=out[2], obstacles=out[3])


def step_crowd(
    crowd: CrowdState,
    dt: float,
    params: SRFMParams | None = None,
    robot: RobotBody | None = None,
    obstacles: Obstacles | None = None,
    *,
    parallel: bool = False,
    cutoff: Cutoff = "auto",
) -> None:
    """Advance ``crowd`` in place by one step of ``dt`` seconds.

    All forces are computed from one snapshot, then every pedestrian is moved with
    semi-implicit Euler (v ← v + F dt, |v| ≤ vmax, x ← x + v dt); the result does not
    depend on the order of the pedestrians.

    Args:
        dt: step (s), in (0, 1].
        parallel: use the threaded kernel (for idle cores only; the serial kernel is
            the default). Both kernels give identical results.
        cutoff: interaction cut-off, see :func:`kernel_cutoffs`.
    """
    if not 0.0 < dt <= MAX_DT_S:  # also false for NaN
        raise SimulationError(f"dt must be in (0, {MAX_DT_S:g}] s, got {plain(dt)}")
    params = _DEFAULT_PARAMS if params is None else params
    obstacles = _NO_OBSTACLES if obstacles is None else obstacles
    robot_arr, robot_on = _robot_args(robot)
    cut = _shared_cut(cutoff, params, crowd.radius)
    if parallel:
        kernel = _kernels.step_parallel
    elif math.isinf(cut[0]):
        kernel = _kernels.step_exact  # the same sums, without compiling the cell list
    else:
        kernel = _kernels.step_serial
    context = ForceContext(params.for_kernels(), robot_arr, robot_on, obstacles.for_kernels(), cut)
    args = (crowd.for_kernels(), context, float(dt), np.empty_like(crowd.pos))
    specialize_once(kernel, *args)(*args)
