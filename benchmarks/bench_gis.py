"""GIS polygon meshing at scale: polygons per second, batch path against the peers.

Workload G1: the Natural Earth 1:50m countries (``../shared/corpus/gis/
ne_50m_admin_0_countries.geojson``), made valid with ``shapely.make_valid``, split
into their Polygons (1,618) and replicated to at least 100,000 polygons (about 6
million vertices). Every implementation meshes the same polygons:

* ``cdt_plugin triangulate_batch``: the compiled batch path
  (:func:`cdt_plugin.adapters.shapely.triangulate_batch`, GEOS validity check
  included), flat arrays out;
* ``cdt_plugin geo.triangulate``: the same, to a GeoDataFrame of triangle Polygons
  carrying the feature's columns;
* ``cdt_plugin triangulate_dask``: :func:`cdt_plugin.adapters.geo.triangulate_dask`
  on a ``dask.distributed.LocalCluster`` with 1 and with 2 worker processes (one
  thread each; 16 partitions), computed to one GeoDataFrame in the client;
* ``cdt_plugin loop``: a Python loop of :func:`cdt_plugin.adapters.shapely.triangulate`,
  one call per polygon (what the batch path replaces);
* ``shapely.constrained_delaunay_triangles`` (GEOS), vectorised over the array;
* ``trimesh earcut``: a loop of ``trimesh.creation.triangulate_polygon(p, engine="earcut")``.

Each implementation runs once after a warm-up on a small input (numba compiled and
cached, imports done), in this one process (the dask workers are separate processes
started before timing). The table gives seconds, polygons per second and the speed-up
over GEOS measured in the same run.

Usage (from the repository root)::

    python benchmarks/bench_gis.py                    # ~3 minutes on 2 cores
    python benchmarks/bench_gis.py --write-readme     # and regenerate the README table
    python benchmarks/bench_gis.py --polygons 20000   # a quicker, smaller run
"""
from __future__ import annotations

import argparse
import gc
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DATA = ROOT.parent / "shared" / "corpus" / "gis" / "ne_50m_admin_0_countries.geojson"


def polygons(target: int):
    """The G1 polygons as a GeoDataFrame (``name``, ``copy`` columns), EPSG:4326."""
    import geopandas as gpd
    import shapely
    df = gpd.read_file(DATA)
    parts = shapely.get_parts(shapely.make_valid(df.geometry.values))
    keep = shapely.get_type_id(parts) == 3
    parts = parts[keep]
    copies = -(-target // len(parts))
    geoms = np.tile(parts, copies)
    return gpd.GeoDataFrame({"copy": np.repeat(np.arange(copies), len(parts))},
                            geometry=geoms, crs=df.crs)


def timed(fn):
    gc.collect()
    gc.disable()
    try:
        t0 = time.perf_counter()
        out = fn()
        return time.perf_counter() - t0, out
    finally:
        gc.enable()


def run_all(frame, workers: list[int]):
    import shapely
    import trimesh
    from cdt_plugin.adapters import geo
    from cdt_plugin.adapters.shapely import triangulate, triangulate_batch

    geoms = np.asarray(frame.geometry.values, dtype=object)
    small = geoms[:50]
    rows = []

    def add(name, seconds, triangles, note=""):
        rows.append({"name": name, "seconds": seconds, "polygons": len(geoms),
                     "triangles": triangles, "note": note})
        print(f"{name:45s} {seconds:8.2f} s  {len(geoms) / seconds:10.0f} polygons/s  "
              f"{triangles} triangles", file=sys.stderr)

    triangulate_batch(small)
    s, b = timed(lambda: triangulate_batch(geoms))
    add("cdt_plugin triangulate_batch (arrays)", s, len(b.triangles),
        f"{b.stats['fallback']} of {len(geoms)} polygons took the general route")
    del b

    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # degree space is fine for a plain CDT
        geo.triangulate(frame.iloc[:50], progress=False)
        s, out = timed(lambda: geo.triangulate(frame, progress=False))
    add("cdt_plugin geo.triangulate (GeoDataFrame)", s, len(out))
    del out

    for n in workers:
        s, count = run_dask(frame, n)
        add(f"cdt_plugin triangulate_dask, {n} worker{'s' if n > 1 else ''}", s, count)

    for p in small:
        triangulate(p)
    s, count = timed(lambda: sum(len(triangulate(p).triangles) for p in geoms))
    add("cdt_plugin loop of triangulate() calls", s, count)

    shapely.constrained_delaunay_triangles(small)
    s, out = timed(lambda: shapely.constrained_delaunay_triangles(geoms))
    add("shapely.constrained_delaunay_triangles (GEOS)", s,
        int(shapely.get_num_geometries(out).sum()))
    del out

    trimesh.creation.triangulate_polygon(small[0], engine="earcut")
    s, count = timed(lambda: sum(len(trimesh.creation.triangulate_polygon(p, engine="earcut")[1])
                                 for p in geoms))
    add("trimesh earcut loop", s, count)
    return rows


def run_dask(frame, n_workers: int):
    import warnings

    import dask_geopandas
    from dask.distributed import Client, LocalCluster
    from cdt_plugin.adapters import geo

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            warm = dask_geopandas.from_geopandas(frame.iloc[:200], npartitions=2 * n_workers)
            geo.triangulate_dask(warm).compute()
            ddf = dask_geopandas.from_geopandas(frame, npartitions=16)
            s, out = timed(lambda: geo.triangulate_dask(ddf).compute())
    return s, len(out)


def render(rows, n_polygons: int, n_vertices: int) -> str:
    import numba
    geos = next(r for r in rows if r["name"].startswith("shapely"))
    lines = [
        f"GIS batch meshing (`python benchmarks/bench_gis.py --write-readme`; {platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}, numba {numba.__version__}): "
        f"Natural Earth 1:50m countries split into polygons and replicated to {n_polygons:,} "
        f"polygons ({n_vertices:,} vertices), one timed run each after a warm-up.",
        "",
        "| implementation | seconds | polygons / s | vs GEOS | triangles |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        rate = r["polygons"] / r["seconds"]
        lines.append(f"| {r['name']} | {r['seconds']:.2f} | {rate:,.0f} | "
                     f"{geos['seconds'] / r['seconds']:.2f}x | {r['triangles']:,} |")
    notes = [r["note"] for r in rows if r["note"]]
    if notes:
        lines += [""] + [f"* {n}." for n in notes]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--polygons", type=int, default=100_000)
    ap.add_argument("--workers", type=int, nargs="*", default=[1, 2])
    ap.add_argument("--write-readme", action="store_true")
    ap.add_argument("--out", default=str(HERE / "results" / "gis.md"))
    args = ap.parse_args(argv)
    import shapely
    frame = polygons(args.polygons)
    n_vertices = int(shapely.get_num_coordinates(frame.geometry.values).sum())
    rows = run_all(frame, args.workers)
    table = render(rows, len(frame), n_vertices)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(table)
    print(table)
    if args.write_readme:
        sys.path.insert(0, str(HERE))
        from harness import replace_between_markers
        readme = ROOT / "README.md"
        readme.write_text(replace_between_markers(readme.read_text(), "gis", table))
    return 0


if __name__ == "__main__":
    sys.exit(main())
