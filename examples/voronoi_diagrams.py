"""Voronoi cells of real points clipped to a real outline, and a power diagram, plotted.

    python examples/voronoi_diagrams.py [out/voronoi.png]

Left: Thiessen polygons of Africa's countries. Reads Natural Earth's low-resolution
countries (``../shared/corpus/gis/naturalearth_lowres.geojson``, or ``$CDT_CORPUS``),
takes a point inside each African country (``representative_point``) as a point layer
with the countries' attributes, and gives each point its Voronoi cell clipped to the
continent's outline with :func:`cdt_plugin.adapters.geo.voronoi`, in an equal-area
projection (Lambert azimuthal, centred on Africa), so that the cells are measured in
metres, not degrees. Each cell is the part of the continent nearer to its point than to
any other country's point.

Right: the power diagram of 300 random weighted points in the unit square
(:meth:`cdt_plugin.Triangulation.voronoi` of ``delaunay(points, weights)``): each point's
cell is where its power distance ``|x - p|**2 - w`` is least. Circles of radius
``sqrt(w)`` show the weights; a point whose circle is swallowed by its neighbours'
(submerged, Sec. 2.8) has an empty cell and is drawn as a cross.

Prints the counts and checks that the cells tile the clip regions.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import geopandas as gpd  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

import cdt_plugin  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
LAEA_AFRICA = "+proj=laea +lat_0=5 +lon_0=20 +datum=WGS84 +units=m +no_defs"


def corpus_file() -> Path:
    root = Path(os.environ.get("CDT_CORPUS", REPO_ROOT.parent / "shared" / "corpus"))
    return root / "gis" / "naturalearth_lowres.geojson"


def africa_cells() -> tuple[gpd.GeoDataFrame, gpd.GeoDataFrame, gpd.GeoSeries]:
    """(cells, points, outline) in the equal-area projection."""
    world = gpd.read_file(corpus_file())
    africa = world[world["continent"] == "Africa"].to_crs(LAEA_AFRICA)
    africa = africa.set_geometry(africa.make_valid())     # projecting bends two borders across
    outline = gpd.GeoSeries([africa.union_all()], crs=africa.crs)
    points = africa[["name", "pop_est"]].copy()
    points = gpd.GeoDataFrame(points, geometry=africa.representative_point(), crs=africa.crs)
    cells = geo.voronoi(points, boundary=outline)
    share = cells.area.sum() / outline.area.sum()
    print(f"Africa: {len(points)} country points, {len(cells)} cells, "
          f"cells cover {share:.9f} of the outline's area")
    return cells, points, outline


def power_diagram() -> tuple[cdt_plugin.Voronoi, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(4)
    points = rng.random((300, 2))
    weights = rng.random(300) ** 3 * 4e-3
    vor = cdt_plugin.delaunay(points, weights).voronoi(clip=(0.0, 0.0, 1.0, 1.0))
    sizes = np.diff(vor.cell_offsets)
    area = sum(abs(_area(vor.cell(i))) for i in range(len(vor.points)) if sizes[i])
    print(f"power diagram: {len(points)} points, {int((vor.point_region < 0).sum())} submerged "
          f"(empty cells), {len(vor.vertices)} Voronoi vertices, cells cover {area:.12f} of the square")
    return vor, points, weights


def _area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def draw(path: Path) -> None:
    cells, points, outline = africa_cells()
    vor, P, w = power_diagram()
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 6.5))
    cells.plot(ax=left, column="pop_est", cmap="YlGnBu", edgecolor="k", linewidth=0.4, legend=False)
    outline.boundary.plot(ax=left, color="k", linewidth=0.8)
    points.plot(ax=left, color="crimson", markersize=6)
    left.set_title("Thiessen polygons of Africa's countries\n(geo.voronoi, clipped to the continent)")
    left.set_axis_off()

    rings = [vor.cell(i) for i in range(len(vor.points)) if len(vor.cell(i))]
    colours = plt.cm.Pastel1(np.arange(len(rings)) % 9)
    right.add_collection(PolyCollection(rings, facecolors=colours, edgecolors="k", linewidths=0.4))
    kept = vor.point_region >= 0
    for (x, y), r in zip(P[kept], np.sqrt(w[kept])):
        right.add_patch(plt.Circle((x, y), r, fill=False, color="tab:blue", linewidth=0.5))
    right.plot(P[kept, 0], P[kept, 1], ".", color="tab:blue", markersize=3)
    right.plot(P[~kept, 0], P[~kept, 1], "x", color="crimson", markersize=4)
    right.set_xlim(0, 1)
    right.set_ylim(0, 1)
    right.set_aspect("equal")
    right.set_title("Power diagram of 300 weighted points\n(circles: radius sqrt(w); x: submerged)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=80)
    print(f"wrote {path}")


if __name__ == "__main__":
    draw(Path(sys.argv[1]) if len(sys.argv) > 1 else REPO_ROOT / "examples" / "voronoi.png")
