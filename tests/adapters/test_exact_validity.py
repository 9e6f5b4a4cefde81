"""Validity, errors and error points of the shapely adapter, its drop-ins and
the GIS path at every magnitude: a generated corpus of valid and invalid
polygons (self-touching rings, holes touching shells, folded rings, EMPTY
holes, overlapping and edge-sharing MultiPolygons, bow-ties...) at scales
``2**k`` (k from -1000 to 1000) and offsets up to 1e15 gives the same verdict,
the same message (its point moved with the input) and the same mesh (scaled)
everywhere, and nothing but CDTErrors."""
from __future__ import annotations

import re
from fractions import Fraction

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
from cdt_plugin import InvalidGeometryError, SegmentIntersectionError  # noqa: E402
from cdt_plugin.adapters import shapely as sa  # noqa: E402
from checker import assert_valid  # noqa: E402

#: (WKT, valid by GEOS's rules at ordinary magnitudes); small integer coordinates, so that
#: every transform below is exact
CASES = {
    "square with hole": ("POLYGON ((0 0, 8 0, 8 8, 0 8, 0 0), (2 2, 2 5, 5 5, 5 2, 2 2))", True),
    "hole touching shell at a point": ("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), (0 2, 2 1, 2 3, 0 2))", True),
    "holes touching each other": ("POLYGON ((0 0, 9 0, 9 9, 0 9, 0 0), (1 1, 4 1, 4 4, 1 1), "
                                  "(4 4, 8 4, 8 8, 4 4))", True),
    "EMPTY hole": ("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), EMPTY)", True),
    "parts touching at a point": ("MULTIPOLYGON (((0 0, 2 0, 2 2, 0 2, 0 0)), "
                                  "((2 2, 4 2, 4 4, 2 4, 2 2)))", True),
    "bow-tie": ("POLYGON ((0 0, 2 2, 2 0, 0 2, 0 0))", False),
    "skewed bow-tie": ("POLYGON ((0 0, 7 3, 7 0, 1 5, 0 0))", False),
    "self-touching ring": ("POLYGON ((0 0, 4 0, 4 4, 2 4, 3 2, 1 2, 2 4, 0 4, 0 0))", False),
    "hole touching shell twice": ("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), (0 2, 2 0, 4 2, 2 4, 0 2))", False),
    "hole outside shell": ("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), (5 5, 6 5, 6 6, 5 5))", False),
    "nested holes": ("POLYGON ((0 0, 9 0, 9 9, 0 9, 0 0), (1 1, 8 1, 8 8, 1 8, 1 1), (2 2, 3 2, 3 3, 2 2))",
                     False),
    "folded ring": ("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0, 2 2, 0 0))", False),
    "overlapping parts": ("MULTIPOLYGON (((0 0, 2 0, 2 2, 0 2, 0 0)), ((1 1, 3 1, 3 3, 1 3, 1 1)))", False),
    "parts sharing an edge": ("MULTIPOLYGON (((0 0, 2 0, 2 2, 0 2, 0 0)), ((2 0, 4 0, 4 2, 2 2, 2 0)))",
                              False),
    "nested shells": ("MULTIPOLYGON (((0 0, 4 0, 4 4, 0 4, 0 0)), ((1 1, 2 1, 2 2, 1 2, 1 1)))", False),
}

#: (k, offset): coordinates c become (c + offset) * 2**k, exactly
TRANSFORMS = [(0, 0.0), (-1000, 0.0), (-600, 0.0), (-180, 0.0), (-65, 0.0), (-60, 0.0), (60, 0.0), (120, 0.0),
              (600, 0.0), (1000, 0.0), (0, 1e15), (-60, 1e15), (-1000, 1e15), (970, 1e15), (300, -2.0**49)]

_MESSAGE = re.compile(r"^(?P<head>.*) at \((?P<x>\S+), (?P<y>\S+)\)(?P<tail>.*)$")


def moved(geometry, k: int, offset: float):
    return shapely.transform(geometry, lambda c: np.ldexp(c + offset, k))


def outcome(fn, geometry):
    """``("mesh", tri)`` or ``("error", type, head, point, tail)`` of ``fn(geometry)``;
    an exception other than a CDTError fails the test."""
    try:
        return ("mesh", fn(geometry))
    except cdt_plugin.CDTError as e:
        m = _MESSAGE.match(str(e))
        assert m, str(e)
        return ("error", type(e), m["head"], (float(m["x"]), float(m["y"])), m["tail"])


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_same_verdict_message_and_mesh_at_every_scale(name):
    wkt, valid = CASES[name]
    base_geometry = shapely.from_wkt(wkt)
    base = outcome(sa.triangulate, base_geometry)
    assert (base[0] == "mesh") == valid, base
    geometries = [moved(base_geometry, k, offset) for k, offset in TRANSFORMS]
    for (k, offset), geometry in zip(TRANSFORMS, geometries):
        got = outcome(sa.triangulate, geometry)
        assert got[0] == base[0], (k, offset, got)
        if valid:
            tri, ref = got[1], base[1]
            assert np.array_equal(tri.vertices, np.ldexp(ref.vertices + offset, k)), (k, offset)
            assert np.array_equal(tri.triangles, ref.triangles), (k, offset)
            assert tri.stats.get("empty_rings") == ref.stats.get("empty_rings")
            assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
        else:
            # the same reason and rings; the point moved with the input, exactly
            assert got[1:3] + got[4:] == base[1:3] + base[4:], (k, offset, got, base)
            assert got[3] == tuple(np.ldexp(np.array(base[3]) + offset, k)), (k, offset, got, base)
        # the drop-in meshes each polygon of a MultiPolygon on its own, as GEOS does: parts
        # that overlap or share an edge are each valid, and their triangles come together
        drop_in = outcome(sa.constrained_delaunay_triangles, geometry)
        parts = [outcome(sa.triangulate, part) for part in shapely.get_parts(geometry)]
        if all(part[0] == "mesh" for part in parts):
            assert drop_in[0] == "mesh", (k, offset, drop_in)
            assert len(drop_in[1].geoms) == sum(len(part[1].triangles) for part in parts)
        else:
            assert drop_in[1:] == got[1:], (k, offset, drop_in, got)
    # the batch (the GIS path) gives the same verdicts, geometry by geometry
    batch = sa.triangulate_batch(geometries, errors="skip")
    assert sorted(batch.errors) == ([] if valid else list(range(len(geometries))))
    if valid:
        assert np.array_equal(np.diff(batch.offsets), [len(base[1].triangles)] * len(geometries))


@pytest.mark.parametrize("name", sorted(n for n, (_, valid) in CASES.items() if not valid))
def test_repair_works_at_every_scale(name):
    base_geometry = shapely.from_wkt(CASES[name][0])
    ref = sa.triangulate(base_geometry, repair=True)
    for k, offset in TRANSFORMS:
        tri = sa.triangulate(moved(base_geometry, k, offset), repair=True)
        assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
        if offset == 0:        # the same repair, scaled
            assert np.array_equal(tri.vertices, np.ldexp(ref.vertices, k)), k
            assert np.array_equal(tri.triangles, ref.triangles), k


def exact_crossing(P):
    (x1, y1), (x2, y2), (x3, y3), (x4, y4) = [(Fraction(x), Fraction(y)) for x, y in P]
    t = ((x1 - x3) * (y3 - y4) - (y1 - y3) * (x3 - x4)) / ((x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4))
    return x1 + t * (x2 - x1), y1 + t * (y2 - y1)


@pytest.mark.parametrize("k, offset", TRANSFORMS + [(-1070 + 53, 0.0), (1020, 0.0)])
def test_the_crossing_an_error_names_is_the_one_split_inserts(k, offset):
    # two segments crossing at a point that is not a double: the point named is the exact
    # crossing rounded, as intersections="split" inserts it, at every magnitude
    V = np.ldexp(np.array([[0.0, 0.0], [7.0, 3.0], [1.0, 5.0], [4.0, -2.0]]) + offset, k)
    with pytest.raises(SegmentIntersectionError) as info:
        cdt_plugin.triangulate(V, [[0, 1], [2, 3]])
    x, y = exact_crossing(V)
    assert info.value.point == (float(x), float(y)), (info.value.point, float(x), float(y))
    assert f"cross at about ({float(x)!r}, {float(y)!r})" in str(info.value)
    tri = cdt_plugin.triangulate(V, [[0, 1], [2, 3]], intersections="split", keep_hull=True)
    assert tuple(tri.vertices[tri.steiner[0]]) == info.value.point
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments)


def test_an_empty_hole_is_dropped_in_the_drop_in_and_the_layer():
    geometry = shapely.from_wkt("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), EMPTY)")
    assert len(sa.constrained_delaunay_triangles(geometry).geoms) == 2
    batch = sa.triangulate_batch([geometry, shapely.box(0, 0, 1, 1)])
    assert not batch.errors and batch.stats["empty_rings"] == {0: [(0, 1)]}


def test_geos_exceptions_come_as_cdt_errors():
    # GEOS raises on this hole inside a hole at 1e301; here the verdict is the one at 1
    nested = moved(shapely.from_wkt(CASES["nested holes"][0]), 1000, 0.0)
    with pytest.raises(shapely.errors.GEOSException):
        shapely.is_valid_reason(nested)
    with pytest.raises(InvalidGeometryError, match="Holes are nested at .* on ring 2 of polygon 0"):
        sa.constrained_delaunay_triangles(nested)


def test_skip_skips_a_feature_that_does_not_project():
    gpd = pytest.importorskip("geopandas")
    from cdt_plugin.adapters import geo
    layer = gpd.GeoDataFrame({"name": ["bad", "ok"]}, index=["x", "y"], crs="EPSG:4326",
                             geometry=[shapely.box(0, 80, 10, 95), shapely.box(0, 0, 1, 1)])
    with pytest.raises(geo.ProjectionError, match="^feature x: coordinates do not project") as info:
        geo.triangulate(layer, project="EPSG:3857")
    assert info.value.feature == "x" and info.value.index == 0
    with pytest.warns(geo.SkippedFeaturesWarning, match="1 feature"):
        tris = geo.triangulate(layer, project="EPSG:3857", errors="skip")
    assert list(tris.attrs["cdt_errors"]) == ["x"] and set(tris["feature"]) == {"y"}
    corners, triangles = np.unique(shapely.get_coordinates(tris.geometry), axis=0, return_inverse=True)
    assert_valid(corners, triangles.reshape(-1, 4)[:, :3])


def test_a_file_that_is_no_layer_is_a_file_format_error(tmp_path):
    pytest.importorskip("geopandas")
    from cdt_plugin.adapters import geo
    path = tmp_path / "bad.geojson"
    path.write_text("not a layer")
    with pytest.raises(cdt_plugin.FileFormatError, match="cannot read it as a GIS layer") as info:
        geo.triangulate(path)
    assert info.value.path == path and info.value.__cause__ is not None


def test_coordinates_no_scale_keeps_are_the_engines_range_error():
    # 1e300 beside 1e-300: no power of two brings both into GEOS's range exactly; the
    # verdict is left to the engine, which names the rows (not GEOS's 'Too few points')
    thin = shapely.Polygon([(0, 0), (1e300, 0), (1e300, 1e-300)])
    for call in (sa.triangulate, sa.constrained_delaunay_triangles):
        with pytest.raises(cdt_plugin.CoordinateRangeError, match="row 2"):
            call(thin)
    batch = sa.triangulate_batch([thin, shapely.box(0, 0, 1, 1)], errors="skip")
    assert list(batch.errors) == [0] and isinstance(batch.errors[0], cdt_plugin.CoordinateRangeError)
