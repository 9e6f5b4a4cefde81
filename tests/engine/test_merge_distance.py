"""``merge_distance``: input points closer than it merged before meshing, by the
documented rule (lexicographic order; a point closer than the distance to a
point kept before it goes to the nearest such point), checked against a plain
quadratic reference; the meshes by the exact checker; and the ``min_angle``
range (a warning above the practical termination range, an error where no
triangle can meet the bound)."""
from __future__ import annotations

import warnings

import numpy as np
import pytest
import shapely

import cdt_plugin
from cdt_plugin import (CDTError, InvalidGeometryError, OverlappingSegmentsError,
                        RefinementRangeError, RefinementRangeWarning, SegmentIntersectionError)
from cdt_plugin.merging import close_point_representatives
from cdt_plugin.options import TERMINATING_MIN_ANGLE
from checker import check_steiner_segments, check_triangulation


def reference_representatives(xy, distance):
    """The rule in plain Python: lexicographic order (input order on ties), a
    point goes to the nearest earlier kept point closer than ``distance`` (the
    earliest on a tie), else it is kept."""
    order = sorted(range(len(xy)), key=lambda i: (xy[i][0], xy[i][1], i))
    rep, kept = [None] * len(xy), []
    for p in order:
        best, best_d = None, distance
        for q in kept:                       # in order: strict < keeps the earliest on ties
            d = float(np.hypot(xy[p][0] - xy[q][0], xy[p][1] - xy[q][1]))
            if d < best_d:
                best, best_d = q, d
        if best is None:
            kept.append(p)
            rep[p] = p
        else:
            rep[p] = best
    return rep


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("distance", [1e-3, 0.02, 0.05, 0.3])
def test_rule_matches_the_reference(seed, distance):
    rng = np.random.default_rng(seed)
    # points on a coarse grid: many exact ties of distance and of coordinates
    xy = np.round(rng.random((400, 2)) * 40) / 40 * (1 + seed)
    rep = close_point_representatives(xy, distance)
    assert rep.tolist() == reference_representatives(xy.tolist(), distance)
    kept = np.flatnonzero(rep == np.arange(len(xy)))
    assert (rep[rep] == rep).all()                                   # representatives are kept
    assert (np.hypot(*(xy - xy[rep]).T) < distance).all()           # merged within the distance
    gaps = np.hypot(*(xy[kept, None] - xy[None, kept]).transpose(2, 0, 1))
    assert (gaps[~np.eye(len(kept), dtype=bool)] >= distance).all()  # no two kept points closer


@pytest.mark.parametrize("scale", [1e-200, 1.0, 1e15, 1e200])
def test_rule_at_every_magnitude_and_in_any_input_order(scale):
    rng = np.random.default_rng(7)
    xy = (rng.random((300, 2)) + 1.0) * scale
    xy[100:150] = xy[:50] + rng.normal(size=(50, 2)) * 1e-10 * scale     # near-duplicates
    distance = 1e-8 * scale
    rep = close_point_representatives(xy, distance)
    assert rep.tolist() == reference_representatives(xy.tolist(), distance)
    perm = rng.permutation(len(xy))
    rep_perm = close_point_representatives(xy[perm], distance)
    # the same points kept, each point sent to the same place
    assert np.array_equal(xy[perm][rep_perm], xy[rep][perm])


# -------------------------------------------------------------------- through triangulate
NEAR = shapely.Polygon([(0, 0), (1e-12, 0), (4, 0), (4, 4), (4, 4 + 1e-13), (0, 4)],
                       [[(1, 1), (1, 3), (3, 3), (3, 1), (3 + 1e-14, 1)]])


def area(tri):
    a, b, c = (tri.vertices[tri.triangles[:, k]] for k in range(3))
    return 0.5 * float(((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]).sum())


def merged_input(tri, vertices):
    """The input as the engine meshed it: each point moved onto its output vertex."""
    return np.asarray(tri.vertices)[tri.vertex_map], np.asarray(vertices, float)


def test_near_duplicates_of_a_cad_outline_are_merged_and_reported():
    with pytest.raises(OverlappingSegmentsError):       # without: a needle overlap in the hole
        cdt_plugin.triangulate(NEAR)
    tri = cdt_plugin.triangulate(NEAR, merge_distance=1e-9, min_angle=30)
    plc = cdt_plugin.PLC.from_geo_interface(NEAR)
    moved, original = merged_input(tri, plc.vertices)
    assert tri.stats["merged_points"] == 3
    assert (np.hypot(*(moved - original).T) < 1e-9).all()
    assert sorted(map(tuple, tri.vertices[:8].tolist())) == sorted(
        [(0, 0), (4, 0), (4, 4), (0, 4), (1, 1), (1, 3), (3, 3), (3, 1)])
    # the three segments whose ends merged are gone; the rest meshed exactly
    zero = tri.stats["zero_length_segments"]
    assert len(zero) == 3 and all(tri.vertex_map[a] == tri.vertex_map[b] for a, b in plc.segments[zero])
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="segments",
                              require_all_vertices=False)
    assert rep.ok, str(rep)
    live = np.setdiff1d(np.arange(len(plc.segments)), zero)
    rep = check_steiner_segments(moved, plc.segments[live], tri.vertices, tri.vertex_map,
                                 tri.segments, np.searchsorted(live, tri.segment_ids))
    assert rep.ok, str(rep)
    assert len(tri.below_min_angle) == 0
    # the hole is still a hole: area 16 - 4
    assert area(tri) == pytest.approx(12.0, rel=1e-12)


def test_segments_remapped_duplicates_dropped_seeds_kept():
    # two triangles of segments whose corners nearly coincide, and a hole seed
    V = np.array([[0, 0], [10, 0], [5, 8], [0, 1e-7], [10, 1e-7], [4, 3], [6, 3], [5, 5]], float)
    S = np.array([[0, 1], [1, 2], [2, 0], [3, 4], [0, 3], [5, 6], [6, 7], [7, 5]])
    tri = cdt_plugin.triangulate(V, S, holes=[[5, 3.5]], merge_distance=1e-6)
    assert tri.vertex_map.tolist() == [0, 1, 2, 0, 1, 3, 4, 5]
    assert tri.stats["merged_points"] == 2
    assert tri.stats["zero_length_segments"] == [4]        # 0-3: both ends are now one point
    assert tri.stats["duplicate_segments"] == 1            # 3-4 became 0-1
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    assert rep.ok, str(rep)
    # the hole seed was not moved: the inner triangle is still cut out
    assert area(tri) == pytest.approx(40.0 - 2.0, rel=1e-12)


def test_a_crossing_made_by_merging_is_named_or_split():
    # vertex 3 (1, 0.05) merges into the isolated vertex 4 (1, -0.04), kept before it:
    # segment 1 then crosses segment 0 at (1, 0)
    V = np.array([[0, 0], [2, 0], [1, 1], [1, 0.05], [1, -0.04]])
    S = np.array([[0, 1], [2, 3]])
    with pytest.raises(SegmentIntersectionError, match="segments 1 .* and 0 .* cross|segments 0 .* and 1 .* cross"):
        cdt_plugin.triangulate(V, S, merge_distance=0.1)
    tri = cdt_plugin.triangulate(V, S, merge_distance=0.1, intersections="split", keep_hull=True)
    assert tri.vertex_map[3] == tri.vertex_map[4] and tri.stats["merged_points"] == 1
    assert tri.stats["intersection_points"] == 1
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments)
    assert rep.ok, str(rep)


def test_default_and_zero_change_nothing():
    square = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 1e-12]]
    plain = cdt_plugin.triangulate(square)
    for distance in (None, 0, 0.0):
        tri = cdt_plugin.triangulate(square, merge_distance=distance)
        assert np.array_equal(tri.vertices, plain.vertices)
        assert np.array_equal(tri.triangles, plain.triangles)
        assert tri.stats["merged_points"] == 0


@pytest.mark.parametrize("value", [-1.0, float("inf"), float("nan"), "1e-9", True, [1e-9]])
def test_bad_merge_distance_is_named(value):
    with pytest.raises(CDTError, match="merge_distance"):
        cdt_plugin.triangulate([[0, 0], [1, 0], [0, 1]], merge_distance=value)


def test_batch_refuses_merge_distance():
    from cdt_plugin.batch import triangulate_rings
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    with pytest.raises(CDTError, match="merge_distance is not supported by the batch path"):
        triangulate_rings(xy, [0, 4], [0, 1], [0], [False], merge_distance=1e-9)


# -------------------------------------------------------------------------- min_angle range
BOX = shapely.box(0, 0, 3, 1)


def test_min_angle_above_the_practical_range_warns_before_any_work():
    with warnings.catch_warnings():
        warnings.simplefilter("error", RefinementRangeWarning)
        # the input is invalid (a hole outside its shell): the warning comes first
        bad = shapely.Polygon([(0, 0), (1, 0), (0, 1)], [[(5, 5), (6, 5), (5, 6)]])
        with pytest.raises(RefinementRangeWarning, match=r"min_angle=40 is above .*about 34"):
            cdt_plugin.triangulate(bad, min_angle=40)
    with pytest.raises(InvalidGeometryError):
        with pytest.warns(RefinementRangeWarning):
            cdt_plugin.triangulate(bad, min_angle=40)


def test_min_angle_warning_is_given_at_every_call_and_the_mesh_still_made():
    for _ in range(2):        # (the options of a call are cached: the warning must not be)
        with pytest.warns(RefinementRangeWarning):
            tri = cdt_plugin.triangulate(BOX, min_angle=35)
        rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments,
                                  domain="segments", require_all_vertices=False)
        assert rep.ok, str(rep)


@pytest.mark.parametrize("angle", [0, 20.7, 30, TERMINATING_MIN_ANGLE])
def test_min_angle_within_the_range_does_not_warn(angle):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RefinementRangeWarning)
        cdt_plugin.triangulate(BOX, min_angle=angle)


@pytest.mark.parametrize("angle", [60, 75.0, -1, float("nan"), float("inf")])
def test_min_angle_no_triangle_can_meet_raises_with_the_range(angle):
    with pytest.raises(RefinementRangeError, match=r"min_angle must be in \[0, 60\) degrees"):
        cdt_plugin.triangulate(BOX, min_angle=angle)
    assert issubclass(RefinementRangeError, CDTError)


def test_refine_and_batch_check_min_angle_the_same_way():
    tri = cdt_plugin.triangulate(BOX)
    with pytest.warns(RefinementRangeWarning):
        tri.refine(min_angle=36)
    with pytest.raises(RefinementRangeError):
        tri.refine(min_angle=60)
    from cdt_plugin.batch import triangulate_rings
    xy = np.array([[0, 0], [3, 0], [3, 1], [0, 1.0]])
    with pytest.warns(RefinementRangeWarning):
        triangulate_rings(xy, [0, 4], [0, 1], [0], [False], min_angle=36)
