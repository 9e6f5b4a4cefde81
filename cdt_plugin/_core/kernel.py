"""Geometric tests on mesh vertices: exact predicates plus the infinite vertex
and the symbolic weight perturbation of Sec. 2.9.

Vertex ``inf`` is the infinite vertex of the ghost triangles. A ghost triangle
``(u, v, inf)`` stands for the open half-plane left of ``u -> v`` (outside the
hull); its "circumdisk" is that half-plane, which is what the lifted
orientation test becomes when one lifted vertex goes to infinity.

Ties in the in-circle (lifted orientation) test are broken by giving every
vertex an infinitesimal weight ``eps^rank``, rank being the vertex's position
in lexicographic (x, then y) order (Sec. 2.9, Prop. 2.12): the result is the
unique weighted Delaunay triangulation of the perturbed points, which is a
Delaunay triangulation of the real ones, whatever the input order.
"""
from __future__ import annotations

import numpy as np

from .jit import kernel
from .predicates import incircle, incircle_weighted, orient2d


@kernel(inline='always')
def lex_less(x, y, i, j):
    """Whether vertex ``i`` precedes vertex ``j`` in lexicographic order."""
    return x[i] < x[j] or (x[i] == x[j] and y[i] < y[j])


@kernel("float64(float64[::1], float64[::1], int64, int64, int64)", forceinline=True)
def orient(x, y, a, b, c):
    """Exact orientation of real vertices ``a, b, c`` (> 0 counter-clockwise)."""
    return orient2d(x[a], y[a], x[b], y[b], x[c], y[c])


@kernel
def perturbed_incircle_sign(x, y, a, b, c, d):
    """Sign of the lifted test of ``d`` against ``(a, b, c)`` when the exact value
    is zero, under the symbolic weights ``eps^rank`` (Sec. 2.9).

    The lifted determinant is linear in each lifted height; lowering vertex ``i``
    by ``eps^rank(i)`` changes it by ``eps^rank(i)`` times the cofactor below, so
    the lexicographically smallest vertex with a non-zero cofactor decides.
    """
    used0 = False
    used1 = False
    used2 = False
    used3 = False
    for _ in range(4):
        # pick the lexicographically smallest unused vertex
        k = -1
        best = -1
        if not used0:
            k = 0
            best = a
        if not used1 and (k < 0 or lex_less(x, y, b, best)):
            k = 1
            best = b
        if not used2 and (k < 0 or lex_less(x, y, c, best)):
            k = 2
            best = c
        if not used3 and (k < 0 or lex_less(x, y, d, best)):
            k = 3
            best = d
        if k == 0:
            used0 = True
            s = -orient(x, y, b, c, d)
        elif k == 1:
            used1 = True
            s = orient(x, y, a, c, d)
        elif k == 2:
            used2 = True
            s = -orient(x, y, a, b, d)
        else:
            used3 = True
            s = orient(x, y, a, b, c)
        if s > 0:
            return 1
        if s < 0:
            return -1
    return 0


@kernel(inline='always')
def lifted_test(x, y, w, weighted, a, b, c, d):
    """Exact sign of the (weighted) in-circle test, > 0: ``d`` lies strictly in
    the circumdisk (below the lifted plane) of counter-clockwise ``(a, b, c)``.
    Never returns 0 on distinct vertices: ties are perturbed (Sec. 2.9)."""
    if weighted:
        r = incircle_weighted(x[a], y[a], w[a], x[b], y[b], w[b],
                              x[c], y[c], w[c], x[d], y[d], w[d])
    else:
        r = incircle(x[a], y[a], x[b], y[b], x[c], y[c], x[d], y[d])
    if r > 0:
        return 1
    if r < 0:
        return -1
    return perturbed_incircle_sign(x, y, np.int64(a), np.int64(b), np.int64(c), np.int64(d))


@kernel(inline='always')
def edge_is_illegal(x, y, w, weighted, inf, a, b, p, d):
    """Whether edge ``a-b`` of triangle ``(a, b, p)``, opposite ``d`` across it, is
    not locally (weighted) Delaunay (Def. 2.4), with ghost triangles handled.

    A ghost's circumdisk is the open outer half-plane of its hull edge, so a hull
    edge is never illegal and an edge to ``inf`` is illegal when the hull is not
    convex there.
    """
    if d == inf:
        return False
    if a == inf:  # (inf, b, p): hull edge b -> p, outside on its left
        return orient(x, y, b, p, d) > 0
    if b == inf:  # (a, inf, p): hull edge p -> a
        return orient(x, y, p, a, d) > 0
    if p == inf:  # (a, b, inf): d is on the inner side of a -> b
        return orient(x, y, a, b, d) > 0
    return lifted_test(x, y, w, weighted, a, b, p, d) > 0
