"""Delaunay triangulation of point sets: cdt_plugin against its peers.

Workloads (DESIGN.md, "Benchmarks"):

* D1 — uniform random points in the unit square, 1e4 / 1e5 / 1e6 / 1e7 points (seeded;
  1e7: Triangle and cdt_plugin only, one round, for time and peak memory at scale);
* D2 — the 1000 x 1000 integer grid (1e6 points, massively cocircular);
* D3 — 1e5 points with a large coordinate offset: ``round(5e5 + U(0, 1000), 3)``
  (UTM-like coordinates at millimetre resolution).

Peers, all run in the same worker process, interleaved round-robin:

* ``triangle``  — Shewchuk's Triangle (``triangle.triangulate({'vertices': P}, 'Q')``); the reference;
* ``qhull``     — ``scipy.spatial.Delaunay(P)``;
* ``pythoncdt`` — artem-ogre/CDT (``pythoncdt.Triangulation``: ``insert_vertices(P)``,
  ``erase_super_triangle()``, ``triangles_array()['vertices']``);
* ``geos``      — ``shapely.delaunay_triangles(shapely.multipoints(P))`` (GEOS);
* ``ours``      — ``cdt_plugin.delaunay(P, workers=1)``;
* ``ours_threads`` — ``cdt_plugin.delaunay(P)``: from 50,000 points the halves of
  the first cut are built on two threads.

Usage (from the repository root)::

    python benchmarks/bench_delaunay.py --quick            # smoke test, 2-3 minutes (mostly the cold compile)
    python benchmarks/bench_delaunay.py                    # full run, 3 rounds
    python benchmarks/bench_delaunay.py --write-readme     # full run + the README summary rows
    python benchmarks/bench_delaunay.py --only ours,triangle --workloads d1-1e5

Options: ``--repeat R``, ``--slow-repeat R`` (rounds for Qhull/GEOS on the 1e6 workloads,
default 1: on the grid they take ~35 s and ~70 s per call), ``--skip-slow-peers`` (none at all),
``--timeout S`` per call, ``--no-memory``, ``--no-cold``, ``--out PATH.md``.
The machinery (interleaving, timeouts, memory, cold start, tables) is in ``harness.py``.

This module must not import numba or cdt_plugin at import time: the cold-start
measurement re-runs it as a fresh worker and times the import.
"""
from __future__ import annotations

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import Impl, Suite, Workload, all_threads_label, main  # noqa: E402

# ----------------------------------------------------------------------------- workloads


def uniform(n: int, seed: int):
    def make() -> np.ndarray:
        rng = np.random.default_rng(seed)
        return np.ascontiguousarray(rng.uniform(0.0, 1.0, (n, 2)), dtype=np.float64)
    return make


def grid(m: int):
    def make() -> np.ndarray:
        ij = np.mgrid[0:m, 0:m].reshape(2, -1).T
        return np.ascontiguousarray(ij, dtype=np.float64)
    return make


def offset(n: int, seed: int):
    def make() -> np.ndarray:
        rng = np.random.default_rng(seed)
        return np.ascontiguousarray(np.round(5e5 + rng.uniform(0.0, 1000.0, (n, 2)), 3))
    return make


def subset(data: np.ndarray, k: int = 5000) -> np.ndarray:
    """Warm-up input: k points of the workload itself (same kind of geometry)."""
    if len(data) <= k:
        return data
    idx = np.random.default_rng(0).choice(len(data), k, replace=False)
    return np.ascontiguousarray(data[np.sort(idx)])


WORKLOADS = [
    Workload("d1-1e4", "D1 uniform 1e4", uniform(10_000, 101), subset, 10_000),
    Workload("d1-1e5", "D1 uniform 1e5", uniform(100_000, 102), subset, 100_000),
    Workload("d1-1e6", "D1 uniform 1e6", uniform(1_000_000, 103), subset, 1_000_000, large=True),
    Workload("d1-1e7", "D1 uniform 1e7", uniform(10_000_000, 105), subset, 10_000_000, large=True,
             impls=("triangle", "ours", "ours_threads"), rounds=1),
    Workload("d2-grid", "D2 grid 1000x1000", grid(1000), subset, 1_000_000, large=True),
    Workload("d3-offset", "D3 offset 5e5, 1e5 pts", offset(100_000, 104), subset, 100_000),
]

# ----------------------------------------------------------------------------- implementations


def setup_triangle():
    import triangle

    def run(P):
        return triangle.triangulate({"vertices": P}, "Q")
    return run


def setup_qhull():
    from scipy.spatial import Delaunay

    def run(P):
        return Delaunay(P)
    return run


def setup_pythoncdt():
    import pythoncdt as cdt

    def run(P):
        t = cdt.Triangulation(cdt.VertexInsertionOrder.AUTO,
                              cdt.IntersectingConstraintEdges.NOT_ALLOWED, 0.0)
        t.insert_vertices(P)           # (n, 2) C-contiguous float64 buffer
        t.erase_super_triangle()
        return t.triangles_array(copy=False)["vertices"]
    return run


def setup_geos():
    import shapely
    if not hasattr(shapely, "delaunay_triangles"):
        raise ImportError(f"shapely {shapely.__version__} has no delaunay_triangles (need 2.x)")

    def run(P):
        return shapely.delaunay_triangles(shapely.multipoints(P))
    return run


def count_geos(result) -> int:
    import shapely
    return int(shapely.get_num_geometries(result))


def setup_ours(workers=None):
    def setup():
        from cdt_plugin import delaunay

        def run(P):
            return delaunay(P, workers=workers)
        return run
    return setup


IMPLS = [
    Impl("triangle", "Triangle", setup_triangle, lambda r: len(r["triangles"]),
         timed="dict in, dict of arrays out", dist="triangle"),
    Impl("ours", "cdt_plugin, 1 thread", setup_ours(1), lambda t: len(t.triangles),
         timed="delaunay(P, workers=1), array in, Triangulation out", dist="cdt-plugin",
         numba_cold_start=True, package="cdt_plugin"),
    Impl("ours_threads", f"cdt_plugin, {all_threads_label()}", setup_ours(None), lambda t: len(t.triangles),
         timed="delaunay(P) (workers: every core), array in, Triangulation out"),
    Impl("pythoncdt", "CDT (pythoncdt)", setup_pythoncdt, len,
         timed="insert + erase super-triangle + triangle array", dist="pythoncdt"),
    Impl("geos", "GEOS (shapely)", setup_geos, count_geos,
         timed="MultiPoint from array + delaunay_triangles (polygons out)", slow=True, dist="shapely"),
    Impl("qhull", "Qhull (scipy)", setup_qhull, lambda r: len(r.simplices),
         timed="Delaunay(P)", slow=True, dist="scipy"),
]

SUITE = Suite(
    name="delaunay",
    title="Delaunay triangulation of point sets",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="triangle",
    script=os.path.abspath(__file__),
    cold_workload="d1-1e4",
)

if __name__ == "__main__":
    sys.exit(main(SUITE))
