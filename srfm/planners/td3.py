"""TD3 policies as planners: ``td3-srfm`` and ``td3-base``, and any policy file you train.

A policy file is a stable-baselines3 ``TD3`` zip written by ``srfm train``. It is read
with SB3's loader, **which unpickles Python objects and can therefore execute
arbitrary code: load only policy files from a source you trust** (the two shipped in
``srfm/policies/`` are built by ``tools/train_policies.sh``).

After loading, the planner runs the actor in NumPy (weights copied out of the SB3
actor, float32), so a step costs microseconds and torch is not called during an
episode. The observation is built by the environment's own code
(:class:`srfm.rl.ObservationBuilder`), so a policy sees in evaluation exactly what
it saw in training.
"""

from __future__ import annotations

import threading
from importlib import resources
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np
from numba import njit
from numpy.typing import NDArray

from srfm.errors import PlannerError
from srfm.planners._base import FloatArray, Observation, PlannerContext

__all__ = [
    "SHIPPED_POLICIES",
    "NumpyActor",
    "PolicyPlanner",
    "TD3Planner",
    "load_policy",
    "shipped_policy_path",
    "td3_base",
    "td3_srfm",
]

# Registry name -> file in srfm/policies/.
SHIPPED_POLICIES: Final = {"td3-srfm": "td3_srfm.zip", "td3-base": "td3_base.zip"}

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


def _env_config_from(data: Any, source: str) -> Any:
    from srfm.rl import EnvConfig

    if not isinstance(data, dict):
        raise PlannerError(
            f"{source}: no srfm environment configuration in the policy file; "
            "train it with `srfm train`"
        )
    try:
        return EnvConfig(**data)
    except (TypeError, ValueError) as exc:
        raise PlannerError(f"{source}: bad environment configuration: {exc}") from None


def load_policy(path: str | Path) -> tuple[NumpyActor, Any]:
    """Load a policy file written by ``srfm train``: its NumPy actor and EnvConfig.

    Uses SB3's loader (``TD3.load``), which unpickles: trusted files only.

    Raises:
        PlannerError: missing file, not a TD3 policy, or no srfm configuration in it.
        MissingDependencyError: stable-baselines3 / torch are not installed.
    """
    from srfm.rl._deps import require

    path = Path(path)
    if not path.is_file():
        raise PlannerError(f"policy file {str(path)!r} does not exist")
    sb3 = require("stable_baselines3")
    require("torch")
    try:
        model = sb3.TD3.load(path, device="cpu")
    except Exception as exc:  # SB3 raises many kinds on a bad file
        raise PlannerError(f"{path}: cannot load a TD3 policy: {exc}") from None
    config = _env_config_from(getattr(model, "srfm_env_config", None), str(path))
    actor = NumpyActor.from_sb3(model.actor)
    return actor, config


_CACHE: dict[str, tuple[NumpyActor, Any]] = {}
_CACHE_LOCK = threading.Lock()


def _cached_policy(path: Path) -> tuple[NumpyActor, Any]:
    key = str(path.resolve())
    with _CACHE_LOCK:
        if key not in _CACHE:
            _CACHE[key] = load_policy(path)
        return _CACHE[key]


class PolicyPlanner:
    """A planner that runs a NumPy actor on the environment's observation.

    Args:
        actor: the policy network.
        config: the :class:`srfm.rl.EnvConfig` it was trained with (observation layout,
            social zone, kinematics).
        name: the planner's name.
    """

    def __init__(self, actor: NumpyActor, config: Any, name: str = "policy") -> None:
        from srfm.rl import ObservationBuilder

        self.name = name
        self._actor = actor
        self._config = config
        self.detection_range_m: float | None = float(config.social_zone_m)
        self._builder_cls = ObservationBuilder
        self._builder: Any = None
        self._obs: F32 = np.zeros(actor.obs_size, dtype=np.float32)
        self._last = np.zeros(2)

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Start an episode (the policy is deterministic and draws nothing from ``rng``)."""
        want = self._config.kinematics
        if want is not None and context.robot.kinematics != want:
            raise PlannerError(
                f"planner {self.name!r} was trained for a {want} robot; scenario "
                f"{context.scenario!r} has a {context.robot.kinematics} robot"
            )
        builder = self._builder_cls(context, self._config)
        if builder.size != self._actor.obs_size:
            raise PlannerError(
                f"planner {self.name!r}: the actor takes {self._actor.obs_size} inputs, "
                f"the observation has {builder.size}"
            )
        self._builder = builder
        self._last[:] = 0.0

    def act(self, observation: Observation) -> FloatArray:
        """The command for this step."""
        builder = self._builder
        if builder is None:
            raise PlannerError(f"planner {self.name!r}: call reset() before act()")
        obs = builder.build(observation, self._last, self._obs)
        action = self._actor.forward(obs)
        self._last[0] = action[0]
        self._last[1] = action[1]
        command: FloatArray = builder.command(self._last, observation.robot.theta)
        return command


class TD3Planner:
    """A TD3 policy file as a planner; the file is loaded at the first reset.

    Args:
        path: the policy zip (trusted files only: SB3's loader unpickles).
        name: the planner's name.
    """

    def __init__(self, path: str | Path, name: str = "td3") -> None:
        self.name = name
        self.path = Path(path)
        # The social zone once the file is loaded (by this or an earlier instance);
        # None (observe everyone) before: the observation is the same either way.
        cached = _CACHE.get(str(self.path.resolve()))
        self.detection_range_m: float | None = (
            None if cached is None else float(cached[1].social_zone_m)
        )
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
    """The file of a shipped policy (``td3-srfm`` or ``td3-base``)."""
    try:
        filename = SHIPPED_POLICIES[name]
    except KeyError:
        raise PlannerError(
            f"unknown shipped policy {name!r}; known: {', '.join(SHIPPED_POLICIES)}"
        ) from None
    return Path(str(resources.files("srfm.policies").joinpath(filename)))


def td3_srfm() -> TD3Planner:
    """The shipped SRFM-aware TD3 policy (trained with the deviation penalty k2 > 0)."""
    return TD3Planner(shipped_policy_path("td3-srfm"), "td3-srfm")


def td3_base() -> TD3Planner:
    """The shipped RL_base TD3 policy (trained without the deviation penalty, k2 = 0)."""
    return TD3Planner(shipped_policy_path("td3-base"), "td3-base")
