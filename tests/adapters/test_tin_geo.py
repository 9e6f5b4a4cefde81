"""Terrain from spot heights and breaklines (issue #19, part 4): geo.tin and geo.grid.

The TINs are checked with the independent exact checker (a constrained Delaunay
triangulation of the points' (x, y) with the breaklines as segments), their
heights against the input, and the grids against the plane or ridge the data
were sampled from.
"""
from __future__ import annotations

import numpy as np
import pytest

geopandas = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")

from cdt_plugin.adapters import geo
from checker import check_triangulation

from cdt_plugin import CDTError, InputShapeError


def _plane(x, y):
    return 2 * x + 3 * y + 1


def _corners(surface):
    return shapely.get_coordinates(surface.geometry.array, include_z=True).reshape(-1, 4, 3)[:, :3]


def _check(surface, segments_xy=()):
    """Exact check of the TIN's (x, y) triangles; returns vertices, triangles."""
    C = _corners(surface)
    xy, inv = np.unique(C[:, :, :2].reshape(-1, 2), axis=0, return_inverse=True)
    T = inv.reshape(-1, 3)
    index = {tuple(p): i for i, p in enumerate(xy.tolist())}
    S = np.array([[index[tuple(a)], index[tuple(b)]] for a, b in segments_xy], np.int64).reshape(-1, 2)
    rep = check_triangulation(xy, T, segments=S if len(S) else None, domain="hull")
    assert rep.ok, rep.problems[:3]
    return xy, T


def test_plane_from_a_point_layer():
    rng = np.random.default_rng(0)
    xy = rng.uniform(0, 100, (300, 2))
    pts = geopandas.GeoDataFrame({"h": _plane(xy[:, 0], xy[:, 1])},
                                 geometry=shapely.points(xy), crs="EPSG:32631")
    surface = geo.tin(pts, z="h")
    assert surface.crs == pts.crs and surface.has_z.all()
    C = _corners(surface)
    assert np.array_equal(C[:, :, 2], _plane(C[:, :, 0], C[:, :, 1]))     # the input heights exactly
    _check(surface)
    for method in ("linear", "natural"):
        dem, transform = geo.grid(surface, 5.0, method)
        rows, cols = dem.shape
        col, row = np.meshgrid(np.arange(cols) + 0.5, np.arange(rows) + 0.5)
        x, y = transform * (col, row)
        inside = ~np.isnan(dem)
        assert inside.mean() > 0.8
        assert np.allclose(dem[inside], _plane(x, y)[inside], rtol=1e-12)
        hull = shapely.convex_hull(shapely.multipoints(xy))
        assert not shapely.contains_xy(hull, x[~inside], y[~inside]).any()


def test_breakline_ridge_is_kept():
    xyz = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], float)
    ridge = shapely.LineString([(1, 5, 7), (5, 5.5, 9), (9, 5, 7)])
    surface = geo.tin(xyz, breaklines=[ridge])
    _check(surface, [((1, 5), (5, 5.5)), ((5, 5.5), (9, 5))])
    dem, _ = geo.grid(surface, 0.5, bounds=(1, 5, 5, 5.5))
    assert dem.shape == (1, 8) and not np.isnan(dem).any()
    # on the ridge itself: its own heights (linear between its vertices)
    line = np.array([[3.0, 5.25], [5.0, 5.5], [7.0, 5.25]])
    from cdt_plugin import Triangulation
    C = _corners(surface)
    xy, inv = np.unique(C[:, :, :2].reshape(-1, 2), axis=0, return_inverse=True)
    h = np.zeros(len(xy))
    h[inv] = C[:, :, 2].reshape(-1)
    tri = Triangulation.from_triangles(xy, inv.reshape(-1, 3))
    assert np.allclose(tri.interpolate(h, line), [8.0, 9.0, 8.0])


def test_crossing_breaklines_get_heights_along_the_first():
    xyz = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], float)
    a = shapely.LineString([(1, 1, 2), (9, 9, 10)])
    b = shapely.LineString([(1, 9, 5), (9, 1, 5)])
    C = _corners(geo.tin(xyz, breaklines=[a, b]))
    at = (C[:, :, 0] == 5) & (C[:, :, 1] == 5)
    assert at.any() and (C[:, :, 2][at] == 6).all()


def test_boundary_clips_and_gets_heights():
    rng = np.random.default_rng(1)
    xy = rng.uniform(0, 10, (200, 2))
    xyz = np.column_stack([xy, _plane(xy[:, 0], xy[:, 1])])
    xyz = np.vstack([xyz, [[0, 0, _plane(0, 0)], [10, 0, _plane(10, 0)], [10, 10, _plane(10, 10)],
                           [0, 10, _plane(0, 10)]]])
    area = shapely.Polygon([(2, 2), (8, 2), (8, 8), (2, 8)], [[(4, 4), (6, 4), (6, 6), (4, 6)]])
    surface = geo.tin(xyz, boundary=area)
    C = _corners(surface)
    assert np.allclose(C[:, :, 2], _plane(C[:, :, 0], C[:, :, 1]))
    assert shapely.union_all(surface.geometry.array).area == pytest.approx(area.area, rel=1e-12)
    dem, transform = geo.grid(surface, 0.5)
    rows, cols = dem.shape
    col, row = np.meshgrid(np.arange(cols) + 0.5, np.arange(rows) + 0.5)
    x, y = transform * (col, row)
    assert (np.isnan(dem) == ~shapely.contains_xy(area, x, y)).all()
    with pytest.raises(CDTError, match="outside"):
        geo.tin(xyz, boundary=shapely.box(-1, -1, 5, 5))


def test_geotiff_round_trip(tmp_path):
    rasterio = pytest.importorskip("rasterio")
    xyz = np.array([[0, 0, 0], [4, 0, 8], [4, 4, 12], [0, 4, 4]], float)
    pts = geopandas.GeoDataFrame(geometry=shapely.points(xyz), crs="EPSG:3857")
    dem, transform = geo.grid(geo.tin(pts), 1.0, path=tmp_path / "dem.tif")
    with rasterio.open(tmp_path / "dem.tif") as src:
        assert np.array_equal(src.read(1), dem)
        assert tuple(src.transform)[:6] == tuple(transform)[:6]
        assert src.crs.to_epsg() == 3857


def test_bad_input_is_named():
    xyz = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    with pytest.raises(CDTError, match="rows 0 and 3"):
        geo.tin(np.vstack([xyz, [[0, 0, 1]]]))
    with pytest.raises(CDTError, match="no heights"):
        geo.tin(xyz[:, :2])
    with pytest.raises(InputShapeError, match="one height per point"):
        geo.tin(xyz[:, :2], z=[1, 2])
    pts = geopandas.GeoDataFrame({"h": [1, 2, 3]}, geometry=shapely.points(xyz[:, :2]))
    with pytest.raises(CDTError, match="no such column"):
        geo.tin(pts, z="height")
    with pytest.raises(CDTError, match="has no Z"):
        geo.tin(xyz, breaklines=[shapely.LineString([(0, 0), (1, 1)])])
    surface = geo.tin(xyz)
    with pytest.raises(CDTError, match="resolution"):
        geo.grid(surface, 0)
    with pytest.raises(CDTError, match="method"):
        geo.grid(surface, 1.0, method="cubic")
    assert len(geo.tin(pts, z="h")) == 1
