"""``cdt-plugin mesh --size H --size-near PATH[:LAYER]:MIN:MAX:DIST``, end to end:
Triangle files, GeoJSON and GIS layers in, the meshes read back and checked
exactly, every triangle's longest edge against the field at its centroid; bad
specs are usage errors, missing files one line naming them."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cdt_plugin
import cdt_plugin.cli as cli
from cdt_plugin import io as tio
from cdt_plugin.nearness import SmallestSize
from checker import assert_valid
from helpers import longest_over_field
from corpus import corpus_dir

ROOT = Path(__file__).resolve().parents[2]
A_POLY = corpus_dir() / "triangle" / "A.poly"
needs_corpus = pytest.mark.skipif(not A_POLY.exists(), reason="corpus not found")


def read_triangle_files(base: Path):
    V = tio.read_node(base.with_suffix(".node")).vertices
    T = tio.read_ele(base.with_suffix(".ele")).triangles
    segments = tio.read_poly(base.with_suffix(".poly")).segments
    assert_valid(V, T, segments=segments, domain="segments")
    return V, T


@needs_corpus
def test_size_on_a_poly_file(tmp_path, capsys):
    assert cli.main(["mesh", str(A_POLY), "-o", str(tmp_path / "A.ele"), "--size", "0.05",
                     "--min-angle", "25"]) == 0
    V, T = read_triangle_files(tmp_path / "A")
    ratio = longest_over_field(V, T, 0.05)
    assert ratio.max() <= 1.5 and len(T) > 3 * 29        # (29 input vertices)


@needs_corpus
def test_size_near_lines_and_points_on_a_poly_file(tmp_path):
    """Two --size-near files (a GeoJSON line, a .node point set) and --size: the
    smallest of the three fields at every point."""
    line = {"type": "LineString", "coordinates": [[0.2, -0.8], [0.8, -0.2]]}    # (A is in 0.2..0.8, -0.8..-0.2)
    (tmp_path / "line.geojson").write_text(json.dumps(line))
    tio.write_node(tmp_path / "wells.node", np.array([[0.3, -0.3]]))
    assert cli.main(["mesh", str(A_POLY), "-o", str(tmp_path / "A.ele"), "--size", "0.1",
                     "--size-near", f"{tmp_path / 'line.geojson'}:0.01:0.1:0.3",
                     "--size-near", f"{tmp_path / 'wells.node'}:0.005:0.1:0.2"]) == 0
    V, T = read_triangle_files(tmp_path / "A")
    field = SmallestSize([0.1, cdt_plugin.size_near(line, 0.01, 0.1, distance=0.3),
                          cdt_plugin.size_near([[0.3, -0.3]], 0.005, 0.1, distance=0.2)])
    assert longest_over_field(V, T, field).max() <= 1.5
    plain = cdt_plugin.triangulate(tio.read_poly(A_POLY).to_plc(), size=0.1)
    assert len(T) > 3 * len(plain.triangles)


def test_size_near_on_a_layer_in_another_crs(tmp_path):
    """Layer in, layer out: the river file (lon/lat) is reprojected to the layer's
    metres before the field is made."""
    gpd = pytest.importorskip("geopandas")
    shapely = pytest.importorskip("shapely")
    x0, y0 = 500_000.0, 5_000_000.0
    lake = gpd.GeoDataFrame({"name": ["lake"]}, crs="EPSG:32633",
                            geometry=[shapely.box(x0, y0, x0 + 2000, y0 + 1000)])
    river_utm = gpd.GeoSeries([shapely.LineString([(x0 - 50, y0 + 500), (x0 + 2050, y0 + 500)])],
                              crs="EPSG:32633")
    lake.to_file(tmp_path / "lake.gpkg")
    gpd.GeoDataFrame(geometry=river_utm.to_crs("EPSG:4326")).to_file(
        tmp_path / "water.gpkg", layer="rivers")
    out = tmp_path / "mesh.gpkg"
    assert cli.main(["mesh", str(tmp_path / "lake.gpkg"), "-o", str(out), "--size", "150",
                     "--size-near", f"{tmp_path / 'water.gpkg'}:rivers:15:150:500"]) == 0
    triangles = gpd.read_file(out)
    xy = shapely.get_coordinates(triangles.geometry.to_numpy())
    V, inverse = np.unique(xy, axis=0, return_inverse=True)
    T = inverse.reshape(-1, 4)[:, :3]         # (each triangle a closed ring of 4 points)
    assert_valid(V, T)
    field = SmallestSize([150.0, cdt_plugin.size_near(river_utm, 15.0, 150.0, distance=500.0)])
    assert longest_over_field(V, T, field).max() <= 1.5
    assert (np.abs(V[T].mean(axis=1)[:, 1] - (y0 + 500)) < 20).sum() > 100


def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "cdt_plugin", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=600)


@needs_corpus
@pytest.mark.parametrize("args, status, words", [
    (["--size-near", "r.gpkg:1:2"], 2, "expected PATH[:LAYER]:MIN:MAX:DIST, got 'r.gpkg:1:2'"),
    (["--size-near", "r.gpkg:x:2:3"], 2, "MIN must be a number"),
    (["--size-near", "r.gpkg:5:1:3"], 2, "size_max must be >= size_min"),
    (["--size-near", "r.gpkg:1:2:0"], 2, "distance must be a finite number > 0"),
    (["--size", "big"], 2, "invalid float value: 'big'"),
    (["--size", "-1"], 1, "size must be a positive finite length, got -1.0"),
    (["--size-near", "no_such.gpkg:1:2:3"], 1, "--size-near no_such.gpkg: no such file"),
    (["--size-near", "A.txt:1:2:3"], 1, "--size-near A.txt: unknown input format '.txt'"),
])
def test_bad_sizes_are_named(tmp_path, args, status, words):
    """Bad numbers are usage errors (status 2); bad values and files one line (status 1)."""
    proc = run("mesh", A_POLY, "-o", tmp_path / "A.ele", *args)
    assert proc.returncode == status and words in proc.stderr and "Traceback" not in proc.stderr
    if status == 1:
        assert len(proc.stderr.strip().splitlines()) == 1
