"""The layering of the package (DESIGN's "Layout"), read from the sources with ``ast``.

Every module of ``cdt_plugin`` (and of the adapters, installed as
``cdt_plugin.adapters``) has a layer in :data:`LAYERS`, bottom up; a module the
table does not place fails the test, so a new module must be placed. Every
import counts, at module level, inside a function or under ``TYPE_CHECKING``:

* no import runs up the layer order (imports within a layer are fine);
* no import circle among the modules (strongly connected components of the
  import graph);
* no module of the engine imports ``cdt_plugin.adapters`` except the
  conversion hooks, :data:`HOOKS` (the one documented exception, whose imports
  of the adapters are also the only upward imports allowed);
* the compiled kernels live in ``_core`` and nothing imports another module's
  ``_private`` names.

The checks are plain functions of a graph, so the tests below also feed them
made-up graphs and show that each one fails where it should.
"""
from __future__ import annotations

import ast
from pathlib import Path
from typing import Iterable, Iterator, Mapping

import pytest

ROOT = Path(__file__).resolve().parents[2]

#: The layers, bottom up: a module imports only from its own layer and those below.
#: A name ending in ``*`` places every module under that prefix.
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("kernels", ("cdt_plugin._core*",)),
    ("types, errors, validation, helpers", (
        "cdt_plugin.types", "cdt_plugin.errors", "cdt_plugin.validate", "cdt_plugin.parallel",
        "cdt_plugin.interrupts", "cdt_plugin.optional", "cdt_plugin.switches",
        "cdt_plugin.hooks",       # the conversion hooks: imports the adapters inside its functions
        "cdt_plugin.options",     # the options record, checked once
        "cdt_plugin.compiling",   # the cache guard, imported first by __init__
        "cdt_plugin.fields",      # the size field type: checked and evaluated
        "cdt_plugin.planar",      # planes of 3D input
    )),
    ("plc", ("cdt_plugin.plc", "cdt_plugin.merging")),
    ("route drivers", ("cdt_plugin._routes", "cdt_plugin.plain")),
    ("services of the results", ("cdt_plugin.queries", "cdt_plugin.report", "cdt_plugin.plot",
                                 "cdt_plugin.voronoi", "cdt_plugin.markers",
                                 "cdt_plugin.quadratic", "cdt_plugin.refining", "cdt_plugin.fem",
                                 "cdt_plugin.grading", "cdt_plugin.smoothing")),
    ("results", ("cdt_plugin.triangulation",)),
    ("public functions", ("cdt_plugin", "cdt_plugin.delaunay", "cdt_plugin.cdt", "cdt_plugin.dynamic",
                          "cdt_plugin.batch", "cdt_plugin.lift", "cdt_plugin.sizing",
                          "cdt_plugin.nearness", "cdt_plugin.faces",
                          "cdt_plugin.solids")),
    ("tools and adapters", ("cdt_plugin.io*", "cdt_plugin.warmup", "cdt_plugin.adapters*",
                            "cdt_plugin.triangle*")),
    ("command line", ("cdt_plugin.cli*", "cdt_plugin.__main__")),
]

#: The one module of the engine that may import the adapters (inside its functions).
HOOKS = "cdt_plugin.hooks"
ADAPTERS = "cdt_plugin.adapters"

def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[0] == "adapters":                       # installed as cdt_plugin.adapters
        parts = ["cdt_plugin", *parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> list[tuple[str, Path, ast.Module]]:
    paths = sorted((ROOT / "cdt_plugin").rglob("*.py")) + sorted((ROOT / "adapters").rglob("*.py"))
    return [(_module_name(p), p, ast.parse(p.read_text(), str(p))) for p in paths]


def _imports(module: str, path: Path, tree: ast.Module) -> Iterator[tuple[str, list[str], bool]]:
    """``(target module, imported names, at module level)`` of every import of the
    package by ``module``, wherever it stands; relative imports resolved."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    top_level = {id(node) for node in tree.body}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            target, names = "", [a.name for a in node.names]
        else:
            continue
        for full in ([target] if target else names):
            if full.startswith("cdt_plugin"):
                yield full, (names if target else []), id(node) in top_level


MODULES = _modules()
NAMES = {m for m, _, _ in MODULES}


def import_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports. ``from P import m`` of a
    submodule ``m`` is an edge to ``P.m``, not to the package ``P`` (a package's
    ``__init__`` runs before any of its modules anyway)."""
    graph: dict[str, set[str]] = {m: set() for m in NAMES}
    for module, path, tree in MODULES:
        for target, names, _ in _imports(module, path, tree):
            subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in NAMES]
            rest = len(subs) < len(names) or not names
            for t in subs + ([target] if rest else []):
                if t != module:
                    graph[module].add(t)
    return graph


# ------------------------------------------------------------------ the checks
def layer_of(module: str, layers: list[tuple[str, tuple[str, ...]]] = LAYERS) -> int | None:
    """The index of ``module``'s layer (None: not placed); an exact name wins over a prefix."""
    for i, (_, names) in enumerate(layers):
        if module in names:
            return i
    for i, (_, names) in enumerate(layers):
        if any(n.endswith("*") and (module == n[:-1] or module.startswith(n[:-1] + "."))
               for n in names):
            return i
    return None


def allowed(edge: tuple[str, str]) -> bool:
    """The documented exception: the hooks' imports of the adapters."""
    source, target = edge
    return source == HOOKS and _is_adapter(target)


def _is_adapter(module: str) -> bool:
    return module == ADAPTERS or module.startswith(ADAPTERS + ".")


def unplaced(graph: Mapping[str, Iterable[str]], layers=LAYERS) -> list[str]:
    return sorted(m for m in graph if layer_of(m, layers) is None)


def upward_imports(graph: Mapping[str, Iterable[str]], layers=LAYERS) -> list[str]:
    """Every import from a lower layer into a higher one, but the allowed ones."""
    found = []
    for source, targets in graph.items():
        for target in targets:
            low, high = layer_of(source, layers), layer_of(target, layers)
            if low is not None and high is not None and high > low and not allowed((source, target)):
                found.append(f"{source} ({layers[low][0]}) imports {target} ({layers[high][0]})")
    return sorted(found)


def circles(graph: Mapping[str, Iterable[str]]) -> list[list[str]]:
    """The import circles: strongly connected components of more than one module
    (or a module importing itself), Tarjan's algorithm without recursion; the
    allowed imports are left out."""
    edges = {m: sorted(t for t in ts if not allowed((m, t))) for m, ts in graph.items()}
    for ts in list(edges.values()):
        for t in ts:
            edges.setdefault(t, [])
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found = []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(edges[root]))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(edges[child])))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    m = stack.pop()
                    on_stack.discard(m)
                    component.append(m)
                    if m == node:
                        break
                if len(component) > 1 or node in edges[node]:
                    found.append(sorted(component))
    return sorted(found)


def engine_imports_of_adapters(graph: Mapping[str, Iterable[str]], layers=LAYERS) -> list[str]:
    """Imports of ``cdt_plugin.adapters`` by a module of the engine (below the
    command line, not an adapter) other than the hooks."""
    top = len(layers) - 1
    return sorted(f"{source} imports {target}" for source, targets in graph.items()
                  for target in targets
                  if _is_adapter(target) and not _is_adapter(source) and layer_of(source, layers) != top
                  and not allowed((source, target)))


GRAPH = import_graph()


# ------------------------------------------------------------------ the package
def test_the_layout_is_read():
    assert {"cdt_plugin._core.pipeline", "cdt_plugin.cdt", "cdt_plugin.report",
            "cdt_plugin.adapters.shapely", HOOKS} <= NAMES
    # the reader resolves relative imports: the one call of the route is seen
    cdt = next((m, p, t) for m, p, t in MODULES if m == "cdt_plugin.cdt")
    assert any(target == "cdt_plugin._core.pipeline" and "cdt_route_packed" in names
               for target, names, _ in _imports(*cdt))
    # in-function and type-only imports are edges too: the hooks' and __init__'s lazy ones
    assert "cdt_plugin.adapters.shapely" in GRAPH[HOOKS]
    assert {"cdt_plugin.voronoi", "cdt_plugin.dynamic"} <= GRAPH["cdt_plugin"]
    # ``from . import report`` is an import of the module, not of the package
    assert "cdt_plugin.report" in GRAPH["cdt_plugin.triangulation"]
    assert "cdt_plugin" not in GRAPH["cdt_plugin.triangulation"]


def test_every_module_has_a_layer():
    assert not unplaced(GRAPH), f"place these modules in LAYERS: {unplaced(GRAPH)}"


def test_no_import_runs_up_the_layers():
    found = upward_imports(GRAPH)
    assert not found, "\n".join(found)


def test_no_import_circle():
    found = circles(GRAPH)
    assert not found, found


def test_the_engine_imports_the_adapters_only_in_the_hooks():
    found = engine_imports_of_adapters(GRAPH)
    assert not found, found


def test_the_hooks_import_the_adapters_only_inside_functions():
    hooks = next((m, p, t) for m, p, t in MODULES if m == HOOKS)
    at_top = [target for target, _, top in _imports(*hooks) if top and _is_adapter(target)]
    assert not at_top, at_top


# --------------------------------------------------- the checks can fail
SYNTHETIC_LAYERS = [("low", ("a", "b")), ("mid", ("c", HOOKS)), ("high", ("d", f"{ADAPTERS}*"))]


def test_the_checks_pass_a_clean_graph():
    graph = {"a": {"b"}, "b": set(), "c": {"a"}, "d": {"c", "b"}, HOOKS: {f"{ADAPTERS}.x"},
             f"{ADAPTERS}.x": {"d"}}
    assert not unplaced(graph, SYNTHETIC_LAYERS)
    assert not upward_imports(graph, SYNTHETIC_LAYERS)
    assert not circles(graph)                  # (hooks -> adapters -> d -> c: no loop back)
    assert not engine_imports_of_adapters(graph, SYNTHETIC_LAYERS)


def test_a_circle_fails():
    graph = {"a": {"b"}, "b": {"a"}, "c": {"c"}, "d": set()}
    assert circles(graph) == [["a", "b"], ["c"]]
    # a longer one, through the hooks' allowed edge and back
    graph = {"c": {HOOKS}, HOOKS: {f"{ADAPTERS}.x"}, f"{ADAPTERS}.x": {"d"}, "d": {"c"}}
    assert circles(graph) == []                # the hooks' edge is the documented exception
    graph["c"].add("d")
    graph["d"].add("c")
    assert circles(graph) == [["c", "d"]]


def test_an_upward_import_fails():
    graph = {"a": {"c"}, "c": set(), "b": set(), "d": set()}
    assert upward_imports(graph, SYNTHETIC_LAYERS) == ["a (low) imports c (mid)"]


def test_an_unplaced_module_fails():
    assert unplaced({"a": set(), "e": set()}, SYNTHETIC_LAYERS) == ["e"]


def test_an_engine_import_of_the_adapters_fails():
    graph = {"c": {f"{ADAPTERS}.x"}, HOOKS: {f"{ADAPTERS}.x"}, f"{ADAPTERS}.x": set()}
    assert engine_imports_of_adapters(graph, SYNTHETIC_LAYERS) == [f"c imports {ADAPTERS}.x"]
    assert upward_imports(graph, SYNTHETIC_LAYERS) == [f"c (mid) imports {ADAPTERS}.x (high)"]


# ------------------------------------------------------------ kernels, names
def test_no_module_imports_another_modules_private_names():
    found = [f"{module} imports {name} from {target}"
             for module, path, tree in MODULES
             for target, names, _ in _imports(module, path, tree)
             for name in names
             if name.startswith("_") and not name.startswith("__") and target != module
             and f"{target}.{name}" not in NAMES]   # (a subpackage: _core)
    assert not found, found


def test_every_kernel_is_in_the_core():
    found = []
    for module, path, tree in MODULES:
        if module.startswith("cdt_plugin._core"):
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for d in node.decorator_list:
                    f = d.func if isinstance(d, ast.Call) else d
                    name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
                    if name in ("kernel", "njit", "jit", "cfunc", "vectorize"):
                        found.append(f"{module}.{node.name}")
    assert not found, found


@pytest.mark.parametrize("layer", [name for name, _ in LAYERS])
def test_every_layer_holds_a_module(layer):
    # a layer that names only modules that are gone is a stale table
    i = next(i for i, (name, _) in enumerate(LAYERS) if name == layer)
    assert any(layer_of(m) == i for m in NAMES), layer
