"""Z for every output vertex: 2.5D meshes from polygons with Z.

Meshing is planar; a third coordinate given on the input vertices is carried
along. Input vertices keep their own z (a merged duplicate takes the z of its
first occurrence). A Steiner vertex gets z by linear interpolation:

* on an input segment (a split piece, an intersection point): along that
  segment, between the z of its two input endpoints;
* inside the domain (refinement points): inside the triangle that contains it
  in the constrained Delaunay triangulation of the vertices whose z is known
  (input vertices and points on segments, with the segment pieces as
  constraints), by barycentric coordinates.

The interpolation is floating point; it never decides topology. Vertices
without z (NaN: a 2D polygon in a batch with 3D ones) give NaN, and so do the
Steiner vertices interpolated from them.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.certify import locate_all
from .cdt import triangulate
from .errors import CDTError
from .types import TriangulationLike
from .validate import exact_range, near_unit


def lift_z(tri: TriangulationLike, plc_z: ArrayLike, plc_segments: ArrayLike) -> NDArray[np.float64]:
    """The z of every vertex of ``tri``, a triangulation of a PLC whose input
    vertices have z ``plc_z`` and whose input segments are ``plc_segments``.

    Examples
    --------
    >>> import cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [0, 2]], [[0, 1], [1, 2], [2, 0]],
    ...                              max_area=0.1)
    >>> z = lift_z(tri, [0.0, 2.0, 2.0], [[0, 1], [1, 2], [2, 0]])
    >>> bool(np.allclose(z, tri.vertices[:, 0] + tri.vertices[:, 1]))   # the plane z = x + y
    True
    """
    plc_z = np.asarray(plc_z, dtype=np.float64)
    plc_segments = np.asarray(plc_segments, dtype=np.int64).reshape(-1, 2)
    V, _ = near_unit(np.asarray(tri.vertices, dtype=np.float64))   # interpolation at any scale
    z = np.full(len(V), np.nan)
    vm = np.asarray(tri.vertex_map)
    first = np.flatnonzero(vm >= 0)[::-1]           # reversed: the first occurrence writes last
    z[vm[first]] = plc_z[first]
    steiner = np.asarray(tri.steiner, dtype=np.int64)
    if not len(steiner):
        return z
    _lift_on_segments(tri, V, z, plc_z, plc_segments)
    inner = steiner[np.isnan(z[steiner])]
    if len(inner):
        _lift_inside(tri, V, z, inner)
    return z


def _lift_on_segments(tri, V, z, plc_z, plc_segments):
    """Steiner vertices on segment pieces: linear along the input segment."""
    pieces = np.asarray(tri.segments, dtype=np.int64).reshape(-1, 2)
    sid = np.asarray(tri.segment_ids, dtype=np.int64)
    if not len(pieces):
        return
    v = pieces.ravel()
    s = np.repeat(sid, 2)
    want = np.isnan(z[v]) & (s >= 0)
    v, s = v[want], s[want]
    if not len(v):
        return
    a, b = plc_segments[s, 0], plc_segments[s, 1]
    vm = np.asarray(tri.vertex_map)
    A, B = V[vm[a]], V[vm[b]]
    d = B - A
    t = ((V[v] - A) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), np.finfo(float).tiny)
    t = np.clip(t, 0.0, 1.0)
    z[v] = plc_z[a] + t * (plc_z[b] - plc_z[a])


def _lift_inside(tri, V, z, inner):
    """Interior Steiner vertices: barycentric in the CDT of the known vertices."""
    known = np.flatnonzero(~np.isnan(z))
    if len(known) < 3:          # no z to interpolate from (a 2D polygon in a 3D batch)
        return
    local = np.full(len(V), -1, np.int64)
    local[known] = np.arange(len(known))
    pieces = np.asarray(tri.segments, dtype=np.int64).reshape(-1, 2)
    pieces = pieces[(local[pieces] >= 0).all(axis=1)]
    try:
        base = triangulate(V[known], local[pieces], keep_hull=True, intersections="split")
    except CDTError:            # the known vertices are collinear: nothing to interpolate in
        return
    BV = base.vertices
    bz = np.full(len(BV), np.nan)
    bz[base.vertex_map] = z[known]
    T = base.triangles
    # located exactly at any scale: both point sets scaled by one power of two
    x, y, _, _ = exact_range(np.r_[BV[:, 0], V[inner, 0]], np.r_[BV[:, 1], V[inner, 1]])
    nb = len(BV)
    k = locate_all(x[:nb].copy(), y[:nb].copy(), T, base.neighbors, x[nb:].copy(), y[nb:].copy())
    found = k >= 0
    z[inner[found]] = _barycentric(BV[T[k[found]]], bz[T[k[found]]], V[inner[found]])


def _barycentric(P, pz, q):
    """z at points ``q`` (m, 2) of the planes through triangles ``P`` (m, 3, 2)
    with heights ``pz`` (m, 3)."""
    d1, d2, dq = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0], q - P[:, 0]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    safe = np.where(det == 0, 1.0, det)
    l1 = (dq[:, 0] * d2[:, 1] - d2[:, 0] * dq[:, 1]) / safe
    l2 = (d1[:, 0] * dq[:, 1] - dq[:, 0] * d1[:, 1]) / safe
    out = pz[:, 0] + l1 * (pz[:, 1] - pz[:, 0]) + l2 * (pz[:, 2] - pz[:, 0])
    return np.where(det == 0, np.nanmean(pz, axis=1), out)
