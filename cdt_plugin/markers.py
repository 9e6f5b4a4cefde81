"""Boundary markers and vertex attributes of a triangulation, by Triangle's rules.

What the user gave to mark and carry (per input vertex and input segment) is
one record, :class:`Tags`, kept on the result as ``tri.tags``; the functions
here derive the per-output arrays from it and from arrays the result already
has (``segments``, ``segment_ids``, ``steiner``, ``neighbors``,
``vertex_map``), on first access.

Markers (Triangle's rules, checked against the ``triangle`` package):

* a **segment piece** (a row of ``tri.segments``) has the marker of its input
  segment if that is nonzero, else 1 if it lies on the boundary of the
  triangulation (the outer boundary or a hole's), else 0; an **edge** (a row
  of ``tri.edges``) the marker of the piece it is, else 1 on the boundary,
  else 0;
* a **vertex** has its input marker if that is nonzero; else the nonzero
  marker of a segment it lies on (an endpoint, an input vertex splitting it, a
  Steiner point on it, a crossing of two segments) -- of the segment given
  first when several are marked, as Triangle inserts them in input order;
  else 1 on the boundary; else 0.

Choices where the input is irregular: merged duplicate vertices take the
first nonzero marker among their copies; a repeated segment the first nonzero
marker among its copies; a zero-length segment marks nothing (Triangle skips
it); collinear overlapping segments merged by ``intersections="split"`` give
the shared part the marker of the segment ``segment_ids`` names for it; a
vertex in no triangle (all-collinear input, a vertex inside a hole) is on no
boundary: it keeps its input marker or that of a segment it ends, else 0.

Attributes (``vertex_attributes``, k columns): input vertices keep theirs (a
merged duplicate: its first copy's); a Steiner point on an input segment gets
the linear interpolation along that segment (the segment given first, for a
crossing); any other Steiner point the linear interpolation on the triangle
that contains it in a base mesh -- for :func:`cdt_plugin.triangulate`, the
constrained Delaunay triangulation of the input before refinement
(:func:`carry_attributes`). Linear data are reproduced up to rounding.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial
from typing import Callable, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.boundary import boundary_flags
from ._core.certify import locate_all
from ._core.query import convex_disk
from ._routes import hull_triangles
from .types import TriangulationLike
from .validate import as_attributes, as_index, as_markers, as_points, exact_range, near_unit

__all__ = ["Tags", "carry_attributes", "edge_markers", "make_tags", "refined_tags",
           "segment_markers", "vertex_attributes", "vertex_markers"]

#: A base mesh for interpolation: vertices (n, 2), triangles (k, 3), attributes (n, k).
BaseMesh = Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]
_NONE = np.iinfo(np.int64).max          # "no candidate" in the minimum reductions below
_NO_PAIRS = np.empty((0, 2), np.int64)


@dataclass(frozen=True)
class Tags:
    """Markers and attributes given with the input of a triangulation.

    Attributes
    ----------
    segments : (m, 2) int64
        The input segments, as input vertex indices (what ``segment_ids`` names).
    vertex_markers : (n_input,) int64 or None
    segment_markers : (m,) int64 or None
    vertex_attributes : (n_input, k) float64 or None
    base : callable or None
        Makes the :data:`BaseMesh` in which Steiner points off the segments are
        interpolated (called once, on first access; None: no such points).
    """

    segments: NDArray[np.int64]
    vertex_markers: NDArray[np.int64] | None = None
    segment_markers: NDArray[np.int64] | None = None
    vertex_attributes: NDArray[np.float64] | None = None
    base: Callable[[], BaseMesh] | None = None


def make_tags(n: int, segments: NDArray[np.int64], vertex_markers: ArrayLike | None = None,
              segment_markers: ArrayLike | None = None,
              vertex_attributes: ArrayLike | None = None) -> Tags | None:
    """The checked :class:`Tags` of ``n`` input vertices and input ``segments``
    (None when nothing is given): markers one integer per vertex / segment,
    attributes (n,) or (n, k) finite numbers, else the :class:`CDTError` naming
    what is wrong.

    >>> tags = make_tags(3, np.array([[0, 1]]), segment_markers=[5], vertex_attributes=[1, 2, 3.0])
    >>> tags.segment_markers.tolist(), tags.vertex_attributes.shape
    ([5], (3, 1))
    """
    if vertex_markers is None and segment_markers is None and vertex_attributes is None:
        return None
    return Tags(
        segments,
        None if vertex_markers is None else as_markers(vertex_markers, n, "vertex_markers", "input vertex"),
        None if segment_markers is None else as_markers(segment_markers, len(segments),
                                                        "segment_markers", "input segment"),
        None if vertex_attributes is None else as_attributes(vertex_attributes, n))


def refined_tags(tags: Tags | None, tri: TriangulationLike,
                 attributes: Callable[[], NDArray[np.float64] | None]) -> Tags | None:
    """The tags of a refinement of ``tri`` (its vertices first, in order, then the
    new Steiner points; ``vertex_map`` and ``segment_ids`` still naming the
    original input): the same markers and attributes, and a refinement point
    off the segments interpolated on the triangle of ``tri`` that holds it
    (``attributes()``: ``tri``'s vertex attributes, made when first needed), as
    Triangle's ``-r`` interpolates in the mesh it refines."""
    if tags is None or tags.vertex_attributes is None:
        return tags
    return replace(tags, base=partial(_mesh_with, tri.vertices, tri.triangles, attributes))


def _mesh_with(vertices: NDArray[np.float64], triangles: NDArray[np.int64],
               attributes: Callable[[], NDArray[np.float64] | None]) -> BaseMesh:
    values = attributes()
    assert values is not None, "a triangulation with attribute tags has attributes"
    return vertices, triangles, values


# ------------------------------------------------------------------ markers
def _keys(a: NDArray[np.int64], b: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """One number per undirected edge ``a``-``b`` of vertices ``0..n-1``."""
    return np.minimum(a, b) * n + np.maximum(a, b)


def _boundary(tri: TriangulationLike, pairs: NDArray[np.int64]) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Which of ``pairs`` (vertex pairs) are boundary edges of the triangulation
    (in one triangle only), and which vertices lie on the boundary."""
    T = np.ascontiguousarray(tri.triangles, np.int64)
    nb = np.ascontiguousarray(tri.neighbors, np.int64)
    return boundary_flags(T, nb, len(tri.vertices), np.ascontiguousarray(pairs, np.int64))


def _input_segment_markers(tri: TriangulationLike, tags: Tags | None) -> NDArray[np.int64] | None:
    """The marker of each input segment after merging: a segment given several
    times (after merging duplicate vertices, either direction) takes the first
    nonzero marker among its copies; a zero-length one has none. None: no markers."""
    if tags is None or tags.segment_markers is None:
        return None
    marks = tags.segment_markers
    vm = np.asarray(tri.vertex_map)
    a, b = vm[tags.segments[:, 0]], vm[tags.segments[:, 1]]
    marks = np.where(a == b, 0, marks)
    if len(marks) < 2:
        return marks
    _, group = np.unique(_keys(a, b, max(len(tri.vertices), 1)), return_inverse=True)
    group = group.reshape(-1)
    first = np.full(group.max() + 1, _NONE)
    marked = np.flatnonzero(marks != 0)
    np.minimum.at(first, group[marked], marked)
    chosen = first[group]
    return np.where(chosen == _NONE, 0, marks[np.minimum(chosen, len(marks) - 1)])


def segment_markers(tri: TriangulationLike, tags: Tags | None) -> NDArray[np.int64]:
    """The marker of each row of ``tri.segments``: its input segment's marker if
    nonzero, else 1 on the boundary, else 0 (a piece of the convex hull, id -1,
    is on the boundary)."""
    pieces = np.asarray(tri.segments, np.int64).reshape(-1, 2)
    out = _boundary(tri, pieces)[0].astype(np.int64)
    marks = _input_segment_markers(tri, tags)
    if marks is not None and len(pieces):
        ids = np.asarray(tri.segment_ids, np.int64)
        given = np.where(ids >= 0, marks[np.maximum(ids, 0)], 0)
        out = np.where(given != 0, given, out)
    return out


def edge_markers(tri: TriangulationLike, tags: Tags | None) -> NDArray[np.int64]:
    """The marker of each row of ``tri.edges``: that of the segment piece it is,
    else 1 on the boundary, else 0."""
    edges = np.asarray(tri.edges, np.int64).reshape(-1, 2)
    out = _boundary(tri, edges)[0].astype(np.int64)
    pieces = np.asarray(tri.segments, np.int64).reshape(-1, 2)
    if tags is not None and tags.segment_markers is not None and len(pieces) and len(edges):
        n = len(tri.vertices)
        pk = _keys(pieces[:, 0], pieces[:, 1], n)
        by = np.argsort(pk)
        ek = _keys(edges[:, 0], edges[:, 1], n)
        at = np.minimum(np.searchsorted(pk[by], ek), len(pk) - 1)
        hit = pk[by][at] == ek
        out[hit] = segment_markers(tri, tags)[by[at[hit]]]
    return out


def vertex_markers(tri: TriangulationLike, tags: Tags | None) -> NDArray[np.int64]:
    """The marker of each output vertex: its input marker if nonzero, else the
    nonzero marker of the first input segment it lies on, else 1 on the
    boundary, else 0."""
    out = _boundary(tri, _NO_PAIRS)[1].astype(np.int64)
    vm = np.asarray(tri.vertex_map)
    marks = _input_segment_markers(tri, tags)
    if tags is not None and marks is not None and len(marks):
        pieces = np.asarray(tri.segments, np.int64).reshape(-1, 2)
        ids = np.asarray(tri.segment_ids, np.int64)
        m = len(marks)
        v = np.concatenate([pieces[:, 0], pieces[:, 1], vm[tags.segments[:, 0]], vm[tags.segments[:, 1]]])
        s = np.concatenate([ids, ids, np.arange(m), np.arange(m)])
        keep = (s >= 0) & (v >= 0)
        v, s = v[keep], s[keep]
        keep = marks[s] != 0
        _first_wins(out, v[keep], s[keep], marks)
    if tags is not None and tags.vertex_markers is not None:
        given = np.flatnonzero((tags.vertex_markers != 0) & (vm >= 0))
        _first_wins(out, vm[given], given, tags.vertex_markers)
    return out


def _first_wins(out: NDArray[np.int64], where: NDArray[np.int64], rank: NDArray[np.int64],
                value_of: NDArray[np.int64]) -> None:
    """``out[w] = value_of[r]`` for the smallest rank ``r`` given at each ``w``."""
    best = np.full(len(out), _NONE)
    np.minimum.at(best, where, rank)
    has = best != _NONE
    out[has] = value_of[best[has]]


# --------------------------------------------------------------- attributes
def vertex_attributes(tri: TriangulationLike, tags: Tags | None) -> NDArray[np.float64] | None:
    """The attributes of every output vertex, (n, k), or None when none were
    given (see the module's notes). Rows left unknown are NaN (a Steiner point
    off the segments without a base mesh); NaN input propagates."""
    if tags is None or tags.vertex_attributes is None:
        return None
    given = tags.vertex_attributes
    V = np.asarray(tri.vertices, np.float64)
    n = len(V)
    out = np.full((n, given.shape[1]), np.nan)
    known = np.zeros(n, bool)
    vm = np.asarray(tri.vertex_map)
    inputs = np.flatnonzero(vm >= 0)
    first = np.full(n, _NONE)
    np.minimum.at(first, vm[inputs], inputs)
    has = first != _NONE
    out[has], known[has] = given[first[has]], True
    steiner = np.asarray(tri.steiner, np.int64)
    if not len(steiner):
        return out
    _along_segments(tri, tags, V, out, known)
    rest = steiner[~known[steiner]]
    if len(rest) and tags.base is not None:
        out[rest] = carry_attributes(*tags.base(), V[rest])
    return out


def _along_segments(tri: TriangulationLike, tags: Tags, V: NDArray[np.float64],
                    out: NDArray[np.float64], known: NDArray[np.bool_]) -> None:
    """Fill the unknown vertices that end a piece of an input segment: linear
    along that segment (the first such segment), between its input ends."""
    pieces = np.asarray(tri.segments, np.int64).reshape(-1, 2)
    ids = np.asarray(tri.segment_ids, np.int64)
    v, s = pieces.T.ravel(), np.tile(ids, 2)
    want = (s >= 0) & ~known[v]
    if not want.any():
        return
    best = np.full(len(V), _NONE)
    np.minimum.at(best, v[want], s[want])
    v = np.flatnonzero(best != _NONE)
    s = best[v]
    a, b = tags.segments[s, 0], tags.segments[s, 1]
    vm = np.asarray(tri.vertex_map)
    W, _ = near_unit(V)                   # (products of coordinates at any scale)
    A, B = W[vm[a]], W[vm[b]]
    d = B - A
    t = ((W[v] - A) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), np.finfo(float).tiny)
    t = np.clip(t, 0.0, 1.0)[:, None]
    given = tags.vertex_attributes
    assert given is not None
    out[v] = given[a] + t * (given[b] - given[a])
    known[v] = True


def carry_attributes(base_vertices: ArrayLike, base_triangles: ArrayLike, base_attributes: ArrayLike,
                     points: ArrayLike) -> NDArray[np.float64]:
    """The linear interpolation of ``base_attributes`` ((n,) or (n, k), one row
    per base vertex) at ``points`` (m, 2), on the triangle of the base mesh
    that contains each point (exact location; a point at a base vertex gets
    that vertex's row exactly). Points outside the base mesh by rounding (a
    Steiner point on its boundary) get the interpolation on the nearest
    triangle of its convex hull, or along the nearest hull edge. (m, k), or
    (m,) for (n,) attributes; NaN everywhere for a base without triangles.

    >>> import numpy as np
    >>> V = np.array([[0, 0], [2, 0], [0, 2], [2, 2.0]])
    >>> carry_attributes(V, [[0, 1, 2], [1, 3, 2]], V[:, 0] + 2 * V[:, 1], [[1, 0.5], [2, 1], [3, 3]])
    array([2., 4., 6.])
    """
    BV = as_points(base_vertices, "base_vertices")
    T = as_index(base_triangles, "base_triangles", 3, len(BV))
    raw = np.asarray(base_attributes, np.float64)
    A = raw.reshape(len(BV), -1)
    P = np.asarray(points, np.float64).reshape(-1, 2)
    out = np.full((len(P), A.shape[1]), np.nan)
    if len(P) and len(T):
        T, N = _convex_cover(BV, T)
        x, y, _, _ = exact_range(np.r_[BV[:, 0], P[:, 0]], np.r_[BV[:, 1], P[:, 1]])
        nb = len(BV)
        k = locate_all(x[:nb].copy(), y[:nb].copy(), T, N, x[nb:].copy(), y[nb:].copy())
        inside = k >= 0
        W, _ = near_unit(np.r_[BV, P])
        out[inside] = _barycentric(W[T[k[inside]]], A[T[k[inside]]], W[nb:][inside])
        if not inside.all():
            a, b = _boundary_ends_of(T, N)
            out[~inside] = _along_nearest_edge(W[a], W[b], A[a], A[b], W[nb:][~inside])
    return out[:, 0].copy() if raw.ndim == 1 else out


def _convex_cover(V: NDArray[np.float64], T: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """``(triangles, neighbors)`` covering the convex hull of ``V`` and holding
    every triangle of ``T`` (``T`` itself when it covers one convex polygon):
    a visibility walk needs a convex region, and a point just outside a
    concave boundary by rounding then still finds a triangle."""
    from .report import mesh_neighbors        # (loaded on first use, as the result class does)
    N, _ = mesh_neighbors(T)
    x, y, _, _ = exact_range(V[:, 0].copy(), V[:, 1].copy(), None, "base_vertices")
    if convex_disk(T, N, x, y):
        return T, N
    ends = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    return hull_triangles(V, np.unique(ends, axis=0))


def _boundary_ends_of(T: NDArray[np.int64], N: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    k, j = np.nonzero(N < 0)
    return T[k, (j + 1) % 3], T[k, (j + 2) % 3]


def _barycentric(P: NDArray[np.float64], values: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Values (m, k) at points ``q`` (m, 2) of the linear functions on triangles
    ``P`` (m, 3, 2) with ``values`` (m, 3, k) at their corners; a point at a
    corner gets the corner's values exactly."""
    d1, d2, dq = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0], q - P[:, 0]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    safe = np.where(det == 0, 1.0, det)
    l1 = ((dq[:, 0] * d2[:, 1] - d2[:, 0] * dq[:, 1]) / safe)[:, None]
    l2 = ((d1[:, 0] * dq[:, 1] - dq[:, 0] * d1[:, 1]) / safe)[:, None]
    out = values[:, 0] + l1 * (values[:, 1] - values[:, 0]) + l2 * (values[:, 2] - values[:, 0])
    out = np.where((det == 0)[:, None], np.nanmean(values, axis=1), out)
    for c in range(3):
        at = (q == P[:, c]).all(axis=1)
        out[at] = values[at, c]
    return out


def _along_nearest_edge(A: NDArray[np.float64], B: NDArray[np.float64], va: NDArray[np.float64],
                        vb: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Values at points ``q`` (m, 2) interpolated along the nearest of the edges
    ``A``-``B`` (e, 2) with values ``va``, ``vb`` (e, k) at their ends."""
    out = np.empty((len(q), va.shape[1]))
    d = B - A
    dd = np.maximum((d * d).sum(axis=1), np.finfo(float).tiny)
    for lo in range(0, len(q), 256):             # (bounded memory: chunks of points x edges)
        p = q[lo:lo + 256, None, :]
        t = np.clip(((p - A) * d).sum(axis=2) / dd, 0.0, 1.0)
        gap = ((A + t[..., None] * d - p) ** 2).sum(axis=2)
        e = gap.argmin(axis=1)
        te = t[np.arange(len(e)), e][:, None]
        out[lo:lo + 256] = va[e] + te * (vb[e] - va[e])
    return out
