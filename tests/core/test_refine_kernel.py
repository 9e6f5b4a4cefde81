"""``_core.refine.refine_store`` on small constrained Delaunay stores: it
finishes, meets the angle and area bounds it was given, keeps the store sane,
the mesh constrained Delaunay, the segments chains of their pieces, and the
outside (label ``OUT``) untouched."""
from __future__ import annotations

import math

import numpy as np

from cdt_plugin._core.options import RefineOptions
from cdt_plugin._core.refine import C_SEG_SPLITS, C_STEINER, OUT, refine_store
from cdt_plugin._core.regions import segment_depths
from cdt_plugin._core.status import FINISHED, LIMIT
from core_stores import add_segments, delaunay_store
from store_check import check_store, constrained_pairs, solid_slots

SQUARE = [(0, 0), (4, 0), (4, 4), (0, 4)]
SKINNY = SQUARE + [(1, 0.1), (3, 0.15), (2.1, 3.9), (1.2, 1.3), (2.9, 2.4)]
SIDES = [(0, 1), (1, 2), (2, 3), (3, 0), (7, 8)]          # the square and one inner segment


def cdt(points, segments, extra=0):
    s = delaunay_store(np.asarray(points, float), extra=extra)
    status, _, _ = add_segments(s, segments)
    assert status == 0
    s.seg_ends = s.mesh_of[np.asarray(segments, np.int64)]
    return s


def labels(s, inside=None):
    """Slot labels: -1 (no region) for the solid triangles ``inside`` (all by default), OUT else."""
    lab = np.full(s.tri.shape[0] // 3, OUT, np.int64)
    for t in solid_slots(s.tri, s.ntri, s.inf):
        if inside is None or inside(t):
            lab[t] = -1
    return lab


def run(s, lab, min_angle=0.0, max_area=0.0, max_new=100_000):
    area = np.array([max_area]) if max_area > 0 else np.zeros(1)
    store = (s.tri, s.twin, s.cons, s.x, s.y, s.w, s.inf, s.ntri, s.nv)
    options = RefineOptions(min_angle=float(min_angle), max_area=float(max_area))
    status, counts, lab, seg_ends, store, _ = refine_store(store, lab, s.seg_ends, options, area,
                                                           max_new, 0, np.empty(0, np.int64), -1,
                                                           (np.empty((0, 3), np.int64),) * 2)
    tri, twin, cons, x, y, w, inf, ntri, nv = store
    return int(status), counts, lab, seg_ends, (tri, twin, cons, int(ntri), int(inf), x, y, int(nv))


def min_angle_deg(x, y, t3):
    P = np.column_stack([x[t3], y[t3]])
    out = []
    for j in range(3):
        u, v = P[(j + 1) % 3] - P[j], P[(j + 2) % 3] - P[j]
        out.append(math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)))
    return min(out)


def twice_area(x, y, t3):
    a, b, c = t3
    return abs((x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]))


def assert_pieces_on_segments(tri, cons, ntri, x, y, seg_ends):
    """Every constrained edge lies on its segment: ends exactly on it when they
    are input vertices, within a few ulps when they are Steiner points; and
    each segment's pieces form one chain between its ends."""
    pieces = {}
    for (u, v), sid in constrained_pairs(tri, cons, ntri).items():
        pieces.setdefault(sid, []).append((u, v))
    assert set(pieces) == set(range(1, len(seg_ends) + 1))
    for sid, mine in pieces.items():
        A, B = (int(v) for v in seg_ends[sid - 1])
        deg = {}
        for u, v in mine:
            deg[u] = deg.get(u, 0) + 1
            deg[v] = deg.get(v, 0) + 1
        assert {v for v, d in deg.items() if d == 1} == {A, B} and max(deg.values()) <= 2
        L = math.hypot(x[B] - x[A], y[B] - y[A])
        for v in deg:
            off = abs((x[B] - x[A]) * (y[v] - y[A]) - (y[B] - y[A]) * (x[v] - x[A])) / L
            assert off <= 8 * np.spacing(max(abs(x[A]), abs(y[A]), abs(x[B]), abs(y[B]), 1.0))


def test_refine_meets_the_minimum_angle():
    s = cdt(SKINNY, SIDES)
    before = min(min_angle_deg(s.x, s.y, s.tri[3 * t:3 * t + 3])
                 for t in solid_slots(s.tri, s.ntri, s.inf))
    assert before < 10
    status, counts, lab, seg_ends, (tri, twin, cons, ntri, inf, x, y, nv) = run(
        s, labels(s), min_angle=28)
    assert status == FINISHED
    assert counts[C_STEINER] == nv - s.nv > 0 and counts[C_SEG_SPLITS] > 0
    c = check_store(tri, twin, cons, ntri, inf, x, y)
    assert c["vertices"] == list(range(nv))                 # input vertices all kept
    assert np.array_equal(x[:s.nv], s.x[:s.nv])
    worst = min(min_angle_deg(x, y, tri[3 * t:3 * t + 3]) for t in solid_slots(tri, ntri, inf))
    assert worst >= 28 - 1e-9
    assert seg_ends.shape == (len(SIDES), 2)                 # the hull was segments already
    assert_pieces_on_segments(tri, cons, ntri, x, y, seg_ends)
    for t in solid_slots(tri, ntri, inf):
        assert lab[t] == -1
    for t in range(ntri):
        if inf in tri[3 * t:3 * t + 3]:
            assert lab[t] == OUT


def test_refine_meets_the_area_bound_and_makes_hull_segments():
    pts = SQUARE + [(1.5, 2.5)]
    s = cdt(pts, [])                                         # no segments: the hull becomes them
    s.seg_ends = np.empty((0, 2), np.int64)
    status, counts, lab, seg_ends, (tri, twin, cons, ntri, inf, x, y, nv) = run(
        s, labels(s), max_area=0.3)
    assert status == FINISHED
    assert len(seg_ends) == 4                                # the four hull edges
    check_store(tri, twin, cons, ntri, inf, x, y)
    areas = [twice_area(x, y, tri[3 * t:3 * t + 3]) / 2 for t in solid_slots(tri, ntri, inf)]
    assert max(areas) <= 0.3 and abs(sum(areas) - 16) < 1e-9
    assert_pieces_on_segments(tri, cons, ntri, x, y, seg_ends)


def test_refine_leaves_a_hole_alone():
    outer = [(0, 0), (6, 0), (6, 6), (0, 6)]
    hole = [(2, 2), (4, 2), (4, 4), (2, 4)]
    segs = [(i, (i + 1) % 4) for i in range(4)] + [(4 + i, 4 + (i + 1) % 4) for i in range(4)]
    s = cdt(outer + hole + [(3, 3.2), (1, 5.5)], segs)
    depth, _, _ = segment_depths(s.tri, s.twin, s.cons, s.ntri, s.inf, np.ones(len(segs) + 1, np.int64),
                                 np.zeros(len(segs) + 2, np.int64), np.empty(0, np.int64),
                                 np.empty(0, np.int64))
    lab = labels(s, inside=lambda t: depth[t] % 2 == 1)
    in_hole = [t for t in solid_slots(s.tri, s.ntri, s.inf) if lab[t] == OUT]
    assert in_hole
    status, counts, lab2, seg_ends, (tri, twin, cons, ntri, inf, x, y, nv) = run(
        s, lab, min_angle=25, max_area=0.5)
    assert status == FINISHED and nv > s.nv
    c = check_store(tri, twin, cons, ntri, inf, x, y)
    assert c["vertices"] == list(range(nv))                  # the free point in the hole too
    for t in solid_slots(tri, ntri, inf):
        cx, cy = x[tri[3 * t:3 * t + 3]].mean(), y[tri[3 * t:3 * t + 3]].mean()
        hole_side = 2 < cx < 4 and 2 < cy < 4
        assert (lab2[t] == OUT) == hole_side
        if not hole_side:
            assert min_angle_deg(x, y, tri[3 * t:3 * t + 3]) >= 25 - 1e-9
            assert twice_area(x, y, tri[3 * t:3 * t + 3]) <= 1.0
    # no Steiner point strictly inside the hole: its triangles are those of the CDT
    for v in range(s.nv, nv):
        assert not (2 < x[v] < 4 and 2 < y[v] < 4), (x[v], y[v])
    assert_pieces_on_segments(tri, cons, ntri, x, y, seg_ends)


def test_refine_stops_at_the_steiner_limit_with_a_sane_store():
    s = cdt(SKINNY, SIDES)
    status, counts, lab, seg_ends, (tri, twin, cons, ntri, inf, x, y, nv) = run(
        s, labels(s), min_angle=30, max_new=3)
    assert status == LIMIT
    assert counts[C_STEINER] == 3 and nv == s.nv + 3
    check_store(tri, twin, cons, ntri, inf, x, y)
    assert_pieces_on_segments(tri, cons, ntri, x, y, seg_ends)
    assert (cons >= 0).all()                                 # frozen pieces unfrozen on return
