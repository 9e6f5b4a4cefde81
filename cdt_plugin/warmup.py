"""Every route compiled ahead of time: the ``cdt-plugin compile`` command.

Each route of :data:`cdt_plugin.compiling.ROUTES` is warmed up by the public
calls that compile it (or load it from numba's cache), as a user makes them:
for Docker images, CI and Dask workers.

>>> from cdt_plugin.warmup import WARMUPS
>>> from cdt_plugin.compiling import ROUTES
>>> tuple(WARMUPS) == ROUTES
True
"""
from __future__ import annotations

import time
from typing import Callable, Iterable

import numpy as np

from ._core.plain import (plain_polygon_collection, plain_polygon_faces, plain_ring_collection,
                          plain_ring_faces)
from ._core.rings import drop_closing_points, open_rings, polygon_rings
from .batch import triangulate_rings
from .cdt import PARALLEL_VERTICES, triangulate
from .compiling import ROUTES
from .delaunay import PARALLEL_POINTS, delaunay
from .dynamic import DynamicCDT
from .errors import CDTError, SegmentIntersectionError
from .nearness import size_near


def _square():
    return np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]]), np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def _delaunay():
    delaunay(np.random.default_rng(0).uniform(size=(20, 2)))
    delaunay(np.random.default_rng(0).uniform(size=(PARALLEL_POINTS, 2)), workers=2)   # two threads


def _weighted():
    rng = np.random.default_rng(0)
    delaunay(rng.uniform(size=(20, 2)), rng.uniform(0, 0.01, 20))


def _triangulate():
    tri = triangulate(*_square())
    tri.is_delaunay()
    triangulate(*_square(), merge_distance=1e-9)                 # (the merging kernel)
    tri.vertex_markers, tri.segment_markers, tri.edge_markers    # (the boundary kernel)
    xy, bounds = open_rings(np.zeros((4, 2)), np.zeros(0, np.int64))    # the reader of shapely Polygons
    polygon_rings(xy, bounds[:-1], bounds[1:])
    drop_closing_points(np.zeros((4, 2)), np.array([4]))    # ... of MultiPolygons and layers
    closed = np.array([[0, 0], [1, 0], [1, 1], [0, 0.0]])     # the drop-ins' one-polygon route
    for route in (plain_ring_faces, plain_polygon_faces):
        route(closed, 1e-9)
    for route in (plain_ring_collection, plain_polygon_collection):
        route(closed)
    n = PARALLEL_VERTICES
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
    r = 1.0 + 0.1 * np.sin(7 * t)
    triangulate(np.column_stack([r * np.cos(t), r * np.sin(t)]), ring, workers=2)    # Delaunay stage on two threads


def _refine():
    tri = triangulate(*_square(), min_angle=30, max_area=0.1)
    tri.refine(max_area=np.full(len(tri.triangles), 0.05))      # an existing mesh (-r)
    triangulate(*_square(), size=size_near([[0.5, 0.5]], 0.2, 0.5, distance=1.0))   # sizes near
    tri.smooth(iterations=1)                                     # smoothing its Steiner points


def _split():
    bowtie = np.array([[0, 0], [2, 2], [2, 0], [0, 2.0]])
    triangulate(bowtie, [[0, 1], [1, 2], [2, 3], [3, 0]], intersections="split")
    try:       # the error naming the crossing where split would insert it (split_crossing)
        triangulate(bowtie, [[0, 1], [1, 2], [2, 3], [3, 0]])
    except SegmentIntersectionError:
        pass


def _batch():
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [3, 0], [2, 1.0]])
    triangulate_rings(xy, [0, 4, 7], [0, 1, 2], [0, 0], [False, False])
    triangulate_rings(xy, [0, 4, 7], [0, 1, 2], [0, 0], [False, False], min_angle=30)


def _voronoi():
    tri = delaunay(np.random.default_rng(0).uniform(size=(20, 2)))
    tri.voronoi(clip=(0.0, 0.0, 1.0, 1.0))      # from the store: the cells, a box clip
    tri.delaunay_subdivision().indices          # the faces of triangles
    grid = delaunay(np.array([[x, y] for x in range(3) for y in range(3)], float))
    grid.voronoi()                               # ties: the faces fused, the general route


def _query():
    tri = triangulate(*_square())
    tri.locate([[0.5, 0.5]])
    tri.interpolate([0.0, 1.0, 2.0, 1.0], [[0.5, 0.25]])
    tri.interpolate([0.0, 1.0, 2.0, 1.0], [[0.5, 0.25]], method="natural")


def _dynamic():
    dyn = DynamicCDT(_square()[0], [[0, 2]])
    dyn.insert_points([[0.25, 0.5]])
    dyn.remove_vertices([4])
    dyn.triangulation(domain="even-odd")


#: The warm-up of each route of :data:`cdt_plugin.compiling.ROUTES`, in that order.
WARMUPS: dict[str, Callable[[], None]] = {
    "delaunay": _delaunay, "weighted": _weighted, "triangulate": _triangulate,
    "refine": _refine, "split": _split, "batch": _batch, "voronoi": _voronoi, "query": _query,
    "dynamic": _dynamic,
}


def compile_routes(routes: Iterable[str] | None = None,
                   report: Callable[[str], None] | None = None) -> dict[str, float]:
    """Compile (or load from the cache) every route, or the ``routes`` named
    (of :data:`cdt_plugin.compiling.ROUTES`). Returns the seconds each took;
    ``report`` is called with a line per route."""
    names = list(ROUTES) if routes is None else list(routes)
    unknown = [n for n in names if n not in WARMUPS]
    if unknown:
        raise CDTError(f"unknown route {unknown[0]!r}; the routes are {sorted(ROUTES)}")
    seconds = {}
    for name in names:
        t0 = time.perf_counter()
        WARMUPS[name]()
        seconds[name] = time.perf_counter() - t0
        if report is not None:
            report(f"{name}: {seconds[name]:.1f} s")
    return seconds
