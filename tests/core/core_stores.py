"""Small stores for the kernel tests, built with the kernels themselves the way
the compiled route builds them (``pipeline.cdt_route``): lexicographic order,
seed triangle first for the incremental constructions, coordinates gathered in
mesh order with room for Steiner points, the infinite vertex last.

Not a test module: the tests in this folder import it (pytest puts the folder
on ``sys.path``)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from cdt_plugin._core.construct import (DIVIDE, build_mesh, gather_coords, horizontal_order,
                                        seed_first, seed_triangle)
from cdt_plugin._core.mesh import IDX
from cdt_plugin._core.ordering import lexicographic_order_compiled
from cdt_plugin._core.segments import insert_segments, make_buffers
from checker import canonical_triangles
from store_check import to_arrays

NO_IDS = np.empty(0, np.int64)


def delaunay_store(points, algorithm=DIVIDE, extra=0, with_cons=True):
    """The Delaunay triangulation of ``points`` (not all collinear) in a fresh
    store by construction ``algorithm``, with room for ``extra`` more vertices.
    Returns a namespace: the store (``tri twin cons ntri inf``), the mesh
    coordinates ``x y w``, ``order`` (mesh vertex ``i`` is point ``order[i]``),
    ``mesh_of`` (its inverse), ``dup`` (per mesh vertex, -1 or the vertex it
    repeats), ``nv`` (vertices in use), ``status`` and ``counts``."""
    P = np.asarray(points, np.float64).reshape(-1, 2)
    px, py = P[:, 0].copy(), P[:, 1].copy()
    n = len(P)
    order = lexicographic_order_compiled(px, py)
    k1, k2 = seed_triangle(px, py, order)
    assert k2 >= 0, "collinear input: no store"
    if algorithm != DIVIDE:
        order = seed_first(order, k1, k2)
    x, y, w = gather_coords(px, py, np.zeros(n), order, extra)
    inf = n + extra
    mesh_of = np.empty(n, np.int64)
    mesh_of[order] = np.arange(n)
    horizontal = horizontal_order(x, y, n, NO_IDS, mesh_of) if algorithm == DIVIDE else NO_IDS
    counts = np.zeros(2, np.int64)
    status, tri, twin, cons, ntri, dup, sub = build_mesh(x, y, (w, False), n, inf, algorithm,
                                                         horizontal, extra, with_cons, counts)
    return SimpleNamespace(tri=tri, twin=twin, cons=cons, ntri=int(ntri), inf=int(inf), x=x, y=y,
                           w=w, order=order, mesh_of=mesh_of, dup=dup, sub=sub, nv=n,
                           status=int(status), counts=counts, points=P)


def mesh(s):
    """The ``mesh`` bundle of store ``s`` that the kernels take (see ``_core.mesh``)."""
    return (s.tri, s.twin, s.cons, s.x, s.y, s.inf)


def add_segments(s, segments, split=False, max_steiner=100):
    """Insert ``segments`` (pairs of *input* point ids; segment ``k`` gets id
    ``k + 1``) into store ``s`` with ``segments.insert_segments``, walk buffers
    made large enough at once. Updates ``s.ntri``/``s.nv``; returns
    ``(status, info, counts)`` (counts: T-junction splits, merged overlaps,
    Steiner points)."""
    S = np.asarray(segments, np.int64).reshape(-1, 2)
    m = len(S)
    seg_ends = s.mesh_of[S]
    tasks = np.zeros((m + 64, 3), np.int64)
    for k in range(m):                  # a LIFO stack: segment 1 on top
        r = m - 1 - k
        tasks[k] = seg_ends[r, 0], seg_ends[r, 1], r + 1
    counts = np.zeros(3, np.int64)
    info = np.zeros(4, np.int64)
    stack = np.empty(s.inf + 16, np.int64)
    buf = make_buffers(2 * s.tri.shape[0] // 3 + 8)
    status, ntri, nv, ntask = insert_segments(mesh(s), s.ntri, s.nv, tasks, m, seg_ends, split,
                                              max_steiner, (counts, info), (stack, buf))
    s.ntri, s.nv, s.ntask = int(ntri), int(nv), int(ntask)
    return int(status), info, counts


def empty_store(cap):
    """Arrays for a store of ``cap`` triangles (what ``construct.build`` allocates)."""
    return (np.full(3 * cap, -1, IDX), np.full(3 * cap, -1, IDX), np.zeros(3 * cap, IDX))


def store_triangles(s):
    """The solid triangles of store ``s`` as coordinate triples (compares
    triangulations whatever the vertex numbering)."""
    return canonical_triangles(*to_arrays(s.tri, s.ntri, s.inf, s.x, s.y))
