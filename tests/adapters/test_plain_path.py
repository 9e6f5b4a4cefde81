"""The drop-ins' one-polygon path (cdt_plugin.plain, cdt_plugin._core.plain):
one compiled call from a small 2D Polygon's coordinates to the triangles or
to the GeometryCollection's WKB. It must take exactly the polygons the
general rule calls plainly valid (``mesh_if_plainly_valid``), give the very
mesh and bytes of the general path, at every magnitude, and leave everything
else (invalid, touching, Z, MultiPolygons, large, close points) to the general
path, whose results and errors the drop-ins then give."""
from __future__ import annotations

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
from cdt_plugin._core.ordering import SMALL_SORT  # noqa: E402
from cdt_plugin._core.rings import closed_rings  # noqa: E402
from cdt_plugin.adapters.shapely import constrained_delaunay_triangles  # noqa: E402
from cdt_plugin.adapters.shapely import validity  # noqa: E402
from cdt_plugin.adapters.shapely.building import plain_triangles, to_shapely  # noqa: E402
from cdt_plugin.adapters.shapely.reading import mesh_if_plainly_valid  # noqa: E402
from cdt_plugin.plain import plain_mesh  # noqa: E402
from checker import assert_valid  # noqa: E402
from polygons import random_polygon  # noqa: E402

#: (k, offset): coordinates c become (c + offset) * 2**k, exactly
SCALES = [(0, 0.0), (-1000, 0.0), (1000, 0.0), (-60, 1e15), (300, -2.0 ** 49)]


def moved(geometry, k, offset):
    return shapely.transform(geometry, lambda c: np.ldexp(c + offset, k))


def star(n, holes=0):
    """A star of n vertices (radii 1 and 0.5) with ``holes`` small 8-gons inside."""
    t = np.arange(n) * 2 * np.pi / n
    r = np.where(np.arange(n) % 2 == 0, 1.0, 0.5)
    a = np.arange(8) * 2 * np.pi / 8
    rings = [np.column_stack([0.2 * np.cos(2 * np.pi * h / max(holes, 1)) + 0.1 * np.cos(a),
                              0.2 * np.sin(2 * np.pi * h / max(holes, 1)) + 0.1 * np.sin(a)])
             for h in range(holes)]
    return shapely.Polygon(np.column_stack([r * np.cos(t), r * np.sin(t)]), rings)


def test_it_takes_what_the_general_rule_takes_and_gives_its_very_mesh():
    """600 random polygons valid or invalid by a hair (holes touching, crossing,
    outside, nested, repeated points) at five magnitudes: the plain path
    meshes a polygon exactly when the general rule does, only valid ones, with
    the same vertices, triangles and WKB; every mesh passes the exact checker."""
    rng = np.random.default_rng(11)
    taken = valid_count = 0
    for _ in range(600):
        g = random_polygon(rng)
        valid = bool(validity.is_valid(np.array([g]))[0])
        valid_count += valid
        for k, offset in SCALES:
            h = moved(g, k, offset)
            tri = mesh_if_plainly_valid(h)
            plain = plain_mesh(h)
            assert (plain is None) == (tri is None), shapely.to_wkt(g)
            if plain is None:
                assert plain_triangles(h) is None
                continue
            assert valid, shapely.to_wkt(g)
            taken += k == 0 and offset == 0
            vertices, triangles = plain
            np.testing.assert_array_equal(vertices, tri.vertices)
            np.testing.assert_array_equal(triangles, tri.triangles)
            assert shapely.to_wkb(plain_triangles(h)) == shapely.to_wkb(to_shapely(tri))
            segments = tri.segments if k == 0 and offset == 0 else None
            if segments is not None:
                assert_valid(vertices, triangles, segments=segments, domain="segments")
    assert valid_count > 100 and taken > 0.5 * valid_count


@pytest.mark.parametrize("holes", [0, 2, 4])
@pytest.mark.parametrize("k", [0, -1000, 1000])
def test_stars_at_every_magnitude(holes, k):
    g = moved(star(60, holes), k, 0.0)
    vertices, triangles = plain_mesh(g)
    assert len(triangles) == 60 + 8 * holes + 2 * holes - 2
    tri = cdt_plugin.triangulate(g)
    np.testing.assert_array_equal(triangles, tri.triangles)
    np.testing.assert_array_equal(vertices, tri.vertices)
    assert_valid(np.ldexp(vertices, -k), triangles, segments=tri.segments, domain="segments")
    assert shapely.to_wkb(constrained_delaunay_triangles(g)) == shapely.to_wkb(to_shapely(tri))


@pytest.mark.parametrize("wkt", [
    "POLYGON Z ((0 0 1, 1 0 1, 1 1 1, 0 0 1))",                                # Z: the general path keeps it
    "MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)))",
    "POLYGON EMPTY",
    "POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), EMPTY)",                               # an EMPTY hole
    "POLYGON ((0 0, 4 0, 4 4, 2 4, 3 2, 1 2, 2 4, 0 4, 0 0))",                  # touches itself
    "POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), (0 2, 2 1, 2 3, 0 2))",                # hole touches the shell
    "POLYGON ((0 0, 2 2, 2 0, 0 2, 0 0))",                                      # bow-tie
    "POLYGON ((0 0, 4 0, 4 0, 4 4, 0 0))",                                      # a repeated point
    "POLYGON ((0 0, 1 1, 2 2, 0 0))",                                           # no area
    "POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0), (1 1, 2 1, 2 2, 1 1), (1 1, 2 2, 1 2, 1 1))",
    "POLYGON ((0 0, 4 0, 4 4, 0 0, 0 4, -4 4, 0 0))",                           # through its first point
])
def test_what_it_leaves_to_the_general_path(wkt):
    """Each of these goes the general way: the drop-in's answer is the general
    path's (a mesh or a CDTError), never the plain path's."""
    g = shapely.from_wkt(wkt)
    assert plain_mesh(g) is None and plain_triangles(g) is None
    try:
        general = ("mesh", shapely.to_wkb(constrained_delaunay_triangles(g)))
    except cdt_plugin.CDTError as e:
        general = ("error", type(e))
    if general[0] == "mesh":       # the same as element-wise (never the plain path)
        arr = constrained_delaunay_triangles(np.array([g, shapely.box(0, 0, 1, 1)]))
        assert shapely.to_wkb(arr[0]) == general[1]


def test_nan_and_large_polygons_go_the_general_way():
    nan = shapely.Polygon([(0, 0), (1, 0), (np.nan, 1)])
    assert plain_mesh(nan) is None
    with pytest.raises(cdt_plugin.CDTError):
        constrained_delaunay_triangles(nan)
    big = star(SMALL_SORT + 2)
    assert plain_mesh(big) is None
    gc = constrained_delaunay_triangles(big)
    assert len(gc.geoms) == SMALL_SORT


def test_close_points_are_left_to_the_merge():
    """With a merge distance (the trimesh drop-in's trimesh.tol.merge) a polygon
    with two vertices closer than it goes the general way, which merges them."""
    trimesh_adapter = pytest.importorskip("cdt_plugin.adapters.trimesh")
    g = shapely.Polygon([(0, 0), (1, 0), (1, 1e-10), (1, 1), (0, 1)])
    assert plain_mesh(g) is not None and plain_mesh(g, 1e-8) is None
    vertices, faces = trimesh_adapter.triangulate_polygon(g)
    assert len(vertices) == 4 and len(faces) == 2
    assert_valid(vertices, faces)


def test_the_trimesh_drop_in_gives_the_general_paths_arrays():
    trimesh_adapter = pytest.importorskip("cdt_plugin.adapters.trimesh")
    rng = np.random.default_rng(5)
    for _ in range(200):
        g = random_polygon(rng)
        try:
            tri = cdt_plugin.triangulate(g, merge_distance=1e-8)
        except cdt_plugin.CDTError as e:
            with pytest.raises(type(e)):
                trimesh_adapter.triangulate_polygon(g)
            continue
        vertices, faces = trimesh_adapter.triangulate_polygon(g)
        used = np.unique(tri.triangles)
        np.testing.assert_array_equal(vertices, tri.vertices[used])
        np.testing.assert_array_equal(vertices[faces], tri.vertices[tri.triangles])


@pytest.mark.parametrize("coords, rings, starts", [
    ([[0, 0], [1, 0], [0, 1], [0, 0]], 1, [0, 3]),
    ([[0, 0], [4, 0], [0, 4], [0, 0], [1, 1], [2, 1], [1, 2], [1, 1]], 2, [0, 3, 6]),
    ([[0, 0], [4, 0], [0, 4], [0, 0], [1, 1], [2, 1], [1, 2], [1, 1]], 1, []),     # more rings than said
    ([[0, 0], [4, 0], [0, 4], [0, 0]], 2, []),                                     # fewer
    ([[0, 0], [4, 0], [0, 0]], 1, []),                                             # two points
    ([[0, 0], [4, 0], [4, 4], [0, 0], [0, 4], [-4, 4], [0, 0]], 1, []),            # back at its start
    ([[0, 0], [4, 0], [0, 4], [0, 1]], 1, []),                                     # not closed
    (np.zeros((0, 2)), 1, []),
])
def test_closed_rings(coords, rings, starts):
    xy, ring_start = closed_rings(np.array(coords, dtype=np.float64), np.int64(rings))
    assert ring_start.tolist() == starts
    if starts:
        closing = np.cumsum([0] + [b - a + 1 for a, b in zip(starts[:-1], starts[1:])])[1:] - 1
        np.testing.assert_array_equal(xy, np.delete(np.array(coords, float), closing, axis=0))
