"""cdt_plugin: constrained Delaunay triangulation and edge flips for NumPy arrays."""
from .delaunay import delaunay
from .errors import (
    CDTError,
    FileFormatError,
    InputShapeError,
    InvertedTriangleError,
    NonFiniteCoordinateError,
    TooFewPointsError,
)

from .triangulation import Triangulation

__all__ = [
    "CDTError",
    "Triangulation",
    "delaunay",
    "FileFormatError",
    "InputShapeError",
    "InvertedTriangleError",
    "NonFiniteCoordinateError",
    "TooFewPointsError",
]
__version__ = "0.1.0"
