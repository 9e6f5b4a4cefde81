"""Kernel tests for :mod:`cdt_plugin._core.scaling` (powers of two into the
exact predicates' range)."""
from __future__ import annotations

import numpy as np
import pytest

from cdt_plugin._core.scaling import (HOME, LOW, MAX_SHIFT, NO_FIT, TOP, exponents, fit_shift,
                                      on_grid, scaled_area, scaled_seeds, unscale_rows)

NONE = np.empty(0)


@pytest.mark.parametrize("v, top, low", [
    (1.0, 1, 0), (0.75, 0, -2), (-3.0, 2, 0), (2.0 ** 1023, 1024, 1023), (5e-324, -1073, -1074),
    (1e-310, -1029, -1074), (0.1, -3, -55), (12.0, 4, 2)])
def test_exponents(v, top, low):
    assert exponents(v) == (top, low)
    assert np.frexp(v)[1] == top                   # 2**(top-1) <= |v| < 2**top
    assert np.ldexp(abs(v), -low) % 2 == 1           # an odd multiple of 2**low


def test_ordinary_coordinates_are_left_alone():
    x = np.array([0.0, 1e6, -3.5, 1e-9])
    assert fit_shift(x, x, NONE)[0] == 0
    assert fit_shift(NONE, NONE, NONE)[0] == 0          # nothing to fit
    assert fit_shift(np.zeros(3), np.zeros(3), NONE)[0] == 0


def test_far_coordinates_are_brought_near_one():
    x = np.array([3 * 2.0 ** 298, 2.0 ** 300])
    k, _, _ = fit_shift(x, x, NONE)
    assert k == -301 and 0.5 <= abs(x[1] * 2.0 ** k) < 1
    x = np.array([3.0, 2.0 ** 300])              # 3.0's lowest bit bounds the shift
    assert fit_shift(x, x, NONE)[0] == LOW          # 3.0 * 2**LOW keeps its lowest bit in range
    tiny = np.array([5e-324, 2.0 ** -1000])      # the finest bit forces the largest shift
    k, _, _ = fit_shift(tiny, tiny, NONE)
    assert k == MAX_SHIFT and tiny[0] * 2.0 ** k == 2.0 ** LOW


def test_no_fit_names_the_rows():
    x = np.array([1.0, 2.0 ** 300, 0.0, 2.0 ** -200])
    k, fine, large = fit_shift(x, np.zeros(4), NONE)
    assert (k, fine, large) == (NO_FIT, 3, 1)
    assert TOP - LOW < 300 + 200


def test_weights_count_twice():
    x = np.array([1.0, 2.0])
    assert fit_shift(x, x, np.array([0.0, 2.0 ** -400]))[0] == 0       # within 2 LOW
    assert fit_shift(x, x, np.array([0.0, 2.0 ** -700]))[0] == 110      # 4**110 * 2**-700 = 2**2LOW
    k, fine, _ = fit_shift(x, x, np.array([0.0, 2.0 ** -1000]))
    assert k == NO_FIT and fine == 1
    k, _, _ = fit_shift(x, x, np.array([0.0, 2.0 ** 600]))             # 2**300 in length
    assert k < 0 and 2.0 ** 600 * 4.0 ** k < 2.0 ** (2 * HOME)


def test_on_grid():
    assert on_grid(0.1) == 0.1                       # above the grid's reach: unchanged
    assert on_grid(2.0 ** (LOW + 53) * 1.5) == 2.0 ** (LOW + 53) * 1.5
    assert on_grid(2.0 ** (LOW - 2)) == 0.0
    assert on_grid(3 * 2.0 ** (LOW - 1)) == 2 * 2.0 ** LOW      # ties to even
    assert np.isnan(on_grid(np.nan))


def test_seeds_are_scaled_clamped_and_gridded():
    seeds = np.array([[1e300, -1e300, 7.0, 4.0], [0.5, 2.0 ** -300, 1.0, 0.0]])
    out = scaled_seeds(seeds, -100)
    assert out[0, 0] == 2.0 ** TOP and out[0, 1] == -(2.0 ** TOP)
    assert out[1, 0] == 0.5 * 2.0 ** -100 and out[1, 1] == 0.0        # below the grid
    assert out[0, 2] == 7.0 and out[0, 3] == 4.0 * 2.0 ** -200 and out[1, 3] == 0.0


def test_area_bounds_stay_positive():
    assert scaled_area(1.0, -800) == 5e-324
    assert scaled_area(0.0, -800) == 0.0
    assert scaled_area(3.0, 10) == 3.0 * 2.0 ** 20
    assert scaled_area(1.0, 600) == np.inf          # a bound larger than any area


def test_unscale_is_exact_on_the_grid():
    v = np.array([[2.0 ** LOW, 3 * 2.0 ** LOW], [1.0, -2.0 ** 200]])
    out = v.copy()
    unscale_rows(out, MAX_SHIFT)
    assert out[0, 0] == 5e-324 and out[0, 1] == 3 * 5e-324
    unscale_rows(out, -MAX_SHIFT)
    assert np.array_equal(out, v)
