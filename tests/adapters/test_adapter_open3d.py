"""Open3D adapter against the real Open3D (no mocks)."""
import numpy as np
import pytest

o3d = pytest.importorskip("open3d")

import cdt_plugin  # noqa: E402
from cdt_plugin.adapters.open3d import NonPlanarError, from_lineset, to_open3d  # noqa: E402


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
    assert tri.is_delaunay()
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
    mesh = tri.to_open3d(z=np.array([0.0, 1.0, 2.0, 3.0]))
    assert np.array_equal(np.asarray(mesh.vertices)[:, 2], [0.0, 1.0, 2.0, 3.0])
    assert len(mesh.triangles) == 2


def test_non_planar_lineset_names_the_point():
    ls = _square_with_hole(0.0)
    P = np.asarray(ls.points).copy()
    P[5, 2] = 1e-9
    ls.points = o3d.utility.Vector3dVector(P)
    with pytest.raises(NonPlanarError, match=r"point 5 = \[3\.0, 1\.0, 1e-09\]") as info:
        from_lineset(ls)
    assert isinstance(info.value, cdt_plugin.CDTError)
    assert info.value.index == 5
    assert len(from_lineset(ls, atol=1e-6).vertices) == 8


def test_empty_and_bad_lines():
    with pytest.raises(cdt_plugin.TooFewPointsError):
        from_lineset(o3d.geometry.LineSet())
    ls = _square_with_hole()
    ls.lines = o3d.utility.Vector2iVector(np.array([[0, 1], [1, 9]]))
    with pytest.raises(cdt_plugin.SegmentIndexError):
        cdt_plugin.triangulate(from_lineset(ls))
