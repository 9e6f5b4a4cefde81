"""Unit tests of the insertion orders and their sort (cdt_plugin._core.ordering),
of divide and conquer's selection (cdt_plugin._core.divide.select) and of the
array copy the kernels share (cdt_plugin._core.arrays)."""
import numpy as np
import pytest

from cdt_plugin._core.arrays import copy_rows
from cdt_plugin._core.divide import select
from cdt_plugin._core.ordering import (HILBERT_BITS, SMALL_SORT, brio_sort, hilbert_keys,
                                       lexicographic_order, lexicographic_order_compiled,
                                       sort_ids, sort_ties)


def tied_points(n, seed):
    """Coordinates with many exact ties in x, in y and in both (and -0.0 beside 0.0)."""
    rng = np.random.default_rng(seed)
    x = rng.integers(-3, 4, n).astype(float)
    y = rng.integers(-2, 3, n).astype(float)
    x[rng.random(n) < 0.1] = -0.0
    return x, y


@pytest.mark.parametrize("n", [0, 1, 2, 15, 16, 17, 33, 64, 1000])
def test_lexicographic_order_is_x_then_y_then_index(n):
    x, y = tied_points(n, n)
    expected = np.lexsort((np.arange(n), y, x))
    assert lexicographic_order_compiled(x, y).tolist() == expected.tolist()
    assert lexicographic_order(x, y).tolist() == expected.tolist()


def test_lexicographic_order_numpy_path_for_many_points():
    x, y = tied_points(SMALL_SORT + 500, 7)
    expected = np.lexsort((np.arange(len(x)), y, x))
    assert lexicographic_order(x, y).tolist() == expected.tolist()


def test_sort_ties_orders_each_run_of_equal_x_by_y_then_index():
    x, y = tied_points(300, 3)
    order = np.argsort(x, kind="quicksort").astype(np.int64)   # runs in arbitrary order
    sort_ties(x, y, order)
    assert order.tolist() == np.lexsort((np.arange(300), y, x)).tolist()


def test_sort_ids_sorts_a_slice_only():
    k = np.array([5.0, 1.0, 4.0, 1.0, 3.0, 0.0])
    ids = np.array([0, 1, 2, 3, 4, 5], np.int64)
    sort_ids(ids, 1, 5, k, k, np.empty(6, np.int64))
    assert ids.tolist() == [0, 1, 3, 4, 2, 5]              # 1 before 3: equal keys, by id


@pytest.mark.parametrize("n", [0, 1, 64, 65, 200, 5000])
def test_brio_sort_rounds(n):
    """A permutation; the first round (at most 64 points) stays in random order, every
    later round is its slice of the permutation sorted along the Hilbert curve, equal
    keys keeping their random order (a stable sort)."""
    rng = np.random.default_rng(n)
    x, y = rng.uniform(size=n), rng.uniform(size=n)
    x[: n // 3] = 0.5                                      # many equal keys too
    y[: n // 3] = 0.5
    perm = rng.permutation(n).astype(np.int64)
    out = brio_sort(x, y, perm)
    assert sorted(out.tolist()) == list(range(n))
    hi = n
    while hi > 64:
        lo = hi // 2
        chunk = perm[lo:hi]
        keys = hilbert_keys(x, y, chunk, HILBERT_BITS)
        assert out[lo:hi].tolist() == chunk[np.argsort(keys, kind="stable")].tolist()
        hi = lo
    assert out[:hi].tolist() == perm[:hi].tolist()


@pytest.mark.parametrize("size", [1, 2, 3, 4, 9, 10, 11, 12, 50, 1000])
def test_select_puts_the_k_smallest_first_and_moves_b_along(size):
    rng = np.random.default_rng(size)
    lo = 5                               # a slice of a longer array: the rest stays
    ks = range(size) if size <= 50 else [0, 1, size // 2, size - 2, size - 1, 317]
    for k in ks:
        a = rng.permutation(size + 10).astype(np.int32)
        b = (a * 7 + 1).astype(np.int32)
        before = a.copy()
        select(a, b, np.int64(lo), np.int64(lo + size), np.int64(lo + k))
        part = a[lo:lo + size]
        assert sorted(part.tolist()) == sorted(before[lo:lo + size].tolist())
        assert (a[:lo] == before[:lo]).all() and (a[lo + size:] == before[lo + size:]).all()
        assert (b == a * 7 + 1).all()
        assert k == 0 or part[:k].max() < part[k:].min()


def test_copy_rows():
    a = np.arange(12).reshape(4, 3)
    b = np.full((6, 3), -1)
    copy_rows(b, a, 3)
    assert b.tolist() == [[0, 1, 2], [3, 4, 5], [6, 7, 8]] + [[-1, -1, -1]] * 3
    v = np.zeros(4)
    copy_rows(v, np.array([1.5, 2.5, 3.5]), 2)
    assert v.tolist() == [1.5, 2.5, 0.0, 0.0]
    copy_rows(v, np.empty(0), 0)                            # nothing to copy, nothing read
    assert v.tolist() == [1.5, 2.5, 0.0, 0.0]
