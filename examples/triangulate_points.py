"""Delaunay triangulation of a real point set: Triangle's greenland.node (33,343 points).

    python examples/triangulate_points.py [path/to/points.node]

Reads ``../shared/corpus/triangle/greenland.node`` (relative to the repository root)
unless a path is given; without the corpus it falls back to 100,000 seeded random
points. Triangulates with ``cdt_plugin.delaunay`` and prints the vertex / triangle /
edge counts, the exact Delaunay certificate (``tri.is_delaunay()``), the minimum
angle and the timings (the first call includes numba compilation or cache loading).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import cdt_plugin

REPO_ROOT = Path(__file__).resolve().parent.parent
DEFAULT_NODE = REPO_ROOT.parent / "shared" / "corpus" / "triangle" / "greenland.node"


def parse_node(path: Path) -> np.ndarray:
    """Vertices of a Triangle .node file: header ``n dim attrs markers``, then
    ``index x y [attrs...] [marker]`` lines; ``#`` starts a comment."""
    records = []
    with open(path) as fh:
        for line in fh:
            fields = line.split("#", 1)[0].split()
            if fields:
                records.append(fields)
    n, dim = int(records[0][0]), int(records[0][1])
    if dim != 2:
        raise ValueError(f"{path}: dimension {dim}, expected 2")
    return np.array([[float(r[1]), float(r[2])] for r in records[1:1 + n]], dtype=np.float64)


def read_points(path: Path) -> np.ndarray:
    """cdt_plugin.io.read_node when the package has it, the inline parser otherwise."""
    try:
        from cdt_plugin.io import read_node
    except ImportError:
        return parse_node(path)
    data = read_node(path)
    vertices = data if isinstance(data, np.ndarray) else getattr(data, "vertices", None)
    if vertices is None and isinstance(data, dict):
        vertices = data.get("vertices")
    return parse_node(path) if vertices is None else np.asarray(vertices, dtype=np.float64)


def min_angle_degrees(vertices: np.ndarray, triangles: np.ndarray) -> float:
    """Smallest interior angle over all triangles, from the arrays."""
    if len(triangles) == 0:
        return float("nan")
    p = vertices[triangles]                            # (k, 3, 2)
    smallest = np.inf
    for i in range(3):
        u = p[:, (i + 1) % 3] - p[:, i]
        v = p[:, (i + 2) % 3] - p[:, i]
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        dot = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
        smallest = min(smallest, float(np.arctan2(cross, dot).min()))
    return float(np.degrees(smallest))


def main(argv: list[str]) -> int:
    path = Path(argv[1]) if len(argv) > 1 else DEFAULT_NODE
    if path.exists():
        points = read_points(path)
        source = str(path)
    else:
        points = np.random.default_rng(2024).uniform(0.0, 1.0, (100_000, 2))
        source = f"100,000 seeded random points ({path} not found)"
    print(f"input: {source}: {len(points):,d} points")

    t0 = time.perf_counter()
    tri = cdt_plugin.delaunay(points)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    tri = cdt_plugin.delaunay(points)
    second = time.perf_counter() - t0

    t0 = time.perf_counter()
    certified = bool(tri.is_delaunay())
    check = time.perf_counter() - t0

    print(f"vertices:  {len(tri.vertices):,d}")
    print(f"triangles: {len(tri.triangles):,d}")
    print(f"edges:     {len(tri.edges):,d}")
    print(f"Delaunay (exact check): {certified}")
    print(f"minimum angle: {min_angle_degrees(tri.vertices, tri.triangles):.6g} degrees")
    print(f"time: first call {first:.3f} s (includes JIT compile or cache load), "
          f"second call {second:.3f} s, is_delaunay {check:.3f} s")
    return 0 if certified else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
