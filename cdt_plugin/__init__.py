"""cdt_plugin: constrained Delaunay triangulation and edge flips for NumPy arrays."""
from .cdt import triangulate
from .delaunay import delaunay
from .errors import (
    CDTError,
    FileFormatError,
    InputShapeError,
    InvalidGeometryError,
    InvertedTriangleError,
    NonFiniteCoordinateError,
    OverlappingSegmentsError,
    RefinementLimitError,
    SegmentIndexError,
    SegmentIntersectionError,
    TooFewPointsError,
)
from .plc import PLC

from .triangulation import Triangulation

__all__ = [
    "CDTError",
    "PLC",
    "Triangulation",
    "delaunay",
    "triangulate",
    "InvalidGeometryError",
    "OverlappingSegmentsError",
    "RefinementLimitError",
    "SegmentIndexError",
    "SegmentIntersectionError",
    "FileFormatError",
    "InputShapeError",
    "InvertedTriangleError",
    "NonFiniteCoordinateError",
    "TooFewPointsError",
]
__version__ = "0.1.0"
