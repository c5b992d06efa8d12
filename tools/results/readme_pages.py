"""The README's generated install table: what the quick start's first install costs,
from ``docs/results/performance/install.json`` (``tools/bench/bench_install.py``).
``tools/results/generate.py`` registers :data:`BLOCKS`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from tools.results import performance_pages
from tools.results.fitting_pages import prose

INSTALL = "install.json"  # in docs/results/performance/
TARGETS = {
    "run": (
        "`make benchmark`",
        "srfm without extras (what the quick benchmark needs; the shipped TD3 policies run "
        "on NumPy)",
    ),
    "dev": (
        "`make test`",
        "srfm with every extra: `dev,rl,sbx,dask,sweep,docs,release` (torch, JAX, Dask, MkDocs, …)",
    ),
}


def _duration(seconds: float) -> str:
    """``72 s`` below two minutes, else ``3 min 33 s``."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    minutes, rest = divmod(round(seconds), 60)
    return f"{minutes} min {rest} s"


def _index(config: list[str]) -> str:
    """Where pip took the packages from, as its configuration says."""

    def values(key: str) -> set[str]:
        return {
            value
            for line in config
            if key in line
            for value in line.split("=", 1)[1].strip("'").split()
        }

    links, extra = values("find-links"), values("index-url")
    parts = ["the default index (PyPI)"]
    if extra:
        parts.append("extra indexes " + ", ".join(f"`{x}`" for x in sorted(extra)))
    if links:
        parts.append("local wheels in " + ", ".join(f"`{x}`" for x in sorted(links)))
    return " and ".join(parts)


def readme_install() -> str:
    """What the first install of each quick-start target costs."""
    doc: dict[str, Any] = performance_pages.record(INSTALL)  # checked: what its command wrote
    run = doc["run"]
    head = prose(
        "What the first install costs (a new `.venv`, pip's cache off, Python "
        f"{doc['python']}; measured {run['started'][:10]} on commit `{run['commit']}`, "
        f"{run['machine']}, packages from "
        f"{_index(doc['pip_config'])}: `{run['command']}`):"
    )
    lines = ["| target | installs | time | `.venv` size |", "|---|---|---|---|"]
    for step in doc["steps"]:
        target, what = TARGETS[step["step"]]
        lines.append(
            f"| {target} | {what} | {_duration(step['seconds'])} | "
            f"{step['venv_bytes'] / 1e9:.1f} GB |"
        )
    return head + "\n\n" + "\n".join(lines)


BLOCKS: dict[str, Callable[[], str]] = {"readme-install": readme_install}
