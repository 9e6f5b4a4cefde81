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

from typing import TYPE_CHECKING, Any, Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.dual import (cell_rings, clip_cells, face_centres, fuse_ties, mark_close, pack_cells,
                         redo_centres, ring_offsets, subdivision_faces, triangle_faces, unfused_cells,
                         vertex_rings)
from .errors import ClipRegionError, CollinearPointsError, NotDelaunayError
from .optional import require
from .parallel import check_workers, map_ordered, mapped_empty, resolve_workers
from .validate import exact_range

if TYPE_CHECKING:
    from .triangulation import Triangulation

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
        self.offsets = offsets
        self.indices = indices
        self.face_of_triangle = face_of_triangle

    def __len__(self) -> int:
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

    def __init__(self, tri: Triangulation, fused: NDArray[np.bool_], subdivision: Subdivision,
                 vertices: NDArray[np.float64], region_offsets: NDArray[np.int64],
                 region_indices: NDArray[np.int64], unbounded: NDArray[np.bool_],
                 rings: tuple[NDArray[np.int64], NDArray[np.int64]], threads: int = 1) -> None:
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
            k, j = np.nonzero((nb < 0) | ((np.arange(len(t))[:, None] < nb) & ~self._fused))
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
            from cdt_plugin.adapters.shapely import clip_cells_to_polygon
            out._clipped = clip_cells_to_polygon(self, clip)
            out.cell_offsets = out.cell_xy = None
        out.clip = clip
        return out

    def _box_cells(self, box: Box) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        pts = self.points
        xmin, ymin, xmax, ymax = box
        inside = ((pts[:, 0] >= xmin) & (pts[:, 0] <= xmax) & (pts[:, 1] >= ymin) & (pts[:, 1] <= ymax))
        if not inside.any():
            raise ClipRegionError(f"the clip box {box} contains none of the {len(pts)} points")
        x, y, w, e = _near_unit(pts, self.weights, np.array(box), self.vertices)
        offsets, ring = self._rings
        centres = np.ldexp(self.vertices, -e) if e else self.vertices
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
        from cdt_plugin.adapters.shapely import cells_to_polygons
        if self._clipped is not None:
            return self._clipped
        if self.cell_offsets is None or self.cell_xy is None:
            return self.clipped(self.envelope()).to_shapely()
        return cells_to_polygons(self.cell_offsets, self.cell_xy)


def delaunay_subdivision(tri: Triangulation) -> Subdivision:
    """The faces of the Delaunay subdivision of ``tri`` (see :class:`Subdivision`)."""
    return _dual(tri, resolve_workers(None, 2))[1]


def voronoi(tri: Triangulation, clip: Any = None, *, workers: int | None = None) -> Voronoi:
    """The Voronoi diagram (power diagram) of ``tri``'s vertices, dual to it
    (see :meth:`cdt_plugin.Triangulation.voronoi`)."""
    check_clip(clip)                     # options first, before any work
    threads = resolve_workers(check_workers(workers), 2)
    fused, sub, x, y = _dual(tri, threads)
    pts, T, nv = tri.vertices, tri.triangles, len(tri.vertices)
    offsets, first = ring_offsets(T, np.int64(nv))
    lonely = np.flatnonzero(first < 0)
    if len(lonely):
        raise NotDelaunayError(f"vertex {lonely[0]} {pts[lonely[0]].tolist()} is in no triangle: "
                               "not the Delaunay triangulation of its vertices")
    ring = mapped_empty(3 * len(T), np.int64)
    hull = mapped_empty(nv, bool, fill=False)
    reflex = min(_in_ranges(threads, len(T), lambda lo, hi: vertex_rings(
        x, y, T, tri.neighbors, offsets, first, ring, hull, lo, hi)))
    if reflex < nv:
        raise NotDelaunayError(f"the triangulation's boundary turns inwards at vertex {reflex} "
                               f"{pts[reflex].tolist()}: not the Delaunay triangulation of its vertices "
                               "(its domain is not their convex hull)")
    ux, uy, uw, e = _near_unit(pts, tri.weights)
    centres = mapped_empty((len(sub), 2))
    err = mapped_empty(len(sub))
    redo = mapped_empty(len(sub), bool, fill=False)
    _in_ranges(threads, len(sub), lambda lo, hi: face_centres(
        ux, uy, uw, sub.offsets, sub.indices, centres, err, lo, hi))
    _in_ranges(threads, len(T), lambda lo, hi: mark_close(
        T, tri.neighbors, sub.face_of_triangle, centres, err, redo, lo, hi))
    _in_ranges(threads, len(sub), lambda lo, hi: redo_centres(
        ux, uy, uw, sub.offsets, sub.indices, centres, redo, lo, hi))
    # each cell in one pass into room for its ring (and a hull cell's -1): the
    # cells themselves unless cocircular triangles were fused, then packed
    slots = offsets + np.concatenate([[0], np.cumsum(hull)])
    cells = mapped_empty(slots[-1], np.int64)
    region_offsets, region_indices = slots, cells
    if len(sub) == len(T):               # nothing fused: face t is triangle t
        _in_ranges(threads, nv, lambda lo, hi: unfused_cells(
            offsets, ring, hull, sub.face_of_triangle, slots, cells, lo, hi))
    else:
        sizes = mapped_empty(nv, np.int64)
        _in_ranges(threads, nv, lambda lo, hi: cell_rings(
            T, offsets, ring, hull, sub.face_of_triangle, slots, cells, sizes, lo, hi))
        region_offsets = np.concatenate([[0], np.cumsum(sizes)])
        region_indices = mapped_empty(region_offsets[-1], np.int64)
        _in_ranges(threads, nv, lambda lo, hi: pack_cells(
            slots, cells, sizes, region_offsets, region_indices, lo, hi))
    vor = Voronoi(tri, fused, sub, np.ldexp(centres, e) if e else centres, region_offsets,
                  region_indices, hull, (offsets, ring), threads)
    return vor if clip is None else vor.clipped(clip)


#: From this many triangles the kernels run on two threads (each on half the range)
PARALLEL_TRIANGLES = 100_000


def _in_ranges(threads: int, n: int, fn: Any) -> list[Any]:
    """``fn(lo, hi)`` over ``threads`` consecutive ranges of ``0:n`` (one
    range below :data:`PARALLEL_TRIANGLES`), on threads; results in order."""
    pieces = threads if n >= PARALLEL_TRIANGLES else 1
    bounds = [n * i // pieces for i in range(pieces + 1)]
    return map_ordered(lambda i: fn(np.int64(bounds[i]), np.int64(bounds[i + 1])), range(pieces), pieces)


def _dual(tri: Triangulation, threads: int = 1) -> tuple[NDArray[np.bool_], Subdivision, NDArray[np.float64],
                                                         NDArray[np.float64]]:
    """Check that ``tri`` is a (weighted) Delaunay triangulation and fuse its
    cocircular triangles: (both sides' fused edge flags, the subdivision, and
    the coordinates scaled into the exact predicates' range)."""
    if len(tri.triangles) == 0:
        raise CollinearPointsError(
            f"{len(tri.vertices)} point(s), all on one line or fewer than three: no triangle, "
            "so no Voronoi vertex and no Delaunay subdivision")
    if len(tri.segments) or tri.constrained.any():
        raise NotDelaunayError("the triangulation has segments: the Voronoi diagram and the Delaunay "
                               "subdivision are defined for Delaunay triangulations of points; "
                               "use cdt_plugin.delaunay(tri.vertices)")
    pts = tri.vertices
    x, y, w, _ = exact_range(pts[:, 0], pts[:, 1], tri.weights, "vertices")
    weighted = w is not None
    fused = mapped_empty(tri.triangles.shape, bool, fill=False)
    found = [b for b in _in_ranges(threads, len(tri.triangles), lambda lo, hi: fuse_ties(
        x, y, w if weighted else x, weighted, tri.triangles, tri.neighbors, fused, lo, hi)) if b >= 0]
    if found:
        t, j = divmod(int(found[0]), 3)
        edge = [int(tri.triangles[t, (j + 1) % 3]), int(tri.triangles[t, (j + 2) % 3])]
        raise NotDelaunayError(f"edge {edge} of triangle {t} is not locally "
                               f"{'regular' if weighted else 'Delaunay'}: not a "
                               f"{'weighted ' if weighted else ''}Delaunay triangulation")
    T = tri.triangles
    if fused.any():
        face_of, offsets, ring = subdivision_faces(T, tri.neighbors, fused)
    else:                                # face t is triangle t
        face_of, offsets = np.arange(len(T)), np.arange(0, 3 * len(T) + 1, 3)
        ring = mapped_empty(3 * len(T), np.int64)
        _in_ranges(threads, len(T), lambda lo, hi: triangle_faces(T, ring, lo, hi))
    return fused, Subdivision(offsets, ring, face_of), x, y


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


def _near_unit(pts: NDArray[np.float64], weights: NDArray[np.float64] | None,
               *more: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                    NDArray[np.float64], int]:
    """x, y, weights (zeros if None) times ``2**-e``, ``4**-e`` for the
    constructions, with ``e`` chosen from the points and ``more`` so that
    squares of differences neither overflow nor underflow (0 at ordinary scales)."""
    top = max([float(np.abs(pts).max())] + [float(np.abs(m).max()) for m in more])
    e = int(np.frexp(top)[1])
    e = 0 if -64 <= e <= 64 else e
    x = np.ldexp(pts[:, 0], -e) if e else np.ascontiguousarray(pts[:, 0])
    y = np.ldexp(pts[:, 1], -e) if e else np.ascontiguousarray(pts[:, 1])
    w = np.zeros(len(pts)) if weights is None else np.ldexp(weights, -2 * e)
    return x, y, w, e


__all__ = ["Subdivision", "Voronoi", "check_box", "check_clip", "delaunay_subdivision", "voronoi"]
