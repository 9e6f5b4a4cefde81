"""A gradation limit on values over a graph (a size field's growth, Persson's
``|grad h| <= g``): :func:`limit_growth`.

The limited value of a node is the smallest, over every node ``j``, of
``values[j] + slope * d(i, j)`` with ``d`` the shortest-path length along the
graph's edges: Dijkstra's algorithm from every node at once, each starting at
its own value. Floating point throughout: sizes are not topology.
"""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel


@entry
def limit_growth(vertices, triangles, values, order, slope):
    """The sizes of the nodes of a mesh, ``values`` (nodes ``0..n-1`` its
    vertices, ``n + t`` the centroid of triangle ``t``; inf: none), limited so
    that along no edge of the mesh, nor from a centroid to its triangle's
    corners, does a size exceed its neighbour's by more than ``slope`` times
    the distance; ``order`` sorts ``values`` (numpy's sort beats the compiled
    one). Returns the limited sizes of the centroids."""
    n, m = vertices.shape[0], triangles.shape[0]
    first = np.zeros(n + 1, np.int64)      # the triangles at each vertex, in compressed rows
    for t in range(m):
        for k in range(3):
            first[triangles[t, k] + 1] += 1
    for v in range(n):
        first[v + 1] += first[v]
    fill = first[:n].copy()
    at = np.empty(3 * m, np.int64)
    for t in range(m):
        for k in range(3):
            v = triangles[t, k]
            at[fill[v]] = t
            fill[v] += 1
    px = np.empty(n + m)
    py = np.empty(n + m)
    out = np.empty(n + m)
    for v in range(n):
        px[v], py[v], out[v] = vertices[v, 0], vertices[v, 1], values[v]
    for t in range(m):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        px[n + t] = (vertices[a, 0] + vertices[b, 0] + vertices[c, 0]) / 3.0
        py[n + t] = (vertices[a, 1] + vertices[b, 1] + vertices[c, 1]) / 3.0
        out[n + t] = values[n + t]
    # Dijkstra's order: the nodes by their own value (a sorted array), merged with a
    # heap of the nodes whose value a neighbour lowered (few when the field is graded)
    own = out.copy()
    done = np.zeros(n + m, np.bool_)
    keys = np.empty(12 * m + 1)      # (at most one push per settled node and neighbour)
    nodes = np.empty(12 * m + 1, np.int64)
    size = 0
    p = 0
    while True:
        while p < n + m and done[order[p]]:
            p += 1
        if size > 0 and (p == n + m or keys[0] < own[order[p]]):
            key, v = keys[0], nodes[0]
            size = _pop(keys, nodes, size)
            if done[v] or key > out[v]:
                continue        # an older, larger entry of a node already settled
        elif p < n + m:
            v = order[p]
            key = out[v]
            if key < own[v]:
                continue        # lowered: its heap entry comes first
        else:
            break
        done[v] = True
        if v >= n:          # a centroid: to its corners
            for k in range(3):
                size = _relax(keys, nodes, size, px, py, out, key, slope, v, triangles[v - n, k])
            continue
        for i in range(first[v], first[v + 1]):      # a vertex: its neighbours, its centroids
            t = at[i]
            for k in range(3):
                u = triangles[t, k]
                if u != v:
                    size = _relax(keys, nodes, size, px, py, out, key, slope, v, u)
            size = _relax(keys, nodes, size, px, py, out, key, slope, v, n + t)
    return out[n:].copy()


@entry
def within_limit(vertices, triangles, values, slope):
    """Whether no edge of the mesh, nor any centroid link, has values (nodes as
    :func:`limit_growth` numbers them) farther apart than ``slope`` times its
    length: the limit would change nothing (most smooth fields), and
    :func:`limit_growth`'s search can be spared."""
    n = vertices.shape[0]
    for t in range(triangles.shape[0]):
        cx = (vertices[triangles[t, 0], 0] + vertices[triangles[t, 1], 0] + vertices[triangles[t, 2], 0]) / 3.0
        cy = (vertices[triangles[t, 0], 1] + vertices[triangles[t, 1], 1] + vertices[triangles[t, 2], 1]) / 3.0
        hc = values[n + t]
        for k in range(3):
            a, b = triangles[t, k], triangles[t, (k + 1) % 3]
            d = np.sqrt((vertices[a, 0] - vertices[b, 0]) ** 2 + (vertices[a, 1] - vertices[b, 1]) ** 2)
            if abs(values[a] - values[b]) > slope * d:
                return False
            d = np.sqrt((vertices[a, 0] - cx) ** 2 + (vertices[a, 1] - cy) ** 2)
            if abs(values[a] - hc) > slope * d:
                return False
    return True


@kernel(inline="always")
def _relax(keys, nodes, size, px, py, out, key, slope, v, u):
    """Lower node ``u``'s value to ``key`` plus ``slope`` times its distance
    from node ``v``, if that is lower (queued again); the heap's new size."""
    reach = key + slope * np.sqrt((px[u] - px[v]) ** 2 + (py[u] - py[v]) ** 2)
    if reach < out[u]:
        out[u] = reach
        size = _push(keys, nodes, size, reach, u)
    return size


@kernel(inline="always")
def _push(keys, nodes, size, key, node):
    """Add ``(key, node)`` to the binary heap of ``size`` entries; its new size."""
    i = size
    while i > 0:
        parent = (i - 1) // 2
        if keys[parent] <= key:
            break
        keys[i] = keys[parent]
        nodes[i] = nodes[parent]
        i = parent
    keys[i] = key
    nodes[i] = node
    return size + 1


@kernel(inline="always")
def _pop(keys, nodes, size):
    """Remove the heap's smallest entry (its root); the heap's new size."""
    size -= 1
    key, node = keys[size], nodes[size]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and keys[child + 1] < keys[child]:
            child += 1
        if keys[child] >= key:
            break
        keys[i] = keys[child]
        nodes[i] = nodes[child]
        i = child
    keys[i] = key
    nodes[i] = node
    return size


@entry
def triangle_measures(vertices, triangles):
    """The centroid ``(cx, cy)``, area and longest edge of every triangle
    (floating point; the area inf where it overflows), in one pass."""
    m = triangles.shape[0]
    cx = np.empty(m)
    cy = np.empty(m)
    area = np.empty(m)
    longest = np.empty(m)
    for t in range(m):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        ax, ay = vertices[a, 0], vertices[a, 1]
        bx, by = vertices[b, 0], vertices[b, 1]
        qx, qy = vertices[c, 0], vertices[c, 1]
        cx[t] = (ax + bx + qx) / 3.0
        cy[t] = (ay + by + qy) / 3.0
        d = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax)
        area[t] = np.inf if np.isnan(d) else 0.5 * abs(d)
        longest[t] = np.sqrt(max((bx - ax) ** 2 + (by - ay) ** 2, (qx - bx) ** 2 + (qy - by) ** 2,
                                 (ax - qx) ** 2 + (ay - qy) ** 2))
    return cx, cy, area, longest
