"""The examples in the docstrings of every module of the package run and give
what they show (``cdt_plugin.*`` and ``cdt_plugin.adapters.*``; the compiled
``_core`` and ``__main__`` excepted). NumPy prints scalars as NumPy 1 did
(``1.0``, not ``np.float64(1.0)``), so that the examples read the same under
NumPy 1 and 2. A module whose optional library is not installed is skipped."""
from __future__ import annotations

import contextlib
import doctest
import importlib
import importlib.util
import io
import pkgutil
from typing import Iterator

import numpy as np
import pytest

import cdt_plugin

# libraries a module's examples need beyond numpy and numba (its extra)
OPTIONAL = {
    "cdt_plugin.plot": ["matplotlib"],
    "cdt_plugin.report": ["mapbox_earcut"],
    "cdt_plugin.triangulation": ["matplotlib"],
    "cdt_plugin.cli": ["shapely", "trimesh"],
    "cdt_plugin.hooks": ["shapely"],
    "cdt_plugin.triangle": ["matplotlib"],
    "cdt_plugin.adapters.shapely": ["shapely"],
    "cdt_plugin.adapters.trimesh": ["shapely", "trimesh"],
    "cdt_plugin.adapters.open3d": ["open3d"],
    "cdt_plugin.adapters.geo": ["shapely", "geopandas", "dask_geopandas"],
    "cdt_plugin.adapters.layers": ["shapely", "geopandas"],
}
SKIPPED = ("cdt_plugin.__main__",)     # importing it runs the command line


def _modules() -> list[str]:
    names = ["cdt_plugin"]
    names += [m.name for m in pkgutil.iter_modules(cdt_plugin.__path__, "cdt_plugin.")
              if not m.name.startswith("cdt_plugin._")]
    adapters_path = importlib.util.find_spec("cdt_plugin.adapters").submodule_search_locations
    names += [m.name for m in pkgutil.iter_modules(adapters_path, "cdt_plugin.adapters.")]
    return [n for n in names if n not in SKIPPED]


@contextlib.contextmanager
def numpy_1_reprs() -> Iterator[None]:
    """NumPy scalars printed as NumPy 1 printed them (NumPy 2's ``legacy="1.25"``)."""
    if int(np.__version__.split(".")[0]) >= 2:
        with np.printoptions(legacy="1.25"):
            yield
    else:
        yield


def _with_submodules(module) -> list:
    """``module``, and the modules of an adapter package or of :mod:`cdt_plugin.io`
    (split by concern)."""
    found = [module]
    if hasattr(module, "__path__") and (module.__name__.startswith("cdt_plugin.adapters.")
                                        or module.__name__ in ("cdt_plugin.io", "cdt_plugin.triangle")):
        found += [importlib.import_module(m.name)
                  for m in pkgutil.iter_modules(module.__path__, module.__name__ + ".")]
    return found


def run_doctests(module) -> tuple[doctest.TestResults, str]:
    """Every example of ``module`` (docstrings of the module and of what it defines;
    of an adapter package or of cdt_plugin.io, of its modules too)."""
    tests = [t for m in _with_submodules(module) for t in doctest.DocTestFinder().find(m, m.__name__)]
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    report = io.StringIO()
    with numpy_1_reprs():
        for test in sorted(tests, key=lambda t: t.name):
            runner.run(test, out=report.write)
    return runner.summarize(verbose=False), report.getvalue()


def test_module_list_is_complete():
    names = _modules()
    assert {"cdt_plugin", "cdt_plugin.cdt", "cdt_plugin.delaunay",
            "cdt_plugin.adapters.shapely"} <= set(names)
    assert not any(n.startswith("cdt_plugin._core") for n in names)


def test_numpy_reprs_are_version_independent():
    with numpy_1_reprs():
        assert repr(np.float64(1.5)) == "1.5"
        assert repr(np.int64(3)) == "3"
        assert repr((np.float64(0.5), np.bool_(True))) == "(0.5, True)"


def test_a_failing_example_is_reported():
    """The runner above counts a wrong expected output as a failure."""
    import types

    module = types.ModuleType("fake_module", '>>> 1 + 1\n3\n')
    (failed, attempted), report = run_doctests(module)
    assert (failed, attempted) == (1, 1)
    assert "Expected:\n    3\nGot:\n    2" in report


@pytest.mark.parametrize("name", _modules())
def test_doctests(name):
    for library in OPTIONAL.get(name, []):
        pytest.importorskip(library)
    module = importlib.import_module(name)
    (failed, attempted), report = run_doctests(module)
    assert attempted > 0, f"{name} has no examples in its docstrings"
    assert failed == 0, f"{failed} of {attempted} examples of {name} fail:\n{report}"
