"""What a benchmark runs (:class:`BenchmarkRequest`) and the manifest that ties a
results folder to it.

``manifest.json`` records what every episode file of a folder was run with (package
versions, SRFM and metric parameters, each scenario's content) and the request and
command of the run that wrote it last; a run on an existing folder is checked against
it (:func:`check_manifest`), and the results page shows it (:mod:`srfm.benchmark._html`).
The runner, the figures and the results page all take the request from here.
"""

from __future__ import annotations

import collections
import json
import platform
from collections.abc import Sequence
from importlib import metadata
from pathlib import Path
from typing import Any, Final

import attrs

from srfm import _validate
from srfm._io import MAX_DOCUMENT_BYTES, read_input_bytes
from srfm._validate import path_name, planner_name
from srfm._version import DISTRIBUTION
from srfm.benchmark._results import fingerprint
from srfm.errors import BenchmarkError
from srfm.metrics import MetricParams
from srfm.metrics.report import MANIFEST
from srfm.models.params import SRFMParams
from srfm.planners import available_planners
from srfm.scenarios import EVALUATION_SCENARIOS, Scenario, load_scenario
from srfm.scenarios._schema import MAX_CROWD_SUBSTEPS
from srfm.sim.episode import build_planner

__all__ = [
    "MANIFEST",
    "MANIFEST_SCHEMA",
    "MAX_SEEDS",
    "QUICK_SEEDS",
    "BenchmarkRequest",
    "check_manifest",
    "check_manifest_schema",
    "default_planners",
    "new_manifest",
    "package_versions",
]

QUICK_SEEDS: Final = (0, 1, 2)
"""Seeds of ``--quick``: enough for a mean, a standard deviation and the tests."""
MAX_SEEDS: Final = 100_000
"""Most seeds in one request (each is a file per scenario and planner)."""


def default_planners() -> tuple[str, ...]:
    """Every registered planner that runs on any scenario (``default``), by name."""
    return tuple(p.name for p in available_planners() if p.default)


@attrs.frozen(kw_only=True, eq=False)
class BenchmarkRequest:
    """What to run.

    Attributes:
        scenarios: the scenarios (built-in or from files), in table order.
        planners: planner names (registry names or ``module:attribute``), in table order.
        seeds: episode seeds, shared by every (scenario, planner) cell.
        params: SRFM parameters of the factual crowd.
        reference: the planner others are tested against (None: no significance tests).
        figure_seed: the seed drawn in the path figures (the first seed when None).
    """

    scenarios: tuple[Scenario, ...]
    planners: tuple[str, ...]
    seeds: tuple[int, ...]
    params: SRFMParams = attrs.field(factory=SRFMParams)
    reference: str | None = None
    figure_seed: int | None = None

    def __attrs_post_init__(self) -> None:
        if len(self.seeds) > MAX_SEEDS:
            raise BenchmarkError(
                f"{len(self.seeds)} seeds requested; at most {MAX_SEEDS} in one benchmark"
            )
        for s in self.seeds:
            _validate.seed(s, BenchmarkError)
        for scenario in self.scenarios:
            path_name(scenario.name, "scenario name", BenchmarkError)
        for name in self.planners:
            planner_name(name, BenchmarkError)
        for label, items in (
            ("scenario", [s.name for s in self.scenarios]),
            ("planner", list(self.planners)),
            ("seed", [str(s) for s in self.seeds]),
        ):
            if not items:
                raise BenchmarkError(f"the benchmark needs at least one {label}")
            counts = collections.Counter(items)  # linear: 100,000 seeds check at once
            dupes = sorted(x for x, k in counts.items() if k > 1)
            if dupes:
                shown = ", ".join(dupes[:10]) + (", ..." if len(dupes) > 10 else "")
                raise BenchmarkError(f"{label}s given twice: {shown}")
        if self.reference is not None and self.reference not in self.planners:
            raise BenchmarkError(
                f"reference planner {self.reference!r} is not among the planners "
                f"{list(self.planners)}"
            )
        if self.figure_seed is not None and self.figure_seed not in self.seeds:
            raise BenchmarkError(f"figure seed {self.figure_seed} is not among the seeds")

    @property
    def drawn_seed(self) -> int:
        """The seed of the path figures."""
        return self.seeds[0] if self.figure_seed is None else self.figure_seed

    @classmethod
    def create(
        cls,
        *,
        scenarios: Sequence[str] | None = None,
        planners: Sequence[str] | None = None,
        seeds: Sequence[int] | None = None,
        params: SRFMParams | None = None,
        reference: str | None = None,
        quick: bool = False,
        crowd_substeps: int | None = None,
    ) -> BenchmarkRequest:
        """A request with the defaults filled in: the five evaluation scenarios, every
        registered planner, seeds 0–99 (``quick``: seeds 0–2); the reference is
        ``td3-srfm`` when it runs, else none. ``crowd_substeps`` replaces every
        scenario's crowd substeps (:attr:`srfm.scenarios.Scenario.crowd_substeps`)."""
        scenario_objs = tuple(load_scenario(s) for s in (scenarios or EVALUATION_SCENARIOS))
        if crowd_substeps is not None:
            if (
                isinstance(crowd_substeps, bool)
                or not isinstance(crowd_substeps, int)
                or not 1 <= crowd_substeps <= MAX_CROWD_SUBSTEPS
            ):
                raise BenchmarkError(
                    f"crowd_substeps must be an integer in [1, {MAX_CROWD_SUBSTEPS}], "
                    f"got {crowd_substeps!r}"
                )
            scenario_objs = tuple(
                attrs.evolve(s, crowd_substeps=crowd_substeps) for s in scenario_objs
            )
        planner_names = tuple(planners) if planners else default_planners()
        for name in planner_names:
            build_planner(name)  # an unknown name or a failing factory: here, before any work
        if seeds is None:
            seeds = QUICK_SEEDS if quick else tuple(range(100))
        if reference is None and "td3-srfm" in planner_names:
            reference = "td3-srfm"
        return cls(
            scenarios=scenario_objs,
            planners=planner_names,
            seeds=tuple(int(s) for s in seeds),
            params=params or SRFMParams(),
            reference=reference,
        )


MANIFEST_SCHEMA: Final = "srfm.benchmark_manifest/2"
"""Layout of ``manifest.json``. 2 (issue 16): the metrics of docs/metrics.md, the metric
thresholds, the request and the command; a folder of schema 1 holds episode files
without those metrics and is refused."""


def package_versions() -> dict[str, str]:
    """The versions a results folder was made with: Python, srfm (the version of the
    installed distribution, :data:`srfm._version.DISTRIBUTION`, under the key ``srfm``),
    NumPy, numba and SciPy."""
    out = {"python": platform.python_version()}
    for key, dist in (
        ("srfm", DISTRIBUTION),
        ("numpy", "numpy"),
        ("numba", "numba"),
        ("scipy", "scipy"),
    ):
        try:
            out[key] = metadata.version(dist)
        except metadata.PackageNotFoundError:  # pragma: no cover - always installed
            out[key] = "unknown"
    return out


def new_manifest(request: BenchmarkRequest, command: str | None) -> dict[str, Any]:
    """The identity of a results folder: what every episode file in it was run with,
    and the request and command of the run that wrote it last."""
    return {
        "schema": MANIFEST_SCHEMA,
        "versions": package_versions(),
        "params": request.params.as_dict(),
        "metric_params": MetricParams().as_dict(),
        "scenarios": {s.name: fingerprint(s) for s in request.scenarios},
        "request": {
            "scenarios": [s.name for s in request.scenarios],
            "planners": list(request.planners),
            "seeds": list(request.seeds),
            "reference": request.reference,
            "figure_seed": request.drawn_seed,
        },
        "command": command,
    }


def check_manifest_schema(path: Path, doc: Any) -> None:
    """Refuse a manifest that is not srfm's current layout, saying what to do.

    Raises:
        BenchmarkError: not a JSON object of srfm's, or of an older or newer schema.
    """
    if not isinstance(doc, dict) or not isinstance(doc.get("scenarios", {}), dict):
        raise BenchmarkError(f"{path}: damaged manifest (not srfm's layout); use a new --out")
    schema = doc.get("schema")
    if schema == MANIFEST_SCHEMA:
        return
    if isinstance(schema, str) and schema.startswith("srfm.benchmark_manifest/"):
        raise BenchmarkError(
            f"{path.parent}: a results folder of an older or newer srfm (manifest schema "
            f"{schema!r}; this srfm reads {MANIFEST_SCHEMA!r}): its episode files lack the "
            "metrics of docs/metrics.md or hold others. Run the benchmark again into a new "
            "--out folder"
        )
    raise BenchmarkError(f"{path}: not an srfm benchmark folder (schema {schema})")


def check_manifest(
    out: Path, request: BenchmarkRequest, command: str | None = None
) -> dict[str, Any]:
    """Create the manifest, or check that an existing one matches the request.

    Episodes of a folder must all come from the same parameters, scenario content and
    package versions; adding scenarios, planners or seeds to a folder is fine.
    """
    path = out / MANIFEST
    new = new_manifest(request, command)
    if not path.exists():
        return new
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES, error=BenchmarkError, what="benchmark manifest"
    )
    try:
        old = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise BenchmarkError(
            f"{path}: damaged manifest ({exc}); the folder's episodes cannot be trusted to "
            "match the request: use a new --out"
        ) from None
    check_manifest_schema(path, old)
    for key in ("versions", "params", "metric_params"):
        if old.get(key) != new[key]:
            raise BenchmarkError(
                f"{out} holds episodes run with other {key} ({old.get(key)} != {new[key]}); "
                "use a new --out folder"
            )
    known = old.get("scenarios", {})
    for name, digest in new["scenarios"].items():
        if name in known and known[name] != digest:
            raise BenchmarkError(
                f"{out} holds episodes of a different scenario {name!r} (content changed); "
                "use a new --out folder"
            )
    merged = dict(new)
    merged["scenarios"] = {**known, **new["scenarios"]}
    return merged
