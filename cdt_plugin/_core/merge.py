"""Merging input points closer than a distance (``merge_distance``), compiled.

The rule, deterministic and the same for any input order: the points are taken
in lexicographic order (x, then y, then input index); a point closer than the
distance to a point kept before it is merged into the nearest such point (the
earliest in that order on a tie), otherwise it is kept. So no two kept points
are closer than the distance, and every merged point lies within it of its
representative. Closeness is the floating-point Euclidean distance
(``hypot``); the search goes through a grid of cells at least twice the
distance wide, so each point looks at the kept points of nine cells only.
"""
from __future__ import annotations

import math

import numpy as np

from .jit import entry, kernel


@kernel
def find_cell(cell_x, cell_y, cx, cy):
    """Index of the cell ``(cx, cy)`` among the rows ``(cell_x, cell_y)``,
    sorted lexicographically, or -1 when no point lies in it."""
    lo, hi = 0, cell_x.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if cell_x[mid] < cx or (cell_x[mid] == cx and cell_y[mid] < cy):
            lo = mid + 1
        else:
            hi = mid
    if lo < cell_x.shape[0] and cell_x[lo] == cx and cell_y[lo] == cy:
        return lo
    return -1


@entry
def merge_representatives(x, y, order, cell_of, cell_x, cell_y, distance):
    """The representative of every point (itself when kept): the module's rule
    with the points taken in ``order``, ``cell_of[i]`` the row of point ``i``'s
    cell in the sorted cells ``(cell_x, cell_y)``, whose width is at least twice
    ``distance`` (so a point closer than ``distance`` lies in one of the nine
    cells around)."""
    n = x.shape[0]
    rank = np.empty(n, np.int64)
    for k in range(n):
        rank[order[k]] = k
    rep = np.empty(n, np.int64)
    head = np.full(cell_x.shape[0], -1, np.int64)     # kept points of each cell, as a list
    after = np.full(n, -1, np.int64)
    for k in range(n):
        p = order[k]
        c = cell_of[p]
        best, best_d = -1, distance
        for dx in range(-1, 2):
            for dy in range(-1, 2):
                d_cell = find_cell(cell_x, cell_y, cell_x[c] + dx, cell_y[c] + dy)
                q = head[d_cell] if d_cell >= 0 else -1
                while q >= 0:
                    d = math.hypot(x[p] - x[q], y[p] - y[q])
                    if d < best_d or (best >= 0 and d == best_d and rank[q] < rank[best]):
                        best, best_d = q, d
                    q = after[q]
        if best >= 0:
            rep[p] = best
        else:
            rep[p] = p
            after[p] = head[c]
            head[c] = p
    return rep
