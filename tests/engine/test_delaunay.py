"""Engine tests for cdt_plugin.delaunay: every result goes through the exact checker."""
from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError, NonFiniteCoordinateError, TooFewPointsError
from checker import canonical_triangles
from helpers import verify

rng = np.random.default_rng(20261122)


def both_routes(points, **kw):
    """Triangulate by the default route (divide and conquer), incremental
    insertion and the flip algorithm, verify all, check they agree; return the
    default and the flip result."""
    a = cdt_plugin.delaunay(points, **kw)
    b = cdt_plugin.delaunay(points, algorithm="flip", **kw)
    c = cdt_plugin.delaunay(points, algorithm="incremental", **kw)
    for t in (a, b, c):
        verify(points, t)
    want = canonical_triangles(a.vertices, a.triangles)
    assert want == canonical_triangles(b.vertices, b.triangles)
    assert want == canonical_triangles(c.vertices, c.triangles)
    return a, b


def shuffled_same(points, tri, seeds=(1, 2)):
    """The triangles as coordinate triples do not depend on the input order."""
    want = canonical_triangles(tri.vertices, tri.triangles)
    for s in seeds:
        perm = np.random.default_rng(s).permutation(len(points))
        other = cdt_plugin.delaunay(np.asarray(points)[perm], seed=s)
        assert canonical_triangles(other.vertices, other.triangles) == want


# ----------------------------------------------------------------- generic input
@pytest.mark.parametrize("n", [3, 4, 10, 100, 2000])
def test_random_points(n):
    p = rng.random((n, 2))
    a, b = both_routes(p)
    assert a.is_delaunay() and a.is_unique()
    assert len(a.triangles) == a.stats["triangles"]
    assert b.stats["flips"] > 0 or n <= 4


def test_matches_scipy_on_generic_points():
    from scipy.spatial import Delaunay
    p = rng.random((3000, 2))
    tri = cdt_plugin.delaunay(p)
    ours = set(map(tuple, np.sort(tri.triangles, axis=1)))
    theirs = set(map(tuple, np.sort(Delaunay(p).simplices, axis=1)))
    assert ours == theirs


def test_triangles_are_counter_clockwise_and_edges_listed_once():
    p = rng.random((500, 2))
    tri = cdt_plugin.delaunay(p)
    v, t = tri.vertices, tri.triangles
    area2 = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    assert (area2 > 0).all()
    e = np.sort(tri.edges, axis=1)
    assert len(np.unique(e, axis=0)) == len(e)
    # Euler: V - E + F = 1 for a triangulated disk
    assert len(v) - len(e) + len(t) == 1


# ------------------------------------------------------------- degenerate input
def test_grid_is_cocircular_but_deterministic():
    g = np.stack(np.meshgrid(np.arange(25.0), np.arange(17.0)), -1).reshape(-1, 2)
    a, _ = both_routes(g)
    assert not a.is_unique()
    assert len(a.triangles) == 2 * 24 * 16
    shuffled_same(g, a)


def test_cocircular_integer_ring():
    # all integer points on x^2 + y^2 = 25^2 (exactly cocircular) plus the centre
    r = 25
    ring = [(x, y) for x in range(-r, r + 1) for y in range(-r, r + 1) if x * x + y * y == r * r]
    pts = np.array(ring + [(0, 0)], float) + 1e6
    a, _ = both_routes(pts)
    shuffled_same(pts, a)
    ring_only = np.array(ring, float)
    b, _ = both_routes(ring_only)
    assert not b.is_unique()
    shuffled_same(ring_only, b)


def test_regular_polygon_near_cocircular():
    k = np.arange(64) * 2 * np.pi / 64
    p = np.column_stack([np.cos(k), np.sin(k)]) * 3.0
    a, _ = both_routes(p)
    shuffled_same(p, a)


def test_duplicates_are_merged_and_mapped():
    p = np.array([[0, 0], [1, 0], [0, 1], [1, 0], [1, 1], [0, 0], [1, 1]], float)
    tri = cdt_plugin.delaunay(p)
    verify(p, tri)
    assert tri.vertex_map.tolist() == [0, 1, 2, 1, 3, 0, 3]
    assert tri.stats["duplicates"] == 3
    assert len(tri.vertices) == 4


def test_many_duplicates_random():
    base = rng.random((300, 2))
    p = base[rng.integers(0, 300, 3000)]
    tri = cdt_plugin.delaunay(p)
    verify(p, tri)
    assert len(tri.vertices) == len(np.unique(p, axis=0))


@pytest.mark.parametrize("pts,nedges", [
    ([[0, 0]], 0),
    ([[0, 0], [0, 0]], 0),
    ([[0, 0], [1, 2]], 1),
    ([[0, 0], [2, 2], [1, 1], [3, 3], [1, 1]], 3),
    ([[5, 1], [5, -3], [5, 0.5], [5, 7]], 3),
])
def test_collinear_gives_edges_and_no_triangles(pts, nedges):
    tri = cdt_plugin.delaunay(pts)
    assert tri.triangles.shape == (0, 3)
    assert len(tri.edges) == nedges
    verify(pts, tri)


def test_collinear_then_one_point_off_the_line():
    line = np.column_stack([np.arange(50.0), np.arange(50.0) * 0.5])
    p = np.vstack([line[rng.permutation(50)], [[10.0, 30.0]]])
    a, _ = both_routes(p)
    assert len(a.triangles) == 49


def test_collinear_hull_points_are_kept():
    # points on the edges of a square: all must be hull vertices
    t = np.linspace(0, 1, 11)
    sq = np.vstack([np.column_stack([t, 0 * t]), np.column_stack([t, 0 * t + 1]),
                    np.column_stack([0 * t, t]), np.column_stack([0 * t + 1, t])])
    p = np.vstack([sq, rng.random((30, 2))])
    a, _ = both_routes(p)
    assert len(a.vertices) == len(np.unique(p, axis=0))


@pytest.mark.parametrize("offset", [1e6, 1e9, 1e12, 1e15])
def test_large_offsets(offset):
    # a small grid plus jitter of a few ulps, far from the origin
    g = np.stack(np.meshgrid(np.arange(8.0), np.arange(8.0)), -1).reshape(-1, 2)
    p = offset + g * (offset * 4e-16 if offset > 1e12 else 1.0)
    p = np.vstack([p, np.nextafter(p[::5], np.inf)])
    a, _ = both_routes(p)
    shuffled_same(p, a)


def test_tiny_coordinates():
    p = rng.random((200, 2)) * 1e-30
    both_routes(p)


def test_near_collinear_points():
    x = np.linspace(0.0, 1.0, 200)
    p = np.column_stack([x, 0.3 * x + 0.1])
    p[1::2, 1] = np.nextafter(p[1::2, 1], np.inf)
    p[2::4, 1] = np.nextafter(p[2::4, 1], -np.inf)
    a, _ = both_routes(p)
    assert len(a.triangles) > 0


# ------------------------------------------------------- divide and conquer
def _degenerate_sets():
    r = np.random.default_rng(7)
    g = np.array([(i, j) for i in range(40) for j in range(30)], float)
    ang = np.arange(720) * (2 * np.pi / 720)
    yield "grid", g
    yield "grid turned 45 degrees", np.c_[g[:, 0] - g[:, 1], g[:, 0] + g[:, 1]]
    yield "grid with duplicates", np.r_[g, g[::7]]
    yield "cocircular integer ring", np.array([(5, 0), (-5, 0), (0, 5), (0, -5), (3, 4), (4, 3), (-3, 4),
                                               (-4, 3), (3, -4), (4, -3), (-3, -4), (-4, -3)], float)
    yield "two crossing lines", np.r_[np.c_[np.arange(300.0), np.zeros(300)],
                                      np.c_[np.full(300, 150.0), np.arange(-150.0, 150.0)]]
    yield "vertical line and one point", np.r_[np.c_[np.zeros(500), np.arange(500.0)], [[1.0, 3.0]]]
    yield "circle", np.c_[np.cos(ang), np.sin(ang)]
    yield "snapped random, many ties", np.round(r.random((3000, 2)) * 32) / 32
    yield "offset 1e9", r.random((2000, 2)) + 1e9
    yield "clustered", np.r_[r.random((1000, 2)) * 1e-6, r.random((1000, 2)) * 1e6]
    # subproblems with most or all of their points on their hulls, whose ends
    # the horizontal cuts find by walking the hull (divide.hull_extreme)
    t = 2 * np.pi * (np.arange(5000) + r.uniform(-0.4, 0.4, 5000)) / 5000
    rad = 1 + 0.25 * np.sin(7 * t)
    yield "along a wavy closed curve", np.c_[rad * np.cos(t), rad * np.sin(t)]
    yield "three horizontal lines", np.c_[r.permutation(3000) % 1000, np.arange(3000) % 3].astype(float)
    yield "three vertical lines", np.c_[np.arange(3000) % 3, r.permutation(3000) % 1000].astype(float)


@pytest.mark.parametrize("name,points", list(_degenerate_sets()), ids=[n for n, _ in _degenerate_sets()])
def test_divide_and_conquer_matches_incremental(name, points):
    dc = cdt_plugin.delaunay(points, algorithm="divide")
    inc = cdt_plugin.delaunay(points, algorithm="incremental")
    assert dc.stats["algorithm"] == "divide" and inc.stats["algorithm"] == "incremental"
    verify(points, dc)
    assert canonical_triangles(dc.vertices, dc.triangles) == canonical_triangles(inc.vertices, inc.triangles)
    assert (dc.vertex_map == inc.vertex_map).all()


def test_auto_route_is_divide_unweighted_and_incremental_weighted():
    p = rng.random((50, 2))
    assert cdt_plugin.delaunay(p).stats["algorithm"] == "divide"
    assert cdt_plugin.delaunay(p, weights=np.zeros(50)).stats["algorithm"] == "incremental"
    with pytest.raises(CDTError, match="divide"):
        cdt_plugin.delaunay(p, weights=np.zeros(50), algorithm="divide")


# -------------------------------------------------------------- property tests
small_ints = st.integers(min_value=-4, max_value=4)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(small_ints, small_ints), min_size=1, max_size=40))
def test_hypothesis_integer_points(pts):
    p = np.array(pts, float)
    tri = cdt_plugin.delaunay(p)
    verify(p, tri)
    for algorithm in ("flip", "incremental"):
        other = cdt_plugin.delaunay(p, algorithm=algorithm)
        verify(p, other)
        assert canonical_triangles(tri.vertices, tri.triangles) == canonical_triangles(other.vertices, other.triangles)
    rev = cdt_plugin.delaunay(p[::-1])
    assert canonical_triangles(rev.vertices, rev.triangles) == canonical_triangles(tri.vertices, tri.triangles)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.0, 1e3, 5e5, 1e8]))
def test_hypothesis_snapped_random(seed, offset):
    r = np.random.default_rng(seed)
    p = np.round(r.random((int(r.integers(3, 120)), 2)) * 16) / 16 + offset
    tri = cdt_plugin.delaunay(p)
    verify(p, tri)


# ------------------------------------------------------------------- weighted
def test_zero_weights_equal_unweighted():
    p = rng.random((300, 2))
    a = cdt_plugin.delaunay(p)
    b = cdt_plugin.delaunay(p, weights=np.zeros(300))
    assert canonical_triangles(a.vertices, a.triangles) == canonical_triangles(b.vertices, b.triangles)
    assert b.is_delaunay()


@pytest.mark.parametrize("scale", [0.001, 0.01, 0.05])
def test_random_weights_submerge_points(scale):
    p = rng.random((400, 2))
    w = rng.random(400) * scale
    tri = cdt_plugin.delaunay(p, weights=w)
    verify(p, tri, w)
    assert tri.is_delaunay()
    if scale >= 0.01:
        assert len(tri.submerged) > 0
    assert (tri.vertex_map[tri.submerged] == -1).all()
    assert tri.stats["submerged"] == len(tri.submerged)


def test_weighted_matches_lower_hull_of_lifted_points():
    from scipy.spatial import ConvexHull
    p = rng.random((300, 2))
    w = rng.random(300) * 0.02
    tri = cdt_plugin.delaunay(p, weights=w)
    lifted = np.column_stack([p, (p ** 2).sum(1) - w])
    hull = ConvexHull(lifted)
    lower = hull.simplices[hull.equations[:, 2] < 0]
    assert set(np.flatnonzero(tri.vertex_map >= 0)) == set(np.unique(lower))


def test_weighted_duplicates_keep_the_heaviest():
    p = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5], [0.5, 0.5], [0.5, 0.5]], float)
    w = np.array([0, 0, 0, 0, 0.1, 0.3, 0.3])
    tri = cdt_plugin.delaunay(p, weights=w)
    verify(p, tri, w)
    assert tri.vertex_map[4] == -1
    assert tri.vertex_map[5] == tri.vertex_map[6] >= 0


def test_weighted_collinear_lower_chain():
    p = np.array([[0, 0], [1, 0], [2, 0], [3, 0]], float)
    w = np.array([0.0, -5.0, 0.0, 0.0])   # point 1 lifted far above: submerged
    tri = cdt_plugin.delaunay(p, weights=w)
    assert tri.vertex_map[1] == -1
    assert len(tri.edges) == 2


@settings(max_examples=80, deadline=None)
@given(st.lists(st.tuples(small_ints, small_ints, st.integers(-3, 3)), min_size=3, max_size=30))
def test_hypothesis_weighted_integer(rows):
    a = np.array(rows, float)
    p, w = a[:, :2], a[:, 2]
    tri = cdt_plugin.delaunay(p, weights=w)
    verify(p, tri, w)
    assert tri.is_delaunay()


# --------------------------------------------------------------- moving vertices
def test_move_vertices_restores_delaunay_with_flips():
    p = rng.random((500, 2))
    tri = cdt_plugin.delaunay(p)
    moved = tri.vertices + rng.normal(0, 1e-4, tri.vertices.shape)
    flips = tri.move_vertices(moved)
    assert not tri.stats["rebuilt"] and flips == tri.stats["move_flips"]
    verify(moved, tri)
    fresh = cdt_plugin.delaunay(moved)
    assert canonical_triangles(fresh.vertices, fresh.triangles) == canonical_triangles(tri.vertices, tri.triangles)


def test_move_repairs_a_hull_that_lost_its_convexity():
    k = np.arange(12) * 2 * np.pi / 12
    p = np.vstack([np.column_stack([np.cos(k), np.sin(k)]) * 10, [[0.0, 0.0], [1.0, 2.0]]])
    tri = cdt_plugin.delaunay(p)
    moved = tri.vertices.copy()
    moved[0] = [8.0, 0.0]  # a hull vertex moves inward: the hull is no longer convex
    flips = tri.move_vertices(moved)
    assert not tri.stats["rebuilt"] and flips >= 1
    verify(moved, tri)


def test_move_that_inverts_triangles_rebuilds_or_raises():
    p = rng.random((200, 2))
    tri = cdt_plugin.delaunay(p)
    moved = tri.vertices.copy()
    moved[:100] = moved[:100][::-1]   # swaps: inverts triangles
    with pytest.raises(cdt_plugin.InvertedTriangleError, match="inverts triangle"):
        tri.move_vertices(moved, rebuild=False)
    tri.move_vertices(moved)
    assert tri.stats["rebuilt"]
    verify(moved, tri)


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("bad,err,msg", [
    (np.empty((0, 2)), TooFewPointsError, "empty"),
    ([[0, 0], [1, np.nan]], NonFiniteCoordinateError, "row.*1"),
    ([[0, 0], [np.inf, 1], [2, 2]], NonFiniteCoordinateError, r"\(inf, 1.0\)"),
    (np.zeros((4, 3)), InputShapeError, r"\(n, 2\)"),
    ([1.0, 2.0], InputShapeError, r"\(n, 2\)"),
    ([["a", "b"]], InputShapeError, "float64"),
    ([[0, 0], [1, 0, 5], [0, 1]], InputShapeError, "row 1 has 3 entries, row 0 has 2"),
    ([[0, 0], 1, [0, 1]], InputShapeError, "rows of equal length"),
    (np.array([[0, 0], [1, 0], [0, 1 + 2j]]), InputShapeError, r"complex values \(imaginary parts at row\(s\) 2\)"),
])
def test_bad_points(bad, err, msg):
    with pytest.raises(err, match=msg):
        cdt_plugin.delaunay(bad)


def test_integers_beyond_2_53_are_rounded_with_a_warning():
    """int64 coordinates beyond 2**53 were rounded to float64 silently, and points
    that round together merged as duplicates without a word."""
    big = 2 ** 53
    pts = np.array([[big, 0], [big + 1, 0], [0, big], [big, big]], np.int64)
    with pytest.warns(cdt_plugin.PrecisionWarning, match=r"row\(s\) 1 .*9007199254740993 -> 9007199254740992.0"):
        tri = cdt_plugin.delaunay(pts)
    assert tri.vertex_map.tolist() == [0, 0, 1, 2]        # rows 0 and 1 are one float64 point
    verify(pts.astype(float), tri)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                    # exact integers: no warning
        cdt_plugin.delaunay(np.array([[big, 0], [big + 2, 0], [0, 1]], np.int64))
    with pytest.raises(InputShapeError, match="complex"):
        cdt_plugin.delaunay(rng.random((3, 2)), weights=np.array([0, 1j, 0]))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.one_of(
    st.lists(st.one_of(st.floats(-10, 10), st.integers(-2 ** 60, 2 ** 60), st.complex_numbers(max_magnitude=5),
                       st.text(max_size=2)), min_size=1, max_size=3),
    st.floats(-1, 1)), min_size=1, max_size=8))
def test_any_nested_input_meshes_or_raises_a_cdt_error(rows):
    """Ragged rows, complex numbers, strings, huge integers: a triangulation or a
    CDTError (with at most a PrecisionWarning), never numpy's own exception."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cdt_plugin.PrecisionWarning)
        try:
            tri = cdt_plugin.delaunay(rows)
        except CDTError:
            return
    verify(np.asarray(rows, float), tri)


def test_bad_options():
    with pytest.raises(InputShapeError, match="weights"):
        cdt_plugin.delaunay(rng.random((5, 2)), weights=[1, 2])
    with pytest.raises(NonFiniteCoordinateError, match="weights"):
        cdt_plugin.delaunay(rng.random((3, 2)), weights=[0, np.nan, 0])
    with pytest.raises(CDTError, match="algorithm"):
        cdt_plugin.delaunay(rng.random((5, 2)), algorithm="qhull")
    with pytest.raises(CDTError, match="flip"):
        cdt_plugin.delaunay(rng.random((5, 2)), weights=np.zeros(5), algorithm="flip")
    assert issubclass(CDTError, ValueError)


# ------------------------------------------------------------------- corpus
def corpus_point_sets():
    from corpus import iter_point_sets
    try:
        return [pytest.param(p, id=p.name) for p in iter_point_sets()
                if len(p.vertices) and not p.name.startswith("gis/")]
    except FileNotFoundError:
        return []


@pytest.mark.parametrize("plc", corpus_point_sets())
def test_corpus_point_sets(plc):
    tri = cdt_plugin.delaunay(plc.vertices)
    verify(plc.vertices, tri)


@pytest.mark.parametrize("n", [1, 7, 300, 2047, 2048, 5000])
def test_lexicographic_order_equals_lexsort(n):
    """Both paths of the lexicographic order (compiled below 2048 points, numpy's
    sort above) give np.lexsort's order: by x, then y, then input index."""
    from cdt_plugin._core.ordering import lexicographic_order
    r = np.random.default_rng(n)
    for x, y in ((r.integers(0, 6, n).astype(float), r.integers(0, 6, n).astype(float)),
                 (r.uniform(-1, 1, n), r.uniform(-1, 1, n)),
                 (np.zeros(n), r.integers(0, 3, n).astype(float))):
        assert np.array_equal(lexicographic_order(x, y), np.lexsort((np.arange(n), y, x)))


def test_move_vertices_that_change_the_hull_keeps_per_triangle_arrays_in_step():
    """Regression (found by fuzzing): a move that makes a hull vertex interior is
    repaired by flips and adds a triangle; the per-triangle arrays (constrained
    flags, regions) must follow, or is_delaunay() indexed past their end."""
    tri = cdt_plugin.delaunay([[0, 0], [1, -0.1], [2, 0], [1, 2]])
    assert len(tri.triangles) == 2
    new = [[0, -0.4], [1, -0.1], [2, 0], [1, 2]]
    assert tri.move_vertices(new) >= 1 and not tri.stats["rebuilt"]
    assert len(tri.triangles) == 3
    assert tri.constrained.shape == tri.triangles.shape and len(tri.regions) == 3
    assert tri.is_delaunay()
    verify(new, tri)


def test_neighbours_flags_and_regions_are_made_on_first_access():
    """A Delaunay result holds its triangles; the neighbours (as large again at
    a million points), constrained flags and regions are made from the kept
    store when first asked for, and a rebuild by move_vertices replaces any
    made before it."""
    p = rng.random((300, 2))
    tri = cdt_plugin.delaunay(p)
    assert not {"neighbors", "constrained", "regions"} & set(vars(tri))
    verify(p, tri)                                   # checks the neighbours
    assert tri.constrained.shape == tri.triangles.shape and not tri.constrained.any()
    assert (tri.regions == -1).all() and len(tri.regions) == len(tri.triangles)
    moved = tri.vertices.copy()
    moved[:150] = moved[:150][::-1]                  # inverts triangles: a rebuild
    tri.move_vertices(moved)
    assert tri.stats["rebuilt"]
    verify(moved, tri)
    assert len(tri.regions) == len(tri.constrained) == len(tri.triangles)
