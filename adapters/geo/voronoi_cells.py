"""The Voronoi cell of every point of a point layer (:func:`voronoi`), clipped
to a boundary."""
from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Union

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

import cdt_plugin
from cdt_plugin import InputShapeError
from cdt_plugin.adapters.geo.errors import (GeographicCRSWarning, TYPE_NAMES, caller_stacklevel,
                                            describe, is_geographic, plain, relabel)
from cdt_plugin.adapters.layers import LayerLike, read
import cdt_plugin.adapters.shapely.validity as validity
from cdt_plugin.adapters.shapely.reading import MULTIPOINT, MULTIPOLYGON, POINT, POLYGON

if TYPE_CHECKING:
    from geopandas import GeoDataFrame

#: What :func:`voronoi`'s ``boundary`` takes: None, a shapely (Multi)Polygon, or a
#: polygon layer (anything :func:`read` takes).
BoundaryLike = Union["shapely.Geometry", LayerLike, None]


def voronoi(points: LayerLike, boundary: BoundaryLike = None, *,
            weights: str | ArrayLike | None = None) -> GeoDataFrame:
    """The Voronoi cell of every point of a point layer (the power diagram's cell
    with ``weights``), clipped to ``boundary``: one row per point.

    The diagram is :meth:`cdt_plugin.Triangulation.voronoi` of
    ``cdt_plugin.delaunay(xy, weights)`` (exact predicates: cocircular points
    give one Voronoi vertex, a grid gives square cells); the cells are cut to
    ``boundary`` with GEOS.

    Parameters
    ----------
    points : GeoDataFrame, GeoSeries, GeoJSON dict, or path
        A layer of Point geometries (see :func:`read`); Z is ignored (the cells
        are 2D). A MultiPoint, another geometry type, an empty or a missing
        (None) geometry raises :class:`cdt_plugin.InputShapeError` naming the
        row (explode MultiPoints first: ``layer.explode(index_parts=True)``).
    boundary : None, shapely Polygon / MultiPolygon, or a polygon layer
        What the cells are clipped to. None: the points' bounding box grown by
        its larger side on every side (:meth:`cdt_plugin.Voronoi.envelope`, the
        box ``shapely.voronoi_polygons`` uses; in a geographic CRS cut to
        longitudes -180..180 and latitudes -90..90). A shapely geometry is taken
        to be in the points' CRS. A layer (GeoDataFrame, GeoSeries, GeoJSON dict
        or path): the union of its polygons, reprojected to the points' CRS when
        both have a CRS and they differ (missing and empty rows are left out; a
        GeoJSON dict without a ``"crs"`` member is WGS 84, as :func:`read` says).
    weights : None, str, or array_like (n,)
        A power diagram: the name of a numeric column of ``points``, or one
        weight per row (in row order). Point ``p`` with weight ``w`` claims
        ``x`` where ``|x - p|^2 - w`` is smallest. A point whose weight is too
        small to claim anything (submerged; also the lighter of two equal points)
        gets an empty Polygon.

    Returns
    -------
    GeoDataFrame
        ``points`` with the same index, every attribute column and the CRS; the
        geometry column holds each point's cell: a Polygon, a MultiPolygon where
        a non-convex boundary cuts a cell in pieces, an empty Polygon where
        nothing of the cell is left (a point outside ``boundary`` whose cell
        misses it, a submerged weighted point). Equal points (duplicates) share
        their cell: every one of their rows gets it. Without weights the cells
        tile the boundary and every point inside it lies in its own cell.

    Raises
    ------
    cdt_plugin.TooFewPointsError
        The layer has no rows.
    cdt_plugin.InputShapeError
        A row that is not a Point (its ``index`` and ``feature`` attributes name
        it), or ``weights`` that is not a column or does not have one number per row.
    cdt_plugin.NonFiniteCoordinateError
        A NaN or infinite coordinate or weight.
    cdt_plugin.CollinearPointsError
        Fewer than three distinct points, or all on one line (no Voronoi vertex).
    cdt_plugin.ClipRegionError
        A boundary that is not polygonal, is invalid or empty, or contains none
        of the points.

    Coordinates are taken as they are: in a geographic CRS (lon/lat) the cells
    are those of distances in degrees, and :class:`GeographicCRSWarning` says
    so; reproject the points first (e.g. ``points.to_crs(points.estimate_utm_crs())``)
    for cells of distances on the ground.

    Examples
    --------
    >>> import geopandas, shapely
    >>> shops = geopandas.GeoDataFrame({"name": ["a", "b", "c", "d"]}, crs="EPSG:32633",
    ...     geometry=shapely.points([(1, 1), (3, 1), (1, 3), (3, 3)]), index=[10, 11, 12, 13])
    >>> cells = voronoi(shops, shapely.box(0, 0, 4, 4))
    >>> cells.index.tolist(), cells["name"].tolist(), cells.crs.to_epsg()
    ([10, 11, 12, 13], ['a', 'b', 'c', 'd'], 32633)
    >>> cells.geometry[10].bounds, cells.area.tolist()
    ((0.0, 0.0, 2.0, 2.0), [4.0, 4.0, 4.0, 4.0])
    >>> voronoi(shops, shapely.box(0, 0, 4, 4), weights=[1, 0, 0, 0]).area.tolist()
    [5.03125, 3.5, 3.5, 3.96875]
    """
    import geopandas


    frame = read(points)
    xy = _point_xy(frame)
    w = _point_weights(frame, weights)
    geographic = is_geographic(frame.crs)
    if geographic:
        _warn_geographic_voronoi(frame.crs)
    clip = None if boundary is None else _clip_region(boundary, frame.crs)
    vor = cdt_plugin.delaunay(xy, w).voronoi()
    if clip is None:
        clip = _lonlat_box(vor.envelope(), xy) if geographic else vor.envelope()
    try:
        cells = vor.clipped(clip).to_shapely()
    except cdt_plugin.ClipRegionError as exc:
        raise cdt_plugin.ClipRegionError(f"boundary: {exc}") from None
    site = vor.point_region
    geoms = np.empty(len(frame), dtype=object)
    geoms[site >= 0] = cells[site[site >= 0]]
    geoms[site < 0] = shapely.Polygon()
    out = frame.copy()
    out[frame.geometry.name] = geopandas.GeoSeries(geoms, index=frame.index, crs=frame.crs)
    return out


def _point_xy(frame: GeoDataFrame) -> NDArray[np.float64]:
    """(n, 2) x, y of a layer of Points; InputShapeError naming the first row that
    is not a (non-empty) Point."""
    if not len(frame):
        from cdt_plugin import TooFewPointsError
        raise TooFewPointsError("the point layer is empty: no point, no Voronoi cell")
    geoms = np.asarray(frame.geometry.array, dtype=object)
    types = shapely.get_type_id(geoms)
    bad = np.flatnonzero((types != POINT) | shapely.is_empty(geoms))
    if len(bad):
        i = int(bad[0])
        t = int(types[i])
        if t < 0:
            what, hint = "a missing geometry (None)", "drop the row or give it a point"
        elif shapely.is_empty(geoms[i]):
            what, hint = f"an empty {TYPE_NAMES[t]}", "drop the row or give it a point"
        elif t == MULTIPOINT:
            what = "a MultiPoint"
            hint = "explode it first (layer.explode(index_parts=True)) to give each point a cell"
        else:
            what, hint = f"a {TYPE_NAMES[t]}", "the Voronoi diagram is of Point layers"
        more = f" ({len(bad)} such rows: {describe(geoms[bad])})" if len(bad) > 1 else ""
        raise relabel(InputShapeError(f"{what} where a Point is expected; {hint}{more}"), i, frame, None)
    return np.column_stack([shapely.get_x(geoms), shapely.get_y(geoms)]).astype(np.float64)


def _point_weights(frame: GeoDataFrame, weights: str | ArrayLike | None) -> NDArray[np.float64] | None:
    """The weights as (n,) float64: a column of ``frame`` or one value per row."""
    if weights is None:
        return None
    if isinstance(weights, str):
        columns = [c for c in frame.columns if c != frame.geometry.name]
        if weights not in columns:
            raise InputShapeError(f"weights={weights!r} is not a column of the point layer "
                                  f"(columns: {', '.join(map(str, columns)) or 'none'})")
        values: Any = frame[weights]
        name = f"column {weights!r}"
    else:
        values, name = weights, "weights"
    try:
        w = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name}: weights must be numbers") from None
    if w.shape != (len(frame),):
        raise InputShapeError(f"{name}: one weight per point is needed ({len(frame)}), "
                              f"got shape {w.shape}")
    bad = np.flatnonzero(~np.isfinite(w))
    if len(bad):
        from cdt_plugin import NonFiniteCoordinateError
        raise relabel(NonFiniteCoordinateError(
            f"weight ({name}) {'missing' if np.isnan(w[bad[0]]) else 'infinite'}"
            + (f" ({len(bad)} rows without a finite weight)" if len(bad) > 1 else "")),
            int(bad[0]), frame, None)
    return w


def _clip_region(boundary: BoundaryLike, crs: Any) -> Any:
    """``boundary`` as one shapely geometry in ``crs``: a geometry as it is (the
    clip checks it), a layer as the union of its polygons."""
    from cdt_plugin import ClipRegionError

    if isinstance(boundary, shapely.Geometry):
        return boundary
    try:
        layer = read(boundary)
    except InputShapeError as exc:
        raise ClipRegionError(f"boundary: {exc}, or a shapely Polygon / MultiPolygon") from None
    if crs is not None and layer.crs is not None and layer.crs != crs:
        layer = layer.to_crs(crs)
    geoms = np.asarray(layer.geometry.array, dtype=object)
    present = ~shapely.is_missing(geoms) & ~shapely.is_empty(geoms)
    types = shapely.get_type_id(geoms)
    for i in np.flatnonzero(present & ~np.isin(types, (POLYGON, MULTIPOLYGON))):
        raise ClipRegionError(f"boundary feature {plain(layer.index[i])} is a "
                              f"{TYPE_NAMES[types[i]]}: the boundary is a layer of polygons")
    for i in np.flatnonzero(present & ~validity.is_valid(geoms)):
        raise ClipRegionError(f"boundary feature {plain(layer.index[i])} is invalid "
                              f"({validity.reason(geoms[i])}): repair it "
                              "(shapely.make_valid) first")
    if not present.any():
        raise ClipRegionError(f"the boundary layer has no polygon ({describe(geoms)})")
    k = int(validity.unit_shift(shapely.geometrycollections(geoms[present])))
    try:       # (at unit size, as validity: GEOS's overlay is not exact at extreme magnitudes)
        return validity.scaled(shapely.union_all(validity.scaled(geoms[present], k)), -k)
    except shapely.errors.GEOSException as exc:
        raise ClipRegionError(f"the boundary's polygons cannot be merged by GEOS ({exc}); "
                              "merge them first") from exc


def _lonlat_box(box: tuple[float, float, float, float],
                xy: NDArray[np.float64]) -> tuple[float, float, float, float]:
    """The envelope of lon/lat points cut to longitudes -180..180 and latitudes
    -90..90 (when the points are in that range: else as it is)."""
    if not ((np.abs(xy[:, 0]) <= 180).all() and (np.abs(xy[:, 1]) <= 90).all()):
        return box
    xmin, ymin, xmax, ymax = box
    return (max(xmin, -180.0), max(ymin, -90.0), min(xmax, 180.0), min(ymax, 90.0))


def _warn_geographic_voronoi(crs: Any) -> None:
    warnings.warn(GeographicCRSWarning(
        f"the layer's CRS ({crs.name}) is geographic: the Voronoi cells are those of distances "
        "in degrees of longitude and latitude (not the nearest point on the ground away from "
        "the equator); reproject the points to a projected CRS first, e.g. "
        "points.to_crs(points.estimate_utm_crs()), for cells in metres"),
        stacklevel=caller_stacklevel())
