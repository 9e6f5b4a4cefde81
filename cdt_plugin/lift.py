"""Z for every output vertex: 2.5D meshes from polygons with Z.

Meshing is planar; a third coordinate given on the input vertices is carried
along as a vertex attribute (:mod:`cdt_plugin.markers`, one implementation for
z and for ``triangulate(..., vertex_attributes=)``). Input vertices keep their
own z (a merged duplicate takes the z of its first occurrence). A Steiner
vertex gets z by linear interpolation:

* on an input segment (a split piece, an intersection point): along that
  segment, between the z of its two input endpoints;
* inside the domain (refinement points): inside the triangle that contains it
  in the constrained Delaunay triangulation of the input before refinement
  (:func:`cdt_plugin.cdt.unrefined_base`), by barycentric coordinates.

The interpolation is floating point; it never decides topology. Vertices
without z (NaN: a 2D polygon in a batch with 3D ones) give NaN, and so do the
Steiner vertices interpolated from them.
"""
from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .cdt import unrefined_base
from .errors import CDTError
from .markers import BaseMesh, Tags, vertex_attributes
from .types import TriangulationLike


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
    z = np.asarray(plc_z, dtype=np.float64).reshape(-1, 1)
    segments = np.asarray(plc_segments, dtype=np.int64).reshape(-1, 2)
    # the base is made from the input points as the result holds them (their first copies)
    vm = np.asarray(tri.vertex_map)
    inputs = np.flatnonzero(vm >= 0)
    first = np.full(len(tri.vertices), len(vm))
    np.minimum.at(first, vm[inputs], inputs)
    distinct = first < len(vm)
    base = functools.partial(_base_or_none, np.asarray(tri.vertices)[distinct], vm[segments],
                             z[first[distinct]])
    lifted = vertex_attributes(tri, Tags(segments, vertex_attributes=z, base=base))
    assert lifted is not None
    return lifted[:, 0]


def _base_or_none(vertices, segments, z) -> BaseMesh:
    """:func:`unrefined_base`, or a mesh without triangles where the points are
    collinear or their segments cannot be triangulated again (NaN z then)."""
    try:
        return unrefined_base(vertices, segments[segments[:, 0] != segments[:, 1]], z)
    except CDTError:
        return vertices, np.empty((0, 3), np.int64), z
