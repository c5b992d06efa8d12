"""Dataset MCAP files are read with every checksum validated; a damaged file
is either refused with a DatasetError naming it, or read to exactly the data written
(a flip in a part that carries no data, e.g. padding of the summary). Never silently
changed trajectories, never a raw library exception."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import srfm
from srfm.datasets import read_mcap, write_mcap
from srfm.errors import DatasetError
from tests.datasets._synthetic import simulate_scene


def _content(path: Path) -> list[tuple[object, ...]]:
    data = read_mcap(path)
    return [
        (
            s.scene,
            s.agent_ids,
            s.kinds,
            s.agent.tobytes(),
            s.frame.tobytes(),
            s.t_ns.tobytes(),
            s.xy.tobytes(),
            s.frame_of_reference,
            dict(s.source),
        )
        for s in data.scenes
    ]


def test_single_bit_flips_are_refused_or_harmless(tmp_path: Path) -> None:
    path = tmp_path / "d.mcap"
    write_mcap(path, [simulate_scene(srfm.SRFMParams(), 1, name="s", robot=True)], dataset="x")
    original = path.read_bytes()
    expected = _content(path)
    rng = np.random.default_rng(13)
    damaged = tmp_path / "damaged.mcap"
    refused = 0
    flips = 1500
    for bit in rng.choice(len(original) * 8, size=flips, replace=False):
        data = bytearray(original)
        data[bit // 8] ^= 1 << (bit % 8)
        damaged.write_bytes(bytes(data))
        try:
            got = _content(damaged)
        except DatasetError as exc:
            message = str(exc)
        else:
            assert got == expected, f"bit {bit}: changed data read without complaint"
            continue
        assert "damaged.mcap" in message
        refused += 1
    assert refused > flips // 2  # the checksums catch the flips in the data
