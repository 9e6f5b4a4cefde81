"""The quality report: per-triangle metrics against closed forms, the exact
certificate against the independent rational checker, the report object
(table, dict, JSON), and Theorem 2.8 / 2.17 on the corpus against
mapbox_earcut: with the same vertices our minimum angle is never smaller, our
largest circumdisk and largest min-containment disk never larger."""
from __future__ import annotations

import doctest
import inspect
import json
import math

import numpy as np
import pytest

import cdt_plugin
import cdt_plugin.report as report_module
from cdt_plugin import CDTError, InputShapeError
from cdt_plugin.report import RTOL, Report, compare, earcut, mesh_neighbors, mesh_report, triangle_quality
from checker import incircle_exact, orient2d_exact

SQUARE_WITH_HOLE = ([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]],
                    [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])


def test_docstring_examples():
    result = doctest.testmod(report_module)
    assert result.attempted >= 15 and result.failed == 0


# ------------------------------------------------------------ per triangle
def test_triangle_quality_closed_forms():
    s = 2.0
    h = s * math.sqrt(3) / 2
    V = [[0, 0], [s, 0], [s / 2, h],          # equilateral
         [10, 0], [13, 0], [10, 4],           # 3-4-5 right triangle
         [20, 0], [28, 0], [24, 1]]           # obtuse (angle at the apex)
    q = triangle_quality(V, [[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    assert np.allclose(q["angles"][0], 60.0)
    assert np.isclose(q["circumradius"][0], s / math.sqrt(3))
    assert np.isclose(q["inradius"][0], s / (2 * math.sqrt(3)))
    assert np.isclose(q["radius_edge_ratio"][0], 1 / math.sqrt(3))
    assert np.isclose(q["min_containment_radius"][0], q["circumradius"][0])
    assert np.allclose(q["angles"][1], [90.0, math.degrees(math.atan2(4, 3)), math.degrees(math.atan2(3, 4))])
    assert np.isclose(q["circumradius"][1], 2.5)          # half the hypotenuse
    assert np.isclose(q["min_containment_radius"][1], 2.5)
    assert np.isclose(q["inradius"][1], 1.0)              # (3 + 4 - 5) / 2
    # obtuse: the circumdisk (R = abc / 4A) is larger than the disk on the longest edge
    a = b = math.hypot(4, 1)
    assert np.isclose(q["circumradius"][2], a * b * 8 / (4 * 4.0))
    assert np.isclose(q["min_containment_radius"][2], 4.0)
    assert np.isclose(q["angles"][2].sum(), 180.0)
    assert np.isclose(q["shortest_edge"][2], a)


def test_triangle_quality_degenerate_and_independent_of_order():
    q = triangle_quality([[0, 0], [1, 0], [2, 0]], [[0, 1, 2]])
    assert q["circumradius"][0] == np.inf and q["radius_edge_ratio"][0] == np.inf
    assert q["inradius"][0] == 0.0 and q["min_containment_radius"][0] == 1.0
    # a sliver: the same triangle in any corner order gives bit-identical figures
    V = np.array([[33.961620000000096, 9.583580000000097], [33.963392794971185, 9.464285229420625],
                  [33.97498000000007, 8.68455999999992]])
    rows = [[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1]]
    q = triangle_quality(V, rows)
    assert len(set(q["circumradius"].tolist())) == 1
    assert len(set(q["angles"].min(axis=1).tolist())) == 1
    assert np.allclose(q["angles"].sum(axis=1), 180.0)


def test_mesh_neighbors_match_the_engine():
    pts = np.random.default_rng(5).uniform(0, 1, (300, 2))
    tri = cdt_plugin.delaunay(pts)
    nb, nonmanifold = mesh_neighbors(tri.triangles)
    assert nonmanifold == 0
    assert np.array_equal(nb, tri.neighbors)


def test_mesh_neighbors_non_manifold_edge():
    nb, nonmanifold = mesh_neighbors([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 2, 5]])
    assert nonmanifold == 1
    assert nb[0, 2] == nb[1, 2] == nb[2, 2] == -1       # edge 0-1 is in three triangles
    assert nb[0, 0] == 3 and nb[3, 2] == 0              # edge 1-2 is shared normally


# ------------------------------------------------------------- certificate
def _exact_certificate(V, T):
    """Independent count of (not locally Delaunay, cocircular) interior edges with
    the checker's rational predicates."""
    V = np.asarray(V, float)
    T = [list(t) if orient2d_exact(V[t[0]], V[t[1]], V[t[2]]) > 0 else [t[0], t[2], t[1]] for t in T]
    owner = {}
    bad = cocircular = 0
    for k, t in enumerate(T):
        for j in range(3):
            edge = frozenset((t[(j + 1) % 3], t[(j + 2) % 3]))
            if edge in owner:
                m, far = owner.pop(edge)
                s = incircle_exact(V[t[0]], V[t[1]], V[t[2]], V[far])
                bad += s > 0
                cocircular += s == 0
            else:
                owner[edge] = (k, t[j])
    return bad, cocircular


def test_certificate_of_earcut_matches_exact_checker():
    pytest.importorskip("mapbox_earcut")
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    ring = np.column_stack([np.cos(t) * (3 + np.sin(5 * t)), np.sin(t) * 2])
    gi = {"type": "Polygon", "coordinates": [ring.tolist()]}
    V, T = earcut(gi)
    rep = mesh_report(V, T)
    bad, cocircular = _exact_certificate(V, T)
    assert bad > 0                                       # ear clipping is not Delaunay
    assert (rep.non_delaunay_edges, rep.cocircular_edges) == (bad, cocircular)
    assert rep.unique is None                            # not Delaunay: uniqueness is moot
    ours = cdt_plugin.triangulate(gi).report()
    assert ours.non_delaunay_edges == 0 and ours.triangles == rep.triangles == 38


def test_cocircular_grid_counts_ties_exactly():
    g = np.array([[i, j] for i in range(5) for j in range(4)], float)
    tri = cdt_plugin.delaunay(g)
    rep = tri.report()
    bad, cocircular = _exact_certificate(tri.vertices, tri.triangles)
    assert bad == 0 and rep.non_delaunay_edges == 0
    assert rep.cocircular_edges == cocircular == 12      # each unit square's diagonal
    assert rep.unique is False and tri.is_unique() is False


def test_segments_are_exempt_from_the_certificate():
    # two 2x1 rectangles side by side, each cut by a diagonal: two cocircular ties
    V = [[0, 0], [4, 0], [4, 1], [0, 1], [2, 0], [2, 1]]
    T = [[0, 4, 3], [4, 5, 3], [4, 1, 5], [1, 2, 5]]
    free = mesh_report(V, T)
    assert (free.cocircular_edges, free.non_delaunay_edges, free.unique) == (2, 0, False)
    one = mesh_report(V, T, segments=[[3, 4]])
    assert (one.cocircular_edges, one.segment_edges, one.unique) == (1, 1, False)
    both = mesh_report(V, T, segments=[[3, 4], [5, 1], [0, 2]])   # 0-2 is no edge
    assert (both.cocircular_edges, both.segment_edges, both.unique) == (0, 2, True)
    # a non-Delaunay diagonal is acceptable only when it is a segment
    kite = [[0, 0], [2, -1], [4, 0], [2, 3]]
    assert mesh_report(kite, [[0, 1, 2], [0, 2, 3]]).non_delaunay_edges == 1
    assert mesh_report(kite, [[0, 1, 2], [0, 2, 3]], segments=[[2, 0]]).non_delaunay_edges == 0


def test_duplicate_positions_are_merged_for_topology():
    # two triangles that share an edge only geometrically (separate vertex rows)
    V = [[0, 0], [4, 0], [4, 4], [0, 0], [4, 4], [0, 4]]
    rep = mesh_report(V, [[0, 1, 2], [3, 4, 5]])
    assert rep.merged_duplicates == 2 and rep.vertices == 4 and rep.input_vertices == 6
    assert rep.cocircular_edges == 1                     # the diagonal of a square
    # clockwise triangles are fine too
    assert mesh_report(V, [[0, 2, 1], [3, 5, 4]]).cocircular_edges == 1


def test_degenerate_triangles_in_another_mesh():
    V = [[0, 0], [2, 0], [4, 0], [2, 2]]
    rep = mesh_report(V, [[0, 1, 3], [1, 2, 3], [0, 2, 1]])    # plus a flat triangle 0-2-1
    assert rep.degenerate_triangles == 1
    assert rep.max_circumradius == np.inf and rep.min_angle == 0.0
    assert rep.non_delaunay_edges >= 1 and rep.unique is None


# ------------------------------------------------------------ the report
def test_report_figures_of_a_polygon_with_a_hole():
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    rep = tri.report()
    assert isinstance(rep, Report)
    assert (rep.input_vertices, rep.merged_duplicates, rep.steiner_vertices) == (8, 0, 0)
    assert (rep.vertices, rep.triangles, rep.segments, rep.segment_edges) == (8, 8, 8, 8)
    q = triangle_quality(tri.vertices, tri.triangles)
    angles = q["angles"]
    assert rep.min_angle == angles.min() and rep.max_angle == angles.max()
    assert angles[rep.min_angle_triangle].min() == rep.min_angle
    assert angles[rep.max_angle_triangle].max() == rep.max_angle
    assert q["circumradius"][rep.max_circumradius_triangle] == rep.max_circumradius == q["circumradius"].max()
    assert rep.max_min_containment_radius == q["min_containment_radius"].max()
    assert rep.mean_inradius == pytest.approx(q["inradius"].mean())
    assert rep.max_radius_edge_ratio == q["radius_edge_ratio"].max()
    assert rep.angle_counts.sum() == 3 * rep.triangles
    assert np.array_equal(rep.angle_bins, np.arange(0, 181, 10))
    assert rep.non_delaunay_edges == 0 and rep.degenerate_triangles == 0
    assert rep.flips == tri.stats["flips"] and rep.seconds == tri.stats["seconds"]
    assert rep.against is None and rep.comparison is None


def test_report_of_merged_duplicates_and_custom_bins():
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2], [2, 2]],
                                 [[0, 1], [1, 2], [2, 3], [3, 0]])
    rep = tri.report(bins=[0, 45.5, 90.5, 180])
    assert rep.input_vertices == 5 and rep.merged_duplicates == 1 and rep.vertices == 4
    assert rep.angle_counts.tolist() == [4, 2, 0]


def test_report_to_dict_json_and_table():
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    other = (tri.vertices, tri.triangles[:, [0, 2, 1]])      # same triangles, clockwise
    rep = compare(tri, other, against_name="mine")
    d = rep.to_dict()
    assert json.loads(rep.to_json()) == d
    assert d["triangles"] == 8 and d["against"]["name"] == "mine"
    assert d["angle_histogram"]["counts"] == rep.angle_counts.tolist()
    assert sum(d["against"]["angle_histogram"]["counts"]) == 24
    assert d["comparison"]["theorem_applies"] is True
    # the same mesh: the same figures (our segment pieces are its segments)
    for key in ("min_angle", "max_angle", "max_circumradius", "max_min_containment_radius",
                "mean_inradius", "non_delaunay_edges", "cocircular_edges", "segment_edges"):
        assert d[key] == d["against"][key], key
    text = str(rep)
    lines = text.splitlines()
    assert lines[0].split() == ["quality", "report", "cdt_plugin", "mine"]
    row = next(line for line in lines if line.startswith("triangles"))
    assert row.split() == ["triangles", "8", "8"]
    row = next(line for line in lines if line.startswith("min angle"))
    assert f"{rep.min_angle:.6g} (#{rep.min_angle_triangle})" in row
    assert lines[-1].startswith("Theorem 2.17 (same vertices): min angle not smaller: yes")


def test_report_without_triangles():
    tri = cdt_plugin.delaunay([[0, 0], [1, 1], [2, 2]])        # collinear: edges only
    rep = tri.report()
    assert rep.triangles == 0 and rep.min_angle is None and rep.unique is None
    assert json.loads(rep.to_json())["min_angle"] is None
    assert "min angle (deg)" in str(rep)


def test_report_of_weighted_triangulation_uses_lifted_test():
    pts = np.random.default_rng(2).uniform(0, 1, (60, 2))
    w = np.random.default_rng(3).uniform(0, 0.01, 60)
    tri = cdt_plugin.delaunay(pts, w)
    rep = tri.report()
    assert rep.non_delaunay_edges == 0 and tri.is_delaunay()
    assert rep.input_vertices == 60 and rep.vertices == len(np.unique(tri.triangles))


def test_against_accepts_triangulations_and_trimesh():
    trimesh = pytest.importorskip("trimesh")
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    by_pair = tri.report(against=(tri.vertices, tri.triangles)).against.to_dict()
    by_tri = tri.report(against=tri).against.to_dict()
    by_mesh = tri.report(against=tri.to_trimesh()).against.to_dict()
    assert by_pair == by_tri == by_mesh
    with pytest.raises(InputShapeError):
        tri.report(against="earcut")
    with pytest.raises(InputShapeError, match="out of range"):
        tri.report(against=(tri.vertices, [[0, 1, 99]]))
    with pytest.raises(CDTError):
        compare(tri, None)
    assert trimesh.Trimesh(np.c_[tri.vertices, np.zeros(8)], tri.triangles).area == 12.0


def test_steiner_points_make_the_comparison_not_applicable():
    pts = [[0, 0], [2, 2], [0, 2], [2, 0]]
    tri = cdt_plugin.triangulate(pts, [[0, 1], [2, 3]], intersections="split", keep_hull=True)
    assert len(tri.steiner) == 1
    rep = tri.report(against=(pts, [[0, 3, 1], [0, 1, 2]]))
    assert rep.steiner_vertices == 1
    assert rep.comparison["same_vertices"] is False and rep.comparison["theorem_applies"] is False
    assert str(rep).splitlines()[-1] == "Theorem 2.17 comparison: not applicable (the vertex sets differ)"
    rep = tri.report(against=tri)                            # with the Steiner point itself
    assert rep.comparison["same_vertices"] and not rep.comparison["theorem_applies"]
    assert str(rep).splitlines()[-1] == "Theorem 2.17 comparison: not applicable (Steiner points)"


def test_a_mesh_with_a_vertex_inside_an_edge_is_not_compared():
    # a quadrilateral with vertex 1 in the middle of the diagonal 0-2
    V = [[0, 0], [2, 0], [4, 0], [2, 2], [2, -2]]
    tri = cdt_plugin.triangulate(V, [[0, 4], [4, 2], [2, 3], [3, 0]])
    assert len(tri.triangles) == 4
    t_junction = [[0, 4, 2], [0, 1, 3], [1, 2, 3]]           # vertex 1 inside edge 0-2
    rep = tri.report(against=(V, t_junction))
    c = rep.comparison
    assert c["same_vertices"] and not c["same_triangle_count"] and not c["theorem_applies"]
    assert "not a triangulation of the same domain" in str(rep).splitlines()[-1]
    dropped = tri.report(against=(V, [[0, 4, 2], [0, 2, 3]]))  # vertex 1 not used at all
    assert not dropped.comparison["same_vertices"]


@pytest.mark.skipif("min_angle" not in inspect.signature(cdt_plugin.triangulate).parameters,
                    reason="triangulate has no quality refinement yet")
def test_report_of_a_refined_mesh():
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE, min_angle=30.0)
    rep = tri.report()
    assert rep.steiner_vertices == len(tri.steiner) > 0
    assert rep.min_angle >= 30.0 - 1e-9 and rep.non_delaunay_edges == 0
    assert rep.vertices == rep.input_vertices + rep.steiner_vertices
    assert rep.flips >= tri.stats["flips"]


# ---------------------------------------------- Theorem 2.17 on the corpus
def _polygon_inputs():
    try:
        from corpus import corpus_files, load_file
    except FileNotFoundError:  # pragma: no cover
        return []
    out = []
    for path in corpus_files():
        if path.parent.name in ("earcut", "gis"):
            out.extend(load_file(path))
    return out


def _mapping(plc):
    return {"type": "MultiPolygon", "coordinates": [[plc.vertices[plc.rings[r]].tolist() for r in poly]
                                                   for poly in plc.polygons]}


def test_theorem_2_17_against_earcut_on_the_corpus():
    """Without Steiner points our minimum angle is never smaller than earcut's, our
    largest circumdisk and min-containment disk never larger, on every corpus
    polygon where earcut triangulates the same vertices and domain."""
    pytest.importorskip("mapbox_earcut")
    shapely = pytest.importorskip("shapely")
    plcs = _polygon_inputs()
    if not plcs:
        pytest.skip("corpus not found")
    compared = earcut_not_delaunay = 0
    for plc in plcs:
        gi = _mapping(plc)
        try:
            geometry = shapely.geometry.shape(gi)
        except ValueError:          # a ring of fewer than 4 points: not a polygon
            continue
        if not geometry.is_valid:
            continue
        try:
            tri = cdt_plugin.triangulate(gi)
        except CDTError:
            continue
        assert len(tri.steiner) == 0
        V, T = earcut(gi)
        rep = tri.report(against=(V, T), against_name="earcut")
        assert rep.non_delaunay_edges == 0, plc.name
        c = rep.comparison
        if not c["theorem_applies"]:
            continue
        # earcut's mesh really is a triangulation of the same polygon: same area,
        # no degenerate triangle, as many triangles as ours
        P = V[T]
        area2 = np.abs((P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1])
                       - (P[:, 1, 1] - P[:, 0, 1]) * (P[:, 2, 0] - P[:, 0, 0]))
        assert area2.sum() / 2 == pytest.approx(geometry.area, rel=1e-9), plc.name
        assert rep.against.degenerate_triangles == 0 and len(T) == len(tri.triangles)
        ours, theirs = rep, rep.against
        assert ours.min_angle >= theirs.min_angle * (1 - RTOL), plc.name
        assert ours.max_circumradius <= theirs.max_circumradius * (1 + RTOL), plc.name
        assert ours.max_min_containment_radius <= theirs.max_min_containment_radius * (1 + RTOL), plc.name
        assert c["min_angle_not_smaller"] and c["max_circumradius_not_larger"] \
            and c["max_min_containment_not_larger"], plc.name
        compared += 1
        earcut_not_delaunay += rep.against.non_delaunay_edges > 0
    assert compared >= 400                  # earcut fixtures + Natural Earth features
    assert earcut_not_delaunay >= compared // 2
