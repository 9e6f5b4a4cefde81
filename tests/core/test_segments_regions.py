"""``_core.segments`` and ``_core.regions`` (and the task dedup of the
pipeline): segments become constrained edges with their ids on both halves,
crossings and overlaps are reported with both ids, a crossing can be split,
and the segment depth of every triangle follows the nesting of rings."""
from __future__ import annotations

import numpy as np
import pytest

from cdt_plugin._core.mesh import nxt
from cdt_plugin._core.pipeline import dedup_tasks, solid_with_flags
from cdt_plugin._core.regions import (NO_POLYGON, POLYGON_CONFLICT, flood_seeds, polygon_across,
                                      segment_depths, segment_rings)
from cdt_plugin._core.segments import by_smaller_end, mark_present
from cdt_plugin._core.status import ALL_DONE, STOP_CROSSING, STOP_OVERLAP
from checker import orient2d_exact
from core_stores import add_segments, delaunay_store
from store_check import check_store, constrained_pairs, solid_slots


def pieces_of(s, sid):
    """The constrained edges of segment ``sid`` as input-coordinate pairs."""
    return {frozenset({(s.x[u], s.y[u]), (s.x[v], s.y[v])})
            for (u, v), k in constrained_pairs(s.tri, s.cons, s.ntri).items() if k == sid}


def on_segment_exactly(s, v, a, b):
    P = lambda i: (s.x[i], s.y[i])      # noqa: E731
    return orient2d_exact(P(a), P(b), P(v)) == 0


# a field of points with long segments across it (they must cut through many triangles)
FIELD = np.concatenate([np.random.default_rng(17).random((40, 2)) * 10,
                        [(0, 0), (10, 0), (10, 10), (0, 10), (0.5, 5.0), (9.5, 5.2), (5, 0.5),
                         (5.1, 9.5), (0.3, 8.0), (9.7, 9.1), (0.2, 2.0), (9.8, 1.1)]])
N0 = 40   # first of the named points above


def test_segments_become_constrained_edges():
    s = delaunay_store(FIELD, extra=8)
    segs = [(N0 + 4, N0 + 5), (N0 + 8, N0 + 9), (N0 + 11, N0 + 10)]   # three long bands
    edges = {frozenset((int(s.tri[e]), int(s.tri[nxt(e)]))) for e in range(3 * s.ntri)}
    for a, b in segs:                  # none is an edge yet: each needs the cavity walk
        assert frozenset((s.mesh_of[a], s.mesh_of[b])) not in edges
    status, info, counts = add_segments(s, segs)
    assert status == ALL_DONE
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    assert c["vertices"] == list(range(len(FIELD)))
    cp = constrained_pairs(s.tri, s.cons, s.ntri)
    assert set(cp.values()) <= {1, 2, 3}
    for sid, (a, b) in enumerate(segs, 1):
        A, B = s.mesh_of[a], s.mesh_of[b]
        mine = [uv for uv, k in cp.items() if k == sid]
        assert mine, f"segment {sid} is not in the mesh"
        # the pieces chain from A to B through vertices exactly on the segment
        verts = {v for uv in mine for v in uv}
        assert A in verts and B in verts and len(verts) == len(mine) + 1
        assert all(on_segment_exactly(s, v, A, B) for v in verts)
    assert counts[2] == 0 and s.nv == len(FIELD)                # no Steiner point


def test_crossing_segments_stop_with_both_ids():
    s = delaunay_store(FIELD, extra=8)
    status, info, counts = add_segments(s, [(N0 + 4, N0 + 5), (N0 + 6, N0 + 7)])
    assert status == STOP_CROSSING
    assert (info[0], info[1]) == (2, 1)          # segment 2 found segment 1 in its way
    # info[2:4] is the crossed piece of segment 1, whose ends lie on it
    A, B = s.mesh_of[N0 + 4], s.mesh_of[N0 + 5]
    assert all(on_segment_exactly(s, v, A, B) for v in info[2:4])
    # the store is sane at the stop, and segment 1 is in it
    sanity = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    assert sanity["solid"] > 0 and pieces_of(s, 1)


def test_crossing_segments_split():
    s = delaunay_store(FIELD, extra=8)
    status, info, counts = add_segments(s, [(N0 + 4, N0 + 5), (N0 + 6, N0 + 7)], split=True)
    assert status == ALL_DONE
    assert counts[2] == 1 and s.nv == len(FIELD) + 1
    X = s.nv - 1                                  # the Steiner point, on both (up to rounding)
    cp = constrained_pairs(s.tri, s.cons, s.ntri)
    for sid in (1, 2):
        assert any(X in uv for uv, k in cp.items() if k == sid)
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    assert X in c["vertices"]


def test_vertex_on_a_segment_splits_it():
    P = np.array([(0, 0), (4, 0), (4, 4), (0, 4), (1, 1), (2, 2), (3, 3), (3, 1)], float)
    s = delaunay_store(P)
    status, info, counts = add_segments(s, [(0, 2)])          # through (1,1), (2,2), (3,3)
    assert status == ALL_DONE
    assert counts[0] == 3                                     # three T-junctions
    assert len(pieces_of(s, 1)) == 4
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)


def test_overlapping_segments_stop_or_merge():
    P = np.array([(0, 0), (4, 0), (4, 4), (0, 4), (1, 1), (2, 2), (3, 1)], float)
    s = delaunay_store(P)
    status, info, counts = add_segments(s, [(0, 5), (4, 2)])   # 0-(2,2) and (1,1)-(4,4)
    assert status == STOP_OVERLAP
    assert (info[0], info[1]) == (2, 1)
    c = check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    assert c["solid"] > 0 and pieces_of(s, 1)              # the store is sane at the stop
    s = delaunay_store(P)
    status, info, counts = add_segments(s, [(0, 5), (4, 2)], split=True)
    assert status == ALL_DONE and counts[1] == 1              # one merged overlap
    assert len(pieces_of(s, 1)) == 2 and len(pieces_of(s, 2)) == 1
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)


# ------------------------------------------------------------------ mark_present
def test_mark_present_constrains_existing_edges_only():
    s = delaunay_store(FIELD)
    edges = []
    for e in range(3 * s.ntri):
        u, v = int(s.tri[e]), int(s.tri[nxt(e)])
        if s.inf not in (u, v) and u < v:
            edges.append((u, v))
        if len(edges) == 3:
            break
    A, B = s.mesh_of[N0 + 0], s.mesh_of[N0 + 2]               # a diagonal of the field: no edge
    far = [(A, B), (s.mesh_of[N0 + 4], s.mesh_of[N0 + 5])]
    rows = [(edges[0][1], edges[0][0], 11), far[0] + (12,), (edges[1][0], edges[1][1], 13),
            far[1] + (14,), (edges[2][0], edges[2][1], 15)]
    tasks = np.array(rows, np.int64)
    kept = mark_present(s.tri, s.twin, s.cons, s.ntri, s.nv, tasks, len(rows))
    assert kept == 2
    assert tasks[:2].tolist() == [list(far[0]) + [12], list(far[1]) + [14]]   # in their order
    got = constrained_pairs(s.tri, s.cons, s.ntri)
    assert got == {tuple(sorted(edges[0])): 11, tuple(sorted(edges[1])): 13,
                   tuple(sorted(edges[2])): 15}
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)


def test_by_smaller_end_groups_rows():
    pairs = np.array([(3, 1), (0, 2), (1, 4), (2, 2), (1, 0), (4, 3)], np.int64)
    start, group = by_smaller_end(pairs, len(pairs), 5)
    groups = {a: group[start[a]:start[a + 1]].tolist() for a in range(5)}
    assert groups == {0: [1, 4], 1: [0, 2], 2: [], 3: [5], 4: []}
    assert start[5] == 5                                     # the pair (2, 2) is left out


def test_dedup_tasks_counts():
    segs = np.array([(0, 1), (1, 2), (2, 2), (1, 0), (2, 3), (3, 2), (0, 1), (4, 4)], np.int64)
    tasks, ntask, mult, nzero, first = dedup_tasks(segs, 5)
    assert nzero == 2 and ntask == 3
    rows = tasks[:ntask].tolist()
    assert rows[-1] == [0, 1, 1]                            # the first segment on top of the stack
    assert sorted(r[2] for r in rows) == [1, 2, 5]          # first occurrences keep their ids
    assert mult[1] == 3 and mult[2] == 1 and mult[5] == 2
    assert mult.sum() == len(segs) - nzero
    assert mult[3] == mult[4] == mult[6] == mult[7] == mult[8] == 0
    assert first.tolist() == [0, 1, -1, 0, 4, 4, 0, -1]


# ------------------------------------------------------------------ regions
def NO_RINGS(m):
    """segment_rings of ``m`` segments without rings, and no ring polygons."""
    return np.zeros(m + 2, np.int64), np.empty(0, np.int64), np.empty(0, np.int64)


def test_segment_rings_lists_every_ring_on_a_segment():
    first = np.array([0, 1, 0, -1, 4, 4])      # 2 merged into 0, 3 dropped, 5 merged into 4
    seg_ring = np.array([0, 0, 1, 1, -1, 2])
    start, rings = segment_rings(first, seg_ring)
    lists = {sid: sorted(rings[start[sid]:start[sid + 1]].tolist()) for sid in range(1, 7)}
    assert lists == {1: [0, 1], 2: [0], 3: [], 4: [], 5: [2], 6: []}
    start, rings = segment_rings(first, np.empty(0, np.int64))
    assert not start.any() and len(rings) == 0


@pytest.mark.parametrize("label, polys, want", [
    (NO_POLYGON, [], NO_POLYGON), (2, [], 2),              # free segments change nothing
    (NO_POLYGON, [4], 4), (4, [4], NO_POLYGON),            # into a polygon and out again
    (4, [4, 7], 7), (7, [7, 4], 4),                        # across an edge two polygons share
    (NO_POLYGON, [4, 7], POLYGON_CONFLICT),                # two polygons at once: they overlap
    (NO_POLYGON, [4, 4], POLYGON_CONFLICT),                # a ring given twice
    (5, [4], POLYGON_CONFLICT), (5, [4, 7], POLYGON_CONFLICT)])   # another polygon inside one
def test_polygon_across(label, polys, want):
    ring_polygon = np.array([9] + polys + [9], np.int64)     # ring k belongs to polygon polys[k-1]
    rings = np.arange(len(ring_polygon))
    assert polygon_across(label, rings, 1, 1 + len(polys), ring_polygon) == want


def nested_squares(copies=(1, 1, 1)):
    """Squares of half-width 3, 2, 1 around (0, 0), each given ``copies[k]`` times
    (in both directions alternately), plus a few free points between them."""
    pts, segs = [], []
    for h in (3, 2, 1):
        base = len(pts)
        pts += [(-h, -h), (h, -h), (h, h), (-h, h)]
        segs.append([(base + i, base + (i + 1) % 4) for i in range(4)])
    pts += [(0.2, 0.1), (-2.5, 0.3), (1.4, -1.6), (0.1, 2.6), (-1.5, -1.2)]
    out = []
    for ring, c in zip(segs, copies):
        for k in range(c):
            out += ring if k % 2 == 0 else [(b, a) for a, b in ring]
    return np.array(pts, float), np.array(out, np.int64)


def depth_by_position(px, py):
    """How many squares enclose the point."""
    r = max(abs(px), abs(py))
    return sum(r < h for h in (3, 2, 1))


@pytest.mark.parametrize("copies", [(1, 1, 1), (1, 2, 1), (3, 1, 2)])
def test_segment_depths_follow_nesting(copies):
    pts, segs = nested_squares(copies)
    s = delaunay_store(pts)
    mesh_segs = s.mesh_of[segs]
    tasks, ntask, mult, nzero, _ = dedup_tasks(mesh_segs, s.nv)
    assert ntask == 12 and nzero == 0
    # insert the 12 distinct segments (input ids) with the pipeline's ids
    first = {}
    for i, (a, b) in enumerate(segs):
        first.setdefault(frozenset((a, b)), i)
    distinct = sorted(first.values())
    status, info, counts = add_segments(s, [tuple(segs[i]) for i in distinct])
    assert status == ALL_DONE
    # add_segments numbers them 1..12; give them the dedup ids back (mult is by dedup id)
    relabel = {k + 1: i + 1 for k, i in enumerate(distinct)}
    s.cons[:3 * s.ntri] = [relabel.get(int(c), 0) for c in s.cons[:3 * s.ntri]]
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    depth, entry, label = segment_depths(s.tri, s.twin, s.cons, s.ntri, s.inf, mult, *NO_RINGS(len(segs)))
    mult_of_ring = list(copies)
    seen = set()
    for t in range(s.ntri):
        vs = s.tri[3 * t:3 * t + 3]
        if s.inf in vs:
            assert depth[t] == 0 and entry[t] == 0
            continue
        cx, cy = s.x[vs].mean(), s.y[vs].mean()
        k = depth_by_position(cx, cy)              # squares enclosing the triangle
        want = sum(mult_of_ring[:k])
        assert depth[t] == want, (t, cx, cy)
        seen.add(k)
        if k:                                      # entered through the innermost enclosing square
            ring = [r for r, h in enumerate((3, 2, 1)) if max(abs(cx), abs(cy)) < h][-1]
            sid = entry[t]
            a, b = segs[sid - 1]
            assert {a // 4, b // 4} == {ring}, (t, sid)
    assert seen == {1, 2, 3}                       # the outer square is the hull


def test_depth_parity_nested_squares():
    """Depth parity (DESIGN.md, Regions): a loop inside a loop is a hole, an
    island inside it solid again; a ring given twice encloses nothing."""
    for copies, solid in (((1, 1, 1), {1, 3}), ((1, 2, 1), {1, 2})):
        pts, segs = nested_squares(copies)
        s = delaunay_store(pts)
        tasks, ntask, mult, _, _ = dedup_tasks(s.mesh_of[segs], s.nv)
        assert sorted(mult[mult > 0].tolist()) == sorted(copies[0:1] * 4 + copies[1:2] * 4
                                                         + copies[2:3] * 4)
        status, _, _ = add_segments(s, [tuple(segs[r[2] - 1]) for r in tasks[:ntask][::-1]])
        assert status == ALL_DONE
        ids = [int(r[2]) for r in tasks[:ntask][::-1]]          # add_segments numbers from 1
        s.cons[:3 * s.ntri] = [ids[c - 1] if c else 0 for c in s.cons[:3 * s.ntri]]
        check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
        depth, _, _ = segment_depths(s.tri, s.twin, s.cons, s.ntri, s.inf, mult, *NO_RINGS(len(segs)))
        for t in solid_slots(s.tri, s.ntri, s.inf):
            vs = s.tri[3 * t:3 * t + 3]
            k = depth_by_position(s.x[vs].mean(), s.y[vs].mean())
            assert (depth[t] % 2 == 1) == (k in solid), (copies, t, k, depth[t])


def test_flood_seeds_stops_at_segments():
    pts, segs = nested_squares()
    s = delaunay_store(pts)
    status, _, _ = add_segments(s, segs)
    assert status == ALL_DONE
    check_store(s.tri, s.twin, s.cons, s.ntri, s.inf, s.x, s.y)
    T, N, tid, cflag = solid_with_flags(s.tri, s.twin, s.cons, s.ntri, s.inf)
    assert len(T) == len(solid_slots(s.tri, s.ntri, s.inf))
    label = np.full(len(T), -1, np.int64)
    # a seed in the middle ring (between squares 2 and 1), one outside everything (skipped)
    flood_seeds(s.x, s.y, T, N, cflag, np.array([1.5, 50.0]), np.array([0.0, 0.0]),
                np.ones(len(T), np.bool_), label, np.array([7, 8]))
    for i in range(len(T)):
        cx, cy = s.x[T[i]].mean(), s.y[T[i]].mean()
        assert (label[i] == 7) == (depth_by_position(cx, cy) == 2)
    assert 8 not in label
