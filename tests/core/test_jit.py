"""How kernels are compiled (cdt_plugin._core.jit): a declared signature is
compiled once, on first use, and every caller's arguments are converted to it."""
import os

import numpy as np
from numba import njit, types

import cdt_plugin
from cdt_plugin._core import predicates
from cdt_plugin._core.jit import DeclaredKernel, Kernel, kernel


@kernel("int64(int64)")
def plus_one(e):
    return e + 1


@kernel("float64(float64, float64)")
def half_sum(a, b):
    return (a + b) / 2


@kernel
def times_two(x):
    return 2 * x


@njit
def call_with_mixed_types(a):
    # a literal, an int32 and an int64: numba would compile three specialisations
    return plus_one(3) + plus_one(np.int32(a)) + plus_one(a)


def test_kernel_opens_its_disk_cache_on_first_compilation():
    assert isinstance(times_two, Kernel) and not times_two.cache_opened
    assert times_two(np.int64(21)) == 42
    assert times_two.cache_opened and os.path.isdir(times_two.stats.cache_path)


def test_declared_kernel_compiles_on_first_use_only():
    assert isinstance(half_sum, DeclaredKernel)
    assert half_sum.signatures == []                 # nothing compiled at definition
    assert half_sum(1, 2) == 1.5                     # from Python: ints converted to float64
    assert half_sum.signatures == [(types.float64, types.float64)]


def test_declared_kernel_converts_arguments_of_every_caller():
    assert call_with_mixed_types(np.int64(5)) == 4 + 6 + 6
    assert plus_one.signatures == [(types.int64,)]
    assert plus_one(np.int32(7)) == 8 and plus_one(True) == 2
    assert plus_one.signatures == [(types.int64,)]


def test_predicates_compile_once_and_take_integers_as_doubles():
    cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                           min_angle=25)
    cdt_plugin.delaunay(np.random.default_rng(1).random((50, 2)), weights=np.zeros(50))
    declared = [k for k in vars(predicates).values() if isinstance(k, DeclaredKernel)]
    assert len(declared) >= 30
    assert all(len(k.signatures) <= 1 for k in declared)
    assert predicates.orient2d(0, 0, 1, 0, 0, 1) == predicates.orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) > 0
    assert len(predicates.orient2d.signatures) == 1
