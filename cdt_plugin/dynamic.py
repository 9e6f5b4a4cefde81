"""An editable constrained Delaunay triangulation: :class:`DynamicCDT`.

Vertices and segments keep the ids they were given when inserted, whatever is
edited later. Inserting points and segments edits the live half-edge store with
the engine's own kernels (:mod:`cdt_plugin._core.dynamic`): a point costs a walk
and a few flips. Removing and moving rebuild the store from the remaining
vertices and segments (one Delaunay construction, O(n log n)): batch such edits
into one call. Every edit is all or nothing: an error leaves the triangulation
as it was.
"""
from __future__ import annotations

import time
from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.construct import gather_coords, seed_triangle
from ._core.dynamic import insert_points, insert_segments, snapshot, start_grid
from ._core.mesh import grow_store
from ._core.ordering import HILBERT_BITS, hilbert_keys, lexicographic_order
from ._core.output import rotate_min_first
from ._core.snap import snap_route
from ._core.status import (ALL_DONE, OK, ROUTE_CROSSING, ROUTE_OK, ROUTE_OVERLAP, STOP_CROSSING, STOP_LIMIT,
                           STOP_OVERLAP)
from ._routes import build_divide
from .cdt import raise_intersection
from .errors import (CDTError, CoordinateRangeError, InputShapeError, SegmentIndexError, UnknownIdError,
                     UnresolvedCrossingError)
from .parallel import resolve_workers
from .triangulation import Triangulation
from .validate import as_queries, exact_range

INTERSECTIONS = ("raise", "split")
DOMAINS = ("hull", "even-odd")
Store = tuple


class DynamicCDT:
    """A constrained Delaunay triangulation of the convex hull of its vertices
    that can be edited in place.

    Parameters
    ----------
    vertices : (n, 2) array_like, optional
        Initial points (as :meth:`insert_points`).
    segments : (s, 2) array_like of int, optional
        Initial segments, as pairs of vertex ids (as :meth:`insert_segments`).
    intersections : {"raise", "split"}
        What a segment crossing another does: raise
        :class:`cdt_plugin.SegmentIntersectionError` (the edit is undone), or
        snap-round the crossings as :func:`cdt_plugin.triangulate` does: the
        crossing points become Steiner vertices and each segment the chain of
        its pieces through them.

    Notes
    -----
    After any sequence of edits, :meth:`triangulation` equals
    ``cdt_plugin.triangulate(dyn.vertices, dyn.segments, keep_hull=True)``: the
    constrained Delaunay triangulation is unique under the engine's symbolic
    perturbation, however it was reached. With ``intersections="split"`` the
    crossing points are derived from the other vertices and the segments: it
    equals ``triangulate(V, S, intersections="split", keep_hull=True)`` for the
    live vertices less the crossing points (``triangulation().steiner``) and the
    segments. Once segments cross, each edit rounds every crossing again (a
    rebuild: the crossing points get new ids, and one that no longer is a
    crossing goes); a crossing point that a segment ends at, that is moved or
    that is inserted again as a point becomes an ordinary vertex.

    Examples
    --------
    >>> import cdt_plugin
    >>> dyn = cdt_plugin.DynamicCDT([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> dyn.insert_points([[1, 1], [3, 1], [4, 4]]).tolist()     # (4, 4) is vertex 2
    [4, 5, 2]
    >>> dyn.insert_segments([[4, 2]]).tolist()
    [0]
    >>> tri = dyn.triangulation()
    >>> len(tri.triangles), tri.is_delaunay(), len(dyn)
    (6, True, 6)
    >>> dyn.remove_vertices([4])
    >>> len(dyn), len(dyn.segments)                 # its segment went with it
    (5, 0)
    """

    def __init__(self, vertices: ArrayLike | None = None, segments: ArrayLike | None = None, *,
                 intersections: str = "raise") -> None:
        if intersections not in INTERSECTIONS:
            raise CDTError(f"intersections must be one of {INTERSECTIONS}, got {intersections!r}")
        self._split = intersections == "split"
        # per vertex id, with room to grow (the views below are the first _n rows)
        self._n = 0
        self._xy_buf = np.empty((16, 2))
        self._alive_buf = np.zeros(16, bool)
        self._steiner_buf = np.zeros(16, bool)
        self._slot_buf = np.full(16, -1, np.int64)     # store slot of each vertex id (-1: none)
        self._segs = np.empty((0, 2), np.int64)
        self._seg_alive = np.empty(0, bool)
        self._seg_key: dict[tuple[int, int], int] = {}
        self._store: Store | None = None
        self._id_of = np.empty(0, np.int64)      # vertex id of each store slot
        self._adopted = 0                        # store slots that have a vertex id
        self._stack = np.empty(0, np.int64)      # the flip stack of insert_points
        self._grid_vertices = 0                  # vertices when the start grid was made
        self._grid = np.empty(0, np.int64)
        self._frame = np.empty(4)
        self._last = np.int64(0)
        self._edits = 0
        if vertices is not None:
            self.insert_points(vertices)
        if segments is not None:
            self.insert_segments(segments)

    @classmethod
    def from_triangulation(cls, tri: Triangulation, *, intersections: str = "raise") -> DynamicCDT:
        """A live triangulation of ``tri``'s vertices and segment pieces (vertex
        ``i`` keeps id ``i``; segment piece ``k`` of ``tri.segments`` gets id ``k``).

        >>> import cdt_plugin
        >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]])
        >>> dyn = cdt_plugin.DynamicCDT.from_triangulation(tri)
        >>> len(dyn), len(dyn.segments)
        (4, 4)
        """
        return cls(tri.vertices, tri.segments if len(tri.segments) else None, intersections=intersections)

    # ------------------------------------------------- the per-vertex tables
    @property
    def _xy(self) -> NDArray[np.float64]:
        return self._xy_buf[: self._n]

    @_xy.setter
    def _xy(self, value: NDArray[np.float64]) -> None:
        self._xy_buf[: self._n] = value

    @property
    def _alive(self) -> NDArray[np.bool_]:
        return self._alive_buf[: self._n]

    @_alive.setter
    def _alive(self, value: NDArray[np.bool_]) -> None:
        self._alive_buf[: self._n] = value

    @property
    def _steiner(self) -> NDArray[np.bool_]:
        return self._steiner_buf[: self._n]

    @property
    def _slot_of(self) -> NDArray[np.int64]:
        return self._slot_buf[: self._n]

    @_slot_of.setter
    def _slot_of(self, value: NDArray[np.int64]) -> None:
        self._slot_buf[: self._n] = value

    # ------------------------------------------------------------------ views
    def __len__(self) -> int:
        """The number of vertices (removed ones not counted)."""
        return int(self._alive.sum())

    @property
    def vertices(self) -> NDArray[np.float64]:
        """(n, 2) coordinates of the live vertices, in id order (see :attr:`vertex_ids`)."""
        return self._xy[self._alive]

    @property
    def vertex_ids(self) -> NDArray[np.int64]:
        """The id of each row of :attr:`vertices`."""
        return np.flatnonzero(self._alive)

    @property
    def segments(self) -> NDArray[np.int64]:
        """(s, 2) the live segments as rows of :attr:`vertices` (ready for
        :func:`cdt_plugin.triangulate`); their ids are :attr:`segment_ids`."""
        return self._row_of()[self._segs[self._seg_alive]]

    @property
    def segment_ids(self) -> NDArray[np.int64]:
        """The id of each row of :attr:`segments`."""
        return np.flatnonzero(self._seg_alive)

    def __repr__(self) -> str:
        return f"DynamicCDT({len(self)} vertices, {int(self._seg_alive.sum())} segments)"

    def _row_of(self) -> NDArray[np.int64]:
        return np.cumsum(self._alive) - 1

    # ------------------------------------------------------------------ edits
    def insert_points(self, points: ArrayLike) -> NDArray[np.int64]:
        """Insert points; returns their vertex ids. A point equal to a vertex
        (bit for bit) returns that vertex's id and adds nothing (a crossing
        point so named is kept from then on). A point on a segment splits it.
        With ``"split"`` and segments that cross, the crossings are rounded
        again with the new points (a rebuild)."""
        pts = _as_points(points)
        if len(pts) == 0:
            return np.empty(0, np.int64)
        self._edits += 1
        if not self._split:
            return self._insert_points(pts)
        if not (self._steiner & self._alive).any():
            ids = self._insert_points(pts)
            self._steiner[ids] = False
            return ids
        # (a new point can lie in the pixel of a segment: snap rounding decides)
        n, steiner = self._n, self._steiner.copy()
        ids = self._insert_points(pts)
        try:
            self._steiner[ids] = False
            self._rebuild()
        except CDTError:
            self._alive_buf[n:self._n] = False
            self._steiner_buf[:n] = steiner
            self._n = n
            self._rebuild()
            raise
        return ids

    def _insert_points(self, pts: NDArray[np.float64]) -> NDArray[np.int64]:
        """:meth:`insert_points` into the store as it is (Lawson flips)."""
        if self._store is None:
            return self._insert_without_store(pts)
        m = len(pts)
        self._make_room(m)
        tri, twin, cons, x, y, w, inf, ntri, nv = self._store
        meta = np.array([ntri, nv, self._last], np.int64)
        if m == 1:        # (a loop of single inserts: every microsecond shows)
            order, px, py = None, pts[:, 0].copy(), pts[:, 1].copy()
        else:
            order = _spatial_order(pts)
            px, py = pts[order, 0], pts[order, 1]
        status, slots = insert_points(tri, twin, cons, x, y, w, inf, meta, px, py,
                                      self._stack, self._grid, self._frame)
        self._store = (tri, twin, cons, x, y, w, inf, meta[0], meta[1])
        self._last = meta[2]
        if status != OK:
            raise CDTError("internal error: a point could not be located; please report this input")
        if meta[1] > self._adopted and order is None:
            self._adopt_new_slots(False)
        elif meta[1] > self._adopted and order is not None:
            # new vertices are numbered in the order the caller gave the points
            first = self._adopted
            fresh = slots >= first
            first_input = np.full(int(meta[1]) - first, m, np.int64)
            np.minimum.at(first_input, slots[fresh] - first, order[fresh])
            self._adopt_new_slots(False, first + np.argsort(first_input))
        if order is None:
            return self._id_of[slots]
        out = np.empty(m, np.int64)
        out[order] = self._id_of[slots]
        return out

    def _insert_without_store(self, pts: NDArray[np.float64]) -> NDArray[np.int64]:
        """Fewer than three non-collinear vertices so far: add the points as
        vertices (repeats merged), then build the store if they span a triangle."""
        have = self._xy[self._alive]
        ids_have = np.flatnonzero(self._alive)
        both = np.concatenate([have, pts])
        _, first, inverse = np.unique(both, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
        new_rows = np.setdiff1d(first, np.arange(len(have)))      # rows of `both` not seen before
        new_rows.sort()
        new_ids = self._append_vertices(both[new_rows], steiner=False)
        id_of_row = np.empty(len(both), np.int64)
        id_of_row[: len(have)] = ids_have
        id_of_row[new_rows] = new_ids
        out = id_of_row[first[inverse[len(have):]]]
        try:
            self._rebuild()        # (the segments go in now: they can cross)
        except CDTError:
            self._n -= len(new_ids)
            self._rebuild()        # back to no triangle: nothing to fail
            raise
        return out

    def insert_segments(self, pairs: ArrayLike) -> NDArray[np.int64]:
        """Insert segments between vertex ids; returns their segment ids (a
        segment equal to a live one, either way round, returns that one's id).
        A vertex on a segment splits it; a crossing raises or is split as
        ``intersections`` says."""
        segs = self._as_pairs(pairs)
        if len(segs) == 0:
            return np.empty(0, np.int64)
        out = np.empty(len(segs), np.int64)
        fresh: list[tuple[int, int]] = []
        pending: dict[tuple[int, int], int] = {}
        for k, (a, b) in enumerate(segs.tolist()):
            key = (min(a, b), max(a, b))
            if key in self._seg_key:
                out[k] = self._seg_key[key]
            elif key in pending:
                out[k] = pending[key]
            else:
                out[k] = pending[key] = len(self._segs) + len(fresh)
                fresh.append((a, b))
        if not fresh:
            return out
        self._edits += 1
        old = self._segs, self._seg_alive, self._steiner.copy()
        self._segs = np.concatenate([self._segs, np.array(fresh, np.int64)])
        self._seg_alive = np.concatenate([self._seg_alive, np.ones(len(fresh), bool)])
        self._steiner[np.array(fresh).ravel()] = False     # a crossing point a segment ends at is kept
        try:
            if self._store is not None:
                self._insert_segment_tasks(np.arange(len(old[0]), len(self._segs)))
        except CDTError:
            self._segs, self._seg_alive = old[:2]
            self._steiner_buf[: len(old[2])] = old[2]
            raise
        self._seg_key.update(pending)
        return out

    def remove_vertices(self, ids: ArrayLike) -> None:
        """Remove vertices (and the segments that end at them), then rebuild."""
        idx = self._as_ids(ids, "vertex", self._alive)
        self._edits += 1
        self._change(lambda: self._alive.__setitem__(idx, False))

    def remove_segments(self, ids: ArrayLike) -> None:
        """Remove segments: their pieces become ordinary edges, flipped back to
        Delaunay (the store is rebuilt). Their vertices stay."""
        idx = self._as_ids(ids, "segment", self._seg_alive)
        self._edits += 1
        self._change(lambda: self._seg_alive.__setitem__(idx, False))

    def move_vertices(self, ids: ArrayLike, new_xy: ArrayLike) -> None:
        """Move vertices to new coordinates (their segments follow), then rebuild.
        Raises :class:`CDTError` if a vertex would land on another one."""
        idx = self._as_ids(ids, "vertex", self._alive)
        xy = _as_points(new_xy)
        if xy.shape != (len(idx), 2):
            raise InputShapeError(f"new_xy must have shape ({len(idx)}, 2), got {xy.shape}")
        if len(np.unique(idx)) != len(idx):
            raise CDTError("move_vertices: a vertex id is given twice")
        moved = self._xy.copy()
        moved[idx] = xy
        live = np.flatnonzero(self._alive)
        _, first, inverse = np.unique(moved[live], axis=0, return_index=True, return_inverse=True)
        clash = np.flatnonzero(first[inverse.reshape(-1)] != np.arange(len(live)))
        if len(clash):
            i = live[clash[0]]
            j = live[first[inverse.reshape(-1)[clash[0]]]]
            raise CDTError(f"move_vertices: vertices {j} and {i} would both be at "
                           f"({float(moved[i, 0])!r}, {float(moved[i, 1])!r})")
        self._edits += 1
        self._change(lambda: (self._xy.__setitem__(slice(None), moved),
                              self._steiner.__setitem__(idx, False)))    # (a moved crossing point is kept)

    def _change(self, edit) -> None:
        """Apply ``edit`` to the vertex or segment tables and rebuild; undo both
        if the rebuild fails (segments that cross after a move)."""
        saved = (self._xy.copy(), self._alive.copy(), self._seg_alive.copy(), self._store,
                 self._id_of, self._slot_of.copy(), self._last, self._adopted)
        steiner = self._steiner.copy()
        edit()
        ends = self._segs
        self._seg_alive &= self._alive[ends[:, 0]] & self._alive[ends[:, 1]]
        try:
            self._rebuild()
        except CDTError:
            (self._xy, self._alive, self._seg_alive, self._store, self._id_of, self._slot_of,
             self._last, self._adopted) = saved
            self._steiner_buf[: len(steiner)] = steiner
            self._grid_vertices = 0           # (the start grid is made again for this store)
            raise
        self._seg_key = {(min(a, b), max(a, b)): k for k, (a, b) in enumerate(self._segs.tolist())
                         if self._seg_alive[k]}

    # -------------------------------------------------------------- the store
    def _rebuild(self) -> None:
        """A new store from the live vertices (Delaunay), then every live segment."""
        if self._split and (self._steiner & self._alive).any():
            self._snap_round()          # (crossing points are derived: made again, or dropped)
            return
        self._build_store()
        todo = np.flatnonzero(self._seg_alive)
        if self._store is not None and len(todo):
            self._insert_segment_tasks(todo)

    def _build_store(self) -> None:
        """A new store from the live vertices (Delaunay), without segments; none
        while they are fewer than three or all collinear."""
        live = np.flatnonzero(self._alive)
        self._store = None
        self._slot_buf[: self._n] = -1
        self._id_of = np.empty(0, np.int64)
        self._adopted = 0
        self._grid_vertices = 0
        self._last = np.int64(0)
        if len(live) < 3:
            return
        store, order = _new_store(self._xy[live, 0].copy(), self._xy[live, 1].copy())
        if store is None:
            return                                       # all collinear: no triangle yet
        self._store = store
        self._id_of = np.full(store[6] + 1, -1, np.int64)
        self._id_of[: len(live)] = live[order]
        self._slot_of[live[order]] = np.arange(len(live))
        self._adopted = len(live)

    def _insert_segment_tasks(self, sids: NDArray[np.int64]) -> None:
        """Insert segments ``sids`` into the store (all or nothing). With
        ``"split"``, the first crossing stops the insertion (no room for a
        crossing point) and every live segment is snap-rounded at once instead
        (:meth:`_snap_round`), as :func:`cdt_plugin.triangulate` does; once
        segments cross, every later set of segments is rounded again, whole."""
        assert self._store is not None
        if self._split and (self._steiner & self._alive).any():
            self._snap_round()
            return
        store = self._store
        backup = tuple(a.copy() if isinstance(a, np.ndarray) else a for a in store)
        ends = self._segment_ends()
        tasks = np.column_stack([ends[sids], sids + 1])[::-1].copy()      # first segment on top
        status, info, store = insert_segments(store, tasks, ends, np.bool_(self._split), np.int64(0))
        if self._split and status == STOP_LIMIT:          # segments cross
            self._store = backup
            self._snap_round()
            return
        if status != ALL_DONE:
            self._store = backup
            self._raise_segment_stop(int(status), info)
        self._store = store
        self._adopt_new_slots(new_steiner=True)

    def _segment_ends(self) -> NDArray[np.int64]:
        """The store slots of every segment's ends (0 for a removed segment)."""
        return np.ascontiguousarray(np.where(self._seg_alive[:, None], self._slot_of[self._segs], 0))

    def _snap_round(self) -> None:
        """Snap-round every live segment over the live vertices that are not
        crossing points, as :func:`cdt_plugin.triangulate` does with them (hot
        pixels: the result depends on those vertices and the segments only,
        not on the order of the edits). The crossing points are derived: the
        last rounding's are dropped and the new ones made Steiner vertices
        (new ids); the store is built again and each segment goes in as its
        chain of pieces. All or nothing."""
        inputs = np.flatnonzero(self._alive & ~self._steiner)
        row = np.full(self._n, -1, np.int64)
        row[inputs] = np.arange(len(inputs))
        sids = np.flatnonzero(self._seg_alive)
        segs = np.ascontiguousarray(row[self._segs[sids]])    # (no segment ends at a crossing point)
        status, new_x, new_y, chains = ROUTE_OK, np.empty(0), np.empty(0), np.empty((0, 3), np.int64)
        if len(sids):
            status, _, new_x, new_y, chains = snap_route(
                self._xy[inputs, 0].copy(), self._xy[inputs, 1].copy(), segs, np.int64(-1))
        if status != ROUTE_OK:   # pragma: no cover - no cap on the crossing points
            raise CDTError(f"internal error (snap rounding status {status}); please report this input")
        saved = (self._n, self._alive.copy(), self._store, self._id_of, self._slot_of.copy(),
                 self._last, self._adopted)
        self._alive[self._steiner] = False
        ids = np.concatenate([inputs, self._append_vertices(np.column_stack([new_x, new_y]),
                                                            steiner=True)])
        try:
            self._build_store()
            if self._store is None or len(sids) == 0:   # (all collinear, or no segment left)
                return
            ends = self._segment_ends()
            slots = self._slot_of[ids]
            if len(chains):
                tasks = np.column_stack([slots[chains[:, 0]], slots[chains[:, 1]], sids[chains[:, 2]] + 1])
            else:
                tasks = np.column_stack([ends[sids], sids + 1])
            # (pieces that still cross are split, as the route does)
            status, info, store = insert_segments(self._store, tasks[::-1].copy(), ends,
                                                  np.bool_(True), np.int64(10 * len(ends) + 1000))
            if status != ALL_DONE:
                self._raise_segment_stop(int(status), info)
        except CDTError:
            n = saved[0]
            self._steiner_buf[n:self._n] = False
            self._slot_buf[n:self._n] = -1
            self._alive_buf[n:self._n] = False
            self._n = n
            self._alive, self._store, self._id_of, self._slot_of, self._last, self._adopted = saved[1:]
            self._grid_vertices = 0           # (the start grid is made again for this store)
            raise
        self._store = store
        self._adopt_new_slots(new_steiner=True)

    def _make_room(self, m: int) -> None:
        """Room in the store for ``m`` more vertices, a flip stack to match, and
        a start grid of about four vertices a cell (made again when the
        vertices doubled since)."""
        assert self._store is not None
        tri, twin, cons, x, y, w, inf, ntri, nv = self._store
        if nv + m > inf:
            tri, twin, cons, x, y, w, inf = grow_store(tri, twin, cons, x, y, w, inf, nv,
                                                        np.int64(nv + m + 16))
            self._store = (tri, twin, cons, x, y, w, inf, ntri, nv)
        if len(self._stack) < inf + 16:
            self._stack = np.empty(inf + 16, np.int64)
        if nv + m > 2 * self._grid_vertices:
            g = max(1, int(np.sqrt((nv + m) / 4)))
            self._grid, self._frame = start_grid(tri, x, y, inf, ntri, nv, np.int64(g))
            self._grid_vertices = nv + m

    def _adopt_new_slots(self, new_steiner: bool, slots: NDArray[np.int64] | None = None) -> None:
        """Give the store's new vertex slots (points just inserted, crossings)
        vertex ids, in the order ``slots`` lists them (default: slot order)."""
        assert self._store is not None
        x, y, inf, nv = self._store[3], self._store[4], self._store[6], int(self._store[8])
        if len(self._id_of) < inf + 1:
            self._id_of = _grown(self._id_of, inf + 1, -1)
        a = self._adopted
        if nv > a:
            if slots is None:
                slots = np.arange(a, nv)
            xy = np.empty((nv - a, 2))
            xy[:, 0] = x[slots]
            xy[:, 1] = y[slots]
            ids = self._append_vertices(xy, steiner=new_steiner)
            self._id_of[slots] = ids
            self._slot_buf[ids[0]:ids[-1] + 1] = slots
            self._adopted = nv

    def _append_vertices(self, xy: NDArray[np.float64], steiner: bool) -> NDArray[np.int64]:
        """New vertex ids for the points ``xy`` (the tables grow by doubling)."""
        first, m = self._n, len(xy)
        end = first + m
        if end > len(self._alive_buf):
            cap = max(2 * len(self._alive_buf), end)
            self._xy_buf = _grown(self._xy_buf, cap, 0.0)
            self._alive_buf = _grown(self._alive_buf, cap, False)
            self._steiner_buf = _grown(self._steiner_buf, cap, False)
            self._slot_buf = _grown(self._slot_buf, cap, -1)
        self._n = end
        self._xy_buf[first:end] = xy
        self._alive_buf[first:end] = True
        if steiner:
            self._steiner_buf[first:end] = True
        return np.arange(first, end, dtype=np.int64)

    def _raise_segment_stop(self, status: int, info: NDArray[np.int64]) -> None:
        if status in (STOP_CROSSING, STOP_OVERLAP):
            plc = SimpleNamespace(vertices=self._xy, segments=self._segs)
            raise_intersection(ROUTE_CROSSING if status == STOP_CROSSING else ROUTE_OVERLAP, info, plc)
        if status == STOP_LIMIT:
            s, t = int(info[0]) - 1, int(info[1]) - 1
            raise UnresolvedCrossingError(
                f"segments {s} and {t} still cross after the crossing points were inserted "
                "(they cross within rounding of other segments)", segments=(s, t))
        raise CDTError(f"internal error (segment status {status}, {info.tolist()}); please report this input")

    # ---------------------------------------------------------------- output
    def triangulation(self, domain: str = "hull") -> Triangulation:
        """An immutable :class:`Triangulation` of the current state (vertex ``i``
        of it is row ``i`` of :attr:`vertices`; ``vertex_map`` maps vertex ids to
        those rows, -1 for removed ones; ``segment_ids`` are segment ids).

        ``domain="hull"``: every triangle of the convex hull; ``"even-odd"``:
        the triangles at odd depth (an odd number of segments crossed from
        outside the hull), the rule of :func:`cdt_plugin.triangulate` without
        ``keep_hull``.
        """
        if domain not in DOMAINS:
            raise CDTError(f"domain must be one of {DOMAINS}, got {domain!r}")
        t0 = time.perf_counter()
        row_of = self._row_of()
        vertex_map = np.where(self._alive, row_of, -1).astype(np.int64)
        verts = self.vertices.copy()
        if self._store is None:
            T = np.empty((0, 3), np.int64)
            N, sid, keep = T.copy(), T.copy(), np.empty(0, bool)
        else:
            T, N, sid, keep = snapshot(self._store, np.bool_(domain == "even-odd"))
            T = row_of[self._id_of[T]]
        if not keep.all():
            new = np.cumsum(keep) - 1
            N = np.where(N >= 0, np.where(keep[np.maximum(N, 0)], new[np.maximum(N, 0)], -1), -1)
            T, N, sid = T[keep], N[keep], sid[keep]
        T, N = T.copy(), N.copy()
        turn = (np.arange(3)[None, :] + np.argmin(T, axis=1)[:, None]) % 3
        sid = np.take_along_axis(sid, turn, axis=1)       # as rotate_min_first turns the rows
        rotate_min_first(T, N)
        constrained = sid > 0
        t, j = np.nonzero(constrained)
        once = (N[t, j] < 0) | (t < N[t, j])
        t, j = t[once], j[once]
        segments = np.column_stack([T[t, (j + 1) % 3], T[t, (j + 2) % 3]]).astype(np.int64).reshape(-1, 2)
        stats: dict[str, Any] = {"vertices": len(verts), "segments": int(self._seg_alive.sum()),
                                 "edits": self._edits, "seconds": time.perf_counter() - t0}
        return Triangulation(verts, T, N, vertex_map, stats, constrained=constrained, segments=segments,
                             segment_ids=(sid[t, j] - 1).astype(np.int64),
                             steiner=row_of[np.flatnonzero(self._steiner & self._alive)].astype(np.int64))

    def locate(self, points: ArrayLike) -> NDArray[np.int64]:
        """:meth:`Triangulation.locate` on :meth:`triangulation`."""
        return self.triangulation().locate(points)

    # ------------------------------------------------------------ validation
    def _as_ids(self, ids: ArrayLike, what: str, alive: NDArray[np.bool_]) -> NDArray[np.int64]:
        arr = np.asarray(ids)
        if arr.size == 0:
            return np.empty(0, np.int64)
        if arr.dtype.kind not in "iu":
            raise UnknownIdError(f"{what} ids must be integers, got {arr.dtype}")
        arr = arr.reshape(-1).astype(np.int64)
        bad = arr[(arr < 0) | (arr >= len(alive))]
        if len(bad) == 0:
            bad = arr[~alive[arr]]
            if len(bad):
                raise UnknownIdError(f"{what} {int(bad[0])} was removed")
        else:
            raise UnknownIdError(f"there is no {what} {int(bad[0])} (ids are 0..{len(alive) - 1})")
        return arr

    def _as_pairs(self, pairs: ArrayLike) -> NDArray[np.int64]:
        arr = np.asarray(pairs)
        if arr.size == 0:
            return np.empty((0, 2), np.int64)
        if arr.ndim != 2 or arr.shape[1] != 2:
            raise InputShapeError(f"segments must have shape (s, 2), got {arr.shape}")
        self._as_ids(arr, "vertex", self._alive)
        arr = arr.astype(np.int64)
        same = np.flatnonzero(arr[:, 0] == arr[:, 1])
        if len(same):
            k = int(same[0])
            raise SegmentIndexError(f"segment {k} joins vertex {int(arr[k, 0])} to itself")
        return arr


def _new_store(px: NDArray[np.float64], py: NDArray[np.float64]) -> tuple[Store | None, NDArray[np.int64]]:
    """The Delaunay triangulation of the distinct points ``px, py`` as a store
    with room for a quarter more vertices, built as :func:`cdt_plugin.delaunay`
    builds it (divide and conquer, the halves on two threads for large sets).
    Returns ``(store, order)``: slot ``i`` holds point ``order[i]``; no store
    when the points are all collinear."""
    n = len(px)
    order = lexicographic_order(px, py)
    _, k2 = seed_triangle(px, py, order)
    if k2 < 0:
        return None, order
    room = max(16, n // 4)
    xi, yi, wi = gather_coords(px, py, np.zeros(n), order, np.int64(room))
    inf = n + room
    tri, twin, cons, ntri = build_divide(xi, yi, wi, n, np.full(n, -1, np.int64), max(4, 2 * inf + 2),
                                          resolve_workers(None, 2), inf, True)
    return (tri, twin, cons, xi, yi, wi, inf, np.int64(ntri), np.int64(n)), order


def _spatial_order(pts: NDArray[np.float64]) -> NDArray[np.int64]:
    """An order of the points along a Hilbert curve (each walk then starts near
    its point); the given order for a few points."""
    if len(pts) < 16:
        return np.arange(len(pts))
    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    keys = hilbert_keys(x, y, np.arange(len(pts), dtype=np.int64), np.int64(HILBERT_BITS))
    return np.argsort(keys, kind="stable")


def _grown(a: NDArray[Any], size: int, fill: Any) -> NDArray[Any]:
    """``a`` with ``size`` rows, the new ones ``fill``."""
    out = np.full((size,) + a.shape[1:], fill, a.dtype)
    out[: len(a)] = a
    return out


def _plain(v: float) -> bool:
    """A finite coordinate certainly in the predicates' range unscaled (what
    ``exact_range`` accepts without a shift, checked for one value)."""
    return v == 0.0 or _FINEST <= abs(v) < _LARGEST


_FINEST, _LARGEST = 2.0 ** -180, 2.0 ** 64


def _as_points(points: ArrayLike) -> NDArray[np.float64]:
    """(m, 2) finite float64 points in the exact predicates' range as given."""
    if (isinstance(points, np.ndarray) and points.dtype == np.float64 and points.size == 2
            and points.shape[-1] == 2 and points.ndim <= 2):
        # one point (a loop of single inserts): the checks below in a few operations
        x, y = float(points.flat[0]), float(points.flat[1])
        if _plain(x) and _plain(y):
            return points.reshape(1, 2)
    arr = as_queries(points)
    if len(arr) and exact_range(arr[:, 0], arr[:, 1], None, "points")[3] != 0:
        raise CoordinateRangeError("DynamicCDT keeps coordinates as given: these points are beyond "
                                   "the exact predicates' range without scaling (magnitudes up to 2**64 and "
                                   "no bit finer than 2**-240)")
    return arr
