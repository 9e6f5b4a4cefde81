"""Refining an existing mesh (Triangle's ``-r``): the driver of :meth:`Triangulation.refine`.

:func:`refine_mesh` takes a triangulation (any result: of
:func:`cdt_plugin.triangulate`, of :meth:`Triangulation.from_triangles`, of a
previous refinement), checked options and, optionally, an area bound per
triangle, and returns the refined mesh's arrays (:class:`Refined`); the
result class wraps them. The mesh's half-edge store is made once
(:func:`cdt_plugin._core.remesh.existing_mesh_store`: the constrained Delaunay
triangulation of the vertices with every edge a segment, which is the mesh
itself when it is a valid one and names the triangles where it is not); a
refined result keeps the store it was read from (:class:`RefineState`), so a
further refinement starts from there.

Area bounds per triangle: refinement flips across the edges between triangles
with different bounds like across any other, and every triangle it makes or
changes takes the bound of the triangle of the mesh that holds its centroid
(:func:`cdt_plugin._core.refine.home_of`; the centroid summed smallest
coordinate first, so the same for any order of the corners; edges included):
no triangle of the result is larger than the bound of a triangle of the mesh
that holds its centroid. (Triangle averages the two bounds across a flip,
which promises nothing of where a triangle lies. Keeping those edges as
segments while refinement runs promises more, no triangle larger than the
bound of any triangle it overlaps, but splits them wherever refinement comes
near: on a 97,000-triangle mesh with every other triangle bounded at 0.3 of
its area, 353,000 triangles against Triangle's 275,000 and this rule's
329,000; giving both triangles of a flip the tighter bound spreads it over the
whole mesh.)

>>> import cdt_plugin
>>> from cdt_plugin.options import MeshOptions
>>> tri = cdt_plugin.Triangulation.from_triangles([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
>>> out = refine_mesh(tri, MeshOptions.check(max_area=0.1), None)
>>> out.complete, out.vertices[:3].tolist() == tri.vertices.tolist(), bool((out.parents == 0).all())
(True, True, True)
"""
from __future__ import annotations

import time
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ._core.ordering import SMALL_SORT, lexicographic_order
from ._core.pipeline import AREA_STEINER_CAP
from ._core.refine import (C_ATTEMPTS, C_DEFERRED, C_FLIPS, C_FROZEN, C_SEG_SPLITS, C_STEINER, OUT,
                           STEINER_ROOM)
from ._core.remesh import (MESH_CROSSING, MESH_MISSING, MESH_NOT_EDGE, MESH_OK, MESH_OVERLAP,
                           MESH_RANGE, MESH_REPEATED, existing_mesh_store, refine_existing)
from ._core.status import FINISHED
from .errors import CDTError, InvalidMeshError
from .interrupts import deferred_interrupt
from .options import MeshOptions
from .validate import range_error

_NO_IDS = np.empty(0, np.int64)
_NO_HOME = (np.empty((0, 3), np.int64), np.empty((0, 3), np.int64))
# the route options of the store: divide and conquer, room for refinement
_STORE_OPTIONS = MeshOptions.check(algorithm="divide", keep_hull=True).route_args(refine=True)


class RefineState(NamedTuple):
    """What a refined mesh keeps for a further refinement (private): its
    half-edge store (coordinates scaled by ``2**shift``), the segment each
    Steiner point lies on (``vseg``, :func:`cdt_plugin._core.refine.refine_store`:
    its rule around small input angles goes on working), how many of its
    segments are segments to keep (the first), the ends of each store segment
    (mesh ids), the output id of each mesh vertex below
    ``len(order)`` (``order``; later ones keep their number), the output
    triangle of each store slot (-1: none), the original segment id of each
    store segment (-1: a piece of the mesh's boundary), and the angle bound of
    the refinement that made it and whether it finished."""

    store: tuple
    vseg: NDArray[np.int64]
    kept_segments: int
    seg_ends: NDArray[np.int64]
    order: NDArray[np.int64]
    shift: int
    out_slot: NDArray[np.int64]
    segment_origin: NDArray[np.int64]
    min_angle: float = -1.0         # the angle bound the mesh was refined with (-1: not refined)
    complete: bool = False          # whether that refinement finished


class Refined(NamedTuple):
    """The arrays of a refined mesh (:func:`refine_mesh`): ``parents`` is the
    triangle of the mesh refined (its row) each new triangle was made from
    (with bounds that differ between triangles, the one holding its centroid),
    ``complete`` False when ``max_steiner`` stopped refinement."""

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    neighbors: NDArray[np.int64]
    constrained: NDArray[np.bool_]
    segments: NDArray[np.int64]
    segment_ids: NDArray[np.int64]
    parents: NDArray[np.int64]
    below_min_angle: NDArray[np.int64]
    stats: dict[str, Any]
    complete: bool
    state: RefineState


def refine_mesh(tri: Any, options: MeshOptions, bounds: NDArray[np.float64] | None,
                state: RefineState | None = None) -> Refined:
    """Refine ``tri`` (a :class:`Triangulation`) as ``options`` asks
    (``min_angle``, ``max_area``, ``conforming_delaunay``, ``split_boundary``,
    ``split_segments``, ``max_steiner``), with ``bounds`` an area bound per
    triangle (0: none) instead of ``max_area`` when given; ``state`` the store
    ``tri`` keeps from its own refinement (None: read from its arrays)."""
    t0 = time.perf_counter()
    V, T = tri.vertices, tri.triangles
    if len(T) == 0:
        raise CDTError(f"{tri!r} has no triangles: there is nothing to refine")
    if tri.weights is not None:
        raise CDTError("refine takes unweighted triangulations: refinement inserts unweighted points")
    nv = len(V)
    areas = triangle_areas(V, T)
    home = _NO_HOME
    if bounds is None:
        bounds = np.full(len(T), options.max_area or 0.0)
    bounded = bounds > 0
    if state is not None and already_met(options, areas, bounds, state):
        return unchanged(tri, options, state, t0)
    if state is None:
        state = read_mesh(V, T, tri.neighbors, tri.segments, tri.segment_ids)
    else:       # refinement works in place: the state stays as it is for another call
        state = state._replace(store=tuple(a.copy() if isinstance(a, np.ndarray) else a
                                           for a in state.store), vseg=state.vseg.copy())
    with np.errstate(over="ignore"):
        per_bound = float((areas[bounded] / bounds[bounded]).sum())     # (inf: the caps below)
    max_new = options.max_steiner
    if max_new is None:      # the default cap of triangulate's refinement
        max_new = 100 * nv + 100_000 + int(min(8 * per_bound, AREA_STEINER_CAP))
    room = STEINER_ROOM * nv + 64 + int(min(0.8 * per_bound, 2_000_000))
    area_of_label = np.zeros(len(T) + 1)
    area_of_label[1:] = scaled_areas(bounds, state.shift)
    lab = np.where(state.out_slot >= 0, state.out_slot, OUT)
    if np.any(bounds != bounds[0]):     # labels then follow the centroids (home_of)
        home = (home_triangles(T, state.order, nv), np.ascontiguousarray(tri.neighbors, np.int64))
    with deferred_interrupt(nv):
        (status, counts, (store, vseg), seg_ends, out_slot, vertices, triangles, neighbors,
         constrained, pieces, piece_ids, parents, below) = refine_existing(
            state.store, lab, state.seg_ends, state.kept_segments, tuple(options.route().refinement),
            area_of_label, max_new, room, state.order, state.shift, state.vseg, home)
    origin = state.segment_origin
    new = state._replace(store=store, vseg=vseg, seg_ends=seg_ends, out_slot=out_slot,
                         min_angle=options.min_angle or 0.0, complete=status == FINISHED)
    stats = {"algorithm": "refine", "input_points": nv, "input_triangles": len(T),
             "input_segments": len(tri.segments), "vertices": len(vertices),
             "triangles": len(triangles), "steiner": len(tri.steiner) + len(vertices) - nv,
             "refinement_steiner": int(counts[C_STEINER]),
             "refinement_segment_splits": int(counts[C_SEG_SPLITS]),
             "refinement_flips": int(counts[C_FLIPS]), "frozen_segment_pieces": int(counts[C_FROZEN]),
             "refinement_attempts": int(counts[C_ATTEMPTS]),
             "refinement_deferred": int(counts[C_DEFERRED]), "refinement_complete": status == FINISHED,
             "refinement_limit": int(max_new), "below_min_angle": len(below),
             "seconds": time.perf_counter() - t0}
    return Refined(vertices, triangles, neighbors, constrained, pieces, origin[piece_ids], parents,
                   below, stats, status == FINISHED, new)


def already_met(options: MeshOptions, areas: NDArray[np.float64], bounds: NDArray[np.float64],
                state: RefineState) -> bool:
    """Whether refinement would add nothing to the mesh that ``state`` was
    refined into: that refinement finished with an angle bound at least
    ``options``' (so its triangles meet this one, or are excused as it
    excused them, and no piece is encroached for it), and every triangle is
    within its area bound by more than rounding (``areas``, ``bounds``)."""
    if not state.complete or options.conforming_delaunay or (options.min_angle or 0.0) > state.min_angle:
        return False
    bounded = bounds > 0
    return bool((areas[bounded] <= bounds[bounded] * (1 - 1e-12)).all())


def unchanged(tri: Any, options: MeshOptions, state: RefineState, t0: float) -> Refined:
    """:class:`Refined` for a mesh that meets the bounds already: its own arrays."""
    below = tri.below_min_angle
    if options.min_angle and len(below):     # (those the bound excuses: a subset of the last ones)
        from .report import triangle_quality    # (loaded on first use: import cdt_plugin stays fast)
        angles = triangle_quality(tri.vertices, tri.triangles[below])["angles"].min(axis=1)
        below = below[angles < options.min_angle]
    elif not options.min_angle:
        below = below[:0]
    stats = {"algorithm": "refine", "input_points": len(tri.vertices),
             "input_triangles": len(tri.triangles), "input_segments": len(tri.segments),
             "vertices": len(tri.vertices), "triangles": len(tri.triangles),
             "steiner": len(tri.steiner), "refinement_steiner": 0,
             "refinement_segment_splits": 0, "refinement_flips": 0, "frozen_segment_pieces": 0,
             "refinement_attempts": 0, "refinement_deferred": 0, "refinement_complete": True,
             "refinement_limit": 0, "below_min_angle": len(below), "seconds": time.perf_counter() - t0}
    return Refined(tri.vertices, tri.triangles, tri.neighbors, tri.constrained, tri.segments,
                   tri.segment_ids, np.arange(len(tri.triangles)), below, stats, True, state)


def read_mesh(V: NDArray[np.float64], T: NDArray[np.int64], neighbors: NDArray[np.int64],
              segments: NDArray[np.int64], segment_ids: NDArray[np.int64]) -> RefineState:
    """The half-edge store of the mesh ``V, T`` (``neighbors`` as a
    :class:`Triangulation` has them) keeping ``segments`` (of
    original ids ``segment_ids``), ready for :func:`refine_mesh`; or the
    :class:`InvalidMeshError` that names where the triangles are not a
    triangulation."""
    x, y = V[:, 0].copy(), V[:, 1].copy()
    order = horizontal = _NO_IDS
    if len(x) >= SMALL_SORT:        # numpy's sorts beat the compiled one on many points
        order, horizontal = lexicographic_order(x, y), lexicographic_order(y, -x)
    segs = np.ascontiguousarray(segments, np.int64)
    with deferred_interrupt(len(x)):
        status, info, shift, order, store, lab, seg_ends = existing_mesh_store(
            x, y, np.ascontiguousarray(T, np.int64), np.ascontiguousarray(neighbors, np.int64), segs,
            order, horizontal, _STORE_OPTIONS)
    if status != MESH_OK:
        raise_mesh_error(status, info, V, T, segs, order[seg_ends])
    out_slot = np.where(lab != OUT, lab, -1)
    origin = np.full(len(seg_ends), -1, np.int64)
    origin[:len(segs)] = segment_ids
    return RefineState(store, _NO_IDS, len(segs), seg_ends, order, int(shift), out_slot, origin)


def raise_mesh_error(status: int, info: NDArray[np.int64], V: NDArray[np.float64],
                     T: NDArray[np.int64], segs: NDArray[np.int64], edges: NDArray[np.int64]) -> None:
    """The :class:`InvalidMeshError` (or range error) for a mesh that
    :func:`read_mesh` could not read (``edges``: the store's segments, as
    vertex pairs, where two of them cross or overlap)."""
    i, j = int(info[0]), int(info[1])
    if status == MESH_RANGE:
        raise range_error("vertices", V[:, 0], V[:, 1], None, i, j)
    if status == MESH_REPEATED:
        raise InvalidMeshError(f"vertices {j} and {i} are the same point {V[i].tolist()}")
    if status == MESH_NOT_EDGE:
        raise InvalidMeshError(f"segment {i} {segs[i].tolist()} is not an edge of the triangles",
                               segments=(i,))
    if status == MESH_MISSING:
        inside = _vertices_in(V, T[i])
        why = (f"vertex {inside[0]} lies inside it or on its edges" if len(inside)
               else "it overlaps other triangles")
        raise InvalidMeshError(f"triangle {i} {T[i].tolist()} is not a triangle of the mesh: {why}",
                               triangles=(i,))
    if status in (MESH_CROSSING, MESH_OVERLAP):
        a, b = edges[i], edges[j]
        t, u = _triangle_with(T, a), _triangle_with(T, b)
        how = "cross" if status == MESH_CROSSING else "overlap (collinear)"
        raise InvalidMeshError(f"triangles {t} {T[t].tolist()} and {u} {T[u].tolist()} overlap: "
                               f"their edges {a.tolist()} and {b.tolist()} {how}", triangles=(t, u))
    raise CDTError(f"internal error reading the mesh (status {status}, {info.tolist()}); "
                   "please report this input")


def _triangle_with(T, edge):
    """The first triangle with ``edge`` (either way) among its edges."""
    has = (T == edge[0]).any(axis=1) & (T == edge[1]).any(axis=1)
    return int(np.flatnonzero(has)[0])


def _vertices_in(V, corners):
    """The vertices (other than ``corners``) in the closed triangle ``corners``
    (counter-clockwise), by floating-point orientation: for a message only."""
    a, b, c = V[corners]
    def side(p, q):
        return (q[0] - p[0]) * (V[:, 1] - p[1]) - (q[1] - p[1]) * (V[:, 0] - p[0])
    inside = (side(a, b) >= 0) & (side(b, c) >= 0) & (side(c, a) >= 0)
    inside[corners] = False
    return np.flatnonzero(inside)


def home_triangles(T: NDArray[np.int64], order: NDArray[np.int64], nv: int) -> NDArray[np.int64]:
    """The triangles ``T`` over ``nv`` output vertices in the ids of the store,
    whose vertex ``i`` is output vertex ``order[i]`` below ``len(order)``, ``i`` after."""
    store_id = np.arange(nv)
    store_id[order] = np.arange(len(order))
    return np.ascontiguousarray(store_id[T], np.int64)


def triangle_areas(V: NDArray[np.float64], T: NDArray[np.int64]) -> NDArray[np.float64]:
    """The area of each triangle (floating point; inf where it overflows, at
    coordinates near the largest doubles)."""
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    with np.errstate(over="ignore", invalid="ignore"):
        d = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return np.where(np.isnan(d), np.inf, 0.5 * np.abs(d))


def scaled_areas(bounds: NDArray[np.float64], shift: int) -> NDArray[np.float64]:
    """Area bounds in the units of the store (points scaled by ``2**shift``),
    as :func:`cdt_plugin._core.scaling.scaled_area` scales one: a positive bound
    stays positive."""
    s = bounds * 2.0 ** shift * 2.0 ** shift
    return np.where((bounds > 0) & (s == 0), 5e-324, s)
