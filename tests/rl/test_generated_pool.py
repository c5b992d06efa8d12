"""Training on generated walled layouts (issue 43): the pool's third share."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("gymnasium")

from srfm.errors import ParameterError
from srfm.planners._observation import EnvConfig
from srfm.scenarios.training import GENERATED, LIBRARY_TRAINING, pool_scenario


def test_one_draw_splits_library_generated_and_mixed() -> None:
    """Shares 0.3 / 0.4 / 0.3 over 4,000 seeds; without a generated share the pool
    picks exactly what it picked before (the same library scenario or None)."""
    picks = [pool_scenario(s, LIBRARY_TRAINING, 0.3, 0.4) for s in range(4000)]
    generated = picks.count(GENERATED) / len(picks)
    mixed = picks.count(None) / len(picks)
    assert abs(generated - 0.4) < 0.03
    assert abs(mixed - 0.3) < 0.03
    for seed, pick in enumerate(picks[:500]):
        before = pool_scenario(seed, LIBRARY_TRAINING, 0.3)
        assert before == (pick if pick in LIBRARY_TRAINING else None)
    only = [pool_scenario(s, (), 0.0, 1.0) for s in range(50)]
    assert only == [GENERATED] * 50


def test_the_environment_runs_generated_layouts_by_seed() -> None:
    from srfm.rl import SocialNavEnv
    from srfm.scenarios.generated import generated_scenario

    config = EnvConfig(range_beams=24, range_max_m=4.0, action_repeat=4)
    env = SocialNavEnv("mixed", config, generated_share=1.0)
    for seed in (4, 11):
        env.reset(seed=seed)
        assert env.layout.name == generated_scenario(seed).name
        assert env.layout.obstacles.segments.shape[0] > 0
        for _ in range(5):
            _, _, terminated, truncated, _ = env.step(np.array([1.0, 0.0], dtype=np.float32))
            if terminated or truncated:
                break
    again = SocialNavEnv("mixed", config, generated_share=1.0)
    first, _ = env.reset(seed=7)
    second, _ = again.reset(seed=7)
    assert first.tobytes() == second.tobytes()
    assert env.layout.name == again.layout.name


@pytest.mark.parametrize(
    ("scenario", "kwargs", "word"),
    [
        ("mixed", {"generated_share": 1.5}, "generated_share must be a number in"),
        ("mixed", {"generated_share": -0.1}, "-0.1"),
        (
            "mixed",
            {"library": LIBRARY_TRAINING, "library_share": 0.7, "generated_share": 0.4},
            "at most 1, got 0.7 \\+ 0.4",
        ),
        ("crosswalk", {"generated_share": 0.4}, "'mixed' scenario only"),
    ],
)
def test_bad_generated_shares_are_refused(
    scenario: str, kwargs: dict[str, object], word: str
) -> None:
    from srfm.rl import SocialNavEnv

    with pytest.raises(ParameterError, match=word):
        SocialNavEnv(scenario, **kwargs)  # type: ignore[arg-type]


def test_train_takes_a_generated_share() -> None:
    from srfm.rl.training import TrainConfig

    assert TrainConfig(scenario="mixed", generated_share=0.4).generated_share == 0.4
    with pytest.raises(ParameterError):
        TrainConfig(generated_share=2.0)
