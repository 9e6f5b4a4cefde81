"""Open3D adapter: planar ``LineSet`` in, ``TriangleMesh`` out.

Data flow (DESIGN.md): ``open3d.geometry.LineSet`` (planar, z = const) ->
:func:`from_lineset` -> :class:`cdt_plugin.PLC` -> :func:`cdt_plugin.triangulate`
-> Triangulation -> :func:`to_open3d` -> ``open3d.geometry.TriangleMesh``.

>>> import numpy as np, open3d as o3d, cdt_plugin
>>> from cdt_plugin.adapters.open3d import from_lineset, to_open3d
>>> pts = [[0, 0, 2], [4, 0, 2], [4, 4, 2], [0, 4, 2]]
>>> ls = o3d.geometry.LineSet(o3d.utility.Vector3dVector(np.array(pts, float)),
...                           o3d.utility.Vector2iVector(np.array([[0, 1], [1, 2], [2, 3], [3, 0]])))
>>> mesh = to_open3d(cdt_plugin.triangulate(from_lineset(ls)), z=2.0)
>>> len(mesh.vertices), len(mesh.triangles), mesh.get_surface_area()
(4, 2, 16.0)
"""
from __future__ import annotations

import numpy as np
import open3d

from cdt_plugin import PLC, InvalidGeometryError, TooFewPointsError

__all__ = ["to_open3d", "from_lineset", "NonPlanarError"]


class NonPlanarError(InvalidGeometryError):
    """A LineSet point does not lie in the plane z = const of the first point;
    ``index`` and ``point`` name the first offending point."""

    def __init__(self, message, index=None, point=None):
        super().__init__(message)
        self.index = index
        self.point = point


def to_open3d(tri, z=0.0) -> "open3d.geometry.TriangleMesh":
    """The triangulation as a flat ``open3d.geometry.TriangleMesh`` in the plane
    ``z`` (a scalar, or one value per vertex of ``tri.vertices``).

    Vertices are ``tri.vertices`` in order (so indices agree with ``tri.triangles``;
    vertices outside the meshed domain stay, unreferenced: call
    ``mesh.remove_unreferenced_vertices()`` to drop them). Triangles are
    counter-clockwise seen from +z, and every vertex and triangle normal is
    (0, 0, 1).
    """
    V = np.asarray(tri.vertices, dtype=np.float64)
    zz = np.broadcast_to(np.asarray(z, dtype=np.float64), (len(V),))
    T = np.ascontiguousarray(tri.triangles, dtype=np.int32)
    mesh = open3d.geometry.TriangleMesh(
        open3d.utility.Vector3dVector(np.column_stack([V, zz])),
        open3d.utility.Vector3iVector(T.reshape(-1, 3)))
    up = np.zeros((len(V), 3))
    up[:, 2] = 1.0
    mesh.vertex_normals = open3d.utility.Vector3dVector(up)
    up_t = np.zeros((len(T), 3))
    up_t[:, 2] = 1.0
    mesh.triangle_normals = open3d.utility.Vector3dVector(up_t)
    return mesh


def from_lineset(lineset, *, atol: float = 0.0) -> PLC:
    """A :class:`cdt_plugin.PLC` from a planar ``open3d.geometry.LineSet``.

    The points must lie in one plane z = const (the z of point 0, within ``atol``;
    exact by default), else :class:`NonPlanarError` (an
    :class:`cdt_plugin.InvalidGeometryError`) names the first offending point.
    Points become vertices (x, y; z kept in ``plc.z``), lines become segments;
    no rings are known, so the domain is decided by depth parity (a closed loop
    inside a closed loop is a hole). Bad line indices raise
    :class:`cdt_plugin.SegmentIndexError` in :func:`cdt_plugin.triangulate`.
    """
    P = np.asarray(lineset.points, dtype=np.float64).reshape(-1, 3)
    L = np.asarray(lineset.lines, dtype=np.int64).reshape(-1, 2)
    if len(P) == 0:
        raise TooFewPointsError("the LineSet has no points")
    z0 = P[0, 2]
    off = np.flatnonzero(~(np.abs(P[:, 2] - z0) <= atol))
    if len(off):
        i = int(off[0])
        raise NonPlanarError(
            f"LineSet is not planar in z = {z0!r}: point {i} = {P[i].tolist()} lies off the plane"
            + (f" ({len(off)} such points)" if len(off) > 1 else "")
            + (f" by more than atol={atol!r}" if atol else ""),
            index=i, point=tuple(P[i]))
    return PLC(np.ascontiguousarray(P[:, :2]), L, z=P[:, 2].copy())
