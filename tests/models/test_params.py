"""SRFM parameters: presets, immutability, validation, parameter files; state validation."""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import attrs
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

import srfm
from srfm.models import _kernels
from srfm.models import params as params_module
from srfm.models._arrays import CrowdArrays, ForceContext, ObstacleArrays
from tests.models import _reference as ref

FIELDS = (
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

# --------------------------------------------------------------------------------------
# Presets.


def test_agrawal2024_preset_is_paper_table_1() -> None:
    p = srfm.SRFMParams.preset("agrawal2024")
    assert (p.a_ped, p.b_ped, p.lambda_ped, p.tau) == (2.0, 0.89, 0.4, 0.6)
    assert (p.a_robot, p.b_robot, p.lambda_robot) == (7.93, 0.99, 1.0)


def test_ferrer2013_preset_is_paper_table_1() -> None:
    p = srfm.SRFMParams.preset("ferrer2013")
    assert (p.a_ped, p.b_ped, p.lambda_ped, p.tau) == (2.66, 0.79, 0.59, 0.43)
    assert (p.a_robot, p.b_robot, p.lambda_robot) == (2.66, 0.79, 1.0)


def test_default_is_agrawal2024() -> None:
    assert srfm.SRFMParams() == srfm.SRFMParams.preset("agrawal2024")
    assert srfm.PRESETS["agrawal2024"] == srfm.SRFMParams()
    assert srfm.SRFMParams() != srfm.SRFMParams.preset("ferrer2013")


def test_obstacle_defaults_are_helbing2000_and_robot_isotropic() -> None:
    # Helbing, Farkas, Vicsek 2000: A = 2000 N / 80 kg, B = 0.08 m (documented defaults).
    p = srfm.SRFMParams()
    assert (p.a_obs, p.b_obs, p.lambda_robot) == (25.0, 0.08, 1.0)


def test_presets_share_obstacle_parameters() -> None:
    a, f = srfm.PRESETS["agrawal2024"], srfm.PRESETS["ferrer2013"]
    assert (a.a_obs, a.b_obs) == (f.a_obs, f.b_obs)


def test_unknown_preset_raises_naming_it() -> None:
    with pytest.raises(srfm.ParameterError, match=r"'helbing1995'.*agrawal2024, ferrer2013"):
        srfm.SRFMParams.preset("helbing1995")


# --------------------------------------------------------------------------------------
# Frozen and keyword-only.


@pytest.mark.parametrize("name", FIELDS)
def test_params_are_frozen(name: str) -> None:
    p = srfm.SRFMParams()
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        setattr(p, name, 1.0)
    assert getattr(p, name) == getattr(srfm.SRFMParams(), name)


def test_presets_cannot_be_altered_through_an_instance() -> None:
    p = srfm.SRFMParams.preset("agrawal2024")
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        p.a_ped = 9.0  # type: ignore[misc]
    assert srfm.PRESETS["agrawal2024"].a_ped == 2.0


def test_params_are_keyword_only() -> None:
    with pytest.raises(TypeError):
        srfm.SRFMParams(2.0)  # type: ignore[misc]
    with pytest.raises(TypeError):
        srfm.SRFMParams(2.0, 0.89, 0.4, 0.6, 7.93, 0.99, 1.0, 25.0, 0.08)  # type: ignore[misc]


def test_params_are_hashable_and_compare_by_value() -> None:
    assert hash(srfm.SRFMParams(tau=0.5)) == hash(srfm.SRFMParams(tau=0.5))
    assert srfm.SRFMParams(tau=0.5) == srfm.SRFMParams(tau=0.5)
    assert srfm.SRFMParams(tau=0.5) != srfm.SRFMParams(tau=0.51)


def test_replace_returns_a_validated_copy() -> None:
    p = srfm.SRFMParams()
    q = p.replace(lambda_ped=1.0, a_robot=0.0)
    assert (q.lambda_ped, q.a_robot, p.lambda_ped, p.a_robot) == (1.0, 0.0, 0.4, 7.93)
    with pytest.raises(srfm.ParameterError, match=r"tau.*-1\.0"):
        p.replace(tau=-1.0)
    with pytest.raises(srfm.ParameterError, match=r"'gamma'"):
        p.replace(gamma=1.0)


def test_integers_and_numpy_scalars_are_converted_to_float() -> None:
    p = srfm.SRFMParams(a_ped=3, b_ped=np.float32(0.5), tau=np.int64(1))
    assert type(p.a_ped) is float
    assert p.a_ped == 3.0
    assert type(p.b_ped) is float
    assert p.b_ped == pytest.approx(0.5)
    assert type(p.tau) is float
    assert p.tau == 1.0


def test_as_array_follows_the_kernel_layout() -> None:
    p = srfm.SRFMParams(
        a_ped=1.0,
        b_ped=2.0,
        lambda_ped=0.3,
        tau=4.0,
        a_robot=5.0,
        b_robot=6.0,
        lambda_robot=0.7,
        a_obs=8.0,
        b_obs=9.0,
    )
    arr = p.as_array()
    index = params_module.SRFMKernelParams._fields.index
    assert arr.dtype == np.float64
    assert arr.shape == (len(params_module.SRFMKernelParams._fields),)
    assert arr[index("a_ped")] == 1.0
    assert arr[index("b_ped")] == 2.0
    assert arr[index("lambda_ped")] == 0.3
    assert arr[index("tau")] == 4.0
    assert arr[index("a_robot")] == 5.0
    assert arr[index("b_robot")] == 6.0
    assert arr[index("lambda_robot")] == 0.7
    assert arr[index("a_obs")] == 8.0
    assert arr[index("b_obs")] == 9.0
    assert list(p.as_dict()) == list(FIELDS)


def test_kernel_tuple_array_and_attributes_share_one_layout() -> None:
    # Distinct values, so that any two fields swapped would show.
    floats = [n for n in attrs.fields_dict(srfm.SRFMParams) if n != "robot_form"]
    values = {name: 0.1 * (k + 1) for k, name in enumerate(floats)}
    values["cp_t_max"] = 10.0  # >= cp_t_min
    p = srfm.SRFMParams(robot_form="elliptical", **values)
    kp = p.for_kernels()
    assert isinstance(kp, params_module.SRFMKernelParams)
    assert kp._fields[: len(FIELDS)] == FIELDS  # the paper's nine first
    assert kp._fields == tuple(attrs.fields_dict(srfm.SRFMParams))
    code = params_module.ROBOT_FORMS.index("elliptical")
    assert kp == tuple(code if n == "robot_form" else getattr(p, n) for n in kp._fields)
    assert all(type(v) is float for n, v in zip(kp._fields, kp, strict=True) if n != "robot_form")
    assert type(kp.robot_form) is int
    np.testing.assert_array_equal(p.as_array(), np.array(kp, dtype=np.float64))
    assert p.for_kernels() is kp  # built once per instance
    assert p.replace(tau=2.0).for_kernels().tau == 2.0


def test_kernel_reads_the_tuple_by_name_like_its_python_body() -> None:
    # Every parameter changes the forces of this scene; jitted and pure-Python kernels
    # (attribute access on the NamedTuple in both) give the same components.
    values = (1.5, 0.7, 0.2, 0.8, 4.0, 0.6, 0.5, 10.0, 0.2)
    p = srfm.SRFMParams(**dict(zip(FIELDS, values, strict=True)))
    pos = np.array([[0.0, 0.0], [0.6, 0.2], [1.0, -0.5]])
    vel = np.array([[0.5, 0.0], [0.0, 0.3], [-0.2, 0.1]])
    goal = np.array([[5.0, 0.0], [0.0, 5.0], [-5.0, 0.0]])
    radius = np.full(3, 0.25)
    v0 = np.full(3, 1.2)
    robot = np.array([0.3, -0.4, 0.3, 0.2, -0.1])
    segments = np.array([[-2.0, -0.8, 2.0, -0.8]])
    circles = np.array([[0.5, 0.6, 0.1]])
    crowd = CrowdArrays(pos, vel, goal, radius, v0, v0.copy())
    obstacles = ObstacleArrays(segments, circles, circles[:, :2].copy(), circles[:, 2].copy())
    context = ForceContext(p.for_kernels(), robot, True, obstacles, np.full(2, np.inf))
    jit_out = np.zeros((4, 3, 2))
    py_out = np.zeros((4, 3, 2))
    _kernels.force_components_kernel(crowd, context, jit_out)
    _kernels.force_components_kernel.py_func(crowd, context, py_out)
    np.testing.assert_allclose(py_out, jit_out, rtol=1e-13, atol=0.0)
    assert np.all(np.linalg.norm(jit_out, axis=2) > 0.0)  # every component on every agent
    for name in FIELDS:  # each field is read (a change of it changes the forces)
        other = np.zeros((4, 3, 2))
        changed = p.replace(**{name: getattr(p, name) * 0.9})
        changed_context = context._replace(params=changed.for_kernels())
        _kernels.force_components_kernel(crowd, changed_context, other)
        assert not np.array_equal(other, jit_out), name


# --------------------------------------------------------------------------------------
# Validation.

NAN, INF = float("nan"), float("inf")
POSITIVE = ("b_ped", "tau", "b_robot", "b_obs")
NON_NEGATIVE = ("a_ped", "a_robot", "a_obs")
UNIT = ("lambda_ped", "lambda_robot")

INVALID = (
    [(name, value, text) for name in POSITIVE for value, text in [(0.0, "0.0"), (-0.5, "-0.5")]]
    + [(name, -1, "-1.0") for name in NON_NEGATIVE]
    + [(name, -1e-9, "-1e-09") for name in NON_NEGATIVE]
    + [(name, value, text) for name in UNIT for value, text in [(-0.1, "-0.1"), (1.5, "1.5")]]
    + [(name, NAN, "nan") for name in FIELDS]
    + [(name, INF, "inf") for name in FIELDS]
    + [(name, -INF, "-inf") for name in FIELDS]
    + [(name, "0.5", "'0.5'") for name in FIELDS]
    + [(name, None, "None") for name in FIELDS]
    + [(name, True, "True") for name in FIELDS]
    + [(name, [1.0], r"\[1.0\]") for name in ("a_ped", "tau")]
)


@pytest.mark.parametrize(("name", "value", "text"), INVALID)
def test_invalid_value_raises_naming_parameter_and_value(name, value, text) -> None:
    pattern = rf"\b{name}\b.*{text}"
    with pytest.raises(srfm.ParameterError, match=pattern):
        srfm.SRFMParams(**{name: value})
    # Also a ValueError, and the same through replace().
    with pytest.raises(ValueError, match=pattern):
        srfm.SRFMParams().replace(**{name: value})


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("a_ped", 0.0),
        ("a_robot", 0.0),
        ("a_obs", 0.0),
        ("lambda_ped", 0.0),
        ("lambda_ped", 1.0),
        ("lambda_robot", 0.0),
        ("lambda_robot", 1.0),
        ("b_ped", 1e-6),
        ("tau", 1e-3),
        ("a_robot", 1e6),
        ("a_ped", 1e6),
        ("a_obs", 1e6),
    ],
)
def test_boundary_values_are_accepted(name: str, value: float) -> None:
    assert getattr(srfm.SRFMParams(**{name: value}), name) == value


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("tau", 1e-6, r"tau must be >= 0\.001 s, got 1e-06"),
        ("a_ped", 1e7, r"a_ped must be <= 1e\+06, got 10000000\.0"),
        ("a_robot", 2e6, r"a_robot must be <= 1e\+06"),
        ("a_obs", 1e300, r"a_obs must be <= 1e\+06"),
    ],
)
def test_bounds_that_keep_forces_finite(name: str, value: float, message: str) -> None:
    with pytest.raises(srfm.ParameterError, match=message):
        srfm.SRFMParams(**{name: value})


def test_parameter_error_is_an_srfm_error_and_a_value_error() -> None:
    assert issubclass(srfm.ParameterError, srfm.SrfmError)
    assert issubclass(srfm.ParameterError, ValueError)
    assert issubclass(srfm.SimulationError, ValueError)


# --------------------------------------------------------------------------------------
# Crowd state and obstacle validation.


@pytest.mark.parametrize("name", ["radius", "v0", "vmax"])
def test_negative_per_agent_values_raise(name: str) -> None:
    values = [0.3, -0.25, 0.3]
    with pytest.raises(srfm.SimulationError, match=rf"{name}.*-0\.25.*pedestrian 1"):
        srfm.CrowdState.create(pos=np.zeros((3, 2)), goal=np.ones((3, 2)), **{name: values})


def test_negative_scalar_radius_raises() -> None:
    with pytest.raises(srfm.SimulationError, match=r"radius.*-0\.3"):
        srfm.CrowdState.create(pos=np.zeros((2, 2)), goal=np.ones((2, 2)), radius=-0.3)


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"pos": [[0.0, float("nan")]], "goal": [[1.0, 1.0]]}, r"pos.*nan"),
        ({"pos": [[0.0, 0.0]], "goal": [[1.0, float("inf")]]}, r"goal.*inf"),
        ({"pos": [[0.0, 0.0, 0.0]], "goal": [[1.0, 1.0]]}, r"pos.*shape"),
        ({"pos": [[0.0, 0.0]], "goal": [[1.0, 1.0], [2.0, 2.0]]}, r"goal.*shape"),
        ({"pos": [[0.0, 0.0]], "goal": [[1.0, 1.0]], "vel": [[1.0, "x"]]}, r"vel"),
        ({"pos": [[0.0, 0.0]], "goal": [[1.0, 1.0]], "radius": [0.3, 0.3]}, r"radius.*shape"),
        ({"pos": [[0.0, 0.0]], "goal": [[1.0, 1.0]], "v0": float("nan")}, r"v0.*nan"),
    ],
)
def test_malformed_crowd_raises(kwargs, pattern) -> None:
    with pytest.raises(srfm.SimulationError, match=pattern):
        srfm.CrowdState.create(**kwargs)


def test_crowd_defaults_and_copies() -> None:
    radius = np.array([0.3, 0.2])
    c = srfm.CrowdState.create(pos=[[0, 0], [1, 1]], goal=[[2, 2], [3, 3]], radius=radius, v0=1.0)
    np.testing.assert_array_equal(c.vel, 0.0)
    np.testing.assert_array_equal(c.vmax, c.v0)
    radius[0] = 9.0
    assert c.radius[0] == 0.3  # the crowd owns its arrays
    for name in ("pos", "vel", "goal", "radius", "v0", "vmax"):
        arr = getattr(c, name)
        assert arr.dtype == np.float64
        assert arr.flags.c_contiguous


def test_negative_pillar_radius_raises() -> None:
    with pytest.raises(srfm.SimulationError, match=r"pillar radius.*-0\.1 at index 1"):
        srfm.Obstacles.create(circles=[[0.0, 0.0, 0.5], [1.0, 1.0, -0.1]])


def test_malformed_walls_raise() -> None:
    with pytest.raises(srfm.SimulationError, match=r"segments.*shape"):
        srfm.Obstacles.create(segments=[[0.0, 0.0, 1.0]])
    with pytest.raises(srfm.SimulationError, match=r"segments.*nan"):
        srfm.Obstacles.create(segments=[[0.0, 0.0, 1.0, float("nan")]])


# --------------------------------------------------------------------------------------
# Parameter files.


@pytest.mark.parametrize("name", sorted(srfm.PRESETS))
def test_save_load_round_trip_presets(tmp_path: Path, name: str) -> None:
    path = tmp_path / "params.toml"
    srfm.save_params(srfm.PRESETS[name], path)
    assert srfm.load_params(path) == srfm.PRESETS[name]
    assert srfm.load_params(str(path)) == srfm.PRESETS[name]


@settings(
    deadline=None, max_examples=40, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(p=ref.params_values())
def test_save_load_round_trip_is_exact(tmp_path: Path, p: srfm.SRFMParams) -> None:
    path = tmp_path / "sub" / "fitted.toml"
    srfm.save_params(p, path, meta={"source": 'JRDB "train" \\ split', "tracks": 42, "ok": True})
    q = srfm.load_params(path)
    assert q == p
    np.testing.assert_array_equal(q.as_array(), p.as_array())


def test_saved_file_is_readable_toml(tmp_path: Path) -> None:
    import tomllib

    path = tmp_path / "p.toml"
    srfm.save_params(srfm.SRFMParams(tau=0.5), path, meta={"rmse": 0.59})
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    assert data["schema_version"] == 1
    assert data["meta"] == {"rmse": 0.59}
    assert data["params"]["tau"] == 0.5
    assert set(data["params"]) == set(FIELDS)
    assert [p.name for p in tmp_path.iterdir()] == ["p.toml"]  # no temporary left behind


def test_save_overwrites(tmp_path: Path) -> None:
    path = tmp_path / "p.toml"
    srfm.save_params(srfm.SRFMParams(tau=0.5), path)
    srfm.save_params(srfm.SRFMParams(tau=0.7), path)
    assert srfm.load_params(path).tau == 0.7


def test_non_finite_meta_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(srfm.ParameterError, match="nan"):
        srfm.save_params(srfm.SRFMParams(), tmp_path / "p.toml", meta={"rmse": float("nan")})


def _write(tmp_path: Path, text: str, name: str = "params.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_load_partial_file_starts_from_preset(tmp_path: Path) -> None:
    path = _write(tmp_path, 'schema_version = 1\npreset = "ferrer2013"\n[params]\ntau = 0.5\n')
    assert srfm.load_params(path) == srfm.PRESETS["ferrer2013"].replace(tau=0.5)
    path = _write(tmp_path, "schema_version = 1\n[params]\nlambda_robot = 0.25\n")
    assert srfm.load_params(path) == srfm.SRFMParams(lambda_robot=0.25)
    path = _write(tmp_path, "schema_version = 1\n")
    assert srfm.load_params(path) == srfm.SRFMParams()


def test_load_accepts_integer_values(tmp_path: Path) -> None:
    path = _write(tmp_path, "schema_version = 1\n[params]\na_ped = 3\n")
    p = srfm.load_params(path)
    assert p.a_ped == 3.0
    assert type(p.a_ped) is float


MALFORMED = [
    ("unknown-top-level-key", "schema_version = 1\nalpha = 2\n", r"'alpha'"),
    ("unknown-param", "schema_version = 1\n[params]\ngamma = 1.0\n", r"'gamma'"),
    ("negative-b", "schema_version = 1\n[params]\nb_ped = -0.5\n", r"b_ped.*-0\.5"),
    ("lambda-too-big", "schema_version = 1\n[params]\nlambda_ped = 2.0\n", r"lambda_ped.*2\.0"),
    ("nan", "schema_version = 1\n[params]\ntau = nan\n", r"tau.*nan"),
    ("inf", "schema_version = 1\n[params]\na_robot = inf\n", r"a_robot.*inf"),
    ("string-value", 'schema_version = 1\n[params]\ntau = "fast"\n', r"tau.*'fast'"),
    ("bool-value", "schema_version = 1\n[params]\na_ped = true\n", r"a_ped.*True"),
    ("params-not-table", "schema_version = 1\nparams = 3\n", r"params.*3"),
    ("schema-2", "schema_version = 2\n[params]\ntau = 0.5\n", r"schema_version.*2"),
    ("schema-string", 'schema_version = "1"\n', r"schema_version.*'1'"),
    ("schema-missing", "[params]\ntau = 0.5\n", r"schema_version.*None"),
    ("not-toml", "this is = not [toml\n", r"TOML"),
    ("empty-key", "= 1\n", r"TOML"),
]


@pytest.mark.parametrize(
    ("text", "pattern"), [m[1:] for m in MALFORMED], ids=[m[0] for m in MALFORMED]
)
def test_malformed_file_raises_naming_the_file(tmp_path: Path, text: str, pattern: str) -> None:
    path = _write(tmp_path, text, name="bad-params.toml")
    with pytest.raises(srfm.ParameterError, match=re.escape(str(path)) + ".*" + pattern):
        srfm.load_params(path)


def test_binary_file_raises_naming_the_file(tmp_path: Path) -> None:
    path = tmp_path / "weights.bin"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(srfm.ParameterError, match=re.escape(str(path))):
        srfm.load_params(path)


def test_missing_file_raises_naming_the_file(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.toml"
    with pytest.raises(srfm.ParameterError, match=re.escape(str(path)) + ".*not found"):
        srfm.load_params(path)


# srfm bug: load_params looks the preset up outside its try block, so a bad preset
# raises without the file name, and an unhashable one raises TypeError.
@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ('schema_version = 1\npreset = "helbing1995"\n', r"'helbing1995'"),
        ("schema_version = 1\npreset = 5\n", r"preset.*5"),
        ('schema_version = 1\npreset = ["agrawal2024"]\n', r"preset.*agrawal2024"),
    ],
    ids=["unknown-name", "number", "list"],
)
def test_bad_preset_in_file_raises_naming_the_file(tmp_path: Path, text: str, pattern) -> None:
    path = _write(tmp_path, text, name="bad-preset.toml")
    with pytest.raises(srfm.ParameterError, match=re.escape(str(path)) + ".*" + pattern):
        srfm.load_params(path)


# srfm bug: load_params compares with !=, and True == 1.0 == 1 in Python.
@pytest.mark.parametrize("version", ["true", "1.0"])
def test_schema_version_must_be_the_integer_one(tmp_path: Path, version: str) -> None:
    path = _write(tmp_path, f"schema_version = {version}\n", name="loose.toml")
    with pytest.raises(srfm.ParameterError, match=re.escape(str(path)) + ".*schema_version"):
        srfm.load_params(path)


def test_extreme_values_round_trip(tmp_path: Path) -> None:
    # Huge and tiny but valid values are accepted and the file keeps them exactly.
    p = srfm.SRFMParams(a_robot=1e6, b_obs=math.ulp(0.0) * 2**60)
    path = tmp_path / "extreme.toml"
    srfm.save_params(p, path)
    assert srfm.load_params(path) == p


def test_save_params_meta_round_trips_awkward_keys_and_values(tmp_path: Path) -> None:
    meta = {"fit date": "2026-11-21", "note": 'two\nlines "quoted" é', "n": 2**60 + 1, "ok": True}
    path = tmp_path / "p.toml"
    srfm.save_params(srfm.SRFMParams(), path, meta=meta)
    assert tomllib.loads(path.read_text())["meta"] == meta
    assert srfm.load_params(path) == srfm.SRFMParams()


def test_save_params_rejects_non_scalar_meta_and_keeps_the_old_file(tmp_path: Path) -> None:
    path = tmp_path / "p.toml"
    srfm.save_params(srfm.SRFMParams(tau=0.5), path)
    before = path.read_bytes()
    with pytest.raises(srfm.ParameterError, match=r"meta value 'tracks' must be a string"):
        srfm.save_params(srfm.SRFMParams(), path, meta={"tracks": [1, 2]})
    with pytest.raises(srfm.ParameterError, match="meta value 'rmse'"):
        srfm.save_params(srfm.SRFMParams(), path, meta={"rmse": float("nan")})
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.toml"]


def test_load_params_on_a_folder(tmp_path: Path) -> None:
    with pytest.raises(srfm.ParameterError, match="is a folder, expected a parameter file"):
        srfm.load_params(tmp_path)


def test_load_params_reads_like_every_input(tmp_path: Path) -> None:
    """The shared reader (srfm._io.read_input_text): a BOM is fine, other encodings
    and missing files get a message naming the file."""
    path = tmp_path / "p.toml"
    srfm.save_params(srfm.SRFMParams(a_robot=0.5), path)
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    assert srfm.load_params(bom).a_robot == 0.5
    latin = tmp_path / "latin.toml"
    latin.write_bytes(path.read_bytes() + "# caf\u00e9\n".encode("latin-1"))
    with pytest.raises(srfm.ParameterError, match=r"latin\.toml: not UTF-8"):
        srfm.load_params(latin)
    with pytest.raises(srfm.ParameterError, match=r"missing\.toml: parameter file not found"):
        srfm.load_params(tmp_path / "missing.toml")
