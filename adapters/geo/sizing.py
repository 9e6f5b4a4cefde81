"""Sizes for meshing a layer (:func:`triangulate`'s ``size=`` and ``size_near=``):
a size field for the whole layer or one size per feature (a column), and sizes near
other layers (:func:`cdt_plugin.size_near`), reprojected to the CRS the layer is
meshed in; several combine by the smallest at every point."""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple, Sequence

import numpy as np

from cdt_plugin import CDTError, size_near
from cdt_plugin.errors import SizeFieldError
from cdt_plugin.fields import as_size_field
from cdt_plugin.nearness import SizeNear, SmallestSize, check_near
from cdt_plugin.adapters.geo.errors import plain
from cdt_plugin.adapters.layers import read

if TYPE_CHECKING:
    from geopandas import GeoDataFrame
    from pyproj import CRS


class NearLayer(NamedTuple):
    """One ``size_near=`` entry, its numbers checked: the geometries (a layer, a
    path, or anything :func:`cdt_plugin.size_near` takes) and the field's numbers."""
    geometries: Any
    size_min: float
    size_max: float
    distance: float | None
    growth: float | None


class LayerSizing(NamedTuple):
    """``size=`` and ``size_near=`` of a layer, checked before any work."""
    size: Any                    # None, a size field, or the name of a column
    near: list[NearLayer | SizeNear]


def check_layer_sizing(size: Any, size_near: Any) -> LayerSizing | None:
    """The checked sizing of :func:`triangulate`'s keywords (None when neither
    is given); a :class:`~cdt_plugin.errors.SizeFieldError` naming what is wrong.

    >>> check_layer_sizing(None, ("rivers.gpkg", 5, 100, 1000))
    LayerSizing(size=None, near=[NearLayer(geometries='rivers.gpkg', size_min=5.0, size_max=100.0, distance=1000.0, growth=None)])
    >>> check_layer_sizing("mesh_size", [{"geometries": "wells.gpkg", "size_min": 1, "size_max": 10,
    ...                                   "growth": 1.2}]).near[0].growth
    1.2
    """
    if size is None and size_near is None:
        return None
    if size is not None and not isinstance(size, str):
        size = as_size_field(size)
    entries = [] if size_near is None else (
        [size_near] if isinstance(size_near, (tuple, dict, SizeNear)) else list(size_near))
    near: list[NearLayer | SizeNear] = []
    for k, entry in enumerate(entries):
        if isinstance(entry, SizeNear):
            near.append(entry)
        elif isinstance(entry, dict):
            unknown = set(entry) - set(NearLayer._fields)
            if unknown or "geometries" not in entry:
                raise SizeFieldError(f"size_near[{k}]: expected the keys {NearLayer._fields} "
                                     f"(geometries, size_min and size_max needed), got {sorted(entry)}")
            near.append(NearLayer(entry["geometries"], *check_near(
                entry.get("size_min"), entry.get("size_max"), entry.get("distance"),
                entry.get("growth"))))
        elif isinstance(entry, tuple) and len(entry) in (4, 5):
            near.append(NearLayer(entry[0], *check_near(*entry[1:])))
        else:
            raise SizeFieldError(f"size_near[{k}]: expected (geometries, size_min, size_max, "
                                 "distance[, growth]), a mapping of size_near's keywords or a "
                                 f"size_near field, got {entry!r}")
    return LayerSizing(size, near)


def layer_size(frame: GeoDataFrame, sizing: LayerSizing, crs: CRS | None) -> Any:
    """The ``size=`` of the batch call that meshes ``frame`` in ``crs``: one field
    for every feature, or (a size column) a list with one field (or None) per
    feature. The ``size_near`` layers are read and reprojected to ``crs``."""
    near = [entry if isinstance(entry, SizeNear) else _near_field(entry, crs)
            for entry in sizing.near]
    if not isinstance(sizing.size, str):
        fields = ([sizing.size] if sizing.size is not None else []) + near
        return fields[0] if len(fields) == 1 else SmallestSize(fields)
    values = column_sizes(frame, sizing.size)
    return [_smallest(([float(v)] if np.isfinite(v) else []) + near) for v in values]


def column_sizes(frame: GeoDataFrame, column: str) -> np.ndarray:
    """The sizes of a column, one per feature (NaN: none), or the error naming
    the column and the feature whose value is no positive length."""
    if column not in frame.columns:
        raise SizeFieldError(f"size={column!r}: the layer has no such column (its columns: "
                             f"{', '.join(map(str, frame.columns))})")
    try:
        values = frame[column].to_numpy(dtype=float, na_value=np.nan)
    except (TypeError, ValueError):
        raise SizeFieldError(f"size={column!r}: the column must hold numbers (sizes), it holds "
                             f"{frame[column].dtype}") from None
    bad = np.flatnonzero(~(values > 0) & ~np.isnan(values) | np.isinf(values))
    if len(bad):
        i = int(bad[0])
        raise SizeFieldError(f"size={column!r}: feature {plain(frame.index[i])} has size "
                             f"{float(values[i])!r}: sizes must be positive lengths (NaN: none)",
                             value=float(values[i]))
    return values


def _near_field(entry: NearLayer, crs: CRS | None) -> SizeNear:
    """The field of one ``size_near`` entry, its layer in ``crs``."""
    geometries = entry.geometries
    if isinstance(geometries, (str, Path)):
        try:
            geometries = read(geometries)
        except FileNotFoundError:
            raise CDTError(f"size_near: {geometries}: no such file") from None
    if crs is not None and getattr(geometries, "crs", None) is not None \
            and hasattr(geometries, "to_crs") and geometries.crs != crs:
        geometries = geometries.to_crs(crs)
    return size_near(geometries, entry.size_min, entry.size_max, entry.distance, entry.growth)


def _smallest(fields: Sequence[Any]) -> Any:
    if not fields:
        return None
    return fields[0] if len(fields) == 1 else SmallestSize(fields)
