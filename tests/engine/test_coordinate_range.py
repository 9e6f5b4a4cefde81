"""Every finite double, or a named error (issue: reliability, coordinates).

The engine scales its input by a power of two into the exact predicates'
range, so the result is the same at any scale: the same triangles, and the
Steiner points scaled by the same power of two. Inputs whose magnitudes span
more than the predicates support raise :class:`CoordinateRangeError` naming the
rows. Every result is checked by the independent exact checker, at its own
scale."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import CoordinateRangeError
from cdt_plugin.report import mesh_report
from checker import check_steiner_segments, check_triangulation
from helpers import verify

P200 = np.random.default_rng(0).random((200, 2))
GRID = np.array([[i, j] for i in range(6) for j in range(6)], float)   # cocircular everywhere
SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1.5], [3, 3], [1, 3]]
RINGS = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
# exponents over the whole range of doubles (P200 has bits down to 2**-53, so
# P200 * 2**e is exact for e >= -1021)
EXPONENTS = [-1021, -900, -560, -300, -264, -256, -100, 0, 100, 256, 264, 300, 560, 900, 1022]


def _mixed():
    return np.vstack([P200[:40], [[1e-300, 1e-300], [1e300, 1e300], [-1e300, 1e300]]])


def _verify_cdt(vertices, segments, tri):
    """Exact check of a constrained result: valid, constrained Delaunay, every
    segment made of pieces on it."""
    V, T = tri.vertices, tri.triangles
    edges = {frozenset(e) for t in T.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    inside = np.array([frozenset(p) in edges for p in tri.segments.tolist()], bool)
    rep = check_triangulation(V, T, segments=tri.segments[inside].reshape(-1, 2), domain="segments",
                              require_all_vertices=False)
    assert rep.ok, str(rep)
    rep = check_steiner_segments(np.asarray(vertices, float), segments, V, tri.vertex_map,
                                 tri.segments, tri.segment_ids)
    assert rep.ok, str(rep)
    assert tri.is_delaunay()
    assert np.array_equal(V[tri.vertex_map], np.asarray(vertices, float))


# ------------------------------------------------------------------ Delaunay
@pytest.mark.parametrize("e", EXPONENTS)
@pytest.mark.parametrize("algorithm", ["divide", "incremental", "flip"])
def test_delaunay_is_the_same_at_every_scale(e, algorithm):
    base = cdt_plugin.delaunay(P200, algorithm=algorithm)
    pts = P200 * 2.0 ** e
    tri = cdt_plugin.delaunay(pts, algorithm=algorithm)
    assert np.array_equal(tri.triangles, base.triangles)
    assert np.array_equal(tri.vertices, pts)
    assert tri.is_delaunay() and tri.is_unique()
    verify(pts, tri)


@pytest.mark.parametrize("e", [-1074, -1060, -600, 0, 600, 1020])
def test_cocircular_grid_at_every_scale_including_subnormals(e):
    # integer points times 2**-1074 are subnormal doubles, exactly
    base = cdt_plugin.delaunay(GRID)
    pts = GRID * 2.0 ** e
    tri = cdt_plugin.delaunay(pts)
    assert np.array_equal(tri.triangles, base.triangles)
    assert not tri.is_unique() and tri.is_delaunay()
    verify(pts, tri)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(-50, 50), st.integers(-50, 50)), min_size=3, max_size=40),
       st.integers(-1074, 1017), st.sampled_from(["divide", "incremental"]))
def test_hypothesis_integer_points_scaled_anywhere(coords, e, algorithm):
    pts = np.array(coords, float)
    scaled = pts * 2.0 ** e            # exact: |coordinates| <= 50 < 2**6, bits >= 2**-1074
    base = cdt_plugin.delaunay(pts, algorithm=algorithm)
    tri = cdt_plugin.delaunay(scaled, algorithm=algorithm)
    assert np.array_equal(tri.triangles, base.triangles)
    assert np.array_equal(tri.vertex_map, base.vertex_map)
    verify(scaled, tri)


@pytest.mark.parametrize("e", [-500, -200, 200, 500])
def test_weighted_delaunay_scales_weights_by_the_square(e):
    w = np.random.default_rng(1).random(200) * 0.01
    base = cdt_plugin.delaunay(P200, w)
    pts, wts = P200 * 2.0 ** e, w * 4.0 ** e
    tri = cdt_plugin.delaunay(pts, wts)
    assert np.array_equal(tri.triangles, base.triangles)
    assert np.array_equal(tri.vertex_map, base.vertex_map)
    assert tri.is_delaunay()
    verify(pts, tri, wts, exact_submerged=False)


@pytest.mark.parametrize("algorithm", ["divide", "incremental", "flip"])
def test_magnitudes_beyond_the_span_raise_naming_the_rows(algorithm):
    # (incremental insertion crashed the process on this input)
    with pytest.raises(CoordinateRangeError, match=r"row 41 \(1e\+300, 1e\+300\).*row 40 \(1e-300") as err:
        cdt_plugin.delaunay(_mixed(), algorithm=algorithm)
    assert err.value.rows == (41, 40)


def test_weights_beyond_the_span_raise():
    w = np.zeros(len(P200))
    w[7] = 1e-300
    with pytest.raises(CoordinateRangeError, match=r"row 7 .*weight"):
        cdt_plugin.delaunay(P200, w)


def test_the_span_limit_is_2_to_the_480():
    # 2**240 beside an odd multiple of 2**-240 fits; one more bit does not
    fits = np.array([[0.0, 0.0], [2.0 ** 239, 0.0], [0.0, 2.0 ** 239], [2.0 ** -240, 2.0 ** -240]])
    verify(fits, cdt_plugin.delaunay(fits))
    with pytest.raises(CoordinateRangeError):
        cdt_plugin.delaunay(fits * [[1.0, 1.0], [2.0, 1.0], [1.0, 1.0], [1.0, 1.0]])


def test_move_vertices_far_away_and_out_of_range():
    tri = cdt_plugin.delaunay(P200)
    moved = P200 * 1e300
    assert tri.move_vertices(moved) == 0          # same shape: no flip needed
    assert np.array_equal(tri.triangles, cdt_plugin.delaunay(moved).triangles)
    verify(moved, tri)
    before = tri.triangles.copy()
    bad = moved.copy()
    bad[3] = [1e-300, 1e-300]
    with pytest.raises(CoordinateRangeError, match="new_vertices"):
        tri.move_vertices(bad)
    assert np.array_equal(tri.triangles, before) and np.array_equal(tri.vertices, moved)


# ------------------------------------------------------------ constrained
@pytest.mark.parametrize("e", [-1000, -600, -264, 0, 264, 600, 1000])
def test_constrained_with_holes_is_the_same_at_every_scale(e):
    s = 2.0 ** e
    base = cdt_plugin.triangulate(SQUARE, RINGS)
    v = np.array(SQUARE) * s
    tri = cdt_plugin.triangulate(v, RINGS)
    assert np.array_equal(tri.triangles, base.triangles)
    _verify_cdt(v, RINGS, tri)
    seeded = cdt_plugin.triangulate(v, RINGS, holes=[[2 * s, 2.2 * s]])
    assert np.array_equal(seeded.triangles, base.triangles)


def test_a_seed_far_outside_marks_nothing():
    # a hole seed at (1e300, -1e300) removed an annulus (orient2d overflowed)
    base = cdt_plugin.triangulate(SQUARE, RINGS, holes=[[2, 2.2]])
    far = cdt_plugin.triangulate(SQUARE, RINGS, holes=[[2, 2.2], [1e300, -1e300], [-1e308, 5e-324]])
    assert np.array_equal(far.triangles, base.triangles)
    regions = cdt_plugin.triangulate(SQUARE, RINGS, regions=[[0.5, 0.5, 1, 0], [1e300, -1e300, 2, 0]])
    assert set(regions.regions.tolist()) == {0, -1} or set(regions.regions.tolist()) == {0}


@pytest.mark.parametrize("e", [-1000, -400, 400, 1000])
def test_crossings_split_at_every_scale(e):
    v = [[0, 0], [10, 3], [0, 3], [10, 0], [5, -2], [5, 7]]
    segs = [[0, 1], [2, 3], [4, 5]]
    base = cdt_plugin.triangulate(v, segs, intersections="split", keep_hull=True)
    s = 2.0 ** e
    tri = cdt_plugin.triangulate(np.array(v, float) * s, segs, intersections="split", keep_hull=True)
    assert np.array_equal(tri.vertices, base.vertices * s)       # crossings scaled exactly
    assert np.array_equal(tri.triangles, base.triangles)
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull")
    assert rep.ok, str(rep)


@pytest.mark.parametrize("e", [-1010, -600, 0, 600, 1000])
def test_refinement_is_the_same_at_every_scale(e):
    s = 2.0 ** e
    area = 0.05 if abs(e) < 500 else None     # an area bound in range at this scale
    base = cdt_plugin.triangulate(SQUARE, RINGS, min_angle=30, max_area=area)
    v = np.array(SQUARE) * s
    tri = cdt_plugin.triangulate(v, RINGS, min_angle=30, max_area=None if area is None else area * s * s)
    assert len(tri.steiner) > 0
    assert np.array_equal(tri.vertices, base.vertices * s)      # Steiner points scaled exactly
    assert np.array_equal(tri.triangles, base.triangles)
    _verify_cdt(v, RINGS, tri)
    rep = tri.report()
    assert rep.min_angle == pytest.approx(base.report().min_angle, rel=1e-12)
    assert rep.non_delaunay_edges == 0


def test_triangulate_beyond_the_span_raises_naming_the_rows():
    v = np.vstack([SQUARE, [[2, 1e-200]]])
    with pytest.raises(CoordinateRangeError, match=r"vertices .*row 8"):
        cdt_plugin.triangulate(v * 1e100, RINGS)
    with pytest.raises(CoordinateRangeError):
        cdt_plugin.triangulate(v * 1e100, RINGS, intersections="split", min_angle=20)


def test_batch_reports_the_geometry_out_of_range():
    shapely = pytest.importorskip("shapely")
    from cdt_plugin.adapters.shapely import triangulate_batch
    ok = shapely.box(0, 0, 1e300, 1e300)
    bad = shapely.Polygon([(0, 0), (1e300, 0), (1e300, 1e300), (1e-300, 1e300)])
    out = triangulate_batch([ok, bad, shapely.box(0, 0, 1e-300, 1e-300)], errors="skip")
    assert isinstance(out.errors[1], CoordinateRangeError)
    assert set(out.errors) == {1}
    with pytest.raises(CoordinateRangeError):
        triangulate_batch([ok, bad])


# ------------------------------------------------------------ certificates
def test_report_of_a_foreign_mesh_at_extreme_scales():
    V = np.array([[0, 0], [4, 0], [4, 1], [0, 1]], float)
    T = [[0, 1, 2], [0, 2, 3]]
    base = mesh_report(V, T)
    for s in (2.0 ** -1060, 2.0 ** 1000):
        rep = mesh_report(V * s, T)
        assert (rep.non_delaunay_edges, rep.cocircular_edges) == (base.non_delaunay_edges,
                                                                 base.cocircular_edges)
        assert rep.min_angle == pytest.approx(base.min_angle, rel=1e-12)
        assert rep.max_circumradius == pytest.approx(base.max_circumradius * s, rel=1e-12)
    with pytest.raises(CoordinateRangeError, match="mesh vertices"):
        mesh_report(np.vstack([V, [[1e-300, 1e300]]]), T + [[0, 3, 4]])


@pytest.mark.parametrize("s", [2.0 ** -1000, 1.0, 2.0 ** 900])
def test_z_of_steiner_points_at_every_scale(s):
    from cdt_plugin.lift import lift_z
    v = np.array([[0, 0], [3, 0], [3, 1], [0, 1]], float) * s
    segs = [[0, 1], [1, 2], [2, 3], [3, 0]]
    z = np.array([0.0, 3.0, 4.0, 1.0])          # the plane z = x + y (in units of s)
    tri = cdt_plugin.triangulate(v, segs, min_angle=30)
    lifted = lift_z(tri, z, segs)
    assert len(tri.steiner) and not np.isnan(lifted).any()
    assert np.allclose(lifted, (tri.vertices[:, 0] + tri.vertices[:, 1]) / s, rtol=1e-12, atol=1e-12)
