"""``srfm/SocialNav-v0``: the paper's RL environment on the twin simulator."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Final

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from srfm.errors import ParameterError, PlannerError, SimulationError
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState
from srfm.rl import _kernels as _k
from srfm.rl._config import EnvConfig
from srfm.rl._core import EVENT_OUTCOMES, EnvCore, resolve_scenario
from srfm.scenarios import Scenario, load_scenario, validate_seed

__all__ = ["SocialNavEnv"]

# Episode seeds drawn by reset() without a seed lie in [0, MAX_DRAWN_SEED).
MAX_DRAWN_SEED: Final = 2**31 - 1
_TERMINAL: Final = frozenset({_k.EV_COLLISION, _k.EV_OBSTACLE, _k.EV_OUT_OF_BOUNDS, _k.EV_GOAL})

ObsType = NDArray[np.float32]
ActType = NDArray[np.float32]


class SocialNavEnv(gym.Env[ObsType, ActType]):
    """Robot navigation among SRFM pedestrians, with the paper's observation and reward.

    One step advances the robot and both crowds of :class:`srfm.TwinSimulator` by one
    simulation step (bit-identical dynamics), computes the one-step counterfactual
    deviation and builds the observation, in one numba call.

    - **Action**: Box([−1, 1]², float32). Unicycle: (v, ω) = (a0 v_max, a1 ω_max);
      holonomic: robot-frame velocity (a0, a1) v_max. Clipped to [−1, 1], then to the
      robot's speed and acceleration limits, as in the simulator.
    - **Observation**: Box([−1, 1]^(9 + 6K), float32), robot frame, normalised; see
      :func:`srfm.rl._kernels.build_observation` and ``docs/rl.md``.
    - **Reward**: r = r_term − k1 r_dist − k2 r_div (:class:`EnvConfig`).
    - **Episode end**: terminated on goal, collision (centre distance below the sum of
      radii, or overlap with a wall or pillar) or leaving the world; truncated at the
      scenario's horizon (750 steps).

    ``reset(seed=s)`` starts episode ``s`` of the scenario (the same set-up as
    ``srfm.run_episode(scenario, s)``); ``reset()`` draws the next episode seed from
    the environment's generator, itself seeded by the last ``reset(seed=...)``;
    ``reset(options={"episode_seed": s})`` picks an episode without reseeding.

    Args:
        scenario: a built-in name (``"random"`` for training, or an evaluation
            scenario), a TOML path or a :class:`srfm.Scenario`.
        config: reward and observation options.
        params: SRFM parameters (default: the ``agrawal2024`` preset).
        render_mode: only None (use ``srfm.run_episode`` and its sinks to look at runs).
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 (gymnasium API)

    def __init__(
        self,
        scenario: Scenario | str | Path = "random",
        config: EnvConfig | None = None,
        params: SRFMParams | None = None,
        render_mode: str | None = None,
    ) -> None:
        if render_mode is not None:
            raise ParameterError(f"render_mode must be None, got {render_mode!r}")
        if config is None:
            config = EnvConfig()
        elif not isinstance(config, EnvConfig):
            raise ParameterError(f"config must be an srfm.rl.EnvConfig, got {config!r}")
        if params is None:
            params = SRFMParams()
        elif not isinstance(params, SRFMParams):
            raise ParameterError(f"params must be an srfm.SRFMParams, got {params!r}")
        if not isinstance(scenario, Scenario):
            scenario = load_scenario(scenario)
        self.render_mode = render_mode
        self.scenario = resolve_scenario(scenario, config)
        self.config = config
        self.params = params
        self._core = EnvCore(self.scenario, config, params)
        size = _k.obs_size(config.max_pedestrians)
        self.observation_space = gym.spaces.Box(-1.0, 1.0, shape=(size,), dtype=np.float32)
        self.action_space = gym.spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._running = False
        self.episode_seed: int | None = None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[ObsType, dict[str, Any]]:
        """Start an episode; see the class docstring for how the episode is chosen."""
        super().reset(seed=seed)
        if options and "episode_seed" in options:
            episode = validate_seed(options["episode_seed"])
        elif seed is not None:
            episode = validate_seed(seed)
        else:
            episode = int(self.np_random.integers(0, MAX_DRAWN_SEED))
        self._core.reset(episode)
        self.episode_seed = episode
        self._running = True
        return self._core.obs.copy(), {"episode_seed": episode}

    def step(self, action: ActType) -> tuple[ObsType, float, bool, bool, dict[str, Any]]:
        """Advance one step; see the class docstring."""
        if not self._running:
            raise SimulationError("the episode is over (or never started): call reset()")
        try:
            a0 = float(action[0])
            a1 = float(action[1])
        except (TypeError, ValueError, IndexError):
            raise PlannerError(f"an action must be two numbers, got {action!r}") from None
        if not (math.isfinite(a0) and math.isfinite(a1)):
            raise PlannerError(f"an action must be finite, got {action!r}")
        core = self._core
        event = core.step(a0, a1)
        out = core.out
        info: dict[str, Any] = {
            "r_dist": float(out[_k.O_R_DIST]),
            "r_div": float(out[_k.O_R_DIV]),
            "r_term": float(out[_k.O_R_TERM]),
        }
        terminated = event in _TERMINAL
        truncated = event == _k.EV_TIMEOUT
        if event != _k.EV_NONE:
            self._running = False
            info["outcome"] = EVENT_OUTCOMES[event]
            info["is_success"] = event == _k.EV_GOAL
        return core.obs.copy(), float(out[_k.O_REWARD]), terminated, truncated, info

    # Read-only views for scoring and tests.

    @property
    def step_index(self) -> int:
        """Steps taken in the current episode."""
        return self._core.step_index

    @property
    def robot_state(self) -> RobotState:
        """The robot now."""
        return self._core.robot_state()

    @property
    def robot_goal(self) -> NDArray[np.float64]:
        """(2,) the robot's goal (m)."""
        cfg = self._core.cfg
        return np.array([cfg[_k.C_GOAL_X], cfg[_k.C_GOAL_Y]])

    @property
    def factual_pos(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian positions (m), a copy."""
        out: NDArray[np.float64] = self._core.crowd[_k.F_POS].copy()
        return out

    @property
    def factual_vel(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian velocities (m/s), a copy."""
        out: NDArray[np.float64] = self._core.crowd[_k.F_VEL].copy()
        return out

    @property
    def counterfactual_pos(self) -> NDArray[np.float64]:
        """(N, 2) counterfactual pedestrian positions (m), a copy; frozen at the start
        when ``config.counterfactual_twin`` is False."""
        out: NDArray[np.float64] = self._core.crowd[_k.C_POS].copy()
        return out

    @property
    def factual_goal(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian goals (m), a copy."""
        out: NDArray[np.float64] = self._core.crowd[_k.F_GOAL].copy()
        return out
