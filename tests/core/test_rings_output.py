"""``_core.rings`` (rings to segments, the exact degenerate-ring test) and
``_core.output`` (store compaction: solid triangles and neighbours, min-first
rotation, the CDT output arrays, the moved-mesh defect test)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from cdt_plugin._core.output import (cdt_arrays, cdt_vertices, first_defect, rotate_min_first,
                                     solid_triangles)
from cdt_plugin._core.pipeline import solid_with_flags
from cdt_plugin._core.rings import (open_rings, polygon_rings, ring_is_degenerate, ring_segments,
                                    segments_of_rings)
from checker import assert_valid, canonical_triangles
from core_stores import add_segments, delaunay_store
from helpers import check_neighbors
from store_check import check_store, ghost_slots, solid_slots, to_arrays


def xy(pts):
    P = np.asarray(pts, float).reshape(-1, 2)
    return P[:, 0].copy(), P[:, 1].copy()


# ------------------------------------------------------------------ ring_is_degenerate
TINY = 2.0 ** -60
DEGENERATE = {
    "collinear": [(0, 0), (1, 1), (2, 2), (3, 3)],
    "collinear_back_and_forth": [(0, 0), (2, 2), (1, 1)],
    "all_one_point": [(5, 5), (5, 5), (5, 5)],
    "two_points": [(0, 0), (0, 0), (1, 0), (1, 0), (0, 0)],
    "collinear_huge_offset": [(1e15, 1e15), (1e15 + 2, 1e15 + 2), (1e15 + 4, 1e15 + 4)],
    "one_vertex": [(1, 2)],
}
PROPER = {
    "triangle": [(0, 0), (1, 0), (0, 1)],
    "one_ulp_off_the_line": [(0, 0), (1, 1), (2, np.nextafter(2.0, 3.0))],
    "tiny": [(0, 0), (TINY, 0), (0, TINY)],
    "repeats_then_a_corner": [(0, 0), (0, 0), (1, 0), (1, 0), (1, 1)],
}


@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_ring_is_degenerate(name):
    x, y = xy(DEGENERATE[name])
    assert ring_is_degenerate(x, y, 0, len(x))


@pytest.mark.parametrize("name", sorted(PROPER))
def test_ring_is_not_degenerate(name):
    x, y = xy(PROPER[name])
    assert not ring_is_degenerate(x, y, 0, len(x))


def test_ring_is_degenerate_reads_only_its_range():
    x, y = xy([(9, 8), (0, 0), (1, 1), (2, 2), (7, -3)])
    assert ring_is_degenerate(x, y, 1, 4)
    assert not ring_is_degenerate(x, y, 0, 4)
    assert not ring_is_degenerate(x, y, 1, 5)


# ------------------------------------------------------------------ rings to segments
def test_segments_of_rings():
    begin = np.array([10, 14, 17, 20])
    end = np.array([14, 17, 20, 25])
    keep = np.array([True, False, True, True])
    segs, ring_of = segments_of_rings(begin, end, keep, 10)
    assert segs.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0],
                             [7, 8], [8, 9], [9, 7],
                             [10, 11], [11, 12], [12, 13], [13, 14], [14, 10]]
    assert ring_of.tolist() == [0] * 4 + [1] * 3 + [2] * 5     # counted among the kept rings


def test_ring_segments_of_flat_arrays():
    ring_start = np.array([0, 3, 7, 11])
    segs, ring_of = ring_segments(ring_start, 1, 3, np.ones(2, np.bool_))
    assert segs.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    assert ring_of.tolist() == [0] * 4 + [1] * 4


def test_polygon_rings_drops_degenerate_rings():
    pts = [(0, 0), (4, 0), (4, 4), (0, 4),          # ring 0: a square
           (1, 1), (2, 2), (3, 3),                  # ring 1: collinear
           (1, 3), (1, 3),                          # ring 2: one point twice
           (1, 2), (2, 1), (3, 2)]                  # ring 3: a triangle
    x, y = xy(pts)
    begin, end = np.array([0, 4, 7, 9]), np.array([4, 7, 9, 12])
    bad, degenerate, n_degenerate, segs, ring_of = polygon_rings(np.column_stack([x, y]), begin, end)
    assert bad == -1 and n_degenerate == 2
    assert degenerate.tolist() == [False, True, True, False]
    assert segs.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0], [9, 10], [10, 11], [11, 9]]
    assert ring_of.tolist() == [0] * 4 + [1] * 3


def test_open_rings_drops_each_closing_point():
    shell = [(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)]
    hole1 = [(1, 1), (1, 2), (2, 2), (1, 1)]
    hole2 = [(3, 3), (3, 3.5), (3.5, 3.5), (3.5, 3), (3, 3)]
    coords = np.array(shell + hole1 + hole2, float)
    xy, bounds = open_rings(coords, np.array([4, 5]))
    assert bounds.tolist() == [0, 4, 7, 11]
    assert xy.tolist() == [list(p) for p in shell[:-1] + hole1[:-1] + hole2[:-1]]


@pytest.mark.parametrize("hole_sizes", [[3, 5], [5, 4], [4], [4, 10], [4, 4, 0], [1, 8], [4, 5, -1],
                                        [0, 0, 4, 4], [11, 0]])
def test_open_rings_refuses_sizes_that_do_not_close_the_rings(hole_sizes):
    """(the reader then takes the polygon ring by ring; a ring of no points was
    refused only after the rings before it had overrun ``xy``: the sizes are
    checked first)"""
    coords = np.array([(0, 0), (4, 0), (4, 4), (0, 4), (0, 0),
                       (1, 1), (1, 2), (2, 2), (1, 1), (3, 3), (3, 4), (4, 3), (3, 3)], float)
    assert open_rings(coords, np.array([4, 4]))[1].tolist() == [0, 4, 7, 10]
    assert open_rings(coords, np.array(hole_sizes))[1].size == 0


def test_polygon_rings_finds_the_first_non_finite_vertex():
    pts = np.array([[0, 0], [1, 0], [np.nan, 1], [0, np.inf]], float)
    bad, _, _, _, _ = polygon_rings(pts, np.array([0]), np.array([4]))
    assert bad == 2


# ------------------------------------------------------------------ solid triangles
def store_of(points, segments=(), extra=0):
    s = delaunay_store(np.asarray(points, float), extra=extra)
    if len(segments):
        assert add_segments(s, segments)[0] == 0
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    return s


RANDOM = np.random.default_rng(44).random((30, 2))


def test_solid_triangles_and_neighbours():
    s = store_of(RANDOM)
    T, N, tid = solid_triangles(s.tri, s.twin, s.ntri, s.inf)
    solid = solid_slots(s.tri, s.ntri, s.inf)
    assert len(T) == len(solid)
    assert [t for t in range(s.ntri) if tid[t] >= 0] == solid
    for t in solid:
        assert T[tid[t]].tolist() == s.tri[3 * t:3 * t + 3].tolist()
    # neighbour j is across the edge opposite vertex j; -1 exactly on the hull
    check_neighbors(SimpleNamespace(triangles=T, neighbors=N))
    assert (N < 0).sum() == len(ghost_slots(s.tri, s.ntri, s.inf))
    V, Tc = to_arrays(s.tri, s.ntri, s.inf, s.x, s.y)
    assert canonical_triangles(np.column_stack([s.x, s.y]), T) == canonical_triangles(V, Tc)
    assert_valid(np.column_stack([s.x[:s.nv], s.y[:s.nv]]), T)


def test_rotate_min_first():
    s = store_of(RANDOM)
    T, N, _ = solid_triangles(s.tri, s.twin, s.ntri, s.inf)
    T0, N0 = T.copy(), N.copy()
    rotate_min_first(T, N)
    assert (T[:, 0] < T[:, 1]).all() and (T[:, 0] < T[:, 2]).all()
    for i in range(len(T)):
        r = list(T0[i]).index(T[i, 0])
        assert T[i].tolist() == np.roll(T0[i], -r).tolist()
        assert N[i].tolist() == np.roll(N0[i], -r).tolist()
    check_neighbors(SimpleNamespace(triangles=T, neighbors=N))
    assert_valid(np.column_stack([s.x[:s.nv], s.y[:s.nv]]), T)


# ------------------------------------------------------------------ cdt_arrays
def test_cdt_arrays_consistent_with_the_store():
    # a square with a square hole; keep the triangles outside the hole
    pts = [(0, 0), (5, 0), (5, 5), (0, 5), (2, 2), (3, 2), (3, 3), (2, 3), (1, 4), (4, 1.2)]
    segs = [(i, (i + 1) % 4) for i in range(4)] + [(4 + i, 4 + (i + 1) % 4) for i in range(4)]
    s = store_of(pts, segs)
    T, N, tid, cflag = solid_with_flags(s.tri, s.twin, s.cons, s.ntri, s.inf)
    centre = np.column_stack([s.x[T].mean(axis=1), s.y[T].mean(axis=1)])
    inside = ~((centre > 2) & (centre < 3)).all(axis=1)
    assert 0 < inside.sum() < len(T)
    # output ids: the input order (mesh vertex i is input point order[i])
    remap = np.empty(s.nv, np.int64)
    remap[np.arange(s.nv)] = s.order
    triangles, neighbors, constrained, pieces, piece_ids, keep = cdt_arrays(T, N, cflag, inside,
                                                                          remap)
    assert len(triangles) == inside.sum() and keep.tolist() == np.flatnonzero(inside).tolist()
    assert (triangles[:, 0] < triangles[:, 1]).all() and (triangles[:, 0] < triangles[:, 2]).all()
    for i, t in enumerate(keep):
        assert sorted(triangles[i].tolist()) == sorted(remap[T[t]].tolist())
    # neighbours: -1 across the domain boundary, symmetric inside
    check_neighbors(SimpleNamespace(triangles=triangles, neighbors=neighbors))
    P = np.asarray(pts, float)
    assert constrained[neighbors < 0].all()     # the domain is bounded by segments only
    assert (neighbors < 0).sum() == 8           # 4 hull sides and the 4 sides of the hole
    # every segment piece once, with its input segment (0-based)
    assert len(pieces) == len(segs)
    assert {frozenset(p) for p in pieces.tolist()} == {frozenset(sg) for sg in segs}
    for (u, v), sid in zip(pieces.tolist(), piece_ids.tolist()):
        assert {u, v} == set(segs[sid])
    # constrained flags mark exactly the pieces among the kept triangles' edges
    flagged = {frozenset((triangles[i, (j + 1) % 3], triangles[i, (j + 2) % 3]))
               for i in range(len(triangles)) for j in range(3) if constrained[i, j]}
    assert flagged == {frozenset(sg) for sg in segs}
    rep = assert_valid(P, triangles, segments=np.array(segs), domain="segments")
    assert rep.ok


def test_cdt_vertices_keeps_inputs_then_steiner_points():
    px, py = xy([(0, 0), (1, 0), (0, 1), (1, 0)])           # input 3 repeats input 1
    order = np.array([0, 2, 1, 3])                          # mesh vertex i = input order[i]
    vertex_map = np.array([0, 1, 2, 1])
    kept = np.array([0, 1, 2])
    mx = np.array([0, 0, 1, 1, 0.5, 0.25])
    my = np.array([0, 1, 0, 0, 0.5, 0.25])
    vertices, remap = cdt_vertices(px, py, kept, vertex_map, order, mx, my, 4, 6)
    assert vertices.tolist() == [[0, 0], [1, 0], [0, 1], [0.5, 0.5], [0.25, 0.25]]
    assert remap.tolist() == [0, 2, 1, 1, 3, 4]
    for i in range(6):
        assert vertices[remap[i]].tolist() == [mx[i], my[i]]


# ------------------------------------------------------------------ first_defect
def test_first_defect():
    s = store_of(RANDOM)
    assert first_defect(s.tri, s.twin, s.ntri, s.x, s.y, s.inf, True) == -1
    # move an inner vertex far across its neighbours: some triangle turns clockwise
    hull = {int(v) for t in ghost_slots(s.tri, s.ntri, s.inf) for v in s.tri[3 * t:3 * t + 3]}
    v = next(v for v in range(s.nv) if v not in hull)
    x = s.x.copy()
    x[v] += 0.6 if x[v] < 0.5 else -0.6
    t = first_defect(s.tri, s.twin, s.ntri, x, s.y, s.inf, True)
    assert t >= 0 and v in s.tri[3 * t:3 * t + 3]


def test_first_defect_sees_a_reflex_hull_only_when_asked():
    # (1, -0.1) is a hull vertex with no hull-to-hull triangle: pulling it up
    # to (1, 0.05) keeps every triangle counter-clockwise but makes the hull reflex
    s = store_of([(0, 0), (2, 0), (1, -0.1), (1, 1.5), (0, 2), (2, 2)])
    v = s.mesh_of[2]
    y = s.y.copy()
    y[v] = 0.05
    assert first_defect(s.tri, s.twin, s.ntri, s.x, y, s.inf, False) == -1
    t = first_defect(s.tri, s.twin, s.ntri, s.x, y, s.inf, True)
    assert t >= 0 and s.inf in s.tri[3 * t:3 * t + 3]
    assert first_defect(s.tri, s.twin, s.ntri, s.x, s.y, s.inf, True) == -1
