"""Ecosystem adapters (shapely, trimesh, Open3D, GeoJSON): installed as ``cdt_plugin.adapters``."""
from __future__ import annotations

from typing import Any


def claim_modules_names(namespace: dict[str, Any]) -> None:
    """Make the functions and classes an adapter package (``namespace``: its
    ``globals()``) imports from its own modules name the package as their module,
    as before the adapter was split into modules: their repr, pickling and
    doctest's finder go by ``__module__``."""
    package = namespace["__name__"]
    for value in list(namespace.values()):
        if getattr(value, "__module__", "").startswith(package + "."):
            value.__module__ = package
