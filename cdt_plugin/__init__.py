"""cdt_plugin: constrained Delaunay triangulation and edge flips for NumPy arrays.

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
>>> tri.triangles.shape, tri.is_delaunay()
((2, 3), True)
"""
from importlib.metadata import PackageNotFoundError, version as _version
from typing import TYPE_CHECKING, Any

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
    InvalidMeshError,
    InvertedTriangleError,
    MeshExportError,
    NoPolygonsError,
    NonFiniteCoordinateError,
    NonPlanarError,
    NotDelaunayError,
    OverlappingSegmentsError,
    PrecisionWarning,
    RefinementLimitError,
    RefinementRangeError,
    RefinementRangeWarning,
    SegmentIndexError,
    SegmentIntersectionError,
    SizeFieldError,
    TooFewPointsError,
    UnknownIdError,
    UnresolvedCrossingError,
)
from .nearness import size_near
from .faces import FaceMesh, triangulate_faces
from .plc import PLC

from .triangulation import Triangulation

if TYPE_CHECKING:
    from .dynamic import DynamicCDT
    from .voronoi import Subdivision, Voronoi

__all__ = [
    "CDTError",
    "ClipRegionError",
    "CollinearPointsError",
    "DynamicCDT",
    "CoordinateRangeError",
    "PLC",
    "Triangulation",
    "delaunay",
    "triangulate",
    "size_near",
    "triangulate_faces",
    "FaceMesh",
    "InvalidGeometryError",
    "NonPlanarError",
    "InvalidMeshError",
    "OverlappingSegmentsError",
    "PrecisionWarning",
    "MeshExportError",
    "RefinementLimitError",
    "RefinementRangeError",
    "RefinementRangeWarning",
    "SegmentIndexError",
    "SegmentIntersectionError",
    "SizeFieldError",
    "FileFormatError",
    "InputShapeError",
    "InvertedTriangleError",
    "NoPolygonsError",
    "NonFiniteCoordinateError",
    "NotDelaunayError",
    "Subdivision",
    "Voronoi",
    "TooFewPointsError",
    "UnknownIdError",
    "UnresolvedCrossingError",
]
try:
    __version__ = _version("cdt-plugin")
except PackageNotFoundError:  # pragma: no cover - run from a source tree that is not installed
    __version__ = "0+unknown"


def __getattr__(name: str) -> Any:
    # the Voronoi result classes and DynamicCDT load with their kernels on first
    # use: a process pays for importing them only if it uses them
    if name in ("Subdivision", "Voronoi"):
        from . import voronoi
        return getattr(voronoi, name)
    if name == "DynamicCDT":
        from .dynamic import DynamicCDT
        return DynamicCDT
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
