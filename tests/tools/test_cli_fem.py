"""``cdt-plugin mesh ... -o mesh.msh | .vtu | .xdmf``: finite-element files through meshio,
tagged by the input's markers, read back with the same cells and tags as the Python
API's triangulation of the same input."""
from __future__ import annotations

import contextlib
import io
import json
from collections import Counter

import numpy as np
import pytest
from checker import assert_valid

import cdt_plugin
import cdt_plugin.cli as cli
from cdt_plugin import io as tio
from cdt_plugin.fem import gmsh_physical

meshio = pytest.importorskip("meshio")

V = [[0, 0], [2, 0], [2, 2], [0, 2], [0.8, 0.8], [1.2, 0.8], [1.2, 1.2], [0.8, 1.2]]
S = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
MARKS = [3, 4, 3, 4, 7, 7, 7, 7]


def mesh_command(*argv):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert cli.main(["mesh", *map(str, argv)]) == 0
    return out.getvalue()


def tagged(points, mesh, kind):
    """Counter of (cell as a set of node coordinates, physical tag) over ``kind`` cells."""
    P = np.asarray(points)[:, :2]
    return Counter((frozenset(map(tuple, P[c].tolist())), int(t))
                   for b, tags in zip(mesh.cells, mesh.cell_data["gmsh:physical"]) if b.type == kind
                   for c, t in zip(b.data, tags))


@pytest.fixture
def poly(tmp_path):
    path = tmp_path / "plate.poly"
    tio.write_poly(path, V, S, holes=[[1, 1]], segment_markers=MARKS)
    return path


def reference(**options):
    tri = cdt_plugin.triangulate(V, S, holes=[[1, 1]], segment_markers=MARKS, **options)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    lines = Counter((frozenset(map(tuple, tri.vertices[s].tolist())), int(m))
                    for s, m in zip(tri.segments, tri.segment_markers))
    triangles = Counter((frozenset(map(tuple, tri.vertices[t].tolist())), int(p))
                        for t, p in zip(tri.triangles, gmsh_physical(tri)))
    return tri, lines, triangles


@pytest.mark.parametrize("suffix", [".msh", ".vtu", ".xdmf"])
def test_mesh_writes_tagged_files(poly, tmp_path, suffix):
    if suffix == ".xdmf":
        pytest.importorskip("h5py")
    out = tmp_path / f"plate{suffix}"
    printed = mesh_command(poly, "-o", out, "--max-area", "0.05", "--min-angle", "25")
    tri, lines, triangles = reference(max_area=0.05, min_angle=25)
    assert f"wrote {out}" in printed and f"{len(tri.triangles):,} triangles" in printed
    back = meshio.read(out)
    assert tagged(back.points, back, "line") == lines
    assert tagged(back.points, back, "triangle") == triangles
    assert {m for (_, m) in lines} == {3, 4, 7}          # the .poly file's markers
    if suffix == ".msh":
        assert "(gmsh 4.1)" in printed
        assert set(back.cell_data) == {"gmsh:physical", "gmsh:geometrical"}   # tags only
    else:
        assert "region" in back.cell_data and "vertex_markers" in back.point_data


def test_mesh_msh_falls_back_to_gmsh22(tmp_path):
    # four differently marked sides of a square in two triangles: gmsh 4.1 as meshio
    # writes it needs a node for each of five entities; 2.2 tags every element
    path = tmp_path / "square.poly"
    tio.write_poly(path, V[:4], S[:4], segment_markers=[1, 2, 3, 4])
    out = tmp_path / "square.msh"
    printed = mesh_command(path, "-o", out)
    assert "(gmsh 2.2)" in printed
    assert out.read_text().startswith("$MeshFormat\n2.2")
    back = meshio.read(out)
    lines = np.concatenate([t for b, t in zip(back.cells, back.cell_data["gmsh:physical"])
                            if b.type == "line"])
    assert sorted(lines.tolist()) == [1, 2, 3, 4]


def test_mesh_of_features_tags_each_feature(tmp_path):
    shapely = pytest.importorskip("shapely")  # noqa: F841  (GeoJSON polygons are validated)
    src = tmp_path / "two.geojson"
    squares = [[[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]], [[[2, 0], [3, 0], [3, 1], [2, 1], [2, 0]]]]
    src.write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": c}}
        for c in squares]}))
    out = tmp_path / "two.vtu"
    mesh_command(src, "-o", out)
    back = meshio.read(out)
    tri = next(b for b in back.cells if b.type == "triangle").data
    k = [b.type for b in back.cells].index("triangle")
    physical = back.cell_data["gmsh:physical"][k]
    x = back.points[tri][:, :, 0].mean(axis=1)
    assert np.array_equal(physical, np.where(x < 1.5, 1, 2))      # feature 0 -> 1, 1 -> 2


def test_unknown_output_lists_the_fem_formats(poly, tmp_path):
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = cli.main(["mesh", str(poly), "-o", str(tmp_path / "x.unv")])
    assert status != 0 and ".msh" in err.getvalue() and ".xdmf" in err.getvalue()
