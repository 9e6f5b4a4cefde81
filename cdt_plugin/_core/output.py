"""Compaction of the half-edge store into the output arrays: solid (real,
live) triangles with their neighbours, listed from their smallest vertex id,
constrained flags and segment pieces, vertices in output ids; and the moved-mesh
defect test.

Three id spaces meet here: *input ids* (rows of the user's vertices), *mesh ids*
(insertion order: mesh vertex ``i`` is input point ``order[i]``, Steiner points
after them, the infinite vertex last) and *output ids* (distinct input points in
order of first appearance, then Steiner points). ``mesh_of`` maps input to mesh
ids, ``dup_of`` an input point to the one it repeats, ``vertex_map`` input to
output ids, ``remap`` mesh to output ids.
"""
from __future__ import annotations

import numpy as np

from .jit import B1, B1_2, I64, I64_2, Tuple, entry, kernel
from .kernel import edge_is_illegal, orient
from .mesh import DEAD, is_ghost, is_solid, nxt, prv


@kernel
def solid_ids(tri, ntri, inf):
    """``(tid, k)``: the row of each real (non-ghost, live) triangle of the
    store among them, -1 for the others, and how many there are."""
    tid = np.full(ntri, -1, np.int64)
    k = 0
    for t in range(ntri):
        if not is_solid(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2], inf):
            continue
        tid[t] = k
        k += 1
    return tid, k


@kernel
def solid_triangles(tri, twin, ntri, inf):
    """The real (non-ghost, live) triangles and their neighbours, from the
    half-edge store: neighbour ``j`` is opposite vertex ``j`` (-1: hull)."""
    tid, k = solid_ids(tri, ntri, inf)
    triangles = np.empty((k, 3), np.int64)
    neighbors = np.empty((k, 3), np.int64)
    for t in range(ntri):
        i = tid[t]
        if i < 0:
            continue
        for j in range(3):
            triangles[i, j] = tri[3 * t + j]
            neighbors[i, j] = tid[twin[3 * t + (j + 1) % 3] // 3]
    return triangles, neighbors, tid


@entry
def relabel_store(tri, ntri, remap):
    """In place: every vertex ``v`` of the first ``ntri`` triangles becomes
    ``remap[v]`` (negative entries, DEAD and -1, index ``remap`` from its end)."""
    for e in range(3 * ntri):
        tri[e] = remap[tri[e]]


@entry
def store_triangles(tri, ntri, inf):
    """The real (non-ghost, live) triangles of the store, each listed from its
    smallest vertex id: :func:`solid_triangles` turned by
    :func:`rotate_min_first`, without the neighbours (:func:`store_neighbors`
    makes those when they are asked for; no row map either, 16 MB at a
    million points)."""
    k = 0
    for t in range(ntri):
        k += is_solid(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2], inf)
    triangles = np.empty((k, 3), np.int64)
    i = 0
    for t in range(ntri):
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        if not is_solid(a, b, c, inf):
            continue
        r = min_first(a, b, c)
        for j in range(3):
            triangles[i, j] = tri[3 * t + (j + r) % 3]
        i += 1
    return triangles


@entry
def store_neighbors(tri, twin, ntri, inf):
    """The neighbours of :func:`store_triangles`' rows: neighbour ``j`` is
    opposite vertex ``j`` (-1: hull)."""
    tid, k = solid_ids(tri, ntri, inf)
    neighbors = np.empty((k, 3), np.int64)
    for t in range(ntri):
        i = tid[t]
        if i < 0:
            continue
        r = min_first(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2])
        for j in range(3):
            neighbors[i, j] = tid[twin[3 * t + (j + r + 1) % 3] // 3]
    return neighbors


@entry
def rotate_min_first(triangles, neighbors):
    """List every triangle from its smallest vertex id (neighbours alike), in place."""
    for i in range(triangles.shape[0]):
        r = min_first(triangles[i, 0], triangles[i, 1], triangles[i, 2])
        if r == 0:
            continue
        a0, a1, a2 = triangles[i, 0], triangles[i, 1], triangles[i, 2]
        n0, n1, n2 = neighbors[i, 0], neighbors[i, 1], neighbors[i, 2]
        if r == 1:
            triangles[i, 0], triangles[i, 1], triangles[i, 2] = a1, a2, a0
            neighbors[i, 0], neighbors[i, 1], neighbors[i, 2] = n1, n2, n0
        else:
            triangles[i, 0], triangles[i, 1], triangles[i, 2] = a2, a0, a1
            neighbors[i, 0], neighbors[i, 1], neighbors[i, 2] = n2, n0, n1


@kernel("int64(int64, int64, int64)")
def min_first(a, b, c):
    """The rotation that lists a triangle from its smallest vertex id: output
    triangles then do not depend on the insertion order."""
    if a < b and a < c:
        return 0
    return 1 if b < c else 2


@kernel(apart=True, ahead=(I64_2, I64_2, I64_2, B1, I64), returns=Tuple((I64_2, I64_2, B1_2, I64_2, I64, I64)))
def cdt_arrays(T, N, cflag, inside, remap):
    """One pass over the real triangles of a constrained triangulation: the
    kept ones (``inside``) in output ids with their neighbours (-1 across the
    domain boundary) and constrained flags, and once each segment piece that
    borders a kept triangle, with its input segment."""
    newid = np.full(T.shape[0], -1, np.int64)
    k = 0
    for t in range(T.shape[0]):
        if inside[t]:
            newid[t] = k
            k += 1
    triangles = np.empty((k, 3), np.int64)
    neighbors = np.empty((k, 3), np.int64)
    constrained = np.zeros((k, 3), np.bool_)
    keep = np.empty(k, np.int64)
    npieces = 0
    for t in range(T.shape[0]):
        for j in range(3):
            if is_listed_piece(t, N[t, j], cflag[t, j], inside):
                npieces += 1
    segments = np.empty((npieces, 2), np.int64)
    segment_ids = np.empty(npieces, np.int64)
    p = 0
    for t in range(T.shape[0]):
        i = newid[t]
        r = min_first(remap[T[t, 0]], remap[T[t, 1]], remap[T[t, 2]])
        for j in range(3):
            if is_listed_piece(t, N[t, j], cflag[t, j], inside):
                segments[p, 0] = remap[T[t, (j + 1) % 3]]
                segments[p, 1] = remap[T[t, (j + 2) % 3]]
                segment_ids[p] = cflag[t, j] - 1
                p += 1
            if i >= 0:
                s = (j + r) % 3
                m = N[t, s]
                triangles[i, j] = remap[T[t, s]]
                neighbors[i, j] = newid[m] if m >= 0 else -1
                constrained[i, j] = cflag[t, s] != 0
        if i >= 0:
            keep[i] = t
    return triangles, neighbors, constrained, segments, segment_ids, keep


@kernel(forceinline=True)
def is_listed_piece(t, m, flag, inside):
    """Whether the constrained edge of triangle ``t`` across from neighbour ``m``
    is listed as a segment piece: once (from its lower triangle), and only
    where a kept triangle borders it (as Triangle, which deletes the
    subsegments that holes eat)."""
    return flag != 0 and (m < 0 or t < m) and (inside[t] or (m >= 0 and inside[m]))


@kernel
def cdt_vertices(px, py, kept, vertex_map, order, mx, my, m, nv):
    """Output vertices (the kept input points, then the Steiner points ``m..nv-1``
    of the mesh) and the output id of every mesh vertex."""
    nk = kept.shape[0]
    vertices = np.empty((nk + nv - m, 2))
    for i in range(nk):
        vertices[i, 0] = px[kept[i]]
        vertices[i, 1] = py[kept[i]]
    remap = np.empty(nv, np.int64)
    for i in range(m):
        remap[i] = vertex_map[order[i]]
    for i in range(m, nv):
        vertices[nk + i - m, 0] = mx[i]
        vertices[nk + i - m, 1] = my[i]
        remap[i] = nk + i - m
    return vertices, remap


@entry
def first_defect(tri, twin, ntri, x, y, inf, check_hull):
    """First live triangle that stops the mesh from being a triangulation of a
    convex region after its vertices moved: a real triangle that is not strictly
    counter-clockwise, or (``check_hull``) a ghost edge where the hull is not
    convex. Returns -1 when there is none. No defect means the mesh is embedded:
    positive triangles with a convex boundary cover its inside exactly once."""
    for t in range(ntri):
        if tri[3 * t] == DEAD:
            continue
        e = 3 * t
        if not is_ghost(tri, t, inf):
            if orient(x, y, tri[e], tri[e + 1], tri[e + 2]) <= 0:
                return t
            continue
        for k in range(3 if check_hull else 0):
            a = tri[e + k]
            b = tri[nxt(e + k)]
            if a == inf or b == inf:
                f = twin[e + k]
                if edge_is_illegal(x, y, x, False, inf, a, b, tri[prv(e + k)], tri[prv(f)]):
                    return t
    return -1
