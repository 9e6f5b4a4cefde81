"""The one shapely-polygon reader (``plc.shapely_polygon_rings``) and the one GeoJSON
walker (``plc.geojson_parts``): a shapely geometry, its ``__geo_interface__``
mapping and a layer of such geometries (the batch's flat ring arrays) give the
same PLC, which is the PLC of the rings as shapely's ring objects hold them; and
the meshes made from them pass the exact checker."""
from __future__ import annotations

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
from cdt_plugin import PLC, NonFiniteCoordinateError  # noqa: E402
from cdt_plugin.batch import geometry_plc  # noqa: E402
from cdt_plugin.plc import geojson_features, geojson_parts, shapely_polygon_rings  # noqa: E402
from cdt_plugin.report import earcut  # noqa: E402
from checker import assert_valid, check_triangulation  # noqa: E402

from cdt_plugin.adapters.shapely.reading import layer_rings  # noqa: E402


def _star(n: int, cx: float = 0.0, cy: float = 0.0) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.where(np.arange(n) % 2, 1.0, 2.0)
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


STAR_WITH_HOLES = shapely.Polygon(_star(60), [shapely.box(-0.3, -0.3, -0.1, -0.1).exterior.coords,
                                              shapely.box(0.1, 0.1, 0.3, 0.3).exterior.coords[::-1]])
GEOMETRIES = {
    "square": shapely.box(0, 0, 1, 1),
    "star with two holes": STAR_WITH_HOLES,
    "multipolygon with holes": shapely.MultiPolygon([STAR_WITH_HOLES, shapely.box(5, 5, 6, 6),
                                                     shapely.Polygon(_star(12, 10, 0))]),
    "polygon z": shapely.Polygon([(0, 0, 1), (3, 0, 1.75), (3, 3, 3.25), (0, 3, 2.5)],   # z = 1 + x/4 + y/2
                                 [[(1, 1, 1.75), (2, 1, 2), (1, 2, 2.25)]]),
    "zero-area hole": shapely.Polygon(_star(20), [[(0.1, 0.1), (0.3, 0.3), (0.2, 0.2)]]),
    "repeated-point hole": shapely.Polygon(_star(20), [[(0.1, 0.1), (0.1, 0.1), (0.1, 0.1)]]),
    "multipolygon with a degenerate part": shapely.MultiPolygon(
        [shapely.box(0, 0, 1, 1), shapely.Polygon([(2, 2), (3, 3), (4, 4)])]),
    "empty polygon": shapely.Polygon(),
}


def _by_ring_objects(geometry) -> PLC:
    """The PLC the rings make, read through shapely's ring objects (another way to
    the same coordinates): each ring's closing point dropped, each vertex joined to
    the next of its ring; a ring enclosing nothing keeps its points, named."""
    polygons = list(getattr(geometry, "geoms", [geometry]))
    polygons = [p for p in polygons if not p.is_empty]
    xy, z, segs, ring_polygon, ring_is_hole, named = [], [], [], [], [], []
    n = 0
    for p, polygon in enumerate(polygons):
        for r, ring in enumerate([polygon.exterior, *polygon.interiors]):
            coords = np.asarray(ring.coords)[:-1]
            xy.append(coords[:, :2])
            z.append(coords[:, 2] if coords.shape[1] > 2 else np.full(len(coords), np.nan))
            if shapely.Polygon(coords[:, :2]).area == 0:
                named.append((p, r))
            else:
                idx = np.arange(n, n + len(coords))
                segs.append(np.column_stack([idx, np.roll(idx, -1)]))
                ring_polygon.append(p)
                ring_is_hole.append(r > 0)
            n += len(coords)
    return PLC(np.concatenate(xy) if xy else np.empty((0, 2)),
               np.concatenate(segs) if segs else np.empty((0, 2), np.int64),
               ring_polygon=np.array(ring_polygon, np.int64), ring_is_hole=np.array(ring_is_hole, bool),
               z=np.concatenate(z) if geometry.has_z else None, degenerate_rings=named)


def _assert_same_plc(a: PLC, b: PLC) -> None:
    assert np.array_equal(a.vertices, b.vertices)
    assert np.array_equal(a.segments, b.segments)
    assert np.array_equal(a.ring_polygon, b.ring_polygon)
    assert np.array_equal(a.ring_is_hole, b.ring_is_hole)
    assert (a.z is None) == (b.z is None)
    if a.z is not None:
        assert np.array_equal(a.z, b.z, equal_nan=True)
    assert a.degenerate_rings == b.degenerate_rings


@pytest.mark.parametrize("name", GEOMETRIES)
def test_the_reader_and_the_walker_give_the_rings_plc(name):
    geometry = GEOMETRIES[name]
    expected = _by_ring_objects(geometry)
    read = PLC.from_geo_interface(geometry)                          # the shapely reader
    walked = PLC.from_geo_interface(geometry.__geo_interface__)      # the GeoJSON walker
    _assert_same_plc(read, expected)
    _assert_same_plc(walked, expected)
    assert np.array_equal(read.segment_ring, walked.segment_ring)


@pytest.mark.parametrize("name", [n for n in GEOMETRIES if n != "empty polygon"])
def test_a_layer_read_at_once_gives_each_geometry_its_plc(name):
    """The batch's flat ring arrays (the same reader over an array) cut back into
    each geometry's PLC: the PLC of the geometry alone, wherever it sits in the layer."""
    layer = np.array([shapely.box(-5, -5, -4, -4), GEOMETRIES[name],
                      GEOMETRIES["multipolygon with holes"]], object)
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, _, has_z, _ = layer_rings(layer)
    for g, geometry in enumerate(layer):
        plc = geometry_plc(xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole,
                           z if has_z[g] else None, g)
        _assert_same_plc(plc, _by_ring_objects(geometry))


def test_one_polygon_and_a_layer_of_one_read_the_same():
    for geometry in GEOMETRIES.values():
        if geometry.geom_type != "Polygon":
            continue
        one = shapely_polygon_rings(shapely, geometry)
        layer = shapely_polygon_rings(shapely, np.array([geometry], object))
        for a, b in zip(one, layer):
            assert (a is None) == (b is None)
            if a is not None:
                assert np.array_equal(a, b)


@pytest.mark.parametrize("as_mapping", [False, True])
def test_nan_coordinates_are_refused_alike(as_mapping):
    polygon = shapely.Polygon([(0, 0), (1, 0), (np.nan, 1), (0, 1)])
    with pytest.raises(NonFiniteCoordinateError, match=r"vertex position\(s\) \[2\]"):
        PLC.from_geo_interface(polygon.__geo_interface__ if as_mapping else polygon)


def test_collections_are_walked_in_input_order():
    line = shapely.LineString([(-1, -1), (9, -1)])
    collection = shapely.GeometryCollection([STAR_WITH_HOLES, line, shapely.Point(7, 7),
                                             shapely.box(5, 5, 6, 6)])
    plc = PLC.from_geo_interface(collection)
    star, box = _by_ring_objects(STAR_WITH_HOLES), _by_ring_objects(shapely.box(5, 5, 6, 6))
    n_star = len(star.vertices)
    assert np.array_equal(plc.vertices, np.concatenate(
        [star.vertices, np.asarray(line.coords), [(7, 7)], box.vertices]))
    assert np.array_equal(plc.segments, np.concatenate(
        [star.segments, [(n_star, n_star + 1)], box.segments + n_star + 3]))
    assert plc.segment_ring.tolist() == ([0] * 60 + [1] * 4 + [2] * 4 + [-1] + [3] * 4)
    assert plc.ring_polygon.tolist() == [0, 0, 0, 1]
    # a Feature, and a collection inside a collection, are opened the same way
    nested = {"type": "GeometryCollection", "geometries": [
        {"type": "Feature", "properties": {}, "geometry": STAR_WITH_HOLES.__geo_interface__},
        {"type": "GeometryCollection", "geometries": [line, shapely.Point(7, 7)]},
        shapely.box(5, 5, 6, 6)]}
    _assert_same_plc(PLC.from_geo_interface(nested), plc)


def test_the_walker_opens_feature_collections_only_when_asked():
    features = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": shapely.box(0, 0, 1, 1).__geo_interface__},
        {"type": "Feature", "properties": {}, "geometry": None},
        {"type": "Feature", "properties": {}, "geometry": GEOMETRIES["multipolygon with holes"]}]}
    assert [kind for kind, _ in geojson_parts(features, features=True)] == ["Polygon", "MultiPolygon"]
    assert [kind for kind, _ in geojson_parts(features)] == ["FeatureCollection"]
    with pytest.raises(cdt_plugin.InputShapeError, match="unsupported geometry type 'FeatureCollection'"):
        PLC.from_geo_interface(features)
    assert len(geojson_features(features)) == 3
    assert geojson_features(features["features"][0]) == [features["features"][0]]
    with pytest.raises(cdt_plugin.InputShapeError, match="got type 'Topology'"):
        geojson_features({"type": "Topology"})
    # earcut reads the same polygons from the features as from the geometries
    multi = GEOMETRIES["multipolygon with holes"]
    v1, t1 = earcut(features)
    v2, t2 = earcut(shapely.GeometryCollection([shapely.box(0, 0, 1, 1), multi]))
    assert np.array_equal(v1, v2) and np.array_equal(t1, t2)


@pytest.mark.parametrize("name", ["square", "star with two holes", "multipolygon with holes",
                                  "polygon z"])
def test_meshes_of_the_reader_and_the_walker_agree_and_check(name):
    geometry = GEOMETRIES[name]
    read = cdt_plugin.triangulate(geometry, min_angle=20)
    walked = cdt_plugin.triangulate(geometry.__geo_interface__, min_angle=20)
    assert np.array_equal(read.vertices, walked.vertices)
    assert np.array_equal(read.triangles, walked.triangles)
    report = check_triangulation(read.vertices, read.triangles, segments=read.segments,
                                 domain="segments", require_all_vertices=False)
    assert report.ok, report


@pytest.mark.parametrize("wkt", ["POLYGON ((0 0, 2 0, 2 2, 0 0), EMPTY)",
                                 "MULTIPOLYGON (((0 0, 2 0, 2 2, 0 0), EMPTY), ((5 5, 6 5, 6 6, 5 5)))"])
def test_an_empty_hole_is_dropped_and_named_in_stats(wkt):
    # GEOS holds an EMPTY hole as a ring of no points (valid for GEOS, which drops it): the
    # one call, the batch and the reader of arrays all drop it and name it in stats
    from cdt_plugin.adapters.shapely import triangulate as shapely_triangulate, triangulate_batch
    geometry = shapely.from_wkt(wkt)
    without = shapely.from_wkt(wkt.replace(", EMPTY", ""))
    expected = cdt_plugin.triangulate(without)
    for tri in (cdt_plugin.triangulate(geometry), shapely_triangulate(geometry),
                shapely_triangulate([geometry] * 17)[16]):       # (17: the vectorised reader)
        assert tri.stats["empty_rings"] == [(0, 1)]
        assert np.array_equal(tri.vertices, expected.vertices)
        assert np.array_equal(tri.triangles, expected.triangles)
        assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    rings = shapely_polygon_rings(shapely, np.array([geometry, shapely.box(0, 0, 1, 1)]))
    assert np.diff(rings.ring_start).tolist()[:2] == [3, 0] and np.diff(rings.ring_start)[-1] == 4
    batch = triangulate_batch(np.array([shapely.box(0, 0, 1, 1), geometry]))
    assert not batch.errors and batch.stats["empty_rings"] == {1: [(0, 1)]}
    assert len(batch.triangles) == 2 + len(expected.triangles)
    V, T = batch.mesh(1)      # the same triangles as the geometry without its EMPTY ring

    def corners(V, T):
        return sorted(sorted(map(tuple, V[t, :2].tolist())) for t in T)
    assert corners(V, T) == corners(expected.vertices, expected.triangles)
