"""Unit tests of the compiled input checks (cdt_plugin._core.checks)."""
import numpy as np

from cdt_plugin._core.checks import first_nonfinite_row, first_segment_out_of_range


def test_first_nonfinite_row():
    xy = np.zeros((5, 2))
    assert first_nonfinite_row(xy) == -1
    xy[3, 1] = np.inf
    xy[4, 0] = np.nan
    assert first_nonfinite_row(xy) == 3
    xy[1, 0] = -np.inf
    assert first_nonfinite_row(xy) == 1
    assert first_nonfinite_row(np.empty((0, 2))) == -1


def test_first_segment_out_of_range():
    segs = np.array([[0, 1], [1, 2], [2, 0]], np.int64)
    assert first_segment_out_of_range(segs, 3) == -1
    assert first_segment_out_of_range(segs, 2) == 1          # vertex 2 of segment 1
    assert first_segment_out_of_range(np.array([[0, 1], [-1, 0]], np.int64), 3) == 1
    assert first_segment_out_of_range(np.empty((0, 2), np.int64), 0) == -1
