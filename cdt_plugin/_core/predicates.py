"""Exact geometric predicates: orient2d, incircle and the weighted (lifted) incircle.

Adaptive in the style of Shewchuk 1997 (J. R. Shewchuk, *Adaptive Precision
Floating-Point Arithmetic and Fast Robust Geometric Predicates*, Discrete Comput.
Geom. 18, 1997): each predicate first evaluates its determinant in ordinary
floating point and returns it when its magnitude exceeds a rigorous forward error
bound (``errbound * permanent``, stage A).  Otherwise ``orient2d`` and
``incircle`` run Shewchuk's intermediate stages, each with its own proven error
bound, and only what they cannot decide reaches the exact evaluation:

* stage B, the determinant of the *rounded* coordinate differences, evaluated
  exactly (orient2d: Shewchuk's four-component expansion) or, for incircle, in
  double-double arithmetic with a bound proven in ``_incircle_adapt``;
* stage C, stage B plus the first-order terms of the differences' roundoff
  tails (exact by two_diff), in floating point;
* stage D / exact: orient2d finishes with Shewchuk's stage D (B plus the exact
  tail products, a 44-double workspace); incircle calls its exact fallback.

Stages B and C are allocation-free scalar code of a few dozen (orient2d) or a few
hundred (incircle) flops, and decide every input that is not degenerate to
within about eps^2 of its permanent; in practice only exactly collinear or
cocircular inputs reach the exact evaluation (for orient2d only those whose
coordinate differences are not exact in floating point: with exact differences
stage B is already exact).  ``_orient2d_staged`` and ``_incircle_staged`` run
the same stages as the public predicates and also return the deciding stage
(1 = A, 2 = B, 3 = C, 4 = exact), for tests and benchmarks (compiled lazily, on
first use).

The exact fallbacks evaluate the same determinant with expansion arithmetic
(two_sum, two_diff, Dekker-split two_product, scale_expansion_zeroelim,
fast_expansion_sum_zeroelim) and return the most significant component of the
exact result.  The SIGN of every returned value is the sign of the real-number
determinant of the input doubles; the magnitude is only an approximation.  The
helpers that other kernels build on (snap rounding, the queries) are named
without a leading underscore: ``two_diff``, ``two_product``, ``two_one_sum``,
``orient_expansion``, ``double_double``.

The weighted test is the lifted orientation test of the seed chapter (Sec. 2.8):
a weighted point ``v`` has lifted companion ``v+ = (vx, vy, vx^2 + vy^2 - w_v)``;
it has the float filter and the exact fallback only (no intermediate stages).

Every function but the two staged ones is ``@kernel(inline='never')``
with an explicit signature (compiled once, float64 only), nopython,
allocation-free on the fast path and in stages B and C.  What follows the
float filter is compiled apart, once, and the public predicates call it by
symbol (see "The slow stages" below), so the kernels that call a predicate
link its filter only.  The exact fallbacks
live in separate compiled functions (``orient2d_exact``, ``incircle_exact``,
``incircle_weighted_exact``).  They first try a scalar route that is exact
whenever the coordinate differences (and, for the circle tests, the squares and
2x2 minors) come out exact in one double -- the common degenerate case of
integer or grid coordinates, which costs tens of nanoseconds; the circle tests
then try Shewchuk's stage-B expansion, exact whenever the differences alone are
exact (decimal grids: a few hundred nanoseconds) -- and otherwise run full
expansion arithmetic in one local float64 workspace (np.empty), addressed by
integer offsets (no slicing).  No recursion, no epsilons other than the proven
error bounds below.

Guaranteed range (IEEE binary64, round-to-nearest-even, no FMA contraction, which
is numba's default without ``fastmath``): the results are exact as long as no
intermediate product overflows or underflows, which holds when every nonzero
coordinate satisfies

* ``orient2d``:  1e-130 <= |x| <= 1e130,
* ``incircle``:  1e-60  <= |x| <= 1e60,
* ``incircle_weighted``: coordinates as for ``incircle`` and every nonzero
  weight 1e-120 <= |w| <= 1e120.

In short, coordinates whose products underflow or overflow are outside the
guaranteed range: roughly |x| > 1e100 or nonzero |x| < 1e-100 for orient2d
(products of two differences), and already |x| > 1e60 or nonzero |x| < 1e-60 for
the circle tests (products of four).  Subnormal inputs are outside it too.
Inputs must be finite (the engine validates this before calling).  Every caller
in the engine first scales its points by a power of two into a range that is
safe for all of them (:mod:`.scaling`), which makes every finite double usable.
"""
from __future__ import annotations

import numpy as np
from numba import types

from .jit import entry, kernel

__all__ = [
    "EPSILON",
    "SPLITTER",
    "CCW_ERRBOUND_A",
    "ICC_ERRBOUND_A",
    "ICCW_ERRBOUND_A",
    "orient2d",
    "incircle",
    "incircle_weighted",
    "orient2d_exact",
    "incircle_exact",
    "incircle_weighted_exact",
    "orient2d_fast",
    "incircle_fast",
]

# ---------------------------------------------------------------------------
# Constants (Shewchuk 1997, Sec. 4 and the predicates' error bounds).
# ---------------------------------------------------------------------------

#: Half an ulp of 1.0 for binary64: every correctly rounded operation has
#: relative error at most EPSILON.
EPSILON = 2.0 ** -53
#: Dekker's splitter 2^ceil(53/2) + 1 (Shewchuk 1997, Theorem 17).
SPLITTER = 2.0 ** 27 + 1.0
#: orient2d filter: |det - det_exact| <= CCW_ERRBOUND_A * (|detleft| + |detright|).
CCW_ERRBOUND_A = (3.0 + 16.0 * EPSILON) * EPSILON
#: incircle filter: Shewchuk's iccerrboundA.
ICC_ERRBOUND_A = (10.0 + 96.0 * EPSILON) * EPSILON
#: Weighted incircle filter.  Counting roundings along every root-to-leaf path of
#: the evaluation tree (at most 12 per monomial: 2 for adx twice, 3 for the
#: lift, 4 for the cross product, 1 for the multiplication, 2 for the final sum)
#: gives |det - det_exact| <= (12 eps + O(eps^2)) * permanent; 16 eps leaves a
#: wide margin for the O(eps^2) terms and the rounding of the permanent itself.
ICCW_ERRBOUND_A = (16.0 + 256.0 * EPSILON) * EPSILON

# Explicit signatures everywhere: every function is compiled exactly once (numba
# would otherwise specialise the expansion routines on every literal offset),
# and the public predicates take float64 only (integer arguments are converted,
# never evaluated in overflowing int64). They are compiled on first use
# (:class:`.jit.DeclaredKernel`), not at import: a process whose routes load
# from the cache never loads them.
#
# The predicates and their stages take the coordinates of their three or four
# points (and weights) as scalars, as Shewchuk's do, which makes up to a dozen
# arguments and up to 18 in the exact stages' helpers: that is the algorithm
# (each term of the determinant is a product of these scalars), and scalars stay
# in registers where a tuple would have to be taken apart at every stage. The
# store-threading kernels elsewhere keep to about ten arguments with bundles
# (see :mod:`.mesh`).
_f8 = types.float64
_i8 = types.int64
_b1 = types.boolean
_W = types.float64[::1]
_T2 = types.UniTuple(_f8, 2)
_T3 = types.UniTuple(_f8, 3)
_T4 = types.UniTuple(_f8, 4)
_T5 = types.UniTuple(_f8, 5)
_FI = types.Tuple((_f8, _i8))
_F6 = "float64(" + ", ".join(["float64"] * 6) + ")"
_F8 = "float64(" + ", ".join(["float64"] * 8) + ")"
_F12 = "float64(" + ", ".join(["float64"] * 12) + ")"

# ---------------------------------------------------------------------------
# Error-free transformations (Shewchuk 1997, Sec. 2).
# ---------------------------------------------------------------------------

@kernel(_T2(_f8, _f8), inline='never')
def _fast_two_sum(a, b):
    """x + y == a + b exactly, x = fl(a + b); requires |a| >= |b| (Shewchuk 1997, Thm 6)."""
    x = a + b
    bvirt = x - a
    y = b - bvirt
    return x, y


@kernel(_T2(_f8, _f8), inline='never')
def _two_sum(a, b):
    """x + y == a + b exactly, x = fl(a + b), no precondition (Shewchuk 1997, Thm 7)."""
    x = a + b
    bvirt = x - a
    avirt = x - bvirt
    bround = b - bvirt
    around = a - avirt
    return x, around + bround


@kernel(_T2(_f8, _f8), inline='never')
def two_diff(a, b):
    """x + y == a - b exactly, x = fl(a - b) (Shewchuk 1997, Two-Diff)."""
    x = a - b
    bvirt = a - x
    avirt = x + bvirt
    bround = bvirt - b
    around = a - avirt
    return x, around + bround


@kernel(_T2(_f8), inline='never')
def _split(a):
    """Dekker split a = hi + lo with hi, lo of at most 26 significant bits (Shewchuk 1997, Thm 17)."""
    c = SPLITTER * a
    abig = c - a
    hi = c - abig
    return hi, a - hi


@kernel(_T2(_f8, _f8, _f8, _f8), inline='never')
def _two_product_presplit(a, b, bhi, blo):
    """x + y == a * b exactly, x = fl(a * b), with b already split (Shewchuk 1997, Thm 18)."""
    x = a * b
    ahi, alo = _split(a)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


@kernel(_T2(_f8, _f8), inline='never')
def two_product(a, b):
    """x + y == a * b exactly, x = fl(a * b), via Dekker's split (no FMA) (Shewchuk 1997, Thm 18)."""
    bhi, blo = _split(b)
    return _two_product_presplit(a, b, bhi, blo)


# ---------------------------------------------------------------------------
# Small fixed-size expansion sums on scalars (Shewchuk 1997's Two_One_Sum,
# Two_Two_Sum, Four_One_Sum, Four_Two_Sum macros: Grow-Expansion, Thm 10).
# Outputs are nonoverlapping and increasing except for interspersed zeros, so
# the sign of the sum is the sign of the most significant nonzero component.
# ---------------------------------------------------------------------------

@kernel(_T3(_f8, _f8, _f8), inline='never')
def two_one_sum(a1, a0, b):
    """(x2, x1, x0) == (a1, a0) + b exactly (Shewchuk 1997, Two_One_Sum)."""
    i, x0 = _two_sum(a0, b)
    x2, x1 = _two_sum(a1, i)
    return x2, x1, x0


@kernel(_T4(_f8, _f8, _f8, _f8), inline='never')
def _two_two_sum(a1, a0, b1, b0):
    """(x3, x2, x1, x0) == (a1, a0) + (b1, b0) exactly (Shewchuk 1997, Two_Two_Sum)."""
    j, z, x0 = two_one_sum(a1, a0, b0)
    x3, x2, x1 = two_one_sum(j, z, b1)
    return x3, x2, x1, x0


@kernel(_T5(_f8, _f8, _f8, _f8, _f8), inline='never')
def _four_one_sum(a3, a2, a1, a0, b):
    """(x4 .. x0) == (a3 .. a0) + b exactly (Shewchuk 1997, Four_One_Sum)."""
    j, x1, x0 = two_one_sum(a1, a0, b)
    x4, x3, x2 = two_one_sum(a3, a2, j)
    return x4, x3, x2, x1, x0


@kernel(_T3(_f8, _f8, _f8), inline='never')
def _two_one_diff(a1, a0, b):
    """(x2, x1, x0) == (a1, a0) - b exactly (Shewchuk 1997, Two_One_Diff)."""
    i, x0 = two_diff(a0, b)
    x2, x1 = _two_sum(a1, i)
    return x2, x1, x0


@kernel(_T4(_f8, _f8, _f8, _f8), inline='never')
def _two_two_diff(a1, a0, b1, b0):
    """(x3, x2, x1, x0) == (a1, a0) - (b1, b0) exactly (Shewchuk 1997, Two_Two_Diff)."""
    j, z, x0 = _two_one_diff(a1, a0, b0)
    x3, x2, x1 = _two_one_diff(j, z, b1)
    return x3, x2, x1, x0


@kernel(_f8(_f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _sum_of_three_two_products(p1, e1, p2, e2, p3, e3):
    """(p1 + e1) + (p2 + e2) + (p3 + e3) exactly, returned as its most significant component.

    Each (p, e) is a two-component expansion (a Two_Product result): merged with
    Grow-Expansion steps (Two_Two_Sum, Four_Two_Sum; Shewchuk 1997) into six
    nonoverlapping components, whose most significant nonzero one has the sign
    of the sum.  No arrays.
    """
    a3, a2, a1, a0 = _two_two_sum(p1, e1, p2, e2)
    # Four_Two_Sum(a3, a2, a1, a0, p3, e3)
    k, z2, z1, z0, x0 = _four_one_sum(a3, a2, a1, a0, e3)
    x5, x4, x3, x2, x1 = _four_one_sum(k, z2, z1, z0, p3)
    if x5 != 0.0:
        return x5
    if x4 != 0.0:
        return x4
    if x3 != 0.0:
        return x3
    if x2 != 0.0:
        return x2
    if x1 != 0.0:
        return x1
    return x0


@kernel(_f8(_f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _sign_of_sum_of_three_products(l1, c1, l2, c2, l3, c3):
    """l1*c1 + l2*c2 + l3*c3 exactly, returned as its most significant component (Shewchuk 1997).

    Three two_products (6 components) merged with Grow-Expansion steps; no arrays.
    """
    p1, e1 = two_product(l1, c1)
    p2, e2 = two_product(l2, c2)
    p3, e3 = two_product(l3, c3)
    return _sum_of_three_two_products(p1, e1, p2, e2, p3, e3)


# ---------------------------------------------------------------------------
# Expansion arithmetic in one workspace array w.  An expansion is a pair
# (offset, length) into w: nonoverlapping, increasing in magnitude,
# zero-eliminated, and always >= 1 component (zero is [0.0]), as Shewchuk's
# *_zeroelim routines produce.  Offsets instead of slices: a numpy slice costs
# a reference-count round trip in numba, and these routines are called often.
# ---------------------------------------------------------------------------

@kernel(_i8(_W, _i8, _f8, _f8), inline='never')
def _diff_expansion(w, h, a, b):
    """Write a - b as an exact expansion at w[h:]; return its length (1 or 2) (Shewchuk 1997)."""
    x, y = two_diff(a, b)
    if y != 0.0:
        w[h] = y
        w[h + 1] = x
        return 2
    w[h] = x
    return 1


@kernel(_i8(_W, _i8, _i8, _f8, _i8), inline='never')
def _scale_expansion_zeroelim(w, e, elen, b, h):
    """w[h:] = b * w[e:e+elen] exactly; returns the length <= 2 * elen (Shewchuk 1997, Fig. 13, zeroelim)."""
    bhi, blo = _split(b)
    q, hh = _two_product_presplit(w[e], b, bhi, blo)
    hindex = h
    if hh != 0.0:
        w[hindex] = hh
        hindex += 1
    for eindex in range(e + 1, e + elen):
        p1, p0 = _two_product_presplit(w[eindex], b, bhi, blo)
        sm, hh = _two_sum(q, p0)
        if hh != 0.0:
            w[hindex] = hh
            hindex += 1
        q, hh = _fast_two_sum(p1, sm)
        if hh != 0.0:
            w[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == h:
        w[hindex] = q
        hindex += 1
    return hindex - h


@kernel(_i8(_W, _i8, _i8, _i8, _i8, _i8), inline='never')
def _fast_expansion_sum_zeroelim(w, e, elen, f, flen, h):
    """w[h:] = w[e:e+elen] + w[f:f+flen] exactly; returns the length <= elen + flen.

    Shewchuk 1997, Fig. 9 (fast_expansion_sum_zeroelim), except that it never
    reads past the end of an input (the C code reads one element beyond).  The
    output must not overlap the inputs.
    """
    eend = e + elen
    fend = f + flen
    ei = e
    fi = f
    enow = w[ei]
    fnow = w[fi]
    if (fnow > enow) == (fnow > -enow):
        q = enow
        ei += 1
        if ei < eend:
            enow = w[ei]
    else:
        q = fnow
        fi += 1
        if fi < fend:
            fnow = w[fi]
    hi = h
    if ei < eend and fi < fend:
        if (fnow > enow) == (fnow > -enow):
            q, hh = _fast_two_sum(enow, q)
            ei += 1
            if ei < eend:
                enow = w[ei]
        else:
            q, hh = _fast_two_sum(fnow, q)
            fi += 1
            if fi < fend:
                fnow = w[fi]
        if hh != 0.0:
            w[hi] = hh
            hi += 1
        while ei < eend and fi < fend:
            if (fnow > enow) == (fnow > -enow):
                q, hh = _two_sum(q, enow)
                ei += 1
                if ei < eend:
                    enow = w[ei]
            else:
                q, hh = _two_sum(q, fnow)
                fi += 1
                if fi < fend:
                    fnow = w[fi]
            if hh != 0.0:
                w[hi] = hh
                hi += 1
    while ei < eend:
        q, hh = _two_sum(q, enow)
        ei += 1
        if ei < eend:
            enow = w[ei]
        if hh != 0.0:
            w[hi] = hh
            hi += 1
    while fi < fend:
        q, hh = _two_sum(q, fnow)
        fi += 1
        if fi < fend:
            fnow = w[fi]
        if hh != 0.0:
            w[hi] = hh
            hi += 1
    if q != 0.0 or hi == h:
        w[hi] = q
        hi += 1
    return hi - h


@kernel(_i8(_W, _i8, _i8, _i8, _i8, _i8, _i8, _i8), inline='never')
def _expansion_product(w, e, elen, f, flen, h, t, s):
    """w[h:] = w[e:] * w[f:] exactly: sum over f's components of scale_expansion(e, f_i) (Shewchuk 1997).

    Returns the length <= 2 * elen * flen.  Scratch: w[t:] holds >= 2 * elen
    values, w[s:] >= 2 * elen * flen; h, t, s must not overlap e, f or each other.
    """
    hlen = _scale_expansion_zeroelim(w, e, elen, w[f], h)
    for i in range(1, flen):
        tlen = _scale_expansion_zeroelim(w, e, elen, w[f + i], t)
        slen = _fast_expansion_sum_zeroelim(w, h, hlen, t, tlen, s)
        for k in range(slen):
            w[h + k] = w[s + k]
        hlen = slen
    return hlen


@kernel(_i8(_W, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8), inline='never')
def _cross_expansion(w, p, plen, q, qlen, r, rlen, s, slen, h, scr):
    """w[h:] = p*q - r*s exactly for expansions of <= 2 components; returns the length <= 16.

    Scratch w[scr:scr+48].  (orient2d's exact determinant; Shewchuk 1997.)
    """
    pq = scr
    rs = scr + 8
    t = scr + 16
    u = scr + 24
    pqlen = _expansion_product(w, p, plen, q, qlen, pq, t, u)
    rslen = _expansion_product(w, r, rlen, s, slen, rs, t, u)
    for k in range(rs, rs + rslen):
        w[k] = -w[k]
    return _fast_expansion_sum_zeroelim(w, pq, pqlen, rs, rslen, h)


# Scratch layout of one lift * cross term (offsets relative to its scratch base).
_LC_SQ1 = 0        # x^2, <= 8
_LC_SQ2 = 8        # y^2, <= 8
_LC_PQ = 16        # p*q, <= 8
_LC_RS = 24        # r*s, <= 8
_LC_LIFT = 32      # x^2 + y^2 (- w), <= 18
_LC_LIFT2 = 56     # <= 18
_LC_CROSS = 80     # p*q - r*s, <= 16
_LC_NEGW = 96      # -w, <= 2
_LC_T = 104        # scale scratch, >= 2 * 18
_LC_U = 144        # product scratch, >= 2 * 18 * 16 = 576
_LC_SIZE = _LC_U + 576


@kernel(_i8(_W, _i8, _i8, _i8, _i8, _i8, _i8, _b1, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8, _i8), inline='never')
def _lift_cross_term(w, x, xlen, y, ylen, wd, wdlen, use_w,
                     p, plen, q, qlen, r, rlen, s, slen, h, scr):
    """w[h:] = (x^2 + y^2 - wd) * (p*q - r*s) exactly; returns the length <= 576.

    One row's contribution to the (lifted) incircle determinant expanded along
    its third column: the lifted height of the seed's Sec. 2.8 (z = x^2 + y^2 - w,
    relative to the apex d) times its 2x2 minor (Shewchuk 1997 expansion
    arithmetic).  Every argument expansion has <= 2 components; wd is ignored
    unless use_w.  Scratch w[scr:scr+_LC_SIZE].  (The four small products run
    in one loop so that the compiled code holds a single inlined copy.)
    """
    t = scr + _LC_T
    u = scr + _LC_U
    nsq1 = nsq2 = npq = nrs = 0
    for j in range(4):
        if j == 0:
            e, elen, f, flen, out = x, xlen, x, xlen, scr + _LC_SQ1
        elif j == 1:
            e, elen, f, flen, out = y, ylen, y, ylen, scr + _LC_SQ2
        elif j == 2:
            e, elen, f, flen, out = p, plen, q, qlen, scr + _LC_PQ
        else:
            e, elen, f, flen, out = r, rlen, s, slen, scr + _LC_RS
        n = _expansion_product(w, e, elen, f, flen, out, t, u)
        if j == 0:
            nsq1 = n
        elif j == 1:
            nsq2 = n
        elif j == 2:
            npq = n
        else:
            nrs = n
    rs = scr + _LC_RS
    for k in range(rs, rs + nrs):
        w[k] = -w[k]
    lift = scr + _LC_LIFT
    liftlen = 0
    crosslen = 0
    # Three exact sums through one call site: lift = sq1 + sq2, lift2 = lift - w,
    # cross = pq + (-rs).
    for j in range(3):
        if j == 0:
            a, alen, b, blen, out = scr + _LC_SQ1, nsq1, scr + _LC_SQ2, nsq2, lift
        elif j == 1:
            if not use_w or (wdlen == 1 and w[wd] == 0.0):
                continue
            negw = scr + _LC_NEGW
            for k in range(wdlen):
                w[negw + k] = -w[wd + k]
            a, alen, b, blen, out = lift, liftlen, negw, wdlen, scr + _LC_LIFT2
        else:
            a, alen, b, blen, out = scr + _LC_PQ, npq, rs, nrs, scr + _LC_CROSS
        n = _fast_expansion_sum_zeroelim(w, a, alen, b, blen, out)
        if j == 2:
            crosslen = n
        else:
            lift = out
            liftlen = n
    # Scale the longer expansion (the lift, <= 18) by the cross's components.
    return _expansion_product(w, lift, liftlen, scr + _LC_CROSS, crosslen, h, t, u)


# Workspace layout of the incircle fallback (worst case: every difference a
# two-component expansion, every weight difference too).
# Slot i = 0..8 (adx, ady, bdx, bdy, cdx, cdy, awd, bwd, cwd) at offset 2 i.
_W_LEN = 20                 # the 9 slot lengths (stored as floats)
_W_TERM = 32                # one lift * cross term, <= 576
_W_ACC0 = _W_TERM + 576     # running sum of the terms, <= 1728
_W_ACC1 = _W_ACC0 + 1728    # (double-buffered)
_W_SCR = _W_ACC1 + 1728     # scratch of one term
_W_SIZE = _W_SCR + _LC_SIZE


# Workspace layout of the exact determinant of exact differences (Shewchuk's
# stage B of incircleadapt, with the weight term): per row the minor M (4),
# x M (8), x x M (16), y M (8), y y M (16), -w M (8), x x M + y y M (32); the
# three rows (40 each), their partial sum (80) and the total (120).
_RB_M = 0
_RB_XM = 4
_RB_XXM = 12
_RB_YM = 28
_RB_YYM = 36
_RB_WM = 52
_RB_S = 60
_RB_ROW = 92
_RB_AB = _RB_ROW + 120
_RB_FIN = _RB_AB + 80
_RB_SIZE = _RB_FIN + 120


@kernel(_f8(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _b1), inline='never')
def _incircle_exact_of_doubles(adx, ady, awd, bdx, bdy, bwd, cdx, cdy, cwd, use_w):
    """Exact (weighted) incircle determinant of rows [x, y, x^2 + y^2 - wd] whose entries are doubles.

    Shewchuk's stage B of incircleadapt (predicates.c): per row the 2x2 minor
    as a four-component expansion (Two_Product, Two_Two_Diff), scaled twice by
    x and twice by y (scale_expansion_zeroelim) and summed; with weights, -wd
    times the minor is added.  The rows are summed with
    fast_expansion_sum_zeroelim.  Exact when the coordinate differences (and
    weight differences) are exact in one double each, i.e. their two_diff tails
    vanish; returns the most significant component of the result.
    """
    w = np.empty(_RB_SIZE)
    rowlen0 = rowlen1 = rowlen2 = 0
    for k in range(3):
        if k == 0:
            x, y, wd, p, q, r, s = adx, ady, awd, bdx, cdy, cdx, bdy
        elif k == 1:
            x, y, wd, p, q, r, s = bdx, bdy, bwd, cdx, ady, adx, cdy
        else:
            x, y, wd, p, q, r, s = cdx, cdy, cwd, adx, bdy, bdx, ady
        p1, p0 = two_product(p, q)
        q1, q0 = two_product(r, s)
        m3, m2, m1, m0 = _two_two_diff(p1, p0, q1, q0)
        w[_RB_M] = m0
        w[_RB_M + 1] = m1
        w[_RB_M + 2] = m2
        w[_RB_M + 3] = m3
        n = _scale_expansion_zeroelim(w, _RB_M, 4, x, _RB_XM)
        nxx = _scale_expansion_zeroelim(w, _RB_XM, n, x, _RB_XXM)
        n = _scale_expansion_zeroelim(w, _RB_M, 4, y, _RB_YM)
        nyy = _scale_expansion_zeroelim(w, _RB_YM, n, y, _RB_YYM)
        row = _RB_ROW + 40 * k
        if use_w and wd != 0.0:
            ns = _fast_expansion_sum_zeroelim(w, _RB_XXM, nxx, _RB_YYM, nyy, _RB_S)
            nw = _scale_expansion_zeroelim(w, _RB_M, 4, -wd, _RB_WM)
            n = _fast_expansion_sum_zeroelim(w, _RB_S, ns, _RB_WM, nw, row)
        else:
            n = _fast_expansion_sum_zeroelim(w, _RB_XXM, nxx, _RB_YYM, nyy, row)
        if k == 0:
            rowlen0 = n
        elif k == 1:
            rowlen1 = n
        else:
            rowlen2 = n
    nab = _fast_expansion_sum_zeroelim(w, _RB_ROW, rowlen0, _RB_ROW + 40, rowlen1, _RB_AB)
    nfin = _fast_expansion_sum_zeroelim(w, _RB_AB, nab, _RB_ROW + 80, rowlen2, _RB_FIN)
    return w[_RB_FIN + nfin - 1]


# ---------------------------------------------------------------------------
# Exact fallbacks.
# ---------------------------------------------------------------------------

@kernel(_F6, inline='never')
def orient2d_exact(ax, ay, bx, by, cx, cy):
    """Exact orient2d by expansion arithmetic (Shewchuk 1997): sign of det[[ax-cx, ay-cy], [bx-cx, by-cy]].

    Returns the most significant component of the exact determinant, so its sign
    is exact (0.0 iff a, b, c are collinear).  Always exact, never filtered: the
    fallback of :func:`orient2d`.
    """
    acx, acxt = two_diff(ax, cx)
    bcx, bcxt = two_diff(bx, cx)
    acy, acyt = two_diff(ay, cy)
    bcy, bcyt = two_diff(by, cy)
    if acxt == 0.0 and bcxt == 0.0 and acyt == 0.0 and bcyt == 0.0:
        # The differences are exact: det = acx*bcy - acy*bcx.  Rounding is
        # monotone, so fl(acx*bcy) != fl(acy*bcx) already decides the sign;
        # otherwise the heads cancel exactly and the roundoff tails decide.
        left = acx * bcy
        right = acy * bcx
        if left != right:
            return left - right
        l1, l0 = two_product(acx, bcy)
        r1, r0 = two_product(acy, bcx)
        return l0 - r0
    w = np.empty(72)
    n_acx = _diff_expansion(w, 0, ax, cx)
    n_bcx = _diff_expansion(w, 2, bx, cx)
    n_acy = _diff_expansion(w, 4, ay, cy)
    n_bcy = _diff_expansion(w, 6, by, cy)
    hlen = _cross_expansion(w, 0, n_acx, 6, n_bcy, 4, n_acy, 2, n_bcx, 8, 24)
    return w[8 + hlen - 1]


@kernel(_f8(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _b1), inline='never')
def _incircle_exact_core(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, use_w):
    """Exact (weighted) incircle determinant, translated to d (Shewchuk 1997; seed Sec. 2.8).

    det of rows [pdx, pdy, pdx^2 + pdy^2 - (pw - dw)] for p = a, b, c.  Returns
    the most significant component of the exact result.

    Three routes, all exact.  (1) When every difference and every second-order
    quantity (squares, 2x2 minors, lifts) happens to be exact in one double --
    checked by their two_diff/two_product/two_sum roundoff being exactly zero,
    as for integer or grid coordinates -- the determinant is a sum of three
    products of doubles, evaluated exactly on scalars.  (2) When only the
    differences are exact: Shewchuk's stage B expansion on them
    (_incircle_exact_of_doubles, <= 120 components).  (3) Otherwise full
    expansion arithmetic on two_diff expansions of every difference.
    """
    adx, adxt = two_diff(ax, dx)
    ady, adyt = two_diff(ay, dy)
    bdx, bdxt = two_diff(bx, dx)
    bdy, bdyt = two_diff(by, dy)
    cdx, cdxt = two_diff(cx, dx)
    cdy, cdyt = two_diff(cy, dy)
    awd, awdt = two_diff(aw, dw)
    bwd, bwdt = two_diff(bw, dw)
    cwd, cwdt = two_diff(cw, dw)
    tails = (abs(adxt) + abs(adyt) + abs(bdxt) + abs(bdyt) + abs(cdxt) + abs(cdyt)
             + abs(awdt) + abs(bwdt) + abs(cwdt))
    if tails == 0.0:
        p1, t1 = two_product(bdx, cdy)
        p2, t2 = two_product(cdx, bdy)
        ca, t3 = two_diff(p1, p2)
        p1, t4 = two_product(cdx, ady)
        p2, t5 = two_product(adx, cdy)
        cb, t6 = two_diff(p1, p2)
        p1, t7 = two_product(adx, bdy)
        p2, t8 = two_product(bdx, ady)
        cc, t9 = two_diff(p1, p2)
        s1, u1 = two_product(adx, adx)
        s2, u2 = two_product(ady, ady)
        la, u3 = _two_sum(s1, s2)
        la, u4 = two_diff(la, awd)
        s1, u5 = two_product(bdx, bdx)
        s2, u6 = two_product(bdy, bdy)
        lb, u7 = _two_sum(s1, s2)
        lb, u8 = two_diff(lb, bwd)
        s1, u9 = two_product(cdx, cdx)
        s2, u10 = two_product(cdy, cdy)
        lc, u11 = _two_sum(s1, s2)
        lc, u12 = two_diff(lc, cwd)
        tails = (abs(t1) + abs(t2) + abs(t3) + abs(t4) + abs(t5) + abs(t6) + abs(t7)
                 + abs(t8) + abs(t9) + abs(u1) + abs(u2) + abs(u3) + abs(u4) + abs(u5)
                 + abs(u6) + abs(u7) + abs(u8) + abs(u9) + abs(u10) + abs(u11) + abs(u12))
        if tails == 0.0:
            return _sign_of_sum_of_three_products(la, ca, lb, cb, lc, cc)
        return _incircle_exact_of_doubles(adx, ady, awd, bdx, bdy, bwd, cdx, cdy, cwd, use_w)
    w = np.empty(_W_SIZE)
    # Slot i (offset 2 i) holds the exact difference: adx, ady, bdx, bdy, cdx,
    # cdy, awd, bwd, cwd; its length is kept in w[_W_LEN + i].
    minuend = (ax, ay, bx, by, cx, cy, aw, bw, cw)
    subtrahend = (dx, dy, dx, dy, dx, dy, dw, dw, dw)
    for i in range(9):
        w[_W_LEN + i] = _diff_expansion(w, 2 * i, minuend[i], subtrahend[i])
    # Term k (k = a, b, c): lift_k * minor_k, with the minor of (a, b, c) cyclic:
    # a: bdx*cdy - cdx*bdy, b: cdx*ady - adx*cdy, c: adx*bdy - bdx*ady.
    # One call site in a loop keeps the compiled code (and compile time) small.
    finlen = 0
    fin = _W_ACC0
    for k in range(3):
        k1 = (k + 1) % 3
        k2 = (k + 2) % 3
        # slots of x, y, w, p, q, r, s (expansion offset = 2 * slot)
        sx, sy, sw = 2 * k, 2 * k + 1, 6 + k
        sp, sq, sr, ss = 2 * k1, 2 * k2 + 1, 2 * k2, 2 * k1 + 1
        n = _lift_cross_term(w, 2 * sx, int(w[_W_LEN + sx]), 2 * sy, int(w[_W_LEN + sy]),
                             2 * sw, int(w[_W_LEN + sw]), use_w,
                             2 * sp, int(w[_W_LEN + sp]), 2 * sq, int(w[_W_LEN + sq]),
                             2 * sr, int(w[_W_LEN + sr]), 2 * ss, int(w[_W_LEN + ss]),
                             _W_TERM, _W_SCR)
        if k == 0:
            for i in range(n):
                w[fin + i] = w[_W_TERM + i]
            finlen = n
        else:
            out = _W_ACC1 if fin == _W_ACC0 else _W_ACC0
            finlen = _fast_expansion_sum_zeroelim(w, fin, finlen, _W_TERM, n, out)
            fin = out
    return w[fin + finlen - 1]


@kernel(_F8, inline='never')
def incircle_exact(ax, ay, bx, by, cx, cy, dx, dy):
    """Exact incircle by expansion arithmetic (Shewchuk 1997); the fallback of :func:`incircle`.

    Returns the most significant component of the exact determinant
    (> 0: d strictly inside the circle through counter-clockwise a, b, c).
    """
    return _incircle_exact_core(ax, ay, 0.0, bx, by, 0.0, cx, cy, 0.0, dx, dy, 0.0, False)


@kernel(_F12, inline='never')
def incircle_weighted_exact(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """Exact lifted orientation (power) test (Shewchuk 1997; seed Sec. 2.8, z = x^2 + y^2 - w).

    The fallback of :func:`incircle_weighted`; returns the most significant
    component of the exact determinant.
    """
    return _incircle_exact_core(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, True)


# ---------------------------------------------------------------------------
# Adaptive intermediate stages (Shewchuk 1997, and orient2dadapt and
# incircleadapt in his predicates.c).  Stages, as reported by the
# *_staged functions: 1 = the float filter (stage A), 2 = stage B, 3 = stage C,
# 4 = the exact value (orient2d: Shewchuk's stage D; incircle: incircle_exact).
# ---------------------------------------------------------------------------

#: Relative error of a stage's final rounding (Shewchuk's resulterrbound).
RESULT_ERRBOUND = (3.0 + 8.0 * EPSILON) * EPSILON
#: orient2d stage B (exact determinant of the rounded differences): Shewchuk's ccwerrboundB.
CCW_ERRBOUND_B = (2.0 + 12.0 * EPSILON) * EPSILON
#: orient2d stage C (plus the first-order tail terms): Shewchuk's ccwerrboundC.
CCW_ERRBOUND_C = (9.0 + 64.0 * EPSILON) * EPSILON * EPSILON
#: incircle stage B: the determinant of the rounded differences evaluated in
#: double-double arithmetic (see _incircle_adapt: the analysis needs
#: 4 eps + 89.3 eps^2; the eps^2 term is taken with a margin of almost 3).
ICC_ERRBOUND_B = (4.0 + 256.0 * EPSILON) * EPSILON
#: incircle stage C: stage B's double-double value plus the first-order tail
#: terms; the analysis needs 90.5 eps^2 (plus RESULT_ERRBOUND * |det|).
ICC_ERRBOUND_C = 256.0 * EPSILON * EPSILON


@kernel(_FI(_f8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _orient2d_adapt(ax, ay, bx, by, cx, cy, detsum):
    """Shewchuk's orient2dadapt: stages B, C and D; returns (value, stage).

    Called when the float filter fails, with detsum = |detleft| + |detright|
    (> 0; detleft and detright then have the same sign).  Stage B: the exact
    determinant B of the rounded differences (Two_Product, Two_Two_Diff: four
    components, no arrays), decided when its estimate clears ccwerrboundB *
    detsum, or returned outright when the differences were exact.  Stage C: adds
    the first-order terms of the differences' roundoff tails in floating point
    (ccwerrboundC).  Stage D: the exact determinant B + three four-component
    tail products by fast_expansion_sum_zeroelim in a 44-double workspace.
    """
    acx = ax - cx
    bcx = bx - cx
    acy = ay - cy
    bcy = by - cy
    detleft, detlefttail = two_product(acx, bcy)
    detright, detrighttail = two_product(acy, bcx)
    b3, b2, b1, b0 = _two_two_diff(detleft, detlefttail, detright, detrighttail)
    det = ((b0 + b1) + b2) + b3  # Shewchuk's estimate()
    errbound = CCW_ERRBOUND_B * detsum
    if det >= errbound or -det >= errbound:
        return det, 2
    acxtail = two_diff(ax, cx)[1]
    bcxtail = two_diff(bx, cx)[1]
    acytail = two_diff(ay, cy)[1]
    bcytail = two_diff(by, cy)[1]
    if acxtail == 0.0 and acytail == 0.0 and bcxtail == 0.0 and bcytail == 0.0:
        # B is the exact determinant: return its most significant nonzero
        # component (its sign is the expansion's sign).
        if b3 != 0.0:
            return b3, 2
        if b2 != 0.0:
            return b2, 2
        if b1 != 0.0:
            return b1, 2
        return b0, 2
    errbound = CCW_ERRBOUND_C * detsum + RESULT_ERRBOUND * abs(det)
    det += (acx * bcytail + bcy * acxtail) - (acy * bcxtail + bcx * acytail)
    if det >= errbound or -det >= errbound:
        return det, 3
    # Stage D: B + (acxtail*bcy - acytail*bcx) + (acx*bcytail - acy*bcxtail)
    #            + (acxtail*bcytail - acytail*bcxtail), exactly.
    # Workspace: B w[0:4], u w[4:8], C1 w[8:16], C2 w[16:28], D w[28:44].
    w = np.empty(44)
    w[0] = b0
    w[1] = b1
    w[2] = b2
    w[3] = b3
    src = 0
    srclen = 4
    for k in range(3):
        if k == 0:
            p, q, r, s, out = acxtail, bcy, acytail, bcx, 8
        elif k == 1:
            p, q, r, s, out = acx, bcytail, acy, bcxtail, 16
        else:
            p, q, r, s, out = acxtail, bcytail, acytail, bcxtail, 28
        s1, s0 = two_product(p, q)
        t1, t0 = two_product(r, s)
        u3, u2, u1, u0 = _two_two_diff(s1, s0, t1, t0)
        w[4] = u0
        w[5] = u1
        w[6] = u2
        w[7] = u3
        srclen = _fast_expansion_sum_zeroelim(w, src, srclen, 4, 4, out)
        src = out
    return w[src + srclen - 1], 4


@kernel(_T4(_f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _lift_minor_dd(x, y, p, q, r, s):
    """(h, g, c, r) with h + g + c ~= (x^2 + y^2) * (p*q - r*s), a double-double product.

    h + g == l1 * m1 exactly (Two_Product) and c ~= l1*m0 + l0*m1, where
    l1 + l0 ~= x^2 + y^2 and m1 + m0 ~= p*q - r*s are double-double values of
    the lift and the 2x2 minor.  With L = x^2 + y^2 and S = |p q| + |r s|
    (eps = 2^-53, barring underflow):
    |l1 + l0 - L| <= 3.0001 eps^2 L, |l0| <= 2.0001 eps L;
    |m1 + m0 - M| <= 3.0001 eps^2 S, |m0| <= 2.0001 eps S;
    and |h + g + c - L M| <= 18.01 eps^2 L S (the errors of l, m: 6.001, the
    dropped l0*m0: 4.001, the three roundings of c: 8.005), |g| <= eps |h|,
    |h| <= (1 + 6.01 eps) L S, |c| <= 4.01 eps L S.

    r is 0.0 iff the lift and the minor are exact in one double each (all their
    roundoff terms vanish, as for integer or grid coordinates): then c == 0
    and h + g == L M exactly.
    """
    s1, s0 = two_product(x, x)
    t1, t0 = two_product(y, y)
    l1, e = _two_sum(s1, t1)
    l0 = e + (s0 + t0)
    p1, p0 = two_product(p, q)
    q1, q0 = two_product(r, s)
    m1, f = two_diff(p1, q1)
    m0 = f + (p0 - q0)
    h, g = two_product(l1, m1)
    c = l1 * m0 + l0 * m1
    rough = (abs(s0) + abs(t0)) + (abs(e) + abs(p0)) + (abs(q0) + abs(f))
    return h, g, c, rough


@kernel(_T2(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _incircle_dd_sum(ha, ga, ca, hb, gb, cb, hc, gc, cc):
    """(v1, lo) ~= the sum of the three rows' (h, g, c) (see _incircle_dd)."""
    u1, u0 = _two_sum(ha, hb)
    v1, v0 = _two_sum(u1, hc)
    lo = ((u0 + v0) + (ga + gb)) + ((gc + ca) + (cb + cc))
    return v1, lo


@kernel(_T2(_f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _incircle_dd(adx, ady, bdx, bdy, cdx, cdy):
    """(v1, lo): the incircle determinant of the (rounded) differences in double-double.

    With P* = sum over the rows of L_k S_k (the exact permanent of these
    doubles, = the sum of the |monomials|): |v1 + lo - det| <= 39.2 eps^2 P*
    (rows: 18.01; lo sums 8 terms of total size <= 7.02 eps P* in a tree of
    depth 3: 21.1), and |lo| <= 7.03 eps P*.
    """
    ha, ga, ca, _ = _lift_minor_dd(adx, ady, bdx, cdy, cdx, bdy)
    hb, gb, cb, _ = _lift_minor_dd(bdx, bdy, cdx, ady, adx, cdy)
    hc, gc, cc, _ = _lift_minor_dd(cdx, cdy, adx, bdy, bdx, ady)
    return _incircle_dd_sum(ha, ga, ca, hb, gb, cb, hc, gc, cc)


@kernel(_F12, inline='never')
def _incircle_tail_terms(adx, ady, bdx, bdy, cdx, cdy,
                         adxtail, adytail, bdxtail, bdytail, cdxtail, cdytail):
    """The first-order tail terms of the incircle determinant in floating point (Shewchuk's stage C).

    Per row (lift L, minor M of the rounded differences): L dM + 2 dL M, where
    dM, dL are the first-order changes of the minor and of the half lift from
    the tails.  With |tail| <= eps |difference|, the result is within
    34.01 eps^2 P* of the exact first-order terms (P* as in _incircle_dd): per
    row L dM is within 12.002 eps^2 L S (L: 2 roundings, dM: 3 roundings of
    terms totalling 2 eps S, the product: 1), 2 dL M within 10.002 eps^2 L S,
    their sum within 4.0002 eps^2 L S more; the two row sums add 8.003 eps^2 P*.
    """
    rowa = ((adx * adx + ady * ady) * ((bdx * cdytail + cdy * bdxtail) - (bdy * cdxtail + cdx * bdytail))
            + 2.0 * (adx * adxtail + ady * adytail) * (bdx * cdy - bdy * cdx))
    rowb = ((bdx * bdx + bdy * bdy) * ((cdx * adytail + ady * cdxtail) - (cdy * adxtail + adx * cdytail))
            + 2.0 * (bdx * bdxtail + bdy * bdytail) * (cdx * ady - cdy * adx))
    rowc = ((cdx * cdx + cdy * cdy) * ((adx * bdytail + bdy * adxtail) - (ady * bdxtail + bdx * adytail))
            + 2.0 * (cdx * cdxtail + cdy * cdytail) * (adx * bdy - ady * bdx))
    return (rowa + rowb) + rowc


@kernel(_FI(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _incircle_adapt(ax, ay, bx, by, cx, cy, dx, dy, permanent):
    """incircle stages B and C after Shewchuk's incircleadapt; returns (value, stage).

    Stage 4 means undecided (the value is then meaningless): the caller runs
    incircle_exact (kept out of this function so that its code is not compiled
    into it twice).

    Called when the float filter fails, with the filter's permanent P.
    Shewchuk's stage B evaluates the determinant of the rounded differences x
    exactly (expansions of up to 96 components, arrays); here it is evaluated in
    double-double arithmetic instead (_incircle_dd, a few hundred flops, no
    arrays), with a rigorous bound on its error, and stage C adds Shewchuk's
    first-order tail terms to that value.  Between the two, when the
    differences, lifts and minors all came out exact (integer or grid
    coordinates) the determinant is the exact sum of the rows' two_products
    (returned as stage B, exact).

    Error analysis (eps = 2^-53, no underflow).  X = x + t are the exact
    differences, |t| <= eps |x| by round-to-nearest (the tails t are exact by
    two_diff); F is the determinant; P* = the sum of the |monomials| of F at x
    (= sum over the rows of lift * (|p q| + |r s|)), and P* <= (1 + 7.0001 eps) P
    because every monomial of the filter's P passes through at most 7 roundings
    of nonnegative values.

    * B: |F(X) - F(x)| <= ((1 + eps)^4 - 1) P*/(1 - eps)^4 <= (4 eps + 22.01 eps^2) P*;
      |v1 + lo - F(x)| <= 39.2 eps^2 P*; det = fl(v1 + lo) adds eps |det|.  So
      |det - F(X)| <= (4 eps + 89.3 eps^2) P + eps |det|, and |det| >
      fl(ICC_ERRBOUND_B * P) (>= (4 eps + 256 eps^2)(1 - eps) P) decides.
    * C: F(X) = F(x) + C1 + R2 with C1 the first-order tail terms and
      |R2| <= 6.0001 eps^2 P*.  Shewchuk's floating-point C1 (per row
      L dM + 2 dL M) is off by <= 34.01 eps^2 P* (each row: 26.005 eps^2 L S,
      the two row sums: 8.003 eps^2 P*); w = fl(lo + C1) adds <= 11.04 eps^2 P*;
      det = fl(v1 + w) adds eps |det|.  In all |det - F(X)| <= 90.5 eps^2 P +
      eps |det|, and |det| > fl(fl(ICC_ERRBOUND_C P) + fl(RESULT_ERRBOUND |det|))
      decides.  With all tails zero C1 = R2 = 0 and the same test applies.
    """
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    ha, ga, ca, ra = _lift_minor_dd(adx, ady, bdx, cdy, cdx, bdy)
    hb, gb, cb, rb = _lift_minor_dd(bdx, bdy, cdx, ady, adx, cdy)
    hc, gc, cc, rc = _lift_minor_dd(cdx, cdy, adx, bdy, bdx, ady)
    v1, lo = _incircle_dd_sum(ha, ga, ca, hb, gb, cb, hc, gc, cc)
    det = v1 + lo
    errbound = ICC_ERRBOUND_B * permanent
    if det > errbound or -det > errbound:
        return det, 2
    adxtail = two_diff(ax, dx)[1]
    adytail = two_diff(ay, dy)[1]
    bdxtail = two_diff(bx, dx)[1]
    bdytail = two_diff(by, dy)[1]
    cdxtail = two_diff(cx, dx)[1]
    cdytail = two_diff(cy, dy)[1]
    tails = ((abs(adxtail) + abs(adytail)) + (abs(bdxtail) + abs(bdytail))
             + (abs(cdxtail) + abs(cdytail)))
    if tails == 0.0 and ra + rb + rc == 0.0:
        # Exact differences, lifts and minors (integer or grid coordinates):
        # the determinant is exactly (ha + ga) + (hb + gb) + (hc + gc).
        return _sum_of_three_two_products(ha, ga, hb, gb, hc, gc), 2
    corr = _incircle_tail_terms(adx, ady, bdx, bdy, cdx, cdy,
                                adxtail, adytail, bdxtail, bdytail, cdxtail, cdytail)
    det = v1 + (lo + corr)
    errbound = ICC_ERRBOUND_C * permanent + RESULT_ERRBOUND * abs(det)
    if det > errbound or -det > errbound:
        return det, 3
    return 0.0, 4  # undecided: the caller runs incircle_exact


@kernel(_T3(_f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _orient2d_filter(ax, ay, bx, by, cx, cy):
    """(det, errbound, detsum): Shewchuk's orient2d in floating point with its ccwerrboundA test.

    det is exact in sign when |det| >= errbound (stage A); detsum is what the
    adaptive stages need.
    """
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    # Shewchuk's bound holds for any signs of detleft, detright; his early exit
    # on opposite signs is left out because its branches are unpredictable on
    # random input (measured: ~40% slower per call).  With opposite signs (or a
    # zero product) the test |det| >= errbound always passes, as his exit would.
    detsum = abs(detleft) + abs(detright)
    return det, CCW_ERRBOUND_A * detsum, detsum


@kernel(_T3(_f8, _f8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy):
    """(det, errbound, permanent): Shewchuk's incircle in floating point with its iccerrboundA test."""
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy

    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    alift = adx * adx + ady * ady

    cdxady = cdx * ady
    adxcdy = adx * cdy
    blift = bdx * bdx + bdy * bdy

    adxbdy = adx * bdy
    bdxady = bdx * ady
    clift = cdx * cdx + cdy * cdy

    det = (alift * (bdxcdy - cdxbdy)
           + blift * (cdxady - adxcdy)
           + clift * (adxbdy - bdxady))
    permanent = ((abs(bdxcdy) + abs(cdxbdy)) * alift
                 + (abs(cdxady) + abs(adxcdy)) * blift
                 + (abs(adxbdy) + abs(bdxady)) * clift)
    return det, ICC_ERRBOUND_A * permanent, permanent


# The staged variants are for tests and benchmarks only: compiled lazily (on
# first use), so that importing the engine does not pay for them.

@kernel
def _orient2d_staged(ax, ay, bx, by, cx, cy):
    """(orient2d value, deciding stage 1..4): :func:`orient2d`, also reporting the stage."""
    det, errbound, detsum = _orient2d_filter(ax, ay, bx, by, cx, cy)
    if det >= errbound or -det >= errbound:
        return det, 1
    return _orient2d_adapt(ax, ay, bx, by, cx, cy, detsum)


@kernel
def _incircle_staged(ax, ay, bx, by, cx, cy, dx, dy):
    """(incircle value, deciding stage 1..4): :func:`incircle`, also reporting the stage."""
    det, errbound, permanent = _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy)
    if det > errbound or -det > errbound:
        return det, 1
    det, stage = _incircle_adapt(ax, ay, bx, by, cx, cy, dx, dy, permanent)
    if stage == 4:
        det = incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)
    return det, stage


# ---------------------------------------------------------------------------
# An exact construction: the crossing point of two segments.
# ---------------------------------------------------------------------------

@kernel(_i8(_W, _i8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def orient_expansion(w, at, ax, ay, bx, by, cx, cy):
    """The exact orient2d(a, b, c) as an expansion at ``w[at + 8:]``; uses
    ``w[at:at + 72]``; returns its length (<= 16)."""
    n_acx = _diff_expansion(w, at, ax, cx)
    n_bcx = _diff_expansion(w, at + 2, bx, cx)
    n_acy = _diff_expansion(w, at + 4, ay, cy)
    n_bcy = _diff_expansion(w, at + 6, by, cy)
    return _cross_expansion(w, at, n_acx, at + 6, n_bcy, at + 4, n_acy, at + 2, n_bcx, at + 8, at + 24)


@kernel(_T2(_W, _i8, _i8), inline='never')
def double_double(w, e, elen):
    """A double-double ``hi + lo`` within a few units of 2^-106 of the
    expansion ``w[e:e+elen]`` (components increasing, non-overlapping)."""
    s = 0.0
    c = 0.0
    for k in range(e, e + elen):
        s, err = _two_sum(s, w[k])
        c += err
    return _fast_two_sum(s, c)


@kernel(_f8(*[_f8] * 9), apart=True, ahead=(_f8,) * 9)
def _crossing_coordinate(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, axis):
    """Coordinate ``axis`` (0.0: x, 1.0: y) of the crossing point of lines
    ``p0 p1`` and ``q0 q1``, rounded to the nearest double (exact when it is a
    double). With d0 = orient(q0, q1, p0) and d1 = orient(q0, q1, p1) as exact
    expansions, the coordinate is (p1 d0 - p0 d1) / (d0 - d1); numerator and
    denominator are taken to double-double precision (relative error ~2^-104)
    and divided with one correction step, so only a value within ~2^-100 of a
    midpoint between doubles could round the other way."""
    w = np.empty(432)
    n0 = orient_expansion(w, 0, q0x, q0y, q1x, q1y, p0x, p0y)          # d0 at w[8:]
    n1 = orient_expansion(w, 72, q0x, q0y, q1x, q1y, p1x, p1y)         # d1 at w[80:]
    for k in range(80, 80 + n1):
        w[150 + k - 80] = -w[k]                                          # -d1 at w[150:]
    nd = _fast_expansion_sum_zeroelim(w, 8, n0, 150, n1, 170)            # d0 - d1 at w[170:]
    a = p1x if axis == 0.0 else p1y
    b = p0x if axis == 0.0 else p0y
    na = _scale_expansion_zeroelim(w, 8, n0, a, 210)                     # p1 d0
    nb = _scale_expansion_zeroelim(w, 150, n1, b, 250)                   # -p0 d1
    nn = _fast_expansion_sum_zeroelim(w, 210, na, 250, nb, 300)          # numerator at w[300:]
    dh, dl = double_double(w, 170, nd)
    nh, nl = double_double(w, 300, nn)
    if dh == 0.0:
        return np.nan
    q = nh / dh
    ph, pl = two_product(q, dh)
    r = ((nh - ph) - pl + nl) - q * dl                                   # N - q D
    return q + r / dh


@kernel(_f8(_W, _i8, _f8, _f8, _f8, _f8, _f8, _f8), inline='never')
def orient_offset_exact(w, n0, ax, ay, bx, by, hx, hy):
    """The sign (+1.0, -1.0 or 0.0) of orient2d(a, b, c + (hx, hy)) for powers
    of two ``hx, hy`` (or zeros), exactly: a corner of a hot pixel (:mod:`.snap`),
    a midpoint between doubles and so not a double itself. ``w[8:8 + n0]``
    holds orient2d(a, b, c) as an exact expansion (:func:`orient_expansion`
    at 0), computed once for the four corners; the sum adds ``(bx - ax) hy -
    (by - ay) hx``, whose terms scale exact differences by powers of two
    (exact). Uses ``w[80:160]``."""
    n1 = _diff_expansion(w, 80, bx, ax)
    for k in range(80, 80 + n1):
        w[k] *= hy
    n2 = _diff_expansion(w, 84, ay, by)
    for k in range(84, 84 + n2):
        w[k] *= hx
    n3 = _fast_expansion_sum_zeroelim(w, 8, n0, 80, n1, 90)
    n4 = _fast_expansion_sum_zeroelim(w, 90, n3, 84, n2, 120)
    top = w[120 + n4 - 1]
    return 1.0 if top > 0.0 else (-1.0 if top < 0.0 else 0.0)


# ---------------------------------------------------------------------------
# The slow stages, compiled once and called by symbol.
# ---------------------------------------------------------------------------
# numba links a callee's code into every caller and code-generates it there
# again. The stages after the float filter are most of the predicates' code
# (about a third of everything the routes compile) and rarely run, so they are
# compiled apart (:mod:`.jit`, "stages compiled apart"): a caller links the
# filter only and calls them by symbol. They compile when the first kernel that
# calls a predicate compiles, not at import.

@kernel(_f8(*[_f8] * 7), apart=True, ahead=(_f8,) * 7)
def _orient2d_slow(ax, ay, bx, by, cx, cy, detsum):
    return _orient2d_adapt(ax, ay, bx, by, cx, cy, detsum)[0]


@kernel(_f8(*[_f8] * 9), apart=True, ahead=(_f8,) * 9)
def _incircle_slow(ax, ay, bx, by, cx, cy, dx, dy, permanent):
    det, stage = _incircle_adapt(ax, ay, bx, by, cx, cy, dx, dy, permanent)
    if stage == 4:
        return incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)
    return det


@kernel(_f8(*[_f8] * 12), apart=True, ahead=(_f8,) * 12)
def _incircle_weighted_slow(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    return incircle_weighted_exact(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)


@kernel
def _before(ax, ay, bx, by):
    """Whether point a comes before point b in lexicographic (x, y) order."""
    return ax < bx or (ax == bx and ay < by)


@kernel(inline='never')
def crossing_point(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y):
    """The crossing point of the lines ``p0 p1`` and ``q0 q1`` (not parallel),
    each coordinate the double nearest to the exact one (exact when it is a
    double), the same for either order and direction of the two segments
    (their canonical order is used); NaN for parallel lines."""
    if _before(p1x, p1y, p0x, p0y):
        p0x, p0y, p1x, p1y = p1x, p1y, p0x, p0y
    if _before(q1x, q1y, q0x, q0y):
        q0x, q0y, q1x, q1y = q1x, q1y, q0x, q0y
    if _before(q0x, q0y, p0x, p0y) or (q0x == p0x and q0y == p0y and _before(q1x, q1y, p1x, p1y)):
        p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y = q0x, q0y, q1x, q1y, p0x, p0y, p1x, p1y
    return (_crossing_coordinate(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, 0.0),
            _crossing_coordinate(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, 1.0))


# ---------------------------------------------------------------------------
# Public filtered predicates.
# ---------------------------------------------------------------------------

@entry(_F6, inline='never')
def orient2d(ax, ay, bx, by, cx, cy):
    """Orientation of (a, b, c), exact in sign (Shewchuk 1997, orient2d with ccwerrboundA).

    Returns a value > 0 if a, b, c are in counter-clockwise order, < 0 if
    clockwise and 0.0 if collinear: the sign of det[[ax-cx, ay-cy], [bx-cx, by-cy]]
    for the exact input doubles (twice the signed area of triangle abc,
    approximately).  Fast path: the floating-point determinant, returned when
    |det| >= CCW_ERRBOUND_A * (|detleft| + |detright|) (when both are 0 the
    determinant is exactly 0); otherwise Shewchuk's adaptive stages B, C, D
    (``_orient2d_adapt``), exact in sign.  Guaranteed for nonzero |coordinates|
    in [1e-130, 1e130] (see the module docstring).
    """
    det, errbound, detsum = _orient2d_filter(ax, ay, bx, by, cx, cy)
    if det >= errbound or -det >= errbound:
        return det
    return _orient2d_slow(ax, ay, bx, by, cx, cy, detsum)


@entry(_F8, inline='never')
def incircle(ax, ay, bx, by, cx, cy, dx, dy):
    """In-circle test, exact in sign (Shewchuk 1997, incircle with iccerrboundA).

    Returns > 0 if d lies strictly inside the circle through a, b, c when a, b, c
    are counter-clockwise (the signs flip when they are clockwise), < 0 if d is
    strictly outside and 0.0 if the four points are cocircular.  This is the
    lifted orientation test of the seed's Sec. 2.8 with all weights zero
    (z = x^2 + y^2): > 0 iff d+ lies below the plane through a+, b+, c+.
    When the float filter fails: stages B and C (``_incircle_adapt``), then
    :func:`incircle_exact`.  Guaranteed for nonzero |coordinates| in [1e-60, 1e60].
    """
    det, errbound, permanent = _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy)
    if det > errbound or -det > errbound:
        return det
    return _incircle_slow(ax, ay, bx, by, cx, cy, dx, dy, permanent)


@entry(_F12, inline='never')
def incircle_weighted(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """Power (weighted in-circle) test: lifted orientation, exact in sign (Shewchuk 1997 filter style).

    Each weighted point p lifts to its companion p+ = (px, py, px^2 + py^2 - pw)
    (seed Sec. 2.8).  With a, b, c counter-clockwise, returns > 0 iff d+ lies
    strictly below the plane through a+, b+, c+ (d is strictly inside the power
    circle: the edge is not locally weighted-Delaunay), < 0 iff strictly above,
    0.0 iff the four lifted points are coplanar.  Computes
    det of rows [pdx, pdy, pdx^2 + pdy^2 - (pw - dw)] for p = a, b, c (translated
    to d; equal to the orient3d of the lifted points).  With all weights 0 it
    equals :func:`incircle` in sign.  Filter: ICCW_ERRBOUND_A times the permanent
    with |pw - dw| in the lift; fallback :func:`incircle_weighted_exact`.
    Weights are arbitrary finite doubles; guaranteed for nonzero |coordinates|
    in [1e-60, 1e60] and nonzero |weights| in [1e-120, 1e120].
    """
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    awd = aw - dw
    bwd = bw - dw
    cwd = cw - dw

    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    asq = adx * adx + ady * ady

    cdxady = cdx * ady
    adxcdy = adx * cdy
    bsq = bdx * bdx + bdy * bdy

    adxbdy = adx * bdy
    bdxady = bdx * ady
    csq = cdx * cdx + cdy * cdy

    det = ((asq - awd) * (bdxcdy - cdxbdy)
           + (bsq - bwd) * (cdxady - adxcdy)
           + (csq - cwd) * (adxbdy - bdxady))
    permanent = ((abs(bdxcdy) + abs(cdxbdy)) * (asq + abs(awd))
                 + (abs(cdxady) + abs(adxcdy)) * (bsq + abs(bwd))
                 + (abs(adxbdy) + abs(bdxady)) * (csq + abs(cwd)))
    errbound = ICCW_ERRBOUND_A * permanent
    if det > errbound or -det > errbound:
        return det
    return _incircle_weighted_slow(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)


# ---------------------------------------------------------------------------
# Unfiltered float determinants (no exactness!): for benchmarks and for the
# tests that show the adversarial inputs defeat plain floating point.
# ---------------------------------------------------------------------------

@kernel(_F6, inline='never')
def orient2d_fast(ax, ay, bx, by, cx, cy):
    """Plain floating-point orient2d, NOT robust (Shewchuk 1997's orient2dfast): for comparison only."""
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


@kernel(_F8, inline='never')
def incircle_fast(ax, ay, bx, by, cx, cy, dx, dy):
    """Plain floating-point incircle, NOT robust (Shewchuk 1997's incirclefast): for comparison only."""
    adx = ax - dx
    ady = ay - dy
    bdx = bx - dx
    bdy = by - dy
    cdx = cx - dx
    cdy = cy - dy
    abdet = adx * bdy - bdx * ady
    bcdet = bdx * cdy - cdx * bdy
    cadet = cdx * ady - adx * cdy
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    return alift * bcdet + blift * cadet + clift * abdet
