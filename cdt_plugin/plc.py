"""Planar straight-line complexes (Def. 2.8): the one currency between the
adapters and the engine.

A :class:`PLC` holds vertices, segments (pairs of vertex indices), hole seed
points and region seed points; when it comes from polygons it also knows its
rings (which segments form which ring, which ring is a hole of which polygon).
``PLC.from_geo_interface`` reads any object with ``__geo_interface__`` (or the
GeoJSON-like mapping itself) without importing a geometry library.
"""
from __future__ import annotations

import dataclasses
import sys
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.rings import open_rings, polygon_rings
from .errors import CDTError, InputShapeError, NonFiniteCoordinateError, TooFewPointsError
from .types import GeometryLike
from .validate import as_points, as_segments, as_xy, raise_nonfinite, real_array


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

    vertices: NDArray[np.float64]
    segments: NDArray[np.int64] = field(default_factory=lambda: np.empty((0, 2), np.int64))
    holes: NDArray[np.float64] | None = None
    regions: NDArray[np.float64] | None = None
    segment_ring: NDArray[np.int64] | None = None
    ring_polygon: NDArray[np.int64] | None = None
    ring_is_hole: NDArray[np.bool_] | None = None
    z: NDArray[np.float64] | None = None
    degenerate_rings: list[tuple[int, int]] = field(default_factory=list)

    @property
    def has_rings(self) -> bool:
        return self.ring_polygon is not None and len(self.ring_polygon) > 0

    @classmethod
    def from_geo_interface(cls, geometry: GeometryLike) -> PLC:
        """Read a geometry (an object with ``__geo_interface__`` or its mapping):
        Polygon, MultiPolygon, GeometryCollection, LinearRing, LineString,
        MultiLineString (constraints), Point, MultiPoint (isolated vertices).

        >>> plc = PLC.from_geo_interface({"type": "Polygon", "coordinates":
        ...     [[(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)], [(1, 1), (2, 1), (1, 2), (1, 1)]]})
        >>> len(plc.vertices), len(plc.segments), plc.ring_is_hole.tolist()
        (7, 7, [False, True])
        """
        return _read_geometry(geometry, required=True)


def _read_geometry(obj, required):
    """The PLC of a geometry: a shapely-style polygon through its coordinate
    arrays, anything else through its GeoJSON-like mapping. None for input
    that is no geometry, unless ``required``."""
    plc = _shapely_polygon(obj)
    if plc is not None:
        return plc
    builder = _Builder()
    if not builder.add_geometry(obj):
        gi = _mapping(obj, required)
        if gi is None:
            return None
        builder.add(gi)
    return builder.finish()


def _shapely_polygon(obj):
    """The PLC of a 2D shapely Polygon (the common small call), its rings
    read in one GEOS call (the holes' sizes in one more) without the
    builder's bookkeeping: what the builder makes of it. None for anything
    else."""
    shapely = _shapely_of(obj)
    if shapely is None or type(obj) is not shapely.Polygon or obj.has_z:
        return None
    holes = int(shapely.get_num_interior_rings(obj))
    coords = shapely.get_coordinates(obj)      # (each ring closed: its last point is its first)
    if len(coords) == 0:
        return None
    if holes == 0:       # (the common case, without open_rings' call and bounds: about 1 µs less)
        xy = np.ascontiguousarray(coords[:-1])
        return _ring_plc(xy, np.zeros(1, np.int64), np.array([len(xy)]), np.zeros(1, np.int64),
                         np.zeros(1, bool), [(0, 0)])[0]
    sizes = shapely.get_num_coordinates(shapely.get_interior_ring(obj, np.arange(holes)))
    xy, bounds = open_rings(coords, sizes.astype(np.int64))
    if len(bounds) == 0:
        return None
    is_hole = np.ones(holes + 1, bool)
    is_hole[0] = False
    return _ring_plc(xy, bounds[:-1], bounds[1:], np.zeros(holes + 1, np.int64), is_hole,
                     [(0, r) for r in range(holes + 1)])[0]


def _ring_plc(xy, begin, end, ring_polygon, ring_is_hole, ring_name, z=None):
    """``(plc, degenerate)``: the PLC of rings ``xy[begin[r]:end[r]]``
    (polygon ``ring_polygon[r]``, a hole or not; ``ring_name[r]`` names it in
    errors), their segments made in one compiled pass, a degenerate ring's
    points kept as isolated vertices and named; and which rings were
    degenerate. :class:`NonFiniteCoordinateError` for NaN or infinite coordinates."""
    bad, degenerate, n_degenerate, segs, seg_ring = polygon_rings(xy, begin, end)
    if bad >= 0:
        rows = np.flatnonzero(~(np.isfinite(xy[:, 0]) & np.isfinite(xy[:, 1])))
        raise NonFiniteCoordinateError(f"geometry has NaN or infinite coordinates at vertex "
                                       f"position(s) {rows[:5].tolist()}")
    names = []
    if n_degenerate:
        kept = ~degenerate
        names = [ring_name[r] for r in np.flatnonzero(degenerate)]
        ring_polygon, ring_is_hole = ring_polygon[kept], ring_is_hole[kept]
    return PLC(xy, segs, segment_ring=seg_ring, ring_polygon=ring_polygon, ring_is_hole=ring_is_hole,
               z=z, degenerate_rings=names), degenerate


def _shapely_of(geometry):
    """The shapely module when ``geometry`` is a shapely geometry (shapely is
    then imported already), else None: shapely is not a dependency here."""
    return sys.modules.get("shapely") if type(geometry).__module__.startswith("shapely.") else None


def _mapping(obj, required=True):
    """The GeoJSON-like mapping of ``obj`` (its ``__geo_interface__``, read
    once: shapely builds it anew on every access). Input that is no geometry
    gives None, or an error when ``required``; a malformed
    ``__geo_interface__`` is always an error."""
    if isinstance(obj, dict):
        gi, malformed = (obj if "type" in obj else None), False
    else:
        gi = getattr(obj, "__geo_interface__", None)
        malformed = gi is not None and not (isinstance(gi, dict) and "type" in gi)
    if malformed or (gi is None and required):
        raise InputShapeError(f"expected a geometry with __geo_interface__ or a GeoJSON-like "
                              f"mapping, got {type(obj).__name__}")
    return gi


class _Builder:
    """Accumulates vertices, rings and lines from GeoJSON-like geometries; the
    rings become segments in one compiled pass (:mod:`cdt_plugin._core.rings`)."""

    def __init__(self):
        self.xy: list = []
        self.z: list = []            # (first vertex, z values) of the parts that have Z
        self.nv = 0
        self.pieces: list = []       # ring numbers and arrays of line segments, in input order
        self.ring_begin: list = []
        self.ring_end: list = []
        self.ring_polygon: list = []
        self.ring_is_hole: list = []
        self.ring_name: list = []    # (polygon, ring within it) for error messages
        self.n_polygons = 0
        self.has_lines = False

    def _add_vertices(self, coords, closed=False) -> int:
        """Append the (x, y[, z]) rows (a ring's closing point dropped); returns how many."""
        arr = real_array(coords, "coordinates")
        if arr.size == 0:
            return 0
        if arr.ndim != 2 or arr.shape[1] < 2:
            raise InputShapeError(f"coordinates must be (x, y[, z]) tuples, got shape {arr.shape}")
        if closed and len(arr) > 1 and arr[0, 0] == arr[-1, 0] and arr[0, 1] == arr[-1, 1]:
            arr = arr[:-1]
        if arr.shape[1] > 2:
            self.z.append((self.nv, arr[:, 2]))
        self.xy.append(arr[:, :2])
        self.nv += len(arr)
        return len(arr)

    def add_ring(self, coords, polygon, is_hole, ring_no):
        start = self.nv
        self._add_vertices(coords, closed=True)
        self.pieces.append(len(self.ring_begin))
        self.ring_begin.append(start)
        self.ring_end.append(self.nv)
        self.ring_polygon.append(polygon)
        self.ring_is_hole.append(is_hole)
        self.ring_name.append((polygon, ring_no))

    def add_line(self, coords):
        start = self.nv
        k = self._add_vertices(coords)
        if k >= 2:
            idx = np.arange(start, start + k)
            self.pieces.append(np.column_stack([idx[:-1], idx[1:]]))
            self.has_lines = True

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
                self._add_vertices([coords])
        elif kind == "MultiPoint":
            self._add_vertices(coords)
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

    def add_geometry(self, geometry) -> bool:
        """Read a shapely-style Polygon or MultiPolygon through its coordinate
        arrays (``exterior.coords``, ``interiors``, ``geoms``): the same rings as
        its ``__geo_interface__``, which shapely builds as a tuple per
        coordinate on every access (most of a small call's time). Returns
        False for anything else."""
        kind = getattr(geometry, "geom_type", None)
        if kind == "Polygon" and hasattr(geometry, "exterior"):
            polygons = (geometry,)
        elif kind == "MultiPolygon" and hasattr(geometry, "geoms"):
            polygons = geometry.geoms
        else:
            return False
        shapely = _shapely_of(geometry)
        for polygon in polygons:
            if shapely is not None and shapely.get_num_interior_rings(polygon) == 0:
                # no holes: the one ring is all of its coordinates, read in one GEOS
                # call (the ring object and its coordinate sequence cost more; ring
                # objects for the holes cost more than their coordinate sequences)
                coords = shapely.get_coordinates(polygon, include_z=polygon.has_z)
                if len(coords):
                    self._add_polygon([coords])
            elif not polygon.is_empty:
                self._add_polygon([polygon.exterior.coords]
                                  + [hole.coords for hole in polygon.interiors])
        return True

    def finish(self) -> PLC:
        if not self.xy:
            xy = np.empty((0, 2))
        else:
            xy = np.ascontiguousarray(self.xy[0] if len(self.xy) == 1 else np.concatenate(self.xy))
        begin = np.array(self.ring_begin, np.int64)
        end = np.array(self.ring_end, np.int64)
        z = None
        if self.z:
            z = np.full(len(xy), np.nan)
            for start, values in self.z:
                z[start:start + len(values)] = values
        plc, degenerate = _ring_plc(xy, begin, end, np.array(self.ring_polygon, np.int64),
                                    np.array(self.ring_is_hole, bool), self.ring_name, z)
        if self.has_lines:
            plc.segments, plc.segment_ring = self._in_input_order(plc.segments, plc.segment_ring,
                                                                  ~degenerate, begin, end)
        return plc

    def _in_input_order(self, ring_segs, ring_of, kept, begin, end):
        """Rings' and lines' segments interleaved as the input gave them."""
        offsets = np.concatenate([[0], np.cumsum((end - begin)[kept])])
        kept_no = np.cumsum(kept) - 1
        seg_parts, ring_parts = [], []
        for p in self.pieces:
            if not isinstance(p, int):
                seg_parts.append(p)
                ring_parts.append(np.full(len(p), -1, np.int64))
            elif kept[p]:
                j = kept_no[p]
                seg_parts.append(ring_segs[offsets[j]:offsets[j + 1]])
                ring_parts.append(ring_of[offsets[j]:offsets[j + 1]])
        return (np.concatenate(seg_parts).astype(np.int64),
                np.concatenate(ring_parts).astype(np.int64))


def as_plc(vertices: ArrayLike | PLC | GeometryLike, segments: ArrayLike | None = None,
           holes: ArrayLike | None = None, regions: ArrayLike | None = None) -> PLC:
    """Validate user arrays (or a geometry, or a PLC) into a :class:`PLC`,
    raising precise errors that name the offending rows. A PLC passed in is
    not changed: the result is a checked copy."""
    if isinstance(vertices, PLC):
        if segments is not None:
            raise CDTError("pass segments either inside the PLC/geometry or as an array, not both")
        pts = as_points(vertices.vertices, "vertices")
        plc = dataclasses.replace(vertices, vertices=pts,
                                  segments=as_segments(vertices.segments, len(pts)))
    else:
        plc = _read_geometry(vertices, required=False)   # its vertices checked, segments valid
        if plc is not None:
            if segments is not None:
                raise CDTError("pass segments either inside the PLC/geometry or as an array, not both")
            if len(plc.vertices) == 0:
                raise TooFewPointsError("the input has no vertices")
        else:
            pts = as_points(cast(ArrayLike, vertices), "vertices")     # (no geometry: arrays)
            segs = _NO_SEGMENTS if segments is None else as_segments(segments, len(pts))
            plc = PLC(pts, segs, segment_ring=np.full(len(segs), -1, np.int64))
    if holes is not None:
        plc.holes = as_xy(holes, "holes", "h", pair=True, empty=True)
    if regions is not None:
        plc.regions = _as_regions(regions)
    return plc


_NO_SEGMENTS = np.empty((0, 2), np.int64)


def _as_regions(regions) -> np.ndarray:
    arr = real_array(regions, "regions")
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
    raise_nonfinite(out, "regions")
    return out
