"""cdt_plugin: constrained Delaunay triangulation and edge flips for NumPy arrays."""
from .errors import (
    CDTError,
    FileFormatError,
    InputShapeError,
    InvertedTriangleError,
    NonFiniteCoordinateError,
    TooFewPointsError,
)

__all__ = [
    "CDTError",
    "FileFormatError",
    "InputShapeError",
    "InvertedTriangleError",
    "NonFiniteCoordinateError",
    "TooFewPointsError",
]
__version__ = "0.1.0"
