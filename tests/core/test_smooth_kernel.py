"""The smoothing kernels (``cdt_plugin._core.smooth``) on their half-edge store: the
store they make from a result's arrays, the roles of the vertices, and the store
after sweeps and flips (twins paired, boundary edges paired with their ghosts,
labels carried, every triangle counter-clockwise, exactly)."""
from __future__ import annotations

import math

import numpy as np

import cdt_plugin
from cdt_plugin._core import smooth as K
from cdt_plugin.smoothing import _edge_codes
from checker import orient2d_exact


def store_of(tri):
    T = np.ascontiguousarray(tri.triangles)
    N = np.ascontiguousarray(tri.neighbors)
    n = len(tri.vertices)
    full, twin, cons = K.smoothing_store(T, N, _edge_codes(tri, T, N), n)
    return T, full, twin, cons


def assert_store_sound(full, twin, cons, k, x, y, n):
    """Every real half-edge has a twin running the other way with the same
    label; a boundary edge's twin is its ghost's; every real triangle is
    counter-clockwise (exact)."""
    real = np.arange(3 * k)
    nxt = np.where(real % 3 == 2, real - 2, real + 1)
    assert (twin[real] >= 0).all()
    assert (twin[twin[real]] == real).all()
    assert (full[twin[real]] == full[nxt]).all() and (full[np.where(twin[real] % 3 == 2, twin[real] - 2, twin[real] + 1)] == full[real]).all()
    assert (cons[twin[real]] == cons[real]).all()
    ghost = twin[real] >= 3 * k
    assert (cons[real[ghost]] >= K.BOUNDARY_EDGE).all()
    assert (full[3 * k:].reshape(-1, 3)[:, 2] == n).all()
    P = np.column_stack([x, y])
    for t in full[:3 * k].reshape(-1, 3):
        assert orient2d_exact(P[t[0]], P[t[1]], P[t[2]]) > 0


def test_sweeps_and_flips_keep_the_store_sound():
    tri = cdt_plugin.triangulate([[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2]],
                                 [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
                                 holes=[[1.5, 1.5]], min_angle=30, max_area=0.01)
    T, full, twin, cons = store_of(tri)
    k, n = len(T), len(tri.vertices)
    x, y = tri.vertices[:, 0].copy(), tri.vertices[:, 1].copy()
    steiner = np.zeros(n, bool)
    steiner[tri.steiner] = True
    real = full[:3 * k]
    role, chain, ends = K.vertex_roles(real, twin, cons, n, steiner, True)
    assert_store_sound(full, twin, cons, k, x, y, n)
    h = K.mean_edge_lengths(real, twin, x, y)
    active, went = role != K.FIXED, np.zeros(n, bool)
    total = 0
    for sweep, method in enumerate((K.ODT, K.LLOYD, K.ODT, K.LLOYD)):
        moved = K.smooth_sweep(real, x, y, h, role, chain, ends, method, math.inf, active, went)
        assert moved == went.sum() > 0
        if sweep == 0:
            went[:] = True
        flips = K.restore_delaunay(full, twin, cons, x, y, n, k, went, active)
        assert flips >= 0
        total += flips
        assert_store_sound(full, twin, cons, k, x, y, n)
    assert total > 0         # (the flips ran, across the boundary's ghosts too)
    T2, N2, C2 = K.smoothed_arrays(real, twin, cons)
    assert (N2 >= 0).sum() == (tri.neighbors >= 0).sum() and C2.sum() == tri.constrained.sum()


def test_vertex_roles_of_a_refined_square():
    """On a refined square with a crossing of two diagonals: the Steiner points
    inside are free, those on a side slide between the side's corners, those on
    a diagonal slide between its end and the crossing, the crossing stays."""
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]],
                                 [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [1, 3]],
                                 intersections="split", min_angle=25, max_area=0.02)
    T, full, twin, cons = store_of(tri)
    n = len(tri.vertices)
    steiner = np.zeros(n, bool)
    steiner[tri.steiner] = True
    role, chain, ends = K.vertex_roles(full[:3 * len(T)], twin, cons, n, steiner, True)
    V = tri.vertices
    crossing = int(np.flatnonzero((V == [1.0, 1.0]).all(axis=1))[0])
    assert role[crossing] == K.FIXED and (role[:4] == K.FIXED).all()
    on_pieces = np.unique(tri.segments)
    slides = np.flatnonzero(role == K.SLIDES)
    assert set(slides.tolist()) == set(np.intersect1d(on_pieces, tri.steiner).tolist()) - {crossing}
    assert set(np.flatnonzero(role == K.FREE).tolist()) == set(tri.steiner.tolist()) - set(on_pieces.tolist())
    for v in slides:
        P, Q = V[ends[v]]
        on_side = V[v, 0] in (0, 2) or V[v, 1] in (0, 2)
        if on_side:          # a side of the square: its two corners
            assert set(ends[v].tolist()) <= {0, 1, 2, 3}
        else:                # a diagonal: a corner and the crossing
            assert crossing in ends[v].tolist()
        # the vertex lies on the line of its ends, between them
        d = Q - P
        t = np.dot(V[v] - P, d) / np.dot(d, d)
        assert 0 < t < 1 and abs(d[0] * (V[v, 1] - P[1]) - d[1] * (V[v, 0] - P[0])) < 1e-12
    role, _, _ = K.vertex_roles(full[:3 * len(T)], twin, cons, n, steiner, False)
    assert not (role == K.SLIDES).any()
