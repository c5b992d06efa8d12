"""The environment's options are checked like every other input: an unknown
``EnvConfig`` option is a ``ParameterError`` naming it (it was a raw ``TypeError``),
``max_pedestrians=0`` is refused (it was accepted: a robot blind to everyone), and so
is an unknown ``reset(options=...)`` key (it was ignored, and the episode drawn)."""

from __future__ import annotations

import pytest

from srfm.errors import ParameterError
from srfm.planners._observation import EnvConfig


def test_unknown_and_positional_options_are_parameter_errors() -> None:
    with pytest.raises(ParameterError, match=r"EnvConfig: unknown option 'foo'; known: k1, k2"):
        EnvConfig(foo=1)  # type: ignore[call-arg]
    with pytest.raises(ParameterError, match=r"unknown option 'social_zone'"):
        EnvConfig().replace(social_zone=2.0)
    with pytest.raises(ParameterError, match=r"EnvConfig takes keyword options only"):
        EnvConfig(0.1)  # type: ignore[misc]


@pytest.mark.parametrize("count", [0, -1, 1001, 2.0, True, "10"])
def test_max_pedestrians_is_a_count_from_1(count: object) -> None:
    with pytest.raises(ParameterError, match=r"max_pedestrians must be an integer in \[1, 1000\]"):
        EnvConfig(max_pedestrians=count)  # type: ignore[arg-type]
    assert EnvConfig(max_pedestrians=1).max_pedestrians == 1


def test_unknown_reset_options_are_refused_and_change_nothing() -> None:
    pytest.importorskip("gymnasium")
    from srfm.rl import SocialNavEnv

    env = SocialNavEnv("crosswalk")
    obs, info = env.reset(seed=3)
    for options in ({"episode-seed": 5}, {"episode_seed": 5, "seed": 1}, {1: 2}):
        with pytest.raises(ParameterError, match=r"unknown reset option .*; known: episode_seed"):
            env.reset(options=options)
        assert env.episode_seed == 3
    again, info = env.reset(options={"episode_seed": 3})
    assert info == {"episode_seed": 3}
    assert (again == obs).all()
    env.reset(options={})  # an empty dict is no option
