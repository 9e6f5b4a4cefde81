"""Meshes with a size field: cdt_plugin's ``triangulate(size=...)`` against gmsh and Triangle.

Domains (the issue's three), each with a size field that is ``size_min`` on a source
and grows linearly to ``size_max`` at distance ``distance`` (gmsh's Distance +
Threshold fields with ``DistMin = 0``; ours ``cdt_plugin.size_near``):

* S1 — the unit square, a point source at (0.3, 0.4);
* S2 — a 2 x 1 rectangle with three circular holes (48 vertices each), a line source
  across it (the line is a source only, not a segment of the domain);
* S3 — a real coastline: Great Britain, the largest polygon of the United Kingdom in
  Natural Earth's 1:50m countries (``../shared/corpus/gis``), in kilometres (a local
  equirectangular projection), the source its own coastline.

gmsh (its Python package) meshes each with ``Mesh.Algorithm`` 6 (Frontal-Delaunay)
and 5 (Delaunay), the Threshold field as the background mesh and every other size
source off (``MeshSizeFromPoints``, ``...FromCurvature``, ``...ExtendFromBoundary``);
its Distance field samples each curve densely enough that the distances are those of
the curves. Only ``gmsh.model.mesh.generate(2)`` is timed (the model is built and
the field set before; ``mesh.clear()`` between rounds). Ours is one
``cdt_plugin.triangulate(vertices, segments, holes=..., size=field, min_angle=MIN_ANGLE)``
call, field evaluation included; where ``Triangulation.smooth`` exists, also that mesh
after ``smooth("odt", size=field)`` (10 sweeps; its time includes the meshing). All run
in this one process, interleaved
round-robin after a warm-up (numba compiled and cached before timing); each time is
the minimum over the rounds.

For every mesh, untimed: the triangle count, the minimum angle, the mean radius
ratio (``2 inradius / circumradius``, 1 for an equilateral triangle), the size ratio
(each triangle's longest edge over the field at its centroid: 5%, 50%, 95% quantiles
and the share above 1.5), and the distribution of the triangles' smallest angles.

Then a constant field against Triangle's ``pq30a``: ``size = h`` against the area
bound our refinement takes for a size, ``a = cdt_plugin.grading.SIZE_AREA h**2``
(0.49 h**2; the equilateral triangle of side ``h`` has 0.433 h**2), on S1 and S2
(goal: time and triangle count within 1.1x of Triangle's).

Usage (from the repository root)::

    python benchmarks/bench_sizing.py               # 2 rounds, about three minutes
    python benchmarks/bench_sizing.py --rounds 1    # a smoke run
"""
from __future__ import annotations

import argparse
import inspect
import json
import math
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

MIN_ANGLE = 30.0           # ours and Triangle's angle bound (gmsh has none to set)
ANGLE_BINS = (0, 20, 30, 40, 50, 60)
ALGORITHMS = {"gmsh Frontal-Delaunay": 6, "gmsh Delaunay": 5}
SMOOTHED = "cdt_plugin + ODT smoothing"


# ----------------------------------------------------------------------------- domains


class Domain:
    """A polygonal domain (rings: the first the outer boundary, then holes, each
    an (n, 2) array, not closed), hole points, a size source and its field's numbers."""

    def __init__(self, name, rings, holes, source, size_min, size_max, distance, constant=None):
        self.name, self.rings, self.holes, self.source = name, rings, holes, source
        self.size_min, self.size_max, self.distance = size_min, size_max, distance
        self.constant = constant          # the size of the constant-field comparison (or None)
        self.vertices = np.vstack(rings)
        starts = np.cumsum([0] + [len(r) for r in rings])
        self.segments = np.vstack([np.column_stack([np.arange(a, b), np.r_[a + 1:b, a]])
                                   for a, b in zip(starts[:-1], starts[1:])])

    def field(self):
        import cdt_plugin
        return cdt_plugin.size_near(self.source["geometry"], self.size_min, self.size_max,
                                    distance=self.distance)


def circle(cx, cy, r, n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def great_britain():
    """Great Britain's coastline in km: the largest polygon of the United Kingdom
    (Natural Earth 1:50m), equirectangular about its mean latitude, closing point dropped."""
    data = json.loads((CORPUS / "gis" / "ne_50m_admin_0_countries.geojson").read_text())
    uk = next(f for f in data["features"] if f["properties"].get("NAME", f["properties"].get("name")) == "United Kingdom")
    rings = [np.array(p[0], float)[:-1] for p in uk["geometry"]["coordinates"]]
    lonlat = max(rings, key=lambda r: abs(_ring_area(r)))
    lat0 = math.radians(lonlat[:, 1].mean())
    km = np.column_stack([(lonlat[:, 0] - lonlat[:, 0].mean()) * 111.32 * math.cos(lat0),
                          (lonlat[:, 1] - lonlat[:, 1].mean()) * 110.574])
    return km if _ring_area(km) > 0 else km[::-1]


def _ring_area(r):
    x, y = r[:, 0], r[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def domains():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    holes = [(0.5, 0.5, 0.2), (1.0, 0.3, 0.12), (1.5, 0.6, 0.2)]
    plate = [np.array([[0, 0], [2, 0], [2, 1], [0, 1.0]])] + [circle(x, y, r, 48)[::-1]
                                                                for x, y, r in holes]
    line = np.array([[0.1, 0.9], [1.9, 0.1]])
    coast = great_britain()
    return [
        Domain("S1 square, point source", [square], None,
               {"kind": "point", "xy": np.array([[0.3, 0.4]]), "geometry": np.array([[0.3, 0.4]])},
               0.001, 0.01, 0.5, constant=0.006),
        Domain("S2 plate with 3 holes, line source", plate, np.array([h[:2] for h in holes]),
               {"kind": "line", "xy": line,
                "geometry": {"type": "LineString", "coordinates": line.tolist()}},
               0.002, 0.02, 0.4, constant=0.008),
        Domain(f"S3 Great Britain ({len(coast)} vertices), coastline source", [coast], None,
               {"kind": "rings", "geometry": {"type": "Polygon",
                                              "coordinates": [np.vstack([coast, coast[:1]]).tolist()]}},
               1.0, 20.0, 100.0),
    ]


# ----------------------------------------------------------------------------- gmsh


def gmsh_model(dom, algorithm, name):
    """Build ``dom`` in gmsh (a model of its own) with its size field; returns the
    function to time, which meshes it with ``algorithm``."""
    import gmsh
    model = f"{dom.name.split()[0]} {name}"
    gmsh.model.add(model)
    geo = gmsh.model.geo
    loops = []
    ring_curves = []
    for ring in dom.rings:
        pts = [geo.addPoint(x, y, 0) for x, y in ring]
        curves = [geo.addLine(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]
        ring_curves += curves
        loops.append(geo.addCurveLoop(curves))
    geo.addPlaneSurface(loops)
    src = dom.source
    if src["kind"] == "point":
        source_points = [geo.addPoint(x, y, 0) for x, y in src["xy"]]
    elif src["kind"] == "line":
        a, b = (geo.addPoint(x, y, 0) for x, y in src["xy"])
        source_curves = [geo.addLine(a, b)]
    else:
        source_curves = ring_curves
    geo.synchronize()
    fields = gmsh.model.mesh.field
    dist = fields.add("Distance")
    if src["kind"] == "point":
        fields.setNumbers(dist, "PointsList", source_points)
    else:
        # samples at most a quarter of size_min apart on the longest curve: distances
        # within size_min / 8 of the curves'
        longest = max(np.linalg.norm(np.diff(_curve_ends(dom, src), axis=1), axis=2).max(), 0)
        fields.setNumbers(dist, "CurvesList", source_curves)
        fields.setNumber(dist, "Sampling", int(math.ceil(longest / (dom.size_min / 4))) + 1)
    thr = fields.add("Threshold")
    fields.setNumber(thr, "InField", dist)
    for key, value in (("SizeMin", dom.size_min), ("SizeMax", dom.size_max),
                       ("DistMin", 0.0), ("DistMax", dom.distance)):
        fields.setNumber(thr, key, value)
    fields.setAsBackgroundMesh(thr)

    def run():
        gmsh.model.setCurrent(model)
        gmsh.option.setNumber("Mesh.Algorithm", algorithm)
        gmsh.model.mesh.clear()
        gmsh.model.mesh.generate(2)
    return run


def _curve_ends(dom, src):
    """(k, 2, 2) end points of the source's segments."""
    if src["kind"] == "line":
        return src["xy"][None]
    return np.stack([dom.vertices[dom.segments[:, 0]], dom.vertices[dom.segments[:, 1]]], axis=1)


def gmsh_mesh():
    """The current gmsh mesh's triangles as (vertices, triangles)."""
    import gmsh
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.zeros(int(tags.max()) + 1, np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    _, nodes = gmsh.model.mesh.getElementsByType(2)
    return coords.reshape(-1, 3)[:, :2], index[nodes.astype(np.int64)].reshape(-1, 3)


# ----------------------------------------------------------------------------- ours, Triangle


def has_size() -> bool:
    import cdt_plugin
    return "size" in inspect.signature(cdt_plugin.triangulate).parameters


def ours_run(dom, size):
    import cdt_plugin

    def run():
        return cdt_plugin.triangulate(dom.vertices, dom.segments, holes=dom.holes, size=size,
                                      min_angle=MIN_ANGLE)
    return run


def has_smooth() -> bool:
    import cdt_plugin
    return hasattr(cdt_plugin.Triangulation, "smooth")


def smoothed_run(dom, size):
    """Ours, then ODT smoothing (10 sweeps) weighted by the same field."""
    mesh = ours_run(dom, size)

    def run():
        return mesh().smooth("odt", size=size)
    return run


def size_area() -> float:
    """The area bound per squared size our refinement uses for a constant size
    (``cdt_plugin.grading.SIZE_AREA``), or the equilateral triangle's."""
    try:
        from cdt_plugin.grading import SIZE_AREA
    except ImportError:
        return math.sqrt(3) / 4
    return float(SIZE_AREA)


def triangle_run(dom, area):
    import triangle
    inp = {"vertices": dom.vertices, "segments": dom.segments}
    if dom.holes is not None:
        inp["holes"] = dom.holes
    switches = f"pq{MIN_ANGLE:g}a" + np.format_float_positional(area, trim="-") + "Q"

    def run():
        return triangle.triangulate(inp, switches)
    return run


# ----------------------------------------------------------------------------- measures


def quality(V, T, field):
    """Untimed figures of a mesh against the field it was asked for (a callable,
    or a number for a constant field)."""
    from types import SimpleNamespace
    from cdt_plugin.report import size_ratios, triangle_quality
    q = triangle_quality(V, T)
    smallest = q["angles"].min(axis=1)
    ratio = size_ratios(SimpleNamespace(vertices=V, triangles=T), field)
    hist = np.histogram(smallest, bins=ANGLE_BINS)[0] / len(T)
    return {"triangles": len(T), "min_angle": float(smallest.min()),
            "radius_ratio": float(np.mean(2 * q["inradius"] / q["circumradius"])),
            "ratio_q": [ratio["q05"], ratio["median"], ratio["q95"]],
            "over_1_5": ratio["over_1_5"] / len(T), "angle_hist": hist.tolist()}


def interleaved(runs: dict, rounds: int) -> dict:
    """Minimum seconds of each run over ``rounds`` round-robin rounds."""
    best = {name: math.inf for name in runs}
    for _ in range(rounds):
        for name, run in runs.items():
            t0 = time.perf_counter()
            run()
            best[name] = min(best[name], time.perf_counter() - t0)
    return best


def measure_graded(doms, rounds: int) -> list[dict]:
    import gmsh
    gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    for key in ("Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature",
                "Mesh.MeshSizeExtendFromBoundary"):
        gmsh.option.setNumber(key, 0)
    rows = []
    try:
        for dom in doms:
            field = dom.field()
            results, runs = {}, {}
            for name, algorithm in ALGORITHMS.items():
                runs[name] = gmsh_model(dom, algorithm, name)
                runs[name]()                                 # warm-up
                results[name] = quality(*gmsh_mesh(), field)
            if has_size():
                runs["cdt_plugin"] = ours_run(dom, field)
                tri = runs["cdt_plugin"]()                   # warm-up (and compile)
                results["cdt_plugin"] = quality(tri.vertices, tri.triangles, field)
            if has_size() and has_smooth():
                runs[SMOOTHED] = smoothed_run(dom, field)
                tri = runs[SMOOTHED]()
                results[SMOOTHED] = quality(tri.vertices, tri.triangles, field)
            seconds = interleaved(runs, rounds)
            for name, figures in results.items():
                rows.append({"domain": dom.name, "mesher": name, "seconds": seconds[name], **figures})
                print(f"{dom.name:48s} {name:24s} {figures['triangles']:8d} triangles "
                      f"{seconds[name]:.3f} s", file=sys.stderr)
    finally:
        gmsh.finalize()
    return rows


def measure_constant(doms, rounds: int) -> list[dict]:
    rows = []
    for dom in doms:
        if dom.constant is None:
            continue
        h = dom.constant
        area = size_area() * h * h
        runs = {"Triangle": triangle_run(dom, area)}
        if has_size():
            runs["cdt_plugin"] = ours_run(dom, h)
        meshes = {name: run() for name, run in runs.items()}      # warm-up
        seconds = interleaved(runs, rounds)
        for name, mesh in meshes.items():
            V, T = ((mesh["vertices"], mesh["triangles"]) if isinstance(mesh, dict)
                    else (mesh.vertices, mesh.triangles))
            rows.append({"domain": dom.name, "mesher": name, "size": h, "area": area,
                         "seconds": seconds[name], **quality(V, T, h)})
    return rows


# ----------------------------------------------------------------------------- table


def render(graded, constant, rounds: int) -> str:
    import gmsh
    import numba
    import triangle  # noqa: F401
    head = (f"Meshes with a size field (`python benchmarks/bench_sizing.py`; {platform.machine()}, "
            f"{os.cpu_count()} cores, Python {platform.python_version()}, numba {numba.__version__}, "
            f"gmsh {gmsh.__version__}; minimum of {rounds} interleaved rounds, warm cache; "
            f"ours with `min_angle={MIN_ANGLE:g}`). Goals: our time at most 0.5x gmsh's, "
            "triangle counts within 10%.")
    lines = [head, "",
             "| domain | mesher | triangles | count vs gmsh F-D | seconds | time vs gmsh F-D "
             "| min angle | mean radius ratio | size ratio 5% / 50% / 95% | over 1.5x |",
             "|---|---|---:|---:|---:|---:|---:|---:|---|---:|"]
    for r in graded:
        ref = next(g for g in graded if g["domain"] == r["domain"]
                   and g["mesher"] == "gmsh Frontal-Delaunay")
        q5, q50, q95 = r["ratio_q"]
        lines.append(f"| {r['domain']} | {r['mesher']} | {r['triangles']} | "
                     f"{r['triangles'] / ref['triangles']:.3f} | {r['seconds']:.4f} | "
                     f"{r['seconds'] / ref['seconds']:.2f}x | {r['min_angle']:.1f} | "
                     f"{r['radius_ratio']:.4f} | {q5:.2f} / {q50:.2f} / {q95:.2f} | "
                     f"{100 * r['over_1_5']:.2f}% |")
    if not any(r["mesher"] == "cdt_plugin" for r in graded):
        lines += ["", "cdt_plugin: n/a (this `triangulate` has no `size=` keyword)."]
    elif not any(r["mesher"] == SMOOTHED for r in graded):
        lines += ["", f"{SMOOTHED}: n/a (this `Triangulation` has no `smooth`)."]
    bins = [f"{a}-{b}°" for a, b in zip(ANGLE_BINS[:-1], ANGLE_BINS[1:])]
    lines += ["", "Smallest angle of each triangle, share of the triangles per bin:", "",
              "| domain | mesher | " + " | ".join(bins) + " |",
              "|---|---|" + "---:|" * len(bins)]
    for r in graded + constant:
        lines.append(f"| {r['domain']} | {r['mesher']} | "
                     + " | ".join(f"{100 * v:.1f}%" for v in r["angle_hist"]) + " |")
    lines += ["", f"A constant field against Triangle's `pq{MIN_ANGLE:g}a` (`size=h` against "
                  f"`a = {size_area():.4g} h^2`, the area bound our refinement takes for a size). "
                  "Goal: time and triangle count within 1.1x of Triangle's.", "",
              "| domain | mesher | h | triangles | count ratio | seconds | time ratio | min angle "
              "| mean radius ratio | size ratio 5% / 50% / 95% |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in constant:
        ref = next(g for g in constant if g["domain"] == r["domain"] and g["mesher"] == "Triangle")
        q5, q50, q95 = r["ratio_q"]
        lines.append(f"| {r['domain']} | {r['mesher']} | {r['size']:g} | {r['triangles']} | "
                     f"{r['triangles'] / ref['triangles']:.3f} | {r['seconds']:.4f} | "
                     f"{r['seconds'] / ref['seconds']:.2f}x | {r['min_angle']:.1f} | "
                     f"{r['radius_ratio']:.4f} | {q5:.2f} / {q50:.2f} / {q95:.2f} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", default=str(HERE / "results" / "sizing.md"))
    args = ap.parse_args(argv)
    doms = domains()
    graded = measure_graded(doms, args.rounds)
    constant = measure_constant(doms, args.rounds)
    table = render(graded, constant, args.rounds)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(table)
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
