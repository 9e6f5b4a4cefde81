"""``_core.pipeline``: the one compiled CDT route (status codes and ``info``
for every stop, output arrays the exact checker accepts) and the batch loop,
which must give per geometry exactly what the route gives."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from cdt_plugin._core.construct import DIVIDE, FLIP, INCREMENTAL
from cdt_plugin._core.options import RefineOptions, RouteOptions, plain
from cdt_plugin._core.pipeline import (K_DUPLICATE_SEGMENTS, K_DUPLICATES, K_FLIPS,
                                       K_INTERSECTIONS, K_MERGED_OVERLAPS, K_REF_COMPLETE,
                                       K_ZERO_SEGMENTS, cdt_route, mesh_geometries, no_store)
from cdt_plugin._core.snap import snap_route
from cdt_plugin._core.status import (ROUTE_COLLINEAR, ROUTE_CROSSING, ROUTE_HOLE_OUTSIDE,
                                     ROUTE_NEEDS_SNAP, ROUTE_OK, ROUTE_OVERLAP, ROUTE_REFINE_LIMIT,
                                     ROUTE_STEINER_LIMIT)
from checker import assert_valid, canonical_triangles, check_steiner_segments
from helpers import check_neighbors

NO_IDS = np.empty(0, np.int64)
NO_RINGS = np.empty(0, np.bool_)
NO_SEEDS = np.empty((0, 2))
NO_REGIONS = np.empty((0, 4))
NOT_SNAPPED = (np.empty(0), np.empty(0), np.empty((0, 3), np.int64))
BUILD_HERE = no_store()       # the route builds its Delaunay triangulation itself


def route(points, segs=(), rings=None, algorithm=DIVIDE, split=False, keep_hull=False,
          max_steiner=-1, refinement=None, holes=NO_SEEDS):
    """``cdt_route`` with the arguments :func:`cdt_plugin.triangulate` passes: the
    options in a :class:`RouteOptions` (``refinement``: a :class:`RefineOptions`,
    or None not to refine). ``rings``: ``(seg_ring, ring_polygon, ring_is_hole)``."""
    P = np.asarray(points, float).reshape(-1, 2)
    S = np.asarray(segs, np.int64).reshape(-1, 2)
    seg_ring, ring_polygon, ring_is_hole = ((NO_IDS, NO_IDS, NO_RINGS) if rings is None else
                                            (np.asarray(rings[0], np.int64),
                                             np.asarray(rings[1], np.int64),
                                             np.asarray(rings[2], np.bool_)))
    holes = np.asarray(holes, float).reshape(-1, 2)
    x, y = P[:, 0].copy(), P[:, 1].copy()
    options = RouteOptions(algorithm=algorithm, split=split, keep_hull=keep_hull,
                           use_seeds=len(holes) > 0, max_steiner=max_steiner,
                           refine=refinement is not None, refinement=refinement or RefineOptions())
    snapped = NOT_SNAPPED
    while True:
        status, info, counts, out = cdt_route(
            (x, y, S, seg_ring, ring_polygon, ring_is_hole, holes, NO_REGIONS), (NO_IDS, NO_IDS),
            options, snapped, BUILD_HERE)
        if status != ROUTE_NEEDS_SNAP:
            break
        status, info, *plan = snap_route(x, y, S, max_steiner)   # segments cross: snap them
        if status != ROUTE_OK:
            return int(status), info, None, None
        snapped = tuple(plan)
    names = ("vertices", "triangles", "neighbors", "constrained", "pieces", "piece_ids",
             "regions", "vertex_map", "kept", "below")
    return int(status), info, counts, SimpleNamespace(**dict(zip(names, out)))


def ring_segs(*sizes):
    """Segments and ring of each for consecutive rings of the given sizes."""
    segs, ring_of, v = [], [], 0
    for r, n in enumerate(sizes):
        segs += [(v + i, v + (i + 1) % n) for i in range(n)]
        ring_of += [r] * n
        v += n
    return segs, ring_of


def area(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return 0.5 * np.sum((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def verify_out(points, o, segs=(), keep_hull=False, merged=False):
    """The route's output for the exact checker: a CDT of its vertices and pieces
    (bounded by segments, or the whole hull with ``keep_hull``), neighbours
    symmetric, every input point accounted for in ``vertex_map``, every input
    segment the chain of its pieces (with ``merged`` overlaps a shared piece
    carries one segment's id only: then each input segment must be a chain of
    edges through vertices exactly on it)."""
    P = np.asarray(points, float).reshape(-1, 2)
    assert len(o.triangles) > 0
    assert np.array_equal(o.vertices[o.vertex_map], P)
    assert len(np.unique(o.vertex_map)) == len(o.kept) <= len(o.vertices)
    assert (o.triangles[:, 0] < o.triangles[:, 1]).all() and (o.triangles[:, 0] < o.triangles[:, 2]).all()
    check_neighbors(SimpleNamespace(triangles=o.triangles, neighbors=o.neighbors))
    if not keep_hull:
        assert o.constrained[o.neighbors < 0].all()
    rep = assert_valid(o.vertices, o.triangles, segments=o.pieces,
                       domain="hull" if keep_hull else "segments",
                       require_all_vertices=keep_hull)
    if len(segs) and merged:
        assert len(o.vertices) == len(o.kept)     # (no Steiner point: chains exactly on segments)
        assert_valid(o.vertices, o.triangles, segments=o.vertex_map[np.asarray(segs)],
                     domain="hull" if keep_hull else "segments", require_all_vertices=keep_hull)
    elif len(segs):
        sr = check_steiner_segments(P, np.asarray(segs), o.vertices, o.vertex_map, o.pieces,
                                    o.piece_ids)
        assert sr.ok, str(sr)
    return rep


SHELL = [(0, 0), (6, 0), (6, 6), (0, 6)]
HOLE = [(2, 2), (4, 2), (4, 4), (2, 4)]


# ------------------------------------------------------------------ ROUTE_OK
@pytest.mark.parametrize("algorithm", [DIVIDE, INCREMENTAL, FLIP])
def test_route_ok_square_with_hole(algorithm):
    pts = SHELL + HOLE + [(1, 3), (5, 1.5), (3, 3)]
    segs, ring_of = ring_segs(4, 4)
    status, info, counts, o = route(pts, segs, (ring_of, [0, 0], [False, True]), algorithm)
    assert status == ROUTE_OK
    verify_out(pts, o, segs)
    assert math.isclose(area(o.vertices, o.triangles), 36 - 4)
    assert (o.regions == 0).all()                 # every kept triangle is polygon 0's
    assert o.vertex_map.tolist() == list(range(len(pts)))
    centre = o.vertices[o.triangles].mean(axis=1)
    assert not ((centre > 2) & (centre < 4)).all(axis=1).any()


def test_route_same_triangles_by_every_algorithm():
    rng = np.random.default_rng(5)
    pts = np.concatenate([SHELL, rng.random((30, 2)) * 6])
    segs = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (6, 7)]
    got = []
    for alg in (DIVIDE, INCREMENTAL, FLIP):
        status, info, counts, o = route(pts, segs, split=True, algorithm=alg)
        assert status == ROUTE_OK
        verify_out(pts, o, segs)
        got.append(canonical_triangles(o.vertices, o.triangles))
    assert got[0] == got[1] == got[2]


def test_route_counts_duplicates_and_repeated_segments():
    pts = SHELL + [(3, 3), (6, 0), (3, 3)]          # input 5 repeats 1, input 6 repeats 4
    segs = [(0, 1), (1, 2), (2, 3), (3, 0), (2, 1), (4, 6), (0, 5)]
    status, info, counts, o = route(pts, segs)
    assert status == ROUTE_OK
    assert counts[K_DUPLICATES] == 2
    assert counts[K_ZERO_SEGMENTS] == 1             # 4-6 is one point
    assert counts[K_DUPLICATE_SEGMENTS] == 2        # 2-1 and 0-5 (= 0-1)
    assert o.vertex_map[5] == o.vertex_map[1] and o.vertex_map[6] == o.vertex_map[4]
    assert len(o.vertices) == 5
    verify_out(pts, o)


def test_route_with_refinement():
    pts = SHELL + HOLE + [(0.5, 0.2), (5.5, 0.3)]
    segs, ring_of = ring_segs(4, 4)
    status, info, counts, o = route(pts, segs, (ring_of, [0, 0], [False, True]),
                                    refinement=RefineOptions(min_angle=25.0))
    assert status == ROUTE_OK and counts[K_REF_COMPLETE] == 1
    assert len(o.below) == 0 and len(o.vertices) > len(pts)
    verify_out(pts, o, segs)
    assert math.isclose(area(o.vertices, o.triangles), 32)
    status, info, counts, o = route(pts, segs, (ring_of, [0, 0], [False, True]),
                                    refinement=RefineOptions(min_angle=30.0), max_steiner=2)
    assert status == ROUTE_REFINE_LIMIT and counts[K_REF_COMPLETE] == 0
    assert len(o.vertices) == len(pts) + 2          # the partial mesh is complete
    verify_out(pts, o, segs)


# ------------------------------------------------------------------ the stops
def test_route_collinear():
    pts = [(0, 0), (1, 1), (3, 3), (2, 2)]
    status, info, counts, o = route(pts, [(0, 2)])
    assert status == ROUTE_COLLINEAR
    assert len(o.triangles) == 0 and len(o.vertices) == 0


def test_route_crossing_reports_both_segments():
    pts = SHELL + [(1, 1), (5, 4), (1, 5), (4, 0.5)]
    segs = [(0, 1), (1, 2), (4, 5), (6, 7)]          # 3 (id 3) and 4 (id 4) cross
    status, info, counts, o = route(pts, segs)
    assert status == ROUTE_CROSSING
    assert sorted(info[:2].tolist()) == [3, 4]       # 1-based segment ids
    assert len(o.triangles) == 0
    status, info, counts, o = route(pts, segs, split=True, keep_hull=True)
    assert status == ROUTE_OK and counts[K_INTERSECTIONS] == 1
    assert len(o.vertices) == len(pts) + 1
    verify_out(pts, o, segs, keep_hull=True)


def test_route_overlap_and_steiner_limit():
    pts = SHELL + [(1, 1), (2, 2), (3, 3)]
    status, info, counts, o = route(pts, [(4, 6), (5, 2)])          # (1,1)-(3,3) and (2,2)-(6,6)
    assert status == ROUTE_OVERLAP and sorted(info[:2].tolist()) == [1, 2]
    status, info, counts, o = route(pts, [(4, 6), (5, 2)], split=True, keep_hull=True)
    assert status == ROUTE_OK and counts[K_MERGED_OVERLAPS] == 1
    verify_out(pts, o, [(4, 6), (5, 2)], keep_hull=True, merged=True)
    # open segments enclose nothing: without keep_hull no triangle is inside
    status, info, counts, o = route(pts, [(4, 6), (5, 2)], split=True)
    assert status == ROUTE_OK and len(o.triangles) == 0
    cross = SHELL + [(1, 1), (5, 4), (1, 5), (4, 0.5)]
    status, info, counts, o = route(cross, [(4, 5), (6, 7)], split=True, max_steiner=0)
    assert status == ROUTE_STEINER_LIMIT
    assert sorted(info[:2].tolist()) == [1, 2] and info[2] == 0


def test_route_hole_outside_its_shell():
    pts = SHELL + [(8, 2), (10, 2), (10, 4), (8, 4)]
    segs, ring_of = ring_segs(4, 4)
    status, info, counts, o = route(pts, segs, (ring_of, [0, 0], [False, True]))
    assert status == ROUTE_HOLE_OUTSIDE and info[0] == 1
    # the same rings, the second a shell, are fine
    status, info, counts, o = route(pts, segs, (ring_of, [0, 1], [False, False]))
    assert status == ROUTE_OK
    assert sorted(set(o.regions.tolist())) == [0, 1]
    verify_out(pts, o, segs)


def test_route_keep_hull_and_hole_seeds():
    pts = SHELL + HOLE
    segs = ring_segs(4, 4)[0]
    status, _, _, o = route(pts, segs, keep_hull=True)
    assert status == ROUTE_OK and math.isclose(area(o.vertices, o.triangles), 36)
    verify_out(pts, o, segs, keep_hull=True)
    status, _, _, o = route(pts, segs, holes=[(3, 3)])
    assert status == ROUTE_OK and math.isclose(area(o.vertices, o.triangles), 32)
    verify_out(pts, o, segs)


# ------------------------------------------------------------------ mesh_geometries
def test_mesh_geometries_equals_the_route_per_geometry():
    # geometry 0: square with hole; 1: triangle; 2: bow-tie (crossing); 3: empty; 4: star
    star = [(10 + 3 * math.cos(k * math.pi / 5) * (1 if k % 2 else 0.4),
             3 * math.sin(k * math.pi / 5) * (1 if k % 2 else 0.4)) for k in range(10)]
    rings = [SHELL, HOLE, [(20, 0), (23, 0), (21, 2)], [(30, 0), (32, 2), (32, 0), (30, 2)], star]
    geom_rings = [[0, 1], [2], [3], [], [4]]
    ring_is_hole = np.array([False, True, False, False, False])
    ring_polygon = np.array([0, 0, 0, 0, 0])
    xy = np.array([p for r in rings for p in r], float)
    ring_start = np.cumsum([0] + [len(r) for r in rings])
    geom_ring_start = np.cumsum([0] + [len(g) for g in geom_rings])
    x, y = xy[:, 0].copy(), xy[:, 1].copy()
    T, G, R, S, failed = mesh_geometries(x, y, ring_start, geom_ring_start, ring_polygon,
                                         ring_is_hole, 0, len(geom_rings), plain(RouteOptions()),
                                         len(xy))
    assert failed.tolist() == [False, False, True, False, False]
    assert len(S) == 0
    assert sorted(set(G.tolist())) == [0, 1, 4]
    for g, rs in enumerate(geom_rings):
        if not rs or failed[g]:
            continue
        v0, v1 = ring_start[rs[0]], ring_start[rs[-1] + 1]
        segs, ring_of = ring_segs(*[len(rings[r]) for r in rs])
        status, info, counts, o = route(xy[v0:v1], segs,
                                        (ring_of, ring_polygon[rs], ring_is_hole[rs]))
        assert status == ROUTE_OK
        verify_out(xy[v0:v1], o, segs)
        mine = T[G == g]
        assert mine.tolist() == (v0 + o.kept[o.triangles]).tolist()
        assert R[G == g].tolist() == o.regions.tolist()
    # the failing geometry fails the route the same way
    segs, ring_of = ring_segs(4)
    status, *_ = route(xy[ring_start[3]:ring_start[4]], segs, (ring_of, [0], [False]))
    assert status == ROUTE_CROSSING


# ------------------------------------------------------------------ defects found by these tests (fixed)
def test_route_flip_counts_the_flips_of_the_flip_algorithm():
    pts = np.random.default_rng(3).random((60, 2))
    status, info, counts, o = route(pts, [(0, 1)], algorithm=FLIP, keep_hull=True)
    assert status == ROUTE_OK
    verify_out(pts, o, [(0, 1)], keep_hull=True)
    assert counts[K_FLIPS] > 0


def test_mesh_geometries_refuses_a_degenerate_ring_like_triangulate():
    import cdt_plugin
    from cdt_plugin import InvalidGeometryError
    shell, hole = [(0, 0), (4, 0), (4, 4), (0, 4)], [(1, 3), (1, 3), (2, 2)]
    with pytest.raises(InvalidGeometryError):
        cdt_plugin.triangulate({"type": "Polygon",
                                "coordinates": [shell + shell[:1], hole + hole[:1]]})
    xy = np.array(shell + hole, float)
    T, G, R, S, failed = mesh_geometries(xy[:, 0].copy(), xy[:, 1].copy(), np.array([0, 4, 7]),
                                         np.array([0, 2]), np.array([0, 0]),
                                         np.array([False, True]), 0, 1, plain(RouteOptions()),
                                         len(xy))
    assert failed[0] or len(T) == 0


def test_crossings_stop_the_route_until_they_are_snap_rounded():
    """Splitting, the route stops at the first crossing with ROUTE_NEEDS_SNAP (the
    snap rounding is compiled apart, for the inputs that need it); called again with
    ``snap_route``'s crossings it finishes. The batch loop leaves such a geometry to
    the single call."""
    bowtie = np.array([[0, 0], [2, 2], [2, 0], [0, 2.0]])
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    x, y = bowtie[:, 0].copy(), bowtie[:, 1].copy()
    status, *_ = cdt_route((x, y, S, NO_IDS, NO_IDS, NO_RINGS, NO_SEEDS, NO_REGIONS), (NO_IDS, NO_IDS),
                           RouteOptions(split=True), NOT_SNAPPED, BUILD_HERE)
    assert status == ROUTE_NEEDS_SNAP
    status, info, new_x, new_y, chains = snap_route(x, y, S, -1)
    assert status == ROUTE_OK and new_x.tolist() == [1.0] and new_y.tolist() == [1.0]
    # (the new point is vertex 4: segments 0 and 2 pass through it, in order)
    assert chains.tolist() == [[0, 4, 0], [4, 1, 0], [1, 2, 1], [2, 4, 2], [4, 3, 2], [3, 0, 3]]
    status, info, counts, o = route(bowtie, S, split=True)
    assert status == ROUTE_OK and counts[K_INTERSECTIONS] == 1
    verify_out(bowtie, o, S)
    T, G, R, St, failed = mesh_geometries(x, y, np.array([0, 4]), np.array([0, 1]), NO_IDS,
                                          NO_RINGS, 0, 1, plain(RouteOptions(split=True)), 4)
    assert failed.tolist() == [True] and len(T) == 0
