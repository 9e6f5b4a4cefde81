"""Many polygons in one call: the batch path for GIS-scale work.

Input is flat ring arrays (what GEOS hands out for a whole GeoSeries at once):
every geometry is a set of rings, every ring a closed chain of vertices. The
result is one :class:`MeshBatch`: all triangles of all geometries in one
array, with the geometry each comes from.

Each geometry is the PLC of its rings (a Polygon with holes, or a
MultiPolygon); inside and outside follow from the rings as in
:func:`cdt_plugin.triangulate`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable, SupportsIndex

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.pipeline import mesh_geometries
from .cdt import checked_sizing, triangulate_plc
from .errors import CDTError
from .grading import refine_to_size
from .interrupts import deferred_interrupt
from .lift import lift_z
from .options import MeshOptions
from .parallel import check_workers, map_ordered, resolve_workers
from .plc import PLC, as_plc, ring_plc

ERRORS = ("raise", "skip")
CHUNK = 4096               # geometries per compiled call (progress granularity)
MIN_CHUNK = 64             # geometries worth a thread of their own
# options of cdt_plugin.triangulate that go geometry by geometry (the others make a MeshOptions)
_SEED_OPTIONS = ("holes", "regions")
# a size field: every geometry meshed one by one, then refined to it (size= may also be
# a sequence, one field or None per geometry)
_SIZE_OPTIONS = ("size", "growth", "min_size")
_OPTIONS = frozenset(MeshOptions._fields + _SEED_OPTIONS + _SIZE_OPTIONS)


@dataclass
class MeshBatch:
    """Triangles of many geometries, as flat NumPy arrays.

    Attributes
    ----------
    vertices : (n, 2) float64
        Every input ring vertex, geometry after geometry, ring after ring
        (closing points dropped), then the Steiner vertices.
    z : (n,) float64 or None
        Z of every vertex when the input has Z (Steiner vertices interpolated,
        see :mod:`cdt_plugin.lift`; NaN for the vertices of geometries without Z).
    triangles : (k, 3) int64
        Indices into ``vertices``, counter-clockwise, grouped by geometry.
    geometry : (k,) int64
        Which input geometry each triangle belongs to (non-decreasing).
    region : (k,) int64
        The polygon of its geometry each triangle lies in (0 for a Polygon,
        the part number for a MultiPolygon).
    offsets : (g + 1,) int64
        Triangles of geometry ``i`` are ``triangles[offsets[i]:offsets[i + 1]]``.
    errors : dict
        Geometry index -> :class:`CDTError` for geometries that failed
        (``errors="skip"``); they have no triangles.
    stats : dict
        ``geometries``, ``triangles``, ``steiner``, ``fallback`` (geometries
        meshed one by one), ``seconds``.
    """

    vertices: NDArray[np.float64]
    z: NDArray[np.float64] | None
    triangles: NDArray[np.int64]
    geometry: NDArray[np.int64]
    region: NDArray[np.int64]
    offsets: NDArray[np.int64]
    errors: dict[int, CDTError] = field(default_factory=dict)
    stats: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.offsets) - 1

    def mesh(self, i: int) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
        """Geometry ``i`` alone: ``(vertices, triangles)`` with only the
        vertices its triangles use (``vertices`` is (m, 3) when there is Z)."""
        T = self.triangles[self.offsets[i]:self.offsets[i + 1]]
        used, local = np.unique(T, return_inverse=True)
        V = self.vertices[used]
        if self.z is not None:
            V = np.column_stack([V, self.z[used]])
        return V, local.reshape(-1, 3)


def geometry_plc(xy: NDArray[np.float64], ring_start: NDArray[np.int64],
                 geom_ring_start: NDArray[np.int64], ring_polygon: NDArray[np.int64],
                 ring_is_hole: NDArray[np.bool_], z: NDArray[np.float64] | None, g: int) -> PLC:
    """The PLC of geometry ``g`` of flat ring arrays, by :func:`cdt_plugin.plc.ring_plc`
    (its rings' edges are the segments; a degenerate ring is named in
    ``degenerate_rings``, as a geometry's is); the PLC has its own ring arrays."""
    r0, r1 = geom_ring_start[g], geom_ring_start[g + 1]
    v0, v1 = ring_start[r0], ring_start[r1]
    bounds = np.asarray(ring_start[r0:r1 + 1], np.int64) - v0
    # non-finite coordinates are left to the triangulation, whose error names the row
    plc, _ = ring_plc(np.ascontiguousarray(xy[v0:v1]), bounds[:-1], bounds[1:],
                      np.array(ring_polygon[r0:r1], np.int64), np.array(ring_is_hole[r0:r1], bool),
                      None if z is None else z[v0:v1].copy(), check_finite=False)
    return plc


def check_batch_options(*, errors: str = "raise", workers: SupportsIndex | None = None,
                        **options: Any) -> tuple[MeshOptions, dict[str, Any], int | None]:
    """Validate the options of a batch call before any work starts. Returns
    ``(mesh_options, seeds, workers)``: the :class:`MeshOptions` of every
    geometry, the seed options (applied geometry by geometry) and the checked
    ``workers``."""
    if errors not in ERRORS:
        raise CDTError(f"errors must be one of {ERRORS}, got {errors!r}")
    unknown = options.keys() - _OPTIONS
    if unknown:
        raise CDTError(f"unknown option {sorted(unknown)[0]!r}")
    if options.get("merge_distance"):
        raise CDTError("merge_distance is not supported by the batch path (triangulate_rings, "
                       "layers): triangulate the geometries one by one with cdt_plugin.triangulate")
    mesh_options = MeshOptions.check(**{k: v for k, v in options.items()
                                        if k not in _SEED_OPTIONS + _SIZE_OPTIONS})
    seeds = {k: v for k, v in options.items() if k in _SEED_OPTIONS}
    sizes = {k: options.get(k) for k in _SIZE_OPTIONS}
    if any(v is not None for v in sizes.values()):
        seeds["sizing"] = _checked_sizes(mesh_options, **sizes)
    return mesh_options, seeds, check_workers(workers)


#: The checked size field of a geometry and the options of its first pass.
SizedOptions = tuple[Any, MeshOptions]


def _checked_sizes(options: MeshOptions, size: Any, growth: Any,
                   min_size: Any) -> SizedOptions | list[SizedOptions | None]:
    """The sizing of every geometry (:func:`cdt_plugin.cdt.checked_sizing`): one
    for all, or a list with one (or None: not refined to a size) per geometry
    when ``size`` is a list, tuple or array."""
    if not isinstance(size, (list, tuple, np.ndarray)):
        return checked_sizing(options, size, options.max_area, growth, min_size)
    return [None if s is None else checked_sizing(options, s, options.max_area, growth, min_size)
            for s in size]


def triangulate_rings(xy: ArrayLike, ring_start: ArrayLike, geom_ring_start: ArrayLike,
                      ring_polygon: ArrayLike, ring_is_hole: ArrayLike, *, z: ArrayLike | None = None,
                      errors: str = "raise", progress: Callable[[int], object] | None = None,
                      workers: int | None = None, **options: Any) -> MeshBatch:
    """Constrained Delaunay triangulation of many geometries given as rings.

    Parameters
    ----------
    xy : (n, 2) float64
        Ring vertices, without closing points, geometry after geometry.
    ring_start : (r + 1,) int64
        Ring ``j`` is ``xy[ring_start[j]:ring_start[j + 1]]``.
    geom_ring_start : (g + 1,) int64
        Geometry ``i`` is made of rings ``geom_ring_start[i]:geom_ring_start[i + 1]``.
    ring_polygon : (r,) int64
        The polygon (part) number of each ring within its geometry.
    ring_is_hole : (r,) bool
        Whether each ring is a hole of its polygon (checked: a hole outside its
        shell raises :class:`cdt_plugin.InvalidGeometryError`).
    z : (n,) float64, optional
        Z of the ring vertices, carried to the output (Steiner vertices interpolated).
    errors : {"raise", "skip"}
        A geometry that cannot be meshed raises its :class:`CDTError` with
        ``geometry i:`` in front of the message and an ``index`` attribute, or
        (``"skip"``) is left without triangles and its error (the same) recorded
        in ``errors``.
    progress : callable, optional
        Called with the number of geometries finished since the last call.
    workers : int, optional
        Threads to mesh on (the compiled route runs without the GIL). Default:
        every available core once the batch has :data:`MIN_CHUNK` geometries
        per core; 1 meshes in the calling thread. Any number gives the same
        result: chunks of geometries are meshed apart and joined in order.
    **options
        Passed to :func:`cdt_plugin.triangulate` (``intersections``,
        ``min_angle``, ``max_area``, ``size``, ``growth``, ``min_size``, ...).
        ``size`` may also be a sequence with one size field (or None) per
        geometry; with a size field the geometries are meshed one by one.

    Examples
    --------
    >>> import numpy as np
    >>> xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [3, 0], [2, 1.0]])
    >>> b = triangulate_rings(xy, [0, 4, 7], [0, 1, 2], [0, 0], [False, False])
    >>> len(b), b.triangles.shape, b.geometry.tolist()
    (2, (3, 3), [0, 0, 1])
    """
    t0 = time.perf_counter()
    mesh_options, seeds, workers = check_batch_options(errors=errors, workers=workers, **options)
    xy = np.ascontiguousarray(xy, dtype=np.float64).reshape(-1, 2)
    ring_start = np.asarray(ring_start, np.int64)
    geom_ring_start = np.asarray(geom_ring_start, np.int64)
    ng = len(geom_ring_start) - 1
    ring_polygon = np.asarray(ring_polygon, np.int64)
    ring_is_hole = np.asarray(ring_is_hole, np.bool_)
    z = None if z is None else np.asarray(z, np.float64)
    sizing = seeds.get("sizing")
    if isinstance(sizing, list) and len(sizing) != ng:
        raise CDTError(f"size has {len(sizing)} size fields for {ng} geometries: give one "
                       "field for all, or one (or None) per geometry")
    parts = []          # (geometry, triangles (batch ids), region)
    steiner_xy, steiner_z = [], []
    nsteiner = 0
    # one by one: seeds or keep_hull, or Steiner points whose Z must be interpolated
    compiled = (all(v is None or v is False for v in seeds.values()) and not mesh_options.keep_hull
                and not (z is not None and (mesh_options.split or mesh_options.refines)))
    if compiled:
        x, y = xy[:, 0].copy(), xy[:, 1].copy()
        route_options = mesh_options.route_args()

        def mesh_chunk(chunk):
            g0, g1 = chunk
            with deferred_interrupt(ring_start[geom_ring_start[g1]] - ring_start[geom_ring_start[g0]]):
                # Steiner ids from len(xy) in every chunk: shifted below, in chunk order
                return mesh_geometries(x, y, ring_start, geom_ring_start, ring_polygon, ring_is_hole,
                                       g0, g1, route_options, len(xy))

        def report(chunk, result):
            if progress is not None:
                progress(chunk[1] - chunk[0] - int(result[4].sum()))

        threads = resolve_workers(workers, ng // MIN_CHUNK)
        chunks = geometry_chunks(ng, threads)
        todo: list[int] = []
        for (g0, _), (T, G, R, S, failed) in zip(chunks, map_ordered(mesh_chunk, chunks, threads,
                                                                    report)):
            if len(S):
                T[T >= len(xy)] += nsteiner
                steiner_xy.append(S)
                nsteiner += len(S)
            parts.append((G, T, R))
            todo.extend((g0 + np.flatnonzero(failed)).tolist())
    else:
        todo = list(range(ng))
    failed = {}
    for g in todo:
        if geom_ring_start[g] == geom_ring_start[g + 1]:     # empty geometry: no triangles
            if progress is not None:
                progress(1)
            continue
        plc = geometry_plc(xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole, z, g)
        v0 = ring_start[geom_ring_start[g]]
        try:
            plc = as_plc(plc, holes=seeds.get("holes"), regions=seeds.get("regions"))
            sized = sizing[g] if isinstance(sizing, list) else sizing
            tri = triangulate_plc(plc, mesh_options if sized is None else sized[1])
            if sized is not None:
                tri = _refined_to_size(tri, sized[0], mesh_options)
        except CDTError as e:
            e.args = (f"geometry {g}: {e.args[0] if e.args else ''}",) + tuple(e.args[1:])
            e.index = g
            if errors == "raise":
                raise
            failed[g] = e
            continue
        finally:
            if progress is not None:
                progress(1)
        glob = _global_ids(tri, v0, len(xy) + nsteiner)
        st = np.asarray(tri.steiner, np.int64)
        if len(st):
            steiner_xy.append(tri.vertices[st])
            if plc.z is not None:          # (the geometry's part of z)
                steiner_z.append(lift_z(tri, plc.z, plc.segments)[st])
            nsteiner += len(st)
        parts.append((np.full(len(tri.triangles), g, np.int64), glob[tri.triangles],
                      np.asarray(tri.regions, np.int64)))
    out = _assemble(xy, z, parts, steiner_xy, steiner_z, ng, failed, t0)
    out.stats["fallback"] = len(todo)
    return out


def _refined_to_size(tri: Any, sizing: Any, options: MeshOptions) -> Any:
    """``tri`` refined to its size field with the batch's other bounds (as
    :func:`cdt_plugin.triangulate` does with ``size=``)."""
    return refine_to_size(tri, sizing, max_area=options.max_area, max_steiner=options.max_steiner,
                          min_angle=options.min_angle,
                          conforming_delaunay=options.conforming_delaunay,
                          split_boundary=options.split_boundary,
                          split_segments=options.split_segments)


def geometry_chunks(ng: int, threads: int) -> list[tuple[int, int]]:
    """Geometry ranges ``(g0, g1)`` of one compiled call each: at most
    :data:`CHUNK` geometries; with several threads, about four chunks per
    thread (so that a chunk of large polygons does not hold up the others),
    of at least :data:`MIN_CHUNK` geometries."""
    size = CHUNK if threads == 1 else min(CHUNK, max(MIN_CHUNK, -(-ng // (4 * threads))))
    return [(g0, min(ng, g0 + size)) for g0 in range(0, ng, size)]


def _global_ids(tri, v0, steiner0):
    """Batch vertex id of each output vertex of ``tri``: input vertices map to
    their first input occurrence (offset ``v0``), Steiner vertices to new ids
    from ``steiner0``."""
    vm = np.asarray(tri.vertex_map)
    glob = np.empty(len(tri.vertices), np.int64)
    first = np.flatnonzero(vm >= 0)[::-1]
    glob[vm[first]] = v0 + first
    st = np.asarray(tri.steiner, np.int64)
    glob[st] = steiner0 + np.arange(len(st))
    return glob


def _assemble(xy, z, parts, steiner_xy, steiner_z, ng, failed, t0):
    """One MeshBatch from the parts (kernel chunks and single geometries), with
    the triangles grouped by geometry."""
    if parts:
        geometry = np.concatenate([G for G, _, _ in parts], dtype=np.int64)
        triangles = np.concatenate([T.reshape(-1, 3) for _, T, _ in parts], dtype=np.int64)
        region = np.concatenate([R for _, _, R in parts], dtype=np.int64)
        # the chunks come in geometry order; geometries meshed one by one after them do not
        if len(parts) > 1 and (geometry[1:] < geometry[:-1]).any():
            by = np.argsort(geometry, kind="stable")
            geometry, triangles, region = geometry[by], triangles[by], region[by]
    else:
        geometry, region = np.empty(0, np.int64), np.empty(0, np.int64)
        triangles = np.empty((0, 3), np.int64)
    offsets = np.searchsorted(geometry, np.arange(ng + 1)).astype(np.int64)
    vertices = np.vstack([xy] + steiner_xy) if steiner_xy else xy
    zz = None
    if z is not None:
        zz = np.concatenate([np.asarray(z, np.float64)] + steiner_z)
    stats = {"geometries": ng, "triangles": len(triangles), "steiner": len(vertices) - len(xy),
             "failed": len(failed), "seconds": time.perf_counter() - t0}
    return MeshBatch(vertices, zz, triangles, geometry, region, offsets, failed, stats)
