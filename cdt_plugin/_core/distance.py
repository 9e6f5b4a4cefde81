"""Distances from many query points to many points and segments, through a
uniform grid of buckets (the kernel of :func:`cdt_plugin.size_near`).

A *source* is a segment ``(ax, ay) - (bx, by)``; a point is a segment of length
zero. :func:`bucket_grid` lays a grid of square cells over the sources' bounding
box (about one cell per source) and lists in each cell the sources that pass
through it, in compressed rows (``start``, ``items``). :func:`nearest_distances`
searches, for each query point, the rings of cells around the cell it falls in
(Chebyshev distance ``r = 0, 1, 2...`` from it, clipped to the grid), skips a
cell whose box is farther than the nearest source found so far, and stops when
that source is closer than anything in the rings not yet searched can be:
``(r - 1) h`` for cell side ``h``. Beyond ``limit`` nothing is searched (the
size field is constant there).

Floating point, not exact predicates: these distances set mesh sizes, they
decide no topology.
"""
from __future__ import annotations

import math

import numpy as np

from .jit import entry, kernel

#: Query cells beyond this many cells from the grid are clamped (coordinates 2**40
#: cells away are no meshing query; the clamp keeps the cell numbers in int64).
FAR_CELLS = 2.0 ** 40


@kernel(forceinline=True)
def segment_distance2(px, py, ax, ay, bx, by):
    """The squared distance from ``(px, py)`` to the segment ``a b`` (a point
    when ``a == b``)."""
    dx = bx - ax
    dy = by - ay
    length2 = dx * dx + dy * dy
    t = 0.0
    if length2 > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / length2
        t = min(max(t, 0.0), 1.0)
    ex = ax + t * dx - px
    ey = ay + t * dy - py
    return ex * ex + ey * ey


@kernel
def cell_side(width, height, sources):
    """The side of the grid's square cells: about one cell per source, at most
    ``sources + 1`` cells along either axis (a thin box is not cut into slivers
    of cells); 1.0 when the box is a single point."""
    n = max(sources, 1)
    h = max(math.sqrt(width) * math.sqrt(height) / math.sqrt(n), width / n, height / n)
    if not (h > 0.0) or not math.isfinite(h):
        h = 1.0 if not (max(width, height) > 0.0) else max(width, height)
    return h


@kernel
def column_rows(i, x0, y0, h, ny, ax, ay, bx, by):
    """The rows ``(j0, j1)`` of column ``i``'s cells that the segment ``a b`` passes
    through (padded by a millionth of a cell against rounding), clipped to the grid."""
    xl = max(min(ax, bx), x0 + i * h)
    xr = min(max(ax, bx), x0 + (i + 1) * h)
    if bx != ax:
        yl = ay + (by - ay) * ((xl - ax) / (bx - ax))
        yr = ay + (by - ay) * ((xr - ax) / (bx - ax))
    else:
        yl, yr = ay, by
    pad = 1e-6 * h
    j0 = int(math.floor((min(yl, yr) - pad - y0) / h))
    j1 = int(math.floor((max(yl, yr) + pad - y0) / h))
    return max(j0, 0), min(j1, ny - 1)


@kernel
def source_columns(x0, h, nx, ax, bx):
    """The columns ``(i0, i1)`` that a segment from x ``ax`` to ``bx`` spans."""
    i0 = int(math.floor((min(ax, bx) - x0) / h))
    i1 = int(math.floor((max(ax, bx) - x0) / h))
    return max(i0, 0), min(i1, nx - 1)


@entry
def bucket_grid(ax, ay, bx, by):
    """The grid of buckets over the sources ``(ax[s], ay[s]) - (bx[s], by[s])``
    (finite float64 arrays, at least one source): ``(x0, y0, h, nx, ny, start,
    items)``, cell ``(i, j)`` (column ``i``, row ``j``, lower-left corner
    ``(x0 + i h, y0 + j h)``) holding the sources
    ``items[start[c]:start[c + 1]]`` for ``c = j nx + i``."""
    m = ax.shape[0]
    # (a loop, not numpy's min and max: their compiled implementation makes a new process
    # whose routes come from the cache import numba's array maths, and scipy)
    x0, y0, x1, y1 = math.inf, math.inf, -math.inf, -math.inf
    for s in range(m):
        x0, x1 = min(x0, ax[s], bx[s]), max(x1, ax[s], bx[s])
        y0, y1 = min(y0, ay[s], by[s]), max(y1, ay[s], by[s])
    width = x1 - x0
    height = y1 - y0
    h = cell_side(width, height, m)
    nx = int(width / h) + 1
    ny = int(height / h) + 1
    start = np.zeros(nx * ny + 1, np.int64)
    for s in range(m):                      # count, then fill the compressed rows
        i0, i1 = source_columns(x0, h, nx, ax[s], bx[s])
        for i in range(i0, i1 + 1):
            j0, j1 = column_rows(i, x0, y0, h, ny, ax[s], ay[s], bx[s], by[s])
            for j in range(j0, j1 + 1):
                start[j * nx + i + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    items = np.empty(start[nx * ny], np.int64)
    fill = start[:-1].copy()
    for s in range(m):
        i0, i1 = source_columns(x0, h, nx, ax[s], bx[s])
        for i in range(i0, i1 + 1):
            j0, j1 = column_rows(i, x0, y0, h, ny, ax[s], ay[s], bx[s], by[s])
            for j in range(j0, j1 + 1):
                c = j * nx + i
                items[fill[c]] = s
                fill[c] += 1
    return x0, y0, h, nx, ny, start, items


@kernel(forceinline=True)
def cell_of(p, p0, h):
    """The (unclipped) cell number of coordinate ``p`` along one axis."""
    f = (p - p0) / h
    return int(math.floor(min(max(f, -FAR_CELLS), FAR_CELLS)))


@kernel(forceinline=True)
def nearest_in_cell(px, py, i, j, best, bound, x0, y0, h, nx, start, items, ax, ay, bx, by):
    """``best`` lowered to the squared distance of the nearest source of cell
    ``(i, j)``; the cell is skipped when its box is ``bound`` (squared) or farther."""
    gx = max(x0 + i * h - px, 0.0, px - (x0 + (i + 1) * h))
    gy = max(y0 + j * h - py, 0.0, py - (y0 + (j + 1) * h))
    if gx * gx + gy * gy >= min(best, bound):
        return best
    c = j * nx + i
    for k in range(start[c], start[c + 1]):
        s = items[k]
        best = min(best, segment_distance2(px, py, ax[s], ay[s], bx[s], by[s]))
    return best


@kernel(forceinline=True)
def nearest_distance(px, py, limit, x0, y0, h, nx, ny, start, items, ax, ay, bx, by):
    """The distance from ``(px, py)`` to the nearest source, or ``limit`` when
    that is nearer: the rings of cells around the point's cell, nearest first.
    NaN for a point with a NaN or infinite coordinate."""
    if not (math.isfinite(px) and math.isfinite(py)):
        return math.nan
    ci = cell_of(px, x0, h)
    cj = cell_of(py, y0, h)
    r0 = max(0, -ci, ci - (nx - 1), -cj, cj - (ny - 1))     # the first ring that meets the grid
    r1 = max(abs(ci), abs(ci - (nx - 1)), abs(cj), abs(cj - (ny - 1)))
    best = math.inf
    bound = limit * limit
    for r in range(r0, r1 + 1):
        # every source not seen yet lies in a ring >= r: at least (r - 1) h away
        reach = (r - 1) * h
        if r > 0 and (reach >= limit or best <= reach * reach):
            break
        for j in range(max(cj - r, 0), min(cj + r, ny - 1) + 1):
            if j == cj - r or j == cj + r:                 # a whole row of the ring
                for i in range(max(ci - r, 0), min(ci + r, nx - 1) + 1):
                    best = nearest_in_cell(px, py, i, j, best, bound, x0, y0, h, nx, start,
                                           items, ax, ay, bx, by)
            else:                                          # its two side cells
                if ci - r >= 0:
                    best = nearest_in_cell(px, py, ci - r, j, best, bound, x0, y0, h, nx,
                                           start, items, ax, ay, bx, by)
                if ci + r <= nx - 1:
                    best = nearest_in_cell(px, py, ci + r, j, best, bound, x0, y0, h, nx,
                                           start, items, ax, ay, bx, by)
    return min(math.sqrt(best), limit)


@kernel(_nrt=False)
def fill_distances(out, qx, qy, limit, x0, y0, h, nx, ny, start, items, ax, ay, bx, by):
    """``out[k]``: :func:`nearest_distance` of query point ``k`` (allocates
    nothing: no reference counting in the loop)."""
    for k in range(qx.shape[0]):
        out[k] = nearest_distance(qx[k], qy[k], limit, x0, y0, h, nx, ny, start, items,
                                  ax, ay, bx, by)


@entry
def nearest_distances(qx, qy, limit, x0, y0, h, nx, ny, start, items, ax, ay, bx, by):
    """The distance from each query point ``(qx[k], qy[k])`` to its nearest source
    (:func:`bucket_grid`'s grid), or ``limit`` where that is nearer (``limit``
    may be ``inf``)."""
    out = np.empty(qx.shape[0])
    fill_distances(out, qx, qy, limit, x0, y0, h, nx, ny, start, items, ax, ay, bx, by)
    return out
