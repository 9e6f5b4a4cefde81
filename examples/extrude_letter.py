"""Extrude a letter "B" (an outline with two counters) to an STL solid.

The letter is drawn with shapely (a stem, two round bowls, two counters cut
out), turned into a trimesh ``Path2D``, triangulated by cdt_plugin (constrained
Delaunay, no Steiner points), extruded into a watertight solid, written as STL,
reloaded and checked. For comparison it also prints the minimum angle of
trimesh's default earcut triangulation of the same polygon.

    python examples/extrude_letter.py                 # writes out/letter_B.stl
    python examples/extrude_letter.py my/letter.stl --height 2.5
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import shapely
import trimesh

import cdt_plugin
from cdt_plugin.adapters.trimesh import extrude_path, from_path2d


def letter_b(quad_segs: int = 16) -> shapely.Polygon:
    """A capital B, 7 units tall: a Polygon with two holes."""
    point = shapely.Point
    lower = shapely.union(shapely.box(0.0, 0.0, 3.0, 3.8), point(3.0, 1.9).buffer(1.9, quad_segs=quad_segs))
    upper = shapely.union(shapely.box(0.0, 3.4, 2.7, 7.0), point(2.7, 5.2).buffer(1.8, quad_segs=quad_segs))
    outline = shapely.union(lower, upper)
    counter_low = shapely.union(shapely.box(1.2, 1.0, 3.0, 2.8), point(3.0, 1.9).buffer(0.9, quad_segs=quad_segs))
    counter_up = shapely.union(shapely.box(1.2, 4.4, 2.7, 6.0), point(2.7, 5.2).buffer(0.8, quad_segs=quad_segs))
    letter = shapely.difference(outline, shapely.union(counter_low, counter_up))
    assert letter.geom_type == "Polygon" and len(letter.interiors) == 2 and letter.is_valid
    return letter


def min_angle(vertices, faces) -> float:
    p = np.asarray(vertices, float)[np.asarray(faces)]
    worst = 180.0
    for k in range(3):
        u, w = p[:, (k + 1) % 3] - p[:, k], p[:, (k + 2) % 3] - p[:, k]
        cos = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        worst = min(worst, float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).min()))
    return worst


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", nargs="?", default="out/letter_B.stl", help="STL file to write")
    parser.add_argument("--height", type=float, default=1.5, help="extrusion height")
    args = parser.parse_args(argv)

    letter = letter_b()
    path = trimesh.load_path(letter)                     # a trimesh Path2D of Line entities
    plc = from_path2d(path)
    tri = cdt_plugin.triangulate(plc)
    print(f"letter B: {len(plc.vertices)} vertices, {len(plc.segments)} segments, "
          f"{int(plc.ring_is_hole.sum())} holes; area {letter.area:.6f}")
    print(f"cdt_plugin: {len(tri.triangles)} triangles, constrained Delaunay: {tri.is_delaunay()}, "
          f"min angle {min_angle(tri.vertices, tri.triangles):.2f} deg")
    try:
        ev, ef = trimesh.creation.triangulate_polygon(letter, engine="earcut")
        print(f"earcut (trimesh's default): {len(ef)} triangles, min angle {min_angle(ev, ef):.2f} deg")
    except (ImportError, ValueError) as exc:              # mapbox_earcut not installed
        print(f"earcut not available: {exc}")

    (solid,) = extrude_path(path, args.height)
    output = Path(args.output)
    output.parent.mkdir(parents=True, exist_ok=True)
    solid.export(output)

    reloaded = trimesh.load(output)                       # STL: vertices merged on load
    expected = letter.area * args.height
    print(f"wrote {output}: {len(reloaded.vertices)} vertices, {len(reloaded.faces)} faces")
    print(f"reloaded: watertight {reloaded.is_watertight}, winding consistent "
          f"{reloaded.is_winding_consistent}, volume {reloaded.volume:.6f} "
          f"(area x height = {expected:.6f}, relative error {abs(reloaded.volume - expected) / expected:.1e})")
    ok = reloaded.is_watertight and reloaded.is_winding_consistent and np.isclose(
        reloaded.volume, expected, rtol=1e-6)             # STL stores float32 coordinates
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
