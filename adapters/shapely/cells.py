"""The Voronoi services the engine calls through GEOS: cells as Polygons
(:func:`cells_to_polygons`) and cells clipped to a polygon
(:func:`clip_cells_to_polygon`)."""
from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

import cdt_plugin
import cdt_plugin.adapters.shapely.validity as validity
from cdt_plugin.adapters.shapely.reading import MULTIPOLYGON, POLYGON


def cells_to_polygons(offsets: NDArray[np.int64], xy: NDArray[np.float64]) -> NDArray[np.object_]:
    """One Polygon per cell from flat counter-clockwise rings (not closed):
    cell ``i`` is ``xy[offsets[i]:offsets[i + 1]]``, an empty Polygon where it
    is empty (:attr:`cdt_plugin.Voronoi.cell_xy`). Vectorised
    (``shapely.from_ragged_array``).

    >>> import numpy as np
    >>> cells_to_polygons(np.array([0, 3, 3]), np.array([[0.0, 0], [1, 0], [0, 1]])).tolist()
    [<POLYGON ((0 0, 1 0, 0 1, 0 0))>, <POLYGON EMPTY>]
    """
    sizes = np.diff(offsets)
    full = sizes > 0
    # close each ring: its first corner again after its last
    coords = np.insert(xy, offsets[1:][full], xy[offsets[:-1][full]], axis=0)
    ring_offsets = np.concatenate([[0], np.cumsum(sizes[full] + 1)]).astype(np.int64)
    polygon_offsets = np.concatenate([[0], np.cumsum(full)]).astype(np.int64)
    return shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords, (ring_offsets, polygon_offsets))


def clip_cells_to_polygon(vor: cdt_plugin.Voronoi, clip: Any) -> NDArray[np.object_]:
    """Every cell of ``vor`` cut to a polygonal geometry ``clip`` (a Polygon
    or MultiPolygon, any object with ``__geo_interface__``): the cells are
    cut to its bounding box first, exactly as a box clip does, then intersected
    with it by GEOS. One Polygon or MultiPolygon per site (a non-convex region
    can cut a cell in pieces), an empty Polygon where nothing is left.
    Raises :class:`cdt_plugin.ClipRegionError` for a non-polygonal, invalid or
    empty region, or one that contains none of the sites, and
    :class:`cdt_plugin.CoordinateRangeError` when two sites are too close for
    GEOS beside the region's coordinates (:data:`GEOS_RANGE`)."""
    from cdt_plugin.errors import ClipRegionError
    geom = clip if isinstance(clip, shapely.Geometry) else shapely.geometry.shape(clip) \
        if hasattr(clip, "__geo_interface__") else None
    if geom is None or shapely.get_type_id(geom) not in (POLYGON, MULTIPOLYGON):
        raise ClipRegionError(f"clip must be a box (xmin, ymin, xmax, ymax) or a Polygon / "
                              f"MultiPolygon, got {type(clip).__name__}")
    if geom.is_empty:
        raise ClipRegionError("clip polygon is empty")
    if not validity.is_valid(np.array([geom], dtype=object))[0]:
        raise ClipRegionError(f"clip polygon is invalid: {validity.reason(geom)}")
    # GEOS works on everything scaled by a power of two (exact) to the region's size
    e = _geos_exponent(vor, geom)
    region = _scaled(geom, -e)
    shapely.prepare(region)
    if not shapely.intersects(region, _scaled(shapely.points(vor.points), -e)).any():
        raise ClipRegionError(f"the clip polygon contains none of the {len(vor.points)} points")
    boxed = vor.clipped(tuple(geom.bounds))
    assert boxed.cell_offsets is not None and boxed.cell_xy is not None
    try:
        cells = shapely.intersection(_scaled(cells_to_polygons(boxed.cell_offsets, boxed.cell_xy), -e),
                                     region)
    except shapely.errors.GEOSException as exc:
        raise ClipRegionError(f"GEOS cannot cut the cells with the clip polygon ({exc}); clip "
                              "with a box (xmin, ymin, xmax, ymax), which cdt_plugin cuts itself") from exc
    return _polygonal_parts(_scaled(cells, e))


_scaled = validity.scaled


#: GEOS intersects in doubles: the closest sites' distance, relative to the
#: clip region's coordinates, at least 2**-510 (squares of such differences
#: stay normal doubles; below, cells a few such distances wide came out of GEOS
#: overlapping or empty)
GEOS_RANGE = 510


def _geos_exponent(vor: cdt_plugin.Voronoi, geom: Any) -> int:
    """The power of two that brings the clip region's coordinates near 1 for
    GEOS (exact scaling: any overall scale works), or a
    :class:`cdt_plugin.CoordinateRangeError` when the closest two sites are
    too close for GEOS beside the region's coordinates."""
    from cdt_plugin.errors import CoordinateRangeError
    top = float(np.abs(np.asarray(geom.bounds)).max())
    e = int(np.frexp(top)[1]) if top > 0 else 0
    pts = vor.points
    a, b = vor.ridge_points.T            # neighbouring cells (the closest two sites are among them)
    gap = np.hypot(pts[a, 0] - pts[b, 0], pts[a, 1] - pts[b, 1])
    k = int(np.argmin(gap))
    if np.ldexp(gap[k], -e) < 2.0 ** -GEOS_RANGE:
        raise CoordinateRangeError(
            f"sites {int(a[k])} {pts[a[k]].tolist()} and {int(b[k])} {pts[b[k]].tolist()} are "
            f"{gap[k]:.3g} apart, beside clip coordinates up to {top:.3g}: too close for GEOS to "
            f"intersect their cells with the clip polygon in doubles (at most 2**{GEOS_RANGE} "
            "between them); clip with a box (xmin, ymin, xmax, ymax), which cdt_plugin cuts itself "
            "at any scale, or clip the points' own neighbourhood", rows=(int(a[k]), int(b[k])))
    return e


def _polygonal_parts(geoms: NDArray[np.object_]) -> NDArray[np.object_]:
    """Each geometry as a Polygon or MultiPolygon: the polygons of a collection
    (an intersection that also touches the region along a line or at a point),
    an empty Polygon where there are none."""
    out = geoms.copy()
    types = shapely.get_type_id(geoms)
    for i in np.flatnonzero(~np.isin(types, (POLYGON, MULTIPOLYGON))):
        parts = shapely.get_parts(geoms[i])
        parts = parts[shapely.get_type_id(parts) == POLYGON]
        out[i] = (shapely.Polygon() if not len(parts) else parts[0] if len(parts) == 1
                  else shapely.multipolygons(parts))
    return out
