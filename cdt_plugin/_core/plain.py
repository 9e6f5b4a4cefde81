"""One plain polygon per call, compiled from its coordinates to its output.

What most single calls of the drop-ins pass is one valid Polygon without
options. :func:`plain_polygon_route` meshes it in one compiled call from the
coordinates GEOS gives (shell, then holes, each closed) and shows on the way
that it is valid, exactly and at every magnitude: the engine refuses rings
that cross, a hole outside its shell or inside another, and counts repeated
points and points on other rings' edges; rings that are simple and pairwise
disjoint, with every hole inside the shell and in no other hole, make a valid
polygon, whose constrained triangulation without Steiner points has ``n + 2h
- 2`` triangles (``n`` vertices, ``h`` holes). Anything else (a ring touching
itself or another, a repeated point, a ring without area) is refused here and
goes the general way, which names the defect or meshes what is valid.

The two entries give what the two drop-ins return: the vertices and triangles
(trimesh's ``triangulate_polygon``), and the well-known binary of the
GeometryCollection of the triangles (shapely's ``constrained_delaunay_triangles``),
which GEOS reads in one call. A small call pays about a microsecond for each
call from Python and each array handed back: one call instead of the reader's,
the route's and the writer's, and no :class:`cdt_plugin.Triangulation` in
between, is most of what makes the drop-ins as fast as ``triangulate``.
"""
from __future__ import annotations

import numpy as np

from .checks import first_nonfinite_row
from .jit import entry, kernel
from .merge import close_representatives
from .options import named
from .pipeline import (K_DUPLICATE_SEGMENTS, K_DUPLICATES, K_MERGED_OVERLAPS, K_ON_SEGMENTS,
                       rings_route)
from .rings import closed_rings
from .status import ROUTE_OK
from .wkb import POLYGON_HEADER_BYTES, write_polygon_records


@kernel
def plain_polygon_route(coords, holes, merge_distance, options):
    """The constrained Delaunay triangulation of one polygon of ``holes`` holes
    from its coordinates (n, 2 or more columns; see :func:`.rings.closed_rings`)
    when it is plainly valid (the module's rule): ``(True, vertices,
    triangles)``, the vertices those of the rings without their closing points
    (every one used), the triangles counter-clockwise; ``(False, ...)``
    otherwise. With ``merge_distance`` >= 0 a polygon with two vertices closer
    than it (:func:`.merge.close_representatives`) is refused too (merging
    them is the general way's). ``options``: :func:`.options.plain` of the
    route's default options."""
    no = (False, np.empty((0, 2)), np.empty((0, 3), np.int64))
    rings = holes + 1
    xy, ring_start = closed_rings(coords, rings)
    if ring_start.shape[0] == 0 or first_nonfinite_row(xy) >= 0:
        return no
    n = xy.shape[0]
    if merge_distance >= 0:
        _, moved = close_representatives(xy, np.empty(0, np.int64), merge_distance)
        if moved > 0:
            return no
    x = np.empty(n)
    y = np.empty(n)
    for i in range(n):
        x[i] = xy[i, 0]
        y[i] = xy[i, 1]
    ring_is_hole = np.ones(rings, np.bool_)
    ring_is_hole[0] = False
    degenerate, status, counts, out = rings_route(x, y, ring_start, np.int64(0), np.int64(rings),
                                                  np.zeros(rings, np.int64), ring_is_hole,
                                                  named(options), np.ones(rings, np.bool_))
    if degenerate or status != ROUTE_OK:
        return no
    if (counts[K_DUPLICATES] or counts[K_ON_SEGMENTS] or counts[K_MERGED_OVERLAPS]
            or counts[K_DUPLICATE_SEGMENTS]):
        return no
    vertices, triangles = out[0], out[1]
    if triangles.shape[0] != n + 2 * holes - 2:
        return no
    return True, vertices, triangles


@entry
def plain_polygon_faces(coords, holes, merge_distance, options):
    """:func:`plain_polygon_route` from Python: ``(plain, vertices, triangles)``."""
    return plain_polygon_route(coords, holes, merge_distance, options)


@entry
def plain_polygon_collection(coords, holes, options, collection_header, polygon_header, corners):
    """The well-known binary of the GeometryCollection of the triangles of
    :func:`plain_polygon_route`: ``collection_header`` (byte order and type,
    5 bytes), the number of triangles (a 32-bit integer in this machine's byte
    order, which the header names), then one Polygon record per triangle
    (:func:`.wkb.write_polygon_records` with ``polygon_header`` and the
    ring's ``corners``). ``(False, empty)`` when the polygon is not plainly
    valid."""
    plain, vertices, triangles = plain_polygon_route(coords, holes, -1.0, options)
    if not plain:
        return False, np.empty(0, np.uint8)
    coordinate_bytes = vertices.view(np.uint8)
    head = collection_header.shape[0]
    size = POLYGON_HEADER_BYTES + 4 * coordinate_bytes.shape[1]
    out = np.empty(head + 4 + triangles.shape[0] * size, np.uint8)
    for j in range(head):
        out[j] = collection_header[j]
    count = np.empty(1, np.uint32)
    count[0] = triangles.shape[0]
    count_bytes = count.view(np.uint8)
    for j in range(4):
        out[head + j] = count_bytes[j]
    write_polygon_records(out, head + 4, coordinate_bytes, triangles, corners, polygon_header)
    return True, out
