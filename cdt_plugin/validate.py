"""Input validation: turn user arrays into clean float64 arrays or raise a
precise :class:`CDTError` subclass naming the offending rows.

The one implementation of each check of the package: points (:func:`as_xy`,
with :func:`as_points` and :func:`as_queries` its two common forms), weights
(:func:`as_weights`), index arrays (:func:`as_index`), segments
(:func:`as_segments`), boundary markers (:func:`as_markers`), vertex attributes
(:func:`as_attributes`), a mesh made elsewhere (:func:`as_mesh`), an area bound per
triangle (:func:`as_triangle_bounds`) and the coordinate range of the exact predicates
(:func:`exact_range`)."""
from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.checks import first_nonfinite_row, first_segment_out_of_range
from ._core.scaling import LOW, NO_FIT, TOP, exponents, fit_shift
from .errors import (CoordinateRangeError, InputShapeError, NonFiniteCoordinateError, PrecisionWarning,
                     SegmentIndexError, TooFewPointsError)

EXACT_INT = 2 ** 53     # every integer up to this is a float64, not every one beyond


def _rows(idx: NDArray[np.intp], limit: int = 5) -> str:
    shown = ", ".join(str(int(i)) for i in idx[:limit])
    more = f" and {len(idx) - limit} more" if len(idx) > limit else ""
    return shown + more


def real_array(data: ArrayLike, name: str) -> NDArray[np.float64]:
    """``data`` as a float64 array. Ragged rows, complex values and anything but
    numbers raise :class:`InputShapeError` naming the place; integers that float64
    cannot hold exactly (beyond 2**53) are rounded with a :class:`PrecisionWarning`
    naming the rows."""
    raw = as_array(data, name)
    kind = raw.dtype.kind
    if kind == "f":
        return raw.astype(np.float64, copy=False)
    if kind == "c":
        bad = _rows_where(raw.imag != 0)
        raise InputShapeError(f"{name} must be real numbers, got complex values"
                              + (f" (imaginary parts at row(s) {_rows(bad)})" if len(bad) else ""))
    if kind in "iu":
        _warn_if_rounded(raw, name)
    try:
        return raw.astype(np.float64)
    except (TypeError, ValueError) as exc:
        raise InputShapeError(f"{name} must be numbers convertible to float64: {exc}") from None


def as_array(data: ArrayLike, name: str) -> NDArray[Any]:
    """``np.asarray(data)``; ragged rows raise :class:`InputShapeError` naming the row."""
    try:
        return np.asarray(data)
    except ValueError:
        raise InputShapeError(f"{name} must be rows of equal length: {_ragged_place(data)}") from None


def _ragged_place(data: Any) -> str:
    """Where nested sequences stop having one length (for the error message)."""
    try:
        lengths = [len(row) for row in data]
    except TypeError:
        return "numbers and sequences are mixed"
    i = next((i for i, k in enumerate(lengths) if k != lengths[0]), None)
    if i is None:
        return "rows of rows have different lengths"
    return f"row {i} has {lengths[i]} entries, row 0 has {lengths[0]}"


def _rows_where(mask: NDArray[np.bool_]) -> NDArray[np.intp]:
    """The rows (first index) where ``mask`` holds anywhere."""
    mask = np.atleast_1d(mask)
    return np.flatnonzero(mask.reshape(len(mask), -1).any(axis=1))


def _warn_if_rounded(raw: NDArray[Any], name: str) -> None:
    big = (raw > EXACT_INT) | (raw < -EXACT_INT)
    if not big.any():
        return
    values = raw[big]
    inexact = [int(v) for v in values.tolist() if int(float(v)) != int(v)]
    if inexact:
        warnings.warn(f"{name}: {len(inexact)} integer(s) beyond 2**53 rounded to float64 at row(s) "
                      f"{_rows(_rows_where(big))} (e.g. {inexact[0]} -> {float(inexact[0])!r}); points that round "
                      "to the same value are merged as duplicates", PrecisionWarning, stacklevel=4)


def as_points(points: ArrayLike, name: str = "points") -> NDArray[np.float64]:
    """``points`` as a C-contiguous (n, 2) float64 array with n >= 1, all finite.

    >>> as_points([[0, 0], [1, 2]]).dtype
    dtype('float64')
    >>> as_points([[0, 0], [1, float("nan")]])
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.NonFiniteCoordinateError: points has NaN or infinite coordinates at row(s) 1 (row 1 is (1.0, nan))
    """
    arr = as_xy(points, name)
    if arr.shape[0] == 0:
        raise TooFewPointsError(f"{name} is empty: at least one point is needed")
    return arr


def as_queries(points: ArrayLike, name: str = "points") -> NDArray[np.float64]:
    """Points as an (m, 2) float64 array (m may be 0; one point may be given as
    a pair), all finite: else a named :class:`CDTError`."""
    return as_xy(points, name, "m", pair=True)


def as_xy(points: ArrayLike, name: str, rows: str = "n", *, pair: bool = False,
          empty: bool = False) -> NDArray[np.float64]:
    """``points`` as a C-contiguous (m, 2) float64 array, all finite, else an
    error naming ``name`` (and ``rows``, the letter of the expected shape
    ``(rows, 2)``). ``pair``: one point may be given as a pair; ``empty``:
    any empty input is no points."""
    arr = real_array(points, name)
    if empty and arr.size == 0:
        return np.empty((0, 2))
    if pair and arr.shape == (2,):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputShapeError(f"{name} must have shape ({rows}, 2), got {arr.shape}")
    arr = np.ascontiguousarray(arr)
    if first_nonfinite_row(arr) >= 0:
        raise_nonfinite(arr, name)
    return arr


def as_index(a: ArrayLike, what: str, cols: int, n: int | None = None) -> NDArray[np.int64]:
    """``a`` as an (m, ``cols``) int64 array of vertex indices (any empty input:
    none), each in ``0..n-1`` when ``n`` is given; else :class:`InputShapeError`
    naming the first bad row."""
    arr = np.asarray(a)
    if arr.size == 0:
        return np.zeros((0, cols), dtype=np.int64)
    if arr.ndim != 2 or arr.shape[1] != cols or not np.issubdtype(arr.dtype, np.integer):
        raise InputShapeError(f"{what} must be an integer array of shape (m, {cols}), "
                              f"got {arr.dtype} {arr.shape}")
    arr = arr.astype(np.int64)
    if n is not None:
        bad = ((arr < 0) | (arr >= n)).any(axis=1)
        if bad.any():
            j = int(np.flatnonzero(bad)[0])
            raise InputShapeError(f"{what} row {j} {arr[j].tolist()} refers to a vertex "
                                  f"out of range 0..{n - 1}")
    return arr


def as_mesh(vertices: ArrayLike, triangles: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A mesh made elsewhere: its vertices' (n, 2) float64 x, y (a z column is
    dropped) and its (k, 3) int64 triangles, each naming vertices in ``0..n-1``."""
    V = np.asarray(vertices, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise InputShapeError(f"vertices must have shape (n, 2) or (n, 3), got {V.shape}")
    T = as_index(triangles, "triangles", 3, len(V))
    return np.ascontiguousarray(V[:, :2]), T


def as_segments(segments: ArrayLike, n: int) -> NDArray[np.int64]:
    """Segments as a C-contiguous (m, 2) int64 array of vertex indices in
    ``0..n-1``; whole numbers given as floats are taken. Else
    :class:`InputShapeError` or :class:`SegmentIndexError` naming the segment."""
    arr = as_array(segments, "segments")
    if arr.size == 0:
        return np.empty((0, 2), np.int64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputShapeError(f"segments must have shape (m, 2), got {arr.shape}")
    if arr.dtype.kind not in "iu":
        arr = real_array(arr, "segments")
        bad = np.flatnonzero((arr != np.round(arr)).any(axis=1) | ~np.isfinite(arr).all(axis=1))
        if bad.size:
            raise SegmentIndexError(f"segment {int(bad[0])} has non-integer vertex indices "
                                    f"{arr[bad[0]].tolist()}")
    # floats and unsigned integers are compared as given: int64 would wrap the largest
    if arr.dtype.kind != "i" and ((arr < 0) | (arr >= n)).any():
        _raise_segment_out_of_range(arr, n)
    arr = np.ascontiguousarray(arr, dtype=np.int64)
    if first_segment_out_of_range(arr, n) >= 0:
        _raise_segment_out_of_range(arr, n)
    return arr


def _raise_segment_out_of_range(arr: NDArray[Any], n: int) -> None:
    bad = np.flatnonzero(((arr < 0) | (arr >= n)).any(axis=1))
    i = int(bad[0])
    raise SegmentIndexError(
        f"segment {i} = {arr[i].tolist()} names a vertex outside 0..{n - 1}"
        + (f" ({bad.size} such segments)" if bad.size > 1 else ""))


def as_triangle_bounds(values: ArrayLike, k: int) -> NDArray[np.float64]:
    """An area bound per triangle of a mesh of ``k`` triangles (Triangle's
    ``.area`` file, ``triangle_max_area``): ``(k,)`` or ``(k, 1)`` numbers, as a
    (k,) float64 array in which 0 means no bound (values <= 0, NaN or +inf, as
    Triangle's -1). Else :class:`InputShapeError` naming what is wrong.

    >>> as_triangle_bounds([[0.5], [-1], [float("nan")]], 3).tolist()
    [0.5, 0.0, 0.0]
    """
    arr = real_array(values, "max_area")
    if arr.ndim == 2 and arr.shape[1] == 1:
        arr = arr[:, 0]
    if arr.shape != (k,):
        raise InputShapeError(f"max_area as an array needs one value per triangle, shape ({k},), "
                              f"got {arr.shape}")
    return np.where(np.isfinite(arr) & (arr > 0), arr, 0.0)


def raise_nonfinite(xy: NDArray[np.float64], name: str) -> None:
    """Raise :class:`NonFiniteCoordinateError` naming the rows of ``xy`` (n, 2)
    with a NaN or infinite coordinate, if there are any."""
    bad = np.flatnonzero(~(np.isfinite(xy[:, 0]) & np.isfinite(xy[:, 1])))
    if len(bad):
        i = int(bad[0])
        raise NonFiniteCoordinateError(
            f"{name} has NaN or infinite coordinates at row(s) {_rows(bad)} "
            f"(row {i} is ({float(xy[i, 0])!r}, {float(xy[i, 1])!r}))")


def as_weights(weights: ArrayLike | None, n: int) -> NDArray[np.float64] | None:
    """``weights`` as a finite float64 array of length ``n`` (or None)."""
    if weights is None:
        return None
    w = real_array(weights, "weights")
    if w.shape != (n,):
        raise InputShapeError(f"weights must have shape ({n},) to match the points, got {w.shape}")
    bad = np.flatnonzero(~np.isfinite(w))
    if bad.size:
        raise NonFiniteCoordinateError(f"weights are NaN or infinite at row(s) {_rows(bad)}")
    return np.ascontiguousarray(w)


def as_markers(markers: ArrayLike, n: int, name: str, what: str) -> NDArray[np.int64]:
    """Boundary markers (Triangle's): one integer per ``what`` (``n`` of them), as an
    (n,) int64 array; an (n, 1) column (the ``triangle`` package's shape) and whole
    numbers given as floats are taken. Else :class:`InputShapeError` naming the
    first bad row."""
    arr = as_array(markers, name)
    if arr.ndim == 2 and arr.shape[1] == 1:
        arr = arr[:, 0]
    if arr.shape != (n,):
        raise InputShapeError(f"{name} must have one marker per {what}: shape ({n},), "
                              f"got {arr.shape}")
    if arr.dtype.kind == "b":
        return arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        arr = real_array(arr, name)
        bad = np.flatnonzero((arr != np.round(arr)) | ~np.isfinite(arr) | (np.abs(arr) > 2**62))
        if bad.size:
            raise InputShapeError(f"{name} must be integers: row {int(bad[0])} is "
                                  f"{float(arr[bad[0]])!r} ({bad.size} such rows)")
    elif arr.dtype == np.uint64 and (arr > 2**62).any():
        bad = np.flatnonzero(arr > 2**62)
        raise InputShapeError(f"{name} row {int(bad[0])} is too large for int64 ({int(arr[bad[0]])})")
    return np.ascontiguousarray(arr, dtype=np.int64)


def as_attributes(attributes: ArrayLike, n: int, name: str = "vertex_attributes") -> NDArray[np.float64]:
    """Vertex attributes: an (n,) or (n, k) array of finite numbers, as an (n, k)
    float64 array (k may be 0). Else :class:`InputShapeError` for the shape or
    :class:`NonFiniteCoordinateError` naming the rows with NaN or infinity."""
    arr = real_array(attributes, name)
    if arr.ndim == 1 and len(arr) == n:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[0] != n:
        raise InputShapeError(f"{name} must have one row per input vertex: shape ({n},) or "
                              f"({n}, k), got {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if bad.size:
        raise NonFiniteCoordinateError(f"{name} are NaN or infinite at row(s) {_rows(bad)}")
    return np.ascontiguousarray(arr)


_NO_WEIGHTS = np.empty(0)


def exact_range(x: NDArray[np.float64], y: NDArray[np.float64], w: NDArray[np.float64] | None = None,
                name: str = "points"
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None, int]:
    """``(x, y, w, shift)``: copies of the coordinates (and weights) times
    ``2**shift``, the power of two that brings them into the exact predicates'
    range (:mod:`cdt_plugin._core.scaling`; ``shift`` is 0 and the arrays are
    the inputs for ordinary coordinates). Raises :class:`CoordinateRangeError`
    naming the rows when no power of two does."""
    # (contiguous arrays: one compilation of fit_shift for every caller)
    x, y = np.ascontiguousarray(x), np.ascontiguousarray(y)
    w = None if w is None else np.ascontiguousarray(w)
    shift, fine, large = fit_shift(x, y, _NO_WEIGHTS if w is None else w)
    if shift == NO_FIT:
        raise range_error(name, x, y, w, int(fine), int(large))
    if shift == 0:
        return x, y, w, 0
    s = 2.0 ** shift
    return x * s, y * s, None if w is None else w * s * s, int(shift)


def near_unit(v: NDArray[np.float64]) -> tuple[NDArray[np.float64], int]:
    """``(v * 2**-e, e)``: float arrays far from unit scale (beyond 2**+-64)
    brought near 1 by a power of two (exact), so that products of a few
    coordinates (areas, radii, interpolation weights) neither overflow nor
    underflow; ``e`` is 0 and ``v`` itself is returned at ordinary scales.
    Lengths computed from the result are scaled back with ``np.ldexp(l, e)``."""
    e = int(np.frexp(np.abs(v).max(initial=0.0))[1])
    if -64 <= e <= 64:
        return v, 0
    return np.ldexp(v, -e), e


def range_error(name: str, x: NDArray[np.float64], y: NDArray[np.float64],
                w: NDArray[np.float64] | None, fine: int, large: int) -> CoordinateRangeError:
    """The error for coordinates no power of two brings into range: the row
    with the finest bit and the row with the largest magnitude."""
    def values(i: int) -> list[float]:
        return [float(x[i]), float(y[i])] + ([] if w is None else [float(w[i])])

    def bits(i: int) -> list[tuple[int, int]]:   # (top, low) of row i's nonzero values (weights count half)
        out = []
        for j, v in enumerate(values(i)):
            if v:
                top, low = exponents(v)
                out.append((-(-top // 2), low // 2) if j == 2 else (top, low))
        return out

    top = max(t for t, _ in bits(large))
    low = min(b for _, b in bits(fine))
    weight = " (or weight)" if w is not None else ""
    return CoordinateRangeError(
        f"{name} span too many binary orders of magnitude for exact predicates: row {large} "
        f"{tuple(values(large))} reaches 2**{top} and row {fine} {tuple(values(fine))} has a "
        f"coordinate{weight} with bits down to 2**{low}; at most 2**{TOP - LOW} from the largest "
        "magnitude to the finest bit is supported, at any overall scale (round the finest values "
        "or mesh the parts separately)", rows=(large, fine))
