"""Edits of a live constrained Delaunay triangulation (:class:`cdt_plugin.DynamicCDT`).

The store is the engine's half-edge store (:mod:`.mesh`), ``store = (tri,
twin, cons, x, y, w, inf, ntri, nv)``: vertex slots ``0..nv-1`` in use, slots up
to ``inf`` free, the infinite vertex at ``inf``. Every edit runs the engine's own
kernels: the Delaunay construction (``delaunay``'s divide and conquer), Lawson
insertion (:func:`.insertion.insert_vertex`) and segment insertion
(:func:`.pipeline.insert_all_segments`, which splits at vertices on a segment
and, when asked, at crossings).
"""
from __future__ import annotations

import numpy as np

from .borrow import unowned
from .insertion import insert_vertex
from .jit import entry, kernel
from .mesh import DEAD
from .output import solid_triangles
from .pipeline import insert_all_segments
from .regions import segment_depths
from .status import LOCATE_FAILED, OK, ON_VERTEX


@kernel(forceinline=True)
def cell_of(frame, qx, qy):
    """The cell of ``(qx, qy)`` in the start grid ``frame = (x0, y0, 1 / cell
    size, cells per side)`` (points beyond it: the nearest border cell)."""
    g = frame[3]
    fx = min(max((qx - frame[0]) * frame[2], 0.0), g - 1.0)
    fy = min(max((qy - frame[1]) * frame[2], 0.0), g - 1.0)
    return int(fy) * int(g) + int(fx)


@entry
def start_grid(tri, x, y, inf, ntri, nv, g):
    """A ``g`` by ``g`` grid over the vertices' bounding box holding, for each
    cell, a triangle with a corner in it (-1: none): a point's walk starts
    there and takes a few steps (jump and walk), wherever the previous point
    was. Returns ``(grid, frame)`` (see :func:`cell_of`)."""
    x0 = x[0]
    x1 = x[0]
    y0 = y[0]
    y1 = y[0]
    for v in range(nv):
        x0 = min(x0, x[v])
        x1 = max(x1, x[v])
        y0 = min(y0, y[v])
        y1 = max(y1, y[v])
    span = max(x1 - x0, y1 - y0)
    frame = np.array([x0, y0, g / span if span > 0 else 0.0, float(g)])
    grid = np.full(g * g, -1, np.int64)
    for t in range(ntri):
        v = tri[3 * t]
        if v == DEAD:
            continue
        if v == inf:
            v = tri[3 * t + 1]
        grid[cell_of(frame, x[v], y[v])] = t
    return grid, frame


@entry
def insert_points(tri, twin, cons, x, y, w, inf, meta, px, py, stack, grid, frame):
    """Insert the points one by one (Lawson: locate, split, flip; segments are
    never flipped), each walk starting at its cell of the start grid (else at
    the previous point's triangle). ``meta = (ntri, nv, last)`` is updated in
    place; the caller made room for every point (``nv + len(px) <= inf``) and
    keeps the flip ``stack`` (at least ``inf + 16``). Returns ``(status,
    slots)``: ``slots[k]`` is the slot of point ``k`` (an existing vertex's for
    a point that repeats one).

    (The store's arrays come one by one, not as a ``mesh`` tuple: this entry is
    called from Python once per point in a loop of single inserts, and numba's
    dispatch of a tuple of arrays costs 0.5-0.9 us a call.)"""
    # (borrowed views: unpacking the bundles in the kernels below counts no references)
    mesh = (unowned(tri), unowned(twin), unowned(cons), unowned(x), unowned(y), inf)
    unweighted = (unowned(w), np.bool_(False))
    ntri = meta[0]
    nv = meta[1]
    last = meta[2]
    m = px.shape[0]
    slots = np.empty(m, np.int64)
    submerged = np.zeros(1, np.int8)     # (unweighted: never written)
    counts = np.zeros(2, np.int64)
    status = np.int64(OK)
    for k in range(m):
        x[nv] = px[k]
        y[nv] = py[k]
        c = cell_of(frame, px[k], py[k])
        start = grid[c]
        if start < 0 or start >= ntri or tri[3 * start] == DEAD:
            start = last          # (a grid made for an earlier store)
        code, v, ntri, last = insert_vertex(mesh, unweighted, nv, start, ntri, np.bool_(False),
                                            submerged, counts, stack)
        if code == LOCATE_FAILED:
            status = np.int64(code)
            break
        grid[c] = last
        if code == ON_VERTEX:
            slots[k] = v
        else:
            slots[k] = nv
            nv += 1
    meta[0] = ntri
    meta[1] = nv
    meta[2] = last
    return status, slots


@entry
def insert_segments(store, tasks, seg_ends, split, limit):
    """Insert the segment tasks (rows: slot a, slot b, segment id from 1;
    ``seg_ends`` the end slots of every segment id, for crossings), with
    ``split`` at most ``limit`` crossing points (STOP_LIMIT at the next one).
    Returns ``(status, info, store)`` with the status of
    :func:`.pipeline.insert_all_segments` (``ALL_DONE`` or why it stopped; on
    a stop the store is left half edited: the caller keeps a copy)."""
    info = np.zeros(4, np.int64)
    seg_counts = np.zeros(3, np.int64)
    status, out = insert_all_segments(store, tasks, np.int64(tasks.shape[0]), seg_ends, split, limit,
                                      seg_counts, info)
    return np.int64(status), info, out


@entry
def snapshot(store, even_odd):
    """The real triangles (slots), their neighbours, the segment id on the edge
    opposite each corner (0: none), and for ``even_odd`` which triangles lie at
    odd depth (an odd number of segments crossed from outside the hull)."""
    tri, twin, cons, x, y, w, inf, ntri, nv = store
    triangles, neighbors, tid = solid_triangles(tri, twin, ntri, inf)
    k = triangles.shape[0]
    sid = np.zeros((k, 3), np.int64)
    keep = np.ones(k, np.bool_)
    for t in range(ntri):
        i = tid[t]
        if i >= 0:
            for j in range(3):
                sid[i, j] = cons[3 * t + (j + 1) % 3]
    if even_odd:
        nseg = 0
        for e in range(3 * ntri):
            nseg = max(nseg, np.int64(cons[e]))
        depth, _, _ = segment_depths(tri, twin, cons, ntri, inf, np.full(nseg + 1, 1, np.int64),
                                     np.zeros(nseg + 2, np.int64), np.empty(0, np.int64),
                                     np.empty(0, np.int64))
        for t in range(ntri):
            i = tid[t]
            if i >= 0:
                keep[i] = depth[t] % 2 == 1
    return triangles, neighbors, sid, keep


