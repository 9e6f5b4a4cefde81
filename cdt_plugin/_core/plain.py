"""One plain polygon per call, compiled from its coordinates to its output.

What most single calls of the drop-ins pass is one valid Polygon without
options. The routes here mesh it in one compiled call from the coordinates
GEOS gives (shell, then holes, each closed) and show on the way that it is
valid, exactly and at every magnitude, or refuse it:

* :func:`plain_ring_route`, a polygon without holes of up to
  :data:`EAR_RING_MAX` vertices (most of them): its ring checked simple, cut
  into ears and flipped to the constrained Delaunay triangulation
  (:func:`ear_route`, :mod:`.ears`), a few times faster than the general route,
  which builds the Delaunay triangulation of the vertices first;
* :func:`plain_polygon_route`, any other polygon, by the general route
  (:func:`.pipeline.rings_route`): the engine refuses rings that cross, a hole
  outside its shell or inside another, and counts repeated points and points
  on other rings' edges; rings that are simple and pairwise disjoint, with
  every hole inside the shell and in no other hole, make a valid polygon, whose
  constrained triangulation without Steiner points has ``n + 2h - 2``
  triangles (``n`` vertices, ``h`` holes).

Anything else (a ring touching itself or another, a repeated point, a ring
without area) is refused here and goes the general way, which names the
defect or meshes what is valid. The two routes are compiled apart (a first
use with a polygon without holes compiles the first only).

The entries give what the two drop-ins return: the vertices and triangles
(trimesh's ``triangulate_polygon``), and the well-known binary of the
GeometryCollection of the triangles (shapely's ``constrained_delaunay_triangles``),
which GEOS reads in one call. A small call pays about a microsecond for each
call from Python and each array handed back: one call instead of the reader's,
the route's and the writer's, and no :class:`cdt_plugin.Triangulation` in
between.
"""
from __future__ import annotations

import numpy as np

from .checks import first_nonfinite_row
from .ears import counter_clockwise, ear_store, ring_is_simple
from .flips import flip_to_delaunay
from .jit import entry, kernel
from .merge import close_representatives
from .options import RouteOptions, named, plain
from .pipeline import (K_DUPLICATE_SEGMENTS, K_DUPLICATES, K_MERGED_OVERLAPS, K_ON_SEGMENTS,
                       rings_route)
from .output import min_first
from .rings import closed_rings
from .scaling import NO_FIT, fit_shift, scaled
from .status import ROUTE_OK
from .wkb import (COLLECTION_HEADER_2D, CW_CORNERS, POLYGON_HEADER_2D, POLYGON_HEADER_BYTES,
                  write_polygon_records)


#: The route's default options (triangulate's without keywords), as the kernels take them
DEFAULTS = plain(RouteOptions())

#: Rings of at most this many vertices (a polygon without holes) are cut into ears
#: and flipped (:func:`ear_route`); larger ones, or with holes, take the general route,
#: which the ear tests' quadratic worst case would lose to
EAR_RING_MAX = 128
#: The ear tests may look at this many vertices per vertex of the ring before they give
#: way to the general route (a spiral of 128 vertices takes 200; most rings a few)
EAR_WORK = 256


# What a one-polygon route gives: the mesh, a refusal (not plainly valid), or the word
# that the polygon is for the other route (holes, a large ring, one out of ear tests)
PLAIN_DONE = 0
PLAIN_REFUSED = 1
PLAIN_ELSEWHERE = 2


@kernel
def plain_rings(coords, merge_distance, max_rings, max_points):
    """The rings of one polygon from its coordinates (see
    :func:`.rings.closed_rings`) as the one-polygon routes take them:
    ``(status, xy, x, y, ring_start)`` (``x, y`` the columns of ``xy``),
    PLAIN_REFUSED for rings that do not close,
    a non-finite coordinate, or (``merge_distance`` >= 0) two vertices closer
    than it (:func:`.merge.close_representatives`: merging them is the general
    way's); PLAIN_ELSEWHERE, before that search, for more than ``max_rings``
    rings or ``max_points`` points."""
    xy, ring_start = closed_rings(coords)
    n = xy.shape[0]
    x = np.empty(n)
    y = np.empty(n)
    for i in range(n):
        x[i] = xy[i, 0]
        y[i] = xy[i, 1]
    if ring_start.shape[0] == 0 or first_nonfinite_row(xy) >= 0:
        return PLAIN_REFUSED, xy, x, y, ring_start
    if ring_start.shape[0] - 1 > max_rings or n > max_points:
        return PLAIN_ELSEWHERE, xy, x, y, ring_start
    if merge_distance >= 0:
        _, moved = close_representatives(xy, np.empty(0, np.int64), merge_distance)
        if moved > 0:
            return PLAIN_REFUSED, xy, x, y, ring_start
    return PLAIN_DONE, xy, x, y, ring_start


@kernel
def plain_ring_route(coords, merge_distance):
    """The constrained Delaunay triangulation of a polygon without holes of at
    most :data:`EAR_RING_MAX` vertices from its coordinates, when it is plainly
    valid (the module's rule), by :func:`ear_route`: ``(status, vertices,
    triangles)``, PLAIN_DONE with the vertices of the ring without its closing
    point (every one used) and the triangles counter-clockwise; PLAIN_REFUSED
    (not plainly valid, see :func:`plain_rings`); PLAIN_ELSEWHERE for
    :func:`plain_polygon_route`. Apart from it so that a first use with such a
    polygon compiles no more than this."""
    status, xy, x, y, _ = plain_rings(coords, merge_distance, np.int64(1), np.int64(EAR_RING_MAX))
    if status != PLAIN_DONE:
        return status, xy, np.empty((0, 3), np.int64)
    status, triangles = ear_route(x, y)
    return status, xy, triangles


@kernel
def plain_polygon_route(coords, merge_distance):
    """:func:`plain_ring_route` of any polygon, by the general route
    (:func:`.pipeline.rings_route`): PLAIN_DONE or PLAIN_REFUSED."""
    no = np.empty((0, 3), np.int64)
    status, xy, x, y, ring_start = plain_rings(coords, merge_distance, np.int64(coords.shape[0]),
                                               np.int64(coords.shape[0]))
    if status != PLAIN_DONE:
        return status, xy, no
    rings = ring_start.shape[0] - 1
    n = xy.shape[0]
    ring_is_hole = np.ones(rings, np.bool_)
    ring_is_hole[0] = False
    degenerate, status, counts, out = rings_route(x, y, ring_start, np.int64(0), np.int64(rings),
                                                  np.zeros(rings, np.int64), ring_is_hole,
                                                  named(DEFAULTS), np.ones(rings, np.bool_))
    if degenerate or status != ROUTE_OK:
        return PLAIN_REFUSED, xy, no
    if (counts[K_DUPLICATES] or counts[K_ON_SEGMENTS] or counts[K_MERGED_OVERLAPS]
            or counts[K_DUPLICATE_SEGMENTS]):
        return PLAIN_REFUSED, xy, no
    vertices, triangles = out[0], out[1]
    if triangles.shape[0] != n + 2 * (rings - 1) - 2:
        return PLAIN_REFUSED, xy, no
    return PLAIN_DONE, vertices, triangles


@kernel
def ear_route(x, y):
    """The constrained Delaunay triangulation of the polygon of one ring,
    vertices ``0..n-1`` of ``x, y``: the ring checked simple
    (:func:`.ears.ring_is_simple`), cut into ears (:func:`.ears.ear_store`), then
    flipped until every edge that is not on the ring is locally Delaunay (the
    modified flip algorithm, Sec. 2.10.3), with the same perturbed in-circle
    test as the general route, so the same triangles: ``(status, triangles)``,
    each triangle counter-clockwise from its smallest vertex id; PLAIN_REFUSED
    for a ring that is not simple, PLAIN_ELSEWHERE for one out of the
    predicates' range or out of ear tests."""
    n = x.shape[0]
    no = np.empty((0, 3), np.int64)
    shift, _, _ = fit_shift(x, y, np.empty(0))
    if shift == NO_FIT:
        return PLAIN_ELSEWHERE, no
    if shift != 0:
        x = scaled(x, shift)
        y = scaled(y, shift)
    if not ring_is_simple(x, y):
        return PLAIN_REFUSED, no
    done, tri, twin, cons = ear_store(x, y, counter_clockwise(x, y), np.int64(EAR_WORK * n))
    if not done:
        return PLAIN_ELSEWHERE, no
    k = n - 2
    flip_to_delaunay(tri, twin, cons, x, y, x, np.bool_(False), np.int64(n), np.int64(k))
    triangles = np.empty((k, 3), np.int64)
    for t in range(k):
        r = min_first(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2])
        for j in range(3):
            triangles[t, j] = tri[3 * t + (j + r) % 3]
    return PLAIN_DONE, triangles


@entry
def plain_ring_faces(coords, merge_distance):
    """:func:`plain_ring_route` from Python: ``(status, vertices, triangles)``."""
    return plain_ring_route(coords, merge_distance)


@entry
def plain_polygon_faces(coords, merge_distance):
    """:func:`plain_polygon_route` from Python: ``(status, vertices, triangles)``."""
    return plain_polygon_route(coords, merge_distance)


@entry
def plain_ring_collection(coords):
    """The well-known binary of the GeometryCollection of the triangles of
    :func:`plain_ring_route` (:func:`collection_wkb`): ``(status, bytes)``."""
    status, vertices, triangles = plain_ring_route(coords, -1.0)
    return status, collection_wkb(vertices, triangles, status == PLAIN_DONE)


@entry
def plain_polygon_collection(coords):
    """:func:`plain_ring_collection` by :func:`plain_polygon_route`."""
    status, vertices, triangles = plain_polygon_route(coords, -1.0)
    return status, collection_wkb(vertices, triangles, status == PLAIN_DONE)


@kernel
def collection_wkb(vertices, triangles, made):
    """The well-known binary of the GeometryCollection of ``triangles``, as
    GEOS gives them: the collection's header, the number of triangles (a
    32-bit integer in this machine's byte order, which the header names), then
    one Polygon record per triangle, its ring clockwise
    (:func:`.wkb.write_polygon_records`); empty unless ``made``."""
    if not made:
        return np.empty(0, np.uint8)
    coordinate_bytes = vertices.view(np.uint8)
    head = COLLECTION_HEADER_2D.shape[0]
    size = POLYGON_HEADER_BYTES + 4 * coordinate_bytes.shape[1]
    out = np.empty(head + 4 + triangles.shape[0] * size, np.uint8)
    for j in range(head):
        out[j] = COLLECTION_HEADER_2D[j]
    count = np.empty(1, np.uint32)
    count[0] = triangles.shape[0]
    count_bytes = count.view(np.uint8)
    for j in range(4):
        out[head + j] = count_bytes[j]
    write_polygon_records(out, head + 4, coordinate_bytes, triangles, CW_CORNERS, POLYGON_HEADER_2D)
    return out
