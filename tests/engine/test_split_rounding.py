"""Segments that cross within rounding of each other, with intersections="split"
(issue #16): the rounded crossing points of near-concurrent or nearly collinear
segments can keep making new crossings, or make a segment's pieces turn back or
branch. Where the mesh cannot contain the segments as given, the route raises
UnresolvedCrossingError naming them, never a mesh the exact checker rejects.
Reproducers found by a search over such inputs (exact bits as hex)."""
from __future__ import annotations

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin import SegmentIntersectionError, UnresolvedCrossingError
from tests.support.checker import check_steiner_segments, check_triangulation

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



def test_rounded_crossings_that_keep_crossing_raise_a_named_error():
    """Three segments through nearly one point (two 0.2 degrees apart): the three
    rounded crossings lie within 5e-15 of each other and the split loop never
    converged (a plain CDTError at the cap, in every order); now a
    SegmentIntersectionError subclass naming the segments, whatever the cap."""
    V, S = THREE_THROUGH_ONE_POINT
    for cap in (None, 20_000):
        with pytest.raises(UnresolvedCrossingError, match="still cross; they cross within rounding") as e:
            cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True, max_steiner=cap)
        assert isinstance(e.value, SegmentIntersectionError) and len(e.value.segments) == 2
    with pytest.raises(UnresolvedCrossingError):
        cdt_plugin.triangulate(V, S[::-1, ::-1], intersections="split")


def test_a_low_cap_still_says_raise_max_steiner():
    P = np.array([[0, 1], [4, 1], [0, 2], [4, 2], [0, 3], [4, 3],
                  [1, 0], [1, 4], [2, 0], [2, 4], [3, 0], [3, 4]], float)
    S = np.arange(12).reshape(6, 2)                 # three by three: nine crossings
    with pytest.raises(UnresolvedCrossingError, match="raise max_steiner"):
        cdt_plugin.triangulate(P, S, intersections="split", max_steiner=1)
    tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
    assert check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids).ok


@pytest.mark.parametrize("case", ["FOLD", "FOLD_B", "BRANCH"])
def test_pieces_that_would_turn_back_or_branch_raise(case):
    """These gave a valid, Delaunay-checked mesh whose segment pieces fold back
    (positions 0, 0.444, 0.435, 1 along a segment) or branch from one vertex: a
    silently wrong mesh. Now the error names a segment and where."""
    V, S = globals()[case]
    with pytest.raises(UnresolvedCrossingError, match="within rounding of each other near") as e:
        cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True)
    s, = e.value.segments
    assert 0 <= s < len(S) and e.value.point is not None


def test_every_result_of_near_crossings_is_right_or_the_named_error():
    """Random fans through nearly one point: each result has every segment as the
    chain of its pieces (exact checker) or raises UnresolvedCrossingError."""
    rng = np.random.default_rng(16)
    meshes = errors = 0
    for _ in range(60):
        m = int(rng.integers(3, 12))
        angle = rng.random(m) * np.pi
        d = np.column_stack([np.cos(angle), np.sin(angle)])
        c = rng.random(2) + 1e-15 * rng.standard_normal((m, 2))
        P = np.empty((2 * m, 2))
        P[0::2], P[1::2] = c - d, c + d * rng.random((m, 1))
        S = np.arange(2 * m).reshape(m, 2)
        try:
            tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
        except UnresolvedCrossingError:
            errors += 1
            continue
        meshes += 1
        assert check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull").ok
        if tri.stats["merged_overlaps"] or tri.stats["duplicate_segments"]:
            continue            # (merged segments' pieces carry one of their ids)
        assert check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids,
                                      snapped_inputs=True).ok
    assert meshes and errors

