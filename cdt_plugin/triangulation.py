"""The result of a triangulation: plain NumPy arrays plus certificates."""
from __future__ import annotations

import functools
import time
from typing import TYPE_CHECKING, Any, Callable, Dict, Optional, Union, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.certify import edge_lifted_values, orientation_signs, submerged_ok
from ._core.mesh import DEAD
from ._core.ordering import lexicographic_order
from ._core.output import (relabel_store, rotate_min_first,
                           store_neighbors, store_triangles)
from ._routes import (DelaunayBuild, build_delaunay, collinear_chain, flip_moved, route_arrays,
                      route_triangles)
from . import hooks, markers, queries
from .errors import (CDTError, InputShapeError, InvalidMeshError, InvertedTriangleError,
                     RefinementLimitError)
from .options import MeshOptions, resolve_algorithm
from .optional import require
from .parallel import resolve_workers
from .planar import Plane
from .plc import PLC
from .types import MeshLike, MeshStore
from .validate import as_points, as_segments, as_triangle_bounds, exact_range

if TYPE_CHECKING:
    from .refining import RefineState
    import matplotlib.tri
    import meshio
    import open3d
    import shapely
    import skfem
    import trimesh
    from matplotlib.axes import Axes

    from .quadratic import QuadraticMesh
    from .report import Report
    from .voronoi import Subdivision, Voronoi

__all__ = ["MeshStore", "Stats", "Triangulation"]

#: A result's counts, or a function of the result that makes them on first access
#: (it takes the result rather than holding it: no reference cycle to collect).
Stats = Union[Dict[str, Any], Callable[["Triangulation"], Dict[str, Any]]]


def _frozen_empty(shape: int | tuple[int, ...]) -> NDArray[np.int64]:
    a = np.empty(shape, np.int64)
    a.flags.writeable = False
    return a


_NO_SEGMENTS = _frozen_empty((0, 2))   # shared defaults: empty and read-only
_NO_IDS = _frozen_empty(0)
# the attributes of a route's result that are made on first access (Triangulation.from_route)
# the markers and attributes made on first access (functools.cached_property)
_MARKED = ("vertex_markers", "segment_markers", "edge_markers", "vertex_attributes")
_LAZY_ATTRIBUTES = frozenset({"neighbors", "vertex_map", "constrained", "regions", "segments",
                              "segment_ids", "steiner", "below_min_angle", "region_attributes"})


class Triangulation:
    """A (weighted, constrained) Delaunay triangulation as NumPy arrays.

    Attributes
    ----------
    vertices : (n, 2) float64
        Output vertices: the distinct input points in order of first appearance.
    triangles : (k, 3) int64
        Vertex indices of each triangle, counter-clockwise.
    neighbors : (k, 3) int64
        ``neighbors[t, j]`` is the triangle across the edge opposite vertex
        ``j`` of triangle ``t``, or -1 on the boundary.
    vertex_map : (n_input,) int64
        Output vertex of each input point (equal for duplicates, -1 for a
        submerged weighted point).
    weights : (n,) float64 or None
        Weights of the output vertices (weighted input only).
    stats : dict
        Counts (``flips``, ``duplicates``, ``submerged``...) and ``seconds``.
    constrained : (k, 3) bool
        Whether the edge opposite vertex ``j`` of triangle ``t`` lies on a segment.
    segments : (s, 2) int64
        Every constrained edge (segment piece) that borders a triangle of
        ``triangles``, once, as output vertex pairs (pieces inside holes or
        outside the domain are dropped with their triangles, as in Triangle).
    segment_ids : (s,) int64
        The input segment each piece comes from.
    regions : (k,) int64
        Input polygon (geometry input) or region seed index of each triangle, -1 if none.
    region_attributes : (k,) float64 or None
        With region seeds: the attribute of each triangle's region (the seed's
        third column; NaN for a triangle no seed painted), as Triangle's
        ``-A`` gives each triangle its regional attribute. None without seeds.
    steiner : (p,) int64
        Output indices of vertices that are not input points (intersection and
        refinement points).
    below_min_angle : (q,) int64
        After refinement with ``min_angle``: the triangles that still miss the
        bound (at small input angles); empty otherwise.
    plane : :class:`~cdt_plugin.planar.Plane` or None
        For 3D input (a planar polygon in any plane): its plane; ``vertices``
        are then the 2D coordinates it was meshed in and :attr:`vertices3d`
        the vertices in 3D. None for 2D input.
    tags : :class:`~cdt_plugin.markers.Tags` or None
        The markers and attributes given with the input (None: none given);
        ``vertex_markers``, ``segment_markers``, ``edge_markers`` and
        ``vertex_attributes`` are derived from it on first access.
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    neighbors: NDArray[np.int64]
    vertex_map: NDArray[np.int64]
    weights: NDArray[np.float64] | None
    constrained: NDArray[np.bool_]
    regions: NDArray[np.int64]
    segments: NDArray[np.int64]
    segment_ids: NDArray[np.int64]
    steiner: NDArray[np.int64]
    below_min_angle: NDArray[np.int64]
    region_attributes: NDArray[np.float64] | None
    tags: markers.Tags | None = None      # (set only when markers or attributes are given)
    plane: Plane | None = None            # (set only for 3D input)
    input_w: NDArray[np.float64] | None = None   # with plane: the input vertices' dropped coordinate
    _stats: Stats
    _refinement: RefineState | None = None     # the store a refined result keeps (refine())
    _edges: NDArray[np.int64] | None
    _mesh: MeshStore | None
    # set by from_mesh only (weighted certificates: the submerged points' check)
    _input_points: NDArray[np.float64]
    _input_weights: NDArray[np.float64] | None
    # set by from_route only, until the lazy arrays are made (__getattr__)
    _lazy: Callable[[], dict[str, Any]]

    def __init__(self, vertices: NDArray[np.float64], triangles: NDArray[np.int64],
                 neighbors: NDArray[np.int64], vertex_map: NDArray[np.int64], stats: Stats,
                 weights: NDArray[np.float64] | None = None, edges: NDArray[np.int64] | None = None,
                 mesh: MeshStore | None = None, constrained: NDArray[np.bool_] | None = None,
                 regions: NDArray[np.int64] | None = None, *, segments: NDArray[np.int64] | None = None,
                 segment_ids: NDArray[np.int64] | None = None, steiner: NDArray[np.int64] | None = None,
                 below_min_angle: NDArray[np.int64] | None = None,
                 region_attributes: NDArray[np.float64] | None = None) -> None:
        self.vertices = vertices
        self.triangles = triangles
        self.neighbors = neighbors
        self.vertex_map = vertex_map
        self.stats = stats
        self.weights = weights
        self.constrained = np.zeros(triangles.shape, bool) if constrained is None else constrained
        self.regions = np.full(len(triangles), -1, np.int64) if regions is None else regions
        self.segments = _NO_SEGMENTS if segments is None else segments
        self.segment_ids = _NO_IDS if segment_ids is None else segment_ids
        self.steiner = _NO_IDS if steiner is None else steiner
        self.below_min_angle = _NO_IDS if below_min_angle is None else below_min_angle
        self.region_attributes = region_attributes
        self._edges = edges
        self._mesh = mesh  # (tri, twin, cons, ntri, inf) half-edge store in output ids

    # ---------------------------------------------------------------- builders
    @classmethod
    def from_build(cls, pts: NDArray[np.float64], w_in: NDArray[np.float64] | None,
                   build: DelaunayBuild, t0: float) -> Triangulation:
        """Wrap a Delaunay triangulation of ``pts`` (:func:`~cdt_plugin._routes.build_delaunay`)."""
        if build.tri is None or build.twin is None or build.cons is None:
            return cls.from_collinear(pts, build.order, w_in, build.dup_of, build.submerged, build.stats, t0)
        return cls.from_mesh(pts, w_in, build.tri, build.twin, build.cons, build.ntri, build.order,
                             build.dup_of, build.submerged, build.stats, t0)

    @classmethod
    def from_mesh(cls, pts: NDArray[np.float64], w_in: NDArray[np.float64] | None,
                  tri: NDArray[np.int32], twin: NDArray[np.int32], cons: NDArray[np.int32], ntri: int,
                  ids: NDArray[np.int64], dup_of: NDArray[np.int64], submerged: NDArray[np.int8],
                  stats: dict[str, Any], t0: float) -> Triangulation:
        """Compact a finished half-edge store into output arrays. Mesh vertex ``i``
        is input point ``ids[i]``; ``len(ids)`` is the infinite vertex."""
        n = len(pts)
        vertex_map, kept, duplicates = _vertex_map(n, dup_of, submerged)
        nv = n if kept is None else len(kept)
        # in place (the store is ours): negative entries index from the end,
        # -2 (DEAD) and -1 map to themselves
        remap = np.empty(len(ids) + 3, tri.dtype)
        remap[: len(ids)] = ids if kept is None else vertex_map[ids]   # (no copy of a large map)
        remap[len(ids)] = nv  # the infinite vertex
        remap[-2] = DEAD
        remap[-1] = -1
        relabel_store(tri, ntri, remap)
        mesh = (tri[: 3 * ntri], twin[: 3 * ntri], cons[: 3 * ntri], ntri, nv)
        out = cls.__new__(cls)
        out.vertices = _kept_rows(pts, kept)
        out.triangles = store_triangles(tri, ntri, nv)
        out.vertex_map = vertex_map
        out.weights = None if w_in is None else _kept_rows(w_in, kept)
        # the counts are made on first access: most callers never look
        out._stats = functools.partial(_finished_stats, stats, n, duplicates, time.perf_counter() - t0)
        out.segments, out.segment_ids, out.steiner = _NO_SEGMENTS, _NO_IDS, _NO_IDS
        out.below_min_angle, out.region_attributes = _NO_IDS, None
        out._edges = None
        out._mesh = mesh
        # neighbours, flags and regions on first access: at a million points they
        # would be as large as the triangles, and many callers never look
        out._lazy = functools.partial(_mesh_attributes, mesh)
        out._input_points, out._input_weights = pts, w_in
        return out

    @classmethod
    def from_collinear(cls, pts: NDArray[np.float64], order: NDArray[np.int64],
                       w_in: NDArray[np.float64] | None, dup_of: NDArray[np.int64],
                       submerged: NDArray[np.int8], stats: dict[str, Any], t0: float) -> Triangulation:
        """All points on one line (Sec. 2.1): no triangles, the chain of edges."""
        n = len(pts)
        line = collinear_chain(pts, order, w_in, dup_of, submerged)
        vertex_map, kept, duplicates = _vertex_map(n, dup_of, submerged)
        edges = np.column_stack([vertex_map[line[:-1]], vertex_map[line[1:]]]).astype(np.int64)
        empty = np.empty((0, 3), np.int64)
        stats["collinear"] = True
        weights = None if w_in is None else _kept_rows(w_in, kept)
        return cls(_kept_rows(pts, kept), empty, empty.copy(), vertex_map,
                   functools.partial(_finished_stats, stats, n, duplicates, time.perf_counter() - t0),
                   weights, edges=edges.reshape(-1, 2))

    @classmethod
    def from_route(cls, ints: NDArray[np.int64], vertices: NDArray[np.float64], plc: PLC,
                   stats: dict[str, Any] | Callable[[Triangulation], dict[str, Any]]) -> Triangulation:
        """Wrap the output of the compiled CDT route (``ints``: its integer
        arrays in one, see ``pipeline.cdt_route_packed``; input vertices,
        distinct and in input order, then the Steiner vertices). ``triangles``
        is a view made now; the other arrays (``neighbors``, ``constrained``,
        ``segments``...) on first access, all at once: a small call costs a
        few microseconds, and most callers use the triangles only. ``stats``
        may be a function of the result that makes the dict on first access."""
        tri = cls.__new__(cls)
        tri.vertices = vertices
        tri.triangles = route_triangles(ints)
        tri.weights = None
        tri._stats = stats
        tri._edges = None
        tri._mesh = None
        tri._lazy = functools.partial(route_arrays, ints, vertices,
                                      None if plc.regions is None else plc.regions[:, 2])
        return tri

    @classmethod
    def from_triangles(cls, vertices: ArrayLike, triangles: ArrayLike,
                       segments: ArrayLike | None = None, *,
                       vertex_markers: ArrayLike | None = None, segment_markers: ArrayLike | None = None,
                       vertex_attributes: ArrayLike | None = None) -> Triangulation:
        """A triangulation given as vertices and index triangles (a mesh made
        elsewhere, a TIN read back from a file), for queries, certificates and
        refinement (:meth:`refine`).

        Triangles may turn either way (clockwise ones are turned round).
        ``segments``: (m, 2) vertex pairs that must stay edges when the mesh is
        refined (``tri.segments``, ``tri.segment_ids`` their rows, repeats
        dropped; the mesh's boundary stays too). ``vertex_markers``,
        ``segment_markers`` (one per row of ``segments``) and
        ``vertex_attributes`` as for :func:`cdt_plugin.triangulate`: kept in
        ``tags`` and carried by refinement. Raises
        :class:`InputShapeError` for bad shapes or indices,
        :class:`InvertedTriangleError` for a triangle without area,
        :class:`CDTError` for repeated vertices, and :class:`InvalidMeshError`
        for triangles that overlap along an edge (an edge in more than two
        triangles, or twice in one direction) or a segment that is not an edge
        of the triangles. (Triangles that overlap otherwise are found by
        :meth:`refine`, which names them.)

        >>> import cdt_plugin
        >>> tri = cdt_plugin.Triangulation.from_triangles([[0, 0], [1, 0], [1, 1], [0, 1]],
        ...                                               [[0, 1, 2], [0, 3, 2]])
        >>> tri.triangles.tolist(), tri.neighbors.tolist()
        ([[0, 1, 2], [0, 2, 3]], [[-1, 1, -1], [-1, -1, 0]])
        """
        V = as_points(vertices, "vertices")
        n = len(V)
        raw = np.asarray(triangles)
        if raw.size and raw.dtype.kind not in "iu":
            raise InputShapeError(f"triangles must be integer vertex indices, got {raw.dtype}")
        T = raw.astype(np.int64).reshape(-1, 3) if raw.size else np.empty((0, 3), np.int64)
        if raw.size and (raw.ndim != 2 or raw.shape[1] != 3):
            raise InputShapeError(f"triangles must have shape (k, 3), got {raw.shape}")
        bad = np.flatnonzero(((T < 0) | (T >= n)).any(axis=1))
        if len(bad):
            raise InputShapeError(f"triangle {int(bad[0])} {T[bad[0]].tolist()} names a vertex outside 0..{n - 1}")
        _raise_repeated_vertex(V)
        x, y, _, _ = exact_range(V[:, 0].copy(), V[:, 1].copy(), None, "vertices")
        signs = orientation_signs(x, y, np.ascontiguousarray(T))
        flat = np.flatnonzero(signs == 0)
        if len(flat):
            t = int(flat[0])
            raise InvertedTriangleError(f"triangle {t} {T[t].tolist()} has no area (its corners are collinear)")
        T = np.where((signs < 0)[:, None], T[:, [0, 2, 1]], T)
        T = np.ascontiguousarray(T)
        from ._core.remesh import triangle_neighbors    # (loaded on first use, with refining's kernels)
        nb, t, u = triangle_neighbors(T, n)
        if t >= 0:
            raise InvalidMeshError(
                f"triangles {t} {T[t].tolist()} and {u} {T[u].tolist()} overlap: their edge "
                f"{[int(v) for v in T[t] if v in T[u]]} lies on the same side of both "
                "(an edge in more than two triangles, or two triangles folded over)",
                triangles=(t, u))
        rotate_min_first(T, nb)
        out = cls(V, T, nb, np.arange(n, dtype=np.int64), {"triangles": len(T)})
        segs = out.segments
        if segments is not None:
            segs = as_segments(segments, n)
            out.segments, out.segment_ids, out.constrained = _segments_of_mesh(segs, T)
        if vertex_markers is not None or segment_markers is not None or vertex_attributes is not None:
            out.tags = markers.make_tags(n, segs, vertex_markers, segment_markers, vertex_attributes)
        return out

    def refine(self, *, min_angle: float | None = None, max_area: float | ArrayLike | Callable | None = None,
               conforming_delaunay: bool = False, split_boundary: bool = True,
               split_segments: bool = True, max_steiner: int | None = None,
               size: Any = None, growth: float | None = None,
               min_size: float | None = None) -> Triangulation:
        """This mesh refined (Triangle's ``-r``): Steiner points added until the
        bounds hold, every vertex and segment kept.

        The domain is the union of the triangles (holes and pockets stay
        empty); its boundary edges and ``segments`` are kept as segments (split
        into pieces by the Steiner points on them, unless ``split_boundary`` or
        ``split_segments`` forbid it). The options are those of
        :func:`cdt_plugin.triangulate`, but ``max_area`` may also be an array
        with one bound per triangle of ``triangles`` (Triangle's ``.area``
        file; a value <= 0 or NaN: no bound for that triangle). Bounds go by
        location: no triangle of the result is larger than the bound of the
        triangle of this mesh that holds its centroid (decided exactly; where
        refinement flips an edge between triangles with different bounds,
        Triangle averages the two instead). The mesh is made constrained
        Delaunay first (flips that cross no segment or boundary edge), as
        refinement needs, and the result is constrained Delaunay.

        The result's ``vertices`` are this mesh's, in the same order, then the
        new Steiner points; ``segment_ids`` name the original segments (those
        of ``triangulate``'s input, or of :meth:`from_triangles`; -1 for the
        boundary's pieces); ``regions`` and ``region_attributes`` follow each
        triangle's parent; ``below_min_angle`` and ``stats`` as
        ``triangulate`` gives them; markers and attributes (``tags``) carried,
        a new point's attributes interpolated in this mesh (as Triangle's
        ``-r``). The refined mesh keeps its internal
        store: refining it again goes on from there, without reading the mesh
        anew. Raises :class:`InvalidMeshError` naming a triangle that
        overlaps others, :class:`RefinementLimitError` (with the partial
        mesh) at ``max_steiner``.

        ``size``, ``growth``, ``min_size`` and a callable ``max_area`` are
        the size fields of :func:`cdt_plugin.triangulate` (refined in rounds,
        :mod:`cdt_plugin.grading`); ``max_area`` is then a number or a callable.

        >>> import cdt_plugin
        >>> tri = cdt_plugin.Triangulation.from_triangles([[0, 0], [2, 0], [2, 1], [0, 1]],
        ...                                               [[0, 1, 2], [0, 2, 3]])
        >>> fine = tri.refine(max_area=[0.05, -1])   # the first triangle only
        >>> fine.vertices[:4].tolist() == tri.vertices.tolist(), len(fine.triangles) > 2
        (True, True)
        """
        if size is not None or growth is not None or min_size is not None or callable(max_area):
            from .grading import refine_sized    # (loaded on first use: import cdt_plugin stays fast)
            return refine_sized(self, min_angle=min_angle, max_area=max_area,
                                conforming_delaunay=conforming_delaunay, split_boundary=split_boundary,
                                split_segments=split_segments, max_steiner=max_steiner, size=size,
                                growth=growth, min_size=min_size)
        per_triangle = max_area is not None and np.ndim(max_area) > 0
        options = MeshOptions.check(min_angle=min_angle,
                                    max_area=None if per_triangle else cast(Optional[float], max_area),
                                    conforming_delaunay=conforming_delaunay,
                                    split_boundary=split_boundary, max_steiner=max_steiner,
                                    split_segments=split_segments)
        bounds = as_triangle_bounds(cast(ArrayLike, max_area), len(self.triangles)) if per_triangle else None
        from .refining import refine_mesh      # (loaded on first use: import cdt_plugin stays fast)
        r = refine_mesh(self, options, bounds, self._refinement)
        out = Triangulation(
            r.vertices, r.triangles, r.neighbors, self.vertex_map, r.stats, constrained=r.constrained,
            regions=self.regions[r.parents], segments=r.segments, segment_ids=r.segment_ids,
            steiner=np.concatenate([self.steiner, np.arange(len(self.vertices), len(r.vertices))]),
            below_min_angle=r.below_min_angle,
            region_attributes=None if self.region_attributes is None else self.region_attributes[r.parents])
        out._refinement = r.state
        out.plane, out.input_w = self.plane, self.input_w
        out.tags = markers.refined_tags(self.tags, self, lambda: self.vertex_attributes)
        if not r.complete:
            raise RefinementLimitError(
                f"refinement stopped at max_steiner={r.stats['refinement_limit']} Steiner points "
                "with triangles still breaking the bounds; raise max_steiner (or relax "
                "min_angle/max_area); the partial mesh is in this error's .triangulation",
                triangulation=out)
        return out

    def smooth(self, method: str = "odt", iterations: int = 10, *, size: Any = None,
               on_segments: bool = True, min_angle: float | None = None) -> Triangulation:
        """This mesh smoothed: its Steiner points moved to improve the shape of
        the triangles while keeping their sizes (see :mod:`cdt_plugin.smoothing`).

        ``method``: ``"odt"`` (optimal Delaunay triangulation: each vertex to the
        area-weighted mean of its triangles' circumcentres) or ``"lloyd"`` (to
        the centroid of its Voronoi cell); ``iterations`` sweeps over the
        vertices, each followed by flips that make the mesh constrained Delaunay
        again. Input vertices never move; a Steiner point on a segment or on the
        boundary slides along it (``on_segments=False``: stays). ``size``: the
        target edge length that weights the moves (density ``1 / size**2``):
        None for each vertex's own (a graded mesh stays graded), a number, or a
        callable ``size(x, y)`` over arrays. No triangle turns over, the
        smallest angle never falls (with ``min_angle``: never below that bound),
        the mean radius ratio does not fall through the moves. Same vertices in
        the same order, same segments, regions, markers and attributes;
        ``stats["smoothing"]`` compares the quality before and after.

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0], [3, 0], [3, 2], [0, 2]], min_angle=30, max_area=0.05)
        >>> smooth = tri.smooth("lloyd", 5)
        >>> smooth.is_delaunay(), len(smooth.vertices) == len(tri.vertices)
        (True, True)
        >>> s = smooth.stats["smoothing"]
        >>> s["after"]["mean_radius_ratio"] > s["before"]["mean_radius_ratio"]
        True
        """
        from .smoothing import smooth      # (loaded on first use, with its kernels)
        return smooth(self, method, iterations, size=size, on_segments=on_segments, min_angle=min_angle)

    def __getattr__(self, name: str) -> Any:
        # only called when ``name`` is not set: the route's arrays made on first access
        lazy = self.__dict__.get("_lazy")
        if lazy is None or name not in _LAZY_ATTRIBUTES:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        del self.__dict__["_lazy"]
        for key, value in lazy().items():
            self.__dict__.setdefault(key, value)      # (keep what was assigned meanwhile)
        return self.__dict__[name]

    @property
    def stats(self) -> dict[str, Any]:
        """Counts (``flips``, ``duplicates``, ``steiner``...) and ``seconds``."""
        if callable(self._stats):        # made on first access: most callers never look
            self._stats = self._stats(self)
        return self._stats

    @stats.setter
    def stats(self, value: Stats) -> None:
        self._stats = value

    # ------------------------------------------------------------------ views
    @property
    def edges(self) -> NDArray[np.int64]:
        """(e, 2) vertex indices of every edge, each listed once."""
        if self._edges is None:
            t, nb = self.triangles, self.neighbors
            k = np.repeat(np.arange(len(t)), 3)
            j = np.tile(np.arange(3), len(t))
            keep = (nb[k, j] < 0) | (k < nb[k, j])
            self._edges = np.column_stack([t[k, (j + 1) % 3], t[k, (j + 2) % 3]])[keep]
        return self._edges

    # ------------------------------------------- markers and attributes (lazy)
    @functools.cached_property
    def vertex_markers(self) -> NDArray[np.int64]:
        """(n,) int64 boundary marker of each vertex, Triangle's rules: its input
        marker if nonzero, else the nonzero marker of a segment it lies on, else
        1 on the boundary, else 0 (see :mod:`cdt_plugin.markers`)."""
        return markers.vertex_markers(self, self.tags)

    @functools.cached_property
    def segment_markers(self) -> NDArray[np.int64]:
        """(s,) int64 marker of each row of ``segments``: its input segment's
        marker if nonzero, else 1 on the boundary, else 0."""
        return markers.segment_markers(self, self.tags)

    @functools.cached_property
    def edge_markers(self) -> NDArray[np.int64]:
        """(e,) int64 marker of each row of ``edges``: the marker of the segment
        piece it is, else 1 on the boundary, else 0."""
        return markers.edge_markers(self, self.tags)

    @functools.cached_property
    def vertex_attributes(self) -> NDArray[np.float64] | None:
        """(n, k) float64 attributes of every vertex, or None when none were
        given: input vertices keep theirs, Steiner points get the linear
        interpolation on their segment, or on the triangle of the unrefined
        mesh that holds them (see :mod:`cdt_plugin.markers`)."""
        return markers.vertex_attributes(self, self.tags)

    def quadratic(self) -> QuadraticMesh:
        """Second-order elements (Triangle's ``-o2``): the six-node triangles of
        this triangulation, node ``3 + i`` of each at the midpoint of the edge
        opposite corner ``i``, one midpoint per row of ``edges`` after the
        vertices, shared by the edge's triangles; a midpoint has its edge's
        marker and the mean of its ends' attributes
        (see :class:`cdt_plugin.quadratic.QuadraticMesh`).

        >>> import cdt_plugin
        >>> mesh = cdt_plugin.triangulate([[0, 0], [2, 0], [0, 2]], [[0, 1], [1, 2], [2, 0]]).quadratic()
        >>> mesh.triangles.tolist(), mesh.vertices[3:].tolist()
        ([[0, 1, 2, 3, 4, 5]], [[1.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
        """
        from .quadratic import quadratic      # (loaded on first use)
        return quadratic(self, self.vertex_markers, self.edge_markers, self.vertex_attributes)

    @property
    def vertices3d(self) -> NDArray[np.float64]:
        """(n, 3) float64: every vertex in 3D. For 3D input (:attr:`plane`) the
        input vertices exactly as given (a merged duplicate as its first
        occurrence), the Steiner points on the plane (the coordinate the
        projection dropped from the plane's equation); for 2D input z = 0.

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0, 0], [2, 0, 2], [2, 2, 2], [0, 2, 0]],
        ...                              [[0, 1], [1, 2], [2, 3], [3, 0]], max_area=0.5)
        >>> V = tri.vertices3d
        >>> bool(np.allclose(V[:, 2], V[:, 0])), len(V) > 4    # the plane z = x
        (True, True)
        """
        if self.plane is None:
            return np.column_stack([self.vertices, np.zeros(len(self.vertices))])
        return self.plane.lift(self.vertices, self.vertex_map, self.input_w)

    @property
    def submerged(self) -> NDArray[np.intp]:
        """Input indices of weighted points that are in no triangle."""
        return np.flatnonzero(self.vertex_map < 0)

    def __repr__(self) -> str:
        return (f"Triangulation({len(self.vertices)} vertices, {len(self.triangles)} triangles, "
                f"{len(self.edges)} edges)")

    # ------------------------------------------------ outputs (lazy adapters)
    def to_trimesh(self, z: float | None = None, **kwargs: Any) -> trimesh.Trimesh:
        """This triangulation as a flat ``trimesh.Trimesh`` in its plane (3D
        input; z = 0 for 2D input) or at height ``z``
        (see :func:`cdt_plugin.adapters.trimesh.to_trimesh`; needs trimesh)."""
        return hooks.to_trimesh(self, z=z, **kwargs)

    def to_open3d(self, z: ArrayLike | None = None) -> open3d.geometry.TriangleMesh:
        """This triangulation as an ``open3d.geometry.TriangleMesh`` (needs Open3D);
        ``z``: one height for all vertices or one per vertex."""
        return hooks.to_open3d(self, z=z)

    def to_shapely(self) -> shapely.GeometryCollection:
        """The triangles as a shapely GeometryCollection of Polygons, in the form
        ``shapely.constrained_delaunay_triangles`` returns (needs shapely)."""
        return hooks.to_shapely(self)

    def to_matplotlib(self) -> matplotlib.tri.Triangulation:
        """This triangulation as a ``matplotlib.tri.Triangulation`` (needs
        matplotlib, the ``plot`` extra): x and y are the columns of
        ``self.vertices``, copied (unreferenced vertices included, so indices agree) and
        ``triangles`` is ``self.triangles``, counter-clockwise; ready for
        ``triplot``, ``tripcolor``, ``tricontour`` or a ``TriInterpolator``.

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
        >>> mtri = tri.to_matplotlib()
        >>> mtri.x.tolist(), mtri.triangles.shape
        ([0.0, 2.0, 2.0, 0.0], (2, 3))
        """
        mtri = require("matplotlib.tri", "Triangulation.to_matplotlib")
        if len(self.triangles) == 0:
            raise CDTError(f"{self!r} has no triangles (all-collinear input, or nothing "
                           "inside the domain): matplotlib.tri.Triangulation needs at least one")
        x, y = self.vertices.T.copy()          # a copy: matplotlib keeps what it is given
        return mtri.Triangulation(x, y, self.triangles)

    def to_meshio(self, quadratic: bool = False) -> meshio.Mesh:
        """This triangulation as a ``meshio.Mesh`` for finite-element codes (needs
        meshio): ``triangle`` cells (``triangle6`` with ``quadratic``) and the
        segments as ``line`` cells (``line3``), tagged as gmsh and meshio users
        expect (``gmsh:physical``: segment markers, region attributes or ids), ready
        for ``meshio.write`` to ``.msh`` (``file_format="gmsh"`` or ``"gmsh22"``),
        ``.vtu`` or ``.xdmf`` (see :func:`cdt_plugin.fem.to_meshio`).

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [0, 2]], [[0, 1], [1, 2], [2, 0]])
        >>> [(block.type, len(block.data)) for block in tri.to_meshio().cells]
        [('triangle', 1), ('line', 3)]
        """
        from .fem import to_meshio            # (loaded on first use)
        return to_meshio(self, quadratic)

    def to_skfem(self, quadratic: bool = False, *, boundaries: Any = None,
                 subdomains: Any = None) -> skfem.Mesh:
        """This triangulation as a scikit-fem ``MeshTri`` (``MeshTri2`` with
        ``quadratic``; needs scikit-fem) with boundaries named by the edge markers
        and subdomains by the regions (see :func:`cdt_plugin.fem.to_skfem`).

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [0, 2]], [[0, 1], [1, 2], [2, 0]],
        ...                              segment_markers=[4, 0, 0])
        >>> mesh = tri.to_skfem(boundaries={"bottom": 4, "rest": 1})
        >>> mesh.boundaries["bottom"].tolist(), len(mesh.boundaries["rest"])
        ([0], 2)
        """
        from .fem import to_skfem
        return to_skfem(self, quadratic, boundaries=boundaries, subdomains=subdomains)

    # ------------------------------------------------------- report and plots
    def report(self, against: MeshLike | None = None, **kwargs: Any) -> Report:
        """Quality report (angles, circumdisks, certificate), optionally side by side
        with another triangulation of the same input (see :func:`cdt_plugin.report.report`)."""
        from .report import report     # (loaded on first use: `import cdt_plugin` stays as fast)
        return report(self, against, **kwargs)

    def plot(self, ax: Axes | None = None, **kwargs: Any) -> Axes:
        """Draw the triangles, segments in bold and the worst triangles with their
        circumcircles on a matplotlib Axes (see :func:`cdt_plugin.plot.plot`)."""
        from .plot import plot
        return plot(self, ax=ax, **kwargs)

    # ----------------------------------------------------------- certificates
    def _edge_signs(self) -> np.ndarray:
        """(triangle, j, sign) for every interior edge that is not a segment."""
        v = self.vertices
        x, y, w, _ = exact_range(v[:, 0].copy(), v[:, 1].copy(), self.weights, "vertices")
        s = edge_lifted_values(x, y, w if w is not None else np.zeros(len(v)), w is not None,
                               self.triangles, self.neighbors)
        return s[~self.constrained[s[:, 0], s[:, 1]]]

    def non_delaunay_edges(self) -> NDArray[np.int64]:
        """Interior edges that are not locally (weighted) Delaunay, as vertex pairs."""
        s = self._edge_signs()
        bad = s[s[:, 2] > 0]
        t = self.triangles
        return np.column_stack([t[bad[:, 0], (bad[:, 1] + 1) % 3], t[bad[:, 0], (bad[:, 1] + 2) % 3]])

    def is_delaunay(self) -> bool:
        """Delaunay Lemma (2.3) check, exact, in linear time: every interior edge is
        locally Delaunay (Constrained Delaunay Lemma 2.14: or a segment). For weighted input, every edge is locally regular and
        every submerged point lies on or above the lifted triangulation (Sec. 2.8).
        """
        if len(self.non_delaunay_edges()):
            return False
        if self.weights is not None and len(self.triangles) and len(self.submerged):
            return bool(self._submerged_ok().all())
        return True

    def _submerged_ok(self) -> np.ndarray:
        v = self.vertices
        s = self.submerged
        pts, w, weights = self._input_points, self._input_weights, self.weights
        assert w is not None and weights is not None, "called for weighted results only"
        _, _, _, shift = exact_range(pts[:, 0], pts[:, 1], w)   # one scale for both sets
        f = 2.0 ** shift
        return submerged_ok(v[:, 0] * f, v[:, 1] * f, weights * f * f, self.triangles,
                            self.neighbors, pts[s, 0] * f, pts[s, 1] * f, w[s] * f * f)

    def is_unique(self) -> bool:
        """Whether this is the only Delaunay triangulation of its points
        (Theorem 2.11): no interior edge has four exactly cocircular vertices
        (lifted-coplanar for weighted points)."""
        return not bool((self._edge_signs()[:, 2] == 0).any())

    # ---------------------------------------------------------------- duals
    def delaunay_subdivision(self) -> Subdivision:
        """The faces of the Delaunay subdivision (Fig. 2.3c): the triangles whose
        shared edges are exact cocircular ties (lifted-coplanar for weights)
        fused into convex polygons of vertex ids, counter-clockwise. A triangle
        where the triangulation is unique; on a square grid, unit squares.
        Raises :class:`NotDelaunayError` for a constrained or non-Delaunay
        triangulation (see :class:`cdt_plugin.voronoi.Subdivision`).

        >>> import cdt_plugin
        >>> cdt_plugin.delaunay([[0, 0], [1, 0], [1, 1], [0, 1], [3, 0]]).delaunay_subdivision().tolist()
        [[0, 1, 2, 3], [1, 4, 2]]
        """
        from .voronoi import delaunay_subdivision   # (loaded with its kernels on first use)
        return delaunay_subdivision(self)

    def voronoi(self, clip: Any = None, *, workers: int | None = None) -> Voronoi:
        """The Voronoi diagram of the vertices, dual to this Delaunay
        triangulation (Sec. 2.2), or their power diagram if it is weighted
        (Sec. 2.8): one Voronoi vertex per face of the Delaunay subdivision,
        each vertex's cell as a counter-clockwise ring of them (-1 where an
        unbounded cell opens to infinity), ridges with the sites they separate.

        ``clip``: None, a box ``(xmin, ymin, xmax, ymax)`` or a shapely polygon
        (needs shapely): every cell cut to it (:meth:`Voronoi.cell`,
        :meth:`Voronoi.to_shapely`). Raises :class:`NotDelaunayError` for a
        constrained or non-Delaunay triangulation, :class:`CollinearPointsError`
        without triangles, :class:`ClipRegionError` for a malformed clip or
        one that contains none of the points (see :class:`cdt_plugin.voronoi.Voronoi`).
        ``workers``: threads for large triangulations (default: every core from
        100,000 triangles; the result is the same for any number).

        >>> import cdt_plugin
        >>> vor = cdt_plugin.delaunay([[0, 0], [2, 0], [0, 2], [2, 2], [1, 1.5]]).voronoi(clip=(0, 0, 2, 2))
        >>> vor
        Voronoi(Voronoi diagram: 5 sites, 4 vertices, 4 unbounded cells, clipped)
        >>> vor.vertices.round(4).tolist()
        [[0.125, 1.0], [1.875, 1.0], [1.0, 0.4167], [1.0, 2.75]]
        >>> vor.regions[4]                  # the centre point's cell: four Voronoi vertices
        [0, 2, 1, 3]
        >>> vor.cell(4).round(4).tolist()   # cut to the box
        [[1.375, 2.0], [0.625, 2.0], [0.125, 1.0], [1.0, 0.4167], [1.875, 1.0]]
        """
        from .voronoi import voronoi                 # (loaded with its kernels on first use)
        return voronoi(self, clip, workers=workers)

    # -------------------------------------------------------- moving vertices
    # -------------------------------------------------------------- queries
    def locate(self, points: ArrayLike) -> NDArray[np.int64]:
        """The triangle (row of ``triangles``) that holds each point, -1 outside
        the domain (exact predicates).

        A point on an edge or a vertex gets the smallest id among the triangles
        that hold it, whatever the order of the queries. Queries are sorted along
        a Hilbert curve and each walk starts at the previous hit, so a million
        points cost a few walks' steps each.

        >>> import cdt_plugin
        >>> tri = cdt_plugin.delaunay([[0, 0], [2, 0], [0, 2], [2, 2]])
        >>> tri.locate([[0.5, 0.2], [1, 1], [3, 3]]).tolist()     # (1, 1): on the diagonal of 0 and 1
        [1, 0, -1]
        """
        return queries.locate(self, points)

    def interpolate(self, values: ArrayLike, points: ArrayLike, method: str = "linear") -> NDArray[np.float64]:
        """Interpolate vertex ``values`` ((n,) or (n, k), one row per vertex) at
        ``points``: NaN outside the domain.

        ``method="linear"``: the linear interpolant on the triangle that holds the
        point. ``"natural"``: Sibson's natural neighbour interpolation (the share
        of each vertex's Voronoi cell the point's new cell would take; smooth away
        from the vertices, weights non-negative, summing to 1, reproducing linear
        functions). Its neighbourhood does not cross segments, the domain's
        boundary, or edges that are not locally Delaunay; on a segment or the
        boundary the linear interpolant along that edge applies, and so it does
        where a segment hides part of the point's neighbourhood, and where
        rounding spoils the coordinates (slivers, points nearly on a line: a
        :class:`PrecisionWarning` says how many). Both give a vertex's own value
        at the vertex.

        >>> import numpy as np, cdt_plugin
        >>> pts = np.array([[0, 0], [4, 0], [0, 4], [4, 4], [1, 2]], float)
        >>> tri = cdt_plugin.delaunay(pts)
        >>> plane = 1 + 2 * pts[:, 0] - pts[:, 1]
        >>> tri.interpolate(plane, [[2, 1], [1, 2], [9, 9]], method="natural").round(12).tolist()
        [4.0, 1.0, nan]
        """
        return queries.interpolate(self, values, points, method)

    def move_vertices(self, new_vertices: ArrayLike, *, rebuild: bool = True) -> int:
        """Move the vertices to ``new_vertices`` (same shape as ``vertices``) and
        restore the Delaunay property with flips (Sec. 2.5, the simulation case).

        A hull that lost its convexity is repaired by flips too. If a move
        inverts a triangle, flips cannot repair the mesh: with ``rebuild=True`` the triangulation is rebuilt from
        scratch (``stats["rebuilt"]``), otherwise :class:`InvertedTriangleError`
        is raised. Weighted triangulations are always rebuilt. Returns the number
        of flips (0 after a rebuild).

        >>> import numpy as np, cdt_plugin
        >>> tri = cdt_plugin.delaunay([[0, 0], [2, 0], [0, 2], [2, 2.1]])
        >>> tri.move_vertices([[0, 0], [2, 0], [0, 2], [2, 1.9]])
        1
        >>> tri.is_delaunay()
        True
        """
        t0 = time.perf_counter()
        new = as_points(new_vertices, "new_vertices")
        if self.constrained.any() or len(self.segments):
            raise CDTError("move_vertices supports unconstrained Delaunay triangulations only")
        if new.shape != self.vertices.shape:
            raise InputShapeError(f"new_vertices must have shape {self.vertices.shape}, got {new.shape}")
        flips = defect = -1
        if self._mesh is not None and self.weights is None:
            (tri, twin, cons, ntri, inf), flips, defect = flip_moved(self._mesh, new)
        for derived in ("_walk", "_blocked", *_MARKED):   # the queries' meshes and markers follow
            self.__dict__.pop(derived, None)
        if flips >= 0 and defect < 0:
            self._mesh = (tri, twin, cons, ntri, inf)
            self.__dict__.pop("_lazy", None)     # every array is made here
            self.triangles = store_triangles(tri, ntri, inf)
            self.neighbors = store_neighbors(tri, twin, ntri, inf)
            # hull flips can change the number of triangles: the per-triangle arrays follow
            self.constrained = np.zeros(self.triangles.shape, bool)
            self.regions = np.full(len(self.triangles), -1, np.int64)
            self.vertices = new
            self._edges = None
            self.stats.update(move_flips=flips, rebuilt=False)
        else:
            if not rebuild:
                raise InvertedTriangleError(
                    "moving the vertices inverts triangle "
                    f"{_triangle_name(tri, defect, new) if defect >= 0 else '(after flips)'}; "
                    "pass rebuild=True to retriangulate")
            weighted = self.weights is not None
            fresh = Triangulation.from_build(new, self.weights, build_delaunay(
                new, self.weights, resolve_algorithm("auto", weighted), 0, resolve_workers(None, 2)), t0)
            old_map = self.vertex_map
            for name in _LAZY_ATTRIBUTES:        # the fresh result's are made on first access
                self.__dict__.pop(name, None)
            self.__dict__.update(fresh.__dict__)
            self.vertex_map = np.where(old_map >= 0, fresh.vertex_map[np.maximum(old_map, 0)], -1)
            self.stats.update(move_flips=0, rebuilt=True)
            flips = 0
        self.stats["move_seconds"] = time.perf_counter() - t0
        return flips


def _raise_repeated_vertex(V: NDArray[np.float64]) -> None:
    """:class:`CDTError` naming the first vertex that repeats an earlier one (a
    sort, which ``np.unique(V, axis=0)`` was four times slower at, and
    ``np.lexsort`` four times slower than :func:`._core.ordering.lexicographic_order`)."""
    order = lexicographic_order(V[:, 0].copy(), V[:, 1].copy())   # (a repeat after its first)
    Vo = V[order]
    same = np.r_[False, (Vo[1:] == Vo[:-1]).all(axis=1)]
    if not same.any():
        return
    head = order[np.maximum.accumulate(np.where(same, 0, np.arange(len(V))))]
    k = np.flatnonzero(same)[np.argmin(order[same])]
    i = int(order[k])
    raise CDTError(f"vertices {int(head[k])} and {i} are the same point {V[i].tolist()}")


def _segments_of_mesh(segs: NDArray[np.int64], T: NDArray[np.int64]
                      ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """The segments (repeats dropped), their rows and the constrained flags of
    the triangles ``T`` (edge opposite corner ``j``); :class:`InvalidMeshError`
    naming the first segment that is not an edge of ``T``."""
    n = int(max(T.max(), segs.max(initial=0))) + 1
    u, v = T[:, [1, 2, 0]], T[:, [2, 0, 1]]
    edge_keys = np.minimum(u, v) * n + np.maximum(u, v)        # (k, 3): opposite corner j
    seg_keys = segs.min(axis=1) * n + segs.max(axis=1)
    missing = np.flatnonzero(~np.isin(seg_keys, edge_keys) | (segs[:, 0] == segs[:, 1]))
    if len(missing):
        i = int(missing[0])
        raise InvalidMeshError(f"segment {i} {segs[i].tolist()} is not an edge of the triangles",
                               segments=(i,))
    _, ids = np.unique(seg_keys, return_index=True)
    ids = np.sort(ids)
    return segs[ids], ids.astype(np.int64), np.isin(edge_keys, seg_keys)


def _triangle_name(tri, t, xy) -> str:
    """``t``'s vertices and their (moved) coordinates, for error messages."""
    vs = [int(v) for v in tri[3 * t: 3 * t + 3] if 0 <= v < len(xy)]
    return "with vertices " + ", ".join(f"{v} at ({xy[v, 0]!r}, {xy[v, 1]!r})" for v in vs)


def _vertex_map(n, dup_of, submerged):
    """Output index of every input point, the input index kept for each output
    vertex (the first appearance of each distinct point, in input order; None
    when every point is kept, in order) and the number of repeated points."""
    merged = dup_of >= 0
    if not merged.any() and not submerged.any():  # the common case: nothing merged
        return np.arange(n), None, 0
    dups = np.flatnonzero(merged)
    root = np.where(dup_of >= 0, dup_of, np.arange(n))
    in_mesh = (dup_of < 0) & (submerged == 0)
    rep = np.arange(n)
    if dups.size:
        np.minimum.at(rep, root[dups], dups)
    roots = np.flatnonzero(in_mesh)
    perm = np.argsort(rep[roots], kind="stable")
    out_of_root = np.full(n, -1, np.int64)
    out_of_root[roots[perm]] = np.arange(len(roots))
    vertex_map = np.where(in_mesh[root], out_of_root[root], -1)
    return vertex_map, rep[roots[perm]], dups.size


def _kept_rows(a, kept):
    """A copy of the rows ``kept`` of ``a`` (all of them when None)."""
    return a.copy() if kept is None else a[kept]


def _finished_stats(stats, n, duplicates, seconds, tri) -> dict:
    """``stats`` with the counts of ``tri``, a finished triangulation, added."""
    stats["duplicates"] = int(duplicates)
    stats["submerged"] = int((tri.vertex_map < 0).sum())
    stats["vertices"] = int(tri.vertex_map.max() + 1) if n else 0
    stats["triangles"] = len(tri.triangles)
    stats["seconds"] = seconds
    return stats


def _mesh_attributes(mesh) -> dict:
    """The arrays of a Delaunay result that are made on first access
    (:meth:`Triangulation.from_mesh`): neighbours from the store, no
    constrained edges, no regions."""
    tri, twin, _, ntri, inf = mesh
    neighbors = store_neighbors(tri, twin, ntri, inf)
    k = len(neighbors)
    return {"neighbors": neighbors, "constrained": np.zeros((k, 3), bool),
            "regions": np.full(k, -1, np.int64)}
