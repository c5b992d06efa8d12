"""The package's layout: no import cycle among srfm's modules, and no package imports a
package of a higher layer (the layers of docs/design.md and README.md, "Layout").

Every ``import`` and ``from ... import`` of every module counts, also those inside
functions and under ``if TYPE_CHECKING:``: a lazy import hides a cycle from Python, not
from a reader.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping
from pathlib import Path

import srfm

SRFM = Path(srfm.__file__).parent

# srfm's packages (and top-level modules), from the bottom layer up: a package may
# import only packages of lower layers (and its own modules); the packages of one layer
# do not import each other. "srfm" is the package's face, srfm/__init__.py.
LAYERS: tuple[tuple[str, ...], ...] = (
    # policies: the shipped policy files, no code; _text: message text; _version: the
    # distribution's name and version, from its metadata; _blas: SciPy's BLAS for numba,
    # loaded by the srfm program before numba looks for it
    ("errors", "policies", "_text", "_version", "_blas"),
    ("_deps", "_io", "_jit", "_lazy", "_streams", "_user_code", "_validate"),
    ("models", "datasets"),
    ("world",),
    ("scenarios",),
    ("planners",),
    ("sim",),
    ("metrics", "rl"),
    ("logs", "fitting"),
    ("benchmark",),
    ("sweep",),
    ("cli", "srfm"),
)
LAYER = {package: k for k, layer in enumerate(LAYERS) for package in layer}

Edge = tuple[str, str, int]  # importer module, imported module, line


def _modules() -> dict[str, Path]:
    """Every module of srfm by its dotted name (a package by its own name)."""
    out = {}
    for path in sorted(SRFM.rglob("*.py")):
        parts = list(path.relative_to(SRFM.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _imported(node: ast.Import | ast.ImportFrom, package: str) -> list[str]:
    """The dotted names an import statement names (``from a import b``: ``a.b``)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    base = node.module or ""
    if node.level:  # relative: resolved against the importing module's package
        anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
        base = ".".join([*anchor, *([base] if base else [])])
    return [f"{base}.{alias.name}" for alias in node.names]


def import_edges(modules: Mapping[str, Path]) -> list[Edge]:
    """(importer, imported, line) for every import of one srfm module by another."""
    edges: set[Edge] = set()
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Import | ast.ImportFrom):
                continue
            for dotted in _imported(node, package):
                target = dotted
                while target and target not in modules:  # a name inside a module
                    target = target.rpartition(".")[0]
                if target and target != name:
                    edges.add((name, target, node.lineno))
    return sorted(edges)


def cycles(nodes: Iterable[str], edges: Iterable[tuple[str, str]]) -> list[list[str]]:
    """The strongly connected components of more than one node (Tarjan), sorted."""
    graph: dict[str, set[str]] = {n: set() for n in nodes}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def _package(module: str) -> str:
    """The layer unit of a module: ``srfm.sim.episode`` -> ``sim``; ``srfm`` -> ``srfm``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "srfm"


def test_the_cycle_finder_finds_a_lazy_circle() -> None:
    assert cycles("abcd", [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]) == [["a", "b", "c"]]
    assert cycles("abc", [("a", "b"), ("b", "c"), ("a", "c")]) == []
    source = "def f():\n    from srfm.sim import episode\n"
    tree = ast.parse(source)
    node = next(n for n in ast.walk(tree) if isinstance(n, ast.ImportFrom))
    assert _imported(node, "srfm.scenarios") == ["srfm.sim.episode"]


def test_no_import_cycle_among_srfm_modules() -> None:
    modules = _modules()
    edges = import_edges(modules)
    found = cycles(modules, [(a, b) for a, b, _ in edges])
    lines = []
    for component in found:
        lines.append(" <-> ".join(component))
        lines.extend(
            f"    {a} -> {b} (line {n})" for a, b, n in edges if a in component and b in component
        )
    assert not found, "import cycles:\n" + "\n".join(lines)


def test_every_package_has_one_layer() -> None:
    listed = [package for layer in LAYERS for package in layer]
    assert len(listed) == len(set(listed)), "a package in two layers"
    packages = {_package(m) for m in _modules()}
    assert packages - set(LAYER) == set(), "add the new package to LAYERS (and to README.md)"
    assert set(LAYER) - packages == set(), "LAYERS names a package that is gone"


def test_no_package_imports_a_higher_or_equal_layer() -> None:
    modules = _modules()
    wrong = [
        f"{modules[a].relative_to(SRFM.parent)}:{n}: {a} imports {b} ({_package(a)} is in "
        f"layer {LAYER[_package(a)]}, {_package(b)} in layer {LAYER[_package(b)]})"
        for a, b, n in import_edges(modules)
        if _package(a) != _package(b) and LAYER[_package(a)] <= LAYER[_package(b)]
    ]
    assert not wrong, "imports that go up (or sideways) in LAYERS:\n" + "\n".join(wrong)
