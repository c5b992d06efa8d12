"""The bit-plane form of a float64 time series: exact, and about 40 % smaller once zstd
has compressed it than the plain ``.npy`` file.

A float64 array ``a`` of shape ``(S, *rest)`` (axis 0 is time, S samples) is stored as
the bit planes of the second differences in time of its IEEE-754 bit patterns:

1. ``u = a.view("<u8")``: the bit patterns as unsigned 64-bit integers;
2. ``d[k] = u[k] - 2 u[k-1] + u[k-2]`` modulo 2**64, with ``u[-1] = u[-2] = 0``
   (``d[0] = u[0]``, ``d[1] = u[1] - 2 u[0]``): the second differences in time, in
   integer arithmetic, so that any value (NaN payloads, signed zeros, infinities)
   comes back with its bits, on any machine; two cumulative sums undo them;
3. ``z = (d << 1) ^ (d >> 63)`` on signed 64-bit integers (zigzag: a difference of
   small magnitude, either sign, has its high bits zero);
4. time last (``z`` moved to shape ``(*rest, S)``, C order, ``M`` values), and bit ``j``
   (0: least significant) of the ``M`` values is row ``j`` of a ``(64, ceil(M / 8))``
   uint8 array: ``numpy.packbits`` with ``bitorder="little"`` of the values' bits.

A smooth trajectory has second differences far smaller than its values, so their high
bit planes are mostly zeros, which zstd (the MCAP chunks' compression) stores in a few
bytes; the factual positions of a paper episode take 4.7 bytes a value instead of 7.5
(docs/history/performance.md). :func:`from_planes` undoes the four steps; it is the
whole decoder, a dozen lines of NumPy (docs/logging.md shows it without srfm).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["from_planes", "to_planes"]

_BITS = 64
_SWAPS = (  # (shift, mask) of the three delta swaps that transpose an 8 x 8 bit matrix
    (7, np.uint64(0x00AA00AA00AA00AA)),
    (14, np.uint64(0x0000CCCC0000CCCC)),
    (28, np.uint64(0x00000000F0F0F0F0)),
)


def _transpose_bits(words: NDArray[np.uint64]) -> NDArray[np.uint64]:
    """Each word's 8 x 8 bit matrix transposed (bit ``8 r + c`` to bit ``8 c + r``): what
    ``unpackbits``, a transpose and ``packbits`` do to 8 bytes, without the 64 bytes of
    bits in between. Its own inverse."""
    x = words.copy()
    for shift, mask in _SWAPS:
        t = (x ^ (x >> np.uint64(shift))) & mask
        x ^= t ^ (t << np.uint64(shift))
    return x


def to_planes(a: NDArray[np.float64]) -> NDArray[np.uint8]:
    """The ``(64, ceil(M / 8))`` bit planes of float64 array ``a`` (time on axis 0)."""
    u = np.ascontiguousarray(a, dtype="<f8").view("<u8")
    e = u.copy()
    e[1:] -= u[:-1]  # first differences, modulo 2**64
    d = e.copy()
    d[1:] -= e[:-1]  # second differences
    s = d.view("<i8")
    z = ((s << 1) ^ (s >> 63)).view("<u8")
    m = z.size
    values = np.zeros((m + 7) // 8 * 8, dtype="<u8")
    values[:m] = np.moveaxis(z, 0, -1).reshape(-1)
    # Byte planes (8, M): row p holds byte p of every value; then, 8 values at a time,
    # the 8 x 8 bits of a row turned so that byte i holds bit i of the 8 values.
    byte_planes = np.ascontiguousarray(values.view(np.uint8).reshape(-1, 8).T)
    turned = _transpose_bits(byte_planes.view("<u8")).view(np.uint8)
    n = values.size // 8
    return np.ascontiguousarray(turned.reshape(8, n, 8).transpose(0, 2, 1)).reshape(_BITS, n)


def from_planes(planes: NDArray[np.uint8], shape: tuple[int, ...]) -> NDArray[np.float64]:
    """The float64 array of ``shape`` (time on axis 0) whose bit planes are ``planes``.

    Raises:
        ValueError: ``planes`` is not a uint8 array of shape ``(64, ceil(M / 8))`` for
            the ``M`` values of ``shape``.
    """
    m = math.prod(shape)
    n = (m + 7) // 8
    if not shape or planes.dtype != np.uint8 or planes.shape != (_BITS, n):
        raise ValueError(
            f"bit planes of shape {planes.shape} and type {planes.dtype} do not hold a "
            f"float64 array of shape {shape}: expected uint8 ({_BITS}, {n})"
        )
    grouped = np.ascontiguousarray(planes.reshape(8, 8, n).transpose(0, 2, 1))
    byte_planes = _transpose_bits(grouped.reshape(8, n * 8).view("<u8")).view(np.uint8)
    values = np.ascontiguousarray(byte_planes.reshape(8, n * 8).T).view("<u8").reshape(-1)
    z = np.moveaxis(values[:m].reshape(*shape[1:], shape[0]), -1, 0)
    d = (z >> np.uint64(1)) ^ (np.uint64(0) - (z & np.uint64(1)))
    u = np.cumsum(np.cumsum(d, axis=0, dtype=np.uint64), axis=0, dtype=np.uint64)
    return np.ascontiguousarray(u).view(np.float64)
