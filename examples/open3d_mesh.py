"""A planar Open3D LineSet meshed by cdt_plugin and written to .ply.

    python examples/open3d_mesh.py [out/open3d_mesh.ply]

Builds an ``open3d.geometry.LineSet`` at height z = 2 (a 12-sided outline with a
square hole and a triangular hole), reads it into a PLC with
``cdt_plugin.adapters.open3d.from_lineset``, triangulates it, converts the result
with ``to_open3d`` (normals +z) and writes a .ply file; then reads the file back
with Open3D and checks counts, area and normals. Needs open3d (``pip install
open3d-cpu``).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import open3d as o3d

import cdt_plugin
from cdt_plugin.adapters.open3d import from_lineset, to_open3d

REPO_ROOT = Path(__file__).resolve().parent.parent
Z = 2.0


def loop(points):
    """Segments closing the given run of point indices into a loop."""
    idx = np.asarray(points)
    return np.column_stack([idx, np.roll(idx, -1)])


def make_lineset() -> o3d.geometry.LineSet:
    t = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)
    outer = np.column_stack([5.0 * np.cos(t), 5.0 * np.sin(t)])
    square = np.array([[-2.5, -1.0], [-0.5, -1.0], [-0.5, 1.0], [-2.5, 1.0]])
    triangle = np.array([[1.0, -1.0], [3.0, -1.0], [2.0, 1.5]])
    xy = np.vstack([outer, square, triangle])
    lines = np.vstack([loop(range(0, 12)), loop(range(12, 16)), loop(range(16, 19))])
    pts = np.column_stack([xy, np.full(len(xy), Z)])
    return o3d.geometry.LineSet(o3d.utility.Vector3dVector(pts), o3d.utility.Vector2iVector(lines))


def main(argv) -> int:
    out = Path(argv[1]) if len(argv) > 1 else REPO_ROOT / "out" / "open3d_mesh.ply"
    lineset = make_lineset()
    tri = cdt_plugin.triangulate(from_lineset(lineset))
    mesh = to_open3d(tri, z=Z)
    expected_area = 0.5 * 12 * 25.0 * np.sin(2 * np.pi / 12) - 4.0 - 2.5
    print(f"LineSet: {len(lineset.points)} points, {len(lineset.lines)} lines (z = {Z})")
    print(f"mesh: {len(mesh.vertices)} vertices, {len(mesh.triangles)} triangles, "
          f"area {mesh.get_surface_area():.6f} (expected {expected_area:.6f}), "
          f"is_delaunay {tri.is_delaunay()}")

    out.parent.mkdir(parents=True, exist_ok=True)
    if not o3d.io.write_triangle_mesh(str(out), mesh, write_ascii=False):
        print(f"could not write {out}")
        return 1
    back = o3d.io.read_triangle_mesh(str(out))
    ok = (len(back.vertices) == len(mesh.vertices) and len(back.triangles) == len(mesh.triangles)
          and np.array_equal(np.asarray(back.triangles), np.asarray(mesh.triangles))
          and np.allclose(np.asarray(back.vertices), np.asarray(mesh.vertices))
          and back.has_vertex_normals()
          and np.allclose(np.asarray(back.vertex_normals), [0.0, 0.0, 1.0])
          and abs(back.get_surface_area() - expected_area) <= 1e-9 * expected_area)
    print(f"wrote {out}; read back: {len(back.vertices)} vertices, {len(back.triangles)} triangles, "
          f"normals +z: {np.allclose(np.asarray(back.vertex_normals), [0.0, 0.0, 1.0])} -> "
          f"{'OK' if ok else 'MISMATCH'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
