"""``cdt-plugin triangle``: Triangle's own command line. The files it writes are read
back with :mod:`cdt_plugin.io` and compared with what the ``triangle`` package gives
for the same input and switches (its core also returns the Voronoi output of ``v``);
every mesh is checked with the exact checker."""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

import cdt_plugin.cli as cli
from cdt_plugin import io as tio
from checker import assert_valid, canonical_triangles
from corpus import corpus_dir

triangle = pytest.importorskip("triangle")
CORPUS = corpus_dir() / "triangle"
pytestmark = pytest.mark.skipif(not CORPUS.exists(), reason="corpus not found")


def _copy(tmp_path: Path, name: str, *exts: str) -> Path:
    for ext in exts:
        shutil.copy(CORPUS / f"{name}{ext}", tmp_path / f"{name}{ext}")
    return tmp_path / name


def _run(capsys, *argv) -> tuple[int, str, str]:
    code = cli.main(["triangle", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def _package(base: Path, switches: str) -> dict:
    """The ``triangle`` package's mesh of the same input (its files read by itself)."""
    return triangle.triangulate(triangle.load(str(base.parent), base.name), switches)


def _min_angle(V, T) -> float:
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    out = np.inf
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = q - p, r - p
        cos = (u * v).sum(1) / np.sqrt((u * u).sum(1) * (v * v).sum(1))
        out = min(out, np.degrees(np.arccos(np.clip(cos, -1, 1))).min())
    return out


def test_p_writes_what_triangle_writes_with_the_same_triangles(tmp_path, capsys):
    base = _copy(tmp_path, "A", ".poly")
    code, out, err = _run(capsys, "-p", base.with_suffix(".poly"))
    assert code == 0, err
    assert f"Writing {base}.1.node." in out and f"Writing {base}.1.ele." in out
    node, ele = tio.read_node(f"{base}.1.node"), tio.read_ele(f"{base}.1.ele")
    poly = tio.read_poly(f"{base}.1.poly")
    assert node.first_index == 1 and node.markers is not None and node.attributes.shape[1] == 1
    theirs = _package(base, "p")
    assert canonical_triangles(node.vertices, ele.triangles) == \
        canonical_triangles(theirs["vertices"], theirs["triangles"])
    ours_marks = {tuple(v): int(m) for v, m in zip(node.vertices, node.markers)}
    their_marks = {tuple(v): int(m) for v, m in zip(theirs["vertices"], theirs["vertex_markers"][:, 0])}
    assert ours_marks == their_marks
    assert len(poly.segments) == len(theirs["segments"])
    assert_valid(node.vertices, ele.triangles, segments=poly.segments, domain="segments")


def test_quality_switches_and_numbering_from_zero(tmp_path, capsys):
    base = _copy(tmp_path, "A", ".poly")
    code, out, err = _run(capsys, "-pq30a0.05zen", base)
    assert code == 0, err
    node = tio.read_node(f"{base}.1.node")
    ele = tio.read_ele(f"{base}.1.ele")
    assert node.first_index == 0 and ele.first_index == 0
    areas = np.abs(np.cross(node.vertices[ele.triangles[:, 1]] - node.vertices[ele.triangles[:, 0]],
                            node.vertices[ele.triangles[:, 2]] - node.vertices[ele.triangles[:, 0]])) / 2
    assert areas.max() <= 0.05
    assert _min_angle(node.vertices, ele.triangles) >= 30      # (A has no small input angle)
    T = ele.triangles
    mesh_edges = {tuple(sorted(e)) for e in np.vstack([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])}
    edges = tio.read_edge(f"{base}.1.edge")
    assert {tuple(sorted(e)) for e in edges.edges} == mesh_edges
    assert edges.markers is not None and set(np.unique(edges.markers)) <= {0, 1}
    neigh = tio.read_neigh(f"{base}.1.neigh")
    assert neigh.shape == (len(T), 3)
    poly = tio.read_poly(f"{base}.1.poly")
    assert_valid(node.vertices, T, segments=poly.segments, domain="segments")


def test_output_switches_leave_out_files_and_markers(tmp_path, capsys):
    base = _copy(tmp_path, "A", ".poly")
    code, out, err = _run(capsys, "-pNEQ", base)
    assert code == 0 and out == "", err
    assert not list(tmp_path.glob("A.1.node")) and not list(tmp_path.glob("A.1.ele"))
    assert (tmp_path / "A.1.poly").exists()
    (tmp_path / "A.1.poly").unlink()
    code, out, err = _run(capsys, "-pPBeQ", base)
    assert code == 0, err
    assert not (tmp_path / "A.1.poly").exists()
    assert tio.read_node(f"{base}.1.node").markers is None
    assert tio.read_edge(f"{base}.1.edge").markers is None


def test_iteration_numbers(tmp_path, capsys):
    base = _copy(tmp_path, "A", ".poly")
    assert _run(capsys, "-pQ", base)[0] == 0
    assert _run(capsys, "-rq25Q", f"{base}.1")[0] == 0
    assert (tmp_path / "A.2.node").exists() and (tmp_path / "A.2.ele").exists()
    first = tio.read_node(tmp_path / "A.1.node").vertices
    second = tio.read_node(tmp_path / "A.2.node").vertices
    assert {tuple(v) for v in first} <= {tuple(v) for v in second}     # -r keeps every vertex
    other = tmp_path / "B"
    shutil.copy(base.with_suffix(".poly"), other.with_suffix(".poly"))
    assert _run(capsys, "-pIQ", other)[0] == 0
    assert (tmp_path / "B.node").exists() and (tmp_path / "B.ele").exists()


def test_voronoi_and_geomview_files(tmp_path, capsys):
    base = _copy(tmp_path, "A", ".poly")
    code, out, err = _run(capsys, "-pcvgQ", base)
    assert code == 0, err
    node = tio.read_node(f"{base}.1.node")
    ele = tio.read_ele(f"{base}.1.ele")
    vnode = tio.read_node(f"{base}.1.v.node")
    assert len(vnode.vertices) == len(ele.triangles)
    data = triangle.load(str(tmp_path), "A")
    from triangle.core import triang
    _, vorout = triang({"pointlist": data["vertices"], "segmentlist": data["segments"],
                                 "holelist": data["holes"]}, "Qzpcv")
    edge_lines = [l.split() for l in (tmp_path / "A.1.v.edge").read_text().splitlines()
                  if l.strip() and not l.startswith("#")]
    assert int(edge_lines[0][0]) == len(vorout["edgelist"])
    rays = [l for l in edge_lines[1:] if l[2] == "-1"]
    assert len(rays) == int((vorout["edgelist"][:, 1] == -1).sum())
    off = (tmp_path / "A.1.off").read_text().split()
    assert off[0] == "OFF" and int(off[1]) == len(node.vertices) and int(off[2]) == len(ele.triangles)


def test_reads_node_files_without_p_as_points(tmp_path, capsys):
    base = _copy(tmp_path, "double_hex3", ".node")
    code, out, err = _run(capsys, "-Q", base.with_suffix(".node"))
    assert code == 0, err
    node = tio.read_node(f"{base}.1.node")
    ele = tio.read_ele(f"{base}.1.ele")
    theirs = triangle.triangulate({"vertices": node.vertices[: len(tio.read_node(base.with_suffix('.node')).vertices)]}, "")
    assert len(ele.triangles) == len(theirs["triangles"])
    assert_valid(node.vertices, ele.triangles)


def test_errors_are_one_line(tmp_path, capsys):
    code, out, err = _run(capsys, "-p", tmp_path / "missing.poly")
    assert code == 1 and "missing.poly" in err and "Traceback" not in err
    base = _copy(tmp_path, "A", ".poly")
    code, out, err = _run(capsys, "-pa1e-3", base)
    assert code == 1 and "exponent" in err
    code, out, err = _run(capsys, "-h", base)
    assert code == 0 and "Triangle" in out
