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
from cdt_plugin._core.plain import EAR_RING_MAX, PLAIN_DONE, ear_route  # noqa: E402
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


def same_triangles(a, b):
    """The same triangles, each from its smallest vertex (the engine's rotation), in any order."""
    return sorted(map(tuple, np.asarray(a).tolist())) == sorted(map(tuple, np.asarray(b).tolist()))


def same_members(a, b):
    """Collections of the same Polygons, bit for bit, in any order."""
    return sorted(shapely.to_wkb(np.asarray(a.geoms))) == sorted(shapely.to_wkb(np.asarray(b.geoms)))


def test_it_takes_what_the_general_rule_takes_and_gives_its_very_mesh():
    """600 random polygons valid or invalid by a hair (holes touching, crossing,
    outside, nested, repeated points) at five magnitudes: the plain path
    meshes a polygon exactly when the general rule (``mesh_if_plainly_valid``,
    which trusts the engine's mesh instead of GEOS's check) does, only polygons
    valid at unit scale (decided exactly), most of the valid ones, with the
    same vertices, triangles and WKB; every mesh passes the exact checker."""
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
            assert same_triangles(triangles, tri.triangles)
            assert same_members(plain_triangles(h), to_shapely(tri))
            segments = tri.segments if k == 0 and offset == 0 else None
            if segments is not None:
                assert_valid(vertices, triangles, segments=segments, domain="segments")
    assert valid_count > 100 and taken > 0.5 * valid_count


def rings_without_holes():
    """Rings that the ear route takes or must refuse: ties everywhere (integer
    grids, exactly cocircular points, straight angles), combs and spirals whose
    ears are few, random stars up to its size limit, and rings that touch or
    cross themselves."""
    rng = np.random.default_rng(17)
    circle = [(5, 0), (4, 3), (3, 4), (0, 5), (-3, 4), (-4, 3), (-5, 0), (-4, -3), (-3, -4), (0, -5),
              (3, -4), (4, -3)]                                          # exactly cocircular
    yield circle
    yield [p for k, p in enumerate(circle) if k % 3] + [(0, 0)]         # with a reflex corner at the centre
    yield [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2), (2, 2), (1, 2), (0, 2), (0, 1)]  # straight angles
    yield [(0, 0), (6, 0), (6, 1), (5, 1), (5, 4), (4, 4), (4, 1), (3, 1), (3, 4), (2, 4), (2, 1), (1, 1),
           (1, 4), (0, 4)]                                                                     # a comb
    t = np.linspace(0, 5 * np.pi, 40)
    outer = np.column_stack([(t + 2) * np.cos(t), (t + 2) * np.sin(t)])
    inner = np.column_stack([(t + 1) * np.cos(t), (t + 1) * np.sin(t)])[::-1]
    yield np.vstack([outer, inner]).tolist()                                                   # a spiral
    for _ in range(150):
        n = int(rng.integers(3, 130))
        a = np.sort(rng.choice(720, n, replace=False)) * np.pi / 360
        r = rng.integers(1, 6, n) * (4 if rng.random() < 0.5 else 1.0 + rng.random(n))
        yield np.round(np.column_stack([r * np.cos(a), r * np.sin(a)]), int(rng.integers(0, 3))).tolist()
    for _ in range(50):                                                     # crossing, touching, repeating
        yield rng.integers(0, 5, (int(rng.integers(3, 9)), 2)).tolist()


def test_the_ear_route_gives_the_constrained_delaunay_triangulation():
    """Polygons without holes take the ear route (cut into ears, then flipped):
    the same verdict and the same triangles as the general route at every
    magnitude, each mesh passing the exact checker."""
    taken = 0
    for ring in rings_without_holes():
        try:
            g = shapely.Polygon(ring)
        except Exception:      # (GEOS refuses a ring of too few points)
            continue
        for k, offset in SCALES:
            h = moved(g, k, offset)
            tri = mesh_if_plainly_valid(h)
            plain = plain_mesh(h)
            assert (plain is None) == (tri is None), (ring, k, offset)
            if plain is None:
                continue
            taken += 1
            assert same_triangles(plain[1], tri.triangles), (ring, k, offset)
            if k == 0 and offset == 0:
                assert_valid(plain[0], plain[1], segments=tri.segments, domain="segments")
                if len(plain[0]) <= EAR_RING_MAX:       # (taken by the ear route itself)
                    status, triangles = ear_route(plain[0][:, 0].copy(), plain[0][:, 1].copy())
                    assert status == PLAIN_DONE and same_triangles(triangles, tri.triangles)
    assert taken > 400


@pytest.mark.parametrize("holes", [0, 2, 4])
@pytest.mark.parametrize("k", [0, -1000, 1000])
def test_stars_at_every_magnitude(holes, k):
    g = moved(star(60, holes), k, 0.0)
    vertices, triangles = plain_mesh(g)
    assert len(triangles) == 60 + 8 * holes + 2 * holes - 2
    tri = cdt_plugin.triangulate(g)
    assert same_triangles(triangles, tri.triangles)
    np.testing.assert_array_equal(vertices, tri.vertices)
    assert_valid(np.ldexp(vertices, -k), triangles, segments=tri.segments, domain="segments")
    assert same_members(constrained_delaunay_triangles(g), to_shapely(tri))


@pytest.mark.parametrize("wkt", [
    "POLYGON Z ((0 0 1, 1 0 1, 1 1 1, 0 0 1))",                                # Z: the general path keeps it
    "MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)))",
    "POLYGON EMPTY",
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


def test_an_empty_hole_is_dropped_as_the_general_path_drops_it():
    g = shapely.from_wkt("POLYGON ((0 0, 4 0, 3 3, 0 4, 0 0), EMPTY)")
    vertices, triangles = plain_mesh(g)
    tri = cdt_plugin.triangulate(g)
    assert tri.stats["empty_rings"] == [(0, 1)]
    np.testing.assert_array_equal(vertices, tri.vertices)
    assert same_triangles(triangles, tri.triangles)
    assert same_members(constrained_delaunay_triangles(g), to_shapely(tri))


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
        assert same_triangles(used[faces], tri.triangles)


@pytest.mark.parametrize("coords, starts", [
    ([[0, 0], [1, 0], [0, 1], [0, 0]], [0, 3]),
    ([[0, 0], [4, 0], [0, 4], [0, 0], [1, 1], [2, 1], [1, 2], [1, 1]], [0, 3, 6]),
    ([[0, 0], [4, 0], [4, 4], [0, 0], [0, 4], [-4, 4], [0, 0]], []),          # back at its start: the rest
    ([[0, 0], [4, 0], [4, 4], [0, 0], [0, 0], [0, 4], [-4, 4], [0, 0]], [0, 3, 6]),  # does not close
    ([[0, 0], [4, 0], [0, 0]], []),                                            # two points
    ([[0, 0], [4, 0], [0, 4], [0, 0], [1, 1], [1, 1]], []),                    # a ring of one point
    ([[0, 0], [4, 0], [0, 4], [0, 1]], []),                                    # not closed
    (np.zeros((0, 2)), []),
])
def test_closed_rings(coords, starts):
    xy, ring_start = closed_rings(np.array(coords, dtype=np.float64))
    assert ring_start.tolist() == starts
    if starts:
        closing = np.cumsum([0] + [b - a + 1 for a, b in zip(starts[:-1], starts[1:])])[1:] - 1
        np.testing.assert_array_equal(xy, np.delete(np.array(coords, float), closing, axis=0))


def test_its_options_are_triangulates_defaults():
    from cdt_plugin._core.plain import DEFAULTS
    from cdt_plugin.options import MeshOptions
    assert DEFAULTS == MeshOptions.check().route_args()
