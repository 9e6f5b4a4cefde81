"""Merging input points closer than a distance (``merge_distance``), compiled.

The rule, deterministic and the same for any input order: the points are taken
in lexicographic order (x, then y, then input index); a point closer than the
distance to a point kept before it is merged into the nearest such point (the
earliest in that order on a tie), otherwise it is kept. So no two kept points
are closer than the distance, and every merged point lies within it of its
representative. Closeness is the floating-point Euclidean distance
(``hypot``). The search goes through a grid of cells at least twice the
distance wide, held in a hash table of the cells that have kept points: each
point looks at the kept points of nine cells only, and kept points are at
least the distance apart, so a cell holds a few of them.
"""
from __future__ import annotations

import math

import numpy as np

from .jit import entry, kernel
from .ordering import lexicographic_order_compiled


@kernel
def cell_slot(table, cx, cy):
    """The slot of cell ``(cx, cy)`` in the open-addressing table (rows ``cx,
    cy, first kept point``, linear probing; a row whose point is -1 is free):
    the cell's own slot, or the free slot where it would go."""
    mask = table.shape[0] - 1
    h = ((cx * 73856093) ^ (cy * 19349663)) & mask
    while table[h, 2] >= 0 and (table[h, 0] != cx or table[h, 1] != cy):
        h = (h + 1) & mask
    return h


#: Cells are at least this fraction of the points' extent wide, so that the cell
#: numbers (below 2**48) are exact whatever the distance: the rounding of
#: ``(x - xmin) / width`` then moves a point by far less than half a cell.
CELL_FLOOR = 2.0 ** -48


@kernel
def cell_numbers(v, width):
    """The cell of every coordinate of ``v`` along its axis, cells ``width``
    wide from the least coordinate (a span beyond float64, or an infinite
    width, puts the points in one cell at most 2**50 along)."""
    n = v.shape[0]
    lo = v[0]
    for i in range(n):
        lo = min(lo, v[i])
    cells = np.empty(n, np.int64)
    for i in range(n):
        q = (v[i] - lo) / width
        if not q > 0.0:                  # (0, or NaN: inf / inf)
            q = 0.0
        cells[i] = np.int64(math.floor(min(q, 2.0 ** 50)))
    return cells


@entry
def close_representatives(xy, order, distance):
    """The representative of every point of ``xy`` (n, 2) (itself when kept)
    by the module's rule, the points taken in ``order`` (their lexicographic
    order; empty: made here), in a grid of cells at least twice ``distance``
    wide and at least ``CELL_FLOOR`` of the points' extent; and how many points
    are moved (merged onto a representative at another position: exact
    duplicates are not counted)."""
    n = xy.shape[0]
    if n == 0:
        return np.empty(0, np.int64), 0
    x, y = np.empty(n), np.empty(n)
    for i in range(n):
        x[i], y[i] = xy[i, 0], xy[i, 1]
    if order.shape[0] != n:
        order = lexicographic_order_compiled(x, y)
    x_lo, x_hi, y_lo, y_hi = x[0], x[0], y[0], y[0]
    for i in range(n):
        x_lo, x_hi = min(x_lo, x[i]), max(x_hi, x[i])
        y_lo, y_hi = min(y_lo, y[i]), max(y_hi, y[i])
    width = max(2.0 * distance, max(x_hi - x_lo, y_hi - y_lo) * CELL_FLOOR)
    table_size = np.int64(1)
    while table_size <= 2 * n:
        table_size *= 2
    rep = merge_representatives(x, y, order, cell_numbers(x, width), cell_numbers(y, width),
                                distance, table_size)
    moved = 0
    for i in range(n):
        if x[rep[i]] != x[i] or y[rep[i]] != y[i]:
            moved += 1
    return rep, moved


@kernel
def merge_representatives(x, y, order, cell_x, cell_y, distance, table_size):
    """The representative of every point (itself when kept): the module's rule
    with the points taken in ``order``; ``(cell_x[i], cell_y[i])`` is point
    ``i``'s cell, of a grid at least twice ``distance`` wide (so a point closer
    than ``distance`` lies in one of the nine cells around); ``table_size``, a
    power of two above twice the number of points, sizes the table of cells."""
    n = x.shape[0]
    rank = np.empty(n, np.int64)
    for k in range(n):
        rank[order[k]] = k
    rep = np.empty(n, np.int64)
    after = np.full(n, -1, np.int64)                   # the kept points of a cell, as a list
    table = np.full((table_size, 3), -1, np.int64)    # (one row per slot: one cache line)
    for k in range(n):
        p = order[k]
        best, best_d = -1, distance
        for dx in range(-1, 2):
            for dy in range(-1, 2):
                q = table[cell_slot(table, cell_x[p] + dx, cell_y[p] + dy), 2]
                while q >= 0:
                    d = math.hypot(x[p] - x[q], y[p] - y[q])
                    if d < best_d or (best >= 0 and d == best_d and rank[q] < rank[best]):
                        best, best_d = q, d
                    q = after[q]
        if best >= 0:
            rep[p] = best
        else:
            rep[p] = p
            h = cell_slot(table, cell_x[p], cell_y[p])
            table[h, 0], table[h, 1] = cell_x[p], cell_y[p]
            after[p] = table[h, 2]
            table[h, 2] = p
    return rep
