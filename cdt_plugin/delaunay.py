"""Delaunay and weighted Delaunay triangulations of point sets.

Three routes to the same triangulation (unique thanks to the symbolic
perturbation of Sec. 2.9), built in :mod:`cdt_plugin._core.construct`:

* ``"divide"`` (the default): divide and conquer with alternating cuts
  (Guibas-Stolfi, Dwyer);
* ``"incremental"``: BRIO/Hilbert insertion order, walking point location,
  Lawson flips (Sec. 2.5), ghost triangles for the hull; the route for
  weighted points (Sec. 2.8);
* ``"flip"``: the lexicographic triangulation (Sec. 2.1) followed by the flip
  algorithm (Sec. 2.5).
"""
from __future__ import annotations

import functools
import time
from typing import Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.construct import build, gather_coords, seed_first, seed_triangle, to_input_ids
from ._core.divide import (build_half, build_subdivision, cut_ranks, join_halves, quad_store,
                           right_base, split_halves)
from ._core.flips import flip_to_delaunay
from ._core.insertion import redundant_vertices
from ._core.ordering import brio_order, lexicographic_order
from ._core.status import OK
from .errors import CDTError
from .interrupts import deferred_interrupt
from .options import resolve_algorithm
from .parallel import check_workers, map_ordered, release_freed_memory, resolve_workers
from .triangulation import Triangulation
from .validate import as_points, as_weights, exact_range

_NO_IDS = np.empty(0, np.int64)
#: A half-edge store: (tri, twin, cons, ntri)
Store = Tuple[NDArray[np.int32], NDArray[np.int32], NDArray[np.int32], int]
_NO_WEIGHTS = np.empty(0)         # divide and conquer is unweighted: it never reads them
MAX_WEIGHTED_PASSES = 50
PARALLEL_POINTS = 50_000    # from this many points, divide and conquer splits over two threads
TRIM_POINTS = 500_000       # from this many points, freed temporaries go back to the system


def _merge_weighted_duplicates(pts, w, dup_of, submerged):
    """Coincident weighted points: the heaviest one stays (its lifted point is
    lowest), lighter ones are submerged, equal weights are duplicates."""
    order = np.lexsort((-w, pts[:, 1], pts[:, 0]))
    p = pts[order]
    same = np.r_[False, (p[1:] == p[:-1]).all(axis=1)]
    if not same.any():
        return np.ones(len(pts), bool)
    group_start = np.maximum.accumulate(np.where(~same, np.arange(len(p)), 0))
    head = order[group_start]            # the heaviest of each group (first in order)
    active = np.zeros(len(pts), bool)
    active[head] = True
    later = order[same]
    lighter = w[later] < w[head[same]]
    submerged[later[lighter]] = 1
    dup_of[later[~lighter]] = head[same][~lighter]
    return active


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
    n = len(pts)
    w_in = as_weights(weights, n)
    weighted = w_in is not None
    algorithm = resolve_algorithm(algorithm, weighted)
    threads = resolve_workers(check_workers(workers), 2)
    x, y, w = _scaled_coordinates(pts, w_in)
    dup_of = np.full(n, -1, np.int64)
    submerged = np.zeros(n, np.int8)
    active = _merge_weighted_duplicates(pts, w_in, dup_of, submerged) if weighted else None
    idx = np.flatnonzero(active) if active is not None else None

    if algorithm in ("flip", "divide"):
        order = lexicographic_order(x[:n], y[:n])
    elif idx is None:
        order = brio_order(x[:n], y[:n], seed)
    else:
        order = idx[brio_order(x[idx], y[idx], seed)]
    k1, k2 = seed_triangle(x, y, order)
    stats = {"algorithm": algorithm, "input_points": n, "flips": 0, "submerged": 0}
    if k2 < 0:
        return Triangulation.from_collinear(pts, order, w_in, dup_of, submerged, stats, t0)

    if algorithm != "divide":
        order = seed_first(order, k1, k2)
    for _ in range(MAX_WEIGHTED_PASSES):
        with deferred_interrupt(n):
            tri, twin, cons, ntri, counts = _build_in_order(x, y, w, weighted, order, algorithm,
                                                            dup_of, submerged, threads)
        if not weighted:
            break
        xi, yi, wi = (np.append(a[order], 0.0) for a in (x, y, w))
        for _ in range(MAX_WEIGHTED_PASSES):   # flip leftovers until nothing changes
            redundant, flips, unexplained = redundant_vertices(tri, twin, xi, yi, wi, len(order), ntri)
            counts[0] += flips
            if flips == 0 or len(redundant):
                break
        if unexplained and len(redundant) == 0:  # refuse rather than be wrong
            raise CDTError(f"internal error: {unexplained} weighted edges could not be made regular")
        if len(redundant) == 0:
            break
        # degenerate leftovers are submerged in the true answer: rebuild without them
        submerged[order[redundant]] = 1
        order = order[submerged[order] == 0]
        k1, k2 = seed_triangle(x, y, order)
        if k2 < 0:
            return Triangulation.from_collinear(pts, order, w_in, dup_of, submerged, stats, t0)
        order = seed_first(order, k1, k2)
    stats["flips"] = int(counts[0])
    del x, y, w     # (scaled and sorted coordinates: the output of a large input needs their room)
    return Triangulation.from_mesh(pts, w_in, tri, twin, cons, ntri, order, dup_of, submerged, stats, t0)


def _scaled_coordinates(pts, w_in):
    """The coordinates (and weights) scaled by a power of two (exact), each with
    one more slot for the infinite vertex; zero weights when unweighted."""
    n = len(pts)
    sx, sy, sw, _ = exact_range(pts[:, 0], pts[:, 1], w_in)
    x = np.zeros(n + 1)
    y = np.zeros(n + 1)
    w = np.zeros(n + 1)
    x[:n] = sx
    y[:n] = sy
    if w_in is not None:
        w[:n] = sw
    return x, y, w


def _build_in_order(x, y, w, weighted, order, algorithm, dup_of, submerged, threads=1):
    """Triangulate the points ``order`` (seed triangle first) and record
    duplicates and submerged points in ``dup_of`` / ``submerged`` (input ids).
    Divide and conquer sorts ``x`` and ``y`` in place.
    Returns ``(tri, twin, cons, ntri, counts)`` over the mesh vertices of
    :mod:`cdt_plugin._core.construct` (``counts[0]``: flips). Only the
    construction asked for is called, so only it is compiled on first use."""
    m = len(order)
    counts = np.zeros(2, np.int64)
    if algorithm == "divide":
        # The largest inputs take this route (unweighted, every point in
        # order), so it holds as little as it can: the coordinates are sorted in
        # place, and dup_of (all -1 so far) first takes the repeats in mesh ids.
        x[:m] = x[order]
        y[:m] = y[order]
        tri, twin, cons, ntri = build_divide(x, y, _NO_WEIGHTS, m, dup_of, 0, threads)
        repeats = np.flatnonzero(dup_of >= 0)
        firsts = order[dup_of[repeats]]
        dup_of[repeats] = -1
        dup_of[order[repeats]] = firsts
        return tri, twin, cons, ntri, counts
    dup = np.full(m, -1, np.int64)
    sub = np.zeros(m, np.int8)
    xi, yi, wi = gather_coords(x, y, w, order, 0)
    status, tri, twin, cons, ntri = build(xi, yi, wi, weighted, m, np.arange(m),
                                          algorithm == "flip", dup, sub, counts, 0, False)
    if status != OK:  # pragma: no cover - a located point always exists
        raise CDTError(f"internal error: point location failed (status {status})")
    if algorithm == "flip":
        counts[0] = flip_to_delaunay(tri, twin, cons, xi, yi, wi, False, m, ntri)
    to_input_ids(order, dup, sub, dup_of, submerged)
    return tri, twin, cons, ntri, counts


def build_divide(xi: NDArray[np.float64], yi: NDArray[np.float64], wi: NDArray[np.float64], m: int,
                 dup: NDArray[np.int64], cap: int, threads: int, inf: int | None = None,
                 with_cons: bool | np.bool_ = False) -> Store:
    """Divide and conquer over the sorted points ``0..m-1``; with two threads
    and enough points, the halves of the first cut are built side by side in
    one set of quad-edge arrays (the kernels release the GIL) and joined into
    the arrays one thread makes. ``inf``: the infinite vertex's id (default
    ``m``: no room for more vertices); ``cap``: room for at least this many
    triangles; ``with_cons``: allocate the per-half-edge segment ids (a store
    that segments will be inserted into)."""
    inf = m if inf is None else inf
    cons = np.bool_(with_cons)
    if threads < 2 or m < PARALLEL_POINTS:
        horizontal = lexicographic_order(yi[:m], -xi[:m])   # (numpy's sort: the fastest here)
        u, r = cut_ranks(xi, yi, m, dup, horizontal)
        del horizontal
        _release_freed_memory(m)      # the sorts' temporaries, before the quad-edges are taken
        return build_subdivision(xi, yi, wi, u, r, inf, cap, cons)
    return build_divide_two_threads(xi, yi, wi, m, dup, cap, inf, cons)


def build_divide_two_threads(xi: NDArray[np.float64], yi: NDArray[np.float64], wi: NDArray[np.float64],
                             m: int, dup: NDArray[np.int64], cap: int, inf: int,
                             with_cons: bool | np.bool_) -> Store:
    """:func:`build_divide` with the halves of the first cut on two threads."""
    u, mid = split_halves(xi, yi, m, dup)
    nu = len(u)
    ranks = np.empty(nu, u.dtype)
    _release_freed_memory(m)      # the sorts' and the scaling's temporaries, before the quad-edges
    onext, org, free = quad_store(nu)
    base = right_base(mid)
    task = functools.partial(_build_half, xi, yi, wi, u, ranks, onext, org)
    left, right = map_ordered(task, [(0, mid, free[:base], 0), (mid, nu, free[base:], base)], 2)
    del task, u, ranks            # (not needed by the join: their memory is free for it)
    store = join_halves(xi, yi, wi, onext, org, free, base, *left, *right, inf, cap, with_cons)
    _release_freed_memory(m)      # what the threads and the join freed, before the output is made
    return store


def _release_freed_memory(m: int) -> None:
    """:func:`~cdt_plugin.parallel.release_freed_memory` for an input of ``m``
    points, from :data:`TRIM_POINTS` on (where what was freed is tens of MB).
    Below, the few MB freed stay for the next allocations, which would
    otherwise fault in fresh pages: at 100,000 points, the trims and the
    faults after them were 4-8 ms of an 80 ms ``delaunay(P).voronoi()``; they
    saved about 3 MB of peak memory."""
    if m >= TRIM_POINTS:
        release_freed_memory()


def _build_half(xi, yi, wi, u, ranks, onext, org, part):
    """One half ``u[lo:hi]`` of the first cut, on its thread: its ranks in the
    order of horizontal cuts, then its triangulation in the shared quad-edge
    arrays from quad-edge ``first`` on, with its own free stack."""
    lo, hi, own_free, first = part
    ids = u[lo:hi]
    ranks[lo + lexicographic_order(yi[ids], -xi[ids])] = np.arange(hi - lo)
    _release_freed_memory(len(u))     # the sort's temporaries, kept in this thread's arena
    return build_half(xi, yi, wi, u, ranks, lo, hi, onext, org, own_free, np.int64(first))
