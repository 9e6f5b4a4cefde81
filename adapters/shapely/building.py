"""Building shapely geometries from meshes: a Triangulation as a
GeometryCollection of triangles (:func:`to_shapely`, one GEOS call:
:func:`polygon_collection`), triangles as Polygons in bulk
(:func:`triangle_polygons`)."""
from __future__ import annotations

import struct
from typing import NamedTuple

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.io import DecodingErrorOptions

import cdt_plugin
from cdt_plugin._core.wkb import (COLLECTION_HEADER_2D, COLLECTION_HEADER_3D, CCW_CORNERS, CW_CORNERS,
                                  POLYGON_HEADER_2D, POLYGON_HEADER_3D, triangle_polygon_records)
from cdt_plugin.parallel import map_ordered, resolve_workers
from cdt_plugin.plain import plain_collection_wkb


def to_shapely(tri: cdt_plugin.Triangulation, *, z: ArrayLike | None = None,
               ccw: bool = False) -> shapely.GeometryCollection:
    """The triangles of ``tri`` as a ``shapely.GeometryCollection`` of Polygons, in the
    form ``shapely.constrained_delaunay_triangles`` returns: one Polygon per
    triangle (in ``tri.triangles`` order), each a closed 4-point shell, clockwise
    like GEOS's output (``ccw=True`` for counter-clockwise shells, the order of
    ``tri.triangles``); no triangles give ``GEOMETRYCOLLECTION EMPTY``.

    Parameters
    ----------
    tri : cdt_plugin.Triangulation
    z : float or (n,) array, optional
        A z coordinate for every vertex (a scalar for all): the polygons are 3D.
        Without it, a triangulation of 3D input (``tri.plane``) gives 3D
        polygons in its plane (``tri.vertices3d``).
    ccw : bool
        Orientation of the triangle shells (default ``False``: clockwise, as GEOS).

    Examples
    --------
    >>> import shapely, cdt_plugin
    >>> gc = to_shapely(cdt_plugin.triangulate(shapely.box(0, 0, 1, 1)))
    >>> gc.geom_type, len(gc.geoms), bool(shapely.is_ccw(gc.geoms[0].exterior))
    ('GeometryCollection', 2, False)
    """
    return polygon_collection([triangle_records(tri, z=z, ccw=ccw)])


# A GeometryCollection of triangles goes to GEOS as well-known binary (WKB), read in
# one call: the collection's header, then per triangle a Polygon record (its header:
# byte order, type, one ring of four points; then the ring's coordinates), written by
# one compiled pass (cdt_plugin._core.wkb). GEOS makes the Polygons straight into the
# collection: Polygons made first (shapely.from_ragged_array) and gathered with
# shapely.geometrycollections, which copies each one, took 2-3x as long.
_POLYGON_HEADER = {2: POLYGON_HEADER_2D, 3: POLYGON_HEADER_3D}
_COLLECTION_HEADER = {2: COLLECTION_HEADER_2D.tobytes(), 3: COLLECTION_HEADER_3D.tobytes()}   # (then the count)
_COUNT = struct.Struct("=I")


class PolygonRecords(NamedTuple):
    """The WKB of ``polygons`` Polygons of dimension ``dim`` (2 or 3), one after the other."""
    data: NDArray[np.uint8]
    polygons: int
    dim: int


def triangle_records(tri: cdt_plugin.Triangulation, *, z: ArrayLike | None = None,
                     ccw: bool = False) -> PolygonRecords:
    """The Polygons of :func:`to_shapely`, as WKB records (one per triangle,
    in ``tri.triangles`` order)."""
    T = np.ascontiguousarray(tri.triangles, dtype=np.int64)
    V = tri.vertices
    if z is None and getattr(tri, "plane", None) is not None:
        V = tri.vertices3d                      # 3D input: the triangles in its plane
    elif z is not None:
        zz = np.broadcast_to(np.asarray(z, dtype=np.float64), (len(V),))
        V = np.column_stack([V, zz])
    return mesh_records(V, T, ccw=ccw)


def mesh_records(vertices: NDArray[np.float64], triangles: NDArray[np.int64], *,
                 ccw: bool = False) -> PolygonRecords:
    """The Polygons of the ``triangles`` (k, 3) of ``vertices`` (n, 2 or 3), as
    WKB records (one per triangle, in order; clockwise unless ``ccw``)."""
    V = np.ascontiguousarray(vertices, dtype=np.float64)
    dim = V.shape[1]
    data = triangle_polygon_records(V.view(np.uint8), np.ascontiguousarray(triangles, dtype=np.int64),
                                    CCW_CORNERS if ccw else CW_CORNERS, _POLYGON_HEADER[dim])
    return PolygonRecords(data, len(triangles), dim)


def polygon_collection(parts: list[PolygonRecords]) -> shapely.GeometryCollection:
    """The GeometryCollection of the Polygons of ``parts``, in order (Z when
    one of them is 3D: a collection's members may differ in dimension, as
    GEOS's may), made by one GEOS call; ``GEOMETRYCOLLECTION EMPTY`` for none.

    >>> import numpy as np, cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0.0, 0], [1, 0], [0, 1]])
    >>> polygon_collection([triangle_records(tri), triangle_records(tri, z=5.0)]).wkt
    'GEOMETRYCOLLECTION Z (POLYGON ((0 0, 0 1, 1 0, 0 0)), POLYGON Z ((0 0 5, 0 1 5, 1 0 5, 0 0 5)))'
    """
    head = _COLLECTION_HEADER[max((p.dim for p in parts), default=2)]
    count = _COUNT.pack(sum(p.polygons for p in parts))
    return _from_wkb(b"".join([head, count] + [p.data.tobytes() for p in parts]))


def plain_triangles(geometry: object) -> shapely.GeometryCollection | None:
    """:func:`to_shapely` of the triangulation of a small 2D Polygon that is
    plainly valid (:mod:`cdt_plugin.plain`: one compiled call from its
    coordinates to the collection's WKB, then one GEOS call); None for any
    other geometry, which the caller takes the general way.

    >>> plain_triangles(shapely.box(0, 0, 1, 1)).wkt
    'GEOMETRYCOLLECTION (POLYGON ((1 0, 0 0, 1 1, 1 0)), POLYGON ((1 1, 0 0, 0 1, 1 1)))'
    """
    data = plain_collection_wkb(geometry)
    return None if data is None else _from_wkb(data)


_RAISE = np.uint8(DecodingErrorOptions.get_value("raise"))


def _from_wkb(data: bytes) -> shapely.Geometry:
    """``shapely.from_wkb(data)`` of one bytes object, without its argument
    handling (a third of a small call's)."""
    wkb = np.empty((), object)          # (an object array: a bytes dtype would drop trailing zeros)
    wkb[()] = data
    return shapely.lib.from_wkb(wkb, _RAISE)




#: Triangles per thread worth starting one for when making their polygons
POLYGONS_PER_THREAD = 50_000


#: At most this many triangles' rings are gathered at once when making their polygons
POLYGON_PIECE = 1_000_000


def triangle_polygons(vertices: NDArray[np.float64], corners: NDArray[np.int64],
                      workers: int | None = 1) -> NDArray[np.object_]:
    """One Polygon per row of ``corners`` ``(k, 4)``: the closed ring of those
    rows of ``vertices`` ``(n, 2)`` or ``(n, 3)``, made by one vectorised call
    (``shapely.from_ragged_array``) per piece of at most ``POLYGON_PIECE``
    rings, gathered piece by piece (never all the rings at once), on ``workers``
    threads (None: every core) for large ``k`` (GEOS makes the polygons without
    the GIL: two threads took 0.67 s for 2 million, one 1.47 s).

    >>> import numpy as np
    >>> triangle_polygons(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2, 0]])).tolist()
    [<POLYGON ((0 0, 1 0, 0 1, 0 0))>]
    """
    k = len(corners)
    if k < POLYGONS_PER_THREAD and k <= POLYGON_PIECE:     # (one piece, this thread: a small call's path)
        return _ring_polygons(vertices[corners])
    threads = resolve_workers(workers, k // POLYGONS_PER_THREAD)
    pieces = max(threads, -(-k // POLYGON_PIECE))     # (a piece's rings: at most 64 MB in 2D)
    bounds = [k * i // pieces for i in range(pieces + 1)]
    parts = map_ordered(lambda i: _ring_polygons(vertices[corners[bounds[i]:bounds[i + 1]]]),
                        range(pieces), threads)
    return parts[0] if pieces == 1 else np.concatenate(parts)


def _ring_polygons(rings: NDArray[np.float64]) -> NDArray[np.object_]:
    """Polygons from closed rings of four corners, ``(k, 4, 2)`` or ``(k, 4, 3)``."""
    k = len(rings)
    return shapely.from_ragged_array(
        shapely.GeometryType.POLYGON, np.ascontiguousarray(rings.reshape(4 * k, rings.shape[2])),
        (np.arange(0, 4 * k + 1, 4, dtype=np.int64), np.arange(k + 1, dtype=np.int64)))
