"""TD3 policies as planners: ``td3-srfm``, ``td3-base``, and any policy you train.

Two kinds of policy file:

- **NumPy policy files** (what ``srfm/policies/`` ships, and what
  ``srfm export-policy`` writes): the actor's weights in ``<stem>.npz`` and its
  metadata in ``<stem>.json`` (format and observation layout versions, the
  :class:`EnvConfig` with the kinematics, the action scaling, the training
  configuration and seed, evaluation figures). Loading needs NumPy only: no torch,
  stable-baselines3, gymnasium, and no pickle (``np.load(allow_pickle=False)`` and
  :mod:`json`). Everything is validated on load and a bad file is named with what is
  wrong (:class:`~srfm.errors.PlannerError`).
- **Training checkpoints**: the stable-baselines3 (or SBX) ``TD3`` zips written by
  ``srfm train``. They are read with SB3's loader, **which unpickles Python objects and
  can therefore execute arbitrary code: load only checkpoints from a source you
  trust** (a :class:`UserWarning` says so on every load). Export one with
  ``srfm export-policy`` to get a NumPy policy file.

Either way the planner runs the actor in NumPy (float32, one numba call per layer), so
a step costs microseconds. The observation is built by the environment's own kernel
(:class:`srfm.planners._observation.ObservationBuilder`), so a policy sees in
evaluation exactly what it saw in training. This module never imports the
environment (:mod:`srfm.rl`) or gymnasium; torch / SB3 / SBX only to read a zip.
"""

from __future__ import annotations

import hashlib
import json
import threading
import warnings
import zipfile
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np
from numba import njit
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import MissingDependencyError, PlannerError
from srfm.models.robot import KINEMATICS
from srfm.planners._base import FloatArray, Observation, PlannerContext
from srfm.planners._observation import EnvConfig, ObservationBuilder

__all__ = [
    "ACTION_SIZE",
    "OBSERVATION_LAYOUT_VERSION",
    "POLICY_FORMAT",
    "POLICY_FORMAT_VERSION",
    "SHIPPED_POLICIES",
    "NumpyActor",
    "NumpyPolicy",
    "PolicyPlanner",
    "TD3Planner",
    "checkpoint_backend",
    "load_checkpoint",
    "load_numpy_policy",
    "load_policy",
    "read_policy_config",
    "save_numpy_policy",
    "shipped_policy_path",
    "td3_base",
    "td3_srfm",
]

# Registry name -> NumPy policy file (metadata JSON; the weights are <stem>.npz beside
# it) in srfm/policies/. The SB3 checkpoints they were exported from are not shipped:
# the repository keeps them as tools/rl/policies/<stem>.zip.
SHIPPED_POLICIES: Final = {"td3-srfm": "td3_srfm.json", "td3-base": "td3_base.json"}

# Identifies a NumPy policy file and the version of its layout (bump on a change of the
# files' keys or meaning).
POLICY_FORMAT: Final = "srfm-td3-actor"
POLICY_FORMAT_VERSION: Final = 1
# Version of the observation vector (the table in srfm/planners/_observation.py). Bump
# it whenever build_observation changes what an entry means: old policy files are then
# refused instead of silently fed another input.
OBSERVATION_LAYOUT_VERSION: Final = 1
ACTION_SIZE: Final = 2

F32 = NDArray[np.float32]


@njit(cache=True)
def dense_layer(wt: np.ndarray, b: np.ndarray, x: np.ndarray, y: np.ndarray, relu: bool) -> None:
    """One layer into ``y``: y = act(b + Σ_j x_j W[:, j]), float32.

    ``wt`` (in, out) is the transposed weight matrix; act is ReLU (``relu``) or tanh.
    The loop over outputs is innermost, so it vectorises without reassociating any
    sum; zero inputs (after a ReLU, about half) are skipped.
    """
    n_in = wt.shape[0]
    n_out = wt.shape[1]
    for i in range(n_out):
        y[i] = b[i]
    for j in range(n_in):
        xj = x[j]
        if xj == 0.0:
            continue
        for i in range(n_out):
            y[i] += wt[j, i] * xj
    if relu:
        for i in range(n_out):
            if y[i] < 0.0:
                y[i] = 0.0
    else:
        for i in range(n_out):
            y[i] = np.tanh(y[i])


@attrs.frozen(eq=False)
class NumpyActor:
    """A TD3 actor as float32 layers: ReLU between layers, tanh at the end.

    The forward pass runs one numba call per layer (:func:`dense_layer`); it equals
    torch's within float32 rounding (the sums are taken in another order).

    Attributes:
        weights: per layer (out, in) matrices.
        biases: per layer (out,) vectors.
    """

    weights: tuple[F32, ...]
    biases: tuple[F32, ...]
    _layers: tuple[tuple[F32, F32, F32, bool], ...] = attrs.field(init=False)

    def __attrs_post_init__(self) -> None:
        last = len(self.weights) - 1
        layers = tuple(
            (
                np.ascontiguousarray(w.T, dtype=np.float32),
                np.ascontiguousarray(b, dtype=np.float32),
                np.zeros(w.shape[0], dtype=np.float32),
                k < last,
            )
            for k, (w, b) in enumerate(zip(self.weights, self.biases, strict=True))
        )
        object.__setattr__(self, "_layers", layers)

    @property
    def obs_size(self) -> int:
        """Length of the observation the actor takes."""
        return int(self.weights[0].shape[1])

    def forward(self, obs: F32) -> F32:
        """The action in [−1, 1]² for one observation (float32)."""
        x = obs
        for wt, b, y, relu in self._layers:
            dense_layer(wt, b, x, y, relu)
            x = y
        return x.copy()

    def forward_numpy(self, obs: F32) -> F32:
        """The same forward pass in plain NumPy (a reference for tests)."""
        x = obs
        last = len(self.weights) - 1
        for k, (w, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            x = w @ x
            x += b
            if k < last:
                np.maximum(x, 0.0, out=x)
        return np.tanh(x)

    @classmethod
    def from_sb3(cls, actor: Any) -> NumpyActor:
        """Copy the layers of an SB3 TD3 ``Actor`` (its ``mu`` network)."""
        import torch

        weights = []
        biases = []
        layers = list(actor.mu)
        for layer in layers:
            if isinstance(layer, torch.nn.Linear):
                weights.append(layer.weight.detach().cpu().numpy().astype(np.float32).copy())
                biases.append(layer.bias.detach().cpu().numpy().astype(np.float32).copy())
            elif not isinstance(layer, torch.nn.ReLU | torch.nn.Tanh):
                raise PlannerError(
                    f"unsupported layer {layer!r} in the TD3 actor: only Linear, ReLU and "
                    "a final Tanh (SB3's default activation) can run in NumPy"
                )
        if not isinstance(layers[-1], torch.nn.Tanh) or not all(
            isinstance(layers[i], torch.nn.ReLU) for i in range(1, len(layers) - 1, 2)
        ):
            raise PlannerError("the TD3 actor must be Linear/ReLU layers with a final Tanh")
        return cls(tuple(weights), tuple(biases))

    @classmethod
    def from_sbx(cls, params: Any) -> NumpyActor:
        """Copy the layers of an SBX TD3 actor (``model.policy.actor_state.params``).

        SBX's actor is flax ``Dense`` layers ``Dense_0 … Dense_n`` with ReLU between
        them and a final tanh; a ``kernel`` is (in, out), the transpose of torch's
        weight.
        """
        inner = params.get("params", params) if isinstance(params, Mapping) else None
        if not isinstance(inner, Mapping):
            raise PlannerError("the SBX actor parameters are not a mapping of flax layers")
        names = sorted(inner, key=lambda n: int(n.rsplit("_", 1)[-1]) if "_" in n else -1)
        if not names or any(n != f"Dense_{k}" for k, n in enumerate(names)):
            raise PlannerError(
                f"unsupported SBX actor layers {sorted(inner)}: only Dense_0 … Dense_n "
                "(SBX's default TD3 actor) can run in NumPy"
            )
        weights = tuple(
            np.ascontiguousarray(np.asarray(inner[n]["kernel"], dtype=np.float32).T) for n in names
        )
        biases = tuple(np.asarray(inner[n]["bias"], dtype=np.float32).copy() for n in names)
        return cls(weights, biases)


def _env_config_from(data: Any, source: str) -> EnvConfig:
    if not isinstance(data, dict):
        raise PlannerError(
            f"{source}: no srfm environment configuration in the policy file; "
            "train it with `srfm train`"
        )
    try:
        return EnvConfig(**data)
    except (TypeError, ValueError) as exc:
        raise PlannerError(f"{source}: bad environment configuration: {exc}") from None


def _is_numpy_policy(path: Path) -> bool:
    return path.suffix.lower() in (".json", ".npz")


def _policy_paths(path: str | Path) -> tuple[Path, Path]:
    """(metadata JSON, weights NPZ) of a NumPy policy named by either file."""
    path = Path(path)
    return path.with_suffix(".json"), path.with_suffix(".npz")


@attrs.frozen(eq=False)
class NumpyPolicy:
    """A NumPy policy file, loaded: the actor, its EnvConfig and the metadata.

    Attributes:
        actor: the network.
        config: the :class:`EnvConfig` it was trained with.
        metadata: the whole JSON document (see :func:`save_numpy_policy`).
    """

    actor: NumpyActor
    config: EnvConfig
    metadata: dict[str, Any]


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def save_numpy_policy(
    actor: NumpyActor,
    config: EnvConfig,
    path: str | Path,
    *,
    training: Mapping[str, Any] | None = None,
    evaluation: Mapping[str, Any] | None = None,
) -> tuple[Path, Path]:
    """Write a NumPy policy file: ``<stem>.npz`` (weights) and ``<stem>.json`` (metadata).

    The NPZ holds float32 arrays ``weight_k`` (out, in) and ``bias_k`` (out,) for layers
    k = 0 … n (ReLU after every layer but the last, tanh after the last). The JSON holds
    ``format``/``format_version``, ``observation_layout_version``, ``obs_size``,
    ``action_size``, ``layers`` (the (out, in) shapes), ``activations``, ``env_config``
    (the :class:`EnvConfig`, with ``kinematics``), ``action_scaling`` (how an action in
    [−1, 1]² becomes a command), ``training`` (configuration, seed, steps, source
    checkpoint; as given) and ``evaluation`` (as given, or null), and the SHA-256 of the
    NPZ, checked on load.

    Args:
        actor: the network.
        config: the :class:`EnvConfig` the policy was trained with (its kinematics set).
        path: the file name; its suffix is replaced by ``.npz`` and ``.json``.
        training: what is known of the training run (JSON-serialisable).
        evaluation: evaluation figures (JSON-serialisable).

    Returns:
        The paths of the JSON and the NPZ.

    Raises:
        PlannerError: the actor does not fit the configuration.
    """
    json_path, npz_path = _policy_paths(path)
    if config.kinematics is None:
        raise PlannerError("the policy's EnvConfig must name its kinematics")
    _check_layers(
        [w.shape for w in actor.weights],
        [b.shape for b in actor.biases],
        config.obs_size,
        str(json_path),
    )
    arrays: dict[str, F32] = {}
    for k, (w, b) in enumerate(zip(actor.weights, actor.biases, strict=True)):
        arrays[f"weight_{k}"] = np.ascontiguousarray(w, dtype=np.float32)
        arrays[f"bias_{k}"] = np.ascontiguousarray(b, dtype=np.float32)
    npz_path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(npz_path, allow_pickle=False, **arrays)
    n = len(actor.weights)
    meta: dict[str, Any] = {
        "format": POLICY_FORMAT,
        "format_version": POLICY_FORMAT_VERSION,
        "observation_layout_version": OBSERVATION_LAYOUT_VERSION,
        "obs_size": actor.obs_size,
        "action_size": ACTION_SIZE,
        "layers": [list(w.shape) for w in actor.weights],
        "activations": ["relu"] * (n - 1) + ["tanh"],
        "env_config": attrs.asdict(config),
        "kinematics": config.kinematics,
        "action_scaling": {
            "low": [-1.0, -1.0],
            "high": [1.0, 1.0],
            "unicycle": "(v, omega) = (a0 v_max, a1 omega_max)",
            "holonomic": "robot-frame (vx, vy) = (a0, a1) v_max",
            "clip": "actions are clipped to [-1, 1] before scaling",
        },
        "training": dict(training) if training is not None else None,
        "evaluation": dict(evaluation) if evaluation is not None else None,
        "weights_file": npz_path.name,
        "weights_sha256": _sha256(npz_path),
    }
    json_path.write_text(json.dumps(meta, indent=2, sort_keys=True) + "\n")
    return json_path, npz_path


def _check_layers(
    weights: list[tuple[int, ...]], biases: list[tuple[int, ...]], n_obs: int, source: str
) -> None:
    """Shapes of a chain of dense layers from ``n_obs`` inputs to the 2 actions."""
    if not weights:
        raise PlannerError(f"{source}: the actor has no layers")
    width = n_obs
    for k, (w, b) in enumerate(zip(weights, biases, strict=True)):
        if len(w) != 2 or w[1] != width:
            raise PlannerError(
                f"{source}: weight_{k} has shape {tuple(w)}, expected (out, {width})"
                + (" (the observation size)" if k == 0 else " (the previous layer's outputs)")
            )
        if tuple(b) != (w[0],):
            raise PlannerError(f"{source}: bias_{k} has shape {tuple(b)}, expected ({w[0]},)")
        width = w[0]
    if width != ACTION_SIZE:
        raise PlannerError(
            f"{source}: the last layer has {width} outputs, expected {ACTION_SIZE} (the action)"
        )


def _require(meta: Mapping[str, Any], key: str, source: str) -> Any:
    if key not in meta:
        raise PlannerError(f"{source}: metadata has no {key!r}")
    return meta[key]


def load_numpy_policy(path: str | Path) -> NumpyPolicy:
    """Load and validate a NumPy policy file (name either the ``.json`` or the ``.npz``).

    Needs NumPy only: the NPZ is read with ``allow_pickle=False`` and the metadata with
    :mod:`json`.

    Raises:
        PlannerError: a missing file, a format or observation layout version this srfm
            does not read, an invalid EnvConfig or kinematics, a weights file that is
            not the one the metadata names (SHA-256), missing or extra arrays, shapes
            that do not chain from the observation to the two actions, non-float or
            non-finite weights. The message names the file and what is wrong.
    """
    json_path, npz_path = _policy_paths(path)
    source = str(json_path)
    for p in (json_path, npz_path):
        if not p.is_file():
            raise PlannerError(f"policy file {str(p)!r} does not exist")
    try:
        meta = json.loads(json_path.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise PlannerError(f"{source}: not a JSON policy metadata file: {exc}") from None
    if not isinstance(meta, dict):
        raise PlannerError(f"{source}: the metadata must be a JSON object")
    fmt = meta.get("format")
    if fmt != POLICY_FORMAT:
        raise PlannerError(f"{source}: format is {fmt!r}, expected {POLICY_FORMAT!r}")
    version = _require(meta, "format_version", source)
    if version != POLICY_FORMAT_VERSION:
        raise PlannerError(
            f"{source}: format_version {version!r}; this srfm reads version {POLICY_FORMAT_VERSION}"
        )
    layout = _require(meta, "observation_layout_version", source)
    if layout != OBSERVATION_LAYOUT_VERSION:
        raise PlannerError(
            f"{source}: observation_layout_version {layout!r}, but this srfm builds "
            f"observation layout {OBSERVATION_LAYOUT_VERSION}: retrain or re-export the policy"
        )
    config = _env_config_from(_require(meta, "env_config", source), source)
    kinematics = _require(meta, "kinematics", source)
    if kinematics not in KINEMATICS or config.kinematics != kinematics:
        raise PlannerError(
            f"{source}: kinematics {kinematics!r} must be one of {KINEMATICS} and equal "
            f"env_config.kinematics ({config.kinematics!r})"
        )
    digest = meta.get("weights_sha256")
    if digest is not None and digest != _sha256(npz_path):
        raise PlannerError(
            f"{npz_path}: its SHA-256 differs from weights_sha256 in {json_path.name}: "
            "the weights and the metadata do not belong together"
        )
    try:
        with np.load(npz_path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise PlannerError(f"{npz_path}: cannot read the weights: {exc}") from None
    n = len(arrays) // 2
    expected = {f"{kind}_{k}" for k in range(n) for kind in ("weight", "bias")}
    if set(arrays) != expected or n == 0:
        raise PlannerError(
            f"{npz_path}: arrays {sorted(arrays)}; expected weight_0, bias_0, … weight_n, bias_n"
        )
    weights = [arrays[f"weight_{k}"] for k in range(n)]
    biases = [arrays[f"bias_{k}"] for k in range(n)]
    for name, a in arrays.items():
        if a.dtype.kind != "f":
            raise PlannerError(f"{npz_path}: {name} has dtype {a.dtype}, expected float32")
        if not np.all(np.isfinite(a)):
            raise PlannerError(f"{npz_path}: {name} holds NaN or infinite values")
    n_obs = config.obs_size
    if _require(meta, "obs_size", source) != n_obs:
        raise PlannerError(
            f"{source}: obs_size {meta['obs_size']!r} does not match env_config "
            f"(max_pedestrians {config.max_pedestrians} and range_beams "
            f"{config.range_beams} give {n_obs})"
        )
    _check_layers([w.shape for w in weights], [b.shape for b in biases], n_obs, str(npz_path))
    layers = _require(meta, "layers", source)
    if layers != [list(w.shape) for w in weights]:
        raise PlannerError(
            f"{source}: layers {layers!r} do not match the arrays in {npz_path.name} "
            f"({[list(w.shape) for w in weights]})"
        )
    activations = _require(meta, "activations", source)
    if activations != ["relu"] * (n - 1) + ["tanh"]:
        raise PlannerError(
            f"{source}: activations {activations!r}; only ReLU between layers and a final "
            "tanh are supported"
        )
    actor = NumpyActor(
        tuple(w.astype(np.float32) for w in weights), tuple(b.astype(np.float32) for b in biases)
    )
    return NumpyPolicy(actor=actor, config=config, metadata=meta)


_PICKLE_WARNING: Final = (
    "{path}: a stable-baselines3/SBX checkpoint is loaded with SB3's loader, which "
    "unpickles Python objects and can execute arbitrary code: load only files you trust "
    "(`srfm export-policy` turns a checkpoint into a NumPy policy file that needs no pickle)"
)


def _checkpoint_data(path: Path, what: str = "read a TD3 policy file") -> dict[str, Any]:
    """The JSON ``data`` member of an SB3/SBX zip (nothing unpickled, no torch)."""
    try:
        with zipfile.ZipFile(path) as archive:
            data = json.loads(archive.read("data"))
    except (OSError, zipfile.BadZipFile, KeyError, ValueError) as exc:
        raise PlannerError(f"{path}: cannot {what}: {exc}") from None
    if not isinstance(data, dict):
        raise PlannerError(f"{path}: cannot {what}: no SB3 data")
    return data


def checkpoint_backend(path: str | Path, what: str = "read a TD3 policy file") -> str:
    """``"sbx"`` or ``"sb3"``: the library that wrote a checkpoint zip (read from its
    JSON, nothing unpickled)."""
    policy_class = _checkpoint_data(Path(path), what).get("policy_class")
    module = policy_class.get("__module__", "") if isinstance(policy_class, dict) else ""
    return "sbx" if str(module).startswith("sbx") else "sb3"


def read_policy_config(path: str | Path) -> EnvConfig:
    """The :class:`EnvConfig` recorded in a policy file, without loading the policy.

    A NumPy policy file's JSON, or an SB3/SBX zip's member ``data`` (JSON, where
    ``srfm train`` records the configuration as a plain mapping), read with
    :mod:`zipfile` and :mod:`json` only: nothing is unpickled, and neither torch nor
    stable-baselines3 is imported.

    Raises:
        PlannerError: missing file, not a policy file, or no srfm configuration in it.
    """
    path = Path(path)
    if _is_numpy_policy(path):
        json_path = path.with_suffix(".json")
        if not json_path.is_file():
            raise PlannerError(f"policy file {str(json_path)!r} does not exist")
        try:
            meta = json.loads(json_path.read_text())
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise PlannerError(f"{json_path}: not a JSON policy metadata file: {exc}") from None
        recorded = meta.get("env_config") if isinstance(meta, dict) else None
        return _env_config_from(recorded, str(json_path))
    if not path.is_file():
        raise PlannerError(f"policy file {str(path)!r} does not exist")
    recorded = _checkpoint_data(path).get("srfm_env_config")
    return _env_config_from(recorded, str(path))


def load_checkpoint(path: str | Path) -> tuple[NumpyActor, EnvConfig, dict[str, Any]]:
    """Load an SB3 or SBX TD3 checkpoint written by ``srfm train``.

    Uses the library's loader (``TD3.load``), which unpickles: trusted files only (a
    :class:`UserWarning` says so).

    Returns:
        The NumPy actor, the EnvConfig, and what the zip records of the run:
        ``backend``, ``steps`` (``num_timesteps``), ``seed``.

    Raises:
        PlannerError: missing file, not a TD3 policy, or no srfm configuration in it.
        MissingDependencyError: the library that wrote it is not installed.
    """
    from srfm._deps import install_hint, require

    path = Path(path)
    if not path.is_file():
        raise PlannerError(f"policy file {str(path)!r} does not exist")
    backend = checkpoint_backend(path, "load a TD3 policy")
    warnings.warn(_PICKLE_WARNING.format(path=path), UserWarning, stacklevel=2)
    if backend == "sbx":
        try:
            lib = require("sbx")
        except MissingDependencyError:
            raise MissingDependencyError(
                f"{path} is an SBX checkpoint: install the sbx extra to read it: "
                + install_hint("rl,sbx")
            ) from None
    else:
        lib = require("stable_baselines3")
        require("torch")
    try:
        model = lib.TD3.load(path, device="cpu")
    except Exception as exc:  # SB3 raises many kinds on a bad file
        raise PlannerError(f"{path}: cannot load a TD3 policy: {exc}") from None
    config = _env_config_from(getattr(model, "srfm_env_config", None), str(path))
    if backend == "sbx":
        actor = NumpyActor.from_sbx(model.policy.actor_state.params)
    else:
        actor = NumpyActor.from_sb3(model.actor)
    seed = getattr(model, "seed", None)
    info = {
        "backend": backend,
        "steps": int(model.num_timesteps),
        "seed": None if seed is None else int(seed),
    }
    return actor, config, info


def load_policy(path: str | Path) -> tuple[NumpyActor, EnvConfig]:
    """Load a policy file: its NumPy actor and EnvConfig.

    A ``.json``/``.npz`` is a NumPy policy file (:func:`load_numpy_policy`: NumPy only);
    anything else a training checkpoint (:func:`load_checkpoint`: SB3's loader, which
    unpickles; trusted files only).

    Raises:
        PlannerError: missing or invalid file (the message says what is wrong).
        MissingDependencyError: a checkpoint, and SB3 / SBX is not installed.
    """
    path = Path(path)
    if _is_numpy_policy(path):
        policy = load_numpy_policy(path)
        return policy.actor, policy.config
    actor, config, _ = load_checkpoint(path)
    return actor, config


_CACHE: dict[str, tuple[NumpyActor, EnvConfig]] = {}
_CONFIG_CACHE: dict[str, EnvConfig] = {}
_CACHE_LOCK = threading.Lock()


def _cached_policy(path: Path) -> tuple[NumpyActor, EnvConfig]:
    key = str(path.resolve())
    with _CACHE_LOCK:
        if key not in _CACHE:
            _CACHE[key] = load_policy(path)
        return _CACHE[key]


def _cached_config(path: Path) -> EnvConfig:
    key = str(path.resolve())
    with _CACHE_LOCK:
        if key in _CACHE:
            return _CACHE[key][1]
        if key not in _CONFIG_CACHE:
            _CONFIG_CACHE[key] = read_policy_config(path)
        return _CONFIG_CACHE[key]


class PolicyPlanner:
    """A planner that runs a NumPy actor on the environment's observation.

    Args:
        actor: the policy network.
        config: the :class:`srfm.rl.EnvConfig` it was trained with (observation layout,
            social zone, kinematics).
        name: the planner's name.
    """

    def __init__(self, actor: NumpyActor, config: EnvConfig, name: str = "policy") -> None:
        self.name = name
        self._actor = actor
        self._config = config
        self.detection_range_m: float | None = float(config.social_zone_m)
        self._builder: ObservationBuilder | None = None
        self._obs: F32 = np.zeros(actor.obs_size, dtype=np.float32)
        self._last = np.zeros(2)
        self._held = 0  # steps the last action has been applied (config.action_repeat)

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Start an episode (the policy is deterministic and draws nothing from ``rng``)."""
        want = self._config.kinematics
        if want is not None and context.robot.kinematics != want:
            raise PlannerError(
                f"planner {self.name!r} was trained for a {want} robot; scenario "
                f"{context.scenario!r} has a {context.robot.kinematics} robot"
            )
        builder = ObservationBuilder(context, self._config)
        if builder.size != self._actor.obs_size:
            raise PlannerError(
                f"planner {self.name!r}: the actor takes {self._actor.obs_size} inputs, "
                f"the observation has {builder.size}"
            )
        self._builder = builder
        self._last[:] = 0.0
        self._held = 0

    def act(self, observation: Observation) -> FloatArray:
        """The command for this step: a new action every ``config.action_repeat``
        steps (as in training), the last one held in between."""
        builder = self._builder
        if builder is None:
            raise PlannerError(f"planner {self.name!r}: call reset() before act()")
        if self._held % self._config.action_repeat == 0:
            obs = builder.build(observation, self._last, self._obs)
            action = self._actor.forward(obs)
            self._last[0] = action[0]
            self._last[1] = action[1]
        self._held += 1
        command: FloatArray = builder.command(self._last, observation.robot.theta)
        return command


class TD3Planner:
    """A TD3 policy file as a planner; the policy is loaded at the first reset.

    The construction reads only the configuration recorded in the file
    (:func:`read_policy_config`, no unpickling, no torch), so that
    ``detection_range_m``, the social zone the policy observes, is valid from the
    start (:func:`srfm.run_episode` reads it before the first reset). The network is
    loaded at the first :meth:`reset` (or :meth:`load`): a NumPy policy file with NumPy
    only, a checkpoint zip with SB3 / SBX.

    Args:
        path: a NumPy policy file (``.json`` or ``.npz``), or an SB3/SBX checkpoint
            zip (trusted files only: SB3's loader unpickles).
        name: the planner's name.

    Raises:
        PlannerError: the file is missing or holds no srfm configuration.
    """

    def __init__(self, path: str | Path, name: str = "td3") -> None:
        self.name = name
        self.path = Path(path)
        self.config = _cached_config(self.path)
        self.detection_range_m: float | None = float(self.config.social_zone_m)
        self._inner: PolicyPlanner | None = None

    def _load(self) -> PolicyPlanner:
        actor, config = _cached_policy(self.path)
        inner = PolicyPlanner(actor, config, self.name)
        self.detection_range_m = inner.detection_range_m
        self._inner = inner
        return inner

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Load the policy (first call only) and start an episode."""
        inner = self._inner or self._load()
        inner.reset(context, rng)

    def act(self, observation: Observation) -> FloatArray:
        """The policy's command for this step."""
        if self._inner is None:
            raise PlannerError(f"planner {self.name!r}: call reset() before act()")
        return self._inner.act(observation)

    def load(self) -> TD3Planner:
        """Load the policy now (normally done by the first reset); returns self."""
        if self._inner is None:
            self._load()
        return self


def shipped_policy_path(name: str) -> Path:
    """The NumPy policy file (its JSON) of a shipped policy (``td3-srfm`` or ``td3-base``)."""
    try:
        filename = SHIPPED_POLICIES[name]
    except KeyError:
        raise PlannerError(
            f"unknown shipped policy {plain(name)}; known: {', '.join(SHIPPED_POLICIES)}"
        ) from None
    return Path(str(resources.files("srfm.policies").joinpath(filename)))


def td3_srfm() -> TD3Planner:
    """The shipped SRFM-aware TD3 policy (trained with the deviation penalty k2 > 0)."""
    return TD3Planner(shipped_policy_path("td3-srfm"), "td3-srfm")


def td3_base() -> TD3Planner:
    """The shipped RL_base TD3 policy (trained without the deviation penalty, k2 = 0)."""
    return TD3Planner(shipped_policy_path("td3-base"), "td3-base")
