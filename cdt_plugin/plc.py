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
from typing import Any, Iterator, Mapping, NamedTuple, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.rings import drop_closing_points, open_rings, polygon_rings
from .errors import CDTError, InputShapeError, NonFiniteCoordinateError, TooFewPointsError
from .planar import ring_projection
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
        (3D input: rows of five, ``x, y, z, attribute, max_area``, until
        projected on its plane)
    segment_ring : (m,) int64 ring of each segment, -1 for free segments
    ring_polygon : (R,) int64 polygon of each ring
    ring_is_hole : (R,) bool
    z : (n,) float64 or None, a third coordinate carried along (not used in meshing)
    degenerate_rings : list of (polygon, ring) rings dropped as rings (too few
        distinct points or zero area); their vertices stay as isolated vertices
    vertex_markers, segment_markers : (n,) and (m,) int, or None
        Boundary markers to carry (:func:`cdt_plugin.triangulate`'s keywords of
        the same names, which win over these).
    vertex_attributes : (n,) or (n, k) float, or None
        Vertex attributes to carry (likewise).
    empty_rings : list of (polygon, ring) EMPTY rings (no points at all, as in
        ``POLYGON ((...), EMPTY)``), dropped as GEOS drops them; named in the
        triangulation's ``stats["empty_rings"]``
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
    vertex_markers: ArrayLike | None = None
    segment_markers: ArrayLike | None = None
    vertex_attributes: ArrayLike | None = None
    empty_rings: list[tuple[int, int]] = field(default_factory=list)

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
    """The PLC of a geometry: a shapely Polygon or MultiPolygon through
    :func:`shapely_polygon_rings`, anything else through its GeoJSON-like
    mapping (:func:`geojson_parts`). None for input that is no geometry,
    unless ``required``."""
    shapely = shapely_of(obj)
    kind = type(obj)
    if shapely is not None and (kind is shapely.Polygon or kind is shapely.MultiPolygon):
        # (the one Polygon's reader called directly: a small call pays for every Python call)
        rings = (_one_polygon_rings(shapely, obj) if kind is shapely.Polygon
                 else shapely_polygon_rings(shapely, obj))
        if len(rings.ring_start):     # (else a ring that does not close, an EMPTY hole: the builder names it)
            return ring_plc(rings.xy, rings.ring_start[:-1], rings.ring_start[1:], rings.ring_polygon,
                            rings.ring_is_hole, rings.z)[0]
    gi = _mapping(obj, required)
    if gi is None:
        return None
    builder = _Builder()
    builder.add(gi)
    return builder.finish()


class PolygonRings(NamedTuple):
    """Polygons as flat ring arrays, each ring's closing point dropped:
    geometry ``g`` holds rings ``geom_ring_start[g]:geom_ring_start[g + 1]``,
    ring ``r`` the points ``xy[ring_start[r]:ring_start[r + 1]]`` (exterior
    first, then its holes, polygon by polygon)."""

    xy: NDArray[np.float64]              # (n, 2)
    z: NDArray[np.float64] | None        # (n,), None when no geometry has Z
    ring_start: NDArray[np.int64]        # (R + 1,)
    geom_ring_start: NDArray[np.int64]   # (G + 1,)
    ring_polygon: NDArray[np.int64]      # (R,) polygon of each ring within its geometry
    ring_is_hole: NDArray[np.bool_]      # (R,)


def shapely_polygon_rings(shapely: Any, geoms: Any) -> PolygonRings:
    """The one reader of shapely polygons: the rings of a Polygon or
    MultiPolygon, or of a 1-D object array of them (empty parts dropped), read
    from GEOS coordinate arrays, the same rings and order as their
    ``__geo_interface__``. ``shapely`` is the module, passed in: the engine
    does not import it.

    The coordinates come in one GEOS call, their ring sizes in a few more; the
    closing points are dropped in one compiled pass
    (:func:`cdt_plugin._core.rings.drop_closing_points`)."""
    if type(geoms) is shapely.Polygon:
        return _one_polygon_rings(shapely, geoms)
    if type(geoms) is shapely.MultiPolygon:
        return _one_multipolygon_rings(shapely, geoms)
    coords = shapely.get_coordinates(geoms, include_z=bool(shapely.has_z(geoms).any()))
    ring_len, ring_geom, ring_polygon, ring_is_hole = _layer_layout(shapely, geoms)
    geom_ring_start = np.searchsorted(ring_geom, np.arange(len(geoms) + 1)).astype(np.int64)
    points, ring_start = _open_rings(coords, ring_len)
    return PolygonRings(np.ascontiguousarray(points[:, :2]),
                        points[:, 2].copy() if points.shape[1] > 2 else None, ring_start,
                        geom_ring_start, ring_polygon, ring_is_hole)


def _one_polygon_rings(shapely, polygon):
    """:func:`shapely_polygon_rings` of one Polygon (the common small call):
    the holes' sizes in one GEOS call, the shell the rest of the coordinates;
    without holes, the one ring is all of them."""
    has_z = polygon.has_z
    coords = shapely.get_coordinates(polygon, include_z=has_z)
    holes = int(shapely.get_num_interior_rings(polygon))
    if holes == 0 and len(coords):     # (the common case, without the compiled call: 1 µs less)
        points, ring_start, ring_is_hole = coords[:-1], np.array([0, len(coords) - 1]), np.zeros(1, bool)
    elif len(coords):                  # (the shell's size is what the holes leave)
        hole_sizes = shapely.get_num_coordinates(shapely.get_interior_ring(polygon, np.arange(holes)))
        points, ring_start = open_rings(coords, hole_sizes.astype(np.int64))
        ring_is_hole = np.ones(holes + 1, bool)
        ring_is_hole[0] = False
    else:
        points, ring_start, ring_is_hole = coords, np.zeros(1, np.int64), np.zeros(0, bool)
    rings = len(ring_is_hole)
    return PolygonRings(np.ascontiguousarray(points[:, :2]) if has_z else points,
                        points[:, 2].copy() if has_z else None, ring_start,
                        _ONE_RING if rings == 1 else np.array([0, rings]), np.zeros(rings, np.int64),
                        ring_is_hole)


def _open_rings(coords, ring_len):
    """:func:`~cdt_plugin._core.rings.drop_closing_points` of rings as GEOS
    holds them, where an EMPTY ring (a hole without points) has no closing
    point: it stays a ring of no points, which the PLC names as degenerate,
    rather than refusing every ring of the layer."""
    empty = ring_len == 0
    if not empty.any():
        return drop_closing_points(coords, ring_len)
    points, start = drop_closing_points(coords, ring_len[~empty])
    if len(start) == 0:
        return points, start
    sizes = np.zeros(len(ring_len), np.int64)
    sizes[~empty] = np.diff(start)
    return points, np.concatenate([[0], np.cumsum(sizes)])


_ONE_RING = np.array([0, 1])            # (geom_ring_start of a Polygon without holes: read only)
_ONE_RING.flags.writeable = False


def _one_multipolygon_rings(shapely, multipolygon):
    """:func:`shapely_polygon_rings` of one MultiPolygon."""
    has_z = multipolygon.has_z
    coords = shapely.get_coordinates(multipolygon, include_z=has_z)
    ring_len, _, ring_is_hole = _rings_of_polygons(shapely, shapely.get_parts(multipolygon))
    points, ring_start = _open_rings(coords, ring_len)
    return PolygonRings(np.ascontiguousarray(points[:, :2]), points[:, 2].copy() if has_z else None,
                        ring_start, np.array([0, len(ring_len)]), np.cumsum(~ring_is_hole) - 1,
                        ring_is_hole)


def _rings_of_polygons(shapely, polygons):
    """``(ring_len, ring_part, ring_is_hole)`` of an array of Polygons, in the
    order of their coordinates: their rings in one GEOS call, the rings' sizes
    in one more (an empty Polygon has none)."""
    rings, ring_part = shapely.get_rings(polygons, return_index=True)
    ring_is_hole = np.zeros(len(rings), bool)
    ring_is_hole[1:] = ring_part[1:] == ring_part[:-1]                   # exterior first
    return shapely.get_num_coordinates(rings).astype(np.int64), ring_part, ring_is_hole


def _layer_layout(shapely, geoms):
    """``(ring_len, ring_geom, ring_polygon, ring_is_hole)`` of every ring of
    an array of Polygons / MultiPolygons, in the order of their coordinates.

    Most geometries of a layer are Polygons without holes, whose one ring is
    all of their coordinates; only the others are taken apart into ring
    objects (which GEOS makes one by one, holding the GIL: on a layer of
    100,000 polygons that was half of the reading time, and it did not run
    faster on threads)."""
    n_coords = shapely.get_num_coordinates(geoms).astype(np.int64)
    simple = (shapely.get_type_id(geoms) == 3) & (shapely.get_num_interior_rings(geoms) == 0)
    s_geom = np.flatnonzero(simple & (n_coords > 0))
    others = np.flatnonzero(~simple)
    parts, part_geom = shapely.get_parts(geoms[others], return_index=True)
    o_len, ring_part, o_hole = _rings_of_polygons(shapely, parts)
    o_geom = others[part_geom[ring_part]]
    shells = np.cumsum(~o_hole)
    o_polygon = shells - shells[np.searchsorted(o_geom, o_geom)]     # polygon number in its geometry
    ring_geom = np.concatenate([s_geom, o_geom])
    by = np.argsort(ring_geom, kind="stable")                        # the order of the coordinates
    return (np.concatenate([n_coords[s_geom], o_len])[by], ring_geom[by],
            np.concatenate([np.zeros(len(s_geom), np.int64), o_polygon])[by],
            np.concatenate([np.zeros(len(s_geom), bool), o_hole])[by])


def ring_plc(xy: NDArray[np.float64], begin: NDArray[np.int64], end: NDArray[np.int64],
             ring_polygon: NDArray[np.int64], ring_is_hole: NDArray[np.bool_],
             z: NDArray[np.float64] | None = None, *,
             check_finite: bool = True) -> tuple[PLC, NDArray[np.bool_]]:
    """The one place rings become a PLC.

    Parameters
    ----------
    xy : (n, 2) float64, C-contiguous
        Ring vertices without closing points.
    begin, end : (r,) int64
        Ring ``i`` is ``xy[begin[i]:end[i]]``.
    ring_polygon : (r,) int64
        The polygon each ring belongs to.
    ring_is_hole : (r,) bool
        Whether each ring is a hole of its polygon.
    z : (n,) float64, optional
        Z of the vertices, kept on the PLC.
    check_finite : bool
        Raise :class:`NonFiniteCoordinateError` here for NaN or infinite
        coordinates; ``False`` leaves them to the validation of the
        triangulation, whose message names the first bad row.

    Returns
    -------
    plc : PLC
        The rings' edges as segments (made in one compiled pass); a degenerate
        ring's points kept as isolated vertices and named ``(polygon, ring
        within it)`` in ``degenerate_rings``; a ring without points (EMPTY)
        dropped and named in ``empty_rings``.
    degenerate : (r,) bool
        Which rings were degenerate.

    Examples
    --------
    >>> import numpy as np
    >>> xy = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1], [1, 1.0]])
    >>> plc, degenerate = ring_plc(xy, np.array([0, 4]), np.array([4, 6]), np.array([0, 0]),
    ...                            np.array([False, True]))
    >>> len(plc.segments), plc.degenerate_rings, degenerate.tolist()
    (4, [(0, 1)], [False, True])
    """
    bad, degenerate, n_degenerate, segs, seg_ring = polygon_rings(
        xy if z is None else ring_projection(xy, z, begin, end), begin, end)
    if bad >= 0 and check_finite:
        rows = np.flatnonzero(~(np.isfinite(xy[:, 0]) & np.isfinite(xy[:, 1])))
        raise NonFiniteCoordinateError(f"geometry has NaN or infinite coordinates at vertex "
                                       f"position(s) {rows[:5].tolist()}")
    names: list[tuple[int, int]] = []
    empty_names: list[tuple[int, int]] = []
    if n_degenerate:
        rank = _rank_in_polygon(ring_polygon)
        empty = degenerate & (end == begin)
        names = [(int(ring_polygon[r]), int(rank[r])) for r in np.flatnonzero(degenerate & ~empty)]
        empty_names = [(int(ring_polygon[r]), int(rank[r])) for r in np.flatnonzero(empty)]
        kept = ~degenerate
        ring_polygon, ring_is_hole = ring_polygon[kept], ring_is_hole[kept]
    return PLC(xy, segs, segment_ring=seg_ring, ring_polygon=ring_polygon,
               ring_is_hole=ring_is_hole, z=z, degenerate_rings=names,
               empty_rings=empty_names), degenerate


def _rank_in_polygon(ring_polygon: NDArray[np.int64]) -> NDArray[np.int64]:
    """Each ring's number within its polygon: how many rings of the same
    polygon come before it (the rings of a polygon need not be consecutive)."""
    order = np.argsort(ring_polygon, kind="stable")
    grouped = ring_polygon[order]
    rank = np.empty(len(ring_polygon), np.int64)
    rank[order] = np.arange(len(grouped)) - np.searchsorted(grouped, grouped)
    return rank


def shapely_of(geometry: object) -> Any:
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


#: The GeoJSON geometry types (RFC 7946).
GEOJSON_GEOMETRIES = ("Point", "MultiPoint", "LineString", "MultiLineString", "Polygon",
                      "MultiPolygon", "GeometryCollection")


def geojson_parts(gi: Mapping[str, Any], *, features: bool = False) -> Iterator[tuple[str, Any]]:
    """The one walker of GeoJSON-like mappings: ``(type, coordinates)`` of every
    geometry that is no collection, depth first in input order. A
    GeometryCollection's members (mappings, or objects with
    ``__geo_interface__``) and a Feature's geometry are opened (a Feature
    without geometry gives nothing); a FeatureCollection's features too when
    ``features``, else it is given as it is, as is any other type (the caller
    decides what it reads).

    >>> [kind for kind, _ in geojson_parts({"type": "GeometryCollection", "geometries": [
    ...     {"type": "Point", "coordinates": (0, 0)},
    ...     {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [(0, 0), (1, 1)]}}]})]
    ['Point', 'LineString']
    """
    kind = gi["type"]
    if kind == "GeometryCollection":
        for g in gi.get("geometries", []):
            yield from geojson_parts(_mapping(g), features=features)
    elif kind == "Feature":
        if gi.get("geometry"):
            yield from geojson_parts(_mapping(gi["geometry"]), features=features)
    elif kind == "FeatureCollection" and features:
        for f in gi.get("features") or []:
            yield from geojson_parts(_mapping(f), features=features)
    else:
        yield kind, gi.get("coordinates")


def geojson_features(gi: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """The features of a GeoJSON mapping: a FeatureCollection's, a Feature
    itself, a bare geometry as a Feature without properties.
    :class:`InputShapeError` for any other type."""
    kind = gi.get("type")
    if kind == "FeatureCollection":
        return list(gi.get("features") or [])
    if kind == "Feature":
        return [gi]
    if kind in GEOJSON_GEOMETRIES:
        return [{"type": "Feature", "geometry": gi, "properties": {}}]
    raise InputShapeError(f"expected a GeoJSON FeatureCollection, Feature or geometry, "
                          f"got type {kind!r}")


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
        self.n_polygons = 0
        self.has_lines = False

    def _add_vertices(self, coords, closed=False) -> int:
        """Append the (x, y[, z]) rows (a ring's closing point dropped); returns how many."""
        arr = real_array(coords, "coordinates")
        if arr.size == 0:
            return 0
        if arr.ndim != 2 or arr.shape[1] < 2:
            raise InputShapeError(f"coordinates must be (x, y[, z]) tuples, got shape {arr.shape}")
        # (every coordinate compared: the two ends of a vertical ring's edge share x, y)
        if closed and len(arr) > 1 and np.array_equal(arr[0], arr[-1], equal_nan=True):
            arr = arr[:-1]
        if arr.shape[1] > 2:
            self.z.append((self.nv, arr[:, 2]))
        self.xy.append(arr[:, :2])
        self.nv += len(arr)
        return len(arr)

    def add_ring(self, coords, polygon, is_hole):
        start = self.nv
        self._add_vertices(coords, closed=True)
        self.pieces.append(len(self.ring_begin))
        self.ring_begin.append(start)
        self.ring_end.append(self.nv)
        self.ring_polygon.append(polygon)
        self.ring_is_hole.append(is_hole)

    def add_line(self, coords):
        start = self.nv
        k = self._add_vertices(coords)
        if k >= 2:
            idx = np.arange(start, start + k)
            self.pieces.append(np.column_stack([idx[:-1], idx[1:]]))
            self.has_lines = True

    def add(self, gi):
        """Add every part of a GeoJSON-like mapping (:func:`geojson_parts`)."""
        for kind, coords in geojson_parts(gi):
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
            else:
                raise InputShapeError(f"unsupported geometry type {kind!r}")

    def _add_polygon(self, rings):
        if not rings:
            return
        p = self.n_polygons
        self.n_polygons += 1
        for r, ring in enumerate(rings):
            self.add_ring(ring, p, r > 0)

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
        plc, degenerate = ring_plc(xy, begin, end, np.array(self.ring_polygon, np.int64),
                                   np.array(self.ring_is_hole, bool), z)
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
            z = None
            try:                                                    # (no geometry: arrays)
                pts = as_points(cast(ArrayLike, vertices), "vertices")
            except InputShapeError:       # (n, 3): 3D, meshed in its plane (cdt_plugin.planar)
                pts, z = _xy_and_z(vertices)
            segs = _NO_SEGMENTS if segments is None else as_segments(segments, len(pts))
            plc = PLC(pts, segs, segment_ring=np.full(len(segs), -1, np.int64), z=z)
    if holes is not None:
        plc.holes = (as_xy(holes, "holes", "h", pair=True, empty=True) if plc.z is None
                     else _seeds_of_3d(holes))
    if regions is not None:
        plc.regions = _as_regions(regions, plc.z is not None)
    return plc


def _xy_and_z(vertices: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The x, y and z of (n, 3) vertices (all finite); the (n, 2) shape error
    for anything else."""
    arr = real_array(vertices, "vertices")
    if arr.ndim != 2 or arr.shape[1] != 3 or len(arr) == 0:
        as_points(arr, "vertices")          # (raises the error for its shape)
        raise InputShapeError(f"vertices must have shape (n, 2) or (n, 3), got {arr.shape}")
    _raise_nonfinite_3d(arr, "vertices")
    return np.ascontiguousarray(arr[:, :2]), np.ascontiguousarray(arr[:, 2])


def _raise_nonfinite_3d(arr: NDArray[np.float64], name: str) -> None:
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if len(bad):
        raise NonFiniteCoordinateError(f"{name} has NaN or infinite coordinates at row(s) "
                                       f"{bad[:5].tolist()} (row {int(bad[0])} is {arr[bad[0]].tolist()})")


def _seeds_of_3d(holes: Any) -> NDArray[np.float64]:
    """Hole seeds of 3D input: (h, 3) points (projected on the plane with the
    vertices) or (h, 2) points in the triangulation's 2D coordinates."""
    arr = real_array(holes, "holes")
    if arr.ndim == 2 and arr.shape[1] == 3:
        _raise_nonfinite_3d(arr, "holes")
        return np.ascontiguousarray(arr)
    return as_xy(holes, "holes", "h", pair=True, empty=True)


_NO_SEGMENTS = np.empty((0, 2), np.int64)
RING_ROLES = ("exterior", "holes")


def ring_markers(plc: PLC, markers: int | Mapping[str, int]) -> NDArray[np.int64]:
    """Segment markers that mark each ring of ``plc`` (a PLC of polygons) by its
    role: ``markers`` one integer for every ring, or a mapping
    ``{"exterior": e, "holes": h}`` (a role left out: 0, Triangle's "unmarked",
    so the boundary default 1 applies). Segments of no ring (lines) get 0.
    :class:`InputShapeError` for anything else.

    >>> plc = PLC.from_geo_interface({"type": "Polygon", "coordinates":
    ...     [[(0, 0), (4, 0), (4, 4), (0, 0)], [(1, 0.5), (3, 1), (3, 2), (1, 0.5)]]})
    >>> ring_markers(plc, {"exterior": 1, "holes": 2}).tolist()
    [1, 1, 1, 2, 2, 2]
    """
    if isinstance(markers, Mapping):
        unknown = set(markers) - set(RING_ROLES)
        if unknown:
            raise InputShapeError(f"markers keys must be among {RING_ROLES}, got {sorted(map(str, unknown))}")
        exterior, holes = (_ring_marker(markers.get(role, 0), role) for role in RING_ROLES)
    else:
        exterior = holes = _ring_marker(markers, "every ring")
    ring = plc.segment_ring if plc.segment_ring is not None else np.full(len(plc.segments), -1)
    is_hole = plc.ring_is_hole if plc.ring_is_hole is not None else np.zeros(0, bool)
    out = np.zeros(len(plc.segments), np.int64)
    on_ring = ring >= 0
    out[on_ring] = np.where(is_hole[ring[on_ring]], holes, exterior)
    return out


def _ring_marker(value: Any, role: str) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputShapeError(f"the marker of {role} must be an integer, got {value!r}")
    return int(value)


def _as_regions(regions: Any, three_d: bool = False) -> np.ndarray:
    """Region seeds as (r, 4) rows ``x, y, attribute, max_area`` (a missing
    attribute: the row's index; a missing max_area: NaN); for 3D input
    (``three_d``) rows of five, ``x, y, z, attribute, max_area``, are 3D
    seeds, kept as they are (projected on the plane with the vertices)."""
    arr = real_array(regions, "regions")
    if arr.size == 0:
        return np.empty((0, 4))
    if arr.ndim == 1:
        arr = arr[None, :]
    if three_d and arr.ndim == 2 and arr.shape[1] == 5:
        _raise_nonfinite_3d(arr[:, :3], "regions")
        return np.array(arr, np.float64)
    if arr.ndim != 2 or arr.shape[1] not in (2, 3, 4):
        raise InputShapeError(f"regions must be rows (x, y[, attribute[, max_area]])"
                              f"{' or, in 3D, (x, y, z, attribute, max_area)' if three_d else ''}, "
                              f"got {arr.shape}")
    out = np.full((len(arr), 4), np.nan)
    out[:, : arr.shape[1]] = arr
    if arr.shape[1] == 2:
        out[:, 2] = np.arange(len(arr))
    raise_nonfinite(out, "regions")
    return out
