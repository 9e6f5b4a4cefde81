"""Input checks in one compiled pass each: the first offending row, or -1.

On a small input a NumPy reduction costs more in call overhead (about 1.5 us
each) than the whole check; the Python side (:mod:`cdt_plugin.validate`,
:mod:`cdt_plugin.plc`) turns a row number into the precise error.
"""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel


@entry
def first_nonfinite_row(xy):
    """The first row of ``xy`` (n, 2) with a NaN or infinite coordinate, or -1."""
    for i in range(xy.shape[0]):
        if not (np.isfinite(xy[i, 0]) and np.isfinite(xy[i, 1])):
            return i
    return -1


@entry
def first_segment_out_of_range(segs, n):
    """The first row of ``segs`` (m, 2) naming a vertex outside ``0..n-1``, or -1."""
    for i in range(segs.shape[0]):
        if not (0 <= segs[i, 0] < n and 0 <= segs[i, 1] < n):
            return i
    return -1
