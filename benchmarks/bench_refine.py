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

``--existing`` times refinement of an existing mesh instead (Triangle's ``-r``,
``results/refine_existing.md``): R3, a mesh of about 100,000 triangles (Triangle's
``pq`` of a unit square with an area bound), every other triangle (a fixed random
half) bounded at 0.3 of its area and the others unbounded (Triangle's ``.area`` file
with -1), ``Triangulation.from_triangles(V, T).refine(max_area=per_triangle)``
against ``triangle.triangulate({vertices, triangles, triangle_max_area}, "ra")``,
reading the mesh included in both; goal <= 1.0x.

Usage (from the repository root)::

    python benchmarks/bench_refine.py                 # 5 rounds, ~1 minute
    python benchmarks/bench_refine.py --write-readme  # and the README summary rows
    python benchmarks/bench_refine.py --existing      # the -r case only, ~10 s
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


def _areas(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])) / 2


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


def existing_mesh(target: int = 100_000):
    """R3's input: Triangle's mesh of the unit square with about ``target``
    triangles, and the per-triangle bounds (-1: none)."""
    import triangle
    square = {"vertices": np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]]),
              "segments": np.array([[0, 1], [1, 2], [2, 3], [3, 0]])}
    mesh = triangle.triangulate(square, "pqa" + np.format_float_positional(1.55 / target, precision=6, trim="-") + "Q")
    V, T = mesh["vertices"], mesh["triangles"]
    bounds = np.where(np.random.default_rng(0).random(len(T)) < 0.5, 0.3 * _areas(V, T), -1.0)
    return V, T, bounds


def measure_existing(rounds: int):
    """R3: ``-r`` refinement with per-triangle areas, ours against Triangle's ``ra``."""
    import triangle
    import cdt_plugin
    V, T, bounds = existing_mesh()

    def ours():
        return cdt_plugin.Triangulation.from_triangles(V, T).refine(max_area=bounds)

    def theirs():
        return triangle.triangulate({"vertices": V, "triangles": T,
                                     "triangle_max_area": bounds[:, None]}, "raQ")
    mine, ref = ours(), theirs()          # warm-up (and compile)
    t_ours, t_theirs = [], []
    for _ in range(rounds):
        t0 = time.perf_counter()
        theirs()
        t1 = time.perf_counter()
        ours()
        t2 = time.perf_counter()
        t_theirs.append(t1 - t0)
        t_ours.append(t2 - t1)
    # untimed: every vertex kept, and each new triangle within the bound of the triangle
    # of the mesh its centroid lies in (the rule; the centroid summed smallest first)
    base = cdt_plugin.Triangulation.from_triangles(V, T)
    corners = np.sort(mine.vertices[mine.triangles], axis=1)
    bound = bounds[base.locate(((corners[:, 0] + corners[:, 1]) + corners[:, 2]) / 3)]
    bounded = bound > 0
    problems = int(not np.array_equal(mine.vertices[:len(V)], V))
    problems += int((_areas(mine.vertices, mine.triangles)[bounded] > bound[bounded]).any())
    if problems:
        print("WARNING R3: a vertex moved or a bound is missed", file=sys.stderr)
    row = {"workload": f"R3 -r of a {len(T) // 1000}k-triangle mesh", "switch": "ra (per-triangle areas)",
           "triangle_tris": len(ref["triangles"]), "ours_tris": len(mine.triangles),
           "count_ratio": len(mine.triangles) / len(ref["triangles"]),
           "triangle_s": min(t_theirs), "ours_s": min(t_ours), "time_ratio": min(t_ours) / min(t_theirs),
           "below": 0, "problems": problems}
    print(f"{row['workload']:32s} count {row['count_ratio']:.3f} time {row['time_ratio']:.2f}x",
          file=sys.stderr)
    return [row]


def render(rows, rounds: int, goal: str = "time <= 2x", command: str = "--write-readme") -> str:
    import numba
    import triangle  # noqa: F401
    lines = [
        f"Quality meshing against Triangle (`python benchmarks/bench_refine.py {command}`; "
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numba {numba.__version__}; minimum of {rounds} interleaved rounds, warm cache). "
        f"Goals: triangle count <= 1.1x Triangle's, {goal}.",
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
    ap.add_argument("--existing", action="store_true",
                    help="time refinement of an existing mesh (-r) only")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    if args.existing:
        rows = measure_existing(args.rounds)
        table = render(rows, args.rounds, goal="time <= 1.0x", command="--existing")
        args.out = args.out or str(HERE / "results" / "refine_existing.md")
    else:
        rows = measure(args.rounds)
        table = render(rows, args.rounds)
        args.out = args.out or str(HERE / "results" / "refine.md")
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
