"""``cdt-plugin tin``: spot heights and breaklines to a TIN layer or a DEM grid."""
from __future__ import annotations

import numpy as np
import pytest

geopandas = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")

from cdt_plugin.adapters import geo

from cdt_plugin import cli


@pytest.fixture
def files(tmp_path):
    rng = np.random.default_rng(3)
    xy = np.vstack([rng.uniform(0, 100, (150, 2)), [[0, 0], [100, 0], [100, 100], [0, 100]]])
    pts = geopandas.GeoDataFrame({"h": xy[:, 0] + 2 * xy[:, 1]}, geometry=shapely.points(xy),
                                 crs="EPSG:32632")
    pts.to_file(tmp_path / "points.gpkg")
    ridge = shapely.LineString([(10, 50, 150), (90, 50, 150)])      # a level ridge across the plane
    geopandas.GeoDataFrame(geometry=[ridge], crs="EPSG:32632").to_file(tmp_path / "lines.gpkg")
    return tmp_path


def test_grid_as_npy_and_layer(files, capsys):
    out = files / "dem.npy"
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "h", "--breaklines", str(files / "lines.gpkg"),
                     "-o", str(out), "--resolution", "10", "--method", "natural"]) == 0
    assert "10 x 10 cells" in capsys.readouterr().out
    dem = np.load(out)
    x = 5 + 10 * np.arange(10)
    y = 95 - 10 * np.arange(10)
    want = x[None, :] + 2 * y[:, None]
    # the ridge (10..90, 50) at height 150 is not on the plane 110..230 except at x=50: compare away from it
    far = np.abs(y[:, None] - 50) > 15
    assert np.allclose(dem[np.broadcast_to(far, dem.shape)], want[np.broadcast_to(far, dem.shape)], rtol=1e-9)
    layer = files / "tin.gpkg"
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "h", "-o", str(layer)]) == 0
    back = geopandas.read_file(layer)
    assert back.has_z.all() and back.crs.to_epsg() == 32632
    assert np.allclose(geo.grid(back, 10.0)[0], want, rtol=1e-9)


def test_geotiff(files, capsys):
    rasterio = pytest.importorskip("rasterio")
    out = files / "dem.tif"
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "h", "-o", str(out), "--resolution", "25"]) == 0
    with rasterio.open(out) as src:
        assert src.shape == (4, 4) and src.crs.to_epsg() == 32632
        assert src.read(1)[0, 0] == pytest.approx(12.5 + 2 * 87.5)


def test_errors(files, capsys):
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "h", "-o", str(files / "dem.npy")]) == 1
    assert "needs --resolution" in capsys.readouterr().err
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "nope", "-o", str(files / "t.gpkg")]) == 1
    assert "no such column" in capsys.readouterr().err
    assert cli.main(["tin", str(files / "points.gpkg"), "--z", "h", "-o", str(files / "t.png")]) == 1
    assert "tin writes a layer" in capsys.readouterr().err
