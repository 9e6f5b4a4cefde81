"""The trimesh adapter against the real trimesh (and its own triangulation
engines, mapbox_earcut and manifold3d): same area and boundary, never a worse
minimum angle, watertight extrusions with exact volumes, Path2D read as trimesh
reads it."""
import doctest
import warnings

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
import cdt_plugin.adapters.trimesh as ct  # noqa: E402
from trimesh.path.entities import Arc, Line  # noqa: E402

from checker import assert_valid, canonical_triangles  # noqa: E402

# trimesh's own function, read before any test can register the hook
TRIMESH_TRIANGULATE = trimesh.creation.triangulate_polygon
assert not ct.is_registered()


@pytest.fixture(autouse=True)
def trimesh_left_unpatched():
    """Every test leaves trimesh as it found it: a leaked hook is undone and fails the test."""
    yield
    leaked = trimesh.creation.triangulate_polygon is not TRIMESH_TRIANGULATE
    if leaked:
        trimesh.creation.triangulate_polygon = TRIMESH_TRIANGULATE
    ct.unregister()
    assert not leaked, "a test left trimesh.creation.triangulate_polygon patched"


@pytest.fixture
def hooked():
    """engine="cdt_plugin" registered in trimesh for the test."""
    with ct.registered():
        yield


@pytest.fixture
def hooked_default():
    """cdt_plugin registered as trimesh's default engine for the test."""
    with ct.registered(default=True):
        yield


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


def _boundary_pairs(faces):
    """Directed edges (index pairs) of the faces that no other face shares."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    und = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(und, axis=0, return_inverse=True, return_counts=True)
    return directed[counts[inverse.ravel()] == 1]


def _boundary_edges(vertices, faces):
    once = _boundary_pairs(faces)
    return _edge_set(zip(vertices[once[:, 0]], vertices[once[:, 1]]))


# ------------------------------------------------------ triangulate_polygon
def test_docstring_examples():
    result = doctest.testmod(ct)
    assert result.attempted >= 20 and result.failed == 0


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


def test_extrude_merges_below_trimesh_merge_tolerance_before_meshing():
    # two shell vertices 1e-11 apart: merged before meshing by default (as trimesh
    # merges them), kept with merge_distance=0; watertight either way (built by index)
    polygon = shapely.Polygon([(0, 0), (1, 0), (1, 1), (0.5, 1.0 + 1e-11), (0.5 - 1e-11, 1.0), (0, 1)])
    kept = ct.extrude_polygon(polygon, 1.0, merge_distance=0)
    _check_solid(kept, polygon, 1.0)
    assert len(kept.vertices) == 2 * 6
    merged = ct.extrude_polygon(polygon, 1.0)
    _check_solid(merged, polygon, 1.0)
    assert len(merged.vertices) == 2 * 5


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


# ------------------------------------------- register(): trimesh's own functions
def _ring_segments(vertices, polygon):
    """The ring edges of ``polygon`` as index pairs into ``vertices`` (exact
    coordinates); a KeyError means an input vertex is missing from the mesh."""
    index = {tuple(p): k for k, p in enumerate(np.asarray(vertices)[:, :2].tolist())}
    segments = []
    for part in shapely.get_parts(polygon):
        for ring in [part.exterior, *part.interiors]:
            ids = [index[tuple(c)] for c in np.asarray(ring.coords)[:, :2].tolist()]
            segments += [(a, b) for a, b in zip(ids[:-1], ids[1:]) if a != b]
    return np.array(segments, dtype=np.int64)


def _assert_cdt_of(polygon, vertices, faces):
    """(vertices, faces) is the constrained Delaunay triangulation of ``polygon``:
    verified from scratch by the exact checker (every ring edge an edge, bounded by
    the rings, every other edge locally Delaunay) and the same triangles as
    cdt_plugin's own result."""
    vertices, faces = np.asarray(vertices, dtype=np.float64), np.asarray(faces)
    assert_valid(vertices, faces, segments=_ring_segments(vertices, polygon), domain="segments")
    ours = cdt_plugin.triangulate(polygon)
    assert canonical_triangles(vertices, faces) == canonical_triangles(ours.vertices, ours.triangles)


def _cap(mesh, z):
    """The faces of ``mesh`` lying in the plane ``z`` as a 2D triangulation,
    counter-clockwise seen from +z, with only the vertices they use."""
    on = np.abs(mesh.vertices[:, 2] - z) <= 1e-9
    faces = mesh.faces[on[mesh.faces].all(axis=1)]
    assert len(faces) and np.allclose(np.abs(mesh.face_normals[on[mesh.faces].all(axis=1), 2]), 1.0)
    used, faces = np.unique(faces, return_inverse=True)
    faces = faces.reshape(-1, 3)
    return _ccw(mesh.vertices[used, :2], faces)


def _ccw(vertices, faces):
    """The faces turned counter-clockwise where they are not."""
    faces = np.array(faces)
    clockwise = _areas(vertices, faces) < 0
    faces[clockwise] = faces[clockwise][:, ::-1]
    return vertices, faces


def _cap_polygon(vertices, faces):
    """The polygon (with holes) that the boundary edges of a 2D triangulation enclose."""
    edges = [list(edge) for edge in _boundary_edges(vertices, faces)]
    return shapely.build_area(shapely.MultiLineString(edges))


def _turned_back(vertices, polygon, tol=1e-9):
    """``vertices`` moved back onto ``polygon``'s vertices, exactly: sweep_polygon
    places the profile in a frame turned (or mirrored) by a multiple of 90 degrees
    and rounds; find that map, undo it and snap each vertex to the polygon vertex
    it came from."""
    coords = shapely.get_coordinates(polygon)
    for quarter in range(4):
        for mirror in (1.0, -1.0):
            c, s = np.rint(np.cos(quarter * np.pi / 2)), np.rint(np.sin(quarter * np.pi / 2))
            back = vertices @ np.array([[c, -s], [s, c]]) * [1.0, mirror]
            distance = np.linalg.norm(back[:, None, :] - coords[None, :, :], axis=2)
            if (distance.min(axis=1) <= tol).all():
                return coords[distance.argmin(axis=1)]
    raise AssertionError("the cap is not the polygon turned by a multiple of 90 degrees")


# trimesh's own extrusion merges wall vertices by tolerance: at a pinch vertex (a hole
# touching its shell) its solid is not watertight whatever the engine (see
# test_extrude_pinch_vertex_stays_watertight for ours)
MANIFOLD_POLYGONS = [name for name in POLYGONS if name != "hole_touches_shell"]
# a polygon with no four cocircular vertices: its CDT is unique, also after trimesh
# rotates a slice into its own 2D frame
IRREGULAR = shapely.Polygon([(0, 0), (7.3, 0.4), (9.1, 5.2), (4.4, 8.7), (1.2, 6.1), (2.5, 3.3)],
                            [[(3.1, 2.2), (5.9, 2.9), (4.8, 5.1)]])


@pytest.mark.parametrize("name", list(POLYGONS))
def test_hook_engine_name_in_trimesh_triangulate_polygon(hooked, name):
    polygon = POLYGONS[name]
    vertices, faces = trimesh.creation.triangulate_polygon(polygon, engine=ct.ENGINE)
    assert vertices.shape[1] == 2 and faces.dtype == np.int64
    _assert_cdt_of(polygon, vertices, faces)


@pytest.mark.parametrize("name", MANIFOLD_POLYGONS)
def test_hook_trimesh_extrude_polygon_is_watertight_with_our_caps(hooked, name):
    polygon, height = POLYGONS[name], 2.5
    mesh = trimesh.creation.extrude_polygon(polygon, height, engine=ct.ENGINE)
    _check_solid(mesh, polygon, height)
    _check_outward(mesh, polygon)
    _assert_cdt_of(polygon, *_cap(mesh, height))
    _assert_cdt_of(polygon, *_cap(mesh, 0.0))


def test_hook_keywords_reach_the_engine(hooked):
    polygon = POLYGONS["letter_a"]
    # Triangle's switches and cdt_plugin.triangulate keywords, through trimesh
    v, f = trimesh.creation.triangulate_polygon(polygon, engine=ct.ENGINE, triangle_args="pq30a0.5")
    assert np.isclose(_areas(v, f).sum(), polygon.area, rtol=1e-12) and _areas(v, f).max() <= 0.5
    assert _min_angle(v, f) >= 30 * (1 - 1e-9)
    assert_valid(v, f, segments=_boundary_pairs(f), domain="segments")    # refined: pieces of the rings
    with pytest.raises(cdt_plugin.CDTError, match="intersections"):
        trimesh.creation.triangulate_polygon(polygon, engine=ct.ENGINE, intersections="bogus")
    with pytest.raises(ValueError, match="force_vertices"):
        trimesh.creation.triangulate_polygon(polygon, engine=ct.ENGINE, min_angle=30,
                                             force_vertices=True)
    mesh = trimesh.creation.extrude_polygon(polygon, 1.0, engine=ct.ENGINE, max_area=0.5)
    _check_solid(mesh, polygon, 1.0)
    assert _areas(*_cap(mesh, 1.0)).max() <= 0.5


def test_hook_sweep_polygon(hooked):
    polygon = IRREGULAR
    path = [[0, 0, 0], [0, 0, 1.5], [0, 0, 3.0]]           # straight: volume area * 3
    mesh = trimesh.creation.sweep_polygon(polygon, path, engine=ct.ENGINE)
    _check_solid(mesh, polygon, 3.0)
    for z in (0.0, 3.0):
        vertices, faces = _cap(mesh, z)
        _assert_cdt_of(polygon, *_ccw(_turned_back(vertices, polygon), faces))


def test_hook_path2d_triangulate(hooked, needs_rtree):
    two = shapely.MultiPolygon([POLYGONS["letter_a"],
                                shapely.affinity.translate(POLYGONS["square_two_holes"], xoff=10)])
    path = trimesh.load_path(two)
    vertices, faces = path.triangulate(engine=ct.ENGINE)
    _assert_cdt_of(two, vertices, faces)


def test_hook_default_path2d_extrude(hooked_default, needs_rtree):
    # Path2D.extrude passes no engine (its keywords go to the Extrusion primitive):
    # only the default reaches it
    polygon = POLYGONS["letter_a"]
    extrusion = trimesh.load_path(polygon).extrude(2.0)
    assert isinstance(extrusion, trimesh.primitives.Extrusion)
    _check_solid(extrusion, polygon, 2.0)                 # the mesh is made here, hook in force
    _assert_cdt_of(polygon, *_cap(extrusion, 2.0))


@pytest.mark.parametrize("name", ["letter_a", "irregular"])
def test_hook_slice_plane_cap(hooked, name):
    polygon = IRREGULAR if name == "irregular" else POLYGONS[name]
    solid = ct.extrude_polygon(polygon, 4.0)
    upper = solid.slice_plane([0, 0, 1.0], [0, 0, 1.0], cap=True, engine=ct.ENGINE)
    _check_solid(upper, polygon, 3.0)
    # the plane also cuts the diagonals of the wall quads: the cap's boundary has the
    # polygon's vertices plus one (rounded) point on each ring edge
    vertices, faces = _cap(upper, 1.0)
    section = _cap_polygon(vertices, faces)
    assert np.isclose(section.area, polygon.area, rtol=1e-12)
    assert set(map(tuple, shapely.get_coordinates(polygon))) <= set(map(tuple, vertices.tolist()))
    if name == "irregular":     # no near-ties: exactly cdt_plugin's CDT of the section
        _assert_cdt_of(section, vertices, faces)
    else:                       # cocircular vertices: a valid CDT, ties broken either way
        assert_valid(vertices, faces, segments=_ring_segments(vertices, section), domain="segments")


def test_hook_default_engine_and_other_engines(hooked_default):
    pytest.importorskip("mapbox_earcut")
    polygon = IRREGULAR
    _assert_cdt_of(polygon, *trimesh.creation.triangulate_polygon(polygon))
    # a named engine still goes to trimesh's own function, with the same result
    v, f = trimesh.creation.triangulate_polygon(polygon, engine="earcut")
    v0, f0 = TRIMESH_TRIANGULATE(polygon, engine="earcut")
    assert np.array_equal(v, v0) and np.array_equal(f, f0)
    earcut = canonical_triangles(v, f)
    ours = cdt_plugin.triangulate(polygon)
    assert earcut != canonical_triangles(ours.vertices, ours.triangles)   # the test can tell them apart
    mesh = trimesh.creation.extrude_polygon(polygon, 1.0, engine="earcut")
    _check_solid(mesh, polygon, 1.0)
    assert canonical_triangles(*_cap(mesh, 1.0)) == earcut


def test_hook_without_default_leaves_trimesh_default(hooked):
    pytest.importorskip("mapbox_earcut")
    polygon = IRREGULAR
    v, f = trimesh.creation.triangulate_polygon(polygon)          # trimesh picks its own engine
    v0, f0 = TRIMESH_TRIANGULATE(polygon)
    assert np.array_equal(v, v0) and np.array_equal(f, f0)


def test_register_is_idempotent_and_unregister_restores_trimesh():
    ct.register()
    hook = trimesh.creation.triangulate_polygon
    assert hook is not TRIMESH_TRIANGULATE and ct.is_registered()
    ct.register()                                   # no second wrapper
    assert trimesh.creation.triangulate_polygon is hook
    ct.register(default=True)                       # only the default changes
    assert trimesh.creation.triangulate_polygon is hook
    _assert_cdt_of(IRREGULAR, *trimesh.creation.triangulate_polygon(IRREGULAR))
    ct.unregister()
    assert trimesh.creation.triangulate_polygon is TRIMESH_TRIANGULATE
    assert not ct.is_registered()
    ct.unregister()                                 # a no-op when not registered
    assert trimesh.creation.triangulate_polygon is TRIMESH_TRIANGULATE
    # trimesh no longer knows the engine name
    with pytest.raises(ValueError, match="No available triangulation engine"):
        trimesh.creation.triangulate_polygon(IRREGULAR, engine=ct.ENGINE)


def test_register_validates_default_before_patching():
    with pytest.raises(cdt_plugin.CDTError, match="default must be True or False, got 'yes'"):
        ct.register(default="yes")
    assert trimesh.creation.triangulate_polygon is TRIMESH_TRIANGULATE


def test_registered_context_restores_the_state_before_it():
    with pytest.raises(RuntimeError):
        with ct.registered(default=True):
            assert ct.is_registered()
            raise RuntimeError("boom")
    assert trimesh.creation.triangulate_polygon is TRIMESH_TRIANGULATE
    with ct.registered():
        with ct.registered(default=True):
            _assert_cdt_of(IRREGULAR, *trimesh.creation.triangulate_polygon(IRREGULAR))
        assert ct.is_registered()                   # the outer registration stays...
        pytest.importorskip("mapbox_earcut")
        v, f = trimesh.creation.triangulate_polygon(IRREGULAR)
        assert np.array_equal(f, TRIMESH_TRIANGULATE(IRREGULAR)[1])   # ...without the default
    assert trimesh.creation.triangulate_polygon is TRIMESH_TRIANGULATE


def test_hook_polygon_with_z_warns_that_z_is_dropped(hooked):
    polygon = shapely.Polygon([(0, 0, 5), (4, 0, 5), (4, 3, 5), (0, 3, 5)])
    with pytest.warns(ct.DroppedZWarning, match="z is dropped"):
        vertices, faces = trimesh.creation.triangulate_polygon(polygon, engine=ct.ENGINE)
    assert vertices.shape == (4, 2)
    _assert_cdt_of(shapely.force_2d(polygon), vertices, faces)
    with warnings.catch_warnings():
        warnings.simplefilter("error")              # a 2D polygon: no warning
        trimesh.creation.triangulate_polygon(shapely.force_2d(polygon), engine=ct.ENGINE)


def test_hook_default_revolve_cap(hooked_default):
    # revolve(cap=True) triangulates its profile with no engine named: the default's route
    profile = np.array([[1.0, 0.0], [2.3, 0.2], [2.1, 1.1], [1.6, 1.9], [1.2, 1.3], [1.0, 0.0]])
    mesh = trimesh.creation.revolve(profile, angle=np.pi / 2, cap=True)     # a closed profile
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    start = np.abs(mesh.vertices[:, 1]) == 0.0                   # the cap at angle 0: the xz plane
    faces = mesh.faces[start[mesh.faces].all(axis=1)]
    used, faces = np.unique(faces, return_inverse=True)
    vertices = mesh.vertices[used][:, [0, 2]]
    _assert_cdt_of(shapely.Polygon(profile), *_ccw(vertices, faces.reshape(-1, 3)))
