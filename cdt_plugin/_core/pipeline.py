"""The constrained Delaunay route, once, compiled (Sec. 2.10).

:func:`cdt_route` takes one PLC as flat arrays and runs every step:
lexicographic order, the Delaunay triangulation of the vertices, duplicate
vertices merged, segments inserted by cavity retriangulation (and crossings
split, with ``split``), the domain classified by segment depth or seeds,
optional Delaunay refinement, and the output arrays. A single call to
:func:`cdt_plugin.triangulate` makes one call of it; the batch path
(:func:`mesh_geometries`) loops it over many geometries without going back to
Python. Errors come back as a status code (:mod:`.status`) with ``info``; the
Python side raises the precise :class:`cdt_plugin.CDTError`.

The route's options are one :class:`.options.RouteOptions`, whatever they
ask (refinement or not), so that numba compiles the route once: each distinct
argument type (None against a tuple) would compile and code-generate the whole
route a second time.
"""
from __future__ import annotations

import math

import numpy as np

from .arrays import copy_rows
from .borrow import unowned
from .construct import (DIVIDE, FLIP, build_mesh, gather_coords, horizontal_order, seed_first, seed_triangle,
                        store_room, to_input_ids)
from .flips import flip_to_delaunay
from .insertion import insert_vertex
from .jit import B1, F8_2, I64, I64_2, STORE, Tuple, b1, entry, i8, kernel
from .mesh import DEAD, IDX, grow_store, nxt
from .options import ROUTE_OPTIONS, named
from .ordering import HILBERT_BITS, hilbert_keys, lexicographic_order_compiled
from .output import cdt_arrays, cdt_vertices, solid_triangles
from .refine import (C_ATTEMPTS, C_DEFERRED, C_FLIPS, C_FROZEN, C_SEG_SPLITS, C_STEINER, OUT,
                     STEINER_ROOM, count_below, refine_store)
from .regions import flood_seeds, polygon_across, segment_depths, segment_rings
from .rings import ring_is_degenerate, ring_segments
from .scaling import NO_FIT, fit_shift, scaled, scaled_area, scaled_seeds, unscale_rows
from .segments import by_smaller_end, insert_segments, make_buffers, pieces_out_of_order
from .snap import steiner_limit
from .status import (ALL_DONE, FINISHED, LOCATE_FAILED, LOCATION_FAILED, NEED_EDGE_ROOM,
                     NEED_VERTEX_ROOM, OK, ROUTE_COLLINEAR, ROUTE_CROSSING, ROUTE_HOLE_OUTSIDE,
                     ROUTE_INTERNAL, ROUTE_OK, ROUTE_OVERLAP, ROUTE_POLYGONS_OVERLAP, ROUTE_RANGE,
                     ROUTE_NEEDS_SNAP, ROUTE_REFINE_LIMIT, ROUTE_STEINER_LIMIT, ROUTE_UNRESOLVED,
                     STOP_CROSSING, STOP_LIMIT, STOP_OVERLAP)

# what one route counts (``counts``; the Python side names them in ``stats``)
K_FLIPS = 0
K_ZERO_SEGMENTS = 1
K_DUPLICATE_SEGMENTS = 2
K_ON_SEGMENTS = 3
K_MERGED_OVERLAPS = 4
K_INTERSECTIONS = 5
K_DUPLICATES = 6
K_REF_STEINER = 7
K_REF_SPLITS = 8
K_REF_FLIPS = 9
K_FROZEN = 10
K_ATTEMPTS = 11
K_DEFERRED = 12
K_REF_COMPLETE = 13
K_REF_LIMIT = 14
NCOUNTS = 15

# the default cap on refinement's Steiner points: 100 per vertex + 100,000, and with
# max_area about 4 per bound area of the domain, at most AREA_STEINER_CAP more (a bound
# far below the domain's size stops there with RefinementLimitError, not after millions)
AREA_STEINER_CAP = 1_000_000

SMALL_MESH = 1 << 16    # triangles: below this, work arrays are made at once rather than on demand


@kernel
def dedup_tasks(segs, nv):
    """Segments (mesh ids) as tasks: zero-length ones dropped, repeated ones
    (either direction) merged into the first. Returns ``(tasks, ntask, mult,
    zero-length count, first)``: task rows ``a, b, segment id`` (1-based)
    stacked so that the first segment is on top, ``mult[sid]`` how many input
    segments lie on segment ``sid``, and ``first[i]`` the segment that segment
    ``i`` was merged into (-1: zero length)."""
    m = segs.shape[0]
    start, group = by_smaller_end(segs, m, nv)
    first = np.full(m, -1, np.int64)     # the kept segment each one repeats
    mult = np.zeros(m + 1, np.int64)
    for a in range(nv):
        for k in range(start[a], start[a + 1]):
            i = group[k]
            first[i] = i
            b = max(segs[i, 0], segs[i, 1])
            for kk in range(start[a], k):          # an earlier segment with the same ends
                j = group[kk]
                if first[j] == j and max(segs[j, 0], segs[j, 1]) == b:
                    first[i] = j
                    break
            mult[first[i] + 1] += 1
    nzero = m - start[nv]
    ntask = 0
    tasks = np.empty((m - nzero + 16, 3), np.int64)
    for i in range(m - 1, -1, -1):       # a stack: the first segment on top
        if first[i] == i:
            tasks[ntask, 0] = segs[i, 0]
            tasks[ntask, 1] = segs[i, 1]
            tasks[ntask, 2] = i + 1
            ntask += 1
    return tasks, ntask, mult, nzero, first


@kernel
def float_bits(v):
    """The bits of double ``v`` as an int64 (a float in the integer ``info``)."""
    return np.array([v]).view(np.int64)[0]


@kernel
def insert_points_at(mesh, w, ntri, nv, px, py):
    """Insert points ``px, py`` (distinct, none at a vertex; room made) as
    vertices ``nv, nv + 1, ...`` of ``mesh`` (``(tri, twin, cons, x, y, inf)``,
    see :mod:`.mesh`; weights ``w`` zero), in Hilbert order (short walks).
    Returns ``(ntri, nv, status)``."""
    x, y, inf = mesh[3], mesh[4], mesh[5]
    k = px.shape[0]
    for j in range(k):
        x[nv + j] = px[j]
        y[nv + j] = py[j]
        w[nv + j] = 0.0
    keys = hilbert_keys(px, py, np.arange(k), np.int64(HILBERT_BITS))
    fkeys = np.empty(k)
    for j in range(k):
        fkeys[j] = keys[j]          # (below 2**32: exact, for the compiled sort the route has)
    order = lexicographic_order_compiled(fkeys, np.zeros(k))
    stack = np.empty(inf + 16, np.int64)
    flip_counts = np.zeros(2, np.int64)
    no_weights = np.zeros(1, np.int8)
    hint = np.int64(0)
    for r in range(k):
        q = nv + order[r]
        code, p, ntri, hint = insert_vertex(mesh, (w, np.bool_(False)), q, hint, ntri,
                                            np.bool_(False), no_weights, flip_counts, stack)
        if code == LOCATE_FAILED or p != q:
            return ntri, nv, LOCATION_FAILED
    return ntri, nv + k, OK


@kernel
def chain_tasks(chains, first, segs, mesh_of, n):
    """The segment tasks for snap-rounded chains (:func:`.snap.snap_route`): the
    pieces ``(u, v, segment)`` of the segments kept by :func:`dedup_tasks`, in
    mesh ids (new points ``n + j`` are mesh vertices ``n + j``), stacked so
    that the first segment's first piece is on top. Returns ``(tasks, ntask,
    input vertices the chains pass through)``."""
    tasks = np.empty((chains.shape[0] + 16, 3), np.int64)
    ntask = 0
    passed = 0
    for r in range(chains.shape[0] - 1, -1, -1):
        u, v, s = chains[r, 0], chains[r, 1], chains[r, 2]
        if first[s] != s:
            continue
        mu = mesh_of[u] if u < n else u
        mv = mesh_of[v] if v < n else v
        if u < n and u != segs[s, 0]:
            passed += 1
        tasks[ntask, 0] = mu
        tasks[ntask, 1] = mv
        tasks[ntask, 2] = s + 1
        ntask += 1
    return tasks, ntask, passed


@kernel(apart=True, ahead=(STORE, I64_2, i8, I64_2, b1, i8, I64, I64), returns=Tuple((i8, STORE)))
def insert_all_segments(store, tasks, ntask, seg_ends, split, limit, seg_counts, info):
    """Run the segment tasks to the end in ``store`` (``(tri, twin, cons, x, y,
    w, inf, ntri, nv)``), growing it and the walk buffers as asked
    (:func:`segments.insert_segments` has the arguments). Returns ``(status,
    store)`` with the status of :func:`segments.insert_segments` (ALL_DONE or a stop)."""
    # the walk buffers: made now on small meshes (asking for them later would redo the
    # pass over the edges that are segments already), on the first walk on large ones
    tri, twin, cons, x, y, w, inf, ntri, nv = store
    buf = make_buffers(ntri if ntri <= SMALL_MESH else np.int64(0))
    while True:
        stack = np.empty(inf + 16, np.int64)
        status, ntri, nv, ntask = insert_segments((tri, twin, cons, x, y, inf), ntri, nv, tasks,
                                                  ntask, seg_ends, split, limit, (seg_counts, info),
                                                  (stack, buf))
        if status == NEED_VERTEX_ROOM:
            tri, twin, cons, x, y, w, inf = grow_store(tri, twin, cons, x, y, w, inf, nv, np.int64(0))
            grown = np.empty((2 * tasks.shape[0] + 16, 3), np.int64)
            copy_rows(grown, tasks, ntask)
            tasks = grown
        elif status == NEED_EDGE_ROOM:
            buf = make_buffers(2 * ntri)
        else:
            return status, (tri, twin, cons, x, y, w, inf, ntri, nv)


@kernel
def solid_with_flags(tri, twin, cons, ntri, inf):
    """The solid triangles ``T`` with their neighbours ``N``, the index in ``T``
    of each mesh slot (``tid``, -1: ghost or dead) and the segment id (1-based,
    0 none) of the edge opposite each vertex (``cflag``)."""
    T, N, tid = solid_triangles(tri, twin, ntri, inf)
    cflag = np.zeros((T.shape[0], 3), np.int64)
    for t in range(ntri):
        i = tid[t]
        if i >= 0:
            for j in range(3):
                cflag[i, j] = cons[3 * t + (j + 1) % 3]
    return T, N, tid, cflag


# classify's arguments in the route, for a helper process to compile it ahead (first use)
_CLASSIFY_ARGS = (STORE, Tuple((I64_2, I64_2, I64, I64_2)), Tuple((I64, I64, I64, I64, B1)),
                  Tuple((F8_2, F8_2)), ROUTE_OPTIONS, I64)


@kernel(apart=True, ahead=_CLASSIFY_ARGS, returns=Tuple((B1, I64, i8)))
def classify(store, solid, rings, seeds, options, info):
    """Which solid triangles are inside the domain, and their region: depth
    parity by default, Triangle's rule (everything enclosed, less the hole
    seeds' regions) with ``options.use_seeds``; the polygon a triangle lies in
    (rings: :func:`.regions.segment_depths`), or the region seed that paints it.

    ``store`` is the mesh ``(tri, twin, cons, x, y, w, inf, ntri, nv)``,
    ``solid`` its solid triangles ``(T, N, tid, cflag)`` (:func:`solid_with_flags`),
    ``rings`` ``(mult, seg_start, seg_rings, ring_polygon, ring_is_hole)`` (the
    input segments on each segment and their rings: :func:`.regions.segment_rings`),
    ``seeds`` ``(holes, regions)``. Returns ``(inside, region, status)``; unless
    ``options.split`` (with rings) the status is ROUTE_HOLE_OUTSIDE (``info[0]`` =
    the ring) when a polygon is entered through a hole ring from outside its
    shell, ROUTE_POLYGONS_OVERLAP (``info`` = two polygons and the mesh vertices
    of an edge where they overlap) when the rings cannot bound disjoint polygons."""
    tri, twin, cons, x, y, _, inf, ntri, _ = store
    T, N, tid, cflag = solid
    mult, seg_start, seg_rings, ring_polygon, ring_is_hole = rings
    holes, regions = seeds
    use_seeds, keep_hull, check_holes = options.use_seeds, options.keep_hull, not options.split
    k = T.shape[0]
    depth_mesh, entry_mesh, label_mesh = segment_depths(tri, twin, cons, ntri, inf, mult,
                                                        seg_start, seg_rings, ring_polygon)
    has_segments = False
    for e in range(3 * ntri):
        if cons[e] != 0:
            has_segments = True
            break
    inside = np.ones(k, np.bool_)
    region = np.full(k, -1, np.int64)
    for t in range(ntri):
        i = tid[t]
        if i < 0:
            continue
        depth = depth_mesh[t]
        if has_segments and not keep_hull:
            inside[i] = depth > 0 if use_seeds else depth % 2 == 1
        region[i] = label_mesh[t]
    if check_holes and ring_polygon.shape[0] > 0 and not keep_hull:
        for t in range(ntri):       # slot order is the order of T: the error names the first
            i = tid[t]
            if i < 0 or not inside[i] or entry_mesh[t] <= 0 or label_mesh[t] < 0:
                continue
            ring = entered_through_hole(label_mesh[t], seg_rings, seg_start[entry_mesh[t]],
                                        seg_start[entry_mesh[t] + 1], ring_polygon, ring_is_hole)
            if ring >= 0:
                info[0] = ring
                return inside, region, ROUTE_HOLE_OUTSIDE
        if may_overlap(ring_polygon, seg_start) and not polygons_disjoint(
                tri, twin, cons, ntri, label_mesh, seg_start, seg_rings, ring_polygon, info):
            return inside, region, ROUTE_POLYGONS_OVERLAP
    if holes.shape[0] > 0:
        label = np.zeros(k, np.int64)
        flood_seeds(x, y, T, N, cflag, holes[:, 0].copy(), holes[:, 1].copy(), inside, label,
                    np.full(holes.shape[0], 1, np.int64))
        for i in range(k):
            if label[i] != 0:
                inside[i] = False
    if regions.shape[0] > 0:
        label = np.full(k, -1, np.int64)
        flood_seeds(x, y, T, N, cflag, regions[:, 0].copy(), regions[:, 1].copy(),
                    np.ones(k, np.bool_), label, np.arange(regions.shape[0]))
        region = label
    return inside, region, ROUTE_OK


@kernel
def entered_through_hole(label, rings, a, b, ring_polygon, ring_is_hole):
    """The hole ring through which polygon ``label`` was entered from outside
    when the entry segment carries only hole rings of it (a hole outside its
    shell), else -1."""
    hole = -1
    for k in range(a, b):
        r = rings[k]
        if ring_polygon[r] == label:
            if not ring_is_hole[r]:
                return -1
            hole = r
    return hole


@kernel
def may_overlap(ring_polygon, seg_start):
    """Whether the rings can bound overlapping polygons at all: with one
    polygon and one ring on every segment, the rings are closed curves that do
    not cross (crossings stop the route before), so the sides of every ring
    segment alternate between inside and outside consistently."""
    for r in range(ring_polygon.shape[0]):
        if ring_polygon[r] != ring_polygon[0]:
            return True
    for s in range(1, seg_start.shape[0] - 1):
        if seg_start[s + 1] - seg_start[s] > 1:
            return True
    return False


@kernel
def polygons_disjoint(tri, twin, cons, ntri, label, seg_start, seg_rings, ring_polygon, info):
    """Whether the polygon labels agree across every ring segment (each side
    is what :func:`.regions.polygon_across` makes of the other). If not,
    ``info`` holds two polygons that overlap there (the same one twice: its own
    rings overlap) and the segment piece's mesh vertices."""
    for e in range(3 * ntri):
        sid = cons[e]
        if sid <= 0 or tri[e] == DEAD:
            continue
        a = seg_start[sid]
        b = seg_start[sid + 1]
        if a == b:
            continue
        near = label[e // 3]
        if polygon_across(near, seg_rings, a, b, ring_polygon) == label[twin[e] // 3]:
            continue
        info[0] = near if near >= 0 else ring_polygon[seg_rings[a]]
        info[1] = info[0]
        for j in range(a, b):
            if ring_polygon[seg_rings[j]] != info[0]:
                info[1] = ring_polygon[seg_rings[j]]
                break
        info[2] = tri[e]
        info[3] = tri[nxt(e)]
        return False
    return True


@kernel
def slot_labels(tid, inside, region, cap):
    """Refinement's label of every mesh slot: the region of an inside solid
    triangle, else OUT."""
    lab = np.full(cap, OUT, np.int64)
    for t in range(tid.shape[0]):
        i = tid[t]
        if i >= 0 and inside[i]:
            lab[t] = region[i]
    return lab


@kernel
def triangle_labels(tid, lab, k):
    """Back from slot labels: ``inside`` and ``region`` (-1 outside) of the
    ``k`` solid triangles."""
    inside = np.zeros(k, np.bool_)
    region = np.full(k, -1, np.int64)
    for t in range(tid.shape[0]):
        i = tid[t]
        if i >= 0 and lab[t] != OUT:
            inside[i] = True
            region[i] = lab[t]
    return inside, region


@kernel
def area_bounds(max_area, regions, lab):
    """Area bound per triangle label (``label + 1`` indexes it; 0: none): the
    global ``max_area`` (0: none) or a region seed's fourth column where
    positive. A single 0 when there is no bound at all."""
    any_region = False
    for r in range(regions.shape[0]):
        if regions[r, 3] > 0:
            any_region = True
    if max_area <= 0 and not any_region:
        return np.zeros(1)
    top = -1
    for t in range(lab.shape[0]):
        top = max(top, lab[t])
    bounds = np.full(top + 2, max_area if max_area > 0 else 0.0)
    for r in range(min(regions.shape[0], top + 1)):
        a = regions[r, 3]
        if np.isfinite(a) and a > 0:
            bounds[r + 1] = a
    return bounds


@kernel
def twice_area(x, y, a, b, c):
    return abs((x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]))


@kernel
def refinement_room(x, y, T, inside, region, area_of_label, cap):
    """About how many Steiner points the area bounds alone will add (the mesh
    is made that large at once instead of growing by doubling); at most ``cap``.
    A refined mesh has about 1.6 triangles, so 0.8 vertices, per bound area."""
    total = 0.0
    for i in range(T.shape[0]):
        if inside[i]:
            label = region[i] + 1
            bound = area_of_label[label] if label < area_of_label.shape[0] else 0.0
            if bound > 0:
                total += twice_area(x, y, T[i, 0], T[i, 1], T[i, 2]) / 2 / bound
    return int(min(0.8 * total, cap))


@kernel
def domain_area(x, y, T, inside):
    total = 0.0
    for i in range(T.shape[0]):
        if inside[i]:
            total += twice_area(x, y, T[i, 0], T[i, 1], T[i, 2])
    return total / 2


@kernel
def output_ids(n, dup_of):
    """Output id of every input point (``vertex_map``: duplicates share the id
    of the point they repeat) and the input point kept for each output id
    (``kept``): the distinct points in order of first appearance."""
    vertex_map = np.full(n, -1, np.int64)
    first = np.full(n, -1, np.int64)      # output id of each root point
    kept = np.empty(n, np.int64)
    nk = 0
    for i in range(n):
        root = dup_of[i] if dup_of[i] >= 0 else i
        if first[root] < 0:
            first[root] = nk
            kept[nk] = i
            nk += 1
        vertex_map[i] = first[root]
    return vertex_map, kept[:nk]


@kernel
def no_mesh():
    """The output of a route that made no mesh (an error, or all points collinear)."""
    e2 = np.empty((0, 2), np.int64)
    e3 = np.empty((0, 3), np.int64)
    e1 = np.empty(0, np.int64)
    return (np.empty((0, 2)), e3, e3.copy(), np.empty((0, 3), np.bool_), e2, e1, e1.copy(),
            e1.copy(), e1.copy(), e1.copy())


@kernel(inline="always")
def route_points(px, py, order_in, ms, nsnap, options):
    """The route's vertices before the Delaunay triangulation: ``(status,
    info0, info1, shift, px, py, order, xi, yi, wi, inf, extra)``. The input
    scaled into the exact predicates' range by ``2**shift`` (:mod:`.scaling`;
    ROUTE_RANGE and the offending values where it cannot be), the insertion
    ``order`` (ROUTE_COLLINEAR where all points are on a line), and the mesh
    coordinates in that order with room for ``extra`` more vertices and the
    infinite one, ``inf``: room for the ``ms`` segments' crossings (``nsnap``
    snapped already) when ``options.split``, for refinement when ``options.refine``."""
    algorithm, split, refine = options.algorithm, options.split, options.refine
    n = px.shape[0]
    no = np.empty(0)
    order = order_in
    shift, i0, i1 = fit_shift(px, py, no)
    if shift == NO_FIT:
        return ROUTE_RANGE, i0, i1, shift, px, py, order, no, no, no, np.int64(0), np.int64(0)
    if shift != 0:
        px = scaled(px, shift)
        py = scaled(py, shift)
    if order.shape[0] == 0:
        order = lexicographic_order_compiled(px, py)
    k1, k2 = seed_triangle(px, py, order)
    if k2 < 0:
        return ROUTE_COLLINEAR, i0, i1, shift, px, py, order, no, no, no, np.int64(0), np.int64(0)
    if algorithm != DIVIDE:
        order = seed_first(order, k1, k2)
    extra = np.int64(16 + ms // 2 + nsnap if split else 0)
    if refine:   # the room refinement starts with, made now rather than by a copy
        extra = max(extra, STEINER_ROOM * n + 64 - n)
    xi, yi, wi = gather_coords(px, py, np.zeros(n), order, extra)
    return ROUTE_OK, i0, i1, shift, px, py, order, xi, yi, wi, n + extra, extra


@entry
def route_points_for_threads(px, py, order_in, ms, nsnap, options):
    """:func:`route_points` of the divide-and-conquer route (``options`` as
    :func:`.options.plain` gives them), for a caller that builds the Delaunay
    triangulation on threads: ``(status, order, xi, yi, inf, cap)``, ``cap``
    the triangles its store needs room for."""
    status, _, _, _, _, _, order, xi, yi, _, inf, extra = route_points(
        px, py, order_in, ms, nsnap, named(options))
    return status, order, xi, yi, inf, store_room(px.shape[0], extra)


@kernel
def no_store():
    """The ``prebuilt`` argument of :func:`cdt_route` that asks it to build the
    Delaunay triangulation itself."""
    e = np.empty(0, IDX)
    return e, e.copy(), e.copy(), np.empty(0, np.int64), np.int64(0)


# (compiled apart: its entry from Python, cdt_route_packed, and the batch loop,
# mesh_geometries, call it by symbol; each would otherwise link, optimise and
# code-generate the whole route again: 5-8 s of a first triangulate)
@kernel(apart=True)
def cdt_route(plc, orders, options, snapped, prebuilt):
    """Constrained Delaunay triangulation of one PLC, every step in one call.

    Parameters: ``plc`` the arrays ``(px, py, segs, seg_ring, ring_polygon,
    ring_is_hole, holes, regions)``: the vertices ``px, py`` (n,), ``segs``
    (m, 2) vertex pairs, ``seg_ring`` (m,) the ring of each segment (-1 free;
    empty without rings), ``ring_polygon`` / ``ring_is_hole`` per ring, the
    ``holes`` (h, 2) and ``regions`` (r, 4) seeds; ``orders`` ``(order_in,
    horizontal_in)`` the insertion and (y, -x) orders when the caller sorted
    already (empty: sorted here); ``options`` a :class:`.options.RouteOptions`
    (``max_steiner`` caps the intersection points and refinement's Steiner
    points); ``snapped`` the snap-rounded crossings ``(new points x, y,
    chains)`` of :func:`.snap.snap_route` (empty: none yet; splitting segments
    that cross then stops with ROUTE_NEEDS_SNAP, so that only inputs with
    crossings compile and run the snap rounding); ``prebuilt`` the Delaunay
    triangulation of the vertices ``(tri, twin, cons, dup, ntri)`` when the
    caller built it (on threads, from :func:`route_points` with the same
    arguments), else :func:`no_store`.

    Returns ``(status, info, counts, out)`` with ``out = (vertices, triangles,
    neighbors, constrained, segments, segment_ids, regions, vertex_map, kept,
    below_min_angle)`` in output ids (see :mod:`.output`).
    """
    px, py, segs, seg_ring, ring_polygon, ring_is_hole, holes, regions = plc
    order_in, horizontal_in = orders
    algorithm, split, max_steiner, refine = (options.algorithm, options.split, options.max_steiner,
                                             options.refine)
    n = px.shape[0]
    info = np.zeros(4, np.int64)
    counts = np.zeros(NCOUNTS, np.int64)
    ms = segs.shape[0]
    snap_x, snap_y, chains = snapped
    status, info[0], info[1], shift, px, py, order, xi, yi, wi, inf, extra = route_points(
        px, py, order_in, ms, snap_x.shape[0], options)
    if status != ROUTE_OK:
        return status, info, counts, no_mesh()
    holes = scaled_seeds(holes, shift)
    regions = scaled_seeds(regions, shift)
    mesh_of = np.empty(n, np.int64)
    for i in range(n):
        mesh_of[order[i]] = i
    build_counts = np.zeros(2, np.int64)
    tri, twin, cons, dup, ntri = prebuilt
    sub = np.zeros(n, np.int8)
    status = OK
    if tri.shape[0] == 0:     # (else the caller built it on threads: :func:`route_points`)
        horizontal = np.empty(0, np.int64)
        if algorithm == DIVIDE:
            horizontal = horizontal_order(xi, yi, n, horizontal_in, mesh_of)
        # (np.bool_: literal constants would compile the whole construction a second time)
        status, tri, twin, cons, ntri, dup, sub = build_mesh(xi, yi, (wi, np.bool_(False)), n, inf,
                                                             algorithm, horizontal, extra,
                                                             np.bool_(True), build_counts)
    if status != OK:  # (a located point always exists)
        info[0] = 1
        info[1] = status
        return ROUTE_INTERNAL, info, counts, no_mesh()
    dup_of = np.full(n, -1, np.int64)
    to_input_ids(order, dup, sub, dup_of, np.zeros(n, np.int8))
    for i in range(n):
        if dup_of[i] >= 0:
            counts[K_DUPLICATES] += 1
            mesh_of[i] = mesh_of[dup_of[i]]

    # segments
    seg_ends = np.empty((ms, 2), np.int64)
    for s in range(ms):
        seg_ends[s, 0] = mesh_of[segs[s, 0]]
        seg_ends[s, 1] = mesh_of[segs[s, 1]]
    tasks, ntask, mult, nzero, first = dedup_tasks(seg_ends, n)
    counts[K_ZERO_SEGMENTS] = nzero
    counts[K_DUPLICATE_SEGMENTS] = ms - nzero - ntask
    limit = steiner_limit(max_steiner, ms)
    seg_counts = np.zeros(3, np.int64)
    nv = n
    if split and chains.shape[0] > 0:     # the crossings, snap-rounded: points, then chains
        if shift != 0:
            snap_x = scaled(snap_x, shift)
            snap_y = scaled(snap_y, shift)
        ntri, nv, status = insert_points_at((tri, twin, cons, xi, yi, inf), wi, ntri, n, snap_x,
                                            snap_y)
        if status != OK:
            info[0] = 3
            info[1] = status
            return ROUTE_INTERNAL, info, counts, no_mesh()
        tasks, ntask, passed = chain_tasks(chains, first, segs, mesh_of, n)
        seg_counts[0] = passed
    # (splitting before the crossings are snapped: no room for a crossing point, so the
    # first crossing stops the loop; most inputs have none)
    cap = limit
    if split and chains.shape[0] == 0:
        cap = np.int64(0)
    elif max_steiner >= 0:
        cap = limit - (nv - n)
    status, store = insert_all_segments((tri, twin, cons, xi, yi, wi, inf, ntri, nv), tasks, ntask,
                                        seg_ends, split, cap, seg_counts, info)
    tri, twin, cons, xi, yi, wi, inf, ntri, nv = store
    if split and status == STOP_LIMIT and chains.shape[0] == 0:
        return ROUTE_NEEDS_SNAP, info, counts, no_mesh()
    counts[K_ON_SEGMENTS] = seg_counts[0]
    counts[K_MERGED_OVERLAPS] = seg_counts[1]
    counts[K_INTERSECTIONS] = nv - n
    if status != ALL_DONE:
        if status == STOP_CROSSING:
            return ROUTE_CROSSING, info, counts, no_mesh()
        if status == STOP_OVERLAP:
            return ROUTE_OVERLAP, info, counts, no_mesh()
        if status == STOP_LIMIT:
            info[2] = limit
            return ROUTE_STEINER_LIMIT, info, counts, no_mesh()
        info[1] = status
        info[2] = 2
        return ROUTE_INTERNAL, info, counts, no_mesh()
    if split:      # every segment's pieces along it in order (a net under the rounding)
        nbad, s_bad, u, v = pieces_out_of_order(tri, cons, ntri, xi, yi, seg_ends)
        if nbad:
            info[0] = s_bad
            info[1] = nbad
            info[2] = float_bits(0.5 * (xi[u] + xi[v]) * 2.0 ** -shift)
            info[3] = float_bits(0.5 * (yi[u] + yi[v]) * 2.0 ** -shift)
            return ROUTE_UNRESOLVED, info, counts, no_mesh()
    counts[K_FLIPS] = build_counts[0]
    if algorithm == FLIP:     # the modified flip algorithm after the segments (Sec. 2.10.3)
        counts[K_FLIPS] += flip_to_delaunay(tri, twin, cons, xi, yi, wi, np.bool_(False), inf, ntri)

    # the domain
    solid = solid_with_flags(tri, twin, cons, ntri, inf)
    T, N, tid, cflag = solid
    seg_start, seg_rings = segment_rings(first, seg_ring)
    inside, region, status = classify(store, solid, (mult, seg_start, seg_rings, ring_polygon,
                                                     ring_is_hole), (holes, regions), options, info)
    if status != ROUTE_OK:
        if status == ROUTE_POLYGONS_OVERLAP:   # the edge's ends as input vertex ids
            info[2] = order[info[2]]
            info[3] = order[info[3]]
        return status, info, counts, no_mesh()

    route_status = ROUTE_OK
    sin2_bound = 0.0
    if refine:
        refinement = options.refinement
        min_angle, max_new = refinement.min_angle, max_steiner
        max_area = scaled_area(refinement.max_area, shift)
        lab = slot_labels(tid, inside, region, tri.shape[0] // 3)
        area_of_label = area_bounds(max_area, regions, lab)
        if max_new < 0:
            max_new = 100 * nv + 100_000
            if max_area > 0:
                max_new += int(min(8 * domain_area(xi, yi, T, inside) / max_area, AREA_STEINER_CAP))
        counts[K_REF_LIMIT] = max_new
        budget = max(max_new - counts[K_INTERSECTIONS], 0)
        room = STEINER_ROOM * nv + 64
        if area_of_label.shape[0] > 1:
            room += refinement_room(xi, yi, T, inside, region, area_of_label, 2_000_000)
        no_home = np.empty((0, 3), np.int64)
        rstatus, rc, lab, _, store, _ = refine_store(store, lab, seg_ends, refinement, area_of_label,
                                                     budget, room, np.empty(0, np.int64), np.int64(-1),
                                                     (no_home, no_home))
        tri, twin, cons, xi, yi, wi, inf, ntri, nv = store
        counts[K_REF_STEINER] = rc[C_STEINER]
        counts[K_REF_SPLITS] = rc[C_SEG_SPLITS]
        counts[K_REF_FLIPS] = rc[C_FLIPS]
        counts[K_FROZEN] = rc[C_FROZEN]
        counts[K_ATTEMPTS] = rc[C_ATTEMPTS]
        counts[K_DEFERRED] = rc[C_DEFERRED]
        counts[K_REF_COMPLETE] = rstatus == FINISHED
        if rstatus != FINISHED:
            route_status = ROUTE_REFINE_LIMIT
        T, N, tid, cflag = solid_with_flags(tri, twin, cons, ntri, inf)
        inside, region = triangle_labels(tid, lab, T.shape[0])
        if min_angle > 0:
            sin2_bound = math.sin(math.radians(min_angle)) ** 2

    # output arrays
    vertex_map, kept = output_ids(n, dup_of)
    vertices, remap = cdt_vertices(px, py, kept, vertex_map, order, xi, yi, n, nv)
    triangles, neighbors, constrained, pieces, piece_ids, keep = cdt_arrays(T, N, cflag, inside, remap)
    out_regions = np.empty(keep.shape[0], np.int64)
    for i in range(keep.shape[0]):
        out_regions[i] = region[keep[i]]
    below = np.empty(0, np.int64)
    if refine:
        for p in range(piece_ids.shape[0]):
            if piece_ids[p] >= ms:        # a convex-hull piece made a segment by refinement
                piece_ids[p] = -1
        if sin2_bound > 0:
            below = count_below(vertices, triangles, sin2_bound)
    if shift != 0:
        unscale_rows(vertices, shift)
    return route_status, info, counts, (vertices, triangles, neighbors, constrained, pieces,
                                        piece_ids, out_regions, vertex_map, kept, below)


# ------------------------------------------------------------------ one call from Python
PACK_HEADER = 5       # triangles, segment pieces, input points, kept points, below-bound triangles
PACK_ARRAYS = PACK_HEADER + 4 + NCOUNTS      # then info and counts, then the arrays


@entry
def cdt_route_packed(px, py, segs, seg_ring, ring_polygon, ring_is_hole, holes, regions, order_in,
                     horizontal_in, options, snapped, prebuilt):
    """:func:`cdt_route` for a call from Python: ``(status, ints, vertices)``,
    every integer output in the one array ``ints`` (read by ``Triangulation.from_route``).
    numba hands each returned array to Python on its own, about a microsecond
    apiece: for a small polygon the twelve arrays of :func:`cdt_route` were a
    quarter of the call. The arrays come one by one and ``options`` as a plain
    tuple (:func:`.options.plain`): numba types a tuple of arrays, or a named
    tuple, in Python, 0.5-0.9 us more per call."""
    px, py, segs, seg_ring = unowned(px), unowned(py), unowned(segs), unowned(seg_ring)
    ring_polygon, ring_is_hole = unowned(ring_polygon), unowned(ring_is_hole)
    holes, regions = unowned(holes), unowned(regions)
    order_in, horizontal_in = unowned(order_in), unowned(horizontal_in)
    snapped = (unowned(snapped[0]), unowned(snapped[1]), unowned(snapped[2]))
    prebuilt = (unowned(prebuilt[0]), unowned(prebuilt[1]), unowned(prebuilt[2]), unowned(prebuilt[3]),
                prebuilt[4])
    status, info, counts, out = cdt_route((px, py, segs, seg_ring, ring_polygon, ring_is_hole,
                                           holes, regions), (order_in, horizontal_in),
                                          named(options), snapped, prebuilt)
    vertices, triangles, neighbors, constrained, pieces, piece_ids, out_regions, vertex_map, kept, \
        below = out
    k = triangles.shape[0]
    s = pieces.shape[0]
    ints = np.empty(PACK_HEADER + info.shape[0] + counts.shape[0] + 10 * k + 3 * s
                    + vertex_map.shape[0] + kept.shape[0] + below.shape[0], np.int64)
    ints[0] = k
    ints[1] = s
    ints[2] = vertex_map.shape[0]
    ints[3] = kept.shape[0]
    ints[4] = below.shape[0]
    p = put(ints, np.int64(PACK_HEADER), info)
    p = put(ints, p, counts)
    for t in range(k):
        for j in range(3):
            ints[p + 3 * t + j] = triangles[t, j]
            ints[p + 3 * (k + t) + j] = neighbors[t, j]
            ints[p + 3 * (2 * k + t) + j] = constrained[t, j]
    p += 9 * k
    for i in range(s):
        ints[p + 2 * i] = pieces[i, 0]
        ints[p + 2 * i + 1] = pieces[i, 1]
    p += 2 * s
    p = put(ints, p, piece_ids)
    p = put(ints, p, out_regions)
    p = put(ints, p, vertex_map)
    p = put(ints, p, kept)
    put(ints, p, below)
    return status, ints, vertices


@kernel(forceinline=True)
def put(dst, p, src):
    """Copy ``src`` (1-D) into ``dst`` from slot ``p``; returns the slot after it."""
    for i in range(src.shape[0]):
        dst[p + i] = src[i]
    return p + src.shape[0]


# ------------------------------------------------------------------ flat rings
@kernel
def rings_route(x, y, ring_start, r0, r1, ring_polygon, ring_is_hole, options, keep):
    """:func:`cdt_route` of the rings ``r0:r1`` of flat ring arrays (ring ``r``
    the vertices ``ring_start[r]..ring_start[r + 1] - 1`` of ``x, y``, without
    its closing point), without seeds, in vertex ids from ``ring_start[r0]``;
    ``keep`` (at least ``r1 - r0`` flags, all set) as :func:`.rings.ring_segments`
    takes it. Returns ``(degenerate, status, counts, out)`` as :func:`cdt_route`,
    ``degenerate`` set (and nothing routed) when a ring has no area
    (:func:`.rings.ring_is_degenerate`)."""
    v0 = ring_start[r0]
    v1 = ring_start[r1]
    for r in range(r0, r1):
        if ring_is_degenerate(x, y, ring_start[r], ring_start[r + 1]):
            return True, ROUTE_INTERNAL, np.zeros(NCOUNTS, np.int64), no_mesh()
    segs, ring_of = ring_segments(ring_start, r0, r1, keep)
    plc = (x[v0:v1], y[v0:v1], segs, ring_of, ring_polygon[r0:r1], ring_is_hole[r0:r1],
           np.empty((0, 2)), np.empty((0, 4)))
    no_order = np.empty(0, np.int64)
    not_snapped = (np.empty(0), np.empty(0), np.empty((0, 3), np.int64))
    status, _, counts, out = cdt_route(plc, (no_order, no_order), options, not_snapped, no_store())
    return False, status, counts, out


# ------------------------------------------------------------------ many geometries
@entry
def mesh_geometries(x, y, ring_start, geom_ring_start, ring_polygon, ring_is_hole, g0, g1,
                    options, steiner0):
    """:func:`cdt_route` over geometries ``g0:g1`` of flat ring arrays, in one
    compiled loop, with ``options`` (:func:`.options.plain`; without seeds,
    without ``keep_hull``: the caller meshes such geometries one by one).
    Returns ``(triangles, geometry, region, steiner_xy, failed)``: triangles
    in batch vertex ids (a geometry's input vertices keep their ring
    position, Steiner vertices are numbered from ``steiner0`` in the order of
    ``steiner_xy``), grouped by geometry; ``failed[g - g0]`` marks the
    geometries whose route stopped (a crossing, a hole outside its shell, all
    points collinear...), which the caller meshes one by one to get the
    precise result or error (a degenerate ring, too)."""
    nv_all = ring_start[geom_ring_start[g1]] - ring_start[geom_ring_start[g0]]
    cap = 2 * nv_all + 16
    T = np.empty((cap, 3), np.int64)
    G = np.empty(cap, np.int64)
    R = np.empty(cap, np.int64)
    S = np.empty((16, 2))
    ns = np.int64(0)    # (typed, not literal: see copy_rows below)
    k = np.int64(0)
    failed = np.zeros(g1 - g0, np.bool_)
    options = named(options)
    keep_all = np.ones(geom_ring_start[g1] - geom_ring_start[g0] + 1, np.bool_)
    for g in range(g0, g1):
        r0 = geom_ring_start[g]
        r1 = geom_ring_start[g + 1]
        if r0 == r1:
            continue
        v0 = ring_start[r0]
        # (a degenerate ring: the single call reports it, or, splitting, keeps its points)
        degenerate, status, _, out = rings_route(x, y, ring_start, r0, r1, ring_polygon, ring_is_hole,
                                                 options, keep_all)
        if degenerate or status != ROUTE_OK:
            failed[g - g0] = True
            continue
        vertices, triangles, _, _, _, _, regions, _, kept, _ = out
        nk = kept.shape[0]
        glob = np.empty(vertices.shape[0], np.int64)
        for j in range(nk):
            glob[j] = v0 + kept[j]
        nnew = vertices.shape[0] - nk
        if ns + nnew > S.shape[0]:
            grown = np.empty((2 * (ns + nnew), 2))
            copy_rows(grown, S, ns)
            S = grown
        for j in range(nk, vertices.shape[0]):
            glob[j] = steiner0 + ns
            S[ns, 0] = vertices[j, 0]
            S[ns, 1] = vertices[j, 1]
            ns += 1
        nt = triangles.shape[0]
        if k + nt > T.shape[0]:
            size = 2 * (k + nt)
            T2 = np.empty((size, 3), np.int64)
            G2 = np.empty(size, np.int64)
            R2 = np.empty(size, np.int64)
            copy_rows(T2, T, k)
            copy_rows(G2, G, k)
            copy_rows(R2, R, k)
            T, G, R = T2, G2, R2
        for t in range(nt):         # batch ids keep the order of output ids: still min first
            for j in range(3):
                T[k, j] = glob[triangles[t, j]]
            G[k] = g
            R[k] = regions[t]
            k += 1
    return T[:k], G[:k], R[:k], S[:ns], failed
