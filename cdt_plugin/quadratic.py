"""Second-order (six-node) triangles: :meth:`cdt_plugin.Triangulation.quadratic`,
Triangle's ``-o2``.

Each edge gets one node at its midpoint, shared by the two triangles of the
edge; node ``3 + i`` of a triangle is the midpoint of the edge opposite its
corner ``i``, as in Triangle. The midpoints follow the corners, one per row of
the triangulation's ``edges``, in that order. A midpoint's marker is its
edge's (:mod:`cdt_plugin.markers`), its attributes the mean of its ends'.

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
...                              segment_markers=[5, 0, 0, 0], vertex_attributes=[0.0, 2, 4, 2])
>>> mesh = tri.quadratic()
>>> mesh
QuadraticMesh(9 nodes, 2 six-node triangles)
>>> mesh.triangles.tolist()
[[0, 2, 3, 4, 5, 6], [0, 1, 2, 7, 6, 8]]
>>> mesh.vertices[4:].tolist(), mesh.vertex_markers[4:].tolist()
([[1.0, 2.0], [0.0, 1.0], [1.0, 1.0], [2.0, 1.0], [1.0, 0.0]], [1, 1, 0, 1, 5])
>>> mesh.vertex_attributes[4:, 0].tolist()
[3.0, 1.0, 2.0, 3.0, 1.0]
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .optional import require
from .types import TriangulationLike

if TYPE_CHECKING:
    import meshio

__all__ = ["QuadraticMesh", "edge_rows", "quadratic"]


@dataclass(frozen=True)
class QuadraticMesh:
    """A mesh of six-node triangles.

    Attributes
    ----------
    vertices : (n + e, 2) float64
        The corners (the triangulation's vertices), then one midpoint per edge.
    triangles : (k, 6) int64
        Corners counter-clockwise, then node ``3 + i`` at the midpoint of the
        edge opposite corner ``i``.
    edges : (e, 2) int64
        The corner pairs of the edges; edge ``j``'s midpoint is node ``n + j``.
    vertex_markers : (n + e,) int64
        Boundary markers: the corners', then each edge's.
    vertex_attributes : (n + e, a) float64 or None
        The corners' attributes, then the mean of each edge's ends'.
    edge_markers : (e,) int64
        Each edge's boundary marker.
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    edges: NDArray[np.int64]
    vertex_markers: NDArray[np.int64]
    vertex_attributes: NDArray[np.float64] | None
    edge_markers: NDArray[np.int64]

    def __repr__(self) -> str:
        return (f"QuadraticMesh({len(self.vertices)} nodes, {len(self.triangles)} six-node "
                f"triangles)")

    def to_meshio(self) -> meshio.Mesh:
        """This mesh as a ``meshio.Mesh`` (needs meshio): cells of type
        ``"triangle6"`` (meshio's node order is Triangle's corners then the
        midpoints of edges 01, 12, 20), point data ``"vertex_markers"`` and,
        with attributes, ``"vertex_attributes"``."""
        meshio = require("meshio", "QuadraticMesh.to_meshio")
        point_data: dict[str, NDArray[Any]] = {"vertex_markers": self.vertex_markers}
        if self.vertex_attributes is not None:
            point_data["vertex_attributes"] = self.vertex_attributes
        # meshio's triangle6: corners, then midpoints of 0-1, 1-2, 2-0 (opposite 2, 0, 1)
        return meshio.Mesh(self.vertices, [("triangle6", self.triangles[:, [0, 1, 2, 5, 3, 4]])],
                           point_data=point_data)


def quadratic(tri: TriangulationLike, vertex_markers: NDArray[np.int64],
              edge_markers: NDArray[np.int64],
              vertex_attributes: NDArray[np.float64] | None) -> QuadraticMesh:
    """The six-node mesh of ``tri`` with its markers and attributes (see
    :meth:`cdt_plugin.Triangulation.quadratic`)."""
    V = np.asarray(tri.vertices, np.float64)
    E = np.asarray(tri.edges, np.int64).reshape(-1, 2)
    T = np.asarray(tri.triangles, np.int64)
    n = len(V)
    opposite = np.stack([T[:, [1, 2, 0]], T[:, [2, 0, 1]]], axis=-1)   # edge opposite corner 0, 1, 2
    side = edge_rows(E, opposite.reshape(-1, 2)).reshape(-1, 3)
    attributes = None
    if vertex_attributes is not None:
        attributes = np.concatenate([vertex_attributes,
                                     (vertex_attributes[E[:, 0]] + vertex_attributes[E[:, 1]]) / 2])
    return QuadraticMesh(np.concatenate([V, (V[E[:, 0]] + V[E[:, 1]]) / 2]),
                         np.concatenate([T, n + side], axis=1).reshape(-1, 6), E,
                         np.concatenate([vertex_markers, edge_markers]), attributes, edge_markers)


def edge_rows(edges: NDArray[np.int64], pairs: NDArray[np.int64]) -> NDArray[np.int64]:
    """The row of ``edges`` ((e, 2) vertex pairs) that is each of ``pairs`` ((m, 2),
    either direction; each pair must be one of the edges).

    >>> edge_rows(np.array([[0, 1], [1, 2], [2, 0]]), np.array([[2, 1], [0, 2]])).tolist()
    [1, 2]
    """
    n = int(max(edges.max(initial=0), pairs.max(initial=0))) + 1
    key = np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(edges[:, 0], edges[:, 1])
    by = np.argsort(key)
    return by[np.searchsorted(key[by], np.minimum(pairs[:, 0], pairs[:, 1]) * n
                              + np.maximum(pairs[:, 0], pairs[:, 1]))]
