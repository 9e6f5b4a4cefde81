"""Triangle file formats (cdt_plugin.io) and the corpus loaders (tests/corpus.py)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import cdt_plugin
import corpus
from cdt_plugin import io as tio
from checker import assert_valid
from cdt_plugin.errors import (CDTError, FileFormatError, InputShapeError,
                               NonFiniteCoordinateError)

CORPUS = corpus.corpus_dir()
needs_corpus = pytest.mark.skipif(not (CORPUS / "README.md").exists(),
                                  reason=f"corpus not found at {CORPUS}")

# The Triangle rows of the corpus README's statistics table (V, S, holes), kept here too so
# that a README parsing slip cannot make the test vacuous.
TRIANGLE_TABLE = {
    "A.poly": (29, 29, 1), "box.poly": (8, 5, 1), "diamond_02_00009.node": (9, 0, 0),
    "dots.node": (100, 0, 0), "double_hex.poly": (96, 96, 2), "double_hex2.poly": (48, 48, 2),
    "double_hex3.node": (16, 0, 0), "double_hex3.poly": (16, 16, 2), "ell.node": (21, 0, 0),
    "face.poly": (26, 22, 3), "greenland.node": (33343, 0, 0), "la.poly": (141, 148, 0),
    "spiral.node": (15, 0, 0), "square_circle_hole.poly": (826, 135, 1),
}


def _read_any(path):
    return tio.read_poly(path) if path.suffix == ".poly" else tio.read_node(path)


# ----------------------------------------------------------------------------------------
# the real Triangle files
# ----------------------------------------------------------------------------------------

@needs_corpus
@pytest.mark.parametrize("fname", sorted(TRIANGLE_TABLE))
def test_triangle_corpus_counts(fname):
    d = _read_any(CORPUS / "triangle" / fname)
    V, S, H = TRIANGLE_TABLE[fname]
    assert d.vertices.shape == (V, 2) and d.vertices.dtype == np.float64
    assert d.first_index == 1
    if fname.endswith(".poly"):
        assert d.segments.shape == (S, 2) and d.segments.dtype == np.int64
        assert d.segments.min() >= 0 and d.segments.max() < V     # zero-based
        assert d.holes.shape == (H, 2)
    row = corpus.read_stats_table()[f"triangle/{fname}"]
    assert (row["V"], row["S"], row["holes"]) == (str(V), str(S), str(H))


@needs_corpus
def test_triangle_corpus_details():
    la = tio.read_poly(CORPUS / "triangle" / "la.poly")
    assert la.vertices[0, 0] == 0.0 and math.copysign(1, la.vertices[0, 1]) == -1  # -.000000E+00
    assert la.vertices[1, 0] == 41.8893
    assert la.vertices[2, 1] == -0.235585
    assert la.markers is not None and la.markers[0] == 101 and la.markers[2] == 0
    # 6 region lines "<#> x y value": Triangle uses the value as attribute AND max area
    assert la.regions.shape == (6, 4)
    assert la.regions[0].tolist() == [6.0, -0.2, 0.05, 0.05]
    assert la.regions[5].tolist() == [5.0, -10.0, 3.0, 3.0]
    a = tio.read_poly(CORPUS / "triangle" / "A.poly")
    assert a.attributes.shape == (29, 1) and a.attributes[0, 0] == -0.57
    assert a.markers is None and a.segment_markers is None
    box = tio.read_poly(CORPUS / "triangle" / "box.poly")
    assert box.markers.tolist() == [0, 0, 0, 33, 0, 0, 0, 0]
    assert box.segments.tolist() == [[0, 1], [4, 6], [6, 7], [7, 5], [5, 4]]
    assert box.segment_markers.tolist() == [5, 0, 0, 10, 0]
    assert box.holes.tolist() == [[1.5, 1.5]]
    face = tio.read_poly(CORPUS / "triangle" / "face.poly")
    assert face.holes.tolist() == [[0, -50], [-50, 50], [50, 50]]
    # double_hex3.node is the point-only copy of double_hex3.poly's vertices
    n3 = tio.read_node(CORPUS / "triangle" / "double_hex3.node")
    p3 = tio.read_poly(CORPUS / "triangle" / "double_hex3.poly")
    np.testing.assert_array_equal(n3.vertices, p3.vertices)


@needs_corpus
def test_corpus_table_matches_every_file():
    rows = corpus.read_stats_table()
    files = corpus.corpus_files()
    assert len(files) == 122 and len(rows) == 122
    for path in files:
        plcs = corpus.load_file(path)
        key = f"{path.parent.name}/{path.name}"
        row = rows[key]
        V = sum(len(p.vertices) for p in plcs)
        S = sum(len(p.segments) for p in plcs)
        if path.parent.name == "triangle":
            H = sum(len(p.holes) for p in plcs)
        else:
            H = sum(p.hole_rings for p in plcs)
        assert (str(V), str(S), str(H)) == (row["V"], row["S"], row["holes"]), key
        for p in plcs:
            assert p.vertices.dtype == np.float64 and p.segments.dtype == np.int64
            assert p.vertices.ndim == 2 and p.vertices.shape[1] == 2
            assert p.segments.ndim == 2 and p.segments.shape[1] == 2
            assert p.holes.ndim == 2 and p.holes.shape[1] == 2
            if len(p.segments):
                assert 0 <= p.segments.min() and p.segments.max() < len(p.vertices)
            if p.rings is not None:
                assert sum(len(r) for r in p.rings) == len(p.vertices)


@needs_corpus
def test_corpus_loader_details():
    (steiner,) = corpus.load("earcut/steiner.json")
    assert [len(r) for r in steiner.rings] == [4, 1, 1, 1, 1]
    assert len(steiner.segments) == 4 and steiner.polygons == [[0, 1, 2, 3, 4]]
    (debug2,) = corpus.load("cdt/debug2.txt")                    # CRLF, 1.5e-05 style
    assert debug2.vertices.shape == (10000, 2) and debug2.kind == "cdt"
    (sq,) = corpus.load("cdt/unit square.txt")                   # space in the name
    assert sq.name == "cdt/unit square.txt" and len(sq.segments) == 4
    feats = corpus.load("gis/naturalearth_lowres.geojson")
    assert len(feats) == 177 and all(f.kind == "geojson" for f in feats)
    assert sum(len(f.polygons) for f in feats) == 288
    assert sum(len(f.rings) for f in feats) == 289
    for f in feats:          # closing points dropped: every ring is a closed segment chain
        for r in f.rings:
            assert not np.array_equal(f.vertices[r[0]], f.vertices[r[-1]])
    assert len(corpus.load("gis/ne_50m_admin_0_countries.geojson")) == 241


@needs_corpus
def test_iterators():
    plcs = list(corpus.iter_plcs())
    assert len(plcs) == 14 + 47 + 59 + 177 + 241
    kinds = {p.kind for p in plcs}
    assert kinds == set(corpus.KINDS)
    pts = list(corpus.iter_point_sets())
    assert len(pts) == len(plcs)
    assert all(len(p.segments) == 0 and p.rings is None for p in pts)
    names = {p.name for p in pts}
    assert {"triangle/greenland.node", "cdt/Sweden.txt", "triangle/A.poly"} <= names
    assert sum(len(p.vertices) for p in pts) == sum(len(p.vertices) for p in plcs)


def test_corpus_dir_env(monkeypatch, tmp_path):
    monkeypatch.setenv("CDT_CORPUS", str(tmp_path))
    assert corpus.corpus_dir() == tmp_path


def test_cdt_txt_malformed(tmp_path):
    p = tmp_path / "bad edges.txt"
    p.write_text("3 1\r\n0 0\r\n1 0\r\n0 1\r\n0 3\r\n")
    with pytest.raises(FileFormatError, match=r"bad edges.txt: edge 0 \[0, 3\]"):
        corpus.load_cdt_txt(p)
    p.write_text("3 1\n0 0\n1 0\n0 1\n")
    with pytest.raises(FileFormatError, match="need 10 tokens, the file has 8"):
        corpus.load_cdt_txt(p)
    p.write_text("3 0\n0 0\n1 x\n0 1\n")
    with pytest.raises(FileFormatError, match="unparsable"):
        corpus.load_cdt_txt(p)


# ----------------------------------------------------------------------------------------
# lexical details and first index 0
# ----------------------------------------------------------------------------------------

NODE0 = """\
# a 0-based file with comments, blank lines and odd floats

4 2 1 1   # header
0  0.0   -.000000E+00  7.5   1
1  1.0e0  0.0          -1e-3  0    # comment after a record

2  1.0    1.0          0      0
3  0      1            2.86e-05 2
"""

POLY0 = NODE0 + """\
4 1
0 0 1 5
1 1 2 5
2 2 3 6
3 3 0 6
1
0 0.5 0.5
2
0 0.25 0.25 3 2.86e-05
1 0.75 0.75 -2
"""


def test_zero_based_files(tmp_path):
    (tmp_path / "z.node").write_text(NODE0)
    nd = tio.read_node(tmp_path / "z.node")
    assert nd.first_index == 0
    assert nd.vertices.tolist() == [[0, 0], [1, 0], [1, 1], [0, 1]]
    assert math.copysign(1, nd.vertices[0, 1]) == -1
    assert nd.attributes[:, 0].tolist() == [7.5, -1e-3, 0.0, 2.86e-05]
    assert nd.markers.tolist() == [1, 0, 0, 2]
    (tmp_path / "z.poly").write_text(POLY0)
    pd = tio.read_poly(tmp_path / "z.poly")
    assert pd.segments.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    assert pd.segment_markers.tolist() == [5, 5, 6, 6]
    assert pd.holes.tolist() == [[0.5, 0.5]]
    # exponents kept (Triangle's -a switch bug turned 2.86e-05 into 2.86)
    assert pd.regions[0].tolist() == [0.25, 0.25, 3.0, 2.86e-05]
    assert pd.regions[1].tolist() == [0.75, 0.75, -2.0, -2.0]


def test_one_based_equals_zero_based(tmp_path):
    one = "\n".join(
        " ".join([str(int(t[0]) + 1)] + t[1:]) if t and t[0].isdigit() and i in range(3, 9)
        else line
        for i, line in enumerate(NODE0.splitlines()) for t in [line.split()])
    (tmp_path / "o.node").write_text(one)
    (tmp_path / "z.node").write_text(NODE0)
    a, b = tio.read_node(tmp_path / "o.node"), tio.read_node(tmp_path / "z.node")
    assert a.first_index == 1 and b.first_index == 0
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.attributes, b.attributes)


def test_poly_with_zero_vertices_reads_node(tmp_path):
    (tmp_path / "shape.node").write_text(NODE0)
    (tmp_path / "shape.poly").write_text(
        "0 2 0 0\n2 0\n1 0 2\n2 1 3\n0\n")
    pd = tio.read_poly(tmp_path / "shape.poly")
    assert pd.vertices.shape == (4, 2) and pd.first_index == 0
    assert pd.segments.tolist() == [[0, 2], [1, 3]]
    assert pd.node_path == tmp_path / "shape.node"
    assert pd.holes.shape == (0, 2) and pd.regions.shape == (0, 4)
    (tmp_path / "orphan.poly").write_text("0 2 0 0\n0 0\n0\n")
    with pytest.raises(FileFormatError, match="orphan.node"):
        tio.read_poly(tmp_path / "orphan.poly")


def test_missing_attributes_and_markers_default_to_zero(tmp_path):
    p = tmp_path / "lenient.node"
    p.write_text("3 2 2 1\n1 0 0\n2 1 0 5\n3 0 1 5 6 7 99 extra\n")
    nd = tio.read_node(p)
    assert nd.attributes.tolist() == [[0, 0], [5, 0], [5, 6]]
    assert nd.markers.tolist() == [0, 0, 7]


# ----------------------------------------------------------------------------------------
# round trips
# ----------------------------------------------------------------------------------------

AWKWARD = np.array([[0.0, -0.0], [1e-300, 5e-324], [2.86e-05, 1 / 3], [1e308, -1e308],
                    [0.1, 0.2], [-123456789.123456789, 2.0 ** 52 + 1]])


def test_node_roundtrip(tmp_path):
    attrs = np.array([[1.5, -2], [0, 0], [1e-9, 3], [7, 7], [0.1, 0.3], [1, 2]])
    marks = np.array([0, 1, 2, 3, 4, -5])
    p = tmp_path / "rt.node"
    tio.write_node(p, AWKWARD, attrs, marks)
    nd = tio.read_node(p)
    assert nd.first_index == tio.WRITE_FIRST_INDEX == 1
    np.testing.assert_array_equal(nd.vertices, AWKWARD)
    assert np.signbit(nd.vertices[0, 1])
    np.testing.assert_array_equal(nd.attributes, attrs)
    np.testing.assert_array_equal(nd.markers, marks)
    tio.write_node(p, AWKWARD)
    nd = tio.read_node(p)
    assert nd.attributes.shape == (6, 0) and nd.markers is None


def test_poly_roundtrip(tmp_path):
    segs = np.array([[0, 1], [1, 2], [2, 5], [5, 0]])
    holes = np.array([[0.5, 0.25]])
    regions = np.array([[0.1, 0.1, 1.0, 2.86e-05], [0.2, 0.2, 2.0, np.nan]])
    p = tmp_path / "rt.poly"
    tio.write_poly(p, AWKWARD, segs, holes=holes, regions=regions,
                   segment_markers=[1, 2, 3, 4])
    pd = tio.read_poly(p)
    np.testing.assert_array_equal(pd.vertices, AWKWARD)
    np.testing.assert_array_equal(pd.segments, segs)
    assert pd.segment_markers.tolist() == [1, 2, 3, 4]
    np.testing.assert_array_equal(pd.holes, holes)
    assert pd.regions[0].tolist() == [0.1, 0.1, 1.0, 2.86e-05]
    assert pd.regions[1].tolist() == [0.2, 0.2, 2.0, -1.0]     # NaN: "no constraint"
    tio.write_poly(p, AWKWARD, np.zeros((0, 2), np.int64))
    pd = tio.read_poly(p)
    assert pd.segments.shape == (0, 2) and pd.holes.shape == (0, 2)
    assert pd.regions.shape == (0, 4)


@needs_corpus
@pytest.mark.parametrize("fname", ["A.poly", "la.poly", "box.poly", "square_circle_hole.poly"])
def test_corpus_poly_roundtrip(tmp_path, fname):
    a = tio.read_poly(CORPUS / "triangle" / fname)
    tio.write_poly(tmp_path / fname, a.vertices, a.segments, holes=a.holes,
                   regions=a.regions if len(a.regions) else None,
                   segment_markers=a.segment_markers, attributes=a.attributes,
                   markers=a.markers)
    b = tio.read_poly(tmp_path / fname)
    for name in ("vertices", "attributes", "segments", "holes", "regions"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    for name in ("markers", "segment_markers"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None and y is None) or np.array_equal(x, y)


def test_ele_edge_neigh_roundtrip(tmp_path):
    tris = np.array([[0, 1, 2], [0, 2, 3], [3, 2, 4]])
    tio.write_ele(tmp_path / "m.ele", tris, attributes=[1.0, 2.0, 3.5])
    e = tio.read_ele(tmp_path / "m.ele")
    np.testing.assert_array_equal(e.triangles, tris)
    assert e.attributes[:, 0].tolist() == [1.0, 2.0, 3.5] and e.first_index == 1
    assert tio.read_ele(tmp_path / "m.ele", n_vertices=5).triangles.shape == (3, 3)
    with pytest.raises(FileFormatError, match="corner 3 of triangle 3 is 5, out of range"):
        tio.read_ele(tmp_path / "m.ele", n_vertices=4)
    edges = np.array([[0, 1], [1, 2], [2, 0]])
    tio.write_edge(tmp_path / "m.edge", edges, markers=[1, 0, 1])
    ed = tio.read_edge(tmp_path / "m.edge")
    np.testing.assert_array_equal(ed.edges, edges)
    assert ed.markers.tolist() == [1, 0, 1]
    nb = np.array([[-1, 1, -1], [2, -1, 0], [-1, -1, 1]])
    tio.write_neigh(tmp_path / "m.neigh", nb)
    np.testing.assert_array_equal(tio.read_neigh(tmp_path / "m.neigh"), nb)


def test_zero_based_ele_edge_neigh(tmp_path):
    (tmp_path / "z.ele").write_text("2 3 0\n0 0 1 2\n1 0 2 3\n")
    assert tio.read_ele(tmp_path / "z.ele").triangles.tolist() == [[0, 1, 2], [0, 2, 3]]
    (tmp_path / "z.edge").write_text("1 0\n0 3 0\n")
    assert tio.read_edge(tmp_path / "z.edge").edges.tolist() == [[3, 0]]
    (tmp_path / "z.neigh").write_text("2 3\n0 -1 1 -1\n1 0 -1 -1\n")
    assert tio.read_neigh(tmp_path / "z.neigh").tolist() == [[-1, 1, -1], [0, -1, -1]]


def test_writer_rejects_bad_arrays(tmp_path):
    with pytest.raises(InputShapeError):
        tio.write_node(tmp_path / "x.node", np.zeros((3, 3)))
    with pytest.raises(NonFiniteCoordinateError):
        tio.write_node(tmp_path / "x.node", [[0.0, np.nan]])
    with pytest.raises(InputShapeError, match="segments row 0"):
        tio.write_poly(tmp_path / "x.poly", np.zeros((3, 2)), [[0, 3]])
    with pytest.raises(InputShapeError):
        tio.write_neigh(tmp_path / "x.neigh", [[0, 5, -1]])


# ----------------------------------------------------------------------------------------
# malformed files
# ----------------------------------------------------------------------------------------

BAD = [
    # (file name, content, regex the message must match)
    ("spiral.node", "# c\n3 2 0 0\n1 0 0\n2 1\n3 0 1\n",
     r"^spiral.node line 4: expected 3 numbers \(index x y\), got 2$"),
    ("num.node", "3 2 0 0\n1 0 0\n2 1 zero\n3 0 1\n",
     r"num.node line 3: expected a number for y of vertex 2, got 'zero'"),
    ("short.node", "3 2 0 0\n1 0 0\n2 1 0\n",
     r"short.node: unexpected end of file: .*declares 3 vertices, found 2"),
    ("base.node", "2 2 0 0\n2 0 0\n3 1 0\n",
     r"base.node line 2: the first vertex must be numbered 0 or 1, got 2"),
    ("seq.node", "3 2 0 0\n1 0 0\n2 1 0\n4 0 1\n",
     r"seq.node line 4: vertex number 4 out of sequence \(expected 3\)"),
    ("dim.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n",
     r"dim.node line 1: dimension must be 2, got 3"),
    ("extra.node", "1 2 0 0\n1 0 0\n2 1 0\n", r"extra.node line 3: unexpected extra record"),
    ("nan.node", "1 2 0 0\n1 nan 0\n", r"nan.node line 2: x of vertex 1 is not finite"),
    ("under.node", "1 2 0 0\n1 1_000 0\n", r"under.node line 2: expected a number"),
    ("marks.node", "1 2 0 2\n1 0 0 0\n", r"marks.node line 1: number of boundary markers must be 0 or 1"),
    ("neg.node", "-1 2 0 0\n", r"neg.node line 1: number of vertices must be >= 0"),
    ("empty.node", "# nothing\n\n", r"empty.node: unexpected end of file: expected the node header"),
    ("hdr.node", "three 2 0 0\n", r"hdr.node line 1: expected an integer for number of vertices"),
    ("seg.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 3 4\n0\n",
     r"seg.poly line 7: segment 2's second endpoint is 4, out of range: vertices are numbered 1..3"),
    ("seg0.poly", "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n0 3 0\n0\n",
     r"seg0.poly line 6: segment 0's first endpoint is 3, out of range: vertices are numbered 0..2"),
    ("segfew.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 1\n0\n",
     r"segfew.poly line 6: expected 3 numbers \(index endpoint endpoint\), got 2"),
    ("segtrunc.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n",
     r"segtrunc.poly: unexpected end of file: 2 segments declared, found 1"),
    ("nosegs.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n",
     r"nosegs.poly: unexpected end of file: expected the segment header"),
    ("hole.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n1\n1 0.5\n",
     r"hole.poly line 7: expected 3 numbers \(index x y\), got 2"),
    ("region.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n1\n1 0.5 0.5\n",
     r"region.poly line 8: expected 4 numbers \(index x y attribute \[max_area\]\), got 3"),
    ("after.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n0\n7\n",
     r"after.poly line 8: unexpected extra record '7' after the regions section"),
    ("tri.ele", "1 3 0\n1 1 2\n", r"tri.ele line 2: expected 4 numbers \(index n1 n2 n3\), got 3"),
    ("nodes.ele", "1 4 0\n1 1 2 3 4\n", r"nodes.ele line 1: nodes per triangle must be 3 or 6"),
    ("zero.ele", "1 3 0\n1 0 1 2\n", r"zero.ele line 2: corner 1 of triangle 1 is 0, out of range"),
    ("e.edge", "1 0\n1 1\n", r"e.edge line 2: expected 3 numbers"),
    ("n.neigh", "2 3\n1 -1 2 3\n2 1 -1 -1\n",
     r"n.neigh line 2: neighbour 3 of triangle 1 is 3, out of range: triangles are numbered 1..2"),
]


@pytest.mark.parametrize("fname,content,pattern", BAD, ids=[b[0] for b in BAD])
def test_malformed_files(tmp_path, fname, content, pattern):
    p = tmp_path / fname
    p.write_text(content)
    reader = {".node": tio.read_node, ".poly": tio.read_poly, ".ele": tio.read_ele,
              ".edge": tio.read_edge, ".neigh": tio.read_neigh}[p.suffix]
    with pytest.raises(FileFormatError, match=pattern) as info:
        reader(p)
    assert isinstance(info.value, CDTError) and isinstance(info.value, ValueError)
    assert info.value.path == p


def test_missing_file(tmp_path):
    with pytest.raises(FileFormatError, match="cannot read"):
        tio.read_node(tmp_path / "nope.node")


def test_error_carries_line_number(tmp_path):
    p = tmp_path / "spiral.node"
    p.write_text("# c\n3 2 0 0\n1 0 0\n2 1\n3 0 1\n")
    with pytest.raises(FileFormatError) as info:
        tio.read_node(p)
    assert info.value.line == 4


# ------------------------------------------------- PolyData -> triangulate, Triangulation -> files (#17)
@needs_corpus
@pytest.mark.parametrize("fname", ["A.poly", "face.poly", "square_circle_hole.poly", "la.poly"])
def test_read_poly_output_triangulates(fname):
    """``triangulate(read_poly(f).to_plc())``: the file's vertices, segments, hole
    points and region seeds all reach the engine, as Triangle reads them."""
    pd = tio.read_poly(CORPUS / "triangle" / fname)
    with pytest.raises(InputShapeError):
        cdt_plugin.triangulate(pd)                         # the file's data, not a PLC
    tri = cdt_plugin.triangulate(pd.to_plc())
    same = cdt_plugin.triangulate(pd.vertices, pd.segments, holes=pd.holes,
                                  regions=pd.regions if len(pd.regions) else None)
    assert np.array_equal(tri.triangles, same.triangles) and np.array_equal(tri.vertices, same.vertices)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    if fname == "la.poly":                                # its regions bound the areas
        assert len(tri.steiner) and tri.region_attributes is not None


def test_region_max_area_bounds_its_region(tmp_path):
    """The README's two squares: a region seed's max_area refines its region alone."""
    V = [[0, 0], [4, 0], [4, 4], [0, 4], [2, 0], [2, 4]]
    S = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    path = tmp_path / "two.poly"
    tio.write_poly(path, V, S, regions=[[1, 2, 7, 0.05], [3, 2, 8, 1.0]])
    tri = cdt_plugin.triangulate(tio.read_poly(path).to_plc())
    P = tri.vertices[tri.triangles]
    area = 0.5 * np.abs((P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1])
                        - (P[:, 1, 1] - P[:, 0, 1]) * (P[:, 2, 0] - P[:, 0, 0]))
    left, right = tri.region_attributes == 7, tri.region_attributes == 8
    assert left.sum() + right.sum() == len(tri.triangles)
    assert area[left].max() <= 0.05 and area[left].sum() == pytest.approx(8.0)
    assert area[right].max() <= 1.0 and area[right].sum() == pytest.approx(8.0)
    assert left.sum() > 10 * right.sum()                  # the left square is much finer
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def test_writers_take_a_triangulation(tmp_path):
    sq = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]]
    rings = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    tri = cdt_plugin.triangulate(sq, rings, min_angle=25)
    tio.write_node(tmp_path / "t.node", tri)
    tio.write_ele(tmp_path / "t.ele", tri)
    tio.write_poly(tmp_path / "t.poly", tri)
    tio.write_edge(tmp_path / "t.edge", tri)
    tio.write_neigh(tmp_path / "t.neigh", tri)
    V = tio.read_node(tmp_path / "t.node").vertices
    T = tio.read_ele(tmp_path / "t.ele").triangles
    poly = tio.read_poly(tmp_path / "t.poly")
    assert np.array_equal(V, tri.vertices) and np.array_equal(T, tri.triangles)
    assert np.array_equal(poly.vertices, tri.vertices) and np.array_equal(poly.segments, tri.segments)
    assert np.array_equal(tio.read_edge(tmp_path / "t.edge").edges, tri.edges)
    assert np.array_equal(tio.read_neigh(tmp_path / "t.neigh"), tri.neighbors)
    assert_valid(V, T, segments=poly.segments, domain="segments")
    paths = tio.write_triangulation(tmp_path / "all.ele", tri, attributes=np.arange(len(T)))
    assert [p.name for p in paths] == ["all.node", "all.ele", "all.poly"]
    ele = tio.read_ele(paths[1])
    assert np.array_equal(ele.triangles, T) and ele.attributes[:, 0].tolist() == list(range(len(T)))
    assert np.array_equal(tio.read_poly(paths[2]).segments, tri.segments)
    with pytest.raises(InputShapeError, match="needs segments"):
        tio.write_poly(tmp_path / "x.poly", tri.vertices)
