"""Open3D adapter: planar ``LineSet`` in, ``TriangleMesh`` out.

Data flow (DESIGN.md): ``open3d.geometry.LineSet`` or ``open3d.t.geometry.LineSet``
(planar, in any plane) -> :func:`from_lineset` -> :class:`cdt_plugin.PLC` (with z) ->
:func:`cdt_plugin.triangulate` (meshed in its plane, :mod:`cdt_plugin.planar`) ->
Triangulation -> :func:`to_open3d` (the legacy ``open3d.geometry.TriangleMesh``) or
:func:`to_open3d_tensor` (the tensor API's ``open3d.t.geometry.TriangleMesh``), in
the LineSet's plane.

>>> import numpy as np, open3d as o3d, cdt_plugin
>>> from cdt_plugin.adapters.open3d import from_lineset, to_open3d
>>> pts = [[0, 0, 2], [4, 0, 2], [4, 4, 2], [0, 4, 2]]
>>> ls = o3d.geometry.LineSet(o3d.utility.Vector3dVector(np.array(pts, float)),
...                           o3d.utility.Vector2iVector(np.array([[0, 1], [1, 2], [2, 3], [3, 0]])))
>>> mesh = to_open3d(cdt_plugin.triangulate(from_lineset(ls)))
>>> len(mesh.vertices), len(mesh.triangles), mesh.get_surface_area(), mesh.get_center().tolist()
(4, 2, 16.0, [2.0, 2.0, 2.0])

The tensor API the same way:

>>> from cdt_plugin.adapters.open3d import to_open3d_tensor
>>> tls = o3d.t.geometry.LineSet.from_legacy(ls)
>>> tmesh = to_open3d_tensor(cdt_plugin.triangulate(from_lineset(tls)))
>>> tmesh.vertex.positions.shape, tmesh.triangle.indices.dtype
(SizeVector[4, 3], Int64)
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cdt_plugin.optional import missing

try:
    import open3d
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.open3d", extra="open3d") from exc

from cdt_plugin import PLC, InputShapeError, NonPlanarError, TooFewPointsError

if TYPE_CHECKING:
    from cdt_plugin import Triangulation

__all__ = ["to_open3d", "to_open3d_tensor", "from_lineset", "NonPlanarError"]   # (the error: cdt_plugin's)

#: A LineSet of the legacy API or of the tensor API.
AnyLineSet = Union[open3d.geometry.LineSet, open3d.t.geometry.LineSet]


def _positions(tri: Triangulation, z: ArrayLike | None
               ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """(n, 3) float64 vertices, (k, 3) int64 triangles (exactly ``tri``'s) and
    the unit normal: ``tri.vertices3d`` and its plane's normal when ``z`` is
    None (the plane z = 0 for a 2D triangulation), else ``tri.vertices`` in the
    plane ``z`` (a scalar or one value per vertex) with normal (0, 0, 1)."""
    T = np.ascontiguousarray(tri.triangles, dtype=np.int64).reshape(-1, 3)
    if z is None:
        plane = getattr(tri, "plane", None)
        normal = np.array([0.0, 0.0, 1.0]) if plane is None else plane.normal
        return np.asarray(tri.vertices3d, dtype=np.float64), T, normal
    V = np.asarray(tri.vertices, dtype=np.float64).reshape(-1, 2)
    zz = np.asarray(z, dtype=np.float64)
    if zz.shape not in ((), (len(V),)):
        raise InputShapeError(f"z must be a number or one value per vertex ({len(V)}), "
                              f"got shape {zz.shape}")
    zz = np.broadcast_to(zz, (len(V),))
    return np.column_stack([V, zz]), T, np.array([0.0, 0.0, 1.0])


def _copies(normal: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    """n copies of the unit normal."""
    return np.tile(normal, (n, 1))


def to_open3d(tri: Triangulation, z: ArrayLike | None = None) -> open3d.geometry.TriangleMesh:
    """The triangulation as a flat ``open3d.geometry.TriangleMesh``: in its own
    plane (``tri.vertices3d``: a LineSet's or any 3D input's plane, z = 0 for 2D
    input), or with ``z`` given in the plane ``z`` (a scalar, or one value per
    vertex of ``tri.vertices``).

    Vertices are ``tri.vertices`` in order (so indices agree with ``tri.triangles``;
    vertices outside the meshed domain stay, unreferenced: call
    ``mesh.remove_unreferenced_vertices()`` to drop them). Triangles are
    counter-clockwise seen from the plane's normal (+z with ``z`` given), and
    every vertex and triangle normal is that normal. For the tensor API see
    :func:`to_open3d_tensor`.
    """
    P, T, normal = _positions(tri, z)
    mesh = open3d.geometry.TriangleMesh(open3d.utility.Vector3dVector(P),
                                        open3d.utility.Vector3iVector(T.astype(np.int32)))
    mesh.vertex_normals = open3d.utility.Vector3dVector(_copies(normal, len(P)))
    mesh.triangle_normals = open3d.utility.Vector3dVector(_copies(normal, len(T)))
    return mesh


def to_open3d_tensor(tri: Triangulation, z: ArrayLike | None = None) -> open3d.t.geometry.TriangleMesh:
    """The triangulation as a flat ``open3d.t.geometry.TriangleMesh`` (Open3D's
    tensor API) in its own plane or in the plane ``z`` (as :func:`to_open3d`), on the CPU.

    ``mesh.vertex.positions`` is Float64 (exactly ``tri.vertices3d``, or
    ``tri.vertices`` with ``z``) and
    ``mesh.triangle.indices`` Int64 (exactly ``tri.triangles``: counter-clockwise
    from +z, unreferenced vertices kept as in :func:`to_open3d`); Open3D takes
    Float32/Float64 positions and Int32/Int64 indices, and these two lose
    nothing. ``vertex.normals`` and ``triangle.normals`` are the plane's normal, Float64.

    >>> import cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> mesh = to_open3d_tensor(tri, z=0.5)
    >>> mesh.vertex.positions.numpy()[:, 2].tolist(), mesh.triangle.indices.shape
    ([0.5, 0.5, 0.5, 0.5], SizeVector[2, 3])
    """
    P, T, normal = _positions(tri, z)
    # dtype and device as Tensor infers them by default, given: Open3D's stubs omit those defaults
    tensor, cpu = open3d.core.Tensor, open3d.core.Device("CPU:0")
    f64, i64 = open3d.core.float64, open3d.core.int64
    mesh = open3d.t.geometry.TriangleMesh(tensor(P, f64, cpu), tensor(T, i64, cpu))
    mesh.vertex.normals = tensor(_copies(normal, len(P)), f64, cpu)
    mesh.triangle.normals = tensor(_copies(normal, len(T)), f64, cpu)
    return mesh


def _lineset_arrays(lineset: AnyLineSet) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Points (n, 3) float64 and lines (m, 2) int64 of a legacy or tensor LineSet."""
    if isinstance(lineset, open3d.t.geometry.LineSet):
        points, lines = lineset.point, lineset.line
        P = points.positions.cpu().numpy() if "positions" in points else np.empty((0, 3))
        L = lines.indices.cpu().numpy() if "indices" in lines else np.empty((0, 2))
    elif isinstance(lineset, open3d.geometry.LineSet):
        P, L = np.asarray(lineset.points), np.asarray(lineset.lines)
    else:
        raise TypeError("expected an open3d.geometry.LineSet or open3d.t.geometry.LineSet, "
                        f"got {type(lineset).__name__}")
    return (np.asarray(P, dtype=np.float64).reshape(-1, 3),
            np.asarray(L, dtype=np.int64).reshape(-1, 2))


def from_lineset(lineset: AnyLineSet) -> PLC:
    """A :class:`cdt_plugin.PLC` from a planar ``open3d.geometry.LineSet`` or
    ``open3d.t.geometry.LineSet`` (tensor API; Float32 points are widened exactly
    to float64, a GPU LineSet is copied to the CPU), in any plane.

    Points become vertices (x, y, with z in ``plc.z``), lines become segments;
    no rings are known, so the domain is decided by depth parity (a closed loop
    inside a closed loop is a hole). :func:`cdt_plugin.triangulate` meshes it in
    its plane (:mod:`cdt_plugin.planar`): points off the plane raise
    :class:`cdt_plugin.NonPlanarError` there naming the farthest (its
    ``plane_tolerance`` option sets how far is too far), bad line indices
    :class:`cdt_plugin.SegmentIndexError`.
    """
    P, L = _lineset_arrays(lineset)
    if len(P) == 0:
        raise TooFewPointsError("the LineSet has no points")
    return PLC(np.ascontiguousarray(P[:, :2]), L, z=P[:, 2].copy())
