"""Array blocks: exact round trips, the documented decoder, compactness, bad input."""

from __future__ import annotations

import base64

import numpy as np
import pytest
import zstandard
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from srfm.errors import LogError
from srfm.logs._codec import decode_array, encode_array
from tests.logs.conftest import same_bits


def _documented_decoder(block: dict[str, object]) -> np.ndarray:
    """The NumPy decoder as docs/logging.md and the module docstring spell it out."""
    shape = list(block["shape"])  # type: ignore[call-overload]
    t1 = shape[0]
    raw = base64.b64decode(str(block["data"]))
    planes = np.frombuffer(raw, np.uint8).reshape(8, -1)
    z = planes.T.copy().view("<u8").reshape(-1, t1)
    one = np.uint64(1)
    d = (z >> one) ^ (np.uint64(0) - (z & one))
    x = np.zeros(z.shape)
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(t1):
            if k == 0:
                p = np.zeros(len(z))
            elif k == 1:
                p = x[:, 0].copy()
            elif k == 2:
                p = 2 * x[:, 1] - x[:, 0]
            else:
                p = 3 * x[:, k - 1] - 3 * x[:, k - 2] + x[:, k - 3]
            p[~np.isfinite(p)] = 0.0
            x[:, k] = (p.view("<u8") + d[:, k]).view("<f8")
    return np.moveaxis(x.reshape([*shape[1:], t1]), -1, 0)


SPECIAL = np.array(
    [
        [np.inf, -np.inf],
        [np.nan, 1e308],
        [1e308, -0.0],
        [5e-324, 0.0],
        [-1.0, 1.0],
        [1.0, -1.0],
        [-1.7976931348623157e308, 1.7976931348623157e308],
    ]
)


@pytest.mark.parametrize(
    "array",
    [
        np.cumsum(np.random.default_rng(0).normal(size=(200, 5, 2)), axis=0),
        np.random.default_rng(1).normal(size=(50, 3)) * 1e6,
        SPECIAL,
        np.zeros((1, 4)),
        np.zeros((0, 2)),
        np.arange(7.0),
    ],
)
def test_float_round_trip_is_bit_exact(array: np.ndarray) -> None:
    block = encode_array(array)
    assert block["dtype"] == "float64"
    assert block["shape"] == list(array.shape)
    assert same_bits(decode_array(block, "x"), array.astype(np.float64))
    if array.size:
        assert same_bits(_documented_decoder(block), array.astype(np.float64))


def test_nan_payloads_and_negative_zero_survive() -> None:
    bits = np.array([0x7FF8000000000001, 0xFFF0000000000123, 0x8000000000000000], dtype="<u8")
    array = np.tile(bits.view("<f8"), (4, 1))
    assert same_bits(decode_array(encode_array(array), "x"), array)


@settings(max_examples=60, deadline=None)
@given(
    hnp.arrays(
        dtype=np.float64,
        shape=hnp.array_shapes(min_dims=1, max_dims=3, min_side=1, max_side=6),
        elements=st.floats(allow_nan=True, allow_infinity=True),
    )
)
def test_any_float_array_round_trips(array: np.ndarray) -> None:
    assert same_bits(decode_array(encode_array(array), "x"), array)


def test_bool_round_trip() -> None:
    array = np.array([True, False, True, True])
    out = decode_array(encode_array(array), "x")
    assert out.dtype == np.bool_
    assert np.array_equal(out, array)


def test_trajectories_compress_to_about_five_bytes_a_value(episode) -> None:  # type: ignore[no-untyped-def]
    """The point of the encoding: exact positions at well under the 7.5 bytes a value
    that raw float64 costs after zstd (the benchmark's MCAP budget depends on it)."""
    _, record, _ = episode("crosswalk", 0, "straight")
    pos = record.factual_pos
    block = encode_array(pos)
    packed = len(zstandard.ZstdCompressor(level=3).compress(block["data"].encode()))
    raw = len(zstandard.ZstdCompressor(level=3).compress(pos.tobytes()))
    assert packed / pos.size < 5.3
    assert packed < 0.8 * raw


@pytest.mark.parametrize(
    ("block", "match"),
    [
        ("not a dict", "expected an array block"),
        ({"dtype": "float64", "shape": [], "encoding": "x", "data": ""}, "bad array shape"),
        ({"dtype": "float64", "shape": [2, -1], "encoding": "x", "data": ""}, "bad array shape"),
        (
            {"dtype": "float64", "shape": [2], "encoding": "f64-pred3-planes-base64", "data": "@@"},
            "not valid base64",
        ),
        (
            {
                "dtype": "float64",
                "shape": [3],
                "encoding": "f64-pred3-planes-base64",
                "data": "AAAA",
            },
            "3 bytes for a float64 array",
        ),
        ({"dtype": "float32", "shape": [1], "encoding": "raw", "data": "AAAA"}, "unknown array"),
        ({"dtype": "bool", "shape": [2], "encoding": "u8-base64", "data": "AgI="}, "other than 0"),
    ],
)
def test_malformed_blocks_are_log_errors(block: object, match: str) -> None:
    with pytest.raises(LogError, match=match):
        decode_array(block, "file.mcap: factual.pos")
