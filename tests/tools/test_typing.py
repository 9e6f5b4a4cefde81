"""Typing of the public modules: mypy finds no error in them, and every public
callable in them is fully annotated (parameters and return), so that neither
can regress. Extend ``TYPED_MODULES`` as modules become clean; mypy's
settings are ``[tool.mypy]`` in pyproject.toml."""
from __future__ import annotations

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
    "cdt_plugin.batch",
    "cdt_plugin.cdt",
    "cdt_plugin.compiling",
    "cdt_plugin.delaunay",
    "cdt_plugin.errors",
    "cdt_plugin.interrupts",
    "cdt_plugin.lift",
    "cdt_plugin.parallel",
    "cdt_plugin.plc",
    "cdt_plugin.plot",
    "cdt_plugin.report",
    "cdt_plugin.switches",
    "cdt_plugin.validate",
]

_ADAPTERS = "cdt_plugin.adapters."


def _mypy_target(module: str) -> list[str]:
    """mypy's arguments for a module: by name, or, for an adapter (installed as
    cdt_plugin.adapters from the folder adapters/, which mypy cannot map), by file."""
    if module.startswith(_ADAPTERS):
        return [str(Path("adapters", module[len(_ADAPTERS):] + ".py"))]
    return ["-m", module]


def test_mypy_finds_no_error():
    pytest.importorskip("mypy")
    args = [arg for module in TYPED_MODULES for arg in _mypy_target(module)]
    run = subprocess.run([sys.executable, "-m", "mypy", "--no-error-summary", "--hide-error-context",
                          *args], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"mypy on {TYPED_MODULES}:\n{run.stdout}{run.stderr}"


def _defined_here(fn: Any, module: types.ModuleType) -> bool:
    """Whether ``fn`` is a Python function written in ``module``'s source file
    (not generated, e.g. a dataclass's ``__eq__``, nor imported)."""
    code = getattr(fn, "__code__", None)
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
        if inspect.isclass(obj) and obj.__module__ == module.__name__:
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


def test_py_typed_marker_ships():
    """PEP 561: the marker is in the package and pyproject ships it as package data."""
    tomllib = pytest.importorskip("tomllib")      # Python 3.11+
    import cdt_plugin

    assert (Path(cdt_plugin.__file__).parent / "py.typed").is_file()
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "py.typed" in config["tool"]["setuptools"]["package-data"]["cdt_plugin"]
