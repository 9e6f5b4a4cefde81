"""Building shapely geometries from meshes: a Triangulation as a
GeometryCollection of triangles (:func:`to_shapely`), triangles as Polygons in
bulk (:func:`triangle_polygons`)."""
from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

import cdt_plugin
from cdt_plugin.parallel import map_ordered, resolve_workers


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
    return shapely.geometrycollections(triangle_shells(tri, z=z, ccw=ccw))


def triangle_shells(tri: cdt_plugin.Triangulation, *, z: ArrayLike | None = None,
                    ccw: bool = False) -> NDArray[np.object_]:
    """The Polygons of :func:`to_shapely`, as an array (one per triangle)."""
    T = np.asarray(tri.triangles)
    V = np.asarray(tri.vertices, dtype=np.float64)
    if z is None and getattr(tri, "plane", None) is not None:
        V = np.asarray(tri.vertices3d)          # 3D input: the triangles in its plane
    elif z is not None:
        zz = np.broadcast_to(np.asarray(z, dtype=np.float64), (len(V),))
        V = np.column_stack([V, zz])
    return triangle_polygons(V, T[:, _CCW if ccw else _CW]) if len(T) else np.empty(0, object)


_CCW = np.array([0, 1, 2, 0], np.intp)     # (corner orders of the closed shells)
_CW = np.array([0, 2, 1, 0], np.intp)


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
