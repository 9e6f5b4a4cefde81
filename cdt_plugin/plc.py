"""Planar straight-line complexes (Def. 2.8): the one currency between the
adapters and the engine.

A :class:`PLC` holds vertices, segments (pairs of vertex indices), hole seed
points and region seed points; when it comes from polygons it also knows its
rings (which segments form which ring, which ring is a hole of which polygon).
``PLC.from_geo_interface`` reads any object with ``__geo_interface__`` (or the
GeoJSON-like mapping itself) without importing a geometry library.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import CDTError, InputShapeError, NonFiniteCoordinateError, SegmentIndexError
from .validate import as_points


@dataclass
class PLC:
    """Vertices, segments, hole and region seeds of a planar domain.

    Attributes
    ----------
    vertices : (n, 2) float64
    segments : (m, 2) int64 vertex indices
    holes : (h, 2) float64, or None (None: inside/outside by depth parity)
    regions : (r, 4) float64 rows ``x, y, attribute, max_area`` (NaN: none), or None
    segment_ring : (m,) int64 ring of each segment, -1 for free segments
    ring_polygon : (R,) int64 polygon of each ring
    ring_is_hole : (R,) bool
    z : (n,) float64 or None, a third coordinate carried along (not used in meshing)
    degenerate_rings : list of (polygon, ring) rings dropped as rings (too few
        distinct points or zero area); their vertices stay as isolated vertices
    """

    vertices: np.ndarray
    segments: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.int64))
    holes: np.ndarray | None = None
    regions: np.ndarray | None = None
    segment_ring: np.ndarray | None = None
    ring_polygon: np.ndarray | None = None
    ring_is_hole: np.ndarray | None = None
    z: np.ndarray | None = None
    degenerate_rings: list = field(default_factory=list)

    @property
    def has_rings(self) -> bool:
        return self.ring_polygon is not None and len(self.ring_polygon) > 0

    @classmethod
    def from_geo_interface(cls, geometry) -> "PLC":
        """Read a geometry (an object with ``__geo_interface__`` or its mapping):
        Polygon, MultiPolygon, GeometryCollection, LinearRing, LineString,
        MultiLineString (constraints), Point, MultiPoint (isolated vertices).

        >>> plc = PLC.from_geo_interface({"type": "Polygon", "coordinates":
        ...     [[(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)], [(1, 1), (2, 1), (1, 2), (1, 1)]]})
        >>> len(plc.vertices), len(plc.segments), plc.ring_is_hole.tolist()
        (7, 7, [False, True])
        """
        builder = _Builder()
        builder.add(_mapping(geometry))
        return builder.finish()


def _mapping(geometry):
    gi = getattr(geometry, "__geo_interface__", geometry)
    if not isinstance(gi, dict) or "type" not in gi:
        raise InputShapeError(f"expected a geometry with __geo_interface__ or a GeoJSON-like "
                              f"mapping, got {type(geometry).__name__}")
    return gi


class _Builder:
    """Accumulates vertices, segments and rings from GeoJSON-like geometries."""

    def __init__(self):
        self.xy: list = []
        self.z: list = []
        self.has_z = False
        self.segs: list = []
        self.seg_ring: list = []
        self.ring_polygon: list = []
        self.ring_is_hole: list = []
        self.degenerate: list = []
        self.n_polygons = 0

    def _points(self, coords):
        arr = np.asarray(coords, dtype=np.float64)
        if arr.size == 0:
            return np.empty((0, 2)), np.empty(0)
        if arr.ndim != 2 or arr.shape[1] < 2:
            raise InputShapeError(f"coordinates must be (x, y[, z]) tuples, got shape {arr.shape}")
        if not np.isfinite(arr[:, :2]).all():
            bad = np.flatnonzero(~np.isfinite(arr[:, :2]).all(axis=1))
            raise NonFiniteCoordinateError(f"geometry has NaN or infinite coordinates at position(s) "
                                           f"{bad[:5].tolist()}")
        if arr.shape[1] > 2:
            self.has_z = True
            return arr[:, :2], arr[:, 2]
        return arr[:, :2], np.full(len(arr), np.nan)

    def _add_vertices(self, xy, z):
        start = sum(len(a) for a in self.xy)
        self.xy.append(xy)
        self.z.append(z)
        return start

    def add_ring(self, coords, polygon, is_hole, ring_no):
        xy, z = self._points(coords)
        if len(xy) > 1 and (xy[0] == xy[-1]).all():
            xy, z = xy[:-1], z[:-1]
        start = self._add_vertices(xy, z)
        distinct = len(np.unique(xy, axis=0)) if len(xy) else 0
        area2 = _shoelace2(xy) if len(xy) >= 3 else 0.0
        if distinct < 3 or (area2 == 0.0 and _all_collinear(xy)):
            # too few points or zero area: keep the points, not the ring
            self.degenerate.append((polygon, ring_no))
            return
        ring = len(self.ring_polygon)
        self.ring_polygon.append(polygon)
        self.ring_is_hole.append(is_hole)
        k = len(xy)
        idx = np.arange(start, start + k)
        self.segs.append(np.column_stack([idx, np.roll(idx, -1)]))
        self.seg_ring.append(np.full(k, ring))

    def add_line(self, coords):
        xy, z = self._points(coords)
        start = self._add_vertices(xy, z)
        if len(xy) >= 2:
            idx = np.arange(start, start + len(xy))
            self.segs.append(np.column_stack([idx[:-1], idx[1:]]))
            self.seg_ring.append(np.full(len(xy) - 1, -1))

    def add(self, gi):
        kind = gi["type"]
        coords = gi.get("coordinates")
        if kind == "Polygon":
            self._add_polygon(coords)
        elif kind == "MultiPolygon":
            for poly in coords:
                self._add_polygon(poly)
        elif kind == "LinearRing":
            self._add_polygon([coords])
        elif kind == "LineString":
            self.add_line(coords)
        elif kind == "MultiLineString":
            for line in coords:
                self.add_line(line)
        elif kind == "Point":
            if coords:
                self._add_vertices(*self._points([coords]))
        elif kind == "MultiPoint":
            self._add_vertices(*self._points(coords))
        elif kind == "GeometryCollection":
            for g in gi.get("geometries", []):
                self.add(_mapping(g))
        elif kind == "Feature":
            if gi.get("geometry"):
                self.add(_mapping(gi["geometry"]))
        else:
            raise InputShapeError(f"unsupported geometry type {kind!r}")

    def _add_polygon(self, rings):
        if not rings:
            return
        p = self.n_polygons
        self.n_polygons += 1
        for r, ring in enumerate(rings):
            self.add_ring(ring, p, r > 0, r)

    def finish(self) -> PLC:
        xy = np.concatenate(self.xy) if self.xy else np.empty((0, 2))
        z = np.concatenate(self.z) if self.z else np.empty(0)
        segs = np.concatenate(self.segs).astype(np.int64) if self.segs else np.empty((0, 2), np.int64)
        seg_ring = np.concatenate(self.seg_ring).astype(np.int64) if self.seg_ring else np.empty(0, np.int64)
        return PLC(np.ascontiguousarray(xy, dtype=np.float64), segs,
                   segment_ring=seg_ring,
                   ring_polygon=np.asarray(self.ring_polygon, np.int64),
                   ring_is_hole=np.asarray(self.ring_is_hole, bool),
                   z=z if self.has_z else None, degenerate_rings=self.degenerate)


def _shoelace2(xy):
    x, y = xy[:, 0], xy[:, 1]
    return float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _all_collinear(xy) -> bool:
    from .predicates import orient2d
    a = xy[0]
    others = xy[(xy != a).any(axis=1)]
    if len(others) == 0:
        return True
    b = others[0]
    return all(orient2d(a[0], a[1], b[0], b[1], c[0], c[1]) == 0 for c in xy)


def as_plc(vertices, segments=None, holes=None, regions=None) -> PLC:
    """Validate user arrays (or a geometry, or a PLC) into a :class:`PLC`,
    raising precise errors that name the offending rows."""
    checked = False
    if isinstance(vertices, PLC):
        plc = vertices
    elif hasattr(vertices, "__geo_interface__") or (isinstance(vertices, dict) and "type" in vertices):
        plc = PLC.from_geo_interface(vertices)
    else:
        plc = PLC(as_points(vertices, "vertices"))
        checked = True
    if segments is not None:
        if isinstance(vertices, PLC) or plc.has_rings:
            raise CDTError("pass segments either inside the PLC/geometry or as an array, not both")
        plc.segments = _as_segments(segments, len(plc.vertices))
        plc.segment_ring = np.full(len(plc.segments), -1, np.int64)
    else:
        plc.segments = _as_segments(plc.segments, len(plc.vertices))
    if holes is not None:
        plc.holes = _as_xy(holes, "holes")
    if regions is not None:
        plc.regions = _as_regions(regions)
    if len(plc.vertices) == 0:
        from .errors import TooFewPointsError
        raise TooFewPointsError("the input has no vertices")
    if not checked:
        plc.vertices = as_points(plc.vertices, "vertices")
    return plc


def _as_segments(segments, n) -> np.ndarray:
    arr = np.asarray(segments)
    if arr.size == 0:
        return np.empty((0, 2), np.int64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputShapeError(f"segments must have shape (m, 2), got {arr.shape}")
    if not np.issubdtype(arr.dtype, np.integer):
        as_int = np.asarray(arr, dtype=np.float64)
        bad = np.flatnonzero((as_int != np.round(as_int)).any(axis=1) | ~np.isfinite(as_int).all(axis=1))
        if bad.size:
            raise SegmentIndexError(f"segment {int(bad[0])} has non-integer vertex indices "
                                    f"{arr[bad[0]].tolist()}")
    arr = np.ascontiguousarray(arr, dtype=np.int64)
    if arr.min() < 0 or arr.max() >= n:
        bad = np.flatnonzero((arr[:, 0] < 0) | (arr[:, 0] >= n) | (arr[:, 1] < 0) | (arr[:, 1] >= n))
        i = int(bad[0])
        raise SegmentIndexError(
            f"segment {i} = {arr[i].tolist()} names a vertex outside 0..{n - 1}"
            + (f" ({bad.size} such segments)" if bad.size > 1 else ""))
    return arr


def _as_xy(points, name) -> np.ndarray:
    arr = np.asarray(points, dtype=np.float64)
    if arr.size == 0:
        return np.empty((0, 2))
    arr = arr.reshape(-1, 2) if arr.ndim == 1 and arr.size == 2 else arr
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputShapeError(f"{name} must have shape (h, 2), got {arr.shape}")
    if not np.isfinite(arr).all():
        raise NonFiniteCoordinateError(f"{name} has NaN or infinite coordinates")
    return arr


def _as_regions(regions) -> np.ndarray:
    arr = np.asarray(regions, dtype=np.float64)
    if arr.size == 0:
        return np.empty((0, 4))
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] not in (2, 3, 4):
        raise InputShapeError(f"regions must be rows (x, y[, attribute[, max_area]]), got {arr.shape}")
    out = np.full((len(arr), 4), np.nan)
    out[:, : arr.shape[1]] = arr
    if arr.shape[1] == 2:
        out[:, 2] = np.arange(len(arr))
    if not np.isfinite(out[:, :2]).all():
        raise NonFiniteCoordinateError("regions have NaN or infinite seed coordinates")
    return out
