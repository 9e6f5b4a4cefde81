"""Extruded city blocks, drawn to PNG.

    python examples/city_blocks.py [out/city_blocks.png]

Four city blocks of building footprints in UTM coordinates (EPSG:32633): plain
rectangles, L shapes, courtyard blocks (a hole), a block whose two courtyards touch
at a corner (a pinch point) and a building in two parts (a MultiPolygon), each
with a ``height`` and a ``base`` column. :func:`cdt_plugin.adapters.geo.extrude`
makes one watertight solid per footprint; the script checks every solid
(watertight, volume = area x height), prints the totals and draws the merged mesh
with matplotlib (``mplot3d.art3d.Poly3DCollection``, coloured by height, shaded by
the faces' normals).
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import geopandas
import matplotlib.pyplot as plt
import numpy as np
import shapely
import trimesh
from cdt_plugin.adapters import geo
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

REPO_ROOT = Path(__file__).resolve().parent.parent
X0, Y0 = 500_000.0, 5_000_000.0


def block(x: float, y: float, kind: int) -> list[shapely.Geometry]:
    """The footprints of one 60 x 60 m block at (x, y)."""
    if kind == 0:            # four rectangles
        return [shapely.box(x + i, y + j, x + i + 26, y + j + 26) for i in (0, 32) for j in (0, 32)]
    if kind == 1:            # a courtyard block and an L
        yard = shapely.box(x, y, x + 60, y + 28).difference(shapely.box(x + 8, y + 8, x + 52, y + 20))
        ell = shapely.Polygon([(x, y + 34), (x + 60, y + 34), (x + 60, y + 44), (x + 12, y + 44),
                               (x + 12, y + 60), (x, y + 60)])
        return [yard, ell]
    if kind == 2:            # two courtyards touching at a corner: a pinch point
        return [shapely.Polygon([(x, y), (x + 60, y), (x + 60, y + 60), (x, y + 60)],
                                [[(x + 8, y + 8), (x + 8, y + 30), (x + 30, y + 30), (x + 30, y + 8)],
                                 [(x + 30, y + 30), (x + 30, y + 52), (x + 52, y + 52), (x + 52, y + 30)]])]
    return [shapely.MultiPolygon([shapely.box(x, y, x + 25, y + 60),      # one building, two parts
                                  shapely.box(x + 35, y, x + 60, y + 60)])]


def city() -> geopandas.GeoDataFrame:
    footprints = [f for k in range(4) for f in block(X0 + 80 * (k % 2), Y0 + 80 * (k // 2), k)]
    rng = np.random.default_rng(7)
    return geopandas.GeoDataFrame(
        {"height": np.round(rng.uniform(8, 40, len(footprints)), 1),
         "base": np.round(rng.uniform(0, 3, len(footprints)), 1)},
        geometry=footprints, crs="EPSG:32633")


def draw(solids, heights, out: Path) -> None:
    """The solids, each coloured by its height and shaded by its faces' normals; cut
    into small triangles for the drawing only (matplotlib sorts whole faces by depth)."""
    fig = plt.figure(figsize=(6.4, 4.8), dpi=90)
    ax = fig.add_subplot(projection="3d")
    light = np.array([0.45, -0.35, 0.82]) / np.linalg.norm([0.45, -0.35, 0.82])
    polygons, colours = [], []
    for mesh, h in zip(solids, heights):
        V, F = trimesh.remesh.subdivide_to_size(mesh.vertices - [X0, Y0, 0.0], mesh.faces, 3.0)
        normals = trimesh.triangles.normals(V[F])[0]
        shade = 0.45 + 0.55 * np.clip(normals @ light, 0, 1)
        colours.append(plt.cm.viridis((h - 5) / 40)[:3] * shade[:, None])
        polygons.append(V[F])
    ax.add_collection3d(Poly3DCollection(np.concatenate(polygons), facecolors=np.concatenate(colours),
                                         edgecolors="none", linewidths=0, antialiased=False))
    ax.set(xlim=(0, 140), ylim=(0, 140), zlim=(0, 60), xlabel="x (m)", ylabel="y (m)",
           zlabel="z (m)")
    ax.set_box_aspect((140, 140, 60))
    ax.view_init(elev=32, azim=-58)
    ax.set_title("Footprints extruded by geo.extrude: watertight solids")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def main(argv: list[str]) -> int:
    out = Path(argv[1]) if len(argv) > 1 else REPO_ROOT / "out" / "city_blocks.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    layer = city()
    solids = geo.extrude(layer, height="height", base="base")
    for mesh, footprint, h in zip(solids, layer.geometry, layer["height"]):
        moved = mesh.copy()
        moved.apply_translation(-mesh.vertices[0])          # volume sums near the origin
        assert mesh.is_watertight and abs(moved.volume - footprint.area * h) <= 1e-9 * moved.volume
    merged = geo.extrude(layer, height="height", base="base", output="merged")
    print(f"{len(solids)} solids, {len(merged.faces):,} triangles, all watertight, "
          f"{float((layer.area * layer['height']).sum()):,.0f} m3")
    draw(solids, layer["height"], out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
