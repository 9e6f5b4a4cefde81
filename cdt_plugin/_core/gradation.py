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
def limit_growth(start, targets, lengths, values, slope):
    """``values`` (n,) limited so that along no edge of the graph does a value
    exceed its neighbour's by more than ``slope`` times the edge's length. The
    graph is in compressed rows: the neighbours of node ``i`` are
    ``targets[start[i]:start[i + 1]]`` at ``lengths`` of the same rows."""
    n = values.shape[0]
    out = values.copy()
    done = np.zeros(n, np.bool_)
    keys = np.empty(n + targets.shape[0] + 1)
    nodes = np.empty(n + targets.shape[0] + 1, np.int64)
    size = 0
    for i in range(n):
        size = _push(keys, nodes, size, out[i], i)
    while size > 0:
        key, v = keys[0], nodes[0]
        size = _pop(keys, nodes, size)
        if done[v] or key > out[v]:
            continue        # an older, larger entry of a node already settled
        done[v] = True
        for k in range(start[v], start[v + 1]):
            u = targets[k]
            reach = key + slope * lengths[k]
            if reach < out[u]:
                out[u] = reach
                size = _push(keys, nodes, size, reach, u)
    return out


@kernel
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


@kernel
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
