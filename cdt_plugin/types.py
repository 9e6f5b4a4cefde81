"""Plain types and protocols of cdt_plugin: what a mesh, a triangulation and a
geometry look like to the code that takes them.

The services below the result class (errors, report, plot, voronoi, queries,
io, lift) annotate with these protocols instead of importing
:class:`cdt_plugin.Triangulation`, as trimesh's services take duck-typed meshes:
so no module imports the result class for a type, and the result class imports
its services, not the other way round. This module imports nothing of the
package.

>>> import cdt_plugin
>>> from cdt_plugin.types import TriangulationLike
>>> isinstance(cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]]), TriangulationLike)
True
"""
from __future__ import annotations

from typing import Any, Dict, Mapping, Protocol, Tuple, Union, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["FacesMesh", "GeometryLike", "MeshLike", "MeshStore", "SupportsGeoInterface",
           "TriangulationLike"]

#: The half-edge store of a result in output ids: ``(tri, twin, cons, ntri, inf)``.
MeshStore = Tuple[NDArray[np.int32], NDArray[np.int32], NDArray[np.int32], int, int]


class SupportsGeoInterface(Protocol):
    """Anything with ``__geo_interface__`` (shapely geometries, GeoJSON-like objects)."""

    @property
    def __geo_interface__(self) -> Mapping[str, Any]: ...


#: A geometry: an object with ``__geo_interface__``, or the GeoJSON-like mapping itself.
GeometryLike = Union[SupportsGeoInterface, Mapping[str, Any]]


@runtime_checkable
class TriangulationLike(Protocol):
    """What the services read of a triangulation (a :class:`cdt_plugin.Triangulation`):
    its arrays, counts and exact certificate."""

    @property
    def vertices(self) -> NDArray[np.float64]: ...

    @property
    def triangles(self) -> NDArray[np.int64]: ...

    @property
    def neighbors(self) -> NDArray[np.int64]: ...

    @property
    def vertex_map(self) -> NDArray[np.int64]: ...

    @property
    def weights(self) -> NDArray[np.float64] | None: ...

    @property
    def constrained(self) -> NDArray[np.bool_]: ...

    @property
    def segments(self) -> NDArray[np.int64]: ...

    @property
    def segment_ids(self) -> NDArray[np.int64]: ...

    @property
    def steiner(self) -> NDArray[np.int64]: ...

    @property
    def edges(self) -> NDArray[np.int64]: ...

    @property
    def stats(self) -> Dict[str, Any]: ...

    # the half-edge store of a Delaunay result (None for others): the Voronoi
    # diagram reads its dual from it
    @property
    def _mesh(self) -> MeshStore | None: ...

    def non_delaunay_edges(self) -> NDArray[np.int64]: ...


class FacesMesh(Protocol):
    """A mesh with ``vertices`` and ``faces`` (a ``trimesh.Trimesh``)."""

    @property
    def vertices(self) -> ArrayLike: ...

    @property
    def faces(self) -> ArrayLike: ...


#: Another triangulation to compare with: a Triangulation, a mesh with ``vertices``
#: and ``faces``, or a ``(vertices, triangles)`` pair.
MeshLike = Union[TriangulationLike, FacesMesh, Tuple[ArrayLike, ArrayLike]]
