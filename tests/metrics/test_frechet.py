"""The exact discrete Fréchet distance: known value, reference, docs/metrics.md's properties."""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from srfm.errors import MetricError
from srfm.metrics import frechet_distance, frechet_distances
from srfm.metrics._kernels import frechet_sq


def reference_frechet(p: np.ndarray, q: np.ndarray) -> float:
    """The Eiter–Mannila recurrence on a full matrix, plain Python (independent)."""
    n, m = len(p), len(q)
    d = [[math.dist(p[i], q[j]) for j in range(m)] for i in range(n)]
    c = [[0.0] * m for _ in range(n)]
    for i in range(n):
        for j in range(m):
            if i == 0 and j == 0:
                c[i][j] = d[0][0]
            elif i == 0:
                c[i][j] = max(c[0][j - 1], d[0][j])
            elif j == 0:
                c[i][j] = max(c[i - 1][0], d[i][0])
            else:
                c[i][j] = max(min(c[i - 1][j], c[i - 1][j - 1], c[i][j - 1]), d[i][j])
    return c[n - 1][m - 1]


coords = st.floats(-50, 50, allow_nan=False, allow_infinity=False, width=32)
curves = arrays(np.float64, st.tuples(st.integers(1, 12), st.just(2)), elements=coords)


def test_known_value() -> None:
    p = [[1, 1], [2, 1], [2, 2]]
    q = [[2, 2], [0, 1], [2, 4]]
    assert frechet_distance(p, q) == 2.0


@settings(deadline=None, max_examples=300)
@given(curves, curves)
def test_equals_independent_reference(p: np.ndarray, q: np.ndarray) -> None:
    assert frechet_distance(p, q) == pytest.approx(reference_frechet(p, q), rel=1e-12, abs=1e-12)


@settings(deadline=None, max_examples=200)
@given(curves, st.integers(0, 2**32 - 1), st.sampled_from([1e-3, 0.1, 1.0, 10.0]))
def test_twin_like_curves_match_the_reference(p: np.ndarray, seed: int, scale: float) -> None:
    """Equal lengths and small perturbations: where the pruning does the most work."""
    q = p + np.random.default_rng(seed).normal(scale=scale, size=p.shape)
    assert frechet_distance(p, q) == pytest.approx(reference_frechet(p, q), rel=1e-12, abs=1e-12)


@settings(deadline=None, max_examples=150)
@given(
    st.integers(20, 90),
    st.integers(0, 2**32 - 1),
    st.sampled_from(["walk_and_stand", "stand_and_push", "converge"]),
)
def test_structured_twins_match_the_reference(n: int, seed: int, shape: str) -> None:
    """Standing, converging and pushed twins: the shapes the shortcuts are built for."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)[:, None]
    if shape == "walk_and_stand":  # walk to a goal, then hover there
        goal = rng.uniform(-5, 5, 2)
        q = np.minimum(t * 2.0, 1.0) * goal + rng.normal(scale=0.01, size=(n, 2))
    elif shape == "stand_and_push":  # stand on a spot with a little jitter
        q = rng.normal(scale=rng.choice([0.0, 0.01, 0.2]), size=(n, 2))
    else:  # two walks that meet at the same end
        q = t * rng.uniform(-5, 5, 2) + np.sin(t * 7) * rng.uniform(-1, 1, 2)
    bump = np.exp(-(((t - rng.uniform(0.2, 0.8)) / 0.1) ** 2)) * rng.uniform(-2, 2, 2)
    p = q + bump
    if rng.random() < 0.3:
        p = np.round(p, 1)  # ties between distances
        q = np.round(q, 1)
    assert frechet_distance(p, q) == pytest.approx(reference_frechet(p, q), rel=1e-12, abs=1e-12)


def test_matches_reference_on_a_real_twin_episode() -> None:
    from srfm import run_episode

    for scenario, pedestrians in (("crosswalk", (1, 6)), ("concert", (2, 5))):
        record = run_episode(scenario, 0)
        for i in pedestrians:  # pedestrians the robot pushes
            p = record.factual_pos[::2, i]
            q = record.counterfactual_pos[::2, i]
            expected = reference_frechet(p, q)
            assert expected > 0.2
            assert frechet_distance(p, q) == pytest.approx(expected, rel=1e-12)


@settings(deadline=None)
@given(curves)
def test_identity(p: np.ndarray) -> None:
    assert frechet_distance(p, p) == 0.0


@settings(deadline=None)
@given(curves, curves)
def test_symmetry(p: np.ndarray, q: np.ndarray) -> None:
    assert frechet_distance(p, q) == frechet_distance(q, p)


@settings(deadline=None)
@given(curves, st.integers(-64, 64), st.integers(-64, 64))
def test_translation_gives_exactly_the_offset(p: np.ndarray, vx: int, vy: int) -> None:
    # Dyadic offsets and grid points keep p + v exact, so the answer is exactly |v|.
    p = np.round(p * 4) / 4
    v = np.array([vx, vy]) / 8
    assert frechet_distance(p, p + v) == math.hypot(v[0], v[1])


@settings(deadline=None)
@given(curves, curves)
def test_bounded_below_by_endpoints_and_hausdorff(p: np.ndarray, q: np.ndarray) -> None:
    f = frechet_distance(p, q)
    d = np.linalg.norm(p[:, None] - q[None], axis=2)
    assert f >= d[0, 0]
    assert f >= d[-1, -1]
    hausdorff = max(d.min(axis=1).max(), d.min(axis=0).max())
    assert f >= hausdorff - 1e-12


@settings(deadline=None)
@given(curves, st.integers(0, 2**32 - 1))
def test_bounded_above_by_pointwise_max_for_equal_lengths(p: np.ndarray, seed: int) -> None:
    q = np.random.default_rng(seed).uniform(-50, 50, size=p.shape)
    assert frechet_distance(p, q) <= np.linalg.norm(p - q, axis=1).max()


@settings(deadline=None)
@given(curves, curves, curves)
def test_triangle_inequality(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> None:
    assert frechet_distance(p, r) <= frechet_distance(p, q) + frechet_distance(q, r) + 1e-9


def test_kernel_matches_its_python_version() -> None:
    rng = np.random.default_rng(3)
    p = rng.normal(size=(40, 2))
    q = p + rng.normal(scale=0.2, size=p.shape)
    args = (p, q, np.empty(40), np.empty(40))
    assert frechet_sq(*args) == frechet_sq.py_func(*args)


def test_batch_equals_single_pairs() -> None:
    rng = np.random.default_rng(5)
    a = rng.normal(size=(60, 4, 2)).cumsum(axis=0)
    b = a + rng.normal(scale=0.3, size=a.shape)
    out = frechet_distances(a, b)
    assert out.shape == (4,)
    for k in range(4):
        assert out[k] == frechet_distance(a[:, k], b[:, k])


@pytest.mark.parametrize(
    ("p", "match"),
    [
        (np.zeros((0, 2)), "empty"),
        (np.zeros((3, 3)), r"shape \(n, 2\)"),
        (np.zeros(4), r"shape \(n, 2\)"),
        ([[0.0, 0.0], [1.0, np.nan]], r"non-finite value at row 1"),
        ([[0.0, np.inf]], r"non-finite value at row 0"),
        ([["a", "b"]], "array of numbers"),
    ],
)
def test_bad_input_is_a_value_error_naming_it(p: object, match: str) -> None:
    with pytest.raises(MetricError, match=match):
        frechet_distance(p, [[0.0, 0.0]])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=match):
        frechet_distance([[0.0, 0.0]], p)  # type: ignore[arg-type]


def test_batch_rejects_mismatched_shapes() -> None:
    with pytest.raises(MetricError, match=r"\(T, N, 2\)"):
        frechet_distances(np.zeros((5, 2, 2)), np.zeros((5, 3, 2)))


def test_ten_thousand_points_each_without_a_memory_blow_up() -> None:
    """A full 10,000 × 10,000 matrix would take 800 MB; two rows take 160 kB."""
    script = textwrap.dedent(
        """
        import resource
        import numpy as np
        from srfm.metrics import frechet_distance

        frechet_distance(np.zeros((5, 2)), np.ones((5, 2)))  # load the kernel
        rng = np.random.default_rng(0)
        p = rng.uniform(0, 10, size=(10_000, 2))
        q = rng.uniform(0, 10, size=(10_000, 2))  # unrelated curves: no pruning helps
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        value = frechet_distance(p, q)
        after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        print(value, (after - before) / 1024)
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    ).stdout.split()
    value, grown_mb = float(out[0]), float(out[1])
    assert 0 < value < 15
    assert grown_mb < 50
