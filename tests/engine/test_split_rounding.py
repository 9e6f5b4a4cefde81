"""Segments that cross within rounding of each other, with intersections="split"
(issue #16). One crossing at a time, the rounded crossing points of near-concurrent
or nearly collinear segments kept making new crossings, or made a segment's pieces
turn back or branch, and the result depended on the order of the segments. Snap
rounding (``_core/snap.py``) rounds every crossing at once: each of these now gives
a mesh the exact checker accepts, the same for any order and direction of the
segments. Reproducers found by a search over such inputs (exact bits as hex)."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import UnresolvedCrossingError
from cdt_plugin._core.scaling import GRID, ON_GRID_ABOVE
from cdt_plugin._core.snap import meets_pixel
from tests.support.checker import (
    canonical_triangles,
    check_steiner_segments,
    check_triangulation,
)

h = float.fromhex

THREE_THROUGH_ONE_POINT = (np.array([[h('-0x1.cbdab73b69d77p+2'), h('-0x1.8742c939233aap+2')],
              [h('0x1.1567f9f72c700p-1'), h('0x1.8a0c9207e5f80p-3')],
              [h('-0x1.70ad801a5237ep+2'), h('-0x1.3b81a49f0ae26p+2')],
              [h('0x1.134b7f5def056p+0'), h('0x1.405be626a514fp-1')],
              [h('-0x1.6b5a94531f660p+0'), h('-0x1.f47ed0afb51a0p+2')],
              [h('0x1.32e2a86229845p+0'), h('0x1.a8477f34ec57dp+1')]]),
    np.array([[0, 1], [2, 3], [4, 5]]))

FOLD = (np.array([[h('0x1.f2a07e7745da4p+1'), h('0x1.c08665d5608c3p+2')], [h('-0x1.f675b6cb8d140p+0'), h('-0x1.a554bb08f9819p+1')], [h('-0x1.d78e68eee8fa4p+0'), h('-0x1.8a29fe9c3fbd3p+1')], [h('0x1.9b1d3d5df5ca0p-2'), h('0x1.bae887dfb9ad6p-1')], [h('-0x1.8ecbfe88fe280p-5'), h('0x1.2d715d23d3b2dp-4')]]),
    np.array([[1, 3], [1, 0], [4, 2]]))

FOLD_B = (np.array([[h('-0x1.83c77c5f30954p-1'), h('-0x1.80996fe270567p-2')], [h('0x1.2f40dda0cd5c7p+0'), h('0x1.5ddaf7d1da0cep+0')], [h('-0x1.719fc808b4b79p-1'), h('-0x1.60062f7c33bcfp-2')], [h('0x1.262d03758f6e1p+0'), h('0x1.55b627b84ae60p+0')], [h('-0x1.2ee7cc462afa1p+0'), h('-0x1.83e764d8d1942p-1')], [h('0x1.9c44ebb7600bfp+0'), h('0x1.bfa84e45a6c15p+0')]]),
    np.array([[0, 1], [2, 3], [4, 5]]))

BRANCH = (np.array([[h('0x1.dbc03970a2d81p-1'), h('-0x1.6b2bffa639d1cp-2')], [h('-0x1.a2a4f03ae1810p-2'), h('0x1.a612fea8e6bc5p+0')], [h('0x1.d12ce8c471870p-1'), h('-0x1.4b80dfd3e0ff5p-2')], [h('-0x1.8d7e4ee27ee60p-2'), h('0x1.9e2836b450868p+0')], [h('0x1.40df93c532e89p+0'), h('-0x1.ae20137c18facp-1')], [h('-0x1.7751663733b65p-1'), h('0x1.112c043eb2633p+1')], [h('0x1.dee156a89608ep-1'), h('-0x1.748af4932aaf4p-2')], [h('-0x1.a8e72aaac7d09p-2'), h('0x1.a86abbe422f6bp+0')]]),
    np.array([[0, 1], [2, 3], [4, 5], [6, 7]]))


def assert_snapped_mesh(P, S, **options):
    """The split mesh of ``P, S`` passes the exact checker (a constrained Delaunay
    triangulation of its pieces; every segment the chain of its pieces through
    points within rounding of it) and is the same for reversed and permuted
    segments. Returns it."""
    tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True, **options)
    assert check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull").ok
    merged = bool(tri.stats["merged_overlaps"] or tri.stats["duplicate_segments"])
    rep = check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids,
                                 snapped_inputs=True, partial=merged)
    assert rep.ok, rep
    assert np.array_equal(tri.vertices[tri.vertex_map], P)
    assert tri.is_delaunay()
    want = canonical_triangles(tri.vertices, tri.triangles)
    rng = np.random.default_rng(len(S))
    for S2 in (S[::-1], S[:, ::-1], S[rng.permutation(len(S))][:, ::-1]):
        other = cdt_plugin.triangulate(P, np.ascontiguousarray(S2), intersections="split",
                                       keep_hull=True, **options)
        assert canonical_triangles(other.vertices, other.triangles) == want
    return tri


@pytest.mark.parametrize("case", ["THREE_THROUGH_ONE_POINT", "FOLD", "FOLD_B", "BRANCH"])
def test_crossings_within_rounding_give_the_right_mesh_in_any_order(case):
    """THREE_THROUGH_ONE_POINT: three segments through nearly one point (two 0.2
    degrees apart), whose rounded crossings lie within 5e-15 of each other: one
    crossing at a time never converged. FOLD, FOLD_B, BRANCH gave meshes whose
    segment pieces fold back (positions 0, 0.444, 0.435, 1 along a segment) or
    branch, then UnresolvedCrossingError."""
    V, S = globals()[case]
    tri = assert_snapped_mesh(V, S)
    assert tri.stats["intersection_points"] >= 1


def test_the_crossings_count_against_max_steiner_before_anything_is_built():
    P = np.array([[0, 1], [4, 1], [0, 2], [4, 2], [0, 3], [4, 3],
                  [1, 0], [1, 4], [2, 0], [2, 4], [3, 0], [3, 4]], float)
    S = np.arange(12).reshape(6, 2)                 # three by three: nine crossings
    with pytest.raises(UnresolvedCrossingError, match="need 9 intersection points, more than "
                                                       "max_steiner=8.*raise max_steiner") as e:
        cdt_plugin.triangulate(P, S, intersections="split", max_steiner=8)
    assert len(e.value.segments) == 2
    tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True, max_steiner=9)
    assert tri.stats["intersection_points"] == 9
    assert check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids).ok


def test_a_vertex_within_rounding_of_a_segment_where_segments_cross_joins_its_chain():
    """Snap rounding routes a segment through every hot pixel it meets: here the
    input point 4 lies a few units in the last place off segment 0, inside the
    pixel that segment passes through, and the chain of segment 0 passes through it."""
    x = 0.1 + 0.7 * 3 ** -0.5
    P = np.array([[0.0, 0.0], [1.0, 0.7], [0.0, 1.0], [1.0, 0.0], [x, 0.7 * x]])
    S = np.array([[0, 1], [2, 3]])
    tri = assert_snapped_mesh(P, S)
    chain = {tuple(p) for p, i in zip(tri.segments.tolist(), tri.segment_ids) if i == 0}
    on_chain = any(4 in p for p in chain)
    assert on_chain == bool(meets_pixel(0.0, 0.0, 1.0, 0.7, x, 0.7 * x, np.empty(160)))


# ------------------------------------------------------------------ property tests
@st.composite
def fans(draw):
    """Segments through nearly one point: a random centre moved by a few units in
    the last place per segment, random directions and lengths."""
    m = draw(st.integers(3, 12))
    seed = draw(st.integers(0, 2**32 - 1))
    spread = draw(st.sampled_from([0.0, 1e-17, 1e-15, 1e-12]))
    scale = draw(st.sampled_from([1.0, 1e3, 2.0 ** -30]))
    rng = np.random.default_rng(seed)
    c = rng.random(2) + spread * rng.standard_normal((m, 2))
    angle = rng.random(m) * np.pi
    d = np.column_stack([np.cos(angle), np.sin(angle)])
    P = np.empty((2 * m, 2))
    P[0::2], P[1::2] = c - d, c + d * rng.random((m, 1))
    return P * scale, np.arange(2 * m).reshape(m, 2)


@settings(max_examples=60, deadline=None)
@given(fans())
def test_fans_through_nearly_one_point_are_right_in_any_order(case):
    assert_snapped_mesh(*case)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(-900, 900))
def test_split_is_scale_invariant(seed, e):
    """Pixels scale with the coordinates (the engine brings them near 1 by a power
    of two first): the split mesh of ``P * 2**e`` is that of ``P``, times ``2**e``."""
    rng = np.random.default_rng(seed)
    m = int(rng.integers(3, 10))
    P = rng.random((2 * m, 2))
    S = np.arange(2 * m).reshape(m, 2)
    unit = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
    scaled = cdt_plugin.triangulate(np.ldexp(P, e), S, intersections="split", keep_hull=True)
    assert np.array_equal(np.ldexp(unit.vertices, e), scaled.vertices)
    assert np.array_equal(unit.triangles, scaled.triangles)


# ------------------------------------------------------------------ pixels, exactly
def pixel(c: float) -> tuple[Fraction, Fraction]:
    """The half-open pixel around coordinate ``c``: ``[lo, hi)`` (half the gap to
    the neighbouring doubles, or to the neighbouring multiples of 2**-240 near 0)."""
    if abs(c) < ON_GRID_ABOVE:
        g = Fraction(GRID) / 2
        return Fraction(c) - g, Fraction(c) + g
    return ((Fraction(c) + Fraction(math.nextafter(c, -math.inf))) / 2,
            (Fraction(c) + Fraction(math.nextafter(c, math.inf))) / 2)


def meets_half_open_box(a, b, box) -> bool:
    """Whether segment ``a b`` meets ``[x0, x1) x [y0, y1)``, by the parameter
    interval of the segment inside each slab, in rationals."""
    lo, lo_open, hi, hi_open = Fraction(0), False, Fraction(1), False
    for axis in (0, 1):
        p, d = Fraction(a[axis]), Fraction(b[axis]) - Fraction(a[axis])
        s0, s1 = box[axis]
        if d == 0:
            if not s0 <= p < s1:
                return False
            continue
        t0, t1 = (s0 - p) / d, (s1 - p) / d           # closed at s0, open at s1
        if d > 0:
            cand = ((t0, False), (t1, True))
        else:
            cand = ((t1, True), (t0, False))
        (u, u_open), (v, v_open) = cand
        if u > lo or (u == lo and u_open):
            lo, lo_open = u, u_open
        if v < hi or (v == hi and v_open):
            hi, hi_open = v, v_open
    return lo < hi or (lo == hi and not lo_open and not hi_open)


def corner_cases(rng, n):
    """Segments and pixel centres where the answer is on a knife's edge: through
    pixel corners and along pixel sides, at powers of two (pixels wider above than
    below), near zero (the 2**-240 grid), and random near misses."""
    out = []
    for _ in range(n):
        kind = int(rng.integers(0, 5))
        cx, cy = rng.random(2) * 4 - 2
        if kind == 1:
            cx, cy = 2.0 ** int(rng.integers(-3, 3)), -(2.0 ** int(rng.integers(-3, 3)))
        if kind == 2:
            cx, cy = float(rng.integers(-3, 4)) * 2.0 ** -240, float(rng.integers(-3, 4)) * 2.0 ** -240
        (x0, x1), (y0, y1) = pixel(cx), pixel(cy)
        corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
        target = corners[int(rng.integers(0, 4))] if kind in (1, 2, 3) else (Fraction(cx), Fraction(cy))
        # a line through the target (a corner, or the centre for near misses), its ends doubles
        ang = rng.random() * np.pi
        if kind == 4 or rng.random() < 0.3:
            ang = float(rng.choice([0.0, np.pi / 4, np.pi / 2, 3 * np.pi / 4]))
        L = float(rng.choice([1e-15, 1e-10, 1.0]))
        tx, ty = float(target[0]), float(target[1])
        a = (tx - L * math.cos(ang), ty - L * math.sin(ang))
        b = (tx + L * math.cos(ang) * rng.random(), ty + L * math.sin(ang) * rng.random())
        if kind == 3:            # a side of the pixel, exactly, as the segment's line
            a, b = (tx, ty - L), (tx, ty + L)
        out.append((a, b, (cx, cy)))
    return out


def test_meets_pixel_is_exact_on_knife_edges():
    rng = np.random.default_rng(5)
    w = np.empty(160)
    hits = 0
    for a, b, (cx, cy) in corner_cases(rng, 4000):
        if a == b:
            continue
        want = meets_half_open_box(a, b, (pixel(cx), pixel(cy)))
        got = bool(meets_pixel(a[0], a[1], b[0], b[1], cx, cy, w))
        assert got == want, (a, b, (cx, cy))
        hits += want
    assert 400 < hits < 3600           # both answers well represented


def lattice(c: float, k: int) -> list[float]:
    """The ``2k + 1`` doubles around ``c`` (on the 2**-240 grid near zero)."""
    if abs(c) < ON_GRID_ABOVE:
        return [c + i * GRID for i in range(-k, k + 1)]
    below, above, v = [], [], c
    for _ in range(k):
        v = math.nextafter(v, -math.inf)
        below.append(v)
    v = c
    for _ in range(k):
        v = math.nextafter(v, math.inf)
        above.append(v)
    return below[::-1] + [c] + above


@pytest.mark.parametrize("cx, cy", [(1.0, 1.0), (2.0, -0.5), (0.75, 3.0), (-1.0, 2.0 ** -200),
                                    (2.0 ** -187, 1.5), (0.0, 0.0), (1e10, 3e-10)])
def test_meets_pixel_on_every_segment_between_neighbouring_doubles(cx, cy):
    """Every segment between two of the 5 x 5 doubles around a centre passes through
    pixel corners, along pixel sides or just past them: the exact answer each time,
    also where the pixel is wider on one side (a power of two) or on the 2**-240 grid."""
    w = np.empty(160)
    pts = [(x, y) for x in lattice(cx, 2) for y in lattice(cy, 2)]
    box = (pixel(cx), pixel(cy))
    answers = set()
    for i, a in enumerate(pts):
        for b in pts[i + 1:]:
            want = meets_half_open_box(a, b, box)
            assert bool(meets_pixel(a[0], a[1], b[0], b[1], cx, cy, w)) == want, (a, b)
            assert bool(meets_pixel(b[0], b[1], a[0], a[1], cx, cy, w)) == want, (b, a)
            answers.add(want)
    assert answers == {True, False}


# ------------------------------------------------------------------ the net under it
def store(triangles, constrained):
    """A half-edge store of ``triangles`` (vertex triples) whose first edge
    carries segment id ``constrained[t]`` (0: none): what the check reads."""
    tri = np.array(triangles, np.int64).ravel()
    cons = np.zeros_like(tri)
    cons[0::3] = constrained
    return tri, cons, len(triangles)


def test_pieces_out_of_order_finds_overlapping_and_overshooting_pieces():
    """The compiled check that runs after every split (single calls and batches):
    pieces of segment 1 from (0, 0) to (4, 0) through (1, 0), (2, 0), (3, 0)."""
    from cdt_plugin._core.segments import pieces_out_of_order
    x = np.array([0.0, 1, 2, 3, 4, 5, 2])
    y = np.array([0.0, 0, 0, 0, 0, 0, 1])
    ends = np.array([[0, 4]], np.int64)
    apex = 6
    in_order = store([[0, 1, apex], [1, 2, apex], [2, 4, apex]], [1, 1, 1])
    assert pieces_out_of_order(*in_order, x, y, ends) == (0, -1, -1, -1)
    with_gap = store([[0, 1, apex], [2, 4, apex]], [1, 1])            # a merged overlap's gap
    assert pieces_out_of_order(*with_gap, x, y, ends)[0] == 0
    overlapping = store([[0, 2, apex], [1, 3, apex], [3, 4, apex]], [1, 1, 1])
    assert pieces_out_of_order(*overlapping, x, y, ends) == (1, 1, 1, 3)
    beyond = store([[0, 2, apex], [2, 5, apex]], [1, 1])              # past the segment's end
    assert pieces_out_of_order(*beyond, x, y, ends) == (1, 1, 2, 5)
    reversed_ends = np.array([[4, 0]], np.int64)                      # the same, either direction
    assert pieces_out_of_order(*overlapping, x, y, reversed_ends)[0] == 1


def test_the_route_stop_for_pieces_out_of_order_names_segment_and_point():
    from cdt_plugin._core.status import ROUTE_UNRESOLVED
    from cdt_plugin.cdt import _raise_stop
    from cdt_plugin.plc import as_plc
    plc = as_plc(np.array([[0.0, 0], [4, 0], [2, -1], [2, 1]]), np.array([[0, 1], [2, 3]]))
    bits = np.array([2.0, 1e-16]).view(np.int64)
    with pytest.raises(UnresolvedCrossingError, match=r"segment 1 \(\(2.0, -1.0\)-\(2.0, 1.0\)\).*"
                                                       r"near \(2.0, 1e-16\).*\(3 such pieces\)") as e:
        _raise_stop(ROUTE_UNRESOLVED, np.array([2, 3, bits[0], bits[1]]), plc)
    assert e.value.segments == (1,) and e.value.point == (2.0, 1e-16)


def test_every_crossing_of_a_dense_soup_by_default():
    """Snap rounding counts the crossings before anything is built, so the default cap
    of the one-at-a-time rounding (10 m + 1000 points) does not apply: 200 random
    segments cross about 4,400 times."""
    m = 200
    P = np.random.default_rng(9).random((2 * m, 2))
    S = np.arange(2 * m).reshape(m, 2)
    tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
    assert tri.stats["intersection_points"] > 10 * m + 1000
    assert check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull").ok
    assert check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids,
                                  partial=bool(tri.stats["merged_overlaps"])).ok


def _jagged_ring(n, offset):
    rng = np.random.default_rng(0)
    angle = np.sort(rng.random(n)) * 2 * np.pi
    radius = 50 + 10 * rng.random(n)
    P = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)]) + offset
    return P, np.column_stack([np.arange(n), (np.arange(n) + 1) % n])


def test_the_buckets_stay_small_far_from_the_origin():
    """A drawing 120 wide at 1e15 from the origin (coordinates on a grid of 0.125):
    the buckets' margin follows the coordinates' rounding (a few ulps), not a
    fraction of their size that spans the drawing. With the old margin (2**-40 of
    the largest coordinate, 900 units here) every piece fell in every bucket and
    the crossing search tested every pair in each (minutes); now a piece meets a
    few buckets, and the result is the snap-rounded mesh (checked exactly)."""
    from cdt_plugin._core.snap import bucket_segments, make_grid
    P, S = _jagged_ring(2000, 1e15)
    x, y = P[:, 0].copy(), P[:, 1].copy()
    pieces = np.column_stack([S, np.arange(len(S))]).astype(np.int64)
    start, _ = bucket_segments(x, y, pieces, make_grid(x, y, np.int64(len(S))))
    assert start[-1] / len(S) < 20          # buckets per piece (2,000 with the old margin)
    tri = assert_snapped_mesh(P, S)
    assert tri.stats["intersection_points"] > 0      # rounding made edges cross
