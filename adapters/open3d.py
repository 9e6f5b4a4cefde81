"""Open3D adapter: planar ``LineSet`` in, ``TriangleMesh`` out.

Data flow (DESIGN.md): ``open3d.geometry.LineSet`` or ``open3d.t.geometry.LineSet``
(planar, z = const) -> :func:`from_lineset` -> :class:`cdt_plugin.PLC` ->
:func:`cdt_plugin.triangulate` -> Triangulation -> :func:`to_open3d` (the legacy
``open3d.geometry.TriangleMesh``) or :func:`to_open3d_tensor` (the tensor API's
``open3d.t.geometry.TriangleMesh``).

>>> import numpy as np, open3d as o3d, cdt_plugin
>>> from cdt_plugin.adapters.open3d import from_lineset, to_open3d
>>> pts = [[0, 0, 2], [4, 0, 2], [4, 4, 2], [0, 4, 2]]
>>> ls = o3d.geometry.LineSet(o3d.utility.Vector3dVector(np.array(pts, float)),
...                           o3d.utility.Vector2iVector(np.array([[0, 1], [1, 2], [2, 3], [3, 0]])))
>>> mesh = to_open3d(cdt_plugin.triangulate(from_lineset(ls)), z=2.0)
>>> len(mesh.vertices), len(mesh.triangles), mesh.get_surface_area()
(4, 2, 16.0)

The tensor API the same way:

>>> from cdt_plugin.adapters.open3d import to_open3d_tensor
>>> tls = o3d.t.geometry.LineSet.from_legacy(ls)
>>> tmesh = to_open3d_tensor(cdt_plugin.triangulate(from_lineset(tls)), z=2.0)
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

from cdt_plugin import PLC, InputShapeError, InvalidGeometryError, TooFewPointsError

if TYPE_CHECKING:
    from cdt_plugin import Triangulation

__all__ = ["to_open3d", "to_open3d_tensor", "from_lineset", "NonPlanarError"]

#: A LineSet of the legacy API or of the tensor API.
AnyLineSet = Union[open3d.geometry.LineSet, open3d.t.geometry.LineSet]


class NonPlanarError(InvalidGeometryError):
    """A LineSet point does not lie in the plane z = const of the first point;
    ``index`` and ``point`` name the first offending point."""

    def __init__(self, message: str, index: int | None = None,
                 point: tuple[float, ...] | None = None) -> None:
        super().__init__(message)
        self.index = index
        self.point = point


def _positions(tri: Triangulation, z: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """(n, 3) float64 vertices in the plane ``z`` (a scalar or one value per
    vertex) and (k, 3) int64 triangles, exactly ``tri``'s values."""
    V = np.asarray(tri.vertices, dtype=np.float64).reshape(-1, 2)
    zz = np.asarray(z, dtype=np.float64)
    if zz.shape not in ((), (len(V),)):
        raise InputShapeError(f"z must be a number or one value per vertex ({len(V)}), "
                              f"got shape {zz.shape}")
    zz = np.broadcast_to(zz, (len(V),))
    T = np.ascontiguousarray(tri.triangles, dtype=np.int64).reshape(-1, 3)
    return np.column_stack([V, zz]), T


def _up(n: int) -> NDArray[np.float64]:
    """n copies of the unit normal (0, 0, 1)."""
    up = np.zeros((n, 3))
    up[:, 2] = 1.0
    return up


def to_open3d(tri: Triangulation, z: ArrayLike = 0.0) -> open3d.geometry.TriangleMesh:
    """The triangulation as a flat ``open3d.geometry.TriangleMesh`` in the plane
    ``z`` (a scalar, or one value per vertex of ``tri.vertices``).

    Vertices are ``tri.vertices`` in order (so indices agree with ``tri.triangles``;
    vertices outside the meshed domain stay, unreferenced: call
    ``mesh.remove_unreferenced_vertices()`` to drop them). Triangles are
    counter-clockwise seen from +z, and every vertex and triangle normal is
    (0, 0, 1). For the tensor API see :func:`to_open3d_tensor`.
    """
    P, T = _positions(tri, z)
    mesh = open3d.geometry.TriangleMesh(open3d.utility.Vector3dVector(P),
                                        open3d.utility.Vector3iVector(T.astype(np.int32)))
    mesh.vertex_normals = open3d.utility.Vector3dVector(_up(len(P)))
    mesh.triangle_normals = open3d.utility.Vector3dVector(_up(len(T)))
    return mesh


def to_open3d_tensor(tri: Triangulation, z: ArrayLike = 0.0) -> open3d.t.geometry.TriangleMesh:
    """The triangulation as a flat ``open3d.t.geometry.TriangleMesh`` (Open3D's
    tensor API) in the plane ``z`` (a scalar, or one value per vertex), on the CPU.

    ``mesh.vertex.positions`` is Float64 (exactly ``tri.vertices`` with ``z``) and
    ``mesh.triangle.indices`` Int64 (exactly ``tri.triangles``: counter-clockwise
    from +z, unreferenced vertices kept as in :func:`to_open3d`); Open3D takes
    Float32/Float64 positions and Int32/Int64 indices, and these two lose
    nothing. ``vertex.normals`` and ``triangle.normals`` are (0, 0, 1), Float64.

    >>> import cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> mesh = to_open3d_tensor(tri, z=0.5)
    >>> mesh.vertex.positions.numpy()[:, 2].tolist(), mesh.triangle.indices.shape
    ([0.5, 0.5, 0.5, 0.5], SizeVector[2, 3])
    """
    P, T = _positions(tri, z)
    # dtype and device as Tensor infers them by default, given: Open3D's stubs omit those defaults
    tensor, cpu = open3d.core.Tensor, open3d.core.Device("CPU:0")
    f64, i64 = open3d.core.float64, open3d.core.int64
    mesh = open3d.t.geometry.TriangleMesh(tensor(P, f64, cpu), tensor(T, i64, cpu))
    mesh.vertex.normals = tensor(_up(len(P)), f64, cpu)
    mesh.triangle.normals = tensor(_up(len(T)), f64, cpu)
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


def from_lineset(lineset: AnyLineSet, *, atol: float = 0.0) -> PLC:
    """A :class:`cdt_plugin.PLC` from a planar ``open3d.geometry.LineSet`` or
    ``open3d.t.geometry.LineSet`` (tensor API; Float32 points are widened exactly
    to float64, a GPU LineSet is copied to the CPU).

    The points must lie in one plane z = const (the z of point 0, within ``atol``;
    exact by default), else :class:`NonPlanarError` (an
    :class:`cdt_plugin.InvalidGeometryError`) names the first offending point.
    Points become vertices (x, y; z kept in ``plc.z``), lines become segments;
    no rings are known, so the domain is decided by depth parity (a closed loop
    inside a closed loop is a hole). Bad line indices raise
    :class:`cdt_plugin.SegmentIndexError` in :func:`cdt_plugin.triangulate`.
    """
    P, L = _lineset_arrays(lineset)
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
