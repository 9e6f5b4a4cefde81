"""``cdt_plugin.size_near``: sizes on known geometry (a point, a segment, a polygon's
rings) in the distance and the growth forms, the bucket grid against a brute-force
distance, every input kind, and bad arguments named."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

import cdt_plugin
from cdt_plugin.errors import CDTError, InputShapeError, NonFiniteCoordinateError, SizeFieldError
from cdt_plugin.nearness import SizeNear, read_sources


def brute_distances(field: SizeNear, x, y):
    """The distance from each point to the nearest source, every source tried (numpy)."""
    ax, ay, bx, by = field._sources
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    px, py = np.asarray(x, float)[:, None], np.asarray(y, float)[:, None]
    t = np.clip(((px - ax) * dx + (py - ay) * dy) / np.where(length2 > 0, length2, 1), 0, 1)
    return np.sqrt((ax + t * dx - px) ** 2 + (ay + t * dy - py) ** 2).min(axis=1)


def test_point_source_distance_form():
    field = cdt_plugin.size_near([[2.0, 1.0]], 0.5, 5.0, distance=9.0)
    x = np.array([2.0, 5.0, 2.0, 20.0, -100.0])
    y = np.array([1.0, 5.0, -3.5, 1.0, 1.0])
    d = np.hypot(x - 2, y - 1)                       # 0, 5, 4.5, 18, 102
    assert field(x, y) == pytest.approx(np.minimum(0.5 + 4.5 * d / 9.0, 5.0), rel=1e-12)
    assert field(2.0, 10.0) == pytest.approx(5.0)     # exactly at `distance`


def test_segment_source_growth_form():
    field = cdt_plugin.size_near({"type": "LineString", "coordinates": [(0, 0), (10, 0)]},
                                 0.1, 2.0, growth=1.25)
    # beside the segment, beyond each end (distance to the end point), and far
    x = np.array([3.0, 7.0, -3.0, 14.0, 5.0])
    y = np.array([0.0, -2.0, 4.0, 3.0, 50.0])
    d = np.array([0.0, 2.0, 5.0, 5.0, 50.0])
    assert field(x, y) == pytest.approx(np.minimum(0.1 + 0.25 * d, 2.0), rel=1e-12)


def test_both_forms_take_the_finer():
    # distance form: slope (4 - 1) / 30 = 0.1; growth form: slope 0.2 -> the distance form
    both = cdt_plugin.size_near([[0.0, 0.0]], 1.0, 4.0, distance=30.0, growth=1.2)
    assert both(np.array([10.0]), np.array([0.0])) == pytest.approx([2.0])
    steep = cdt_plugin.size_near([[0.0, 0.0]], 1.0, 4.0, distance=30.0, growth=1.05)
    assert steep(np.array([10.0]), np.array([0.0])) == pytest.approx([1.5])


def test_polygon_counts_by_its_rings():
    """Inside a polygon the size grows away from the shell and the hole alike."""
    shell = [(0, 0), (10, 0), (10, 10), (0, 10)]
    hole = [(4, 4), (6, 4), (6, 6), (4, 6)]
    field = cdt_plugin.size_near(shapely.Polygon(shell, [hole]), 1.0, 100.0, distance=99.0)
    assert (field.points, field.segments) == (0, 8)
    x = np.array([2.0, 5.0, 5.0, 3.0, 15.0])
    y = np.array([5.0, 5.0, 3.0, 5.0, 5.0])
    d = np.array([2.0, 1.0, 1.0, 1.0, 5.0])          # to the shell, the hole (inside it: its ring), the hole, out
    assert field(x, y) == pytest.approx(1.0 + d, rel=1e-12)


def test_constant_when_sizes_are_equal():
    field = cdt_plugin.size_near([[0.0, 0.0]], 3.0, 3.0, distance=1.0)
    assert (field(np.linspace(-5, 5, 7), np.zeros(7)) == 3.0).all()


@pytest.mark.parametrize("seed", [0, 1])
def test_bucket_grid_matches_brute_force(seed):
    """Points, short and long segments over a grid; queries inside, on and far outside it."""
    rng = np.random.default_rng(seed)
    lines = [rng.uniform(0, 100, (2, 2)) for _ in range(60)] + [np.array([[0, 50], [100, 51]])]
    geoms = [rng.uniform(20, 30, (40, 2)),
             shapely.MultiLineString(lines), shapely.LineString([(50, 50), (50, 50.001)])]
    field = cdt_plugin.size_near(geoms, 1.0, 1e6, distance=1e6)
    q = np.vstack([rng.uniform(-50, 150, (3000, 2)), rng.uniform(-1e5, 1e5, (200, 2)),
                   np.array([[0, 50], [25, 25], [1e12, -1e12]])])
    d = field.distances(q[:, 0], q[:, 1])
    assert d == pytest.approx(brute_distances(field, q[:, 0], q[:, 1]), rel=1e-9, abs=1e-9)
    # with a reach, the sizes are those of the exact distances
    assert field(q[:, 0], q[:, 1]) == pytest.approx(
        np.minimum(1.0 + (1e6 - 1) / 1e6 * brute_distances(field, q[:, 0], q[:, 1]), 1e6), rel=1e-9)


def test_degenerate_grids():
    """All sources on one horizontal line, and one point repeated."""
    flat = cdt_plugin.size_near([[x, 5.0] for x in range(50)], 1.0, 10.0, growth=2.0)
    assert flat.distances([10.5, 200.0], [5.0, 5.0]) == pytest.approx([0.5, 151.0])
    one = cdt_plugin.size_near([[1.0, 1.0]] * 3, 1.0, 10.0, growth=2.0)
    assert one.distances([4.0], [5.0]) == pytest.approx([5.0])


def test_call_keeps_the_shape_and_broadcasts():
    field = cdt_plugin.size_near([[0.0, 0.0]], 1.0, 10.0, distance=9.0)
    x, y = np.meshgrid(np.arange(4.0), np.arange(3.0))
    out = field(x, y)
    assert out.shape == (3, 4) and out.dtype == np.float64
    assert out == pytest.approx(1.0 + np.hypot(x, y))
    assert field(np.arange(3.0), 0.0).shape == (3,)


RING = [(0, 0), (4, 0), (4, 3), (0, 3), (0, 0)]


@pytest.mark.parametrize("kind", ["array", "list of pairs", "plc", "shapely", "geojson",
                                  "feature", "feature collection", "geoseries", "geodataframe",
                                  "object array", "mixed list"])
def test_every_input_kind(kind):
    """The same rectangle boundary (and one point) given every way: the same field."""
    import geopandas
    poly = shapely.Polygon(RING)
    point = shapely.Point(10, 10)
    mapping = {"type": "GeometryCollection",
               "geometries": [poly.__geo_interface__, point.__geo_interface__]}
    inputs = {
        "array": None, "list of pairs": None,
        "plc": cdt_plugin.PLC(np.array([[0, 0], [4, 0], [4, 3], [0, 3], [10, 10.0]]),
                              np.array([[0, 1], [1, 2], [2, 3], [3, 0]])),
        "shapely": shapely.GeometryCollection([poly, point]),
        "geojson": mapping,
        "feature": {"type": "Feature", "geometry": mapping, "properties": {}},
        "feature collection": {"type": "FeatureCollection", "features": [
            {"type": "Feature", "geometry": poly.__geo_interface__, "properties": {}},
            {"type": "Feature", "geometry": None, "properties": {}},
            {"type": "Feature", "geometry": point.__geo_interface__, "properties": {"a": 1}}]},
        "geoseries": geopandas.GeoSeries([poly, None, point]),
        "geodataframe": geopandas.GeoDataFrame({"a": [1, 2]}, geometry=[poly, point]),
        "object array": np.array([poly, point, None], dtype=object),
        "mixed list": [poly.exterior, np.array([[10.0, 10.0]])],
    }
    x, y = np.array([2.0, 2.0, 10.0, 9.0]), np.array([1.0, -1.0, 10.0, 10.0])
    if kind in ("array", "list of pairs"):
        corners = [[0, 0], [4, 0], [4, 3], [0, 3], [10, 10]]
        field = cdt_plugin.size_near(np.array(corners, float) if kind == "array" else corners,
                                     1.0, 50.0, distance=49.0)
        assert (field.points, field.segments) == (5, 0)
        assert field(x, y) == pytest.approx([1 + math.hypot(2, 1), 1 + math.hypot(2, 1), 1, 2])
        return
    field = cdt_plugin.size_near(inputs[kind], 1.0, 50.0, distance=49.0)
    assert (field.points, field.segments) == (1, 4)
    assert field(x, y) == pytest.approx([2.0, 2.0, 1.0, 2.0])


def test_z_coordinates_are_ignored():
    field = cdt_plugin.size_near(shapely.LineString([(0, 0, 5), (2, 0, 9)]), 1.0, 10.0, growth=2.0)
    assert field(np.array([1.0]), np.array([3.0])) == pytest.approx([4.0])


def test_read_sources_orders_points_first():
    (ax, ay, bx, by), points = read_sources([shapely.LineString([(0, 0), (1, 0), (1, 1)]),
                                             np.array([[5.0, 5.0]])])
    assert points == 1
    assert np.column_stack([ax, ay, bx, by]).tolist() == [[5, 5, 5, 5], [0, 0, 1, 0], [1, 0, 1, 1]]


@pytest.mark.parametrize("args, kwargs, words", [
    ((0.0, 1.0), {"distance": 1.0}, "size_min must be a finite number > 0, got 0.0"),
    ((-1.0, 1.0), {"distance": 1.0}, "size_min must be a finite number > 0"),
    ((float("nan"), 1.0), {"distance": 1.0}, "size_min must be a finite number > 0"),
    ((1.0, float("inf")), {"distance": 1.0}, "size_max must be a finite number > 0"),
    ((2.0, 1.0), {"distance": 1.0}, "size_max must be >= size_min"),
    (("1", 2.0), {"distance": 1.0}, "size_min must be a number, got '1' (str)"),
    ((True, 2.0), {"distance": 1.0}, "size_min must be a number"),
    ((1.0, 2.0), {}, "needs distance= "),
    ((1.0, 2.0), {"distance": 0.0}, "distance must be a finite number > 0, got 0.0"),
    ((1.0, 2.0), {"distance": None, "growth": 1.0}, "growth must be a finite number > 1, got 1.0"),
    ((1.0, 2.0), {"growth": float("inf")}, "growth must be a finite number > 1"),
    ((1.0, 2.0), {"growth": [1.2]}, "growth must be a number, got [1.2] (list)"),
])
def test_bad_numbers_are_named(args, kwargs, words):
    with pytest.raises(CDTError) as info:
        cdt_plugin.size_near([[0.0, 0.0]], *args, **kwargs)
    assert words in str(info.value)


@pytest.mark.parametrize("geometries, error, words", [
    ([], CDTError, "no point and no segment"),
    (shapely.Polygon(), CDTError, "no point and no segment"),
    ({"type": "FeatureCollection", "features": []}, CDTError, "no point and no segment"),
    ([[0.0, 0.0], [1.0, float("nan")]], NonFiniteCoordinateError, "row(s) 1"),
    (np.zeros((3, 3)), InputShapeError, "must have shape (n, 2)"),
    ("coast.gpkg", CDTError, "geometries"),
    ({"type": "Curve", "coordinates": []}, InputShapeError, "unsupported geometry type 'Curve'"),
])
def test_bad_geometries_are_named(geometries, error, words):
    with pytest.raises(error) as info:
        cdt_plugin.size_near(geometries, 1.0, 2.0, distance=1.0)
    assert words in str(info.value)


def test_non_finite_queries_give_nan():
    field = cdt_plugin.size_near([[0.0, 0.0], [1.0, 1.0]], 1.0, 10.0, distance=9.0)
    out = field(np.array([np.nan, np.inf, 0.0]), np.array([0.0, 0.0, -np.inf]))
    assert np.isnan(out).all()


def test_a_span_beyond_double_precision_is_named():
    with pytest.raises(SizeFieldError, match="beyond the range of double precision"):
        cdt_plugin.size_near([[-1e308, 0.0], [1e308, 0.0]], 1.0, 2.0, distance=1.0)


def test_repr_says_what_it_holds():
    field = cdt_plugin.size_near([shapely.LineString([(0, 0), (1, 0), (2, 1)]), [[5.0, 5.0]]],
                                 0.5, 8.0, distance=100.0, growth=1.3)
    assert repr(field) == ("size_near(1 point(s), 2 segment(s), size_min=0.5, size_max=8, "
                           "distance=100, growth=1.3)")
