"""Insertion orders: biased randomised insertion order (BRIO) over a Hilbert curve.

Amenta, Choi & Rote (2003): insert in rounds of doubling size, each round a
random sample, and sort each round along a space-filling curve so that walking
point location from the previous point takes a few steps. The random rounds
keep the expected work of incremental insertion optimal; the Hilbert order
keeps memory access local.
"""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel

HILBERT_BITS = 16


@kernel
def hilbert_index(ix, iy, order):
    """Index of cell ``(ix, iy)`` along the Hilbert curve on a ``2^order`` grid."""
    d = 0
    s = 1 << (order - 1)
    while s > 0:
        rx = 1 if (ix & s) > 0 else 0
        ry = 1 if (iy & s) > 0 else 0
        d += s * s * ((3 * rx) ^ ry)
        if ry == 0:  # rotate the quadrant
            if rx == 1:
                ix = s - 1 - ix
                iy = s - 1 - iy
            ix, iy = iy, ix
        s >>= 1
    return d


@entry
def hilbert_keys(x, y, idx, bits):
    """Hilbert keys of the points ``idx`` on a ``2^bits`` grid over their
    bounding box."""
    n = idx.shape[0]
    keys = np.empty(n, np.int64)
    if n == 0:
        return keys
    x0 = x[idx[0]]
    x1 = x0
    y0 = y[idx[0]]
    y1 = y0
    for k in range(n):
        i = idx[k]
        x0 = min(x0, x[i])
        x1 = max(x1, x[i])
        y0 = min(y0, y[i])
        y1 = max(y1, y[i])
    cells = (1 << bits) - 1
    span = max(x1 - x0, y1 - y0)
    scale = cells / span if span > 0 else 0.0
    for k in range(n):
        i = idx[k]
        ix = min(cells, max(0, int((x[i] - x0) * scale)))
        iy = min(cells, max(0, int((y[i] - y0) * scale)))
        keys[k] = hilbert_index(ix, iy, bits)
    return keys


def brio_order(x: np.ndarray, y: np.ndarray, seed: int = 0) -> np.ndarray:
    """A BRIO permutation of the points ``(x, y)``: rounds of doubling size, each
    sorted along a Hilbert curve. Deterministic for a given ``seed``.

    >>> import numpy as np
    >>> sorted(brio_order(np.arange(5.0), np.zeros(5)))
    [0, 1, 2, 3, 4]
    """
    perm = np.random.default_rng(seed).permutation(x.shape[0]).astype(np.int64)
    return brio_sort(x, y, perm)


@entry
def brio_sort(x, y, perm):
    """Sort the random permutation ``perm`` into BRIO rounds: the last half of
    the points, the half before it, ... down to at most 64 points, each round
    but the first along a Hilbert curve over its own bounding box."""
    n = perm.shape[0]
    out = perm.copy()
    pos = np.empty(n, np.int64)
    tmp = np.empty(n, np.int64)
    hi = n
    while hi > 64:
        # (the first round, at most 64 points, stays random: points along a
        # curve (a polygon's ring) inserted in curve order flip O(n) edges each)
        lo = hi // 2
        chunk = perm[lo:hi]
        # the finest grid: points along curves (rings) crowd a coarse grid's cells,
        # and inside a cell their order is random, which makes long walks
        keys = hilbert_keys(x, y, chunk, HILBERT_BITS)
        m = hi - lo
        for p in range(m):
            pos[p] = p
        sort_ids(pos, np.int64(0), m, keys, keys, tmp)      # ties keep the random order
        for p in range(m):
            out[lo + p] = chunk[pos[p]]
        hi = lo
    return out


SMALL_SORT = 2048   # below this many points one compiled call beats numpy's faster sort


def lexicographic_order(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Indices of the points sorted by x, then y (Sec. 2.1); equal points keep
    their input order. (The same as ``np.lexsort((y, x))``, about four times
    faster: one sort by x, then the runs of equal x sorted by y.)"""
    if len(x) < SMALL_SORT:
        return lexicographic_order_compiled(x, y)
    order = np.argsort(x).astype(np.int64)
    sort_ties(x, y, order)
    return order


@entry
def lexicographic_order_compiled(x, y):
    """:func:`lexicographic_order` in one compiled call."""
    n = x.shape[0]
    order = np.arange(n)
    sort_ids(order, np.int64(0), n, x, y, np.empty(n, np.int64))
    return order


@entry
def sort_ties(x, y, order):
    """Sort each run of equal ``x[order]`` by ``y``, then by index, in place."""
    n = order.shape[0]
    lo = next_run(x, order, np.int64(0))
    if lo == n:
        return
    # (allocated once, before the loop: an array reassigned inside it cost
    # two reference counts per point)
    tmp = np.empty(n, np.int64)
    while lo < n:
        hi = lo + 1
        while hi < n and x[order[hi]] == x[order[lo]]:
            hi += 1
        sort_ids(order, lo, hi, x, y, tmp)
        lo = next_run(x, order, hi)


@kernel
def next_run(x, order, lo):
    """The first slot from ``lo`` on that begins a run of two or more equal
    ``x[order]`` (``len(order)``: none)."""
    n = order.shape[0]
    for i in range(lo, n - 1):
        if x[order[i + 1]] == x[order[i]]:
            return i
    return n


@kernel
def before(k1, k2, a, b):
    """Whether id ``a`` comes before id ``b``: by ``k1``, then ``k2``, then the id."""
    if k1[a] != k1[b]:
        return k1[a] < k1[b]
    if k2[a] != k2[b]:
        return k2[a] < k2[b]
    return a < b


RUN = 16    # runs this short are sorted by insertion before merging


@kernel
def sort_ids(ids, lo, hi, k1, k2, tmp):
    """Sort ``ids[lo:hi]`` in place by ``(k1[id], k2[id], id)``: a merge sort
    (runs of :data:`RUN` by insertion, then merged in passes between ``ids``
    and ``tmp``, which holds at least ``hi`` items). Our own: numba's generic
    sorts compile for seconds on first use, this one in a fraction."""
    for start in range(lo, hi, RUN):
        end = min(start + RUN, hi)
        for i in range(start + 1, end):
            v = ids[i]
            j = i - 1
            while j >= start and before(k1, k2, v, ids[j]):
                ids[j + 1] = ids[j]
                j -= 1
            ids[j + 1] = v
    src, dst = ids, tmp
    in_tmp = False
    width = RUN
    while width < hi - lo:
        for start in range(lo, hi, 2 * width):
            mid = min(start + width, hi)
            end = min(start + 2 * width, hi)
            i, j = start, mid
            for k in range(start, end):
                if j >= end or (i < mid and not before(k1, k2, src[j], src[i])):
                    dst[k] = src[i]
                    i += 1
                else:
                    dst[k] = src[j]
                    j += 1
        src, dst = dst, src
        in_tmp = not in_tmp
        width *= 2
    if in_tmp:
        for k in range(lo, hi):
            ids[k] = src[k]
