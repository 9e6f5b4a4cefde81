"""``_core.locate`` and ``_core.insertion``: point location answers exactly
(inside / on an edge / on a vertex, ghosts outside the hull) from every start,
and vertex insertion keeps the store sane and Delaunay after every vertex."""
from __future__ import annotations

import numpy as np
import pytest

from cdt_plugin._core.construct import DIVIDE, INCREMENTAL
from cdt_plugin._core.insertion import insert_vertex, insert_vertices
from cdt_plugin._core.locate import locate, locate_by_scan
from cdt_plugin._core.mesh import ghost_hull_edge, is_ghost, nxt
from cdt_plugin._core.status import INSIDE, ON_EDGE, ON_VERTEX, SUBMERGED
from checker import orient2d_exact
from core_stores import delaunay_store, mesh, store_triangles
from store_check import check_store, live_triangles, sanity_check

GRID = np.array([(i, j) for i in range(4) for j in range(4)], float)   # 0..3 x 0..3


def grid_store(extra=8, algorithm=DIVIDE):
    return delaunay_store(GRID, algorithm=algorithm, extra=extra)


def put(s, q, xy):
    s.x[q], s.y[q] = xy


def P(s, v):
    return (s.x[v], s.y[v])


def assert_location(s, q, code, e):
    """``(code, e)`` is a correct answer for vertex ``q``, checked exactly."""
    t = e // 3
    u, v = s.tri[e], s.tri[nxt(e)]
    if code == ON_VERTEX:
        assert P(s, u) == P(s, q)
        return
    if is_ghost(s.tri, t, s.inf):
        assert e == ghost_hull_edge(s.tri, t, s.inf)
        o = orient2d_exact(P(s, u), P(s, v), P(s, q))
        if code == INSIDE:
            assert o > 0                       # strictly outside the hull, beyond u -> v
        else:
            assert code == ON_EDGE and o == 0
        return
    o = [orient2d_exact(P(s, s.tri[3 * t + k]), P(s, s.tri[3 * t + (k + 1) % 3]), P(s, q))
         for k in range(3)]
    if code == INSIDE:
        assert min(o) > 0, o
    else:
        assert code == ON_EDGE
        assert orient2d_exact(P(s, u), P(s, v), P(s, q)) == 0 and sorted(o)[1] > 0, o


CASES = [
    ((1.25, 1.6), INSIDE, False),          # inside a solid triangle
    ((1.5, 1.0), ON_EDGE, False),          # on a grid edge (interior)
    ((0.5, 0.5), ON_EDGE, False),          # on a diagonal, if the triangulation has it: see test
    ((2.0, 0.0), ON_VERTEX, False),        # a hull vertex
    ((1.0, 2.0), ON_VERTEX, False),        # an inner vertex
    ((1.5, 0.0), ON_EDGE, True),           # on a hull edge
    ((-1.0, 1.5), INSIDE, True),           # outside: a ghost
    ((5.0, 0.0), INSIDE, True),            # outside, on the line of the bottom hull edges
    ((3.0, 7.0), INSIDE, True),            # outside, on the line of the right hull edges
]


@pytest.mark.parametrize("xy,want,ghost_side", CASES, ids=[str(c[0]) for c in CASES])
def test_locate_from_every_start(xy, want, ghost_side):
    s = grid_store()
    q = s.nv
    put(s, q, xy)
    answers = set()
    results = [locate(s.tri, s.twin, s.x, s.y, s.inf, q, start, s.ntri)
               for start in live_triangles(s.tri, s.ntri)]
    results.append(locate_by_scan(s.tri, s.x, s.y, s.inf, q, s.ntri))
    for code, e in results:
        assert code >= 0
        assert_location(s, q, code, e)
        answers.add(code)
        if code == INSIDE:   # a ghost exactly for points outside the hull
            assert is_ghost(s.tri, e // 3, s.inf) == ghost_side
    if xy == (0.5, 0.5):   # on the diagonal of cell (0,0) only if that cell was cut that way
        diag = any({P(s, s.tri[f]), P(s, s.tri[nxt(f)])} == {(0.0, 0.0), (1.0, 1.0)}
                   for f in range(3 * s.ntri))
        want = ON_EDGE if diag else INSIDE
    assert answers == {want}


def test_locate_does_not_modify_the_store():
    s = grid_store()
    before = s.tri.copy(), s.twin.copy(), s.cons.copy()
    put(s, s.nv, (2.5, 2.25))
    locate(s.tri, s.twin, s.x, s.y, s.inf, s.nv, 0, s.ntri)
    assert all(np.array_equal(a, b) for a, b in zip(before, (s.tri, s.twin, s.cons)))


# ------------------------------------------------------------------ insert_vertex
def insert(s, q, last=0, weighted=False, counts=None):
    sub = np.zeros(s.inf + 1, np.int8)
    counts = np.zeros(2, np.int64) if counts is None else counts
    code, v, ntri, last = insert_vertex(mesh(s), (s.w, weighted), q, last, s.ntri, False, sub,
                                        counts, np.empty(s.inf + 16, np.int64))
    s.ntri = int(ntri)
    return code, v, last, sub


def test_insert_vertex_kinds_keep_the_store_delaunay():
    s = grid_store()
    q = s.nv
    want_codes = []
    for xy, code, _ in CASES:
        if code == ON_VERTEX or xy == (0.5, 0.5):
            continue
        put(s, q, xy)
        before = s.ntri
        got, v, last, _ = insert(s, q)
        want_codes.append((got, code))
        assert v == q and s.ntri == before + 2
        assert s.tri[3 * last] != -2
        c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
        assert q in c["vertices"]
        q += 1
    assert [g for g, _ in want_codes] == [w for _, w in want_codes]
    # the same triangles as building from all the points at once
    assert store_triangles(s) == store_triangles(delaunay_store(np.column_stack([s.x[:q], s.y[:q]])))


def test_insert_vertex_on_a_vertex_changes_nothing():
    s = grid_store()
    before = s.tri.copy(), s.twin.copy(), s.ntri
    put(s, s.nv, (1.0, 2.0))
    code, v, last, _ = insert(s, s.nv)
    assert code == ON_VERTEX and P(s, v) == (1.0, 2.0) and v < s.nv
    assert s.ntri == before[2]
    assert np.array_equal(s.tri, before[0]) and np.array_equal(s.twin, before[1])


def test_insert_vertex_never_flips_a_segment():
    """A constrained edge stays an edge whatever is inserted beside it; the
    result is constrained Delaunay (Lemma 2.14) for the checker."""
    pts = np.array([(0, 0), (4, 0), (4, 4), (0, 4), (1.7, 0.9), (2.2, 3.1)], float)
    s = delaunay_store(pts, extra=4)
    a, b = s.mesh_of[4], s.mesh_of[5]          # (1.7, 0.9) - (2.2, 3.1): constrain it
    e = next(e for e in range(3 * s.ntri) if {s.tri[e], s.tri[nxt(e)]} == {a, b})
    s.cons[e] = s.cons[s.twin[e]] = 1
    q = s.nv
    # close to the edge on both sides: each lies in the circumcircles across it
    for xy in [(2.0475, 1.978), (1.8525, 2.022), (1.8975, 1.318)]:
        put(s, q, xy)
        code, v, _, _ = insert(s, q)
        assert code == INSIDE and v == q
        c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
        q += 1
    edges = {frozenset((int(s.tri[f]), int(s.tri[nxt(f)]))) for f in range(3 * s.ntri)
             if s.cons[f]}
    assert edges == {frozenset((a, b))}
    # and without the constraint the Delaunay triangulation has no such edge
    assert store_triangles(s) != store_triangles(delaunay_store(np.column_stack([s.x[:q], s.y[:q]])))
    assert c["solid"] == len(store_triangles(s))


def test_insert_vertices_marks_duplicates():
    s = delaunay_store(GRID[:3].tolist() + [(0, 3), (3, 0)], algorithm=INCREMENTAL, extra=6)
    n = s.nv
    new = [(1.5, 1.5), (3.0, 0.0), (0.5, 2.0), (1.5, 1.5), (2.0, 1.0), (0.0, 0.0)]
    for k, xy in enumerate(new):
        put(s, n + k, xy)
    order = np.arange(n + len(new))
    dup_of = np.full(s.inf + 1, -1, np.int64)
    counts = np.zeros(2, np.int64)
    status, ntri = insert_vertices(mesh(s), (s.w, False), order, n, s.ntri, False, dup_of,
                                   np.zeros(s.inf + 1, np.int8), counts)
    assert status == 0
    got = {int(i): int(dup_of[i]) for i in np.flatnonzero(dup_of >= 0)}
    assert sorted(got) == [n + 1, n + 3, n + 5]
    for i, j in got.items():
        assert P(s, i) == P(s, j) and dup_of[j] < 0
    assert counts[0] > 0
    c = check_store(s.tri, s.twin, s.cons, ntri, s.inf, s.x, s.y)
    assert len(c["vertices"]) == n + len(new) - 3


def test_weighted_point_below_the_lifted_plane_is_submerged():
    pts = np.array([(0, 0), (4, 0), (2, 4)], float)
    s = delaunay_store(pts, extra=2)
    s.w[:3] = 10.0                              # heavy corners
    q = s.nv
    put(s, q, (2.0, 1.0))                       # weight 0: its lifted point lies above the plane
    before = s.tri.copy(), s.ntri
    code, v, _, sub = insert(s, q, weighted=True)
    assert code == SUBMERGED and v == -1 and sub[q] == 1
    assert s.ntri == before[1] and np.array_equal(s.tri, before[0])
    sanity_check(s.tri, s.twin, s.cons, s.ntri, s.inf)
    s.w[q] = 20.0                               # heavier than the corners: it is a vertex
    code, v, _, sub = insert(s, q, weighted=True)
    assert code == INSIDE and v == q
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y, weights=s.w[:q + 1])
    assert c["solid"] == 3
