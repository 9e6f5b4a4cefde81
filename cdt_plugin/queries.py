"""Point location and interpolation on a finished :class:`Triangulation`.

Queries walk over the triangles (:mod:`cdt_plugin._core.query`), which needs a
convex region: a domain that is not one convex polygon (a polygon's CDT, with
holes or concave corners) is completed once, on the first query, with the
triangles of its complement in the convex hull (a constrained triangulation of
the vertices with every domain edge a segment, which holds every domain
triangle). Queries in a filler triangle are outside the domain.

>>> import cdt_plugin
>>> square = [[0, 0], [4, 0], [4, 4], [0, 4]]
>>> hole = [[1, 1], [3, 1], [3, 3], [1, 3]]
>>> tri = cdt_plugin.triangulate({"type": "Polygon", "coordinates": [square, hole]})
>>> tri.locate([[0.5, 2], [2, 2]]).tolist()         # the second point is in the hole
[3, -1]
>>> walk_mesh(tri).own.tolist().count(-1)           # the hole's two filler triangles
2
"""
from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.ordering import HILBERT_BITS, hilbert_keys
from ._core.query import (
    convex_disk,
    interpolate_linear,
    interpolate_natural,
    locate_all,
)
from ._routes import hull_triangles
from .errors import CDTError, InputShapeError, PrecisionWarning
from .types import TriangulationLike
from .validate import as_queries, exact_range

METHODS = ("linear", "natural")


class WalkMesh(NamedTuple):
    """Triangles covering the convex hull, for walking: ``own`` maps each to the
    domain triangle it is (-1: a filler outside the domain); ``first_at[v]`` is
    the smallest domain triangle at vertex ``v``."""
    T: NDArray[np.int64]
    N: NDArray[np.int64]
    own: NDArray[np.int64]
    first_at: NDArray[np.int64]


def walk_mesh(tri: TriangulationLike) -> WalkMesh:
    """The triangulation's :class:`WalkMesh` (made once, kept on ``tri``)."""
    cached = tri.__dict__.get("_walk")
    if cached is not None:
        return cached
    T, N = tri.triangles, tri.neighbors
    k, n = len(T), len(tri.vertices)
    own = np.arange(k, dtype=np.int64)
    x, y = _scaled_vertices(tri)
    if k and not convex_disk(T, N, x, y):
        T, N, own = _completed(tri)
    first_at = np.full(n, k, np.int64)
    mine = own >= 0
    np.minimum.at(first_at, T[mine].ravel(), np.repeat(own[mine], 3))
    first_at[first_at == k] = -1
    mesh = WalkMesh(np.ascontiguousarray(T, dtype=np.int64), np.ascontiguousarray(N, dtype=np.int64),
                    own, first_at)
    tri.__dict__["_walk"] = mesh
    return mesh


def _completed(tri: TriangulationLike) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Triangles of the convex hull: the constrained triangulation of the
    vertices with every edge of ``tri`` a segment (so it holds each triangle of
    ``tri``), and which of ``tri``'s triangles each one is."""
    triangles, neighbors = hull_triangles(np.ascontiguousarray(tri.vertices), tri.edges)
    ours = np.sort(tri.triangles, axis=1)
    theirs = np.sort(triangles, axis=1)
    both = np.concatenate([ours, theirs])
    order = np.lexsort(both.T[::-1])
    same = (both[order[1:]] == both[order[:-1]]).all(axis=1)
    own = np.full(len(theirs), -1, np.int64)
    a, b = order[:-1][same], order[1:][same]
    mine, other = np.where(a < len(ours), a, b), np.where(a < len(ours), b, a)
    own[other - len(ours)] = mine
    if (own >= 0).sum() != len(ours):
        raise CDTError("the triangulation's triangles overlap: it cannot be queried")
    return triangles, neighbors, own


def _scaled_vertices(tri: TriangulationLike, qx: NDArray[np.float64] | None = None,
                     qy: NDArray[np.float64] | None = None) -> tuple[NDArray[np.float64], ...]:
    """Vertex (and query) coordinates scaled by one power of two into the exact
    predicates' range."""
    v = tri.vertices
    if qx is None or qy is None:
        x, y, _, _ = exact_range(v[:, 0].copy(), v[:, 1].copy(), None, "vertices")
        return x, y
    n = len(v)
    x, y, _, _ = exact_range(np.concatenate([v[:, 0], qx]), np.concatenate([v[:, 1], qy]), None,
                             "vertices and points")
    return x[:n].copy(), y[:n].copy(), x[n:].copy(), y[n:].copy()


def _located(tri: TriangulationLike, pts: NDArray[np.float64]):
    """``(mesh, x, y, qx, qy, found, where, code, j, near)``: the walk over
    spatially sorted queries (see :func:`cdt_plugin._core.query.locate_all`)
    for the queries ``near`` (indices) in the vertices' bounding box; the others
    are outside, whatever their magnitude."""
    mesh = walk_mesh(tri)
    V = tri.vertices
    inbox = (pts >= V.min(axis=0)).all(axis=1) & (pts <= V.max(axis=0)).all(axis=1)
    near = np.flatnonzero(inbox)
    sub = pts[near]
    if len(near) and not inbox.all():      # (rows numbered as given: far ones as zeros, which fit any scale)
        named = np.where(inbox[:, None], pts, 0.0)
        exact_range(named[:, 0], named[:, 1], None, "points")
    else:
        exact_range(sub[:, 0], sub[:, 1], None, "points")    # names the rows out of range
    x, y, qx, qy = _scaled_vertices(tri, sub[:, 0], sub[:, 1])
    idx = np.arange(len(sub), dtype=np.int64)
    order = np.argsort(hilbert_keys(qx, qy, idx, np.int64(HILBERT_BITS)), kind="stable")
    found, where, code, j = locate_all(mesh.T, mesh.N, mesh.own, mesh.first_at, x, y, qx, qy, order)
    return mesh, x, y, qx, qy, found, where, code, j, near


def locate(tri: TriangulationLike, points: ArrayLike) -> NDArray[np.int64]:
    """See :meth:`Triangulation.locate`."""
    pts = as_queries(points)
    out = np.full(len(pts), -1, np.int64)
    if len(pts) and len(tri.triangles):
        located = _located(tri, pts)
        out[located[-1]] = located[5]
    return out


def interpolate(tri: TriangulationLike, values: ArrayLike, points: ArrayLike,
                method: str = "linear") -> NDArray[np.float64]:
    """See :meth:`Triangulation.interpolate`."""
    if method not in METHODS:
        raise CDTError(f"method must be one of {METHODS}, got {method!r}")
    vals = np.asarray(values, dtype=np.float64) if not isinstance(values, np.ndarray) else values
    if vals.dtype.kind not in "fiub":
        raise InputShapeError(f"values must be real numbers, got dtype {vals.dtype}")
    n = len(tri.vertices)
    if vals.ndim not in (1, 2) or vals.shape[0] != n:
        raise InputShapeError(f"values must have shape ({n},) or ({n}, k): one row per vertex, "
                              f"got {vals.shape}")
    if method == "natural" and tri.weights is not None:
        raise CDTError("method='natural' needs an unweighted triangulation (use 'linear')")
    pts = as_queries(points)
    table = np.ascontiguousarray(vals.reshape(n, -1), dtype=np.float64)
    out = np.full((len(pts), table.shape[1]), np.nan)
    if len(pts) and len(tri.triangles):
        mesh, x, y, qx, qy, found, where, code, j, near = _located(tri, pts)
        T_own = np.ascontiguousarray(tri.triangles, dtype=np.int64)
        if method == "linear":
            out[near] = interpolate_linear(T_own, x, y, qx, qy, found, table)
        else:
            out[near], fallbacks = interpolate_natural(mesh.T, mesh.N, _blocked(tri, mesh), x, y, qx, qy,
                                                       found, where, code, j, table)
            if fallbacks[1]:
                warnings.warn(f"{int(fallbacks[1])} of {len(pts)} points got the linear interpolant: "
                              "their natural neighbour coordinates lost every digit to rounding "
                              "(slivers or points nearly on a line)", PrecisionWarning, stacklevel=3)
    return out[:, 0].copy() if vals.ndim == 1 else out


def _blocked(tri: TriangulationLike, mesh: WalkMesh) -> NDArray[np.bool_]:
    """Edges of the walk mesh a natural neighbour cavity does not cross: the
    boundary of the domain, segments, and edges that are not locally Delaunay."""
    cached = tri.__dict__.get("_blocked")
    if cached is not None:
        return cached
    T, N, own = mesh.T, mesh.N, mesh.own
    n = len(tri.vertices)
    a, b = T[:, [1, 2, 0]], T[:, [2, 0, 1]]
    key = np.minimum(a, b) * n + np.maximum(a, b)
    nb = np.where(N >= 0, N, 0)
    blocked = (N < 0) | (own[:, None] < 0) | (own[nb] < 0)
    stops = [tri.segments] if len(tri.segments) else []
    t_own = tri.triangles
    if tri.constrained.any():
        tt, jj = np.nonzero(tri.constrained)
        stops.append(np.column_stack([t_own[tt, (jj + 1) % 3], t_own[tt, (jj + 2) % 3]]))
    bad = tri.non_delaunay_edges()
    if len(bad):
        stops.append(bad)
    if stops:
        e = np.concatenate(stops).astype(np.int64)
        blocked |= np.isin(key, np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1]))
    tri.__dict__["_blocked"] = blocked
    return blocked
