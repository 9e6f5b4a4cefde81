"""``cdt-plugin extrude``: a GeoPackage of footprints (written by geopandas through
pyogrio) to a .glb scene or one merged mesh, through the real command."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

geopandas = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
trimesh = pytest.importorskip("trimesh")
pytest.importorskip("pyogrio")

from cdt_plugin import cli

X0, Y0 = 500_000.0, 5_000_000.0


@pytest.fixture
def buildings(tmp_path):
    yard = shapely.box(X0 + 40, Y0, X0 + 70, Y0 + 20).difference(
        shapely.box(X0 + 45, Y0 + 5, X0 + 65, Y0 + 15))
    pinch = shapely.Polygon([(X0 + 100, Y0), (X0 + 120, Y0), (X0 + 120, Y0 + 20), (X0 + 100, Y0 + 20)],
                            [[(X0 + 104, Y0 + 4), (X0 + 104, Y0 + 10), (X0 + 110, Y0 + 10), (X0 + 110, Y0 + 4)],
                             [(X0 + 110, Y0 + 10), (X0 + 110, Y0 + 16), (X0 + 116, Y0 + 16), (X0 + 116, Y0 + 10)]])
    layer = geopandas.GeoDataFrame(
        {"name": ["hall", "yard", "pinch"], "height": [12.0, 7.5, 20.0], "ground": [1.0, 0.0, 2.5]},
        geometry=[shapely.box(X0, Y0, X0 + 20, Y0 + 10), yard, pinch], crs="EPSG:32633")
    path = tmp_path / "buildings.gpkg"
    layer.to_file(path, engine="pyogrio")
    return path, layer


def run(*args):
    return subprocess.run([sys.executable, "-m", "cdt_plugin", "extrude", *map(str, args)],
                          capture_output=True, text=True)


def volume(mesh) -> float:
    moved = mesh.copy()
    moved.apply_translation(-mesh.vertices[0])
    return float(moved.volume)


def test_glb_one_node_per_feature(buildings, tmp_path):
    path, layer = buildings
    out = tmp_path / "city.glb"
    done = run(path, "--height", "height", "--base", "ground", "-o", out)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"wrote {out}: 3 solid(s)")
    scene = trimesh.load(out)
    assert sorted(scene.graph.nodes_geometry) == ["0", "1", "2"]
    for node in scene.graph.nodes_geometry:
        row = layer.iloc[int(node)]
        parent = scene.graph.transforms.parents[node]
        extras = scene.graph.transforms.edge_data[(parent, node)]["metadata"]
        assert extras["name"] == row["name"] and extras["height"] == row["height"]
        transform, geometry = scene.graph[node]
        mesh = scene.geometry[geometry].copy()
        mesh.apply_transform(transform)
        assert mesh.is_watertight and mesh.is_winding_consistent
        assert mesh.bounds[:, 2] == pytest.approx([row["ground"], row["ground"] + row["height"]])
        assert volume(mesh) == pytest.approx(row.geometry.area * row["height"], rel=1e-5)


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_one_merged_mesh(buildings, tmp_path, suffix):
    path, layer = buildings
    out = tmp_path / f"city{suffix}"
    done = run(path, "--height", "10", "-o", out)
    assert done.returncode == 0, done.stderr
    mesh = trimesh.load(out, force="mesh", process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert set(np.unique(mesh.vertices[:, 2])) == {0.0, 10.0}
    expected = float(layer.area.sum() * 10)
    assert volume(mesh) == pytest.approx(expected, rel=1e-9 if suffix == ".obj" else 1e-4)


def test_errors_named(buildings, tmp_path, capsys):
    path, _ = buildings
    out = tmp_path / "city.glb"
    assert cli.main(["extrude", str(path), "--height", "storeys", "-o", str(out)]) == 1
    assert "height='storeys': the layer has no such attribute column" in capsys.readouterr().err
    assert cli.main(["extrude", str(path), "--height", "-3", "-o", str(out)]) == 1
    assert "height must be positive and finite" in capsys.readouterr().err
    assert cli.main(["extrude", str(path), "--height", "name", "-o", str(out)]) == 1
    assert "not numeric" in capsys.readouterr().err
    assert cli.main(["extrude", str(path), "--height", "5", "-o", str(tmp_path / "city.gpkg")]) == 1
    assert "extrude writes .glb" in capsys.readouterr().err
    assert not out.exists()


def test_points_skipped_with_errors_skip(buildings, tmp_path, capsys):
    _, layer = buildings
    mixed = layer.copy()
    mixed.loc[1, "geometry"] = shapely.Point(X0, Y0)
    mixed_path = tmp_path / "mixed.gpkg"
    mixed.to_file(mixed_path, engine="pyogrio")
    out = tmp_path / "city.glb"
    assert cli.main(["extrude", str(mixed_path), "--height", "height", "-o", str(out)]) == 1
    assert "feature 1 (yard): no polygon to extrude" in capsys.readouterr().err
    assert cli.main(["extrude", str(mixed_path), "--height", "height", "-o", str(out),
                     "--errors", "skip"]) == 0
    captured = capsys.readouterr()
    assert "warning: skipped feature 1 (yard): no polygon to extrude" in captured.err
    assert "2 solid(s)" in captured.out
    assert sorted(trimesh.load(out).graph.nodes_geometry) == ["0", "2"]


def test_lon_lat_layer_projected(buildings, tmp_path, capsys):
    _, layer = buildings
    lonlat = tmp_path / "lonlat.gpkg"
    layer.to_crs("EPSG:4326").to_file(lonlat, engine="pyogrio")
    out = tmp_path / "city.obj"
    assert cli.main(["extrude", str(lonlat), "--height", "height", "-o", str(out)]) == 0
    assert "pass --project utm" in capsys.readouterr().err
    assert cli.main(["extrude", str(lonlat), "--height", "height", "--project", "utm",
                     "-o", str(out)]) == 0
    mesh = trimesh.load(out, force="mesh", process=False)
    assert mesh.is_watertight
    assert mesh.bounds[0, :2] == pytest.approx([X0, Y0], abs=1e-6)     # back in UTM metres
