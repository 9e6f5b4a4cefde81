"""GIS polygon meshing at scale: polygons per second, batch path against the peers.

Workload G1: the Natural Earth 1:50m countries (``../shared/corpus/gis/
ne_50m_admin_0_countries.geojson``), made valid with ``shapely.make_valid``, split
into their Polygons (1,618) and replicated to at least 100,000 polygons (about 6
million vertices). Every implementation meshes the same polygons:

* ``cdt_plugin triangulate_batch``: the compiled batch path
  (:func:`cdt_plugin.adapters.shapely.triangulate_batch`, GEOS validity check
  included), flat arrays out, on 1 thread and on every usable core (``workers=``);
* ``cdt_plugin geo.triangulate``: the same, to a GeoDataFrame of triangle Polygons
  carrying the feature's columns (1 thread, all cores), to the same rows as a
  ``pyarrow.Table`` with GeoArrow polygons (``output="geoarrow"``) and to the flat
  arrays of a ``GeoMesh`` (``output="mesh"``), neither with a polygon object per
  triangle;
* ``cdt_plugin triangulate_dask``: :func:`cdt_plugin.adapters.geo.triangulate_dask`
  with 16 partitions: on Dask's threaded scheduler with 1 and 2 threads, computed
  to one GeoDataFrame; on a ``dask.distributed.LocalCluster`` with 1 and 2 worker
  processes (one thread each), the input partitions persisted on the workers
  before timing (as a layer read by the workers would be; sending them from the
  client with every compute cost about 4 s more on the 100k workload) and the
  triangles counted on the workers (gathering millions of Polygons into the
  client pickles each one: about 50 s here, more than the meshing);
* ``cdt_plugin loop``: a Python loop of :func:`cdt_plugin.adapters.shapely.triangulate`,
  one call per polygon (what the batch path replaces);
* ``shapely.constrained_delaunay_triangles`` (GEOS), vectorised over the array;
* ``trimesh earcut``: a loop of ``trimesh.creation.triangulate_polygon(p, engine="earcut")``.

The small layer (issue #47): the same polygons once each, not replicated, meshed by
``geo.triangulate`` (all cores and 1 thread) against a Python loop of shapely's own
``constrained_delaunay_triangles``, one call per polygon (and GEOS's call on the
array), in interleaved runs (``--small-rounds``, the least time of each).

Each implementation runs once after a warm-up on a small input (numba compiled and
cached, imports done), in this one process (the dask workers are separate processes
started before timing). The table gives seconds, polygons per second and the speed-up
over GEOS and the ratio to earcut's time, measured in the same run. A second
table times the GeoJSON writer against ``json.dump`` of geopandas' feature dicts.

Usage (from the repository root)::

    python benchmarks/bench_gis.py                    # ~6 minutes on 2 cores
    python benchmarks/bench_gis.py --write-readme     # and the README summary rows
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

from cdt_plugin.parallel import available_cores

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

    cores = available_cores()
    triangulate_batch(small)
    for threads in sorted({1, cores}):
        s, b = timed(lambda: triangulate_batch(geoms, workers=threads))
        add(f"cdt_plugin triangulate_batch (arrays), {_threads(threads)}", s, len(b.triangles),
            f"{b.stats['fallback']} of {len(geoms)} polygons took the general route"
            if threads == 1 else "")
        del b

    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # degree space is fine for a plain CDT
        geo.triangulate(frame.iloc[:50], progress=False)
        geo.triangulate(frame.iloc[:50], progress=False, output="geoarrow")   # (pyarrow imported)
        for threads in sorted({1, cores}):
            s, out = timed(lambda: geo.triangulate(frame, progress=False, workers=threads))
            add(f"cdt_plugin geo.triangulate (GeoDataFrame), {_threads(threads)}", s, len(out))
            del out
        s, out = timed(lambda: geo.triangulate(frame, progress=False, output="geoarrow"))
        add(f"cdt_plugin geo.triangulate (output='geoarrow'), {_threads(cores)}", s, out.num_rows)
        del out
        s, out = timed(lambda: geo.triangulate(frame, progress=False, output="mesh"))
        add(f"cdt_plugin geo.triangulate (output='mesh'), {_threads(cores)}", s, len(out))
        del out

    for n in workers:
        s, count = run_dask_threads(frame, n)
        add(f"cdt_plugin triangulate_dask, threaded scheduler, {_threads(n)}", s, count)
    for n in workers:
        s, count = run_dask(frame, n)
        add(f"cdt_plugin triangulate_dask, distributed, {n} worker process{'es' if n > 1 else ''} "
            "(input on the workers, triangles counted there)", s, count)

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


def _threads(n: int) -> str:
    return f"{n} thread{'s' if n > 1 else ''}"


def small_layer_rows(frame, rounds: int = 7):
    """The small layer (the Natural Earth polygons, not replicated): geo.triangulate
    against a Python loop of shapely's own ``constrained_delaunay_triangles``, one
    call per polygon, as a script that meshes a layer without this package does
    (and GEOS's vectorised call); interleaved rounds, the least time of each."""
    import warnings

    import shapely
    from cdt_plugin.adapters import geo

    geoms = np.asarray(frame.geometry.values, dtype=object)
    cores = available_cores()
    runs = {
        f"cdt_plugin geo.triangulate (GeoDataFrame), {_threads(cores)}":
            lambda: len(geo.triangulate(frame, progress=False)),
        "cdt_plugin geo.triangulate (GeoDataFrame), 1 thread":
            lambda: len(geo.triangulate(frame, progress=False, workers=1)),
        "loop of shapely.constrained_delaunay_triangles (GEOS), one call per polygon":
            lambda: sum(len(shapely.constrained_delaunay_triangles(p).geoms) for p in geoms),
        "shapely.constrained_delaunay_triangles (GEOS) of the array":
            lambda: int(shapely.get_num_geometries(shapely.constrained_delaunay_triangles(geoms)).sum()),
    }
    best = {name: float("inf") for name in runs}
    counts = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # degree space is fine for a plain CDT
        for name, fn in runs.items():
            counts[name] = fn()               # (warm-up)
        for _ in range(rounds):
            for name, fn in runs.items():
                seconds, _ = timed(fn)
                best[name] = min(best[name], seconds)
    rows = [{"name": name, "seconds": best[name], "polygons": len(geoms), "triangles": counts[name]}
            for name in runs]
    for r in rows:
        print(f"small layer: {r['name']:70s} {r['seconds']:8.3f} s", file=sys.stderr)
    return rows


def small_layer_lines(rows, n_vertices: int, rounds: int) -> list[str]:
    loop = next(r for r in rows if r["name"].startswith("loop"))
    lines = ["", f"The small layer: the same polygons, not replicated ({rows[0]['polygons']:,} polygons, "
             f"{n_vertices:,} vertices), least of {rounds} interleaved runs each after a warm-up:", "",
             "| implementation | seconds | polygons / s | / the loop's time | triangles |",
             "|---|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['name']} | {r['seconds']:.3f} | {r['polygons'] / r['seconds']:,.0f} | "
                     f"{r['seconds'] / loop['seconds']:.2f}x | {r['triangles']:,} |")
    return lines


def run_dask_threads(frame, n_threads: int):
    """triangulate_dask on Dask's threaded scheduler (the kernels release the GIL)."""
    import warnings

    import dask
    import dask_geopandas
    from cdt_plugin.adapters import geo

    with warnings.catch_warnings(), dask.config.set(scheduler="threads", num_workers=n_threads):
        warnings.simplefilter("ignore")
        ddf = dask_geopandas.from_geopandas(frame, npartitions=16)
        s, out = timed(lambda: geo.triangulate_dask(ddf).compute())
    return s, len(out)


def geojson_rows(frame, n_polygons: int):
    """Writing a layer of triangles as GeoJSON: ``geo.write_geojson`` against
    ``json.dump`` of geopandas' feature dicts (how it wrote before), on the
    triangles of the first ``n_polygons`` polygons; both read back bit for bit."""
    import json
    import tempfile
    import warnings

    from cdt_plugin.adapters import geo
    from cdt_plugin.adapters.layers import json_value

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tris = geo.triangulate(frame.iloc[:n_polygons], progress=False)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "t.geojson"

        def plain_json():
            with open(path, "w", encoding="utf-8") as f:
                json.dump(tris.to_geo_dict(na="null", drop_id=True), f, default=json_value)

        for name, fn in (("geo.write_geojson", lambda: geo.write_geojson(tris, path)),
                         ("json.dump(frame.to_geo_dict())", plain_json)):
            s, _ = timed(fn)
            rows.append({"name": name, "seconds": s, "triangles": len(tris),
                         "megabytes": path.stat().st_size / 2**20})
            print(f"{name:45s} {s:8.2f} s  {len(tris)} triangles", file=sys.stderr)
    return rows


def run_dask(frame, n_workers: int):
    """triangulate_dask on a LocalCluster of worker processes; the triangles of
    each partition are counted where they were made (as a pipeline that writes
    from the workers, ``to_parquet``, would use them): gathering millions of
    Polygons into the client pickles each one and costs more than the meshing."""
    import warnings

    import dask_geopandas
    from dask.distributed import Client, LocalCluster, wait
    from cdt_plugin.adapters import geo

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            warm = dask_geopandas.from_geopandas(frame.iloc[:200], npartitions=2 * n_workers)
            geo.triangulate_dask(warm).compute()
            # the input on the workers before the timed span, as a layer read there would be
            # (shipping it from this process each time costs seconds more than the meshing saves)
            ddf = dask_geopandas.from_geopandas(frame, npartitions=16).persist()
            wait(ddf)
            s, counts = timed(lambda: geo.triangulate_dask(ddf).map_partitions(len).compute())
    return s, int(counts.sum())


def render(rows, n_polygons: int, n_vertices: int, writes, small=None) -> str:
    import numba
    geos = next(r for r in rows if r["name"].startswith("shapely"))
    earcut = next(r for r in rows if r["name"].startswith("trimesh earcut"))
    lines = [
        f"GIS batch meshing (`python benchmarks/bench_gis.py --write-readme`; {platform.machine()}, "
        f"{os.cpu_count()} cores ({available_cores()} usable), Python "
        f"{platform.python_version()}, numba {numba.__version__}): Natural Earth 1:50m countries "
        f"split into polygons and replicated to {n_polygons:,} polygons ({n_vertices:,} "
        "vertices), one timed run each after a warm-up.",
        "",
        "| implementation | seconds | polygons / s | vs GEOS | / earcut's time | triangles |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        rate = r["polygons"] / r["seconds"]
        lines.append(f"| {r['name']} | {r['seconds']:.2f} | {rate:,.0f} | "
                     f"{geos['seconds'] / r['seconds']:.2f}x | {r['seconds'] / earcut['seconds']:.2f}x | "
                     f"{r['triangles']:,} |")
    notes = [r["note"] for r in rows if r["note"]]
    if notes:
        lines += [""] + [f"* {n}." for n in notes]
    lines += ["", f"Writing a layer of triangles as GeoJSON ({writes[0]['triangles']:,} triangles, "
              f"{writes[0]['megabytes']:.0f} MB; coordinates read back bit for bit):", "",
              "| writer | seconds | triangles / s | speed-up |", "|---|---:|---:|---:|"]
    slow = writes[-1]["seconds"]
    for w in writes:
        lines.append(f"| {w['name']} | {w['seconds']:.2f} | {w['triangles'] / w['seconds']:,.0f} | "
                     f"{slow / w['seconds']:.1f}x |")
    if small:
        lines += small_layer_lines(*small)
    return "\n".join(lines + goal_lines(rows, writes, small[0] if small else [])) + "\n"


def goal_lines(rows, writes, small_rows=()) -> list[str]:
    """The goals of issues #18 and #47 that these tables measure, judged on this
    run's ratios (the rows a partial run left out are skipped)."""
    by = {r["name"]: r["seconds"] for r in rows}

    def find(*words):
        return next((s for name, s in by.items() if all(w in name for w in words)), None)

    batch1, batch_all = find("batch", "1 thread"), find("batch", "threads")
    earcut, geos = find("earcut"), find("GEOS")
    frame1, frame_all = find("GeoDataFrame", "1 thread"), find("GeoDataFrame", "threads")
    goals = [
        ("2. batch (arrays): speed-up of all cores over 1 thread", batch1, batch_all, ">= 1.7x", lambda r: r >= 1.7),
        ("4. batch (arrays), 1 thread / earcut", batch1, earcut, "<= 2x", lambda r: r <= 2.0),
        ("4. batch (arrays), all cores / earcut", batch_all, earcut, "< 1x", lambda r: r < 1.0),
        ("5. geo.triangulate (GeoDataFrame), all cores / GEOS", frame_all, geos, "< 1x",
         lambda r: r < 1.0),
        ("5. geo.write_geojson: speed-up over json.dump", writes[-1]["seconds"], writes[0]["seconds"], ">= 5x",
         lambda r: r >= 5.0),
    ]
    for kind in ("threaded scheduler", "distributed"):
        one, two = find(kind, "1 "), find(kind, "2 ")
        goals += [(f"6. Dask {kind}: 2 workers / 1 worker", two, one, "< 1x", lambda r: r < 1.0),
                  (f"6. Dask {kind}: 2 workers / geo.triangulate, all cores", two, frame_all, "< 1x",
                   lambda r: r < 1.0),
                  (f"6. Dask {kind}: 2 workers / geo.triangulate, 1 thread", two, frame1, "< 1x",
                   lambda r: r < 1.0)]
    small_by = {r["name"]: r["seconds"] for r in small_rows}
    small_loop = next((t for name, t in small_by.items() if name.startswith("loop")), None)
    for name, t in small_by.items():
        if name.startswith("cdt_plugin geo.triangulate"):
            goals.append((f"#47: small layer, {name.removeprefix('cdt_plugin ')} / the loop of shapely's "
                          "constrained_delaunay_triangles", t, small_loop, "< 1x", lambda r: r < 1.0))
    out = ["", "Against the goals of issues #18 and #47 that these tables measure, in this run (A / B: A's "
           "time over B's):", "",
           "| goal | ratio | wanted | verdict |", "|---|---:|---|---|"]
    for name, a, b, wanted, ok in goals:
        if a is None or b is None:
            continue
        ratio = a / b
        out.append(f"| {name} | {ratio:.2f}x | {wanted} | {'met' if ok(ratio) else 'not met'} |")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--polygons", type=int, default=100_000)
    ap.add_argument("--workers", type=int, nargs="*", default=[1, 2])
    ap.add_argument("--geojson-polygons", type=int, default=5000,
                    help="polygons whose triangles the GeoJSON writers write")
    ap.add_argument("--write-readme", action="store_true")
    ap.add_argument("--small-rounds", type=int, default=7,
                    help="interleaved runs of the small layer's table (the least time of each is shown)")
    ap.add_argument("--out", default=str(HERE / "results" / "gis.md"))
    args = ap.parse_args(argv)
    import shapely
    layer = polygons(1)                 # the small layer: every polygon once
    small = (small_layer_rows(layer, args.small_rounds),
             int(shapely.get_num_coordinates(layer.geometry.values).sum()), args.small_rounds)
    frame = polygons(args.polygons)
    n_vertices = int(shapely.get_num_coordinates(frame.geometry.values).sum())
    rows = run_all(frame, args.workers)
    writes = geojson_rows(frame, args.geojson_polygons)
    table = render(rows, len(frame), n_vertices, writes, small)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(table)
    print(table)
    if args.write_readme:
        sys.path.insert(0, str(HERE))
        from summary import write_readme
        write_readme()                   # the README's summary rows, from results/
    return 0


if __name__ == "__main__":
    sys.exit(main())
