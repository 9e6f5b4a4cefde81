"""The layering of the package (README, development notes), read from the sources with
``ast``: the compiled kernels in ``cdt_plugin/_core`` depend on nothing above them, every
kernel lives there (the cache guard of ``cdt_plugin.compiling`` watches ``_core`` only),
the public API imports the tools and the adapters only inside the convenience methods
that hand over to them, and no module imports another module's ``_private`` names."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TOOLS = ("cdt_plugin.report", "cdt_plugin.plot", "cdt_plugin.cli")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[0] == "adapters":                       # installed as cdt_plugin.adapters
        parts = ["cdt_plugin", *parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> list[tuple[str, Path, ast.Module]]:
    paths = sorted((ROOT / "cdt_plugin").rglob("*.py")) + sorted((ROOT / "adapters").rglob("*.py"))
    return [(_module_name(p), p, ast.parse(p.read_text(), str(p))) for p in paths]


def _imports(module: str, path: Path, tree: ast.Module):
    """``(target module, imported names, at module level)`` of every import of the
    package by ``module``; relative imports resolved."""
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


def _layer_of(module: str) -> str:
    if module.startswith("cdt_plugin._core"):
        return "core"
    if module.startswith("cdt_plugin.adapters"):
        return "adapters"
    if module.startswith(TOOLS) or module == "cdt_plugin.__main__":
        return "tools"
    return "api"


MODULES = _modules()


def test_the_layout_is_read():
    names = {m for m, _, _ in MODULES}
    assert {"cdt_plugin._core.pipeline", "cdt_plugin.cdt", "cdt_plugin.report",
            "cdt_plugin.adapters.shapely"} <= names
    # the reader resolves relative imports: the one call of the route is seen
    cdt = next((m, p, t) for m, p, t in MODULES if m == "cdt_plugin.cdt")
    assert any(target == "cdt_plugin._core.pipeline" and "cdt_route_packed" in names
               for target, names, _ in _imports(*cdt))


def test_no_module_imports_another_modules_private_names():
    found = [f"{module} imports {name} from {target}"
             for module, path, tree in MODULES
             for target, names, _ in _imports(module, path, tree)
             for name in names
             if name.startswith("_") and not name.startswith("__") and target != module
             and f"{target}.{name}" not in {m for m, _, _ in MODULES}]   # (a subpackage: _core)
    assert not found, found


def test_the_kernels_depend_on_nothing_above_them():
    found = [f"{module} imports {target}"
             for module, path, tree in MODULES if _layer_of(module) == "core"
             for target, _, _ in _imports(module, path, tree) if _layer_of(target) != "core"]
    assert not found, found


def test_every_kernel_is_in_the_core():
    found = []
    for module, path, tree in MODULES:
        if _layer_of(module) == "core":
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for d in node.decorator_list:
                    f = d.func if isinstance(d, ast.Call) else d
                    name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
                    if name in ("kernel", "njit", "jit", "cfunc", "vectorize"):
                        found.append(f"{module}.{node.name}")
    assert not found, found


@pytest.mark.parametrize("upper", ["tools", "adapters"])
def test_the_api_imports_tools_and_adapters_only_where_it_hands_over(upper):
    found = [f"{module} imports {target} at module level"
             for module, path, tree in MODULES if _layer_of(module) in ("core", "api")
             for target, _, top in _imports(module, path, tree)
             if top and _layer_of(target) == upper]
    assert not found, found
