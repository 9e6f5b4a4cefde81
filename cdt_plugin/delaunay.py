"""Delaunay and weighted Delaunay triangulations of point sets.

Three routes to the same triangulation (unique thanks to the symbolic
perturbation of Sec. 2.9), built in :mod:`cdt_plugin._core.construct` (the
Python around them, ordering, scaling, threads and weighted retries, is the
private route driver ``cdt_plugin._routes.build_delaunay``):

* ``"divide"`` (the default): divide and conquer with alternating cuts
  (Guibas-Stolfi, Dwyer);
* ``"incremental"``: BRIO/Hilbert insertion order, walking point location,
  Lawson flips (Sec. 2.5), ghost triangles for the hull; the route for
  weighted points (Sec. 2.8);
* ``"flip"``: the lexicographic triangulation (Sec. 2.1) followed by the flip
  algorithm (Sec. 2.5).
"""
from __future__ import annotations

import time

from numpy.typing import ArrayLike

from ._routes import PARALLEL_POINTS, TRIM_POINTS, build_delaunay
from .options import ALGORITHMS, resolve_algorithm
from .parallel import check_workers, resolve_workers
from .triangulation import Triangulation
from .validate import as_points, as_weights

__all__ = ["ALGORITHMS", "PARALLEL_POINTS", "TRIM_POINTS", "delaunay"]


def delaunay(points: ArrayLike, weights: ArrayLike | None = None, *, algorithm: str = "auto",
             seed: int = 0,
             workers: int | None = None) -> Triangulation:
    """Delaunay triangulation of a point set (weighted Delaunay with ``weights``).

    Parameters
    ----------
    points : array_like, shape (n, 2)
        The points. Exact duplicates are merged (``vertex_map``).
    weights : array_like, shape (n,), optional
        Point weights for the weighted Delaunay triangulation (Sec. 2.8): point
        ``p`` is lifted to ``|p|^2 - w``. Submerged points appear in no triangle
        and have ``vertex_map == -1``.
    algorithm : {"auto", "divide", "incremental", "flip"}
        ``"divide"``: divide and conquer with alternating cuts (Guibas-Stolfi,
        Dwyer; Triangle's default), the fastest. ``"incremental"``: randomised
        incremental insertion (BRIO order, walking location, Lawson flips).
        ``"flip"``: the lexicographic triangulation followed by the flip
        algorithm; the number of flips is ``stats["flips"]``. ``"auto"``
        (default): ``"divide"``, or ``"incremental"`` for weighted points. All
        give the same triangles; ``stats["algorithm"]`` names the route taken.
    seed : int
        Seed of the random insertion order (the output does not depend on it).
    workers : int, optional
        Threads for divide and conquer: from :data:`PARALLEL_POINTS` points,
        the two halves of the first cut are triangulated on two threads and
        merged. Default: every available core (two are used today); 1: one
        thread. The result is the same array for array whatever the number.

    Returns
    -------
    Triangulation

    Examples
    --------
    >>> import numpy as np, cdt_plugin
    >>> tri = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1], [1, 1], [0, 0]])
    >>> len(tri.triangles), tri.vertex_map.tolist(), tri.is_delaunay()
    (2, [0, 1, 2, 3, 0], True)
    """
    t0 = time.perf_counter()
    pts = as_points(points)
    w_in = as_weights(weights, len(pts))
    algorithm = resolve_algorithm(algorithm, w_in is not None)
    threads = resolve_workers(check_workers(workers), 2)
    return Triangulation.from_build(pts, w_in, build_delaunay(pts, w_in, algorithm, seed, threads), t0)
