"""cdt_plugin: constrained Delaunay triangulation and edge flips for NumPy arrays.

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
>>> tri.triangles.shape, tri.is_delaunay()
((2, 3), True)
"""
from importlib.metadata import PackageNotFoundError, version as _version

from . import compiling  # noqa: F401  (first: it says when numba compiles a route)
from .cdt import triangulate
from .delaunay import delaunay
from .errors import (
    CDTError,
    ClipRegionError,
    CollinearPointsError,
    CoordinateRangeError,
    FileFormatError,
    InputShapeError,
    InvalidGeometryError,
    InvertedTriangleError,
    NoPolygonsError,
    NonFiniteCoordinateError,
    NotDelaunayError,
    OverlappingSegmentsError,
    PrecisionWarning,
    RefinementLimitError,
    SegmentIndexError,
    SegmentIntersectionError,
    TooFewPointsError,
    UnresolvedCrossingError,
)
from .plc import PLC

from .triangulation import Triangulation
from .voronoi import Subdivision, Voronoi

__all__ = [
    "CDTError",
    "ClipRegionError",
    "CollinearPointsError",
    "CoordinateRangeError",
    "PLC",
    "Triangulation",
    "delaunay",
    "triangulate",
    "InvalidGeometryError",
    "OverlappingSegmentsError",
    "PrecisionWarning",
    "RefinementLimitError",
    "SegmentIndexError",
    "SegmentIntersectionError",
    "FileFormatError",
    "InputShapeError",
    "InvertedTriangleError",
    "NoPolygonsError",
    "NonFiniteCoordinateError",
    "NotDelaunayError",
    "Subdivision",
    "Voronoi",
    "TooFewPointsError",
    "UnresolvedCrossingError",
]
try:
    __version__ = _version("cdt-plugin")
except PackageNotFoundError:  # pragma: no cover - run from a source tree that is not installed
    __version__ = "0+unknown"
