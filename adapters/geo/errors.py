"""The warnings and errors of the GIS adapter, and how they name a feature."""
from __future__ import annotations

import os
import sys
import warnings
from types import FrameType
from typing import TYPE_CHECKING, Any, Callable, Iterable

import numpy as np
import shapely

from cdt_plugin import CDTError, InvalidGeometryError

if TYPE_CHECKING:
    import pyproj
    from geopandas import GeoDataFrame


TYPE_NAMES = ("Point", "LineString", "LinearRing", "Polygon", "MultiPoint", "MultiLineString",
               "MultiPolygon", "GeometryCollection")


class GeographicCRSWarning(UserWarning):
    """The layer is in a geographic CRS (lon/lat) and is meshed in degree space."""


class SkippedFeaturesWarning(UserWarning):
    """``errors="skip"``: some features could not be meshed and have no triangles."""


class ProjectionError(CDTError):
    """``project=`` cannot be applied (no CRS, not a projected CRS, coordinates that
    do not project to finite values, a feature that does not map back)."""


class NotGeographicError(CDTError, AttributeError):
    """``.cdt`` on a pandas object that is not a GeoDataFrame with an active
    geometry column or a GeoSeries. Also an ``AttributeError``, so that
    ``hasattr(frame, "cdt")`` is False for it, as pandas accessors expect."""


def describe(geoms: np.ndarray) -> str:
    """What a layer holds, e.g. ``3 feature(s): 2 Point, 1 None``."""
    if not len(geoms):
        return "the layer is empty"
    types = shapely.get_type_id(geoms)
    empty = shapely.is_empty(geoms)
    kinds = ["None" if t < 0 else ("empty " if e else "") + TYPE_NAMES[t]
             for t, e in zip(types, empty)]
    values, counts = np.unique(kinds, return_counts=True)
    return f"{len(geoms)} feature(s): " + ", ".join(f"{c} {v}" for v, c in zip(values, counts))


def relabel(e: CDTError, i: int, frame: GeoDataFrame, target: pyproj.CRS | None) -> CDTError:
    """A batch error (``geometry i: ...``, for row ``i``) renamed after the feature's
    index label."""
    label = plain(frame.index[i])
    message = e.args[0] if e.args else ""
    prefix = f"geometry {i}: "
    message = message[len(prefix):] if message.startswith(prefix) else message
    if target is not None:
        message += f" (coordinates in the meshing CRS {target.name!r})"
    e.args = (f"feature {label}: {message}",) + tuple(e.args[1:])
    e.index, e.feature = i, label
    return e


def feature_errors(kind: type[CDTError], frame: GeoDataFrame, rows: Iterable[int],
                   reason: Callable[[int], str], errors: str) -> dict[int, CDTError]:
    """A ``kind`` error for each of ``rows`` (``feature <label>: <reason(row)>``,
    its ``index`` and ``feature`` set), by row; the first is raised when
    ``errors == "raise"``."""
    out: dict[int, CDTError] = {}
    for i in rows:
        label = plain(frame.index[i])
        e = kind(f"feature {label}: {reason(i)}")
        e.index, e.feature = i, label
        if errors == "raise":
            raise e
        out[i] = e
    return out


def plain(value: Any) -> Any:
    """A NumPy scalar as the Python value (labels in messages and columns)."""
    return value.item() if isinstance(value, np.generic) else value


def warn_skipped(failed: dict, frame: GeoDataFrame,
                 what: str = "could not be meshed and have no triangles",
                 where: str = '; their errors are in result.attrs["cdt_errors"]') -> None:
    """A SkippedFeaturesWarning: ``N feature(s) <what> (<labels>)<where>``."""
    labels = [str(plain(frame.index[i])) for i in sorted(failed)]
    shown = ", ".join(labels[:10]) + (", ..." if len(labels) > 10 else "")
    warnings.warn(SkippedFeaturesWarning(f"{len(failed)} feature(s) {what} ({shown}){where}"),
                  stacklevel=caller_stacklevel())


def is_geographic(crs: Any) -> bool:
    return crs is not None and bool(crs.is_geographic)


_PACKAGE_DIR = os.path.dirname(__file__)


def caller_stacklevel() -> int:
    """The ``stacklevel`` (for ``warnings.warn`` called by the caller of this function)
    that points at the first frame outside this package: the user's line, whether it
    called :func:`triangulate`, :func:`triangulate_dask` or ``gdf.cdt.triangulate``."""
    frame: FrameType | None = sys._getframe(1)
    level = 1
    while frame is not None and os.path.dirname(frame.f_code.co_filename) == _PACKAGE_DIR:
        frame, level = frame.f_back, level + 1
    return level


def warn_geographic(crs: Any) -> None:
    warnings.warn(GeographicCRSWarning(
        f"the layer's CRS ({crs.name}) is geographic: the triangulation is Delaunay, and "
        "min_angle / max_area are measured, in degrees of longitude and latitude (angles and "
        "areas distorted away from the equator); pass project='utm', 'aeqd' or a projected "
        "CRS to mesh in metres (input vertices keep their coordinates exactly)"),
        stacklevel=caller_stacklevel())


class HeightError(CDTError):
    """``height=`` / ``base=`` of :func:`~cdt_plugin.adapters.geo.extrude` cannot be
    used: a column the layer does not have, or that is not numeric; a height that is
    not positive and finite, a base that is not finite. The message names the column
    and the first features concerned; ``feature`` / ``index`` are the first one's
    label and row number (None when the whole option is wrong)."""


class NotPolygonalError(InvalidGeometryError):
    """A feature that :func:`~cdt_plugin.adapters.geo.extrude` cannot make a solid of:
    a point, a line, an empty or missing geometry (``errors="skip"`` skips it)."""
