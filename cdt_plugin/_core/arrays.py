"""Array helpers the kernels share."""
from __future__ import annotations

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
