"""``geo.triangulate(size=..., size_near=...)`` against the real geopandas and pyproj:
a size for the layer, one per feature (a column), sizes near another layer in
another CRS; every feature's mesh checked exactly, every triangle's longest edge
against the field at its centroid; bad arguments named."""
from __future__ import annotations

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyproj")

import cdt_plugin  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402
from cdt_plugin.errors import SizeFieldError  # noqa: E402

from checker import assert_valid  # noqa: E402
from helpers import longest_over_field  # noqa: E402

X0, Y0 = 500_000.0, 5_000_000.0        # UTM zone 33N metres


def layer(sizes=(np.nan, np.nan)):
    """Two squares 1 km apart, 1 km a side, with a size column."""
    return gpd.GeoDataFrame(
        {"name": ["west", "east"], "mesh_size": list(sizes)}, crs="EPSG:32633",
        geometry=[shapely.box(X0, Y0, X0 + 1000, Y0 + 1000),
                  shapely.box(X0 + 2000, Y0, X0 + 3000, Y0 + 1000)], index=["w", "e"])


def checked(mesh, i):
    """Feature ``i``'s mesh, checked exactly (bounded by its boundary edges)."""
    V, T = mesh.feature_mesh(i)
    e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    assert_valid(V[:, :2], T, segments=uniq[count == 1], domain="segments")
    return V[:, :2], T


def test_one_size_for_the_layer():
    mesh = geo.triangulate(layer(), output="mesh", size=100.0, min_angle=25)
    for i in range(2):
        V, T = checked(mesh, i)
        ratio = longest_over_field(V, T, 100.0)
        assert ratio.max() <= 1.5 and np.median(ratio) > 0.5
        assert 100 < len(T) < 1000


def test_a_size_per_feature_from_a_column():
    mesh = geo.triangulate(layer(sizes=(50.0, np.nan)), output="mesh", size="mesh_size")
    west, east = checked(mesh, 0), checked(mesh, 1)
    assert longest_over_field(*west, 50.0).max() <= 1.5 and len(west[1]) > 500
    assert len(east[1]) == 2            # NaN: no size, the square as it is
    rows = geo.triangulate(layer(sizes=(50.0, np.nan)), size="mesh_size")
    assert set(rows["feature"]) == {"w", "e"} and rows["name"].tolist().count("east") == 2


def test_sizes_near_a_river_in_another_crs():
    """A river given in lon/lat is reprojected to the layer's UTM metres; with a
    column too, the smaller of the two at every point."""
    river_utm = shapely.LineString([(X0 - 100, Y0 + 500), (X0 + 3100, Y0 + 500)])
    river = gpd.GeoSeries([river_utm], crs="EPSG:32633").to_crs("EPSG:4326")
    mesh = geo.triangulate(layer(sizes=(80.0, np.nan)), output="mesh", size="mesh_size",
                           size_near=(river, 10.0, 200.0, 400.0), min_angle=20)
    near = cdt_plugin.size_near(river.to_crs("EPSG:32633"), 10.0, 200.0, distance=400.0)
    for i, cap in ((0, 80.0), (1, None)):
        V, T = checked(mesh, i)
        field = near if cap is None else cdt_plugin.nearness.SmallestSize([cap, near])
        ratio = longest_over_field(V, T, field)
        assert ratio.max() <= 1.5
        c = V[T].mean(axis=1)
        by_river = np.abs(c[:, 1] - (Y0 + 500)) < 30
        assert by_river.sum() > 50            # fine along the river in both squares
    # the river's layer as a file, by path
    assert len(geo.triangulate(layer(), size_near=[{"geometries": river, "size_min": 50.0,
                                                    "size_max": 200.0, "growth": 1.5}])) > 100


def test_size_near_from_a_file(tmp_path):
    wells = gpd.GeoDataFrame(geometry=[shapely.Point(X0 + 500, Y0 + 500)], crs="EPSG:32633")
    path = tmp_path / "wells.gpkg"
    wells.to_file(path)
    mesh = geo.triangulate(layer(), output="mesh", size_near=(str(path), 5.0, 300.0, 500.0))
    V, T = checked(mesh, 0)
    field = cdt_plugin.size_near(wells, 5.0, 300.0, distance=500.0)
    assert longest_over_field(V, T, field).max() <= 1.5
    assert len(T) > 4 * len(checked(mesh, 1)[1])       # the well is in the west square


def test_projected_meshing_takes_sizes_in_metres():
    lonlat = layer().to_crs("EPSG:4326")
    mesh = geo.triangulate(lonlat, output="mesh", project="utm", size=100.0)
    V, T = mesh.batch.vertices, mesh.triangles[mesh.position == 0]    # the meshing CRS's
    assert longest_over_field(V, T, 100.0).max() <= 1.5
    assert 100 < len(T) < 1000


@pytest.mark.parametrize("kwargs, words", [
    ({"size": "no_such"}, "size='no_such': the layer has no such column"),
    ({"size": "name"}, "size='name': the column must hold numbers"),
    ({"size": -5.0}, "size must be a positive finite length, got -5.0"),
    ({"size_near": ("r.gpkg", 0.0, 1.0, 1.0)}, "size_min must be a finite number > 0, got 0.0"),
    ({"size_near": ("r.gpkg", 1.0, 2.0)}, "size_near[0]: expected (geometries, size_min"),
    ({"size_near": [{"geometries": "r.gpkg", "size_min": 1, "size_max": 2, "dist": 3}]},
     "size_near[0]: expected the keys"),
    ({"size_near": ("r.gpkg", 1.0, 2.0, None)}, "size_near needs distance="),
])
def test_bad_sizing_is_named_before_any_work(kwargs, words):
    with pytest.raises(SizeFieldError) as info:
        geo.triangulate(layer(), **kwargs)
    assert words in str(info.value)


def test_a_bad_size_in_the_column_names_the_feature():
    with pytest.raises(SizeFieldError, match=r"feature e has size -1\.0"):
        geo.triangulate(layer(sizes=(50.0, -1.0)), size="mesh_size")


def test_a_missing_size_near_file_is_named(tmp_path):
    with pytest.raises(cdt_plugin.CDTError, match="no_such.gpkg: no such file"):
        geo.triangulate(layer(), size_near=(str(tmp_path / "no_such.gpkg"), 1.0, 2.0, 3.0))
