"""The checker must accept correct triangulations and report every kind of defect."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import Delaunay

from checker import (_Lazy, _incircle_signs, _orient_signs, assert_valid, canonical_triangles,
                     check_collinear_edges, check_triangulation, incircle_exact, orient2d_exact)


def ccw(P, T):
    """Reorder each triangle counter-clockwise (scipy does not promise an orientation)."""
    P = np.asarray(P, dtype=float)
    T = np.array(T, dtype=np.int64)
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    d = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    T[d < 0] = T[d < 0][:, [0, 2, 1]]
    return T


def grid(nx, ny, offset=0.0):
    """A structured triangulation of an nx-by-ny integer grid (collinear hull points,
    every interior edge a cocircular tie or Delaunay)."""
    P = np.array([(x + offset, y + offset) for y in range(ny) for x in range(nx)], dtype=float)
    T = []
    for y in range(ny - 1):
        for x in range(nx - 1):
            a, b, c, d = y * nx + x, y * nx + x + 1, (y + 1) * nx + x + 1, (y + 1) * nx + x
            if (x + y) % 2:
                T += [(a, b, c), (a, c, d)]
            else:
                T += [(a, b, d), (b, c, d)]
    return P, np.array(T, dtype=np.int64)


@pytest.fixture
def random_delaunay():
    rng = np.random.default_rng(12345)
    P = rng.random((300, 2))
    return P, ccw(P, Delaunay(P).simplices)


SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


# ----------------------------------------------------------------------------------------
# correct inputs pass
# ----------------------------------------------------------------------------------------

def test_random_scipy_delaunay_passes(random_delaunay):
    P, T = random_delaunay
    rep = assert_valid(P, T)
    assert rep.ok and rep.problems == []
    assert rep.counts["triangles"] == len(T)
    assert rep.counts["area"] == rep.counts["hull_area"]
    assert isinstance(rep.counts["area"], Fraction)
    assert rep.counts["delaunay_checked_edges"] == rep.counts["interior_edges"] > 0


@pytest.mark.parametrize("tris", [[(0, 1, 2), (0, 2, 3)], [(0, 1, 3), (1, 2, 3)]])
def test_square_both_diagonals_pass_as_cocircular_tie(tris):
    rep = assert_valid(SQUARE, tris)
    assert rep.counts["cocircular_ties"] == 1


def test_grid_with_collinear_hull_points_passes():
    P, T = grid(7, 5)
    rep = assert_valid(P, T)
    assert rep.counts["hull_vertices"] == 2 * (7 + 5) - 4
    assert rep.counts["cocircular_ties"] == (7 - 1) * (5 - 1)     # the square diagonals


def test_triangle_order_and_rotation_do_not_matter(random_delaunay):
    P, T = random_delaunay
    rng = np.random.default_rng(1)
    T2 = T[rng.permutation(len(T))]
    T2 = np.array([np.roll(t, r) for t, r in zip(T2, rng.integers(0, 3, len(T2)))])
    assert_valid(P, T2)
    assert canonical_triangles(P, T) == canonical_triangles(P, T2)


def test_canonical_triangles_ignores_vertex_numbering(random_delaunay):
    P, T = random_delaunay
    perm = np.random.default_rng(2).permutation(len(P))
    inv = np.argsort(perm)
    P2 = P[perm]                 # new vertex j is old vertex perm[j]
    T2 = inv[T]
    assert canonical_triangles(P, T) == canonical_triangles(P2, T2)
    assert canonical_triangles(P, T) != canonical_triangles(SQUARE, [(0, 1, 2), (0, 2, 3)])


def test_exact_cocircular_with_large_offset():
    """12 integer points on x^2 + y^2 = 25, shifted by 2**30: still exactly cocircular.
    Float incircle cannot decide them; the exact fallback must report ties, not failures."""
    circle = [(3, 4), (4, 3), (5, 0), (4, -3), (3, -4), (0, -5), (-3, -4), (-4, -3),
              (-5, 0), (-4, 3), (-3, 4), (0, 5)]
    circle.sort(key=lambda p: np.arctan2(p[1], p[0]))
    P = np.array(circle, dtype=float) + 2.0 ** 30
    fan = [(0, i, i + 1) for i in range(1, len(P) - 1)]
    rep = assert_valid(P, fan)
    assert rep.counts["cocircular_ties"] == len(P) - 3
    assert rep.counts.get("exact_fallbacks", 0) > 0


def test_near_cocircular_decided_exactly():
    eps = 2.0 ** -52
    P = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0 + eps], [0.0, 1.0]])
    # (1,1+eps) is just outside the circle through the other three: diagonal 1-3 is Delaunay
    assert_valid(P, [(0, 1, 3), (1, 2, 3)])
    rep = check_triangulation(P, [(0, 1, 2), (0, 2, 3)])
    assert not rep.ok and rep.kinds == {"not_delaunay": 1}


def test_filtered_predicates_agree_with_fractions():
    rng = np.random.default_rng(7)
    # near-degenerate quadruples: points close to the unit circle, with a huge offset
    ang = rng.random((400, 4)) * 2 * np.pi
    rad = 1.0 + rng.integers(-2, 3, (400, 4)) * 2.0 ** -50
    off = rng.choice([0.0, 1e6, 2.0 ** 40], (400, 1))
    xy = np.stack([np.cos(ang) * rad + off, np.sin(ang) * rad + off], axis=-1)
    P = xy.reshape(-1, 2)
    q = np.arange(1600).reshape(400, 4)
    stats = {}
    ex = _Lazy(P, None)
    s_in = _incircle_signs(P, None, ex, q[:, 0], q[:, 1], q[:, 2], q[:, 3], stats)
    s_or = _orient_signs(P, ex, q[:, 0], q[:, 1], q[:, 2], stats)
    for j in range(400):
        a, b, c, d = P[q[j]]
        assert s_in[j] == incircle_exact(a, b, c, d)
        assert s_or[j] == orient2d_exact(a, b, c)


def test_weighted_filter_agrees_with_fractions():
    rng = np.random.default_rng(11)
    P = rng.integers(-4, 5, (800, 2)).astype(float) * 0.5 + rng.choice([0.0, 1e7], (800, 1))
    w = rng.integers(-3, 4, 800) * 0.25 + rng.choice([0.0, 2.0 ** -40], 800)
    q = np.arange(800).reshape(200, 4)
    s = _incircle_signs(P, w, _Lazy(P, w), q[:, 0], q[:, 1], q[:, 2], q[:, 3], {})
    for j in range(200):
        F = [(Fraction(x), Fraction(y), Fraction(x) ** 2 + Fraction(y) ** 2 - Fraction(ww))
             for (x, y), ww in zip(P[q[j]], w[q[j]])]
        (ax, ay, az), (bx, by, bz), (cx, cy, cz), (dx, dy, dz) = F
        m = [[ax - dx, ay - dy, az - dz], [bx - dx, by - dy, bz - dz], [cx - dx, cy - dy, cz - dz]]
        det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
               - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
               + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
        assert s[j] == (det > 0) - (det < 0), j
    assert (s > 0).any() and (s < 0).any()


def test_weighted_regular_triangulation():
    w = np.array([0.5, 0.0, 0.5, 0.0])      # lifting lowers vertices 0 and 2
    assert_valid(SQUARE, [(0, 1, 2), (0, 2, 3)], weights=w)
    rep = check_triangulation(SQUARE, [(0, 1, 3), (1, 2, 3)], weights=w)
    assert rep.kinds == {"not_regular": 1}
    # with zero weights both are fine (tie), exactly like the unweighted test
    rep = assert_valid(SQUARE, [(0, 1, 3), (1, 2, 3)], weights=np.zeros(4))
    assert rep.counts["cocircular_ties"] == 1


def test_weighted_submerged_vertex():
    P = np.vstack([SQUARE, [[0.5, 0.5]]])
    w = np.array([0.0, 0.0, 0.0, 0.0, -1.0])       # centre lifted far up: not a vertex
    assert_valid(P, [(0, 1, 2), (0, 2, 3)], weights=w, submerged=[4])
    rep = check_triangulation(P, [(0, 1, 2), (0, 2, 3)], weights=w)
    assert rep.kinds == {"unused_vertex": 1}
    # with a large weight the centre point is NOT submerged: leaving it out is an error
    w[4] = 1.0
    rep = check_triangulation(P, [(0, 1, 2), (0, 2, 3)], weights=w, submerged=[4])
    assert rep.kinds == {"not_submerged": 1}
    # a submerged point outside the hull is an error too
    Q = np.vstack([SQUARE, [[2.0, 2.0]]])
    rep = check_triangulation(Q, [(0, 1, 2), (0, 2, 3)], weights=np.zeros(5), submerged=[4])
    assert rep.kinds == {"submerged_outside": 1}


def test_constrained_delaunay_segment_exempts_edge():
    P = np.array([[0.0, 0.0], [2.0, -0.2], [4.0, 0.0], [2.0, 0.2]])
    # a flat kite: its long diagonal (0, 2) is not Delaunay ...
    bad = [(0, 1, 2), (0, 2, 3)]
    assert check_triangulation(P, bad).kinds == {"not_delaunay": 1}
    # ... but is legal as a segment (Lemma 2.14)
    rep = assert_valid(P, bad, segments=[(0, 2)])
    assert rep.counts["delaunay_checked_edges"] == 0


def test_segment_split_into_collinear_pieces():
    P = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, -1.0]])
    T = [(0, 1, 3), (1, 2, 3), (0, 4, 1), (1, 4, 2)]
    rep = assert_valid(P, T, segments=[(0, 2), (3, 1)])
    assert rep.counts["segments_split"] == 1


def test_domain_segments_annulus():
    outer = [(0, 0), (3, 0), (3, 3), (0, 3)]
    inner = [(1, 1), (2, 1), (2, 2), (1, 2)]
    P = np.array(outer + inner, dtype=float)
    T = [(0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    segs = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4)]
    assert_valid(P, T, segments=segs, domain="segments")
    # as a hull triangulation the hole is an error
    assert "boundary_not_hull" in check_triangulation(P, T, segments=segs).kinds
    # dropping the inner loop's segments leaves boundary edges that are no segments
    rep = check_triangulation(P, T, segments=segs[:4], domain="segments")
    assert rep.kinds.get("boundary_not_segment") == 4


def test_collinear_edges():
    P = np.array([[2.0, 1.0], [0.0, 0.0], [4.0, 2.0], [1.0, 0.5]])
    assert check_collinear_edges(P, [(1, 3), (3, 0), (0, 2)]).ok
    assert check_collinear_edges(P, [(3, 1), (2, 0), (0, 3)]).ok
    rep = check_collinear_edges(P, [(1, 3), (3, 2)])
    assert {"missing_edge", "extra_edge"} <= set(rep.kinds)
    Q = P.copy()
    Q[3, 1] = np.nextafter(0.5, 1.0)
    assert "not_collinear" in check_collinear_edges(Q, [(1, 3), (3, 0), (0, 2)]).kinds
    assert check_collinear_edges(P[:1], np.zeros((0, 2), int)).ok


# ----------------------------------------------------------------------------------------
# defects are reported
# ----------------------------------------------------------------------------------------

def _interior_triangle(P, T):
    """Index of a triangle none of whose vertices lies on the convex hull."""
    hull = set(Delaunay(P).convex_hull.ravel().tolist())
    for t, tri in enumerate(T):
        if not hull & set(tri.tolist()):
            return t
    raise AssertionError("no interior triangle")


def test_clockwise_triangle(random_delaunay):
    P, T = random_delaunay
    T = T.copy()
    T[5] = T[5][[0, 2, 1]]
    rep = check_triangulation(P, T)
    assert not rep.ok
    assert rep.kinds["orientation"] == 1
    assert any("triangle 5" in p and "clockwise" in p for p in rep.problems)
    with pytest.raises(AssertionError, match="clockwise"):
        assert_valid(P, T)


def test_degenerate_triangle():
    P = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    rep = check_triangulation(P, [(0, 1, 3), (1, 2, 3), (0, 2, 1)])
    assert "degenerate" in " ".join(rep.problems)


def test_missing_triangle_hole(random_delaunay):
    P, T = random_delaunay
    t = _interior_triangle(P, T)
    rep = check_triangulation(P, np.delete(T, t, axis=0))
    assert rep.kinds.get("boundary_not_hull") == 3
    assert "area" in rep.kinds
    assert "unused_vertex" not in rep.kinds


def test_hull_not_covered(random_delaunay):
    P, T = random_delaunay
    # remove a triangle with a hull edge whose three vertices stay used
    hull_edges = {frozenset(e) for e in Delaunay(P).convex_hull.tolist()}
    for t, tri in enumerate(T.tolist()):
        edges = [frozenset((tri[i], tri[(i + 1) % 3])) for i in range(3)]
        if sum(e in hull_edges for e in edges) == 1:
            break
    rep = check_triangulation(P, np.delete(T, t, axis=0))
    assert rep.kinds.get("hull_not_covered") == 1
    assert rep.kinds.get("boundary_not_hull") == 2
    assert "area" in rep.kinds


def test_overlapping_extra_triangle(random_delaunay):
    P, T = random_delaunay
    t = _interior_triangle(P, T)
    a, b, c = T[t]
    # a triangle on edge (a, b) lying on the same side as c overlaps triangle t
    others = [i for i in range(len(P)) if i not in (a, b, c)]
    d = next(i for i in others if orient2d_exact(P[a], P[b], P[i]) > 0)
    rep = check_triangulation(P, np.vstack([T, [(a, b, d)]]))
    assert not rep.ok
    assert "edge_orientation" in rep.kinds
    assert "area" in rep.kinds


def test_duplicate_triangle(random_delaunay):
    P, T = random_delaunay
    rep = check_triangulation(P, np.vstack([T, T[3:4, [1, 2, 0]]]))
    assert rep.kinds.get("duplicate_triangle") == 1


def test_non_delaunay_edge_flipped_diagonal():
    rng = np.random.default_rng(3)
    while True:
        P = rng.random((4, 2))
        d = Delaunay(P)
        if len(d.simplices) == 2:
            break
    T = ccw(P, d.simplices)
    assert_valid(P, T)
    shared = sorted(set(T[0]) & set(T[1]))
    other = sorted(set(T[0]) ^ set(T[1]))
    flipped = ccw(P, [(shared[0], other[0], other[1]), (shared[1], other[0], other[1])])
    rep = check_triangulation(P, flipped)
    assert rep.kinds == {"not_delaunay": 1}
    assert f"({min(other)}, {max(other)})" in rep.problems[0] or \
        f"({max(other)}, {min(other)})" in rep.problems[0]


def test_non_delaunay_in_big_triangulation(random_delaunay):
    P, T = random_delaunay
    T = [tuple(t) for t in T.tolist()]
    # flip one interior edge
    edges = {}
    for i, t in enumerate(T):
        for k in range(3):
            edges.setdefault(frozenset((t[k], t[(k + 1) % 3])), []).append(i)
    for e, ts in edges.items():
        if len(ts) == 2:
            u, v = sorted(e)
            p = (set(T[ts[0]]) - e).pop()
            q = (set(T[ts[1]]) - e).pop()
            # flippable only if the quadrilateral is convex
            if orient2d_exact(P[p], P[q], P[u]) * orient2d_exact(P[p], P[q], P[v]) < 0:
                break
    new = [t for i, t in enumerate(T) if i not in ts] + [(p, q, u), (p, q, v)]
    rep = check_triangulation(P, ccw(P, new))
    assert rep.kinds == {"not_delaunay": 1}


def test_missing_segment(random_delaunay):
    P, T = random_delaunay
    t0, t1 = T[0], T[-1]
    edges = {frozenset((t[k], t[(k + 1) % 3])) for t in T.tolist() for k in range(3)}
    a = int(t0[0])
    b = next(int(v) for v in range(len(P)) if v != a and frozenset((a, v)) not in edges)
    rep = check_triangulation(P, T, segments=[(int(t1[0]), int(t1[1])), (a, b)])
    assert rep.kinds == {"missing_segment": 1}
    assert f"segment 1 ({a}, {b})" in rep.problems[0]


def test_unused_vertex(random_delaunay):
    P, T = random_delaunay
    P2 = np.vstack([P, [[0.5, 0.5]]])         # inside the hull, used by nothing
    rep = check_triangulation(P2, T)
    assert rep.kinds == {"unused_vertex": 1}
    assert "vertex 300" in rep.problems[0]
    assert check_triangulation(P2, T, require_all_vertices=False).ok
    assert check_triangulation(P2, T, submerged=[300]).ok
    rep = check_triangulation(P, T, submerged=[int(T[0, 0])])
    assert "submerged_used" in rep.kinds


def test_nonmanifold_vertex_bowtie():
    P = np.array([[0.0, 0.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    rep = check_triangulation(P, [(0, 1, 2), (0, 3, 4)])
    assert "nonmanifold_vertex" in rep.kinds
    assert any("vertex 0" in p for p in rep.problems)
    # a domain bounded by segments may pinch at a vertex (a hole touching its
    # shell): allowed there; callers check such results against the whole hull
    rep = check_triangulation(P, [(0, 1, 2), (0, 3, 4)], domain="segments",
                              segments=[(0, 1), (1, 2), (2, 0), (0, 3), (3, 4), (4, 0)])
    assert rep.ok


def test_nonmanifold_vertex_fan_plus_extra_triangle():
    P = np.array([[0.0, 0.0], [1.0, 0.0], [-1.0, 1.0], [-1.0, -1.0], [2.0, 1.0], [1.0, 2.0]])
    T = [(0, 1, 2), (0, 2, 3), (0, 3, 1), (0, 4, 5)]
    rep = check_triangulation(P, T, require_all_vertices=False)
    assert rep.kinds.get("nonmanifold_vertex") == 1
    assert "vertex 0" in " ".join(rep.problems) and "2 components" in " ".join(rep.problems)
    assert "area" in rep.kinds


def test_coincident_vertices():
    P = np.vstack([SQUARE, [[1.0, 1.0]]])
    rep = check_triangulation(P, [(0, 1, 2), (0, 4, 3)])
    assert "coincident_vertices" in rep.kinds


def test_bad_indices():
    rep = check_triangulation(SQUARE, [(0, 1, 7)])
    assert rep.kinds == {"index": 1}
    rep = check_triangulation(SQUARE, [(0, 1, 1)])
    assert rep.kinds == {"index": 1}
    rep = check_triangulation(np.array([[0.0, np.nan]]), np.zeros((0, 3), int))
    assert rep.kinds == {"input": 1}


def test_many_problems_are_capped():
    P, T = grid(20, 20)
    rep = check_triangulation(P, T[:, [0, 2, 1]])
    assert rep.kinds["orientation"] == len(T)
    assert len([p for p in rep.problems if p.startswith("[orientation]")]) <= 26


def test_checker_is_fast_enough():
    """~70k triangles must be checked in a couple of seconds."""
    import time
    P, T = grid(190, 190, offset=1e5)
    t = time.perf_counter()
    rep = check_triangulation(P, T)
    assert rep.ok, rep
    assert len(T) > 70_000
    assert time.perf_counter() - t < 10.0


# ----------------------------------------------------------------------------------------
# real constrained Delaunay triangulations (Shewchuk's Triangle) on corpus inputs
# ----------------------------------------------------------------------------------------

TRIANGLE_POLYS = ["A.poly", "face.poly", "la.poly", "double_hex.poly", "double_hex2.poly",
                  "square_circle_hole.poly"]


@pytest.mark.parametrize("name", TRIANGLE_POLYS)
def test_triangle_package_cdts_pass(name):
    triangle = pytest.importorskip("triangle")
    import corpus
    if not (corpus.corpus_dir() / "triangle" / name).exists():
        pytest.skip("corpus not available")
    (plc,) = corpus.load("triangle/" + name)
    d = {"vertices": plc.vertices, "segments": plc.segments}
    # -pc without holes: a CDT of the whole convex hull
    out = triangle.triangulate(d, "pc")
    assert len(out["vertices"]) == len(plc.vertices)
    assert_valid(out["vertices"], out["triangles"], segments=plc.segments)
    # -p with the file's hole points: the domain is bounded by segments
    if len(plc.holes):
        d["holes"] = plc.holes
    out = triangle.triangulate(d, "p")
    assert_valid(out["vertices"], out["triangles"], segments=plc.segments, domain="segments",
                 require_all_vertices=False)
    if len(plc.holes):
        # ... and is not a triangulation of the convex hull
        rep = check_triangulation(out["vertices"], out["triangles"], segments=plc.segments)
        assert "boundary_not_hull" in rep.kinds and "area" in rep.kinds


def test_degenerate_integer_point_sets_triangle_and_hull():
    """Small integer point sets (many collinear and cocircular points): Triangle's Delaunay
    triangulation passes, and the exact hull keeps exactly the boundary points."""
    triangle = pytest.importorskip("triangle")
    from scipy.spatial import ConvexHull
    from checker import _convex_hull
    rng = np.random.default_rng(5)
    done = 0
    while done < 60:
        P = np.unique(rng.integers(0, rng.integers(3, 8), (rng.integers(4, 40), 2)), axis=0)
        P = P.astype(float)
        if len(P) < 3 or np.linalg.matrix_rank(P[1:] - P[0]) < 2:
            continue
        done += 1
        out = triangle.triangulate({"vertices": P}, "")
        assert_valid(out["vertices"], out["triangles"])
        hull = _convex_hull(P, np.arange(len(P)), _Lazy(P, None), {})
        on = set()
        for a, b in ConvexHull(P).simplices:
            lo, hi = np.minimum(P[a], P[b]), np.maximum(P[a], P[b])
            for i in range(len(P)):
                if orient2d_exact(P[a], P[b], P[i]) == 0 and (lo <= P[i]).all() and (P[i] <= hi).all():
                    on.add(i)
        assert sorted(hull) == sorted(on)


def test_partial_segment_chains_are_checked_for_order_and_overlap():
    from checker import check_steiner_segments
    P = np.array([[0, 0], [4, 0.0]])
    V = np.array([[0, 0], [4, 0], [1, 0], [2, 0], [3, 0], [2, 1.0]])
    vm = np.array([0, 1])
    S = [[0, 1]]

    def report(pieces, partial=True):
        return check_steiner_segments(P, S, V, vm, np.array(pieces), np.zeros(len(pieces), int),
                                      partial=partial)

    assert report([[0, 2], [3, 4]]).ok                    # a gap where the domain ends
    assert report([]).ok                                  # wholly outside the domain
    assert not report([[0, 2], [3, 4]], partial=False).ok  # the full chain is required otherwise
    assert not report([[0, 3], [2, 4]]).ok                # overlapping pieces
    assert not report([[0, 5]]).ok                        # off the segment
