"""Constrained Delaunay triangulation of a PLC (Sec. 2.10): the Python front.

:func:`triangulate` validates every option, reads the input into a
:class:`PLC`, makes one call of the compiled route
(:func:`cdt_plugin._core.pipeline.cdt_route`: Delaunay triangulation, segment
insertion, domain classification, optional refinement, output arrays; through
``cdt_route_packed``, which hands its integer outputs back in one array) and
wraps the result, or raises the precise error for the route's stop.
"""
from __future__ import annotations

import dataclasses
import functools
import time
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.mesh import IDX
from ._core.ordering import SMALL_SORT, brio_order, lexicographic_order
from ._core.pipeline import (K_ATTEMPTS, K_DEFERRED, K_DUPLICATE_SEGMENTS, K_DUPLICATES, K_FLIPS,
                             K_FROZEN, K_INTERSECTIONS, K_MERGED_OVERLAPS, K_ON_SEGMENTS,
                             K_REF_COMPLETE, K_REF_FLIPS, K_REF_LIMIT, K_REF_SPLITS, K_REF_STEINER,
                             K_ZERO_SEGMENTS, PACK_ARRAYS, PACK_HEADER, cdt_route_packed,
                             route_points_for_threads)
from ._core.segments import split_crossing
from ._core.snap import snap_route
from ._core.status import (ROUTE_COLLINEAR, ROUTE_CROSSING, ROUTE_HOLE_OUTSIDE, ROUTE_OK,
                           ROUTE_OVERLAP, ROUTE_POLYGONS_OVERLAP, ROUTE_RANGE, ROUTE_REFINE_LIMIT,
                           ROUTE_NEEDS_SNAP, ROUTE_STEINER_LIMIT, ROUTE_UNRESOLVED)
from ._routes import build_divide_two_threads
from .errors import (CDTError, InvalidGeometryError, OverlappingSegmentsError, RefinementLimitError,
                     SegmentIntersectionError, UnresolvedCrossingError)
from .interrupts import deferred_interrupt
from .markers import BaseMesh, Tags, make_tags
from .markers import vertex_attributes as attributes_of
from .merging import merge_close_points
from .options import MeshOptions, checked_options, route_plan
from .parallel import check_workers, resolve_workers
from .planar import check_plane_tolerance, planar_plc
from .plc import PLC, GeometryLike, as_plc
from .fields import ConstantSize, SizeField, Sizing, check_sizing
from .grading import SIZE_AREA, refine_to_size
from .sizing import SizeTest, check_size_test, refine_until_suitable
from .triangulation import Triangulation
from .validate import range_error

_NO_IDS = np.empty(0, np.int64)
_NO_RINGS = np.empty(0, np.bool_)
_NO_SEEDS = np.empty((0, 2))
_NOT_SNAPPED = (np.empty(0), np.empty(0), np.empty((0, 3), np.int64))   # crossings not snapped yet
_NO_REGIONS = np.empty((0, 4))
_NO_WEIGHTS = np.empty(0)
#: From this many vertices the Delaunay stage of the route is built on two threads. Below
#: it the threads' set-up (the halves' own sorts, the join) costs what they save: on the
#: C1 polygons (benchmarks/bench_cdt.py) two threads took 1.0x one thread's time at 63,000
#: and 113,000 vertices, 0.87x at 250,000, 0.77x at 500,000. (At 113,000, warm in one
#: process, 30 interleaved rounds gave 0.90-0.97x; in fresh processes 1.0-1.1x, and the
#: constrained benchmark 1.15x with the threshold there: not worth lowering it.)
PARALLEL_VERTICES = 200_000
_NO_STORE = (np.empty(0, IDX), np.empty(0, IDX), np.empty(0, IDX), np.empty(0, np.int64),
             np.int64(0))     # (pipeline.no_store: the route builds its Delaunay triangulation itself)


def triangulate(vertices: ArrayLike | PLC | GeometryLike, segments: ArrayLike | None = None, *,
                holes: ArrayLike | None = None, regions: ArrayLike | None = None,
                intersections: str = "raise",
                keep_hull: bool = False, algorithm: str = "auto",
                min_angle: float | None = None, max_area: float | SizeField | None = None,
                conforming_delaunay: bool = False, split_boundary: bool = True,
                max_steiner: int | None = None, workers: int | None = None,
                vertex_markers: ArrayLike | None = None, segment_markers: ArrayLike | None = None,
                vertex_attributes: ArrayLike | None = None,
                split_segments: bool = True, suitable: SizeTest | None = None,
                size: float | SizeField | Triangulation | None = None, growth: float | None = None,
                min_size: float | None = None, smooth: str | int | None = None,
                merge_distance: float | None = None,
                plane_tolerance: float | None = None) -> Triangulation:
    """Constrained Delaunay triangulation of a planar straight-line complex.

    Parameters
    ----------
    vertices : (n, 2) array, a :class:`PLC`, or a geometry
        Vertices; or any object with ``__geo_interface__`` (shapely Polygon,
        MultiPolygon, GeometryCollection, LineString, Point...), read from its
        GeoJSON-like mapping: rings give the domain exactly, any winding.
        With several polygons (also a coverage sharing edges) ``tri.regions``
        is the polygon each triangle lies in; polygons whose interiors
        overlap raise :class:`InvalidGeometryError` naming both.
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
        Region seeds ``x, y[, attribute[, max_area]]`` (3D input: also
        ``x, y, z, attribute, max_area``, see Notes): each paints its
        segment-bounded region; ``tri.regions`` gives the seed index per
        triangle and ``tri.region_attributes`` the attribute. A positive
        ``max_area`` bounds the area of the region's triangles (Steiner points
        are added, as with the ``max_area`` option, which need not be given).
    intersections : {"raise", "split"}
        Crossing or collinear-overlapping segments raise
        :class:`SegmentIntersectionError` / :class:`OverlappingSegmentsError`
        naming both segments and the point, or (``"split"``) the crossing point
        is inserted — each coordinate the double nearest to the exact crossing
        (exact when it is a double), the same for any order and direction of
        the segments, so it may lie off the exact segments by a rounding
        error — and overlaps merged.
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
        degrees. Refinement is proven to finish up to 20.7 degrees and finishes
        in practice up to about 34 (Triangle's documentation); above 34 a
        :class:`RefinementRangeWarning` is given before any work (it may run
        until ``max_steiner`` and raise :class:`RefinementLimitError`), and 60
        or more raises :class:`RefinementRangeError` (no triangle has a smallest
        angle above 60). Triangles at an input angle smaller than the bound
        cannot meet it: they are left as they are and counted in
        ``stats["below_min_angle"]``.
    max_area : float or callable, optional
        Refine until no triangle is larger (Triangle's ``-a``). A region seed's
        fourth column, when positive, bounds its region instead (``-a -A``).
        A callable ``f(x, y) -> areas`` over arrays bounds every triangle by
        its value at the triangle's centroid (strictly, as Triangle's ``-a``),
        evaluated vectorised in rounds (:mod:`cdt_plugin.grading`).
    size : float, callable or Triangulation, optional
        A target edge length, as in gmsh (:mod:`cdt_plugin.fields`): a
        number, a callable ``f(x, y) -> lengths`` over arrays, or a background
        mesh with the sizes in its ``vertex_attributes[:, 0]``. Every
        triangle's longest edge ends at most 1.5 times the size at its
        centroid, the median of that ratio near 1
        (:func:`cdt_plugin.report.size_ratios` measures it);
        ``stats["size_rounds"]`` counts the rounds of refinement it took.
    growth : float, optional
        A gradation limit (> 1) on ``size`` or a callable ``max_area``: the
        field is lowered where needed so that it grows by at most
        ``growth - 1`` per unit of distance (neighbouring edges differ at most
        by about that factor): a small size somewhere grades the mesh around it.
    min_size : float, optional
        A floor on ``size``: a field that goes to zero (or below) is raised to
        it. Without a floor such a field raises
        :class:`~cdt_plugin.errors.SizeFieldError` naming the point, or ends
        at the Steiner cap or the double-precision limit with
        :class:`RefinementLimitError`.
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
    split_segments : bool
        With ``False`` no Steiner point goes on any segment, inside the domain
        or on its boundary (Triangle's ``-YY``); the triangles at segments may
        then miss the bounds.
    suitable : callable, optional
        A size test (Triangle's ``-u``): ``suitable(org, dest, apex, area)``
        over arrays, the corners (k, 2) and areas (k,) of every triangle,
        returning (k,) booleans, True where a triangle is good enough. The
        triangles it rejects are refined (each to at most half its area) until
        it accepts them all, the other bounds kept; it is called once per round
        on the whole mesh (:func:`cdt_plugin.sizing.refine_until_suitable`).
    max_steiner : int, optional
        Cap on Steiner points (intersections with ``"split"`` plus refinement).
        Crossings are counted before anything is built: more than the cap
        raise :class:`UnresolvedCrossingError`; by default every crossing is
        inserted (at most ``m (m - 1) / 2`` for ``m`` segments). Refinement
        that reaches the cap raises :class:`RefinementLimitError` carrying the
        partial mesh. The default cap stops runaway refinement:
        100 per input vertex plus 100,000, and with ``max_area`` 8 per
        ``max_area`` of the domain's area, at most 1,000,000 more (pass a
        larger ``max_steiner`` for finer meshes).
    workers : int, optional
        Threads for the Delaunay triangulation of the vertices (divide and
        conquer, from 200,000 vertices: the first cut's halves side by side);
        default every core. The result is the same with any number.
    vertex_markers : (n,) int array, optional
        Boundary markers of the input vertices (Triangle's); the result's
        ``vertex_markers`` follow Triangle's rules (see
        :mod:`cdt_plugin.markers`). For geometry input, one per vertex of
        its PLC (:meth:`PLC.from_geo_interface`, closing points dropped).
    segment_markers : (m,) int array, optional
        Boundary markers of the input segments; each piece of a segment and
        each Steiner point on it inherit the segment's marker
        (``tri.segment_markers``, ``tri.edge_markers``, ``tri.vertex_markers``).
        Markers are derived on first access; without these keywords they are
        Triangle's defaults (1 on the boundary, 0 inside).
    merge_distance : float, optional
        Merge input points closer than this before meshing (CAD outlines with
        points a rounding error apart make needles no refinement removes).
        The points are taken in lexicographic order (x, then y, then input
        index); a point closer than ``merge_distance`` (floating-point
        Euclidean distance) to a point kept before it goes to the nearest such
        point, so no two kept points are that close. ``tri.vertex_map`` names
        the output vertex of every input point, ``stats["merged_points"]``
        counts the points moved; a segment whose ends merge is dropped (named
        in ``stats["zero_length_segments"]``) and segments made equal are
        merged. Hole and region seeds do not move. Moving points may make
        segments cross (raised as without it). Default (None or 0): only exact
        duplicates are merged.
    plane_tolerance : float, optional
        For 3D input (see below): how far (a distance) a vertex may lie from
        the fitted plane. Default: 64 roundings of the largest coordinate
        (``64 * 2**-52 * max|coordinate|``, :data:`cdt_plugin.planar.PLANE_ROUNDINGS`);
        0: the vertices must be exactly coplanar (decided in exact arithmetic).
        Farther vertices raise :class:`NonPlanarError` naming the farthest
        and its distance.
    vertex_attributes : (n,) or (n, k) float array, optional
        Attributes of the input vertices, carried to every output vertex
        (``tri.vertex_attributes``): Steiner points get the linear
        interpolation along the segment they lie on, or on the triangle of the
        unrefined triangulation that holds them.
    smooth : {"odt", "lloyd"} or int, optional
        Smooth the mesh after refinement (:meth:`Triangulation.smooth`): that
        method for 10 iterations, or a number of ODT iterations. Only Steiner
        points move, so it changes nothing without refinement; the smallest
        angle never falls and the result is constrained Delaunay
        (``stats["smoothing"]`` compares before and after).

    Notes
    -----
    3D input (an (n, 3) array, a geometry with Z, a PLC with ``z``) is a planar
    polygon in any plane (:mod:`cdt_plugin.planar`): it is meshed in its plane,
    ``tri.vertices`` are the 2D coordinates it was meshed in (two of each input
    vertex's coordinates, exactly: x, y for a horizontal plane),
    ``tri.vertices3d`` every vertex in 3D (input vertices exactly, Steiner
    points on the plane) and ``tri.plane`` the plane. Seeds may then be 3D
    points of the plane, projected as the vertices are: holes as (h, 3),
    regions as rows of five ``x, y, z, attribute, max_area`` (NaN: none); a
    seed farther from the plane than ``plane_tolerance`` (its default when
    0) raises :class:`NonPlanarError` naming it. Seeds of two columns (and
    regions of two to four) are in ``tri.vertices``' 2D coordinates, as before.

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
    area: Any = max_area   # (a number; a callable max_area is an area field)
    if max_area is not None and callable(max_area):
        area = None
    try:     # (cached: a small call pays for every Python call the checks make)
        options = checked_options(intersections, algorithm, keep_hull, min_angle, area,
                                  conforming_delaunay, split_boundary, max_steiner, split_segments,
                                  merge_distance)
    except TypeError:      # an unhashable value (or a warning to give): checked anew, and named
        options = MeshOptions.check(intersections=intersections, algorithm=algorithm,
                                    keep_hull=keep_hull, min_angle=min_angle, max_area=area,
                                    conforming_delaunay=conforming_delaunay,
                                    split_boundary=split_boundary, max_steiner=max_steiner,
                                    split_segments=split_segments, merge_distance=merge_distance)
    workers = check_workers(workers)
    if suitable is not None:
        check_size_test(suitable)
    sizing = None
    if size is not None or growth is not None or min_size is not None or area is not max_area:
        sizing, options = checked_sizing(options, size, max_area, growth, min_size)
    smoothing = None
    if smooth is not None:
        from .smoothing import smooth_keyword    # (loaded when asked for)
        smoothing = smooth_keyword(smooth)
    if plane_tolerance is not None:
        plane_tolerance = check_plane_tolerance(plane_tolerance)
    plc = as_plc(vertices, segments, holes, regions)
    plane = None
    if plc.z is not None:     # 3D input: meshed in its plane
        plc, plane = planar_plc(plc, plane_tolerance)
        if plane.axes[2] != 2 and (sizing is not None or smoothing is not None):
            raise CDTError("size fields and smoothing take their coordinates in x, y: 3D input "
                           f"in a plane closer to vertical (normal {plane.normal.tolist()}) is "
                           "meshed in another pair of axes; mesh it without them")
        if options.max_area is not None:    # (a bound on the area in the plane, not the projection's)
            options = options._replace(max_area=options.max_area * plane.area_scale)
        if area is not None:
            area = area * plane.area_scale
    merged = 0
    if options.merge_distance is not None:
        plc, merged = merge_close_points(plc, options.merge_distance)
    tags = None
    if (vertex_markers is not None or segment_markers is not None or vertex_attributes is not None
            or plc.vertex_markers is not None or plc.segment_markers is not None
            or plc.vertex_attributes is not None):
        tags = plc_tags(plc, vertex_markers, segment_markers, vertex_attributes)
    tri = triangulate_plc(plc, options, t0=t0, workers=workers, tags=tags)
    if sizing is not None:
        tri = refine_to_size(tri, sizing, max_area=area,
                             max_steiner=max_steiner, min_angle=min_angle,
                             conforming_delaunay=conforming_delaunay, split_boundary=split_boundary,
                             split_segments=split_segments)
    if suitable is not None:
        tri = refine_until_suitable(tri, suitable, max_area=area, max_steiner=max_steiner,
                                    min_angle=min_angle, conforming_delaunay=conforming_delaunay,
                                    split_boundary=split_boundary, split_segments=split_segments)
    if merged:
        tri.stats["merged_points"] = merged
    if smoothing is not None:
        tri = tri.smooth(smoothing.method, smoothing.iterations,
                         size=None if sizing is None else sizing.size)
    if plane is not None:
        tri.plane, tri.input_w = plane, plc.z
    return tri


def checked_sizing(options: MeshOptions, size: object, max_area: object, growth: object,
                   min_size: object) -> tuple[Sizing, MeshOptions]:
    """The checked sizing keywords, and the options of the first pass: a
    constant size (with no area field) bounds it as a number does, so that
    such a mesh is made in one pass, as with ``max_area``."""
    sizing = check_sizing(size, max_area, growth, min_size)
    assert sizing is not None
    if isinstance(sizing.size, ConstantSize) and sizing.area is None:
        h = max(sizing.size.value, sizing.min_size or 0.0)
        area = SIZE_AREA * h * h
        options = options._replace(max_area=area if options.max_area is None
                                   else min(options.max_area, area))
    return sizing, options


def plc_tags(plc: PLC, vertex_markers: ArrayLike | None = None, segment_markers: ArrayLike | None = None,
             vertex_attributes: ArrayLike | None = None) -> Tags | None:
    """The checked markers and attributes of ``plc`` (the keywords win over the
    PLC's own), with the unrefined triangulation as the base of the attributes'
    interpolation."""
    tags = make_tags(len(plc.vertices), plc.segments,
                     plc.vertex_markers if vertex_markers is None else vertex_markers,
                     plc.segment_markers if segment_markers is None else segment_markers,
                     plc.vertex_attributes if vertex_attributes is None else vertex_attributes)
    if tags is not None and tags.vertex_attributes is not None:
        tags = dataclasses.replace(tags, base=functools.partial(
            unrefined_base, plc.vertices, plc.segments, tags.vertex_attributes))
    return tags


def unrefined_base(vertices: NDArray[np.float64], segments: NDArray[np.int64],
                   attributes: NDArray[np.float64]) -> BaseMesh:
    """The base mesh of the attributes' interpolation at refinement points: the
    constrained Delaunay triangulation of the input ``vertices`` and
    ``segments`` (crossings split, every triangle of the convex hull kept),
    with ``attributes`` (one row per input vertex) carried to its vertices
    (crossing points: along their segment). Its vertices, triangles and
    attributes."""
    base = triangulate(vertices, segments, keep_hull=True, intersections="split")
    base.tags = Tags(segments, vertex_attributes=attributes)
    values = attributes_of(base, base.tags)
    assert values is not None
    return base.vertices, base.triangles, values


def triangulate_plc(plc: PLC, options: MeshOptions, *, t0: float | None = None,
                    workers: int | None = 1, tags: Tags | None = None) -> Triangulation:
    """:func:`triangulate` of a checked PLC with checked options: one call of
    the compiled route, then the result wrapped (or the route's stop raised).
    With many vertices and ``workers`` (checked) not 1, the Delaunay
    triangulation of divide and conquer is built on two threads first
    (:func:`_threaded_store`). ``tags``: the checked markers and attributes to
    keep on the result (:func:`plc_tags`)."""
    t0 = time.perf_counter() if t0 is None else t0
    algorithm, split = options.algorithm, options.intersections == "split"
    # a region seed's max_area refines on its own (Triangle's -a)
    refine, route_options = route_plan(
        options, plc.holes is not None or plc.regions is not None,
        plc.regions is not None and bool((plc.regions[:, 3] > 0).any()))
    if plc.degenerate_rings and not split:
        p, r = plc.degenerate_rings[0]
        raise InvalidGeometryError(
            f"ring {r} of polygon {p} has fewer than three distinct points or zero area "
            f"({len(plc.degenerate_rings)} such rings); use intersections='split' to keep their "
            "points as isolated vertices")
    pts = plc.vertices
    n = len(pts)
    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    order = horizontal = _NO_IDS
    on_threads = algorithm == "divide" and n >= PARALLEL_VERTICES and resolve_workers(workers, 2) >= 2
    if algorithm == "incremental":
        order = brio_order(x, y)
    elif n >= SMALL_SORT:        # numpy's sorts beat the compiled one on many points
        order = lexicographic_order(x, y)
        if algorithm == "divide" and not on_threads:
            horizontal = lexicographic_order(y, -x)
    rings = plc.has_rings
    holes = plc.holes if plc.holes is not None and len(plc.holes) else _NO_SEEDS
    regions = plc.regions if plc.regions is not None and len(plc.regions) else _NO_REGIONS
    segment_ring = plc.segment_ring if rings else _NO_IDS
    ring_polygon = plc.ring_polygon if rings else _NO_IDS
    ring_is_hole = plc.ring_is_hole if rings else _NO_RINGS
    snapped = _NOT_SNAPPED
    while True:   # (a loop, not a helper: a small call pays for every Python call)
        with deferred_interrupt(n):
            prebuilt, order_in = _NO_STORE, order
            if on_threads:
                prebuilt, order_in = _threaded_store(x, y, order, len(plc.segments), snapped,
                                                     route_options)
            status, ints, vertices = cdt_route_packed(
                x, y, plc.segments, segment_ring, ring_polygon, ring_is_hole, holes, regions,
                order_in, horizontal, route_options, snapped, prebuilt)
        if status != ROUTE_NEEDS_SNAP or snapped is not _NOT_SNAPPED:
            break
        # segments cross: snap-round them all (compiled apart: only such inputs pay for
        # it), then run the route again on the snapped segments
        with deferred_interrupt(n):
            status, info, *plan = snap_route(x, y, plc.segments, options.steiner_cap)
        if status != ROUTE_OK:
            _raise_stop(status, info, plc)
        snapped = tuple(plan)
    info, counts = ints[PACK_HEADER:PACK_HEADER + 4], ints[PACK_HEADER + 4:PACK_ARRAYS]
    if status == ROUTE_COLLINEAR:
        tri = _collinear_result(plc, algorithm, t0)
        tri.tags = tags
        return tri
    if status not in (ROUTE_OK, ROUTE_REFINE_LIMIT):
        _raise_stop(status, info, plc)
    seconds = time.perf_counter() - t0
    tri = Triangulation.from_route(ints, vertices, plc, functools.partial(
        _stats, plc, algorithm, counts, int(ints[3]), refine, seconds))
    if tags is not None:
        tri.tags = tags
    if status == ROUTE_REFINE_LIMIT:
        raise RefinementLimitError(
            f"refinement stopped at max_steiner={int(counts[K_REF_LIMIT])} Steiner points with "
            "triangles still breaking the bounds; raise max_steiner (or relax min_angle/max_area); "
            "the partial mesh is in this error's .triangulation", triangulation=tri)
    return tri


def _threaded_store(x, y, order, n_segments, snapped, route_options):
    """``(prebuilt, order)`` for the route: the Delaunay triangulation of its
    vertices built by divide and conquer with the first cut's halves on two
    threads (:func:`cdt_plugin._routes.build_divide_two_threads`: the same
    store one thread makes), on the very coordinates and room the route
    (:func:`~cdt_plugin._core.pipeline.route_points`) gives them. Where the
    route stops before its triangulation (coordinates out of range, all points
    on a line), it builds nothing and the route reports the stop."""
    status, order, xi, yi, inf, cap = route_points_for_threads(
        x, y, order, n_segments, len(snapped[0]), route_options)
    if status != ROUTE_OK:
        return _NO_STORE, order
    n = len(x)
    dup = np.full(n, -1, np.int64)
    tri, twin, cons, ntri = build_divide_two_threads(xi, yi, _NO_WEIGHTS, n, dup, cap, inf,
                                                     np.bool_(True))
    return (tri, twin, cons, dup, np.int64(ntri)), order


def _stats(plc, algorithm, counts, kept, refine, seconds, tri) -> dict:
    """The route's counts by name (``tri``: its result, whose vertices after
    the first ``kept`` are Steiner points; its other arrays are made only
    where a count needs them)."""
    segs = plc.segments
    counts = counts.tolist()     # (Python ints at once: a dict of NumPy scalars one by one cost more)
    zero = []
    if counts[K_ZERO_SEGMENTS]:
        vertex_map = tri.vertex_map
        zero = np.flatnonzero(vertex_map[segs[:, 0]] == vertex_map[segs[:, 1]]).tolist()
    stats = {"algorithm": algorithm, "input_points": len(plc.vertices), "input_segments": len(segs),
             "zero_length_segments": zero, "duplicate_segments": counts[K_DUPLICATE_SEGMENTS],
             "vertices_on_segments": counts[K_ON_SEGMENTS],
             "merged_overlaps": counts[K_MERGED_OVERLAPS],
             "intersection_points": counts[K_INTERSECTIONS], "flips": counts[K_FLIPS],
             "duplicates": counts[K_DUPLICATES], "merged_points": 0, "submerged": 0,
             "vertices": len(tri.vertices),
             "triangles": len(tri.triangles), "steiner": len(tri.vertices) - kept, "seconds": seconds}
    if plc.empty_rings:
        stats["empty_rings"] = list(plc.empty_rings)
    if refine:
        stats.update(refinement_steiner=counts[K_REF_STEINER],
                     refinement_segment_splits=counts[K_REF_SPLITS],
                     refinement_flips=counts[K_REF_FLIPS],
                     frozen_segment_pieces=counts[K_FROZEN],
                     refinement_attempts=counts[K_ATTEMPTS],
                     refinement_deferred=counts[K_DEFERRED],
                     refinement_complete=bool(counts[K_REF_COMPLETE]),
                     below_min_angle=len(tri.below_min_angle))
    return stats


def _raise_stop(status, info, plc):
    """The precise error for a route that stopped."""
    if status in (ROUTE_CROSSING, ROUTE_OVERLAP):
        raise_intersection(status, info, plc)
    if status == ROUTE_RANGE:
        P = plc.vertices
        raise range_error("vertices", P[:, 0], P[:, 1], None, int(info[0]), int(info[1]))
    if status == ROUTE_STEINER_LIMIT:
        s, t, cap, need = int(info[0]) - 1, int(info[1]) - 1, int(info[2]), int(info[3])
        a, b = plc.segments[s]
        if need:      # the snap-rounded crossings, counted before anything was inserted
            raise UnresolvedCrossingError(
                f"the crossing segments need {need} intersection points, more than "
                f"max_steiner={cap} (segments {s} ({_fmt(plc.vertices[a])}-"
                f"{_fmt(plc.vertices[b])}) and {t} cross, among others); raise max_steiner",
                segments=(s, t))
        m = len(plc.segments)
        if cap < m * (m - 1) // 2 + len(plc.vertices):   # fewer than the crossings there can be
            hint = "raise max_steiner"
        else:                                            # more: rounded crossings keep crossing
            hint = ("they cross within rounding of other segments (near-concurrent or nearly "
                    "collinear): move or merge them, e.g. snap the input to a coarser grid")
        raise UnresolvedCrossingError(
            f"max_steiner={cap} intersection points inserted and segments {s} "
            f"({_fmt(plc.vertices[a])}-{_fmt(plc.vertices[b])}) and {t} still cross; {hint}",
            segments=(s, t))
    if status == ROUTE_UNRESOLVED:
        s, nbad = int(info[0]) - 1, int(info[1])
        x, y = (float(v) for v in np.array(info[2:4], np.int64).view(np.float64))
        a, b = plc.segments[s]
        raise UnresolvedCrossingError(
            f"segment {s} ({_fmt(plc.vertices[a])}-{_fmt(plc.vertices[b])}) crosses other segments "
            f"within rounding of each other near ({x!r}, {y!r}): the rounded crossing points would "
            "make its pieces turn back or branch, so the mesh would not contain it as given; move "
            f"or merge the segments that cross there (e.g. snap the input to a coarser grid) "
            f"({nbad} such pieces)", segments=(s,), point=(x, y))
    if status == ROUTE_HOLE_OUTSIDE:
        r = int(info[0])
        p = int(plc.ring_polygon[r])
        raise InvalidGeometryError(
            f"a hole of polygon {p} (ring {r}) lies outside its shell or overlaps another ring; "
            "use intersections='split' to mesh by even-odd depth instead")
    if status == ROUTE_POLYGONS_OVERLAP:
        p, q, a, b = (int(v) for v in info)
        P = plc.vertices
        what = (f"rings of polygon {p} overlap (a ring given twice, or a hole on its shell)"
                if p == q else f"polygons {p} and {q} overlap")
        raise InvalidGeometryError(
            f"{what}: their interiors meet at the edge {_fmt(P[a])}-{_fmt(P[b])} (GEOS calls such "
            "a geometry invalid); use intersections='split' to mesh by even-odd depth instead")
    raise CDTError(f"internal error (status {status}, {info.tolist()}); please report this input")


def raise_intersection(status: int, info: NDArray[np.int64], plc: Any) -> NoReturn:
    """Raise the error for two segments that cross (``ROUTE_CROSSING``) or overlap
    (``ROUTE_OVERLAP``): ``info`` holds their ids plus one, ``plc`` anything with
    ``vertices`` and ``segments`` (a :class:`PLC`; the live triangulation's state)."""
    s, t = int(info[0]) - 1, int(info[1]) - 1
    P = plc.vertices
    a, b = plc.segments[s]
    c, d = plc.segments[t]
    if status == ROUTE_CROSSING:
        # (where split would place it: the exact crossing rounded, at every magnitude)
        px, py = split_crossing(np.ascontiguousarray(P[:, 0]), np.ascontiguousarray(P[:, 1]),
                                int(a), int(b), int(c), int(d))
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


def _collinear_result(plc, algorithm, t0):
    """All vertices on one line (Sec. 2.1): the chain of edges, no triangles."""
    n = len(plc.vertices)
    x, y = plc.vertices[:, 0].copy(), plc.vertices[:, 1].copy()
    order = brio_order(x, y) if algorithm == "incremental" else lexicographic_order(x, y)
    stats = {"algorithm": algorithm, "input_points": n, "input_segments": len(plc.segments)}
    tri = Triangulation.from_collinear(plc.vertices, order, None, np.full(n, -1, np.int64),
                                       np.zeros(n, np.int8), stats, t0)
    tri.segments = np.empty((0, 2), np.int64)
    tri.segment_ids = np.empty(0, np.int64)
    return tri
