"""Refining an existing mesh (Triangle's ``-r``): its half-edge store, then :mod:`.refine`.

:func:`existing_mesh_store` makes the store of a mesh given as vertices and
triangles, the store that :func:`.refine.refine_store` refines: the
constrained Delaunay triangulation of the vertices with every edge of the mesh
a segment. That forces exactly the given triangles when they form a
triangulation (interiors disjoint, no vertex inside a triangle or on an edge
it does not end), and tells where they do not: two edges cross, or a given
triangle is not a triangle of the store. Every triangle of the convex hull is
kept, so the holes and pockets of the mesh are triangles too, labelled
``OUT``, with the ghosts around the hull. Each given triangle's slot is
labelled with its index (the area bound of label ``t`` is then the bound of
triangle ``t``); the edges that are neither a segment to keep nor on the
mesh's boundary lose their segment id, so refinement may flip them. With
per-triangle bounds a label is only where refinement starts looking: each
triangle it makes or changes takes the label of the given triangle that holds
its centroid (:func:`.refine.home_of`).

:func:`refine_existing` refines such a store (or the store a previous
refinement left) and makes the output arrays, with what a further refinement
of its result needs (each output triangle's slot).
"""
from __future__ import annotations

import math

import numpy as np

from .arrays import copy_rows
from .construct import DIVIDE, build_mesh, horizontal_order
from .flips import flip_to_delaunay
from .jit import entry, kernel
from .mesh import nxt, prv
from .options import RefineOptions, named
from .output import cdt_arrays
from .pipeline import dedup_tasks, insert_all_segments, route_points, solid_with_flags
from .refine import C_FLIPS, OUT, count_below, refine_store
from .scaling import unscale_rows
from .segments import by_smaller_end
from .status import ALL_DONE, OK, ROUTE_OK, STOP_CROSSING, STOP_OVERLAP

# what existing_mesh_store reports (``info`` says where)
MESH_OK = 0
MESH_RANGE = 1         # no power of two brings the coordinates into range: rows (finest, largest)
MESH_REPEATED = 2      # two vertices are the same point: (vertex, the vertex it repeats)
MESH_NOT_EDGE = 3      # a segment to keep is not an edge of the triangles: (segment,)
MESH_CROSSING = 4      # two edges cross: (edge, edge) as rows of ``edges``
MESH_OVERLAP = 5       # two edges overlap (collinear): (edge, edge)
MESH_MISSING = 6       # a triangle is not one of the triangulation: (triangle,)
MESH_INTERNAL = 7      # (never seen) a stage stopped: (stage, status)


@kernel
def mesh_edges(T, nb, segs, n):
    """The segments ``segs`` (vertex pairs), then every other edge of the
    triangles ``T`` once, from its smaller end (``nb`` their neighbours,
    :func:`triangle_neighbors`: an edge is listed by the triangle of smaller
    index): ``(edges, -1)``, or ``(segs, s)`` when segment ``s`` is not an
    edge of the triangles. Linear time (the segments grouped by their smaller
    end)."""
    m = segs.shape[0]
    start, group = by_smaller_end(segs, m, n)
    found = np.zeros(m, np.bool_)         # a segment's first row: an edge of the triangles
    edges = np.empty((m + 3 * T.shape[0], 2), np.int64)
    copy_rows(edges, segs, m)
    k = m
    for t in range(T.shape[0]):
        for j in range(3):
            if 0 <= nb[t, j] < t:
                continue                  # listed from the other side
            a = min(T[t, (j + 1) % 3], T[t, (j + 2) % 3])
            b = max(T[t, (j + 1) % 3], T[t, (j + 2) % 3])
            s = find_edge(segs, start, group, a, b)
            if s >= 0:
                found[s] = True
                continue
            edges[k, 0] = a
            edges[k, 1] = b
            k += 1
    for s in range(m):
        f = find_edge(segs, start, group, segs[s, 0], segs[s, 1])
        if f < 0 or not found[f]:
            return segs, np.int64(s)
    return edges[:k], np.int64(-1)


@entry
def triangle_neighbors(T, n):
    """Neighbours of the counter-clockwise triangles ``T`` over vertices
    ``0..n-1``: ``neighbors[t, j]`` shares the edge opposite corner ``j`` of
    ``t`` (-1: none). Returns ``(neighbors, t, u)``: ``t < u`` two triangles
    with an edge the same way round (they overlap; an edge in three triangles
    is in two of them so), else -1, -1. Linear time (the half-edges grouped
    by their smaller end)."""
    k = T.shape[0]
    half = np.empty((3 * k, 2), np.int64)        # half-edge 3t+j: opposite corner j
    for t in range(k):
        for j in range(3):
            half[3 * t + j, 0] = T[t, (j + 1) % 3]
            half[3 * t + j, 1] = T[t, (j + 2) % 3]
    start, group = by_smaller_end(half, 3 * k, n)
    nb = np.full((k, 3), -1, np.int64)
    for a in range(n):
        for p in range(start[a], start[a + 1]):
            i = group[p]
            for q in range(p + 1, start[a + 1]):
                g = group[q]
                if max(half[g, 0], half[g, 1]) != max(half[i, 0], half[i, 1]):
                    continue
                if half[g, 0] == half[i, 0]:
                    return nb, min(i, g) // 3, max(i, g) // 3
                nb[i // 3, i % 3] = g // 3
                nb[g // 3, g % 3] = i // 3
    return nb, np.int64(-1), np.int64(-1)


@kernel
def find_edge(pairs, start, group, u, v):
    """The first row of the vertex pairs ``pairs`` (grouped by
    :func:`.segments.by_smaller_end`) joining ``u`` and ``v`` either way; -1 if none."""
    if u == v:
        return -1
    a, b = min(u, v), max(u, v)
    for p in range(start[a], start[a + 1]):
        i = group[p]
        if max(pairs[i, 0], pairs[i, 1]) == b:
            return i
    return -1


@kernel
def label_given(tri, twin, ntri, mesh_of, T, nv):
    """Label the slot of each given triangle ``T[t]`` (input ids) with ``t``,
    every other slot ``OUT``. Returns ``(labels, -1)``, or ``(labels, t)``
    for the first given triangle that is not a triangle of the store."""
    out_edge = np.full(nv, -1, np.int64)     # one half-edge out of each vertex
    for e in range(3 * ntri):
        v = tri[e]
        if 0 <= v < nv and tri[3 * (e // 3)] >= 0:
            out_edge[v] = e
    lab = np.full(tri.shape[0] // 3, OUT, np.int64)
    for t in range(T.shape[0]):
        a = mesh_of[T[t, 0]]
        b = mesh_of[T[t, 1]]
        c = mesh_of[T[t, 2]]
        e0 = out_edge[a]
        e = e0
        found = -1
        while e >= 0:
            if tri[nxt(e)] == b:
                found = e
                break
            e = twin[prv(e)]             # the next half-edge out of a
            if e == e0:
                break
        if found < 0 or tri[prv(found)] != c:
            return lab, np.int64(t)
        lab[found // 3] = t
    return lab, np.int64(-1)


@kernel
def free_inner_edges(tri, twin, cons, ntri, lab, m):
    """Unconstrain the edges whose segment id is past the ``m`` segments to
    keep and that have a given triangle on both sides."""
    for e in range(3 * ntri):
        if cons[e] > m and lab[e // 3] != OUT and lab[twin[e] // 3] != OUT:
            cons[e] = 0


@entry
def existing_mesh_store(px, py, T, nb, segs, order_in, horizontal_in, options):
    """The store of the mesh ``T`` (counter-clockwise triangles, indices checked,
    ``nb`` their neighbours as :func:`triangle_neighbors` gives them)
    over the vertices ``px, py``, keeping the segments ``segs``, as the
    module's docstring says; ``options`` the route's (:func:`.options.plain`:
    divide and conquer, room for refinement). Returns ``(status, info, shift,
    order, store, lab, seg_ends)``: ``status`` one of the ``MESH_*`` codes,
    the coordinates scaled by ``2**shift``, mesh vertex ``i`` is vertex
    ``order[i]``, ``store`` ``(tri, twin, cons, x, y, w, inf, ntri, nv)``,
    ``lab`` the slot labels, ``seg_ends`` (mesh ids) the ends of segment
    ``id - 1`` (the segments to keep, then the other edges; also where two
    of them cross or overlap)."""
    n = px.shape[0]
    info = np.full(2, -1, np.int64)
    no_store = (np.empty(0, np.int32), np.empty(0, np.int32), np.empty(0, np.int32), np.empty(0),
                np.empty(0), np.empty(0), np.int64(0), np.int64(0), np.int64(0))
    no = np.empty(0, np.int64)
    no2 = np.empty((0, 2), np.int64)
    edges, bad = mesh_edges(T, nb, segs, n)
    if bad >= 0:
        info[0] = bad
        return MESH_NOT_EDGE, info, np.int64(0), no, no_store, no, no2
    route = named(options)
    status, info[0], info[1], shift, px, py, order, xi, yi, wi, inf, extra = route_points(
        px, py, order_in, edges.shape[0], np.int64(0), route)
    if status != ROUTE_OK:      # (collinear vertices have no triangles: the caller says so first)
        return MESH_RANGE, info, shift, no, no_store, no, no2
    mesh_of = np.empty(n, np.int64)
    for i in range(n):
        mesh_of[order[i]] = i
    horizontal = horizontal_order(xi, yi, n, horizontal_in, mesh_of)
    counts = np.zeros(2, np.int64)
    status, tri, twin, cons, ntri, dup, _ = build_mesh(xi, yi, (wi, np.bool_(False)), n, inf, DIVIDE,
                                                       horizontal, extra, np.bool_(True), counts)
    if status != OK:
        info[0] = 1
        info[1] = status
        return MESH_INTERNAL, info, shift, order, no_store, no, no2
    for i in range(n):
        if dup[i] >= 0:
            info[0] = max(order[i], order[dup[i]])
            info[1] = min(order[i], order[dup[i]])
            return MESH_REPEATED, info, shift, order, no_store, no, no2
    seg_ends = np.empty_like(edges)
    for s in range(edges.shape[0]):
        seg_ends[s, 0] = mesh_of[edges[s, 0]]
        seg_ends[s, 1] = mesh_of[edges[s, 1]]
    tasks, ntask, _, _, _ = dedup_tasks(seg_ends, n)
    seg_counts = np.zeros(3, np.int64)
    stop = np.zeros(4, np.int64)
    status, store = insert_all_segments((tri, twin, cons, xi, yi, wi, inf, ntri, np.int64(n)), tasks,
                                        ntask, seg_ends, np.bool_(False), np.int64(0), seg_counts, stop)
    if status != ALL_DONE:
        info[0] = stop[0] - 1
        info[1] = stop[1] - 1
        code = MESH_CROSSING if status == STOP_CROSSING else MESH_OVERLAP
        if status != STOP_CROSSING and status != STOP_OVERLAP:
            code = MESH_INTERNAL
            info[0] = 2
            info[1] = status
        return code, info, shift, order, no_store, no, seg_ends
    tri, twin, cons, xi, yi, wi, inf, ntri, nv = store
    lab, missing = label_given(tri, twin, ntri, mesh_of, T, nv)
    if missing >= 0:
        info[0] = missing
        return MESH_MISSING, info, shift, order, no_store, no, no2
    free_inner_edges(tri, twin, cons, ntri, lab, segs.shape[0])
    return MESH_OK, info, shift, order, store, lab, seg_ends


@entry
def refine_existing(store, lab, seg_ends, m, refinement, area_of_label, max_new, room, order, shift,
                    vseg, home):
    """Refine ``store`` (the coordinates scaled by ``2**shift``, mesh vertex
    ``i < n`` output vertex ``order[i]``, later ones in their order) whose slot
    labels are ``lab``, as ``refinement`` (a plain :class:`.options.RefineOptions`)
    asks, with the area bound of each label in ``area_of_label``
    (:func:`.refine.area_bound`), at most ``max_new`` Steiner points and room
    for ``room`` vertices from the start, ``vseg`` what the refinement before
    returned (empty for a store none has touched: :func:`.refine.refine_store`),
    ``home`` the triangles the labels name with their neighbours, each label
    moved to the triangle that holds its triangle's centroid (per-triangle
    bounds; two empty arrays for one bound: :func:`.refine.refine_store`).
    The store's arrays are refined in place (or grown). Returns ``(status,
    counts, (store, vseg), seg_ends, out_slot,
    vertices, triangles, neighbors, constrained, pieces, piece_ids, parents,
    below)``: the refinement's status and counts, what a further refinement
    needs (the store, its segments' ends and the slot of each output
    triangle), and the output arrays: ``piece_ids`` the segment id less one
    of each segment piece, ``parents`` the label each output triangle ended
    with, ``below`` the triangles whose smallest angle is below
    ``refinement``'s bound.

    The ``m`` first segments are those to keep; the others bound the domain
    (their ids are past ``m`` and the outside is on one side). The mesh is
    made constrained Delaunay first: refinement needs it."""
    options = RefineOptions(*refinement)
    tri, twin, cons, ntri = store[0], store[1], store[2], store[7]
    n_base = seg_ends.shape[0]
    free_inner_edges(tri, twin, cons, ntri, lab, m)
    # refinement needs a constrained Delaunay triangulation (its walks and cavities do)
    flips = flip_to_delaunay(tri, twin, cons, store[3], store[4], store[3], np.bool_(False), store[6],
                             ntri)
    n = order.shape[0]
    status, counts, lab, seg_ends, store, vseg = refine_store(store, lab, seg_ends, options,
                                                              area_of_label, max_new, room, vseg, n,
                                                              home)
    tri, twin, cons, xi, yi, wi, inf, ntri, nv = store
    free_inner_edges(tri, twin, cons, ntri, lab, m)
    for v in range(vseg.shape[0]):
        if vseg[v] > n_base:        # on a segment this refinement made: none next time
            vseg[v] = 0
    counts[C_FLIPS] += flips
    T, N, tid, cflag = solid_with_flags(tri, twin, cons, ntri, inf)
    inside = np.zeros(T.shape[0], np.bool_)
    label_of = np.full(T.shape[0], OUT, np.int64)
    slot_of = np.empty(T.shape[0], np.int64)
    for t in range(ntri):
        i = tid[t]
        if i >= 0:
            slot_of[i] = t
            label_of[i] = lab[t]
            inside[i] = lab[t] != OUT
    remap = np.empty(nv, np.int64)
    vertices = np.empty((nv, 2))
    for i in range(nv):
        remap[i] = order[i] if i < n else i
        vertices[remap[i], 0] = xi[i]
        vertices[remap[i], 1] = yi[i]
    triangles, neighbors, constrained, pieces, piece_ids, keep = cdt_arrays(T, N, cflag, inside, remap)
    out_slot = np.full(tri.shape[0] // 3, -1, np.int64)
    parents = np.empty(keep.shape[0], np.int64)
    for i in range(keep.shape[0]):
        out_slot[slot_of[keep[i]]] = i
        parents[i] = label_of[keep[i]]
    below = np.empty(0, np.int64)
    if options.min_angle > 0:
        below = count_below(vertices, triangles, math.sin(math.radians(options.min_angle)) ** 2)
    if shift != 0:
        unscale_rows(vertices, shift)
    return (status, counts, (store, vseg), seg_ends[:n_base], out_slot, vertices, triangles,
            neighbors, constrained, pieces, piece_ids, parents, below)
