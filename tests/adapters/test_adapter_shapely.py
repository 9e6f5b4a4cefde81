"""shapely adapter against the real shapely/GEOS (no mocks)."""
import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
from cdt_plugin import PLC  # noqa: E402
from cdt_plugin.adapters import shapely as sa  # noqa: E402
from cdt_plugin.adapters.shapely import reading  # noqa: E402
from cdt_plugin.plain import plain_mesh  # noqa: E402

from checker import assert_valid, canonical_triangles, check_collinear_edges  # noqa: E402


def _circle(cx, cy, r, n, cw=False):
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    xy = np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])
    return xy[::-1] if cw else xy


def _holed():
    shell = np.array([[0, 0], [10, 0], [10, 6], [6, 6], [6, 10], [0, 10]], float)
    holes = [_circle(2.5, 2.5, 1.2, 17), [(5, 7), (5, 9), (3, 9), (3, 7)], _circle(7.5, 3, 1.0, 11)]
    return shapely.Polygon(shell, holes)


def _min_angle(V, T):
    V, T = np.asarray(V, float), np.asarray(T)
    if not len(T):
        return np.nan
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    out = []
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = q - p, r - p
        out.append(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(axis=1)))
    return float(np.degrees(np.min(out)))


def _collection_min_angle(gc):
    coords = shapely.get_coordinates(np.asarray(gc.geoms, dtype=object)).reshape(-1, 4, 2)[:, :3]
    return _min_angle(coords.reshape(-1, 2), np.arange(3 * len(coords)).reshape(-1, 3))


def _assert_covers(tri, geom):
    gc = sa.to_shapely(tri)
    union = shapely.union_all(np.asarray(gc.geoms, dtype=object))
    assert abs(gc.area - geom.area) <= 1e-12 * geom.area
    assert shapely.symmetric_difference(union, geom).area <= 1e-12 * geom.area
    assert shapely.equals(union, geom)


def test_polygon_with_holes_area_union_and_regions():
    poly = _holed()
    tri = sa.triangulate(poly)
    _assert_covers(tri, poly)
    assert tri.is_delaunay()
    assert (tri.regions == 0).all()
    n_ring_vertices = len(shapely.get_coordinates(poly)) - 1 - len(poly.interiors)
    assert len(tri.vertices) == n_ring_vertices
    # Euler for a polygon with h holes: T = n + 2h - 2 (all vertices on rings)
    assert len(tri.triangles) == n_ring_vertices + 2 * len(poly.interiors) - 2
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def _reader_cases():
    return [_holed(),
            shapely.MultiPolygon([_holed(), shapely.box(20, 0, 21, 1)]),
            shapely.Polygon([(0, 0, 1), (1, 0, 2), (1, 1, 3), (0, 1, 2)]),   # on z = 1 + x + y
            shapely.Polygon(_circle(0, 0, 1, 9, cw=True)),
            shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (2, 2), (3, 3), (1, 1)]]),
            shapely.MultiPolygon([shapely.Polygon(), shapely.box(0, 0, 1, 1)]),
            shapely.box(0, 0, 4, 3),                                   # hole-free: read in one call
            shapely.Polygon([(0, 0), (1, 1), (2, 2)]),                 # hole-free and degenerate
            shapely.Polygon(_circle(0, 0, 5, 12), [_circle(-2, 0, 1, 8, cw=True), _circle(2, 0, 1, 5),
                                                   [(0, 3), (0.5, 3.5), (0, 4)]]),   # holes: one more call
            shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0, 0), (1, 2), (2, 1)]]),   # hole at a corner
            shapely.Polygon([(0, 0), (2, 0), (1, 1), (0, 0), (0, 2), (-1, 1)], [[(0.5, 0.2), (1, 0.5), (1.5, 0.2)]])]


def _assert_same_plc(a, b):
    for f in ("vertices", "segments", "segment_ring", "ring_polygon", "ring_is_hole"):
        assert np.array_equal(getattr(a, f), getattr(b, f)), f
    assert a.degenerate_rings == b.degenerate_rings
    assert (a.z is None) == (b.z is None)
    if a.z is not None:
        assert np.array_equal(a.z, b.z)


def test_coordinate_reader_equals_geo_interface():
    # a shapely Polygon/MultiPolygon is read through its coordinate arrays; its
    # GeoJSON mapping must give the very same PLC
    for g in _reader_cases():
        _assert_same_plc(PLC.from_geo_interface(g), PLC.from_geo_interface(g.__geo_interface__))
    # a Polygon without holes is read in one call (its coordinates): an empty one has none,
    # a degenerate one keeps its points, a NaN is named
    with pytest.raises(cdt_plugin.TooFewPointsError, match="no vertices"):
        cdt_plugin.triangulate(shapely.Polygon())
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="ring 0 of polygon 0 has fewer than three"):
        cdt_plugin.triangulate(shapely.Polygon([(0, 0), (1, 1), (2, 2)]))
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match=r"vertex position\(s\) \[2\]"):
        cdt_plugin.triangulate(shapely.Polygon([(0, 0), (1, 0), (np.nan, 1), (0, 1)]))
    # a Polygon with holes: its coordinates, cut at its holes' sizes; the exact checker on the result
    holed = _holed()
    tri = cdt_plugin.triangulate(holed)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    _assert_covers(tri, holed)
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="ring 2 of polygon 0 has fewer than three"):
        cdt_plugin.triangulate(shapely.Polygon(_circle(0, 0, 5, 12), [_circle(2, 0, 1, 5), [(0, 3), (0, 4), (0, 3.5)]]))
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match=r"vertex position\(s\) \[14\]"):
        cdt_plugin.triangulate(shapely.Polygon(_circle(0, 0, 5, 12), [[(0, 0), (1, 0), (np.nan, 1)]]))


def test_flat_ring_reader_equals_geo_interface():
    # the batch's reader takes the rings of plain Polygons from their coordinates
    # and takes the others apart: interleaved, every PLC equals the mapping's
    cases = [g for g in _reader_cases() if not g.is_empty]
    layer = np.array(cases + [shapely.box(5, 5, 6, 6)] + cases[::-1], dtype=object)
    for g, plc in zip(layer, reading._polygon_plcs(layer)):
        ref = PLC.from_geo_interface(g.__geo_interface__)
        assert plc is not None        # (None: a ring of fewer than three points)
        _assert_same_plc(plc, ref)


def test_vectorised_reader_equals_one_by_one():
    # from 16 polygons on, the adapter reads them as flat ring arrays: same PLCs, same meshes
    many = [g for g in _reader_cases() if g.is_valid] * 4
    assert len(many) >= reading._VECTORISED_FROM
    for tri, g in zip(sa.triangulate(many, intersections="split"), many):
        one = cdt_plugin.triangulate(g, intersections="split")
        assert np.array_equal(tri.vertices, one.vertices)
        assert np.array_equal(tri.triangles, one.triangles)
        assert np.array_equal(tri.regions, one.regions)


def test_single_polygon_shortcut_equals_the_element_wise_path():
    # one valid 2D Polygon goes straight to the engine: the same mesh and the same
    # collection as the element-wise path gives it inside a list
    polygons = [_holed(), shapely.box(0, 0, 2, 1), shapely.Polygon(_circle(0, 0, 1e-3, 40) + 5e5)]
    for g in polygons:
        assert reading.plain_polygon(g)
        one, listed = sa.triangulate(g, min_angle=20), sa.triangulate([g], min_angle=20)[0]
        for name in ("vertices", "triangles", "segments", "regions"):
            assert np.array_equal(getattr(one, name), getattr(listed, name)), name
        assert_valid(one.vertices, one.triangles, segments=one.segments, domain="segments")
        gc, gcs = sa.constrained_delaunay_triangles(g), sa.constrained_delaunay_triangles([g])
        assert shapely.equals_exact(gc, gcs[0], tolerance=0.0) and gc.wkb == gcs[0].wkb
    bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    for g in (bowtie, shapely.Polygon(), shapely.Polygon([(0, 0, 1), (1, 0, 2), (0, 1, 3)]),
              shapely.MultiPolygon([shapely.box(0, 0, 1, 1)])):
        assert not reading.plain_polygon(g)      # invalid, empty, 3D, not a Polygon: the general path
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="Self-intersection"):
        sa.constrained_delaunay_triangles(bowtie)


def test_multipolygon_regions():
    mp = shapely.MultiPolygon([_holed(), shapely.box(20, 0, 22, 1), shapely.Polygon(_circle(30, 0, 2, 13))])
    tri = sa.triangulate(mp)
    _assert_covers(tri, mp)
    assert sorted(set(tri.regions.tolist())) == [0, 1, 2]
    for p, part in enumerate(mp.geoms):
        mask = tri.regions == p
        V, T = tri.vertices, tri.triangles[mask]
        u, v = V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]
        area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum()
        assert area == pytest.approx(part.area, rel=1e-12)


def test_linestring_constraint_inside_polygon():
    box = shapely.box(0, 0, 4, 4)
    line = shapely.LineString([(0.5, 0.5), (1.7, 3.1), (3.5, 1.0)])
    tri = sa.triangulate(shapely.GeometryCollection([box, line]))
    _assert_covers(tri, box)
    edges = {tuple(sorted(e)) for e in tri.edges.tolist()}
    V = tri.vertices.tolist()
    for a, b in zip(line.coords[:-1], line.coords[1:]):
        assert tuple(sorted((V.index(list(a)), V.index(list(b))))) in edges
    assert tri.is_delaunay()


def test_points_and_multilinestring():
    pts = shapely.MultiPoint(np.random.default_rng(3).uniform(0, 1, (200, 2)))
    tri = sa.triangulate(pts)
    assert len(tri.vertices) == 200 and tri.is_delaunay()
    assert sa.to_shapely(tri).area == pytest.approx(shapely.convex_hull(pts).area, rel=1e-12)
    single = sa.triangulate(shapely.Point(1, 2))
    assert len(single.vertices) == 1 and len(single.triangles) == 0
    lines = shapely.MultiLineString([[(0, 0), (2, 0)], [(0, 1), (2, 1)], [(1, -1), (1, 3)]])
    with pytest.raises(cdt_plugin.SegmentIntersectionError):
        sa.triangulate(lines)
    tri = sa.triangulate(lines, intersections="split")
    assert tri.stats["intersection_points"] == 2


INVALID = {
    "bow-tie": (shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]), "Self-intersection"),
    "self-touching ring": (shapely.Polygon([(0, 0), (4, 0), (4, 4), (2, 0), (0, 4)]), "Ring Self-intersection"),
    "hole crossing shell": (shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                                            [[(3, 1), (5, 1), (5, 3), (3, 3)]]), "Self-intersection"),
}


@pytest.mark.parametrize("name", sorted(INVALID))
def test_invalid_polygon_raises_with_geos_reason(name):
    geom, reason = INVALID[name]
    with pytest.raises(cdt_plugin.InvalidGeometryError) as info:
        sa.triangulate(geom)
    # GEOS's reason, its point as a point of the input, and the ring it lies on
    x, y = map(float, shapely.is_valid_reason(geom).split("[")[1].rstrip("]").split())
    assert f"{reason} at ({x!r}, {y!r}), on ring " in str(info.value)
    assert str(info.value).split(": ", 1)[1].startswith(reason)


@pytest.mark.parametrize("name", sorted(INVALID))
@pytest.mark.parametrize("method", [True, "structure"])
def test_repair(name, method):
    geom, _ = INVALID[name]
    tri = sa.triangulate(geom, repair=method)
    kw = {"method": "structure", "keep_collapsed": False} if method == "structure" else {}
    fixed = shapely.make_valid(geom, **kw)
    assert tri.is_delaunay()
    assert sa.to_shapely(tri).area == pytest.approx(fixed.area, rel=1e-12)


def test_invalid_member_of_collection_and_ring():
    bow = INVALID["bow-tie"][0]
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="member 0 .*Self-intersection"):
        sa.triangulate(shapely.GeometryCollection([bow, shapely.Point(5, 5)]))
    tri = sa.triangulate(shapely.GeometryCollection([bow, shapely.Point(5, 5)]), repair=True)
    assert len(tri.vertices) == 6  # 4 corners, the crossing point, the kept Point
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="LinearRing is not valid"):
        sa.triangulate(shapely.LinearRing(bow.exterior.coords))
    assert sa.to_shapely(sa.triangulate(shapely.LinearRing(bow.exterior.coords), repair=True)).area == 2.0


def test_empty_geometry_raises():
    for empty in (shapely.Polygon(), shapely.MultiPolygon(), shapely.GeometryCollection(),
                  shapely.LineString()):
        with pytest.raises(cdt_plugin.TooFewPointsError, match="empty"):
            sa.triangulate(empty)
    with pytest.raises(cdt_plugin.InputShapeError):
        sa.triangulate(None)
    with pytest.raises(cdt_plugin.InputShapeError, match="geometry 1"):
        sa.triangulate([shapely.box(0, 0, 1, 1), "POLYGON"])


def test_array_input_in_order():
    geoms = [shapely.box(0, 0, 1, 1), _holed(), None, shapely.Polygon(_circle(0, 0, 1, 7)),
             shapely.MultiPolygon([shapely.box(5, 5, 6, 6), shapely.box(7, 7, 8, 9)])]
    out = sa.triangulate(np.array(geoms, dtype=object))
    assert isinstance(out, list) and len(out) == 5 and out[2] is None
    for g, tri in zip(geoms, out):
        if g is not None:
            single = sa.triangulate(g)
            assert np.array_equal(tri.triangles, single.triangles)
            assert np.array_equal(tri.vertices, single.vertices)
            _assert_covers(tri, g)
    assert [len(t.triangles) for t in sa.triangulate(geoms[:2])] == [2, len(out[1].triangles)]
    # an error names the position
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="geometry 2: Polygon is not valid") as info:
        sa.triangulate([geoms[0], geoms[1], INVALID["bow-tie"][0]])
    assert info.value.index == 2
    with pytest.raises(cdt_plugin.TooFewPointsError, match="geometry 1"):
        sa.triangulate([geoms[0], shapely.Polygon()])


def test_to_shapely_matches_geos_format():
    poly = _holed()
    ours = sa.constrained_delaunay_triangles(poly)
    geos = shapely.constrained_delaunay_triangles(poly)
    assert ours.geom_type == geos.geom_type == "GeometryCollection"
    assert len(ours.geoms) == len(geos.geoms)
    assert {g.geom_type for g in ours.geoms} == {g.geom_type for g in geos.geoms} == {"Polygon"}
    for gc in (ours, geos):
        rings = [g.exterior for g in gc.geoms]
        assert all(len(r.coords) == 4 and r.coords[0] == r.coords[-1] for r in rings)
        assert not any(shapely.is_ccw(r) for r in rings)      # GEOS: clockwise shells
        assert all(len(g.interiors) == 0 for g in gc.geoms)
    assert ours.area == pytest.approx(geos.area, rel=1e-12)
    ccw = sa.to_shapely(sa.triangulate(poly), ccw=True)
    assert all(shapely.is_ccw(g.exterior) for g in ccw.geoms)


def _random_polygon(rng, holes):
    """A star-shaped polygon of random radii with ``holes`` small square holes
    near its centre (valid by construction)."""
    n = int(rng.integers(8, 40))
    t = 2 * np.pi * (np.arange(n) + rng.uniform(0, 0.5, n)) / n    # (no side near the holes)
    shell = np.column_stack([np.cos(t), np.sin(t)]) * rng.uniform(0.6, 1.0, n)[:, None]
    inner = [np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * 0.05 + [0.2 * np.cos(a), 0.2 * np.sin(a)]
             for a in 2 * np.pi * np.arange(holes) / max(holes, 1)]
    return shapely.Polygon(shell, inner)


def _reference_collection(V, T, corners):
    """The GeometryCollection of the triangles as it was built before the WKB
    writer: one shapely Polygon per triangle ring, gathered by shapely."""
    polygons = shapely.polygons(np.asarray(V, float)[np.asarray(T)[:, corners]]) if len(T) else []
    return shapely.geometrycollections(polygons)


@pytest.mark.parametrize("scale", [2.0 ** -1000, 1.0, 2.0 ** 1000])
def test_collections_are_the_polygons_shapely_builds_bit_for_bit(scale):
    # the GeometryCollection written as WKB and read by GEOS in one call holds the
    # very Polygons (coordinates, orientation, ring start, dimension) that shapely's
    # own constructors give from the same triangles
    rng = np.random.default_rng(47)
    for k in range(30):
        poly = shapely.affinity.scale(_random_polygon(rng, k % 4), scale, scale, origin=(0, 0))
        tri = cdt_plugin.triangulate(poly)
        cw, ccw = [0, 2, 1, 0], [0, 1, 2, 0]
        assert sa.to_shapely(tri).wkb == _reference_collection(tri.vertices, tri.triangles, cw).wkb
        assert sa.to_shapely(tri, ccw=True).wkb == _reference_collection(tri.vertices, tri.triangles, ccw).wkb
        z = rng.uniform(-1, 1, len(tri.vertices)) * scale
        V3 = np.column_stack([tri.vertices, z])
        assert sa.to_shapely(tri, z=z).wkb == _reference_collection(V3, tri.triangles, cw).wkb
        # the drop-in: the same polygons, 2D and with z (each vertex's own); a polygon the
        # one-polygon path takes comes in its order (cdt_plugin.plain: the same triangles)
        mesh = plain_mesh(poly) or (tri.vertices, tri.triangles)
        assert sa.constrained_delaunay_triangles(poly).wkb == _reference_collection(*mesh, cw).wkb
        coords = shapely.get_coordinates(poly)
        poly3 = shapely.set_coordinates(shapely.force_3d(poly), np.column_stack(
            [coords, coords[:, 0] * 0.5 + coords[:, 1]]))
        tri3 = cdt_plugin.triangulate(shapely.force_2d(poly3))
        V3 = np.column_stack([tri3.vertices, tri3.vertices[:, 0] * 0.5 + tri3.vertices[:, 1]])
        assert sa.constrained_delaunay_triangles(poly3).wkb == _reference_collection(
            V3, tri3.triangles, cw).wkb


def test_collection_of_mixed_dimensions_and_of_nothing():
    # a collection's members may differ in dimension (as GEOS's do): the 2D part
    # stays 2D in a GEOMETRYCOLLECTION Z, as shapely's own constructors make it
    flat, tilted = shapely.box(0, 0, 1, 1), shapely.Polygon([(5, 5, 1), (6, 5, 2), (6, 6, 3)])
    ours = sa.constrained_delaunay_triangles(shapely.GeometryCollection([flat, tilted]))
    t2, t3 = plain_mesh(flat), cdt_plugin.triangulate(shapely.force_2d(tilted))  # (the box: plain)
    V3 = np.column_stack([t3.vertices, [1.0, 2.0, 3.0]])      # (the input order: no point merged)
    parts = list(_reference_collection(*t2, [0, 2, 1, 0]).geoms) + list(
        _reference_collection(V3, t3.triangles, [0, 2, 1, 0]).geoms)
    assert ours.wkb == shapely.geometrycollections(parts).wkb
    assert shapely.has_z(ours) and not shapely.has_z(ours.geoms[0])
    nothing = sa.to_shapely(cdt_plugin.delaunay([[0.0, 0.0], [1.0, 1.0]]))
    assert nothing.wkb == shapely.GeometryCollection().wkb


def test_min_angle_at_least_geos():
    # a polygon big enough that GEOS' capped flip passes may stop short of the CDT
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0, 2 * np.pi, 400))
    r = rng.uniform(0.3, 1.0, 400)
    star = shapely.Polygon(np.column_stack([r * np.cos(t), r * np.sin(t)]), [_circle(0, 0, 0.1, 24)])
    assert star.is_valid
    for poly in (_holed(), star):
        tri = sa.triangulate(poly)
        ours = _min_angle(tri.vertices, tri.triangles)
        geos = _collection_min_angle(shapely.constrained_delaunay_triangles(poly))
        assert ours >= geos - 1e-12
        assert ours == pytest.approx(_collection_min_angle(sa.to_shapely(tri)), abs=1e-9)


def test_dropin_behaviour():
    poly = _holed()
    assert sa.constrained_delaunay_triangles(None) is None
    for g in (shapely.Polygon(), shapely.MultiPoint([(0, 0), (1, 0), (0, 1)]), shapely.LineString([(0, 0), (1, 1)]),
              shapely.LinearRing([(0, 0), (1, 0), (0, 1)])):
        res = sa.constrained_delaunay_triangles(g)
        geos = shapely.constrained_delaunay_triangles(g)
        assert res.geom_type == geos.geom_type == "GeometryCollection" and res.is_empty and geos.is_empty
    # polygonal members of a collection only, as GEOS
    gc = shapely.GeometryCollection([shapely.box(0, 0, 4, 4), shapely.Point(9, 9)])
    assert len(sa.constrained_delaunay_triangles(gc).geoms) == len(shapely.constrained_delaunay_triangles(gc).geoms)
    # z is kept, as GEOS does
    p3 = shapely.Polygon([(0, 0, 1), (1, 0, 2), (1, 1, 3), (0, 1, 4)])
    res = sa.constrained_delaunay_triangles(p3)
    assert shapely.has_z(res) and shapely.has_z(shapely.constrained_delaunay_triangles(p3))
    assert sorted(set(shapely.get_coordinates(res, include_z=True)[:, 2])) == [1, 2, 3, 4]
    # vectorised like shapely's: same shape, None propagates
    arr = np.array([[poly, None], [shapely.Point(0, 0), shapely.box(0, 0, 1, 1)]], dtype=object)
    res = sa.constrained_delaunay_triangles(arr)
    geos = shapely.constrained_delaunay_triangles(arr)
    assert res.shape == geos.shape == (2, 2)
    assert res[0, 1] is None and geos[0, 1] is None
    assert res[1, 0].is_empty
    assert [len(g.geoms) for g in (res[0, 0], res[1, 1])] == [len(g.geoms) for g in (geos[0, 0], geos[1, 1])]
    with pytest.raises(TypeError, match="where"):
        sa.constrained_delaunay_triangles(poly, where=True)
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="geometry 1"):
        sa.constrained_delaunay_triangles([poly, INVALID["bow-tie"][0]])


def test_triangulation_to_shapely_method():
    tri = cdt_plugin.triangulate(shapely.box(0, 0, 2, 1))
    gc = tri.to_shapely()
    assert gc.geom_type == "GeometryCollection" and gc.area == 2.0
    empty = sa.to_shapely(sa.triangulate(shapely.MultiPoint([(0, 0), (1, 1)])))
    assert empty.is_empty and empty.geom_type == "GeometryCollection"


def test_batch_meshes_a_millimetre_ring_at_utm_scale():
    # valid (area 3.6e-7 m2), but its raw shoelace sum x_i y_j - x_j y_i cancels to exactly
    # 0.0 at these magnitudes: the degenerate-ring check must not call it zero-area
    sliver = shapely.from_wkt("POLYGON ((4421750.51858677 -948118.6153869622, 4421750.519423157 "
                              "-948118.6160371872, 4421750.518822999 -948118.6164387744, "
                              "4421750.51858677 -948118.6153869622))")
    xy = shapely.get_coordinates(sliver)[:-1]
    assert sliver.is_valid
    assert (xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]).sum() == 0.0
    batch = sa.triangulate_batch([sliver])
    assert batch.errors == {} and len(batch.triangles) == 1
    assert_valid(batch.vertices, batch.triangles, segments=[[0, 1], [1, 2], [2, 0]], domain="segments")


def test_series_and_geoseries_element_wise_with_their_index():
    """A pandas Series or GeoSeries was read as one geometry: the shapely drop-in
    returned only the first geometry's triangles, triangulate and triangulate_batch
    crashed. They are element-wise, as shapely's functions are, and keep the index
    (a GeoSeries also its CRS)."""
    pd = pytest.importorskip("pandas")
    gpd = pytest.importorskip("geopandas")
    geoms = [shapely.box(0, 0, 1, 1), None, _holed()]
    s = pd.Series(geoms, index=[10, 20, 30])
    g = gpd.GeoSeries(geoms, index=[10, 20, 30], crs="EPSG:3857")
    single = [sa.constrained_delaunay_triangles(x) for x in geoms]
    for series in (s, g, g.values):
        out = sa.constrained_delaunay_triangles(series)
        assert [None if o is None else len(o.geoms) for o in out] == \
            [None if o is None else len(o.geoms) for o in single]
        assert all(o is None or o.equals(e) for o, e in zip(out, single))
    out = sa.constrained_delaunay_triangles(g)
    assert isinstance(out, gpd.GeoSeries) and out.index.tolist() == [10, 20, 30] and out.crs == g.crs
    out = sa.constrained_delaunay_triangles(s)
    assert isinstance(out, pd.Series) and out.index.tolist() == [10, 20, 30]
    ref = shapely.constrained_delaunay_triangles(s)        # GEOS: the same container
    assert type(ref) is type(out) and ref.index.tolist() == out.index.tolist()
    tris = sa.triangulate(g)
    assert isinstance(tris, pd.Series) and tris.index.tolist() == [10, 20, 30] and tris[20] is None
    for geom, tri in zip(geoms, tris):
        if geom is not None:
            assert np.array_equal(tri.triangles, sa.triangulate(geom).triangles)
            _assert_covers(tri, geom)
    batch = sa.triangulate_batch(s)
    assert len(batch) == 3 and np.array_equal(np.unique(batch.geometry), [0, 2])
    assert len(batch.triangles) == len(tris[10].triangles) + len(tris[30].triangles)


# ----------------------------------------------------------- drop-ins (issue #17)
def _mesh_of(gc, ccw):
    """(vertices, counter-clockwise triangles) of a GeometryCollection of triangle
    Polygons (shells counter-clockwise when ``ccw``, else clockwise as GEOS's CDT)."""
    corners = shapely.get_coordinates(np.asarray(gc.geoms, dtype=object)).reshape(-1, 4, 2)[:, :3]
    if not ccw:
        corners = corners[:, ::-1]
    V, T = np.unique(corners.reshape(-1, 2), axis=0, return_inverse=True)
    return V, T.reshape(-1, 3)


def _edge_set(mls):
    """The edges of a MultiLineString of two-point LineStrings, as sorted coordinate pairs."""
    coords = shapely.get_coordinates(np.asarray(mls.geoms, dtype=object)).reshape(-1, 2, 2)
    assert shapely.get_num_coordinates(np.asarray(mls.geoms, dtype=object)).tolist() == [2] * len(coords)
    return {tuple(sorted(map(tuple, e))) for e in coords.tolist()}


def _triangle_edges(V, T):
    return {tuple(sorted((tuple(V[a]), tuple(V[b])))) for t in T.tolist()
            for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}


def _assert_delaunay_of(gc, vertices):
    """The exact checker on a delaunay_triangles result: a Delaunay triangulation
    of the convex hull of exactly the distinct ``vertices``."""
    V, T = _mesh_of(gc, ccw=True)
    assert {tuple(v) for v in V.tolist()} == {tuple(v) for v in np.asarray(vertices)[:, :2].tolist()}
    assert_valid(V, T, domain="hull")
    return V, T


def _assert_cdt_of(gc, geom):
    """The exact checker on a constrained_delaunay_triangles result: every ring
    edge of the (valid) polygonal ``geom`` is an edge, the domain is bounded by
    them, every other edge locally Delaunay."""
    V, T = _mesh_of(gc, ccw=False)
    index = {tuple(v): k for k, v in enumerate(V.tolist())}
    segments = []
    for ring in shapely.get_rings(shapely.get_parts(geom)):
        ids = [index[tuple(p)] for p in shapely.get_coordinates(ring).tolist()]
        segments += [ids[k:k + 2] for k in range(len(ids) - 1)]
    assert_valid(V, T, segments=np.array(segments), domain="segments")
    assert gc.area == pytest.approx(geom.area, rel=1e-12)


def _general_position_cases():
    rng = np.random.default_rng(11)
    pts = rng.uniform(0, 100, (300, 2))
    return {"points": shapely.MultiPoint(pts),
            "polygon with holes": shapely.Polygon(_circle(0, 0, 10, 23) + rng.uniform(0, 0.1, (23, 2)),
                                                  [_circle(1, 0.5, 3, 7) + rng.uniform(0, 0.1, (7, 2))]),
            "linestring": shapely.LineString(rng.uniform(0, 10, (40, 2))),
            "collection": shapely.GeometryCollection([shapely.Point(50, 50), shapely.LineString(pts[:5]),
                                                      shapely.Polygon(_circle(30, 60, 7, 9)
                                                                      + rng.uniform(0, 0.1, (9, 2)))]),
            "3d": shapely.MultiPoint(np.column_stack([pts[:50], rng.uniform(0, 1, 50)]))}


@pytest.mark.parametrize("name", sorted(_general_position_cases()))
def test_delaunay_triangles_matches_geos_in_general_position(name):
    geom = _general_position_cases()[name]
    ours, geos = sa.delaunay_triangles(geom), shapely.delaunay_triangles(geom)
    assert ours.geom_type == geos.geom_type == "GeometryCollection"
    assert shapely.has_z(ours) == shapely.has_z(geos) == (name == "3d")
    V, T = _assert_delaunay_of(ours, shapely.get_coordinates(geom))
    assert canonical_triangles(V, T) == canonical_triangles(*_mesh_of(geos, ccw=True))
    for gc in (ours, geos):      # GEOS's form for this function: closed ccw 4-point shells
        rings = shapely.get_exterior_ring(np.asarray(gc.geoms, dtype=object))
        assert (shapely.get_num_coordinates(rings) == 4).all() and shapely.is_ccw(rings).all()
    assert ours.area == pytest.approx(geos.area, rel=1e-12)
    edges = sa.delaunay_triangles(geom, only_edges=True)
    geos_edges = shapely.delaunay_triangles(geom, only_edges=True)
    assert edges.geom_type == geos_edges.geom_type == "MultiLineString"
    assert _edge_set(edges) == _edge_set(geos_edges) == _triangle_edges(V, T)
    if name == "3d":             # every vertex keeps its z
        given = {tuple(p[:2]): p[2] for p in shapely.get_coordinates(geom, include_z=True).tolist()}
        for p in shapely.get_coordinates(ours, include_z=True).tolist():
            assert given[tuple(p[:2])] == p[2]


def test_delaunay_triangles_degenerate_input_like_geos():
    cases = [shapely.MultiPoint([(0, 0), (1, 0), (3, 0), (2, 0)]), shapely.LineString([(0, 0), (1, 1), (2, 2)]),
             shapely.MultiPoint([(0, 0), (1, 0), (0, 0)]), shapely.Point(0, 0), shapely.Polygon(),
             shapely.GeometryCollection(), shapely.MultiPoint([(5, 5), (5, 5), (5, 5)])]
    for geom in cases:
        ours, geos = sa.delaunay_triangles(geom), shapely.delaunay_triangles(geom)
        assert ours.geom_type == "GeometryCollection" and ours.is_empty and geos.is_empty
        ours, geos = sa.delaunay_triangles(geom, only_edges=True), shapely.delaunay_triangles(geom, only_edges=True)
        assert ours.geom_type == geos.geom_type == "MultiLineString"
        assert _edge_set(ours) == _edge_set(geos)
        if not ours.is_empty:    # collinear: the chain along the line (Sec. 2.1), checked exactly
            P = np.unique(shapely.get_coordinates(geom), axis=0)
            index = {tuple(p): k for k, p in enumerate(P.tolist())}
            E = [[index[a], index[b]] for a, b in _edge_set(ours)]
            report = check_collinear_edges(P, E)
            assert report.ok, report.problems
    assert sa.delaunay_triangles(None) is None
    # duplicates are merged, the first one's z kept
    dup = shapely.MultiPoint([(0, 0, 1), (4, 0, 2), (0, 3, 3), (0, 0, 9), (4, 0, 2)])
    gc = sa.delaunay_triangles(dup)
    _assert_delaunay_of(gc, shapely.get_coordinates(dup))
    assert sorted(shapely.get_coordinates(gc, include_z=True)[:3, 2].tolist()) == [1, 2, 3]


def _greedy_snap(xy, tolerance):
    """Reference for tolerance: lexicographic order, keep a point unless it is
    closer than tolerance to a point kept before it (quadratic, plain Python)."""
    kept = []
    for p in sorted(map(tuple, xy.tolist())):
        if all(np.hypot(p[0] - q[0], p[1] - q[1]) >= tolerance for q in kept):
            kept.append(p)
    return kept


def test_delaunay_triangles_tolerance_snaps_vertices():
    # shapely's own example gives GEOS's triangle
    mp = shapely.MultiPoint([(50, 30), (51, 30), (60, 30), (100, 100)])
    ours = sa.delaunay_triangles(mp, tolerance=2)
    assert shapely.equals(ours, shapely.delaunay_triangles(mp, tolerance=2))
    _assert_delaunay_of(ours, [(50, 30), (60, 30), (100, 100)])
    # tight clusters: one vertex each (the lexicographically first); the rule is exact here,
    # where GEOS (checking only the edge it located) keeps some cluster points
    rng = np.random.default_rng(5)
    centres = rng.uniform(0, 100, (40, 2))
    xy = np.concatenate([centres + rng.uniform(-0.2, 0.2, (40, 2)) for _ in range(3)])
    for tolerance in (1.0, 3.0, 10.0):
        gc = sa.delaunay_triangles(shapely.MultiPoint(xy), tolerance=tolerance)
        kept = np.array(_greedy_snap(xy, tolerance))
        V, T = _assert_delaunay_of(gc, kept)
        d = np.hypot(*(V[:, None] - V[None]).transpose(2, 0, 1))
        assert d[~np.eye(len(V), dtype=bool)].min() >= tolerance          # no two closer than it
        assert np.hypot(*(xy[:, None] - V[None]).transpose(2, 0, 1)).min(axis=1).max() < tolerance
        edges = sa.delaunay_triangles(shapely.MultiPoint(xy), tolerance=tolerance, only_edges=True)
        assert _edge_set(edges) == _triangle_edges(V, T)
    assert len(_greedy_snap(xy, 1.0)) == 40
    # zero tolerance: only exact duplicates merge, as GEOS
    assert shapely.equals(sa.delaunay_triangles(shapely.MultiPoint(xy), tolerance=0.0),
                          shapely.delaunay_triangles(shapely.MultiPoint(xy)))


def test_delaunay_triangles_bad_options_raise_before_any_work():
    poly = _holed()
    for bad in ({"tolerance": -1.0}, {"tolerance": [0.0, -2.0]}):
        with pytest.raises(cdt_plugin.CDTError, match=r"tolerance must be >= 0 .*got (-1.0|-2.0)"):
            sa.delaunay_triangles([poly, "not a geometry"], **bad)
    # a NaN tolerance gives None, as shapely's
    assert sa.delaunay_triangles(poly, tolerance=float("nan")) is None
    assert shapely.delaunay_triangles(poly, tolerance=float("nan")) is None
    with pytest.raises(cdt_plugin.CDTError, match="tolerance must be a number"):
        sa.delaunay_triangles(poly, tolerance="1m")
    for bad in ("yes", 2, [True, "no"]):
        with pytest.raises(cdt_plugin.CDTError, match="only_edges must be True or False"):
            sa.delaunay_triangles(poly, only_edges=bad)
    with pytest.raises(cdt_plugin.InputShapeError, match=r"cannot be broadcast together \(shapes \(2,\), \(3,\)"):
        sa.delaunay_triangles([poly, poly], tolerance=[0, 0, 0])
    with pytest.raises(TypeError, match="ufunc keyword arguments are not supported \\(out, where\\)"):
        sa.delaunay_triangles(poly, where=True, out=None)
    with pytest.raises(TypeError, match="incorrect type: str"):
        sa.delaunay_triangles([poly, "POINT (0 0)"])
    bad_coords = shapely.MultiPoint([(0, 0), (np.inf, 1), (2, 2)])
    for tolerance in (0.0, 0.5):
        with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match="^geometry 1: .*row 1"):
            sa.delaunay_triangles([poly, bad_coords], tolerance=tolerance)


def _check_result(res, geom, function):
    """The exact checker on one element of a drop-in's output."""
    if geom is None:
        assert res is None
    elif function is sa.delaunay_triangles and res.geom_type == "GeometryCollection" and not res.is_empty:
        _assert_delaunay_of(res, shapely.get_coordinates(geom))
    elif function is sa.constrained_delaunay_triangles and not res.is_empty:
        _assert_cdt_of(res, geom)


@pytest.mark.parametrize("function", [sa.constrained_delaunay_triangles, sa.delaunay_triangles])
def test_dropins_are_elementwise_like_shapely(function):
    pd = pytest.importorskip("pandas")
    gpd = pytest.importorskip("geopandas")
    reference = getattr(shapely, function.__name__)
    poly, box = _holed(), shapely.box(0, 0, 2, 1)
    grid = np.array([[poly, None, box], [shapely.Point(0, 0), box, poly]], dtype=object)
    out = function(grid)
    assert isinstance(out, np.ndarray) and out.shape == reference(grid).shape == (2, 3)
    for res, geom in zip(out.ravel(), grid.ravel()):
        _check_result(res, geom, function)
        assert res is None if geom is None else res.equals(function(geom))
    as_list = function([poly, None])
    assert isinstance(as_list, np.ndarray) and as_list.shape == (2,) and as_list[1] is None
    zero_d = function(np.array(poly))                 # shapely returns the geometry itself
    assert isinstance(zero_d, shapely.Geometry) and isinstance(reference(np.array(poly)), shapely.Geometry)
    _check_result(zero_d, poly, function)
    empty = function([])
    assert isinstance(empty, np.ndarray) and empty.shape == (0,)
    series = pd.Series([box, None, poly], index=["a", "b", "c"])
    geoseries = gpd.GeoSeries(series.values, index=series.index, crs="EPSG:32633")
    for s in (series, geoseries):
        res = function(s)
        assert type(res) is type(s) and res.index.tolist() == ["a", "b", "c"] and res["b"] is None
        assert type(reference(s)) is type(s)
        for r, geom in zip(res, s):
            _check_result(r, geom, function)
    assert function(geoseries).crs == geoseries.crs


def test_delaunay_triangles_broadcasts_its_options_like_shapely():
    pd = pytest.importorskip("pandas")
    mp = shapely.MultiPoint(np.random.default_rng(2).uniform(0, 10, (60, 2)))
    out = sa.delaunay_triangles(mp, only_edges=[False, True])
    ref = shapely.delaunay_triangles(mp, only_edges=[False, True])
    assert out.shape == ref.shape == (2,)
    V, T = _assert_delaunay_of(out[0], shapely.get_coordinates(mp))
    assert out[1].geom_type == ref[1].geom_type == "MultiLineString"
    assert _edge_set(out[1]) == _edge_set(ref[1]) == _triangle_edges(V, T)
    grid = sa.delaunay_triangles(np.array([[mp], [mp]], dtype=object), tolerance=[0.0, 1.0, 2.0])
    assert grid.shape == shapely.delaunay_triangles(np.array([[mp], [mp]], dtype=object),
                                                    tolerance=[0.0, 1.0, 2.0]).shape == (2, 3)
    xy = shapely.get_coordinates(mp)
    for row in grid:
        for gc, tolerance in zip(row, (0.0, 1.0, 2.0)):
            _assert_delaunay_of(gc, np.array(_greedy_snap(xy, tolerance)) if tolerance else xy)
    s = pd.Series([mp, None], index=[3, 4])
    res = sa.delaunay_triangles(s, tolerance=pd.Series([0.0, 1.0], index=[3, 4]).to_numpy(), only_edges=True)
    assert isinstance(res, pd.Series) and res.index.tolist() == [3, 4] and res[4] is None
    assert _edge_set(res[3]) == _triangle_edges(V, T)


@pytest.mark.parametrize("repair", [True, "linework", "structure"])
def test_constrained_dropin_repairs_like_triangulate(repair):
    names = sorted(INVALID)
    geoms = [INVALID[name][0] for name in names]
    out = sa.constrained_delaunay_triangles(geoms + [None], repair=repair)
    assert out[-1] is None
    kw = {"method": "structure", "keep_collapsed": False} if repair == "structure" else {}
    for gc, geom in zip(out, geoms):
        tri = sa.triangulate(geom, repair=repair)                      # the same repair path
        assert canonical_triangles(*_mesh_of(gc, ccw=False)) == canonical_triangles(tri.vertices, tri.triangles)
        fixed = shapely.make_valid(geom, **kw)
        polygonal = shapely.MultiPolygon([p for p in shapely.get_parts(fixed) if p.geom_type == "Polygon"]) \
            if fixed.geom_type != "Polygon" else fixed
        _assert_cdt_of(gc, polygonal)
        assert gc.area == pytest.approx(fixed.area, rel=1e-12)
    single = sa.constrained_delaunay_triangles(geoms[0], repair=repair)
    assert single.equals(out[0])


def test_constrained_dropin_repair_option_is_checked_first():
    bowtie = INVALID["bow-tie"][0]
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="^geometry 1: Polygon is not valid.*pass repair=True"):
        sa.constrained_delaunay_triangles([shapely.box(0, 0, 1, 1), bowtie])
    with pytest.raises(cdt_plugin.CDTError, match="repair must be False, True, 'linework' or 'structure', got 'yes'"):
        sa.constrained_delaunay_triangles([bowtie, "not a geometry"], repair="yes")
    # a GeometryCollection's invalid polygonal member is repaired too
    gc = shapely.GeometryCollection([bowtie, shapely.Point(9, 9)])
    res = sa.constrained_delaunay_triangles(gc, repair=True)
    _assert_cdt_of(res, shapely.make_valid(bowtie))


def _mixed_layer(n=40, seed=0):
    """Polygons with holes, with Z and without, MultiPolygons and empties."""
    rng = np.random.default_rng(seed)
    geoms = []
    for i in range(n):
        p = shapely.buffer(shapely.Point(rng.random(2) * 10), 0.5 + rng.random(),
                           quad_segs=int(rng.integers(1, 6)))
        if i % 5 == 0:
            p = p.difference(shapely.buffer(p.centroid, 0.2))
        if i % 7 == 0:
            p = shapely.force_3d(p, 1.5)
        if i % 11 == 0:
            p = shapely.MultiPolygon([p, shapely.box(20 + i, 0, 21 + i, 1)])
        if i % 13 == 0:
            p = shapely.Polygon()
        geoms.append(p)
    return np.array(geoms, dtype=object)


def test_batch_reads_and_checks_the_geometries_on_its_threads(monkeypatch):
    """A large batch reads its rings and checks validity in slices on its
    threads; the joined arrays and the meshes equal one thread's."""
    monkeypatch.setattr(reading, "CHUNK", 3)     # (slices on small inputs too)
    arr = _mixed_layer()
    one = reading.layer_rings(arr)
    for workers in (2, 3, 5):
        many = reading.layer_rings_on_threads(arr, workers)
        for a, b in zip(one, many):
            assert (a is None and b is None) or np.array_equal(a, b, equal_nan=True), workers
        assert np.array_equal(reading._is_valid(arr, workers), shapely.is_valid(arr))
    arr[3] = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])          # a bow tie
    ref = sa.triangulate_batch(arr, workers=1, errors="skip")
    assert list(ref.errors) == [3]
    for workers in (2, 3):
        b = sa.triangulate_batch(arr, workers=workers, errors="skip")
        assert list(b.errors) == [3]
        for name in ("vertices", "triangles", "geometry", "offsets"):
            assert np.array_equal(getattr(ref, name), getattr(b, name)), (workers, name)
    arr[3] = shapely.Polygon()                  # as the batch left it
    xy, _, ring_start, geom_ring_start, *_ = reading.layer_rings(arr)
    for g in range(len(arr)):           # every mesh, exactly, against its geometry's rings
        rings = range(geom_ring_start[g], geom_ring_start[g + 1])
        if not len(rings):
            continue
        segs = np.concatenate([np.column_stack([np.arange(ring_start[r], ring_start[r + 1]),
                                                np.roll(np.arange(ring_start[r], ring_start[r + 1]), -1)])
                               for r in rings])
        ids, local = np.unique(np.concatenate([segs.ravel(), ref.triangles[ref.offsets[g]:ref.offsets[g + 1]]
                                              .ravel()]), return_inverse=True)
        assert np.array_equal(ref.vertices[ids[ids < len(xy)]], xy[ids[ids < len(xy)]])
        assert_valid(ref.vertices[ids], local[segs.size:].reshape(-1, 3),
                     segments=local[:segs.size].reshape(-1, 2), domain="segments")


def test_ring_markers_mark_exterior_and_holes():
    """``markers=``: each ring's segments get its role's marker, their vertices
    and Steiner points too; one value per geometry for array input (a column)."""
    poly = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 3), (3, 3), (3, 1)]])
    tri = sa.triangulate(poly, markers={"exterior": 3, "holes": 2}, max_area=0.5)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    xy = tri.vertices[tri.segments].mean(axis=1)
    inner = (xy >= 1).all(axis=1) & (xy <= 3).all(axis=1)
    assert (tri.segment_markers == np.where(inner, 2, 3)).all()
    on_hole = (tri.vertices >= 1).all(axis=1) & (tri.vertices <= 3).all(axis=1)
    assert (tri.vertex_markers[on_hole] == 2).all() and (tri.vertex_markers[~on_hole & (tri.vertex_markers > 0)] == 3).all()
    both = sa.triangulate([poly, shapely.box(5, 0, 6, 1)], markers=np.array([5, 7]))
    assert [sorted(set(t.segment_markers.tolist())) for t in both] == [[5], [7]]
    assert set(sa.triangulate(poly, markers={"holes": 4}).segment_markers.tolist()) == {1, 4}
    with pytest.raises(cdt_plugin.InputShapeError, match="among"):
        sa.triangulate(poly, markers={"hole": 1})
    with pytest.raises(cdt_plugin.InputShapeError, match="one per geometry"):
        sa.triangulate([poly, poly], markers=[1, 2, 3])


# a CAD outline whose hole has a corner written twice, 1e-14 apart (GEOS: "Self-intersection"),
# and a shell corner twice: valid once its near-duplicates are merged
_NEAR = shapely.Polygon([(0, 0), (1e-12, 0), (4, 0), (4, 4), (4, 4 + 1e-13), (0, 4)],
                        [[(1, 1), (1, 3), (3, 3), (3, 1), (3 + 1e-14, 1)]])


def _area(tri):
    a, b, c = (tri.vertices[tri.triangles[:, k]] for k in range(3))
    return 0.5 * float(((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]).sum())


def test_merge_distance_merges_before_validity_is_decided():
    assert not _NEAR.is_valid
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="Self-intersection"):
        sa.triangulate(_NEAR)
    engine = cdt_plugin.triangulate(_NEAR, merge_distance=1e-9)
    for out in (sa.triangulate(_NEAR, merge_distance=1e-9),
                sa.triangulate([_NEAR, shapely.box(0, 0, 1, 1)], merge_distance=1e-9)[0]):
        assert out.stats["merged_points"] == 3 and np.array_equal(out.vertex_map, engine.vertex_map)
        assert np.array_equal(out.triangles, engine.triangles)
        assert_valid(out.vertices, out.triangles, segments=out.segments, domain="segments",
                     require_all_vertices=False)
        assert _area(out) == pytest.approx(12.0, rel=1e-12)
    # too small a distance merges nothing: GEOS's verdict on the input stands
    with pytest.raises(cdt_plugin.InvalidGeometryError, match="merge_distance=1e-15"):
        sa.triangulate(_NEAR, merge_distance=1e-15)


def test_merge_distance_that_folds_a_polygon_is_refused_alike_one_by_one_and_in_arrays():
    # a slit 2e-10 wide: valid as given, a ring that runs back on itself once its two sides
    # merge; the verdict is the merged polygon's, for one geometry and for an array
    slit = shapely.Polygon([(0, 0), (4, 0), (4, 4), (2 + 1e-10, 4), (2, 1), (2 - 1e-10, 4), (0, 4)])
    assert slit.is_valid and len(sa.triangulate(slit).triangles) == 5
    for geometry in (slit, [slit]):
        with pytest.raises(cdt_plugin.InvalidGeometryError, match="Self-intersection.*merge_distance=1e-09"):
            sa.triangulate(geometry, merge_distance=1e-9)
    fixed = sa.triangulate(slit, merge_distance=1e-9, repair=True)     # make_valid of the merged one
    assert_valid(fixed.vertices, fixed.triangles, segments=fixed.segments, domain="segments")
    assert _area(fixed) == pytest.approx(16.0, rel=1e-12)


@pytest.mark.parametrize("value", [-1.0, float("nan"), "1e-9"])
def test_bad_merge_distance_is_named_before_validity(value):
    with pytest.raises(cdt_plugin.CDTError, match="merge_distance must be"):
        sa.triangulate(_NEAR, merge_distance=value)
