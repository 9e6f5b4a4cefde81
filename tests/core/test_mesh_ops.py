"""The topological operations of ``_core.mesh`` one by one, on stores of a few
triangles: each result must keep the store invariants (``store_check``) and
be a valid triangulation for the exact checker. Plus the sanity check itself:
it must catch a corrupted store."""
from __future__ import annotations

import numpy as np
import pytest

from cdt_plugin._core.construct import DIVIDE
from cdt_plugin._core.mesh import (DEAD, flip, ghost_hull_edge, grow_store, is_ghost,
                                   make_first_triangle, nxt, prv, remove_degree3, split_edge,
                                   split_triangle)
from checker import check_triangulation, orient2d_exact
from core_stores import delaunay_store, empty_store
from store_check import (StoreDefect, check_store, constrained_pairs, sanity_check,
                         store_defects, to_arrays)


def coords(*pts, room=0):
    """x, y (and zero weights) of the points, then ``room`` zeros and the infinite vertex."""
    P = np.array(pts, float)
    x = np.concatenate([P[:, 0], np.zeros(room + 1)])
    y = np.concatenate([P[:, 1], np.zeros(room + 1)])
    return x, y, len(P) + room


def triangle_sets(tri, ntri, inf, solid_only=True):
    """The live triangles as a set of rotation-normalised vertex triples."""
    out = set()
    for t in range(ntri):
        v = tri[3 * t:3 * t + 3].tolist()
        if v[0] == DEAD or (solid_only and inf in v):
            continue
        k = v.index(min(v))
        out.add(tuple(v[k:] + v[:k]))
    return out


def first_triangle_store(room=2):
    """Triangle (0,0) (1,0) (1,1) and its three ghosts; room for ``room`` more vertices."""
    x, y, inf = coords((0, 0), (1, 0), (1, 1), room=room)
    tri, twin, cons = empty_store(16)
    ntri = make_first_triangle(tri, twin, 0, 1, 2, inf)
    return tri, twin, cons, ntri, inf, x, y


def square_store():
    """Two triangles (0 1 2), (0 2 3) of the quadrilateral 0 1 2 3 (diagonal 0-2)
    with four ghosts, built by splitting the ghost beyond hull edge 2->0 at 3."""
    tri, twin, cons, ntri, inf, x, y = first_triangle_store(room=3)
    x[3], y[3] = 0.0, 1.0
    g = [t for t in range(ntri) if is_ghost(tri, t, inf)
         and {tri[ghost_hull_edge(tri, t, inf)], tri[nxt(ghost_hull_edge(tri, t, inf))]} == {0, 2}]
    assert len(g) == 1
    ntri = split_triangle(tri, twin, cons, g[0], 3, ntri)
    return tri, twin, cons, ntri, inf, x, y


def half_edge(tri, ntri, u, v):
    for e in range(3 * ntri):
        if tri[3 * (e // 3)] != DEAD and tri[e] == u and tri[nxt(e)] == v:
            return e
    raise AssertionError(f"no half-edge {u}->{v}")


# ------------------------------------------------------------------ the sanity check itself
def test_sanity_check_accepts_a_built_store():
    s = delaunay_store(np.random.default_rng(3).random((25, 2)))
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    assert c["solid"] + c["ghosts"] == s.ntri and c["dead"] == 0
    assert c["vertices"] == list(range(25))


def _corrupt_twin_not_involution(tri, twin, cons, ntri, inf):
    e = 0
    twin[twin[e]] = (twin[twin[e]] + 1) % 3 + 3 * (twin[e] // 3)   # twin[twin[0]] != 0
    return "twin"


def _corrupt_same_direction(tri, twin, cons, ntri, inf):
    # rewrite triangle 0 clockwise: its edges now run along their twins
    tri[0], tri[1] = tri[1], tri[0]
    return "direction"


def _corrupt_cons_one_half(tri, twin, cons, ntri, inf):
    e = next(e for e in range(3 * ntri) if inf not in (tri[e], tri[nxt(e)]))
    cons[e] = 7              # the twin keeps 0
    return "cons"


def _corrupt_ghost_two_inf(tri, twin, cons, ntri, inf):
    t = next(t for t in range(ntri) if is_ghost(tri, t, inf))
    e = ghost_hull_edge(tri, t, inf)
    tri[e] = inf
    return "repeat"       # a second inf repeats a vertex: caught before the ring


def _corrupt_repeated_vertex(tri, twin, cons, ntri, inf):
    t = next(t for t in range(ntri) if not is_ghost(tri, t, inf))
    tri[3 * t + 2] = tri[3 * t]
    return "repeat"


def _corrupt_dead_but_linked(tri, twin, cons, ntri, inf):
    t = next(t for t in range(ntri) if not is_ghost(tri, t, inf))
    tri[3 * t] = DEAD         # killed without unlinking its neighbours
    return "dead"


def _corrupt_two_ghost_rings(tri, twin, cons, ntri, inf):
    # swap the inf-edge twins of two ghosts: still an involution in opposite
    # directions only if the hull vertices agree, so the ring check must catch it
    gs = [t for t in range(ntri) if is_ghost(tri, t, inf)]
    a, b = gs[0], gs[2]
    ea = next(e for e in range(3 * a, 3 * a + 3) if tri[e] == inf)
    eb = next(e for e in range(3 * b, 3 * b + 3) if tri[e] == inf)
    fa, fb = twin[ea], twin[eb]
    twin[ea], twin[fb] = fb, ea
    twin[eb], twin[fa] = fa, eb
    return "direction"


@pytest.mark.parametrize("corrupt", [_corrupt_twin_not_involution, _corrupt_same_direction,
                                     _corrupt_cons_one_half, _corrupt_ghost_two_inf,
                                     _corrupt_repeated_vertex, _corrupt_dead_but_linked,
                                     _corrupt_two_ghost_rings])
def test_sanity_check_reports_a_corrupted_store(corrupt):
    s = delaunay_store(np.random.default_rng(5).random((12, 2)))
    tri, twin, cons = s.tri.copy(), s.twin.copy(), s.cons.copy()
    assert store_defects(tri, twin, cons, s.ntri, s.inf) == []
    kind = corrupt(tri, twin, cons, s.ntri, s.inf)
    defects = store_defects(tri, twin, cons, s.ntri, s.inf)
    assert defects, "the corruption went unnoticed"
    assert any(d.startswith(kind) for d in defects), defects
    with pytest.raises(StoreDefect) as err:
        sanity_check(tri, twin, cons, s.ntri, s.inf)
    assert err.value.defects == defects


def test_sanity_check_catches_a_ghost_ring_that_is_two_cycles():
    """Two disjoint stores side by side: each closed on its own ghosts, so every
    local invariant holds, but the link of inf is two cycles."""
    tri, twin, cons = empty_store(16)
    inf = 6
    make_first_triangle(tri, twin, 0, 1, 2, inf)
    t2, tw2 = np.full(12, -1, tri.dtype), np.full(12, -1, tri.dtype)
    make_first_triangle(t2, tw2, 3, 4, 5, inf)
    tri[12:24] = t2
    twin[12:24] = tw2 + 12
    defects = store_defects(tri, twin, cons, 8, inf)
    assert any(d.startswith("ghost ring") for d in defects), defects
    assert any(d.startswith("euler") for d in defects), defects


# ------------------------------------------------------------------ make_first_triangle
def test_make_first_triangle():
    tri, twin, cons, ntri, inf, x, y = first_triangle_store()
    assert ntri == 4
    assert tri[:3].tolist() == [0, 1, 2]
    c = check_store(tri, twin, cons, ntri, inf, x, y)
    assert (c["solid"], c["ghosts"]) == (1, 3)
    for k in range(3):                     # the ghost on real half-edge k is (v, u, inf)
        g = twin[k] // 3
        assert tri[3 * g:3 * g + 3].tolist() == [tri[nxt(k)], tri[k], inf]
        assert twin[k] == 3 * g


# ------------------------------------------------------------------ split_triangle
def test_split_triangle_layout_and_constraints():
    tri, twin, cons, ntri, inf, x, y = first_triangle_store()
    x[3], y[3] = 0.75, 0.25
    e_bc = 1                                  # b -> c of triangle 0, on segment 7
    cons[e_bc] = cons[twin[e_bc]] = 7
    ntri2 = split_triangle(tri, twin, cons, 0, 3, ntri)
    assert ntri2 == ntri + 2
    assert tri[0:3].tolist() == [0, 1, 3]
    assert tri[3 * ntri:3 * ntri + 3].tolist() == [1, 2, 3]
    assert tri[3 * ntri + 3:3 * ntri + 6].tolist() == [2, 0, 3]
    # the segment moved with its edge: now slot 0 of the new triangle (b, c, p)
    assert cons[3 * ntri] == 7 and constrained_pairs(tri, cons, ntri2) == {(1, 2): 7}
    c = check_store(tri, twin, cons, ntri2, inf, x, y)
    assert (c["solid"], c["ghosts"]) == (3, 3)


def test_split_ghost_triangle_adds_a_hull_vertex():
    tri, twin, cons, ntri, inf, x, y = square_store()
    c = check_store(tri, twin, cons, ntri, inf, x, y)
    assert (c["solid"], c["ghosts"]) == (2, 4)
    assert triangle_sets(tri, ntri, inf) == {(0, 1, 2), (0, 2, 3)}


def test_remove_degree3_undoes_split_triangle():
    tri, twin, cons, ntri, inf, x, y = first_triangle_store()
    before = tri.copy(), twin.copy()
    x[3], y[3] = 0.75, 0.25
    ntri2 = split_triangle(tri, twin, cons, 0, 3, ntri)
    # the link of vertex 3, counter-clockwise: the half-edges opposite it
    e = remove_degree3(tri, twin, 0, 3 * ntri, 3 * (ntri + 1))
    assert e == 0
    assert tri[3 * ntri] == DEAD and tri[3 * (ntri + 1)] == DEAD
    c = check_store(tri, twin, cons, ntri2, inf, x, y)
    assert (c["solid"], c["ghosts"], c["dead"]) == (1, 3, 2)
    assert tri[:3].tolist() == before[0][:3].tolist()
    assert twin[:3 * ntri].tolist() == before[1][:3 * ntri].tolist()


# ------------------------------------------------------------------ split_edge
def test_split_interior_edge():
    tri, twin, cons, ntri, inf, x, y = square_store()
    x[4], y[4] = 0.5, 0.5
    e = half_edge(tri, ntri, 2, 0)
    cons[e] = cons[twin[e]] = 5                       # the diagonal is segment 5
    cons[half_edge(tri, ntri, 0, 1)] = cons[half_edge(tri, ntri, 1, 0)] = 3
    ntri2 = split_edge(tri, twin, cons, e, 4, ntri)
    assert ntri2 == ntri + 2
    for t in (e // 3, twin[e] // 3, ntri, ntri + 1):  # p in slot 2 of all four
        assert tri[3 * t + 2] == 4
    assert constrained_pairs(tri, cons, ntri2) == {(0, 4): 5, (2, 4): 5, (0, 1): 3}
    c = check_store(tri, twin, cons, ntri2, inf, x, y)
    assert (c["solid"], c["ghosts"]) == (4, 4)
    assert triangle_sets(tri, ntri2, inf) == {(0, 1, 4), (1, 2, 4), (2, 3, 4), (0, 4, 3)}


def test_split_hull_edge():
    tri, twin, cons, ntri, inf, x, y = square_store()
    x[4], y[4] = 0.5, 0.0
    e = half_edge(tri, ntri, 0, 1)
    ntri2 = split_edge(tri, twin, cons, e, 4, ntri)
    c = sanity_check(tri, twin, cons, ntri2, inf)
    assert (c["solid"], c["ghosts"]) == (3, 5)      # the hull gained a vertex
    assert triangle_sets(tri, ntri2, inf) == {(0, 4, 2), (1, 2, 4), (0, 2, 3)}
    # a valid triangulation, but the new vertex lies in the circumcircle of (0, 2, 3):
    # the split alone does not restore the Delaunay property, one flip does
    rep = check_triangulation(*to_arrays(tri, ntri2, inf, x, y))
    assert rep.kinds == {"not_delaunay": 1}, str(rep)
    flip(tri, twin, cons, half_edge(tri, ntri2, 0, 2))
    check_store(tri, twin, cons, ntri2, inf, x, y)
    assert triangle_sets(tri, ntri2, inf) == {(0, 4, 3), (1, 2, 4), (2, 3, 4)}


# ------------------------------------------------------------------ flip
def kite_store():
    """Quadrilateral (0,0) (1,0) (1.2,1.1) (0,1): diagonal 0-2 is not locally
    Delaunay, 1-3 is."""
    tri, twin, cons, ntri, inf, x, y = square_store()
    x[2], y[2] = 1.2, 1.1
    return tri, twin, cons, ntri, inf, x, y


def test_checker_rejects_the_illegal_diagonal():
    tri, twin, cons, ntri, inf, x, y = kite_store()
    sanity_check(tri, twin, cons, ntri, inf)
    V, T = to_arrays(tri, ntri, inf, x, y)
    rep = check_triangulation(V, T)
    assert not rep.ok and "not_delaunay" in rep.kinds


def test_flip_makes_the_legal_diagonal():
    tri, twin, cons, ntri, inf, x, y = kite_store()
    e = half_edge(tri, ntri, 0, 2)                   # a -> b in (a, b, p) = (0, 2, 3)
    f = twin[e]
    cons[half_edge(tri, ntri, 2, 3)] = cons[half_edge(tri, ntri, 3, 2)] = 4
    r = flip(tri, twin, cons, e)
    # documented layout: (p, a, d) in e's triangle, (p, d, b) in the twin's
    assert tri[3 * (e // 3):3 * (e // 3) + 3].tolist() == [3, 0, 1]
    assert tri[3 * (f // 3):3 * (f // 3) + 3].tolist() == [3, 1, 2]
    assert tri[r] == 0 and tri[nxt(r)] == 1          # returns a -> d
    assert tri[3 * (f // 3) + 1] == 1 and tri[nxt(3 * (f // 3) + 1)] == 2   # d -> b
    assert tri[prv(r)] == 3
    assert constrained_pairs(tri, cons, ntri) == {(2, 3): 4}
    check_store(tri, twin, cons, ntri, inf, x, y)
    # flipping the new diagonal gives the old triangles back (as a set)
    flip(tri, twin, cons, half_edge(tri, ntri, 3, 1))
    assert triangle_sets(tri, ntri, inf) == {(0, 2, 3), (0, 1, 2)}
    sanity_check(tri, twin, cons, ntri, inf)


def test_flip_every_interior_edge_twice_is_identity():
    s = delaunay_store(np.random.default_rng(11).random((20, 2)))
    want = triangle_sets(s.tri, s.ntri, s.inf)
    tri, twin, cons = s.tri.copy(), s.twin.copy(), s.cons.copy()
    for e in range(3 * s.ntri):
        a, b = tri[e], tri[nxt(e)]
        if s.inf in (a, b, tri[prv(e)], tri[prv(twin[e])]) or a > b:
            continue
        P = np.column_stack([s.x, s.y])
        p, d = tri[prv(e)], tri[prv(twin[e])]
        if orient2d_exact(P[p], P[a], P[d]) <= 0 or orient2d_exact(P[p], P[d], P[b]) <= 0:
            continue                                  # not a convex quadrilateral
        r = flip(tri, twin, cons, e)
        sanity_check(tri, twin, cons, s.ntri, s.inf)
        u, v = tri[prv(r)], tri[nxt(r)]               # the new diagonal p -> d
        flip(tri, twin, cons, half_edge(tri, s.ntri, u, v))
        assert triangle_sets(tri, s.ntri, s.inf) == want
    check_store(tri, twin, cons, s.ntri, s.inf, s.x, s.y)


# ------------------------------------------------------------------ grow_store
def test_grow_store_keeps_the_mesh_and_moves_inf():
    s = delaunay_store(np.random.default_rng(7).random((15, 2)), extra=3)
    e = next(e for e in range(3 * s.ntri) if s.inf not in (s.tri[e], s.tri[nxt(e)]))
    s.cons[e] = s.cons[s.twin[e]] = 9
    old = triangle_sets(s.tri, s.ntri, s.inf, solid_only=False)
    tri, twin, cons, x, y, w, inf = grow_store(s.tri, s.twin, s.cons, s.x, s.y, s.w, s.inf,
                                               s.nv, 0)
    assert inf == 2 * s.inf + 16 and x.shape[0] == inf + 1
    assert tri.shape[0] >= 3 * (2 * inf + 2) and cons.shape[0] == tri.shape[0]
    assert np.array_equal(x[:s.nv], s.x[:s.nv]) and np.array_equal(y[:s.nv], s.y[:s.nv])
    assert s.inf not in tri[:3 * s.ntri].tolist()           # every inf moved
    moved = {tuple(inf if v == s.inf else v for v in t) for t in old}
    assert triangle_sets(tri, s.ntri, inf, solid_only=False) == moved
    assert (tri[3 * s.ntri:] == -1).all() and (cons[3 * s.ntri:] == 0).all()
    assert constrained_pairs(tri, cons, s.ntri) == constrained_pairs(s.tri, s.cons, s.ntri)
    check_store(tri, twin, cons, s.ntri, inf, x, y, constrained=False)
    # with at_least the new inf is exactly that large
    *_, inf2 = grow_store(s.tri, s.twin, s.cons, s.x, s.y, s.w, s.inf, s.nv, 1000)
    assert inf2 == 1000


def test_grown_store_takes_more_vertices():
    """After growing, a vertex in the new room can be inserted by the kernels."""
    from cdt_plugin._core.insertion import insert_vertex
    from cdt_plugin._core.status import INSIDE
    s = delaunay_store(np.random.default_rng(8).random((10, 2)), algorithm=DIVIDE)
    tri, twin, cons, x, y, w, inf = grow_store(s.tri, s.twin, s.cons, s.x, s.y, s.w, s.inf,
                                               s.nv, 0)
    q = s.nv
    x[q], y[q] = x[:q].mean(), y[:q].mean()
    code, v, ntri, last = insert_vertex((tri, twin, cons, x, y, inf), (w, False), q, 0, s.ntri,
                                        False, np.zeros(inf + 1, np.int8), np.zeros(2, np.int64),
                                        np.empty(inf + 16, np.int64))
    assert code == INSIDE and v == q and ntri == s.ntri + 2
    c = check_store(tri, twin, cons, ntri, inf, x, y)
    assert c["vertices"] == list(range(q + 1))
