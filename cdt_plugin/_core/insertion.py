"""Incremental insertion (Lawson): locate, split, and flip edges until every edge
is locally Delaunay again (Sec. 2.5; for weighted points the bistellar flips of
Sec. 2.8 including the 3-1 flip that submerges a vertex)."""
from __future__ import annotations

import numpy as np

from .borrow import unowned
from .jit import entry, kernel
from .kernel import edge_is_illegal, lifted_test, orient
from .locate import locate
from .mesh import DEAD, flip, nxt, prv, remove_degree3, split_edge, split_triangle
from .status import INSIDE, LOCATE_FAILED, LOCATION_FAILED, OK, ON_VERTEX, SUBMERGED


@kernel
def legalize(mesh, weights, p, stack, sp, hull_only, submerged, counts):
    """Flip the edges on ``stack`` (each opposite the new vertex ``p``) until they
    are all locally (weighted) Delaunay. ``mesh`` is ``(tri, twin, cons, x, y,
    inf)`` and ``weights`` ``(w, weighted)`` (see :mod:`.mesh`). ``counts[0]`` counts 2-2 flips,
    ``counts[1]`` the vertices submerged by 3-1 flips. With ``hull_only`` only
    edges at the infinite vertex are flipped (building the lexicographic
    triangulation of Sec. 2.1). The stack never outgrows its capacity: each
    flip pops one edge and pushes two, and a vertex gains one edge per flip, so
    ``sp <= 4 + number of vertices``. (A fixed array avoids the reference
    counting that returning a grown array costs in the hot loop.)"""
    tri, twin, cons, x, y, inf = mesh
    w, weighted = weights
    # (borrowed views: in a caller that counts references, the helpers inlined
    # in this loop counted them on every edge popped)
    tri, twin, cons, stack = unowned(tri), unowned(twin), unowned(cons), unowned(stack)
    x, y, w, submerged, counts = unowned(x), unowned(y), unowned(w), unowned(submerged), unowned(counts)
    while sp > 0:
        sp -= 1
        e = stack[sp]
        if tri[3 * (e // 3)] == DEAD or tri[prv(e)] != p:
            continue  # this triangle was rewritten by a 3-1 flip
        a = tri[e]
        b = tri[nxt(e)]
        f = twin[e]
        d = tri[prv(f)]
        if hull_only and a != inf and b != inf:
            continue
        if cons.shape[0] > 0 and cons[e] != 0:
            continue  # a segment is never flipped (Lemma 2.14)
        if not edge_is_illegal(x, y, w, weighted, inf, a, b, p, d):
            continue
        if weighted and a != inf and b != inf:
            # a weighted edge can be illegal across a reflex corner: flip only a
            # convex quadrilateral; a reflex vertex of degree three is submerged
            oa = orient(x, y, p, a, d)
            ob = orient(x, y, p, d, b)
            if oa <= 0 or ob <= 0:
                if oa <= 0:
                    g = twin[prv(e)]          # a -> p, in (a, p, ?)
                    if tri[prv(g)] == d:
                        n = remove_degree3(tri, twin, nxt(e), nxt(g), prv(f))
                        submerged[a] = 1
                        counts[1] += 1
                        stack[sp] = n + 2
                        sp += 1
                else:
                    g = twin[nxt(e)]          # p -> b, in (p, b, ?)
                    if tri[prv(g)] == d:
                        n = remove_degree3(tri, twin, prv(e), nxt(f), prv(g))
                        submerged[b] = 1
                        counts[1] += 1
                        stack[sp] = n + 1
                        sp += 1
                continue
        e1 = flip(tri, twin, cons, e)
        counts[0] += 1
        stack[sp] = e1
        stack[sp + 1] = 3 * (f // 3) + 1
        sp += 2


@kernel
def submerged_at(tri, twin, x, y, w, inf, code, e, q):
    """For weighted input: whether ``q``, located at ``(code, e)``, lies on or
    above the lifted triangulation (Sec. 2.8), so that it is not a vertex of the
    weighted Delaunay triangulation. Points outside the hull never are."""
    tri, twin, x, y, w = unowned(tri), unowned(twin), unowned(x), unowned(y), unowned(w)   # (see legalize)
    t = 3 * (e // 3)
    a = tri[t]
    b = tri[t + 1]
    c = tri[t + 2]
    if a == inf or b == inf or c == inf:
        if code == INSIDE:
            return False
        f = twin[e]  # q is on a hull edge: test the real triangle beside it
        t = 3 * (f // 3)
        a = tri[t]
        b = tri[t + 1]
        c = tri[t + 2]
    return lifted_test(x, y, w, True, a, b, c, q) < 0


@kernel(_nrt=False)   # allocates nothing: unpacking the bundles counts no references
def insert_vertex(mesh, weights, q, last, ntri, hull_only, submerged, counts, stack):
    """Insert vertex ``q``: locate it from triangle ``last``, split, flip
    (``mesh`` and ``weights`` as in :func:`legalize`).

    Returns ``(code, v, ntri, last)``: code ``ON_VERTEX`` with ``v`` the vertex
    ``q`` coincides with (not inserted), ``SUBMERGED`` if ``q`` is submerged (weighted),
    ``LOCATE_FAILED`` if location failed, else the located code (``INSIDE``/``ON_EDGE``)
    with ``v == q``. ``last`` is a live triangle near ``q`` for the next walk.
    """
    tri, twin, cons, x, y, inf = mesh
    w, weighted = weights
    code, e = locate(tri, twin, x, y, inf, q, last, ntri)
    if code < 0:
        return LOCATE_FAILED, -1, ntri, last
    if code == ON_VERTEX:
        return ON_VERTEX, tri[e], ntri, e // 3
    if weighted and submerged_at(tri, twin, x, y, w, inf, code, e, q):
        submerged[q] = 1
        counts[1] += 1
        return SUBMERGED, -1, ntri, e // 3
    t = e // 3
    if code == INSIDE:
        ntri = split_triangle(tri, twin, cons, t, q, ntri)
        stack[0] = 3 * t
        stack[1] = 3 * (ntri - 2)
        stack[2] = 3 * (ntri - 1)
        sp = 3
    else:
        t2 = twin[e] // 3
        ntri = split_edge(tri, twin, cons, e, q, ntri)
        stack[0] = 3 * t
        stack[1] = 3 * t2
        stack[2] = 3 * (ntri - 2)
        stack[3] = 3 * (ntri - 1)
        sp = 4
    legalize(mesh, weights, q, stack, sp, hull_only, submerged, counts)
    last = t
    while tri[3 * last] == DEAD:  # killed by a 3-1 flip: any live triangle will do
        last = (last + ntri - 1) % ntri
    return code, q, ntri, last


@kernel(inline="always")
def insert_vertices(mesh, weights, order, first, ntri, hull_only, dup_of, submerged, counts):
    """Insert ``order[first:]`` one by one (``mesh`` and ``weights`` as in
    :func:`legalize`). Exact duplicates are not inserted: ``dup_of[q]``
    receives the vertex they coincide with. Returns ``(status, ntri)``."""
    return insert_vertices_loop(mesh, weights, order, first, ntri, hull_only, dup_of, submerged,
                                counts, np.empty(order.shape[0] + 8, np.int64))


@kernel(_nrt=False)   # allocates nothing: no reference counting either
def insert_vertices_loop(mesh, weights, order, first, ntri, hull_only, dup_of, submerged, counts,
                         stack):
    """The loop of :func:`insert_vertices`, with its flip stack passed in."""
    last = np.int64(0)
    for k in range(first, order.shape[0]):
        q = order[k]
        code, v, ntri, last = insert_vertex(mesh, weights, q, last, ntri, hull_only, submerged,
                                            counts, stack)
        if code == LOCATE_FAILED:
            return LOCATION_FAILED, ntri
        if code == ON_VERTEX:
            dup_of[q] = v
    return OK, ntri


@entry
def redundant_vertices(tri, twin, x, y, w, inf, ntri):
    """Weighted input, after insertion: repair what the incremental flips left.

    Lawson/Edelsbrunner-Shah flips can leave degenerate leftovers: a vertex on a
    straight stretch of the hull, a reflex vertex lying exactly on the diagonal
    of a non-convex quadrilateral, or (after a 3-1 flip) an illegal edge with a
    convex quadrilateral. The last kind is flipped here (2-2 flip); the first two
    are redundant vertices (their lifted point lies above the lifted plane of the
    surrounding triangle, Sec. 2.8) for the caller to leave out. The
    vertices are ``0..inf - 1``.
    Returns ``(redundant vertex ids, flips done, illegal edges no rule explains)``.
    """
    tri, twin, x, y, w = unowned(tri), unowned(twin), unowned(x), unowned(y), unowned(w)   # (see legalize)
    # (room for every vertex, allocated once: an array reassigned in the loop,
    # as a growing one is, counted references on every edge)
    out = np.empty(inf, np.int64)
    n = 0
    unexplained = 0
    flips = 0
    no_cons = np.empty(0, tri.dtype)
    for e in range(3 * ntri):
        if tri[3 * (e // 3)] == DEAD:
            continue
        f = twin[e]
        a = tri[e]
        b = tri[f]
        p = tri[prv(e)]
        d = tri[prv(f)]
        v = -1
        if b == inf and p != inf and d != inf:
            # ghost edge a -> inf: hull p -> a -> d; a straight there?
            if orient(x, y, p, a, d) == 0:
                g = twin[prv(e)]        # a -> p in the real triangle (a, p, z)
                z = tri[prv(g)]
                if lifted_test(x, y, w, True, d, p, z, a) < 0:
                    v = a
        elif a != inf and b != inf and p != inf and d != inf and e < f:
            if lifted_test(x, y, w, True, a, b, p, d) > 0:
                oa = orient(x, y, p, a, d)
                ob = orient(x, y, p, d, b)
                if oa > 0 and ob > 0:
                    flip(tri, twin, no_cons, e)
                    flips += 1
                elif oa <= 0 and lifted_test(x, y, w, True, d, b, p, a) < 0:
                    v = a
                elif ob <= 0 and lifted_test(x, y, w, True, a, d, p, b) < 0:
                    v = b
                else:
                    unexplained += 1
        if v >= 0:
            out[n] = v
            n += 1
    return np.unique(out[:n]), flips, unexplained
