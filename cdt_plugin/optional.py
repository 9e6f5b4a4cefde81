"""Optional packages: which extra of ``cdt-plugin`` brings each one, and the
``ImportError`` that says so.

The engine needs only NumPy and numba; the adapters, plots and parts of the CLI need
other packages. A missing one raises :class:`MissingPackageError` (a
``ModuleNotFoundError``, so ``except ImportError`` still catches it) naming the extra
to install, at import of the adapter that needs it, before anything compiles.

>>> from cdt_plugin.optional import missing, require
>>> str(missing("geopandas", "reading a GIS layer"))
"reading a GIS layer needs geopandas: pip install 'cdt-plugin[gis]'"
>>> require("numpy", "this example").__name__
'numpy'
"""
from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["EXTRA_OF", "MissingPackageError", "missing", "require"]

# the extra of pyproject.toml that installs each optional module
EXTRA_OF = {
    "shapely": "shapely",
    "trimesh": "trimesh", "networkx": "trimesh", "rtree": "trimesh",
    "open3d": "open3d",
    "matplotlib": "plot",
    "geopandas": "gis", "pandas": "gis", "pyogrio": "gis", "pyproj": "gis", "pyarrow": "gis",
    "dask": "dask", "dask_geopandas": "dask", "distributed": "dask",
    "tqdm": "cli",
    "mapbox_earcut": "bench",
    "meshio": "fem", "skfem": "fem", "h5py": "fem", "gmsh": "bench",
}


class MissingPackageError(ModuleNotFoundError):
    """An optional package is not installed; the message names the extra that brings it."""


def missing(module: str | None, purpose: str, extra: str | None = None) -> MissingPackageError:
    """The error for ``module`` missing while doing ``purpose``: raise it ``from`` the
    original ImportError (``missing(exc.name, purpose)`` names the module that was
    actually missing, a dependency of a dependency included). ``module`` may be
    dotted: its top-level package is named; one no extra brings is named alone.
    ``extra`` names the extra instead (the one a whole adapter needs)."""
    top = (module or "?").split(".")[0]
    extra = extra or EXTRA_OF.get(top)
    install = f"'cdt-plugin[{extra}]'" if extra else top
    return MissingPackageError(f"{purpose} needs {top}: pip install {install}", name=top)


def require(module: str, purpose: str, extra: str | None = None) -> ModuleType:
    """Import ``module``, or raise :func:`missing`'s error for what was missing."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        raise missing(exc.name or module, purpose, extra) from exc
