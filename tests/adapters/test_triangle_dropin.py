"""``cdt_plugin.triangle`` against the ``triangle`` package: Triangle's own data set
through both with the same switch strings, compared by the properties Triangle
promises (keys, dtypes and shapes; the same triangles without refinement; the
bounds of q, a, D, Y and YY; markers per vertex), every mesh checked with the exact
checker; the package's examples and typical programs run unchanged but for the
import; one test per named error."""
from __future__ import annotations

import math

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin import triangle as tr
from cdt_plugin.errors import (InputShapeError, NonFiniteCoordinateError, SegmentIndexError,
                               SwitchError, TooFewPointsError)
from cdt_plugin.switches import read_switches
from tests.support.checker import (assert_valid, canonical_triangles,
                                   check_empty_circumcircles, incircle_exact)
from tests.support.corpus import corpus_dir
from tests.support.fuzz import polygon_with_holes

triangle = pytest.importorskip("triangle")

FOLDER = corpus_dir() / "triangle"
NAMES = sorted({p.name.split(".")[0] for p in FOLDER.glob("*.*")})
SWITCHES = ["p", "pq", "pq30a0.01", "pa", "pAa", "pc", "pD", "pY", "pYY", "pe", "pn", "pv", "po2",
            "pq30Aao2", "r", "ra", "rpq", "rpqa", "pj", "pS10", "", "c", "pB", "pP", "pN", "pE",
            "pO", "pi"]


MATRIX = list(SWITCHES)
# what the other parts of issue 44 bring (the markers and refine branches), by attribute
MARKERS = hasattr(cdt_plugin.Triangulation, "vertex_markers")
REFINE = hasattr(cdt_plugin.Triangulation, "refine")
QUADRATIC = hasattr(cdt_plugin.Triangulation, "quadratic")


def _missing(switches: str) -> str | None:
    """What ``switches`` needs that has not landed yet (None: nothing)."""
    s = read_switches(switches)
    if not s.no_markers and not MARKERS:
        return "boundary markers (tri.vertex_markers) not merged yet"
    if s.refine and not REFINE or s.split > 1 and not REFINE:
        return "refinement of a mesh (tri.refine, split_segments) not merged yet"
    if s.order == 2 and not QUADRATIC:
        return "six-node triangles (tri.quadratic) not merged yet"
    return None


def _input(name: str, switches: str) -> dict:
    """The sample ``name`` as both packages take it (read by our loader); for ``r``
    the package's ``pq`` mesh of it, with a bound per triangle for a bare ``a``."""
    data = tr.load(FOLDER, name)
    if read_switches(switches).refine:
        if "segments" not in data:
            pytest.skip("r refines a mesh of a PSLG sample")
        mesh = triangle.triangulate(data, "pq")
        if "triangles" not in mesh:
            pytest.skip("r refines a mesh: Triangle's pq of this sample has no triangle")
        data = {k: mesh[k] for k in ("vertices", "vertex_markers", "triangles", "segments",
                                     "segment_markers") if k in mesh}
        areas = _areas(mesh["vertices"], mesh["triangles"])
        data["triangle_max_area"] = (areas / 4)[:, None]
    return data


def _areas(V, T) -> np.ndarray:
    a, b, c = (V[T[:, i]] for i in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _min_angles(V, T) -> np.ndarray:
    P = V[T[:, :3]]
    out = np.full(len(T), 180.0)
    for i in range(3):
        u, v = P[:, (i + 1) % 3] - P[:, i], P[:, (i + 2) % 3] - P[:, i]
        cos = (u * v).sum(1) / np.hypot(*u.T) / np.hypot(*v.T)
        out = np.minimum(out, np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return out


def _layout(d: dict) -> dict:
    return {k: (str(v.dtype), v.shape[1:]) for k, v in d.items()}


def _compare(name: str, switches: str) -> tuple[dict, dict, dict]:
    """Both outputs of ``switches`` on ``name``, after the key/dtype/shape check."""
    missing = _missing(switches)
    if missing:
        pytest.skip(missing)
    data = _input(name, switches)
    if "vertex_attributes" in data and not MARKERS:
        pytest.skip("vertex attributes (tri.vertex_attributes) not merged yet")
    theirs = triangle.triangulate(data, switches)
    ours = tr.triangulate(data, switches)
    assert _layout(ours) == _layout(theirs)
    return data, theirs, ours


def _boundary(T) -> np.ndarray:
    """The edges of the triangles ``T`` that only one of them has."""
    edges, counts = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]),
                                      axis=1), axis=0, return_counts=True)
    return edges[counts == 1]


def _check_mesh(data: dict, ours: dict, switches: str, theirs: dict) -> None:
    """Our mesh exactly valid (its segments in it), and the bounds the switches ask for."""
    s = read_switches(switches)
    if "triangles" not in ours or "vertices" not in ours:
        return
    V, T = ours["vertices"], ours["triangles"][:, :3]
    used = np.unique(T)
    segments = ours.get("segments", data.get("segments") if s.pslg else None)
    if s.refine and segments is None:
        # (r without p promises a valid mesh, not a Delaunay one: the input mesh need
        # not be Delaunay without its segments; every edge exempt)
        segments = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]),
                                     axis=1), axis=0)
    assert_valid(V, T, segments=segments, domain="hull" if segments is None else "segments",
                 require_all_vertices=False)
    n_in = len(data["vertices"])
    if s.min_angle and not s.split:
        # Triangle's promise holds except at small input angles (and, with Y or YY, at
        # the segments it may not split): no more triangles miss it than in its mesh
        low = (_min_angles(V, T) < s.min_angle - 1e-9).sum()
        assert low <= (_min_angles(theirs["vertices"], theirs["triangles"][:, :3])
                       < s.min_angle - 1e-9).sum()
    if s.max_area:
        assert (_areas(V, T) <= s.max_area * (1 + 1e-12)).all()
    if s.refine and s.area_from_input:
        # each input triangle's bound, at the triangles whose centroid it holds: no more
        # of ours above it than of Triangle's (it averages bounds where it flips)
        assert _over_bound(data, V, T) <= _over_bound(data, theirs["vertices"], theirs["triangles"])
    if s.conforming_delaunay:
        assert check_empty_circumcircles(V, T).ok
    if s.split and "segments" in ours:
        steiner = used[used >= n_in]
        on = _boundary(T) if s.split == 1 else ours["segments"]
        assert not np.isin(steiner, on).any()


def _over_bound(data: dict, V, T) -> int:
    """How many of the triangles ``V[T]`` are larger than the ``triangle_max_area`` of
    the input triangle holding their centroid."""
    base = cdt_plugin.Triangulation.from_triangles(data["vertices"], np.asarray(data["triangles"])[:, :3])
    bound = np.asarray(data["triangle_max_area"], float).ravel()[base.locate(V[T].mean(axis=1))]
    return int(((bound > 0) & (_areas(V, T) > bound * (1 + 1e-12))).sum())


def _same_triangles(V1, T1, V2, T2) -> None:
    """The same triangles as sets of coordinates, but where four or more vertices are
    cocircular (either diagonal is Delaunay: Triangle's choice is its own): every
    triangle of one mesh missing from the other has a vertex of the other's missing
    triangles on its circumcircle."""
    ours, theirs = canonical_triangles(V1, T1), canonical_triangles(V2, T2)
    extra, missing = ours - theirs, theirs - ours
    assert len(extra) == len(missing)
    others = {p for t in missing for p in t}
    for t in extra:
        assert any(incircle_exact(*t, p) == 0 for p in others - set(t)), t


@pytest.mark.parametrize("switches", MATRIX)
@pytest.mark.parametrize("name", NAMES)
def test_matrix_against_triangle(name, switches):
    if (name, switches) == ("face", "pq30a0.01"):
        pytest.skip("3.2 million triangles: a benchmark's size, not a test's")
    data, theirs, ours = _compare(name, switches)
    _check_mesh(data, ours, switches, theirs)
    s = read_switches(switches)
    if not s.quality and not s.conforming_delaunay and not s.refine and "triangles" in ours \
            and "vertices" in ours and s.order == 1:
        _same_triangles(ours["vertices"], ours["triangles"], theirs["vertices"], theirs["triangles"])
    if "vertex_markers" in ours:
        _same_per_vertex(ours, theirs, "vertex_markers")
    if "vertex_attributes" in ours:
        # Triangle interpolates a Steiner point's attributes in the triangle of the mesh
        # being refined that it goes in, cdt_plugin in the unrefined mesh: equal on the
        # segments (linear along them), between the input's values inside
        _same_per_vertex(ours, theirs, "vertex_attributes", on=theirs.get("segments"),
                         inputs=len(data["vertices"]))
        given = data["vertex_attributes"]
        assert (ours["vertex_attributes"] >= given.min(axis=0) - 1e-12).all()
        assert (ours["vertex_attributes"] <= given.max(axis=0) + 1e-12).all()


def _same_per_vertex(ours: dict, theirs: dict, key: str, on=None, inputs: int = 0) -> None:
    """``key`` equal at every vertex both meshes have (by coordinates: Steiner points
    are numbered differently), attributes up to rounding; with ``on`` (segments of
    ``theirs``) only at the ``inputs`` input vertices and the vertices of those segments."""
    mine = {tuple(v): a for v, a in zip(ours["vertices"].tolist(), ours[key].tolist())}
    rows = range(len(theirs["vertices"]))
    if on is not None:
        rows = sorted(set(range(inputs)) | set(np.ravel(on).tolist()))
    V, values = theirs["vertices"].tolist(), theirs[key].tolist()
    common = [(mine[tuple(V[i])], values[i]) for i in rows if tuple(V[i]) in mine]
    assert common
    for a, b in common:
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("switches", [s + "B" for s in SWITCHES if "B" not in s])
@pytest.mark.parametrize("name", ["A", "face", "la", "double_hex", "dots"])
def test_matrix_without_markers(name, switches):
    if (name, switches) == ("face", "pq30a0.01B"):
        pytest.skip("3.2 million triangles: a benchmark's size, not a test's")
    data, theirs, ours = _compare(name, switches)
    _check_mesh(data, ours, switches, theirs)


@pytest.mark.parametrize("seed", range(12))
def test_random_pslgs_against_triangle(seed):
    """Star polygons with square holes and free points, random markers and attributes
    (some segments and vertices unmarked): the same comparisons as the data set's."""
    rng = np.random.default_rng(seed)
    V, S, _ = polygon_with_holes(rng)
    outer = int(np.flatnonzero(S[:, 1] == 0)[0]) + 1             # (the outer ring's length)
    squares = [V[outer + 4 * k:outer + 4 * k + 4] for k in range((len(S) - outer) // 4)]
    holes = [q.mean(axis=0) for q in squares[::2]]               # (every other square a hole)
    data = {"vertices": V, "segments": S.astype(np.int32),
            "vertex_markers": rng.integers(0, 3, (len(V), 1)).astype(np.int32),
            "segment_markers": rng.integers(0, 4, (len(S), 1)).astype(np.int32),
            "vertex_attributes": rng.random((len(V), 2))}
    if holes:
        data["holes"] = np.array(holes)
    for switches in ("p", "pe", "pq", "pq30a0.02", "pcen", "pDj"):
        missing = _missing(switches)
        if missing:
            pytest.skip(missing)
        theirs, ours = triangle.triangulate(data, switches), tr.triangulate(data, switches)
        assert _layout(ours) == _layout(theirs), switches
        _check_mesh(data, ours, switches, theirs)
        if switches in ("p", "pe", "pcen"):
            _same_triangles(*_mesh(ours), *_mesh(theirs))
        _same_per_vertex(ours, theirs, "vertex_markers")
        _same_per_vertex(ours, theirs, "vertex_attributes", on=theirs.get("segments"),
                         inputs=len(V))


def test_region_areas_only_with_a():
    data = tr.load(FOLDER, "la")
    with_a, without = tr.triangulate(data, "pAaB"), tr.triangulate(data, "pAB")
    assert len(without["triangles"]) == len(triangle.triangulate(data, "pAB")["triangles"])
    V, T = with_a["vertices"], with_a["triangles"]
    bound = dict(zip(data["regions"][:, 2], data["regions"][:, 3]))
    limit = np.array([bound.get(a, np.inf) for a in with_a["triangle_attributes"][:, 0]])
    limit[limit <= 0] = np.inf
    assert (_areas(V, T) <= limit * (1 + 1e-12)).all()
    assert len(T) > len(without["triangles"])


def test_holes_ignored_with_O():
    data = tr.load(FOLDER, "face")
    _same_triangles(*_mesh(tr.triangulate(data, "pOB")), *_mesh(triangle.triangulate(data, "pOB")))
    assert len(tr.triangulate(data, "pOB")["triangles"]) > len(tr.triangulate(data, "pB")["triangles"])


def test_switches_that_change_nothing_here(capsys):
    data = tr.load(FOLDER, "face")
    plain = tr.triangulate(data, "pB")
    same = tr.triangulate(data, "pXFlsQIgzvCB")
    assert _layout(same) == _layout(plain)
    assert canonical_triangles(*_mesh(same)) == canonical_triangles(*_mesh(plain))
    assert capsys.readouterr().err == ""
    tr.triangulate(data, "pVB")
    assert "36 triangles" in capsys.readouterr().err


def _mesh(d: dict):
    return d["vertices"], d["triangles"]


@pytest.mark.parametrize("switches", ["p", "pq", "pe", "pB", "pj"])
def test_p_without_segments_removes_every_triangle(switches):
    data = {"vertices": np.array([[0, 0], [1, 0], [0, 1], [1, 1.5]]),
            "vertex_markers": np.array([[3], [0], [2], [0]], np.int32),
            "vertex_attributes": np.array([[1.0], [2.0], [3.0], [4.0]])}
    ours, theirs = tr.triangulate(data, switches), triangle.triangulate(data, switches)
    assert _layout(ours) == _layout(theirs)
    assert all(np.array_equal(ours[k], theirs[k]) for k in theirs)


def test_duplicate_vertices_keep_triangles_numbering():
    v = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [1, 0]], float)
    out = tr.triangulate({"vertices": v}, "B")
    assert len(out["vertices"]) == 5 and 4 not in out["triangles"]
    assert np.array_equal(out["vertices"], v)
    assert len(tr.triangulate({"vertices": v}, "jB")["vertices"]) == 4
    assert_valid(out["vertices"], out["triangles"], require_all_vertices=False)


# ------------------------------------------------------------------------------------------
# the package's own examples (tri.py's docstrings), run with our module, compared by what
# Triangle promises (its numbering and triangle order are not ours)
# ------------------------------------------------------------------------------------------

def test_package_example_triangulate():
    if not MARKERS:
        pytest.skip("boundary markers (tri.vertex_markers) not merged yet")
    v = [[0, 0], [0, 1], [1, 1], [1, 0]]
    t = tr.triangulate({'vertices': v}, 'a0.2')
    assert t['vertices'][:4].tolist() == [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
    assert (_areas(t['vertices'], t['triangles']) <= 0.2).all()
    x, y = t['vertices'].T
    boundary = (x == 0) | (x == 1) | (y == 0) | (y == 1)
    assert t['vertex_markers'].ravel().tolist() == boundary.astype(int).tolist()
    assert_valid(t['vertices'], t['triangles'])


def test_package_example_delaunay():
    pts = [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]
    tri = tr.delaunay(pts)
    assert tri.dtype == np.int32
    assert canonical_triangles(pts, tri) == canonical_triangles(pts, triangle.delaunay(pts))


def test_package_example_convex_hull():
    pts = [[0, 0], [0, 1], [1, 1], [1, 0], [0.5, 0.5], [0, 1]]
    segments = tr.convex_hull(pts)
    theirs = triangle.convex_hull(np.array(pts, float)[:5])
    assert segments.dtype == np.int32
    assert {frozenset(s) for s in segments.tolist()} == {frozenset(s) for s in theirs.tolist()}


def test_package_example_voronoi():
    pts = [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]
    points, edges, ray_origin, ray_direct = tr.voronoi(pts)
    p2, e2, o2, d2 = triangle.voronoi(pts)
    assert sorted(points.tolist()) == sorted(p2.tolist())
    assert [a.dtype for a in (points, edges, ray_origin, ray_direct)] == \
        [a.dtype for a in (p2, e2, o2, d2)]
    rays = sorted((tuple(points[o]), tuple(d)) for o, d in zip(ray_origin, ray_direct))
    assert rays == sorted((tuple(p2[o]), tuple(d)) for o, d in zip(o2, d2))
    assert sorted(map(sorted, points[edges].tolist())) == sorted(map(sorted, p2[e2].tolist()))


def test_load_and_get_data_as_the_package():
    """Every sample of the installed package, read by both (our get_data finds the
    package's data folder); the regions differ where the package misreads them."""
    for name in ("A", "box", "bbox.1", "dots", "double_hex3", "ell", "face", "greenland",
                 "la", "spiral", "spiral.q.1", "square_circle_hole.1"):
        ours, theirs = tr.get_data(name), triangle.get_data(name)
        assert _layout(ours) == _layout(theirs), name
        for key in set(theirs) - {"regions"}:
            assert np.array_equal(ours[key], theirs[key]), (name, key)
    la = tr.load(FOLDER, "la")            # one value after x y: attribute and area, as triangle.c
    assert np.array_equal(la["regions"][:, 2], la["regions"][:, 3])


def test_voronoi_edge_files_as_the_package():
    for name in ("dots.1.v", "diamond_02_00009.1.v"):
        ours, theirs = tr.get_data(name), triangle.get_data(name)
        assert _layout(ours) == _layout(theirs)
        assert all(np.array_equal(ours[k], theirs[k]) for k in theirs)


def test_loads_reads_texts():
    node = "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n"
    ele = "2 3 0\n1 1 2 3\n2 1 3 4\n"
    ours, theirs = tr.loads(node=node, ele=ele), triangle.loads(node=node, ele=ele)
    assert _layout(ours) == _layout(theirs)
    assert np.array_equal(ours["triangles"], theirs["triangles"])


# ------------------------------------------------------------------------------------------
# typical programs, unchanged but for the import
# ------------------------------------------------------------------------------------------

def _section_properties(tr, geometry: dict) -> tuple[float, float, float]:
    """A section-property calculator: six-node triangles of the section, area and
    centroid by the midpoint rule of each six-node triangle."""
    mesh = tr.triangulate(geometry, "pq30Aao2")
    V, T = mesh["vertices"], mesh["triangles"]
    area = _areas(V, T[:, :3])
    mid = V[T[:, 3:]].mean(axis=1)
    return float(area.sum()), *(area[:, None] * mid).sum(axis=0) / area.sum()


def test_section_property_calculator():
    if _missing("po2"):
        pytest.skip(_missing("po2"))
    outer = [[0, 0], [100, 0], [100, 10], [55, 10], [55, 190], [100, 190], [100, 200], [0, 200],
             [0, 190], [45, 190], [45, 10], [0, 10]]
    geometry = {"vertices": np.array(outer, float),
                "segments": np.array([[i, (i + 1) % 12] for i in range(12)]),
                "regions": np.array([[50, 100, 1, 5.0]])}
    ours, theirs = _section_properties(tr, geometry), _section_properties(triangle, geometry)
    assert ours == pytest.approx(theirs, rel=1e-12)
    assert ours[0] == pytest.approx(2 * 100 * 10 + 10 * 180)


def _flood_mesh(tr, domain: dict) -> dict:
    """A flood model: regions (channel, floodplain) with their own maximum areas."""
    return tr.triangulate(domain, "pq30aAB")


def test_flood_model_regions():
    v = np.array([[0, 0], [100, 0], [100, 40], [0, 40], [0, 15], [100, 15], [100, 25], [0, 25]],
                 float)
    s = np.array([[0, 1], [1, 5], [5, 6], [6, 2], [2, 3], [3, 7], [7, 4], [4, 0], [4, 5], [6, 7]])
    regions = np.array([[50, 20, 1, 5.0], [50, 5, 2, 50.0], [50, 35, 2, 50.0]])
    mesh = _flood_mesh(tr, {"vertices": v, "segments": s, "regions": regions})
    V, T, attr = mesh["vertices"], mesh["triangles"], mesh["triangle_attributes"][:, 0]
    areas = _areas(V, T)
    assert (areas[attr == 1] <= 5.0).all() and (areas[attr == 2] <= 50.0).all()
    assert areas.sum() == pytest.approx(4000.0)
    assert (_min_angles(V, T) >= 30 - 1e-9).all()
    assert_valid(V, T, segments=mesh["segments"], domain="segments")


def _trimesh_style(tr, polygon_xy, holes_xy, triangle_args="p"):
    """What trimesh's ``triangulate_polygon(engine="triangle")`` does with a polygon."""
    n = len(polygon_xy)
    arg = {"vertices": np.vstack([polygon_xy, *holes_xy]),
           "segments": np.vstack([np.column_stack([np.arange(n), np.roll(np.arange(n), -1)])]
                                 + [np.column_stack([np.arange(len(h)), np.roll(np.arange(len(h)), -1)])
                                    + n + sum(len(g) for g in holes_xy[:i])
                                    for i, h in enumerate(holes_xy)]),
           "holes": np.array([h.mean(axis=0) for h in holes_xy])}
    result = tr.triangulate(arg, triangle_args)
    return result["vertices"], result["triangles"], result["segments"]


@pytest.mark.parametrize("args", ["p", "pq30a0.5"])
def test_trimesh_triangle_args(args):
    if _missing(args):
        pytest.skip(_missing(args))
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    hole = np.array([[1, 1], [1, 3], [3, 3], [3, 1]], float)
    V, T, S = _trimesh_style(tr, square, [hole], args)
    assert _areas(V, T).sum() == pytest.approx(12.0)
    assert_valid(V, T, segments=S, domain="segments", require_all_vertices=False)
    if args == "p":
        theirs = _trimesh_style(triangle, square, [hole], args)
        _same_triangles(V, T, *theirs[:2])


@pytest.mark.parametrize("text, same_as", [("pqS", "pqS0"), ("-p -q30 -B", "pq30B"),
                                           ("pYqYB", "pqYYB"), ("pq.5B", "pq0.5B")])
def test_switches_read_as_triangle_reads_them(text, same_as):
    """Spellings Triangle reads alike give the same record here and the same mesh there."""
    assert read_switches(text)._replace(text="") == read_switches(same_as)._replace(text="")
    if _missing(same_as):
        pytest.skip(_missing(same_as))
    data = tr.load(FOLDER, "face")
    theirs = [triangle.triangulate(data, t) for t in (text, same_as)]
    assert canonical_triangles(*_mesh(theirs[0])) == canonical_triangles(*_mesh(theirs[1]))
    assert len(tr.triangulate(data, text)["vertices"]) == len(tr.triangulate(data, same_as)["vertices"])


def test_switch_record():
    s = read_switches("pq30.5a0.25AcDjenvgBPNEIOXzo2YYS7iFlsCQVV")
    assert (s.min_angle, s.max_area, s.order, s.split, s.max_steiner, s.verbose) == (30.5, 0.25, 2, 2, 7, 2)
    assert all(getattr(s, f) for f in ("pslg", "region_attributes", "convex_hull", "conforming_delaunay",
                                       "jettison", "edges", "voronoi", "neighbors", "geomview",
                                       "no_markers", "no_poly", "no_nodes", "no_elements",
                                       "no_iteration_numbers", "no_holes", "no_exact", "zero_index",
                                       "incremental", "sweepline", "vertical_cuts",
                                       "split_segments_first", "check", "quiet"))
    assert read_switches("pq30a0.25YYS7").keywords() == {
        "min_angle": 30.0, "max_area": 0.25, "split_boundary": False, "split_segments": False,
        "max_steiner": 7}
    assert read_switches("rpa").area_from_input and read_switches("ru").user_test
    assert read_switches("pcevN").files == (".ele", ".poly", ".edge", ".v.node", ".v.edge")


# ------------------------------------------------------------------------------------------
# malformed input: a named error where Triangle crashes, loops or skips
# ------------------------------------------------------------------------------------------

SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_coordinates(bad):
    with pytest.raises(NonFiniteCoordinateError):
        tr.triangulate({"vertices": [[0, 0], [1, 0], [bad, 1]]}, "pB")


@pytest.mark.parametrize("segment", [[0, 4], [-1, 2]])
def test_segment_index_out_of_range(segment):
    with pytest.raises(SegmentIndexError):
        tr.triangulate(dict(SQUARE, segments=[[0, 1], segment]), "pB")


def test_fewer_than_three_points():
    with pytest.raises(TooFewPointsError):
        tr.triangulate({"vertices": [[0, 0], [1, 0]]}, "")
    with pytest.raises(TooFewPointsError):
        tr.delaunay([[0, 0], [1, 1]])


@pytest.mark.parametrize("switches", ["pk", "pa1e-3", "pS5.5", "pYYY", "po3", "ph", "pq.5.5"])
def test_switch_triangle_would_misread(switches):
    with pytest.raises(SwitchError, match=f"{switches!r}"):
        tr.triangulate(SQUARE, switches)


def _sample_test_holds(t):
    """Every triangle passes triangle.c's sample triunsuitable at some corner taken as
    its origin (Triangle tests the orientation of the moment)."""
    V, T = t["vertices"], t["triangles"][:, :3]
    longest = np.max([((V[T[:, i]] - V[T[:, (i + 1) % 3]]) ** 2).sum(1) for i in range(3)], axis=0)
    ok = np.zeros(len(T), bool)
    for i in range(3):
        ok |= longest <= 0.05 * (V[T[:, i]] ** 2).sum(1) + 0.02
    return ok


@pytest.mark.parametrize("switches", ["pu", "pq25u", "pqu"])
def test_user_test_switch_applies_the_packages_sample_test(switches):
    big = {"vertices": [[0, 0], [4, 0], [4, 4], [0, 4]], "segments": SQUARE["segments"]}
    ours, theirs = tr.triangulate(big, switches), triangle.triangulate(big, switches)
    assert _sample_test_holds(ours).all()
    assert 0.8 < len(ours["triangles"]) / len(theirs["triangles"]) < 1.25
    assert_valid(ours["vertices"], ours["triangles"], segments=ours["segments"], domain="segments")
    if "q" in switches:
        assert _min_angles(ours["vertices"], ours["triangles"]).min() >= (25 if "25" in switches else 20) - 1e-9


def test_user_test_after_refining_a_mesh():
    big = {"vertices": [[0, 0], [4, 0], [4, 4], [0, 4]], "triangles": [[0, 1, 2], [0, 2, 3]]}
    ours = tr.triangulate(big, "ru")
    assert _sample_test_holds(ours).all() and len(ours["triangles"]) > 100
    assert ours["vertices"][:4].tolist() == big["vertices"]


def test_unknown_key():
    with pytest.raises(InputShapeError, match="'vertex'"):
        tr.triangulate({"vertex": [[0, 0], [1, 0], [0, 1]]}, "")


def test_refine_without_triangles():
    with pytest.raises(InputShapeError, match="triangles"):
        tr.triangulate(SQUARE, "r")


def test_bad_refine_triangle():
    if not REFINE:
        pytest.skip("refinement of a mesh (tri.refine) not merged yet")
    with pytest.raises(cdt_plugin.CDTError, match="triangle"):
        tr.triangulate(dict(SQUARE, triangles=[[0, 1, 2], [0, 2, 7]]), "rq")


def test_sample_data_missing(monkeypatch, tmp_path):
    from cdt_plugin.errors import SampleDataError
    monkeypatch.setenv("CDT_TRIANGLE_DATA", str(tmp_path))
    with pytest.raises(SampleDataError, match="'face'"):
        tr.get_data("face")
    monkeypatch.setenv("CDT_TRIANGLE_DATA", str(FOLDER))
    assert len(tr.get_data("face")["vertices"]) == 26
