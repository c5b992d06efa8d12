"""The sweep specification: a TOML file read into a validated :class:`SweepSpec`.

A spec names the scenarios, planners and seeds every cell runs, the base SRFM
parameters, and a design over *factors*: any :class:`~srfm.models.params.SRFMParams`
field, and three scenario factors (``crowd_size`` for scenarios of kind ``random``,
``ped_radius_m`` and ``ped_speed_mps`` for every pedestrian)::

    schema_version = 1
    scenarios = ["footpath", "crosswalk"]   # names or TOML files (relative to the spec)
    planners = ["td3-srfm", "dwa"]
    seeds = "0-29"                          # or a list of seeds
    params = "agrawal2024"                  # optional: base preset or parameter file
    seeds_per_task = 10                     # optional: episodes per scheduled task

    [design]
    kind = "grid"                           # "grid": every combination of the lists
    [design.factors]
    a_robot = [0.0, 7.93, 15.86]
    b_robot = [0.5, 1.0, 1.5]

A random design draws ``samples`` cells with its own ``seed``; each factor is a
``{low = .., high = ..}`` range (uniform) or a list to choose from::

    [design]
    kind = "random"
    samples = 20
    seed = 1
    [design.factors]
    a_robot = { low = 0.0, high = 15.86 }
    crowd_size = [5, 10, 20]

Every mistake is a :class:`~srfm.errors.SweepError` naming the file and the key.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np

from srfm import _validate
from srfm._io import MAX_TOML_BYTES, parse_toml, read_input_text
from srfm._text import plain
from srfm.errors import SrfmError, SweepError
from srfm.models.params import SRFMParams, load_params
from srfm.models.state import MAX_RADIUS_M
from srfm.scenarios import Scenario, load_scenario

__all__ = [
    "MAX_CELLS",
    "SCENARIO_FACTORS",
    "SPEC_SCHEMA",
    "Cell",
    "SweepSpec",
    "apply_scenario_factors",
    "load_spec",
]

SPEC_SCHEMA: Final = 1
MAX_CELLS: Final = 100_000
MAX_CROWD: Final = 1_000
SCENARIO_FACTORS: Final = ("crowd_size", "ped_radius_m", "ped_speed_mps")
"""Factors that change the scenario rather than the model parameters."""
PARAM_FACTORS: Final = tuple(attrs.fields_dict(SRFMParams))
_TOP_KEYS: Final = {
    "schema_version",
    "name",
    "scenarios",
    "planners",
    "seeds",
    "params",
    "seeds_per_task",
    "design",
}


@attrs.frozen
class Cell:
    """One cell of the design: an id and the factor values (in the spec's order)."""

    id: str
    values: tuple[tuple[str, float], ...]

    def as_dict(self) -> dict[str, float]:
        """Factor name -> value."""
        return dict(self.values)


@attrs.frozen(kw_only=True, eq=False)
class SweepSpec:
    """A validated sweep specification (see the module docstring).

    Attributes:
        source: the spec file.
        name: a label for reports.
        scenarios: the scenarios every cell runs.
        planners: planner names.
        seeds: episode seeds, the same in every cell.
        params: the base SRFM parameters (the factors change some fields per cell).
        factors: the design's factor names, in the spec's order.
        cells: the design's cells.
        seeds_per_task: episodes per scheduled task.
        design: the design as read (for the manifest).
    """

    source: Path
    name: str
    scenarios: tuple[Scenario, ...]
    planners: tuple[str, ...]
    seeds: tuple[int, ...]
    params: SRFMParams
    factors: tuple[str, ...]
    cells: tuple[Cell, ...]
    seeds_per_task: int
    design: Mapping[str, Any]

    @property
    def episodes(self) -> int:
        """Episodes in the whole sweep."""
        return len(self.cells) * len(self.scenarios) * len(self.planners) * len(self.seeds)

    def cell_params(self, cell: Cell) -> SRFMParams:
        """The SRFM parameters of ``cell``."""
        changes = {k: v for k, v in cell.values if k in PARAM_FACTORS}
        return self.params.replace(**changes) if changes else self.params

    def identity(self) -> dict[str, Any]:
        """What a results folder must have been made with to be resumed (JSON-ready)."""
        from srfm.benchmark._results import fingerprint

        return {
            "scenarios": {s.name: fingerprint(s) for s in self.scenarios},
            "planners": list(self.planners),
            "seeds": list(self.seeds),
            "params": self.params.as_dict(),
            "factors": list(self.factors),
            "cells": {c.id: c.as_dict() for c in self.cells},
            "seeds_per_task": self.seeds_per_task,
        }


class _Where:
    """Errors that name the spec file and the key."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, key: str, message: str) -> SweepError:
        return SweepError(f"{self.path}: {key}: {message}")


def _string_list(where: _Where, key: str, value: Any) -> list[str]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value:
        raise where.error(key, f"must be a non-empty list of names, got {plain(value)}")
    for item in value:
        if not isinstance(item, str) or not item.strip():
            raise where.error(key, f"must hold names (strings), got {plain(item)}")
    if len(set(value)) != len(value):
        dupes = sorted({v for v in value if value.count(v) > 1})
        raise where.error(key, f"names given twice: {', '.join(dupes)}")
    return [v.strip() for v in value]


def _seeds(where: _Where, value: Any) -> tuple[int, ...]:
    from srfm.benchmark import MAX_SEEDS

    seeds: list[int] = []
    if isinstance(value, str):
        for part in value.split(","):
            texts = part.strip().split("-")
            bounds = [n for t in texts if (n := _validate.decimal(t.strip())) is not None]
            if len(texts) > 2 or len(bounds) != len(texts):  # ASCII digits: not ٣, not 1_000
                raise where.error("seeds", f"{part.strip()!r} is not a seed or a range like 0-29")
            a, b = bounds[0], bounds[-1]
            if b < a or b - a + 1 + len(seeds) > MAX_SEEDS:
                raise where.error("seeds", f"bad range {part.strip()!r} (at most {MAX_SEEDS})")
            seeds.extend(range(a, b + 1))
    elif isinstance(value, list):
        seeds = list(value)
    else:
        raise where.error("seeds", f"must be a range like '0-29' or a list, got {plain(value)}")
    if not seeds:
        raise where.error("seeds", "must name at least one seed")
    for s in seeds:
        if isinstance(s, bool) or not isinstance(s, int):
            raise where.error("seeds", f"seeds must be integers, got {plain(s)}")
        _validate.seed(s, SweepError)
    if len(set(seeds)) != len(seeds):
        raise where.error("seeds", "a seed is given twice")
    return tuple(seeds)


def _number(where: _Where, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise where.error(key, f"must be a finite number, got {plain(value)}")
    return float(value)


def _check_value(where: _Where, key: str, name: str, value: float, base: SRFMParams) -> float:
    """A factor value the model or the scenario accepts."""
    if name in PARAM_FACTORS:
        try:
            base.replace(**{name: value})
        except SrfmError as exc:
            raise where.error(key, str(exc)) from None
    elif name == "crowd_size":
        if value != int(value) or not 1 <= value <= MAX_CROWD:
            raise where.error(
                key, f"must be a whole number in [1, {MAX_CROWD}], got {plain(value)}"
            )
    elif name == "ped_radius_m":
        if not 0.0 < value <= MAX_RADIUS_M:
            raise where.error(key, f"must be in (0, {MAX_RADIUS_M:g}] m, got {plain(value)}")
    elif not 0.0 <= value <= _validate.MAX_PEDESTRIAN_SPEED_MPS:  # ped_speed_mps: as in a scenario
        raise where.error(
            key, f"must be in [0, {_validate.MAX_PEDESTRIAN_SPEED_MPS:g}] m/s, got {plain(value)}"
        )
    return value


def _grid(
    where: _Where, factors: Mapping[str, Any], base: SRFMParams
) -> list[tuple[tuple[str, float], ...]]:
    axes: list[list[float]] = []
    for name, values in factors.items():
        key = f"design.factors.{name}"
        if not isinstance(values, list) or not values:
            raise where.error(key, f"a grid factor must be a non-empty list, got {plain(values)}")
        checked = [_check_value(where, key, name, _number(where, key, v), base) for v in values]
        if len(set(checked)) != len(checked):
            raise where.error(key, "a value is given twice")
        axes.append(checked)
    count = math.prod(len(a) for a in axes)
    if count > MAX_CELLS:
        raise where.error("design.factors", f"{count} cells; at most {MAX_CELLS}")
    names = list(factors)
    return [tuple(zip(names, combo, strict=True)) for combo in itertools.product(*axes)]


def _random(
    where: _Where, design: Mapping[str, Any], factors: Mapping[str, Any], base: SRFMParams
) -> list[tuple[tuple[str, float], ...]]:
    samples, seed = design.get("samples"), design.get("seed")
    if isinstance(samples, bool) or not isinstance(samples, int) or not 1 <= samples <= MAX_CELLS:
        raise where.error("design.samples", f"must be a whole number in [1, {MAX_CELLS}]")
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise where.error("design.seed", f"must be an integer seed, got {plain(seed)}")
    _validate.seed(seed, SweepError)
    draws: dict[str, list[float]] = {}
    rng = np.random.default_rng(seed)
    for name, rule in factors.items():
        key = f"design.factors.{name}"
        if isinstance(rule, list) and rule:
            choices = [_number(where, key, v) for v in rule]
            picked = rng.integers(0, len(choices), size=samples)
            values = [choices[int(i)] for i in picked]
        elif isinstance(rule, dict) and set(rule) == {"low", "high"}:
            low = _number(where, f"{key}.low", rule["low"])
            high = _number(where, f"{key}.high", rule["high"])
            if not low < high:
                raise where.error(key, f"low must be below high, got {plain(low)} and {high!r}")
            values = [float(v) for v in rng.uniform(low, high, size=samples)]
            if name == "crowd_size":
                raise where.error(key, "crowd_size takes a list of sizes, not a range")
        else:
            raise where.error(
                key, f"a random factor is {{low = .., high = ..}} or a list, got {plain(rule)}"
            )
        draws[name] = [_check_value(where, key, name, v, base) for v in values]
    return [tuple((name, draws[name][i]) for name in factors) for i in range(samples)]


def _cell_id(values: tuple[tuple[str, float], ...]) -> str:
    """A name for a cell made from its values (the same values: the same name)."""
    text = json.dumps([[k, v] for k, v in values])
    return "c" + hashlib.sha256(text.encode("utf-8")).hexdigest()[:12]


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a sweep spec (see the module docstring).

    Raises:
        SweepError: a missing or malformed file, or a bad key or value; the message
            names the file and the key.
    """
    path = Path(path)
    where = _Where(path)
    text = read_input_text(path, max_bytes=MAX_TOML_BYTES, error=SweepError, what="sweep spec")
    data = parse_toml(text, path, SweepError)
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise where.error(unknown[0], f"unknown key; known: {', '.join(sorted(_TOP_KEYS))}")
    if data.get("schema_version") != SPEC_SCHEMA:
        raise where.error(
            "schema_version", f"must be {SPEC_SCHEMA}, got {plain(data.get('schema_version'))}"
        )
    name = data.get("name", path.stem)
    if not isinstance(name, str):
        raise where.error("name", f"must be a string, got {plain(name)}")
    for key in ("scenarios", "planners", "seeds", "design"):
        if key not in data:
            raise where.error(key, "is required")
    scenarios = []
    for item in _string_list(where, "scenarios", data["scenarios"]):
        ref: str | Path = item
        if item.endswith(".toml") and not Path(item).is_absolute():
            ref = path.parent / item
        try:
            scenarios.append(load_scenario(ref))
        except SrfmError as exc:
            raise where.error("scenarios", str(exc)) from None
    if len({s.name for s in scenarios}) != len(scenarios):
        raise where.error("scenarios", "two scenarios have the same name")
    planners = _string_list(where, "planners", data["planners"])
    from srfm.sim.episode import build_planner

    for planner in planners:
        try:
            build_planner(planner)
        except SrfmError as exc:
            raise where.error("planners", str(exc)) from None
    seeds = _seeds(where, data["seeds"])
    base = SRFMParams()
    if "params" in data:
        ref_params = data["params"]
        if not isinstance(ref_params, str):
            raise where.error("params", f"must be a preset name or a file, got {plain(ref_params)}")
        try:
            if ref_params.endswith(".toml"):
                file = Path(ref_params)
                base = load_params(file if file.is_absolute() else path.parent / file)
            else:
                base = SRFMParams.preset(ref_params)
        except SrfmError as exc:
            raise where.error("params", str(exc)) from None
    per_task = data.get("seeds_per_task", 10)
    if isinstance(per_task, bool) or not isinstance(per_task, int) or not 1 <= per_task <= 1000:
        raise where.error(
            "seeds_per_task", f"must be a whole number in [1, 1000], got {plain(per_task)}"
        )
    design = data["design"]
    if not isinstance(design, dict):
        raise where.error("design", f"must be a table, got {plain(design)}")
    kind = design.get("kind")
    allowed = {"kind", "factors"} | ({"samples", "seed"} if kind == "random" else set())
    extra = sorted(set(design) - allowed)
    if extra:
        raise where.error(f"design.{extra[0]}", f"unknown key for a {kind!r} design")
    factors = design.get("factors")
    if not isinstance(factors, dict) or not factors:
        raise where.error("design.factors", "must be a table of at least one factor")
    for factor in factors:
        if factor not in PARAM_FACTORS and factor not in SCENARIO_FACTORS:
            known = ", ".join((*PARAM_FACTORS, *SCENARIO_FACTORS))
            raise where.error(f"design.factors.{factor}", f"unknown factor; known: {known}")
    if "crowd_size" in factors:
        fixed = [s.name for s in scenarios if s.random is None]
        if fixed:
            raise where.error(
                "design.factors.crowd_size",
                f"the crowd size of a scenario of kind 'fixed' is its list of pedestrians; "
                f"only scenarios of kind 'random' take it ({', '.join(fixed)} are fixed)",
            )
    if kind == "grid":
        combos = _grid(where, factors, base)
    elif kind == "random":
        combos = _random(where, design, factors, base)
    else:
        raise where.error("design.kind", f"must be 'grid' or 'random', got {plain(kind)}")
    cells = tuple(Cell(_cell_id(values), values) for values in combos)
    if len({c.id for c in cells}) != len(cells):
        raise where.error("design", "two cells have the same values")
    return SweepSpec(
        source=path,
        name=name,
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        seeds=seeds,
        params=base,
        factors=tuple(factors),
        cells=cells,
        seeds_per_task=per_task,
        design=design,
    )


def apply_scenario_factors(scenario: Scenario, values: Mapping[str, float]) -> Scenario:
    """``scenario`` with the cell's scenario factors applied (the same object when the
    cell has none): ``crowd_size`` sets the count of a random scenario, ``ped_radius_m``
    every pedestrian's radius, ``ped_speed_mps`` every desired speed (the maximum speed
    is raised to it where it is lower)."""
    changes: dict[str, Any] = {}
    if "crowd_size" in values:
        if scenario.random is None:
            raise SweepError(f"scenario {scenario.name!r} is of kind 'fixed': no crowd_size")
        changes["random"] = attrs.evolve(scenario.random, count=int(values["crowd_size"]))
    if "ped_radius_m" in values:
        changes["ped_radius_m"] = float(values["ped_radius_m"])
    if "ped_speed_mps" in values:
        speed = float(values["ped_speed_mps"])
        changes["ped_desired_speed_mps"] = speed
        changes["ped_max_speed_mps"] = np.maximum(scenario.ped_max_speed_mps, speed)
        if np.ndim(changes["ped_max_speed_mps"]) == 0:
            changes["ped_max_speed_mps"] = float(changes["ped_max_speed_mps"])
    return attrs.evolve(scenario, **changes) if changes else scenario
