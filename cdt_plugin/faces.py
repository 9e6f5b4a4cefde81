"""A planar-faced model in one call: every face (a 3D polygon with holes, in its
own plane) triangulated in its plane (:mod:`cdt_plugin.planar`), the faces'
triangles concatenated into one mesh.

>>> import cdt_plugin
>>> box = [[(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)], [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],
...        [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], [(1, 1, 0), (0, 1, 0), (0, 1, 1), (1, 1, 1)],
...        [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)], [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)]]
>>> mesh = cdt_plugin.triangulate_faces([[ring] for ring in box], merge=True)
>>> mesh.vertices.shape, mesh.triangles.shape, mesh.face.tolist()
((8, 3), (12, 3), [0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5])
"""
from __future__ import annotations

from typing import Any, Iterable, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .cdt import triangulate
from .errors import CDTError, InputShapeError
from .planar import newell_normal


class FaceMesh(NamedTuple):
    """The mesh of a planar-faced model.

    Attributes
    ----------
    vertices : (n, 3) float64
        Every face's vertices in turn (``merge``: each distinct point once).
        Input vertices are exactly the input points; Steiner points lie on
        their face's plane.
    triangles : (k, 3) int64
        Every face's triangles in turn, each wound as its face's outer ring
        (counter-clockwise seen from the side the ring winds around).
    face : (k,) int64
        The face each triangle comes from.
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    face: NDArray[np.int64]


def _polygon(face: Any) -> Any:
    """A face as something :func:`triangulate` reads: a geometry (or its
    mapping) as it is, a list of 3D rings (outer first, then holes) as a
    GeoJSON Polygon mapping."""
    if hasattr(face, "__geo_interface__") or isinstance(face, dict):
        return face
    rings = [np.asarray(ring, dtype=np.float64) for ring in face]
    return {"type": "Polygon", "coordinates": [
        ring if len(ring) and np.array_equal(ring[0], ring[-1]) else np.vstack([ring, ring[:1]])
        for ring in rings]}


def triangulate_faces(faces: Iterable[Any], *, merge: bool = False, **options: Any) -> FaceMesh:
    """Triangulate a planar-faced polygonal model (the faces of an OBJ, a
    CityJSON-like list of surfaces with holes) in one call.

    Parameters
    ----------
    faces : iterable
        Each face a list of 3D rings (``(k, 3)`` points, outer ring first, then
        its holes; closed or not), a shapely Polygon Z or a GeoJSON Polygon
        mapping with z. Each is triangulated in its own plane
        (:func:`cdt_plugin.triangulate` of 3D input).
    merge : bool
        Merge the vertices that are exactly equal (across faces too), so faces
        that share vertices share them in the mesh: a closed model whose faces
        meet at their vertices then gives a watertight mesh (add no Steiner
        points on shared edges: no refinement, or ``split_boundary=False``).
    **options
        :func:`cdt_plugin.triangulate`'s options (``plane_tolerance``,
        ``min_angle``, ``max_area``...), for every face.

    Returns
    -------
    FaceMesh
        ``vertices``, ``triangles`` and the ``face`` of each triangle. A face
        that fails raises its error (:class:`NonPlanarError`...) with
        ``index`` set to its position.
    """
    vertices, triangles, owner = [], [], []
    start = 0
    for i, face in enumerate(faces):
        polygon = _polygon(face)
        try:
            outer = _outer_normal(polygon)
            tri = triangulate(polygon, **options)
        except CDTError as e:
            e.index = i
            raise
        V, T = tri.vertices3d, np.asarray(tri.triangles, np.int64)
        assert tri.plane is not None           # (3D rings: _outer_normal checked them)
        if outer @ tri.plane.normal < 0:       # (the triangles wind about the plane's normal)
            T = T[:, ::-1]
        vertices.append(V)
        triangles.append(T + start)
        owner.append(np.full(len(T), i, np.int64))
        start += len(V)
    if not vertices:
        return FaceMesh(np.empty((0, 3)), np.empty((0, 3), np.int64), np.empty(0, np.int64))
    V, T = np.concatenate(vertices), np.concatenate(triangles)
    if merge:
        V, inverse = np.unique(V, axis=0, return_inverse=True)
        T = inverse.reshape(-1)[T]
    return FaceMesh(V, T, np.concatenate(owner))


def _outer_normal(polygon: Any) -> NDArray[np.float64]:
    """Newell's normal of a face's outer ring, as it winds (its 3D points)."""
    mapping = polygon.__geo_interface__ if hasattr(polygon, "__geo_interface__") else polygon
    if mapping.get("type") != "Polygon" or not len(mapping.get("coordinates", ())):
        raise InputShapeError(f"a face must be a Polygon (or a list of 3D rings), got "
                              f"{mapping.get('type')!r}")
    ring = np.asarray(mapping["coordinates"][0], dtype=np.float64)
    if ring.ndim != 2 or ring.shape[1] != 3:
        raise InputShapeError(f"a face's rings must be (k, 3) points, got shape {ring.shape}")
    k = np.arange(len(ring))
    return newell_normal(ring, np.column_stack([k, (k + 1) % len(ring)]))
