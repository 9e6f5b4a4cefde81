"""Voronoi diagrams of point sets: cdt_plugin against GEOS (shapely) and Qhull (scipy).

Workloads (seeded, ``numpy.random.default_rng``):

* ``u-1e5`` — 100,000 uniform random points in the unit square;
* ``u-1e6`` — 1,000,000 uniform random points in the unit square.

Implementations, interleaved round-robin in one worker process per workload
(``harness.py``); the Delaunay triangulation is inside every timed span:

* ``ours``          — "cdt_plugin cells (arrays)": ``cdt_plugin.delaunay(P).voronoi()``,
  then ``vor.vertices`` and ``vor.region_indices`` touched (the cells as flat arrays);
* ``ours_clip``     — "cdt_plugin clipped cells (arrays)": ``cdt_plugin.delaunay(P).voronoi(clip=box)``,
  ``box`` = GEOS's default envelope (the points' bounding box grown by its larger side,
  ``Voronoi.envelope()``), computed from ``P`` inside the span; ``cell_xy`` / ``cell_offsets`` out;
* ``ours_polygons`` — "cdt_plugin polygons (shapely)":
  ``cdt_plugin.adapters.shapely.voronoi_polygons(shapely.MultiPoint(P))``: the same input
  and output as GEOS;
* ``geos``          — ``shapely.voronoi_polygons(shapely.MultiPoint(P))`` (GEOS); the reference
  of the ratios;
* ``scipy``         — ``scipy.spatial.Voronoi(P)`` (Qhull); marked slow: one round on 1e6
  (about 20 s per call there).

``cdt_plugin.delaunay`` runs with its default ``workers`` (every core: from 50,000
points the two halves of the first cut are built on two threads); GEOS and Qhull are
single-threaded. Ratios are taken in the same run. The goals (issue #20):
cells (arrays) / GEOS <= 0.3x, cells (arrays) / scipy <= 0.05x, polygons / GEOS <= 1.0x.

Checks, once per workload on the first timed result of each implementation (not
timed): our cell count equals the number of sites, which equals the number of
distinct input points (and no clipped cell is empty); the areas of the
envelope-clipped polygons (ours_clip through ``to_shapely()``, ours_polygons, and
GEOS's as a cross-check of the envelope) add up to the envelope's area within 1e-9
relative. A failure is a WARNING line under the table, and so is a change to a
source file of cdt_plugin or of the adapters while the run goes on (rows measured
before and after it may time different code).

Usage (from the repository root)::

    python benchmarks/bench_voronoi.py --quick --no-cold     # smoke test: 1e5 only, 1 round, ~20 s
    python benchmarks/bench_voronoi.py                       # full run, 3 rounds, 3-5 minutes on 2 cores
    python benchmarks/bench_voronoi.py --write-readme        # full run + the README summary rows
    python benchmarks/bench_voronoi.py --only ours,geos --workloads u-1e5 --no-memory

Options: ``--repeat R`` (rounds, default 3; 1 with ``--quick``), ``--slow-repeat R``
(scipy's rounds on 1e6, default 1), ``--only``, ``--workloads``, ``--timeout S`` per
call, ``--setup-timeout S`` (import + warm-up, numba compilation included), ``--no-memory``
(skip the peak-memory processes), ``--no-cold`` (skip the cold / cached start of
``ours`` on 1e5: 25-60 s of numba compilation here), ``--out PATH.md`` (a .json
with the raw numbers is written beside it; default ``benchmarks/results/voronoi.md``,
``voronoi-quick.md`` with ``--quick``).

This module must not import numba or cdt_plugin at import time: the cold-start
measurement re-runs it as a fresh worker and times the import.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import (  # noqa: E402
    REPO_ROOT,
    WORKER_FLAG,
    Impl,
    Suite,
    Workload,
    command_line,
    fmt_s,
    machine_info,
    measure_cold,
    measure_memory,
    measure_times,
    changed_sources,
    select_by_name,
    short_reason,
    sources_state,
    write_results,
)
from harness import main as harness_main  # noqa: E402

GOAL_CELLS_GEOS = 0.3       # cells (arrays) / shapely.voronoi_polygons
GOAL_CELLS_SCIPY = 0.05     # cells (arrays) / scipy.spatial.Voronoi
GOAL_POLYGONS_GEOS = 1.0    # polygons (shapely) / shapely.voronoi_polygons
AREA_RTOL = 1e-9

# ----------------------------------------------------------------------------- workloads


def uniform(n: int, seed: int):
    def make() -> np.ndarray:
        rng = np.random.default_rng(seed)
        return np.ascontiguousarray(rng.uniform(0.0, 1.0, (n, 2)), dtype=np.float64)
    return make


WARMUP_POINTS = 50_000   # cdt_plugin.delaunay.PARALLEL_POINTS (not imported here: see the docstring)


def subset(data: np.ndarray, k: int = WARMUP_POINTS) -> np.ndarray:
    """Warm-up input: k points of the workload itself, as many as it takes for
    ``delaunay`` to take its two-thread path, so that no kernel of that path is
    compiled or loaded from numba's cache inside a timed call."""
    if len(data) <= k:
        return data
    idx = np.random.default_rng(0).choice(len(data), k, replace=False)
    return np.ascontiguousarray(data[np.sort(idx)])


WORKLOADS = [
    Workload("u-1e5", "uniform 1e5", uniform(100_000, 2001), subset, 100_000),
    Workload("u-1e6", "uniform 1e6", uniform(1_000_000, 2002), subset, 1_000_000, large=True),
]


def envelope_box(P: np.ndarray) -> tuple[float, float, float, float]:
    """GEOS's default clip box (``Voronoi.envelope()``): the points' bounding box
    grown by its larger side on every side."""
    lo, hi = P.min(axis=0), P.max(axis=0)
    grow = float((hi - lo).max())
    return (float(lo[0]) - grow, float(lo[1]) - grow, float(hi[0]) + grow, float(hi[1]) + grow)


def _box_area(box) -> float:
    return (box[2] - box[0]) * (box[3] - box[1])


_DISTINCT: dict[int, int] = {}


def distinct_points(P: np.ndarray) -> int:
    """Number of distinct input points (cached per input array, worker side)."""
    key = id(P)
    if key not in _DISTINCT:
        _DISTINCT[key] = len(np.unique(P, axis=0))
    return _DISTINCT[key]

# ----------------------------------------------------------------------------- implementations


def setup_ours():
    import cdt_plugin

    def run(P):
        vor = cdt_plugin.delaunay(P).voronoi()
        _ = (vor.vertices.shape, vor.region_indices.shape)   # the cells as flat arrays
        return vor
    return run


def setup_ours_clip():
    import cdt_plugin

    def run(P):
        vor = cdt_plugin.delaunay(P).voronoi(clip=envelope_box(P))
        _ = (vor.cell_xy.shape, vor.cell_offsets.shape)
        return vor
    return run


def setup_ours_polygons():
    import shapely

    from cdt_plugin.adapters.shapely import voronoi_polygons

    def run(P):
        return voronoi_polygons(shapely.MultiPoint(P))
    return run


def setup_geos():
    import shapely

    def run(P):
        return shapely.voronoi_polygons(shapely.MultiPoint(P))
    return run


def setup_scipy():
    from scipy.spatial import Voronoi

    def run(P):
        return Voronoi(P)
    return run


def count_geometries(result) -> int:
    import shapely
    return int(shapely.get_num_geometries(result))


def _area_rel(polygons, box) -> float:
    import shapely
    total = float(np.sum(shapely.area(polygons)))
    return abs(total - _box_area(box)) / _box_area(box)


def extras_ours(P, vor) -> dict:
    sites, cells = len(vor.points), len(vor.region_offsets) - 1
    return {"cells": cells, "sites": sites, "distinct": distinct_points(P),
            "ok": bool(cells == sites == distinct_points(P))}


def extras_ours_clip(P, vor) -> dict:
    sites, cells = len(vor.points), len(vor.cell_offsets) - 1
    empty = int(np.count_nonzero(np.diff(vor.cell_offsets) == 0))
    same_box = tuple(vor.envelope()) == tuple(vor.clip)
    return {"cells": cells, "sites": sites, "distinct": distinct_points(P), "empty": empty,
            "envelope_matches": same_box, "area_rel": _area_rel(vor.to_shapely(), vor.clip),
            "ok": bool(cells == sites == distinct_points(P) and empty == 0)}


def extras_geometry_collection(P, gc) -> dict:
    """Polygons out (ours_polygons, GEOS): one per distinct point, none empty,
    their areas adding up to the envelope's."""
    import shapely
    cells = int(shapely.get_num_geometries(gc))
    parts = shapely.get_parts(gc)
    out = {"cells": cells, "distinct": distinct_points(P),
           "empty": int(np.count_nonzero(shapely.is_empty(parts))),
           "area_rel": _area_rel(parts, envelope_box(P))}
    out["ok"] = bool(cells == distinct_points(P) and out["empty"] == 0)
    return out


IMPLS = [
    Impl("ours", "cdt_plugin cells (arrays)", setup_ours, lambda v: len(v.region_offsets) - 1,
         timed="delaunay(P).voronoi(), array in, vertices + region_offsets/region_indices out",
         dist="cdt-plugin", numba_cold_start=True, package="cdt_plugin", extras=extras_ours),
    Impl("ours_clip", "cdt_plugin clipped cells (arrays)", setup_ours_clip, lambda v: len(v.cell_offsets) - 1,
         timed="envelope box from P + delaunay(P).voronoi(clip=box), cell_offsets/cell_xy out",
         extras=extras_ours_clip),
    Impl("ours_polygons", "cdt_plugin polygons (shapely)", setup_ours_polygons, count_geometries,
         timed="cdt_plugin.adapters.shapely.voronoi_polygons(shapely.MultiPoint(P)), GeometryCollection out",
         extras=extras_geometry_collection),
    Impl("geos", "GEOS (shapely.voronoi_polygons)", setup_geos, count_geometries,
         timed="shapely.voronoi_polygons(shapely.MultiPoint(P)), GeometryCollection out (default "
               "envelope)", dist="shapely", extras=extras_geometry_collection),
    Impl("scipy", "Qhull (scipy.spatial.Voronoi)", setup_scipy, lambda r: len(r.point_region),
         timed="Voronoi(P)", slow=True, dist="scipy"),
]

SUITE = Suite(
    name="voronoi",
    title="Voronoi diagrams of point sets",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="geos",
    script=os.path.abspath(__file__),
    cold_workload="u-1e5",
)

# ----------------------------------------------------------------------------- checks


def checks(results: dict) -> list[str]:
    warnings = []
    labels = {i.name: i.label for i in IMPLS}
    for wname, row in results["workloads"].items():
        for name, c in row.items():
            ex = c.get("extras")
            if not ex or c.get("error"):
                continue
            if ex.get("error"):
                warnings.append(f"{wname}: {labels[name]}: the check failed: {ex['error']}")
                continue
            if name != "geos" and ex.get("ok") is not True:
                warnings.append(f"{wname}: {labels[name]}: {ex.get('cells')} cells for {ex.get('sites', '?')} "
                                f"sites, {ex.get('distinct')} distinct points, "
                                f"{ex.get('empty', 0)} empty")
            if name == "geos" and ex.get("cells") != ex.get("distinct"):
                warnings.append(f"{wname}: GEOS gives {ex.get('cells')} polygons for {ex.get('distinct')} "
                                "distinct points")
            if ex.get("area_rel") is not None and ex["area_rel"] > AREA_RTOL:
                warnings.append(f"{wname}: {labels[name]}: the polygons' areas add up to the envelope's area "
                                f"only within {ex['area_rel']:.2g} relative (> {AREA_RTOL:g})")
            if ex.get("envelope_matches") is False:
                warnings.append(f"{wname}: Voronoi.envelope() differs from the benchmark's envelope box")
    if results.get("sources_changed"):
        warnings.append("source files changed during the run (rows measured before and after may time "
                        "different code): " + ", ".join(results["sources_changed"]))
    cold = results.get("cold") or {}
    if cold.get("warning"):
        warnings.append(f"cold start: {cold['warning']}")
    return warnings

# ----------------------------------------------------------------------------- report


def _ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}x" if a and b else "n/a"


def _verdict(a: float | None, b: float | None, goal: float) -> str:
    if not (a and b):
        return "n/a"
    return "met" if a <= goal * b else "not met"


def _check_cell(name: str, c: dict) -> str:
    ex = c.get("extras")
    if c.get("error") or name == "scipy":
        return "-"
    if not ex:
        return "n/a"
    if ex.get("error"):
        return "check failed"
    parts = []
    if name == "geos":
        parts.append("polygons = points" if ex.get("cells") == ex.get("distinct") else "polygons != points")
    else:
        parts.append("cells = sites" if ex.get("ok") else "CELLS WRONG")
    if ex.get("area_rel") is not None:
        parts.append(f"area rel err {ex['area_rel']:.1e}")
    return "; ".join(parts)


def render(results: dict, info: dict, args_line: str) -> str:
    v = ", ".join(f"{k} {val}" for k, val in info["versions"].items() if val)
    impls = [i for i in IMPLS if any(i.name in row for row in results["workloads"].values())]
    lines = [
        f"Machine: {info['cpu_count']} CPUs ({info['cpus_usable']} usable)"
        + (f", {info['cpu_model']}" if info["cpu_model"] else "")
        + f"; {v}; {info['date']}. Command: `{args_line}`"
        + (" (mode: quick)" if results["mode"] == "quick" else "") + ".",
        "",
        "| workload | implementation | median s | ratio to GEOS | cells | check | peak MB |",
        "|---|---|---:|---:|---:|---|---:|",
    ]
    notes: list[str] = []
    for wl in WORKLOADS:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        ref = row.get("geos", {}).get("median")
        for impl in impls:
            c = row.get(impl.name)
            if c is None:
                continue
            if c.get("error"):
                notes.append(f"{wl.label} / {impl.label}: {c['error']}")
            if c.get("peak_mb") is None and c.get("mem_error") and not c.get("error"):
                notes.append(f"{wl.label} / {impl.label} memory: {c['mem_error']}")
            label = impl.label
            med = "n/a" if c.get("error") else fmt_s(c.get("median"))
            count = f"{c['count']:,d}" if c.get("count") is not None else "n/a"
            mem = f"{c['peak_mb']:.1f}" if c.get("peak_mb") is not None else "n/a"
            lines.append(f"| {wl.label} | {label} | {med} | {_ratio(c.get('median'), ref)} | {count} | "
                         f"{_check_cell(impl.name, c)} | {mem} |")

    poly_label = "polygons / GEOS"
    lines += ["", (f"Against the goals (issue #20; ratios of medians in this run): cells (arrays) at most "
                   f"{GOAL_CELLS_GEOS:g}x GEOS and {GOAL_CELLS_SCIPY:g}x scipy, polygons at most "
                   f"{GOAL_POLYGONS_GEOS:g}x GEOS."), "",
              (f"| workload | cells / GEOS | goal <= {GOAL_CELLS_GEOS:g}x | cells / scipy | "
               f"goal <= {GOAL_CELLS_SCIPY:g}x | clipped cells / GEOS | {poly_label} | "
               f"goal <= {GOAL_POLYGONS_GEOS:g}x |"),
              "|---|---:|---|---:|---|---:|---:|---|"]
    for wl in WORKLOADS:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        m = {n: c.get("median") for n, c in row.items()}
        ours, clip, poly, geos, qhull = (m.get(k) for k in ("ours", "ours_clip", "ours_polygons", "geos", "scipy"))
        lines.append(f"| {wl.label} | {_ratio(ours, geos)} | {_verdict(ours, geos, GOAL_CELLS_GEOS)} | "
                     f"{_ratio(ours, qhull)} | {_verdict(ours, qhull, GOAL_CELLS_SCIPY)} | "
                     f"{_ratio(clip, geos)} | {_ratio(poly, geos)} | "
                     f"{_verdict(poly, geos, GOAL_POLYGONS_GEOS)} |")
    lines.append("")

    cold = results.get("cold")
    if cold:
        impl = SUITE.impl(cold["impl"])
        wl = SUITE.workload(cold["workload"])
        warm = results["workloads"].get(wl.name, {}).get(impl.name, {}).get("median")
        parts = [f"cold {fmt_s(cold['cold_s'])} s" if "cold_s" in cold
                 else f"cold n/a ({cold.get('cold_s_error')})"]
        if "cached_s" in cold:
            parts.append(f"cached start {fmt_s(cold['cached_s'])} s")
        parts.append(f"warm {fmt_s(warm)} s" if warm else "warm n/a")
        lines += [f"{impl.label} start-up on {wl.label}: " + "; ".join(parts)
                  + (f" (warning: {cold['warning']})" if cold.get("warning") else "")
                  + ". Cold = new process, empty numba cache (`NUMBA_CACHE_DIR` = fresh temp dir), import + "
                  "first call (compilation of the Delaunay and Voronoi kernels included); cached start = new "
                  "process, filled cache, import + first call; warm = in-process median (the table).", ""]

    spans = []
    for i in impls:
        spans.append(f"{i.label}: {i.timed}")
    methods = sorted({c.get("mem_method") for row in results["workloads"].values()
                      for c in row.values() if c.get("mem_method")})
    large = [w.label for w in WORKLOADS if w.large and w.name in results["workloads"]]
    slow = [i.label for i in impls if i.slow]
    lines.append(
        f"Median of {results['repeat']} interleaved round(s) per workload"
        + (f" ({', '.join(slow)}: {results['slow_repeat']} round(s) on {', '.join(large)})"
           if results["slow_repeat"] < results["repeat"] and slow and large else "")
        + ", one worker process per workload, input generation not timed, the Delaunay triangulation "
        "inside every cdt_plugin span (`delaunay` with its default workers: both cores from 50,000 points; "
        "GEOS and Qhull run on one). "
        + ("Peak MB = extra resident memory of one call in a fresh process (peak minus the baseline after "
           "imports, input and warm-up; MiB; method: " + ", ".join(methods) + ")."
           if methods else "Peak memory not measured.")
        + " Timed spans: " + "; ".join(spans) + ". Cells: cells (one per site) or polygons out; "
        "Qhull: len(point_region). Check (untimed, first result): cell count = sites = distinct input points, "
        "no empty clipped cell; the envelope-clipped polygons' areas add up to the envelope's area "
        f"(relative error shown, at most {AREA_RTOL:g})."
        + (" The machine is shared (2 CPUs, other processes running): read the same-run ratios."
           if info["cpu_count"] <= 2 else ""))
    if notes:
        lines += [""] + [f"- n/a: {n}" for n in notes]
    if results.get("warnings"):
        lines += [""] + [f"- WARNING: {w}" for w in results["warnings"]]
    return "\n".join(lines) + "\n"

# ----------------------------------------------------------------------------- driver


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _parse(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=SUITE.title)
    p.add_argument("--quick", action="store_true", help="smoke test: the 1e5 workload only, 1 round")
    p.add_argument("--repeat", type=int, default=None, help="interleaved rounds per workload (default 3)")
    p.add_argument("--slow-repeat", type=int, default=1,
                   help="rounds for scipy on the 1e6 workload (default 1: about 20 s per call)")
    p.add_argument("--only", default=None,
                   help="comma-separated implementations: " + ",".join(i.name for i in IMPLS))
    p.add_argument("--workloads", default=None,
                   help="comma-separated workloads: " + ",".join(w.name for w in WORKLOADS))
    p.add_argument("--timeout", type=float, default=120.0, help="seconds allowed per timed call (default 120)")
    p.add_argument("--setup-timeout", type=float, default=600.0,
                   help="seconds allowed for import + warm-up, e.g. numba compilation (default 600)")
    p.add_argument("--no-memory", action="store_true", help="skip the peak-memory processes")
    p.add_argument("--no-cold", action="store_true", help="skip the cold / cached start-up of cdt_plugin")
    p.add_argument("--out", default=None,
                   help="markdown output (a .json with raw numbers is written beside it); "
                   "default benchmarks/results/voronoi.md (voronoi-quick.md with --quick)")
    p.add_argument("--write-readme", action="store_true",
                   help="regenerate the README's benchmark summary rows from the stored results")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == [WORKER_FLAG]:                 # a timing / memory / cold worker (harness.py)
        return harness_main(SUITE, argv)
    args = _parse(argv)
    t_start = time.perf_counter()
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)
    slow_repeat = min(repeat, max(args.slow_repeat, 1))
    impls = select_by_name(args.only, IMPLS, "implementation(s)")
    workloads = select_by_name(args.workloads, WORKLOADS, "workload(s)")
    if args.quick:
        workloads = [w for w in workloads if not w.large]
    info = machine_info(SUITE)
    try:
        import shapely
        info["versions"]["GEOS"] = shapely.geos_version_string
    except ImportError:
        pass
    _log(f"{SUITE.title}: {len(workloads)} workload(s) x {len(impls)} implementation(s), {repeat} round(s); "
         f"{info['cpu_count']} CPUs; python {info['versions']['python']}")
    results: dict[str, Any] = {
        "suite": SUITE.name, "mode": "quick" if args.quick else "full", "repeat": repeat,
        "slow_repeat": slow_repeat, "machine": info, "argv": argv, "workloads": {},
    }

    sources_before = sources_state()
    cold_impl = next((i for i in impls if i.numba_cold_start), None)
    if cold_impl is not None and not args.no_cold:
        _log("cold start:")
        results["cold"] = measure_cold(SUITE, cold_impl, SUITE.workload(SUITE.cold_workload),
                                       args.setup_timeout + args.timeout)

    for wl in workloads:
        _log(f"{wl.label}:")
        repeats = {i.name: (slow_repeat if wl.large and i.slow else repeat) for i in impls}
        cells = measure_times(SUITE, wl, impls, repeats, args.timeout, args.setup_timeout)
        if not args.no_memory and wl.memory:
            for impl in impls:
                if cells[impl.name].error is None:
                    measure_memory(SUITE, wl, impl, cells[impl.name], args.timeout, args.setup_timeout)
        results["workloads"][wl.name] = {
            name: {"median": c.median, "times": c.times, "count": c.count, "peak_mb": c.peak_mb,
                   "mem_method": c.mem_method, "error": c.error, "mem_error": c.mem_error,
                   "extras": c.extras}
            for name, c in cells.items()}
        for name, c in cells.items():
            if c.extras:
                _log(f"  {wl.name:<14} {name:<14} check {c.extras}")

    results["sources_changed"] = changed_sources(sources_before, sources_state())
    try:
        results["warnings"] = checks(results)
    except Exception as exc:
        results["warnings"] = [f"the checks failed: {short_reason(exc)}"]
    for w in results["warnings"]:
        _log(f"WARNING: {w}")

    md = render(results, info, command_line(SUITE, argv))
    results["elapsed_s"] = time.perf_counter() - t_start
    return write_results(SUITE, results, md, args)


if __name__ == "__main__":
    sys.exit(main())
