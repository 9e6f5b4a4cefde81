"""Planar polygons in any plane: 3D input triangulated in its own plane.

:func:`cdt_plugin.triangulate` of 3D input (an (n, 3) array, a geometry with
Z, a :class:`~cdt_plugin.PLC` with ``z``) finds the input's plane
(:func:`fit_plane`: the least-squares plane of the vertices), checks that
every vertex lies on it (:func:`check_planar`: within ``plane_tolerance``, or
exactly), and triangulates the vertices' projection on the axis-aligned coordinate plane where the normal's largest
component is (:class:`Plane`).

Why that projection, and not an orthonormal frame of the plane: dropping one
coordinate is exact, so the 2D coordinates of the input vertices are theirs
bit for bit and every decision of the constrained Delaunay triangulation
(exact predicates) is made on the input itself; a rotated frame would round
every vertex and could turn a valid polygon into a crossing one. Projecting
along the normal's largest component is an affine bijection of the plane, so
it keeps the triangulation's topology; the triangles are constrained Delaunay
in the projection (not in the plane's own metric, unless the plane is
horizontal; the same holds for quality bounds).

The result keeps the plane (``tri.plane``) and the dropped coordinate of the
input vertices; ``tri.vertices3d`` is every vertex in 3D: the input vertices
exactly as given, the Steiner points on the plane (their dropped coordinate
from the plane's equation). A horizontal input (all z equal) is triangulated
in x, y exactly as 2D input is, and keeps its z.

>>> import numpy as np, cdt_plugin
>>> wall = [[0, 0, 0], [4, 0, 0], [4, 0, 3], [0, 0, 3]]     # the plane y = 0
>>> tri = cdt_plugin.triangulate(wall, [[0, 1], [1, 2], [2, 3], [3, 0]])
>>> tri.plane.normal.tolist(), len(tri.triangles), tri.vertices3d[:, 1].tolist()
([0.0, 1.0, 0.0], 2, [0.0, 0.0, 0.0, 0.0])
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import CDTError, InputShapeError, NonPlanarError

#: The default ``plane_tolerance``, in roundings of the coordinates: a vertex
#: may lie this many times ``eps * max|coordinate|`` (``eps = 2**-52``) off the
#: fitted plane. Points rotated into a plane and rounded to doubles lie off it
#: by a few such roundings; so does the fitted plane itself.
PLANE_ROUNDINGS = 64.0


@dataclass(frozen=True)
class Plane:
    """The plane of a 3D input and its 2D coordinates.

    Attributes
    ----------
    normal : (3,) float64
        Unit normal, its largest component (``axes[2]``) positive: the
        triangles are counter-clockwise seen from its tip.
    point : (3,) float64
        A point of the plane (the centroid of the input vertices).
    axes : (3,) tuple of int
        ``(u, v, w)``: the triangulation's 2D coordinates are the input's
        coordinates ``u`` and ``v`` (``(0, 1)``, x and y, for a horizontal
        plane); ``w`` is the dropped one, the normal's largest component.
    """

    normal: NDArray[np.float64]
    point: NDArray[np.float64]
    axes: tuple[int, int, int]

    @classmethod
    def from_normal(cls, normal: ArrayLike, point: ArrayLike) -> Plane:
        """The plane through ``point`` with normal ``normal`` (any length and
        sign; made unit, its largest component positive)."""
        n = np.asarray(normal, np.float64)
        # ties go to z, then x: a horizontal plane keeps x, y
        w = max((2, 0, 1), key=lambda k: abs(n[k]))
        n = n / np.linalg.norm(n)
        if n[w] < 0:
            n = -n
        n = n + 0.0                     # (no negative zeros)
        # (u, v) = the two other axes in cyclic order: the projection keeps the
        # orientation seen from +w, which is the normal's side
        return cls(n, np.asarray(point, np.float64), ((w + 1) % 3, (w + 2) % 3, w))

    @property
    def area_scale(self) -> float:
        """The projection's area over the area in the plane (the normal's
        largest component, in (1/sqrt(3), 1])."""
        return float(self.normal[self.axes[2]])

    @property
    def horizontal(self) -> bool:
        """Whether the plane is z = constant (normal exactly (0, 0, 1))."""
        return self.axes[2] == 2 and self.normal[0] == 0.0 and self.normal[1] == 0.0

    def project(self, xyz: NDArray[np.float64]) -> NDArray[np.float64]:
        """The 2D coordinates (u, v) of 3D points: two of their coordinates, exactly."""
        return np.ascontiguousarray(xyz[:, list(self.axes[:2])])

    def dropped(self, uv: NDArray[np.float64]) -> NDArray[np.float64]:
        """The dropped coordinate ``w`` of the points of the plane at ``uv``
        (from the plane's equation)."""
        u, v, w = self.axes
        n, p = self.normal, self.point
        return p[w] - (n[u] * (uv[:, 0] - p[u]) + n[v] * (uv[:, 1] - p[v])) / n[w]

    def distances(self, xyz: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed distances of 3D points from the plane (along ``normal``)."""
        return (xyz - self.point) @ self.normal

    def lift(self, uv: NDArray[np.float64], vertex_map: NDArray[np.int64] | None = None,
             w_in: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """3D points of the plane at ``uv``; with ``vertex_map`` (input vertex ->
        row of ``uv``, -1: none) and ``w_in`` (the input vertices' dropped
        coordinate), the rows of input vertices take their own coordinate
        (a merged duplicate: its first occurrence's)."""
        u, v, w = self.axes
        out = np.empty((len(uv), 3))
        out[:, u], out[:, v] = uv[:, 0], uv[:, 1]
        out[:, w] = self.dropped(uv)
        if vertex_map is not None and w_in is not None:
            kept = np.flatnonzero(vertex_map >= 0)[::-1]      # reversed: the first occurrence wins
            out[vertex_map[kept], w] = w_in[kept]
        return out


def newell_normal(xyz: NDArray[np.float64], segments: NDArray[np.int64]) -> NDArray[np.float64]:
    """Newell's normal of closed rings given as directed segments: twice the
    vector area, summed (a hole wound either way leaves the shell's side).
    Computed about the centroid, which keeps far-off coordinates accurate."""
    c = xyz - xyz.mean(axis=0)
    a, b = c[segments[:, 0]], c[segments[:, 1]]
    return np.cross(a, b).sum(axis=0)


def best_fit_normal(xyz: NDArray[np.float64]) -> NDArray[np.float64]:
    """The normal of the least-squares plane of the points: the last right
    singular vector of their centred coordinates (the SVD of the points
    themselves, not the eigenvectors of their covariance, whose condition is
    the square); (0, 0, 1) for a single point."""
    c = xyz - xyz.mean(axis=0)
    if not c.any():
        return np.array([0.0, 0.0, 1.0])
    return np.linalg.svd(c / np.abs(c).max(), full_matrices=False)[2][-1]


def fit_plane(xyz: NDArray[np.float64]) -> Plane:
    """The plane of 3D points: z = constant when all z are equal (exactly);
    else the least-squares plane (:func:`best_fit_normal`, through the
    centroid), the plane the points are nearest, which the planarity check
    measures against.

    Why not Newell's normal of the rings, the usual estimate for polygons: on
    3,000 random polygons rotated into random planes and rounded to doubles,
    the farthest vertex lay at most 4 roundings of the largest coordinate from
    the least-squares plane, but up to 214 from Newell's plane for thin
    polygons (1000 times longer than wide), whose normal Newell's sum gets
    from small cross products. (Newell's normal gives the side a ring winds
    about: :func:`newell_normal`.)

    >>> plane = fit_plane(np.array([[0, 0, 1.0], [2, 0, 2], [0, 1, 1]]))    # z = x / 2 + 1
    >>> (plane.normal.round(6) + 0.0).tolist(), plane.axes
    ([-0.447214, 0.0, 0.894427], (0, 1, 2))
    """
    z = xyz[:, 2]
    if (z == z[0]).all():
        return Plane(np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, z[0]]), (0, 1, 2))
    return Plane.from_normal(best_fit_normal(xyz), xyz.mean(axis=0))


def check_plane_tolerance(value: object) -> float | None:
    """``plane_tolerance`` checked: None, or a finite number >= 0 (else a
    :class:`CDTError` naming it)."""
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not 0 <= float(value) < np.inf:
        raise CDTError(f"plane_tolerance must be a finite number >= 0 (a distance), got {value!r}")
    return float(value)


def default_tolerance(xyz: NDArray[np.float64]) -> float:
    """``PLANE_ROUNDINGS`` roundings of the largest coordinate."""
    return float(PLANE_ROUNDINGS * np.finfo(np.float64).eps * np.abs(xyz).max())


def check_planar(xyz: NDArray[np.float64], plane: Plane, tolerance: float | None = None) -> None:
    """Raise :class:`NonPlanarError` naming the vertex farthest from ``plane``
    when it lies farther than ``tolerance`` (None: :func:`default_tolerance`;
    0: the points must be exactly coplanar, decided in exact arithmetic)."""
    if plane.horizontal and (xyz[:, 2] == plane.point[2]).all():
        return                      # z = constant, exactly
    if tolerance == 0:
        _check_exactly_planar(xyz, plane)
        return
    tol = default_tolerance(xyz) if tolerance is None else float(tolerance)
    d = np.abs(plane.distances(xyz))
    far = int(np.argmax(d))
    if d[far] > tol:
        _raise_non_planar(xyz, plane, far, float(d[far]), tol, int((d > tol).sum()))


def _raise_non_planar(xyz, plane, far, distance, tol, count):
    bound = "exactly" if tol == 0 else f"within plane_tolerance={tol!r}"
    raise NonPlanarError(
        f"the 3D input is not planar: vertex {far} {xyz[far].tolist()} lies {distance!r} from the "
        f"plane through {plane.point.tolist()} with normal {plane.normal.tolist()} "
        f"({count} vertices not on it {bound}); pass a larger plane_tolerance if the input "
        "is planar up to its precision", vertex=far, distance=distance,
        point=tuple(float(c) for c in xyz[far]), tolerance=tol)


def _check_exactly_planar(xyz: NDArray[np.float64], plane: Plane) -> None:
    """Exact coplanarity: doubles are dyadic rationals, so every point's
    orientation against three spanning points is an exact integer
    determinant (Python integers)."""
    a = int(np.argmax(np.abs(xyz - xyz.mean(axis=0)).sum(axis=1)))
    b = int(np.argmax(np.abs(xyz - xyz[a]).sum(axis=1)))
    c = int(np.argmax(np.linalg.norm(np.cross(xyz[b] - xyz[a], xyz - xyz[a]), axis=1)))
    F = [[Fraction(float(v)) for v in xyz[i]] for i in (a, b, c)]
    e1 = [F[1][k] - F[0][k] for k in range(3)]
    e2 = [F[2][k] - F[0][k] for k in range(3)]
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    if not any(n):
        return                      # every point on one line
    off = []
    for i, p in enumerate(xyz.tolist()):
        if sum(n[k] * (Fraction(p[k]) - F[0][k]) for k in range(3)) != 0:
            off.append(i)
    if off:
        exact = Plane.from_normal([float(v) for v in n], xyz[a])
        d = np.abs(exact.distances(xyz[off]))
        far = off[int(np.argmax(d))]
        _raise_non_planar(xyz, exact, far, float(d.max()), 0.0, len(off))


def ring_projection(xy: NDArray[np.float64], z: NDArray[np.float64], begin: NDArray[np.int64],
                    end: NDArray[np.int64]) -> NDArray[np.float64]:
    """The 2D coordinates rings with z are read in (their degenerate rings
    found, their segments made): ``xy`` for horizontal or partial z, else the
    projection :func:`planar_plc` meshes them in, so a wall (a vertical ring)
    is no line."""
    if not (end > begin).any() or (z == z[0]).all() or not np.isfinite(z).all() \
            or not np.isfinite(xy).all():
        return xy
    xyz = np.column_stack([xy, z])
    return fit_plane(xyz).project(xyz)


def planar_plc(plc: Any, tolerance: float | None = None) -> tuple[Any, Plane]:
    """A :class:`~cdt_plugin.PLC` with ``z`` (3D input) as the PLC of its projection on its plane,
    whose ``z`` is the input vertices' dropped coordinate, and the plane;
    :class:`NonPlanarError` when a vertex lies off the plane.
    Seeds given in 3D, ``plc.holes`` as (h, 3) points and ``plc.regions`` as
    (r, 5) rows ``x, y, z, attribute, max_area``, are projected the same way
    (:func:`projected_seeds`); 2D seeds are in the projection's coordinates."""
    assert plc.z is not None
    z = np.asarray(plc.z, np.float64)
    if np.isnan(z).any():
        i = int(np.flatnonzero(np.isnan(z))[0])
        raise InputShapeError(f"vertex {i} has no z while others have one: 3D input needs z "
                              "on every vertex")
    xyz = np.column_stack([plc.vertices, z])
    plane = fit_plane(xyz)
    check_planar(xyz, plane, tolerance)
    changes: dict = {}
    if plane.axes != (0, 1, 2):     # (else x, y as they are, z the dropped coordinate)
        changes = {"vertices": plane.project(xyz), "z": np.ascontiguousarray(xyz[:, plane.axes[2]])}
    if plc.holes is not None and plc.holes.shape[1] == 3:
        changes["holes"] = projected_seeds(plc.holes, "hole", xyz, plane, tolerance)
    regions = plc.regions
    if regions is not None and regions.shape[1] == 5:
        regions = np.column_stack([projected_seeds(regions[:, :3], "region", xyz, plane, tolerance),
                                   regions[:, 3:]])
    if regions is not None and plane.area_scale != 1.0:
        regions = regions.copy()                # (their max_area: an area in the plane)
        regions[:, 3] *= plane.area_scale
    if regions is not plc.regions:
        changes["regions"] = regions
    return (dataclasses.replace(plc, **changes) if changes else plc), plane


def projected_seeds(seeds: NDArray[np.float64], kind: str, xyz: NDArray[np.float64], plane: Plane,
                    tolerance: float | None = None) -> NDArray[np.float64]:
    """3D seed points (``kind``: "hole" or "region") of the 3D input ``xyz``
    on its ``plane``, projected as its vertices are (:meth:`Plane.project`:
    exact), or :class:`NonPlanarError` naming the seed farthest from the plane
    when it lies farther than ``tolerance`` (None or 0: :func:`default_tolerance`
    of the vertices and seeds; a seed only picks a region, so exact
    coplanarity is asked of the vertices alone)."""
    if len(seeds):
        tol = tolerance if tolerance else default_tolerance(np.vstack([xyz, seeds]))
        d = np.abs(plane.distances(seeds))
        far = int(np.argmax(d))
        if not d[far] <= tol:
            raise NonPlanarError(
                f"{kind} seed {far} {seeds[far].tolist()} lies {float(d[far])!r} from the plane of the "
                f"3D input (through {plane.point.tolist()} with normal {plane.normal.tolist()}), "
                f"farther than plane_tolerance={tol!r}: a 3D seed must be a point of the plane "
                f"(or give it in the 2D coordinates the input is meshed in, axes {list(plane.axes[:2])})",
                distance=float(d[far]), point=tuple(float(c) for c in seeds[far]), tolerance=tol)
    return plane.project(seeds)
