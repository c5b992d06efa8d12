"""``srfm/SocialNav-v0``: the paper's RL environment on the twin simulator."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Final

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import ParameterError, ScenarioError, SimulationError
from srfm.models import _robot_kernels as _rk
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState, command_pair
from srfm.planners._observation import EnvConfig
from srfm.rl._core import EnvCore, resolve_scenario
from srfm.scenarios import BUILTIN_SCENARIOS, Scenario, load_scenario, validate_seed
from srfm.scenarios.generated import generated_scenario
from srfm.scenarios.training import GENERATED, TRAINING_SCENARIO, pool_scenario, training_layout
from srfm.scenarios.training import family_weights as check_family_weights
from srfm.sim.engine import EVENT_OUTCOMES, EpisodeEngine

__all__ = ["MAX_EPISODE_STEPS", "SocialNavEnv"]

# Episode seeds drawn by reset() without a seed lie in [0, MAX_DRAWN_SEED).
MAX_DRAWN_SEED: Final = 2**31 - 1
# The horizon of every built-in scenario (steps): the registered max_episode_steps.
MAX_EPISODE_STEPS: Final = 750
# The keys reset(options=...) reads; any other is refused (a misspelt key would
# otherwise be ignored and the episode drawn instead).
RESET_OPTIONS: Final = ("episode_seed",)
_TERMINAL: Final = frozenset(
    {_rk.EVENT_COLLISION, _rk.EVENT_OBSTACLE, _rk.EVENT_OUT_OF_BOUNDS, _rk.EVENT_GOAL}
)

ObsType = NDArray[np.float32]
ActType = NDArray[np.float32]


def _generated_share(value: float, share: float, mixed: bool) -> float:
    """The checked share of generated walled layouts (see :class:`SocialNavEnv`)."""
    if not (isinstance(value, (int, float)) and 0.0 <= value <= 1.0):
        raise ParameterError(f"generated_share must be a number in [0, 1], got {value!r}")
    if value and not mixed:
        raise ParameterError(f"generated_share applies to the {TRAINING_SCENARIO!r} scenario only")
    if share + value > 1.0:
        raise ParameterError(
            f"library_share + generated_share must be at most 1, got {share!r} + {value!r}"
        )
    return float(value)


def _library(library: Sequence[str], share: float, mixed: bool) -> tuple[str, ...]:
    """The checked library of a training pool (see :class:`SocialNavEnv`)."""
    if isinstance(library, (str, bytes)):
        raise ParameterError(f"library must be a sequence of scenario names, got {plain(library)}")
    names = tuple(library)
    if not (isinstance(share, (int, float)) and 0.0 <= share <= 1.0):
        raise ParameterError(f"library_share must be a number in [0, 1], got {plain(share)}")
    if (names or share) and not mixed:
        raise ParameterError(
            f"library and library_share apply to the {TRAINING_SCENARIO!r} scenario only"
        )
    if share > 0.0 and not names:
        raise ParameterError(f"library_share is {share!r} but the library is empty")
    known = set(BUILTIN_SCENARIOS)
    for name in names:
        if name not in known:
            raise ParameterError(f"unknown library scenario {plain(name)}")
    return names


class SocialNavEnv(gym.Env[ObsType, ActType]):
    """Robot navigation among SRFM pedestrians, with the paper's observation and reward.

    One step advances the robot and both crowds of :class:`srfm.TwinSimulator` by one
    simulation step of dt = 1/15 s (bit-identical dynamics: the same crowd and robot
    kernels), computes the one-step counterfactual deviation and builds the
    observation, in one numba call. ``reset(seed=s)`` starts episode ``s`` of the
    scenario, the same set-up as ``srfm.run_episode(scenario, s)``.

    ## Action space

    ``Box(-1, 1, (2,), float32)``, clipped to [−1, 1], then scaled:

    | kinematics | action (a0, a1) |
    |---|---|
    | unicycle | v = a0 · v_max (0.5 m/s), ω = a1 · ω_max (π rad/s) |
    | holonomic | robot-frame velocity (a0, a1) · v_max, speed capped at v_max |

    The holonomic command is that velocity rotated into the world frame by the heading.
    The robot's acceleration limits (1 m/s², 2π rad/s²) then apply, as for every
    planner in the simulator.

    ## Observation space

    ``Box(-1, 1, (9 + 6K + B,), float32)``, K = ``config.max_pedestrians`` (10 by
    default), B = ``config.range_beams`` (0 by default: 69 entries). Robot frame (x
    forward along the heading, y to the left), every entry normalised:

    | index | entry |
    |---|---|
    | 0 | distance to the goal / world diagonal, capped at 1 |
    | 1 | cos of the goal's bearing |
    | 2 | sin of the goal's bearing |
    | 3 | unicycle: v / v_max; holonomic: robot-frame vx / v_max |
    | 4 | unicycle: ω / ω_max; holonomic: robot-frame vy / v_max |
    | 5 | last action a0 (0 after reset) |
    | 6 | last action a1 (0 after reset) |
    | 7 | success: 1 in the observation of the step that reached the goal, else 0 |
    | 8 | terminated: 1 in the observation of the step that ended the episode, else 0 |
    | 9 + 6m | slot m: present, 1 (0 for an empty slot) |
    | 10 + 6m | slot m: distance / social zone (``config.social_zone_m``) |
    | 11 + 6m | slot m: cos of the pedestrian's bearing |
    | 12 + 6m | slot m: sin of the pedestrian's bearing |
    | 13 + 6m | slot m: relative velocity x (pedestrian − robot) / velocity scale |
    | 14 + 6m | slot m: relative velocity y (pedestrian − robot) / velocity scale |

    | 9 + 6K + j | beam j: wall or pillar distance at heading + 2πj/B / range_max_m, ≤ 1 |

    for slots m = 0 … K − 1 (with K = 10: slot 0 is entries 9–14, slot 1 15–20, …,
    slot 9 63–68) and beams j = 0 … B − 1 (B = 0 by default, the paper's observation;
    the walls-aware recipe uses B = 24 beams of 4 m: entries 69–92). The slots hold
    the pedestrians whose centre is closer than the social zone (3 m) to the robot
    centre, nearest first (ties by index); empty slots are all zeros. The beams see
    walls and pillars, not pedestrians and not the world's bounds. Velocities are
    divided by ``config.velocity_scale_mps`` (2 m/s) and clipped to [−1, 1]. Entry 8
    is 1 at every ending, the horizon (a truncation) included.

    ## Rewards

    r = r_term − k1 · r_dist − k2 · r_div (paper Eq. 7, :class:`EnvConfig`):

    - r_dist = min(goal distance / goal distance at reset, 1);
    - r_div (m): the one-step counterfactual deviation summed over the pedestrians in
      the social zone (each pedestrian's next position predicted with and without the
      robot force, after the robot has moved);
    - r_term: +``success_reward`` (25) at the goal, −``timeout_penalty`` (25) at the
      horizon, −``collision_penalty`` (2 × timeout penalty, 50) on a collision or on
      leaving the world, else 0.

    With ``config.k_progress`` > 0 the potential-based progress term ``r_progress``
    = γ Φ(s') − Φ(s), Φ = −k_progress · d / d_0, is added (:class:`EnvConfig`).

    With ``config.action_repeat`` = k > 1 one ``step`` applies the action for k
    simulation steps (fewer when the episode ends) and returns the sum of their rewards
    and reward terms; the progress term is then γ Φ(s_{t+k}) − Φ(s_t).

    ``info`` holds ``r_dist``, ``r_div``, ``r_term`` and ``r_progress`` at every step,
    and at the end ``outcome`` (``"goal_reached"``, ``"collision"``, ``"out_of_bounds"`` or
    ``"timeout"``) and ``is_success``.

    ## Episode end

    - **terminated** when the robot reaches its goal (centre closer than 0.5 m),
      collides with a pedestrian (centre distance below the sum of radii) or overlaps
      a wall or pillar, or leaves the world;
    - **truncated** at the scenario's horizon (750 steps = 50 s in every built-in
      scenario but ``corridor_flow``, 1200), a timeout. ``gym.make`` registers
      ``max_episode_steps`` = ``MAX_EPISODE_STEPS`` (750), so its ``TimeLimit``
      truncates at the same step as the environment itself; for a scenario with
      another horizon pass ``max_episode_steps=scenario.horizon_steps`` to
      ``gym.make``.

    After the episode's end, ``step`` raises :class:`srfm.SimulationError` until the
    next ``reset``.

    ## Starting an episode

    ``reset(seed=s)`` starts episode ``s``; ``reset()`` draws the next episode seed
    from the environment's generator, itself seeded by the last ``reset(seed=...)``;
    ``reset(options={"episode_seed": s})`` picks an episode without reseeding; any
    other option key is a :class:`srfm.ParameterError`. ``info`` holds ``episode_seed``.

    ## Arguments

    Args:
        scenario: a built-in name (``"random"`` for training, or an evaluation
            scenario), a TOML path or a :class:`srfm.Scenario`.
        config: reward and observation options (:class:`srfm.rl.EnvConfig`).
        params: SRFM parameters (default: the ``agrawal2024`` preset).
        render_mode: only None (use ``srfm.run_episode`` and its sinks to look at runs).
        family_weights: for ``"mixed"`` only: relative probabilities of the layout
            families (:func:`srfm.scenarios.training.family_weights`); None: uniform.
        library: for ``"mixed"`` only: built-in scenarios run in a share
            ``library_share`` of the episodes instead of a training layout (each
            equally likely, chosen from the episode seed:
            :func:`srfm.scenarios.training.pool_scenario`), for example
            :data:`srfm.scenarios.training.LIBRARY_TRAINING`. Their robots must have
            the kinematics of the ``random`` scenario's (or of ``config``).
        library_share: the probability of a library scenario, in [0, 1].
        generated_share: for ``"mixed"`` only: the probability of a generated walled
            layout (:func:`srfm.scenarios.generated.generated_scenario` of the episode
            seed), in [0, 1 − ``library_share``]; the rest of the episodes run the
            training layouts.

    ## Example

    ::

        import gymnasium as gym
        import srfm.rl.env

        env = gym.make("srfm/SocialNav-v0", scenario="crosswalk")
        obs, info = env.reset(seed=3)
        terminated = truncated = False
        while not (terminated or truncated):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        print(info["outcome"])
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 (gymnasium API)

    def __init__(
        self,
        scenario: Scenario | str | Path = "random",
        config: EnvConfig | None = None,
        params: SRFMParams | None = None,
        render_mode: str | None = None,
        family_weights: Sequence[float] | None = None,
        library: Sequence[str] = (),
        library_share: float = 0.0,
        generated_share: float = 0.0,
    ) -> None:
        if render_mode is not None:
            raise ParameterError(f"render_mode must be None, got {plain(render_mode)}")
        if config is None:
            config = EnvConfig()
        elif not isinstance(config, EnvConfig):
            raise ParameterError(f"config must be an srfm.rl.EnvConfig, got {plain(config)}")
        if params is None:
            params = SRFMParams()
        elif not isinstance(params, SRFMParams):
            raise ParameterError(f"params must be an srfm.SRFMParams, got {plain(params)}")
        # "mixed": a new training layout per episode (srfm.scenarios.training), on the
        # world, robot and time step of the random scenario.
        self.mixed = isinstance(scenario, str) and scenario == TRAINING_SCENARIO
        if family_weights is not None and not self.mixed:
            raise ParameterError(
                f"family_weights apply to the {TRAINING_SCENARIO!r} scenario only, "
                f"got scenario {scenario!r}"
            )
        try:
            self.family_weights = check_family_weights(family_weights)
        except ScenarioError as error:
            raise ParameterError(str(error)) from None
        self.library = _library(library, library_share, self.mixed)
        self.library_share = float(library_share)
        self.generated_share = _generated_share(generated_share, self.library_share, self.mixed)
        if not isinstance(scenario, Scenario):
            scenario = load_scenario("random" if self.mixed else scenario)
        self.render_mode = render_mode
        self.scenario = resolve_scenario(scenario, config)
        self.config = config
        self.params = params
        self._core = EnvCore(self.scenario, config, params)
        # one core per (pedestrian count, re-goaling) of the mixed layouts, and one per
        # library scenario
        self._cores: dict[tuple[int, bool], EnvCore] = {}
        self._library_cores: dict[str, EnvCore] = {}
        self._k2 = float(config.k2)
        size = config.obs_size
        self.observation_space = gym.spaces.Box(-1.0, 1.0, shape=(size,), dtype=np.float32)
        self.action_space = gym.spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._running = False
        self.episode_seed: int | None = None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[ObsType, dict[str, Any]]:
        """Start an episode; see the class docstring for how the episode is chosen."""
        if options is not None and not isinstance(options, dict):
            raise ParameterError(f"reset options must be a dict or None, got {plain(options)}")
        unknown = sorted(map(repr, set(options or ()) - set(RESET_OPTIONS)))
        if unknown:
            raise ParameterError(
                f"unknown reset option {unknown[0]}; known: {', '.join(RESET_OPTIONS)}"
            )
        super().reset(seed=seed)
        if options and "episode_seed" in options:
            episode = validate_seed(options["episode_seed"])
        elif seed is not None:
            episode = validate_seed(seed)
        else:
            episode = int(self.np_random.integers(0, MAX_DRAWN_SEED))
        picked = None
        if self.mixed:
            picked = pool_scenario(episode, self.library, self.library_share, self.generated_share)
        if picked == GENERATED:  # a new walled layout: a core of its own
            layout = resolve_scenario(generated_scenario(episode), self.config)
            self._check_kinematics(layout, layout.source)
            self._core = EnvCore(layout, self.config, self.params)
            self._core.set_k2(self._k2)
        elif picked is not None:
            self._core = self._library_core(picked)
            self._core.set_k2(self._k2)
        elif self.mixed:
            drawn = training_layout(self.scenario, episode, weights=self.family_weights)
            layout = resolve_scenario(drawn, self.config)
            key = (layout.n_pedestrians, layout.random is not None)
            if key not in self._cores:
                self._cores[key] = EnvCore(layout, self.config, self.params)
            self._core = self._cores[key]
            self._core.use_layout(layout)
            self._core.set_k2(self._k2)
        self._core.reset(episode)
        self.episode_seed = episode
        self._running = True
        return self._core.obs.copy(), {"episode_seed": episode}

    def _library_core(self, name: str) -> EnvCore:
        core = self._library_cores.get(name)
        if core is None:
            scenario = resolve_scenario(load_scenario(name), self.config)
            self._check_kinematics(scenario, f"library scenario {name!r}")
            core = EnvCore(scenario, self.config, self.params)
            self._library_cores[name] = core
        return core

    def _check_kinematics(self, scenario: Scenario, what: str) -> None:
        if scenario.robot.kinematics != self.scenario.robot.kinematics:
            raise ParameterError(
                f"{what} has a {scenario.robot.kinematics} robot, "
                f"the environment a {self.scenario.robot.kinematics} one"
            )

    def step(self, action: ActType) -> tuple[ObsType, float, bool, bool, dict[str, Any]]:
        """Advance one step; see the class docstring."""
        if not self._running:
            raise SimulationError("the episode is over (or never started): call reset()")
        a0, a1 = command_pair(action, "an action")
        core = self._core
        event = core.step(a0, a1)
        reward, r_dist, r_div, r_term, r_progress = core.total  # in REWARD_TERMS order
        info: dict[str, Any] = {
            "r_dist": r_dist,
            "r_div": r_div,
            "r_term": r_term,
            "r_progress": r_progress,
        }
        terminated = event in _TERMINAL
        truncated = event == _rk.EVENT_TIMEOUT
        if event != _rk.EVENT_NONE:
            self._running = False
            info["outcome"] = EVENT_OUTCOMES[event]
            info["is_success"] = event == _rk.EVENT_GOAL
        return core.obs.copy(), reward, terminated, truncated, info

    def set_k2(self, k2: float) -> None:
        """Change the deviation weight k2 (1/m) from the next step on (a curriculum
        on k2; ``config.k2`` keeps the value the environment was made with)."""
        if not (isinstance(k2, (int, float)) and math.isfinite(k2) and k2 >= 0.0):
            raise ParameterError(f"k2 must be a finite number >= 0, got {plain(k2)}")
        self._k2 = float(k2)
        self._core.set_k2(self._k2)

    @property
    def k2(self) -> float:
        """The deviation weight k2 (1/m) in use."""
        return self._k2

    @property
    def layout(self) -> Scenario:
        """The scenario of the current episode (a training layout for ``"mixed"``)."""
        return self._core.scenario

    # Read-only views for scoring and tests.

    def _engine(self) -> EpisodeEngine:
        engine = self._core.engine
        if engine is None:
            raise SimulationError("no episode yet: call reset()")
        return engine

    @property
    def step_index(self) -> int:
        """Simulation steps taken in the current episode (``action_repeat`` per
        action)."""
        return self._core.step_index

    @property
    def robot_state(self) -> RobotState:
        """The robot now."""
        return self._engine().robot_state

    @property
    def robot_goal(self) -> NDArray[np.float64]:
        """(2,) the robot's goal (m)."""
        return self._engine().setup.robot_goal.copy()

    @property
    def factual_pos(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian positions (m), a copy (in the episode's order: a
        pedestrian not there yet at its start, at rest, as in the simulator)."""
        out: NDArray[np.float64] = self._engine().factual.pos.copy()
        return out

    @property
    def factual_vel(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian velocities (m/s), a copy."""
        out: NDArray[np.float64] = self._engine().factual.vel.copy()
        return out

    @property
    def counterfactual_pos(self) -> NDArray[np.float64]:
        """(N, 2) counterfactual pedestrian positions (m), a copy; frozen at the start
        when ``config.counterfactual_twin`` is False."""
        out: NDArray[np.float64] = self._engine().counterfactual.pos.copy()
        return out

    @property
    def factual_goal(self) -> NDArray[np.float64]:
        """(N, 2) factual pedestrian goals (m), a copy."""
        out: NDArray[np.float64] = self._engine().factual.goal.copy()
        return out
