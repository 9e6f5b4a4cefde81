"""Terrain (TIN) from spot heights and breaklines, and its grid (a DEM).

Exposed as :func:`cdt_plugin.adapters.geo.tin` and :func:`cdt_plugin.adapters.geo.grid`.
The TIN is the constrained Delaunay triangulation of the points' (x, y), every
breakline a chain of segments (its vertices with their heights), clipped to a
boundary when one is given; each vertex keeps its height. The grid samples it
at cell centres with :meth:`cdt_plugin.Triangulation.interpolate` (linear or
natural neighbour), rows north-up as rasters are.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError
from cdt_plugin.optional import require

from cdt_plugin.adapters.layers import read

if TYPE_CHECKING:
    from geopandas import GeoDataFrame

METHODS = ("linear", "natural")
Transform = Union[tuple, Any]     # affine.Affine when the affine package is installed


def tin(points: Any, breaklines: Any = None, boundary: Any = None, *,
        z: str | ArrayLike | None = None) -> GeoDataFrame:
    """A triangulated irregular network: one Polygon Z per triangle.

    Parameters
    ----------
    points : point layer (GeoDataFrame, GeoSeries, path) or (n, 3) array
        Spot heights: Point Z geometries, or 2D points with ``z=``; an (n, 2)
        array needs ``z=`` too.
    breaklines : line layer, GeoSeries, or list of LineString Z, optional
        Lines the surface must follow (ridges, streams, kerbs): each is a chain
        of segments between its vertices, which are vertices of the TIN with
        their own heights. Where two breaklines cross, the crossing gets the
        height along the first of them (linear between its vertices).
    boundary : Polygon or polygon layer, optional
        The TIN covers this area only (its rings are segments, holes stay
        empty); its vertices get heights from the TIN of the points and
        breaklines (linear), so they must lie within their convex hull.
        Default: the convex hull of the points and breaklines.
    z : str or array_like, optional
        The heights: a column of ``points`` or an array (one per point).

    Returns
    -------
    GeoDataFrame
        One row per triangle (counter-clockwise Polygon Z), in the CRS of
        ``points``.

    Raises
    ------
    CDTError
        Two points at the same (x, y) with different heights (the rows are
        named), a point without a height, a boundary vertex outside the data.

    Examples
    --------
    >>> import numpy as np
    >>> xyz = np.array([[0, 0, 1], [10, 0, 2], [10, 10, 3], [0, 10, 2], [5, 5, 9]], float)
    >>> surface = tin(xyz)
    >>> len(surface), bool(surface.has_z.all())
    (4, True)
    """
    import geopandas
    import shapely

    xyz, crs = _spot_heights(points, z)
    lines = _breaklines(breaklines, crs)
    V = np.concatenate([xyz] + lines) if lines else xyz
    chains = _chains([len(xyz)] + [len(line) for line in lines])[1:]      # (none among the points)
    V, S = _merge_repeated(V, np.concatenate(chains) if chains else np.empty((0, 2), np.int64))
    keep_hull = boundary is None
    if boundary is not None:
        V, S = _with_boundary(V, S, boundary, crs)
    tri = cdt_plugin.triangulate(V[:, :2], S if len(S) else None, keep_hull=keep_hull,
                                 intersections="split")
    heights = _vertex_heights(tri, V, S)
    corners = np.concatenate([tri.vertices, heights[:, None]], axis=1)[tri.triangles]
    rings = np.concatenate([corners, corners[:, :1]], axis=1)
    return geopandas.GeoDataFrame({"triangle": np.arange(len(rings))},
                                  geometry=shapely.polygons(rings), crs=crs)


def grid(surface: GeoDataFrame, resolution: float, method: str = "linear", *,
         bounds: ArrayLike | None = None, path: str | Path | None = None
         ) -> tuple[NDArray[np.float64], Transform]:
    """Sample a TIN (the layer :func:`tin` returns, or any layer of triangles
    with Z) at the centres of a regular grid.

    Parameters
    ----------
    surface : GeoDataFrame of Polygon Z triangles
    resolution : float
        The cell size, in the layer's units.
    method : {"linear", "natural"}
        :meth:`cdt_plugin.Triangulation.interpolate`'s method.
    bounds : (xmin, ymin, xmax, ymax), optional
        The grid's extent (default: the TIN's bounds), rounded out to whole cells.
    path : str or Path, optional
        Also write the grid as a GeoTIFF (float64, NaN as nodata, the layer's
        CRS) with rasterio.

    Returns
    -------
    (array, transform)
        The heights, shape (rows, columns), row 0 the northernmost, NaN outside
        the TIN; the affine transform from (column, row) to (x, y) of the cells'
        corners: an ``affine.Affine`` if the package is installed, else the
        tuple ``(a, b, c, d, e, f)`` in its order.

    Examples
    --------
    >>> import numpy as np
    >>> xyz = np.array([[0, 0, 0], [4, 0, 8], [4, 4, 12], [0, 4, 4]], float)   # z = 2x + y
    >>> dem, transform = grid(tin(xyz), 2.0)
    >>> dem.tolist()                    # cell centres (1, 3), (3, 3) / (1, 1), (3, 1)
    [[5.0, 9.0], [3.0, 7.0]]
    >>> tuple(transform)[:6]
    (2.0, 0.0, 0.0, 0.0, -2.0, 4.0)
    """
    import shapely

    if method not in METHODS:
        raise CDTError(f"method must be one of {METHODS}, got {method!r}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float, np.number)) \
            or not math.isfinite(resolution) or resolution <= 0:
        raise CDTError(f"resolution must be a positive number, got {resolution!r}")
    if path is not None:
        require("rasterio", "writing a GeoTIFF")
    geoms = np.asarray(surface.geometry.array, dtype=object)
    if len(geoms) == 0 or not shapely.has_z(geoms).all():
        raise CDTError("the surface must be a layer of triangles with Z (what tin() returns)")
    coords = shapely.get_coordinates(geoms, include_z=True)
    counts = shapely.get_num_coordinates(geoms)
    if not (counts == 4).all():
        raise CDTError("the surface must be a layer of triangles (4 coordinates a ring)")
    corners = coords.reshape(-1, 4, 3)[:, :3]
    xy, inverse = np.unique(corners[:, :, :2].reshape(-1, 2), axis=0, return_inverse=True)
    heights = np.zeros(len(xy))
    heights[inverse.reshape(-1)] = corners[:, :, 2].reshape(-1)
    tri = cdt_plugin.Triangulation.from_triangles(xy, inverse.reshape(-1, 3))
    x0, y0, x1, y1 = (np.asarray(bounds, float) if bounds is not None
                      else (*xy.min(axis=0), *xy.max(axis=0)))
    cols = max(1, math.ceil((x1 - x0) / resolution))
    rows = max(1, math.ceil((y1 - y0) / resolution))
    cx = x0 + (np.arange(cols) + 0.5) * resolution
    cy = y1 - (np.arange(rows) + 0.5) * resolution
    gx, gy = np.meshgrid(cx, cy)
    dem = tri.interpolate(heights, np.column_stack([gx.ravel(), gy.ravel()]), method).reshape(rows, cols)
    transform = _transform(resolution, x0, y1)
    if path is not None:
        _write_geotiff(Path(path), dem, transform, surface.crs)
    return dem, transform


# ------------------------------------------------------------------ inputs
def _spot_heights(points: Any, z: str | ArrayLike | None) -> tuple[NDArray[np.float64], Any]:
    """(n, 3) points with heights, and the CRS (None for arrays)."""
    if isinstance(points, np.ndarray) or isinstance(points, (list, tuple)):
        arr = np.asarray(points, dtype=float)
        if arr.ndim != 2 or arr.shape[1] not in (2, 3):
            raise InputShapeError(f"points must have shape (n, 3), or (n, 2) with z=, got {arr.shape}")
        xy, heights, crs = arr[:, :2], (arr[:, 2] if arr.shape[1] == 3 else None), None
    else:
        import shapely

        frame = read(points)
        geoms = np.asarray(frame.geometry.array, dtype=object)
        if not (shapely.get_type_id(geoms) == 0).all():
            raise CDTError("points must be a layer of Point geometries")
        coords = shapely.get_coordinates(geoms, include_z=True)
        xy, heights, crs = coords[:, :2], coords[:, 2], frame.crs
        if isinstance(z, str):
            if z not in frame.columns:
                raise CDTError(f"z={z!r}: points has no such column (columns: {list(frame.columns)})")
            z = frame[z].to_numpy(dtype=float)
    if z is not None and not isinstance(z, str):
        heights = np.asarray(z, dtype=float).reshape(-1)
        if len(heights) != len(xy):
            raise InputShapeError(f"z must have one height per point ({len(xy)}), got {len(heights)}")
    if heights is None or np.isnan(heights).all():
        raise CDTError("points have no heights: give Point Z geometries, (n, 3) arrays or z=")
    missing = np.flatnonzero(~np.isfinite(heights))
    if len(missing):
        raise CDTError(f"points {missing[:5].tolist()} have no finite height")
    return np.column_stack([xy, heights]), crs


def _breaklines(breaklines: Any, crs: Any) -> list[NDArray[np.float64]]:
    """Each breakline's vertices (m, 3)."""
    if breaklines is None:
        return []
    import shapely

    if isinstance(breaklines, (list, tuple)):
        geoms = np.asarray(breaklines, dtype=object)
    else:
        geoms = _layer_geometries(breaklines, crs)
    parts = shapely.get_parts(geoms)
    if not (shapely.get_type_id(parts) == 1).all():
        raise CDTError("breaklines must be LineStrings (or MultiLineStrings) with Z")
    out = []
    for k, line in enumerate(parts):
        xyz = shapely.get_coordinates(line, include_z=True)
        if not shapely.has_z(line) or not np.isfinite(xyz[:, 2]).all():
            raise CDTError(f"breakline {k} has no Z: its vertices need heights")
        out.append(xyz)
    return out


def _layer_geometries(layer: Any, crs: Any) -> NDArray[np.object_]:
    """The geometries of a layer (anything :func:`read` takes), projected to
    ``crs`` when both have a CRS and they differ."""
    frame = read(layer)
    if crs is not None and frame.crs is not None and frame.crs != crs:
        frame = frame.to_crs(crs)
    return np.asarray(frame.geometry.array, dtype=object)


def _chains(sizes: list[int]) -> list[NDArray[np.int64]]:
    """Segments joining consecutive vertices within each run of ``sizes``
    (runs numbered one after the other)."""
    out, start = [], 0
    for n in sizes:
        ids = np.arange(start, start + n)
        out.append(np.column_stack([ids[:-1], ids[1:]]))
        start += n
    return out


def _merge_repeated(V: NDArray[np.float64], S: NDArray[np.int64]
                    ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """One vertex per (x, y): repeats with the same height merged (segments
    renumbered); different heights at one place raise, naming the rows."""
    xy, first, inverse = np.unique(V[:, :2], axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    clash = np.flatnonzero(V[:, 2] != V[first[inverse], 2])
    if len(clash):
        i = int(clash[0])
        j = int(first[inverse[i]])
        raise CDTError(f"rows {j} and {i} are both at ({V[i, 0]!r}, {V[i, 1]!r}) with heights "
                       f"{V[j, 2]!r} and {V[i, 2]!r} (points first, then breakline vertices)")
    order = np.argsort(first)                  # keep the first appearance order
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    return V[first[order]], rank[inverse[S]] if len(S) else S


def _with_boundary(V: NDArray[np.float64], S: NDArray[np.int64], boundary: Any, crs: Any
                   ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The boundary's rings added as segments, their vertices with heights
    interpolated in the TIN of the data."""
    import shapely

    if isinstance(boundary, shapely.Geometry):
        area = boundary
    else:
        try:
            area = shapely.union_all(_layer_geometries(boundary, crs))
        except shapely.errors.GEOSException as exc:
            raise CDTError(f"the boundary's polygons cannot be merged by GEOS ({exc}); "
                           "merge them first") from exc
    polygons = [g for g in shapely.get_parts(area) if g.geom_type == "Polygon" and not g.is_empty]
    if not polygons:
        raise CDTError("boundary has no polygon")
    data = cdt_plugin.triangulate(V[:, :2], S if len(S) else None, keep_hull=True, intersections="split")
    rings = [np.asarray(r.coords)[:-1, :2] for p in polygons for r in (p.exterior, *p.interiors)]
    xy = np.concatenate(rings)
    hz = _vertex_heights(data, V, S)
    heights = data.interpolate(hz, xy)
    outside = np.flatnonzero(np.isnan(heights))
    if len(outside):
        raise CDTError(f"boundary vertex {xy[outside[0]].tolist()} lies outside the points' and "
                       "breaklines' convex hull: it has no height")
    segs = [s + len(V) for s in _chains([len(r) for r in rings])]
    closing = []
    start = len(V)
    for r in rings:
        closing.append([[start + len(r) - 1, start]])
        start += len(r)
    B = np.concatenate(segs + [np.asarray(c) for c in closing])
    return _merge_repeated(np.concatenate([V, np.column_stack([xy, heights])]), np.concatenate([S, B]))


def _vertex_heights(tri: cdt_plugin.Triangulation, V: NDArray[np.float64],
                    S: NDArray[np.int64]) -> NDArray[np.float64]:
    """The height of each output vertex: an input point's own; a crossing's
    along the first segment it lies on (linear between its ends)."""
    heights = np.full(len(tri.vertices), np.nan)
    inputs = tri.vertex_map >= 0
    heights[tri.vertex_map[inputs]] = V[inputs, 2]
    for s in tri.steiner.tolist():
        on = np.flatnonzero((tri.segments == s).any(axis=1))
        k = int(tri.segment_ids[on].min())
        a, b = S[k]
        d = V[b, :2] - V[a, :2]
        t = float(np.dot(tri.vertices[s] - V[a, :2], d) / np.dot(d, d))
        heights[s] = V[a, 2] + min(1.0, max(0.0, t)) * (V[b, 2] - V[a, 2])
    return heights


# ------------------------------------------------------------------ output
def _transform(resolution: float, x0: float, y1: float) -> Transform:
    values = (float(resolution), 0.0, float(x0), 0.0, -float(resolution), float(y1))
    try:
        from affine import Affine
    except ImportError:
        return values
    return Affine(*values)


def _write_geotiff(path: Path, dem: NDArray[np.float64], transform: Transform, crs: Any) -> None:
    import rasterio
    from affine import Affine

    with rasterio.open(path, "w", driver="GTiff", height=dem.shape[0], width=dem.shape[1], count=1,
                       dtype="float64", nodata=np.nan, crs=None if crs is None else crs.to_wkt(),
                       transform=Affine(*tuple(transform)[:6])) as out:
        out.write(dem, 1)
