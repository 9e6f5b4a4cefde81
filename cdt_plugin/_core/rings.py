"""Rings of polygons as segments: the one place where a ring (a closed chain
of vertices, closing point dropped) becomes the segments from each vertex to
the next, for single geometries and batches alike."""
from __future__ import annotations

import numpy as np

from .checks import first_nonfinite_row
from .jit import F8_2, I64, entry, kernel
from .predicates import orient2d
from .scaling import NO_FIT, fit_shift


@kernel
def ring_is_degenerate(x, y, a, b):
    """Whether the ring of vertices ``a..b-1`` encloses nothing: fewer than three
    distinct points, or all of them on one line (exact, at any scale: the ring
    is scaled into the predicates' range as the route scales it; a ring that
    does not fit is left to the route, which reports it)."""
    p1 = -1
    for k in range(a + 1, b):
        if x[k] != x[a] or y[k] != y[a]:
            p1 = k
            break
    if p1 < 0:
        return True
    shift, _, _ = fit_shift(x[a:b], y[a:b], np.empty(0))
    if shift == NO_FIT:
        return False
    s = 2.0 ** shift
    for k in range(p1 + 1, b):
        if orient2d(x[a] * s, y[a] * s, x[p1] * s, y[p1] * s, x[k] * s, y[k] * s) != 0:
            return False
    return True


@kernel
def segments_of_rings(begin, end, keep, v0):
    """The segments of the rings ``begin[r]..end[r] - 1`` whose ``keep`` flag is
    set (each vertex to the next of its ring; vertex ids less ``v0``) and the
    ring of each, counted among the kept rings from 0."""
    m = 0
    for r in range(begin.shape[0]):
        if keep[r]:
            m += end[r] - begin[r]
    segs = np.empty((m, 2), np.int64)
    ring_of = np.empty(m, np.int64)
    s = 0
    kept = 0
    for r in range(begin.shape[0]):
        if not keep[r]:
            continue
        a = begin[r] - v0
        b = end[r] - v0
        for p in range(a, b):
            segs[s, 0] = p
            segs[s, 1] = p + 1 if p + 1 < b else a
            ring_of[s] = kept
            s += 1
        kept += 1
    return segs, ring_of


@kernel
def ring_segments(ring_start, r0, r1, keep):
    """:func:`segments_of_rings` of the consecutive rings ``r0:r1`` of flat ring
    arrays (ring ``r`` is ``ring_start[r]..ring_start[r + 1] - 1``), in vertex
    ids relative to the first ring's start."""
    return segments_of_rings(ring_start[r0:r1], ring_start[r0 + 1:r1 + 1], keep, ring_start[r0])


@entry(ahead=(F8_2, I64, I64))
def polygon_rings(xy, begin, end):
    """The vertices ``xy`` (n, 2) checked (``bad``: the first row with a NaN or
    infinite coordinate, -1 when none) and every ring ``begin[r]..end[r] - 1``
    turned into segments. Returns ``(bad, degenerate, how many are degenerate,
    segments, segment_ring)``; a degenerate ring (:func:`ring_is_degenerate`)
    gives no segments."""
    bad = first_nonfinite_row(xy)
    degenerate = np.zeros(begin.shape[0], np.bool_)
    n_degenerate = 0
    if bad < 0:
        x = xy[:, 0].copy()     # contiguous, as the batch route's: one compilation of the check
        y = xy[:, 1].copy()
        for r in range(begin.shape[0]):
            degenerate[r] = ring_is_degenerate(x, y, begin[r], end[r])
            n_degenerate += degenerate[r]
    segs, ring_of = segments_of_rings(begin, end, ~degenerate, 0)
    return bad, degenerate, n_degenerate, segs, ring_of


@entry(ahead=(F8_2, I64))
def drop_closing_points(coords, ring_len):
    """Closed rings, one after the other in ``coords`` (n, k) (ring ``r`` of
    ``ring_len[r]`` rows, its last point repeating its first in x and y), with
    each ring's closing point dropped: ``(points, ring_start)``, ring ``r`` being
    ``points[ring_start[r]:ring_start[r + 1]]`` (every column kept). An empty
    ``ring_start`` if the sizes do not add up to ``n``, a ring has fewer than two
    points or is not closed. The one place where closed rings are opened, for
    one polygon and for a whole layer."""
    rings = ring_len.shape[0]
    refused = np.empty(0, np.int64)
    total = 0
    for r in range(rings):
        if ring_len[r] < 2:
            return np.empty((0, coords.shape[1])), refused
        total += ring_len[r]
    if total != coords.shape[0]:
        return np.empty((0, coords.shape[1])), refused
    out = np.empty((total - rings, coords.shape[1]))
    ring_start = np.empty(rings + 1, np.int64)
    ring_start[0] = 0
    start = 0
    for r in range(rings):
        last = start + ring_len[r] - 1
        if coords[last, 0] != coords[start, 0] or coords[last, 1] != coords[start, 1]:
            return out, refused
        for k in range(start, last):
            for c in range(coords.shape[1]):
                out[k - start + ring_start[r], c] = coords[k, c]
        ring_start[r + 1] = ring_start[r] + ring_len[r] - 1
        start += ring_len[r]
    return out, ring_start


@entry(ahead=(F8_2, I64))
def open_rings(coords, hole_sizes):
    """The rings of one polygon as its coordinates come, closed (each ring's
    last point repeats its first; the shell, then holes of ``hole_sizes``
    points, closing points counted), with the closing points dropped:
    ``(xy, bounds)``, ring ``r`` being ``xy[bounds[r]:bounds[r + 1]]``. An
    empty ``bounds`` if the sizes do not add up or a ring is not closed
    (:func:`drop_closing_points`, the shell's size what the holes leave)."""
    ring_len = np.empty(hole_sizes.shape[0] + 1, np.int64)
    ring_len[0] = coords.shape[0]
    for r in range(hole_sizes.shape[0]):
        ring_len[r + 1] = hole_sizes[r]
        ring_len[0] -= hole_sizes[r]
    return drop_closing_points(coords, ring_len)


@kernel
def closed_rings(coords):
    """The closed rings one after another in ``coords`` (n, 2 or more columns,
    as GEOS gives a polygon's coordinates: the shell, then the holes) split
    where each ring's first point comes back in x and y, closing points
    dropped: ``(xy, ring_start)``, ``xy`` (n - rings, 2), ring ``r`` being
    ``xy[ring_start[r]:ring_start[r + 1]]``. An empty ``ring_start`` if a ring
    has fewer than three points or the last one does not close. A ring that
    passes through its first point before its end splits there: the pieces
    then share that point, which the route counts as a repeated vertex (such
    a ring is never valid)."""
    n = coords.shape[0]
    xy = np.empty((n, 2))
    ring_start = np.empty(n // 3 + 2, np.int64)
    refused = np.empty(0, np.int64)
    ring_start[0] = 0
    r = 0
    first = 0
    k = 0
    for i in range(1, n):
        if i > first and coords[i, 0] == coords[first, 0] and coords[i, 1] == coords[first, 1]:
            if i - first < 3:
                return xy, refused
            for j in range(first, i):
                xy[k, 0] = coords[j, 0]
                xy[k, 1] = coords[j, 1]
                k += 1
            r += 1
            ring_start[r] = k
            first = i + 1
    if r == 0 or first != n:
        return xy, refused
    return xy[:k], ring_start[:r + 1]
