"""Open3D adapter against the real Open3D (no mocks): the legacy API
(``open3d.geometry``) and the tensor API (``open3d.t.geometry``)."""
import doctest

import numpy as np
import pytest

o3d = pytest.importorskip("open3d")

import cdt_plugin  # noqa: E402
import cdt_plugin.adapters.open3d as co3d  # noqa: E402
from cdt_plugin.adapters.open3d import NonPlanarError, from_lineset, to_open3d, to_open3d_tensor  # noqa: E402

from checker import assert_valid  # noqa: E402


def test_docstring_examples():
    result = doctest.testmod(co3d)
    assert result.attempted >= 10 and result.failed == 0


def _verify(tri, **kwargs):
    """The exact checker: a CDT bounded by its segments, every other edge locally Delaunay."""
    return assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments", **kwargs)


def _square_with_hole(z=1.5):
    pts = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]], float)
    loops = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    P = np.column_stack([pts, np.full(len(pts), z)])
    return o3d.geometry.LineSet(o3d.utility.Vector3dVector(P), o3d.utility.Vector2iVector(loops))


def test_lineset_round_trip():
    ls = _square_with_hole(1.5)
    plc = from_lineset(ls)
    assert plc.vertices.shape == (8, 2) and plc.segments.shape == (8, 2)
    assert (plc.z == 1.5).all()
    tri = cdt_plugin.triangulate(plc)
    _verify(tri)
    mesh = to_open3d(tri, z=1.5)
    assert isinstance(mesh, o3d.geometry.TriangleMesh)
    assert len(mesh.vertices) == 8 and len(mesh.triangles) == 8
    assert mesh.has_vertex_normals()
    assert np.array_equal(np.asarray(mesh.vertex_normals), np.tile([0.0, 0.0, 1.0], (8, 1)))
    assert mesh.get_surface_area() == pytest.approx(16.0 - 4.0, rel=1e-12)
    assert np.allclose(np.asarray(mesh.vertices)[:, 2], 1.5)
    # counter-clockwise from +z: Open3D's own triangle normals point up
    mesh.compute_triangle_normals()
    assert np.allclose(np.asarray(mesh.triangle_normals), [0.0, 0.0, 1.0])
    assert mesh.is_edge_manifold() and mesh.is_vertex_manifold() and mesh.is_orientable()
    assert np.array_equal(np.asarray(mesh.triangles), tri.triangles)


def test_to_open3d_method_and_per_vertex_z():
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    _verify(tri)
    mesh = tri.to_open3d(z=np.array([0.0, 1.0, 2.0, 3.0]))
    assert np.array_equal(np.asarray(mesh.vertices)[:, 2], [0.0, 1.0, 2.0, 3.0])
    assert len(mesh.triangles) == 2
    with pytest.raises(cdt_plugin.InputShapeError, match=r"one value per vertex \(4\), got shape \(3,\)"):
        to_open3d(tri, z=[0.0, 1.0, 2.0])


def test_non_planar_lineset_names_the_point():
    ls = _square_with_hole(0.0)
    P = np.asarray(ls.points).copy()
    P[5, 2] = 1e-9
    ls.points = o3d.utility.Vector3dVector(P)
    with pytest.raises(NonPlanarError, match=r"vertex 5 \[3\.0, 1\.0, 1e-09\] lies") as info:
        cdt_plugin.triangulate(from_lineset(ls))
    assert info.value is not None and isinstance(info.value, cdt_plugin.CDTError)
    assert info.value.vertex == 5 and 0 < info.value.distance < 1e-9
    tri = cdt_plugin.triangulate(from_lineset(ls), plane_tolerance=1e-6)
    _verify(tri)
    assert np.array_equal(tri.vertices3d[:8], P)


def test_empty_and_bad_lines():
    with pytest.raises(cdt_plugin.TooFewPointsError):
        from_lineset(o3d.geometry.LineSet())
    ls = _square_with_hole()
    ls.lines = o3d.utility.Vector2iVector(np.array([[0, 1], [1, 9]]))
    with pytest.raises(cdt_plugin.SegmentIndexError):
        cdt_plugin.triangulate(from_lineset(ls))


# ------------------------------------------------------------------ tensor API
def _tensor_square_with_hole(z=1.5, float_dtype=np.float64, int_dtype=np.int64):
    legacy = _square_with_hole(z)
    points = np.asarray(legacy.points).astype(float_dtype)
    lines = np.asarray(legacy.lines).astype(int_dtype)
    return o3d.t.geometry.LineSet(o3d.core.Tensor(points), o3d.core.Tensor(lines))


@pytest.mark.parametrize("float_dtype, int_dtype", [(np.float64, np.int64), (np.float32, np.int32)])
def test_tensor_lineset_reads_as_the_legacy_one(float_dtype, int_dtype):
    tls = _tensor_square_with_hole(1.5, float_dtype, int_dtype)
    plc, legacy = from_lineset(tls), from_lineset(_square_with_hole(1.5))
    assert plc.vertices.dtype == np.float64 and plc.segments.dtype == np.int64
    assert np.array_equal(plc.vertices, legacy.vertices)      # float32 widened exactly
    assert np.array_equal(plc.segments, legacy.segments)
    assert np.array_equal(plc.z, legacy.z)
    tri = cdt_plugin.triangulate(plc)
    _verify(tri)
    assert len(tri.triangles) == 8


def test_to_open3d_tensor_exact_float64_int64():
    # coordinates that float32 would round: the tensor mesh must keep them
    pts = np.array([[0.1, 0.2], [4.3, 0.7], [3.9, 4.1], [0.3, 3.7], [2.2, 2.05]])
    tri = cdt_plugin.triangulate(pts, [[0, 1], [1, 2], [2, 3], [3, 0]])
    _verify(tri)
    mesh = to_open3d_tensor(tri, z=0.1)
    assert isinstance(mesh, o3d.t.geometry.TriangleMesh)
    assert mesh.device == o3d.core.Device("CPU:0")
    positions, indices = mesh.vertex.positions, mesh.triangle.indices
    assert positions.dtype == o3d.core.float64 and indices.dtype == o3d.core.int64
    assert np.array_equal(positions.numpy()[:, :2], tri.vertices)
    assert np.array_equal(positions.numpy()[:, 2], np.full(len(tri.vertices), 0.1))
    assert np.array_equal(indices.numpy(), tri.triangles)
    # the tensor mesh read back is the same valid CDT, and Open3D agrees on its geometry
    assert_valid(positions.numpy()[:, :2], indices.numpy(), segments=tri.segments, domain="segments")
    a, b, c = (tri.vertices[tri.triangles[:, k]] for k in range(3))
    area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert (area > 0).all() and mesh.get_surface_area() == pytest.approx(area.sum(), rel=1e-12)
    assert np.array_equal(mesh.vertex.normals.numpy(), np.tile([0.0, 0.0, 1.0], (len(tri.vertices), 1)))
    assert np.array_equal(mesh.triangle.normals.numpy(), np.tile([0.0, 0.0, 1.0], (len(tri.triangles), 1)))
    recomputed = mesh.clone()
    recomputed.compute_triangle_normals()                 # counter-clockwise: Open3D's normals point up
    assert np.allclose(recomputed.triangle.normals.numpy(), [0.0, 0.0, 1.0])
    # the same mesh as the legacy output
    legacy = mesh.to_legacy()
    assert np.array_equal(np.asarray(legacy.vertices), np.asarray(to_open3d(tri, z=0.1).vertices))
    assert np.array_equal(np.asarray(legacy.triangles), tri.triangles)
    assert legacy.is_edge_manifold() and legacy.is_orientable()


def test_tensor_round_trip_with_per_vertex_z_and_unreferenced_vertices():
    tls = _tensor_square_with_hole(2.0)
    tri = cdt_plugin.triangulate(from_lineset(tls))
    _verify(tri)
    z = np.arange(len(tri.vertices), dtype=float)
    mesh = to_open3d_tensor(tri, z=z)
    assert np.array_equal(mesh.vertex.positions.numpy()[:, 2], z)
    assert mesh.get_surface_area() > 12.0                 # tilted by z: more than the flat 12
    # a vertex outside the domain stays (unreferenced), as in to_open3d
    outside = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4], [9, 9]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    _verify(outside, require_all_vertices=False)
    mesh = to_open3d_tensor(outside)
    assert mesh.vertex.positions.shape == o3d.core.SizeVector([5, 3])
    assert mesh.get_surface_area() == pytest.approx(16.0, rel=1e-12)
    with pytest.raises(cdt_plugin.InputShapeError, match="z must be a number or one value per vertex"):
        to_open3d_tensor(outside, z=np.zeros((5, 1)))


def test_tensor_lineset_errors():
    with pytest.raises(cdt_plugin.TooFewPointsError):
        from_lineset(o3d.t.geometry.LineSet())
    tls = _tensor_square_with_hole(0.0)
    positions = tls.point.positions.numpy().copy()
    positions[5, 2] = 1e-9
    tls.point.positions = o3d.core.Tensor(positions)
    with pytest.raises(NonPlanarError, match=r"vertex 5 \[3\.0, 1\.0, 1e-09\] lies") as info:
        cdt_plugin.triangulate(from_lineset(tls))
    assert info.value.vertex == 5
    assert len(from_lineset(tls).vertices) == 8
    tls.line.indices = o3d.core.Tensor(np.array([[0, 1], [1, 9]]))
    with pytest.raises(cdt_plugin.SegmentIndexError):
        cdt_plugin.triangulate(from_lineset(tls), plane_tolerance=1e-6)
    with pytest.raises(TypeError, match="open3d.t.geometry.LineSet"):
        from_lineset(o3d.t.geometry.PointCloud())


def _lineset(P, loops):
    return o3d.geometry.LineSet(o3d.utility.Vector3dVector(np.asarray(P, float)),
                                o3d.utility.Vector2iVector(np.asarray(loops)))


def test_lineset_at_z2_comes_back_at_z2():
    tri = cdt_plugin.triangulate(from_lineset(_square_with_hole(2.0)), max_area=0.5)
    _verify(tri)
    assert tri.plane is not None and tri.plane.horizontal
    for mesh in (to_open3d(tri), tri.to_open3d()):
        V = np.asarray(mesh.vertices)
        assert (V[:, 2] == 2.0).all() and np.array_equal(V[:, :2], tri.vertices)
        assert np.allclose(np.asarray(mesh.triangle_normals), [0, 0, 1])
    tmesh = to_open3d_tensor(tri)
    assert (tmesh.vertex.positions.numpy()[:, 2] == 2.0).all()
    assert to_open3d(tri).get_surface_area() == pytest.approx(12.0, rel=1e-12)


def test_tilted_lineset_stays_on_its_plane():
    ls = _square_with_hole(0.0)
    P2 = np.asarray(ls.points)[:, :2]
    # the plane z = 0.5 x + 0.25 y + 1 (dyadic slopes: the points lie on it exactly)
    P = np.column_stack([P2, 0.5 * P2[:, 0] + 0.25 * P2[:, 1] + 1.0])
    tri = cdt_plugin.triangulate(from_lineset(_lineset(P, np.asarray(ls.lines))), max_area=0.3)
    _verify(tri)
    mesh = to_open3d(tri)
    V = np.asarray(mesh.vertices)
    assert np.array_equal(V[:8], P)                                     # input points exactly
    assert np.allclose(V[:, 2], 0.5 * V[:, 0] + 0.25 * V[:, 1] + 1.0, rtol=0, atol=1e-14)
    normal = np.array([-0.5, -0.25, 1.0]) / np.linalg.norm([-0.5, -0.25, 1.0])
    assert np.allclose(np.asarray(mesh.triangle_normals), normal)
    mesh.compute_triangle_normals()          # Open3D's own normals agree: the winding faces it
    assert np.allclose(np.asarray(mesh.triangle_normals), normal)
    area = 12.0 * np.linalg.norm([-0.5, -0.25, 1.0])                  # 12 in plan, tilted
    assert mesh.get_surface_area() == pytest.approx(area, rel=1e-12)
