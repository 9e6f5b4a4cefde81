"""Half-edge triangle store: flat arrays, no geometry.

Triangle ``t`` owns half-edges ``3t, 3t+1, 3t+2`` (mapbox/delaunator style).
``tri[e]`` is the origin vertex of half-edge ``e``; it runs to ``tri[nxt(e)]``.
``twin[e]`` is the opposite half-edge in the neighbouring triangle.
``cons[e]`` (optional: an empty array when there are no constraints) is the
1-based id of the segment that half-edge ``e`` lies on, or 0; the topological
operations below carry it along with the edges they move. The
triangulation is closed by *ghost triangles* that share one infinite vertex
``inf`` (an index past the last real vertex), so every half-edge has a twin and
the convex hull is the link of ``inf``. A dead triangle (removed by a 3-1 flip)
has ``tri[3t] == DEAD``.

These functions only rewire indices; they know nothing of coordinates.

The kernels that edit a store with coordinates take it bundled, so that they
keep to a few arguments: ``mesh = (tri, twin, cons, x, y, inf)``, unpacked at
the kernel's top (``tri, twin, cons, x, y, inf = mesh``), and, where weights
count, ``weights = (w, weighted)`` (unweighted callers pass ``(x, False)``:
the weights are read only when ``weighted``). numba passes a tuple's members
as it would separate arguments, but unpacking it counts references on each
array: where that runs per point, the bundle holds borrowed views
(:func:`.borrow.unowned`, as segment insertion and the live insert make them)
or the kernel is compiled with ``_nrt=False`` (``insertion.insert_vertex``).
Entries called from Python take the arrays one by one instead, where the
dispatch of a tuple of arrays (0.5-0.9 us) would show.
"""
from __future__ import annotations

import numpy as np

from .arrays import copy_rows
from .borrow import unowned
from .jit import entry, kernel
from .ordering import sort_ids

DEAD = -2
IDX = np.int32  # storage dtype of vertex and half-edge indices


@kernel("int64(int64)")   # (declared: callers pass int32 and int64 half-edges)
def nxt(e):
    """The next half-edge of ``e`` inside its triangle (counter-clockwise)."""
    return e - 2 if e % 3 == 2 else e + 1


@kernel("int64(int64)")
def prv(e):
    """The previous half-edge of ``e`` inside its triangle."""
    return e + 2 if e % 3 == 0 else e - 1


@kernel("void(int32[::1], int64, int64)")
def link(twin, e, f):
    """Make ``e`` and ``f`` twins of each other."""
    twin[e] = f
    twin[f] = e


@kernel("void(int32[::1], int64, int64, int64, int64)")   # (declared: callers pass literals, int32, int64)
def set_triangle(tri, t, a, b, c):
    """Write the vertices of triangle ``t`` as ``(a, b, c)`` (counter-clockwise)."""
    tri[3 * t] = a
    tri[3 * t + 1] = b
    tri[3 * t + 2] = c


@kernel(inline='always')
def is_ghost(tri, t, inf):
    """Whether triangle ``t`` has the infinite vertex."""
    return tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf


@kernel(forceinline=True)
def is_solid(a, b, c, inf):
    """Whether the store's triangle ``a, b, c`` is live and not a ghost. (It
    takes the vertices, not the store: in a loop, a call that takes an array
    costs a reference count each time.)"""
    return a != DEAD and a != inf and b != inf and c != inf


@kernel(inline='always')
def ghost_hull_edge(tri, t, inf):
    """The half-edge ``u -> v`` of ghost triangle ``t`` that avoids ``inf``.

    Its twin is the convex-hull edge ``v -> u`` of a real triangle; the outside of
    the hull lies to the left of ``u -> v``.
    """
    e = 3 * t
    for k in range(3):
        if tri[e + k] != inf and tri[nxt(e + k)] != inf:
            return e + k
    return -1


@kernel
def make_first_triangle(tri, twin, a, b, c, inf):
    """Triangle 0 = (a, b, c) counter-clockwise, closed by three ghosts 1, 2, 3."""
    set_triangle(tri, 0, a, b, c)
    # ghost k+1 sits on real half-edge 0+k (u -> v) as (v, u, inf)
    for k in range(3):
        u = tri[k]
        v = tri[nxt(k)]
        g = k + 1
        set_triangle(tri, g, v, u, inf)
        link(twin, k, 3 * g)
    # ghost (v, u, inf): half-edge u -> inf is 3g+1, inf -> v is 3g+2.
    # u -> inf of the ghost on edge k pairs with inf -> u of the ghost on the
    # previous edge (which ends at u).
    for k in range(3):
        g = k + 1
        gp = (k + 2) % 3 + 1
        link(twin, 3 * g + 1, 3 * gp + 2)
    return np.int64(4)   # (np.int64: a literal would make each callee compile twice)


@kernel(inline='always')
def flip(tri, twin, cons, e):
    """Flip the edge of half-edge ``e`` (Sec. 2.5 edge flip).

    ``e = a -> b`` lies in triangle ``(a, b, p)``, its twin in ``(b, a, d)``. They
    become ``(p, a, d)`` (kept in e's triangle) and ``(p, d, b)`` (in the twin's).
    Returns the half-edge ``a -> d`` of the first; ``d -> b`` of the second is
    ``3 * (twin's triangle) + 1``. Both have ``p`` as their opposite vertex.
    """
    f = twin[e]
    t1 = e // 3
    t2 = f // 3
    a = tri[e]
    b = tri[f]
    p = tri[prv(e)]
    d = tri[prv(f)]
    tw_bp = twin[nxt(e)]
    tw_pa = twin[prv(e)]
    tw_ad = twin[nxt(f)]
    tw_db = twin[prv(f)]
    if cons.shape[0] > 0:
        c_bp = cons[nxt(e)]
        c_pa = cons[prv(e)]
        c_ad = cons[nxt(f)]
        c_db = cons[prv(f)]
        set_triangle(cons, t1, c_pa, c_ad, 0)
        set_triangle(cons, t2, 0, c_db, c_bp)
    set_triangle(tri, t1, p, a, d)
    set_triangle(tri, t2, p, d, b)
    link(twin, 3 * t1, tw_pa)
    link(twin, 3 * t1 + 1, tw_ad)
    link(twin, 3 * t1 + 2, 3 * t2)
    link(twin, 3 * t2 + 1, tw_db)
    link(twin, 3 * t2 + 2, tw_bp)
    return 3 * t1 + 1


@kernel
def split_triangle(tri, twin, cons, t, p, ntri):
    """Split triangle ``t = (a, b, c)`` at new vertex ``p`` into three (1-3 flip).

    ``t`` becomes ``(a, b, p)``; new triangles ``ntri`` and ``ntri+1`` are
    ``(b, c, p)`` and ``(c, a, p)``. ``p`` is in slot 2 of all three, so the
    half-edges opposite ``p`` are ``3t``, ``3 ntri`` and ``3 (ntri+1)``.
    Returns the new triangle count.
    """
    tri, twin, cons = unowned(tri), unowned(twin), unowned(cons)   # (see legalize)
    e = 3 * t
    a = tri[e]
    b = tri[e + 1]
    c = tri[e + 2]
    tw_bc = twin[e + 1]
    tw_ca = twin[e + 2]
    t1 = ntri
    t2 = ntri + 1
    if cons.shape[0] > 0:
        set_triangle(cons, t1, cons[e + 1], 0, 0)
        set_triangle(cons, t2, cons[e + 2], 0, 0)
        cons[e + 1] = 0
        cons[e + 2] = 0
    tri[e + 2] = p
    set_triangle(tri, t1, b, c, p)
    set_triangle(tri, t2, c, a, p)
    link(twin, 3 * t1, tw_bc)
    link(twin, 3 * t2, tw_ca)
    link(twin, e + 1, 3 * t1 + 2)      # b->p  / p->b
    link(twin, 3 * t1 + 1, 3 * t2 + 2)  # c->p  / p->c
    link(twin, 3 * t2 + 1, e + 2)      # a->p  / p->a
    return ntri + 2


@kernel
def split_edge(tri, twin, cons, e, p, ntri):
    """Split the edge of half-edge ``e = a -> b`` at new vertex ``p`` (2-4 flip).

    ``(a, b, c)`` and ``(b, a, d)`` become ``(c, a, p)``, ``(b, c, p)`` (the new
    triangle ``ntri``), ``(d, b, p)`` and ``(a, d, p)`` (``ntri + 1``). Every one
    has ``p`` in slot 2, so the half-edge opposite ``p`` is slot 0. Returns the
    new triangle count.
    """
    tri, twin, cons = unowned(tri), unowned(twin), unowned(cons)   # (see legalize)
    f = twin[e]
    t1 = e // 3
    t2 = f // 3
    a = tri[e]
    b = tri[f]
    c = tri[prv(e)]
    d = tri[prv(f)]
    tw_bc = twin[nxt(e)]
    tw_ca = twin[prv(e)]
    tw_ad = twin[nxt(f)]
    tw_db = twin[prv(f)]
    t3 = ntri
    t4 = ntri + 1
    if cons.shape[0] > 0:
        s_ab = cons[e]  # both halves of a split segment stay on it
        c_bc = cons[nxt(e)]
        c_ca = cons[prv(e)]
        c_ad = cons[nxt(f)]
        c_db = cons[prv(f)]
        set_triangle(cons, t1, c_ca, s_ab, 0)
        set_triangle(cons, t3, c_bc, 0, s_ab)
        set_triangle(cons, t2, c_db, s_ab, 0)
        set_triangle(cons, t4, c_ad, 0, s_ab)
    set_triangle(tri, t1, c, a, p)
    set_triangle(tri, t3, b, c, p)
    set_triangle(tri, t2, d, b, p)
    set_triangle(tri, t4, a, d, p)
    link(twin, 3 * t1, tw_ca)
    link(twin, 3 * t3, tw_bc)
    link(twin, 3 * t2, tw_db)
    link(twin, 3 * t4, tw_ad)
    link(twin, 3 * t1 + 1, 3 * t4 + 2)  # a->p / p->a
    link(twin, 3 * t3 + 1, 3 * t1 + 2)  # c->p / p->c
    link(twin, 3 * t2 + 1, 3 * t3 + 2)  # b->p / p->b
    link(twin, 3 * t4 + 1, 3 * t2 + 2)  # d->p / p->d
    return ntri + 2


@kernel
def remove_degree3(tri, twin, o1, o2, o3):
    """Remove a vertex of degree three (3-1 flip, Sec. 2.8 weighted flips).

    ``o1, o2, o3`` are the three half-edges of the vertex's link (in the three
    triangles around it), in counter-clockwise order around the removed vertex.
    The triangle of ``o1`` becomes the union; the other two are marked dead.
    Returns the half-edge of the new triangle that ``o1`` became.
    """
    t1 = o1 // 3
    a = tri[o1]
    b = tri[o2]
    c = tri[o3]
    w1 = twin[o1]
    w2 = twin[o2]
    w3 = twin[o3]
    tri[3 * (o2 // 3)] = DEAD
    tri[3 * (o3 // 3)] = DEAD
    set_triangle(tri, t1, a, b, c)
    link(twin, 3 * t1, w1)
    link(twin, 3 * t1 + 1, w2)
    link(twin, 3 * t1 + 2, w3)
    return 3 * t1


@entry
def grow_store(tri, twin, cons, x, y, w, inf, nv, at_least):
    """The store with room for about twice the vertices (or ``at_least``, if
    more): coordinates copied up to ``nv``, the infinite vertex moved to the new
    last id, the triangle arrays lengthened (dead room stays -1, ``cons`` 0).
    Returns ``(tri, twin, cons, x, y, w, inf)``."""
    new_inf = max(2 * inf + 16, at_least)
    nx, ny, nw = np.zeros(new_inf + 1), np.zeros(new_inf + 1), np.zeros(new_inf + 1)
    copy_rows(nx, x, nv)
    copy_rows(ny, y, nv)
    copy_rows(nw, w, nv)
    cap = 3 * (2 * new_inf + 2)
    ntri_arr = np.full(cap, -1, IDX)
    ntwin = np.full(cap, -1, IDX)
    ncons = np.zeros(cap, IDX)
    for e in range(tri.shape[0]):
        v = tri[e]
        ntri_arr[e] = new_inf if v == inf else v
        ntwin[e] = twin[e]
    copy_rows(ncons, cons, cons.shape[0])
    return ntri_arr, ntwin, ncons, nx, ny, nw, new_inf


@kernel
def by_first_then_second(first, second, n):
    """The order of items ``0..n-1`` by ``(first, second)`` (whole numbers
    from 0 held as floats): a counting sort by ``first``, then each group by
    ``second`` (:func:`.ordering.sort_ids`) — linear for a triangulation's
    slots, whose groups are as small as the vertices' degrees."""
    top = 0
    for i in range(n):
        top = max(top, int(first[i]))
    start = np.zeros(top + 2, np.int64)
    for i in range(n):
        start[int(first[i]) + 1] += 1
    for v in range(top + 1):
        start[v + 1] += start[v]
    order = np.empty(n, np.int64)
    fill = start[:top + 1].copy()
    for i in range(n):
        v = int(first[i])
        order[fill[v]] = i
        fill[v] += 1
    tmp = np.empty(n, np.int64)
    for v in range(top + 1):
        if start[v + 1] - start[v] > 1:
            sort_ids(order, start[v], start[v + 1], first, second, tmp)
    return order


@kernel
def canonical_slots(tri, twin, cons, ntri):
    """Renumber the live triangles in place in an order that depends on the
    triangulation only, not on how it was built: each starts at its smallest
    vertex, and they are sorted by their first two vertices (a directed edge
    lies in one triangle, so the key is unique). Dead slots are dropped.
    Returns ``(live triangles, old slot of each new slot)``."""
    rot = np.empty(ntri, np.int64)
    first = np.empty(ntri)          # float keys: the sort compiled for coordinates already
    second = np.empty(ntri)
    live = np.empty(ntri, np.int64)
    n = 0
    for t in range(ntri):
        e = 3 * t
        if tri[e] == DEAD:
            continue
        r = 0
        for k in range(1, 3):
            if tri[e + k] < tri[e + r]:
                r = k
        rot[t] = r
        first[n] = tri[e + r]
        second[n] = tri[e + (r + 1) % 3]
        live[n] = t
        n += 1
    order = by_first_then_second(first, second, n)
    old = np.empty(n, np.int64)
    where = np.full(3 * ntri, -1, np.int64)        # old half-edge -> new half-edge
    for i in range(n):
        t = live[order[i]]
        old[i] = t
        for k in range(3):
            where[3 * t + (rot[t] + k) % 3] = 3 * i + k
    t_old = tri[:3 * ntri].copy()
    w_old = twin[:3 * ntri].copy()
    c_old = cons[:3 * ntri].copy()
    for i in range(n):
        t = old[i]
        for k in range(3):
            e = 3 * t + (rot[t] + k) % 3
            tri[3 * i + k] = t_old[e]
            twin[3 * i + k] = where[w_old[e]]
            cons[3 * i + k] = c_old[e]
    for e in range(3 * n, 3 * ntri):
        tri[e] = -1
        twin[e] = -1
        cons[e] = 0
    return np.int64(n), old
