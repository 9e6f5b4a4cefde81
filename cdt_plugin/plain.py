"""One plain shapely Polygon per call: the drop-ins' fast path.

A drop-in called once per small polygon pays for every Python call on its way
(reading, checking, the route, the result object, the output), which is as
much as the mesh itself. Where the polygon is a 2D shapely Polygon of fewer
than :data:`~cdt_plugin._core.ordering.SMALL_SORT` points and no options are
given, these functions read its coordinates in one GEOS call and mesh it in
one compiled call (:mod:`cdt_plugin._core.plain`), which also shows it valid,
exactly at every magnitude; they return None for anything else (a polygon
that is not plainly valid included), which the caller then takes the general
way, with its precise errors. The engine does not import shapely: the module
comes from the geometry (:func:`cdt_plugin.plc.shapely_of`).
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.ordering import SMALL_SORT
from ._core.plain import (PLAIN_DONE, PLAIN_ELSEWHERE, plain_polygon_collection, plain_polygon_faces,
                          plain_ring_collection, plain_ring_faces)
from .plc import shapely_of


def _plain_input(polygon: Any) -> NDArray[np.float64] | None:
    """The coordinates of a small 2D shapely Polygon (shell, then holes, each
    closed), read by one GEOS call; None for anything else."""
    shapely = shapely_of(polygon)
    if shapely is None or type(polygon) is not shapely.Polygon or shapely.lib.has_z(polygon):
        return None
    one = np.empty(1, object)       # (shapely.get_coordinates without its argument handling)
    one[0] = polygon
    coords = shapely.lib.get_coordinates(one, False, False, False)
    return coords if len(coords) < SMALL_SORT else None    # (larger: NumPy's sorts, threads)


def plain_mesh(polygon: Any, merge_distance: float | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.int64]] | None:
    """``(vertices, triangles)`` of :func:`cdt_plugin.triangulate(polygon,
    merge_distance=merge_distance) <cdt_plugin.triangulate>` for a plainly
    valid small 2D shapely Polygon with no two vertices closer than
    ``merge_distance`` (every vertex is used, none is added); None otherwise.
    The same vertices and the same triangles, each from its smallest vertex;
    a polygon without holes gets them in the order its ears make them.

    >>> import shapely
    >>> vertices, triangles = plain_mesh(shapely.box(0, 0, 2, 1))
    >>> vertices.tolist(), len(triangles)
    ([[2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [0.0, 0.0]], 2)
    >>> plain_mesh(shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])) is None   # a bow-tie
    True
    """
    read = _plain_input(polygon)
    if read is None:
        return None
    distance = -1.0 if merge_distance is None else float(merge_distance)
    status, vertices, triangles = plain_ring_faces(read, distance)
    if status == PLAIN_ELSEWHERE:     # (holes, or a large ring: the other route, compiled apart)
        status, vertices, triangles = plain_polygon_faces(read, distance)
    return (vertices, triangles) if status == PLAIN_DONE else None


def plain_collection_wkb(polygon: Any) -> bytes | None:
    """The well-known binary of the GeometryCollection of the triangles of a
    plainly valid small 2D shapely Polygon (as :func:`plain_mesh` makes them),
    in the form ``shapely.constrained_delaunay_triangles`` returns (each
    triangle a Polygon, its ring clockwise); None for any other geometry."""
    read = _plain_input(polygon)
    if read is None:
        return None
    status, data = plain_ring_collection(read)
    if status == PLAIN_ELSEWHERE:
        status, data = plain_polygon_collection(read)
    return data.tobytes() if status == PLAIN_DONE else None
