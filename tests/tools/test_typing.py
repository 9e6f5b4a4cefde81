"""Typing of the public modules: mypy finds no error in them, and every public
callable in them is fully annotated (parameters and return), so that neither
can regress. Extend ``TYPED_MODULES`` as modules become clean; mypy's
settings are ``[tool.mypy]`` in pyproject.toml."""
from __future__ import annotations

import contextlib
import importlib
import inspect
import subprocess
import sys
import types
from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

ROOT = Path(__file__).resolve().parents[2]

TYPED_MODULES = [
    "cdt_plugin",
    "cdt_plugin.adapters.geo",
    "cdt_plugin.adapters.geo.accessor",
    "cdt_plugin.adapters.geo.dask_frames",
    "cdt_plugin.adapters.geo.errors",
    "cdt_plugin.adapters.geo.extruding",
    "cdt_plugin.adapters.geo.meshing",
    "cdt_plugin.adapters.geo.projection",
    "cdt_plugin.adapters.geo.results",
    "cdt_plugin.adapters.geo.sizing",
    "cdt_plugin.adapters.geo.voronoi_cells",
    "cdt_plugin.adapters.layers",
    "cdt_plugin.adapters.open3d",
    "cdt_plugin.adapters.shapely",
    "cdt_plugin.adapters.shapely.building",
    "cdt_plugin.adapters.shapely.cells",
    "cdt_plugin.adapters.shapely.dropins",
    "cdt_plugin.adapters.shapely.reading",
    "cdt_plugin.adapters.shapely.validity",
    "cdt_plugin.adapters.terrain",
    "cdt_plugin.adapters.trimesh",
    "cdt_plugin.batch",
    "cdt_plugin.cdt",
    "cdt_plugin.cli",
    "cdt_plugin.cli.commands",
    "cdt_plugin.cli.extruding",
    "cdt_plugin.cli.formats",
    "cdt_plugin.cli.layers",
    "cdt_plugin.cli.meshing",
    "cdt_plugin.cli.parser",
    "cdt_plugin.cli.readers",
    "cdt_plugin.cli.terminal",
    "cdt_plugin.cli.triangle",
    "cdt_plugin.cli.writers",
    "cdt_plugin.compiling",
    "cdt_plugin.delaunay",
    "cdt_plugin.dynamic",
    "cdt_plugin.errors",
    "cdt_plugin.fields",
    "cdt_plugin.grading",
    "cdt_plugin.hooks",
    "cdt_plugin.interrupts",
    "cdt_plugin.io",
    "cdt_plugin.io.reading",
    "cdt_plugin.io.records",
    "cdt_plugin.io.writing",
    "cdt_plugin.lift",
    "cdt_plugin.optional",
    "cdt_plugin.options",
    "cdt_plugin.parallel",
    "cdt_plugin.plain",
    "cdt_plugin.plc",
    "cdt_plugin.plot",
    "cdt_plugin.markers",
    "cdt_plugin.nearness",
    "cdt_plugin.merging",
    "cdt_plugin.queries",
    "cdt_plugin.quadratic",
    "cdt_plugin.fem",
    "cdt_plugin.refining",
    "cdt_plugin.sizing",
    "cdt_plugin.smoothing",
    "cdt_plugin.report",
    "cdt_plugin.switches",
    "cdt_plugin.triangle",
    "cdt_plugin.triangle.data",
    "cdt_plugin.triangle.plot",
    "cdt_plugin.triangle.tri",
    "cdt_plugin.triangulation",
    "cdt_plugin.planar",
    "cdt_plugin.faces",
    "cdt_plugin.solids",
    "cdt_plugin.types",
    "cdt_plugin.validate",
    "cdt_plugin.voronoi",
    "cdt_plugin.warmup",
]

_ADAPTERS = "cdt_plugin.adapters."


def _mypy_target(module: str) -> str:
    """A module's source file, relative to the checkout: mypy is given files, since an
    adapter (installed as cdt_plugin.adapters from the folder adapters/, a mapping
    mypy cannot see) has no module name mypy can find, and mypy takes module names
    (-m) or files in one run, not both."""
    if module.startswith(_ADAPTERS):
        parts = ["adapters", *module[len(_ADAPTERS):].split(".")]
    else:
        parts = module.split(".")
    package = Path(*parts, "__init__.py")
    return str(package if (ROOT / package).is_file() else Path(*parts[:-1], parts[-1] + ".py"))


def test_every_public_module_is_typed():
    """A new public module is type checked from the start: every module of the package
    (but the compiled kernels in _core and the ``python -m`` entry) is in the list."""
    import pkgutil

    import cdt_plugin
    import cdt_plugin.adapters
    found = {"cdt_plugin"}
    packages = [cdt_plugin, cdt_plugin.adapters]
    while packages:                     # subpackages too (cdt_plugin.cli, the adapters by concern)
        package = packages.pop()
        for info in pkgutil.iter_modules(package.__path__, package.__name__ + "."):
            if not info.name.rsplit(".", 1)[1].startswith("_") and info.name != "cdt_plugin.adapters":
                found.add(info.name)
                if info.ispkg:
                    packages.append(importlib.import_module(info.name))
    assert found == set(TYPED_MODULES), (found ^ set(TYPED_MODULES))


def test_mypy_targets_are_files():
    assert _mypy_target("cdt_plugin") == str(Path("cdt_plugin", "__init__.py"))
    assert _mypy_target("cdt_plugin.cdt") == str(Path("cdt_plugin", "cdt.py"))
    assert _mypy_target("cdt_plugin.adapters.trimesh") == str(Path("adapters", "trimesh.py"))
    assert all((ROOT / _mypy_target(module)).is_file() for module in TYPED_MODULES)


def test_mypy_finds_no_error():
    pytest.importorskip("mypy")
    args = [_mypy_target(module) for module in TYPED_MODULES]
    run = subprocess.run([sys.executable, "-m", "mypy", "--no-error-summary", "--hide-error-context",
                          *args], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"mypy on {TYPED_MODULES}:\n{run.stdout}{run.stderr}"


def _defined_here(fn: Any, module: types.ModuleType) -> bool:
    """Whether ``fn`` is a Python function written in ``module``'s source file
    (not generated, e.g. a dataclass's ``__eq__``, nor imported); a decorated
    function (``functools.wraps``: a ``contextlib.contextmanager``) by what it wraps."""
    code = getattr(inspect.unwrap(fn), "__code__", None)
    return code is not None and Path(code.co_filename) == Path(module.__file__ or "")


def _methods(cls: type, module: types.ModuleType) -> Iterator[tuple[str, Callable[..., Any]]]:
    """The public methods of ``cls`` (and its special methods) written in ``module``,
    properties' getters and setters included."""
    for name, attr in vars(cls).items():
        if name.startswith("_") and not (name.startswith("__") and name.endswith("__")):
            continue
        if isinstance(attr, (staticmethod, classmethod)):
            attr = attr.__func__
        parts = [attr.fget, attr.fset] if isinstance(attr, property) else [attr]
        for fn in parts:
            if fn is not None and _defined_here(fn, module):
                yield f"{cls.__name__}.{name}", fn


def _public_callables(module: types.ModuleType) -> Iterator[tuple[str, Callable[..., Any]]]:
    """Functions and classes of ``module`` (named in ``__all__``, or not starting
    with ``_``) that are defined there, and the methods of those classes."""
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in vars(module) if not n.startswith("_")]
    for name in names:
        obj = getattr(module, name)
        if inspect.isclass(obj):       # (its methods written in this module's file)
            yield from _methods(obj, module)
        elif inspect.isfunction(obj) and _defined_here(obj, module):
            yield name, obj


def _missing_annotations(fn: Callable[..., Any]) -> list[str]:
    sig = inspect.signature(fn)
    params = list(sig.parameters.values())
    if params and params[0].name in ("self", "cls"):
        params = params[1:]
    missing = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    if sig.return_annotation is inspect.Signature.empty:
        missing.append("return")
    return missing


@pytest.mark.parametrize("name", TYPED_MODULES)
def test_public_callables_are_annotated(name):
    module = importlib.import_module(name)
    found = list(_public_callables(module))
    missing = {qual: m for qual, fn in found if (m := _missing_annotations(fn))}
    assert not missing, f"{name}: not annotated (callable: parameters or return): {missing}"


def test_the_annotation_check_can_fail():
    """The check above sees a missing parameter or return annotation."""
    def partly(a: int, b) -> int:
        return a

    def no_return(a: int):
        return a

    def full(a: int, *args: int, **kwargs: str) -> None:
        pass

    assert _missing_annotations(partly) == ["b"]
    assert _missing_annotations(no_return) == ["return"]
    assert _missing_annotations(full) == []


def test_decorated_functions_are_checked():
    """A function wrapped with ``functools.wraps`` (``contextlib.contextmanager``) is
    checked as the function it wraps, where that function is written."""
    @contextlib.contextmanager
    def block(a: int):
        yield a

    assert _defined_here(block, sys.modules[__name__])
    assert _missing_annotations(block) == ["return"]


def test_py_typed_marker_ships():
    """PEP 561: the marker is in the package and pyproject ships it as package data."""
    tomllib = pytest.importorskip("tomllib")      # Python 3.11+
    import cdt_plugin

    assert (Path(cdt_plugin.__file__).parent / "py.typed").is_file()
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "py.typed" in config["tool"]["setuptools"]["package-data"]["cdt_plugin"]
