"""Smoothing (``Triangulation.smooth``, ``triangulate(smooth=)``): ODT and Lloyd on
uniform and graded meshes. Every result is checked from scratch by the exact
checker (a constrained Delaunay triangulation of the same domain, every triangle
counter-clockwise, every segment the chain of its pieces, each Steiner point on a
segment within rounding of it), and against the mesh it came from: input vertices
unmoved, the same segments, the smallest angle not lower, the mean radius ratio
higher, a graded mesh's sizes kept."""
from __future__ import annotations

import numpy as np
import pytest
import triangle

import cdt_plugin
from cdt_plugin import CDTError, SizeFieldError
from cdt_plugin.report import triangle_quality
from checker import check_steiner_segments, check_triangulation, orient2d_exact

SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
HOLE = [[1.5, 1.5], [2.5, 1.5], [2.5, 2.5], [1.5, 2.5]]
SLIT = [[0.5, 3.2], [3.0, 3.4]]                # a segment inside the domain


def ring(n, start=0):
    return [[start + i, start + (i + 1) % n] for i in range(n)]


PTS = SQUARE + HOLE + SLIT
SEGS = ring(4) + ring(4, 4) + [[8, 9]]


def min_angles(V, T):
    """Each triangle's smallest angle (degrees), as the quality report measures it."""
    return triangle_quality(V, T)["angles"].min(axis=1)


def radius_ratios(V, T):
    """2 r / R of each triangle (1: equilateral), from its sides."""
    P = V[T]
    a, b, c = (np.hypot(*(P[:, (j + 1) % 3] - P[:, (j + 2) % 3]).T) for j in range(3))
    s = (a + b + c) / 2
    area = np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0))
    return 2 * (area / s) / (a * b * c / (4 * area))


def longest_edges(V, T):
    P = V[T]
    return np.sqrt(((P - P[:, [1, 2, 0]]) ** 2).sum(axis=2).max(axis=1))


def verify_smoothed(base, out, in_points=None, in_segments=None):
    """``out`` is ``base`` smoothed: the guarantees of ``Triangulation.smooth``."""
    V, T = out.vertices, out.triangles
    assert V.shape == base.vertices.shape
    fixed = np.ones(len(V), bool)
    fixed[base.steiner] = False
    assert np.array_equal(V[fixed], base.vertices[fixed]), "an input vertex moved"
    assert np.array_equal(out.steiner, base.steiner) and np.array_equal(out.vertex_map, base.vertex_map)
    # never inverts: every triangle counter-clockwise, exactly
    for t in T[:: max(1, len(T) // 300)]:
        assert orient2d_exact(V[t[0]], V[t[1]], V[t[2]]) > 0
    # the same segments (as vertex pairs, with their ids) and the flags that say so
    assert np.array_equal(out.segments, base.segments) and np.array_equal(out.segment_ids, base.segment_ids)
    flagged = {frozenset((int(t[(j + 1) % 3]), int(t[(j + 2) % 3])))
               for t, c in zip(T.tolist(), out.constrained.tolist()) for j in range(3) if c[j]}
    assert {frozenset(p) for p in out.segments.tolist()} == flagged
    # a valid constrained Delaunay triangulation of the domain, every triangle oriented
    rep = check_triangulation(V, T, segments=out.segments, domain="segments")
    assert rep.ok, str(rep)
    assert out.is_delaunay()
    # the domain's area is the same (the boundary's Steiner points slid along it)
    assert areas(V, T).sum() == pytest.approx(areas(base.vertices, base.triangles).sum(), rel=1e-12)
    if in_points is not None:   # each Steiner point on a segment within rounding of it, in order
        rep = check_steiner_segments(in_points, in_segments, V, out.vertex_map, out.segments,
                                     out.segment_ids)
        assert rep.ok, str(rep)
    before, after = min_angles(base.vertices, base.triangles), min_angles(V, T)
    assert after.min() >= before.min()
    assert radius_ratios(V, T).mean() > radius_ratios(base.vertices, base.triangles).mean()
    moved = np.flatnonzero((V != base.vertices).any(axis=1))
    assert len(moved) > len(base.steiner) // 4, "smoothing moved (almost) nothing"
    return moved


def areas(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2


def on_segment_steiner(tri):
    """Steiner vertices that are ends of a segment piece."""
    return np.intersect1d(np.unique(tri.segments), tri.steiner)


@pytest.fixture(scope="module")
def uniform():
    return cdt_plugin.triangulate(PTS, SEGS, holes=[[2, 2]], min_angle=28, max_area=0.01)


def size_at(x, y):
    """A graded size: fine at the corner (0, 0), coarse far from it."""
    return 0.02 + 0.12 * np.hypot(x, y)


@pytest.fixture(scope="module")
def graded():
    def small_enough(org, dest, apex, area):
        c = (org + dest + apex) / 3
        return area <= 0.433 * size_at(c[:, 0], c[:, 1]) ** 2
    return cdt_plugin.triangulate(PTS, SEGS, holes=[[2, 2]], min_angle=25, suitable=small_enough)


@pytest.mark.parametrize("method", ["odt", "lloyd"])
def test_uniform_mesh_guarantees(uniform, method):
    out = uniform.smooth(method, 8)
    moved = verify_smoothed(uniform, out, PTS, SEGS)
    sliding = np.intersect1d(on_segment_steiner(uniform), moved)
    assert len(sliding) > 10, "no Steiner point slid along its segment"
    s = out.stats["smoothing"]
    assert s["method"] == method and s["sweeps"] <= 8 and len(s["moved"]) == s["sweeps"]
    assert s["before"]["min_angle"] == pytest.approx(min_angles(uniform.vertices, uniform.triangles).min())
    assert s["after"]["mean_radius_ratio"] == pytest.approx(radius_ratios(out.vertices, out.triangles).mean())
    for side in ("before", "after"):
        assert sum(s[side]["radius_ratio_histogram"]["counts"]) == len(out.triangles)
        assert sum(s[side]["angle_histogram"]["counts"]) == 3 * len(out.triangles)


@pytest.mark.parametrize("method", ["odt", "lloyd"])
@pytest.mark.parametrize("size", [None, size_at])
def test_graded_mesh_stays_graded(graded, method, size):
    out = graded.smooth(method, 10, size=size)
    verify_smoothed(graded, out, PTS, SEGS)
    # the sizes: the side of the equilateral triangle of each triangle's area over
    # the field at its centroid (the longest edge would shrink as shapes improve):
    # the same median, and no wider spread than before
    def ratios(tri):
        c = tri.vertices[tri.triangles].mean(axis=1)
        side = np.sqrt(4 * areas(tri.vertices, tri.triangles) / np.sqrt(3))
        return side / size_at(c[:, 0], c[:, 1])
    before, after = ratios(graded), ratios(out)
    assert np.median(after) == pytest.approx(np.median(before), rel=0.05)
    spread = lambda r: np.quantile(r, 0.9) / np.quantile(r, 0.1)
    assert spread(after) <= spread(before)
    # fine stays fine: the triangles near the corner are as small as before
    near = lambda tri: np.hypot(*tri.vertices[tri.triangles].mean(axis=1).T) < 0.5
    assert longest_edges(out.vertices, out.triangles[near(out)]).mean() == pytest.approx(
        longest_edges(graded.vertices, graded.triangles[near(graded)]).mean(), rel=0.1)


def test_a_uniform_size_on_a_graded_mesh_moves_vertices_toward_the_coarse_side(graded):
    """The size field counts: a uniform one lets the fine corner's vertices
    spread, the mesh's own sizes hold them (the means of the distance of the
    Steiner points to the fine corner)."""
    own = graded.smooth("odt", 10)
    flat = graded.smooth("odt", 10, size=1.0)
    field = graded.smooth("odt", 10, size=size_at)
    spread = lambda tri: np.hypot(*tri.vertices[tri.steiner].T).mean()
    assert spread(flat) > spread(own) and spread(flat) > spread(field)


def test_on_segments_false_keeps_the_points_on_segments(uniform):
    out = uniform.smooth("odt", 5, on_segments=False)
    verify_smoothed(uniform, out, PTS, SEGS)
    on = on_segment_steiner(uniform)
    assert len(on) > 10 and np.array_equal(out.vertices[on], uniform.vertices[on])
    assert out.stats["smoothing"]["sliding_vertices"] == 0


def test_min_angle_lets_the_smallest_angle_fall_to_the_bound_only(uniform):
    before = min_angles(uniform.vertices, uniform.triangles)
    out = uniform.smooth("odt", 8, min_angle=20)
    rep = check_triangulation(out.vertices, out.triangles, segments=out.segments, domain="segments")
    assert rep.ok, str(rep)
    assert min_angles(out.vertices, out.triangles).min() >= 20 and len(out.below_min_angle) == 0
    # a bound above the mesh's smallest angle: the triangles below it are named
    bound = 40.0
    loose = uniform.smooth("odt", 8, min_angle=bound)
    angles = min_angles(loose.vertices, loose.triangles)
    assert angles.min() >= before.min()
    assert np.array_equal(loose.below_min_angle, np.flatnonzero(angles < bound))
    assert len(loose.below_min_angle) > 0


def test_boundary_of_a_refined_mesh_slides_along_it():
    """A mesh made elsewhere, refined: the boundary's Steiner points (pieces of
    id -1) slide along the square's sides, which they never leave (x or y
    exactly 0 or 1 on the sides)."""
    V = [[0, 0], [1, 0], [1, 1], [0, 1], [0.4, 0.6]]
    T = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    base = cdt_plugin.Triangulation.from_triangles(V, T).refine(min_angle=25, max_area=0.002)
    out = base.smooth("lloyd", 6)
    verify_smoothed(base, out)
    on_boundary = np.unique(out.segments)
    P = out.vertices[on_boundary]
    assert ((P[:, 0] == 0) | (P[:, 0] == 1) | (P[:, 1] == 0) | (P[:, 1] == 1)).all()
    assert not np.array_equal(P, base.vertices[on_boundary])


def test_nothing_moves_without_steiner_points():
    tri = cdt_plugin.triangulate(SQUARE + [[1, 2], [3, 1], [2, 3]])
    out = tri.smooth()
    assert np.array_equal(out.vertices, tri.vertices) and np.array_equal(out.triangles, tri.triangles)
    assert out.stats["smoothing"]["sweeps"] == 0


def test_markers_attributes_and_regions_are_carried():
    pts = SQUARE + [[2, 0], [2, 4]]
    segs = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    regions = [[1, 1, 10.0, 0], [3, 3, 20.0, 0]]
    attrs = np.array(pts, float) @ [1.0, 2.0] + 3       # linear: carried exactly up to rounding
    tri = cdt_plugin.triangulate(pts, segs, regions=regions, min_angle=25, max_area=0.05,
                                 segment_markers=[5, 5, 6, 6, 7, 7, 9], vertex_attributes=attrs)
    out = tri.smooth("odt", 6)
    verify_smoothed(tri, out, pts, segs)
    assert np.array_equal(out.segment_markers, tri.segment_markers)
    assert np.array_equal(out.vertex_markers, tri.vertex_markers)
    expected = out.vertices @ [1.0, 2.0] + 3
    assert np.allclose(out.vertex_attributes[:, 0], expected, rtol=0, atol=1e-12)
    # each triangle keeps the region it lies in (the left or right half)
    c = out.vertices[out.triangles].mean(axis=1)
    assert np.array_equal(out.regions, np.where(c[:, 0] < 2, 0, 1))
    assert np.array_equal(out.region_attributes, np.where(c[:, 0] < 2, 10.0, 20.0))


def test_triangulate_smooth_keyword(uniform):
    for smooth, method, iterations in (("odt", "odt", 10), ("lloyd", "lloyd", 10), (3, "odt", 3)):
        out = cdt_plugin.triangulate(PTS, SEGS, holes=[[2, 2]], min_angle=28, max_area=0.01,
                                     smooth=smooth)
        again = uniform.smooth(method, iterations)
        assert np.array_equal(out.vertices, again.vertices)
        assert np.array_equal(out.triangles, again.triangles)
        assert out.stats["smoothing"]["method"] == method
        assert out.stats["smoothing"]["iterations"] == iterations


def test_smoothed_beats_triangles_quality_mesh():
    """The same domain and bounds in Triangle (``pq28a0.01``): our smoothed mesh
    has a larger smallest angle and mean radius ratio than Triangle's."""
    pts = np.array(PTS, float)
    theirs = triangle.triangulate({"vertices": pts, "segments": np.array(SEGS), "holes": [[2, 2]]},
                                  "pq28a0.01Q")
    ours = cdt_plugin.triangulate(PTS, SEGS, holes=[[2, 2]], min_angle=28, max_area=0.01, smooth="odt")
    V, T = theirs["vertices"], theirs["triangles"]
    assert min_angles(ours.vertices, ours.triangles).min() >= min_angles(V, T).min() - 0.5
    assert radius_ratios(ours.vertices, ours.triangles).mean() > radius_ratios(V, T).mean()


@pytest.mark.parametrize("kwargs, message", [
    ({"method": "laplace"}, "method must be one of 'odt', 'lloyd'"),
    ({"iterations": -1}, "iterations must be a whole number"),
    ({"iterations": 2.5}, "iterations must be a whole number"),
    ({"size": -1.0}, "size must be a positive finite length, got -1.0"),
    ({"size": float("nan")}, "size must be a positive finite length, got nan"),
    ({"size": "big"}, "size must be a positive number, a callable f"),
    ({"on_segments": "yes"}, "on_segments must be True or False"),
    ({"min_angle": 70}, "min_angle must be a number of degrees between 0 and 60"),
])
def test_bad_options_are_named(uniform, kwargs, message):
    with pytest.raises(CDTError, match=message):
        uniform.smooth(**kwargs)


def test_bad_size_values_are_named(uniform):
    with pytest.raises(SizeFieldError, match=r"size gave -1.0 at \("):
        uniform.smooth(size=lambda x, y: np.where(x > 2, -1.0, 0.1))
    with pytest.raises(SizeFieldError, match=r"size gave an array of shape \(3,\)|shape"):
        uniform.smooth(size=lambda x, y: np.ones(3))


def test_a_background_mesh_is_a_size_field_here_too(uniform):
    # the size field type of triangulate(size=): a Triangulation carrying sizes at its vertices
    background = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4]],
                                        vertex_attributes=[[0.1], [0.4], [0.4], [0.4]])
    out = uniform.smooth(size=background)
    assert out.stats["smoothing"]["after"]["size_ratio_quantiles"]


def test_bad_smooth_keyword_before_any_work():
    with pytest.raises(CDTError, match="smooth must be None, 'odt', 'lloyd' or a number"):
        cdt_plugin.triangulate([[0, 0], [1, 0]], smooth=2.5)     # (too few points: not reached)
    with pytest.raises(CDTError, match="method must be one of"):
        cdt_plugin.triangulate([[0, 0], [1, 0]], smooth="laplace")


def test_weighted_triangulations_are_refused():
    tri = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1], [1, 1]], weights=[0, 0, 0, 0.1])
    with pytest.raises(CDTError, match="unweighted"):
        tri.smooth()
