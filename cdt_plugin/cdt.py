"""Constrained Delaunay triangulation of a PLC (Sec. 2.10).

Route: Delaunay triangulation of the vertices (or the lexicographic
triangulation with ``algorithm="flip"``), segments inserted by cavity
retriangulation (Sec. 2.10.1), optionally the modified flip algorithm
(Sec. 2.10.3), then the domain classified by a flood fill that stops at
segments.
"""
from __future__ import annotations

import math
import time

import numpy as np
from numba import njit

from .delaunay import _build_in_order, resolve_algorithm, _reorder_seed_first, seed_triangle
from .errors import (CDTError, InvalidGeometryError, OverlappingSegmentsError, RefinementLimitError,
                     SegmentIntersectionError)
from .flips import flip_to_delaunay
from .mesh import IDX
from .ordering import brio_order, lexicographic_order
from .plc import as_plc
from .refine import (C_ATTEMPTS, C_DEFERRED, C_FLIPS, C_FROZEN, C_SEG_SPLITS, C_STEINER, FINISHED, OUT,
                     STEINER_ROOM, count_below, refine_mesh)
from .regions import flood_seeds, segment_depths
from .segments import (ALL_DONE, NEED_EDGE_ROOM, NEED_VERTEX_ROOM, STOP_CROSSING, STOP_LIMIT,
                       STOP_OVERLAP, by_smaller_end, insert_segments, intersection_point,
                       make_buffers)
from .triangulation import Triangulation, solid_triangles

INTERSECTIONS = ("raise", "split")
_NO_AREA_BOUNDS = np.zeros(1)   # read as "no area bound" for every label (see refine's ``area_bound``)
_NO_BUFFERS = tuple(np.empty(0, np.int64) for _ in range(5))   # segment walks' work arrays, unmade


def triangulate(vertices, segments=None, *, holes=None, regions=None, intersections: str = "raise",
                keep_hull: bool = False, algorithm: str = "auto",
                min_angle: float | None = None, max_area: float | None = None,
                conforming_delaunay: bool = False, split_boundary: bool = True,
                max_steiner: int | None = None) -> Triangulation:
    """Constrained Delaunay triangulation of a planar straight-line complex.

    Parameters
    ----------
    vertices : (n, 2) array, a :class:`PLC`, or a geometry
        Vertices; or any object with ``__geo_interface__`` (shapely Polygon,
        MultiPolygon, GeometryCollection, LineString, Point...), read from its
        GeoJSON-like mapping: rings give the domain exactly, any winding.
    segments : (m, 2) int array, optional
        Vertex index pairs that must be edges. A vertex lying on a segment
        splits it. Zero-length segments are dropped and repeated segments
        merged (both reported in ``stats``).
    holes : (h, 2) array, optional
        Hole seed points (Triangle's convention): when given, the triangles
        reachable from outside the hull without crossing a segment are removed
        (unless ``keep_hull``) and so is the segment-bounded region around each
        hole point. Without holes or regions the inside is decided by depth
        parity: odd numbers of segments crossed from outside are inside.
    regions : (r, 2..4) array, optional
        Region seeds ``x, y[, attribute[, max_area]]``: each paints its
        segment-bounded region; ``tri.regions`` gives the seed index per
        triangle and ``tri.region_attributes`` the attribute.
    intersections : {"raise", "split"}
        Crossing or collinear-overlapping segments raise
        :class:`SegmentIntersectionError` / :class:`OverlappingSegmentsError`
        naming both segments and the point, or (``"split"``) the crossing point
        is inserted — computed as accurately as double precision allows, so it
        may lie off the exact segments by a rounding error — and overlaps merged.
    keep_hull : bool
        Keep every triangle of the convex hull (Triangle's ``-c``).
    algorithm : {"auto", "divide", "incremental", "flip"}
        How the Delaunay triangulation of the vertices is built before the
        segments go in: ``"divide"`` (divide and conquer, the default that
        ``"auto"`` stands for) or ``"incremental"`` (see :func:`delaunay`).
        ``"flip"``: lexicographic triangulation, segment insertion, then the
        modified flip algorithm (Sec. 2.10.3). Same result for generic input.
    min_angle : float, optional
        Quality meshing (Delaunay refinement, Triangle's ``-q``): add Steiner
        points until every triangle's smallest angle is at least this many
        degrees (below 60; up to about 34 is guaranteed to finish in
        practice). Triangles at an input angle smaller than the bound cannot
        meet it: they are left as they are and counted in
        ``stats["below_min_angle"]``.
    max_area : float, optional
        Refine until no triangle is larger (Triangle's ``-a``). A region seed's
        fourth column, when positive, bounds its region instead (``-a -A``).
    conforming_delaunay : bool
        Split segments until each is a union of Delaunay edges: every triangle
        is then Delaunay, not merely constrained Delaunay (Triangle's ``-D``).
        A piece too short to split in double precision (counted in
        ``stats["frozen_segment_pieces"]``: needles, crossings rounded together)
        stays as it is, and the triangles at it may then be only constrained
        Delaunay.
    split_boundary : bool
        With ``False`` no Steiner point goes on the domain boundary (Triangle's
        ``-Y``); the triangles there may then miss the bounds.
    max_steiner : int, optional
        Cap on Steiner points (intersections with ``"split"`` plus refinement);
        refinement that reaches it raises :class:`RefinementLimitError`
        carrying the partial mesh. The default cap is generous and only there
        to stop runaway refinement.

    Steiner points are ``tri.steiner``; each segment piece names its input
    segment in ``tri.segment_ids`` (-1 for a piece of the convex hull when the
    hull bounds the domain). A point placed on a segment lies on it up to one
    rounding of its coordinates.

    Examples
    --------
    >>> import cdt_plugin
    >>> square = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]]
    >>> rings = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    >>> tri = cdt_plugin.triangulate(square, rings)   # a square with a square hole
    >>> len(tri.triangles), tri.is_delaunay()
    (8, True)
    """
    t0 = time.perf_counter()
    if intersections not in INTERSECTIONS:
        raise CDTError(f"intersections must be one of {INTERSECTIONS}, got {intersections!r}")
    algorithm = resolve_algorithm(algorithm, False)
    refine = _refinement_options(min_angle, max_area, conforming_delaunay, max_steiner)
    plc = as_plc(vertices, segments, holes, regions)
    split = intersections == "split"
    if plc.degenerate_rings and not split:
        p, r = plc.degenerate_rings[0]
        raise InvalidGeometryError(
            f"ring {r} of polygon {p} has fewer than three distinct points or zero area "
            f"({len(plc.degenerate_rings)} such rings); use intersections='split' to keep their "
            "points as isolated vertices")
    pts = plc.vertices
    n = len(pts)
    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    order = brio_order(x, y) if algorithm == "incremental" else lexicographic_order(x, y)
    dup_of = np.full(n, -1, np.int64)
    submerged = np.zeros(n, np.int8)
    stats = {"algorithm": algorithm, "input_points": n, "input_segments": len(plc.segments)}
    k1, k2 = seed_triangle(x, y, order)
    if k2 < 0:
        return _collinear_result(plc, order, dup_of, submerged, stats, t0)
    if algorithm != "divide":
        order = _reorder_seed_first(order, k1, k2)
    m = len(order)
    extra = 16 + len(plc.segments) // 2 if split else 0
    if refine is not None:   # the room refinement starts with, made now rather than by a copy
        extra = max(extra, STEINER_ROOM * m + 64 - m)
    coords = []
    tri, twin, cons, ntri, counts = _build_in_order(x, y, np.zeros(n), False, order, algorithm,
                                                     dup_of, submerged, extra, True, coords)
    xi, yi, wi = coords
    mesh_of = np.empty(n, np.int64)
    mesh_of[order] = np.arange(m)
    dups = np.flatnonzero(dup_of >= 0)
    mesh_of[dups] = mesh_of[dup_of[dups]]

    segs = mesh_of[plc.segments]
    tasks, ntask, mult = _segment_tasks(segs, m, stats)
    mesh = _Mesh(tri, twin, cons, ntri, xi, yi, wi, m + extra, m, tasks, ntask)
    _insert_all_segments(mesh, segs, split, max_steiner, stats, plc)
    if algorithm == "flip":
        stats["flips"] = int(flip_to_delaunay(mesh.tri, mesh.twin, mesh.cons, mesh.x, mesh.y, mesh.w,
                                              False, mesh.inf, mesh.ntri))
    else:
        stats["flips"] = int(counts[0])
    classes, tid = _classify(plc, mesh, keep_hull, split, mult)
    if refine is not None:
        classes = _refine(plc, mesh, segs, classes, tid, refine, split_boundary, stats)
    out = Triangulation.from_cdt(plc, mesh, order, dup_of, submerged, *classes, stats, t0,
                                 ndup=len(dups))
    if refine is not None:
        _finish_refinement(out, plc, refine, stats)
    return out


def _refinement_options(min_angle, max_area, conforming, max_steiner):
    """Check the quality options; None when no refinement is asked for."""
    if min_angle is not None:
        if not (np.isfinite(min_angle) and 0 <= min_angle < 60):
            raise CDTError(f"min_angle must be in [0, 60) degrees, got {min_angle!r}")
    if max_area is not None:
        if not (np.isfinite(max_area) and max_area > 0):
            raise CDTError(f"max_area must be a positive number, got {max_area!r}")
    if max_steiner is not None and max_steiner < 0:
        raise CDTError(f"max_steiner must be >= 0, got {max_steiner!r}")
    if not min_angle and max_area is None and not conforming:
        return None
    return {"min_angle": float(min_angle or 0.0), "max_area": max_area,
            "conforming": bool(conforming), "max_steiner": max_steiner}


class _Mesh:
    """The growing half-edge store plus its coordinate arrays and task queue."""

    def __init__(self, tri, twin, cons, ntri, x, y, w, inf, nv, tasks, ntask):
        self.tri, self.twin, self.cons, self.ntri = tri, twin, cons, ntri
        self.x, self.y, self.w, self.inf, self.nv = x, y, w, inf, nv
        self.tasks, self.ntask = tasks, ntask

    def grow_vertices(self, at_least: int = 0):
        """Double the room for Steiner vertices, or make room for ``at_least``
        vertices if that is more (the infinite vertex moves)."""
        old_inf = self.inf
        new_inf = max(2 * old_inf + 16, at_least)
        for name in ("x", "y", "w"):
            a = np.zeros(new_inf + 1)
            a[: self.nv] = getattr(self, name)[: self.nv]
            setattr(self, name, a)
        self.tri[self.tri == old_inf] = new_inf
        self.inf = new_inf
        cap = 2 * new_inf + 2
        for name in ("tri", "twin", "cons"):
            old = getattr(self, name)
            a = np.full(3 * cap, -1 if name != "cons" else 0, IDX)
            a[: len(old)] = old
            setattr(self, name, a)
        tasks = np.empty((2 * len(self.tasks) + 16, 3), np.int64)
        tasks[: self.ntask] = self.tasks[: self.ntask]
        self.tasks = tasks


def _segment_tasks(segs, nv, stats):
    """Drop zero-length segments, merge repeated ones; the rest become tasks
    (processed in input order: the queue is a stack). Returns the tasks, the
    number of kept segments and each kept segment's multiplicity (by 1-based id)."""
    tasks, ntask, mult, nzero = _dedup_tasks(segs, nv)
    stats["zero_length_segments"] = (np.flatnonzero(segs[:, 0] == segs[:, 1]).tolist()
                                     if nzero else [])
    stats["duplicate_segments"] = int(len(segs) - nzero - ntask)
    return tasks, ntask, mult


@njit(cache=True)
def _dedup_tasks(segs, nv):
    """:func:`_segment_tasks` compiled: segments grouped by their smaller end
    (:func:`segments.by_smaller_end`), the first of each endpoint pair kept and
    counted. Returns ``(tasks, ntask, mult, zero-length count)``."""
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
    return tasks, ntask, mult, nzero


def _insert_all_segments(mesh, segs, split, max_steiner, stats, plc):
    counts = np.zeros(3, np.int64)
    info = np.zeros(4, np.int64)
    buf = _NO_BUFFERS   # made on the first segment that is not an edge yet (NEED_EDGE_ROOM)
    limit = max_steiner if max_steiner is not None else 10 * len(segs) + 1000
    while True:
        stack = np.empty(mesh.inf + 16, np.int64)
        status, mesh.ntri, mesh.nv, mesh.ntask = insert_segments(
            mesh.tri, mesh.twin, mesh.cons, mesh.x, mesh.y, mesh.w, mesh.inf, mesh.ntri, mesh.nv,
            mesh.tasks, mesh.ntask, segs, split, limit, counts, info, stack, buf)
        if status == ALL_DONE:
            break
        if status == NEED_VERTEX_ROOM:
            mesh.grow_vertices()
        elif status == NEED_EDGE_ROOM:
            buf = make_buffers(2 * mesh.ntri)
        elif status in (STOP_CROSSING, STOP_OVERLAP):
            _raise_intersection(status, info, plc)
        elif status == STOP_LIMIT:
            raise CDTError(f"max_steiner={limit} intersection points inserted and segments "
                           f"{info[0] - 1} and {info[1] - 1} still cross; raise max_steiner")
        else:  # pragma: no cover
            raise CDTError(f"internal error while inserting segment {info[0] - 1} (status {status})")
    stats["vertices_on_segments"] = int(counts[0])
    stats["merged_overlaps"] = int(counts[1])
    stats["intersection_points"] = int(counts[2])


def _raise_intersection(status, info, plc):
    s, t = int(info[0]) - 1, int(info[1]) - 1
    P = plc.vertices
    a, b = plc.segments[s]
    c, d = plc.segments[t]
    if status == STOP_CROSSING:
        xy = np.array([P[a], P[b], P[c], P[d]])
        px, py = intersection_point(xy[:, 0].copy(), xy[:, 1].copy(), 0, 1, 2, 3)
        raise SegmentIntersectionError(
            f"segments {s} ({_fmt(P[a])}-{_fmt(P[b])}) and {t} ({_fmt(P[c])}-{_fmt(P[d])}) "
            f"cross at about ({px!r}, {py!r}); use intersections='split' to insert the crossing",
            segments=(s, t), point=(px, py))
    raise OverlappingSegmentsError(
        f"segments {s} ({_fmt(P[a])}-{_fmt(P[b])}) and {t} ({_fmt(P[c])}-{_fmt(P[d])}) overlap "
        f"(collinear, sharing more than a point); use intersections='split' to merge them",
        segments=(s, t))


def _fmt(p):
    return f"({float(p[0])!r}, {float(p[1])!r})"


@njit(cache=True)
def _real_triangles(tri, twin, cons, ntri, inf):
    """The real triangles ``T`` with their neighbours ``N``, the index in ``T``
    of each mesh slot (``tid``, -1: ghost) and the segment id (1-based, 0 none)
    of the edge opposite each vertex (``cflag``)."""
    T, N, tid = solid_triangles(tri, twin, ntri, inf)
    cflag = np.zeros((T.shape[0], 3), np.int64)
    for t in range(ntri):
        i = tid[t]
        if i >= 0:
            for j in range(3):
                cflag[i, j] = cons[3 * t + (j + 1) % 3]
    return T, N, tid, cflag


@njit(cache=True)
def _depths(tri, twin, cons, ntri, inf, tid, k, mult):
    """:func:`segment_depths` of the real triangles, in the order of ``tid``,
    and whether any edge is a segment."""
    depth_mesh, entry_mesh = segment_depths(tri, twin, cons, ntri, inf, mult)
    depth = np.empty(k, np.int64)
    entry = np.empty(k, np.int64)
    for t in range(ntri):
        if tid[t] >= 0:
            depth[tid[t]] = depth_mesh[t]
            entry[tid[t]] = entry_mesh[t]
    has_segments = False
    for e in range(3 * ntri):
        if cons[e] != 0:
            has_segments = True
            break
    return depth, entry, has_segments


def _classify(plc, mesh, keep_hull, split, mult):
    """Which real triangles are inside the domain, and their regions.
    Returns ``(T, N, cflag, inside, region, attributes)`` over the real
    triangles ``T`` of the mesh (in slot order), and ``tid``, the index in
    ``T`` of each mesh slot (-1: ghost)."""
    tri, twin, cons, ntri, inf = mesh.tri, mesh.twin, mesh.cons, mesh.ntri, mesh.inf
    T, N, tid, cflag = _real_triangles(tri, twin, cons, ntri, inf)
    depth, entry, has_segments = _depths(tri, twin, cons, ntri, inf, tid, len(T), mult)
    triangle_rule = plc.holes is not None or plc.regions is not None
    if keep_hull or not has_segments:
        inside = np.ones(len(T), bool)
    elif triangle_rule:
        inside = depth > 0
    else:
        inside = depth % 2 == 1
    if plc.has_rings:
        ring = np.where(entry > 0, plc.segment_ring[np.maximum(entry - 1, 0)], -1)
        region = np.where(ring >= 0, plc.ring_polygon[np.maximum(ring, 0)], -1)
        if not split and not keep_hull:
            _check_hole_sides(plc, inside, ring)
    else:
        region = np.full(len(T), -1, np.int64)
    vx, vy = mesh.x, mesh.y
    label = np.zeros(len(T), np.int64)
    if plc.holes is not None and len(plc.holes):
        hx, hy = plc.holes[:, 0].copy(), plc.holes[:, 1].copy()
        flood_seeds(vx, vy, T, N, cflag, hx, hy, inside, label, np.ones(len(hx), np.int64))
        inside &= label == 0
    attributes = None
    if plc.regions is not None and len(plc.regions):
        label[:] = -1
        rx, ry = plc.regions[:, 0].copy(), plc.regions[:, 1].copy()
        flood_seeds(vx, vy, T, N, cflag, rx, ry, np.ones(len(T), np.bool_), label,
                    np.arange(len(rx)))
        region = label
        attributes = plc.regions
    return (T, N, cflag, inside, region, attributes), tid


def _refine(plc, mesh, segs, classes, tid, opts, split_boundary, stats):
    """Delaunay refinement of the classified mesh; returns the new classes."""
    T, N, cflag, inside, region, attributes = classes
    lab = _slot_labels(tid, inside, region, len(mesh.tri) // 3)
    area_of_label = _area_bounds(plc, opts["max_area"], lab)
    limit = opts["max_steiner"]
    if limit is None:
        limit = 100 * mesh.nv + 100_000
        if opts["max_area"]:
            limit += int(min(8 * _domain_area(mesh, T, inside) / opts["max_area"], 1e9))
    budget = max(limit - int(stats.get("intersection_points", 0)), 0)
    room = STEINER_ROOM * mesh.nv + 64
    if area_of_label is not _NO_AREA_BOUNDS:
        room += _area_steiner(mesh, T, inside, region, area_of_label)
    status, counts, lab, _ = refine_mesh(
        mesh, lab, segs, min_angle=opts["min_angle"], max_area=opts["max_area"],
        area_of_label=area_of_label, conforming=opts["conforming"],
        split_boundary=split_boundary, max_new=budget, room=room)
    stats["refinement_steiner"] = int(counts[C_STEINER])
    stats["refinement_segment_splits"] = int(counts[C_SEG_SPLITS])
    stats["refinement_flips"] = int(counts[C_FLIPS])
    stats["frozen_segment_pieces"] = int(counts[C_FROZEN])
    stats["refinement_attempts"] = int(counts[C_ATTEMPTS])
    stats["refinement_deferred"] = int(counts[C_DEFERRED])
    stats["refinement_complete"] = status == FINISHED
    stats["_limit"] = limit
    T, N, tid, cflag = _real_triangles(mesh.tri, mesh.twin, mesh.cons, mesh.ntri, mesh.inf)
    inside, region = _triangle_labels(tid, lab, len(T))
    return T, N, cflag, inside, region, attributes


@njit(cache=True)
def _slot_labels(tid, inside, region, cap):
    """Refinement's label of every mesh slot: the region of an inside real
    triangle, else OUT."""
    lab = np.full(cap, OUT, np.int64)
    for t in range(tid.shape[0]):
        i = tid[t]
        if i >= 0 and inside[i]:
            lab[t] = region[i]
    return lab


@njit(cache=True)
def _triangle_labels(tid, lab, k):
    """Back from slot labels: ``inside`` and ``region`` (-1 outside) of the
    ``k`` real triangles."""
    inside = np.zeros(k, np.bool_)
    region = np.full(k, -1, np.int64)
    for t in range(tid.shape[0]):
        i = tid[t]
        if i >= 0 and lab[t] != OUT:
            inside[i] = True
            region[i] = lab[t]
    return inside, region


def _area_steiner(mesh, T, inside, region, area_of_label, cap=2_000_000):
    """About how many Steiner points the area bounds alone will add (the mesh
    is made that large at once instead of growing by doubling); at most ``cap``."""
    bound = area_of_label[np.where(inside, region, -1) + 1]
    use = inside & (bound > 0)
    x, y = mesh.x, mesh.y
    a, b, c = T[use, 0], T[use, 1], T[use, 2]
    area = np.abs((x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a])) / 2
    # a refined mesh has about 1.6 triangles, so 0.8 vertices, per max_area of domain
    return int(min(0.8 * float(np.sum(area / bound[use])), cap))


def _area_bounds(plc, max_area, lab):
    """Area bound per triangle label (label + 1 indexes it; 0: none), or
    :data:`_NO_AREA_BOUNDS` when there is none at all."""
    with_regions = plc.regions is not None and len(plc.regions) > 0
    if max_area is None and not (with_regions and (plc.regions[:, 3] > 0).any()):
        return _NO_AREA_BOUNDS
    top = int(lab.max(initial=-1))
    bounds = np.full(top + 2, float(max_area or 0.0))
    if with_regions:
        ra = plc.regions[:, 3]
        ok = np.isfinite(ra) & (ra > 0)
        k = min(len(ra), top + 1)
        bounds[1: k + 1] = np.where(ok[:k], ra[:k], bounds[1: k + 1])
    return bounds


def _domain_area(mesh, T, inside):
    x, y = mesh.x, mesh.y
    a, b, c = T[inside, 0], T[inside, 1], T[inside, 2]
    return float(np.sum(np.abs((x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]))) / 2)


def _finish_refinement(out, plc, opts, stats):
    """Segment ids of hull pieces to -1; count what misses the bounds; raise
    when the Steiner budget ran out."""
    ids = out.segment_ids
    ids[ids >= len(plc.segments)] = -1
    below = np.empty(0, np.int64)
    if opts["min_angle"]:
        below = count_below(out.vertices, out.triangles, math.sin(math.radians(opts["min_angle"])) ** 2)
    stats["below_min_angle"] = int(len(below))
    out.below_min_angle = below
    limit = stats.pop("_limit")
    if not stats["refinement_complete"]:
        raise RefinementLimitError(
            f"refinement stopped at max_steiner={limit} Steiner points with triangles still "
            "breaking the bounds; raise max_steiner (or relax min_angle/max_area); the partial "
            "mesh is in this error's .triangulation", triangulation=out)


def _check_hole_sides(plc, inside, ring):
    """A hole ring is entered from its shell's inside: a region inside the
    domain entered through a hole ring means the hole lies outside its shell."""
    bad = inside & (ring >= 0) & plc.ring_is_hole[np.maximum(ring, 0)]
    if bad.any():
        r = int(ring[np.flatnonzero(bad)[0]])
        p = int(plc.ring_polygon[r])
        raise InvalidGeometryError(
            f"a hole of polygon {p} (ring {r}) lies outside its shell or overlaps another ring; "
            "use intersections='split' to mesh by even-odd depth instead")


def _collinear_result(plc, order, dup_of, submerged, stats, t0):
    tri = Triangulation.from_collinear(plc.vertices, order, None, dup_of, submerged, stats, t0)
    tri.segments = np.empty((0, 2), np.int64)
    tri.segment_ids = np.empty(0, np.int64)
    return tri
