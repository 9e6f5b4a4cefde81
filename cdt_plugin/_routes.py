"""The route drivers (private): the Python around the compiled constructions.

Each driver orders, scales and threads the input of one compiled construction,
retries where the construction asks for it, and returns plain arrays and
records, never a result class: the public functions (:func:`cdt_plugin.delaunay`,
:func:`cdt_plugin.triangulate`, :class:`cdt_plugin.DynamicCDT`), the result class
(:meth:`Triangulation.move_vertices` rebuilds through :func:`build_delaunay`) and
the services below it (point location completes a domain's hull through
:func:`hull_triangles`) all call them, so nothing below the public functions
calls a public function.

* the Delaunay triangulation of a point set, in order (:func:`build_delaunay`:
  the weighted retries, duplicates and submerged points) or by divide and
  conquer on one or two threads (:func:`build_divide`,
  :func:`build_divide_two_threads`);
* the chain of collinear points (:func:`collinear_chain`) and the flips that
  repair a Delaunay triangulation whose vertices moved (:func:`flip_moved`);
* the CDT route's packed output read into named arrays (:func:`route_arrays`);
* the triangles of a domain's convex hull, through the CDT route
  (:func:`hull_triangles`).
"""
from __future__ import annotations

import functools
from typing import Any, NamedTuple, Tuple

import numpy as np
from numpy.typing import NDArray

from ._core.construct import build, gather_coords, seed_first, seed_triangle, to_input_ids
from ._core.divide import (build_half, build_subdivision, cut_ranks, join_halves, quad_store,
                           right_base, split_halves)
from ._core.flips import flip_to_delaunay
from ._core.insertion import redundant_vertices
from ._core.mesh import IDX
from ._core.ordering import SMALL_SORT, brio_order, lexicographic_order
from ._core.output import first_defect
from ._core.pipeline import PACK_ARRAYS, PACK_HEADER, cdt_route_packed
from ._core.predicates import incircle_weighted, orient2d
from ._core.status import OK, ROUTE_OK
from .errors import CDTError
from .interrupts import deferred_interrupt
from .options import MeshOptions
from .parallel import map_ordered, release_freed_memory
from .types import MeshStore
from .validate import exact_range

#: A half-edge store: (tri, twin, cons, ntri)
Store = Tuple[NDArray[np.int32], NDArray[np.int32], NDArray[np.int32], int]
_NO_WEIGHTS = np.empty(0)         # divide and conquer is unweighted: it never reads them
MAX_WEIGHTED_PASSES = 50
PARALLEL_POINTS = 50_000    # from this many points, divide and conquer splits over two threads
TRIM_POINTS = 500_000       # from this many points, freed temporaries go back to the system
# the CDT route's arguments for no rings, no seeds, no crossings snapped, no store built before
_NO_IDS = np.empty(0, np.int64)
_NO_RINGS = np.empty(0, np.bool_)
_NO_SEEDS = np.empty((0, 2))
_NO_REGIONS = np.empty((0, 4))
_NOT_SNAPPED = (np.empty(0), np.empty(0), np.empty((0, 3), np.int64))
_NO_STORE = (np.empty(0, IDX), np.empty(0, IDX), np.empty(0, IDX), np.empty(0, np.int64), np.int64(0))
# the hull completion's route: divide and conquer, every triangle of the hull kept, no refinement
_HULL_OPTIONS = MeshOptions.check(keep_hull=True).route_args(use_seeds=False, refine=False)


class DelaunayBuild(NamedTuple):
    """A Delaunay triangulation as :func:`build_delaunay` leaves it: the half-edge
    store over the points ``order`` (``tri`` None when every point lies on one
    line), each input point's duplicate (``dup_of``, -1: none) and whether it
    is submerged, and the counts so far."""
    tri: NDArray[np.int32] | None
    twin: NDArray[np.int32] | None
    cons: NDArray[np.int32] | None
    ntri: int
    order: NDArray[np.int64]
    dup_of: NDArray[np.int64]
    submerged: NDArray[np.int8]
    stats: dict[str, Any]


# ------------------------------------------------------------ point sets
def build_delaunay(pts: NDArray[np.float64], w_in: NDArray[np.float64] | None, algorithm: str,
                   seed: int, threads: int) -> DelaunayBuild:
    """The (weighted) Delaunay triangulation of checked points ``pts`` by the
    resolved ``algorithm``: scaled exactly, ordered, built (divide and conquer
    on ``threads``), and for weighted points flipped and rebuilt without the
    degenerate leftovers until every edge is regular."""
    n = len(pts)
    weighted = w_in is not None
    x, y, w = _scaled_coordinates(pts, w_in)
    dup_of = np.full(n, -1, np.int64)
    submerged = np.zeros(n, np.int8)
    active = _merge_weighted_duplicates(pts, w_in, dup_of, submerged) if w_in is not None else None
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
        return DelaunayBuild(None, None, None, 0, order, dup_of, submerged, stats)

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
            return DelaunayBuild(None, None, None, 0, order, dup_of, submerged, stats)
        order = seed_first(order, k1, k2)
    stats["flips"] = int(counts[0])
    return DelaunayBuild(tri, twin, cons, ntri, order, dup_of, submerged, stats)


def collinear_chain(pts: NDArray[np.float64], order: NDArray[np.int64], w_in: NDArray[np.float64] | None,
                    dup_of: NDArray[np.int64], submerged: NDArray[np.int8]) -> NDArray[np.int64]:
    """All points on one line (Sec. 2.1): the input ids of the chain's vertices
    along the line; repeated points are marked in ``dup_of`` (the first in
    ``order`` kept) and, for weighted points, those above the lower chain in
    ``submerged``."""
    _mark_collinear_duplicates(pts, order, dup_of)
    line = np.flatnonzero((dup_of < 0) & (submerged == 0))
    line = line[np.lexsort((pts[line, 1], pts[line, 0]))]
    if w_in is not None:
        line = _lower_chain(pts, w_in, line, submerged)
    return line


def _mark_collinear_duplicates(pts, order, dup_of):
    """Exact duplicates among unsorted points (collinear case): keep the first in
    ``order``."""
    act = order[dup_of[order] < 0]
    srt = act[np.lexsort((pts[act, 1], pts[act, 0]))]
    same = np.r_[False, (pts[srt[1:]] == pts[srt[:-1]]).all(axis=1)]
    if same.any():
        head = srt[np.maximum.accumulate(np.where(~same, np.arange(len(srt)), 0))]
        dup_of[srt[same]] = head[same]


def _lower_chain(pts, w, line, submerged):
    """Weighted collinear points: keep those whose lifted points form the lower
    chain (1D weighted Delaunay); the rest are submerged. The lifted test uses an
    auxiliary point off the line, exact (its plane meets the line's vertical
    plane in the lifted segment whatever the auxiliary point is)."""
    if len(line) < 3:
        return line
    x, y, w, _ = exact_range(pts[:, 0], pts[:, 1], w)   # exact: a power of two
    pts = np.column_stack([x, y])
    a, b = pts[line[0]], pts[line[-1]]
    c = np.array([a[0] - (b[1] - a[1]), a[1] + (b[0] - a[0])])
    ccw = orient2d(a[0], a[1], b[0], b[1], c[0], c[1]) > 0
    keep: list[np.integer[Any]] = []
    for i in line:
        while len(keep) >= 2:
            p, m = keep[-2], keep[-1]
            (u, v) = (p, i) if ccw else (i, p)
            r = incircle_weighted(pts[u, 0], pts[u, 1], w[u], pts[v, 0], pts[v, 1], w[v],
                                  c[0], c[1], 0.0, pts[m, 0], pts[m, 1], w[m])
            if r > 0:
                break
            submerged[m] = 1  # on or above the lifted segment (ties: Sec. 2.9)
            keep.pop()
        keep.append(i)
    return np.asarray(keep, np.int64)


def flip_moved(mesh: MeshStore, new: NDArray[np.float64]) -> tuple[MeshStore, int, int]:
    """A copy of the store ``mesh`` over the moved vertices ``new``, made Delaunay
    again by flips (Sec. 2.5; ghost flips repair a hull that lost its
    convexity): ``(store, flips, defect)``. The store is good when ``flips >= 0``
    (the flips ended) and ``defect < 0``; else ``defect`` names a triangle of
    it that the move inverted (-1: none named) and the points need a rebuild."""
    tri, twin, cons, ntri, inf = mesh
    tri, twin, cons = tri.copy(), twin.copy(), cons.copy()
    sx, sy, _, _ = exact_range(new[:, 0], new[:, 1], None, "new_vertices")
    x = np.append(sx, 0.0)
    y = np.append(sy, 0.0)
    flips = -1
    defect = int(first_defect(tri, twin, ntri, x, y, inf, False))
    if defect < 0:      # flip only from an embedded mesh, and accept only an embedded result
        flips = int(flip_to_delaunay(tri, twin, cons, x, y, x, False, inf, ntri, 20 * ntri + 1000))
        if flips >= 0:
            defect = int(first_defect(tri, twin, ntri, x, y, inf, True))
    return (tri, twin, cons, ntri, inf), flips, defect


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
        repeated = dup_of >= 0
        if repeated.any():        # (a test first: the index arithmetic costs a small call 3 us)
            repeats = np.flatnonzero(repeated)
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
    store = join_halves((xi, yi, wi), (onext, org, free), base, left, right, inf, cap, with_cons)
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
    return build_half((xi, yi, wi), u, ranks, lo, hi, (onext, org, own_free), np.int64(first))


# ------------------------------------------------------------ the CDT route
def route_arrays(ints: NDArray[np.int64], vertices: NDArray[np.float64],
                 region_values: NDArray[np.float64] | None) -> dict[str, Any]:
    """The arrays of a route's result other than its vertices and triangles:
    views of ``ints``, laid out by ``pipeline.cdt_route_packed`` (plain
    slicing: a small call's budget is a few microseconds). ``region_values``:
    the attribute of each region seed (None without seeds)."""
    k, s, n, nk, nb = ints[:PACK_HEADER].tolist()
    p = PACK_ARRAYS + 3 * k                     # after the triangles
    per_triangle = ints[p:p + 6 * k].reshape(2, k, 3)     # neighbours, constrained flags
    p += 6 * k
    segments = ints[p:p + 2 * s].reshape(s, 2)
    p += 2 * s
    segment_ids = ints[p:p + s]
    p += s
    regions = ints[p:p + k]
    p += k
    vertex_map = ints[p:p + n]
    p += n
    below = ints[p + nk:p + nk + nb]
    attributes = None
    if region_values is not None:
        attributes = np.full(k, np.nan)
        painted = regions >= 0
        attributes[painted] = region_values[regions[painted]]
    return {"neighbors": per_triangle[0], "vertex_map": vertex_map,
            "constrained": per_triangle[1] != 0, "regions": regions, "segments": segments,
            "segment_ids": segment_ids, "steiner": np.arange(nk, len(vertices)),
            "below_min_angle": below, "region_attributes": attributes}


def route_triangles(ints: NDArray[np.int64]) -> NDArray[np.int64]:
    """The triangles of a route's packed output (a view)."""
    k = int(ints[0])
    return ints[PACK_ARRAYS:PACK_ARRAYS + 3 * k].reshape(k, 3)


def hull_triangles(vertices: NDArray[np.float64], edges: NDArray[np.int64]
                   ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """``(triangles, neighbors)`` of the convex hull of ``vertices``: their
    constrained Delaunay triangulation with every one of ``edges`` a segment
    (one call of the CDT route, every triangle of the hull kept), so it holds
    every triangle that has its edges among ``edges``. Raises
    :class:`CDTError` where the edges cross or the vertices repeat."""
    x, y = vertices[:, 0].copy(), vertices[:, 1].copy()
    order = horizontal = _NO_IDS
    if len(x) >= SMALL_SORT:        # numpy's sorts beat the compiled one on many points
        order, horizontal = lexicographic_order(x, y), lexicographic_order(y, -x)
    with deferred_interrupt(len(x)):
        status, ints, _ = cdt_route_packed(
            x, y, np.ascontiguousarray(edges, np.int64), _NO_IDS, _NO_IDS, _NO_RINGS, _NO_SEEDS,
            _NO_REGIONS, order, horizontal, _HULL_OPTIONS, _NOT_SNAPPED, _NO_STORE)
    arrays = route_arrays(ints, vertices, None) if status == ROUTE_OK else None
    if arrays is None or not (arrays["vertex_map"] == np.arange(len(x))).all():
        raise CDTError("the triangulation's edges cross or its vertices repeat: it cannot be queried")
    return route_triangles(ints), arrays["neighbors"]
