"""Planar polygons in any plane (cdt_plugin.planar): 3D input meshed in its plane."""
import numpy as np
import pytest

import cdt_plugin
from cdt_plugin.planar import Plane, fit_plane

from checker import assert_valid

SQUARE = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3],
                   [3.5, 0.5], [0.5, 3.5], [3.6, 2.2]], float)       # a square hole, then points
RINGS = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])


def _rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def _check_in_plane(tri, P, max_area=None):
    """Input vertices exactly P, every vertex within rounding of the plane, and the
    exact checker on the 2D coordinates the mesh was made in."""
    V = tri.vertices3d
    assert np.array_equal(V[tri.vertex_map], P)
    scale = np.abs(P).max()
    assert np.abs(tri.plane.distances(V)).max() <= 64 * np.finfo(float).eps * scale
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments",
                 **({} if max_area is None else {"max_area": max_area}))
    assert np.array_equal(tri.vertices, V[:, list(tri.plane.axes[:2])])


@pytest.mark.parametrize("seed", range(12))
def test_polygon_with_hole_in_a_random_plane(seed):
    rng = np.random.default_rng(seed)
    R, shift = _rotation(rng), rng.normal(size=3) * 10 ** rng.integers(0, 4)
    P = np.column_stack([SQUARE, np.zeros(len(SQUARE))]) @ R.T + shift
    tri = cdt_plugin.triangulate(P, RINGS, max_area=0.2)
    _check_in_plane(tri, P)
    # the normal is the rotated +z (up to sign), the mesh the 2D one of its projection
    assert abs(abs(tri.plane.normal @ R[:, 2]) - 1) < 1e-12
    flat = cdt_plugin.triangulate(tri.vertices[:len(P)], RINGS, max_area=0.2 * tri.plane.area_scale)
    assert np.array_equal(flat.triangles, tri.triangles) and np.array_equal(flat.vertices, tri.vertices)
    # the area in the plane is the 2D one (16 - 4), each triangle at most max_area
    a, b, c = (tri.vertices3d[tri.triangles[:, k]] for k in range(3))
    areas = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
    assert areas.sum() == pytest.approx(12.0, rel=1e-12) and areas.max() <= 0.2 * (1 + 1e-9)
    # triangles counter-clockwise seen from the normal
    assert (np.cross(b - a, c - a) @ tri.plane.normal > 0).all()


def test_horizontal_input_is_the_2d_mesh_with_its_z():
    P = np.column_stack([SQUARE, np.full(len(SQUARE), 2.5)])
    tri = cdt_plugin.triangulate(P, RINGS, min_angle=25)
    flat = cdt_plugin.triangulate(SQUARE, RINGS, min_angle=25)
    assert np.array_equal(tri.vertices, flat.vertices) and np.array_equal(tri.triangles, flat.triangles)
    assert tri.plane.horizontal and (tri.vertices3d[:, 2] == 2.5).all()
    assert flat.plane is None and (flat.vertices3d[:, 2] == 0).all()


def test_vertical_planes():
    # the wall x + y = 4 (normal in the xy-plane), a door cut from its bottom edge
    t, h = np.array([[0, 0], [1.5, 0], [1.5, 2], [2.5, 2], [2.5, 0], [4, 0], [4, 3], [0, 3.0]]).T
    P = np.column_stack([t, 4 - t, h])
    ring = np.column_stack([np.arange(8), (np.arange(8) + 1) % 8])
    tri = cdt_plugin.triangulate(P, ring, max_area=0.25)
    _check_in_plane(tri, P)
    assert abs(tri.plane.normal[2]) < 1e-15 and abs(tri.plane.normal[0]) == pytest.approx(2 ** -0.5)
    assert tri.plane.axes[2] in (0, 1)          # meshed in y, z or z, x: a wall is no line


def _building():
    """Walls (with a window) and a gable roof of a 6 x 4 house, eaves at 3, ridge at 5:
    each face a list of 3D rings, outward wound."""
    w = [[(0, 0, 0), (6, 0, 0), (6, 0, 3), (0, 0, 3)], [(2, 0, 1), (2, 0, 2), (4, 0, 2), (4, 0, 1)]]
    faces = [w,
             [[(6, 4, 0), (0, 4, 0), (0, 4, 3), (6, 4, 3)]],
             [[(0, 4, 0), (0, 0, 0), (0, 0, 3), (0, 2, 5), (0, 4, 3)]],
             [[(6, 0, 0), (6, 4, 0), (6, 4, 3), (6, 2, 5), (6, 0, 3)]],
             [[(0, 0, 3), (6, 0, 3), (6, 2, 5), (0, 2, 5)]],
             [[(6, 4, 3), (0, 4, 3), (0, 2, 5), (6, 2, 5)]]]
    return faces


def test_walls_and_roofs_of_a_building():
    shapely = pytest.importorskip("shapely")
    total = 0.0
    for face in _building():
        polygon = shapely.Polygon(face[0], face[1:])
        tri = cdt_plugin.triangulate(polygon, min_angle=20)
        P = np.array([p for ring in face for p in ring], float)
        _check_in_plane(tri, P)
        as_geojson = cdt_plugin.triangulate(shapely.geometry.mapping(polygon), min_angle=20)
        assert np.array_equal(as_geojson.vertices3d, tri.vertices3d)
        a, b, c = (tri.vertices3d[tri.triangles[:, k]] for k in range(3))
        total += np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2
    roof = 2 * 6 * np.hypot(2, 2)
    assert total == pytest.approx(2 * 18 - 2 + 2 * (12 + 4) + roof, rel=1e-12)


def test_shapely_and_geojson_polygon_z_on_a_slope():
    shapely = pytest.importorskip("shapely")
    slope = lambda xy: np.column_stack([xy, 0.3 * xy[:, 0] - 0.7 * xy[:, 1] + 10])  # noqa: E731
    shell, hole = slope(SQUARE[:4]), slope(SQUARE[4:8])
    polygon = shapely.Polygon(shell, [hole])
    for geometry in (polygon, shapely.geometry.mapping(polygon)):
        tri = cdt_plugin.triangulate(geometry, max_area=0.5)
        _check_in_plane(tri, np.vstack([shell, hole]))
        V = tri.vertices3d
        assert np.allclose(V[:, 2], 0.3 * V[:, 0] - 0.7 * V[:, 1] + 10, rtol=0, atol=1e-13)
    triangles = tri.to_shapely()                        # 3D triangles on the slope
    assert shapely.has_z(triangles) and len(triangles.geoms) == len(tri.triangles)
    xyz = shapely.get_coordinates(triangles, include_z=True)
    assert np.allclose(xyz[:, 2], 0.3 * xyz[:, 0] - 0.7 * xyz[:, 1] + 10, rtol=0, atol=1e-13)
    assert shapely.area(shapely.force_2d(triangles)) == pytest.approx(12.0)


def test_non_planar_input_names_the_farthest_vertex():
    P = np.column_stack([SQUARE, np.zeros(len(SQUARE))])
    P[6, 2] = 0.01
    P[9, 2] = -0.5
    with pytest.raises(cdt_plugin.NonPlanarError, match=r"vertex 9 \[0\.5, 3\.5, -0\.5\] lies 0\.3") as e:
        cdt_plugin.triangulate(P, RINGS)
    assert e.value.vertex == 9 and e.value.distance == pytest.approx(abs(fit_plane(P).distances(P[9:10])[0]))
    assert isinstance(e.value, cdt_plugin.InvalidGeometryError)
    tri = cdt_plugin.triangulate(P, RINGS, plane_tolerance=1.0)       # a looser bound takes it
    assert np.array_equal(tri.vertices3d[tri.vertex_map], P)


def test_exact_planarity_with_zero_tolerance():
    rng = np.random.default_rng(5)
    R = _rotation(rng)
    P = np.column_stack([SQUARE, np.zeros(len(SQUARE))]) @ R.T
    tri = cdt_plugin.triangulate(P, RINGS)          # rounded into the plane: within rounding
    _check_in_plane(tri, P)
    with pytest.raises(cdt_plugin.NonPlanarError, match="exactly"):
        cdt_plugin.triangulate(P, RINGS, plane_tolerance=0)       # but not exactly coplanar
    Q = np.column_stack([SQUARE, 0.5 * SQUARE[:, 0] - 0.25 * SQUARE[:, 1]])   # exactly on z = x/2 - y/4
    _check_in_plane(cdt_plugin.triangulate(Q, RINGS, plane_tolerance=0), Q)
    Q[10, 2] = np.nextafter(Q[10, 2], 1)
    with pytest.raises(cdt_plugin.NonPlanarError, match="vertex 10") as e:
        cdt_plugin.triangulate(Q, RINGS, plane_tolerance=0)
    assert e.value.tolerance == 0


@pytest.mark.parametrize("bad", [-1.0, float("nan"), "1", True, float("inf")])
def test_plane_tolerance_is_checked(bad):
    with pytest.raises(cdt_plugin.CDTError, match="plane_tolerance must be"):
        cdt_plugin.triangulate(SQUARE, RINGS, plane_tolerance=bad)


def test_3d_input_errors():
    with pytest.raises(cdt_plugin.InputShapeError, match=r"\(n, 2\), got \(3, 4\)"):
        cdt_plugin.triangulate(np.zeros((3, 4)))
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match="row 1"):
        cdt_plugin.triangulate([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]])


def test_3d_hole_seeds_are_projected():
    rng = np.random.default_rng(3)
    R = _rotation(rng)
    P = np.column_stack([SQUARE[:8], np.zeros(8)]) @ R.T
    hole = np.array([[2.0, 2.0, 0.0]]) @ R.T
    tri = cdt_plugin.triangulate(P, RINGS, holes=hole)
    _check_in_plane(tri, P)
    assert len(tri.triangles) == 8


@pytest.mark.parametrize("seed", range(6))
def test_3d_seeds_are_points_of_the_plane(seed):
    # a square with a square hole, cut in two halves by two walls from the shell's corners to
    # the hole's, rotated into a random plane: a 3D hole seed and 3D region seeds (x, y, z,
    # attribute, max_area) pick the same regions as the 2D seeds of the mesh's projection
    rng = np.random.default_rng(seed)
    R, shift = _rotation(rng), rng.normal(size=3) * 10 ** rng.integers(0, 4)
    rings = np.vstack([RINGS, [[0, 4], [2, 6]]])
    P = np.column_stack([SQUARE[:8], np.zeros(8)]) @ R.T + shift
    seeds = np.array([[2.0, 2.0, 0], [3.0, 0.5, 0], [0.5, 3.0, 0]]) @ R.T + shift
    regions = np.column_stack([seeds[1:], [10.0, 20.0], [np.nan, 0.05]])
    tri = cdt_plugin.triangulate(P, rings, holes=seeds[:1], regions=regions)
    _check_in_plane(tri, P)
    uv = tri.plane.project(seeds)
    flat_regions = np.column_stack([uv[1:], [10.0, 20.0], [np.nan, 0.05 * tri.plane.area_scale]])
    same = cdt_plugin.triangulate(tri.vertices[:len(P)], rings, holes=uv[:1], regions=flat_regions)
    assert np.array_equal(same.triangles, tri.triangles) and np.array_equal(same.vertices, tri.vertices)
    assert np.array_equal(same.region_attributes, tri.region_attributes)
    a, b, c = (tri.vertices3d[tri.triangles[:, k]] for k in range(3))
    areas = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
    assert areas.sum() == pytest.approx(12.0, rel=1e-12)
    for value, bound in ((10.0, np.inf), (20.0, 0.05)):
        part = tri.region_attributes.ravel() == value
        assert areas[part].sum() == pytest.approx(6.0, rel=1e-12) and areas[part].max() <= bound * (1 + 1e-9)


def test_3d_seeds_of_a_polygon_z():
    shapely = pytest.importorskip("shapely")
    # a wall, the plane y = 1: its hole's seed given in 3D
    wall = shapely.Polygon([(0, 1, 0), (4, 1, 0), (4, 1, 3), (0, 1, 3)],
                           [[(1, 1, 1), (2, 1, 1), (2, 1, 2), (1, 1, 2)]])
    tri = cdt_plugin.triangulate(wall, holes=[[1.5, 1, 1.5]], regions=[[3, 1, 2, 7.0, np.nan]])
    assert tri.plane.axes[2] == 1 and (tri.vertices3d[:, 1] == 1).all()
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    a, b, c = (tri.vertices3d[tri.triangles[:, k]] for k in range(3))
    assert np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2 == pytest.approx(11.0)
    assert (tri.region_attributes == 7.0).all()


def test_3d_seeds_off_the_plane_are_named():
    P = np.array([[0, 0, 0], [4, 0, 4], [4, 4, 4], [0, 4, 0]], float)       # the plane z = x
    square = [[0, 1], [1, 2], [2, 3], [3, 0]]
    with pytest.raises(cdt_plugin.NonPlanarError, match=r"hole seed 1 \[2.0, 2.0, 2.5\]") as err:
        cdt_plugin.triangulate(P, square, holes=[[1, 1, 1], [2, 2, 2.5]])
    assert err.value.vertex is None and err.value.point == (2.0, 2.0, 2.5)
    assert err.value.distance == pytest.approx(0.5 / np.sqrt(2))
    with pytest.raises(cdt_plugin.NonPlanarError, match="region seed 0"):
        cdt_plugin.triangulate(P, square, regions=[[1, 1, 1.001, 5.0, np.nan]])
    # within plane_tolerance, taken (projected); an exact plane asks it of the vertices only
    tri = cdt_plugin.triangulate(P, square, regions=[[1, 1, 1.001, 5.0, np.nan]], plane_tolerance=0.01)
    assert (tri.region_attributes == 5.0).all()
    tri = cdt_plugin.triangulate(P, square, regions=[[1, 1, 1, 5.0, np.nan]], plane_tolerance=0)
    assert (tri.region_attributes == 5.0).all()
    # 2D seeds keep their meaning (x, y, attribute) and 2D input refuses rows of five
    tri = cdt_plugin.triangulate(P, square, regions=[[1, 1, 5.0]])
    assert (tri.region_attributes == 5.0).all()
    with pytest.raises(cdt_plugin.InputShapeError, match="regions must be rows"):
        cdt_plugin.triangulate(P[:, :2], square, regions=[[1, 1, 1, 5.0, np.nan]])
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match="regions"):
        cdt_plugin.triangulate(P, square, regions=[[1, 1, np.nan, 5.0, np.nan]])


def test_plane_from_normal_keeps_orientation():
    for normal, axes in (([0, 0, -2], (0, 1, 2)), ([3, 1, 1], (1, 2, 0)), ([0, -5, 1], (2, 0, 1))):
        plane = Plane.from_normal(normal, [0, 0, 0])
        assert plane.axes == axes and plane.normal[axes[2]] > 0
        e = np.eye(3)
        assert np.cross(e[axes[0]], e[axes[1]]) @ e[axes[2]] == 1


def test_trimesh_output_keeps_the_plane():
    pytest.importorskip("trimesh")
    P = np.column_stack([SQUARE[:8], 2.0 * SQUARE[:8, 1]])          # the plane z = 2 y
    tri = cdt_plugin.triangulate(P, RINGS, max_area=0.5)
    mesh = tri.to_trimesh()
    assert np.array_equal(mesh.vertices, tri.vertices3d)
    assert np.allclose(mesh.face_normals, tri.plane.normal)
    assert mesh.area == pytest.approx(12 * np.sqrt(5), rel=1e-12)
    flat = tri.to_trimesh(z=1.0)                              # a height given: the 2D mesh at it
    assert (flat.vertices[:, 2] == 1.0).all()


FLOOR = [[(0, 0, 0), (0, 4, 0), (6, 4, 0), (6, 0, 0)]]


@pytest.mark.parametrize("options", [{}, {"min_angle": 25, "split_boundary": False}])
def test_faces_of_a_closed_building_make_a_watertight_solid(options):
    trimesh = pytest.importorskip("trimesh")
    faces = [[face[0]] for face in _building()] + [FLOOR]      # the window left out: closed
    mesh = cdt_plugin.triangulate_faces(faces, merge=True, **options)
    solid = trimesh.Trimesh(mesh.vertices, mesh.triangles, process=False)
    assert solid.is_watertight and solid.is_winding_consistent
    assert solid.volume == pytest.approx(6 * 4 * 3 + 6 * 4 * 2 / 2, rel=1e-12)    # box + roof prism
    assert np.array_equal(np.unique(mesh.face), np.arange(len(faces)))
    # each face's triangles on its own plane, wound outward as its ring
    for i, face in enumerate(faces):
        ring = np.asarray(face[0], float)
        a, b, c = (mesh.vertices[mesh.triangles[mesh.face == i, k]] for k in range(3))
        normals = np.cross(b - a, c - a)
        newell = np.cross(ring, np.roll(ring, -1, axis=0)).sum(axis=0)
        assert (normals @ newell > 0).all()
    if not options:       # no Steiner points: the input points, each once
        corners = np.unique(np.vstack([np.asarray(f[0], float) for f in faces]), axis=0)
        assert np.array_equal(mesh.vertices, corners)


def test_faces_with_holes_and_their_errors():
    shapely = pytest.importorskip("shapely")
    faces = _building()
    mesh = cdt_plugin.triangulate_faces([faces[0], shapely.Polygon(faces[1][0]), {
        "type": "Polygon", "coordinates": faces[2]}])
    a, b, c = (mesh.vertices[mesh.triangles[:, k]] for k in range(3))
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
    assert area[mesh.face == 0].sum() == pytest.approx(18 - 2)        # the wall less its window
    assert area.sum() == pytest.approx(16 + 18 + 12 + 4)
    bent = [list(faces[1][0])]
    bent[0][2] = (0, 4.5, 3)        # off the wall y = 4
    with pytest.raises(cdt_plugin.NonPlanarError) as e:
        cdt_plugin.triangulate_faces([faces[0], bent])
    # (four points off one plane: a twist, the least-squares plane equally far from all four)
    assert e.value.index == 1 and e.value.vertex in range(4) and e.value.distance > 0.1
    with pytest.raises(cdt_plugin.InputShapeError, match="a face must be a Polygon"):
        cdt_plugin.triangulate_faces([{"type": "LineString", "coordinates": [(0, 0, 0), (1, 0, 0)]}])
    empty = cdt_plugin.triangulate_faces([])
    assert empty.vertices.shape == (0, 3) and empty.triangles.shape == (0, 3)


def test_trimesh_path3d_in_a_tilted_plane():
    trimesh = pytest.importorskip("trimesh")
    from trimesh.path.entities import Line
    from cdt_plugin.adapters.trimesh import from_path3d
    rng = np.random.default_rng(11)
    R = _rotation(rng)
    P = np.column_stack([SQUARE[:8], np.zeros(8)]) @ R.T + [5, -3, 2]
    path = trimesh.path.Path3D([Line([0, 1, 2, 3, 0]), Line([4, 5, 6, 7, 4])], P)
    plc = from_path3d(path)
    read = np.column_stack([plc.vertices, plc.z])         # the path's points (loops closed)
    assert np.array_equal(np.unique(read, axis=0), np.unique(P, axis=0))
    tri = cdt_plugin.triangulate(plc, max_area=0.4)
    _check_in_plane(tri, read)
    mesh = tri.to_trimesh()
    assert mesh.area == pytest.approx(12.0, rel=1e-12)
    assert np.allclose(mesh.face_normals, tri.plane.normal)
    with pytest.raises(TypeError, match="Path3D"):
        from_path3d(trimesh.path.Path2D())


@pytest.mark.parametrize("seed", range(20))
def test_thin_polygons_far_off_pass_the_default_check(seed):
    # a 1000:1 sliver rotated into a random plane far from the origin, rounded to doubles
    rng = np.random.default_rng(100 + seed)
    k = 30
    angle = np.sort(rng.uniform(0, 2 * np.pi, k))
    xy = np.column_stack([np.cos(angle), 1e-3 * np.sin(angle)]) * rng.uniform(0.5, 1, (k, 1))
    P = np.column_stack([xy, np.zeros(k)]) @ _rotation(rng).T + rng.normal(size=3) * 1e5
    ring = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    tri = cdt_plugin.triangulate(P, ring, intersections="split")
    _check_in_plane(tri, P)
