"""Shared test helpers: run the exact checker on an engine result."""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from checker import check_collinear_edges, check_triangulation, orient2d_exact


def lifted_below_or_on(a, b, c, d, wa, wb, wc, wd) -> bool:
    """Exact: lifted d lies on or above the plane of lifted (a, b, c), a b c CCW.
    (The determinant of the lifted points, with Fractions.)"""
    rows = []
    for p, w in ((a, wa), (b, wb), (c, wc)):
        px, py = Fraction(p[0]) - Fraction(d[0]), Fraction(p[1]) - Fraction(d[1])
        rows.append((px, py, px * px + py * py - (Fraction(w) - Fraction(wd))))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    return det <= 0


def verify(points, tri, weights=None, *, exact_submerged=True):
    """Verify ``tri`` (an engine result for ``points``) from scratch, exactly.

    Checks the vertex map (every input point accounted for), the neighbour
    arrays, and runs the independent checker: simplicial complex tiling the hull,
    every edge locally (weighted) Delaunay; for weighted input, every submerged
    point lies on or above the lifted triangulation.
    """
    pts = np.asarray(points, dtype=float)
    vm = tri.vertex_map
    assert vm.shape == (len(pts),)
    kept = vm >= 0
    assert np.array_equal(tri.vertices[vm[kept]], pts[kept]), "vertex_map points at other coordinates"
    if weights is None:
        assert kept.all(), "an unweighted input point was lost"
    assert len(np.unique(vm[kept])) == len(tri.vertices), "an output vertex has no input point"
    if len(tri.triangles) == 0:
        rep = check_collinear_edges(tri.vertices, tri.edges)
        assert rep.ok, str(rep)
        return rep
    check_neighbors(tri)
    rep = check_triangulation(tri.vertices, tri.triangles, weights=tri.weights)
    assert rep.ok, str(rep)
    if weights is not None and exact_submerged:
        w = np.asarray(weights, dtype=float)
        for i in np.flatnonzero(~kept):
            assert submerged_exactly(tri, pts[i], w[i]), f"point {i} {pts[i]} is not submerged"
    return rep


def submerged_exactly(tri, p, wp) -> bool:
    """Exact: point p with weight wp lies on or above the lifted triangulation."""
    V, T = tri.vertices, tri.triangles
    for a, b, c in T:
        if (orient2d_exact(V[a], V[b], p) >= 0 and orient2d_exact(V[b], V[c], p) >= 0
                and orient2d_exact(V[c], V[a], p) >= 0):
            return lifted_below_or_on(V[a], V[b], V[c], p, tri.weights[a], tri.weights[b],
                                      tri.weights[c], wp)
    return False  # outside the hull: every such point must be a vertex


def check_neighbors(tri):
    """neighbors[t, j] is the triangle across the edge opposite vertex j."""
    T, N = tri.triangles, tri.neighbors
    assert N.shape == T.shape
    for t in range(len(T)):
        for j in range(3):
            m = N[t, j]
            if m < 0:
                continue
            u, v = T[t, (j + 1) % 3], T[t, (j + 2) % 3]
            assert {u, v} <= set(T[m].tolist()), f"neighbor {m} of triangle {t} lacks edge {u}-{v}"
            assert t in N[m], f"neighbors not symmetric between {t} and {m}"


def domain_segments(tri):
    """The segment pieces of ``tri`` that are edges of its triangles (dangling
    pieces outside the domain are not)."""
    T = tri.triangles
    edges = {frozenset(e) for t in T.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    return np.array([p for p in tri.segments.tolist() if frozenset(p) in edges], np.int64).reshape(-1, 2)


def longest_over_field(V, T, field):
    """Each triangle's longest edge over the size field at its centroid (``field``
    a number or a callable ``f(x, y)``): at most 1.5 where a mesh meets ``size=``."""
    P = np.asarray(V)[np.asarray(T)]
    longest = np.linalg.norm(P - np.roll(P, -1, axis=1), axis=2).max(axis=1)
    c = P.mean(axis=1)
    target = np.full(len(P), float(field)) if not callable(field) else field(c[:, 0], c[:, 1])
    return longest / target
