"""What closed solids are built from, by vertex index: the boundary of a 2D
triangulation and the pinch vertices where it passes more than once.

The extrusions of the trimesh adapter (``extrude_triangulation``, the sweeps)
and of the GIS adapter (``geo.extrude``) build their walls on the boundary
edges of a triangulation, and split its pinch vertices first (a hole touching
its shell or another hole at a point), so that every edge of the solid lies in
exactly two of its triangles. Both use these two functions.

>>> import numpy as np
>>> from cdt_plugin.solids import boundary_edges, split_pinches
>>> V = np.array([[0, 0], [2, 0], [1, 1], [2, 2], [0, 2]], float)
>>> T = np.array([[0, 1, 2], [2, 3, 4]])        # two triangles meeting at vertex 2
>>> boundary_edges(T, len(V)).tolist()
[[0, 1], [2, 3], [1, 2], [3, 4], [2, 0], [4, 2]]
>>> V2, T2 = split_pinches(V, T)
>>> len(V2), T2.tolist()
(6, [[0, 1, 2], [5, 3, 4]])
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def boundary_edges(T: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """The directed edges ``(i, j)`` of the triangles ``T`` (vertices below
    ``n``) whose reverse ``(j, i)`` is no edge of them: for consistently wound
    counter-clockwise triangles, the boundary with the domain on its left.

    One sort of the edge keys and one search for their reverses (a set test of
    each edge's reverse costs about 15 times as much on a layer of footprints).
    """
    E = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]).astype(np.int64, copy=False)
    if not len(E):
        return E.reshape(0, 2)
    key = np.sort(E[:, 0] * n + E[:, 1])
    reverse = E[:, 1] * n + E[:, 0]
    at = np.minimum(np.searchsorted(key, reverse), len(key) - 1)
    return E[key[at] != reverse]


def split_pinches(V: NDArray[np.float64], T: NDArray[np.int64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A copy of every pinch vertex (where the boundary passes more than once: a
    hole touching its shell or another hole at a point) for each fan of
    counter-clockwise triangles around it after the first, so that walls built
    on the boundary meet in manifold edges. The copies go at the end of ``V``
    (same coordinates); ``V`` and ``T`` come back as they are without pinches.

    Vectorised: only the corners at pinch vertices are looked at; each corner's
    neighbour around its vertex is the corner whose incoming edge is its
    outgoing one, and each fan is labelled by its first corner (pointer
    doubling along the chain).
    """
    n = len(V)
    pinched = np.bincount(boundary_edges(T, n)[:, 0], minlength=n) > 1
    t, c = np.nonzero(pinched[T])
    if not len(t):
        return V, T
    v = T[t, c]
    out_key = v * n + T[t, (c + 1) % 3]            # v -> next corner of the triangle
    in_key = v * n + T[t, (c + 2) % 3]             # (previous corner -> v), reversed
    order = np.argsort(in_key)
    at = np.minimum(np.searchsorted(in_key[order], out_key), len(order) - 1)
    follower = np.where(in_key[order][at] == out_key, order[at], -1)   # across the edge v -> next
    first = np.arange(len(t))                      # the corner that starts each one's fan
    first[follower[follower >= 0]] = np.flatnonzero(follower >= 0)
    for _ in range(max(len(t).bit_length(), 1)):
        first = first[first]
    fans, fan_of = np.unique(first, return_inverse=True)
    fan_vertex = v[fans]
    by_vertex = np.lexsort((fans, fan_vertex))
    keeps = np.ones(len(fans), bool)               # the first fan of each vertex keeps it
    keeps[by_vertex[1:]] = fan_vertex[by_vertex[1:]] != fan_vertex[by_vertex[:-1]]
    new_id = np.where(keeps, fan_vertex, -1)
    copies = np.flatnonzero(~keeps)
    new_id[copies] = n + np.arange(len(copies))
    T = T.copy()
    T[t, c] = new_id[fan_of.ravel()]
    return np.concatenate([V, V[fan_vertex[copies]]]), T
