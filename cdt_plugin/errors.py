"""The one exception family of cdt_plugin.

Every malformed input raises a subclass of :class:`CDTError` whose message names
what is wrong: which vertex or segment (by input index) and where (coordinates).
The compiled core never raises; it returns status codes that the Python layer
turns into these exceptions.
"""
from __future__ import annotations

from pathlib import Path
from typing import Iterable

from .types import TriangulationLike


class CDTError(ValueError):
    """Base class of every error cdt_plugin raises for bad input or options.

    A call over many geometries or features that fails on one of them sets
    ``index`` to its position (and, for a layer, ``feature`` to its label);
    both are None otherwise.

    >>> CDTError("bad input").index is None
    True
    """

    index: int | None = None
    feature: object = None


class InputShapeError(CDTError):
    """An array has the wrong shape, dtype or length (e.g. points not (n, 2))."""


class NonFiniteCoordinateError(CDTError):
    """A coordinate (or weight, or vertex attribute) is NaN or infinite; the message
    names the rows."""


class TooFewPointsError(CDTError):
    """The input has no points at all (after validation)."""


class FileFormatError(CDTError):
    """A Triangle-format (or other) input file cannot be parsed; names file and line
    (also as the attributes ``path`` and ``line``, None when unknown)."""

    path: Path | None = None
    line: int | None = None


class InvertedTriangleError(CDTError):
    """Moving vertices inverted a triangle and no rebuild was allowed."""


class UnknownIdError(CDTError):
    """An edit of a :class:`cdt_plugin.DynamicCDT` names a vertex or segment id
    that does not exist or was removed."""


class SegmentIndexError(CDTError):
    """A segment names a vertex index that does not exist (or is not an integer)."""


class SegmentIntersectionError(CDTError):
    """Two segments cross at a point inside both (``intersections="raise"``).

    ``segments`` holds the two input segment indices, ``point`` the crossing
    (each coordinate the double nearest to the exact one)."""

    def __init__(self, message: str, segments: Iterable[int] = (),
                 point: tuple[float, float] | None = None) -> None:
        super().__init__(message)
        self.segments = tuple(segments)
        self.point = point


class OverlappingSegmentsError(SegmentIntersectionError):
    """Two collinear segments share more than a point (``intersections="raise"``)."""


class UnresolvedCrossingError(SegmentIntersectionError):
    """``intersections="split"`` could not place the crossing points of some
    segments: they need more than ``max_steiner`` of them (raise it), or, in
    :meth:`DynamicCDT.insert_segments`, which rounds crossings one at a time,
    they cross within rounding of each other so that the rounded crossings keep
    making new ones. ``triangulate`` snap-rounds every crossing at once and
    checks that each segment's pieces follow it in order; this error is raised
    rather than a mesh whose segments are not what was given. ``segments``
    names them and ``point`` (when known) is about where."""


class CoordinateRangeError(CDTError):
    """The coordinates (or weights) span more binary orders of magnitude than
    the exact predicates support: from the largest magnitude down to the finest
    bit of any coordinate at most 2**480 (about 144 decimal digits, e.g. 1e+70
    beside 1e-70 is fine, 1e+100 beside 1e-100 is not). Any overall scale is
    supported. The message names the two rows; ``rows`` holds them.

    A Voronoi diagram clipped to a polygon raises it too when two sites are
    closer than 2**-510 times the clip polygon's coordinates: GEOS intersects
    the cells in doubles (a box clip, cut by cdt_plugin, has no such limit)."""

    def __init__(self, message: str, rows: Iterable[int] = ()) -> None:
        super().__init__(message)
        self.rows = tuple(rows)


class NotDelaunayError(CDTError):
    """A Delaunay-only operation (the Voronoi diagram, the Delaunay subdivision)
    was given a triangulation that is not the (weighted) Delaunay triangulation
    of its vertices: it has segments, an edge that is not locally Delaunay, or a
    domain that is not convex. The message names the edge or vertex."""


class CollinearPointsError(CDTError):
    """The points lie on one line (or there are fewer than three): there is no
    triangle, so no Voronoi vertex; the message says how many points there are."""


class ClipRegionError(CDTError):
    """A clip region is malformed (not a finite box with ``xmin < xmax`` and
    ``ymin < ymax``, not a polygon) or contains none of the points."""


class InvalidGeometryError(CDTError):
    """A polygon is not valid (e.g. a hole outside its shell, a ring with fewer
    than three distinct points); the message names the polygon and ring."""


class NonPlanarError(InvalidGeometryError):
    """3D input whose vertices do not lie in one plane (:mod:`cdt_plugin.planar`):
    ``vertex`` is the input vertex farthest from the fitted plane, ``point`` its
    coordinates, ``distance`` its distance from the plane and ``tolerance`` the
    bound it broke (0: exact coplanarity was asked). For a hole or region seed
    given in 3D off the plane, ``vertex`` is None and ``point`` the seed."""

    def __init__(self, message: str, *, vertex: int | None = None, distance: float | None = None,
                 point: tuple[float, ...] | None = None, tolerance: float | None = None) -> None:
        super().__init__(message)
        self.vertex, self.distance, self.point, self.tolerance = vertex, distance, point, tolerance


class InvalidMeshError(CDTError):
    """A mesh given as triangles is not a triangulation: two triangles overlap,
    a vertex lies inside a triangle or on an edge it does not end, two vertices
    are the same point, or a segment to keep is not an edge of the triangles.
    ``triangles`` and ``segments`` hold the indices the message names."""

    def __init__(self, message: str, triangles: Iterable[int] = (),
                 segments: Iterable[int] = ()) -> None:
        super().__init__(message)
        self.triangles = tuple(int(t) for t in triangles)
        self.segments = tuple(int(s) for s in segments)


class NoPolygonsError(CDTError):
    """The input (a layer, a GeoJSON file) has no non-empty Polygon or MultiPolygon
    to mesh; the message says what it holds instead. Raised by
    :func:`cdt_plugin.adapters.geo.triangulate` and the command line (a point set
    goes in a ``.node`` file), and by the trimesh adapter for an empty polygon
    (extruded, or handed over by trimesh with the engine registered)."""


class MeshExportError(CDTError):
    """A finite-element mesh cannot be made as asked
    (:meth:`cdt_plugin.Triangulation.to_meshio`, ``to_skfem``): a malformed option
    (which one, and why), a boundary or subdomain naming a marker or region that no
    edge or triangle has, or a triangulation without triangles."""


class RefinementLimitError(CDTError):
    """Quality refinement inserted ``max_steiner`` points and was not done.

    ``triangulation`` holds the partial mesh (every triangle valid and
    constrained Delaunay, some still breaking the bounds; its
    ``stats["refinement_complete"]`` is False).
    """

    def __init__(self, message: str, triangulation: TriangulationLike | None = None) -> None:
        super().__init__(message)
        self.triangulation = triangulation


class SizeFieldError(CDTError):
    """A size field (``size=``, a callable ``max_area=``, ``min_size=``,
    ``growth=``) is malformed, or gave a value that is not a positive finite
    length (or area) where it was evaluated: the message names the point
    ``(x, y)`` and the value (also as the attributes ``point`` and ``value``,
    None when the error is not about one point)."""

    def __init__(self, message: str, point: tuple[float, float] | None = None,
                 value: object = None) -> None:
        super().__init__(message)
        self.point = point
        self.value = value


class RefinementRangeError(CDTError):
    """``min_angle`` is one no triangle can meet: 60 degrees or more (a
    triangle's smallest angle is at most 60 degrees, and exactly 60 only for an
    equilateral triangle, which floating point cannot make), or below 0."""


class SwitchError(CDTError):
    """A Triangle switch string cannot be read: an unknown switch, a number where
    Triangle would read something else than what was written (``a1e-3``), or a switch
    whose meaning needs what the call lacks (``r`` without a mesh). The message
    names the switch and the position in the string."""


class SampleDataError(CDTError):
    """Triangle's sample files (``cdt_plugin.triangle.get_data``) are not where they
    were looked for; the message names the places and how to point to them."""


class PrecisionWarning(UserWarning):
    """Input numbers that float64 cannot hold exactly (integers beyond 2**53) were
    rounded; the message names the rows. Rounded points may coincide, and are then
    merged as duplicates (``vertex_map``)."""


class RefinementRangeWarning(UserWarning):
    """``min_angle`` is above the range where Delaunay refinement is known to
    finish (:data:`cdt_plugin.options.TERMINATING_MIN_ANGLE`, about 34 degrees):
    it may add Steiner points until ``max_steiner`` and raise
    :class:`RefinementLimitError`. Given before any work starts."""
