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
from ._core.plain import plain_polygon_collection, plain_polygon_faces
from .options import MeshOptions
from .plc import shapely_of

#: The route's options without keywords (triangulate's defaults), as the compiled call takes them
_DEFAULTS = MeshOptions.check().route_args()


def _plain_input(polygon: Any) -> tuple[NDArray[np.float64], int] | None:
    """The coordinates (shell, then holes, each closed) and the number of holes
    of a small 2D shapely Polygon; None for anything else."""
    shapely = shapely_of(polygon)
    if shapely is None or type(polygon) is not shapely.Polygon or shapely.lib.has_z(polygon):
        return None
    coords = shapely.get_coordinates(polygon)
    if len(coords) >= SMALL_SORT:      # (the general way sorts with NumPy, on threads when large)
        return None
    return coords, int(shapely.lib.get_num_interior_rings(polygon))


def plain_mesh(polygon: Any, merge_distance: float | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.int64]] | None:
    """``(vertices, triangles)`` of :func:`cdt_plugin.triangulate(polygon,
    merge_distance=merge_distance) <cdt_plugin.triangulate>` for a plainly
    valid small 2D shapely Polygon with no two vertices closer than
    ``merge_distance`` (every vertex is used, none is added); None otherwise.

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
    plain, vertices, triangles = plain_polygon_faces(read[0], read[1], distance, _DEFAULTS)
    return (vertices, triangles) if plain else None


def plain_collection_wkb(polygon: Any, collection_header: NDArray[np.uint8],
                         polygon_header: NDArray[np.uint8], corners: NDArray[np.int64]) -> bytes | None:
    """The well-known binary of the GeometryCollection of the triangles of a
    plainly valid small 2D shapely Polygon (as ``plain_mesh`` makes them): the
    ``collection_header`` (byte order and type), the count, then one Polygon
    record per triangle, ``polygon_header`` and the closed ring of the
    triangle's ``corners`` (see :func:`cdt_plugin._core.plain.plain_polygon_collection`);
    None for any other geometry."""
    read = _plain_input(polygon)
    if read is None:
        return None
    plain, data = plain_polygon_collection(read[0], read[1], _DEFAULTS, collection_header,
                                           polygon_header, corners)
    return data.tobytes() if plain else None
