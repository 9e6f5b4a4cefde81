"""Boundary markers and vertex attributes (``triangulate(..., vertex_markers=,
segment_markers=, vertex_attributes=)``), against the ``triangle`` package: per
vertex (matched by coordinates) without Steiner points, by Triangle's rules with
refinement; attributes exact for linear data. Every mesh passes the exact checker."""
from __future__ import annotations

import glob
import os

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin import io as tio
from cdt_plugin.errors import CDTError, InputShapeError, NonFiniteCoordinateError
from cdt_plugin.markers import carry_attributes
from checker import assert_valid, check_steiner_segments
import corpus
import fuzz

triangle = pytest.importorskip("triangle")

POLYS = sorted(glob.glob(str(corpus.corpus_dir() / "triangle" / "*.poly")))


def _check(tri, V, S, domain="segments"):
    """The exact checker on the mesh and its segments."""
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain=domain,
                 require_all_vertices=False)
    if len(S):
        rep = check_steiner_segments(V, S, tri.vertices, tri.vertex_map, tri.segments,
                                     tri.segment_ids, partial=True, snapped_inputs=True)
        assert rep.ok, rep


def _by_xy(vertices, values):
    """{(x, y): value} of each vertex."""
    return {tuple(p): int(v) for p, v in zip(np.asarray(vertices).tolist(), np.ravel(values))}


def _by_pair(vertices, pairs, values):
    """{frozenset of two (x, y): value} of each edge."""
    V = np.asarray(vertices).tolist()
    return {frozenset((tuple(V[a]), tuple(V[b]))): int(v) for (a, b), v in zip(pairs, np.ravel(values))}


def _used(triangles, n):
    used = np.zeros(n, bool)
    used[np.asarray(triangles).ravel()] = True
    return used


def _compare_without_steiner(d, ours, theirs):
    """Ours and Triangle's: the same triangles' vertices, and per vertex (by
    coordinates), per segment piece and per edge the same marker."""
    assert len(ours.steiner) == 0
    used = _used(theirs.get("triangles", np.empty((0, 3), int)), len(theirs["vertices"]))
    want = _by_xy(theirs["vertices"][used], theirs["vertex_markers"][used])
    got = _by_xy(ours.vertices, ours.vertex_markers)
    assert {p: got[p] for p in want} == want
    assert (_by_pair(ours.vertices, ours.segments, ours.segment_markers)
            == _by_pair(theirs["vertices"], theirs.get("segments", []), theirs.get("segment_markers", [])))
    _same_edge_markers(ours, theirs)


def _same_edge_markers(ours, theirs):
    """The same marker on every edge both meshes have (cocircular ties may give
    other diagonals), and the same edges marked."""
    a = _by_pair(ours.vertices, ours.edges, ours.edge_markers)
    b = _by_pair(theirs["vertices"], theirs.get("edges", []), theirs.get("edge_markers", []))
    common = a.keys() & b.keys()
    assert {k: a[k] for k in common} == {k: b[k] for k in common}
    assert {k for k in a if a[k]} == {k for k in b if b[k]}


def _poly(path, refine=False):
    pd = tio.read_poly(path)
    d = {"vertices": pd.vertices, "segments": pd.segments}
    if pd.markers is not None:
        d["vertex_markers"] = pd.markers
    if pd.segment_markers is not None:
        d["segment_markers"] = pd.segment_markers
    if len(pd.holes):
        d["holes"] = pd.holes
    if len(pd.regions):
        d["regions"] = pd.regions
        if not refine:               # (Triangle bounds the regions' areas with -a only)
            d["regions"] = np.where(np.arange(4) == 3, -1.0, pd.regions)
    return d


def _ours(d, **options):
    """Our triangulation of a ``triangle``-style dict (hole seeds always given:
    Triangle's notion of the domain)."""
    return cdt_plugin.triangulate(
        d["vertices"], d.get("segments"), holes=d.get("holes", np.empty((0, 2))),
        regions=d.get("regions"), vertex_markers=d.get("vertex_markers"),
        segment_markers=d.get("segment_markers"), vertex_attributes=d.get("vertex_attributes"),
        **options)


@pytest.mark.parametrize("path", POLYS, ids=os.path.basename)
def test_corpus_markers_equal_triangles_without_steiner_points(path):
    d = _poly(path)
    ours = _ours(d)
    _check(ours, d["vertices"], d["segments"])
    _compare_without_steiner(d, ours, triangle.triangulate(d, "pe"))


@pytest.mark.parametrize("path", POLYS, ids=os.path.basename)
def test_corpus_markers_without_input_markers(path):
    d = _poly(path)
    d.pop("vertex_markers", None)
    d.pop("segment_markers", None)
    ours = _ours(d)
    _compare_without_steiner(d, ours, triangle.triangulate(d, "pe"))


def _segment_of(V, S, p):
    """The input segments (indices) whose closed segment holds ``p`` up to rounding."""
    A, B = V[S[:, 0]], V[S[:, 1]]
    d = B - A
    t = ((p - A) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300)
    gap = np.hypot(*(A + np.clip(t, 0, 1)[:, None] * d - p).T)
    scale = np.abs(V).max()
    return np.flatnonzero(gap <= 1e-9 * scale)


def _arrays(tri):
    """A Triangulation's arrays as the ``triangle`` package's dict names them."""
    return {k: getattr(tri, k) for k in ("vertices", "triangles", "segments", "segment_markers",
                                         "vertex_markers", "steiner")}


def _markers_by_rule(V, S, smarks, mesh):
    """On ``mesh`` (a ``triangle``-style dict) of the input ``V``, ``S`` with
    segment markers ``smarks``: every Steiner point on a marked input segment has
    the marker of the first such segment; every segment piece on a marked segment
    has that segment's marker, on an unmarked one 1 on the boundary, else 0."""
    vertices, triangles, segments = mesh["vertices"], mesh["triangles"], mesh["segments"]
    steiner = mesh.get("steiner", np.arange(len(V), len(vertices)))     # (Triangle's: after the input)
    segment_markers, vertex_markers = np.ravel(mesh["segment_markers"]), np.ravel(mesh["vertex_markers"])
    for v in steiner:
        on = _segment_of(V, S, vertices[v])
        marked = [s for s in on if smarks[s] != 0]
        if marked:
            assert vertex_markers[v] == smarks[marked[0]], (v, on)
    nb = {}
    for t in triangles:
        for j in range(3):
            e = frozenset((int(t[(j + 1) % 3]), int(t[(j + 2) % 3])))
            nb[e] = nb.get(e, 0) + 1
    for (a, b), m in zip(segments, segment_markers):
        mid = (vertices[a] + vertices[b]) / 2
        on = [s for s in _segment_of(V, S, mid) if smarks[s] != 0]
        boundary = nb.get(frozenset((int(a), int(b))), 0) == 1
        assert m == (smarks[on[0]] if on else int(boundary)), (a, b, on)


@pytest.mark.parametrize("path", POLYS, ids=os.path.basename)
def test_corpus_markers_and_attributes_with_refinement(path):
    d = _poly(path, refine=True)
    V, S = d["vertices"], d["segments"]
    lo, hi = V.min(axis=0), V.max(axis=0)
    area = float(np.prod(hi - lo)) / (4 * len(V) + 100)
    plane = np.column_stack([1 + 2 * V[:, 0] - 3 * V[:, 1], 0.5 * V[:, 1] - V[:, 0]])
    d["vertex_attributes"] = plane
    ours = _ours(d, min_angle=30, max_area=area)
    theirs = triangle.triangulate(d, f"pq30a{area!r}e")
    if len(ours.triangles) == 0:         # (box.poly: one side a segment, all eaten by the hole)
        assert "triangles" not in theirs
        return
    _check(ours, V, S)
    smarks = d.get("segment_markers", np.zeros(len(S), np.int64))
    for mesh in (_arrays(ours), theirs):           # the same rules hold for both
        _markers_by_rule(V, S, smarks, mesh)
    W = ours.vertices
    want = np.column_stack([1 + 2 * W[:, 0] - 3 * W[:, 1], 0.5 * W[:, 1] - W[:, 0]])
    scale = np.abs(V).max() * 4 + 1
    assert len(ours.steiner)
    np.testing.assert_allclose(ours.vertex_attributes, want, rtol=0, atol=1e-12 * scale)
    # the input vertices keep their markers and attributes exactly
    vm = ours.vertex_map
    np.testing.assert_array_equal(ours.vertex_attributes[vm], plane)
    if "vertex_markers" in d:
        given = d["vertex_markers"] != 0
        np.testing.assert_array_equal(ours.vertex_markers[vm[given]], d["vertex_markers"][given])
    # edges: each boundary edge is a segment piece with its marker
    assert set(map(tuple, np.sort(ours.segments, axis=1).tolist())) >= {
        tuple(sorted(e)) for e, m in zip(ours.edges.tolist(), ours.edge_markers) if m != 0}


def _random_pslg(rng):
    """A star polygon with square holes (their seeds given) and free points,
    random markers on some vertices and segments."""
    V, S, _ = fuzz.polygon_with_holes(rng)
    ring_starts = [i for i in range(1, len(S)) if S[i, 0] != S[i - 1, 1]]
    holes = [V[S[r:r + 4, 0]].mean(axis=0) for r in ring_starts]   # the squares after the star
    vmarks = np.where(rng.random(len(V)) < 0.3, rng.integers(2, 9, len(V)), 0)
    smarks = np.where(rng.random(len(S)) < 0.5, rng.integers(2, 9, len(S)), 0)
    d = {"vertices": V, "segments": S, "vertex_markers": vmarks, "segment_markers": smarks}
    if holes:
        d["holes"] = np.array(holes)
    return d


@pytest.mark.parametrize("seed", range(12))
def test_random_pslgs_against_triangle(seed):
    rng = np.random.default_rng(seed)
    d = _random_pslg(rng)
    ours = _ours(d)
    _check(ours, d["vertices"], d["segments"])
    _compare_without_steiner(d, ours, triangle.triangulate(d, "pe"))
    # with refinement: the rules, and a linear attribute carried exactly
    V = d["vertices"]
    d["vertex_attributes"] = 3 * V[:, 0] - V[:, 1] + 2
    refined = _ours(d, min_angle=25, max_area=0.01)
    _check(refined, V, d["segments"])
    theirs = triangle.triangulate(d, "pq25a0.01")
    for mesh in (_arrays(refined), theirs):
        _markers_by_rule(V, d["segments"], d["segment_markers"], mesh)
    W = refined.vertices
    np.testing.assert_allclose(refined.vertex_attributes[:, 0], 3 * W[:, 0] - W[:, 1] + 2, atol=1e-12)
    # Triangle interpolates as linearly
    TW = theirs["vertices"]
    np.testing.assert_allclose(theirs["vertex_attributes"][:, 0], 3 * TW[:, 0] - TW[:, 1] + 2, atol=1e-12)


def test_keep_hull_marks_the_hull_as_triangle_c():
    V = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3], [2, 0], [2, 2]], float)
    S = np.array([[4, 5], [5, 6], [6, 7], [7, 4]])
    d = {"vertices": V, "segments": S, "segment_markers": np.array([0, 3, 0, 0])}
    ours = cdt_plugin.triangulate(V, S, keep_hull=True, segment_markers=d["segment_markers"])
    assert_valid(ours.vertices, ours.triangles, segments=S)
    theirs = triangle.triangulate(d, "pce")
    used = _used(theirs["triangles"], len(V))
    assert _by_xy(ours.vertices, ours.vertex_markers) == _by_xy(theirs["vertices"][used],
                                                                theirs["vertex_markers"][used])
    _same_edge_markers(ours, theirs)


def test_crossing_point_takes_the_first_marked_segment():
    """``intersections="split"``: the crossing lies on two segments; Triangle gives
    it the marker of the one inserted first (the lower index) when both are marked,
    else the marked one; its attributes interpolate along a segment."""
    V = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    S = np.array([[0, 2], [1, 3], [0, 1], [1, 2], [2, 3], [3, 0]])
    A = np.column_stack([V[:, 0] + V[:, 1], np.ones(4)])
    for smarks in ([0, 6, 0, 0, 0, 0], [4, 6, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]):
        smarks = np.array(smarks)
        ours = cdt_plugin.triangulate(V, S, intersections="split", segment_markers=smarks,
                                      vertex_attributes=A, holes=np.empty((0, 2)))
        _check(ours, V, S)
        theirs = triangle.triangulate({"vertices": V, "segments": S, "segment_markers": smarks,
                                       "vertex_attributes": A}, "pe")
        _compare_without_steiner_points_but_crossings(ours, theirs)
        (c,) = ours.steiner
        assert ours.vertex_attributes[c].tolist() == [2.0, 1.0]


def _compare_without_steiner_points_but_crossings(ours, theirs):
    assert (_by_xy(ours.vertices, ours.vertex_markers)
            == _by_xy(theirs["vertices"], theirs["vertex_markers"]))
    _same_edge_markers(ours, theirs)


def test_duplicates_zero_length_and_repeated_segments():
    """A merged duplicate takes the first nonzero marker of its copies; a repeated
    segment the first nonzero marker of its copies; a zero-length one marks nothing."""
    V = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [0, 1]], float)
    S = np.array([[0, 1], [1, 2], [2, 4], [4, 3], [2, 1], [3, 0], [4, 4]])
    tri = cdt_plugin.triangulate(V, S, vertex_markers=[0, 0, 0, 4, 0],
                                 segment_markers=[2, 0, 0, 0, 8, 9, 5])
    _check(tri, V, S)
    assert tri.vertex_map.tolist() == [0, 1, 2, 0, 3]
    assert tri.vertex_markers.tolist() == [4, 2, 8, 1]     # (4: its copy's; 8: the repeat's)
    got = _by_pair(tri.vertices, tri.segments, tri.segment_markers)
    assert got == {frozenset({(0.0, 0.0), (1.0, 0.0)}): 2, frozenset({(1.0, 0.0), (1.0, 1.0)}): 8,
                   frozenset({(1.0, 1.0), (0.0, 1.0)}): 1, frozenset({(0.0, 1.0), (0.0, 0.0)}): 1}


def test_collinear_input_has_markers_but_no_boundary():
    tri = cdt_plugin.triangulate([[0, 0], [1, 0], [2, 0]], [[0, 2]], segment_markers=[7],
                                 vertex_markers=[0, 3, 0], vertex_attributes=[1.0, 2.0, 3.0])
    assert len(tri.triangles) == 0
    assert tri.vertex_markers.tolist() == [7, 3, 7]
    assert tri.edge_markers.tolist() == [0, 0]
    assert tri.vertex_attributes[:, 0].tolist() == [1.0, 2.0, 3.0]


def test_defaults_without_markers_are_triangles():
    """No markers given: 1 on the boundary (holes too), 0 inside, as Triangle's default."""
    V = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3], [2, 0.5]])
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    tri = cdt_plugin.triangulate(V, S, holes=[[2, 2]])
    assert tri.tags is None and tri.vertex_attributes is None
    theirs = triangle.triangulate({"vertices": V, "segments": S, "holes": [[2, 2]]}, "pe")
    _compare_without_steiner({}, tri, theirs)


def test_regions_and_multipolygon_geometry():
    """Geometry input: markers index the PLC's vertices and segments (closing
    points dropped); two polygons, one with a hole."""
    geom = {"type": "MultiPolygon", "coordinates": [
        [[(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)], [(1, 1), (2, 1), (2, 2), (1, 2), (1, 1)]],
        [[(5, 0), (6, 0), (6, 1), (5, 0)]]]}
    plc = cdt_plugin.PLC.from_geo_interface(geom)
    smarks = np.where(plc.ring_is_hole[plc.segment_ring], 2, 5)
    tri = cdt_plugin.triangulate(geom, segment_markers=smarks, vertex_attributes=plc.vertices[:, 0],
                                 max_area=0.2)
    _check(tri, plc.vertices, plc.segments)
    pieces_in_holes = plc.ring_is_hole[plc.segment_ring[tri.segment_ids]]
    assert (tri.segment_markers == np.where(pieces_in_holes, 2, 5)).all()
    on_hole = np.isin(np.arange(len(tri.vertices)), tri.segments[pieces_in_holes].ravel())
    assert set(tri.vertex_markers[on_hole].tolist()) == {2}
    np.testing.assert_allclose(tri.vertex_attributes[:, 0], tri.vertices[:, 0], atol=1e-12)
    # a PLC may carry them itself; the keywords win
    plc.segment_markers = smarks
    assert cdt_plugin.triangulate(plc).segment_markers.tolist() == \
        cdt_plugin.triangulate(geom, segment_markers=smarks).segment_markers.tolist()
    assert set(cdt_plugin.triangulate(plc, segment_markers=smarks * 0).segment_markers.tolist()) == {1}


def test_interior_steiner_points_interpolate_in_the_unrefined_mesh():
    """A non-linear attribute: a refinement point gets the linear interpolation on
    the triangle of the unrefined triangulation that holds it."""
    V = np.array([[0, 0], [4, 0], [4, 3], [0, 3], [1.5, 1.2]])
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    a = V[:, 0] ** 2 + V[:, 1] ** 3
    tri = cdt_plugin.triangulate(V, S, vertex_attributes=a, max_area=0.05)
    base = cdt_plugin.triangulate(V, S)
    inner = [v for v in tri.steiner if not len(_segment_of(V, S, tri.vertices[v]))]
    assert inner
    k = base.locate(tri.vertices[inner])
    want = base.interpolate(a, tri.vertices[inner])
    np.testing.assert_allclose(tri.vertex_attributes[inner, 0], want, rtol=1e-13, atol=1e-13)
    assert (k >= 0).all()


def test_carry_attributes_on_concave_meshes_and_boundaries():
    """Located exactly in a mesh with a notch; a point a rounding outside the
    boundary, and one beyond the hull, get the value along the nearest edge."""
    V = np.array([[0, 0], [2, 0], [2, 2], [1, 1], [0, 2.0]])
    T = np.array([[0, 1, 3], [1, 2, 3], [0, 3, 4]])
    f = 1 + V[:, 0] - 2 * V[:, 1]
    P = np.array([[1, 0.5], [0.5, 1.0], [1.5, 1.5 + 1e-16], [1, -1e-17], [3, 1]])
    got = carry_attributes(V, T, f, P)
    np.testing.assert_allclose(got, 1 + P[:, 0] - 2 * np.clip(P[:, 1], 0, None)
                               - np.array([0, 0, 0, 0, 1]), atol=1e-12)
    assert carry_attributes(V, T, np.column_stack([f, f]), P[:1]).shape == (1, 2)
    assert carry_attributes(V, T, f, V)[3] == f[3]            # exact at a vertex


@pytest.mark.parametrize("kwargs, error, words", [
    ({"vertex_markers": [1, 2]}, InputShapeError, "one marker per input vertex"),
    ({"vertex_markers": [1, 2, 3.5, 0]}, InputShapeError, "must be integers: row 2"),
    ({"segment_markers": [[1, 2]]}, InputShapeError, "one marker per input segment"),
    ({"segment_markers": ["a", "b", "c", "d"]}, InputShapeError, "segment_markers"),
    ({"vertex_attributes": [[1.0], [2.0]]}, InputShapeError, "one row per input vertex"),
    ({"vertex_attributes": [1.0, np.nan, 0, 0]}, NonFiniteCoordinateError, "row(s) 1"),
])
def test_bad_markers_and_attributes_are_named(kwargs, error, words):
    with pytest.raises(error, match=None) as info:
        cdt_plugin.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                               **kwargs)
    assert words in str(info.value)
    assert issubclass(error, CDTError)


def test_markers_accept_triangle_columns_and_whole_floats():
    tri = cdt_plugin.triangulate([[0, 0], [1, 0], [0, 1]], [[0, 1]], keep_hull=True,
                                 vertex_markers=np.array([[3], [0], [0]], np.int32),
                                 segment_markers=[2.0])
    assert tri.vertex_markers.tolist() == [3, 2, 1] and tri.vertex_markers.dtype == np.int64


def test_from_triangles_keeps_markers_and_attributes():
    V = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]]
    T = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    tri = cdt_plugin.Triangulation.from_triangles(V, T, vertex_markers=[0, 3, 0, 0, 0],
                                                  vertex_attributes=np.arange(10.0).reshape(5, 2))
    assert tri.vertex_markers.tolist() == [1, 3, 1, 1, 0]
    assert tri.vertex_attributes.tolist() == np.arange(10.0).reshape(5, 2).tolist()
    assert tri.edge_markers.tolist() == [int(4 not in e) for e in tri.edges.tolist()]
    with pytest.raises(InputShapeError, match="one marker per input vertex"):
        cdt_plugin.Triangulation.from_triangles(V, T, vertex_markers=[1])


def _six_node(vertices, triangles, markers, attributes):
    """{corner coordinates of a triangle: {corner: (opposite midpoint, its marker,
    its attributes)}} of a six-node mesh."""
    V = np.asarray(vertices).tolist()
    return {frozenset(tuple(V[c]) for c in t[:3]):
            {tuple(V[t[i]]): (tuple(V[t[3 + i]]), int(np.ravel(markers)[t[3 + i]]),
                              tuple(np.round(attributes[t[3 + i]], 12))) for i in range(3)}
            for t in np.asarray(triangles)}


@pytest.mark.parametrize("path", POLYS, ids=os.path.basename)
def test_quadratic_matches_triangles_o2(path):
    d = _poly(path)
    V = d["vertices"]
    d["vertex_attributes"] = np.column_stack([V[:, 0] ** 2, V[:, 1]])
    ours = _ours(d)
    mesh = ours.quadratic()
    theirs = triangle.triangulate(d, "po2")
    n, e = len(ours.vertices), len(ours.edges)
    assert mesh.vertices.shape == (n + e, 2) and mesh.triangles.shape == (len(ours.triangles), 6)
    assert (mesh.triangles[:, :3] == ours.triangles).all()
    # every midpoint is shared by the triangles of its edge: one node per edge
    assert len(np.unique(mesh.triangles[:, 3:])) == e
    if "triangles" not in theirs:
        assert len(ours.triangles) == 0
        return
    assert len(np.unique(theirs["triangles"][:, 3:])) == e
    # Triangle's node convention, midpoints, markers and attributes, on every triangle
    # both meshes have (cocircular ties may give other diagonals)
    mine = _six_node(mesh.vertices, mesh.triangles, mesh.vertex_markers, mesh.vertex_attributes)
    yours = _six_node(theirs["vertices"], theirs["triangles"], theirs["vertex_markers"],
                      theirs["vertex_attributes"])
    common = mine.keys() & yours.keys()
    assert len(common) >= 0.8 * len(yours)
    assert {k: mine[k] for k in common} == {k: yours[k] for k in common}


def test_quadratic_to_meshio():
    meshio = pytest.importorskip("meshio")
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                                 segment_markers=[3, 0, 0, 0], vertex_attributes=[0.0, 2, 4, 2],
                                 max_area=0.5)
    mesh = tri.quadratic()
    m = mesh.to_meshio()
    assert isinstance(m, meshio.Mesh) and m.cells[0].type == "triangle6"
    cells = m.cells[0].data
    P = m.points
    # meshio's order: corners, then the midpoints of 01, 12, 20
    for j, (a, b) in enumerate([(0, 1), (1, 2), (2, 0)]):
        np.testing.assert_array_equal(P[cells[:, 3 + j]], (P[cells[:, a]] + P[cells[:, b]]) / 2)
    np.testing.assert_array_equal(m.point_data["vertex_markers"], mesh.vertex_markers)
    on_bottom = mesh.vertices[:, 1] == 0
    assert set(mesh.vertex_markers[on_bottom].tolist()) == {3}
    np.testing.assert_allclose(mesh.vertex_attributes[:, 0], mesh.vertices.sum(axis=1), atol=1e-12)


@pytest.mark.parametrize("order", [1, 2])
def test_triangle_files_round_trip_markers_attributes_and_six_nodes(tmp_path, order):
    """write_triangulation(markers=True, order=) read back by cdt_plugin.io, and the
    .node/.ele files Triangle's own reader (triangle.load) takes."""
    V = np.array([[0, 0], [3, 0], [3, 2], [0, 2], [1, 1]], float)
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    tri = cdt_plugin.triangulate(V, S, segment_markers=[4, 0, 0, 6], vertex_markers=[0, 0, 0, 0, 9],
                                 vertex_attributes=np.column_stack([V[:, 0], V[:, 1] * 2]), max_area=0.4)
    paths = tio.write_triangulation(tmp_path / "mesh", tri, markers=True, order=order)
    node, ele, poly = tio.read_node(paths[0]), tio.read_ele(paths[1]), tio.read_poly(paths[2])
    mesh = tri.quadratic() if order == 2 else tri
    np.testing.assert_array_equal(node.vertices, mesh.vertices)
    np.testing.assert_array_equal(node.attributes, mesh.vertex_attributes)
    np.testing.assert_array_equal(node.markers, mesh.vertex_markers)
    np.testing.assert_array_equal(ele.triangles, mesh.triangles)
    np.testing.assert_array_equal(poly.segments, tri.segments)
    np.testing.assert_array_equal(poly.segment_markers, tri.segment_markers)
    loaded = triangle.load(str(tmp_path), "mesh")
    np.testing.assert_array_equal(loaded["vertex_markers"].ravel(), mesh.vertex_markers)
    np.testing.assert_array_equal(loaded["triangles"], mesh.triangles)


def test_keep_hull_and_regions_with_refinement():
    """``keep_hull`` (Triangle's -c): the hull's pieces (``segment_ids`` -1) and the
    Steiner points on them are boundary, 1; region seeds with areas; a linear
    attribute exact everywhere, the hull's Steiner points too."""
    V = np.array([[0, 0], [4, 0], [5, 3], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]], float)
    S = np.array([[4, 5], [5, 6], [6, 7], [7, 4], [0, 6]])
    smarks = np.array([0, 3, 0, 4, 6])
    d = {"vertices": V, "segments": S, "segment_markers": smarks,
         "vertex_attributes": 2 * V[:, 0] + V[:, 1], "regions": [[2, 2, 1, 0.05], [4, 0.5, 2, 0.3]]}
    ours = cdt_plugin.triangulate(V, S, keep_hull=True, min_angle=25, regions=d["regions"],
                                  segment_markers=smarks, vertex_attributes=d["vertex_attributes"])
    assert_valid(ours.vertices, ours.triangles, segments=ours.segments)
    assert (ours.segment_ids == -1).any()
    theirs = triangle.triangulate(d, "pcq25aA")
    for mesh in (_arrays(ours), theirs):
        _markers_by_rule(V, S, smarks, mesh)
    W = ours.vertices
    np.testing.assert_allclose(ours.vertex_attributes[:, 0], 2 * W[:, 0] + W[:, 1], atol=1e-12)
    hull = ours.segment_ids == -1
    assert (ours.segment_markers[hull] == 1).all()
    assert (ours.vertex_markers[np.unique(ours.segments[hull])] != 0).all()


def test_refined_tags_interpolate_in_the_mesh_refined():
    """What a refinement of ``tri`` carries (``markers.refined_tags``): the input
    vertices and old Steiner points keep their attributes exactly, a new point on a
    segment is interpolated along it, a new interior point in ``tri``'s triangle."""
    from types import SimpleNamespace
    from cdt_plugin.markers import refined_tags, vertex_attributes
    V = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    S = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    a = V[:, 0] ** 2 + V[:, 1]                        # not linear: the base mesh shows
    tri = cdt_plugin.triangulate(V, S, vertex_attributes=a, max_area=2)
    new = np.array([[1.3, 0], [1.1, 2.7]])
    if any((tri.vertices == p).all(axis=1).any() for p in new):
        pytest.skip("the refinement placed a vertex there already")
    n = len(tri.vertices)
    u, v = tri.segments[np.flatnonzero(tri.segment_ids == 0)[0]]   # (the pieces as a refinement lists them)
    refined = SimpleNamespace(
        vertices=np.concatenate([tri.vertices, new]), vertex_map=tri.vertex_map,
        steiner=np.concatenate([tri.steiner, [n, n + 1]]),
        segments=np.concatenate([tri.segments, [[u, n], [n, v]]]),
        segment_ids=np.concatenate([tri.segment_ids, [0, 0]]))
    tags = refined_tags(tri.tags, tri, lambda: tri.vertex_attributes)
    got = vertex_attributes(refined, tags)
    np.testing.assert_array_equal(got[:n], tri.vertex_attributes)
    assert abs(got[n, 0] - 16 * 1.3 / 4) < 1e-12        # linear along segment 0, from 0 to 16
    k = tri.locate(new[1:])[0]
    want = tri.interpolate(tri.vertex_attributes[:, 0], new[1:])[0]
    assert k >= 0 and abs(got[n + 1, 0] - want) < 1e-12
    assert refined_tags(None, tri, lambda: None) is None
