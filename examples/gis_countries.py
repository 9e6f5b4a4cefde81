"""Natural Earth's 1:50m countries meshed at 25 degrees, continent by continent, plotted.

    python examples/gis_countries.py [out/gis_countries.png] [--quick]

Reads ``../shared/corpus/gis/ne_50m_admin_0_countries.geojson`` (or ``$CDT_CORPUS``)
with geopandas, and meshes each continent with ``cdt_plugin.adapters.geo.triangulate``
in an azimuthal equidistant projection centred on that continent (``project="aeqd"``:
angles and areas in metres, not in degrees), with a 25 degree minimum angle
(``min_angle=25``; triangles at input angles below 25 degrees are left alone) and
``repair=True`` (India's outline self-intersects). Countries split at the
antimeridian (Fiji, Russia) cannot be projected in one piece: they are meshed in
lon/lat. Every country of a continent is
meshed in ONE batch call; the triangles come back in lon/lat with the countries'
attributes, every input vertex with its original coordinates, bit for bit.

Prints the counts, the minimum angle measured in the meshing projection (in degree
space for the two antimeridian countries) and the
timings, and draws the triangles coloured by continent to a PNG (matplotlib).
``--quick`` (or ``CDT_EXAMPLE_QUICK=1``) meshes two small continents only.
"""
from __future__ import annotations

import os
import sys
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import shapely  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from cdt_plugin.adapters import geo  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
CORPUS = Path(os.environ.get("CDT_CORPUS", REPO_ROOT.parent / "shared" / "corpus"))
SOURCE = CORPUS / "gis" / "ne_50m_admin_0_countries.geojson"
QUICK_CONTINENTS = ("Oceania", "South America")
MIN_ANGLE = 25.0


def min_angles(V: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Smallest angle (degrees) of each triangle."""
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    out = []
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = q - p, r - p
        out.append(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(axis=1)))
    return np.degrees(np.min(out, axis=0))


def mesh_continents(countries, continents):
    """One batch call per continent, each in its own azimuthal equidistant projection.
    Countries split at the antimeridian (Fiji, Russia) cannot be projected in one
    piece (their parts meet in the projection): ``errors="skip"`` sets them aside and
    they are meshed in lon/lat instead."""
    frames, angles = [], []
    for name in continents:
        part = countries[countries["continent"] == name]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", geo.SkippedFeaturesWarning)
            mesh = geo.triangulate(part, output="mesh", project="aeqd", min_angle=MIN_ANGLE,
                                   repair=True, errors="skip")
        frames.append(mesh.to_geodataframe())
        angles.append(min_angles(mesh.batch.vertices, mesh.triangles))   # in metres, not degrees
        print(f"  {name:<24} {len(part) - len(mesh.errors):>3} countries  {len(mesh.triangles):>7,} triangles  "
              f"({mesh.mesh_crs.name})")
        if mesh.errors:
            skipped = part.iloc[sorted(mesh.errors)]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", geo.GeographicCRSWarning)
                lonlat = geo.triangulate(skipped, output="mesh", min_angle=MIN_ANGLE, repair=True)
            frames.append(lonlat.to_geodataframe())
            angles.append(min_angles(lonlat.vertices, lonlat.triangles))
            print(f"  {'':<24} {len(skipped):>3} countries  {len(lonlat.triangles):>7,} triangles  "
                  f"(in lon/lat: {', '.join(skipped['name'])}, split at the antimeridian)")
    return pd.concat(frames, ignore_index=True), np.concatenate(angles)


def plot(triangles, out: Path) -> None:
    corners = shapely.get_coordinates(triangles.geometry.array).reshape(-1, 4, 2)[:, :3]
    codes, names = pd.factorize(triangles["continent"])
    colours = plt.get_cmap("tab10")(codes % 10)
    fig, ax = plt.subplots(figsize=(14, 7.5))
    ax.add_collection(PolyCollection(corners, facecolors=colours, edgecolors="0.25", linewidths=0.05))
    ax.set_xlim(-180, 180)
    ax.set_ylim(-90, 90)
    ax.set_aspect("equal")
    ax.set_title(f"Natural Earth 1:50m countries: {len(triangles):,} triangles, min angle "
                 f"{MIN_ANGLE:g} deg in a local azimuthal equidistant projection per continent")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)


def main(argv) -> int:
    quick = "--quick" in argv or os.environ.get("CDT_EXAMPLE_QUICK") == "1"
    args = [a for a in argv[1:] if a != "--quick"]
    out = Path(args[0]) if args else REPO_ROOT / "out" / "gis_countries.png"
    countries = geo.read(SOURCE)
    continents = QUICK_CONTINENTS if quick else sorted(countries["continent"].unique())
    print(f"{SOURCE.name}: {len(countries)} countries, CRS {countries.crs.to_string()}")
    t0 = time.perf_counter()
    triangles, angles = mesh_continents(countries, continents)
    seconds = time.perf_counter() - t0
    below = int((angles < MIN_ANGLE).sum())
    print(f"{triangles['feature'].nunique()} countries, {len(triangles):,} triangles in "
          f"{seconds:.2f} s (first run: + numba compile or cache load)")
    print(f"min angle {angles.min():.3g} deg; {below:,} triangles ({100 * below / len(angles):.2f} %) "
          f"below {MIN_ANGLE:g} deg (refinement leaves triangles at input angles smaller than the "
          "bound alone)")
    plot(triangles, out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
