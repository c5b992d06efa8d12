"""The protocol of issue 40: fitting the sidestep robot response to NavWareSet's people.

docs/robot_response.md states the protocol in words; this module holds its numbers
(:data:`PROTOCOL`), committed before any held-out result of the sidestep form was
computed, and the analysis the page's claims rest on. See the page for what each
number means.
"""

from __future__ import annotations

from typing import Final

import attrs

from srfm.fitting._windows import WindowConfig

__all__ = ["PROTOCOL", "ResponseProtocol"]


@attrs.frozen(kw_only=True)
class ResponseProtocol:
    """The pre-registered numbers of the sidestep fit (docs/robot_response.md).

    Attributes:
        date: the day the protocol was written (UTC).
        windows: the encounter windows (issue 28's, unchanged).
        fields: the fitted parameters of the ``sidestep`` form, the cap included.
        bounds: per field, the search interval.
        log_fields: the fields whose starts are spread on a log scale, over
            [upper bound / ``log_span``, upper bound].
        log_span: see ``log_fields``.
        n_starts: the spread starts (scrambled Sobol points over the bounds), besides
            the form's defaults.
        start_seed: the Sobol sequence's seed.
        spread_nfev: the model evaluations (scipy's ``max_nfev``) of every start of a
            held-out fold before the lowest-cost start is refined.
        refine_nfev: the largest ``max_nfev`` of a refined start, and of every start
            of a full fit (all of a set's scenes).
        tolerance: scipy's ``ftol``, ``xtol``, ``gtol``.
        profile_points: grid points of each parameter's profile.
        profile_nfev: ``max_nfev`` of each profile point's fit of the other fields.
        identified_rise: a parameter is identified when its profile cost rises by at
            least this fraction of the minimum on each side of the fit within the
            bounds (on the one side there is, for a fit at a bound).
        n_boot: bootstrap resamples over scenes of each relative change.
        boot_seed: first seed of the bootstraps (one more per row).
        pass_margin, offset_margin: the success margins: at least this relative
            reduction of the pooled |pass-distance error| and |path-offset error|
            against robot ignored.
        ade_margin: the ADE margin of the two one-sided tests (equivalent or better).
        alpha: the level of the Holm-corrected decisive tests.
        no_overlap: the contact-only baseline: the exponential robot force with these
            (A_r m/s², B_r m, λ_r).
    """

    date: str
    windows: WindowConfig
    fields: tuple[str, ...]
    bounds: dict[str, tuple[float, float]]
    log_fields: tuple[str, ...]
    log_span: float
    n_starts: int
    start_seed: int
    spread_nfev: int
    refine_nfev: int
    tolerance: float
    profile_points: int
    profile_nfev: int
    identified_rise: float
    n_boot: int
    boot_seed: int
    pass_margin: float
    offset_margin: float
    ade_margin: float
    alpha: float
    no_overlap: tuple[float, float, float]


PROTOCOL: Final = ResponseProtocol(
    date="2026-12-05",
    windows=WindowConfig(align="encounter", lead_s=3.0, goal="heading", min_start_speed_mps=0.3),
    fields=("ss_a", "ss_miss", "ss_horizon", "ss_speed_gain", "robot_force_cap"),
    bounds={
        "ss_a": (0.0, 5.0),
        "ss_miss": (0.1, 3.0),
        "ss_horizon": (0.3, 8.0),
        "ss_speed_gain": (-3.0, 3.0),
        "robot_force_cap": (0.02, 20.0),
    },
    log_fields=("ss_a", "robot_force_cap"),
    log_span=500.0,
    n_starts=8,
    start_seed=2040,
    spread_nfev=15,
    refine_nfev=100,
    tolerance=1e-6,
    profile_points=9,
    profile_nfev=30,
    identified_rise=0.01,
    n_boot=2000,
    boot_seed=2040,
    pass_margin=0.10,
    offset_margin=0.05,
    ade_margin=0.02,
    alpha=0.05,
    no_overlap=(20.0, 0.02, 1.0),
)
"""The protocol of docs/robot_response.md, written on 2026-12-05 before any held-out
number of the sidestep form."""
