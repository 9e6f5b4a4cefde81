"""Point location and interpolation (issue #19, parts 2 and 3).

``locate`` is checked exactly: the triangle it returns holds the point (exact
orientations, independent of the engine), a point outside gets -1 only when no
triangle holds it, and a point on an edge or a vertex gets the smallest id of
the triangles holding it, whatever the order of the queries. Interpolation is
checked against linear functions (reproduced by both methods), the vertex
values, scipy's LinearNDInterpolator, and, for the natural neighbour
coordinates, their defining properties (non-negative, summing to one,
reproducing the coordinates themselves).
"""
from __future__ import annotations

import numpy as np
import pytest
from checker import check_triangulation, orient2d_exact
from helpers import verify
from hypothesis import given, settings
from hypothesis import strategies as st

import cdt_plugin
from cdt_plugin import (
    CDTError,
    InputShapeError,
    InvertedTriangleError,
    NonFiniteCoordinateError,
)


def _holders(tri, p):
    """Every triangle that holds ``p`` (closed), by exact orientations."""
    V = tri.vertices
    out = []
    for t, (a, b, c) in enumerate(tri.triangles):
        if (orient2d_exact(V[a], V[b], p) >= 0 and orient2d_exact(V[b], V[c], p) >= 0
                and orient2d_exact(V[c], V[a], p) >= 0):
            out.append(t)
    return out


def _check_locate(tri, Q):
    found = tri.locate(Q)
    for p, t in zip(Q, found):
        holders = _holders(tri, p)
        assert t == (min(holders) if holders else -1), (p, t, holders)
    # the same answers in any order of the queries
    perm = np.random.default_rng(0).permutation(len(Q))
    assert np.array_equal(tri.locate(Q[perm]), found[perm])
    return found


def test_locate_delaunay_with_points_on_vertices_and_edges():
    rng = np.random.default_rng(1)
    P = rng.integers(0, 8, size=(40, 2)).astype(float)
    tri = cdt_plugin.delaunay(P)
    verify(P, tri)
    grid = np.stack(np.meshgrid(np.arange(-1, 9.5, 0.5), np.arange(-1, 9.5, 0.5)), -1).reshape(-1, 2)
    _check_locate(tri, grid)          # vertices, edges (half-integers), outside the hull


def test_locate_polygon_with_hole_and_concave_corner():
    import shapely
    poly = shapely.Polygon([(0, 0), (10, 0), (10, 10), (5, 4), (0, 10)], [[(2, 2), (4, 2), (4, 3), (2, 3)]])
    tri = cdt_plugin.triangulate(poly, max_area=2.0)
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    assert rep.ok
    rng = np.random.default_rng(2)
    Q = np.concatenate([rng.uniform(-1, 11, (300, 2)), [[3, 2.5], [5, 4], [7, 7], [5, 6], [2, 2], [3, 2]]])
    found = _check_locate(tri, Q)
    assert found[-6] == -1 and found[-5] >= 0 and found[-3] == -1         # hole, corner, notch
    assert ((found >= 0) == shapely.intersects_xy(poly, Q[:, 0], Q[:, 1])).all()


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(-4, 4), st.integers(-4, 4)), min_size=3, max_size=25, unique=True),
       st.lists(st.tuples(st.integers(-10, 10), st.integers(-10, 10)), min_size=1, max_size=30))
def test_locate_exact_on_small_grids(points, queries):
    P = np.array(points, float)
    tri = cdt_plugin.delaunay(P)
    if len(tri.triangles) == 0:
        assert (tri.locate(np.array(queries, float) / 2) == -1).all()
        return
    verify(P, tri)
    _check_locate(tri, np.array(queries, float) / 2)


def test_interpolate_reproduces_linear_functions_and_vertex_values():
    rng = np.random.default_rng(3)
    P = rng.random((500, 2))
    tri = cdt_plugin.delaunay(P)
    verify(P, tri)
    f = np.column_stack([3 + 2 * P[:, 0] - 5 * P[:, 1], np.sin(7 * P[:, 0])])
    Q = rng.uniform(-0.1, 1.1, (4000, 2))
    inside = tri.locate(Q) >= 0
    for method in ("linear", "natural"):
        out = tri.interpolate(f, Q, method=method)
        assert out.shape == (4000, 2)
        assert (np.isnan(out[:, 0]) == ~inside).all()
        assert np.abs(out[inside, 0] - (3 + 2 * Q[inside, 0] - 5 * Q[inside, 1])).max() < 1e-12
        assert np.array_equal(tri.interpolate(f[:, 1], P, method=method), f[:, 1])   # exact at vertices
        one = tri.interpolate(f[:, 1], Q, method=method)
        assert one.shape == (4000,) and np.array_equal(one, out[:, 1], equal_nan=True)


def test_linear_matches_scipy():
    from scipy.interpolate import LinearNDInterpolator
    rng = np.random.default_rng(4)
    P = rng.random((2000, 2))
    f = np.cos(5 * P[:, 0]) * P[:, 1]
    Q = rng.uniform(-0.05, 1.05, (5000, 2))
    ours = cdt_plugin.delaunay(P).interpolate(f, Q)
    theirs = LinearNDInterpolator(P, f)(Q)
    assert np.array_equal(np.isnan(ours), np.isnan(theirs))
    assert np.nanmax(np.abs(ours - theirs)) < 1e-12


def _natural_coordinates(tri, Q):
    return tri.interpolate(np.eye(len(tri.vertices)), Q, method="natural")


def test_natural_coordinates_properties():
    rng = np.random.default_rng(5)
    for P in (rng.random((60, 2)), rng.integers(0, 6, (40, 2)).astype(float)):     # generic, degenerate
        P = np.unique(P, axis=0)
        tri = cdt_plugin.delaunay(P)
        verify(P, tri)
        Q = rng.uniform(0, P.max(), (800, 2))
        W = _natural_coordinates(tri, Q)
        ok = tri.locate(Q) >= 0
        assert (np.isnan(W[:, 0]) == ~ok).all()
        W = W[ok]
        assert W.min() >= 0
        assert np.abs(W.sum(axis=1) - 1).max() < 1e-12
        assert np.abs(W @ tri.vertices - Q[ok]).max() < 1e-9 * max(1.0, P.max())
        # natural neighbours only: a weight on a vertex whose circle test says so
        assert (np.count_nonzero(W, axis=1) >= 3).all()


def test_natural_differs_from_linear_and_is_continuous_across_edges():
    rng = np.random.default_rng(6)
    P = rng.random((30, 2))
    tri = cdt_plugin.delaunay(P)
    f = (P ** 2).sum(axis=1)
    # across an interior edge: approach its midpoint from both sides
    t = 0
    j = int(np.flatnonzero(tri.neighbors[t] >= 0)[0])
    a, b = tri.vertices[tri.triangles[t, (j + 1) % 3]], tri.vertices[tri.triangles[t, (j + 2) % 3]]
    mid = (a + b) / 2
    normal = np.array([a[1] - b[1], b[0] - a[0]])
    side = tri.interpolate(f, [mid + 1e-9 * normal, mid - 1e-9 * normal], method="natural")
    assert abs(side[0] - side[1]) < 1e-6
    Q = rng.random((200, 2))
    lin = tri.interpolate(f, Q)
    nat = tri.interpolate(f, Q, method="natural")
    both = ~np.isnan(lin)
    assert np.abs(lin[both] - nat[both]).max() > 1e-4


def test_natural_stops_at_segments_and_domain():
    import shapely
    poly = shapely.Polygon([(0, 0), (10, 0), (10, 10), (5, 4), (0, 10)], [[(2, 2), (4, 2), (4, 3), (2, 3)]])
    tri = cdt_plugin.triangulate(poly, max_area=1.0)
    V = tri.vertices
    g = 2 * V[:, 0] - V[:, 1]
    rng = np.random.default_rng(7)
    Q = rng.uniform(-1, 11, (3000, 2))
    inside = shapely.intersects_xy(poly, Q[:, 0], Q[:, 1])
    for method in ("linear", "natural"):
        out = tri.interpolate(g, Q, method=method)
        assert (np.isnan(out) == ~inside).all()
        assert np.abs(out[inside] - (2 * Q[inside, 0] - Q[inside, 1])).max() < 1e-12
    # on the boundary (a segment): the linear interpolant along it
    on = np.array([[2.5, 0.0], [3.0, 2.0], [4.0, 2.5]])      # (axis-parallel: on the pieces exactly)
    assert np.allclose(tri.interpolate(g, on, method="natural"), 2 * on[:, 0] - on[:, 1], atol=1e-12)


def test_from_triangles_and_queries():
    V = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]], float)
    T = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    tri = cdt_plugin.Triangulation.from_triangles(V, T[:, ::-1])         # clockwise in, turned round
    rep = check_triangulation(V, tri.triangles, domain="hull")
    assert rep.ok
    assert tri.locate([[1, 0.5], [1, 1], [3, 1]]).tolist() == [0, 0, -1]
    assert tri.interpolate(V[:, 0] + V[:, 1], [[0.5, 0.25]], method="natural")[0] == pytest.approx(0.75)
    nonconvex = cdt_plugin.Triangulation.from_triangles(V, T[:3])        # one quarter missing
    assert nonconvex.locate([[1, 0.25], [0.25, 1]]).tolist() == [0, -1]
    with pytest.raises(InvertedTriangleError, match="triangle 1"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 4], [0, 4, 2]])
    with pytest.raises(InputShapeError, match="outside 0..4"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 5]])
    with pytest.raises(CDTError, match="overlap"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 4], [0, 1, 2]])


def test_overlapping_triangles_cannot_be_queried():
    # two triangles whose edges cross (no edge shared: from_triangles takes them); the
    # walk needs the hull completed (cdt_plugin._routes.hull_triangles), which cannot be
    V = np.array([[0, 0], [4, 0], [0, 4], [1, 1], [5, 1], [1, 5]], float)
    tri = cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [3, 4, 5]])
    with pytest.raises(CDTError, match="edges cross or its vertices repeat: it cannot be queried"):
        tri.locate([[0.5, 0.5]])


def test_bad_queries_are_named():
    tri = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]])
    with pytest.raises(CDTError, match="method"):
        tri.interpolate([1, 2, 3], [[0.1, 0.1]], method="cubic")
    with pytest.raises(InputShapeError, match="one row per vertex"):
        tri.interpolate([1, 2], [[0.1, 0.1]])
    with pytest.raises(NonFiniteCoordinateError, match="row"):
        tri.locate([[0.1, 0.1], [np.nan, 0]])
    with pytest.raises(InputShapeError):
        tri.locate([[0.1, 0.1, 0.1]])
    assert tri.locate(np.empty((0, 2))).shape == (0,)
    assert tri.locate([0.2, 0.2]).tolist() == [0]
    weighted = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1], [1, 1]], [0, 0, 0, 0.1])
    with pytest.raises(CDTError, match="unweighted"):
        weighted.interpolate([1, 2, 3, 4], [[0.5, 0.5]], method="natural")


def test_queries_follow_moved_vertices():
    P = np.array([[0, 0], [2, 0], [0, 2], [2, 2.1]])
    tri = cdt_plugin.delaunay(P)
    assert tri.locate([[1.9, 2.0]]).tolist() != [-1]
    tri.move_vertices([[0, 0], [2, 0], [0, 2], [2, 1.5]])
    assert tri.locate([[1.9, 2.0]]).tolist() == [-1]


def test_far_queries_are_outside_whatever_their_magnitude():
    tri = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1], [1, 1]])
    assert tri.locate([[1e300, 0], [0.5, 0.25], [-1e-300, 0.5], [0, -1e308]]).tolist() == [-1, 1, -1, -1]
    out = tri.interpolate([1.0, 2.0, 3.0, 4.0], [[1e300, 0], [0.25, 0.5]], method="natural")
    assert np.isnan(out[0]) and out[1] == pytest.approx(2.25)
    from cdt_plugin import CoordinateRangeError
    with pytest.raises(CoordinateRangeError, match="row 3"):     # inside the box, beyond exact range
        tri.locate([[1e300, 0], [0.5, 0.5], [-1e-300, 0.5], [1e-320, 0.5]])
