"""Constrained Delaunay triangulation of polygons and PSLGs: cdt_plugin against its peers.

Workloads (DESIGN.md, "Benchmarks"):

* C1 — a star-shaped polygon with 200 holes of 64 vertices each (seeded). The outer ring
  has N = 10,000 / 100,000 vertices, ``r = 1 + 0.25 sin(7t + p1) + 0.05 sin(23t + p2)``
  over jittered angles (so 0.7 <= r <= 1.3, star-shaped about the origin); the holes are
  ellipses (semi-axes 0.2-0.35 of the grid step, random rotation, centre jittered by up
  to 0.1 step) in 200 cells of a square grid clipped to the disk of radius 0.66, so they
  touch neither each other nor the boundary. N counts the outer ring only (200 x 64 =
  12,800 hole vertices would not fit in a 10k total): 22,800 and 112,800 vertices in all.
  Vertices are the rings one after the other (outer CCW, holes CW), segments close each
  ring, the hole points are the ellipse centres. Every CDT of it has n + 2h - 2 triangles.
* C2 — Triangle's sample polygons, every ``.poly`` file in ``../shared/corpus/triangle/``
  (read with ``cdt_plugin.io.read_poly``; vertices, segments and hole points, regions
  ignored), one call per file, times summed per round. ``c2-all`` is all of them;
  ``c2-polygons`` only the files that are polygons with holes (no free vertex, no
  dangling segment), so that the polygon-only peers run too.
* C3 — crossing segments: 1,000 random segments in the unit square (seeded; about 110,000
  crossings), meshed over their convex hull with every crossing inserted (ours:
  ``intersections="split", keep_hull=True``, snap rounding; Triangle: ``pcQ``, which
  splits crossing segments too; pythoncdt: ``TRY_RESOLVE`` and ``erase_super_triangle``).
  The polygon peers do not take it.

Peers, all run in the same worker process, interleaved round-robin:

* ``triangle``  — Shewchuk's Triangle, ``triangle.triangulate({vertices, segments, holes}, 'pQ')``;
  the reference;
* ``ours``      — ``cdt_plugin.triangulate(V, S, holes=H, workers=1)`` (Triangle's hole-point
  convention), one thread;
* ``ours_threads`` — the same with its default ``workers`` (every core: from
  ``cdt.PARALLEL_VERTICES`` (200,000) vertices the Delaunay stage builds the first cut's
  halves on two threads);
* ``ours_eo``   — ``cdt_plugin.triangulate(V, S)`` (no hole points: even-odd depth);
* ``pythoncdt`` — artem-ogre/CDT: ``insert_vertices(V)``, ``insert_edges(S as uint32)``,
  ``erase_outer_triangles_and_holes()`` (even-odd depth, it takes no hole points),
  ``triangles_array(copy=False)['vertices']``;
* ``geos``      — ``shapely.constrained_delaunay_triangles(Polygon(shell, holes))`` (GEOS;
  a MultiPolygon of the faces for C2; polygons out);
* ``earcut``    — ``mapbox_earcut.triangulate_float64(V, ring_end_indices)`` (ear clipping,
  not Delaunay), one call per polygon;
* ``manifold``  — ``manifold3d.triangulate([outer, hole, ...])`` (what trimesh uses; ear
  clipping, not Delaunay), one call per polygon.

Each result's minimum angle (degrees) is computed afterwards with numpy, untimed. The
script checks (untimed) that cdt_plugin gives Triangle's triangle count, area and minimum
angle (a CDT maximises the minimum angle, so it must match exactly) and that every peer
gives n + 2h - 2 triangles on C1; any mismatch is a WARNING line in the output.

Usage (from the repository root)::

    python benchmarks/bench_cdt.py --quick            # smoke test (no 100k workload), ~1.5 minutes
    python benchmarks/bench_cdt.py                    # full run, 3 rounds, ~3.5 minutes on 2 cores
    python benchmarks/bench_cdt.py --write-readme     # full run + the README summary rows
    python benchmarks/bench_cdt.py --only ours,triangle --workloads c1-1e5

Options: ``--repeat R``, ``--slow-repeat R`` (rounds for GEOS and manifold3d on the 100k
workload, default 1: ~5 s and ~11 s per call), ``--skip-slow-peers``, ``--timeout S`` per
call, ``--no-memory``, ``--no-cold``, ``--out PATH.md``. The machinery is in ``harness.py``.

This module must not import numba or cdt_plugin at import time: the cold-start
measurement re-runs it as a fresh worker and times the import.
"""
from __future__ import annotations

import functools
import os
import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import REPO_ROOT, Impl, Suite, Workload, all_threads_label, main  # noqa: E402

CORPUS = (REPO_ROOT / ".." / "shared" / "corpus" / "triangle").resolve()
N_HOLES, HOLE_N = 200, 64

# ----------------------------------------------------------------------------- workloads


def _face(rings: list[np.ndarray]) -> dict:
    """One polygon for the polygon peers: rings (outer CCW, holes CW, not closed),
    their concatenation and the ring end indices (earcut's input)."""
    verts = np.ascontiguousarray(np.concatenate(rings), dtype=np.float64)
    ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
    rings = [verts[e - len(r):e] for r, e in zip(rings, ends)]   # views into verts
    return {"rings": rings, "verts": verts, "ends": ends}


def _ring_segments(lengths: list[int]) -> np.ndarray:
    segs, start = [], 0
    for k in lengths:
        i = np.arange(start, start + k)
        segs.append(np.column_stack([i, np.roll(i, -1)]))
        start += k
    return np.ascontiguousarray(np.concatenate(segs), dtype=np.int64)


def star_with_holes(n_outer: int, n_holes: int = N_HOLES, hole_n: int = HOLE_N, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    p1, p2 = rng.uniform(0.0, 2 * np.pi, 2)
    t = 2 * np.pi * (np.arange(n_outer) + rng.uniform(-0.4, 0.4, n_outer)) / n_outer
    r = 1.0 + 0.25 * np.sin(7 * t + p1) + 0.05 * np.sin(23 * t + p2)
    outer = np.column_stack([r * np.cos(t), r * np.sin(t)])

    radius = 0.66                                   # < min r = 0.7
    step = 2 * radius / np.sqrt(n_holes)
    while True:                                     # grid cells inside the disk
        m = int(np.ceil(2 * radius / step)) + 1
        c = (np.arange(m) - (m - 1) / 2) * step
        cells = np.stack(np.meshgrid(c, c), -1).reshape(-1, 2)
        cells = cells[np.hypot(cells[:, 0], cells[:, 1]) + step * np.sqrt(0.5) <= radius]
        if len(cells) >= n_holes:
            break
        step *= 0.98
    cells = cells[np.sort(rng.choice(len(cells), n_holes, replace=False))]
    centres = cells + rng.uniform(-0.1, 0.1, cells.shape) * step
    a = rng.uniform(0.2, 0.35, n_holes) * step
    b = rng.uniform(0.2, 0.35, n_holes) * step
    rot = rng.uniform(0.0, np.pi, n_holes)
    s = -2 * np.pi * np.arange(hole_n) / hole_n     # clockwise
    rings = [outer]
    for i in range(n_holes):
        x, y = a[i] * np.cos(s), b[i] * np.sin(s)
        cr, sr = np.cos(rot[i]), np.sin(rot[i])
        rings.append(np.column_stack([centres[i, 0] + cr * x - sr * y, centres[i, 1] + sr * x + cr * y]))
    face = _face(rings)
    return {"name": f"star{n_outer}", "V": face["verts"], "S": _ring_segments([len(q) for q in rings]),
            "H": np.ascontiguousarray(centres), "faces": [face], "not_polygon": None}


def c1(n_outer: int):
    def make() -> dict:
        return {"items": [star_with_holes(n_outer)]}
    return make


def c1_warmup(_data: dict) -> dict:
    return {"items": [star_with_holes(2000, n_holes=20, seed=1)]}


def _poly_faces(V: np.ndarray, S: np.ndarray, H: np.ndarray) -> tuple[list[dict] | None, str | None]:
    """The domain Triangle meshes (-p, hole points, no -c) as polygons with holes, or
    (None, why) when it is not one (free vertices, dangling or cut segments)."""
    import shapely
    problems = []
    free = len(V) - len(np.unique(S))
    if free:
        problems.append(f"{free} free vertices")
    polys, cuts, dangles, invalid = shapely.polygonize_full(shapely.linestrings(V[S]))
    problems += [f"{shapely.get_num_geometries(g)} {what}"
                 for g, what in ((cuts, "cut edges"), (dangles, "dangling segments"),
                                 (invalid, "invalid rings")) if not g.is_empty]
    if problems:
        return None, ", ".join(problems)
    faces = []
    holes = shapely.points(H) if len(H) else []
    for poly in shapely.get_parts(polys):
        if any(poly.contains(h) for h in holes):
            continue                                 # Triangle eats this face from a hole point
        poly = shapely.orient_polygons(poly)         # exterior CCW, interiors CW
        rings = [np.asarray(poly.exterior.coords)[:-1]] + [np.asarray(r.coords)[:-1] for r in poly.interiors]
        faces.append(_face(rings))
    return faces, None


def _read_poly_files(polygons_only: bool) -> dict:
    from cdt_plugin.io import read_poly
    files = sorted(CORPUS.glob("*.poly"))
    if not files:
        raise FileNotFoundError(f"no .poly files in {CORPUS}")
    items = []
    for f in files:
        p = read_poly(f)
        V = np.ascontiguousarray(p.vertices, dtype=np.float64)
        S = np.ascontiguousarray(p.segments, dtype=np.int64)
        H = np.ascontiguousarray(p.holes, dtype=np.float64).reshape(-1, 2)
        faces, why = _poly_faces(V, S, H)
        if polygons_only and faces is None:
            continue
        items.append({"name": f.name, "V": V, "S": S, "H": H, "faces": faces,
                      "not_polygon": None if faces is not None else f"{f.name} ({why})"})
    return {"items": items}


def c2(polygons_only: bool):
    def make() -> dict:
        return _read_poly_files(polygons_only)
    return make


def segment_soup(m: int, seed: int = 0) -> dict:
    """``m`` random segments in the unit square: ends drawn uniformly, so about m**2 / 9
    pairs cross. Meshed over the convex hull, crossings inserted (``split``)."""
    V = np.random.default_rng(seed).random((2 * m, 2))
    S = np.arange(2 * m, dtype=np.int64).reshape(m, 2)
    return {"name": f"soup{m}", "V": V, "S": S, "H": np.empty((0, 2)), "faces": None,
            "not_polygon": f"soup{m} (crossing segments)", "split": True}


def c3(m: int):
    def make() -> dict:
        return {"items": [segment_soup(m)]}
    return make


def c3_warmup(_data: dict) -> dict:
    return {"items": [segment_soup(30, seed=1)]}


def jagged_ring(n: int, offset: float, seed: int = 0) -> dict:
    """A ring of ``n`` vertices 50-60 from its centre, at ``offset`` on both axes.
    Far from the origin (1e15: coordinates on a grid of 0.125) rounding makes some of
    its edges cross; snap rounding (``split``) must still cost about what it costs at
    the origin, where none cross."""
    rng = np.random.default_rng(seed)
    angle = np.sort(rng.random(n)) * 2 * np.pi
    radius = 50 + 10 * rng.random(n)
    V = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)]) + offset
    S = np.column_stack([np.arange(n), (np.arange(n) + 1) % n]).astype(np.int64)
    return {"name": f"ring{n}@{offset:g}", "V": V, "S": S, "H": np.empty((0, 2)), "faces": None,
            "not_polygon": f"ring{n} at {offset:g} (edges cross after rounding)", "split": True}


def c4(offset: float):
    def make() -> dict:
        return {"items": [jagged_ring(2_000, offset)]}
    return make


def c4_warmup(_data: dict) -> dict:
    return {"items": [jagged_ring(50, 1e15, seed=1)]}


WORKLOADS = [
    Workload("c1-1e4", "C1 star 10k + 200x64 holes (22,800 v)", c1(10_000), c1_warmup,
             10_000 + N_HOLES * HOLE_N),
    Workload("c1-1e5", "C1 star 100k + 200x64 holes (112,800 v)", c1(100_000), c1_warmup,
             100_000 + N_HOLES * HOLE_N, large=True),
    Workload("c1-1e6", "C1 star 1M + 200x64 holes (1,012,800 v)", c1(1_000_000), c1_warmup,
             1_000_000 + N_HOLES * HOLE_N, large=True, impls=("triangle", "ours", "ours_threads")),
    Workload("c2-all", "C2 Triangle's .poly files, all (sum)", c2(False), size=1_000,
             number=50, memory=False),
    Workload("c2-polygons", "C2 Triangle's .poly files, polygons only (sum)", c2(True), size=1_000,
             number=50, memory=False),
    Workload("c3-1e3", "C3 1,000 crossing segments (split, convex hull)", c3(1_000), c3_warmup,
             2_000),
    Workload("c4-origin", "C4 jagged 2,000-vertex ring at the origin (split, convex hull)", c4(0.0),
             c4_warmup, 2_000),
    Workload("c4-1e15", "C4 the same ring translated by 1e15 (48 edge pairs cross after rounding)",
             c4(1e15), c4_warmup, 2_000),
]

# ----------------------------------------------------------------------------- quality


def min_angle_deg(T: np.ndarray) -> float:
    """Smallest interior angle (degrees) of triangles T (k, 3, 2); 0 for a flat one."""
    if len(T) == 0:
        return float("nan")
    angles = []
    for i in range(3):
        u = T[:, (i + 1) % 3] - T[:, i]
        v = T[:, (i + 2) % 3] - T[:, i]
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        dot = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
        angles.append(np.arctan2(cross, dot).min())
    return float(np.degrees(min(angles)))


def quality(tris: list[np.ndarray]) -> dict:
    """min angle, total area and number of clockwise triangles of the per-item triangles."""
    T = np.concatenate([t.reshape(-1, 3, 2) for t in tris]) if tris else np.zeros((0, 3, 2))
    a, b, c = T[:, 0], T[:, 1], T[:, 2]
    signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    return {"min_angle": min_angle_deg(T), "area": float(np.abs(signed).sum()),
            "cw": int((signed < 0).sum()), "per_item": [len(t) for t in tris]}


# ----------------------------------------------------------------------------- implementations


def setup_triangle():
    import triangle

    def one(d):
        pslg = {"vertices": d["V"], "segments": d["S"]}
        if len(d["H"]):
            pslg["holes"] = d["H"]                   # an empty holes array crashes triangle
        return triangle.triangulate(pslg, "pcQ" if d.get("split") else "pQ")

    def run(data):
        return [one(d) for d in data["items"]]
    return run


def count_triangle(res) -> int:
    return sum(len(r.get("triangles", ())) for r in res)


def extras_triangle(_data, res) -> dict:
    return quality([r["vertices"][r["triangles"]] if "triangles" in r else np.zeros((0, 3, 2))
                    for r in res])            # no "triangles" key when everything is eaten (box.poly)


def setup_ours(even_odd: bool = False, workers: int | None = None):
    def setup():
        import cdt_plugin
        triangulate = functools.partial(cdt_plugin.triangulate, workers=workers)

        def one(d):
            if d.get("split"):
                return triangulate(d["V"], d["S"], intersections="split", keep_hull=True)
            if even_odd:
                return triangulate(d["V"], d["S"])
            return triangulate(d["V"], d["S"], holes=d["H"])

        def run(data):
            return [one(d) for d in data["items"]]
        return run
    return setup


def _parallel_vertices() -> int:
    """From how many vertices ``triangulate`` builds its Delaunay stage on two threads
    (``cdt.PARALLEL_VERTICES``, read from the source: importing cdt_plugin here would
    import numba before the cold-start timings of the worker processes)."""
    source = (REPO_ROOT / "cdt_plugin" / "cdt.py").read_text(encoding="utf-8")
    return int(re.search(r"^PARALLEL_VERTICES = ([\d_]+)$", source, re.M).group(1))


def count_ours(res) -> int:
    return sum(len(t.triangles) for t in res)


def extras_ours(_data, res) -> dict:
    return quality([np.asarray(t.vertices)[np.asarray(t.triangles)] for t in res])


def setup_pythoncdt():
    import pythoncdt as cdt

    def one(d):
        split = d.get("split", False)
        t = cdt.Triangulation(cdt.VertexInsertionOrder.AUTO,
                              cdt.IntersectingConstraintEdges.TRY_RESOLVE if split
                              else cdt.IntersectingConstraintEdges.NOT_ALLOWED, 0.0)
        t.insert_vertices(d["V"])                    # (n, 2) C-contiguous float64 buffer
        t.insert_edges(d["S"].astype(np.uint32))     # it accepts only uint32 (CDT::VertInd)
        if split:
            t.erase_super_triangle()                 # the convex hull, crossings inserted
            return t.triangles_array(copy=False)["vertices"], t.vertices_array()
        t.erase_outer_triangles_and_holes()          # even-odd depth; no hole points
        return t.triangles_array(copy=False)["vertices"]   # the view keeps t alive

    def run(data):
        return [one(d) for d in data["items"]]
    return run


def count_pythoncdt(res) -> int:
    return sum(len(r[0]) if isinstance(r, tuple) else len(r) for r in res)


def extras_pythoncdt(data, res) -> dict:
    tris = []
    for d, r in zip(data["items"], res):
        if isinstance(r, tuple):            # split: its vertices, crossings included
            T, V = r
            tris.append(np.column_stack([V["x"], V["y"]])[T.astype(np.int64)])
        else:
            tris.append(d["V"][r.astype(np.int64)])
    return quality(tris)


def _require_polygons(data) -> None:
    bad = [d["name"] for d in data["items"] if d["faces"] is None]
    if bad:
        raise ValueError("not polygons with holes (free vertices or dangling segments): " + ", ".join(bad))


def setup_geos():
    import shapely
    if not hasattr(shapely, "constrained_delaunay_triangles"):
        raise ImportError(f"shapely {shapely.__version__} has no constrained_delaunay_triangles (need 2.1)")

    def one(d):
        polys = [shapely.Polygon(f["rings"][0], f["rings"][1:]) for f in d["faces"]]
        geom = polys[0] if len(polys) == 1 else shapely.MultiPolygon(polys)
        return shapely.constrained_delaunay_triangles(geom)

    def run(data):
        _require_polygons(data)
        return [one(d) for d in data["items"]]
    return run


def count_geos(res) -> int:
    import shapely
    return int(sum(shapely.get_num_geometries(g) for g in res))


def extras_geos(_data, res) -> dict:
    import shapely
    tris = []
    for g in res:
        parts = shapely.get_parts(g)
        tris.append(shapely.get_coordinates(shapely.get_exterior_ring(parts)).reshape(-1, 4, 2)[:, :3])
    return quality(tris)


def setup_earcut():
    import mapbox_earcut as earcut

    def run(data):
        _require_polygons(data)
        return [[earcut.triangulate_float64(f["verts"], f["ends"]) for f in d["faces"]]
                for d in data["items"]]
    return run


def count_earcut(res) -> int:
    return sum(len(idx) // 3 for faces in res for idx in faces)


def extras_earcut(data, res) -> dict:
    return quality([np.concatenate([f["verts"][idx.astype(np.int64).reshape(-1, 3)]
                                    for f, idx in zip(d["faces"], faces)] or [np.zeros((0, 3, 2))])
                    for d, faces in zip(data["items"], res)])


def setup_manifold():
    import manifold3d

    def run(data):
        _require_polygons(data)
        return [[manifold3d.triangulate(f["rings"]) for f in d["faces"]] for d in data["items"]]
    return run


def count_manifold(res) -> int:
    return sum(len(idx) for faces in res for idx in faces)


def extras_manifold(data, res) -> dict:
    return quality([np.concatenate([f["verts"][np.asarray(idx, dtype=np.int64).reshape(-1, 3)]
                                    for f, idx in zip(d["faces"], faces)] or [np.zeros((0, 3, 2))])
                    for d, faces in zip(data["items"], res)])


IMPLS = [
    Impl("triangle", "Triangle", setup_triangle, count_triangle, extras=extras_triangle,
         timed="dict in (vertices, segments, holes), 'pQ', dict of arrays out", dist="triangle"),
    Impl("ours", "cdt_plugin, 1 thread", setup_ours(False, 1), count_ours, extras=extras_ours,
         timed="triangulate(V, S, holes=H, workers=1), arrays in, Triangulation out", dist="cdt-plugin",
         numba_cold_start=True, package="cdt_plugin"),
    Impl("ours_threads", f"cdt_plugin, {all_threads_label()}", setup_ours(False), count_ours,
         extras=extras_ours, timed="triangulate(V, S, holes=H) (workers: every core; the Delaunay "
         f"stage on two threads from {_parallel_vertices():,} vertices)"),
    Impl("ours_eo", "cdt_plugin (even-odd)", setup_ours(True), count_ours, extras=extras_ours,
         timed="triangulate(V, S) without hole points (workers: every core)"),
    Impl("pythoncdt", "CDT (pythoncdt)", setup_pythoncdt, count_pythoncdt, extras=extras_pythoncdt,
         timed="uint32 edges + insert + insert_edges + erase_outer_triangles_and_holes + triangle array",
         dist="pythoncdt"),
    Impl("geos", "GEOS (shapely)", setup_geos, count_geos, extras=extras_geos,
         timed="Polygon from rings + constrained_delaunay_triangles (polygons out)", slow=True,
         dist="shapely"),
    Impl("earcut", "earcut (not Delaunay)", setup_earcut, count_earcut, extras=extras_earcut,
         timed="triangulate_float64(V, ring ends), index array out", dist="mapbox_earcut"),
    Impl("manifold", "manifold3d (not Delaunay)", setup_manifold, count_manifold,
         extras=extras_manifold, timed="triangulate(list of rings), index array out", slow=True,
         dist="manifold3d"),
]

# ----------------------------------------------------------------------------- checks

GOAL_RATIO_TRIANGLE = 1.5      # DESIGN.md: at 100k vertices at most 1.5x Triangle's time
GOAL_SPEEDUP_GEOS = 10.0       # ... and at least 10x faster than shapely
GOAL_THREADS_RATIO = 0.65      # issue #18: with two threads at most 0.65x Triangle's time


def checks(results: dict) -> list[str]:
    warnings: list[str] = []
    labels = {i.name: i.label for i in IMPLS}
    for wl in WORKLOADS:
        row = results["workloads"].get(wl.name)
        if not row:
            continue
        ref = row.get("triangle", {})
        expected = None
        if wl.name.startswith("c1"):
            expected = wl.size + 2 * N_HOLES - 2
            for name, c in row.items():
                if c.get("count") is not None and c["count"] != expected:
                    warnings.append(f"{wl.label}: {labels[name]} gives {c['count']:,d} triangles, "
                                    f"expected n + 2h - 2 = {expected:,d}")
        for name in ("ours", "ours_threads", "ours_eo"):
            c = row.get(name)
            if not c or c.get("count") is None or ref.get("count") is None:
                continue
            if name == "ours_eo" and wl.name.startswith("c2"):
                continue                 # no hole points: a different domain by design (box.poly)
            if c["count"] != ref["count"] and expected is None:
                warnings.append(f"{wl.label}: {labels[name]} gives {c['count']:,d} triangles, "
                                f"Triangle {ref['count']:,d}")
            ours_x, ref_x = c.get("extras") or {}, ref.get("extras") or {}
            if ours_x.get("per_item") and ref_x.get("per_item") and ours_x["per_item"] != ref_x["per_item"]:
                diff = [i for i, (p, q) in enumerate(zip(ours_x["per_item"], ref_x["per_item"])) if p != q]
                warnings.append(f"{wl.label}: {labels[name]} per-input triangle counts differ from "
                                f"Triangle's at item(s) {diff}")
            if ours_x.get("area") is not None and ref_x.get("area") is not None:
                if abs(ours_x["area"] - ref_x["area"]) > 1e-9 * max(abs(ref_x["area"]), 1e-300):
                    warnings.append(f"{wl.label}: {labels[name]} covers area {ours_x['area']!r}, "
                                    f"Triangle {ref_x['area']!r}")
            ma, mb = ours_x.get("min_angle"), ref_x.get("min_angle")
            if ma is not None and mb is not None and ma == ma and mb == mb and abs(ma - mb) > 1e-9:
                warnings.append(f"{wl.label}: {labels[name]} minimum angle {ma:.12g} deg, Triangle "
                                f"{mb:.12g} deg (a CDT maximises the minimum angle: they must agree)")
            if ours_x.get("cw"):
                warnings.append(f"{wl.label}: {labels[name]} has {ours_x['cw']} clockwise triangles")
    big = results["workloads"].get("c1-1e5")
    if big:
        ours = (big.get("ours") or {}).get("median")
        tri = (big.get("triangle") or {}).get("median")
        geos = (big.get("geos") or {}).get("median")
        if ours and tri and ours / tri > GOAL_RATIO_TRIANGLE:
            warnings.append(f"goal not met (DESIGN.md): cdt_plugin takes {ours / tri:.2f}x Triangle's "
                            f"time on C1 100k (goal: at most {GOAL_RATIO_TRIANGLE}x)")
        threads = (big.get("ours_threads") or {}).get("median")
        if threads and tri and threads / tri > GOAL_THREADS_RATIO:
            warnings.append(f"goal not met (issue #18): cdt_plugin on all threads takes {threads / tri:.2f}x "
                            f"Triangle's time on C1 100k (goal with two threads: at most "
                            f"{GOAL_THREADS_RATIO}x): the Delaunay stage runs on two threads (from "
                            f"{_parallel_vertices():,} vertices: below, the threads' set-up costs what "
                            "they save), the segments, the domain and the output on one")
        if ours and geos and geos / ours < GOAL_SPEEDUP_GEOS:
            warnings.append(f"goal not met (DESIGN.md): cdt_plugin is {geos / ours:.1f}x faster than "
                            f"GEOS on C1 100k (goal: at least {GOAL_SPEEDUP_GEOS:g}x)")
    return warnings


SUITE = Suite(
    name="cdt",
    title="Constrained Delaunay triangulation of polygons with holes",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="triangle",
    script=os.path.abspath(__file__),
    cold_workload="c1-1e4",
    quick_max_size=100_000,
    columns=[("min_angle", "min angle deg", ".4g")],
    checks=checks,
    notes=[
        "C1: the outer ring has 10k / 100k vertices, the 200 holes 64 each. C2: the per-call "
        "time summed over the files (mean of 50 back-to-back passes per round); GEOS, earcut "
        "and manifold3d take polygons only, so `c2-all` (which has free vertices and dangling "
        "segments) is n/a for them. CDT (pythoncdt) and cdt_plugin (even-odd) take no hole "
        "points and decide the domain by even-odd depth (box.poly: 2 triangles instead of "
        "Triangle's 0). earcut drops collinear vertices (double_hex*), hence fewer triangles.",
        "C3: 1,000 random segments whose ~110,000 crossings are all inserted, meshed over the "
        "convex hull (Triangle `pcQ`; cdt_plugin `intersections=\"split\", keep_hull=True`, "
        "which snap-rounds the crossings and runs the route twice: once to find that segments "
        "cross, once with the snapped crossings; pythoncdt `TRY_RESOLVE`). Both cdt_plugin rows "
        "run the same call here. The polygon peers do not take crossing segments.",
        "Minimum angle: smallest interior angle of the output triangles, computed with numpy "
        "after the run (untimed). A CDT maximises it over all triangulations of the same input, "
        "so an exact CDT agrees with Triangle. earcut and manifold3d are ear clippers, not "
        "Delaunay. GEOS ear-clips and then runs at most 200 passes of Delaunay flips "
        "(JTS/GEOS `TriDelaunayImprover`), so on large inputs it can stop short of the CDT: "
        "a smaller minimum angle than Triangle's shows it.",
    ],
)

if __name__ == "__main__":
    sys.exit(main(SUITE))
