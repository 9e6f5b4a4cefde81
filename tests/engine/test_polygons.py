"""Polygons in one call (MultiPolygon, GeometryCollection, coverages): each
triangle carries the polygon it lies in, and rings that cannot bound disjoint
polygons raise InvalidGeometryError (issue: reliability, domains and regions).
Every mesh is checked by the exact checker."""
from __future__ import annotations

import numpy as np
import pytest
import shapely

import cdt_plugin
from cdt_plugin import InvalidGeometryError
from checker import check_triangulation


def _verify_labels(geoms, tri):
    """Exact mesh check, and every triangle's centroid lies in the polygon it names."""
    rep = check_triangulation(tri.vertices, tri.triangles, domain="segments",
                              segments=tri.segments, require_all_vertices=False)
    assert rep.ok, str(rep)
    centroids = tri.vertices[tri.triangles].mean(axis=1)
    for c, r in zip(centroids, tri.regions):
        assert 0 <= r < len(geoms)
        assert geoms[r].contains(shapely.Point(c)), (c, r)
    assert sum(g.area for g in geoms) == pytest.approx(
        sum(shapely.Polygon(tri.vertices[t]).area for t in tri.triangles))


def test_a_plus_sign_coverage_labels_every_box():
    # the centre box got no triangle of its own: regions [0,1,1,4,1,0,3,4,3,0]
    boxes = [shapely.box(i, j, i + 1, j + 1) for i, j in [(1, 0), (0, 1), (1, 1), (2, 1), (1, 2)]]
    tri = cdt_plugin.triangulate(shapely.GeometryCollection(boxes))
    _verify_labels(boxes, tri)
    assert np.bincount(tri.regions).tolist() == [2, 2, 2, 2, 2]


@pytest.mark.parametrize("n", [3, 10])
def test_a_lattice_coverage(n):
    boxes = [shapely.box(i, j, i + 1, j + 1) for i in range(n) for j in range(n)]
    tri = cdt_plugin.triangulate(shapely.MultiPolygon(boxes))
    _verify_labels(boxes, tri)
    assert (np.bincount(tri.regions) == 2).all()


def test_a_polygon_filling_another_ones_hole_and_an_island():
    outer = shapely.Polygon([(0, 0), (6, 0), (6, 6), (0, 6)], [[(1, 1), (5, 1), (5, 5), (1, 5)]])
    fill = shapely.Polygon([(1, 1), (5, 1), (5, 5), (1, 5)], [[(2, 2), (4, 2), (4, 4), (2, 4)]])
    island = shapely.box(2.5, 2.5, 3.5, 3.5)
    geoms = [outer, fill, island]
    tri = cdt_plugin.triangulate(shapely.GeometryCollection(geoms))
    _verify_labels(geoms, tri)
    assert set(tri.regions.tolist()) == {0, 1, 2}


def test_two_identical_boxes_raise():
    # silently 0 triangles before (the doubled ring encloses nothing by parity)
    two = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(0, 0, 1, 1)])
    assert not two.is_valid
    with pytest.raises(InvalidGeometryError, match=r"polygons 0 and 1 overlap"):
        cdt_plugin.triangulate(two)
    tri = cdt_plugin.triangulate(two, intersections="split")     # documented: even-odd depth
    assert len(tri.triangles) == 0


def test_overlapping_and_nested_polygons_raise():
    nested = shapely.MultiPolygon([shapely.box(0, 0, 4, 4), shapely.box(1, 1, 2, 2)])
    assert not nested.is_valid
    with pytest.raises(InvalidGeometryError, match=r"polygons 0 and 1 overlap"):
        cdt_plugin.triangulate(nested)
    # sharing part of an edge (valid): the shared piece is a collinear overlap, which
    # intersections="split" merges
    touching = [shapely.box(0, 0, 2, 1), shapely.box(0.5, 1, 1.5, 2)]
    tri = cdt_plugin.triangulate(shapely.MultiPolygon(touching), intersections="split")
    _verify_labels(touching, tri)


def test_a_hole_on_its_shell_raises():
    ring = [(0, 0), (1, 0), (1, 1), (0, 1)]
    with pytest.raises(InvalidGeometryError, match=r"rings of polygon 0 overlap"):
        cdt_plugin.triangulate(shapely.Polygon(ring, [ring[::-1]]))


def test_batch_and_single_call_give_the_same_regions():
    from cdt_plugin.adapters.shapely import triangulate_batch
    outer = shapely.Polygon([(0, 0), (6, 0), (6, 6), (0, 6)], [[(1, 1), (5, 1), (5, 5), (1, 5)]])
    parts = [outer, shapely.box(2, 2, 4, 4), shapely.box(7, 0, 8, 1)]
    multi = shapely.MultiPolygon(parts)
    one = cdt_plugin.triangulate(multi)
    _verify_labels(parts, one)
    batch = triangulate_batch([multi, shapely.MultiPolygon([parts[2], parts[2]])], errors="skip")
    assert np.array_equal(batch.region[batch.geometry == 0], one.regions)
    assert isinstance(batch.errors[1], InvalidGeometryError)
