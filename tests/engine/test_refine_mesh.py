"""Refining an existing mesh (Triangle's ``-r``): ``Triangulation.refine`` and
``Triangulation.from_triangles(..., segments=)``, with Triangle's own meshes as
input and the ``triangle`` package's ``ra`` as the reference; ``split_segments``
(Triangle's ``-YY``). Every result is checked by the exact checker, its segments
against the mesh it came from, and its bounds."""
from __future__ import annotations

import numpy as np
import pytest
import shapely
import triangle

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError, InvalidMeshError, InvertedTriangleError, RefinementLimitError
from checker import check_steiner_segments, check_triangulation, orient2d_exact
from corpus import corpus_dir

TRIANGLE_DIR = corpus_dir() / "triangle"


def areas(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2


def min_angles(V, T):
    P = V[T]
    out = []
    for j in range(3):
        u = P[:, (j + 1) % 3] - P[:, j]
        w = P[:, (j + 2) % 3] - P[:, j]
        cross = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        out.append(np.degrees(np.arctan2(cross, (u * w).sum(axis=1))))
    return np.min(out, axis=0)


def verify(base, out, *, bounds=None, min_angle=None):
    """``out`` refines ``base``: a valid mesh of the same domain (the exact
    checker: constrained Delaunay), every vertex
    of ``base`` first and unmoved, every segment of ``base`` the chain of its
    pieces, the bounds met."""
    V, T = out.vertices, out.triangles
    n = len(base.vertices)
    assert np.array_equal(V[:n], base.vertices)
    assert set(np.unique(T).tolist()) >= set(np.unique(base.triangles).tolist())
    assert np.array_equal(out.steiner[-(len(V) - n):] if len(V) > n else out.steiner[:0],
                          np.arange(n, len(V)))
    flagged = {frozenset((int(t[(j + 1) % 3]), int(t[(j + 2) % 3])))
               for t, c in zip(T.tolist(), out.constrained.tolist()) for j in range(3) if c[j]}
    assert {frozenset(p) for p in out.segments.tolist()} == flagged
    # the domain: the same area, bounded by segment pieces
    assert areas(V, T).sum() == pytest.approx(areas(base.vertices, base.triangles).sum(), rel=1e-12)
    rep = check_triangulation(V, T, segments=out.segments, domain="segments",
                              require_all_vertices=False)
    assert rep.ok, str(rep)
    # every segment of base is the chain of the pieces that name it (where base has one
    # piece per segment; the callers check the others against triangulate's input)
    kept = base.segment_ids >= 0
    ids = np.unique(base.segment_ids[kept])
    if kept.any() and len(ids) == kept.sum():
        ends = np.zeros((ids.max() + 1, 2), np.int64)
        ends[base.segment_ids[kept]] = base.segments[kept]
        mine = np.isin(out.segment_ids, ids)
        rep = check_steiner_segments(base.vertices, ends, V, np.arange(n), out.segments[mine],
                                     out.segment_ids[mine])
        assert rep.ok, str(rep)
    assert out.stats["refinement_complete"]
    assert out.stats["steiner"] == len(out.steiner) and out.stats["triangles"] == len(T)
    if min_angle:
        below = np.flatnonzero(min_angles(V, T) < min_angle * (1 - 1e-9))
        assert set(below.tolist()) <= set(out.below_min_angle.tolist())
    if bounds is not None:
        assert_bounds_met(base, out, bounds)
    return out


def centroids(V, T):
    """Each triangle's centroid as refinement computes it: each coordinate of
    the corners summed smallest first, then divided by 3 (the same for any
    order of the corners)."""
    P = np.sort(V[T], axis=1)
    return ((P[:, 0] + P[:, 1]) + P[:, 2]) / 3


def orient_signs(A, B, C):
    """Exact signs of orient2d for rows of points: the floating-point value
    where Shewchuk's bound makes its sign certain, fractions elsewhere."""
    left = (A[:, 0] - C[:, 0]) * (B[:, 1] - C[:, 1])
    right = (A[:, 1] - C[:, 1]) * (B[:, 0] - C[:, 0])
    det = left - right
    eps = np.finfo(float).eps / 2
    sure = np.abs(det) > (3.0 + 16.0 * eps) * eps * (np.abs(left) + np.abs(right))
    signs = np.sign(det).astype(np.int64)
    for i in np.flatnonzero(~sure):
        signs[i] = orient2d_exact(A[i], B[i], C[i])
    return signs


def assert_bounds_met(base, out, bounds):
    """Every triangle of ``out`` is no larger than the bound of a triangle of
    ``base`` that holds its centroid (:func:`centroids`), edges included: the
    rule of per-triangle bounds (exact: each holder found by exact
    orientations among the triangles whose box has the point)."""
    bounds = np.broadcast_to(np.asarray(bounds, float), (len(base.triangles),))
    bounds = np.where(np.isfinite(bounds) & (bounds > 0), bounds, np.inf)
    c = centroids(out.vertices, out.triangles)
    tree = shapely.STRtree(shapely.polygons(base.vertices[base.triangles]))
    i_new, i_old = tree.query(shapely.points(c))        # boxes that hold the point
    P, T = base.vertices, base.triangles[i_old]
    q = c[i_new]
    held = np.ones(len(i_new), bool)
    for j in range(3):
        held &= orient_signs(P[T[:, (j + 1) % 3]], P[T[:, (j + 2) % 3]], q) >= 0
    i_new, i_old = i_new[held], i_old[held]
    assert len(np.unique(i_new)) == len(c)           # each centroid lies in the mesh
    best = np.zeros(len(c))
    np.maximum.at(best, i_new, bounds[i_old])         # the loosest holder's bound
    a = areas(out.vertices, out.triangles)
    assert (a <= best).all()


def triangle_mesh(name, switches="pq"):
    """A mesh made by Triangle from one of its sample files."""
    data = triangle.load(str(TRIANGLE_DIR), name)
    return triangle.triangulate(data, switches)


# ---------------------------------------------------------------- Triangle's meshes
@pytest.mark.parametrize("name", ["A", "face", "la", "ell"])
def test_per_triangle_areas_against_triangle_ra(name):
    mesh = triangle_mesh(name, "pq" if name != "ell" else "q")
    V, T = mesh["vertices"], mesh["triangles"]
    segs = mesh.get("segments")
    base = cdt_plugin.Triangulation.from_triangles(V, T, segments=segs)
    rng = np.random.default_rng(7)
    a = areas(base.vertices, base.triangles)
    bounds = np.where(rng.random(len(a)) < 0.5, a * rng.uniform(0.05, 0.5, len(a)), -1.0)
    out = verify(base, base.refine(max_area=bounds), bounds=bounds)
    assert len(out.steiner) > 0
    # Triangle's -r with the same .area values: the same vertices kept, its bounds met
    # (averaged across flips), meshes of a like size
    # (no segments for Triangle: with -r but not -p it segfaults on some; its -r keeps the
    # boundary, and these meshes' segments are on it)
    ref = triangle.triangulate({"vertices": V, "triangles": T, "triangle_max_area": bounds[:, None]},
                               "ra")
    assert np.array_equal(ref["vertices"][:len(V)], V)
    assert 0.33 < len(out.triangles) / len(ref["triangles"]) < 3


@pytest.mark.parametrize("name", ["A", "la"])
def test_quality_and_area_against_triangle_rqa(name):
    mesh = triangle_mesh(name)
    base = cdt_plugin.Triangulation.from_triangles(mesh["vertices"], mesh["triangles"],
                                                   segments=mesh["segments"])
    bound = areas(base.vertices, base.triangles).sum() / 500
    out = verify(base, base.refine(min_angle=30, max_area=bound), bounds=bound, min_angle=30)
    assert out.is_delaunay()
    ref = triangle.triangulate({"vertices": mesh["vertices"], "triangles": mesh["triangles"]},
                               f"rq30a{bound:.12f}")
    assert 0.5 < len(out.triangles) / len(ref["triangles"]) < 2


# ---------------------------------------------------------------- our own meshes
SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
HOLE = [[1, 1], [3, 1.5], [3, 3], [1, 3]]


def ring(n, start=0):
    return [[start + i, start + (i + 1) % n] for i in range(n)]


def test_refine_a_triangulate_result_keeps_its_segments_and_regions():
    v = SQUARE + HOLE + [[0, 0.5], [4, 0.6]]      # a segment across the square: two regions
    s = ring(4) + ring(4, 4) + [[8, 9]]
    tri = cdt_plugin.triangulate(v, s, holes=[[2, 2]], regions=[[0.5, 0.3, 7.0, 0], [2, 3.5, 9.0, 0]])
    out = verify(tri, tri.refine(min_angle=28, max_area=0.05), bounds=0.05, min_angle=28)
    # segment ids name the input segments of triangulate; the regions follow
    assert set(out.segment_ids.tolist()) == set(tri.segment_ids.tolist())
    rep = check_steiner_segments(v, s, out.vertices, out.vertex_map, out.segments, out.segment_ids)
    assert rep.ok, str(rep)
    centroids = out.vertices[out.triangles].mean(axis=1)
    below = centroids[:, 1] < 0.5 + 0.1 * centroids[:, 0] / 4
    assert np.array_equal(out.regions, np.where(below, 0, 1))
    assert np.array_equal(out.region_attributes, np.where(below, 7.0, 9.0))


def test_refine_of_a_refined_mesh_goes_on_from_it():
    tri = cdt_plugin.triangulate(SQUARE + HOLE, ring(4) + ring(4, 4))
    first = verify(tri, tri.refine(max_area=0.2), bounds=0.2)
    a = areas(first.vertices, first.triangles)
    bounds = np.where(first.vertices[first.triangles][:, :, 0].mean(axis=1) < 2, a / 4, np.nan)
    second = verify(first, first.refine(max_area=bounds, min_angle=25), bounds=bounds, min_angle=25)
    assert second.stats["input_triangles"] == len(first.triangles)
    # refining the first result again gives the same mesh: its store was not changed
    again = first.refine(max_area=bounds, min_angle=25)
    assert np.array_equal(again.triangles, second.triangles)
    assert np.array_equal(again.vertices, second.vertices)
    # a mesh that meets the bounds already gets no new point, and comes back as it is
    third = second.refine(max_area=0.2)
    assert third.stats["refinement_steiner"] == 0 and len(third.vertices) == len(second.vertices)
    assert np.array_equal(third.triangles, second.triangles)
    assert third.refine(max_area=0.1).stats["refinement_steiner"] > 0      # and goes on from there
    # and the segment ids still name triangulate's segments
    rep = check_steiner_segments(SQUARE + HOLE, ring(4) + ring(4, 4), second.vertices, second.vertex_map,
                                 second.segments, second.segment_ids)
    assert rep.ok, str(rep)


def test_from_triangles_segments_stay_edges():
    # a square in four triangles around its centre, the diagonal 0-4-2 kept as a segment
    V = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]]
    T = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    base = cdt_plugin.Triangulation.from_triangles(V, T, segments=[[0, 4], [4, 2], [4, 0]])
    assert base.segments.tolist() == [[0, 4], [4, 2]] and base.segment_ids.tolist() == [0, 1]
    assert base.constrained.sum() == 4
    out = verify(base, base.refine(min_angle=30, max_area=0.01), bounds=0.01, min_angle=30)
    diag = out.segments[out.segment_ids >= 0]
    assert (np.abs(np.diff(out.vertices[diag], axis=1)[:, 0, 0] - np.diff(out.vertices[diag], axis=1)[:, 0, 1]) < 1e-12).all()
    # no refinement asked for: the same mesh
    same = base.refine()
    assert sorted(map(tuple, same.triangles.tolist())) == sorted(map(tuple, base.triangles.tolist()))
    assert same.stats["refinement_steiner"] == 0


def test_split_segments_false_puts_no_point_on_any_segment():
    v = SQUARE + [[0.5, 2], [3.5, 2.1]]
    s = ring(4) + [[4, 5]]
    boundary_only = cdt_plugin.triangulate(v, s, max_area=0.05, split_boundary=False)
    assert (boundary_only.segment_ids == 4).sum() > 1          # -Y: the inner segment is split
    tri = cdt_plugin.triangulate(v, s, max_area=0.05, split_segments=False)
    assert sorted(tri.segment_ids.tolist()) == [0, 1, 2, 3, 4]   # -YY: none is
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    assert rep.ok, str(rep)
    assert len(tri.steiner) > 0
    # refine alike
    base = cdt_plugin.triangulate(v, s)
    out = verify(base, base.refine(max_area=0.05, split_segments=False))
    assert len(out.segments) == 5
    with pytest.raises(CDTError, match="min_angle"):
        base.refine(min_angle=61, split_segments=False)


def test_refinement_limit_carries_the_partial_mesh():
    base = cdt_plugin.Triangulation.from_triangles(SQUARE, [[0, 1, 2], [0, 2, 3]])
    with pytest.raises(RefinementLimitError) as info:
        base.refine(max_area=1e-4, max_steiner=50)
    partial = info.value.triangulation
    assert len(partial.steiner) == 50 and not partial.stats["refinement_complete"]
    rep = check_triangulation(partial.vertices, partial.triangles, segments=partial.segments, domain="segments")
    assert rep.ok, str(rep)


# ---------------------------------------------------------------- bad input
def test_bad_meshes_are_named():
    V = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]]
    with pytest.raises(InputShapeError, match="triangle 1"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, 2, 5]])
    with pytest.raises(InputShapeError, match="triangle 1"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, -1, 2]])
    with pytest.raises(InvertedTriangleError, match="triangle 1"):
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, 4, 2]])
    with pytest.raises(InvalidMeshError, match="segment 1 \\[1, 3\\] is not an edge") as info:
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, 2, 3]], segments=[[0, 2], [1, 3]])
    assert info.value.segments == (1,)
    # two triangles on the same side of one edge
    with pytest.raises(InvalidMeshError, match="triangles 0 .* and 1 .* overlap") as info:
        cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, 1, 4]])
    assert info.value.triangles == (0, 1)
    # crossing edges: found by refine, which names both triangles
    star = [[0, 0], [2, 0], [1, 2], [0, 1.5], [2, 1.5], [1, -1]]      # two crossing triangles
    crossing = cdt_plugin.Triangulation.from_triangles(star, [[0, 1, 2], [3, 5, 4]])
    with pytest.raises(InvalidMeshError, match="overlap: their edges") as info:
        crossing.refine(max_area=0.1)
    assert len(info.value.triangles) == 2
    # a vertex inside a triangle it is not a corner of
    inner = cdt_plugin.Triangulation.from_triangles(V, [[0, 1, 2], [0, 2, 3], [0, 1, 4]][:2])
    with pytest.raises(InvalidMeshError, match="triangle 0 .* vertex 4 lies inside it") as info:
        inner.refine(max_area=0.1)
    assert info.value.triangles == (0,)


def test_bad_options_before_any_work():
    base = cdt_plugin.Triangulation.from_triangles(SQUARE, [[0, 1, 2], [0, 2, 3]])
    with pytest.raises(InputShapeError, match="one value per triangle, shape \\(2,\\)"):
        base.refine(max_area=[0.1, 0.2, 0.3])
    with pytest.raises(CDTError, match="max_area must be a positive number"):
        base.refine(max_area=-1.0)
    with pytest.raises(InputShapeError, match="max_area"):
        base.refine(max_area=["a", "b"])
    with pytest.raises(CDTError, match="max_steiner"):
        base.refine(max_steiner=-2)
    # <= 0, NaN and inf in an array: no bound on that triangle (Triangle's -1)
    out = base.refine(max_area=[0.5, np.nan])
    assert_bounds_met(base, out, [0.5, np.nan])
    # Steiner points mostly in the bounded triangle (0, 1, 2) and on the diagonal (flips
    # across it let a few triangles of the unbounded one be split too)
    new = out.vertices[out.steiner]
    assert len(new) > 10 and (new[:, 0] - new[:, 1] >= 0).mean() > 0.5
    with pytest.raises(CDTError, match="no triangles"):
        cdt_plugin.delaunay([[0, 0], [1, 1], [2, 2]]).refine(max_area=1)


def test_adaptive_refinement_five_rounds():
    """The loop of adaptive finite elements (the guide's example): estimate an error per
    triangle, bound the marked ones at a quarter of their area, refine, five times; each
    round checked exactly, its bounds against every triangle of the round before."""
    def f(p):
        return np.tanh(40 * (np.hypot(p[..., 0] - 1, p[..., 1] - 1) - 0.6))

    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                                 min_angle=25, max_area=0.05)
    for _ in range(5):
        centroids = tri.vertices[tri.triangles].mean(axis=1)
        error = np.abs(f(centroids) - f(tri.vertices)[tri.triangles].mean(axis=1))
        a = areas(tri.vertices, tri.triangles)
        bounds = np.where(error > 0.05, a / 4, -1.0)
        new = verify(tri, tri.refine(max_area=bounds, min_angle=25), bounds=bounds, min_angle=25)
        rep = check_steiner_segments([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                                     new.vertices, new.vertex_map, new.segments, new.segment_ids)
        assert rep.ok, str(rep)
        assert len(new.triangles) > len(tri.triangles)
        tri = new
    # the error went down where it was large
    centroids = tri.vertices[tri.triangles].mean(axis=1)
    assert np.abs(f(centroids) - f(tri.vertices)[tri.triangles].mean(axis=1)).max() < 0.1


def test_refining_again_at_a_small_input_angle_adds_nothing():
    """Shewchuk's rule leaves the triangles at a small input angle alone; a refined
    result remembers which of its points lie on which segment, so refining it again
    with the same bound leaves them alone too (and adds no point)."""
    v = [[0, 0], [10, 0], [10, 1.2], [0, 3], [5, 0.6]]      # a 6.8 degree angle at vertex 0
    s = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 4]]
    tri = cdt_plugin.triangulate(v, s)
    once = verify(tri, tri.refine(min_angle=30), min_angle=30)
    assert len(once.below_min_angle) > 0
    twice = verify(once, once.refine(min_angle=30), min_angle=30)
    assert twice.stats["refinement_steiner"] == 0 and len(twice.triangles) == len(once.triangles)
    # refined elsewhere (the store runs again): still no point near the small angle
    far = once.vertices[once.triangles].mean(axis=1)[:, 0] > 8
    bounds = np.where(far, areas(once.vertices, once.triangles) / 4, np.nan)
    thrice = verify(once, once.refine(min_angle=30, max_area=bounds), min_angle=30, bounds=bounds)
    new = thrice.vertices[len(once.vertices):]
    assert len(new) > 0 and (np.hypot(new[:, 0], new[:, 1]) > 3).all()


def test_markers_and_attributes_are_carried():
    """Markers and attributes of the mesh refined, as Triangle's -r carries them: the
    segments' markers on their pieces and the points on them, attributes interpolated
    linearly (a linear field stays linear, up to rounding)."""
    V = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]], float)
    T = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    plane = (1 + 2 * V[:, 0] - 3 * V[:, 1])[:, None]
    base = cdt_plugin.Triangulation.from_triangles(V, T, segments=[[0, 4], [4, 2]],
                                                   segment_markers=[7, 7], vertex_markers=[0, 0, 0, 0, 5],
                                                   vertex_attributes=plane)
    out = verify(base, base.refine(max_area=0.02, min_angle=25), bounds=0.02, min_angle=25)
    assert np.allclose(out.vertex_attributes[:, 0], 1 + 2 * out.vertices[:, 0] - 3 * out.vertices[:, 1],
                       atol=1e-12)
    assert (out.segment_markers[out.segment_ids >= 0] == 7).all()
    on_diagonal = np.unique(out.segments[out.segment_ids >= 0])
    inner = on_diagonal[(on_diagonal != 0) & (on_diagonal != 2) & (on_diagonal != 4)]
    assert len(inner) > 0 and (out.vertex_markers[inner] == 7).all() and out.vertex_markers[4] == 5
    boundary = out.segment_ids < 0
    assert (out.segment_markers[boundary] == 1).all()
    again = out.refine(max_area=0.005)
    assert np.allclose(again.vertex_attributes[:, 0], 1 + 2 * again.vertices[:, 0] - 3 * again.vertices[:, 1],
                       atol=1e-12)


def test_home_of_finds_the_holder_in_a_domain_that_is_not_convex():
    """The walk that relocates a label (per-triangle bounds) meets the boundary of a U-shaped
    mesh; the triangles around the corners, then a scan, find the holder all the same."""
    from cdt_plugin._core.refine import home_of, in_fans

    V = np.array([[i, j] for j in range(3) for i in range(4)], float)
    squares = [(i, j) for j in range(2) for i in range(3) if (i, j) != (1, 1)]
    T = []
    for i, j in squares:
        a, b, c, d = i + 4 * j, i + 1 + 4 * j, i + 1 + 4 * (j + 1), i + 4 * (j + 1)
        T += [[a, b, c], [a, c, d]]
    base = cdt_plugin.Triangulation.from_triangles(V, T)
    home, nb = base.triangles.astype(np.int64), base.neighbors.astype(np.int64)
    x, y = base.vertices[:, 0].copy(), base.vertices[:, 1].copy()
    P = base.vertices
    for start in range(len(home)):
        for p in [(2.6, 1.5), (2.2, 1.8), (0.3, 1.6), (1.5, 0.9), (2.0, 1.0), (0.5, 0.5)]:
            got = int(home_of(x, y, home, nb, np.int64(start), *p))
            assert all(orient2d_exact(P[home[got, (j + 1) % 3]], P[home[got, (j + 2) % 3]], p) >= 0
                       for j in range(3)), (start, p, got)
    # around the corners: from a triangle of the upper left square at vertex (1, 1), a point
    # of the lower middle square, which shares that vertex
    h = next(t for t in range(len(home)) if 5 in home[t] and P[home[t]][:, 1].max() == 2)
    got = int(in_fans(x, y, home, nb, np.int64(h), 1.2, 0.8))
    assert got >= 0 and set(home[got].tolist()) <= {1, 2, 5, 6}
