"""Building the (weighted) Delaunay triangulation of the mesh vertices: the first
step of every route (Sec. 2.1, 2.5, 2.8).

Mesh vertex ``i`` is input point ``order[i]`` (coordinates gathered in that
order: vertex ids that follow the insertion order keep coordinate reads
cache-friendly), Steiner room follows, then the infinite vertex ``inf``.
Three constructions give the same triangles (symbolic perturbation, Sec. 2.9):
divide and conquer, incremental insertion, and the lexicographic triangulation
plus the flip algorithm.
"""
from __future__ import annotations

import numpy as np

from .divide import build_divide_sorted
from .flips import flip_to_delaunay
from .insertion import insert_vertices
from .jit import F8, I8, I32, I64, Tuple, b1, entry, i8, kernel
from .kernel import orient
from .locate import same_point
from .mesh import IDX, make_first_triangle
from .ordering import lexicographic_order_compiled
from .status import OK

DIVIDE = 0          # the construction codes the compiled routes take
INCREMENTAL = 1
FLIP = 2
ALGORITHM_CODES = {"divide": DIVIDE, "incremental": INCREMENTAL, "flip": FLIP}


@entry
def seed_triangle(x, y, order):
    """Positions in ``order`` of the 2nd and 3rd vertex of a first, non-degenerate
    triangle (the 1st is ``order[0]``); -1 where none exists (all points equal,
    or all collinear)."""
    n = order.shape[0]
    p0 = order[0]
    k1 = -1
    for k in range(1, n):
        if not same_point(x, y, p0, order[k]):
            k1 = k
            break
    if k1 < 0:
        return -1, -1
    p1 = order[k1]
    for k in range(k1 + 1, n):
        if orient(x, y, p0, p1, order[k]) != 0:
            return k1, k
    return k1, -1


@entry
def seed_first(order, k1, k2):
    """``order`` with the seed triangle's vertices (positions 0, k1, k2) in front."""
    out = np.empty(order.shape[0], np.int64)
    out[0] = order[0]
    out[1] = order[k1]
    out[2] = order[k2]
    j = 3
    for k in range(1, order.shape[0]):
        if k != k1 and k != k2:
            out[j] = order[k]
            j += 1
    return out


@entry(inline="always")
def build(x, y, w, weighted, inf, order, hull_only, dup_of, submerged, counts, extra, with_cons):
    """Triangulate ``order[0:3]`` (a non-degenerate triangle), then insert the rest.
    ``extra`` reserves room for that many more vertices (Steiner points);
    ``with_cons`` allocates the per-half-edge segment ids.
    Returns ``(status, tri, twin, cons, ntri)``."""
    n = order.shape[0]
    cap = max(4, 2 * (n + extra) + 2)
    tri = np.full(3 * cap, -1, IDX)
    twin = np.full(3 * cap, -1, IDX)
    cons = np.zeros(3 * cap if with_cons else 0, IDX)
    a = order[0]
    b = order[1]
    c = order[2]
    if orient(x, y, a, b, c) < 0:
        b, c = c, b
    ntri = make_first_triangle(tri, twin, a, b, c, inf)
    status, ntri = insert_vertices((tri, twin, cons, x, y, inf), (w, weighted), order, 3, ntri,
                                   hull_only, dup_of, submerged, counts)
    return status, tri, twin, cons, ntri


@entry
def gather_coords(x, y, w, order, extra):
    """The coordinates of the points ``order``, then ``extra + 1`` zeros (room
    for Steiner points and the infinite vertex)."""
    n = order.shape[0] + extra + 1
    xi, yi, wi = np.zeros(n), np.zeros(n), np.zeros(n)
    for i in range(order.shape[0]):
        xi[i] = x[order[i]]
        yi[i] = y[order[i]]
        wi[i] = w[order[i]]
    return xi, yi, wi


@kernel
def horizontal_order(xi, yi, m, horizontal_in, mesh_of):
    """The (y, -x) order of mesh vertices ``0..m-1`` that divide and conquer's
    horizontal cuts use: sorted here, or ``horizontal_in`` (input ids, sorted by
    the caller's faster sort) mapped to mesh ids."""
    if horizontal_in.shape[0] == 0:
        return lexicographic_order_compiled(yi[:m], -xi[:m])
    out = np.empty(m, np.int64)
    for k in range(m):
        out[k] = mesh_of[horizontal_in[k]]
    return out


@kernel
def store_room(m, extra):
    """The triangles the store of ``m`` vertices and room for ``extra`` more has room for."""
    return max(4, 2 * (m + extra) + 2)


@kernel(apart=True, ahead=(F8, F8, Tuple((F8, b1)), i8, i8, i8, I64, i8, b1, I64),
        returns=Tuple((i8, I32, I32, I32, i8, I64, I8)))
def build_mesh(xi, yi, weights, m, inf, algorithm, horizontal, extra, with_cons, counts):
    """The Delaunay triangulation of mesh vertices ``0..m-1`` (seed triangle
    first for the incremental routes, lexicographic order for divide and
    conquer) by ``algorithm``; ``weights`` is ``(wi, weighted)``. Returns ``(status, tri, twin, cons, ntri,
    dup, sub)``: ``dup[i]`` the mesh vertex that vertex ``i`` repeats (-1),
    ``sub[i]`` whether it is submerged (weighted)."""
    dup = np.full(m, -1, np.int64)
    sub = np.zeros(m, np.int8)
    wi, weighted = weights
    cap = store_room(m, extra)
    if algorithm == DIVIDE:
        tri, twin, cons, ntri = build_divide_sorted(xi, yi, wi, m, inf, dup, cap, with_cons, horizontal)
        status = OK
    else:
        status, tri, twin, cons, ntri = build(xi, yi, wi, weighted, inf, np.arange(m),
                                              algorithm == FLIP, dup, sub, counts, extra, with_cons)
    if status == OK and algorithm == FLIP:
        counts[0] = flip_to_delaunay(tri, twin, cons, xi, yi, wi, np.bool_(False), inf, ntri)
    return status, tri, twin, cons, ntri, dup, sub


@entry
def to_input_ids(order, dup_int, sub_int, dup_of, submerged):
    """Record the duplicates and submerged points found among the mesh
    vertices ``0..m-1`` (point ``order[i]`` is vertex ``i``) by input id."""
    for i in range(order.shape[0]):
        if dup_int[i] >= 0:
            dup_of[order[i]] = order[dup_int[i]]
        if sub_int[i] > 0:
            submerged[order[i]] = 1
