"""Voronoi cells of a point layer (``cdt_plugin.adapters.geo.voronoi``) against the
real geopandas, shapely, pyogrio and pyproj (no mocks): one cell per point with the
point's index, attributes and CRS; the cells tile the boundary, hold their points,
and every sample point lies in the cell of its nearest point (of least power
distance, weighted); boundaries as polygons and as layers in another CRS."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyogrio")
pytest.importorskip("pyproj")

import cdt_plugin  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402

CRS = "EPSG:32633"
X0, Y0 = 500_000.0, 5_000_000.0          # UTM 33N metres: the coordinates are large
# an L-shaped (non-convex) area with a hole, around the points
AREA = shapely.Polygon(
    [(X0 - 50, Y0 - 50), (X0 + 1050, Y0 - 50), (X0 + 1050, Y0 + 450), (X0 + 450, Y0 + 450),
     (X0 + 450, Y0 + 1050), (X0 - 50, Y0 + 1050)],
    [[(X0 + 100, Y0 + 600), (X0 + 100, Y0 + 700), (X0 + 200, Y0 + 700), (X0 + 200, Y0 + 600)]])


def sample_points(n: int, seed: int, region=AREA) -> np.ndarray:
    """``n`` random points inside ``region``."""
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, ymax = region.bounds
    out = np.empty((0, 2))
    while len(out) < n:
        xy = rng.uniform([xmin, ymin], [xmax, ymax], (4 * n, 2))
        out = np.vstack([out, xy[shapely.contains_xy(region, xy[:, 0], xy[:, 1])]])
    return out[:n]


@pytest.fixture(scope="module")
def layer():
    xy = sample_points(60, seed=7)
    rng = np.random.default_rng(3)
    return gpd.GeoDataFrame(
        {"name": [f"site {i}" for i in range(len(xy))], "count": rng.integers(0, 100, len(xy)),
         "power": rng.uniform(0.0, 8000.0, len(xy))},
        geometry=shapely.points(xy), crs=CRS, index=[f"s{i}" for i in range(len(xy))])


def assert_tiles(cells: np.ndarray, region) -> None:
    """The cells cover ``region`` exactly once: their areas add up to its area,
    their union is it, and no two overlap (beyond rounding)."""
    cells = cells[~shapely.is_empty(cells)]
    total = float(shapely.area(cells).sum())
    assert total == pytest.approx(region.area, rel=1e-9)
    assert shapely.union_all(cells).symmetric_difference(region).area <= 1e-9 * region.area
    tree = shapely.STRtree(cells)
    i, j = tree.query(cells, predicate="intersects")
    pairs = i < j
    overlap = shapely.area(shapely.intersection(cells[i[pairs]], cells[j[pairs]])).sum()
    assert overlap <= 1e-9 * region.area


def assert_nearest(cells: np.ndarray, xy: np.ndarray, samples: np.ndarray,
                   weights: np.ndarray | None = None) -> None:
    """Every sample lies in the cell of the site of least (power) distance; samples
    within rounding of a tie are left out."""
    w = np.zeros(len(xy)) if weights is None else weights
    d = ((samples[:, None, :] - xy[None, :, :]) ** 2).sum(axis=2) - w[None, :]
    order = np.argsort(d, axis=1)
    best, second = d[np.arange(len(d)), order[:, 0]], d[np.arange(len(d)), order[:, 1]]
    clear = second - best > 1e-6 * (np.abs(best) + 1.0)
    assert clear.mean() > 0.99
    owner = order[clear, 0]
    pts = shapely.points(samples[clear])
    assert (shapely.distance(cells[owner], pts) <= 1e-6).all()
    # and no other cell holds them (beyond its boundary)
    tree = shapely.STRtree(cells)
    s, c = tree.query(pts, predicate="contains_properly")
    assert (c == owner[s]).all()


# ---------------------------------------------------------------- the cells
def test_one_cell_per_point_with_index_attributes_and_crs(layer):
    cells = geo.voronoi(layer, AREA)
    assert isinstance(cells, gpd.GeoDataFrame)
    assert cells.index.equals(layer.index)
    assert list(cells.columns) == list(layer.columns)
    assert cells.geometry.name == layer.geometry.name
    assert (cells.drop(columns="geometry") == layer.drop(columns="geometry")).all().all()
    assert cells.crs == layer.crs
    assert set(cells.geom_type) <= {"Polygon", "MultiPolygon"}
    assert not cells.geometry.is_empty.any() and cells.geometry.is_valid.all()
    assert (layer.geom_type == "Point").all()              # the input is not modified


def test_cells_tile_the_boundary_and_hold_their_points(layer):
    cells = geo.voronoi(layer, AREA)
    geoms = np.asarray(cells.geometry.array, dtype=object)
    assert_tiles(geoms, AREA)
    assert shapely.contains(geoms, np.asarray(layer.geometry.array)).all()
    xy = shapely.get_coordinates(layer.geometry.array)
    assert_nearest(geoms, xy, sample_points(2000, seed=11))


def test_cells_match_geos_voronoi_polygons(layer):
    """The same cells as shapely.voronoi_polygons (GEOS) cut to the same area."""
    cells = np.asarray(geo.voronoi(layer, AREA).geometry.array, dtype=object)
    theirs = shapely.get_parts(shapely.voronoi_polygons(shapely.multipoints(layer.geometry.array),
                                                        extend_to=AREA))
    theirs = shapely.intersection(theirs, AREA)
    # match by the point each holds
    pts = np.asarray(layer.geometry.array)
    k = [int(np.flatnonzero(shapely.contains(theirs, p))[0]) for p in pts]
    diff = shapely.area(shapely.symmetric_difference(cells, theirs[k]))
    assert (diff <= 1e-9 * shapely.area(cells)).all()


def test_without_boundary_the_cells_fill_the_envelope(layer):
    cells = geo.voronoi(layer)
    xy = shapely.get_coordinates(layer.geometry.array)
    vor = cdt_plugin.delaunay(xy).voronoi()
    envelope = shapely.box(*vor.envelope())
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    grow = (hi - lo).max()
    assert envelope.bounds == pytest.approx((*(lo - grow), *(hi + grow)), abs=0)
    assert_tiles(np.asarray(cells.geometry.array, dtype=object), envelope)


def test_a_convex_cell_per_point_in_a_box(layer):
    box = shapely.box(X0 - 100, Y0 - 100, X0 + 1100, Y0 + 1100)
    cells = geo.voronoi(layer, box)
    assert (cells.geom_type == "Polygon").all()
    assert cells.area.to_numpy() == pytest.approx(cells.convex_hull.area.to_numpy(), rel=1e-12)
    assert_tiles(np.asarray(cells.geometry.array, dtype=object), box)


def test_square_grid_gives_square_cells():
    xs, ys = np.meshgrid(np.arange(4.0), np.arange(3.0))
    grid = gpd.GeoSeries(shapely.points(X0 + xs.ravel(), Y0 + ys.ravel()), crs=CRS)
    cells = geo.voronoi(grid, shapely.box(X0 - 0.5, Y0 - 0.5, X0 + 3.5, Y0 + 2.5))
    assert isinstance(cells, gpd.GeoDataFrame) and cells.crs == CRS
    assert (cells.area == 1.0).all()
    squares = shapely.buffer(grid.array, 0.5, cap_style="square")
    assert shapely.equals(cells.geometry.array, squares).all()


def test_a_cell_cut_in_pieces_by_the_boundary_is_a_multipolygon():
    # a C-shaped area; the point in its notch (outside it) has a convex cell that
    # the notch cuts in two (the point in the C's back takes the rest)
    c = shapely.box(0, 0, 10, 40).difference(shapely.box(2, 15, 10, 25))
    area = shapely.affinity.translate(c, X0, Y0)
    xy = np.array([(5, 2), (5, 38), (1, 20), (8, 20)]) + [X0, Y0]
    pts = gpd.GeoDataFrame({"v": [0, 1, 2, 3]}, geometry=shapely.points(xy), crs=CRS)
    cells = geo.voronoi(pts, area)
    assert cells.geom_type.tolist() == ["Polygon", "Polygon", "Polygon", "MultiPolygon"]
    assert len(cells.geometry.iloc[3].geoms) == 2
    assert_tiles(np.asarray(cells.geometry.array, dtype=object), area)


# ------------------------------------------------------------- boundary kinds
def test_boundary_as_a_layer_in_another_crs(layer, tmp_path):
    lonlat = gpd.GeoDataFrame({"id": [1]}, geometry=[AREA], crs=CRS).to_crs("EPSG:4326")
    expected = lonlat.to_crs(CRS).geometry.iloc[0]        # what the points' CRS sees
    path = tmp_path / "area.gpkg"
    lonlat.to_file(path, engine="pyogrio")
    for boundary in (lonlat, lonlat.geometry, path, str(path)):
        cells = geo.voronoi(layer, boundary)
        geoms = np.asarray(cells.geometry.array, dtype=object)
        assert_tiles(geoms, expected)
        assert cells.crs == CRS


def test_boundary_layer_is_the_union_of_its_polygons(layer):
    left = shapely.box(X0 - 50, Y0 - 50, X0 + 500, Y0 + 1050)
    right = shapely.box(X0 + 500, Y0 - 50, X0 + 1050, Y0 + 1050)
    parts = gpd.GeoDataFrame(geometry=[left, None, right, shapely.Polygon()], crs=CRS)
    cells = geo.voronoi(layer, parts)
    assert_tiles(np.asarray(cells.geometry.array, dtype=object), shapely.union(left, right))


def test_point_layer_as_a_path_and_as_a_geoseries(layer, tmp_path):
    path = tmp_path / "points.gpkg"
    layer.to_file(path, engine="pyogrio")
    from_file = geo.voronoi(path, AREA)
    from_series = geo.voronoi(layer.geometry, AREA)
    direct = geo.voronoi(layer, AREA)
    assert from_file["name"].tolist() == layer["name"].tolist()
    assert list(from_series.columns) == ["geometry"] and from_series.index.equals(layer.index)
    for other in (from_file, from_series):
        assert shapely.equals_exact(np.asarray(other.geometry.array), np.asarray(direct.geometry.array),
                                    0).all()


def test_points_with_z_give_2d_cells():
    pts = gpd.GeoSeries(shapely.points([(0, 0, 5), (4, 0, 6), (0, 4, 7), (4, 4, 8)]), crs=CRS)
    cells = geo.voronoi(pts, shapely.box(-1, -1, 5, 5))
    assert not cells.has_z.any() and (cells.area == 9.0).all()


def test_points_outside_the_boundary_keep_their_rows():
    pts = gpd.GeoDataFrame({"v": [1, 2, 3, 4]}, crs=CRS,
                           geometry=shapely.points([(1, 1), (3, 1), (2, 3), (50, 50)]))
    cells = geo.voronoi(pts, shapely.box(0, 0, 4, 4))
    assert cells["v"].tolist() == [1, 2, 3, 4]
    assert cells.geometry.iloc[3].is_empty and cells.geom_type.iloc[3] == "Polygon"
    assert cells.area.sum() == pytest.approx(16.0, rel=1e-12)


# ---------------------------------------------------------------- weights
def test_weighted_cells_are_the_power_diagram(layer):
    xy = shapely.get_coordinates(layer.geometry.array)
    w = layer["power"].to_numpy()
    by_name = geo.voronoi(layer, AREA, weights="power")
    by_array = geo.voronoi(layer, AREA, weights=w)
    by_list = geo.voronoi(layer, AREA, weights=w.tolist())
    geoms = np.asarray(by_name.geometry.array, dtype=object)
    for other in (by_array, by_list):
        assert shapely.equals_exact(np.asarray(other.geometry.array), geoms, 0).all()
    assert_tiles(geoms, AREA)
    assert_nearest(geoms, xy, sample_points(2000, seed=12), weights=w)
    assert not np.allclose(by_name.area, geo.voronoi(layer, AREA).area)


def test_a_submerged_point_gets_an_empty_cell():
    pts = gpd.GeoDataFrame({"w": [0.0, 0.0, 0.0, 0.0, -10.0]}, crs=CRS,
                           geometry=shapely.points([(0, 0), (4, 0), (0, 4), (4, 4), (2, 2)]))
    cells = geo.voronoi(pts, shapely.box(-1, -1, 5, 5), weights="w")
    assert cells.geometry.iloc[4].is_empty and cells.geom_type.iloc[4] == "Polygon"
    assert (cells.area.iloc[:4] == 9.0).all()
    unweighted = geo.voronoi(pts, shapely.box(-1, -1, 5, 5))
    assert unweighted.area.iloc[4] > 0


# ------------------------------------------------------------- duplicates
def test_duplicate_points_share_their_cell(layer):
    dup = gpd.GeoDataFrame(
        {"name": ["a", "b", "c", "d", "a again"]}, crs=CRS, index=[5, 6, 7, 8, 9],
        geometry=shapely.points([(X0, Y0), (X0 + 10, Y0), (X0, Y0 + 10), (X0 + 10, Y0 + 10), (X0, Y0)]))
    box = shapely.box(X0 - 5, Y0 - 5, X0 + 15, Y0 + 15)
    cells = geo.voronoi(dup, box)
    assert cells.geometry.loc[5].equals(cells.geometry.loc[9]) and cells.area.loc[9] == 100.0
    assert_tiles(np.asarray(cells.geometry.array[:4], dtype=object), box)
    # weighted: the heavier of two equal points keeps the cell, the lighter one is submerged
    weighted = geo.voronoi(dup, box, weights=[0, 0, 0, 0, 1])
    assert weighted.geometry.loc[5].is_empty and weighted.area.loc[9] > 100.0


# --------------------------------------------------------------- geographic
def test_geographic_points_warn_and_stay_on_the_globe():
    pts = gpd.GeoSeries(shapely.points([(-170, -80), (170, -80), (0, 80), (10, 0)]), crs="EPSG:4326")
    with pytest.warns(geo.GeographicCRSWarning, match="distances in degrees"):
        cells = geo.voronoi(pts)
    assert cells.total_bounds.tolist() == [-180.0, -90.0, 180.0, 90.0]
    assert shapely.area(cells.geometry.array).sum() == pytest.approx(360.0 * 180.0, rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geo.voronoi(pts.to_crs("EPSG:3857"), shapely.box(-1e7, -1e7, 1e7, 1e7))   # projected: quiet


# -------------------------------------------------------------- bad inputs
@pytest.mark.parametrize("geometry, what", [
    (shapely.LineString([(0, 0), (1, 1)]), "a LineString where a Point is expected"),
    (shapely.MultiPoint([(0, 0), (1, 1)]), "explode it first"),
    (None, "a missing geometry (None)"),
    (shapely.Point(), "an empty Point"),
    (shapely.box(0, 0, 1, 1), "a Polygon where a Point is expected"),
])
def test_a_row_that_is_not_a_point_is_named(geometry, what):
    pts = gpd.GeoDataFrame({"v": [1, 2, 3, 4]}, index=["a", "b", "c", "d"], crs=CRS,
                           geometry=[shapely.Point(0, 0), shapely.Point(5, 0), geometry,
                                     shapely.Point(0, 5)])
    with pytest.raises(cdt_plugin.InputShapeError, match="^feature c: ") as info:
        geo.voronoi(pts)
    assert what in str(info.value)
    assert info.value.index == 2 and info.value.feature == "c"


def test_many_bad_rows_are_counted():
    pts = gpd.GeoSeries([shapely.Point(0, 0), None, shapely.LineString([(0, 0), (1, 1)]), None])
    with pytest.raises(cdt_plugin.InputShapeError, match=r"feature 1: .*3 such rows: 3 feature\(s\): "
                                                         r"1 LineString, 2 None"):
        geo.voronoi(pts)


def test_an_empty_layer_is_an_error():
    empty = gpd.GeoDataFrame({"v": []}, geometry=gpd.GeoSeries([], crs=CRS))
    with pytest.raises(cdt_plugin.TooFewPointsError, match="empty"):
        geo.voronoi(empty)
    assert issubclass(cdt_plugin.TooFewPointsError, cdt_plugin.CDTError)


def test_collinear_points_are_an_error():
    pts = gpd.GeoSeries(shapely.points([(0, 0), (1, 1), (2, 2)]), crs=CRS)
    with pytest.raises(cdt_plugin.CollinearPointsError):
        geo.voronoi(pts)


def test_a_boundary_that_misses_the_points_is_a_clip_region_error(layer):
    far = shapely.box(X0 + 5000, Y0, X0 + 6000, Y0 + 1000)
    with pytest.raises(cdt_plugin.ClipRegionError, match="^boundary: .*none of the 60 points"):
        geo.voronoi(layer, far)
    with pytest.raises(cdt_plugin.ClipRegionError, match="none of the 60 points"):
        geo.voronoi(layer, gpd.GeoDataFrame(geometry=[far], crs=CRS).to_crs("EPSG:4326"))


@pytest.mark.parametrize("boundary, message", [
    (gpd.GeoDataFrame(geometry=[shapely.Point(0, 0)], index=["p"], crs=CRS),
     "boundary feature p is a Point"),
    (gpd.GeoDataFrame(geometry=[shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])], crs=CRS),
     "boundary feature 0 is invalid (Polygon is not valid: Self-intersection at (1.0, 1.0), on ring 0"),
    (gpd.GeoDataFrame(geometry=[None, shapely.Polygon()], crs=CRS), "has no polygon"),
    (shapely.LineString([(0, 0), (1, 1)]), "Polygon / MultiPolygon"),
    (shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]), "invalid"),
    (42, "expected a GeoDataFrame"),
])
def test_bad_boundaries_are_clip_region_errors(layer, boundary, message):
    with pytest.raises(cdt_plugin.ClipRegionError) as info:
        geo.voronoi(layer, boundary)
    assert message in str(info.value)


def test_bad_weights_are_named(layer):
    with pytest.raises(cdt_plugin.InputShapeError, match="'nope' is not a column .* name, count, power"):
        geo.voronoi(layer, weights="nope")
    with pytest.raises(cdt_plugin.InputShapeError, match="one weight per point is needed"):
        geo.voronoi(layer, weights=[1.0, 2.0])
    with pytest.raises(cdt_plugin.InputShapeError, match="weights must be numbers"):
        geo.voronoi(layer, weights="name")
    holes = layer.assign(power=layer["power"].where(layer.index != "s3"))
    with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match=r"^feature s3: weight \(column "
                                                                   r"'power'\) missing") as info:
        geo.voronoi(holes, weights="power")
    assert info.value.index == 3


def test_example_voronoi_diagrams(tmp_path):
    """examples/voronoi_diagrams.py (the README's picture) runs and its cells tile
    Africa's outline and the power diagram's square."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    from tests.support.corpus import corpus_dir

    if not (corpus_dir() / "gis" / "naturalearth_lowres.geojson").exists():
        pytest.skip("corpus not found")
    root = Path(__file__).resolve().parents[2]
    png = tmp_path / "voronoi.png"
    env = dict(os.environ, CDT_CORPUS=str(corpus_dir()),
               PYTHONPATH=str(root) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, str(root / "examples" / "voronoi_diagrams.py"), str(png)],
                          capture_output=True, text=True, env=env, timeout=300, cwd=root)
    assert proc.returncode == 0, proc.stderr
    assert "51 country points, 51 cells, cells cover 1.000000000 of the outline's area" in proc.stdout
    assert "cells cover 1.000000000000 of the square" in proc.stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
