"""Array helpers the kernels share."""
from __future__ import annotations

import numpy as np

from .jit import kernel


@kernel
def copy_rows(dst, src, n):
    """``dst[:n] = src[:n]`` for C-contiguous arrays with rows of the same shape.
    A loop, because a slice assignment compiles numba's broadcasting and its
    shape-mismatch message (string formatting) into every caller."""
    if n == 0:
        return
    d = dst.reshape(-1)
    s = src.reshape(-1)
    k = n * (s.shape[0] // src.shape[0])
    for i in range(k):
        d[i] = s[i]


@kernel
def append(arr, n, v):
    """``arr[n] = v`` for a growing 1-D array holding ``n`` values: twice as
    long first when full. Returns ``(arr, n + 1)``."""
    if n == arr.shape[0]:
        bigger = np.empty(2 * n + 8, arr.dtype)
        copy_rows(bigger, arr, n)
        arr = bigger
    arr[n] = v
    return arr, n + 1
