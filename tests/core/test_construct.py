"""``_core.construct`` (and the divide-and-conquer kernel behind it): the three
constructions give one and the same Delaunay triangulation (symbolic
perturbation, Sec. 2.9), duplicates are marked, degenerate seeds are refused."""
from __future__ import annotations

import numpy as np
import pytest

from cdt_plugin._core.construct import (DIVIDE, FLIP, INCREMENTAL, build, gather_coords,
                                        seed_first, seed_triangle)
from cdt_plugin._core.divide import build_divide_sorted
from cdt_plugin._core.ordering import lexicographic_order_compiled
from checker import orient2d_exact
from core_stores import delaunay_store, store_triangles
from store_check import check_store

ALGORITHMS = {"divide": DIVIDE, "incremental": INCREMENTAL, "flip": FLIP}


def circle12():
    """12 points exactly on the circle of radius 5 (Pythagorean triples) and its centre."""
    pts = [(5, 0), (-5, 0), (0, 5), (0, -5)]
    pts += [(sx * a, sy * b) for a, b in ((3, 4), (4, 3)) for sx in (1, -1) for sy in (1, -1)]
    return np.array(pts + [(0, 0)], float)


INPUTS = {
    "random": np.random.default_rng(2024).random((40, 2)),
    "grid": np.array([(i, j) for i in range(6) for j in range(5)], float),
    "cocircular": circle12(),
    "cocircular_no_centre": circle12()[:-1],
    "offset": np.random.default_rng(9).random((25, 2)) + 1e7,
}


@pytest.mark.parametrize("name", sorted(INPUTS))
def test_three_constructions_agree(name):
    P = INPUTS[name]
    got = {}
    for alg, code in ALGORITHMS.items():
        s = delaunay_store(P, algorithm=code)
        assert s.status == 0
        c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
        assert c["solid"] + c["ghosts"] == s.ntri and c["dead"] == 0
        assert len(c["vertices"]) == len(P)
        got[alg] = store_triangles(s)
    assert got["divide"] == got["incremental"] == got["flip"]
    # Euler on the plane: 2n - h - 2 triangles (h hull vertices incl. collinear ones)
    assert len(got["divide"]) == 2 * len(P) - c["ghosts"] - 2


def test_flip_route_counts_flips():
    s = delaunay_store(INPUTS["random"], algorithm=FLIP)
    assert s.counts[0] > 0                            # the lexicographic triangulation is not Delaunay
    s = delaunay_store(INPUTS["random"], algorithm=INCREMENTAL)
    assert s.counts[0] > 0


def test_cocircular_ties_broken_the_same_whatever_the_order():
    P = INPUTS["cocircular"]
    want = store_triangles(delaunay_store(P))
    for seed in (1, 2, 3):
        Q = P[np.random.default_rng(seed).permutation(len(P))]
        for code in ALGORITHMS.values():
            assert store_triangles(delaunay_store(Q, algorithm=code)) == want


@pytest.mark.parametrize("alg", sorted(ALGORITHMS))
def test_duplicates_marked_not_inserted(alg):
    base = np.array([(0, 0), (4, 0), (4, 3), (0, 3), (2, 1), (1, 2)], float)
    P = np.concatenate([base, base[[1, 4, 4, 0]]])      # input 6..9 repeat 1, 4, 4, 0
    s = delaunay_store(P, algorithm=ALGORITHMS[alg])
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    dups = np.flatnonzero(s.dup >= 0)
    assert len(dups) == 4
    used = set(c["vertices"])
    for v in dups:
        r = s.dup[v]
        assert (s.x[v], s.y[v]) == (s.x[r], s.y[r])
        assert s.dup[r] < 0 and r in used and v not in used
    # the duplicates' input ids: exactly the repeats (one of each group of equal points kept)
    groups = {}
    for i in range(len(P)):
        groups.setdefault(tuple(P[i]), []).append(i)
    dup_inputs = sorted(int(s.order[v]) for v in dups)
    assert len(dup_inputs) == sum(len(g) - 1 for g in groups.values())
    kept = {tuple(P[s.order[v]]) for v in c["vertices"]}
    assert kept == set(groups)
    assert store_triangles(s) == store_triangles(delaunay_store(base))


def test_seed_triangle():
    x = np.array([0.0, 0.0, 1.0, 2.0, 2.0, 5.0])
    y = np.array([0.0, 0.0, 1.0, 2.0, 3.0, 5.0])
    order = np.arange(6)
    k1, k2 = seed_triangle(x, y, order)
    assert (k1, k2) == (2, 4)            # skips the repeat of point 0 and the collinear point 3
    P = np.column_stack([x, y])
    assert orient2d_exact(P[order[0]], P[order[k1]], P[order[k2]]) != 0
    assert seed_first(order, k1, k2).tolist() == [0, 2, 4, 1, 3, 5]


def test_seed_triangle_on_collinear_input():
    t = np.linspace(0, 1, 9)
    x, y = 3 * t + 1, 2 * t - 7            # one line, not exactly: check with the exact orient
    P = np.column_stack([x, y])
    exact_line = all(orient2d_exact(P[0], P[-1], P[i]) == 0 for i in range(9))
    order = lexicographic_order_compiled(x, y)
    k1, k2 = seed_triangle(x, y, order)
    assert k1 == 1
    assert (k2 == -1) == exact_line
    xs = np.arange(7, dtype=float)         # exactly collinear
    k1, k2 = seed_triangle(xs, 2 * xs, np.arange(7))
    assert (k1, k2) == (1, -1)
    same = np.full(4, 0.5)                 # all one point
    assert seed_triangle(same, same, np.arange(4)) == (-1, -1)


def test_gather_coords_layout():
    x = np.array([3.0, 1.0, 2.0])
    y = np.array([30.0, 10.0, 20.0])
    w = np.array([0.3, 0.1, 0.2])
    xi, yi, wi = gather_coords(x, y, w, np.array([1, 2, 0]), 2)
    assert xi.tolist() == [1.0, 2.0, 3.0, 0, 0, 0]
    assert yi.tolist() == [10.0, 20.0, 30.0, 0, 0, 0]
    assert wi.tolist() == [0.1, 0.2, 0.3, 0, 0, 0]


def test_build_reserves_room_and_marks_duplicates():
    P = np.array([(0, 0), (2, 0), (0, 2), (2, 2), (1, 1), (1, 1)], float)
    x, y = P[:, 0].copy(), P[:, 1].copy()
    n, extra = len(P), 5
    inf = n + extra
    xi, yi, wi = gather_coords(x, y, np.zeros(n), np.arange(n), extra)
    dup = np.full(n, -1, np.int64)
    status, tri, twin, cons, ntri = build(xi, yi, wi, False, inf, np.arange(n), False, dup,
                                          np.zeros(n, np.int8), np.zeros(2, np.int64), extra, True)
    assert status == 0
    assert tri.shape[0] >= 3 * (2 * (n + extra) + 2) and cons.shape == tri.shape
    assert dup.tolist() == [-1, -1, -1, -1, -1, 4]
    c = check_store(tri, twin, cons, ntri, inf, xi, yi)
    assert c["solid"] == 4 and c["vertices"] == [0, 1, 2, 3, 4]


def test_divide_without_cons_and_with_small_cap():
    """``with_cons=False`` leaves ``cons`` empty; the store is sane all the same."""
    P = INPUTS["grid"]
    order = lexicographic_order_compiled(P[:, 0].copy(), P[:, 1].copy())
    x, y, w = gather_coords(P[:, 0].copy(), P[:, 1].copy(), np.zeros(len(P)), order, 0)
    m = len(P)
    dup = np.full(m, -1, np.int64)
    hor = lexicographic_order_compiled(y[:m], -x[:m])
    tri, twin, cons, ntri = build_divide_sorted(x, y, w, m, m, dup, 2 * m + 2, False, hor)
    assert cons.shape[0] == 0
    c = check_store(tri, twin, cons, ntri, m, x, y)
    assert c["solid"] == 2 * m - c["ghosts"] - 2


@pytest.mark.parametrize("name", ["random", "grid", "cocircular"])
def test_divide_store_takes_over_the_quad_edge_memory_when_it_fits(name):
    """With no room asked beyond its triangles, the store is written into the
    quad-edges' ``onext`` (``tri`` and ``twin`` share one buffer); with room
    asked for (more than onext holds), into arrays of its own. Both stores are sane and equal, and the
    room past the triangles is -1."""
    P = INPUTS[name]
    order = lexicographic_order_compiled(P[:, 0].copy(), P[:, 1].copy())
    x, y, w = gather_coords(P[:, 0].copy(), P[:, 1].copy(), np.zeros(len(P)), order, 0)
    m = len(P)
    hor = lexicographic_order_compiled(y[:m], -x[:m])
    stores = {}
    for cap in (0, 4 * m):
        dup = np.full(m, -1, np.int64)
        tri, twin, cons, ntri = build_divide_sorted(x, y, w, m, m, dup, cap, False, hor)
        assert len(tri) == len(twin) == 3 * max(cap, ntri)
        one_buffer = tri.ctypes.data + tri.nbytes == twin.ctypes.data   # twin right after tri
        assert one_buffer == (cap == 0)
        assert (tri[3 * ntri:] == -1).all() and (twin[3 * ntri:] == -1).all()
        c = check_store(tri, twin, cons, ntri, m, x, y)
        assert c["solid"] == 2 * m - c["ghosts"] - 2
        stores[cap] = (tri[:3 * ntri].copy(), twin[:3 * ntri].copy())
    assert all(np.array_equal(a, b) for a, b in zip(stores[0], stores[4 * m]))
