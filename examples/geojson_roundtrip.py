"""A GeoJSON round trip through the command line: features in, triangles with
attributes out, read back with geopandas.

    python examples/geojson_roundtrip.py [out_dir]

Writes ``parcels.geojson`` (``geo.write_geojson``): three features in UTM zone 33N
(EPSG:32633) at real UTM magnitudes (x ~ 5e5 m, y ~ 5.3e6 m): a field with a pond
(a hole), a two-part MultiPolygon and a sloping plot with Z on its vertices. Runs

    python -m cdt_plugin mesh parcels.geojson -o triangles.geojson --max-area 200

(the ``cdt-plugin`` command) in a subprocess, reads ``triangles.geojson`` back and
prints, per feature, the triangle count, the area check, whether the attributes
came along and whether every input vertex came back with its exact coordinates.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import geopandas as gpd
import numpy as np
import shapely

from cdt_plugin.adapters import geo

REPO_ROOT = Path(__file__).resolve().parent.parent
X0, Y0 = 500_000.0, 5_300_000.0          # UTM zone 33N, near Vienna


def parcels() -> gpd.GeoDataFrame:
    field = shapely.Polygon([(0, 0), (120, 0), (130, 70), (60, 95), (-5, 60)],
                            [[(40, 30), (70, 28), (75, 50), (45, 55)]])
    allotments = shapely.MultiPolygon([shapely.box(150, 0, 190, 30), shapely.box(150, 40, 175, 80)])
    slope = shapely.Polygon([(x, y, 200.0 + 0.05 * x + 0.1 * y)
                             for x, y in [(210, 0), (260, 10), (250, 60), (205, 50)]])
    geometry = [shapely.transform(g, lambda c: c + [X0, Y0], include_z=False) if not g.has_z else
                shapely.transform(g, lambda c: c + [X0, Y0, 0.0], include_z=True)
                for g in (field, allotments, slope)]
    return gpd.GeoDataFrame({"parcel": ["field", "allotments", "slope"], "owner": ["A", "B", "C"],
                             "hectares": [shapely.area(g) / 1e4 for g in geometry]},
                            geometry=geometry, crs="EPSG:32633")


def main(argv) -> int:
    out_dir = Path(argv[1]) if len(argv) > 1 else REPO_ROOT / "out"
    out_dir.mkdir(parents=True, exist_ok=True)
    source, target = out_dir / "parcels.geojson", out_dir / "triangles.geojson"
    layer = parcels()
    geo.write_geojson(layer, source)          # exact coordinates (GDAL's writer trims digits)
    command = [sys.executable, "-m", "cdt_plugin", "mesh", str(source), "-o", str(target),
               "--max-area", "200", "--no-progress"]
    print("$", " ".join(["cdt-plugin"] + command[3:]))
    done = subprocess.run(command, capture_output=True, text=True)
    print(done.stdout.strip() or done.stderr.strip())
    if done.returncode != 0:
        return done.returncode

    triangles = gpd.read_file(target)
    print(f"read back: {len(triangles)} triangles, CRS {triangles.crs.to_string()}, "
          f"columns {list(triangles.columns)}")
    areas = shapely.area(triangles.geometry.array)
    given = {tuple(p) for p in shapely.get_coordinates(layer.geometry.array).tolist()}
    got = {tuple(p) for p in shapely.get_coordinates(triangles.geometry.array).tolist()}
    slope = triangles.geometry.array[(triangles["parcel"] == "slope").to_numpy()]
    given_z = {tuple(p) for p in shapely.get_coordinates(layer.geometry.iloc[2], include_z=True).tolist()}
    got_z = {tuple(p) for p in shapely.get_coordinates(slope, include_z=True).tolist()}
    for i, row in layer.iterrows():
        mine = (triangles["feature"] == i).to_numpy()
        print(f"  {row['parcel']:<11} {int(mine.sum()):>4} triangles, area {areas[mine].sum():9.2f} m2 "
              f"(polygon {row.geometry.area:9.2f}), 3D: {bool(triangles.geometry[mine].has_z.all())}")
    kept = triangles.groupby("feature")[["parcel", "owner", "hectares"]].first()
    print("attributes kept:", kept.reset_index(drop=True).equals(layer.drop(columns="geometry")))
    print("areas match:", bool(np.allclose(np.bincount(triangles["position"], areas), layer.area,
                                           rtol=1e-12)))
    print("input vertices exact:", given <= got, "(and their z:", given_z <= got_z, end=")\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
