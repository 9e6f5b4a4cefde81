"""The ``cdt-plugin`` command line: run as a subprocess on corpus files, the
outputs loaded back with trimesh, shapely and cdt_plugin.io; errors are one line
on stderr with exit status 1, never a traceback. The quicker checks call
``main()`` in-process."""
from __future__ import annotations

import doctest
import inspect
import json
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import cdt_plugin
import cdt_plugin.cli as cli
from cdt_plugin import io as tio
from cdt_plugin.report import triangle_quality
from corpus import corpus_dir

ROOT = Path(__file__).resolve().parents[2]
CORPUS = corpus_dir()
needs_corpus = pytest.mark.skipif(not CORPUS.exists(), reason="corpus not found")
has_refinement = "min_angle" in inspect.signature(cdt_plugin.triangulate).parameters


def run(*args, check=True):
    """``python -m cdt_plugin ARGS`` in a fresh process."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "cdt_plugin", *map(str, args)], capture_output=True,
                          text=True, env=env, timeout=600)
    assert "Traceback" not in proc.stderr, proc.stderr
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def test_docstring_examples():
    results = [doctest.testmod(module) for module in (cli, cli.meshing, cli.terminal)]
    assert sum(r.attempted for r in results) >= 3 and not any(r.failed for r in results)


def test_console_script_is_registered():
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["cdt-plugin"] == "cdt_plugin.cli:main"
    exe = shutil.which("cdt-plugin")
    if exe is not None:       # installed (pip install -e .): the script runs main()
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=120)
        assert out.returncode == 0 and out.stdout.strip() == f"cdt-plugin {cdt_plugin.__version__}"


def test_help_shows_examples():
    proc = run("--help")
    assert "examples:" in proc.stdout and "cdt-plugin mesh" in proc.stdout
    assert "cdt-plugin report polygon.json --against earcut" in proc.stdout


# ------------------------------------------------- subprocess, corpus files
@needs_corpus
def test_mesh_poly_to_ply(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    src = CORPUS / "triangle" / "A.poly"
    out = tmp_path / "A.ply"
    proc = run("mesh", src, "-o", out, "--report")
    pd = tio.read_poly(src)
    tri = cdt_plugin.triangulate(pd.vertices, pd.segments, holes=pd.holes)
    assert proc.stdout.splitlines()[0] == f"wrote {out}: 29 vertices, 29 triangles"
    assert "non-Delaunay non-segment edges" in proc.stdout
    mesh = trimesh.load(out, process=False)
    assert len(mesh.faces) == len(tri.triangles) == 29          # Triangle's -p count
    assert np.allclose(mesh.vertices[:, 2], 0.0)
    assert mesh.area == pytest.approx(_areas(tri.vertices, tri.triangles).sum(), rel=1e-6)   # float32 PLY
    assert (mesh.face_normals[:, 2] > 0).all()                 # counter-clockwise seen from +z


def _areas(V, T):
    P = np.asarray(V)[np.asarray(T)]
    return 0.5 * np.abs((P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1])
                        - (P[:, 1, 1] - P[:, 0, 1]) * (P[:, 2, 0] - P[:, 0, 0]))


@needs_corpus
def test_mesh_feature_collection_to_geojson_layer_with_progress_bar(tmp_path):
    shapely = pytest.importorskip("shapely")
    gpd = pytest.importorskip("geopandas")
    pytest.importorskip("tqdm")
    src = CORPUS / "gis" / "naturalearth_lowres.geojson"
    out = tmp_path / "countries.geojson"
    proc = run("mesh", src, "-o", out, "--progress")
    assert "177/177" in proc.stderr and "meshing" in proc.stderr
    assert "reading: 100%" in proc.stderr and "writing: 100%" in proc.stderr
    assert "9791/9791" in proc.stderr
    assert "cdt-plugin: warning: the layer's CRS (WGS 84) is geographic" in proc.stderr
    assert proc.stdout.strip() == f"wrote {out}: 177 feature(s), 9,791 triangles"
    written = gpd.read_file(out)                       # a layer: one Polygon per triangle
    given = json.loads(src.read_text())["features"]
    assert len(written) == 9791 and (written.geom_type == "Polygon").all()
    assert written["feature"].tolist() == written["position"].tolist()
    parts = written.geometry.to_numpy()
    assert shapely.is_ccw(shapely.get_exterior_ring(parts)).all()
    for i, g in enumerate(given):
        mine = (written["position"] == i).to_numpy()
        polygon = shapely.geometry.shape(g["geometry"])
        assert (written["name"][mine] == g["properties"]["name"]).all()
        assert shapely.area(parts[mine]).sum() == pytest.approx(polygon.area, rel=1e-9)
        assert shapely.union_all(parts[mine]).symmetric_difference(polygon).area <= 1e-9 * polygon.area


@needs_corpus
def test_geojson_output_of_a_polygon_file_is_one_collection_per_feature(tmp_path, capsys):
    pytest.importorskip("shapely")
    out = tmp_path / "dude.geojson"
    assert cli.main(["mesh", str(CORPUS / "earcut" / "dude.json"), "-o", str(out)]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {out}: 1 feature(s), 106 triangles"
    written = json.loads(out.read_text())["features"]
    assert len(written) == 1 and written[0]["geometry"]["type"] == "GeometryCollection"
    assert written[0]["properties"]["triangles"] == 106 == len(written[0]["geometry"]["geometries"])


@needs_corpus
def test_mesh_wkt_extruded_to_stl(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    shapely = pytest.importorskip("shapely")
    rings = json.loads((CORPUS / "earcut" / "dude.json").read_text())
    polygon = shapely.Polygon(rings[0], rings[1:])
    assert polygon.is_valid
    src = tmp_path / "dude.wkt"
    src.write_text(polygon.wkt)
    out = tmp_path / "dude.stl"
    run("mesh", src, "-o", out, "--extrude", 2.5)
    solid = trimesh.load(out)                 # STL: float32, vertices merged on load
    assert solid.is_watertight and solid.is_winding_consistent
    assert solid.volume == pytest.approx(polygon.area * 2.5, rel=1e-5)


@needs_corpus
def test_report_against_earcut_as_json():
    proc = run("report", CORPUS / "earcut" / "dude.json", "--against", "earcut", "--json")
    rep = json.loads(proc.stdout)
    theirs = rep["against"]
    assert theirs["name"] == "earcut" and theirs["triangles"] == rep["triangles"]
    assert rep["comparison"]["theorem_applies"] is True
    assert rep["min_angle"] >= theirs["min_angle"]
    assert rep["max_circumradius"] <= theirs["max_circumradius"]
    assert rep["max_min_containment_radius"] <= theirs["max_min_containment_radius"]
    assert rep["non_delaunay_edges"] == 0 < theirs["non_delaunay_edges"]


def test_error_is_one_line_without_traceback(tmp_path):
    proc = run("mesh", tmp_path / "missing.poly", "-o", tmp_path / "x.ply", check=False)
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.splitlines() == [f"cdt-plugin: error: {tmp_path / 'missing.poly'}: no such file"]


# ------------------------------------------------------------- in-process
@needs_corpus
def test_mesh_to_triangle_files_round_trip(tmp_path, capsys):
    src = CORPUS / "triangle" / "A.poly"
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "A.ele")]) == 0
    assert capsys.readouterr().out.startswith(f"wrote {tmp_path / 'A'}.node/.ele/.poly: 29 vertices")
    pd = tio.read_poly(src)
    tri = cdt_plugin.triangulate(pd.vertices, pd.segments, holes=pd.holes)
    node = tio.read_node(tmp_path / "A.node")
    assert np.array_equal(node.vertices, tri.vertices)                # bit for bit
    assert np.array_equal(tio.read_ele(tmp_path / "A.ele").triangles, tri.triangles)
    poly = tio.read_poly(tmp_path / "A.poly")
    assert np.array_equal(poly.segments, tri.segments)


@needs_corpus
def test_report_against_a_mesh_file(tmp_path, capsys):
    pytest.importorskip("trimesh")
    src = CORPUS / "triangle" / "A.poly"
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "A.obj")]) == 0
    assert cli.main(["report", str(src), "--against", str(tmp_path / "A.obj"), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out.split("\n", 1)[1])
    assert rep["against"]["name"] == "A.obj"
    assert rep["comparison"]["same_vertices"] is True          # OBJ keeps the coordinates
    for key in ("triangles", "min_angle", "max_circumradius", "max_min_containment_radius",
                "non_delaunay_edges", "cocircular_edges"):
        assert rep["against"][key] == rep[key], key


def test_multi_feature_mesh_and_plot(tmp_path, capsys):
    pytest.importorskip("shapely")
    pytest.importorskip("matplotlib")
    features = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "a"},
         "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]],
                                                         [[1, 1], [1, 3], [3, 3], [3, 1], [1, 1]]]}},
        {"type": "Feature", "properties": {"name": "empty"}, "geometry": None},
        {"type": "Feature", "properties": {"name": "b"},
         "geometry": {"type": "Polygon", "coordinates": [[[5, 0], [6, 0], [5, 1], [5, 0]]]}}]}
    src = tmp_path / "two.geojson"
    src.write_text(json.dumps(features))
    png = tmp_path / "two.png"
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "two.node"), "--plot", str(png),
                     "--report", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "2 feature" not in out and "9 triangles" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    ele = tio.read_ele(tmp_path / "two.ele")
    assert ele.attributes[:, 0].tolist() == [0.0] * 8 + [1.0]        # feature of each triangle
    nodes = tio.read_node(tmp_path / "two.node").vertices
    assert nodes.shape == (11, 2) and nodes[ele.triangles[-1]].tolist() == [[5, 0], [6, 0], [5, 1]]


def test_concatenate_offsets_everything():
    a = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]],
                               [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    b = cdt_plugin.triangulate([[10, 0], [11, 0], [10, 1], [10, 0]], [[0, 1], [1, 2], [2, 0]])
    both = cli.concatenate([a, b])
    assert np.array_equal(both.triangles, np.vstack([a.triangles, b.triangles + 8]))
    assert both.neighbors[-1].tolist() == [-1, -1, -1]
    assert np.array_equal(both.neighbors[:8], a.neighbors)
    assert both.vertex_map.tolist() == a.vertex_map.tolist() + [8, 9, 10, 8]
    assert both.segment_ids.tolist() == a.segment_ids.tolist() + (b.segment_ids + 8).tolist()
    assert both.stats["input_points"] == 12 and both.stats["duplicates"] == 1
    assert both.is_delaunay() and both.report().segment_edges == 11


@pytest.mark.parametrize("args, message", [
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.xyz"], "unknown output format '.xyz'"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.geojson", "--extrude", "2"], "--extrude makes a solid"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.ply", "--extrude", "0"], "finite nonzero height"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/nowhere/x.ply"], "does not exist"),
    (["mesh", "{t}/x.shp", "-o", "{t}/x.ply"], "x.shp: no such file"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.gpkg"], ".gpkg output needs a GIS layer input"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.ply", "--layer", "a"], "--layer applies to GIS layers"),
    (["mesh", "{c}/triangle/A.poly", "-o", "{t}/x.ply", "--project", "utm"],
     "--project applies to layer output"),
    (["mesh", "{c}/gis/ne_50m_admin_0_countries.geojson", "-o", "{t}/x.gpkg", "--no-progress"],
     "feature 98 (India): MultiPolygon is not valid"),
    (["mesh", "{c}/gis/naturalearth_lowres.geojson", "-o", "{t}/x.gpkg", "--project", "EPSG:4326"],
     "'WGS 84' is not a projected CRS"),
    (["mesh", "{c}/gis/naturalearth_lowres.geojson", "-o", "{t}/x.gpkg", "--intersections", "split"],
     "--intersections split is for the per-feature formats"),
    (["report", "{c}/README.md"], "unknown input format '.md'"),
    (["report", "{t}/bad.json"], "not valid JSON"),
    (["report", "{c}/triangle/A.poly", "--against", "earcut"], "--against earcut needs polygon input"),
    (["report", "{c}/triangle/A.poly", "--against", "{t}/none.ply"], "expected 'earcut' or an existing"),
    (["report", "{c}/earcut/water.json"], "pass --repair"),
    (["report", "{c}/earcut/steiner.json"], "not a valid GeoJSON geometry"),
    (["report", "{c}/gis/ne_50m_admin_0_countries.geojson", "--no-progress"], "feature 98 (India)"),
    (["report", "{c}/triangle/A.poly", "--max-area", "-1"], "max_area"),
])
@needs_corpus
def test_errors_are_one_clear_line(tmp_path, capsys, args, message):
    (tmp_path / "bad.json").write_text("{not json")
    argv = [a.format(c=CORPUS, t=tmp_path) for a in args]
    assert cli.main(argv) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("cdt-plugin: error: ")
    assert message in err[0]


def test_usage_errors_exit_2(capsys):
    assert cli.main(["mesh"]) == 2
    assert "the following arguments are required: INPUT, -o/--output" in capsys.readouterr().err
    assert cli.main(["report", "x.poly", "--intersections", "maybe"]) == 2
    for bad in ("0", "-2", "two", "1.5"):
        assert cli.main(["mesh", "x.poly", "-o", "x.ply", "--workers", bad]) == 2
        assert f"argument --workers: expected a whole number >= 1, got '{bad}'" in \
            capsys.readouterr().err


@needs_corpus
def test_geopackage_written_in_pieces_reads_back_whole(tmp_path, capsys, monkeypatch):
    gpd = pytest.importorskip("geopandas")
    src = CORPUS / "gis" / "naturalearth_lowres.geojson"
    monkeypatch.setattr(cli.writers, "LAYER_ROWS", 1000)
    out = tmp_path / "pieces.gpkg"
    assert cli.main(["mesh", str(src), "-o", str(out), "--progress"]) == 0
    assert "writing: 100%" in capsys.readouterr().err
    import shapely
    from cdt_plugin.adapters import geo
    back = gpd.read_file(out)
    with pytest.warns(geo.GeographicCRSWarning):
        expected = geo.triangulate(gpd.read_file(src))
    assert len(back) == len(expected) == 9791
    assert back["position"].tolist() == expected["position"].tolist()
    assert shapely.equals_exact(back.geometry.values, expected.geometry.values, 0).all()


@needs_corpus
@pytest.mark.parametrize("suffix", [".geojson", ".node"])
def test_workers_give_the_same_output(tmp_path, capsys, suffix):
    """A layer (one batch call) and per-feature output (one call per feature), on
    one thread and on three: the same bytes."""
    pytest.importorskip("geopandas")
    src = CORPUS / "gis" / "naturalearth_lowres.geojson"
    written = []
    for workers in ("1", "3"):
        out = tmp_path / f"w{workers}{suffix}"
        assert cli.main(["mesh", str(src), "-o", str(out), "--workers", workers,
                         "--no-progress"]) == 0
        written.append(out.read_bytes() if suffix != ".node" else
                       out.with_suffix(".ele").read_bytes())
    assert written[0] == written[1] and len(written[0]) > 100_000
    assert capsys.readouterr().out.count("9,791 triangles") == 2


@needs_corpus
def test_split_and_repair_read_invalid_polygons(capsys):
    src = str(CORPUS / "earcut" / "steiner.json")         # holes of one point each
    assert cli.main(["report", src, "--intersections", "split", "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["input_vertices"] == 8 and rep["non_delaunay_edges"] == 0
    assert cli.main(["report", str(CORPUS / "earcut" / "water3b.json"), "--repair"]) == 0
    assert "non-Delaunay non-segment edges" in capsys.readouterr().out


@pytest.mark.skipif(not has_refinement, reason="triangulate() has no min_angle yet")
@needs_corpus
def test_mesh_with_min_angle(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    out = tmp_path / "A.obj"
    proc = run("mesh", CORPUS / "triangle" / "A.poly", "-o", out, "--min-angle", "30", "--report")
    mesh = trimesh.load(out, process=False)
    q = triangle_quality(mesh.vertices[:, :2], mesh.faces)
    assert q["angles"].min() >= 30.0 - 1e-6
    steiner = next(line for line in proc.stdout.splitlines() if line.strip().startswith("Steiner"))
    assert int(steiner.split()[-1].replace(",", "")) == len(mesh.vertices) - 29 > 0


@pytest.mark.skipif(not has_refinement, reason="triangulate() has no max_area yet")
@needs_corpus
def test_mesh_with_max_area(tmp_path, capsys):
    out = tmp_path / "A.ele"
    assert cli.main(["mesh", str(CORPUS / "triangle" / "A.poly"), "-o", str(out), "--max-area", "0.01"]) == 0
    T = tio.read_ele(out).triangles
    areas = _areas(tio.read_node(tmp_path / "A.node").vertices, T)
    assert len(T) > 29 and areas.max() <= 0.01 * (1 + 1e-12)


# ------------------------------------------------------------------ compile and first use
def test_compile_command_fills_every_route(tmp_path):
    proc = run("compile")
    lines = proc.stdout.splitlines()
    from cdt_plugin.compiling import ROUTES
    assert [line.split(":")[0] for line in lines[:-1]] == list(ROUTES)
    assert lines[-1].startswith("all in ")
    assert "compiling" not in proc.stderr        # the command silences the first-use notice


def test_compile_command_refuses_an_unknown_route(capsys):
    assert cli.main(["compile", "triangulate", "no-such-route"]) == 1
    err = capsys.readouterr().err
    assert "unknown route 'no-such-route'" in err and "triangulate" in err


def test_missing_output_package_is_named_before_any_work(tmp_path, capsys, monkeypatch):
    import importlib.util
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "trimesh" else real(name, *a))
    # the input does not exist: the package check comes first, before reading or meshing
    assert cli.main(["mesh", str(tmp_path / "missing.poly"), "-o", str(tmp_path / "out.ply")]) == 1
    err = capsys.readouterr().err
    assert "writing .ply needs trimesh: pip install 'cdt-plugin[trimesh]'" in err


def test_first_use_notice_says_once_that_a_route_compiles(caplog):
    """A compile of a cdt_plugin function logs one warning naming it (a real numba compile
    of a fresh function in a cdt_plugin module; cached routes compile nothing)."""
    import logging

    import numba
    namespace = {"__name__": "cdt_plugin.probe_for_test"}
    exec("def probe(a):\n    return a + 1\n", namespace)
    probe = numba.njit(namespace["probe"])
    with caplog.at_level(logging.INFO, logger="cdt_plugin"):
        assert probe(1) == 2
        assert probe(2) == 3                 # compiled already: nothing more is said
    messages = [r.getMessage() for r in caplog.records if r.name == "cdt_plugin"]
    assert len([m for m in messages if "compiling" in m]) == 1, messages
    assert "cdt_plugin.probe_for_test.probe" in messages[0] and "cached" in messages[0]
    assert any(m.startswith("cdt_plugin: compiled") for m in messages)



def test_first_use_notice_says_once_per_public_call(caplog, monkeypatch):
    """A call of a public cdt_plugin function that compiles several kernels one after the
    other (fresh ones in a compiled-core module here) is announced once, by the call's
    name; another call that compiles is announced, and so is the same call compiling
    again after a pause (a new burst)."""
    import logging

    import numba
    from cdt_plugin import compiling
    core = {"__name__": "cdt_plugin._core.probe_for_test"}
    exec("def first(a):\n    return a + 1\n\ndef second(a):\n    return a * 2\n\n"
         "def third(a):\n    return a - 1\n\ndef fourth(a):\n    return a * 3\n", core)
    first, second, third, fourth = (numba.njit(core[f]) for f in ("first", "second", "third", "fourth"))
    public = {"__name__": "cdt_plugin.probe_api_for_test", "first": first, "second": second,
              "third": third, "fourth": fourth}
    exec("def mesh_probe(a):\n    return second(first(a))\n\n"
         "def other_probe(a, again=False):\n    return fourth(a) if again else third(a)\n", public)
    with caplog.at_level(logging.WARNING, logger="cdt_plugin"):
        assert public["mesh_probe"](1) == 4          # two kernels compile: one line
        assert public["mesh_probe"](2) == 6          # compiled already: nothing is said
        assert public["other_probe"](5) == 4         # another call compiles: one more line
        monkeypatch.setattr(compiling._notice, "BURST", 0.0)
        assert public["other_probe"](1, True) == 3   # the same call compiling later: one more
    messages = [r.getMessage() for r in caplog.records if r.name == "cdt_plugin"]
    assert len(messages) == 3, messages
    assert "the engine for mesh_probe()" in messages[0] and "cached" in messages[0]
    assert "the engine for other_probe()" in messages[1]
    assert "the engine for other_probe()" in messages[2]

# ------------------------------------------------- --errors skip, no polygons (#17)
def _collection(*geometries) -> dict:
    return {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": f"f{i}"}, "geometry": g}
        for i, g in enumerate(geometries)]}


SQUARE = {"type": "Polygon", "coordinates": [[[0, 0], [2, 0], [2, 2], [0, 2], [0, 0]]]}
BOWTIE = {"type": "Polygon", "coordinates": [[[0, 0], [2, 2], [2, 0], [0, 2], [0, 0]]]}


def test_errors_skip_leaves_out_failing_features_and_names_them(tmp_path, capsys):
    pytest.importorskip("shapely")
    from checker import assert_valid
    src = tmp_path / "two.json"
    src.write_text(json.dumps(_collection(BOWTIE, SQUARE)))
    out = tmp_path / "two.ele"
    assert cli.main(["mesh", str(src), "-o", str(out)]) == 1         # default: raise
    assert "feature 0 (f0): Polygon is not valid" in capsys.readouterr().err
    assert not out.exists()
    assert cli.main(["mesh", str(src), "-o", str(out), "--errors", "skip"]) == 0
    captured = capsys.readouterr()
    assert captured.err.startswith("cdt-plugin: warning: skipped feature 0 (f0): Polygon is not "
                                   "valid: Self-intersection at (1.0, 1.0), on ring 0 of polygon 0")
    assert len(captured.err.splitlines()) == 1
    V = tio.read_node(tmp_path / "two.node").vertices
    T = tio.read_ele(out).triangles
    S = tio.read_poly(tmp_path / "two.poly").segments
    assert V.tolist() == [[0, 0], [2, 0], [2, 2], [0, 2]] and len(T) == 2   # the square only
    assert_valid(V, T, segments=S, domain="segments")


def test_errors_skip_with_nothing_left_is_an_error(tmp_path, capsys):
    pytest.importorskip("shapely")
    src = tmp_path / "bowtie.json"
    src.write_text(json.dumps(BOWTIE))
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "b.ele"), "--errors", "skip"]) == 1
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("cdt-plugin: warning: skipped bowtie.json: Polygon is not valid")
    assert err[1] == f"cdt-plugin: error: {src}: no feature could be meshed (1 skipped)"
    assert not (tmp_path / "b.ele").exists()
    assert cli.main(["mesh", str(src), "-o", "b.ele", "--errors", "ignore"]) == 2   # usage


def test_errors_skip_skips_a_feature_that_is_no_geometry(tmp_path, capsys):
    """A feature whose GeoJSON geometry shapely cannot read fails alone: --errors skip
    names it and meshes the others."""
    pytest.importorskip("shapely")
    src = tmp_path / "two.json"
    src.write_text(json.dumps(_collection({"type": "Polygon", "coordinates": [[[0, 0], [1]]]},
                                          SQUARE)))
    out = tmp_path / "two.ele"
    assert cli.main(["mesh", str(src), "-o", str(out)]) == 1
    assert "feature 0 (f0): not a valid GeoJSON geometry" in capsys.readouterr().err
    assert cli.main(["mesh", str(src), "-o", str(out), "--errors", "skip"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("cdt-plugin: warning: skipped feature 0 (f0): not a valid GeoJSON geometry")
    assert len(tio.read_ele(out).triangles) == 2


@needs_corpus
def test_errors_skip_on_a_projected_world_layer(tmp_path, capsys):
    """The README's world line: in one azimuthal equidistant projection Russia (split
    at the antimeridian) cannot be meshed; --errors skip names it and meshes the rest."""
    gpd = pytest.importorskip("geopandas")
    src = CORPUS / "gis" / "naturalearth_lowres.geojson"
    out = tmp_path / "world.gpkg"
    args = ["mesh", str(src), "-o", str(out), "--project", "aeqd", "--repair", "--no-progress"]
    assert cli.main(args) == 1
    assert "error: feature 18 (Russia): " in capsys.readouterr().err
    assert cli.main(args + ["--errors", "skip"]) == 0
    captured = capsys.readouterr()
    skipped = [line for line in captured.err.splitlines() if "skipped" in line]
    assert skipped == [line for line in skipped if line.startswith(
        "cdt-plugin: warning: skipped feature ")]
    assert any("skipped feature 18 (Russia): " in line and "turn clockwise" in line
               for line in skipped)
    written = gpd.read_file(out)
    names = set(written["name"])
    assert "Russia" not in names and {"France", "Brazil", "Sudan"} <= names
    assert captured.out.strip() == (f"wrote {out}: {177 - len(skipped)} feature(s), "
                                    f"{len(written):,} triangles")
    given = gpd.read_file(src)
    for name in ("France", "Brazil", "Sudan"):       # the triangles tile each feature
        mine = written[written["name"] == name]
        assert (mine.geom_type == "Polygon").all()
        polygon = given[given["name"] == name].geometry.iloc[0]
        assert mine.area.sum() == pytest.approx(polygon.area, rel=1e-6)


def test_errors_skip_skips_a_feature_that_does_not_project(tmp_path, capsys):
    """A feature whose coordinates do not project (a latitude beyond the pole in Web
    Mercator) is skipped and named with --errors skip; the other is meshed."""
    gpd = pytest.importorskip("geopandas")
    src = tmp_path / "two.json"
    src.write_text(json.dumps(_collection({"type": "Polygon", "coordinates": [
        [[0, 80], [10, 80], [10, 95], [0, 95], [0, 80]]]}, SQUARE)))
    out = tmp_path / "two.gpkg"
    args = ["mesh", str(src), "-o", str(out), "--project", "EPSG:3857", "--no-progress"]
    assert cli.main(args) == 1
    assert "error: feature 0 (f0): coordinates do not project" in capsys.readouterr().err
    assert cli.main(args + ["--errors", "skip"]) == 0
    err = capsys.readouterr().err
    assert "cdt-plugin: warning: skipped feature 0 (f0): coordinates do not project" in err
    assert len(gpd.read_file(out)) == 2       # the square's two triangles


@pytest.mark.parametrize("output", ["out.ply", "out.ele", "out.geojson", "out.gpkg"])
@pytest.mark.parametrize("content, kinds", [
    (_collection({"type": "Point", "coordinates": [1, 2]}), "1 feature(s): 1 Point"),
    ({"type": "MultiPoint", "coordinates": [[0, 0], [1, 0], [0, 1]]}, "1 feature(s): 1 MultiPoint"),
    (_collection({"type": "Point", "coordinates": [1, 2]},
                 {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}),
     "2 feature(s): 1 LineString, 1 Point"),
])
def test_no_polygon_is_an_error_naming_it(tmp_path, capsys, output, content, kinds):
    """A GeoJSON without any Polygon or MultiPolygon: NoPolygonsError (exit 1), never an
    empty mesh written with exit 0, whatever the output."""
    pytest.importorskip("geopandas")
    src = tmp_path / "points.geojson"
    src.write_text(json.dumps(content))
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / output)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("cdt-plugin: error: ") and len(err.splitlines()) == 1
    assert "no Polygon or MultiPolygon feature to triangulate" in err
    assert kinds in err
    assert not list(tmp_path.glob("out.*"))


def test_no_polygon_in_wkt_is_an_error(tmp_path, capsys):
    pytest.importorskip("shapely")
    src = tmp_path / "point.wkt"
    src.write_text("POINT (1 2)")
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "p.ele")]) == 1
    assert ("no Polygon or MultiPolygon feature to triangulate (1 feature(s): 1 Point)"
            in capsys.readouterr().err)


@needs_corpus
def test_poly_regions_and_holes_reach_the_engine(tmp_path, capsys):
    """A .poly's hole points and region max areas are used (io.PolyData.to_plc)."""
    from checker import assert_valid
    out = tmp_path / "la.ele"
    assert cli.main(["mesh", str(CORPUS / "triangle" / "la.poly"), "-o", str(out)]) == 0
    tri = cdt_plugin.triangulate(tio.read_poly(CORPUS / "triangle" / "la.poly").to_plc())
    V = tio.read_node(tmp_path / "la.node").vertices
    T = tio.read_ele(out).triangles
    assert np.array_equal(V, tri.vertices) and np.array_equal(T, tri.triangles)
    assert len(tri.steiner) > 0                        # la.poly's region areas refine
    assert_valid(V, T, segments=tio.read_poly(tmp_path / "la.poly").segments, domain="segments")


def test_mesh_with_merge_distance(tmp_path, capsys):
    shapely = pytest.importorskip("shapely")
    # a CAD outline whose hole has a corner given twice, 1e-14 apart: an overlap without merging
    polygon = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                              [[(1, 1), (1, 3), (3, 3), (3, 1), (3 + 1e-14, 1)]])
    src = tmp_path / "near.wkt"
    src.write_text(polygon.wkt)
    out = tmp_path / "near.ele"
    assert cli.main(["mesh", str(src), "-o", str(out)]) == 1
    assert "Self-intersection at (3.0, 1.0)" in capsys.readouterr().err
    assert cli.main(["mesh", str(src), "-o", str(out), "--merge-distance", "1e-9"]) == 0
    V, T = tio.read_node(tmp_path / "near.node").vertices, tio.read_ele(out).triangles
    assert len(V) == 8 and len(T) == 8
    assert cli.main(["mesh", str(src), "-o", str(out), "--merge-distance", "-1"]) == 1
    assert "merge_distance must be a finite number >= 0" in capsys.readouterr().err


def test_mesh_with_smooth(tmp_path, capsys):
    """``--smooth odt`` gives triangulate(smooth="odt")'s mesh: the same vertices
    count, input vertices where they were, a higher mean radius ratio, valid."""
    from checker import assert_valid
    src = CORPUS / "triangle" / "A.poly"
    plain, smooth = tmp_path / "plain.ele", tmp_path / "smooth.ele"
    base = ["mesh", str(src), "--min-angle", "25", "--max-area", "0.5"]
    assert cli.main([*base, "-o", str(plain)]) == 0
    assert cli.main([*base, "--smooth", "odt", "-o", str(smooth)]) == 0
    capsys.readouterr()
    V0, T0 = tio.read_node(tmp_path / "plain.node").vertices, tio.read_ele(plain).triangles
    V1, T1 = tio.read_node(tmp_path / "smooth.node").vertices, tio.read_ele(smooth).triangles
    n = len(tio.read_poly(src).vertices)
    assert len(V1) == len(V0) and np.array_equal(V1[:n], V0[:n])
    assert_valid(V1, T1, segments=tio.read_poly(tmp_path / "smooth.poly").segments, domain="segments")

    def mean_radius_ratio(V, T):
        a, b, c = (np.linalg.norm(V[T[:, (i + 1) % 3]] - V[T[:, (i + 2) % 3]], axis=1) for i in range(3))
        return float(np.mean((b + c - a) * (c + a - b) * (a + b - c) / (a * b * c)))
    assert mean_radius_ratio(V1, T1) > mean_radius_ratio(V0, T0)
    assert cli.main([*base, "--smooth", "laplace", "-o", str(smooth)]) == 2     # a usage error
    assert "invalid choice: 'laplace'" in capsys.readouterr().err


def test_smooth_is_refused_for_layer_output(tmp_path, capsys):
    pytest.importorskip("geopandas")
    src = tmp_path / "one.geojson"
    src.write_text(json.dumps({"type": "FeatureCollection", "features": [{
        "type": "Feature", "properties": {"name": "a"},
        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]}}]}))
    assert cli.main(["mesh", str(src), "-o", str(tmp_path / "out.gpkg"), "--smooth", "odt"]) == 1
    assert "--smooth is for the per-feature formats" in capsys.readouterr().err
