"""Every finite double in the exact predicates' range, by a power of two.

The predicates (:mod:`.predicates`) are exact as long as no product they form
overflows or underflows. Their largest products have degree four in the
coordinates (incircle), so after scaling

* every coordinate has ``|v| < 2**TOP``: degree-four terms stay far below the
  largest double, with room for off-centres outside the hull (orient2d, degree
  two, is safe up to 2**500);
* every coordinate is a multiple of ``2**LOW`` (its lowest set bit): every
  difference, product and expansion component is then a multiple of
  ``2**(4 LOW)`` or zero, which stays above the smallest normal double even
  after the float filter's cancellations (Shewchuk's error bounds assume no
  underflow).

A power-of-two scale ``2**k`` is exact for every such value and changes no
predicate's sign, so the triangulation of the scaled points is the
triangulation of the input. :func:`fit_shift` picks ``k``: 0 when the largest
magnitude lies within ``2**-HOME .. 2**HOME`` and the range already holds (no
work for ordinary inputs), otherwise the ``k`` that brings the largest
magnitude nearest to 1 within the feasible interval. The input fits when its
largest magnitude and its finest bit span at most ``2**(TOP - LOW)``;
otherwise :data:`NO_FIT` (the Python side raises ``CoordinateRangeError``).

Weights (lifted ``x^2 + y^2 - w``) scale by ``2**(2k)`` and must fit twice the
exponents. Points the engine adds (crossings, split points, circumcentres) are
rounded to the ``2**LOW`` grid by :func:`on_grid`: a no-op for any magnitude
above ``2**(LOW + 53)``, and it keeps them exact in the predicates and exact
when scaled back (``k`` never exceeds :data:`MAX_SHIFT`).
"""
from __future__ import annotations

import math

import numpy as np

from .jit import entry, kernel

TOP = 240
LOW = -240
HOME = 64
MAX_SHIFT = 1074 + LOW     # a multiple of 2**LOW scaled by 2**-MAX_SHIFT is still a double
NO_FIT = 1 << 40
GRID = 2.0 ** LOW
ON_GRID_ABOVE = 2.0 ** (LOW + 53)   # every double at least this large is a multiple of GRID
_MANTISSA = 2.0 ** 53


@entry
def exponents(v):
    """``(top, low)`` of a nonzero finite double: ``2**(top-1) <= |v| < 2**top``
    and ``v`` is an odd multiple of ``2**low``."""
    m, e = math.frexp(v)                      # |m| in [0.5, 1), subnormals too
    i = np.int64(abs(m) * _MANTISSA)          # the 53-bit significand, exactly
    _, e_low = math.frexp(float(i & -i))      # its lowest set bit, 2**(e_low - 1)
    return e, e - 53 + e_low - 1


@kernel
def shift_bounds(v, power, lo, hi, row_lo, row_hi):
    """Narrow the feasible shifts ``lo..hi`` by the values ``v`` scaled by
    ``2**(power * k)`` (power 1 for coordinates, 2 for weights). Returns
    ``(lo, hi, row_lo, row_hi, top)``: the rows that set each bound (unchanged
    when none of ``v`` does) and the largest top exponent / power."""
    top = -2000
    for i in range(v.shape[0]):
        if v[i] == 0.0:
            continue
        t, b = exponents(v[i])
        need = -((b - power * LOW) // power)        # ceil((power LOW - b) / power)
        if need > lo:
            lo = need
            row_lo = i
        room = (power * TOP - t) // power           # floor((power TOP - t) / power)
        if room < hi:
            hi = room
            row_hi = i
        top = max(top, -(-t // power))
    return lo, hi, row_lo, row_hi, top


@kernel
def magnitudes(v):
    """The largest ``|v|`` and the smallest nonzero ``|v|`` (inf when none)."""
    big = 0.0
    small = np.inf
    for i in range(v.shape[0]):
        a = abs(v[i])
        big = max(big, a)
        if a != 0.0 and a < small:
            small = a
    return big, small


@kernel
def at_home(v, power):
    """Whether the values ``v`` (scaled by ``2**(power k)``) certainly need no
    shift: largest magnitude within ``2**(power HOME)``, and every bit at least
    ``2**(power LOW)`` because none lies below the smallest value's last bit."""
    big, small = magnitudes(v)
    if big == 0.0:
        return True
    _, top = math.frexp(big)
    _, bottom = math.frexp(small)
    return -power * HOME <= top <= power * HOME and bottom - 53 >= power * LOW


@entry
def fit_shift(x, y, w):
    """The shift ``k`` for points ``x, y`` (and weights ``w``, empty without):
    ``(k, row_fine, row_large)``; ``k`` is :data:`NO_FIT` when no shift
    brings them into range, and the rows name the point with the finest bit
    and the one with the largest magnitude (-1: none). Ordinary inputs are
    settled by one pass over magnitudes (:func:`at_home`)."""
    if at_home(x, np.int64(1)) and at_home(y, np.int64(1)) and at_home(w, np.int64(2)):
        return np.int64(0), np.int64(-1), np.int64(-1)
    lo = np.int64(-MAX_SHIFT)
    hi = np.int64(MAX_SHIFT)
    row_lo = np.int64(-1)
    row_hi = np.int64(-1)
    lo, hi, row_lo, row_hi, tx = shift_bounds(x, np.int64(1), lo, hi, row_lo, row_hi)
    lo, hi, row_lo, row_hi, ty = shift_bounds(y, np.int64(1), lo, hi, row_lo, row_hi)
    lo, hi, row_lo, row_hi, tw = shift_bounds(w, np.int64(2), lo, hi, row_lo, row_hi)
    if lo > hi:
        return np.int64(NO_FIT), row_lo, row_hi
    top = max(tx, ty, tw)
    if top == -2000 or (lo <= 0 <= hi and -HOME <= top <= HOME):
        return np.int64(0), row_lo, row_hi
    return np.int64(min(max(-top, lo), hi)), row_lo, row_hi


@kernel
def scaled_area(a, k):
    """An area bound ``a`` in the units of points scaled by ``2**k``: times
    ``2**(2k)`` (in two steps: ``2**(2k)`` alone may not be a double), and a
    positive bound stays positive (a bound that underflows still asks for
    refinement, which then stops at the Steiner cap)."""
    s = a * 2.0 ** k * 2.0 ** k
    if a > 0.0 and s == 0.0:
        return 5e-324
    return s


@kernel
def scaled(v, k):
    """A copy of array ``v`` times ``2**k``."""
    out = np.empty_like(v)
    s = 2.0 ** k        # a normal double: |k| <= MAX_SHIFT
    for i in range(v.shape[0]):
        out[i] = v[i] * s
    return out


@kernel
def on_grid(v):
    """``v`` rounded to a multiple of ``2**LOW`` (a no-op unless ``|v|`` is
    below ``2**(LOW + 53)``; NaN and infinities pass)."""
    if not abs(v) < ON_GRID_ABOVE:
        return v
    # (np.round's rounding, half to even, sign kept: its implementation would make a new
    # process whose routes come from the cache import numba's array maths, and scipy)
    y = v * 2.0 ** -LOW
    return math.copysign(float(round(y)), y) * GRID


@kernel
def scaled_seeds(seeds, k):
    """Hole or region seeds (rows ``x, y[, attribute, max_area]``) scaled by
    ``2**k``: coordinates clamped to ``+-2**TOP`` (a seed that far out lies
    outside every triangle either way) and rounded to the grid, region areas
    scaled by ``2**(2k)``."""
    out = seeds.copy()
    bound = 2.0 ** TOP
    s = 2.0 ** k        # a normal double: |k| <= MAX_SHIFT
    for i in range(seeds.shape[0]):
        for j in range(2):
            out[i, j] = on_grid(min(max(seeds[i, j] * s, -bound), bound))
        if seeds.shape[1] > 3:
            out[i, 3] = scaled_area(seeds[i, 3], k)
    return out


@kernel
def unscale_rows(v, k):
    """Rows of ``(x, y)`` times ``2**-k``, in place (exact: they are multiples
    of ``2**LOW`` and ``k <= MAX_SHIFT``)."""
    s = 2.0 ** -k
    for i in range(v.shape[0]):
        v[i, 0] *= s
        v[i, 1] *= s
