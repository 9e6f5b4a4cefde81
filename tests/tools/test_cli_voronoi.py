"""``cdt-plugin voronoi``: a point layer in, a layer of cells out (.gpkg, .geojson),
read back with geopandas and compared with :func:`cdt_plugin.adapters.geo.voronoi`;
errors are one line on stderr with exit status 1. The checks call ``main()``
in-process; one runs the command as a subprocess."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyogrio")
pytest.importorskip("pyproj")

import cdt_plugin.cli as cli  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402
import cdt_plugin  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CRS = "EPSG:32633"
X0, Y0 = 500_000.0, 5_000_000.0
AREA = shapely.Polygon([(X0 - 20, Y0 - 20), (X0 + 520, Y0 - 20), (X0 + 520, Y0 + 250),
                        (X0 + 250, Y0 + 250), (X0 + 250, Y0 + 520), (X0 - 20, Y0 + 520)])


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """points.gpkg (projected, with attributes), area.geojson (the boundary in
    lon/lat), area.gpkg (in the points' CRS), lines.gpkg (not points)."""
    d = tmp_path_factory.mktemp("voronoi")
    rng = np.random.default_rng(5)
    xy = rng.uniform([X0, Y0], [X0 + 500, Y0 + 500], (200, 2))
    xy = xy[shapely.contains_xy(AREA, xy[:, 0], xy[:, 1])][:40]
    points = gpd.GeoDataFrame({"name": [f"p{i}" for i in range(len(xy))],
                               "weight": rng.uniform(0, 3000, len(xy))},
                              geometry=shapely.points(xy), crs=CRS)
    points.to_file(d / "points.gpkg", engine="pyogrio")
    area = gpd.GeoDataFrame({"id": [1]}, geometry=[AREA], crs=CRS)
    area.to_file(d / "area.gpkg", engine="pyogrio")
    area.to_crs("EPSG:4326").to_file(d / "area.geojson", engine="pyogrio")
    gpd.GeoDataFrame({"name": ["a", "road"]}, crs=CRS,
                     geometry=[shapely.Point(X0, Y0), shapely.LineString([(X0, Y0), (X0 + 1, Y0)])]
                     ).to_file(d / "lines.gpkg", engine="pyogrio")
    return d, points


def read_back(path: Path):
    return gpd.read_file(path, engine="pyogrio")


def same_cells(a, b) -> bool:
    """The same regions (a GeoPackage may store a Polygon as a one-part MultiPolygon)."""
    a, b = np.asarray(a, dtype=object), np.asarray(b, dtype=object)
    return bool(shapely.equals(a, b).all())


# ------------------------------------------------------------------ outputs
@pytest.mark.parametrize("suffix", [".gpkg", ".geojson"])
def test_cells_with_a_boundary_in_another_crs(files, tmp_path, capsys, suffix):
    d, points = files
    out = tmp_path / f"cells{suffix}"
    assert cli.main(["voronoi", str(d / "points.gpkg"), "--boundary", str(d / "area.geojson"),
                     "-o", str(out), "--no-progress"]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {out}: {len(points)} cell(s)"
    back = read_back(out)
    assert back.crs == CRS
    assert back["name"].tolist() == points["name"].tolist()
    assert back["weight"].tolist() == points["weight"].tolist()
    expected = geo.voronoi(points, gpd.read_file(d / "area.geojson"))
    assert same_cells(back.geometry.array, expected.geometry.array)
    region = gpd.read_file(d / "area.geojson").to_crs(CRS).geometry.iloc[0]
    assert back.area.sum() == pytest.approx(region.area, rel=1e-9)
    assert shapely.contains(np.asarray(back.geometry.array), np.asarray(points.geometry.array)).all()


def test_weights_column_and_boundary_layer_in_the_same_crs(files, tmp_path, capsys):
    d, points = files
    out = tmp_path / "power.gpkg"
    assert cli.main(["voronoi", str(d / "points.gpkg"), "--boundary", str(d / "area.gpkg"),
                     "--weights", "weight", "-o", str(out)]) == 0
    back = read_back(out)
    expected = geo.voronoi(points, AREA, weights="weight")
    assert same_cells(back.geometry.array, expected.geometry.array)
    assert not same_cells(back.geometry.array, geo.voronoi(points, AREA).geometry.array)
    assert back.area.sum() == pytest.approx(AREA.area, rel=1e-9)


def test_without_a_boundary_the_cells_fill_the_envelope(files, tmp_path, capsys):
    d, points = files
    out = tmp_path / "cells.json"
    assert cli.main(["voronoi", str(d / "points.gpkg"), "-o", str(out), "--progress"]) == 0
    assert "writing: 100%" in capsys.readouterr().err
    back = read_back(out)
    assert same_cells(back.geometry.array, geo.voronoi(points).geometry.array)


def test_empty_cells_are_counted_and_written(tmp_path, capsys):
    pts = gpd.GeoDataFrame({"w": [0.0, 0.0, 0.0, 0.0, -10.0]}, crs=CRS,
                           geometry=shapely.points([(0, 0), (4, 0), (0, 4), (4, 4), (2, 2)]))
    src = tmp_path / "submerged.geojson"
    pts.to_file(src, engine="pyogrio")
    for suffix in (".gpkg", ".geojson"):
        out = tmp_path / f"cells{suffix}"
        assert cli.main(["voronoi", str(src), "--weights", "w", "-o", str(out)]) == 0
        assert capsys.readouterr().out.strip() == f"wrote {out}: 5 cell(s), 1 empty"
        back = read_back(out)
        assert len(back) == 5
        last = back.geometry.iloc[4]
        assert last is None or last.is_empty


def test_geographic_points_warn_on_stderr(tmp_path, capsys):
    src = tmp_path / "lonlat.geojson"
    gpd.GeoDataFrame({"v": [1, 2, 3]}, geometry=shapely.points([(10, 50), (11, 50), (10, 51)]),
                     crs="EPSG:4326").to_file(src, engine="pyogrio")
    assert cli.main(["voronoi", str(src), "-o", str(tmp_path / "c.geojson")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1
    assert err[0].startswith("cdt-plugin: warning: the layer's CRS (WGS 84) is geographic")
    assert "ogr2ogr -t_srs" in err[0]


def test_subprocess_run(files, tmp_path):
    d, points = files
    out = tmp_path / "cells.gpkg"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "cdt_plugin", "voronoi", str(d / "points.gpkg"),
                           "--boundary", str(d / "area.gpkg"), "-o", str(out)],
                          capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stdout.strip() == f"wrote {out}: {len(points)} cell(s)"
    assert len(read_back(out)) == len(points)


# ------------------------------------------------------------------- help
def test_help_lists_the_subcommand_and_its_examples(capsys):
    assert cli.main(["--help"]) == 0
    text = capsys.readouterr().out
    assert "{mesh,report,voronoi,tin,extrude,triangle,compile}" in text
    assert "cdt-plugin voronoi shops.gpkg --boundary city.gpkg -o cells.gpkg" in text
    assert cli.main(["voronoi", "--help"]) == 0
    text = capsys.readouterr().out
    assert "--boundary AREA" in text and "--weights COLUMN" in text


# ----------------------------------------------------------------- errors
@pytest.mark.parametrize("args, message", [
    (["{d}/points.gpkg", "-o", "{t}/cells.ply"], "voronoi writes a layer: expected one of .gpkg"),
    (["{d}/points.gpkg", "-o", "{t}/missing/cells.gpkg"], "does not exist"),
    (["{d}/points.wkt", "-o", "{t}/cells.gpkg"], "POINTS must be a layer"),
    (["{d}/none.gpkg", "-o", "{t}/cells.gpkg"], "none.gpkg: no such file"),
    (["{d}/points.gpkg", "--boundary", "{d}/none.gpkg", "-o", "{t}/cells.gpkg"], "no such file"),
    (["{d}/lines.gpkg", "-o", "{t}/cells.gpkg"],
     "feature 1 (road): a LineString where a Point is expected"),
    (["{d}/points.gpkg", "--boundary", "{d}/points.gpkg", "-o", "{t}/cells.gpkg"],
     "boundary feature 0 is a Point"),
    (["{d}/points.gpkg", "--boundary", "{t}/far.gpkg", "-o", "{t}/cells.gpkg"],
     "boundary: the clip polygon contains none of the"),
    (["{d}/points.gpkg", "--weights", "nope", "-o", "{t}/cells.gpkg"],
     "weights='nope' is not a column of the point layer (columns: name, weight)"),
    (["{d}/points.gpkg", "--boundary-layer", "x", "-o", "{t}/cells.gpkg"],
     "--boundary-layer needs --boundary"),
])
def test_errors_are_one_line(files, tmp_path, capsys, args, message):
    d, _ = files
    gpd.GeoDataFrame(geometry=[shapely.box(0, 0, 1, 1)], crs=CRS).to_file(tmp_path / "far.gpkg",
                                                                          engine="pyogrio")
    argv = ["voronoi"] + [a.format(d=d, t=tmp_path) for a in args]
    assert cli.main(argv) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("cdt-plugin: error: "), err
    assert message in err[0]


def test_usage_errors_exit_2(capsys):
    assert cli.main(["voronoi", "points.gpkg"]) == 2
    assert "the following arguments are required: -o/--output" in capsys.readouterr().err


def test_missing_package_is_named_before_any_work(tmp_path, capsys, monkeypatch):
    import importlib.util
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "geopandas" else real(name, *a))
    # the input does not exist: the package check comes first
    assert cli.main(["voronoi", str(tmp_path / "missing.gpkg"), "-o", str(tmp_path / "c.geojson")]) == 1
    assert "cdt-plugin voronoi needs geopandas: pip install 'cdt-plugin[gis]'" in capsys.readouterr().err


def test_node_file_of_points(tmp_path, capsys):
    """A Triangle ``.node`` point set in (no CRS): node numbers, attributes and markers
    kept as columns, the cells those of cdt_plugin.delaunay(...).voronoi() cut to the envelope."""
    node = tmp_path / "pts.node"
    rng = np.random.default_rng(8)
    xy = rng.random((30, 2))
    lines = ["30 2 1 1"] + [f"{i + 1} {float(x)!r} {float(y)!r} {i * 0.5!r} {i % 2}" for i, (x, y) in enumerate(xy)]
    node.write_text("\n".join(lines) + "\n")
    out = tmp_path / "cells.gpkg"
    assert cli.main(["voronoi", str(node), "-o", str(out)]) == 0
    assert f"wrote {out}: 30 cell(s)" in capsys.readouterr().out
    cells = read_back(out)
    assert cells.crs is None
    assert cells["node"].tolist() == list(range(1, 31)) and cells["marker"].tolist() == [i % 2 for i in range(30)]
    assert cells["attribute_1"].tolist() == [i * 0.5 for i in range(30)]
    vor = cdt_plugin.delaunay(xy).voronoi()
    expected = vor.to_shapely()
    assert same_cells(cells.geometry, expected[vor.point_region])
    assert cells.area.sum() == pytest.approx(shapely.box(*vor.envelope()).area, rel=1e-12)
    assert shapely.contains_xy(np.asarray(cells.geometry.array), xy[:, 0], xy[:, 1]).all()


def test_node_file_is_not_a_boundary(tmp_path, files, capsys):
    d, _ = files
    node = tmp_path / "area.node"
    node.write_text("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n")
    assert cli.main(["voronoi", str(d / "points.gpkg"), "--boundary", str(node), "-o",
                     str(tmp_path / "c.gpkg")]) == 1
    assert "--boundary must be a layer" in capsys.readouterr().err
