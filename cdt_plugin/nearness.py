"""Sizes near geometry: :func:`size_near`, a size field fine on points, lines and
polygon boundaries and coarser away from them (gmsh's Distance + Threshold fields).

The geometries are read once into *sources* (points, and segments given by their
end points) with the PLC reader (:meth:`cdt_plugin.PLC.from_geo_interface`, no
geometry library imported): a polygon counts by its boundary rings, a line by its
segments, a point as a point. The distances from the points where the field is
asked go through a uniform grid of buckets over the sources
(:mod:`cdt_plugin._core.distance`), compiled, for many points in one call.
"""
from __future__ import annotations

import numbers
from typing import Any, Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.distance import bucket_grid, nearest_distances
from .errors import SizeFieldError
from .fields import as_size_field
from .plc import PLC, geojson_features
from .validate import as_xy

#: What :func:`size_near` takes as ``geometries`` (one of these, or a list of them).
GeometriesLike = Any


class SizeNear:
    """A size field fine near geometry (what :func:`size_near` returns): called as
    ``field(x, y)`` with arrays of coordinates of one shape, it returns the target
    edge length at each point, a float64 array of that shape.

    Attributes
    ----------
    size_min, size_max : float
    distance, growth : float or None
    points, segments : int
        How many point and segment sources the geometries gave.
    """

    def __init__(self, sources: tuple[NDArray[np.float64], ...], points: int, size_min: float,
                 size_max: float, distance: float | None, growth: float | None) -> None:
        self.size_min, self.size_max = size_min, size_max
        self.distance, self.growth = distance, growth
        self.points, self.segments = points, len(sources[0]) - points
        self._sources = sources
        self._grid = bucket_grid(*sources)
        slopes = []                # size per unit of distance, of each form asked
        if distance is not None:
            slopes.append((size_max - size_min) / distance)
        if growth is not None:
            slopes.append(growth - 1.0)
        self._slope = min(slopes)
        # beyond this distance the size is size_max: the search stops there
        self._reach = (size_max - size_min) / self._slope if self._slope > 0 else 0.0

    def distances(self, x: ArrayLike, y: ArrayLike) -> NDArray[np.float64]:
        """The distance from each point ``(x, y)`` to the nearest source (the
        arrays broadcast together; the result has their shape).

        >>> field = size_near([[0.0, 0.0]], 1.0, 10.0, distance=100.0)
        >>> field.distances([3.0, 0.0], [4.0, 0.0]).tolist()
        [5.0, 0.0]
        """
        return self._nearest(x, y, np.inf)

    def __call__(self, x: ArrayLike, y: ArrayLike) -> NDArray[np.float64]:
        d = self._nearest(x, y, self._reach)
        return np.minimum(self.size_min + self._slope * d, self.size_max)

    def _nearest(self, x: ArrayLike, y: ArrayLike, limit: float) -> NDArray[np.float64]:
        qx, qy = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
        shape = qx.shape
        out = nearest_distances(np.ascontiguousarray(qx.ravel()), np.ascontiguousarray(qy.ravel()),
                                float(limit), *self._grid, *self._sources)
        return out.reshape(shape)

    def __repr__(self) -> str:
        how = ", ".join(f"{k}={v:g}" for k, v in (("distance", self.distance),
                                                    ("growth", self.growth)) if v is not None)
        return (f"size_near({self.points} point(s), {self.segments} segment(s), "
                f"size_min={self.size_min:g}, size_max={self.size_max:g}, {how})")


def size_near(geometries: GeometriesLike, size_min: float, size_max: float,
              distance: float | None = None, growth: float | None = None) -> SizeNear:
    """A size field that is ``size_min`` on the geometries and grows with the
    distance from them up to ``size_max``: for ``triangulate(size=...)``.

    Parameters
    ----------
    geometries : geometry, array, PLC, or a list of them
        Points as an (n, 2) array; a :class:`~cdt_plugin.PLC` (its segments, and
        its vertices on no segment as points); anything with
        ``__geo_interface__`` (shapely geometries, GeoSeries, GeoDataFrames) or a
        GeoJSON mapping (geometry, Feature, FeatureCollection). A polygon counts
        by its boundary rings (holes too), a line by its segments, a point as
        a point. A list (or object array) may mix all of these.
    size_min : float
        The size (target edge length) on the geometries, > 0.
    size_max : float
        The size far from them, >= ``size_min``.
    distance : float, optional
        The distance at which the size reaches ``size_max``: it grows linearly
        from ``size_min`` at distance 0 (gmsh's Threshold field with
        ``DistMin = 0``, ``DistMax = distance``).
    growth : float, optional
        A gradation instead (or as well): the size grows by ``growth - 1`` per
        unit of distance, ``size_min + (growth - 1) d`` (neighbouring edges
        then differ by about the factor ``growth``). With both, the finer of the
        two. One of them is needed.

    Returns
    -------
    SizeNear
        The field: ``field(x, y)`` gives the sizes at arrays of points.

    Raises
    ------
    SizeFieldError
        A bad number (naming the argument and the value), or geometries that
        hold no point and no segment (a :class:`~cdt_plugin.CDTError`). The
        geometry readers' errors (:class:`~cdt_plugin.errors.InputShapeError`,
        :class:`~cdt_plugin.errors.NonFiniteCoordinateError`) for malformed input.

    Examples
    --------
    A point source: size 1 at the point, 10 at distance 90 and beyond.

    >>> import numpy as np
    >>> field = size_near([[0.0, 0.0]], 1.0, 10.0, distance=90.0)
    >>> field(np.array([0.0, 45.0, 200.0]), np.zeros(3)).tolist()
    [1.0, 5.5, 10.0]

    A line (GeoJSON, or a shapely LineString) with a gradation of 1.2: the size
    grows by 0.2 per unit of distance from the segment.

    >>> line = {"type": "LineString", "coordinates": [(0, 0), (10, 0)]}
    >>> field = size_near(line, 0.5, 4.0, growth=1.2)
    >>> field(np.array([5.0, 5.0, 13.0]), np.array([0.0, 5.0, 4.0])).round(6).tolist()
    [0.5, 1.5, 1.5]
    >>> field
    size_near(0 point(s), 1 segment(s), size_min=0.5, size_max=4, growth=1.2)
    """
    size_min, size_max, distance, growth = check_near(size_min, size_max, distance, growth)
    sources, points = read_sources(geometries)
    return SizeNear(sources, points, size_min, size_max, distance, growth)


def check_near(size_min: object, size_max: object, distance: object = None,
               growth: object = None) -> tuple[float, float, float | None, float | None]:
    """:func:`size_near`'s numbers, checked (as floats), or the
    :class:`~cdt_plugin.errors.SizeFieldError` naming the first that is wrong
    (the command line checks them with this before it reads any file).

    >>> check_near(1, 10, distance=100)
    (1.0, 10.0, 100.0, None)
    >>> check_near(1, 10)
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.SizeFieldError: size_near needs distance= (where the size reaches size_max) or growth= (how fast it grows), or both
    """
    low = _positive(size_min, "size_min")
    high = _positive(size_max, "size_max")
    if high < low:
        raise SizeFieldError(f"size_near: size_max must be >= size_min, got size_max={high!r} "
                             f"< size_min={low!r}")
    if distance is None and growth is None:
        raise SizeFieldError("size_near needs distance= (where the size reaches size_max) or "
                             "growth= (how fast it grows), or both")
    reach = None if distance is None else _positive(distance, "distance")
    rate = None if growth is None else _real(growth, "growth")
    if rate is not None and not (np.isfinite(rate) and rate > 1.0):
        raise SizeFieldError(f"size_near: growth must be a finite number > 1, got {growth!r}")
    return low, high, reach, rate


class SmallestSize:
    """The smallest of several size fields at every point (each a number or a
    callable ``f(x, y)``): how fields combine, e.g. a coarse size everywhere
    and sizes near rivers and wells.

    >>> import numpy as np
    >>> both = SmallestSize([4.0, size_near([[0.0, 0.0]], 1.0, 10.0, distance=9.0)])
    >>> both(np.array([0.0, 2.0, 50.0]), np.zeros(3)).tolist()
    [1.0, 3.0, 4.0]
    >>> SmallestSize([0.5, 2])
    SmallestSize([ConstantSize(0.5), ConstantSize(2.0)])
    """

    def __init__(self, fields: Iterable[object]) -> None:
        self.fields = [as_size_field(f) for f in fields]     # (each checked)
        if not self.fields:
            raise SizeFieldError("SmallestSize needs at least one size field")

    def __call__(self, x: ArrayLike, y: ArrayLike) -> NDArray[np.float64]:
        px, py = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
        out = np.full(px.shape, np.inf)
        for f in self.fields:
            np.minimum(out, f(px, py), out=out)
        return out

    def __repr__(self) -> str:
        return f"SmallestSize({self.fields!r})"


def read_sources(geometries: GeometriesLike) -> tuple[tuple[NDArray[np.float64], ...], int]:
    """The sources of ``geometries`` as four arrays ``(ax, ay, bx, by)``, the
    points first (``a == b``), then the segments; and how many points.

    >>> (ax, ay, bx, by), points = read_sources([[[0, 0], [1, 1]],
    ...     {"type": "LineString", "coordinates": [(0, 2), (3, 2)]}])
    >>> points, ax.tolist(), bx.tolist()
    (2, [0.0, 1.0, 0.0], [0.0, 1.0, 3.0])
    """
    point_parts: list[NDArray[np.float64]] = []
    segment_parts: list[NDArray[np.float64]] = []
    for item in _items(geometries):
        if isinstance(item, PLC):
            plc = item
        elif isinstance(item, dict) or hasattr(item, "__geo_interface__"):
            plc = PLC.from_geo_interface(_geometry_mapping(item))
        else:
            point_parts.append(as_xy(item, "geometries", empty=True))
            continue
        used = np.zeros(len(plc.vertices), bool)
        used[plc.segments.ravel()] = True
        point_parts.append(plc.vertices[~used])
        segment_parts.append(plc.vertices[plc.segments].reshape(-1, 4))
    pts = np.concatenate(point_parts) if point_parts else np.empty((0, 2))
    segs = np.concatenate(segment_parts) if segment_parts else np.empty((0, 4))
    if len(pts) + len(segs) == 0:
        raise SizeFieldError("size_near: the geometries hold no point and no segment")
    a = np.concatenate([pts, segs[:, :2]])
    b = np.concatenate([pts, segs[:, 2:]])
    with np.errstate(over="ignore"):
        span = np.maximum(a.max(axis=0), b.max(axis=0)) - np.minimum(a.min(axis=0), b.min(axis=0))
    if not np.isfinite(span).all():
        raise SizeFieldError(f"size_near: the geometries span {span.tolist()}, beyond the "
                             "range of double precision")
    return tuple(np.ascontiguousarray(c) for c in (a[:, 0], a[:, 1], b[:, 0], b[:, 1])), len(pts)


def _items(geometries: GeometriesLike) -> Iterable[Any]:
    """The parts of ``geometries``: one geometry, PLC or point array, or each
    member of a list, tuple or object array holding such things (a list is
    one point array unless it holds a geometry, a PLC or a 2-d array)."""
    if isinstance(geometries, np.ndarray) and geometries.dtype == object:
        return [g for g in geometries.ravel() if g is not None]
    if isinstance(geometries, (list, tuple)) and any(
            _is_geometry(g) or (isinstance(g, np.ndarray) and g.ndim == 2) for g in geometries):
        return [g for g in geometries if g is not None]
    return [geometries]            # (a list of coordinate pairs is one point array)


def _is_geometry(item: Any) -> bool:
    return isinstance(item, (PLC, dict)) or hasattr(item, "__geo_interface__")


def _geometry_mapping(item: Any) -> Any:
    """The geometry to read: a FeatureCollection (a GeoDataFrame's or GeoSeries'
    ``__geo_interface__``) as the collection of its features' geometries."""
    gi = item if isinstance(item, dict) else getattr(item, "__geo_interface__", None)
    if isinstance(gi, dict) and gi.get("type") == "FeatureCollection":
        return {"type": "GeometryCollection",
                "geometries": [f["geometry"] for f in geojson_features(gi) if f.get("geometry")]}
    return item


def _real(value: object, name: str) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise SizeFieldError(f"size_near: {name} must be a number, got {value!r} ({type(value).__name__})")
    return float(value)


def _positive(value: object, name: str) -> float:
    number = _real(value, name)
    if not (np.isfinite(number) and number > 0):
        raise SizeFieldError(f"size_near: {name} must be a finite number > 0, got {value!r}")
    return number
