"""Quality meshing: cdt_plugin's Delaunay refinement against Triangle's ``-q``/``-a``.

Workloads:

* R1 — Triangle's sample polygons (every ``.poly`` in ``../shared/corpus/triangle/``
  that has triangles, read with ``cdt_plugin.io.read_poly``: vertices, segments, hole
  points), one call per file, times summed per round;
* R2 — C1 of ``bench_cdt.py`` at 10,000 outer vertices: a star-shaped polygon with 200
  holes of 64 vertices (22,800 vertices in all).

Switches: ``pq30``, ``pq33`` and ``pq30a<area>`` with ``area`` = domain area / 2000 (per
polygon). The same bounds go to ``cdt_plugin.triangulate(min_angle=, max_area=)``.

Both run in this one process, interleaved round-robin after a warm-up call (numba is
compiled and cached before timing); each cell is the minimum over the rounds. The table
gives both triangle counts, the count ratio (goal <= 1.1) and the time ratio (goal <= 2).
Each result is also checked, untimed: every triangle meets the angle bound unless
cdt_plugin reports it (an input angle below the bound) and meets the area bound.

Usage (from the repository root)::

    python benchmarks/bench_refine.py                 # 5 rounds, ~1 minute
    python benchmarks/bench_refine.py --write-readme  # and the README summary rows
"""
from __future__ import annotations

import argparse
import glob
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CORPUS = ROOT.parent / "shared" / "corpus"
sys.path.insert(0, str(HERE))

SWITCHES = ("pq30", "pq33", "pq30a")


def _area(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return float(np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])).sum() / 2)


def workloads():
    """(name, [(vertices, segments, holes), ...]) pairs."""
    import triangle
    from cdt_plugin.io import read_poly
    from bench_cdt import star_with_holes
    polys = []
    for path in sorted(glob.glob(str(CORPUS / "triangle" / "*.poly"))):
        d = read_poly(path)
        holes = d.holes if d.holes is not None and len(d.holes) else None
        inp = {"vertices": d.vertices, "segments": d.segments}
        if holes is not None:
            inp["holes"] = holes
        if "triangles" in triangle.triangulate(inp, "pQ"):
            polys.append((d.vertices, d.segments, holes))
    star = star_with_holes(10_000)
    return [("R1 Triangle's sample polygons", polys),
            ("R2 star 10k + 200 holes", [(star["V"], star["S"], star["H"])])]


def run_triangle(items, switch, areas):
    import triangle
    out = []
    for (V, S, H), area in zip(items, areas):
        inp = {"vertices": V, "segments": S}
        if H is not None:
            inp["holes"] = H
        # positional digits: Triangle does not read an exponent
        sw = switch + (np.format_float_positional(area, trim="-") if switch.endswith("a") else "")
        out.append(triangle.triangulate(inp, sw + "Q"))
    return out


def run_ours(items, switch, areas):
    import cdt_plugin
    angle = 33.0 if switch == "pq33" else 30.0
    out = []
    for (V, S, H), area in zip(items, areas):
        out.append(cdt_plugin.triangulate(V, S, holes=H, min_angle=angle,
                                          max_area=area if switch.endswith("a") else None))
    return out


def check(items, switch, areas, results) -> list[str]:
    """Untimed: the bounds hold (or the miss is reported by cdt_plugin)."""
    from cdt_plugin.report import triangle_quality
    angle = 33.0 if switch == "pq33" else 30.0
    problems = []
    for i, ((V, S, H), area, tri) in enumerate(zip(items, areas, results)):
        smallest = triangle_quality(tri.vertices, tri.triangles)["angles"].min(axis=1)
        bad = set(np.flatnonzero(smallest < angle * (1 - 1e-9)).tolist())
        if not bad <= set(tri.below_min_angle.tolist()):
            problems.append(f"item {i} {switch}: unreported triangles below {angle} degrees")
        if switch.endswith("a"):
            a, b, c = (tri.vertices[tri.triangles[:, k]] for k in range(3))
            tri_areas = np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                               - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2
            if tri_areas.max() > area * (1 + 1e-12):
                problems.append(f"item {i} {switch}: a triangle above the area bound")
    return problems


def measure(rounds: int):
    import cdt_plugin
    rows = []
    for name, items in workloads():
        plain = [cdt_plugin.triangulate(V, S, holes=H) for V, S, H in items]
        areas = [_area(p.vertices, p.triangles) / 2000 for p in plain]
        for switch in SWITCHES:
            ours = run_ours(items, switch, areas)          # warm-up (and compile)
            theirs = run_triangle(items, switch, areas)
            t_ours, t_theirs = [], []
            for _ in range(rounds):
                t0 = time.perf_counter()
                run_triangle(items, switch, areas)
                t1 = time.perf_counter()
                run_ours(items, switch, areas)
                t2 = time.perf_counter()
                t_theirs.append(t1 - t0)
                t_ours.append(t2 - t1)
            n_theirs = sum(len(r["triangles"]) for r in theirs)
            n_ours = sum(len(r.triangles) for r in ours)
            problems = check(items, switch, areas, ours)
            for p in problems:
                print("WARNING", name, p, file=sys.stderr)
            rows.append({"workload": name, "switch": switch + ("<A/2000>" if switch.endswith("a") else ""),
                         "triangle_tris": n_theirs, "ours_tris": n_ours,
                         "count_ratio": n_ours / n_theirs,
                         "triangle_s": min(t_theirs), "ours_s": min(t_ours),
                         "time_ratio": min(t_ours) / min(t_theirs),
                         "below": sum(int(r.stats["below_min_angle"]) for r in ours),
                         "problems": len(problems)})
            print(f"{name:32s} {rows[-1]['switch']:14s} count {rows[-1]['count_ratio']:.3f} "
                  f"time {rows[-1]['time_ratio']:.2f}x", file=sys.stderr)
    return rows


def render(rows, rounds: int) -> str:
    import numba
    import triangle  # noqa: F401
    lines = [
        f"Quality meshing against Triangle (`python benchmarks/bench_refine.py --write-readme`; "
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numba {numba.__version__}; minimum of {rounds} interleaved rounds, warm cache). "
        "Goals: triangle count <= 1.1x Triangle's, time <= 2x.",
        "",
        "| workload | switches | Triangle triangles | ours | count ratio | Triangle s | ours s | time ratio | below bound (input angles) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['workload']} | `{r['switch']}` | {r['triangle_tris']} | {r['ours_tris']} | "
                     f"{r['count_ratio']:.3f} | {r['triangle_s']:.4f} | {r['ours_s']:.4f} | "
                     f"{r['time_ratio']:.2f}x | {r['below']} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--write-readme", action="store_true")
    ap.add_argument("--out", default=str(HERE / "results" / "refine.md"))
    args = ap.parse_args(argv)
    rows = measure(args.rounds)
    table = render(rows, args.rounds)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(table)
    print(table)
    if args.write_readme:
        sys.path.insert(0, str(HERE))
        from summary import write_readme
        write_readme()                   # the README's summary rows, from results/
    return 1 if any(r["problems"] for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
