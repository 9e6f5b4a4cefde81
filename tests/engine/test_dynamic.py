"""DynamicCDT (issue #19): edits of a live constrained Delaunay triangulation.

The invariant: after any sequence of edits the snapshot is, as a set of
coordinate triangles, ``triangulate(vertices, segments, keep_hull=True)`` of
the final vertices and segments (unique under the symbolic perturbation), and
the independent exact checker accepts it as a constrained Delaunay
triangulation of the hull.
"""
from __future__ import annotations

import numpy as np
import pytest
from checker import canonical_triangles, check_triangulation
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import (
    CDTError,
    DynamicCDT,
    NonFiniteCoordinateError,
    SegmentIndexError,
    SegmentIntersectionError,
    UnknownIdError,
)


def _verify(dyn: DynamicCDT, domain: str = "hull") -> cdt_plugin.Triangulation:
    """The snapshot, checked exactly and against a triangulation from scratch."""
    tri = dyn.triangulation(domain)
    V, S = dyn.vertices, dyn.segments
    assert np.array_equal(tri.vertices, V)
    if len(tri.triangles):
        # (even-odd: the segments' pieces outside the domain go with their triangles)
        S_in = S if domain == "hull" else tri.segments
        rep = check_triangulation(V, tri.triangles, segments=S_in if len(S_in) else None,
                                  domain="hull" if domain == "hull" else "segments",
                                  require_all_vertices=domain == "hull")
        assert rep.ok, rep.problems[:3]
        assert tri.is_delaunay()
    if len(V) >= 3:
        fresh = cdt_plugin.triangulate(V, S if len(S) else None, keep_hull=domain == "hull")
        assert canonical_triangles(V, tri.triangles) == canonical_triangles(fresh.vertices, fresh.triangles)
    return tri


def test_doc_example_and_ids():
    dyn = DynamicCDT([[0, 0], [4, 0], [4, 4], [0, 4]])
    assert dyn.insert_points([[1, 1], [3, 1], [4, 4], [1, 1]]).tolist() == [4, 5, 2, 4]
    assert dyn.insert_segments([[4, 2], [2, 4]]).tolist() == [0, 0]
    tri = _verify(dyn)
    assert tri.segments.tolist() == [[2, 4]] and tri.segment_ids.tolist() == [0]
    dyn.remove_vertices([4])
    assert len(dyn) == 5 and len(dyn.segments) == 0
    assert dyn.vertex_ids.tolist() == [0, 1, 2, 3, 5]
    tri = _verify(dyn)
    assert tri.vertex_map.tolist() == [0, 1, 2, 3, -1, 4]
    assert dyn.insert_points([[2, 3]]).tolist() == [6]         # ids are never reused


def test_point_on_segment_splits_it_and_segment_through_vertex():
    dyn = DynamicCDT([[0, 0], [4, 0], [2, 3], [2, -3]])
    (s,) = dyn.insert_segments([[0, 1]])
    dyn.insert_points([[1, 0], [3, 0]])                        # on the segment
    tri = _verify(dyn)
    assert sorted(map(tuple, np.sort(tri.segments, axis=1).tolist())) == [(0, 4), (1, 5), (4, 5)]
    assert set(tri.segment_ids.tolist()) == {s}
    dyn.insert_points([[2, 1], [2, 2]])
    with pytest.raises(SegmentIntersectionError, match=r"cross at about \(2.0, 0.0\)"):
        dyn.insert_segments([[3, 2]])                          # crosses segment 0 at (2, 0)
    dyn.insert_points([[2, 0]])                                # now a vertex of both
    dyn.insert_segments([[3, 2]])
    tri = _verify(dyn)
    assert len(tri.segments) == 4 + 4                          # (1, 0), (2, 0), (3, 0) and (2, 0), (2, 1), (2, 2)


def test_crossing_raises_and_changes_nothing():
    dyn = DynamicCDT([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 2]])
    before = dyn.triangulation().triangles.copy()
    with pytest.raises(SegmentIntersectionError, match="cross"):
        dyn.insert_segments([[1, 3]])
    assert len(dyn.segments) == 1
    assert np.array_equal(dyn.triangulation().triangles, before)
    _verify(dyn)


def test_crossing_split():
    dyn = DynamicCDT([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 2]], intersections="split")
    dyn.insert_segments([[1, 3]])
    assert len(dyn) == 5 and dyn.vertices[4].tolist() == [2.0, 2.0]
    tri = dyn.triangulation()
    assert tri.steiner.tolist() == [4]
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull")
    assert rep.ok
    assert len(tri.segments) == 4 and sorted(tri.segment_ids.tolist()) == [0, 0, 1, 1]


def _verify_split(dyn: DynamicCDT) -> cdt_plugin.Triangulation:
    """The snapshot of a live triangulation with ``"split"``, checked exactly
    with its segment pieces (a segment that crosses others is the chain of its
    pieces up to rounding), and against triangulate (:func:`_split_reference`)."""
    tri = dyn.triangulation()
    rep = check_triangulation(tri.vertices, tri.triangles,
                              segments=tri.segments if len(tri.segments) else None, domain="hull")
    assert rep.ok, rep.problems[:3]
    assert tri.is_delaunay()
    assert _split_reference(dyn) == canonical_triangles(tri.vertices, tri.triangles)
    return tri


def _split_reference(dyn: DynamicCDT) -> set:
    """What triangulate gives for the live vertices that are not crossing
    points and the live segments, snap-rounded: the snapshot must equal it."""
    tri = dyn.triangulation()
    keep = np.ones(len(tri.vertices), bool)
    keep[tri.steiner] = False
    rows = np.cumsum(keep) - 1
    assert keep[dyn.segments].all(), "a segment ends at a crossing point"
    ref = cdt_plugin.triangulate(tri.vertices[keep], rows[dyn.segments], intersections="split",
                                 keep_hull=True)
    return canonical_triangles(ref.vertices, ref.triangles)


@pytest.mark.parametrize("case", ["THREE_THROUGH_ONE_POINT", "FOLD", "FOLD_B", "BRANCH"])
def test_split_crossings_within_rounding_in_any_order_of_edits(case):
    """Segments that cross within rounding of each other (the reproducers of
    the snap rounding in triangulate): inserted one per edit, in every order,
    the live triangulation is snap-rounded as triangulate rounds them, the
    same mesh whatever the order (it raised UnresolvedCrossingError when it
    rounded one crossing at a time)."""
    import itertools

    from tests.engine import test_split_rounding as reproducers
    V, S = getattr(reproducers, case)
    want = cdt_plugin.triangulate(V, S, intersections="split", keep_hull=True)
    for perm in itertools.permutations(range(len(S))):
        dyn = DynamicCDT(V, intersections="split")
        for k in perm:
            dyn.insert_segments(S[k:k + 1])
        tri = _verify_split(dyn)
        assert canonical_triangles(tri.vertices, tri.triangles) == \
            canonical_triangles(want.vertices, want.triangles), perm


def test_split_crossing_points_are_derived():
    """A crossing point lives while its segments cross: removing one of them
    drops it; a point inserted on it, or a segment that ends at it, keeps it as
    an ordinary vertex; every state equals triangulate's."""
    dyn = DynamicCDT([[0, 0], [4, 0], [4, 4], [0, 4], [1, 3]], [[0, 2]], intersections="split")
    (s1,) = dyn.insert_segments([[1, 3]])
    assert dyn.triangulation().steiner.tolist() == [5] and len(dyn) == 6
    dyn.remove_segments([s1])
    assert len(dyn) == 5 and len(dyn.triangulation().steiner) == 0
    (s1,) = dyn.insert_segments([[1, 3]])
    crossing = int(dyn.vertex_ids[-1])
    assert dyn.vertices[-1].tolist() == [2.0, 2.0]
    dyn.insert_segments([[4, crossing]])          # ends at the crossing point: kept
    dyn.remove_segments([s1])
    tri = _verify_split(dyn)
    assert len(dyn) == 6 and len(tri.steiner) == 0
    (p,) = dyn.insert_points([[3, 0.5]])
    dyn.insert_segments([[1, 3], [4, p]])          # through the kept vertex; a crossing at 1.88..
    assert len(_verify_split(dyn).steiner) == 1
    dyn.insert_points([[0.5, 0.5], [3, 3.5]])      # on a segment, and off: the crossings rounded again
    tri = _verify_split(dyn)
    assert len(tri.steiner) == 1 and len(dyn) == 10


def test_split_crossing_point_goes_with_the_last_segment():
    """Regression (fuzz): removing the vertices that end both crossing segments
    leaves no segment; their crossing point goes too."""
    dyn = DynamicCDT([[2, 3], [3, 1], [4, 3], [0, 3], [3, 5], [5, 3], [0, 6]], intersections="split")
    dyn.insert_segments([[3, 5], [4, 1]])
    assert len(dyn) == 8
    dyn.remove_vertices([1, 5])
    tri = _verify_split(dyn)
    assert len(dyn) == 5 and len(tri.steiner) == 0


def test_bad_input_named_and_state_unchanged():
    dyn = DynamicCDT([[0, 0], [1, 0], [0, 1]])
    before = dyn.triangulation().triangles.copy()
    with pytest.raises(NonFiniteCoordinateError):
        dyn.insert_points([[0.5, 0.2], [np.nan, 1]])
    with pytest.raises(UnknownIdError, match="no vertex 7"):
        dyn.remove_vertices([7])
    with pytest.raises(UnknownIdError, match="no segment 0"):
        dyn.remove_segments([0])
    with pytest.raises(SegmentIndexError, match="to itself"):
        dyn.insert_segments([[1, 1]])
    with pytest.raises(UnknownIdError):
        dyn.insert_segments([[0, 9]])
    with pytest.raises(CDTError, match="intersections"):
        DynamicCDT(intersections="snap")
    with pytest.raises(CDTError, match="domain"):
        dyn.triangulation("inside")
    dyn.remove_vertices([2])
    with pytest.raises(UnknownIdError, match="removed"):
        dyn.move_vertices([2], [[3, 3]])
    with pytest.raises(CDTError, match="both be at"):
        dyn.move_vertices([1], [[0, 0]])
    assert len(dyn) == 2 and len(dyn.triangulation().triangles) == 0
    assert before.shape == (1, 3)


def test_grows_from_collinear_and_empty():
    dyn = DynamicCDT()
    assert len(dyn) == 0 and len(dyn.triangulation().triangles) == 0
    dyn.insert_points([[0, 0], [1, 1], [2, 2]])
    dyn.insert_segments([[0, 2]])
    assert len(dyn.triangulation().triangles) == 0
    dyn.insert_points([[0, 2]])
    tri = _verify(dyn)
    assert len(tri.triangles) == 2


def test_batch_ids_follow_the_input_order():
    rng = np.random.default_rng(8)
    dyn = DynamicCDT(rng.random((100, 2)))
    B = rng.random((300, 2))
    ids = dyn.insert_points(np.vstack([B, B[:5], [dyn.vertices[7]]]))
    assert ids[:300].tolist() == list(range(100, 400))        # sorted inside, numbered as given
    assert ids[300:].tolist() == [100, 101, 102, 103, 104, 7]
    assert np.array_equal(dyn.vertices[ids[:300]], B)
    _verify(dyn)


def test_segments_given_before_the_first_triangle_fail_with_the_edit_that_builds_it():
    dyn = DynamicCDT([[0, 0], [2, 0], [4, 0]])
    dyn.insert_segments([[0, 2], [2, 1]])          # overlap, found once there is a triangle
    with pytest.raises(cdt_plugin.OverlappingSegmentsError):
        dyn.insert_points([[1, 1]])
    assert len(dyn) == 3 and len(dyn.triangulation().triangles) == 0
    dyn.remove_segments([1])
    assert dyn.insert_points([[1, 1]]).tolist() == [3]
    _verify(dyn)


def test_many_single_point_inserts_grow_the_store():
    rng = np.random.default_rng(3)
    pts = rng.random((3000, 2))
    dyn = DynamicCDT(pts[:3])
    for p in pts[3:]:
        dyn.insert_points(p)
    _verify(dyn)


def test_move_and_remove_segments():
    rng = np.random.default_rng(5)
    pts = rng.random((200, 2))
    pts[:6] = [[0.1, 0.1], [0.9, 0.1], [0.1, 0.5], [0.9, 0.5], [0.1, 0.9], [0.9, 0.9]]
    dyn = DynamicCDT(pts)
    ids = dyn.insert_segments([[0, 1], [2, 3], [4, 5]])
    dyn.remove_segments([ids[1]])
    _verify(dyn)
    dyn.move_vertices([0, 7], [[0.5, 0.5], [0.25, 0.75]])
    _verify(dyn)


def test_even_odd_domain_equals_triangulate():
    outer = [[0, 0], [10, 0], [10, 10], [0, 10]]
    inner = [[3, 3], [7, 3], [7, 7], [3, 7]]
    dyn = DynamicCDT(outer + inner + [[12, 5], [5, -2]])
    dyn.insert_segments([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    _verify(dyn, "even-odd")
    tri = dyn.triangulation("even-odd")
    area = 0.5 * np.abs(np.cross(tri.vertices[tri.triangles[:, 1]] - tri.vertices[tri.triangles[:, 0]],
                                 tri.vertices[tri.triangles[:, 2]] - tri.vertices[tri.triangles[:, 0]])).sum()
    assert area == 100 - 16


def test_from_triangulation_round_trip():
    import shapely
    poly = shapely.Polygon([(0, 0), (6, 0), (6, 6), (0, 6)], [[(2, 2), (4, 2), (4, 4), (2, 4)]])
    tri = cdt_plugin.triangulate(poly)
    dyn = DynamicCDT.from_triangulation(tri)
    back = _verify(dyn, "even-odd")
    assert canonical_triangles(back.vertices, back.triangles) == canonical_triangles(tri.vertices, tri.triangles)


@st.composite
def _edits(draw):
    """A random sequence of edits on a small integer grid (duplicates,
    collinear and cocircular points are the rule there)."""
    coord = st.integers(0, 6).map(float)
    point = st.tuples(coord, coord)
    ops = []
    for _ in range(draw(st.integers(1, 12))):
        kind = draw(st.sampled_from(["points", "points", "segment", "remove", "unsegment", "move"]))
        if kind == "points":
            ops.append((kind, draw(st.lists(point, min_size=1, max_size=6))))
        else:
            ops.append((kind, draw(st.integers(0, 10 ** 6)), draw(point)))
    return draw(st.lists(point, min_size=0, max_size=8)), ops


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_edits())
def test_random_edit_sequences_match_a_fresh_triangulation(case):
    start, ops = case
    dyn = DynamicCDT(start if start else None)
    for op in ops:
        ids = dyn.vertex_ids
        before = (dyn.vertices.copy(), dyn.segments.copy(), dyn.triangulation().triangles.copy())
        try:
            if op[0] == "points":
                dyn.insert_points(op[1])
            elif op[0] == "segment" and len(ids) >= 2:
                a = ids[op[1] % len(ids)]
                b = ids[(op[1] // 7) % len(ids)]
                if a != b:
                    dyn.insert_segments([[a, b]])
            elif op[0] == "remove" and len(ids):
                dyn.remove_vertices([ids[op[1] % len(ids)]])
            elif op[0] == "unsegment" and len(dyn.segment_ids):
                dyn.remove_segments([dyn.segment_ids[op[1] % len(dyn.segment_ids)]])
            elif op[0] == "move" and len(ids):
                dyn.move_vertices([ids[op[1] % len(ids)]], [op[2]])
        except CDTError:
            # a crossing, an overlap or a vertex moved onto another: nothing changed
            assert np.array_equal(dyn.vertices, before[0])
            assert np.array_equal(dyn.segments, before[1])
            assert np.array_equal(dyn.triangulation().triangles, before[2])
        _verify(dyn)
        if len(dyn.segments):
            _verify(dyn, "even-odd")


def test_example_moving_points(tmp_path, capsys):
    """examples/moving_points.py (the README's picture) runs: its swirl stays
    Delaunay under move_vertices and its channel snapshots match a rebuild."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "moving_points.py"
    spec = importlib.util.spec_from_file_location("moving_points", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    png = tmp_path / "moving.png"
    module.main(str(png))
    out = capsys.readouterr().out
    assert "channel step 30:" in out and "swirl step 30:" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
