"""Input validation: turn user arrays into clean float64 arrays or raise a
precise :class:`CDTError` subclass naming the offending rows."""
from __future__ import annotations

import numpy as np

from ._core.checks import first_nonfinite_row
from .errors import InputShapeError, NonFiniteCoordinateError, TooFewPointsError


def _rows(idx: np.ndarray, limit: int = 5) -> str:
    shown = ", ".join(str(int(i)) for i in idx[:limit])
    more = f" and {len(idx) - limit} more" if len(idx) > limit else ""
    return shown + more


def as_points(points, name: str = "points") -> np.ndarray:
    """``points`` as a C-contiguous (n, 2) float64 array with n >= 1, all finite."""
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputShapeError(f"{name} must be numbers convertible to float64: {exc}") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputShapeError(f"{name} must have shape (n, 2), got {arr.shape}")
    if arr.shape[0] == 0:
        raise TooFewPointsError(f"{name} is empty: at least one point is needed")
    arr = np.ascontiguousarray(arr)
    if first_nonfinite_row(arr) >= 0:
        bad = np.flatnonzero(~(np.isfinite(arr[:, 0]) & np.isfinite(arr[:, 1])))
        i = int(bad[0])
        raise NonFiniteCoordinateError(
            f"{name} has NaN or infinite coordinates at row(s) {_rows(bad)} "
            f"(row {i} is ({float(arr[i, 0])!r}, {float(arr[i, 1])!r}))")
    return arr


def as_weights(weights, n: int) -> np.ndarray | None:
    """``weights`` as a finite float64 array of length ``n`` (or None)."""
    if weights is None:
        return None
    try:
        w = np.asarray(weights, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputShapeError(f"weights must be numbers convertible to float64: {exc}") from None
    if w.shape != (n,):
        raise InputShapeError(f"weights must have shape ({n},) to match the points, got {w.shape}")
    bad = np.flatnonzero(~np.isfinite(w))
    if bad.size:
        raise NonFiniteCoordinateError(f"weights are NaN or infinite at row(s) {_rows(bad)}")
    return np.ascontiguousarray(w)
