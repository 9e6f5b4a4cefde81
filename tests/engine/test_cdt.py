"""Engine tests for cdt_plugin.triangulate (constrained Delaunay triangulation).

Every result is verified by the exact checker: a valid triangulation, every
segment present (as an edge or a chain of collinear edges), every non-segment
edge locally Delaunay (Constrained Delaunay Lemma 2.14)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import (CDTError, InvalidGeometryError, OverlappingSegmentsError, SegmentIndexError,
                        SegmentIntersectionError)
from checker import canonical_triangles, check_triangulation
from fuzz import check_vertices_split_segments
from helpers import domain_segments

rng = np.random.default_rng(7)


def verify_cdt(vertices, segments, tri, *, domain="segments", split=False):
    """Exact check of a CDT result. With ``domain="hull"`` (keep_hull) every vertex
    must be used; segments are the input ones (or our pieces after splitting)."""
    if domain == "segments":
        # the domain's own segment pieces (dangling ones outside it are checked
        # on the whole-hull triangulation below)
        segs = domain_segments(tri)
    elif split:
        segs = tri.segments
    else:
        vm = tri.vertex_map[np.asarray(segments, np.int64).reshape(-1, 2)]
        segs = vm[vm[:, 0] != vm[:, 1]]
    rep = check_triangulation(tri.vertices, tri.triangles, segments=segs, domain=domain,
                              require_all_vertices=(domain == "hull"))
    assert rep.ok, str(rep)
    assert tri.is_delaunay()
    if domain == "segments" and not split:
        # the domain's triangles are a subset of the (checked) whole-hull CDT
        full = cdt_plugin.triangulate(vertices, segments, keep_hull=True)
        verify_cdt(vertices, segments, full, domain="hull")
        assert canonical_triangles(tri.vertices, tri.triangles) <= canonical_triangles(full.vertices, full.triangles)
    return rep


def ring(points, start=0):
    k = len(points)
    return [[start + i, start + (i + 1) % k] for i in range(k)]


SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
HOLE = [[1, 1], [3, 1], [3, 3], [1, 3]]


def test_square_with_hole():
    v = SQUARE + HOLE
    s = ring(SQUARE) + ring(HOLE, 4)
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert len(tri.triangles) == 8          # n + 2h - 2
    area = _area(tri)
    assert area == pytest.approx(16 - 4)
    assert set(tri.segment_ids.tolist()) == set(range(8))


def _area(tri):
    v, t = tri.vertices, tri.triangles
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.sum((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2)


def test_segment_that_is_not_a_delaunay_edge():
    # a thin rhombus: the long diagonal is not Delaunay, insert it as a segment
    v = [[0, 0], [10, -1], [20, 0], [10, 1]]
    tri = cdt_plugin.triangulate(v, [[0, 2]], keep_hull=True)
    verify_cdt(v, [[0, 2]], tri, domain="hull")
    assert {0, 2} in [set(e) for e in tri.segments.tolist()]
    assert not cdt_plugin.delaunay(v).constrained.any()


def test_long_segment_through_random_points():
    p = rng.random((2000, 2))
    v = np.vstack([p, [[-0.1, 0.5], [1.1, 0.52]]])
    seg = [[2000, 2001]]
    tri = cdt_plugin.triangulate(v, seg, keep_hull=True)
    verify_cdt(v, seg, tri, domain="hull")
    tri2 = cdt_plugin.triangulate(v, seg, keep_hull=True, algorithm="flip")
    assert canonical_triangles(tri.vertices, tri.triangles) == canonical_triangles(tri2.vertices, tri2.triangles)


def test_vertex_on_segment_splits_it():
    v = [[0, 0], [4, 0], [4, 4], [0, 4], [2, 0]]   # vertex 4 on the bottom edge 0-1
    s = [[0, 1], [1, 2], [2, 3], [3, 0]]
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert tri.stats["vertices_on_segments"] == 1
    pieces = {tuple(sorted(e)) for e in tri.segments.tolist()}
    assert (0, 4) in pieces and (1, 4) in pieces


@pytest.mark.parametrize("order", [[0, 1], [1, 0]])
@pytest.mark.parametrize("flip", [False, True])
def test_vertex_on_a_crossed_segment_splits_it(order, flip):
    """Vertex 4 lies exactly on segment 2-3, beyond its crossing with 0-1: the
    piece from the (rounded) crossing point passed it by (pieces 2-5-3)."""
    V = [[0.25, 0.875], [0.875, 0], [0.75, 1], [0, 0], [0.375, 0.5]]
    S = [[[0, 1], [2, 3]][i] for i in order]
    if flip:
        S = [s[::-1] for s in S]
    tri = cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True)
    verify_cdt(V, S, tri, domain="hull", split=True)
    check_vertices_split_segments(V, S, tri)
    assert tri.stats["vertices_on_segments"] == 1


@pytest.mark.parametrize("S", [[[2, 1], [0, 3]], [[0, 3], [2, 1]], [[1, 2], [3, 0]], [[3, 0], [1, 2]]])
def test_crossing_points_are_exact_and_independent_of_order(S):
    """The crossing (18, 1) is a double: it came out as (18, 0.9999999999999982)
    for one order of the segments."""
    V = [[-7, -24], [0, 25], [24, -7], [24, 7], [17, -8]]
    tri = cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True)
    verify_cdt(V, S, tri, domain="hull", split=True)
    assert tri.vertices[tri.steiner].tolist() == [[18.0, 1.0]]


def test_hole_touching_shell_at_a_vertex():
    v = SQUARE + [[0, 0], [2, 1], [1, 2]]       # hole shares the corner (0, 0)
    s = ring(SQUARE) + ring([[0, 0], [2, 1], [1, 2]], 4)
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert _area(tri) == pytest.approx(16 - 1.5)


def test_nested_island_by_parity():
    big = [[0, 0], [10, 0], [10, 10], [0, 10]]
    hole = [[2, 2], [8, 2], [8, 8], [2, 8]]
    island = [[4, 4], [6, 4], [6, 6], [4, 6]]
    v = big + hole + island
    s = ring(big) + ring(hole, 4) + ring(island, 8)
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert _area(tri) == pytest.approx(100 - 36 + 4)
    # windings do not matter
    s_rev = ring(big) + [[b, a] for a, b in ring(hole, 4)] + ring(island, 8)
    assert _area(cdt_plugin.triangulate(v, s_rev)) == pytest.approx(68)


def test_hole_points_follow_triangles_convention():
    v = SQUARE + HOLE
    s = ring(SQUARE) + ring(HOLE, 4)
    with_hole = cdt_plugin.triangulate(v, s, holes=[[2, 2]])
    assert _area(with_hole) == pytest.approx(12)
    filled = cdt_plugin.triangulate(v, s, holes=[])
    assert _area(filled) == pytest.approx(16)
    hull = cdt_plugin.triangulate(v, s, keep_hull=True)
    verify_cdt(v, s, hull, domain="hull")
    assert _area(hull) == pytest.approx(16)


def test_segments_list_only_pieces_that_border_a_kept_triangle():
    """Regression (reliability, domains): with holes= the pieces inside the
    hole were listed; a segment dangling outside the domain too. As Triangle,
    which deletes the subsegments a hole eats."""
    v = SQUARE + HOLE + [[1.5, 2], [2.5, 2], [5, 1], [6, 3]]
    s = ring(SQUARE) + ring(HOLE, 4) + [[8, 9], [10, 11]]     # one inside the hole, one outside
    for kwargs in ({"holes": [[2, 2.5]]}, {}):
        tri = cdt_plugin.triangulate(v, s, **kwargs)
        verify_cdt(v, s, tri)
        edges = {frozenset(e) for t in tri.triangles.tolist()
                 for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
        assert all(frozenset(p) in edges for p in tri.segments.tolist())
        assert sorted(set(tri.segment_ids.tolist())) == list(range(8))   # the rings, not 8 or 9
        assert len(tri.segments) == 8
    hull = cdt_plugin.triangulate(v, s, keep_hull=True)
    verify_cdt(v, s, hull, domain="hull")
    assert sorted(set(hull.segment_ids.tolist())) == list(range(10))


def test_regions_paint_their_areas():
    v = SQUARE + [[2, 0], [2, 4]]
    s = ring(SQUARE) + [[4, 5]]
    tri = cdt_plugin.triangulate(v, s, regions=[[1, 1, 10.0], [3, 1, 20.0]])
    verify_cdt(v, s, tri)
    left = tri.vertices[tri.triangles].mean(axis=1)[:, 0] < 2
    assert (tri.regions[left] == 0).all() and (tri.regions[~left] == 1).all()
    # each triangle's regional attribute (whole seed rows before)
    assert tri.region_attributes.tolist() == np.where(left, 10.0, 20.0).tolist()
    assert cdt_plugin.triangulate(v, s).region_attributes is None
    one = cdt_plugin.triangulate(v, s, regions=[[1, 1, 7.0]])     # the right half: no seed
    assert np.isnan(one.region_attributes[~left]).all() and (one.region_attributes[left] == 7).all()


@pytest.mark.parametrize("kw, match", [
    ({"holes": [[1, 1], [np.nan, 2]]}, r"holes .*row\(s\) 1 \(row 1 is \(nan, 2.0\)\)"),
    ({"regions": [[1, 1, 3], [2, 2, 4], [np.inf, 0, 1]]}, r"regions .*row\(s\) 2 ")])
def test_non_finite_seeds_name_their_rows(kw, match):
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match=match):
        cdt_plugin.triangulate(SQUARE, ring(SQUARE), **kw)


def test_slit_and_isolated_vertex_inside():
    v = SQUARE + [[1, 2], [3, 2], [2, 3]]      # a slit 4-5 and a free vertex 6
    s = ring(SQUARE) + [[4, 5]]
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert (tri.vertex_map >= 0).all() and 6 in tri.triangles


def test_crossing_segments_raise_with_indices_and_point():
    v = [[0, 0], [2, 2], [0, 2], [2, 0]]
    with pytest.raises(SegmentIntersectionError, match=r"segments 1 .* and 0 .* cross at about \(1.0, 1.0\)") as err:
        cdt_plugin.triangulate(v, [[0, 1], [2, 3]])
    assert set(err.value.segments) == {0, 1}
    assert err.value.point == (1.0, 1.0)
    tri = cdt_plugin.triangulate(v, [[0, 1], [2, 3]], intersections="split", keep_hull=True)
    verify_cdt(v, None, tri, domain="hull", split=True)
    assert tri.stats["intersection_points"] == 1 and len(tri.steiner) == 1
    assert tri.vertices[tri.steiner[0]].tolist() == [1.0, 1.0]
    assert len(tri.segments) == 4 and sorted(set(tri.segment_ids.tolist())) == [0, 1]


def test_overlapping_segments_raise_or_merge():
    v = [[0, 0], [2, 0], [1, 0], [3, 0], [1, 1]]
    s = [[0, 1], [2, 3]]
    with pytest.raises(OverlappingSegmentsError, match="segments .* overlap"):
        cdt_plugin.triangulate(v, s)
    tri = cdt_plugin.triangulate(v, s, intersections="split", keep_hull=True)
    verify_cdt(v, s, tri, domain="hull")
    assert tri.stats["merged_overlaps"] == 1


def test_repeated_and_zero_length_segments_are_repaired():
    v = SQUARE + [[0, 0]]
    s = ring(SQUARE) + [[1, 0], [0, 4], [2, 2]]   # repeat, zero length (dup vertex), zero length
    tri = cdt_plugin.triangulate(v, s)
    verify_cdt(v, s, tri)
    assert tri.stats["duplicate_segments"] == 1
    assert tri.stats["zero_length_segments"] == [5, 6]


def test_ring_given_twice_encloses_nothing():
    v = SQUARE + SQUARE
    s = ring(SQUARE) + ring(SQUARE, 4)
    assert len(cdt_plugin.triangulate(v, s).triangles) == 0


@pytest.mark.parametrize("segs,msg", [
    ([[0, 9]], r"segment 0 = \[0, 9\] names a vertex outside 0..3"),
    ([[0, 1], [-1, 2]], "segment 1"),
    ([[0.5, 1]], "non-integer"),
    ([[0, 1, 2]], r"\(m, 2\)"),
    ([[0, 1], [1, 2, 3]], "segments must be rows of equal length: row 1 has 3 entries"),
    (np.array([[0, 1], [1, 2 ** 64 - 1]], np.uint64), r"segment 1 = \[1, 18446744073709551615\]"),
    ([[0, 1], [1, 1e20]], r"segment 1 = \[1.0, 1e\+20\] names a vertex outside"),
    ([[0, 1], [1, 2j]], "complex"),
])
def test_bad_segments(segs, msg):
    with pytest.raises((SegmentIndexError, cdt_plugin.InputShapeError), match=msg):
        cdt_plugin.triangulate(SQUARE, segs)


def test_bad_coordinates_name_the_place():
    """Ragged GeoJSON rings and complex vertices raised numpy's ValueError or lost
    their imaginary part without a word."""
    ring_ = [[0, 0], [4, 0], [4, 4, 1, 2], [0, 4], [0, 0]]
    with pytest.raises(cdt_plugin.InputShapeError, match="coordinates must be rows of equal length: row 2"):
        cdt_plugin.triangulate({"type": "Polygon", "coordinates": [ring_]})
    with pytest.raises(cdt_plugin.InputShapeError, match="complex"):
        cdt_plugin.triangulate(np.array(SQUARE) + 0.5j, ring(SQUARE))
    with pytest.raises(cdt_plugin.InputShapeError, match="holes must be rows of equal length"):
        cdt_plugin.triangulate(SQUARE, ring(SQUARE), holes=[[1, 1], [2]])


def test_bad_options():
    with pytest.raises(CDTError, match="intersections"):
        cdt_plugin.triangulate(SQUARE, ring(SQUARE), intersections="ignore")
    with pytest.raises(CDTError, match="algorithm"):
        cdt_plugin.triangulate(SQUARE, ring(SQUARE), algorithm="sweep")


def test_collinear_input_with_segments():
    v = [[0, 0], [1, 0], [2, 0]]
    tri = cdt_plugin.triangulate(v, [[0, 2]])
    assert tri.triangles.shape == (0, 3) and len(tri.edges) == 2


# --------------------------------------------------------------- geometry input
def test_geo_interface_polygon_with_hole():
    shapely = pytest.importorskip("shapely")
    poly = shapely.Polygon(SQUARE, [HOLE[::-1]])
    tri = cdt_plugin.triangulate(poly)
    assert len(tri.triangles) == 8 and _area(tri) == pytest.approx(poly.area)
    assert (tri.regions == 0).all()
    multi = shapely.MultiPolygon([poly, shapely.Polygon([[10, 0], [12, 0], [11, 1]])])
    tri = cdt_plugin.triangulate(multi)
    assert sorted(set(tri.regions.tolist())) == [0, 1]
    assert _area(tri) == pytest.approx(multi.area)


def test_geo_interface_mapping_and_lines():
    g = {"type": "GeometryCollection", "geometries": [
        {"type": "Polygon", "coordinates": [[(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)]]},
        {"type": "LineString", "coordinates": [(1, 1), (3, 3)]},
        {"type": "Point", "coordinates": (1, 3)}]}
    tri = cdt_plugin.triangulate(g)
    assert _area(tri) == pytest.approx(16)
    assert any(set(e) == {4, 5} for e in tri.segments.tolist())
    assert 6 in tri.triangles


def test_geo_interface_hole_outside_shell():
    g = {"type": "Polygon", "coordinates": [SQUARE + [SQUARE[0]], [[10, 10], [11, 10], [11, 11], [10, 10]]]}
    with pytest.raises(InvalidGeometryError, match="hole of polygon 0"):
        cdt_plugin.triangulate(g)


def test_geo_interface_degenerate_ring():
    g = {"type": "Polygon", "coordinates": [SQUARE + [SQUARE[0]], [[1, 1], [2, 2], [1, 1]]]}
    with pytest.raises(InvalidGeometryError, match="fewer than three distinct points"):
        cdt_plugin.triangulate(g)
    tri = cdt_plugin.triangulate(g, intersections="split")
    assert _area(tri) == pytest.approx(16)


def test_bowtie_ring_raises_then_splits():
    g = {"type": "Polygon", "coordinates": [[(0, 0), (2, 2), (2, 0), (0, 2), (0, 0)]]}
    with pytest.raises(SegmentIntersectionError):
        cdt_plugin.triangulate(g)
    tri = cdt_plugin.triangulate(g, intersections="split")
    assert _area(tri) == pytest.approx(2.0)


# ----------------------------------------------------------- property tests
coord = st.integers(0, 6)


@settings(max_examples=120, deadline=None)
@given(st.lists(st.tuples(coord, coord), min_size=3, max_size=25),
       st.lists(st.tuples(st.integers(0, 24), st.integers(0, 24)), max_size=12))
def test_hypothesis_random_plcs(pts, pairs):
    v = np.array(pts, float)
    s = np.array([(a % len(v), b % len(v)) for a, b in pairs], np.int64).reshape(-1, 2)
    try:
        tri = cdt_plugin.triangulate(v, s, keep_hull=True)
    except (SegmentIntersectionError, OverlappingSegmentsError):
        tri = cdt_plugin.triangulate(v, s, keep_hull=True, intersections="split")
        if len(tri.triangles):
            verify_cdt(v, s, tri, domain="hull", split=True)
        return
    if len(tri.triangles):
        verify_cdt(v, s, tri, domain="hull")
        default = cdt_plugin.triangulate(v, s)
        if len(default.triangles):  # without segments the whole hull is kept
            verify_cdt(v, s, default, domain="segments" if len(default.segments) else "hull")


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_two_routes_agree_on_generic_plcs(seed):
    """Theorem 2.18: a generic PLC has one CDT; both routes must find it."""
    r = np.random.default_rng(seed)
    v = r.random((60, 2))
    s = []
    for _ in range(8):
        a, b = r.choice(60, 2, replace=False)
        s.append([a, b])
    s = np.array(s)
    try:
        one = cdt_plugin.triangulate(v, s, keep_hull=True)
    except SegmentIntersectionError:
        return
    two = cdt_plugin.triangulate(v, s, keep_hull=True, algorithm="flip")
    three = cdt_plugin.triangulate(v, s, keep_hull=True, algorithm="incremental")
    verify_cdt(v, s, one, domain="hull")
    verify_cdt(v, s, two, domain="hull")
    verify_cdt(v, s, three, domain="hull")
    assert canonical_triangles(one.vertices, one.triangles) == canonical_triangles(two.vertices, two.triangles)
    assert canonical_triangles(one.vertices, one.triangles) == canonical_triangles(three.vertices, three.triangles)


def test_spiral_and_comb():
    t = np.linspace(0, 6 * np.pi, 400)
    spiral = np.column_stack([t * np.cos(t), t * np.sin(t)])
    outer = np.vstack([spiral, spiral[::-1] * 0.9 + 0.0])[:-1]
    outer = np.unique(np.round(outer, 9), axis=0, return_index=True)[1]
    k = 50
    comb = [[0, 0]] + [[i, 10 if i % 2 else 1] for i in range(1, 2 * k)] + [[2 * k, 0]]
    s = ring(comb)
    tri = cdt_plugin.triangulate(comb, s)
    verify_cdt(comb, s, tri)
    assert len(tri.triangles) == len(comb) - 2


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 7), st.integers(0, 7)), min_size=1, max_size=40))
def test_repeated_segments_any_direction_are_merged_once(pairs):
    """Repeats (either direction) and zero-length segments among many: the
    kept segments are the first of each endpoint pair, the counts are those
    of a plain set, and the result is the CDT of the distinct segments."""
    V = [[0, 0], [1, 3], [3, 5], [6, 6], [9, 5], [11, 3], [12, 0], [5, 2]]
    kept = {}
    for i, (a, b) in enumerate(pairs):
        if a != b:
            kept.setdefault(frozenset((a, b)), i)
    try:
        tri = cdt_plugin.triangulate(V, pairs, keep_hull=True)
    except (SegmentIntersectionError, OverlappingSegmentsError):
        return  # random pairs may cross; the error path is tested elsewhere
    verify_cdt(V, pairs, tri, domain="hull")
    assert tri.stats["zero_length_segments"] == [i for i, (a, b) in enumerate(pairs) if a == b]
    assert tri.stats["duplicate_segments"] == sum(a != b for a, b in pairs) - len(kept)
    # each distinct segment is one piece (no three of V are collinear) carrying
    # the index of its first occurrence
    got = {frozenset(p): int(i) for p, i in zip(tri.segments.tolist(), tri.segment_ids)}
    assert got == kept


def test_no_three_collinear_in_the_repeat_fixture():
    import itertools
    V = [[0, 0], [1, 3], [3, 5], [6, 6], [9, 5], [11, 3], [12, 0], [5, 2]]
    for a, b, c in itertools.combinations(V, 3):
        assert (b[0] - a[0]) * (c[1] - a[1]) != (b[1] - a[1]) * (c[0] - a[0])


def test_ring_of_parity_with_segments_given_three_times():
    """The multiplicity of a merged segment counts in the even-odd rule: a ring
    given three times encloses its inside like a ring given once."""
    v = SQUARE
    s = ring(SQUARE) * 3
    tri = cdt_plugin.triangulate(v, s)
    assert len(tri.triangles) == 2 and tri.stats["duplicate_segments"] == 8


def test_segments_that_are_edges_and_segments_that_are_not():
    """A fine ring whose edges are all Delaunay edges already (found in one
    pass) and long chords that are not (walked and flipped in): the same CDT
    as the flip route, checked exactly."""
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    V = np.column_stack([np.cos(t), np.sin(t)])
    S = [[i, (i + 1) % 400] for i in range(400)] + [[0, 200], [100, 300]]
    with pytest.raises(SegmentIntersectionError, match="segments 40[01] .* and 40[01] "):
        cdt_plugin.triangulate(V, S)
    S = [[i, (i + 1) % 400] for i in range(400)] + [[0, 200], [10, 150], [220, 390]]
    tri = cdt_plugin.triangulate(V, S)
    verify_cdt(V, S, tri)
    flip = cdt_plugin.triangulate(V, S, algorithm="flip")
    assert canonical_triangles(tri.vertices, tri.triangles) == canonical_triangles(flip.vertices, flip.triangles)


def test_crossing_pieces_of_segments_that_do_not_cross():
    """Regression: after earlier crossings are rounded, pieces of two segments
    can cross where the input segments do not; the crossing point then comes
    from the pieces (it used to divide by zero)."""
    V = [[1.0, 1.0], [0.0, 5.0], [3.0, 2.0], [0.0, 4.0], [5.0, 0.0], [0.0, 2.0], [2.0, 4.0],
         [2.0, 3.0], [2.0, 2.0]]
    S = [[8, 1], [6, 5], [7, 0], [3, 2], [4, 3]]
    tri = cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True)
    verify_cdt(V, S, tri, domain="hull", split=True)
    # the 6 true crossings, each the double nearest to the exact point (rounding them
    # less accurately made two pieces cross again: a 7th point)
    assert tri.stats["intersection_points"] == 6
    assert sorted(map(tuple, tri.vertices[tri.steiner].tolist())) == [
        (1.1111111111111112, 3.111111111111111), (1.2, 3.2), (1.4285714285714286, 2.857142857142857),
        (1.7142857142857142, 2.4285714285714284), (1.7857142857142858, 2.5714285714285716), (1.875, 2.75)]


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 14).flatmap(lambda n: st.tuples(
    st.lists(st.tuples(st.integers(0, 5), st.integers(0, 5)), min_size=n, max_size=n),
    st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), min_size=1, max_size=3 * n))))
def test_fuzz_segment_soups_on_a_small_grid_split(data):
    """Many crossings, collinear overlaps and vertices on segments among few grid
    points, split: a valid CDT of the pieces (or a precise error), and never a
    crash, a division by zero or a hang."""
    pts, segs = data
    try:
        tri = cdt_plugin.triangulate(np.array(pts, float), segs, intersections="split", keep_hull=True)
    except CDTError:
        return
    if tri.stats.get("collinear"):   # all points on a line: edges, no triangles (Sec. 2.1)
        assert len(tri.triangles) == 0
        return
    verify_cdt(pts, segs, tri, domain="hull", split=True)
    check_vertices_split_segments(pts, segs, tri)


def test_route_arrays_made_on_first_access_are_those_of_the_route():
    """The route hands its integer outputs back in one array; the result makes
    everything but the triangles on first access (per-call cost, issue #15)."""
    import copy
    import pickle
    v = SQUARE + HOLE
    s = ring(SQUARE) + ring(HOLE, 4)
    tri = cdt_plugin.triangulate(v, s)
    assert "_lazy" in tri.__dict__ and "neighbors" not in tri.__dict__
    clone = pickle.loads(pickle.dumps(tri))
    deep = copy.deepcopy(tri)
    verify_cdt(v, s, tri)                         # reads segments, neighbours via is_delaunay
    assert "_lazy" not in tri.__dict__
    for other in (clone, deep):
        for name in ("triangles", "neighbors", "constrained", "segments", "segment_ids", "regions",
                     "vertex_map", "steiner", "below_min_angle"):
            assert np.array_equal(getattr(other, name), getattr(tri, name)), name
    assert tri.constrained.dtype == bool and tri.neighbors.shape == tri.triangles.shape
    assert tri.stats["triangles"] == 8 and tri.stats["vertices"] == 8
    fresh = cdt_plugin.triangulate(v, s)
    fresh.segments = np.empty((0, 2), np.int64)     # an assignment before first access is kept
    assert len(fresh.segments) == 0 and len(fresh.segment_ids) == 8
    with pytest.raises(AttributeError, match="no attribute 'colour'"):
        fresh.colour


@pytest.mark.parametrize("call", ["triangulate", "triangulate stats", "delaunay", "delaunay stats",
                                  "collinear stats"])
def test_a_result_leaves_no_reference_cycle(call):
    """A result whose counts are made on first access held a function that
    held the result: every call left a cycle for the garbage collector
    (collections and fresh memory pages: about 2 us of a small call, #15)."""
    import gc
    run = {"triangulate": lambda: cdt_plugin.triangulate(SQUARE, ring(SQUARE)),
           "triangulate stats": lambda: cdt_plugin.triangulate(SQUARE, ring(SQUARE)).stats,
           "delaunay": lambda: cdt_plugin.delaunay(SQUARE),
           "delaunay stats": lambda: cdt_plugin.delaunay(SQUARE).stats,
           "collinear stats": lambda: cdt_plugin.delaunay([[0, 0], [1, 1], [2, 2]]).stats}[call]
    run()
    gc.collect()
    enabled = gc.isenabled()
    gc.disable()
    try:
        result = run()
        del result
        assert gc.collect() == 0
    finally:
        if enabled:
            gc.enable()


def test_counts_made_on_first_access_read_the_result():
    tri = cdt_plugin.triangulate(SQUARE, ring(SQUARE))
    verify_cdt(SQUARE, ring(SQUARE), tri)
    assert tri.stats["triangles"] == 2 and tri.stats["vertices"] == 4
    line = cdt_plugin.delaunay([[0, 0], [1, 1], [2, 2], [1, 1]])
    assert line.stats["collinear"] and line.stats["duplicates"] == 1 and line.stats["vertices"] == 3
    assert line.stats["triangles"] == 0 and line.stats["submerged"] == 0


@pytest.mark.parametrize("option", [{"min_angle": "30"}, {"max_area": "1"}, {"max_steiner": "3"},
                                    {"max_steiner": True}, {"min_angle": [20]}, {"max_area": 1j}])
def test_options_that_are_not_numbers_are_named_before_any_work(option):
    """(#16: a string raised numpy's bare TypeError; True was taken as 1.)"""
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(cdt_plugin.CDTError, match=next(iter(option)) + " must be a number"):
        cdt_plugin.triangulate(square, [[0, 1], [1, 2], [2, 3], [3, 0]], **option)
