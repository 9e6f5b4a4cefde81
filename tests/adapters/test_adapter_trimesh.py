"""The trimesh adapter against the real trimesh (and its own triangulation
engines, mapbox_earcut and manifold3d): same area and boundary, never a worse
minimum angle, watertight extrusions with exact volumes, Path2D read as trimesh
reads it."""
import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
import cdt_plugin.adapters.trimesh as ct  # noqa: E402
from trimesh.path.entities import Arc, Line  # noqa: E402

from checker import assert_valid  # noqa: E402


# ---------------------------------------------------------------- polygons
def _letter_a():
    """A capital "A": an outline with a triangular counter (hole)."""
    shell = [(0, 0), (1.2, 0), (1.75, 1.6), (4.25, 1.6), (4.8, 0), (6, 0), (3.6, 7), (2.4, 7)]
    hole = [(2.2, 2.8), (3.8, 2.8), (3.0, 5.4)]
    return shapely.Polygon(shell, [hole])


def _letter_e():
    """A comb-shaped "E" (non-convex, no hole)."""
    return shapely.Polygon([(0, 0), (5, 0), (5, 1), (1.2, 1), (1.2, 2.5), (4, 2.5), (4, 3.5),
                            (1.2, 3.5), (1.2, 5), (5, 5), (5, 6), (0, 6)])


POLYGONS = {
    "square_two_holes": shapely.Polygon([(0, 0), (10, 0), (10, 10), (0, 10)],
                                        [[(1, 1), (3, 1), (3, 3), (1, 3)],
                                         [(6, 6), (8, 6), (8, 9), (6, 8.5)]]),
    "letter_a": _letter_a(),
    "letter_e": _letter_e(),
    "circle_two_holes": shapely.Point(0, 0).buffer(5)
                               .difference(shapely.Point(2, 0).buffer(1))
                               .difference(shapely.Point(-2, 1).buffer(1.2)),
    "offset_circle": shapely.Point(500_000.0, 4_649_776.0).buffer(30.0, quad_segs=32),
    # a hole touching the shell at one vertex (valid for shapely)
    "hole_touches_shell": shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                                          [[(0, 0), (2, 1), (1, 2)]]),
}
PEER_ENGINES = ["earcut", "manifold"]


def _areas(vertices, faces):
    a, b, c = (np.asarray(vertices, float)[np.asarray(faces)[:, k]] for k in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _min_angle(vertices, faces):
    """Smallest interior angle in degrees (0 for a degenerate triangle)."""
    p = np.asarray(vertices, float)[np.asarray(faces)]
    worst = np.inf
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        w = p[:, (k + 2) % 3] - p[:, k]
        nu, nw = np.linalg.norm(u, axis=1), np.linalg.norm(w, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = np.einsum("ij,ij->i", u, w) / (nu * nw)
        ang = np.degrees(np.arccos(np.clip(np.nan_to_num(cos, nan=1.0), -1, 1)))
        worst = min(worst, float(ang.min()))
    return worst


def _edge_set(pairs):
    """Undirected edges as frozensets of coordinate tuples (exact)."""
    return {frozenset((tuple(a), tuple(b))) for a, b in pairs}


def _ring_edges(polygon):
    edges = []
    for ring in [polygon.exterior, *polygon.interiors]:
        c = np.asarray(ring.coords)[:, :2]
        edges.extend(zip(c[:-1], c[1:]))
    return _edge_set(edges)


def _boundary_edges(vertices, faces):
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    und = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(und, axis=0, return_inverse=True, return_counts=True)
    once = directed[counts[inverse.ravel()] == 1]
    return _edge_set(zip(vertices[once[:, 0]], vertices[once[:, 1]]))


# ------------------------------------------------------ triangulate_polygon
@pytest.mark.parametrize("name", list(POLYGONS))
def test_triangulate_polygon_matches_polygon(name):
    polygon = POLYGONS[name]
    assert polygon.is_valid
    vertices, faces = ct.triangulate_polygon(polygon)
    assert vertices.dtype == np.float64 and vertices.shape[1] == 2
    assert faces.dtype == np.int64 and faces.shape[1] == 3
    # only referenced vertices (trimesh's convention), no repeated closing point
    assert np.array_equal(np.unique(faces), np.arange(len(vertices)))
    assert len(np.unique(vertices, axis=0)) == len(vertices)
    # counter-clockwise, same area, exactly the polygon's boundary
    areas = _areas(vertices, faces)
    assert (areas > 0).all()
    assert np.isclose(areas.sum(), polygon.area, rtol=1e-12, atol=0)
    assert _boundary_edges(vertices, faces) == _ring_edges(polygon)
    union = shapely.union_all([shapely.Polygon(t) for t in vertices[faces]])
    assert union.symmetric_difference(polygon).area <= 1e-9 * polygon.area


@pytest.mark.parametrize("engine", PEER_ENGINES)
@pytest.mark.parametrize("name", list(POLYGONS))
def test_triangulate_polygon_against_trimesh_engines(name, engine):
    pytest.importorskip({"earcut": "mapbox_earcut", "manifold": "manifold3d"}[engine])
    polygon = POLYGONS[name]
    vertices, faces = ct.triangulate_polygon(polygon)
    their_v, their_f = trimesh.creation.triangulate_polygon(polygon, engine=engine)
    their_v, their_f = np.asarray(their_v, float), np.asarray(their_f)
    ours_area = _areas(vertices, faces).sum()
    assert np.isclose(ours_area, np.abs(_areas(their_v, their_f)).sum(), rtol=1e-9)
    # a constrained Delaunay triangulation maximises the minimum angle over
    # all triangulations of the same vertices and segments
    assert _min_angle(vertices, faces) >= _min_angle(their_v, their_f) - 1e-9
    assert len(faces) <= len(their_f)


def test_triangulate_polygon_is_constrained_delaunay():
    polygon = POLYGONS["circle_two_holes"]
    tri = cdt_plugin.triangulate(polygon)
    assert tri.is_delaunay()
    vertices, faces = ct.triangulate_polygon(polygon)
    assert len(faces) == len(tri.triangles)


def test_triangulate_polygon_empty_and_multipolygon():
    v, f = ct.triangulate_polygon(shapely.Polygon())
    assert v.shape == (0, 2) and f.shape == (0, 3)
    two = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 2)])
    v, f = ct.triangulate_polygon(two)
    assert np.isclose(_areas(v, f).sum(), 3.0)
    assert len(v) == 8


def test_triangulate_polygon_keywords():
    polygon = POLYGONS["letter_a"]
    # Triangle's switches are translated: quality meshing with angle and area bounds
    v, f = ct.triangulate_polygon(polygon, triangle_args="pq30a0.5")
    assert np.isclose(_areas(v, f).sum(), polygon.area)
    assert _areas(v, f).max() <= 0.5
    P = v[f]
    for j in range(3):
        u, w = P[:, (j + 1) % 3] - P[:, j], P[:, (j + 2) % 3] - P[:, j]
        ang = np.degrees(np.arctan2(np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]), (u * w).sum(1)))
        assert ang.min() >= 30 * (1 - 1e-9)
    with pytest.raises(ValueError, match="force_vertices"):
        ct.triangulate_polygon(polygon, triangle_args="pq30", force_vertices=True)
    with pytest.raises(cdt_plugin.CDTError, match="'r'"):
        ct.triangulate_polygon(polygon, triangle_args="pr")
    # engine= is accepted (trimesh's signature) and ignored
    v, f = ct.triangulate_polygon(polygon, engine="earcut", force_vertices=True)
    assert np.isclose(_areas(v, f).sum(), polygon.area)
    # other keywords reach cdt_plugin.triangulate
    with pytest.raises(cdt_plugin.CDTError, match="intersections"):
        ct.triangulate_polygon(polygon, intersections="bogus")
    # a bow-tie is rejected, or split with intersections="split"
    bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    with pytest.raises(cdt_plugin.SegmentIntersectionError):
        ct.triangulate_polygon(bowtie)
    v, f = ct.triangulate_polygon(bowtie, intersections="split")
    assert np.isclose(_areas(v, f).sum(), 2.0)
    with pytest.raises(ValueError, match="force_vertices"):
        ct.triangulate_polygon(bowtie, intersections="split", force_vertices=True)


# ------------------------------------------------------------- extrusion
def _check_solid(mesh, polygon, height):
    assert mesh.is_watertight
    assert mesh.is_winding_consistent
    assert mesh.is_volume
    assert mesh.volume > 0
    assert np.isclose(mesh.volume, polygon.area * abs(height), rtol=1e-9, atol=0)


def _check_outward(mesh, polygon):
    """Caps face +z/-z; each wall faces away from the polygon."""
    normals = mesh.face_normals
    centers = mesh.triangles_center
    zmin, zmax = mesh.bounds[:, 2]
    top = np.isclose(centers[:, 2], zmax) & np.isclose(normals[:, 2], 1.0)
    bottom = np.isclose(centers[:, 2], zmin) & np.isclose(normals[:, 2], -1.0)
    walls = np.abs(normals[:, 2]) < 1e-12
    assert (top | bottom | walls).all()
    assert top.any() and bottom.any() and walls.any()
    step = 1e-6 * max(np.ptp(mesh.bounds[:, 0]), np.ptp(mesh.bounds[:, 1]))
    outside = centers[walls, :2] + step * normals[walls, :2]
    inside = centers[walls, :2] - step * normals[walls, :2]
    assert not shapely.contains_xy(polygon, outside[:, 0], outside[:, 1]).any()
    assert shapely.contains_xy(polygon, inside[:, 0], inside[:, 1]).all()


@pytest.mark.parametrize("name", list(POLYGONS))
def test_extrude_polygon_watertight_exact_volume(name):
    polygon = POLYGONS[name]
    height = 2.5
    mesh = ct.extrude_polygon(polygon, height)
    assert isinstance(mesh, trimesh.Trimesh)
    _check_solid(mesh, polygon, height)
    _check_outward(mesh, polygon)
    assert np.isclose(mesh.bounds[0, 2], 0.0) and np.isclose(mesh.bounds[1, 2], height)


@pytest.mark.parametrize("name", ["letter_a", "circle_two_holes"])
def test_extrude_polygon_same_volume_as_trimesh(name):
    pytest.importorskip("mapbox_earcut")
    polygon = POLYGONS[name]
    ours = ct.extrude_polygon(polygon, 3.0)
    theirs = trimesh.creation.extrude_polygon(polygon, 3.0, engine="earcut")
    assert np.isclose(ours.volume, theirs.volume, rtol=1e-9)
    assert np.allclose(ours.bounds, theirs.bounds)


def test_extrude_pinch_vertex_stays_watertight():
    # trimesh's own extrusion of this (valid) polygon has a vertical edge in four faces
    polygon = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                              [[(2, 0), (3, 1), (1, 1)], [(2, 4), (1, 3), (3, 3)],
                               [(1, 1), (1.5, 2), (1, 2.5)]])
    assert polygon.is_valid
    mesh = ct.extrude_polygon(polygon, 1.0)
    _check_solid(mesh, polygon, 1.0)
    _check_outward(mesh, polygon)


def test_extrude_negative_height_mid_plane_and_transform():
    polygon = POLYGONS["letter_a"]
    down = ct.extrude_polygon(polygon, -2.0)
    _check_solid(down, polygon, -2.0)
    assert np.allclose(down.bounds[:, 2], [-2.0, 0.0])
    mid = ct.extrude_polygon(polygon, 2.0, mid_plane=True)
    _check_solid(mid, polygon, 2.0)
    assert np.allclose(mid.bounds[:, 2], [-1.0, 1.0])
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])            # flips winding: faces are flipped back
    mirrored = ct.extrude_polygon(polygon, 2.0, transform=mirror)
    _check_solid(mirrored, polygon, 2.0)
    assert np.allclose(mirrored.bounds[:, 0], -np.asarray(polygon.bounds)[2::-2])


def test_extrude_keeps_vertices_closer_than_trimesh_merge_tolerance():
    # two shell vertices 1e-11 apart: a tolerance merge would collapse them
    polygon = shapely.Polygon([(0, 0), (1, 0), (1, 1), (0.5, 1.0 + 1e-11), (0.5 - 1e-11, 1.0), (0, 1)])
    mesh = ct.extrude_polygon(polygon, 1.0)
    _check_solid(mesh, polygon, 1.0)
    assert len(mesh.vertices) == 2 * 6


def test_extrude_triangulation_either_winding():
    polygon = POLYGONS["letter_e"]
    v, f = ct.triangulate_polygon(polygon)
    for faces in (f, f[:, ::-1]):
        mesh = ct.extrude_triangulation(v, faces, 1.5)
        _check_solid(mesh, polygon, 1.5)
    with pytest.raises(ValueError):
        ct.extrude_triangulation(v, f, 0.0)


# -------------------------------------------------------------- to_trimesh
def test_to_trimesh_flat_keeps_unreferenced_vertices():
    square = [[0, 0], [4, 0], [4, 4], [0, 4], [9, 9]]      # (9, 9) lies outside the domain
    tri = cdt_plugin.triangulate(square, [[0, 1], [1, 2], [2, 3], [3, 0]])
    mesh = ct.to_trimesh(tri, z=1.5)
    assert len(mesh.vertices) == len(tri.vertices) == 5
    assert np.array_equal(mesh.faces, tri.triangles)
    assert np.allclose(mesh.vertices[:, :2], tri.vertices)
    assert np.allclose(mesh.vertices[:, 2], 1.5)
    assert np.allclose(mesh.face_normals, [0, 0, 1])
    assert np.isclose(mesh.area, 16.0)
    compact = ct.to_trimesh(tri, remove_unreferenced=True)
    assert len(compact.vertices) == 4 and np.isclose(compact.area, 16.0)
    assert np.allclose(compact.face_normals, [0, 0, 1])
    # the engine's lazy output method goes through this adapter
    same = tri.to_trimesh(z=1.5)
    assert np.array_equal(same.faces, mesh.faces) and np.allclose(same.vertices, mesh.vertices)


# ------------------------------------------------------------------ Path2D
@pytest.fixture
def needs_rtree():
    # Path2D.polygons_full builds its enclosure tree with rtree
    pytest.importorskip("rtree")


def test_from_path2d_polygon_with_hole(needs_rtree):
    polygon = POLYGONS["square_two_holes"]
    path = trimesh.load_path(polygon)
    plc = ct.from_path2d(path)
    assert isinstance(plc, cdt_plugin.PLC)
    assert plc.ring_is_hole.tolist() == [False, True, True]
    assert len(plc.segments) == 12 and (plc.segment_ring >= 0).all()
    tri = cdt_plugin.triangulate(plc)
    assert np.isclose(_areas(tri.vertices, tri.triangles).sum(), polygon.area)
    assert tri.is_delaunay()
    meshes = ct.extrude_path(path, 2.0)
    assert len(meshes) == 1
    _check_solid(meshes[0], polygon, 2.0)


def _arc_path():
    """A square with a circular hole (closed Arc) and, inside, an open arc and a line."""
    vertices = np.array([[0, 0], [10, 0], [10, 10], [0, 10],           # shell
                         [6, 7], [7, 8], [8, 7],                         # closed arc: hole
                         [1, 2], [2.5, 3.5], [4, 2],                     # open arc
                         [1, 6], [3, 8]], float)                         # open line
    entities = [Line([0, 1, 2, 3, 0]), Arc([4, 5, 6], closed=True),
                Arc([7, 8, 9], closed=False), Line([10, 11])]
    return trimesh.path.Path2D(entities=entities, vertices=vertices)


def test_from_path2d_arcs_discretised_as_trimesh_does(needs_rtree):
    path = _arc_path()
    assert path.dangling.tolist() == [2, 3]
    polygon = path.polygons_full[0]
    assert len(polygon.interiors) == 1
    plc = ct.from_path2d(path)
    assert plc.ring_is_hole.tolist() == [False, True]
    # the rings are trimesh's rings, point for point
    ring_vertices = plc.vertices[plc.segments[plc.segment_ring >= 0].ravel()]
    ring_coords = np.concatenate([np.asarray(polygon.exterior.coords),
                                  np.asarray(polygon.interiors[0].coords)])
    assert _edge_set(zip(ring_vertices[::2], ring_vertices[1::2])) == _ring_edges(polygon)
    assert {tuple(p) for p in ring_vertices} == {tuple(p) for p in ring_coords}
    # open entities: constraint chains of exactly entity.discrete(...)
    arc_points = path.entities[2].discrete(path.vertices, scale=path.scale)
    assert len(arc_points) > 3                                  # really discretised
    free = plc.segments[plc.segment_ring < 0]
    assert len(free) == (len(arc_points) - 1) + 1
    tri = cdt_plugin.triangulate(plc)
    edges = _edge_set(zip(tri.vertices[tri.edges[:, 0]], tri.vertices[tri.edges[:, 1]]))
    assert _edge_set(zip(arc_points[:-1], arc_points[1:])) <= edges
    assert _edge_set([([1, 6], [3, 8])]) <= edges
    # open constraints split no area off: the domain is trimesh's polygon
    assert np.isclose(_areas(tri.vertices, tri.triangles).sum(), polygon.area, rtol=1e-12)
    assert tri.is_delaunay()


def test_from_path2d_open_entities_only():
    path = trimesh.path.Path2D(entities=[Line([0, 1, 2]), Line([3, 4])],
                               vertices=np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 3.0]]))
    plc = ct.from_path2d(path)
    assert len(plc.segments) == 3 and (plc.segment_ring < 0).all()
    tri = cdt_plugin.triangulate(plc)          # open lines enclose nothing (even-odd depth)
    assert len(tri.triangles) == 0 and len(tri.segments) == 0    # no piece borders a triangle
    tri = cdt_plugin.triangulate(plc, keep_hull=True)
    assert len(tri.triangles) == 3 and len(tri.segments) == 3
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="hull")
    with pytest.raises(TypeError):
        ct.from_path2d(POLYGONS["letter_a"])


def test_extrude_path_every_polygon(needs_rtree):
    two = shapely.MultiPolygon([POLYGONS["letter_a"],
                                shapely.affinity.translate(POLYGONS["letter_e"], xoff=10)])
    path = trimesh.load_path(two)
    meshes = ct.extrude_path(path, 1.0)
    assert len(meshes) == 2
    assert sorted(m.volume for m in meshes) == pytest.approx(sorted(p.area for p in two.geoms), rel=1e-9)
    assert all(m.is_watertight and m.is_winding_consistent for m in meshes)
