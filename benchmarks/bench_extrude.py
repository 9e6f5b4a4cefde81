"""Solids from a layer: building footprints extruded by a height column.

Workload E1: synthetic building footprints in a UTM CRS (EPSG:32633), laid out on
a grid of city blocks: a third rectangles, a third L shapes, a third courtyard
blocks (a rectangle with a rectangular hole), each with its own size, position
jitter, height and base (columns ``height``, ``base``, ``kind``). Implementations:

* ``cdt_plugin geo.extrude``: :func:`cdt_plugin.adapters.geo.extrude`, one batch
  triangulation on every core and the solids of the whole layer built with NumPy;
  to the flat arrays (``output="solids"``), to one merged ``Trimesh``
  (``output="merged"``), to one ``Trimesh`` per feature with its attributes
  (``output="trimesh"``), to a ``trimesh.Scene`` with one node per feature
  (``output="scene"``) and written to a ``.glb`` file (``GeoSolids.write``: the scene
  exported by trimesh);
* ``trimesh extrude_polygon``: a Python loop of
  ``trimesh.creation.extrude_polygon(polygon, height)`` per footprint (moved up to
  its base), with the ``earcut`` engine (mapbox_earcut, trimesh's default) and the
  ``manifold`` engine (manifold3d), to a list of meshes; and the earcut list concatenated into one mesh
  (``trimesh.util.concatenate``), the peer of ``output="merged"``.

Each runs once after a warm-up on 50 footprints (numba compiled and cached,
imports done), in this one process. Untimed checks on each result: how many
solids are watertight and how many have the volume area x height (relative
1e-9). The table is written by this script.

Usage (from the repository root)::

    python benchmarks/bench_extrude.py                      # 100,000 footprints
    python benchmarks/bench_extrude.py --footprints 10000   # a quicker run
"""
from __future__ import annotations

import argparse
import platform
import sys
import tempfile
from pathlib import Path

import numpy as np
from bench_gis import timed  # (the benchmarks run from this directory)

from cdt_plugin.parallel import available_cores

HERE = Path(__file__).resolve().parent


def footprints(count: int, seed: int = 0):
    """``count`` building footprints (rectangles, L shapes, courtyards) with
    ``height``, ``base`` and ``kind`` columns, in EPSG:32633."""
    import geopandas
    import shapely

    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(count)))
    k = np.arange(count)
    x0 = 500_000.0 + 40.0 * (k % side) + rng.uniform(0, 4, count)
    y0 = 5_000_000.0 + 40.0 * (k // side) + rng.uniform(0, 4, count)
    w, d = rng.uniform(12, 30, count), rng.uniform(12, 30, count)
    kind = k % 3
    geoms = np.empty(count, dtype=object)
    rect = kind == 0
    geoms[rect] = shapely.box(x0[rect], y0[rect], x0[rect] + w[rect], y0[rect] + d[rect])
    ell = np.flatnonzero(kind == 1)                  # an L: the box less its top-right quarter
    a, b = 0.5 * w[ell], 0.5 * d[ell]
    xs = np.column_stack([x0[ell], x0[ell] + w[ell], x0[ell] + w[ell], x0[ell] + a, x0[ell] + a,
                          x0[ell]])
    ys = np.column_stack([y0[ell], y0[ell], y0[ell] + b, y0[ell] + b, y0[ell] + d[ell],
                          y0[ell] + d[ell]])
    geoms[ell] = shapely.polygons(np.stack([xs, ys], axis=-1))
    yard = np.flatnonzero(kind == 2)                 # a courtyard block: a ring of width 5
    shells = shapely.linearrings(_box_coords(x0[yard], y0[yard], w[yard], d[yard]))
    holes = shapely.linearrings(_box_coords(x0[yard] + 5, y0[yard] + 5, w[yard] - 10,
                                            d[yard] - 10)[:, ::-1])
    geoms[yard] = [shapely.Polygon(s, [h]) for s, h in zip(shells, holes)]
    return geopandas.GeoDataFrame(
        {"kind": np.array(["rectangle", "L", "courtyard"])[kind],
         "height": np.round(rng.uniform(3, 60, count), 1), "base": np.round(rng.uniform(0, 5, count), 1)},
        geometry=geoms, crs="EPSG:32633")


def _box_coords(x, y, w, d):
    return np.stack([np.column_stack([x, x + w, x + w, x]),
                     np.column_stack([y, y, y + d, y + d])], axis=-1)


def checks(meshes, frame) -> tuple[int, int]:
    """(watertight, exact volume) counts over a list of meshes (None: neither)."""
    area = frame.area.to_numpy()
    height = frame["height"].to_numpy()
    tight = exact = 0
    for m, a, h in zip(meshes, area, height):
        if m is None:
            continue
        tight += bool(m.is_watertight)
        # volume of the solid moved near the origin (trimesh's sums lose digits at UTM offsets)
        moved = m.copy()
        moved.apply_translation(-m.vertices[0])
        exact += bool(abs(moved.volume - a * h) <= 1e-9 * a * h)
    return tight, exact


def trimesh_loop(frame, engine: str | None):
    import trimesh

    out = []
    for polygon, h, z in zip(frame.geometry, frame["height"], frame["base"]):
        mesh = trimesh.creation.extrude_polygon(polygon, h, engine=engine)
        mesh.apply_translation((0.0, 0.0, z))
        out.append(mesh)
    return out


def run_all(frame):
    import trimesh
    from cdt_plugin.adapters import geo

    small = frame.iloc[:50]
    rows = []
    n = len(frame)

    def add(name, seconds, solids, note=""):
        rows.append((name, seconds, solids, note))
        print(f"{name:60s} {seconds:8.2f} s {n / seconds:10.0f} footprints/s  {note}",
              file=sys.stderr)

    def ours(output):
        return geo.extrude(frame, height="height", base="base", output=output, progress=False)

    for output in ("solids", "merged", "trimesh", "scene"):
        geo.extrude(small, height="height", base="base", output=output, progress=False)
        s, out = timed(lambda output=output: ours(output))
        note = ""
        if output == "trimesh":
            tight, exact = checks(out, frame)
            note = f"{tight:,} watertight, {exact:,} of exact volume"
        elif output == "merged":
            note = f"watertight: {bool(out.is_watertight)}"
        add(f"cdt_plugin geo.extrude(output={output!r}), {_threads(available_cores())}", s,
            len(out.geometry) if output == "scene" else n, note)
        del out

    with tempfile.TemporaryDirectory() as tmp:
        glb = Path(tmp) / "city.glb"
        geo.extrude(small, height="height", base="base", output="solids").write(glb)
        s, _ = timed(lambda: geo.extrude(frame, height="height", base="base", output="solids",
                                         progress=False).write(glb))
        add(f"cdt_plugin geo.extrude(...).write('city.glb'), {_threads(available_cores())}", s, n,
            f"{glb.stat().st_size / 2**20:.0f} MB, one node per footprint")

    for engine in ("earcut", "manifold"):
        trimesh_loop(small, engine)
        s, out = timed(lambda engine=engine: trimesh_loop(frame, engine))
        tight, exact = checks(out, frame)
        add(f"trimesh.creation.extrude_polygon loop, engine {engine}", s, n,
            f"{tight:,} watertight, {exact:,} of exact volume")
        if engine == "earcut":
            s2, merged = timed(lambda meshes=out: trimesh.util.concatenate(meshes))
            add("trimesh.creation.extrude_polygon loop, engine earcut, + util.concatenate",
                s + s2, n, f"watertight: {bool(merged.is_watertight)}")
            del merged
        del out
    return rows


def _threads(n: int) -> str:
    return f"{n} thread{'s' if n > 1 else ''}"


def table(rows, frame) -> str:
    import numba
    import trimesh

    counts = frame["kind"].value_counts()
    ours = {name: s for name, s, _, _ in rows}
    peer = next(s for name, s, _, _ in rows if "engine earcut" in name and "concatenate" not in name)
    lines = [
        "# Solids from a layer: extruded building footprints",
        "",
        f"Generated by `python benchmarks/bench_extrude.py --footprints {len(frame)}` "
        f"({platform.machine()}, {available_cores()} usable cores, Python "
        f"{platform.python_version()}, numba {numba.__version__}, trimesh {trimesh.__version__}). "
        f"Workload E1: {len(frame):,} synthetic footprints in EPSG:32633 "
        f"({counts.get('rectangle', 0):,} rectangles, {counts.get('L', 0):,} L shapes, "
        f"{counts.get('courtyard', 0):,} courtyard blocks with a hole), a height and a base "
        "each; one run per implementation after a warm-up, all in one process.",
        "",
        "| implementation | seconds | footprints/s | x earcut loop's time | checks |",
        "|---|---:|---:|---:|---|",
    ]
    for name, s, _, note in rows:
        lines.append(f"| {name} | {s:.2f} | {len(frame) / s:,.0f} | {s / peer:.3f} | {note} |")
    del ours
    lines += ["", "Checks (untimed): solids that are watertight, and whose volume equals the "
              "footprint's area times its height within 1e-9 (relative; measured after moving "
              "each solid near the origin, where trimesh's volume sums keep their digits)."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--footprints", type=int, default=100_000)
    ap.add_argument("--out", default=str(HERE / "results" / "extrude.md"))
    args = ap.parse_args(argv)
    frame = footprints(args.footprints)
    rows = run_all(frame)
    text = table(rows, frame)
    Path(args.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
