"""The Rerun sink, read back with rerun's own reader and checked with `rerun rrd verify`."""

from __future__ import annotations

import subprocess
import sys
import warnings
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from srfm.logs import write_rrd
from srfm.logs._rerun import FORCE_ARROW_SCALE_S2
from srfm.models import RobotBody, force_components
from srfm.models.state import CrowdState
from srfm.scenarios import episode_setup

ENTITY_TREE = {
    "/world",
    "/world/bounds",
    "/world/obstacles/walls",
    "/world/obstacles/pillars",
    "/world/pedestrians/factual",
    "/world/pedestrians/factual/velocity",
    "/world/pedestrians/factual/goals",
    "/world/pedestrians/factual/paths",
    "/world/pedestrians/counterfactual",
    "/world/pedestrians/counterfactual/paths",
    "/world/robot",
    "/world/robot/heading",
    "/world/robot/path",
    "/world/robot/goal",
    "/metrics/twin_separation",
    "/metrics/robot_distance",
    "/events",
    "/episode/summary",
}
FORCES = {f"/world/forces/{k}" for k in ("goal", "pedestrians", "robot", "obstacles")}


def _read(
    path: Path,
) -> tuple[dict[str, list[pa.RecordBatch]], dict[str, list[pa.RecordBatch]], Any]:
    """Static and temporal record batches by entity, and the blueprint chunks."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a missing footer would warn
        reader = RrdReader(path)
        recordings, blueprints = reader.recordings(), reader.blueprints()
    assert len(recordings) == 1
    assert len(blueprints) == 1
    assert recordings[0].application_id == "srfm"
    static: dict[str, list[pa.RecordBatch]] = defaultdict(list)
    temporal: dict[str, list[pa.RecordBatch]] = defaultdict(list)
    for chunk in reader.stream():
        (static if chunk.is_static else temporal)[chunk.entity_path].append(chunk.to_record_batch())
    return static, temporal, list(reader.stream(store=blueprints[0]))


def _column(batches: list[pa.RecordBatch], name: str) -> tuple[np.ndarray, np.ndarray]:
    """(steps, values) of a temporal component, sorted by step; values flattened per row."""
    steps, values = [], []
    for b in batches:
        if name not in b.schema.names:
            continue
        steps.append(b.column("step").to_numpy())
        col = b.column(name)
        values.extend(col.to_pylist())
    order = np.argsort(np.concatenate(steps), kind="stable")
    return np.concatenate(steps)[order], np.array(values, dtype=object)[order]


@pytest.fixture(scope="module")
def rrd(tmp_path_factory: pytest.TempPathFactory, episode, short_scenario):  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode(short_scenario, 1, "dwa")
    path = tmp_path_factory.mktemp("rrd") / "ep.rrd"
    size = write_rrd(path, record, scenario=scenario, metrics=metrics, forces=True)
    assert size == path.stat().st_size > 0
    return path, scenario, record


def test_entity_tree_timelines_and_static_data(rrd) -> None:  # type: ignore[no-untyped-def]
    path, _scenario, _record = rrd
    static, temporal, _ = _read(path)
    entities = {e for e in set(static) | set(temporal) if not e.startswith("/__")}
    assert entities == ENTITY_TREE | FORCES  # /__properties: the recording's name
    for entity in (
        "/world",
        "/world/bounds",
        "/world/obstacles/walls",
        "/world/obstacles/pillars",
        "/world/robot/path",
        "/episode/summary",
    ):
        assert entity in static, entity
        assert entity not in temporal, entity
    for entity, batches in temporal.items():
        for b in batches:
            names = set(b.schema.names)
            assert {"step", "sim_time"} <= names, entity
            assert not {"log_time", "log_tick"} & names, entity
    summary = static["/episode/summary"][0].column("TextDocument:text").to_pylist()[0][0]
    assert "short, seed 1, planner dwa" in summary


def test_positions_and_scalars_match_the_record(rrd) -> None:  # type: ignore[no-untyped-def]
    path, _, record = rrd
    _, temporal, _ = _read(path)
    n = record.time_s.shape[0]
    for entity, pos in (
        ("/world/pedestrians/factual", record.factual_pos),
        ("/world/pedestrians/counterfactual", record.counterfactual_pos),
    ):
        steps, values = _column(temporal[entity], "Points2D:positions")
        assert np.array_equal(steps, np.arange(n))
        xy = np.array([np.array(v, dtype=np.float64) for v in values])
        assert np.array_equal(xy, pos.astype(np.float32).astype(np.float64)), entity
    steps, values = _column(temporal["/metrics/twin_separation"], "Scalars:scalars")
    sep = np.array([np.array(v) for v in values])
    assert np.allclose(sep, record.twin_separation_m())
    times = np.concatenate(
        [b.column("sim_time").cast(pa.int64()).to_numpy() for b in temporal["/world/robot"]]
    )
    assert np.array_equal(np.sort(times), np.round(record.time_s * 1e9).astype(np.int64)) or (
        np.abs(np.sort(times) - record.time_s * 1e9).max() <= 1
    )
    steps, _ = _column(temporal["/events"], "TextLog:text")
    assert sorted(steps.tolist()) == sorted(e.step for e in record.events)


def test_force_arrows_are_the_model_forces(rrd) -> None:  # type: ignore[no-untyped-def]
    path, scenario, record = rrd
    _, temporal, _ = _read(path)
    k = 40
    crowd0 = episode_setup(scenario, record.seed).crowd
    crowd = CrowdState(
        pos=record.factual_pos[k].copy(),
        vel=record.factual_vel[k].copy(),
        goal=record.factual_goal[k].copy(),
        radius=crowd0.radius,
        v0=crowd0.v0,
        vmax=crowd0.vmax,
    )
    x, y = record.robot_pose[k, :2]
    fc = force_components(
        crowd,
        record.params,
        RobotBody(x=float(x), y=float(y), radius=record.robot_radius),
        scenario.obstacles,
    )
    for name in ("goal", "pedestrians", "robot", "obstacles"):
        steps, values = _column(temporal[f"/world/forces/{name}"], "Arrows2D:vectors")
        vec = np.array(values[list(steps).index(k)], dtype=np.float64)
        expect = (getattr(fc, name) * FORCE_ARROW_SCALE_S2).astype(np.float32)
        assert np.allclose(vec, expect, atol=1e-6), name


def test_default_blueprint_is_in_the_file(rrd) -> None:  # type: ignore[no-untyped-def]
    path, _, _ = rrd
    _, _, blueprint = _read(path)
    classes = set()
    for chunk in blueprint:
        b = chunk.to_record_batch()
        if "ViewBlueprint:class_identifier" in b.schema.names:
            for value in b.column("ViewBlueprint:class_identifier").to_pylist():
                classes.update(value if isinstance(value, list) else [value])
    assert classes == {"2D", "TimeSeries", "TextDocument", "TextLog"}


def _verify(path: Path) -> None:
    """`rerun rrd verify` accepts the file."""
    done = subprocess.run(
        [sys.executable, "-m", "rerun", "rrd", "verify", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "verified without error" in done.stdout + done.stderr


def test_rerun_rrd_verify_accepts_it(rrd) -> None:  # type: ignore[no-untyped-def]
    path, _, _ = rrd
    _verify(path)


def test_without_forces_and_atomic(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, _metrics = episode("concert", 0, "straight")
    path = tmp_path / "a.rrd"
    path.write_bytes(b"old")
    write_rrd(path, record, scenario=scenario)
    static, temporal, _ = _read(path)
    entities = set(static) | set(temporal)
    assert "/world/pedestrians/factual" in entities
    assert not entities & FORCES
    assert not {"/world/obstacles/walls", "/world/obstacles/pillars"} & entities
    assert [p.name for p in tmp_path.iterdir()] == ["a.rrd"]


def test_rrd_file_mode_is_that_of_every_output(tmp_path: Path, episode, short_scenario) -> None:  # type: ignore[no-untyped-def]
    """Not mkstemp's 0600: the mode a plain open() gives (0o666 less the umask)."""
    import os
    import stat

    scenario, record, _ = episode(short_scenario, 1, "dwa")
    old = os.umask(0o022)
    try:
        write_rrd(tmp_path / "ep.rrd", record, scenario=scenario)
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "ep.rrd").stat().st_mode) == 0o644


def test_a_run_with_entering_pedestrians(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    """corridor_flow: `rerun rrd verify` accepts the recording, and at every step it
    shows exactly the pedestrians there (none at step 0, where nobody has entered)."""
    scenario, record, metrics = episode("corridor_flow", 1, "dwa")
    path = tmp_path / "flow.rrd"
    write_rrd(path, record, scenario=scenario, metrics=metrics, forces=True)
    _verify(path)
    _, temporal, _ = _read(path)
    present = record.present()
    steps, values = _column(temporal["/world/pedestrians/factual"], "Points2D:positions")
    shown = {
        int(k): np.array(v, dtype=np.float64).reshape(-1, 2)
        for k, v in zip(steps, values, strict=True)
    }
    for k in range(record.time_s.shape[0]):
        m = int(present[k].sum())
        xy = shown.get(k, np.zeros((0, 2)))
        assert len(xy) == m, k
        assert np.array_equal(xy, record.factual_pos[k, :m].astype(np.float32).astype(np.float64))
    assert int(present[0].sum()) == 0


def test_identical_runs_write_the_same_recording(tmp_path: Path) -> None:
    """Two runs of the same episode write recordings with the same id and the same
    content (`rerun rrd compare`); another seed gives another id. The files' bytes still
    differ where rerun-sdk draws ids itself (docs/logging.md, "Reproducible files")."""
    from srfm.metrics import episode_metrics
    from srfm.scenarios import load_scenario
    from srfm.sim.episode import run_episode

    scenario = load_scenario("crosswalk")
    paths = []
    for name, seed in (("a", 2), ("b", 2), ("c", 3)):
        record = run_episode(scenario, seed, "straight")
        path = tmp_path / f"{name}.rrd"
        write_rrd(path, record, scenario=scenario, metrics=episode_metrics(record))
        paths.append(path)
    ids = [RrdReader(p).recordings()[0].recording_id for p in paths]
    assert ids[0] == ids[1]
    assert ids[0].startswith("crosswalk-straight-2-")
    assert ids[2] != ids[0]
    layouts = [{c.entity_path for c in _read(p)[2]} for p in paths]
    assert layouts[0] == layouts[1] == layouts[2]  # fixed view ids

    def compare(a: Path, b: Path) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "rerun", "rrd", "compare", "--unordered", str(a), str(b)],
            capture_output=True,
            text=True,
            timeout=120,
        )

    assert compare(paths[0], paths[1]).returncode == 0, compare(paths[0], paths[1]).stderr
    assert compare(paths[0], paths[2]).returncode != 0
