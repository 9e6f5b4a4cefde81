"""The Voronoi diagram (power diagram for weights) as the dual of a Delaunay
triangulation (Sec. 2.2, Fig. 2.3; Sec. 2.8), and the Delaunay subdivision.

Every combinatorial decision is exact: which triangles fuse into one face of
the Delaunay subdivision (the exact incircle / lifted test is 0 across their
edge), which faces surround a vertex, whether the triangulation is Delaunay at
all. So cocircular points give one Voronoi vertex, not several nearly equal
ones, and a square grid gives square cells. The constructions (face centres,
clipped corners) are floating point, computed near unit scale.

>>> import cdt_plugin
>>> tri = cdt_plugin.delaunay([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
>>> tri.delaunay_subdivision().tolist()
[[0, 1, 4, 3], [1, 2, 5, 4]]
>>> vor = tri.voronoi()
>>> vor.vertices.tolist(), vor.regions[1]
([[0.5, 0.5], [1.5, 0.5]], [1, 0, -1])
"""
from __future__ import annotations

from typing import Any, Iterator, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.dual import (cell_rings, clip_cells, face_centres, fuse_ties, mark_close, pack_cells,
                         redo_centres, ring_offsets, solid_rows, store_cells, store_rings, store_ties,
                         subdivision_faces, triangle_centres, triangle_faces, vertex_rings)
from . import hooks
from .errors import ClipRegionError, CollinearPointsError, NotDelaunayError
from .optional import require
from .parallel import check_workers, map_ordered, mapped_empty, resolve_workers
from .types import MeshStore, TriangulationLike
from .validate import exact_range


Box = tuple[float, float, float, float]


class Subdivision:
    """The faces of the Delaunay subdivision (Fig. 2.3c): each a convex polygon
    of vertex ids, counter-clockwise from its smallest id; a triangle where the
    triangulation is unique, a larger polygon where four or more vertices are
    cocircular (lifted-coplanar for weights).

    Attributes
    ----------
    offsets : (f + 1,) int64
        Face ``i`` is ``indices[offsets[i]:offsets[i + 1]]``.
    indices : (sum of face sizes,) int64
        The vertex ids of every face, one after the other.
    face_of_triangle : (k,) int64
        The face each triangle of the triangulation belongs to.
    """

    def __init__(self, offsets: NDArray[np.int64], indices: NDArray[np.int64],
                 face_of_triangle: NDArray[np.int64]) -> None:
        self._arrays: tuple[NDArray[np.int64], ...] | None = (offsets, indices, face_of_triangle)
        self._triangles: NDArray[np.int64] | None = None

    @classmethod
    def of_triangles(cls, triangles: NDArray[np.int64]) -> Subdivision:
        """The subdivision where no triangles are fused: face ``t`` is triangle
        ``t``. Its arrays are made on first access (the cells do not need them)."""
        sub = cls.__new__(cls)
        sub._arrays = None
        sub._triangles = triangles
        return sub

    def _made(self) -> tuple[NDArray[np.int64], ...]:
        if self._arrays is None:
            T = self._triangles
            assert T is not None
            k = len(T)
            ring = np.empty(3 * k, np.int64)
            triangle_faces(T, ring, np.int64(0), np.int64(k))
            self._arrays = (np.arange(0, 3 * k + 1, 3), ring, np.arange(k))
        return self._arrays

    @property
    def offsets(self) -> NDArray[np.int64]:
        """(f + 1,) where each face starts in ``indices``."""
        return self._made()[0]

    @property
    def indices(self) -> NDArray[np.int64]:
        """The vertex ids of every face, one after the other."""
        return self._made()[1]

    @property
    def face_of_triangle(self) -> NDArray[np.int64]:
        """(k,) the face each triangle belongs to."""
        return self._made()[2]

    def __len__(self) -> int:
        if self._arrays is None and self._triangles is not None:
            return len(self._triangles)
        return len(self.offsets) - 1

    def __getitem__(self, i: int) -> NDArray[np.int64]:
        if not -len(self) <= i < len(self):
            raise IndexError(f"face {i} out of range for {len(self)} faces")
        i %= len(self)
        return self.indices[self.offsets[i]:self.offsets[i + 1]]

    def __iter__(self) -> Iterator[NDArray[np.int64]]:
        return (self[i] for i in range(len(self)))

    @property
    def sizes(self) -> NDArray[np.int64]:
        """(f,) the number of vertices of each face."""
        return np.diff(self.offsets)

    def tolist(self) -> list[list[int]]:
        """The faces as lists of vertex ids."""
        return [face.tolist() for face in self]

    def __repr__(self) -> str:
        return f"Subdivision({len(self)} faces, {int((self.sizes > 3).sum())} not triangles)"


class Voronoi:
    """The Voronoi diagram of a triangulation's vertices (its sites), or their
    power diagram when the triangulation is weighted, in scipy's form plus
    flat arrays.

    Attributes
    ----------
    points : (s, 2) float64
        The sites: the triangulation's vertices (distinct input points).
    weights : (s,) float64 or None
        The sites' weights (power diagram), None for a Voronoi diagram.
    vertices : (f, 2) float64
        One Voronoi vertex per face of the Delaunay subdivision: its
        circumcentre (power centre with weights). Cocircular sites give one vertex.
        A vertex beyond the doubles (nearly collinear sites near the largest
        magnitudes) is inf; clipped cells are still cut exactly as elsewhere.
    region_offsets, region_indices : int64 arrays
        The cell of site ``i`` is ``region_indices[region_offsets[i]:region_offsets[i + 1]]``:
        Voronoi vertex ids counter-clockwise; an unbounded cell ends with -1,
        where it opens to infinity (between the rays of its last and first ridges).
    point_region : (n,) int64
        The site of each input point of the triangulation (``vertex_map``):
        duplicates share one, a submerged weighted point has -1 (an empty cell).
    unbounded : (s,) bool
        Whether the cell of each site is unbounded (the site is on the convex hull).
    clip : tuple, geometry or None
        The clip region the cells were cut to.
    cell_offsets, cell_xy : int64 and (m, 2) float64 arrays, or None
        With a box clip: the clipped cell of site ``i`` is
        ``cell_xy[cell_offsets[i]:cell_offsets[i + 1]]``, counter-clockwise, not
        closed, empty where the box misses it.

    ``ridge_points``, ``ridge_vertices`` and ``ridge_directions`` are made on
    first access (see their docstrings).
    """

    def __init__(self, tri: TriangulationLike, fused: NDArray[np.bool_] | None, subdivision: Subdivision,
                 vertices: NDArray[np.float64], region_offsets: NDArray[np.int64],
                 region_indices: NDArray[np.int64], unbounded: NDArray[np.bool_],
                 rings: tuple[NDArray[np.int64], NDArray[np.int64]],
                 unit: tuple[NDArray[np.float64], int] | None = None, threads: int = 1) -> None:
        self.points = tri.vertices
        self.weights = tri.weights
        self.vertices = vertices
        self.region_offsets = region_offsets
        self.region_indices = region_indices
        self.point_region = tri.vertex_map
        self.unbounded = unbounded
        self.subdivision = subdivision
        self.clip: Any = None
        self.cell_offsets: NDArray[np.int64] | None = None
        self.cell_xy: NDArray[np.float64] | None = None
        self._clipped: NDArray[np.object_] | None = None      # cells cut by a polygon
        self._tri = tri
        self._fused = fused
        self._rings = rings
        self._threads = threads
        self._ridges: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]] | None = None
        # the vertices as computed, times 2**-e (beyond the doubles, a vertex is inf in
        # ``vertices`` but finite here: clipping works from these)
        self._unit = unit if unit is not None else (vertices, 0)

    def __repr__(self) -> str:
        kind = "power diagram" if self.weights is not None else "Voronoi diagram"
        return (f"Voronoi({kind}: {len(self.points)} sites, {len(self.vertices)} vertices, "
                f"{int(self.unbounded.sum())} unbounded cells"
                f"{', clipped' if self.clip is not None else ''})")

    # ------------------------------------------------------------- regions
    def region(self, i: int) -> NDArray[np.int64]:
        """The cell of site ``i`` as Voronoi vertex ids (-1 last if unbounded)."""
        return self.region_indices[self.region_offsets[i]:self.region_offsets[i + 1]]

    @property
    def regions(self) -> list[list[int]]:
        """The cells as lists of Voronoi vertex ids, one per site (scipy's form,
        indexed by site: ``regions[point_region[i]]`` is input point ``i``'s)."""
        return [r.tolist() for r in np.split(self.region_indices, self.region_offsets[1:-1])]

    # -------------------------------------------------------------- ridges
    def _make_ridges(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
        if self._ridges is None:
            t, nb = self._tri.triangles, self._tri.neighbors
            once = np.arange(len(t))[:, None] < nb
            k, j = np.nonzero((nb < 0) | (once if self._fused is None else once & ~self._fused))
            a, b = t[k, (j + 1) % 3], t[k, (j + 2) % 3]
            m = nb[k, j]
            face = self.subdivision.face_of_triangle
            far = np.where(m >= 0, face[np.maximum(m, 0)], -1)
            pts = self.points
            d = np.column_stack([pts[b, 1] - pts[a, 1], pts[a, 0] - pts[b, 0]])   # outward normal
            d[m >= 0] = 0.0
            length = np.hypot(d[:, 0], d[:, 1])
            d[m < 0] /= length[m < 0, None]
            self._ridges = (np.column_stack([a, b]), np.column_stack([face[k], far]), d)
        return self._ridges

    @property
    def ridge_points(self) -> NDArray[np.int64]:
        """(r, 2) the two sites each ridge (Voronoi edge) separates: one row per
        edge of the Delaunay subdivision."""
        return self._make_ridges()[0]

    @property
    def ridge_vertices(self) -> NDArray[np.int64]:
        """(r, 2) the Voronoi vertices at each ridge's ends; -1 for the far end of
        a ray (a ridge between two neighbouring hull sites)."""
        return self._make_ridges()[1]

    @property
    def ridge_directions(self) -> NDArray[np.float64]:
        """(r, 2) the unit direction of each ray (from its finite vertex outwards,
        perpendicular to the hull edge between its sites); zero for finite ridges."""
        return self._make_ridges()[2]

    # --------------------------------------------------------------- cells
    def cell(self, i: int) -> NDArray[np.float64]:
        """The cell of site ``i`` as (m, 2) coordinates, counter-clockwise: the
        clipped cell after a box clip, else the Voronoi vertices of a bounded cell
        (an unbounded one needs a clip: :class:`ClipRegionError`)."""
        if self.cell_offsets is not None and self.cell_xy is not None:
            return self.cell_xy[self.cell_offsets[i]:self.cell_offsets[i + 1]]
        if self.unbounded[i]:
            raise ClipRegionError(f"the cell of site {i} is unbounded: pass clip= to voronoi()")
        return self.vertices[self.region(i)]

    def clipped(self, clip: Any) -> Voronoi:
        """This diagram with every cell cut to ``clip``: a box
        ``(xmin, ymin, xmax, ymax)`` or a shapely polygon (needs shapely)."""
        out = Voronoi.__new__(Voronoi)
        out.__dict__.update(self.__dict__)
        check_clip(clip)
        if _is_box(clip):
            box = check_box(clip)
            out.cell_offsets, out.cell_xy = self._box_cells(box)
            out._clipped = None
        else:
            out._clipped = hooks.clip_cells_to_polygon(self, clip)
            out.cell_offsets = out.cell_xy = None
        out.clip = clip
        return out

    def _box_cells(self, box: Box) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        pts = self.points
        xmin, ymin, xmax, ymax = box
        inside = ((pts[:, 0] >= xmin) & (pts[:, 0] <= xmax) & (pts[:, 1] >= ymin) & (pts[:, 1] <= ymax))
        if not inside.any():
            raise ClipRegionError(f"the clip box {box} contains none of the {len(pts)} points")
        x, y, w, e = _near_unit(self._tri, np.array(box))      # (the sites and the box: doubles)
        offsets, ring = self._rings
        unit, unit_e = self._unit
        centres = np.ldexp(unit, unit_e - e) if unit_e != e else unit
        b = np.ldexp(np.array(box), -e)
        parts = _in_ranges(self._threads, len(pts), lambda lo, hi: clip_cells(
            x, y, w, self._tri.triangles, offsets, ring, self.unbounded,
            self.subdivision.face_of_triangle, centres, b[0], b[1], b[2], b[3], lo, hi))
        if len(parts) == 1:
            off, xy = parts[0]
        else:                            # the ranges' cells one after the other
            shift = np.cumsum([0] + [len(p[1]) for p in parts[:-1]])
            off = np.concatenate([[0]] + [p[0][1:] + s for p, s in zip(parts, shift)])
            xy = np.concatenate([p[1] for p in parts])
        return off, (np.ldexp(xy, e) if e else xy)

    def envelope(self) -> Box:
        """The box shapely / GEOS clip a diagram to by default: the sites'
        bounding box grown by its larger side on every side."""
        lo, hi = self.points.min(axis=0), self.points.max(axis=0)
        grow = float((hi - lo).max())
        return (float(lo[0]) - grow, float(lo[1]) - grow, float(hi[0]) + grow, float(hi[1]) + grow)

    def to_shapely(self) -> NDArray[np.object_]:
        """One shapely Polygon per site (needs shapely): the clipped cells, or,
        without a clip, every cell cut to :meth:`envelope` (as
        ``shapely.voronoi_polygons`` does); an empty Polygon where nothing is left."""
        if self._clipped is not None:
            return self._clipped
        if self.cell_offsets is None or self.cell_xy is None:
            return self.clipped(self.envelope()).to_shapely()
        return hooks.cells_to_polygons(self.cell_offsets, self.cell_xy)


def delaunay_subdivision(tri: TriangulationLike) -> Subdivision:
    """The faces of the Delaunay subdivision of ``tri`` (see :class:`Subdivision`)."""
    return _fuse(tri, _predicate_range(tri), resolve_workers(None, 2))[1]


def voronoi(tri: TriangulationLike, clip: Any = None, *, workers: int | None = None) -> Voronoi:
    """The Voronoi diagram (power diagram) of ``tri``'s vertices, dual to it
    (see :meth:`cdt_plugin.Triangulation.voronoi`)."""
    check_clip(clip)                     # options first, before any work
    threads = resolve_workers(check_workers(workers), 2)
    scaled = _predicate_range(tri)
    mesh = tri._mesh
    dual = _store_dual(tri, mesh, scaled, threads) if mesh is not None else None
    if dual is None:                     # no store, or cocircular triangles to fuse
        dual = _general_dual(tri, scaled, threads)
    vor = Voronoi(tri, *dual, threads=threads)
    return vor if clip is None else vor.clipped(clip)


class _Dual(NamedTuple):
    """What :class:`Voronoi` is made of: the fused edge flags (None: none
    fused), the subdivision, the face centres, each vertex's ring of
    triangles (a hull vertex's ending with -1) and its cell, and the hull flags."""
    fused: NDArray[np.bool_] | None
    subdivision: Subdivision
    centres: NDArray[np.float64]
    region_offsets: NDArray[np.int64]
    region_indices: NDArray[np.int64]
    unbounded: NDArray[np.bool_]
    rings: tuple[NDArray[np.int64], NDArray[np.int64]]
    unit: tuple[NDArray[np.float64], int]       # the centres times 2**-e, and e


def _store_dual(tri: TriangulationLike, mesh: MeshStore, scaled: _Scaled, threads: int) -> _Dual | None:
    """The dual read straight off a Delaunay result's half-edge store, where
    no triangles are fused (each face one triangle, each cell the ring of
    triangles round its vertex); None if some are (cocircular points: the
    general route fuses them)."""
    store, twin, _, ntri, inf = mesh
    x, y, w, _ = scaled
    T, nv, k = tri.triangles, len(tri.vertices), len(tri.triangles)
    ux, uy, uw, e = _near_unit(tri, scaled=scaled)
    centres, err = mapped_empty((k, 2)), mapped_empty(k)
    redo = mapped_empty(k, bool, fill=False)

    def rings_and_rows() -> tuple[NDArray[np.int64], NDArray[np.int32], NDArray[np.int32]]:
        return (*store_rings(store, ntri, inf, np.int64(nv)), solid_rows(store, ntri, inf))

    # the counting passes (one thread) beside the centres
    (offsets, start, tid), _ = map_ordered(lambda f: f(), [rings_and_rows, lambda: triangle_centres(
        ux, uy, uw, w is not None, T, centres, err, np.int64(0), np.int64(k))], threads)
    found = _in_ranges(threads, ntri, lambda lo, hi: store_ties(
        x, y, x if w is None else w, w is not None, store, twin, tid, centres, err, redo, lo, hi))
    bad = [int(b) for b, _ in found if b >= 0]
    if bad:                              # (half-edge b runs from store[b] to the next of its triangle)
        b = bad[0]
        _not_locally_delaunay(tri, int(tid[b // 3]), [int(store[b]), int(store[b - b % 3 + (b + 1) % 3])])
    if sum(int(ties) for _, ties in found):
        return None
    cells, hull = mapped_empty(offsets[-1], np.int64), mapped_empty(nv, bool)
    wrong = min(_in_ranges(threads, nv, lambda lo, hi: store_cells(
        x, y, store, twin, tid, offsets, start, cells, hull, lo, hi)))
    if wrong < nv:
        _not_convex(tri, wrong, start[wrong] == -1)
    sub = Subdivision.of_triangles(T)
    if redo.any() or not np.isfinite(centres).all():      # (a triangle so flat its centre rounded to NaN)
        redo_centres(ux, uy, uw, sub.offsets, sub.indices, centres, redo, np.int64(0), np.int64(k))
    return _Dual(None, sub, _scaled_back(centres, e), offsets, cells, hull, (offsets, cells), (centres, e))


def _general_dual(tri: TriangulationLike, scaled: _Scaled, threads: int) -> _Dual:
    """The dual from the triangles and their neighbours: cocircular
    triangles fused into the subdivision's faces, each cell the faces round
    its vertex."""
    fused, sub = _fuse(tri, scaled, threads)
    x, y = scaled.x, scaled.y
    T, N, nv = tri.triangles, tri.neighbors, len(tri.vertices)
    offsets, first, hull, pinched = ring_offsets(T, N, np.int64(nv))
    lonely = np.flatnonzero(first < 0)
    if len(lonely):
        _not_convex(tri, int(lonely[0]), True)
    if pinched < nv:
        _not_convex(tri, int(pinched), False)
    ring = mapped_empty(offsets[-1], np.int64)
    reflex = min(_in_ranges(threads, len(T), lambda lo, hi: vertex_rings(
        x, y, T, N, offsets, first, ring, hull, lo, hi)))
    if reflex < nv:
        _not_convex(tri, reflex, False)
    ux, uy, uw, e = _near_unit(tri, scaled=scaled)
    centres = mapped_empty((len(sub), 2))
    err = mapped_empty(len(sub))
    redo = mapped_empty(len(sub), bool, fill=False)
    _in_ranges(threads, len(sub), lambda lo, hi: face_centres(
        ux, uy, uw, sub.offsets, sub.indices, centres, err, lo, hi))
    _in_ranges(threads, len(T), lambda lo, hi: mark_close(
        T, N, sub.face_of_triangle, centres, err, redo, lo, hi))
    _in_ranges(threads, len(sub), lambda lo, hi: redo_centres(
        ux, uy, uw, sub.offsets, sub.indices, centres, redo, lo, hi))
    region_offsets, region_indices = offsets, ring     # nothing fused: face t is triangle t
    if fused is not None:                # each cell into the room of its ring, then packed
        cells, sizes = mapped_empty(offsets[-1], np.int64), mapped_empty(nv, np.int64)
        _in_ranges(threads, nv, lambda lo, hi: cell_rings(
            T, offsets, ring, hull, sub.face_of_triangle, cells, sizes, lo, hi))
        region_offsets = np.concatenate([[0], np.cumsum(sizes)])
        region_indices = mapped_empty(region_offsets[-1], np.int64)
        _in_ranges(threads, nv, lambda lo, hi: pack_cells(
            offsets, cells, sizes, region_offsets, region_indices, lo, hi))
    return _Dual(fused, sub, _scaled_back(centres, e), region_offsets, region_indices,
                 hull, (offsets, ring), (centres, e))


def _scaled_back(centres: NDArray[np.float64], e: int) -> NDArray[np.float64]:
    """``centres * 2**e``: inf where a Voronoi vertex lies beyond the doubles
    (nearly collinear sites near the largest magnitudes)."""
    if not e:
        return centres
    with np.errstate(over="ignore"):
        return np.ldexp(centres, e)


#: From this many triangles the kernels run on two threads (each on half the range)
PARALLEL_TRIANGLES = 100_000


def _in_ranges(threads: int, n: int, fn: Any) -> list[Any]:
    """``fn(lo, hi)`` over ``threads`` consecutive ranges of ``0:n`` (one
    range below :data:`PARALLEL_TRIANGLES`), on threads; results in order."""
    pieces = threads if n >= PARALLEL_TRIANGLES else 1
    bounds = [n * i // pieces for i in range(pieces + 1)]
    return map_ordered(lambda i: fn(np.int64(bounds[i]), np.int64(bounds[i + 1])), range(pieces), pieces)


class _Scaled(NamedTuple):
    """The vertices (and weights) times ``2**shift``, in the exact predicates' range."""
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    w: NDArray[np.float64] | None
    shift: int


def _predicate_range(tri: TriangulationLike) -> _Scaled:
    """Check that ``tri`` can have a dual (triangles, no segments) and scale
    its vertices (and weights) into the exact predicates' range."""
    if len(tri.triangles) == 0:
        raise CollinearPointsError(
            f"{len(tri.vertices)} point(s), all on one line or fewer than three: no triangle, "
            "so no Voronoi vertex and no Delaunay subdivision")
    # (a half-edge store is a Delaunay result's: never constrained)
    if len(tri.segments) or (tri._mesh is None and tri.constrained.any()):
        raise NotDelaunayError("the triangulation has segments: the Voronoi diagram and the Delaunay "
                               "subdivision are defined for Delaunay triangulations of points; "
                               "use cdt_plugin.delaunay(tri.vertices)")
    pts = tri.vertices
    return _Scaled(*exact_range(pts[:, 0], pts[:, 1], tri.weights, "vertices"))


def _fuse(tri: TriangulationLike, scaled: _Scaled, threads: int) -> tuple[NDArray[np.bool_] | None, Subdivision]:
    """Check that ``tri`` is a (weighted) Delaunay triangulation and fuse its
    cocircular triangles: (both sides' fused edge flags, None if none are;
    the subdivision)."""
    x, y, w, _ = scaled
    T, weighted = tri.triangles, w is not None
    fused = mapped_empty(T.shape, bool, fill=False)
    found = [b for b in _in_ranges(threads, len(T), lambda lo, hi: fuse_ties(
        x, y, w if weighted else x, weighted, T, tri.neighbors, fused, lo, hi)) if b >= 0]
    if found:
        t, j = divmod(int(found[0]), 3)
        _not_locally_delaunay(tri, t, [int(T[t, (j + 1) % 3]), int(T[t, (j + 2) % 3])])
    if not fused.any():                  # face t is triangle t
        return None, Subdivision.of_triangles(T)
    face_of, offsets, ring = subdivision_faces(T, tri.neighbors, fused)
    return fused, Subdivision(offsets, ring, face_of)


def _not_locally_delaunay(tri: TriangulationLike, t: int, edge: list[int]) -> None:
    weighted = tri.weights is not None
    raise NotDelaunayError(f"edge {edge} of triangle {t} is not locally "
                           f"{'regular' if weighted else 'Delaunay'}: not a "
                           f"{'weighted ' if weighted else ''}Delaunay triangulation")


def _not_convex(tri: TriangulationLike, v: int, lonely: bool) -> None:
    where = f"vertex {v} {tri.vertices[v].tolist()}"
    if lonely:
        raise NotDelaunayError(f"{where} is in no triangle: not the Delaunay triangulation of its vertices")
    raise NotDelaunayError(f"the triangulation's boundary turns inwards at {where}: not the Delaunay "
                           "triangulation of its vertices (its domain is not their convex hull)")


def check_clip(clip: Any) -> None:
    """Raise :class:`ClipRegionError` unless ``clip`` is None, a valid box or
    a Polygon / MultiPolygon (``__geo_interface__``; cutting to it needs shapely)."""
    if clip is None:
        return
    if _is_box(clip) or isinstance(clip, str):
        check_box(clip)
        return
    kind = getattr(clip, "__geo_interface__", {}).get("type") if hasattr(clip, "__geo_interface__") else None
    if kind not in ("Polygon", "MultiPolygon"):
        raise ClipRegionError(f"clip must be a box (xmin, ymin, xmax, ymax) or a Polygon / MultiPolygon, "
                              f"got {type(clip).__name__}{f' ({kind})' if kind else ''}")
    require("shapely", "voronoi(clip=<polygon>)")


def _is_box(clip: Any) -> bool:
    return isinstance(clip, (tuple, list, np.ndarray)) and np.ndim(clip) == 1


def check_box(clip: ArrayLike) -> Box:
    """``clip`` as a finite box ``(xmin, ymin, xmax, ymax)`` with positive width
    and height, or :class:`ClipRegionError`."""
    try:
        box = np.asarray(clip, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ClipRegionError(f"clip must be (xmin, ymin, xmax, ymax) or a polygon, got {clip!r}") from e
    if box.shape != (4,) or not np.isfinite(box).all():
        raise ClipRegionError(f"clip box must be 4 finite numbers (xmin, ymin, xmax, ymax), got {clip!r}")
    if not (box[0] < box[2] and box[1] < box[3]):
        raise ClipRegionError(f"clip box {tuple(box.tolist())} is empty: it needs xmin < xmax and ymin < ymax")
    return (float(box[0]), float(box[1]), float(box[2]), float(box[3]))


def _near_unit(tri: TriangulationLike, *more: NDArray[np.float64], scaled: _Scaled | None = None
               ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """The vertices' x, y, weights (zeros if None) times ``2**-e``, ``4**-e``
    for the constructions, with ``e`` chosen from the points and ``more`` so
    that squares of differences neither overflow nor underflow (0 at ordinary
    scales, where the predicates' copies ``scaled`` are used if not scaled)."""
    pts, weights = tri.vertices, tri.weights
    top = max(max(-float(a.min()), float(a.max())) for a in (pts, *more))   # (no |a| made)
    e = int(np.frexp(top)[1])
    e = 0 if -64 <= e <= 64 else e
    if e == 0 and scaled is not None and scaled.shift == 0:
        ux, uy = scaled.x, scaled.y
    else:
        ux, uy = np.ldexp(pts[:, 0], -e), np.ldexp(pts[:, 1], -e)
    w = np.zeros(len(pts)) if weights is None else np.ldexp(weights, -2 * e)
    return ux, uy, w, e


__all__ = ["Subdivision", "Voronoi", "check_box", "check_clip", "delaunay_subdivision", "voronoi"]
