"""The Delaunay subdivision and the Voronoi / power diagram (issue #20, Sec. 2.2, 2.8).

Every triangulation is verified by the independent exact checker; the subdivision's
faces are checked exactly (cocircular, convex, empty circles), the diagram against
scipy's Qhull on generic points and by its defining property on every input: a
point lies in the cell of its nearest site (power distance with weights).
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cdt_plugin
from cdt_plugin import (ClipRegionError, CollinearPointsError, NotDelaunayError, Triangulation,
                        TooFewPointsError)
from tests.support.checker import incircle_exact, orient2d_exact
from tests.support.helpers import verify


def _delaunay(points, weights=None):
    tri = cdt_plugin.delaunay(points, weights)
    verify(points, tri, weights)
    return tri


def _area(ring):
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]    # relative: no cancellation
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _check_subdivision(tri):
    """Exact: each face is a strictly convex CCW polygon whose vertices are
    cocircular, with no vertex inside its circle; the faces tile the triangles."""
    sub = tri.delaunay_subdivision()
    V = tri.vertices
    assert sub.offsets[0] == 0 and sub.offsets[-1] == len(sub.indices)
    seen = np.zeros(len(sub), int)
    np.add.at(seen, sub.face_of_triangle, 1)
    assert (seen >= 1).all()
    for f, face in enumerate(sub):
        assert len(face) >= 3 and len(set(face.tolist())) == len(face)
        assert face[0] == face.min()
        assert len(face) == seen[f] + 2               # a convex m-gon is m - 2 triangles
        for i in range(len(face)):
            assert orient2d_exact(V[face[i - 2]], V[face[i - 1]], V[face[i]]) > 0
        a, b, c = V[face[0]], V[face[1]], V[face[2]]
        for d in face[3:]:
            assert incircle_exact(a, b, c, V[d]) == 0
        if len(V) <= 60:                              # empty circle, against every vertex
            others = np.setdiff1d(np.arange(len(V)), face)
            assert all(incircle_exact(a, b, c, V[d]) < 0 for d in others)
    for t, f in enumerate(sub.face_of_triangle):      # each triangle's vertices are its face's
        assert set(tri.triangles[t].tolist()) <= set(sub[f].tolist())
    return sub


def _owner(sites, weights, q):
    """Index of the site nearest to each query (least power distance), exactly."""
    out = []
    for x, y in q:
        fx, fy = Fraction(float(x)), Fraction(float(y))
        best = None
        for i, (sx, sy) in enumerate(sites):
            w = Fraction(float(weights[i])) if weights is not None else 0
            d = (fx - Fraction(float(sx))) ** 2 + (fy - Fraction(float(sy))) ** 2 - w
            if best is None or d < best[0]:
                best = (d, i)
        out.append(best[1])
    return np.array(out)


def _in_ring(ring, p, slack):
    """Point p inside (or within ``slack`` of) a convex CCW ring."""
    a = ring
    b = np.roll(ring, -1, axis=0)
    cross = (b[:, 0] - a[:, 0]) * (p[1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (p[0] - a[:, 0])
    return bool((cross >= -slack * np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1])).all())


def _check_clipped(vor, box, rng, samples=200):
    xmin, ymin, xmax, ymax = box
    areas = np.array([_area(vor.cell(i)) if len(vor.cell(i)) else 0.0 for i in range(len(vor.points))])
    assert (areas >= -1e-12).all()
    assert abs(areas.sum() - (xmax - xmin) * (ymax - ymin)) <= 1e-9 * (xmax - xmin) * (ymax - ymin)
    q = np.column_stack([rng.uniform(xmin, xmax, samples), rng.uniform(ymin, ymax, samples)])
    owners = _owner(vor.points, vor.weights, q)
    slack = 1e-9 * max(xmax - xmin, ymax - ymin)
    for p, i in zip(q, owners):
        assert _in_ring(vor.cell(i), p, slack), (p, i)


# ------------------------------------------------------------------ subdivision
def test_grid_subdivision_is_unit_squares():
    g = np.array([(x, y) for y in range(6) for x in range(5)], float)
    tri = _delaunay(g)
    assert not tri.is_unique()
    sub = _check_subdivision(tri)
    assert len(sub) == 4 * 5 and (sub.sizes == 4).all()
    for face in sub:
        assert _area(g[face]) == 1.0


def test_generic_points_subdivision_is_the_triangulation():
    P = np.random.default_rng(1).random((60, 2))
    tri = _delaunay(P)
    sub = _check_subdivision(tri)
    assert len(sub) == len(tri.triangles) and (sub.sizes == 3).all()
    assert sorted(map(tuple, sub.tolist())) == sorted(map(tuple, tri.triangles.tolist()))


def test_cocircular_polygon_is_one_face():
    octagon = np.array([[5, 0], [4, 3], [3, 4], [0, 5], [-3, 4], [-4, 3], [-5, 0], [-4, -3],
                        [-3, -4], [0, -5], [3, -4], [4, -3]], float)   # twelve points on one circle
    tri = _delaunay(octagon)
    sub = _check_subdivision(tri)
    assert len(sub) == 1 and sub.sizes.tolist() == [12]
    vor = tri.voronoi()
    assert vor.vertices.tolist() == [[0.0, 0.0]]
    assert vor.regions == [[0, -1]] * 12
    assert len(vor.ridge_points) == 12 and (vor.ridge_vertices[:, 1] == -1).all()
    with_centre = _delaunay(np.vstack([octagon, [[0, 0]]]))
    sub = _check_subdivision(with_centre)
    assert len(sub) == 12 and (sub.sizes == 3).all()


def test_weighted_subdivision_fuses_lifted_coplanar():
    g = np.array([(x, y) for y in range(4) for x in range(4)], float)
    w = np.full(len(g), 0.25)            # equal weights: the same ties as unweighted
    tri = _delaunay(g, w)
    sub = _check_subdivision(tri)
    assert len(sub) == 9 and (sub.sizes == 4).all()


# ------------------------------------------------------------------ the diagram
def test_matches_scipy_on_generic_points():
    from scipy.spatial import Voronoi as QhullVoronoi
    P = np.random.default_rng(7).random((300, 2))
    tri = _delaunay(P)
    vor = tri.voronoi()
    ref = QhullVoronoi(P)
    assert len(vor.vertices) == len(ref.vertices) == len(tri.triangles)
    # the same vertex positions (matched by sorting), the same cells and ridges
    mine = np.lexsort(vor.vertices.T[::-1])
    theirs = np.lexsort(ref.vertices.T[::-1])
    np.testing.assert_allclose(vor.vertices[mine], ref.vertices[theirs], rtol=0, atol=1e-9)
    to_ref = np.empty(len(mine), int)
    to_ref[mine] = theirs
    for i in range(len(P)):
        site = vor.point_region[i]
        region = vor.region(site)
        assert set(to_ref[region[region >= 0]].tolist()) == set(ref.regions[ref.point_region[i]]) - {-1}
        assert (region[-1] == -1) == (-1 in ref.regions[ref.point_region[i]])
    assert {frozenset(r) for r in vor.ridge_points.tolist()} == \
        {frozenset(r) for r in ref.ridge_points.tolist()}
    rv = vor.ridge_vertices
    finite = rv[:, 1] >= 0
    assert ({frozenset(r) for r in to_ref[rv[finite]].tolist()}
            == {frozenset(r) for r in ref.ridge_vertices if -1 not in r})


def test_regions_are_counter_clockwise_rings_around_their_site():
    P = np.random.default_rng(3).random((200, 2))
    vor = _delaunay(P).voronoi()
    for i in range(len(P)):
        r = vor.region(i)
        if vor.unbounded[i]:
            assert r[-1] == -1 and (r[:-1] >= 0).all()
            continue
        ring = vor.vertices[r]
        assert _area(ring) > 0
        assert _in_ring(ring, P[i], 0.0)


def test_rays_point_away_from_the_hull():
    P = np.random.default_rng(4).random((100, 2))
    vor = _delaunay(P).voronoi()
    rv, rp, d = vor.ridge_vertices, vor.ridge_points, vor.ridge_directions
    rays = rv[:, 1] < 0
    assert rays.sum() == vor.unbounded.sum()         # one ray per hull edge
    np.testing.assert_allclose(np.hypot(d[rays, 0], d[rays, 1]), 1.0)
    assert (d[~rays] == 0).all()
    centre = P.mean(axis=0)
    mid = P[rp[rays]].mean(axis=1)
    assert (np.einsum("ij,ij->i", mid - centre, d[rays]) > 0).all()
    edge = P[rp[rays, 1]] - P[rp[rays, 0]]
    np.testing.assert_allclose(np.einsum("ij,ij->i", edge, d[rays]), 0.0, atol=1e-12)


def test_grid_cells_are_unit_squares_and_one_vertex_per_square():
    g = np.array([(x, y) for y in range(5) for x in range(5)], float)
    vor = _delaunay(g).voronoi()
    assert len(vor.vertices) == 16
    assert sorted(map(tuple, vor.vertices.tolist())) == [(x + 0.5, y + 0.5) for x in range(4) for y in range(4)]
    interior = [i for i, (x, y) in enumerate(g) if 0 < x < 4 and 0 < y < 4]
    for i in interior:
        ring = vor.cell(i)
        assert len(ring) == 4 and _area(ring) == 1.0
    assert vor.unbounded.sum() == 16


@pytest.mark.parametrize("e", [-700, -300, 0, 300, 900])
def test_scales_exactly_by_powers_of_two(e):
    P = np.random.default_rng(5).random((150, 2))
    base = cdt_plugin.delaunay(P).voronoi(clip=(0.0, 0.0, 1.0, 1.0))
    s = 2.0 ** e
    vor = _delaunay(P * s).voronoi(clip=(0.0, 0.0, s, s))
    assert np.array_equal(vor.region_indices, base.region_indices)
    assert np.array_equal(vor.vertices, base.vertices * s)
    assert np.array_equal(vor.cell_xy, base.cell_xy * s)


def test_clipped_cells_tile_the_box_and_hold_their_nearest_points():
    rng = np.random.default_rng(11)
    P = rng.random((80, 2)) * [3.0, 2.0] + [10.0, -5.0]
    box = (9.5, -5.5, 13.5, -2.5)
    vor = _delaunay(P).voronoi(clip=box)
    _check_clipped(vor, box, rng)
    for i in range(len(P)):                         # each cell holds its site
        assert _in_ring(vor.cell(i), P[i], 1e-12)


@pytest.mark.parametrize("kind", ["uniform", "grid", "thin"])
def test_clipped_cells_share_their_corners_exactly(kind):
    """An exact coverage: every edge of a clipped cell that is not on the box is
    an edge of exactly one other cell, reversed, bit for bit; every corner
    inside the box is a Voronoi vertex."""
    rng = np.random.default_rng(21)
    if kind == "uniform":
        P = rng.random((400, 2)) * 100
    elif kind == "grid":
        P = np.array([(x, y) for y in range(12) for x in range(9)], float) * 0.1 + 1234.567
    else:                                            # a needle-like hull: sharp corners
        P = np.column_stack([rng.random(200) * 1000, rng.random(200) * 1e-3])
    vor = _delaunay(P).voronoi()
    box = vor.envelope() if kind != "grid" else (1234.6, 1234.6, 1235.3, 1235.5)
    vor = vor.clipped(box)
    xmin, ymin, xmax, ymax = box
    edges = {}
    corners = set(map(tuple, vor.vertices.tolist()))
    for i in range(len(vor.points)):
        ring = [tuple(p) for p in vor.cell(i).tolist()]
        for p in ring:
            on_box = p[0] in (xmin, xmax) or p[1] in (ymin, ymax)
            assert on_box or p in corners, (i, p)
            assert xmin <= p[0] <= xmax and ymin <= p[1] <= ymax
        for p, q in zip(ring, ring[1:] + ring[:1]):
            side = (p[0] == q[0] and p[0] in (xmin, xmax)) or (p[1] == q[1] and p[1] in (ymin, ymax))
            if not side:
                edges[(p, q)] = edges.get((p, q), 0) + 1
    assert all(n == 1 for n in edges.values())
    assert all((q, p) in edges for p, q in edges), [e for e in edges if (e[1], e[0]) not in edges][:3]
    _check_clipped(vor, box, rng, samples=50)


def test_nearly_collinear_points_give_strips_that_tile_the_box():
    """Points within 2**-50 of a line: the triangles are slivers whose centres lie
    1e13 away. The cells near the box are cut along the sites' bisectors (not
    between those far centres), and a straight hull vertex's two rays, a rounding
    error apart out there, do not wrap its cell round the far box (it did)."""
    P = np.array([[0.38567592, 0.19283796], [0.91194573, 0.45597287], [0.11364483, 0.05682241],
                  [0.55442807, 0.27721403], [0.96852372, 0.48426186], [0.22510724, 0.11255362],
                  [0.59370661, 0.29685331], [0.27738827, 0.13869413], [0.60230064, 0.30115032],
                  [0.1462093, 0.07310465]])
    P[:, 1] = P[:, 0] / 2 + np.array([0, 1, -1, 0, 2, 0, -2, 1, 0, 0]) * 2.0 ** -50
    tri = _delaunay(P)
    assert np.abs(tri.voronoi().vertices).max() > 1e10
    box = (0.19, -0.03, 0.89, 0.57)
    vor = tri.voronoi(clip=box)
    _check_clipped(vor, box, np.random.default_rng(5), samples=400)
    order = np.argsort(P[:, 0])
    inside = [i for i in order if box[0] <= P[i, 0] <= box[2]]
    for i in inside:
        assert _in_ring(vor.cell(i), P[i], 1e-12)


def _nearly_collinear(rng, m, flatness):
    """``m`` sites about 100 apart, the ones after the first two off the line
    of those two by ``flatness`` of their distance (either side)."""
    a, b = rng.random(2) * 100, rng.random(2) * 100
    t = rng.uniform(-1, 2, m - 2)[:, None]
    side = rng.choice([-1.0, 1.0], (m - 2, 1)) * flatness * np.array([a[1] - b[1], b[0] - a[0]])
    return np.vstack([a, b, a + t * (b - a) + side])


def _check_strips(vor, k=0):
    """The cells of a box-clipped diagram of a few sites, times ``2**-k``: each
    non-empty and holding its site, their areas summing to the box's, and no
    sample point strictly inside two cells (up to rounding)."""
    box = np.ldexp(np.array(vor.clip), -k)
    sites = np.ldexp(vor.points, -k)
    cells = [np.ldexp(vor.cell(i), -k) for i in range(len(sites))]
    size = max(box[2] - box[0], box[3] - box[1])
    for i, cell in enumerate(cells):
        assert len(cell) >= 3 and _area(cell) > 0, (sites.tolist(), i)
        assert _in_ring(cell, sites[i], 1e-12 * size), (sites.tolist(), i)
    whole = (box[2] - box[0]) * (box[3] - box[1])
    # corners rounded to the doubles: each moves a side by at most a spacing of the coordinates
    perimeter = sum(np.hypot(*(np.roll(c, -1, axis=0) - c).T).sum() for c in cells)
    rounding = 1e-12 * whole + perimeter * np.spacing(np.abs(box).max())
    assert abs(sum(map(_area, cells)) - whole) <= rounding, sites.tolist()
    rng = np.random.default_rng(1)
    for p in np.column_stack([rng.uniform(box[0], box[2], 50), rng.uniform(box[1], box[3], 50)]):
        assert sum(_in_ring(cell, p, -1e-9 * size) for cell in cells) <= 1, (sites.tolist(), p)


@pytest.mark.parametrize("sites", [
    [[59.83762816921075, 27.922305206246634], [82.69416289627772, 7.431842880298822],
     [100.12028001171034, -8.190350094495427]],
    [[66.44037016958879, 69.98885907650752], [91.9051526126196, 4.163148061906419],
     [88.53451814017532, 12.876138687895144]],
    [[45.890455542169484, 26.089789419545863], [13.040035049854948, 71.7734071191463],
     [-17.484806455945737, 114.22294562712791]]])
def test_a_middle_cell_between_ridges_that_meet_1e17_away_is_a_strip(sites):
    """Three sites within about 1e-16 relative of a line: the ridges of the
    middle one meet about 1e17 away, where the far ends of its rays round by
    more than its cell is wide; it came out empty. The cell is the box cut by
    the half-planes of its ridges, which the sites give exactly."""
    tri = _delaunay(sites)
    assert len(tri.triangles) == 1 and np.abs(tri.voronoi().vertices).max() > 1e15
    vor = tri.voronoi()
    _check_strips(vor.clipped(vor.envelope()))


@pytest.mark.parametrize("m", [3, 4])
@pytest.mark.parametrize("flatness", [1e-12, 1e-15, 1e-16, 1e-17, 1e-18])
@pytest.mark.parametrize("k, offset", [(0, 0.0), (-1000, 0.0), (1000, 0.0), (0, 1e9), (0, 1e15)])
def test_nearly_collinear_sites_tile_the_box_at_every_magnitude(m, flatness, k, offset):
    """Random nearly collinear triples and quadruples, scaled by ``2**k`` or
    moved by ``offset``: every cell non-empty and holding its site, the cells
    tiling the box; scaled, the cells are the unit-scale ones times ``2**k``
    exactly."""
    rng = np.random.default_rng(int(-np.log10(flatness)) + 7 * m)
    for _ in range(40):
        P = _nearly_collinear(rng, m, flatness) + offset
        if len(cdt_plugin.delaunay(P).triangles) == 0:      # (rounded onto one line by the offset)
            continue
        vor = _delaunay(np.ldexp(P, k)).voronoi()
        vor = vor.clipped(vor.envelope())
        _check_strips(vor, k)
        if k:
            unit = cdt_plugin.delaunay(P).voronoi()
            assert np.array_equal(vor.cell_xy, np.ldexp(unit.clipped(unit.envelope()).cell_xy, k))


def test_clip_smaller_than_the_points_leaves_empty_cells():
    g = np.array([(x, y) for y in range(5) for x in range(5)], float)
    box = (1.2, 1.2, 2.6, 2.4)
    vor = _delaunay(g).voronoi(clip=box)
    sizes = np.diff(vor.cell_offsets)
    assert (sizes == 0).sum() > 0
    _check_clipped(vor, box, np.random.default_rng(2))
    cell = vor.cell(12)                               # site (2, 2): [1.5, 2.5] x [1.5, 2.4]
    assert sorted(map(tuple, cell.tolist())) == [(1.5, 1.5), (1.5, 2.4), (2.5, 1.5), (2.5, 2.4)]
    assert _area(cell) > 0


def test_power_diagram_sample_points_lie_in_least_power_cells():
    rng = np.random.default_rng(12)
    P = rng.random((60, 2))
    w = rng.random(60) * 0.02
    tri = _delaunay(P, w)
    vor = tri.voronoi(clip=(0.0, 0.0, 1.0, 1.0))
    assert vor.weights is not None
    _check_clipped(vor, (0.0, 0.0, 1.0, 1.0), rng, samples=300)


def test_submerged_points_have_empty_cells_and_duplicates_share_one():
    P = np.array([[0, 0], [4, 0], [0, 4], [4, 4], [2, 2], [1, 1], [4, 0]], float)
    w = np.array([0, 0, 0, 0, 0, -5.0, 0])           # point 5 lies far above the lifted surface
    tri = _delaunay(P, w)
    vor = tri.voronoi()
    assert vor.point_region[5] == -1
    assert vor.point_region[6] == vor.point_region[1]
    assert len(vor.points) == 5


def test_power_centres_are_equal_power_points():
    rng = np.random.default_rng(13)
    P = rng.random((40, 2))
    w = rng.random(40) * 0.01
    tri = _delaunay(P, w)
    vor = tri.voronoi()
    face = vor.subdivision.face_of_triangle
    for t, (a, b, c) in enumerate(tri.triangles):
        x = vor.vertices[face[t]]
        pw = [np.sum((x - tri.vertices[v]) ** 2) - tri.weights[v] for v in (a, b, c)]
        np.testing.assert_allclose(pw, pw[0], rtol=0, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(st.integers(3, 40), st.integers(0, 2**31 - 1), st.sampled_from(["uniform", "grid", "circle"]))
def test_property_subdivision_and_clipped_diagram(n, seed, kind):
    rng = np.random.default_rng(seed)
    if kind == "uniform":
        P = rng.random((n, 2))
    elif kind == "grid":
        P = rng.integers(0, 4, (n, 2)).astype(float)
    else:                                            # Pythagorean points of the circle of radius 5
        ring = np.array([[5, 0], [4, 3], [3, 4], [0, 5], [-3, 4], [-4, 3], [-5, 0], [-4, -3],
                         [-3, -4], [0, -5], [3, -4], [4, -3], [0, 0]], float)
        P = ring[rng.choice(len(ring), size=min(n, len(ring)), replace=False)]
    distinct = np.unique(P, axis=0)
    if len(distinct) < 3 or all(orient2d_exact(distinct[0], distinct[1], p) == 0 for p in distinct[2:]):
        with pytest.raises(CollinearPointsError):
            cdt_plugin.delaunay(P).voronoi()
        return
    tri = _delaunay(P)
    sub = _check_subdivision(tri)
    lo, hi = P.min(axis=0) - 1, P.max(axis=0) + 1
    box = (lo[0], lo[1], hi[0], hi[1])
    vor = tri.voronoi(clip=box)
    assert len(vor.vertices) == len(sub)
    _check_clipped(vor, box, rng, samples=40)


# ------------------------------------------------------------------ bad input
def test_collinear_and_too_few_points_raise():
    with pytest.raises(CollinearPointsError, match="one line"):
        cdt_plugin.delaunay([[0, 0], [1, 1], [2, 2]]).voronoi()
    with pytest.raises(CollinearPointsError):
        cdt_plugin.delaunay([[0, 0], [1, 1]]).delaunay_subdivision()
    with pytest.raises(TooFewPointsError):
        cdt_plugin.delaunay(np.empty((0, 2))).voronoi()


def test_constrained_triangulation_raises():
    tri = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    with pytest.raises(NotDelaunayError, match="segments"):
        tri.voronoi()
    with pytest.raises(NotDelaunayError):
        tri.delaunay_subdivision()


def test_not_delaunay_and_not_convex_raise():
    V = np.array([[0, 0], [1, 0], [1, 1], [0, 0.9]], float)
    # the diagonal 0-2 where 1-3 is Delaunay
    T = np.array([[0, 1, 2], [0, 2, 3]])
    N = np.array([[-1, 1, -1], [-1, -1, 0]])
    bad = Triangulation(V, T, N, np.arange(4), {})
    with pytest.raises(NotDelaunayError, match="not locally Delaunay"):
        bad.voronoi()
    V = np.array([[0, 0], [2, 1], [4, 0], [2, 3]], float)   # a chevron: reflex at vertex 1
    T = np.array([[0, 1, 3], [1, 2, 3]])
    N = np.array([[1, -1, -1], [-1, 0, -1]])
    dart = Triangulation(V, T, N, np.arange(4), {})
    assert dart.is_delaunay()
    with pytest.raises(NotDelaunayError, match="turns inwards at vertex 1"):
        dart.voronoi()
    V = np.array([[0, 0], [1, 0], [0.5, 0.5], [1, 1], [0, 1]], float)   # a bowtie: pinched at 2
    bowtie = Triangulation(V, np.array([[0, 1, 2], [2, 3, 4]]), np.full((2, 3), -1), np.arange(5), {})
    with pytest.raises(NotDelaunayError, match="turns inwards at vertex 2"):
        bowtie.voronoi()


@pytest.mark.parametrize("clip", [(0, 0, 1), (0, 0, np.nan, 1), (1, 0, 0, 1), (0, 1, 1, 1), "box"])
def test_bad_clip_boxes_raise_before_any_work(clip):
    tri = cdt_plugin.delaunay(np.random.default_rng(0).random((10, 2)))
    with pytest.raises(ClipRegionError):
        tri.voronoi(clip=clip)


def test_clip_missing_every_point_raises():
    tri = cdt_plugin.delaunay(np.random.default_rng(0).random((10, 2)))
    with pytest.raises(ClipRegionError, match="none of the 10 points"):
        tri.voronoi(clip=(2, 2, 3, 3))
    with pytest.raises(ClipRegionError, match="unbounded"):
        tri.voronoi().cell(int(np.flatnonzero(tri.voronoi().unbounded)[0]))


@pytest.mark.parametrize("kind", ["uniform", "grid", "weighted"])
def test_threads_give_the_arrays_of_one(kind, monkeypatch):
    """workers=2 splits every kernel's range in two (forced here on small inputs):
    the same subdivision, vertices, cells, ridges and clipped cells as one thread."""
    import cdt_plugin.voronoi as voronoi_module
    rng = np.random.default_rng(31)
    w = None
    if kind == "uniform":
        P = rng.random((3000, 2))
    elif kind == "grid":
        P = np.array([(x, y) for y in range(40) for x in range(50)], float)
    else:
        P, w = rng.random((3000, 2)), rng.random(3000) * 1e-4
    tri = _delaunay(P, w)
    box = (0.1, 0.1, 0.9 * P[:, 0].max(), 0.9 * P[:, 1].max() + 0.5)
    one = tri.voronoi(clip=box, workers=1)
    monkeypatch.setattr(voronoi_module, "PARALLEL_TRIANGLES", 10)
    two = tri.voronoi(clip=box, workers=2)
    for name in ("vertices", "region_offsets", "region_indices", "unbounded", "cell_offsets", "cell_xy",
                 "ridge_points", "ridge_vertices", "ridge_directions"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name
    assert np.array_equal(one.subdivision.indices, two.subdivision.indices)


@pytest.mark.parametrize("kind", ["uniform", "weighted", "submerged", "duplicates", "huge", "few", "moved"])
def test_store_route_equals_the_general_route(kind):
    """A Delaunay result's dual is read straight off its half-edge store
    (centres, the exact ties test, each vertex's ring); the general route
    walks the triangles and their neighbours. Both give the same arrays, bit
    for bit, on generic points (no ties: nothing fused), with weights (heavy
    ones submerge points: the store keeps dead triangles), duplicates, scaled
    far from unit scale, on a few points (every vertex on the hull) and after
    ``move_vertices`` (the store flipped again)."""
    rng = np.random.default_rng(5)
    w = None
    if kind in ("uniform", "moved"):
        P = rng.random((2000, 2))
    elif kind == "weighted":
        P, w = rng.random((2000, 2)), rng.random(2000) * 1e-3
    elif kind == "submerged":
        P, w = rng.random((2000, 2)), rng.random(2000) * 0.05
    elif kind == "duplicates":
        P = np.repeat(rng.random((500, 2)), 2, axis=0)
    elif kind == "huge":
        P = rng.random((500, 2)) * 2.0 ** 900
    else:
        P = np.array([[0, 0], [3, 0.2], [1.4, 2.9], [-0.5, 1.3]])
    tri = _delaunay(P, w)
    if kind == "submerged":
        assert (tri._mesh[0][::3] == -2).any() and (tri.vertex_map < 0).any()
    if kind == "moved":
        P = P + rng.normal(0, 0.01, P.shape)
        tri.move_vertices(P)
        verify(P, tri)
    assert tri._mesh is not None
    plain = Triangulation(tri.vertices, tri.triangles, tri.neighbors, tri.vertex_map, {}, tri.weights)
    lo, hi = P.min(axis=0), P.max(axis=0)
    box = tuple(np.r_[lo + 0.1 * (hi - lo), hi - 0.2 * (hi - lo)] if kind != "few" else np.r_[lo - 1, hi + 1])
    ours, general = tri.voronoi(clip=box), plain.voronoi(clip=box)
    assert len(tri.delaunay_subdivision()) == len(tri.triangles)      # nothing fused
    for name in ("vertices", "region_offsets", "region_indices", "unbounded", "cell_offsets", "cell_xy",
                 "ridge_points", "ridge_vertices", "ridge_directions"):
        assert np.array_equal(getattr(ours, name), getattr(general, name)), name
    for name in ("offsets", "indices", "face_of_triangle"):
        assert np.array_equal(getattr(ours.subdivision, name), getattr(general.subdivision, name)), name
    on_hull = np.zeros(len(tri.vertices), bool)
    t, j = np.nonzero(tri.neighbors < 0)
    on_hull[tri.triangles[t, (j + 1) % 3]] = True
    assert np.array_equal(ours.unbounded, on_hull)


def test_store_route_refuses_what_is_not_delaunay():
    """The store route checks what the general route checks: each interior
    edge locally Delaunay (exact), the boundary convex. A result whose
    vertices were moved after it was made fails both ways, with the same
    named errors."""
    import copy
    tri = _delaunay(np.array([[0, 0], [1, 0], [1, 1], [0, 0.9]]))      # diagonal 1-3
    moved = copy.copy(tri)
    moved.vertices = np.array([[0, 0], [1, 0], [1, 1], [0, 1.1]])    # now 0-2 is Delaunay
    assert moved._mesh is not None
    with pytest.raises(NotDelaunayError, match=r"edge \[\d, \d\] of triangle \d is not locally Delaunay"):
        moved.voronoi()
    tri = _delaunay(np.array([[0, 0], [2, -1], [4, 0], [2, 3]]))     # a kite: diagonal 1-3
    assert sorted(map(sorted, tri.triangles.tolist())) == [[0, 1, 3], [1, 2, 3]]
    dart = copy.copy(tri)
    dart.vertices = np.array([[0, 0], [2, 1], [4, 0], [2, 3]])      # vertex 1 pushed in: reflex
    with pytest.raises(NotDelaunayError, match="turns inwards at vertex 1"):
        dart.voronoi()


def test_unfused_faces_equal_the_general_walk():
    """Where no triangles are fused, each face is its triangle, written in
    ranges (on threads for large inputs); that is what the general face walk
    gives when no edge is fused."""
    from cdt_plugin._core.dual import subdivision_faces
    tri = _delaunay(np.random.default_rng(9).random((3000, 2)))
    sub = tri.delaunay_subdivision()
    T = tri.triangles
    face_of, offsets, ring = subdivision_faces(T, tri.neighbors, np.zeros(T.shape, bool))
    assert len(sub) == len(T)
    assert np.array_equal(sub.face_of_triangle, face_of) and np.array_equal(sub.offsets, offsets)
    assert np.array_equal(sub.indices, ring)
    assert (ring.reshape(-1, 3)[:, 0] == T.min(axis=1)).all()
