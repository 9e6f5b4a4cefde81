"""Reading and writing GIS layers: any layer as a GeoDataFrame (:func:`read`), a
GeoDataFrame as a GeoJSON file (:func:`write_geojson`). Below the GIS adapter
(:mod:`cdt_plugin.adapters.geo`) and the terrain (:mod:`cdt_plugin.adapters.terrain`),
which both read layers with it."""
from __future__ import annotations

import datetime
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Union

import numpy as np
import shapely

from cdt_plugin import FileFormatError, InputShapeError
from cdt_plugin.optional import require
from cdt_plugin.plc import geojson_features

if TYPE_CHECKING:
    from geopandas import GeoDataFrame, GeoSeries

#: What :func:`read` takes: a GeoDataFrame, a GeoSeries, a GeoJSON dict or a path.
LayerLike = Union["GeoDataFrame", "GeoSeries", "dict[str, Any]", str, Path]


GEOJSON_ROWS = 50_000                # features per write (and progress step) of write_geojson


def read(data: LayerLike, *, layer: str | int | None = None) -> GeoDataFrame:
    """The layer ``data`` as a GeoDataFrame (a GeoDataFrame is returned as it is).

    ``data``: a GeoDataFrame; a GeoSeries; a GeoJSON dict (FeatureCollection,
    Feature or bare geometry; its legacy ``"crs"`` member is used, else WGS 84 as
    RFC 7946 says and as GDAL reads a ``.geojson`` file); or a path (str or Path) to
    anything GDAL reads through pyogrio: ``.geojson`` / ``.json``, ``.shp``,
    ``.gpkg`` (``layer=`` picks a layer by name or number); or a GeoParquet file
    (``.parquet``, read by ``geopandas.read_parquet``).

    >>> read({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 1], [0, 0]]]}).crs.to_epsg()
    4326
    """
    geopandas = require("geopandas", "reading a layer")

    if isinstance(data, (str, Path)):
        path = Path(data)
        if not path.exists():
            raise FileNotFoundError(2, "No such file or directory", str(path))
        if path.suffix.lower() == ".parquet":
            if layer is not None:
                raise InputShapeError("layer= applies to multi-layer files (.gpkg): a GeoParquet "
                                      "file holds one layer")
        try:
            if path.suffix.lower() == ".parquet":
                return geopandas.read_parquet(path)
            return geopandas.read_file(path, layer=layer, engine="pyogrio")
        except (RuntimeError, OSError, ValueError) as exc:    # pyogrio's and pyarrow's errors
            error = FileFormatError(f"{path}: cannot read it as a GIS layer "
                                    f"({type(exc).__name__}: {exc})")
            error.path = path
            raise error from exc
    if layer is not None:
        raise InputShapeError("layer= applies to a file path (a .gpkg or other multi-layer file)")
    if isinstance(data, geopandas.GeoDataFrame):
        return data
    if isinstance(data, geopandas.GeoSeries):
        return geopandas.GeoDataFrame(geometry=data)
    if isinstance(data, dict):
        return _from_geojson(data)
    raise InputShapeError(f"expected a GeoDataFrame, GeoSeries, GeoJSON dict or a file path, "
                          f"got {type(data).__name__}")


def _from_geojson(data: dict[str, Any]) -> GeoDataFrame:
    import geopandas

    features = geojson_features(data)       # (InputShapeError for anything but GeoJSON)
    crs = ((data.get("crs") or {}).get("properties") or {}).get("name") or "EPSG:4326"
    frame = geopandas.GeoDataFrame.from_features(features, crs=crs)
    if "geometry" not in frame:          # no features: an empty layer
        frame = geopandas.GeoDataFrame(geometry=geopandas.GeoSeries([], crs=crs))
    return frame


def write_geojson(frame: GeoDataFrame, path: str | Path, *,
                  progress: Callable[[int], object] | None = None) -> None:
    """Write a GeoDataFrame as a GeoJSON FeatureCollection with every coordinate
    exact (Python's shortest round-trip repr: GDAL's GeoJSON writer trims digits
    that look like noise, ``-0.9500000000000001`` becomes ``-0.95``, even with
    ``SIGNIFICANT_FIGURES=17``). A CRS other than WGS 84 lon/lat goes into the
    legacy ``"crs"`` member, which GDAL (so geopandas.read_file) reads back;
    dates and times are written as ISO 8601 strings, missing values as null.

    The text is put together column by column rather than feature by feature:
    each distinct attribute value and coordinate is formatted once (a layer of
    triangles repeats its features' attributes and shares every vertex among
    about six triangles). ``progress``: called with the number of features
    written since the last call.

    >>> import geopandas, shapely, tempfile, os
    >>> layer = geopandas.GeoDataFrame({"v": [1]}, geometry=[shapely.box(0, 0, 0.95, 0.1 + 0.2)],
    ...                                crs="EPSG:32633")
    >>> path = os.path.join(tempfile.mkdtemp(), "exact.geojson")
    >>> write_geojson(layer, path)
    >>> back = geopandas.read_file(path)
    >>> back.crs.to_epsg(), back.geometry[0].equals_exact(layer.geometry[0], 0)
    (32633, True)
    """
    head = '{"type": "FeatureCollection", '
    crs = frame.crs
    if crs is not None and not _is_wgs84_lonlat(crs):
        epsg = crs.to_epsg()
        name = f"urn:ogc:def:crs:EPSG::{epsg}" if epsg else crs.to_wkt()
        head += f'"crs": {{"type": "name", "properties": {{"name": {json.dumps(name)}}}}}, '
    properties = _json_properties(frame.drop(columns=[frame.geometry.name]))
    geometries = _json_geometries(np.asarray(frame.geometry.array, dtype=object))
    with open(path, "w", encoding="utf-8") as f:
        f.write(head + '"features": [')
        for i in range(0, len(frame), GEOJSON_ROWS):
            rows = '{"type": "Feature", "properties": ' + properties[i:i + GEOJSON_ROWS] + \
                ', "geometry": ' + geometries[i:i + GEOJSON_ROWS] + '}'
            f.write(("\n" if i == 0 else ",\n") + ",\n".join(rows.tolist()))
            if progress is not None:
                progress(len(rows))
        f.write("\n]}\n")


def _json_properties(table) -> np.ndarray:
    """The JSON object of every row of ``table``, as an object array of str."""
    import pandas

    rows = np.full(len(table), "{", dtype=object)
    for j, column in enumerate(table.columns):
        values = table[column]
        try:
            codes, uniques = pandas.factorize(values, use_na_sentinel=True)
        except TypeError:                   # unhashable values (lists, dicts)
            codes, uniques = np.arange(len(values)), values.to_numpy(dtype=object)
        text = np.array([_json_text(v) for v in uniques] + ["null"], dtype=object)
        key = ("" if j == 0 else ", ") + json.dumps(str(column)) + ": "
        rows = rows + key + text[codes]     # code -1 (missing) is the last: null
    return rows + "}"


def _json_text(value) -> str:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return "null"                   # JSON has no NaN or infinity
    return json.dumps(value, default=json_value)


def _json_geometries(geoms: np.ndarray) -> np.ndarray:
    """The GeoJSON geometry of every shapely geometry, as an object array of str.
    Triangles (Polygons of one ring of four points, what :func:`triangulate`
    makes) are formatted from their coordinates, each distinct number once;
    anything else through ``shapely.geometry.mapping`` and ``json``."""
    types = shapely.get_type_id(geoms)
    triangles = (types == 3) & (shapely.get_num_interior_rings(geoms) == 0)
    triangles[triangles] = shapely.get_num_coordinates(geoms[triangles]) == 4
    out = np.empty(len(geoms), dtype=object)
    for has_z in (False, True):
        pick = np.flatnonzero(triangles & (shapely.has_z(geoms) == has_z))
        if len(pick):
            out[pick] = _json_triangles(shapely.get_coordinates(geoms[pick], include_z=has_z))
    empty = shapely.is_missing(geoms) | shapely.is_empty(geoms)
    out[empty] = "null"                     # as geopandas writes them
    for i in np.flatnonzero(~triangles & ~empty):
        out[i] = json.dumps(shapely.geometry.mapping(geoms[i]))
    return out


def _json_triangles(coords: np.ndarray) -> np.ndarray:
    """``{"type": "Polygon", ...}`` of triangles given as 4 closed corners each
    (rows of ``coords``); every distinct point is formatted once."""
    index, first = _distinct_rows(np.ascontiguousarray(coords, dtype=np.float64))
    rows = coords[first].tolist()
    text = np.array(["[" + ", ".join(map(repr, row)) + "]" for row in rows], dtype=object)
    corner = text[index.reshape(-1, 4)]
    return ('{"type": "Polygon", "coordinates": [[' + corner[:, 0] + ", " + corner[:, 1] + ", "
            + corner[:, 2] + ", " + corner[:, 3] + "]]}")


def _distinct_rows(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(index, first)``: rows equal bit for bit (so -0.0 is not 0.0) get the
    same ``index``; ``values[first[i]]`` is distinct row ``i``. Hashing, one
    column at a time (``pandas.factorize``), not sorting."""
    import pandas

    bits = values.view(np.int64)
    index = np.zeros(len(values), np.int64)
    for d in range(values.shape[1]):
        column, distinct = pandas.factorize(bits[:, d])
        index, _ = pandas.factorize(index * len(distinct) + column)
    first = np.empty(index.max() + 1 if len(index) else 0, np.int64)
    first[index[::-1]] = np.arange(len(index) - 1, -1, -1)
    return index, first


def _is_wgs84_lonlat(crs) -> bool:
    """EPSG:4326 or OGC:CRS84: what a GeoJSON file without a ``"crs"`` member means."""
    import pyproj

    return crs.to_epsg() == 4326 or crs == pyproj.CRS("OGC:CRS84")


def json_value(value: Any) -> Any:
    """JSON for attribute values the json module does not know."""
    if isinstance(value, (datetime.date, datetime.time)):      # also pandas.Timestamp
        return value.isoformat()
    if isinstance(value, np.generic):
        return value.item()
    return str(value)
