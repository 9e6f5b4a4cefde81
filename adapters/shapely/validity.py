"""Polygon validity decided exactly, at every magnitude: GEOS's ``is_valid``,
``is_valid_reason`` and ``make_valid`` run on the geometry scaled by a power of
two to unit size.

GEOS decides validity with exact orientation tests (double-double arithmetic
on coordinate differences), which hold while their products stay normal
doubles: up to magnitudes of about ``2**500`` and down to about ``2**-500``.
Beyond (``1e300``, ``1e-300``) GEOS calls valid polygons self-intersecting,
overlapping MultiPolygons valid, or raises. A power-of-two scale is exact and
changes no orientation, so the verdict at unit size is the verdict at every
scale: a geometry whose largest coordinate lies outside ``2**-HOME ..
2**HOME`` is scaled to ``[0.5, 1)`` first (:func:`unit_shift`); ordinary
geometries are checked as they are.
"""
from __future__ import annotations

import re
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

import cdt_plugin
from cdt_plugin import PLC, CDTError, SegmentIntersectionError
from cdt_plugin.merging import close_point_representatives

#: Geometries whose largest |coordinate| lies within ``2**-HOME .. 2**HOME``
#: are checked as they are (the products of GEOS's tests stay far from
#: overflow and underflow); others are scaled to unit size first.
HOME = 64

_REASON = re.compile(r"^(?P<what>.*?)\s*\[(?P<x>\S+) (?P<y>\S+)(?: \S+)?\]$")


def unit_shift(geoms: Any) -> NDArray[np.int64]:
    """Per geometry (one or an array), the power of two ``k`` that brings its
    largest |coordinate| into ``[0.5, 1)`` when that lies outside
    ``2**-HOME .. 2**HOME``, else 0 (also for empty geometries).

    >>> import shapely
    >>> unit_shift([shapely.box(0, 0, 1, 1), shapely.box(0, 0, 1e300, 1e300)]).tolist()
    [0, -997]
    """
    with np.errstate(invalid="ignore"):
        bounds = np.abs(shapely.bounds(np.asarray(geoms, dtype=object)))
    top = np.fmax.reduce(bounds, axis=-1)        # NaN (empty) only where every bound is
    _, e = np.frexp(np.where(np.isfinite(top), top, 0.0))
    far = (top > 0) & ((e > HOME) | (e < -HOME))
    return np.where(far, -e, 0).astype(np.int64)


def merged(geoms: NDArray[np.object_], distance: float) -> NDArray[np.object_]:
    """Each geometry with every vertex moved onto its representative for
    ``merge_distance=distance`` (:func:`cdt_plugin.merging.close_point_representatives`
    over all of the geometry's x, y: the rule the engine applies to the
    points it reads from it, so validity is decided on what is meshed).
    Coordinates are copied exactly; a geometry with nothing to merge is
    itself.

    >>> import shapely
    >>> zigzag = shapely.Polygon([(0, 0), (1, 0), (1, 1), (0.5, 1e-9), (0.5 + 1e-9, -1e-9), (0, 1)])
    >>> zigzag.is_valid, merged([zigzag], 1e-6)[0].is_valid
    (False, True)
    """
    out = np.empty(len(geoms), dtype=object)
    for k, g in enumerate(geoms):
        xy = shapely.get_coordinates(g)
        rep = close_point_representatives(xy, distance)
        moved = rep != np.arange(len(xy))
        out[k] = g if not moved.any() else shapely.transform(g, lambda c: c[rep])
    return out


def at_home(geometry: shapely.Geometry) -> bool:
    """Whether one geometry needs no scaling for GEOS (:func:`unit_shift` 0)."""
    xmin, ymin, xmax, ymax = shapely.bounds(geometry).tolist()
    top = max(-xmin, -ymin, xmax, ymax)      # (NaN for an empty geometry: nothing to scale)
    return not (top >= _TOP or _BOTTOM > top > 0.0)


_TOP = 2.0 ** HOME
_BOTTOM = 2.0 ** (-HOME - 1)


def scaled(geometry: Any, k: int) -> Any:
    """``geometry`` (one or an array) with every x and y times ``2**k``, z
    kept: exact (``np.ldexp``) while the results are normal doubles."""
    return _moved(geometry, _ORIGIN, k)


_ORIGIN = np.zeros(2)


def _grouped(fn: Any, arr: NDArray[np.object_], shifts: NDArray[np.int64]) -> NDArray[Any]:
    """``fn`` of every geometry of ``arr`` scaled by its shift, one call per shift."""
    out = np.empty(len(arr), dtype=object)
    for k in np.unique(shifts):
        rows = np.flatnonzero(shifts == k)
        out[rows] = fn(scaled(arr[rows], int(k)))
    return out


def is_valid(arr: NDArray[np.object_]) -> NDArray[np.bool_]:
    """GEOS validity of every geometry of a 1-D object array, each decided at
    unit size (the same verdict at every power-of-two scale). A geometry GEOS
    fails on (raises) is invalid; :func:`reason` then says why."""
    shifts = unit_shift(arr)
    try:
        if not shifts.any():
            return shapely.is_valid(arr)
        valid = _grouped(shapely.is_valid, arr, shifts).astype(bool)
    except shapely.errors.GEOSException:        # one by one, to find the one GEOS fails on
        valid = np.array([_valid_or_false(g) for g in arr], dtype=bool)
    # coordinates spanning more binary orders than doubles hold (1e300 beside 1e-300) do not
    # scale exactly: GEOS cannot decide them, and the engine names them (CoordinateRangeError)
    valid[_inexact(arr, shifts)] = True
    return valid


def _inexact(arr: NDArray[np.object_], shifts: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Which geometries a scale by ``2**shift`` does not keep exactly."""
    out = np.zeros(len(arr), bool)
    rows = np.flatnonzero(shifts)
    xy, which = shapely.get_coordinates(arr[rows], return_index=True)
    k = shifts[rows][which][:, None]
    lost = (np.ldexp(np.ldexp(xy, k), -k) != xy).any(axis=1)
    out[rows[which[lost]]] = True
    return out


def _valid_or_false(geometry: shapely.Geometry) -> bool:
    try:
        return bool(shapely.is_valid(scaled(geometry, int(unit_shift(geometry)))))
    except shapely.errors.GEOSException:
        return False


def reason(geometry: shapely.Geometry) -> str:
    """Why GEOS finds ``geometry`` invalid, decided at unit size: the reason,
    the point and the ring(s) through it, e.g. ``"Polygon is not valid: Ring
    Self-intersection at (2.0, 4.0), on ring 0 of polygon 0"``. The point is
    exact: for edges that cross, a crossing as ``intersections="split"`` places
    it (:class:`cdt_plugin.SegmentIntersectionError`'s point, found by the
    engine); otherwise the input vertex GEOS names (it prints its point
    rounded to 15 digits: GEOS reads the geometry moved to the origin when
    that is exact, so that the digits resolve its vertices also far from the
    origin), or GEOS's point where it names none."""
    ref = _exact_origin(geometry)
    local = _moved(geometry, ref, 0)
    k = int(unit_shift(local))
    unit = _moved(geometry, ref, k)
    head = f"{geometry.geom_type} is not valid"
    try:
        text = shapely.is_valid_reason(unit)
    except shapely.errors.GEOSException as exc:
        return f"{head}: GEOS cannot check it ({exc})"
    match = _REASON.match(text or "")
    try:
        point = np.array([float(match["x"]), float(match["y"])]) if match else None
    except ValueError:
        point = None
    if match is None or point is None or not np.isfinite(point).all():
        return f"{head}: {text}"
    parts = shapely.get_parts(unit)
    rings, part = shapely.get_rings(parts, return_index=True)
    rank = np.arange(len(part)) - np.searchsorted(part, part)   # ring 0: the shell
    names = [f"ring {int(r)} of polygon {int(p)}" for r, p in zip(rank, part)]
    found: tuple[Any, str] | None = None
    if match["what"] == "Self-intersection":     # (GEOS's reason for edges that cross)
        found = _crossing(geometry, names)
    if found is None:
        found = _vertex_near(rings, point, names)
        if found is None:
            found = point, _rings_through(rings, point, names)
        found = np.ldexp(found[0], -k) + ref, found[1]      # (exact for a vertex)
    point, on = found
    x, y = np.asarray(point, dtype=np.float64).tolist()
    return f"{head}: {match['what']} at ({x!r}, {y!r})" + (f", on {on}" if on else "")


def _exact_origin(geometry: shapely.Geometry) -> NDArray[np.float64]:
    """A vertex of ``geometry`` that every coordinate minus it is exact for
    (each difference's rounding error, by Knuth's two-sum, is zero), else the
    origin."""
    xy = shapely.get_coordinates(geometry)
    if not len(xy) or not np.isfinite(xy).all():
        return np.zeros(2)
    ref = xy[0]
    with np.errstate(over="ignore", invalid="ignore"):
        d = xy - ref
        back = d - xy
        err = (xy - (d - back)) + (-ref - back)
    return ref if np.isfinite(d).all() and not err.any() else np.zeros(2)


def _moved(geometry: Any, ref: NDArray[np.float64], k: int) -> Any:
    """``geometry`` with x and y mapped to ``(c - ref) * 2**k`` (exact when
    ``ref`` is :func:`_exact_origin`'s), z kept."""
    if not k and not ref.any():
        return geometry

    def move(coords: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.array(coords, dtype=np.float64)
        out[:, :2] = np.ldexp(out[:, :2] - ref, k)
        return out
    return shapely.transform(geometry, move, include_z=None)


#: A point GEOS names stands for an input vertex within this much of it, relative to
#: the geometry's size at unit scale (GEOS prints 15 significant digits).
_VERTEX_TOLERANCE = 1e-14


def _vertex_near(rings: NDArray[np.object_], point: NDArray[np.float64],
                 names: list[str]) -> tuple[Any, str] | None:
    """The input vertex nearest GEOS's (rounded) point, exactly, when one lies
    within :data:`_VERTEX_TOLERANCE`, with the rings through it."""
    if not len(rings):
        return None
    xy = shapely.get_coordinates(rings)
    gap = np.abs(xy - point).max(axis=1)
    nearest = int(np.argmin(gap))
    if gap[nearest] > _VERTEX_TOLERANCE * max(float(np.abs(xy).max()), 2.0 ** -1000):
        return None
    return xy[nearest], _rings_through(rings, xy[nearest], names)


def _crossing(unit: shapely.Geometry, names: list[str]) -> tuple[Any, str] | None:
    """Where two edges of ``unit`` cross, as the engine finds it exactly (the
    point ``intersections="split"`` would insert) with the rings of the two
    edges; None when no two edges cross inside both."""
    try:
        plc = PLC.from_geo_interface(unit)
        plc.z = None                    # (validity is in x, y)
        cdt_plugin.triangulate(plc)
    except SegmentIntersectionError as e:
        if e.point is None or plc.segment_ring is None:
            return None
        rings = sorted({int(plc.segment_ring[s]) for s in e.segments})
        return np.array(e.point), " and ".join(names[r] for r in rings if 0 <= r < len(names))
    except CDTError:
        return None
    return None


def _rings_through(rings: NDArray[np.object_], point: NDArray[np.float64], names: list[str]) -> str:
    """The rings nearest ``point`` (those through it, up to rounding), named."""
    if not len(rings):
        return ""
    d = shapely.distance(rings, shapely.points(point))
    scale = float(np.abs(shapely.get_coordinates(rings)).max())
    through = np.flatnonzero(d <= d.min() + _VERTEX_TOLERANCE * scale)
    return " and ".join(names[r] for r in through)


def make_valid(geometry: shapely.Geometry, **kwargs: Any) -> shapely.Geometry:
    """``shapely.make_valid(geometry, **kwargs)`` at unit size, scaled back
    (exact both ways while the new points are normal doubles). GEOS's
    exception, if any, passes to the caller."""
    k = int(unit_shift(geometry))
    return scaled(shapely.make_valid(scaled(geometry, k), **kwargs), -k)
