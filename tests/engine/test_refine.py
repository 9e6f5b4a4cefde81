"""Quality meshing (Delaunay refinement, conforming Delaunay): every result is checked by
the exact checker (a constrained Delaunay triangulation of its own vertices and segment
pieces; every input segment the chain of its pieces, Steiner points on it up to rounding),
then against the bounds that were asked for."""
from __future__ import annotations

import glob
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import CDTError, RefinementLimitError
from checker import canonical_triangles, check_empty_circumcircles, check_steiner_segments, check_triangulation

CORPUS = os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "corpus")


def ring(n, start=0):
    return [[start + i, start + (i + 1) % n] for i in range(n)]


SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
HOLE = [[1, 1], [3, 1.5], [3, 3], [1, 3]]


def min_angles(V, T):
    P = V[T]
    out = []
    for j in range(3):   # angle at corner j from the two sides meeting there
        u = P[:, (j + 1) % 3] - P[:, j]
        w = P[:, (j + 2) % 3] - P[:, j]
        cross = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        out.append(np.degrees(np.arctan2(cross, (u * w).sum(axis=1))))
    return np.min(out, axis=0)


def areas(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2


def verify_refined(vertices, segments, tri, *, min_angle=None, max_area=None, domain="segments",
                   conforming=False, partial=False):
    """Exact checks plus the bounds. Returns the result for further asserts.
    ``partial``: some segments lie (partly) outside the domain, so only their
    pieces that border a triangle are listed."""
    V, T = tri.vertices, tri.triangles
    # the listed pieces are exactly the constrained edges of the kept triangles
    flagged = {frozenset((int(t[(j + 1) % 3]), int(t[(j + 2) % 3])))
               for t, c in zip(T.tolist(), tri.constrained.tolist()) for j in range(3) if c[j]}
    assert {frozenset(p) for p in tri.segments.tolist()} == flagged
    assert len(flagged) == len(tri.segments)
    rep = check_triangulation(V, T, segments=tri.segments, domain=domain,
                              require_all_vertices=False, exempt_segments=not conforming)
    assert rep.ok, str(rep)
    if segments is not None and len(segments):
        rep = check_steiner_segments(vertices, segments, V, tri.vertex_map, tri.segments,
                                     tri.segment_ids, partial=partial)
        assert rep.ok, str(rep)
    assert tri.is_delaunay()
    # input points kept exactly; Steiner points are the rest
    vm = tri.vertex_map
    assert np.array_equal(V[vm], np.asarray(vertices, float))
    assert set(tri.steiner.tolist()) == set(range(len(V))) - set(vm.tolist())
    assert tri.stats["refinement_complete"]
    if min_angle:
        below = min_angles(V, T) < min_angle * (1 - 1e-9)
        assert set(np.flatnonzero(below).tolist()) <= set(tri.below_min_angle.tolist())
        assert tri.stats["below_min_angle"] == len(tri.below_min_angle)
    if max_area:
        assert areas(V, T).max() <= max_area * (1 + 1e-12)
    if conforming:
        rep = check_empty_circumcircles(V, T)
        assert rep.ok, str(rep)
    return tri


def test_square_with_hole_min_angle():
    v = SQUARE + HOLE
    s = ring(4) + ring(4, 4)
    plain = cdt_plugin.triangulate(v, s)
    assert min_angles(plain.vertices, plain.triangles).min() < 20
    for angle in (20, 30, 33):
        tri = verify_refined(v, s, cdt_plugin.triangulate(v, s, min_angle=angle), min_angle=angle)
        assert tri.stats["below_min_angle"] == 0
        assert len(tri.steiner) > 0
    # the domain does not change: same area as the unrefined mesh
    assert areas(tri.vertices, tri.triangles).sum() == pytest.approx(areas(plain.vertices, plain.triangles).sum(), rel=1e-14)


def test_max_area_and_counts_grow():
    v = SQUARE + HOLE
    s = ring(4) + ring(4, 4)
    counts = []
    for area in (1.0, 0.1, 0.01):
        tri = verify_refined(v, s, cdt_plugin.triangulate(v, s, max_area=area), max_area=area)
        counts.append(len(tri.triangles))
    assert counts[0] < counts[1] < counts[2]
    assert counts[2] >= 12 / 0.01     # the area alone needs that many


def test_region_max_area():
    # two squares side by side, the right one with a 10x smaller area bound
    v = [[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]]
    s = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4]]
    regions = [[0.5, 0.5, 1, 0.01], [1.5, 0.5, 2, 0.001]]
    tri = cdt_plugin.triangulate(v, s, regions=regions, min_angle=25)
    verify_refined(v, s, tri, min_angle=25)
    a = areas(tri.vertices, tri.triangles)
    left, right = tri.regions == 0, tri.regions == 1
    assert left.any() and right.any() and (left | right).all()
    assert a[left].max() <= 0.01 and a[right].max() <= 0.001
    assert right.sum() > 5 * left.sum()
    # a global bound applies where a region gives none
    tri = cdt_plugin.triangulate(v, s, regions=[[0.5, 0.5, 1, 0], [1.5, 0.5, 2, 0.001]], max_area=0.05)
    a = areas(tri.vertices, tri.triangles)
    assert a[tri.regions == 0].max() <= 0.05 and a[tri.regions == 1].max() <= 0.001


def test_region_max_area_alone_refines():
    """A region seed's max_area did nothing unless max_area= or min_angle= was given
    too (the README's own example). It bounds its region on its own; a region
    without a bound, and the rest of the domain, are left as they are."""
    v = [[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]]
    s = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4]]
    tri = cdt_plugin.triangulate(v, s, regions=[[0.5, 0.5, 1, np.nan], [1.5, 0.5, 2, 0.01]])
    verify_refined(v, s, tri, max_area=None)
    a = areas(tri.vertices, tri.triangles)
    left, right = tri.regions == 0, tri.regions == 1
    assert a[right].max() <= 0.01 and right.sum() >= 100
    # no Steiner point inside the unbounded square (some on the edge the squares share)
    assert len(tri.steiner) > 0 and (tri.vertices[tri.steiner, 0] >= 1).all()
    assert tri.stats["refinement_steiner"] == len(tri.steiner)
    # through the batch path's one-by-one route as well (seeds go one by one)
    from cdt_plugin.batch import triangulate_rings
    xy = np.array([[0, 0], [2, 0], [2, 1], [0, 1.0]])
    out = triangulate_rings(xy, [0, 4], [0, 1], [0], [False], regions=[[1.0, 0.5, 0, 0.01]])
    assert len(out.vertices) > len(xy)                      # Steiner vertices follow the input
    assert areas(out.vertices, out.triangles).max() <= 0.01


def test_points_only_refines_the_hull():
    rng = np.random.default_rng(3)
    pts = rng.random((60, 2))
    tri = cdt_plugin.triangulate(pts, min_angle=30)
    verify_refined(pts, None, tri, min_angle=30)
    assert tri.stats["below_min_angle"] == 0
    assert (tri.segment_ids == -1).all()         # hull pieces, no input segment
    # the hull is the same region (its Steiner points lie on hull edges)
    plain = cdt_plugin.delaunay(pts)
    assert areas(tri.vertices, tri.triangles).sum() == pytest.approx(
        areas(plain.vertices, plain.triangles).sum(), rel=1e-12)


def test_keep_hull_with_segments():
    v = SQUARE + [[1, 1], [3, 2]]
    tri = cdt_plugin.triangulate(v, [[4, 5]], keep_hull=True, min_angle=30)
    verify_refined(v, [[4, 5]], tri, min_angle=30)
    assert set(tri.segment_ids.tolist()) == {-1, 0}


SQUARE_T = (np.array(SQUARE + HOLE, float), cdt_plugin.triangulate(SQUARE + HOLE, ring(4) + ring(4, 4)).triangles)


def test_split_boundary_false_keeps_boundary_whole():
    v = SQUARE + HOLE
    s = ring(4) + ring(4, 4)
    tri = cdt_plugin.triangulate(v, s, max_area=0.5, split_boundary=False)
    verify_refined(v, s, tri)
    assert len(tri.segments) == 8                 # no boundary segment split
    assert len(tri.steiner) > 0                   # but the inside is refined
    assert areas(tri.vertices, tri.triangles).max() < areas(SQUARE_T[0], SQUARE_T[1]).max()
    # an interior segment may still be split
    v2 = SQUARE + [[0.5, 2], [3.5, 2.1]]
    tri = cdt_plugin.triangulate(v2, ring(4) + [[4, 5]], min_angle=30, split_boundary=False)
    verify_refined(v2, ring(4) + [[4, 5]], tri)
    assert (tri.segment_ids < 4).sum() == 4


def test_conforming_delaunay_every_triangle_delaunay():
    # a thin rhombus with its long diagonal as a segment: the CDT is not Delaunay
    v = [[0, 0], [10, -1], [20, 0], [10, 1]]
    s = ring(4) + [[0, 2]]
    plain = cdt_plugin.triangulate(v, s)
    assert not check_empty_circumcircles(plain.vertices, plain.triangles).ok
    tri = cdt_plugin.triangulate(v, s, conforming_delaunay=True)
    verify_refined(v, s, tri, conforming=True)
    assert len(tri.steiner) > 0
    # with quality bounds as well
    tri = cdt_plugin.triangulate(v, s, conforming_delaunay=True, min_angle=25)
    verify_refined(v, s, tri, conforming=True, min_angle=25)


def test_conforming_with_hole_is_delaunay_everywhere():
    v = SQUARE + HOLE
    s = ring(4) + ring(4, 4)
    tri = cdt_plugin.triangulate(v, s, conforming_delaunay=True, max_area=0.5)
    verify_refined(v, s, tri, conforming=True, max_area=0.5)


def test_small_input_angles_terminate():
    # many segments fanning out of one vertex at tiny angles
    k = 12
    ang = np.linspace(0, np.radians(10), k)
    fan = [[0.0, 0.0]] + [[np.cos(a), np.sin(a)] for a in ang]
    v = np.array(fan)
    s = [[0, i] for i in range(1, k + 1)] + [[i, i + 1] for i in range(1, k)]
    tri = cdt_plugin.triangulate(v, s, min_angle=30)
    verify_refined(v, s, tri, min_angle=30)
    assert tri.stats["below_min_angle"] > 0           # the input angles themselves
    small = min_angles(tri.vertices, tri.triangles) < 30
    # every triangle that misses the bound sits at the fan's apex region
    centres = tri.vertices[tri.triangles[small]].mean(axis=1)
    assert np.hypot(*centres.T).max() < 1.0


def test_nearly_parallel_segments():
    v = [[0, 0], [10, 0], [10, 1e-3], [0, 2e-3], [-1, -1], [11, -1], [11, 1], [-1, 1]]
    s = [[0, 1], [2, 3], [4, 5], [5, 6], [6, 7], [7, 4]]
    tri = cdt_plugin.triangulate(v, s, min_angle=28)
    verify_refined(v, s, tri, min_angle=28)


def test_max_steiner_limit_raises_with_partial_mesh():
    v = SQUARE + HOLE
    s = ring(4) + ring(4, 4)
    with pytest.raises(RefinementLimitError, match="max_steiner=50") as err:
        cdt_plugin.triangulate(v, s, max_area=1e-4, max_steiner=50)
    part = err.value.triangulation
    assert part is not None and not part.stats["refinement_complete"]
    assert part.stats["refinement_steiner"] == 50
    rep = check_triangulation(part.vertices, part.triangles, segments=part.segments, domain="segments",
                              require_all_vertices=False)
    assert rep.ok, str(rep)


def test_bad_options():
    for kw in ({"min_angle": 61}, {"min_angle": -1}, {"max_area": 0}, {"max_area": float("nan")},
               {"max_steiner": -3}):
        with pytest.raises(CDTError):
            cdt_plugin.triangulate(SQUARE, ring(4), **kw)


@settings(max_examples=25, deadline=None)
@given(st.one_of(st.floats(5e-324, 1e-6), st.sampled_from([5e-324, 1e-300, 1e-9, 1e-7])),
       st.lists(st.floats(0.2, 3.0), min_size=3, max_size=12))
def test_tiny_min_angles_refine_with_circumcentres(angle, radii):
    """min_angle=1e-9 raised ZeroDivisionError: cos(theta) rounds to 1 there, and the
    off-centre constant divided by 1 - cos(theta). Any angle in (0, 60) must refine."""
    v = _star(radii, len(radii))
    s = ring(len(v))
    tri = cdt_plugin.triangulate(v, s, min_angle=angle)
    verify_refined(v, s, tri, min_angle=angle)


def test_large_offsets_mesh_as_well():
    v = np.array(SQUARE + HOLE, float)
    s = ring(4) + ring(4, 4)
    base = cdt_plugin.triangulate(v, s, min_angle=30)
    for off in (1e5, 1e7):
        w = v + [off, -off]
        tri = verify_refined(w, s, cdt_plugin.triangulate(w, s, min_angle=30), min_angle=30)
        assert abs(len(tri.triangles) - len(base.triangles)) <= 0.2 * len(base.triangles)


def test_intersections_split_then_refine():
    v = [[0, 0], [4, 4], [0, 4], [4, 0], [-1, -1], [5, -1], [5, 5], [-1, 5]]
    s = [[0, 1], [2, 3], [4, 5], [5, 6], [6, 7], [7, 4]]
    tri = cdt_plugin.triangulate(v, s, intersections="split", min_angle=30, keep_hull=True)
    assert tri.stats["intersection_points"] == 1
    verify_refined(v, s, tri, min_angle=30)


def test_shapely_and_trimesh_pass_options():
    shapely = pytest.importorskip("shapely")
    from cdt_plugin.adapters.shapely import triangulate as shp_tri
    from cdt_plugin.adapters.trimesh import extrude_polygon
    poly = shapely.Polygon([(0, 0), (3, 0), (3, 1), (0, 1)], [[(1, 0.3), (2, 0.3), (2, 0.7), (1, 0.7)]])
    tri = shp_tri(poly, min_angle=30, max_area=0.05)
    assert min_angles(tri.vertices, tri.triangles).min() >= 30 * (1 - 1e-9)
    assert areas(tri.vertices, tri.triangles).max() <= 0.05
    solid = extrude_polygon(poly, 1.0, min_angle=30)
    assert solid.is_watertight and solid.volume == pytest.approx(poly.area)


def _poly_files():
    return sorted(glob.glob(os.path.join(CORPUS, "triangle", "*.poly")))


@pytest.mark.parametrize("path", _poly_files(), ids=os.path.basename)
@pytest.mark.parametrize("angle", [20, 30, 33])
def test_triangle_sample_polygons(path, angle):
    from cdt_plugin.io import read_poly
    d = read_poly(path)
    holes = d.holes if d.holes is not None and len(d.holes) else None
    tri = cdt_plugin.triangulate(d.vertices, d.segments, holes=holes, min_angle=angle)
    if len(tri.triangles) == 0:
        return
    verify_refined(d.vertices, d.segments, tri, min_angle=angle)
    if os.path.basename(path) in ("A.poly", "face.poly", "square_circle_hole.poly", "box.poly"):
        assert tri.stats["below_min_angle"] == 0     # no input angle below the bound


def _star(draw_radii, n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.asarray(draw_radii)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(0.2, 3.0), min_size=3, max_size=24),
       st.sampled_from([None, 15.0, 25.0, 30.0, 33.0]),
       st.sampled_from([None, 0.5, 0.05]),
       st.booleans())
def test_fuzz_star_polygons(radii, angle, area, conforming):
    v = _star(radii, len(radii))
    s = ring(len(v))
    if angle is None and area is None and not conforming:
        angle = 20.0
    tri = cdt_plugin.triangulate(v, s, min_angle=angle, max_area=area, conforming_delaunay=conforming)
    verify_refined(v, s, tri, min_angle=angle, max_area=area, conforming=conforming)


def test_triangle_switches():
    from cdt_plugin.switches import options_from_switches
    assert options_from_switches("pq30a0.5Q") == {"min_angle": 30.0, "max_area": 0.5}
    assert options_from_switches("pq") == {"min_angle": 20.0}
    assert options_from_switches("pcDYS100") == {"keep_hull": True, "conforming_delaunay": True,
                                                 "split_boundary": False, "max_steiner": 100}
    assert options_from_switches("pq.5a.25") == {"min_angle": 0.5, "max_area": 0.25}
    for bad in ("pr", "pq30-", "pu"):
        with pytest.raises(CDTError):
            options_from_switches(bad)


def _corpus_plc(name):
    from corpus import iter_plcs
    for plc in iter_plcs():
        if plc.name == name:
            return plc
    pytest.skip(f"{name} not in the corpus")


def test_corpus_sliver_triangles_do_not_crash():
    # duplicate points and a near-degenerate triangle: the circumcentre's float
    # denominator cancels to zero (was a ZeroDivisionError)
    plc = _corpus_plc("earcut/infinite-loop-jhl.json")
    tri = cdt_plugin.triangulate(plc.vertices, plc.segments, intersections="split", min_angle=30)
    # (the rings overlap: by even-odd depth, the doubled edge borders no kept triangle)
    verify_refined(plc.vertices, plc.segments, tri, min_angle=30, partial=True)
    assert set(tri.segment_ids.tolist()) <= {0, 1, 3, 4}


def test_needle_stops_at_the_cap_with_a_valid_partial_mesh():
    # two boundary segments meet at 1e-11 degrees: no finite refinement separates
    # them, so the Steiner cap ends it with the documented error
    plc = _corpus_plc("gis/naturalearth_lowres.geojson#14 Sudan")
    with pytest.raises(RefinementLimitError) as err:
        cdt_plugin.triangulate(plc.vertices, plc.segments, min_angle=30, max_steiner=3000)
    part = err.value.triangulation
    rep = check_triangulation(part.vertices, part.triangles, segments=part.segments,
                              domain="segments", require_all_vertices=False)
    assert rep.ok, str(rep)
    # at 20 degrees the same polygon meshes: the needle's own triangles are reported
    tri = cdt_plugin.triangulate(plc.vertices, plc.segments, max_area=0.5)
    verify_refined(plc.vertices, plc.segments, tri, max_area=0.5)


def test_area_bound_far_below_the_domain_stops_at_the_default_cap():
    """max_area=1e-7 on a unit square ran on to 7.8 million Steiner points (41 s): the
    default cap held for angle bounds only. It now holds for area bounds too (at most a
    million more points for them), and the partial mesh comes with the error."""
    v = [(0, 0), (1, 0), (1, 1), (0, 1), (0.2, 0.5), (0.8, 0.5)]
    s = ring(4) + [[4, 5]]
    with pytest.raises(RefinementLimitError, match="max_steiner=1100600") as err:
        cdt_plugin.triangulate(v, s, max_area=1e-8)
    part = err.value.triangulation
    assert len(part.steiner) == 1_100_600
    rep = check_triangulation(part.vertices, part.triangles, segments=part.segments,
                              domain="segments", require_all_vertices=False)
    assert rep.ok, str(rep)


def check_split_refined(tri):
    """A refined mesh of crossing segments (intersections="split"): a constrained
    Delaunay triangulation of its own vertices and segment pieces, checked
    exactly (the crossing points are rounded, so the pieces are checked rather
    than the input segments)."""
    V, T = tri.vertices, tri.triangles
    edges = {frozenset(e) for t in T.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    inside = np.array([frozenset(p) in edges for p in tri.segments.tolist()], bool)
    rep = check_triangulation(V, T, segments=tri.segments[inside].reshape(-1, 2), domain="segments",
                              require_all_vertices=False, exempt_segments=True)
    assert rep.ok, str(rep)
    assert tri.is_delaunay()


def test_split_point_rounded_off_a_piece_keeps_the_mesh_constrained_delaunay():
    """Regression: refinement splits a piece at a point that lies on it only up
    to rounding; the new edges from that point to the opposite vertices must be
    tested too (Lawson's argument assumes the point is on the edge). Found by
    fuzzing: this input used to come out with a non-Delaunay edge."""
    V = [[1.1, 1.3], [3.4, 3.1], [0.6, 1.8], [3.7, 3.8], [1.5, 4.0], [3.4, 1.7], [2.2, 3.9]]
    S = [[6, 1], [6, 2], [2, 1], [4, 5], [0, 3]]
    tri = cdt_plugin.triangulate(V, S, intersections="split", min_angle=25)
    check_split_refined(tri)
    assert tri.stats["intersection_points"] == 5


@settings(max_examples=40, deadline=None)
@given(st.integers(4, 12).flatmap(lambda n: st.tuples(
    st.lists(st.tuples(st.integers(0, 40), st.integers(0, 40)), min_size=n, max_size=n),
    st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), min_size=2, max_size=2 * n))))
def test_fuzz_crossing_segments_split_then_refined(data):
    """Segment soups on a 0.1 grid (crossings, T-junctions, overlaps, repeats),
    split and refined at 25 degrees: a valid constrained Delaunay mesh, or the
    Steiner cap's error with its partial mesh; never a crash or a hang."""
    pts, segs = data
    V = np.array(pts, float) / 10
    try:
        tri = cdt_plugin.triangulate(V, segs, intersections="split", min_angle=25)
    except RefinementLimitError as err:
        tri = err.triangulation
    except CDTError:
        return   # e.g. all points collinear with no domain
    check_split_refined(tri)


def test_refinement_stops_at_the_limit_of_precision_near_zero():
    """Regression (found by fuzzing): crossings on a small integer grid left a piece
    along x = 4 - 2 ulp down to y = 0, where doubles are dense; refinement halved it
    down to 1e-103, the predicates underflowed and the partial mesh at the Steiner
    cap had triangles that repeat a vertex. Edges shorter than 2^-44 of their
    coordinates are now left alone: the mesh completes and checks exactly."""
    V = [[1, 6], [6, 0], [5, 2], [2, 6], [6, 0], [6, 5], [0, 1], [2, 3], [0, 0], [0, 3], [6, 4],
         [6, 5], [4, 0], [4, 1], [4, 0], [4, 3], [4, 1], [2, 2], [2, 6], [0, 4], [1, 3], [1, 3],
         [4, 1]]
    S = [[22, 18], [12, 11], [4, 14], [3, 0], [14, 2], [13, 19], [1, 10], [10, 11], [6, 8],
         [5, 16], [19, 5], [6, 12], [7, 11], [7, 10], [7, 6], [0, 4], [20, 3], [0, 19], [8, 1],
         [5, 5], [11, 8], [22, 0], [19, 18], [19, 10], [7, 7], [19, 7], [12, 12], [12, 10],
         [22, 3], [18, 10], [7, 6], [14, 14], [2, 15], [13, 2], [12, 0], [11, 6], [22, 20]]
    tri = cdt_plugin.triangulate(np.array(V, float), S, intersections="split", min_angle=28)
    check_split_refined(tri)
    assert tri.stats["refinement_complete"] and len(tri.triangles) < 10_000


@pytest.mark.parametrize("min_angle, max_area", [(22.93, 0.00575), (33, 0.02), (0, 0.01)])
def test_refined_mesh_independent_of_input_order_and_direction(min_angle, max_area):
    """Reversing one segment changed every triangle of a refined triangle, and
    most random cases changed under a permutation: refinement now scans the
    slots in a canonical order and splits each segment from its smaller end."""
    V = np.array([[0.0, 0.0], [1.0, 0.1], [0.3, 0.9], [0.4, 0.3]])
    S = np.array([[0, 1], [1, 2], [2, 0]])
    base = cdt_plugin.triangulate(V, S, min_angle=min_angle or None, max_area=max_area)
    verify_refined(V, S, base, min_angle=min_angle, max_area=max_area)
    assert len(base.steiner) > 3
    want = canonical_triangles(base.vertices, base.triangles)
    rng = np.random.default_rng(5)
    for variant in range(6):
        perm = rng.permutation(len(V))
        S2 = np.argsort(perm)[S][rng.permutation(len(S))]
        S2[variant % 3] = S2[variant % 3][::-1]
        tri = cdt_plugin.triangulate(V[perm], S2, min_angle=min_angle or None, max_area=max_area)
        assert canonical_triangles(tri.vertices, tri.triangles) == want
        assert sorted(map(tuple, tri.vertices.tolist())) == sorted(map(tuple, base.vertices.tolist()))


def test_nearly_straight_boundary_vertex_is_not_a_small_angle():
    """Vertex 0 lies within ~1e-13 of the line through its neighbours: splitting
    the segments there at rounded points would invert the sliver outside it, so
    they froze and 6 triangles down to 6.4 degrees stayed (Triangle -pq30 reaches
    30.03). Only the domain's side of a split must stay counter-clockwise, and
    only an input angle below the bound excuses a triangle."""
    V = [[101.25, 1006.8145], [-0.0, 869.6563], [13.7628, 385.7424], [20.536, 382.9626],
         [207.25, 1143.9864], [202.5, 1143.9727]]
    S = [[i, (i + 1) % 6] for i in range(6)]
    tri = cdt_plugin.triangulate(V, S, min_angle=30)
    verify_refined(V, S, tri, min_angle=30)
    assert len(tri.below_min_angle) == 0 and tri.stats["frozen_segment_pieces"] == 0
    assert min_angles(tri.vertices, tri.triangles).min() >= 30
