"""Size fields in the engine: ``triangulate(size=, max_area=<callable>, growth=, min_size=)``
and ``Triangulation.refine`` with the same keywords (:mod:`cdt_plugin.grading`).

Fields with known answers (constant, a linear ramp, a point source, a line source): every
triangle's longest edge at most 1.5x the field at its centroid, the median near 1, few
triangles needlessly small, and the triangle count following the integral of 1 / size**2
(the number of triangles of size h that fit in an area is proportional to area / h**2,
whatever the field). Every mesh is checked with the exact checker."""
from __future__ import annotations

import time

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin.errors import CDTError, RefinementLimitError, SizeFieldError
from cdt_plugin.fields import as_size_field, graded_sizes, size_values
from cdt_plugin.refining import triangle_areas
from cdt_plugin.report import size_ratios
from tests.support.checker import assert_valid, check_steiner_segments

SQUARE = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
RING = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])

FIELDS = {
    "constant": lambda x, y: np.full(np.shape(x), 0.03),
    "ramp": lambda x, y: 0.01 + 0.06 * x,
    "point": lambda x, y: 0.004 + 0.15 * np.hypot(x - 0.3, y - 0.6),
    "line": lambda x, y: 0.004 + 0.15 * np.abs(y - 0.45),
}


def checked(tri, points=SQUARE, segments=RING):
    """The exact checks every mesh of these tests passes: a valid triangulation of the
    domain whose segments are the input's, split at points on them."""
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    rep = check_steiner_segments(points, segments, tri.vertices, tri.vertex_map, tri.segments,
                                 tri.segment_ids)
    assert rep.ok, str(rep)
    return tri


def min_angles(tri):
    return cdt_plugin.report.triangle_quality(tri.vertices, tri.triangles)["angles"].min(axis=1)


def density_integral(f, n=801):
    """The integral of 1 / f**2 over the unit square, by the midpoint rule on a grid
    (independent of any mesh)."""
    s = (np.arange(n) + 0.5) / n
    x, y = np.meshgrid(s, s)
    return float((1.0 / f(x, y) ** 2).mean())


@pytest.mark.parametrize("min_angle", [None, 28])
@pytest.mark.parametrize("name", list(FIELDS))
def test_known_fields_are_met(name, min_angle):
    f = FIELDS[name]
    size = 0.03 if name == "constant" else f
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, size=size, min_angle=min_angle))
    r = size_ratios(tri, f)
    assert r["over_1_5"] == 0 and r["max"] <= 1.5
    assert 0.85 < r["median"] < 1.15, r
    assert r["q05"] > 0.5, r            # few needlessly small triangles
    if min_angle:
        assert min_angles(tri).min() >= min_angle - 1e-9
    assert tri.stats["size_rounds"] >= 0


def test_the_count_follows_the_integral_of_the_density():
    """N / (integral of 1 / h**2) is the same for every field: the mesh puts its triangles
    where the field asks for them, in the numbers it asks."""
    per_density = []
    for name, f in FIELDS.items():
        tri = cdt_plugin.triangulate(SQUARE, RING, size=f, min_angle=28)
        per_density.append(len(tri.triangles) / density_integral(f))
    assert max(per_density) / min(per_density) < 1.3, per_density


def test_the_ramp_is_met_along_its_slope():
    f = FIELDS["ramp"]
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, size=f, min_angle=28))
    c = tri.vertices[tri.triangles].mean(axis=1)
    V, T = tri.vertices, tri.triangles
    longest = np.sqrt(((V[T] - V[T][:, [1, 2, 0]]) ** 2).sum(axis=2).max(axis=1))
    for lo in np.arange(0.1, 0.9, 0.1):          # strips across the slope, away from the sides
        strip = (c[:, 0] >= lo) & (c[:, 0] < lo + 0.1) & (c[:, 1] > 0.1) & (c[:, 1] < 0.9)
        ratio = np.median(longest[strip] / f(c[strip, 0], c[strip, 1]))
        assert 0.8 < ratio < 1.2, (lo, ratio)


def test_a_callable_max_area_is_a_strict_bound():
    def area(x, y):
        return 1e-4 + 0.01 * (x + y)
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, max_area=area, min_angle=25))
    c = tri.vertices[tri.triangles].mean(axis=1)
    assert (triangle_areas(tri.vertices, tri.triangles) <= area(c[:, 0], c[:, 1])).all()
    assert min_angles(tri).min() >= 25 - 1e-9
    # and with a number as well: both bounds hold
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, max_area=area, size=0.05))
    A = triangle_areas(tri.vertices, tri.triangles)
    c = tri.vertices[tri.triangles].mean(axis=1)
    assert (A <= area(c[:, 0], c[:, 1])).all() and size_ratios(tri, 0.05)["over_1_5"] == 0


def test_a_background_mesh_is_interpolated_linearly():
    """A background whose vertex sizes sample a linear field is that field inside its
    triangles: the mesh meets the ramp itself."""
    f = FIELDS["ramp"]
    grid = np.array([[i / 4, j / 4] for i in range(5) for j in range(5)])
    background = cdt_plugin.triangulate(grid, vertex_attributes=f(grid[:, 0], grid[:, 1]))
    values = as_size_field(background)(np.array([0.3, 0.71]), np.array([0.2, 0.9]))
    assert np.allclose(values, f(np.array([0.3, 0.71]), np.array([0.2, 0.9])), rtol=1e-12)
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, size=background, min_angle=28))
    r = size_ratios(tri, f)
    assert r["over_1_5"] == 0 and 0.85 < r["median"] < 1.15


def test_a_background_that_does_not_cover_the_domain_is_named():
    small = cdt_plugin.triangulate([[0, 0], [0.5, 0], [0, 0.5]], vertex_attributes=[0.1, 0.1, 0.1])
    with pytest.raises(SizeFieldError, match="outside the background mesh") as info:
        cdt_plugin.triangulate(SQUARE, RING, size=small)
    assert info.value.point is not None
    with pytest.raises(SizeFieldError, match="vertex_attributes"):
        cdt_plugin.triangulate(SQUARE, RING, size=cdt_plugin.triangulate(SQUARE))
    negative = cdt_plugin.triangulate(SQUARE, vertex_attributes=[0.1, -0.1, 0.1, 0.1])
    with pytest.raises(SizeFieldError, match=r"vertex 1 \(1.0, 0.0\) is -0.1"):
        cdt_plugin.triangulate(SQUARE, RING, size=negative)


def jump(x, y):
    """0.005 in a band, 0.2 elsewhere: a jump that needs grading."""
    return np.where(np.abs(y - 0.5) < 0.05, 0.005, 0.2)


def neighbour_ratios(tri):
    V, T, N = tri.vertices, tri.triangles, tri.neighbors
    longest = np.sqrt(((V[T] - V[T][:, [1, 2, 0]]) ** 2).sum(axis=2).max(axis=1))
    t, j = np.nonzero(N >= 0)
    return longest[t] / longest[N[t, j]]


def test_growth_grades_a_jump():
    steep = checked(cdt_plugin.triangulate(SQUARE, RING, size=jump))
    graded = checked(cdt_plugin.triangulate(SQUARE, RING, size=jump, growth=1.2))
    # the graded field is what the mesh meets...
    r = size_ratios(graded, jump, growth=1.2)
    assert r["over_1_5"] == 0 and 0.85 < r["median"] < 1.15
    # ...and neighbouring triangles differ less than across the ungraded jump
    assert neighbour_ratios(graded).max() < neighbour_ratios(steep).max()
    assert np.quantile(neighbour_ratios(graded), 0.99) < 2.0
    # near the band the graded mesh is finer than 0.2: at distance d from it the graded size
    # is at most 0.005 + 0.2 (path length), from 0.015 at d = 0.05 to 0.045 at d = 0.2
    for mesh, fine in ((graded, True), (steep, False)):
        V, T = mesh.vertices, mesh.triangles
        d = np.abs(V[T].mean(axis=1)[:, 1] - 0.5) - 0.05
        longest = np.sqrt(((V[T] - V[T][:, [1, 2, 0]]) ** 2).sum(axis=2).max(axis=1))
        near = (d > 0.05) & (d < 0.2)
        assert (np.median(longest[near]) < 0.1) == fine


def test_graded_sizes_is_the_smallest_path_bound():
    """On a small mesh the limited field equals the brute force minimum over every point
    of (its size + slope * shortest path), the path along the edges and centroid links."""
    rng = np.random.default_rng(5)
    tri = cdt_plugin.triangulate(rng.random((40, 2)))
    V, T = tri.vertices, tri.triangles
    n, m = len(V), len(T)
    hv, hc = rng.uniform(0.01, 1, n), rng.uniform(0.01, 1, m)
    got = graded_sizes(V, T, hv, hc, 1.3)
    P = np.vstack([V, V[T].mean(axis=1)])
    D = np.full((n + m, n + m), np.inf)
    np.fill_diagonal(D, 0)
    pairs = [(a, b) for a, b in tri.edges] + [(n + t, v) for t in range(m) for v in T[t]]
    for a, b in pairs:
        D[a, b] = D[b, a] = np.hypot(*(P[a] - P[b]))
    for k in range(n + m):           # Floyd-Warshall
        D = np.minimum(D, D[:, k:k + 1] + D[k:k + 1, :])
    want = (np.concatenate([hv, hc])[None, :] + 0.3 * D).min(axis=1)[n:]
    assert np.allclose(got, want, rtol=1e-12)


def test_a_vanishing_field_ends_with_a_named_error_in_bounded_time():
    def cone(x, y):
        return np.hypot(x - 0.5, y - 0.5)
    t0 = time.perf_counter()
    with pytest.raises(RefinementLimitError, match="size field") as info:
        cdt_plugin.triangulate(SQUARE, RING, size=cone, max_steiner=20_000)
    assert time.perf_counter() - t0 < 120          # (a hang would be caught here, not a speed)
    partial = info.value.triangulation
    assert partial is not None
    checked(partial)
    # with a floor it ends, and meets the floored field
    tri = checked(cdt_plugin.triangulate(SQUARE, RING, size=cone, min_size=0.01, min_angle=25))
    assert size_ratios(tri, cone, min_size=0.01)["over_1_5"] == 0


def test_a_field_that_vanishes_without_the_steiner_cap_still_ends():
    """Triangle's `-u` hangs on a test that no triangle passes; here the double-precision
    limit or the default cap end it."""
    with pytest.raises(RefinementLimitError):
        cdt_plugin.triangulate(SQUARE, RING, size=lambda x, y: np.hypot(x - 0.5, y - 0.5) ** 4)


@pytest.mark.parametrize("size, match", [
    ("fine", "size must be a positive number, a callable"),
    (True, "size must be a positive number, a callable"),
    (-1.0, "size must be a positive finite length, got -1.0"),
    (float("nan"), "size must be a positive finite length"),
    (lambda x, y: np.ones(3), r"size must return one value per point, shape \(\d+,\)"),
    (lambda x, y: np.where(x > 0.5, np.nan, 0.1), r"size gave nan at \("),
    (lambda x, y: 0.1 - x, r"size gave -0\.\d+ at \("),
    (lambda x, y: np.full(np.shape(x), "a"), "size must return real numbers"),
    (lambda x, y: 1 / 0, "size failed on .* ZeroDivisionError"),
])
def test_bad_fields_are_named(size, match):
    with pytest.raises(SizeFieldError, match=match):
        cdt_plugin.triangulate(SQUARE, RING, size=size)


def test_a_bad_value_names_the_point_and_the_value():
    with pytest.raises(SizeFieldError) as info:
        size_values(lambda x, y: x - 0.5, np.array([1.0, 0.25]), np.array([0.0, 0.75]))
    assert info.value.point == (0.25, 0.75) and info.value.value == -0.25


@pytest.mark.parametrize("keywords, match", [
    ({"size": 0.1, "growth": 1.0}, "growth must be a finite number > 1"),
    ({"size": 0.1, "growth": np.inf}, "growth must be a finite number > 1"),
    ({"size": 0.1, "growth": "1.2"}, "growth must be a number"),
    ({"size": 0.1, "min_size": 0}, "min_size must be a positive finite length"),
    ({"growth": 1.2}, "growth applies to a size field"),
    ({"min_size": 0.1}, "min_size applies to a size field"),
    ({"max_area": lambda x, y: x - 2}, r"max_area gave -\d"),
])
def test_bad_keywords_are_named_before_any_work(keywords, match):
    with pytest.raises(SizeFieldError, match=match):
        cdt_plugin.triangulate(SQUARE, RING, **keywords)


def test_refine_takes_the_same_keywords():
    base = cdt_plugin.Triangulation.from_triangles(SQUARE, [[0, 1, 2], [0, 2, 3]])
    f = FIELDS["point"]
    fine = base.refine(size=f, min_angle=28)
    assert_valid(fine.vertices, fine.triangles, segments=fine.segments, domain="segments")
    assert fine.vertices[:4].tolist() == SQUARE.tolist()
    r = size_ratios(fine, f)
    assert r["over_1_5"] == 0 and 0.85 < r["median"] < 1.15
    assert min_angles(fine).min() >= 28 - 1e-9
    # refining again to a finer field goes on from there
    finer = fine.refine(size=lambda x, y: f(x, y) / 2, min_angle=28)
    assert len(finer.triangles) > 3 * len(fine.triangles)
    assert size_ratios(finer, lambda x, y: f(x, y) / 2)["over_1_5"] == 0
    # a field already met changes nothing but what the other options ask
    same = fine.refine(size=f)
    assert len(same.triangles) == len(fine.triangles)
    with pytest.raises(CDTError, match="max_area per triangle"):
        base.refine(size=0.1, max_area=[0.1, 0.1])
    with pytest.raises(CDTError, match="min_angle"):
        base.refine(size=0.1, min_angle=70)


def test_a_domain_with_holes_and_a_line_source():
    outer = [[0, 0], [3, 0], [3, 2], [0, 2]]
    holes = [[[0.5 + i, 0.5], [0.9 + i, 0.5], [0.9 + i, 0.9], [0.5 + i, 0.9]] for i in range(3)]
    polygon = {"type": "Polygon", "coordinates": [outer] + holes}
    f = lambda x, y: 0.01 + 0.2 * np.abs(y - 1.4)
    tri = cdt_plugin.triangulate(polygon, size=f, growth=1.3, min_angle=28)
    plc = cdt_plugin.PLC.from_geo_interface(polygon)
    checked(tri, plc.vertices, plc.segments)
    r = size_ratios(tri, f, growth=1.3)
    assert r["over_1_5"] == 0 and 0.85 < r["median"] < 1.15
    assert min_angles(tri).min() >= 28 - 1e-9


def test_without_sizing_keywords_nothing_changes():
    tri = cdt_plugin.triangulate(SQUARE, RING, max_area=0.01, min_angle=30)
    assert "size_rounds" not in tri.stats
    assert len(cdt_plugin.triangulate(SQUARE, RING, size=0.05, min_angle=30).triangles) > 0
