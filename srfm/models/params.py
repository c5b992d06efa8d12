"""SRFM model parameters: one frozen, validated class and the paper's presets.

The Social Robot Force Model (Agrawal, Dengler, Bennewitz, ICSR 2024) moves pedestrian i
with the acceleration (unit mass, so forces are accelerations, m/s²)

    F_i = f_goal + Σ_j f_ped(i, j) + Σ_o f_obs(i, o) + f_robot(i)

    f_goal     = (v0_i e_i − v_i) / τ                             (paper Eq. 3, sign fixed)
    f_ped      = A_p exp((r_i + r_j − d_ij) / B_p) ψ(φ; λ) n_ji    (Eq. 4 with Eq. 5)
    f_robot    = A_r exp((r_i + r_r − d_ir) / B_r) ψ(φ; λ_r) n_ri  (the paper's robot force)
    f_obs      = A_o exp((r_i − d_io) / B_o) n_oi
    ψ(φ; λ)    = λ + (1 − λ) (1 + cos φ) / 2                      (Eq. 5)

The robot term f_robot has five forms (``robot_form``; docs/model.md): the paper's
exponential force above (the default), the time-to-collision force of Karamouzas,
Skinner and Guy (2014), the collision-prediction force of Zanlungo, Ikeda and Kanda
(2011), the elliptical force of Johansson, Helbing and Shukla (2007) and srfm's
sidestep, a sideways response to a predicted near miss (issue 40); each reads only its
own parameters (:data:`FORM_FIELDS`).

Model-level parameters live here; per-agent values (radius, desired and maximum speed)
are arrays in :class:`srfm.CrowdState`.
"""

from __future__ import annotations

import functools
import json
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any, Final, NamedTuple

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import (
    MAX_TOML_BYTES,
    atomic_write_text,
    parse_toml,
    read_input_text,
    toml_scalar,
)
from srfm._text import plain
from srfm._validate import finite_float, non_negative, positive, unit_interval
from srfm.errors import ParameterError
from srfm.models._forms import ROBOT_FORMS

__all__ = [
    "FORM_FIELDS",
    "PRESETS",
    "ROBOT_FORMS",
    "SRFMKernelParams",
    "SRFMParams",
    "load_params",
    "preset_meta",
    "response_model_name",
    "save_params",
]

PARAMS_SCHEMA_VERSION: Final = 1

FORM_FIELDS: Final[dict[str, tuple[str, ...]]] = {
    "exponential": ("a_robot", "b_robot", "lambda_robot"),
    "ttc": ("ttc_k", "ttc_tau0", "robot_force_cap"),
    "collision_prediction": ("cp_a", "cp_b", "cp_t_min", "cp_t_max", "robot_force_cap"),
    "elliptical": ("ell_a", "ell_b", "ell_dt", "lambda_robot", "robot_force_cap"),
    "sidestep": ("ss_a", "ss_miss", "ss_horizon", "ss_speed_gain", "robot_force_cap"),
}
"""The parameters each robot form reads (its strength first)."""

# The fields of the paper's model: a parameter set of the exponential form is written
# (as_dict, save_params, manifests, logs) with these alone, as before the other forms.
_PAPER_FIELDS: Final = (
    "a_ped",
    "b_ped",
    "lambda_ped",
    "tau",
    "a_robot",
    "b_robot",
    "lambda_robot",
    "a_obs",
    "b_obs",
)


class SRFMKernelParams(NamedTuple):
    """The SRFM parameters as the force kernels take them (see :class:`SRFMParams`).

    The one definition of the parameter layout: :meth:`SRFMParams.for_kernels` builds
    it, and :meth:`SRFMParams.as_array` orders its vector by ``_fields``. numba types it
    as a tuple (the form code an int64, the rest float64) and reads the fields by name.

    Attributes:
        a_ped: A_p, pedestrian repulsion strength (m/s²).
        b_ped: B_p, pedestrian repulsion range (m).
        lambda_ped: λ, anisotropy of the pedestrian force.
        tau: τ, relaxation time (s).
        a_robot: A_r, robot repulsion strength (m/s²).
        b_robot: B_r, robot repulsion range (m).
        lambda_robot: λ_r, anisotropy of the robot force.
        a_obs: A_o, obstacle repulsion strength (m/s²).
        b_obs: B_o, obstacle repulsion range (m).
        robot_form: the robot force's form, the index of ``SRFMParams.robot_form`` in
            :data:`ROBOT_FORMS`.
        ttc_k: k, strength of the time-to-collision force (m²).
        ttc_tau0: τ0, its cut-off time (s).
        cp_a: A, strength of the collision-prediction force (dimensionless).
        cp_b: B, its range (m).
        cp_t_min: shortest time in its 1/t factor (s).
        cp_t_max: its longest prediction time (s).
        ell_a: A_e, strength of the elliptical force (m/s²).
        ell_b: B_e, its range (m).
        ell_dt: Δt, its prediction time (s).
        robot_force_cap: the largest robot force of the ttc, collision_prediction,
            elliptical and sidestep forms (m/s²).
        ss_a: A, amplitude of the sidestep force (m/s²).
        ss_miss: d_on, its onset: the predicted miss below which people react (m).
        ss_horizon: T, its anticipation horizon (s).
        ss_speed_gain: γ, its dependence on the robot's speed (s/m).
    """

    a_ped: float
    b_ped: float
    lambda_ped: float
    tau: float
    a_robot: float
    b_robot: float
    lambda_robot: float
    a_obs: float
    b_obs: float
    robot_form: int
    ttc_k: float
    ttc_tau0: float
    cp_a: float
    cp_b: float
    cp_t_min: float
    cp_t_max: float
    ell_a: float
    ell_b: float
    ell_dt: float
    robot_force_cap: float
    ss_a: float
    ss_miss: float
    ss_horizon: float
    ss_speed_gain: float


def _check_positive(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    positive(value, attribute.name, ParameterError)


# Upper bound on the strengths A and lower bound on τ: far outside any fitted value,
# and what keeps every force finite in float64 (see srfm.models._kernels).
MAX_STRENGTH: Final = 1e6
MIN_TAU_S: Final = 1e-3


def _check_strength(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = non_negative(value, attribute.name, ParameterError)
    if out > MAX_STRENGTH:
        raise ParameterError(f"{attribute.name} must be <= {MAX_STRENGTH:g}, got {plain(value)}")


def _check_tau(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = positive(value, attribute.name, ParameterError)
    if out < MIN_TAU_S:
        raise ParameterError(f"{attribute.name} must be >= {MIN_TAU_S:g} s, got {plain(value)}")


def _check_unit(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    unit_interval(value, attribute.name, ParameterError)


# Bounds of the anticipatory forms' times (s): within them, and the strength and state
# bounds, every robot force is finite before its cap (srfm.models._robot_forces).
MIN_TIME_S: Final = 1e-3
MAX_TIME_S: Final = 1e3


def _check_time(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = positive(value, attribute.name, ParameterError)
    if not MIN_TIME_S <= out <= MAX_TIME_S:
        raise ParameterError(
            f"{attribute.name} must be in [{MIN_TIME_S:g}, {MAX_TIME_S:g}] s, got {plain(value)}"
        )


def _check_duration(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = non_negative(value, attribute.name, ParameterError)
    if out > MAX_TIME_S:
        raise ParameterError(f"{attribute.name} must be <= {MAX_TIME_S:g} s, got {plain(value)}")


# Bound of the sidestep force's speed gain γ (s/m): exp(γ Δv) stays finite below the
# exponent's cap and a response 1e4 times stronger per m/s is far outside any data.
MAX_SPEED_GAIN: Final = 10.0


def _check_gain(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = finite_float(value, attribute.name, ParameterError)
    if not -MAX_SPEED_GAIN <= out <= MAX_SPEED_GAIN:
        raise ParameterError(
            f"{attribute.name} must be in [{-MAX_SPEED_GAIN:g}, {MAX_SPEED_GAIN:g}] s/m, "
            f"got {plain(value)}"
        )


def _check_cap(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    out = positive(value, attribute.name, ParameterError)
    if out > MAX_STRENGTH:
        raise ParameterError(f"{attribute.name} must be <= {MAX_STRENGTH:g}, got {plain(value)}")


def _check_form(inst: Any, attribute: attrs.Attribute[str], value: Any) -> None:
    if not isinstance(value, str) or value not in ROBOT_FORMS:
        known = ", ".join(ROBOT_FORMS)
        raise ParameterError(f"unknown robot_form {plain(value)}; known: {known}")


def _to_float(value: Any) -> Any:
    # Keep non-numbers as they are so the validator can name them in its message.
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        return value
    return float(value)


@attrs.frozen(kw_only=True)
class SRFMParams:
    """Model-level SRFM parameters (paper Table 1 symbols).

    Attributes:
        a_ped: A_p, pedestrian repulsion strength (m/s²), in [0, 1e6].
        b_ped: B_p, pedestrian repulsion range (m), > 0.
        lambda_ped: λ, anisotropy of the pedestrian force in [0, 1]; 1 is isotropic,
            0 ignores whatever is straight behind.
        tau: τ, relaxation time toward the desired velocity (s), >= 1e-3.
        a_robot: A_r, robot repulsion strength (m/s²), in [0, 1e6]; 0 switches the
            robot off.
        b_robot: B_r, robot repulsion range (m), > 0.
        lambda_robot: λ_r, anisotropy of the robot force in [0, 1]; the paper and its
            reference code use the robot force isotropically (λ_r = 1).
        a_obs: A_o, obstacle repulsion strength (m/s²), in [0, 1e6]. The paper fitted none;
            the default is Helbing, Farkas and Vicsek (Nature 2000): A = 2000 N for an
            80 kg pedestrian, i.e. 25 m/s².
        b_obs: B_o, obstacle repulsion range (m), > 0; Helbing et al. 2000: 0.08 m.
        robot_form: the form of the robot force, one of :data:`ROBOT_FORMS`:
            ``"exponential"`` (the paper's; A_r, B_r, λ_r), ``"ttc"`` (Karamouzas,
            Skinner, Guy 2014; k, τ0), ``"collision_prediction"`` (Zanlungo, Ikeda,
            Kanda 2011; A, B, t_min, t_max) or ``"elliptical"`` (Johansson, Helbing,
            Shukla 2007; A_e, B_e, Δt, λ_r) or ``"sidestep"`` (srfm's response to a
            predicted near miss; A, d_on, T, γ). Each form reads only its own fields
            (:data:`FORM_FIELDS`); docs/model.md gives the equations.
        ttc_k: k, strength of the time-to-collision energy E = k τ⁻² e^(−τ/τ0) (m²
            per unit mass), in [0, 1e6]; 0 switches the robot off.
        ttc_tau0: τ0, its exponential cut-off (s), in [1e-3, 1e3]; Karamouzas et al.:
            3 s.
        cp_a: A, strength of the collision-prediction force (dimensionless: the force
            is A |v_i| / t · e^(−d'/B)), in [0, 1e6]; 0 switches the robot off.
        cp_b: B, its range (m), > 0.
        cp_t_min: the shortest time in its 1/t factor (s), in [1e-3, 1e3] (the
            singularity at a closest approach now).
        cp_t_max: the longest prediction time (s), in [1e-3, 1e3], >= ``cp_t_min``.
        ell_a: A_e, strength of the elliptical force (m/s²), in [0, 1e6]; 0 switches
            the robot off.
        ell_b: B_e, its range (m), > 0.
        ell_dt: Δt, its prediction time (s), in [0, 1e3]; 0 is the paper's circular
            force.
        robot_force_cap: the largest robot force (m/s²) of the ttc,
            collision_prediction, elliptical and sidestep forms, in (0, 1e6] (their
            singularities: a collision or closest approach now, a grazing course).
        ss_a: A, amplitude of the sidestep force (m/s²), in [0, 1e6]: its force on a
            predicted collision course, now, of a robot at 1 m/s; 0 switches the robot
            off.
        ss_miss: d_on, its onset (m), > 0: people react while the predicted miss (the
            centre distance at the closest approach, both at constant velocity) is
            below it.
        ss_horizon: T, its anticipation horizon (s), in [1e-3, 1e3]: people react
            while the closest approach is less than T ahead.
        ss_speed_gain: γ, its dependence on the robot's speed (s/m), in [−10, 10]: the
            amplitude is A exp(γ (|v_r| − 1 m/s)); 0 makes it independent of the speed.

    The defaults of the other forms are starting values, not fits (issue 28 fits them
    on NavWareSet): τ0 = 3 s is Karamouzas et al.'s cut-off; the elliptical A_e, B_e
    are the paper's A_r, B_r, so that at equal velocities (or Δt = 0) it is the paper's
    force; the sidestep's d_on = 0.75 m and T = 3.5 s are the model-free onsets of
    docs/real_encounters.md (part 1), A = 0.2 m/s² the size of the sideways
    acceleration measured there, γ = 0 no speed dependence.
    """

    a_ped: float = attrs.field(default=2.0, converter=_to_float, validator=_check_strength)
    b_ped: float = attrs.field(default=0.89, converter=_to_float, validator=_check_positive)
    lambda_ped: float = attrs.field(default=0.4, converter=_to_float, validator=_check_unit)
    tau: float = attrs.field(default=0.6, converter=_to_float, validator=_check_tau)
    a_robot: float = attrs.field(default=7.93, converter=_to_float, validator=_check_strength)
    b_robot: float = attrs.field(default=0.99, converter=_to_float, validator=_check_positive)
    lambda_robot: float = attrs.field(default=1.0, converter=_to_float, validator=_check_unit)
    a_obs: float = attrs.field(default=25.0, converter=_to_float, validator=_check_strength)
    b_obs: float = attrs.field(default=0.08, converter=_to_float, validator=_check_positive)
    robot_form: str = attrs.field(default="exponential", validator=_check_form)
    ttc_k: float = attrs.field(default=1.5, converter=_to_float, validator=_check_strength)
    ttc_tau0: float = attrs.field(default=3.0, converter=_to_float, validator=_check_time)
    cp_a: float = attrs.field(default=1.0, converter=_to_float, validator=_check_strength)
    cp_b: float = attrs.field(default=0.5, converter=_to_float, validator=_check_positive)
    cp_t_min: float = attrs.field(default=0.1, converter=_to_float, validator=_check_time)
    cp_t_max: float = attrs.field(default=4.0, converter=_to_float, validator=_check_time)
    ell_a: float = attrs.field(default=7.93, converter=_to_float, validator=_check_strength)
    ell_b: float = attrs.field(default=0.99, converter=_to_float, validator=_check_positive)
    ell_dt: float = attrs.field(default=1.0, converter=_to_float, validator=_check_duration)
    robot_force_cap: float = attrs.field(default=20.0, converter=_to_float, validator=_check_cap)
    ss_a: float = attrs.field(default=0.2, converter=_to_float, validator=_check_strength)
    ss_miss: float = attrs.field(default=0.75, converter=_to_float, validator=_check_positive)
    ss_horizon: float = attrs.field(default=3.5, converter=_to_float, validator=_check_time)
    ss_speed_gain: float = attrs.field(default=0.0, converter=_to_float, validator=_check_gain)

    def __attrs_post_init__(self) -> None:
        if self.cp_t_max < self.cp_t_min:
            raise ParameterError(
                f"cp_t_max must be >= cp_t_min ({self.cp_t_min!r} s), got {plain(self.cp_t_max)}"
            )

    @classmethod
    def preset(cls, name: str) -> SRFMParams:
        """Return a named preset (``agrawal2024``, ``ferrer2013``, ``navwareset2025`` or
        ``navwareset2026_ttc``)."""
        try:
            return PRESETS[name]
        except (KeyError, TypeError):
            known = ", ".join(sorted(PRESETS))
            raise ParameterError(
                f"unknown parameter preset {plain(name)}; known: {known}"
            ) from None

    def replace(self, **changes: Any) -> SRFMParams:
        """A copy with some fields changed (validated again)."""
        unknown = sorted(set(changes) - set(attrs.fields_dict(SRFMParams)))
        if unknown:
            raise ParameterError(f"unknown SRFM parameter {plain(unknown[0])}")
        return attrs.evolve(self, **changes)

    def for_kernels(self) -> SRFMKernelParams:
        """The parameters as the kernels take them (built once per instance)."""
        return self._kernel_params

    @functools.cached_property
    def _kernel_params(self) -> SRFMKernelParams:
        values = {name: getattr(self, name) for name in SRFMKernelParams._fields}
        values["robot_form"] = ROBOT_FORMS.index(self.robot_form)
        return SRFMKernelParams(**values)

    def as_array(self) -> NDArray[np.float64]:
        """The kernel parameters as a float64 vector, in the order of
        ``SRFMKernelParams._fields`` (the form as its code)."""
        return np.array(self.for_kernels(), dtype=np.float64)

    def as_dict(self) -> dict[str, float | str]:
        """Field name -> value of the fields that define the model: the paper's nine
        (``a_ped`` … ``b_obs``) and, for a robot form other than the paper's
        exponential one, ``robot_form`` and that form's own fields (:data:`FORM_FIELDS`).

        A parameter set of the paper's model is therefore written (parameter files,
        benchmark manifests, logs) as before the other forms existed, and
        ``SRFMParams(**p.as_dict())`` is a model that moves every pedestrian as ``p``.
        """
        names = list(_PAPER_FIELDS)
        if self.robot_form != "exponential":
            names.append("robot_form")
            names += [f for f in FORM_FIELDS[self.robot_form] if f not in names]
        return {name: getattr(self, name) for name in names}


PRESETS: Final[dict[str, SRFMParams]] = {
    # Agrawal, Dengler, Bennewitz 2024, Table 1 (fitted on JRDB).
    "agrawal2024": SRFMParams(),
    # Ferrer, Garrell, Sanfeliu 2013, as quoted in the paper's Table 1; they give one
    # (A, B) pair for people and robot alike.
    "ferrer2013": SRFMParams(
        a_ped=2.66, b_ped=0.79, lambda_ped=0.59, tau=0.43, a_robot=2.66, b_robot=0.79
    ),
}
"""Named SRFM parameter sets (:meth:`SRFMParams.preset`, ``--params NAME``):
``agrawal2024`` (the paper's Table 1, fitted on JRDB; the default), ``ferrer2013`` (one
A = 2.66 m/s², B = 0.79 m for people and robot alike) and the presets srfm made from
real data, shipped as parameter files in ``srfm/models/presets/`` with the fit's
provenance in their ``[meta]`` (:func:`preset_meta`): ``navwareset2025`` (NavWareSet's
own pedestrian part and the paper's exponential robot force fitted on its encounters)
and ``navwareset2026_ttc`` (the same pedestrian part and the time-to-collision robot
force at default parameters, chosen by a held-out test: not fitted, the fit did not
move them; docs/real_encounters.md, part 4). Strengths in m/s², ranges in m, τ in s (docs/model.md,
docs/fitting.md)."""


def load_params(path: str | Path) -> SRFMParams:
    """Read a parameter file written by :func:`save_params` (or by hand).

    The file is TOML: ``schema_version = 1``, an optional ``preset = "name"`` to start
    from, and a ``[params]`` table with any subset of the :class:`SRFMParams` fields
    (the robot force's form as ``robot_form = "ttc"``, with that form's fields).
    Unknown keys and malformed values raise :class:`ParameterError` naming the file.
    """
    path = Path(path)
    # the one reader of input files: a regular file of bounded size, UTF-8 (BOM allowed)
    text = read_input_text(
        path, max_bytes=MAX_TOML_BYTES, error=ParameterError, what="parameter file"
    )
    data = parse_toml(text, path, ParameterError)
    unknown = sorted(set(data) - {"schema_version", "preset", "params", "meta"})
    if unknown:
        raise ParameterError(f"{path}: unknown key {unknown[0]!r}")
    version = data.get("schema_version")
    if type(version) is not int or version != PARAMS_SCHEMA_VERSION:
        raise ParameterError(
            f"{path}: schema_version must be {PARAMS_SCHEMA_VERSION}, got {plain(version)}"
        )
    values = data.get("params", {})
    if not isinstance(values, dict):
        raise ParameterError(f"{path}: [params] must be a table, got {plain(values)}")
    try:
        base = SRFMParams.preset(data["preset"]) if "preset" in data else SRFMParams()
        return base.replace(**values)
    except ParameterError as exc:
        raise ParameterError(f"{path}: {exc}") from None


def save_params(params: SRFMParams, path: str | Path, meta: dict[str, Any] | None = None) -> None:
    """Write ``params`` as a TOML parameter file, atomically (temporary file + rename).

    Args:
        params: the parameters.
        path: destination file.
        meta: optional ``[meta]`` table of strings, integers, floats and booleans
            (provenance: data, date, residual, ...).

    Raises:
        ParameterError: a meta value is not a finite scalar.
    """
    path = Path(path)
    lines = [f"schema_version = {PARAMS_SCHEMA_VERSION}", ""]
    if meta:
        lines.append("[meta]")
        for key, value in meta.items():
            lines.append(f"{json.dumps(str(key))} = {_toml_scalar(key, value)}")
        lines.append("")
    lines.append("[params]")
    for key, value in params.as_dict().items():
        lines.append(f"{key} = {json.dumps(value) if isinstance(value, str) else repr(value)}")
    text = "\n".join(lines) + "\n"
    if tomllib.loads(text).get("meta", {}) != (meta or {}):  # e.g. non-string keys
        raise ParameterError(f"{path}: meta does not round-trip through TOML: {meta!r}")
    atomic_write_text(path, text)


def _toml_scalar(key: Any, value: Any) -> str:
    if isinstance(value, float | np.floating) and not isinstance(value, bool):
        finite_float(value, f"meta value {key!r}", ParameterError)
    text = toml_scalar(value)
    if text is not None:
        return text
    raise ParameterError(
        f"meta value {key!r} must be a string, integer, float or boolean, got {plain(value)}"
    )


def _packaged_presets() -> dict[str, Path]:
    """The parameter files of the real-data presets, by name (``srfm/models/presets``)."""
    folder = resources.files("srfm.models").joinpath("presets")
    return {
        item.name.removesuffix(".toml"): Path(str(item))
        for item in sorted(folder.iterdir(), key=lambda t: t.name)
        if item.name.endswith(".toml")
    }


def preset_meta(name: str) -> dict[str, Any]:
    """The ``[meta]`` table of a real-data preset: where its numbers come from (data,
    windows, fit, held-out results, the command that reproduces it). Empty for the
    published presets (``agrawal2024``, ``ferrer2013``), which carry no file.

    Raises:
        ParameterError: an unknown preset name.
    """
    SRFMParams.preset(name)  # an unknown name is an error naming the known ones
    path = _packaged_presets().get(name)
    if path is None:
        return {}
    meta = tomllib.loads(path.read_text(encoding="utf-8")).get("meta", {})
    return dict(meta)


PRESETS.update({name: load_params(path) for name, path in _packaged_presets().items()})


def response_model_name(params: SRFMParams) -> str:
    """How tables and pages name the model of the pedestrians' response to the robot:
    the preset ``params`` equals, else ``custom parameters (<form> robot force)``."""
    for name, preset in PRESETS.items():
        if preset == params:
            return name
    return f"custom parameters ({params.robot_form} robot force)"
