"""Insertion orders: biased randomised insertion order (BRIO) over a Hilbert curve.

Amenta, Choi & Rote (2003): insert in rounds of doubling size, each round a
random sample, and sort each round along a space-filling curve so that walking
point location from the previous point takes a few steps. The random rounds
keep the expected work of incremental insertion optimal; the Hilbert order
keeps memory access local.
"""
from __future__ import annotations

import numpy as np
from numba import njit

HILBERT_BITS = 16


@njit(cache=True)
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


@njit(cache=True)
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
    n = x.shape[0]
    perm = np.random.default_rng(seed).permutation(n).astype(np.int64)
    out = np.empty(n, np.int64)
    # round boundaries: ..., n/8, n/4, n/2, n (the last round holds half the points)
    bounds = [n]
    while bounds[-1] > 64:
        bounds.append(bounds[-1] // 2)
    bounds.append(0)
    bounds = bounds[::-1]
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        chunk = perm[lo:hi]
        # about four points per grid cell is fine enough for walking
        bits = int(min(HILBERT_BITS, max(1, np.ceil(np.log2(max(hi - lo, 2)) / 2))))
        keys = hilbert_keys(x, y, chunk, bits)
        out[lo:hi] = chunk[np.argsort(keys)]
    return out


def lexicographic_order(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Indices of the points sorted by x, then y (Sec. 2.1)."""
    return np.lexsort((y, x)).astype(np.int64)
