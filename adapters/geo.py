"""GIS adapter: mesh every polygon of a layer (GeoDataFrame, GeoJSON, Shapefile,
GeoPackage) in one call, keeping attributes, CRS and Z.

Data flow (DESIGN.md): a layer -> :class:`geopandas.GeoDataFrame` (:func:`read`)
-> optional projection (pyproj) -> ONE call of
:func:`cdt_plugin.adapters.shapely.triangulate_batch` (one PLC per feature: a
Polygon with its holes, or a MultiPolygon's parts together) -> :class:`GeoMesh`
(flat arrays in the layer's CRS) -> a GeoDataFrame of triangles, or one
``trimesh.Trimesh`` per feature.

* :func:`triangulate` -- the whole layer on one machine.
* :func:`triangulate_dask` -- a dask-geopandas GeoDataFrame, partition by partition
  (``map_partitions``), on any Dask cluster.
* :func:`voronoi` -- the Voronoi cell (the power diagram's, with weights) of every
  point of a point layer, clipped to a boundary polygon or layer; one row per point.
* ``gdf.cdt.triangulate(...)`` / ``gs.cdt.triangulate(...)`` -- :func:`triangulate` as
  a method of a GeoDataFrame or GeoSeries (:class:`CDTAccessor`, a pandas accessor
  registered when this module is imported).

Coordinates. Projected CRSs (UTM: 1e5 to 1e7 metres) need nothing special: the
engine decides every topological question with exact predicates on the coordinates
as given, so they are neither shifted nor scaled (a shift ``x - x0`` rounds). In a
geographic CRS (longitude, latitude) the triangulation would be Delaunay, and
``min_angle`` / ``max_area`` measured, in degree space: :class:`GeographicCRSWarning`
says so unless ``project=`` is given. ``project="utm"`` meshes in the UTM zone of the
data (``estimate_utm_crs`` at its bounding box's centre), ``"aeqd"`` in an
azimuthal equidistant projection centred at the bounding box's centre (for
lon/lat data the box takes the shortest longitude arc, so data across the
antimeridian is centred where it lies), a CRS (anything
``pyproj.CRS.from_user_input`` takes) in that projected CRS. The mesh is then mapped
back: every input vertex gets back its original coordinates exactly (bit for bit);
a Steiner vertex on a boundary edge goes to the same fraction of the original edge
(so the triangles still tile the original polygons, and neighbours sharing a border
stay seamless), and the other Steiner vertices are inverse-projected. The triangles
are constrained Delaunay (and meet ``min_angle``) in the meshing CRS. A feature whose
triangles would not stay counter-clockwise in the layer's CRS (one split at the
antimeridian, whose parts meet in the projection, or one too far from the
projection's centre) raises :class:`ProjectionError` (or is skipped).

Z. Polygons with Z keep it: input vertices keep their own z, Steiner and
intersection vertices get z interpolated linearly along their segment or inside
their triangle (:mod:`cdt_plugin.lift`), so the triangles form a 2.5D surface
(the triangle polygons are then 3D). Features without Z in the same layer give 2D
triangles.

>>> import geopandas, shapely
>>> layer = geopandas.GeoDataFrame({"name": ["square", "triangle"]}, crs="EPSG:32633",
...     geometry=[shapely.box(500000, 5000000, 500004, 5000004),
...               shapely.Polygon([(500010, 5000000), (500012, 5000000), (500011, 5000001)])])
>>> tris = triangulate(layer)
>>> tris[["feature", "position", "part", "name"]].values.tolist()
[[0, 0, 0, 'square'], [0, 0, 0, 'square'], [1, 1, 0, 'triangle']]
>>> tris.crs.to_epsg(), bool(tris.area.sum() == layer.area.sum())
(32633, True)
"""
from __future__ import annotations

import datetime
import json
import math
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, Callable, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cdt_plugin.optional import missing, require

try:
    import shapely
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.geo", extra="gis") from exc

from cdt_plugin import CDTError, InputShapeError, NoPolygonsError   # (NoPolygonsError: re-exported)
from cdt_plugin.batch import MeshBatch, check_batch_options
from cdt_plugin.parallel import available_cores, check_count

from .shapely import Repair, triangle_polygons, triangulate_batch

if TYPE_CHECKING:
    import dask_geopandas
    import pyarrow
    import pyproj
    import trimesh
    from geopandas import GeoDataFrame, GeoSeries

#: What :func:`read` takes: a GeoDataFrame, a GeoSeries, a GeoJSON dict or a path.
LayerLike = Union["GeoDataFrame", "GeoSeries", "dict[str, Any]", str, Path]
#: What ``project=`` takes: None, "utm", "aeqd", or a projected CRS (a ``pyproj.CRS``
#: or what ``pyproj.CRS.from_user_input`` reads: "EPSG:32633", 32633, WKT, ...).
ProjectLike = Union[str, int, "pyproj.CRS", None]
#: What :func:`voronoi`'s ``boundary`` takes: None, a shapely (Multi)Polygon, or a
#: polygon layer (anything :func:`read` takes).
BoundaryLike = Union["shapely.Geometry", LayerLike, None]

__all__ = ["triangulate", "triangulate_dask", "voronoi", "read", "write_geojson", "GeoMesh",
           "GeographicCRSWarning", "SkippedFeaturesWarning", "NoPolygonsError", "ProjectionError",
           "NotGeographicError", "CDTAccessor"]

OUTPUTS = ("geodataframe", "geoarrow", "trimesh", "mesh")
AUTO_PROGRESS_FEATURES = 5000       # progress=None: a bar above this many features (on a tty)
ID_COLUMNS = ("feature", "position", "part")
GEOJSON_ROWS = 50_000                # features per write (and progress step) of write_geojson
_POINT, _POLYGON, _MULTIPOINT, _MULTIPOLYGON, _COLLECTION = 0, 3, 4, 6, 7     # GEOS type ids
_TYPE_NAMES = ("Point", "LineString", "LinearRing", "Polygon", "MultiPoint", "MultiLineString",
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


# ------------------------------------------------------------------------ reading
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
            return geopandas.read_parquet(path)
        return geopandas.read_file(path, layer=layer, engine="pyogrio")
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

    kind = data.get("type")
    if kind == "FeatureCollection":
        features = data.get("features") or []
    elif kind == "Feature":
        features = [data]
    elif kind in ("Polygon", "MultiPolygon", "GeometryCollection", "Point", "MultiPoint",
                  "LineString", "MultiLineString"):
        features = [{"type": "Feature", "geometry": data, "properties": {}}]
    else:
        raise InputShapeError(f"expected a GeoJSON FeatureCollection, Feature or geometry, "
                              f"got type {kind!r}")
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
    return json.dumps(value, default=_json_value)


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


def _json_value(value):
    """JSON for attribute values the json module does not know."""
    if isinstance(value, (datetime.date, datetime.time)):      # also pandas.Timestamp
        return value.isoformat()
    if isinstance(value, np.generic):
        return value.item()
    return str(value)


# ------------------------------------------------------------------------ meshing
def triangulate(data: LayerLike, *, output: str = "geodataframe", project: ProjectLike = None,
                repair: Repair = False, errors: str = "raise", progress: bool | None = None,
                layer: str | int | None = None,
                **options: Any) -> GeoDataFrame | pyarrow.Table | list[trimesh.Trimesh | None] | GeoMesh:
    """Constrained Delaunay triangulation of every polygonal feature of a layer.

    Parameters
    ----------
    data : GeoDataFrame, GeoSeries, GeoJSON dict, or path
        See :func:`read`. Every Polygon / MultiPolygon feature is one PLC (a
        MultiPolygon's parts together; the polygonal members of a
        GeometryCollection too); other features (points, lines, empty, None) get
        no triangles. All features are meshed in ONE batch call.
    output : {"geodataframe", "geoarrow", "trimesh", "mesh"}
        ``"geodataframe"``: one row per triangle (see Returns). ``"geoarrow"``:
        the same rows as a ``pyarrow.Table`` with a GeoArrow geometry column
        (:meth:`GeoMesh.to_arrow`; no shapely object per triangle, so several
        times faster on big layers: the fast path with ``"mesh"``). ``"trimesh"``: a
        list with one ``trimesh.Trimesh`` per feature (``None`` for a feature
        without triangles), vertices (x, y, z) with z = the vertex z when the
        feature has Z, else 0. ``"mesh"``: the :class:`GeoMesh` arrays.
    project : None, "utm", "aeqd", or a projected CRS
        Mesh in a projected CRS and map the mesh back to the layer's CRS (input
        vertices exactly; see the module docstring). ``"utm"``: the layer's UTM
        zone (``estimate_utm_crs`` at its bounding box's centre); ``"aeqd"``: azimuthal
        equidistant centred at the bounding box's centre; anything
        ``pyproj.CRS.from_user_input`` takes: that CRS. Without it, a geographic
        layer warns (:class:`GeographicCRSWarning`).
    repair : bool or {"linework", "structure"}
        Invalid polygons raise :class:`cdt_plugin.InvalidGeometryError` naming the
        feature, unless repaired with ``shapely.make_valid`` (as in
        :func:`cdt_plugin.adapters.shapely.triangulate`).
    errors : {"raise", "skip"}
        ``"skip"``: a feature that cannot be meshed gets no triangles; the errors
        are in ``result.attrs["cdt_errors"]`` (feature label -> ``"ErrorClass:
        message"``, JSON-safe so that ``to_parquet`` still works; the exceptions
        themselves in ``GeoMesh.errors``) and a :class:`SkippedFeaturesWarning` says
        how many.
    progress : bool or None
        A tqdm bar over the features; None: when there are more than
        ``AUTO_PROGRESS_FEATURES`` features and stderr is a terminal.
    layer : str or int, optional
        The layer of a multi-layer file (GeoPackage).
    **options
        ``workers``: threads to mesh on (default: every core for a large layer;
        any number gives the same triangles), and the options of
        :func:`cdt_plugin.triangulate`: ``min_angle``, ``max_area`` (in the
        meshing CRS's units), ``intersections``, ...

    Returns
    -------
    GeoDataFrame (``output="geodataframe"``)
        One row per triangle, in feature order, with columns ``feature`` (the
        source row's index label), ``position`` (its row number), ``part`` (the
        polygon of a MultiPolygon it lies in), then every attribute column of the
        source row, and the geometry: the triangle as a Polygon with a
        counter-clockwise shell (3D when the feature has Z), in the source CRS.
        When a source column is already called ``feature``, ``position`` or
        ``part``, the three get a ``cdt_`` prefix.

    Raises
    ------
    NoPolygonsError
        Nothing polygonal in ``data``.
    cdt_plugin.InvalidGeometryError
        An invalid polygon (without ``repair``); the message starts
        ``feature <label>:`` and the exception has ``feature`` (label) and
        ``index`` (row number) attributes, as every per-feature CDTError.
    ProjectionError
        ``project=`` without a CRS, with a geographic CRS, coordinates that do not
        project, or a feature whose triangles turn clockwise when mapped back (a
        feature split at the antimeridian; ``errors="skip"`` skips it).

    Examples
    --------
    >>> import geopandas, shapely
    >>> square = shapely.Polygon([(0, 0, 0), (2, 0, 2), (2, 2, 2), (0, 2, 0)])
    >>> layer = geopandas.GeoDataFrame({"id": [7]}, geometry=[square], index=["a"])
    >>> tris = triangulate(layer, max_area=0.5)
    >>> len(tris), set(tris["feature"]), bool(tris.has_z.all())
    (8, {'a'}, True)
    >>> xyz = shapely.get_coordinates(tris.geometry, include_z=True)
    >>> bool((xyz[:, 2] == xyz[:, 0]).all())          # z = x on the plane, Steiner points too
    True
    >>> round(float(triangulate(layer, output="trimesh")[0].area), 9)      # 2 x 2 sqrt(2)
    5.656854249
    """
    if output not in OUTPUTS:
        raise CDTError(f"output must be one of {OUTPUTS}, got {output!r}")
    if output == "trimesh":
        require("trimesh", "output='trimesh'")     # before any work
    if output == "geoarrow":
        require("pyarrow", "output='geoarrow'", extra="gis")
    frame = read(data, layer=layer)
    mesh = _mesh(frame, project=project, repair=repair, errors=errors, progress=progress,
                 options=options, require_polygons=True, warn=True)
    if output == "mesh":
        return mesh
    if output == "trimesh":
        return mesh.to_trimesh()
    if output == "geoarrow":
        return mesh.to_arrow()
    return mesh.to_geodataframe()


# ------------------------------------------------------------------------ Voronoi
def voronoi(points: LayerLike, boundary: BoundaryLike = None, *,
            weights: str | ArrayLike | None = None) -> GeoDataFrame:
    """The Voronoi cell of every point of a point layer (the power diagram's cell
    with ``weights``), clipped to ``boundary``: one row per point.

    The diagram is :meth:`cdt_plugin.Triangulation.voronoi` of
    ``cdt_plugin.delaunay(xy, weights)`` (exact predicates: cocircular points
    give one Voronoi vertex, a grid gives square cells); the cells are cut to
    ``boundary`` with GEOS.

    Parameters
    ----------
    points : GeoDataFrame, GeoSeries, GeoJSON dict, or path
        A layer of Point geometries (see :func:`read`); Z is ignored (the cells
        are 2D). A MultiPoint, another geometry type, an empty or a missing
        (None) geometry raises :class:`cdt_plugin.InputShapeError` naming the
        row (explode MultiPoints first: ``layer.explode(index_parts=True)``).
    boundary : None, shapely Polygon / MultiPolygon, or a polygon layer
        What the cells are clipped to. None: the points' bounding box grown by
        its larger side on every side (:meth:`cdt_plugin.Voronoi.envelope`, the
        box ``shapely.voronoi_polygons`` uses; in a geographic CRS cut to
        longitudes -180..180 and latitudes -90..90). A shapely geometry is taken
        to be in the points' CRS. A layer (GeoDataFrame, GeoSeries, GeoJSON dict
        or path): the union of its polygons, reprojected to the points' CRS when
        both have a CRS and they differ (missing and empty rows are left out; a
        GeoJSON dict without a ``"crs"`` member is WGS 84, as :func:`read` says).
    weights : None, str, or array_like (n,)
        A power diagram: the name of a numeric column of ``points``, or one
        weight per row (in row order). Point ``p`` with weight ``w`` claims
        ``x`` where ``|x - p|^2 - w`` is smallest. A point whose weight is too
        small to claim anything (submerged; also the lighter of two equal points)
        gets an empty Polygon.

    Returns
    -------
    GeoDataFrame
        ``points`` with the same index, every attribute column and the CRS; the
        geometry column holds each point's cell: a Polygon, a MultiPolygon where
        a non-convex boundary cuts a cell in pieces, an empty Polygon where
        nothing of the cell is left (a point outside ``boundary`` whose cell
        misses it, a submerged weighted point). Equal points (duplicates) share
        their cell: every one of their rows gets it. Without weights the cells
        tile the boundary and every point inside it lies in its own cell.

    Raises
    ------
    cdt_plugin.TooFewPointsError
        The layer has no rows.
    cdt_plugin.InputShapeError
        A row that is not a Point (its ``index`` and ``feature`` attributes name
        it), or ``weights`` that is not a column or does not have one number per row.
    cdt_plugin.NonFiniteCoordinateError
        A NaN or infinite coordinate or weight.
    cdt_plugin.CollinearPointsError
        Fewer than three distinct points, or all on one line (no Voronoi vertex).
    cdt_plugin.ClipRegionError
        A boundary that is not polygonal, is invalid or empty, or contains none
        of the points.

    Coordinates are taken as they are: in a geographic CRS (lon/lat) the cells
    are those of distances in degrees, and :class:`GeographicCRSWarning` says
    so; reproject the points first (e.g. ``points.to_crs(points.estimate_utm_crs())``)
    for cells of distances on the ground.

    Examples
    --------
    >>> import geopandas, shapely
    >>> shops = geopandas.GeoDataFrame({"name": ["a", "b", "c", "d"]}, crs="EPSG:32633",
    ...     geometry=shapely.points([(1, 1), (3, 1), (1, 3), (3, 3)]), index=[10, 11, 12, 13])
    >>> cells = voronoi(shops, shapely.box(0, 0, 4, 4))
    >>> cells.index.tolist(), cells["name"].tolist(), cells.crs.to_epsg()
    ([10, 11, 12, 13], ['a', 'b', 'c', 'd'], 32633)
    >>> cells.geometry[10].bounds, cells.area.tolist()
    ((0.0, 0.0, 2.0, 2.0), [4.0, 4.0, 4.0, 4.0])
    >>> voronoi(shops, shapely.box(0, 0, 4, 4), weights=[1, 0, 0, 0]).area.tolist()
    [5.03125, 3.5, 3.5, 3.96875]
    """
    import geopandas

    import cdt_plugin

    frame = read(points)
    xy = _point_xy(frame)
    w = _point_weights(frame, weights)
    geographic = _is_geographic(frame.crs)
    if geographic:
        _warn_geographic_voronoi(frame.crs)
    clip = None if boundary is None else _clip_region(boundary, frame.crs)
    vor = cdt_plugin.delaunay(xy, w).voronoi()
    if clip is None:
        clip = _lonlat_box(vor.envelope(), xy) if geographic else vor.envelope()
    try:
        cells = vor.clipped(clip).to_shapely()
    except cdt_plugin.ClipRegionError as exc:
        raise cdt_plugin.ClipRegionError(f"boundary: {exc}") from None
    site = vor.point_region
    geoms = np.empty(len(frame), dtype=object)
    geoms[site >= 0] = cells[site[site >= 0]]
    geoms[site < 0] = shapely.Polygon()
    out = frame.copy()
    out[frame.geometry.name] = geopandas.GeoSeries(geoms, index=frame.index, crs=frame.crs)
    return out


def _point_xy(frame: GeoDataFrame) -> NDArray[np.float64]:
    """(n, 2) x, y of a layer of Points; InputShapeError naming the first row that
    is not a (non-empty) Point."""
    if not len(frame):
        from cdt_plugin import TooFewPointsError
        raise TooFewPointsError("the point layer is empty: no point, no Voronoi cell")
    geoms = np.asarray(frame.geometry.array, dtype=object)
    types = shapely.get_type_id(geoms)
    bad = np.flatnonzero((types != _POINT) | shapely.is_empty(geoms))
    if len(bad):
        i = int(bad[0])
        t = int(types[i])
        if t < 0:
            what, hint = "a missing geometry (None)", "drop the row or give it a point"
        elif shapely.is_empty(geoms[i]):
            what, hint = f"an empty {_TYPE_NAMES[t]}", "drop the row or give it a point"
        elif t == _MULTIPOINT:
            what = "a MultiPoint"
            hint = "explode it first (layer.explode(index_parts=True)) to give each point a cell"
        else:
            what, hint = f"a {_TYPE_NAMES[t]}", "the Voronoi diagram is of Point layers"
        more = f" ({len(bad)} such rows: {_describe(geoms[bad])})" if len(bad) > 1 else ""
        raise _relabel(InputShapeError(f"{what} where a Point is expected; {hint}{more}"), i, frame, None)
    return np.column_stack([shapely.get_x(geoms), shapely.get_y(geoms)]).astype(np.float64)


def _point_weights(frame: GeoDataFrame, weights: str | ArrayLike | None) -> NDArray[np.float64] | None:
    """The weights as (n,) float64: a column of ``frame`` or one value per row."""
    if weights is None:
        return None
    if isinstance(weights, str):
        columns = [c for c in frame.columns if c != frame.geometry.name]
        if weights not in columns:
            raise InputShapeError(f"weights={weights!r} is not a column of the point layer "
                                  f"(columns: {', '.join(map(str, columns)) or 'none'})")
        values: Any = frame[weights]
        name = f"column {weights!r}"
    else:
        values, name = weights, "weights"
    try:
        w = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name}: weights must be numbers") from None
    if w.shape != (len(frame),):
        raise InputShapeError(f"{name}: one weight per point is needed ({len(frame)}), "
                              f"got shape {w.shape}")
    bad = np.flatnonzero(~np.isfinite(w))
    if len(bad):
        from cdt_plugin import NonFiniteCoordinateError
        raise _relabel(NonFiniteCoordinateError(
            f"weight ({name}) {'missing' if np.isnan(w[bad[0]]) else 'infinite'}"
            + (f" ({len(bad)} rows without a finite weight)" if len(bad) > 1 else "")),
            int(bad[0]), frame, None)
    return w


def _clip_region(boundary: BoundaryLike, crs: Any) -> Any:
    """``boundary`` as one shapely geometry in ``crs``: a geometry as it is (the
    clip checks it), a layer as the union of its polygons."""
    from cdt_plugin import ClipRegionError

    if isinstance(boundary, shapely.Geometry):
        return boundary
    try:
        layer = read(boundary)
    except InputShapeError as exc:
        raise ClipRegionError(f"boundary: {exc}, or a shapely Polygon / MultiPolygon") from None
    if crs is not None and layer.crs is not None and layer.crs != crs:
        layer = layer.to_crs(crs)
    geoms = np.asarray(layer.geometry.array, dtype=object)
    present = ~shapely.is_missing(geoms) & ~shapely.is_empty(geoms)
    types = shapely.get_type_id(geoms)
    for i in np.flatnonzero(present & ~np.isin(types, (_POLYGON, _MULTIPOLYGON))):
        raise ClipRegionError(f"boundary feature {_plain(layer.index[i])} is a "
                              f"{_TYPE_NAMES[types[i]]}: the boundary is a layer of polygons")
    for i in np.flatnonzero(present & ~shapely.is_valid(geoms)):
        raise ClipRegionError(f"boundary feature {_plain(layer.index[i])} is invalid "
                              f"({shapely.is_valid_reason(geoms[i])}): repair it "
                              "(shapely.make_valid) first")
    if not present.any():
        raise ClipRegionError(f"the boundary layer has no polygon ({_describe(geoms)})")
    return shapely.union_all(geoms[present])


def _lonlat_box(box: tuple[float, float, float, float],
                xy: NDArray[np.float64]) -> tuple[float, float, float, float]:
    """The envelope of lon/lat points cut to longitudes -180..180 and latitudes
    -90..90 (when the points are in that range: else as it is)."""
    if not ((np.abs(xy[:, 0]) <= 180).all() and (np.abs(xy[:, 1]) <= 90).all()):
        return box
    xmin, ymin, xmax, ymax = box
    return (max(xmin, -180.0), max(ymin, -90.0), min(xmax, 180.0), min(ymax, 90.0))


def _warn_geographic_voronoi(crs: Any) -> None:
    warnings.warn(GeographicCRSWarning(
        f"the layer's CRS ({crs.name}) is geographic: the Voronoi cells are those of distances "
        "in degrees of longitude and latitude (not the nearest point on the ground away from "
        "the equator); reproject the points to a projected CRS first, e.g. "
        "points.to_crs(points.estimate_utm_crs()), for cells in metres"),
        stacklevel=_caller_stacklevel())


# ----------------------------------------------------------------- pandas accessor
class CDTAccessor:
    """``gdf.cdt`` / ``gs.cdt``: this module's meshing as a method of a GeoDataFrame
    or GeoSeries. Registered through pandas' extension API
    (``pandas.api.extensions.register_dataframe_accessor`` and
    ``register_series_accessor``) when this module is imported; geopandas has no
    registry of its own, and its classes subclass pandas', so they inherit it.
    On a pandas object that is not geographic (a DataFrame or Series of plain
    values), ``.cdt`` raises :class:`NotGeographicError`.

    >>> import geopandas, pandas, shapely
    >>> from cdt_plugin.adapters import geo           # registers .cdt
    >>> layer = geopandas.GeoDataFrame({"name": ["a", "b"]}, crs="EPSG:32633",
    ...     geometry=[shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 2)])
    >>> layer.cdt.triangulate()["name"].tolist()
    ['a', 'a', 'b', 'b']
    >>> tris = layer.geometry.cdt.triangulate(max_area=0.5)
    >>> len(tris), tris.crs.to_epsg()
    (6, 32633)
    >>> hasattr(pandas.DataFrame({"x": [1]}), "cdt")
    False
    """

    def __init__(self, obj: Any) -> None:
        self._obj = _geographic(obj)

    def triangulate(self, **options: Any) -> Any:
        """``triangulate(self)``: :func:`triangulate` of this GeoDataFrame or
        GeoSeries, with the same options (``output``, ``project``, ``repair``,
        ``errors``, ``progress``, ``workers``, ``min_angle``, ``max_area``, ...)
        and the same result."""
        return triangulate(self._obj, **options)


def _geographic(obj: Any) -> Any:
    """``obj`` when it is a GeoSeries or a GeoDataFrame with an active geometry
    column; else :class:`NotGeographicError` saying how to make one."""
    geopandas = sys.modules.get("geopandas")      # not imported: obj cannot be geographic
    if geopandas is not None and isinstance(obj, geopandas.GeoSeries):
        return obj
    if geopandas is not None and isinstance(obj, geopandas.GeoDataFrame):
        try:
            _ = obj.geometry              # raises without an active geometry column
        except AttributeError:
            raise NotGeographicError(
                ".cdt: the GeoDataFrame has no active geometry column (columns: "
                f"{list(obj.columns)}); set one with gdf.set_geometry(column)") from None
        return obj
    hint = ("geopandas.GeoDataFrame(frame, geometry=column)" if hasattr(obj, "columns") else
            "geopandas.GeoSeries(series)")
    raise NotGeographicError(f".cdt needs a GeoDataFrame or a GeoSeries, got a pandas "
                             f"{type(obj).__name__} with no geometry; make one with {hint}")


def _register_accessor() -> None:
    """``.cdt`` on every pandas DataFrame and Series (so on geopandas' subclasses)."""
    try:
        import pandas
    except ImportError:                 # no pandas, so no geopandas: nothing to hook into
        return
    pandas.api.extensions.register_dataframe_accessor("cdt")(CDTAccessor)
    pandas.api.extensions.register_series_accessor("cdt")(CDTAccessor)


def triangulate_dask(dask_geodataframe: dask_geopandas.GeoDataFrame, *, project: ProjectLike = None,
                     repair: Repair = False, errors: str = "raise", npartitions: int | None = None,
                     **options: Any) -> dask_geopandas.GeoDataFrame:
    """:func:`triangulate` for a dask-geopandas GeoDataFrame: every partition is
    meshed where it lives (``map_partitions``), on whatever Dask scheduler is
    active (a ``dask.distributed.Client`` connected to a cluster, or the local one).

    Returns a lazy dask-geopandas GeoDataFrame of triangles with the columns of
    ``triangulate(...)`` (``position`` is the row number within the partition;
    the index restarts in every partition). ``project="utm"`` / ``"aeqd"`` is
    resolved once, for the whole frame (from the bounds of every partition: one
    pass over the data; pass a CRS to avoid it), so every partition is meshed in the same
    CRS and the result equals the single-machine one. ``errors="skip"`` leaves the
    failing features without triangles (no warning from the workers). Options are
    those of :func:`triangulate` (``progress``: use Dask's own diagnostics;
    ``workers`` defaults to 1 here: Dask runs the partitions in parallel).

    ``npartitions``: the partitions to mesh (the frame is repartitioned to that
    many first). By default the frame's own, split evenly when there are fewer
    than two per worker that will run them (the threads of the connected
    ``dask.distributed`` client, else this machine's cores), so that a frame
    made in one piece (``from_geopandas(layer, npartitions=1)``) still uses
    every worker; more partitions than that are kept as they are.

    >>> import dask_geopandas, geopandas, shapely
    >>> layer = geopandas.GeoDataFrame({"v": [1, 2]}, geometry=[shapely.box(0, 0, 1, 1),
    ...                                shapely.box(2, 0, 3, 1)])
    >>> tris = triangulate_dask(dask_geopandas.from_geopandas(layer, npartitions=2))
    >>> tris.compute(scheduler="sync")["v"].tolist()
    [1, 1, 2, 2]
    """
    options.pop("progress", None)
    options.setdefault("workers", 1)    # Dask runs the partitions in parallel
    check_batch_options(errors=errors, **options)
    count = check_count(npartitions, "npartitions")
    wanted = count if count is not None else max(dask_geodataframe.npartitions, 2 * _dask_workers())
    if wanted != dask_geodataframe.npartitions:
        dask_geodataframe = dask_geodataframe.repartition(npartitions=wanted)
    crs = dask_geodataframe.crs
    if _centred(project):
        project = _target_crs(project, crs, _dask_extent(dask_geodataframe))
    elif project is not None:
        project = _target_crs(project, crs, None)
    elif _is_geographic(crs):
        _warn_geographic(crs)
    kwargs = dict(project=project, repair=repair, errors=errors, **options)
    meta = _triangulate_partition(dask_geodataframe._meta, **kwargs)
    return dask_geodataframe.map_partitions(_triangulate_partition, meta=meta, **kwargs)


def _dask_workers() -> int:
    """The threads that will run a Dask computation: the connected distributed
    client's (all its workers'), else this machine's cores (the threaded
    scheduler)."""
    try:
        from distributed import get_client
        return max(1, sum(get_client().nthreads().values()))
    except (ImportError, ValueError):       # no distributed, or no client connected
        return available_cores()


def _dask_extent(dask_geodataframe) -> np.ndarray:
    """:func:`_extent` of a dask GeoDataFrame, partition by partition (one pass)."""
    import dask

    geographic = _is_geographic(dask_geodataframe.crs)
    parts = [dask.delayed(_frame_extent)(p, geographic) for p in dask_geodataframe.to_delayed()]
    rows = [r for r in dask.compute(*parts) if len(r)]
    return np.concatenate(rows) if rows else np.empty((0, 4))


def _frame_extent(frame, geographic: bool) -> np.ndarray:
    return _extent(np.asarray(frame.geometry.array, dtype=object), geographic)


def _triangulate_partition(frame, *, project=None, repair=False, errors="raise", **options):
    """One partition of :func:`triangulate_dask` (also its meta, from an empty frame)."""
    mesh = _mesh(frame, project=project, repair=repair, errors=errors, progress=False,
                 options=options, require_polygons=False, warn=False)
    return mesh.to_geodataframe()


def _mesh(frame, *, project, repair, errors, progress, options, require_polygons, warn):
    """Mesh the features of ``frame`` (one batch call) into a :class:`GeoMesh`."""
    check_batch_options(errors=errors, **options)
    geoms = np.asarray(frame.geometry.array, dtype=object)
    if require_polygons:
        _require_polygons(geoms)
    extent = _extent(geoms, _is_geographic(frame.crs)) if _centred(project) else None
    target = _target_crs(project, frame.crs, extent)
    if warn and target is None and _is_geographic(frame.crs):
        _warn_geographic(frame.crs)
    meshed = _uniform_z(geoms if target is None else _project(geoms, frame, target))
    if progress is None:
        progress = len(geoms) > AUTO_PROGRESS_FEATURES and sys.stderr.isatty()
    try:
        batch = triangulate_batch(meshed, repair=repair, errors=errors, progress=bool(progress),
                                  **options)
    except CDTError as e:
        if e.index is None:
            raise
        raise _relabel(e, e.index, frame, target) from None
    failed = {int(i): _relabel(e, int(i), frame, target) for i, e in batch.errors.items()}
    T, position, part, vertices = batch.triangles, batch.geometry, batch.region, batch.vertices
    if target is not None:
        vertices = _restore(vertices, T, geoms, meshed, target, frame.crs)
        folded = _folded_features(vertices, T, position, frame, target, errors)
        if folded:
            failed.update(folded)
            keep = ~np.isin(position, list(folded))
            T, position, part = T[keep], position[keep], part[keep]
    if warn and failed:
        _warn_skipped(failed, frame)
    offsets = np.searchsorted(position, np.arange(len(geoms) + 1)).astype(np.int64)
    return GeoMesh(frame, vertices, batch.z, T, position, part, offsets, failed, target, batch,
                   options.get("workers"))


def _folded_features(V, T, position, frame, target, errors) -> dict:
    """Features with triangles that are no longer counter-clockwise once mapped back
    to the layer's CRS: a ProjectionError each (raised at once with ``errors="raise"``)."""
    bad = position[~_counter_clockwise(V, T)]
    out = {}
    for i, count in zip(*np.unique(bad, return_counts=True)):
        e = ProjectionError(
            f"feature {_plain(frame.index[i])}: {count} of its triangles turn clockwise when mapped "
            f"back from {target.name!r} to {frame.crs.name!r} (parts split at the antimeridian "
            "meet in the projection, or the feature lies too far from the projection's centre); "
            "mesh it unprojected or in a CRS where it is in one piece")
        e.index, e.feature = int(i), _plain(frame.index[i])
        if errors == "raise":
            raise e
        out[int(i)] = e
    return out


def _counter_clockwise(V: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Per triangle: a positive (floating-point) cross product of its edges. A check of
    the mapped-back output, never a meshing decision."""
    P = V[T]
    u, v = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0


def _uniform_z(geoms: np.ndarray) -> np.ndarray:
    """In a layer that mixes features with and without Z, the 2D ones get z = 0
    (so that every vertex of the batch has a z to interpolate from); their
    triangles stay 2D (:attr:`GeoMesh.feature_has_z` is read from the source)."""
    has_z = shapely.has_z(geoms)
    if not has_z.any() or has_z.all():
        return geoms
    return np.where(has_z, geoms, shapely.force_3d(geoms, 0.0))


def _require_polygons(geoms: np.ndarray) -> None:
    if not _polygonal(geoms).any():
        raise NoPolygonsError(f"no Polygon or MultiPolygon feature to triangulate "
                              f"({_describe(geoms)})")


def _polygonal(geoms: np.ndarray) -> np.ndarray:
    """Per geometry: a non-empty Polygon / MultiPolygon, or a GeometryCollection with one."""
    types = shapely.get_type_id(geoms)
    out = np.isin(types, (_POLYGON, _MULTIPOLYGON)) & ~shapely.is_empty(geoms)
    rows = np.flatnonzero(types == _COLLECTION)
    if len(rows):
        parts, where = shapely.get_parts(geoms[rows], return_index=True)
        ok = np.isin(shapely.get_type_id(parts), (_POLYGON, _MULTIPOLYGON)) & ~shapely.is_empty(parts)
        out[rows[where[ok]]] = True
    return out


def _describe(geoms: np.ndarray) -> str:
    """What a layer holds, e.g. ``3 feature(s): 2 Point, 1 None``."""
    if not len(geoms):
        return "the layer is empty"
    types = shapely.get_type_id(geoms)
    empty = shapely.is_empty(geoms)
    kinds = ["None" if t < 0 else ("empty " if e else "") + _TYPE_NAMES[t]
             for t, e in zip(types, empty)]
    values, counts = np.unique(kinds, return_counts=True)
    return f"{len(geoms)} feature(s): " + ", ".join(f"{c} {v}" for v, c in zip(values, counts))


def _relabel(e: CDTError, i: int, frame: GeoDataFrame, target: pyproj.CRS | None) -> CDTError:
    """A batch error (``geometry i: ...``, for row ``i``) renamed after the feature's
    index label."""
    label = _plain(frame.index[i])
    message = e.args[0] if e.args else ""
    prefix = f"geometry {i}: "
    message = message[len(prefix):] if message.startswith(prefix) else message
    if target is not None:
        message += f" (coordinates in the meshing CRS {target.name!r})"
    e.args = (f"feature {label}: {message}",) + tuple(e.args[1:])
    e.index, e.feature = i, label
    return e


def _plain(value):
    """A NumPy scalar as the Python value (labels in messages and columns)."""
    return value.item() if isinstance(value, np.generic) else value


def _warn_skipped(failed: dict, frame) -> None:
    labels = [str(_plain(frame.index[i])) for i in sorted(failed)]
    shown = ", ".join(labels[:10]) + (", ..." if len(labels) > 10 else "")
    warnings.warn(SkippedFeaturesWarning(
        f"{len(failed)} feature(s) could not be meshed and have no triangles ({shown}); "
        'their errors are in result.attrs["cdt_errors"]'), stacklevel=_caller_stacklevel())


# --------------------------------------------------------------------- projection
def _is_geographic(crs) -> bool:
    return crs is not None and bool(crs.is_geographic)


def _caller_stacklevel() -> int:
    """The ``stacklevel`` (for ``warnings.warn`` called by the caller of this function)
    that points at the first frame outside this module: the user's line, whether it
    called :func:`triangulate`, :func:`triangulate_dask` or ``gdf.cdt.triangulate``."""
    frame: FrameType | None = sys._getframe(1)
    level = 1
    while frame is not None and frame.f_code.co_filename == __file__:
        frame, level = frame.f_back, level + 1
    return level


def _warn_geographic(crs) -> None:
    warnings.warn(GeographicCRSWarning(
        f"the layer's CRS ({crs.name}) is geographic: the triangulation is Delaunay, and "
        "min_angle / max_area are measured, in degrees of longitude and latitude (angles and "
        "areas distorted away from the equator); pass project='utm', 'aeqd' or a projected "
        "CRS to mesh in metres (input vertices keep their coordinates exactly)"),
        stacklevel=_caller_stacklevel())


def _extent(geoms: np.ndarray, geographic: bool) -> np.ndarray:
    """Rows (xmin, ymin, xmax, ymax) that together bound the geometries: the total
    bounds, or for a geographic CRS the bounds of the polygon parts with their
    longitude ranges merged (a few rows; the longitudes are on a circle)."""
    geoms = geoms[~shapely.is_missing(geoms) & ~shapely.is_empty(geoms)]
    if not len(geoms):
        return np.empty((0, 4))
    if not geographic:
        b = shapely.bounds(geoms)
        return np.array([[b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()]])
    return _merge_longitudes(shapely.bounds(shapely.get_parts(geoms)))


def _merge_longitudes(rows: np.ndarray) -> np.ndarray:
    """Bounds rows with overlapping longitude ranges merged (latitudes: min / max)."""
    rows = rows[np.argsort(rows[:, 0], kind="stable")]
    out = [rows[0].copy()]
    for r in rows[1:]:
        if r[0] <= out[-1][2]:
            out[-1][1:] = [min(out[-1][1], r[1]), max(out[-1][2], r[2]), max(out[-1][3], r[3])]
        else:
            out.append(r.copy())
    return np.array(out)


def _centre(extent: np.ndarray, crs) -> tuple[float, float]:
    """(lon, lat) of the data's bounding-box centre. For a geographic CRS the box
    is the shortest longitude arc covering the data, so data across the
    antimeridian (Fiji, Russia, Alaska) is centred where it is, not at lon 0."""
    import pyproj

    xmin, ymin, xmax, ymax = extent[:, 0].min(), extent[:, 1].min(), extent[:, 2].max(), extent[:, 3].max()
    if not crs.is_geographic:
        to_lonlat = pyproj.Transformer.from_crs(crs, crs.geodetic_crs, always_xy=True)
        lon, lat = to_lonlat.transform(0.5 * (xmin + xmax), 0.5 * (ymin + ymax))
        return float(lon), float(lat)
    rows = _merge_longitudes(extent)
    starts, ends = rows[:, 0], rows[:, 2]
    gaps = np.append(starts[1:] - ends[:-1], starts[0] + 360.0 - ends[-1])
    k = int(np.argmax(gaps))
    if gaps[k] <= 0:                  # all longitudes covered: the plain centre
        return float(0.5 * (xmin + xmax)), float(0.5 * (ymin + ymax))
    # the covered arc runs east from the end of the largest gap to its start
    west = starts[(k + 1) % len(rows)]
    east = ends[k] + (360.0 if k + 1 < len(rows) else 0.0)
    lon = (0.5 * (west + east) + 180.0) % 360.0 - 180.0
    return float(lon), float(0.5 * (ymin + ymax))


def _centred(project) -> bool:
    """Whether ``project`` is centred on the data (``"utm"`` or ``"aeqd"``)."""
    return isinstance(project, str) and project in ("utm", "aeqd")


def _target_crs(project, crs, extent):
    """The projected CRS to mesh in (None: mesh in the layer's own CRS)."""
    if project is None:
        return None
    import pyproj

    if _centred(project):
        if crs is None:
            raise ProjectionError(f"project={project!r} needs the layer's CRS: the layer has "
                                  "none (set it with gdf.set_crs(...))")
        if extent is None or not len(extent):
            raise ProjectionError(f"project={project!r} needs coordinates to centre the "
                                  "projection on: the layer has none")
        lon, lat = _centre(extent, crs)
        return _utm_crs(crs, lon, lat) if project == "utm" else _aeqd_crs(crs, lon, lat)
    if isinstance(project, pyproj.CRS):
        target = project
    else:
        try:
            target = pyproj.CRS.from_user_input(project)
        except pyproj.exceptions.CRSError as exc:
            raise ProjectionError(f"project must be 'utm', 'aeqd' or a projected CRS, got "
                                  f"{project!r} ({exc})") from None
    if not target.is_projected:
        raise ProjectionError(f"project={target.name!r} is not a projected CRS")
    if crs is None:
        raise ProjectionError("project= needs the layer's CRS: the layer has none "
                              "(set it with gdf.set_crs(...))")
    return target


def _utm_crs(crs, lon: float, lat: float):
    """The UTM zone (WGS 84) at the data's centre (geopandas' ``estimate_utm_crs``)."""
    import geopandas

    return geopandas.GeoSeries([shapely.Point(lon, lat)], crs=crs.geodetic_crs).estimate_utm_crs()


def _aeqd_crs(crs, lon: float, lat: float):
    """Azimuthal equidistant CRS centred at (lon, lat), on the layer's own datum (so
    that projecting is a conversion, no datum shift)."""
    import pyproj
    from pyproj.crs.coordinate_operation import AzimuthalEquidistantConversion

    return pyproj.crs.ProjectedCRS(
        AzimuthalEquidistantConversion(latitude_natural_origin=lat, longitude_natural_origin=lon),
        name=f"Azimuthal equidistant centred at lon {lon:.6f}, lat {lat:.6f}",
        geodetic_crs=crs.geodetic_crs)


def _xy_transform(transformer):
    """A shapely.transform function that maps x and y and keeps z."""
    def apply(coords: np.ndarray) -> np.ndarray:
        out = np.array(coords, dtype=np.float64)
        if len(out):
            out[:, 0], out[:, 1] = transformer.transform(coords[:, 0], coords[:, 1])
        return out
    return apply


def _project(geoms: np.ndarray, frame, target) -> np.ndarray:
    """The geometries in ``target`` (same coordinate count and order, z kept)."""
    import pyproj

    forward = pyproj.Transformer.from_crs(frame.crs, target, always_xy=True)
    projected = shapely.transform(geoms, _xy_transform(forward), include_z=None)
    counts = shapely.get_num_coordinates(projected)
    xy = shapely.get_coordinates(projected)
    bad = ~np.isfinite(xy).all(axis=1)
    if bad.any():
        i = int(np.searchsorted(np.cumsum(counts), np.flatnonzero(bad)[0], side="right"))
        raise ProjectionError(f"feature {_plain(frame.index[i])}: coordinates do not project to "
                              f"finite values in {target.name!r}")
    return projected


def _restore(V: np.ndarray, T: np.ndarray, geoms: np.ndarray, projected: np.ndarray, target,
             crs) -> np.ndarray:
    """Mesh vertices back in the layer's CRS. A vertex at the projected position of
    an input coordinate gets that input coordinate, exactly. A Steiner vertex on a
    boundary edge goes to the same fraction of the original edge (so the triangles
    tile the original polygon), unless that inverts one of its triangles; the
    other Steiner vertices are inverse-projected."""
    import pyproj

    back = pyproj.Transformer.from_crs(target, crs, always_xy=True)
    original = shapely.get_coordinates(geoms)
    row = _find_rows(V, shapely.get_coordinates(projected))
    out = np.empty_like(V)
    is_input = row >= 0
    out[is_input] = original[row[is_input]]
    steiner = np.flatnonzero(~is_input)
    if len(steiner):
        out[steiner] = np.column_stack(back.transform(V[steiner, 0], V[steiner, 1]))
    a, b = _boundary_ends(T, is_input)
    on_edge = np.flatnonzero(a >= 0)
    on_edge = on_edge[_are_input_edges(V[a[on_edge]], V[b[on_edge]], projected)]
    if len(on_edge):
        inverse = out[on_edge].copy()
        a, b = a[on_edge], b[on_edge]
        d = V[b] - V[a]
        t = ((V[on_edge] - V[a]) * d).sum(axis=1) / (d * d).sum(axis=1)
        out[on_edge] = out[a] + t[:, None] * (out[b] - out[a])
        _untangle(out, T, on_edge, inverse)
    return out


def _untangle(out: np.ndarray, T: np.ndarray, moved: np.ndarray, inverse: np.ndarray) -> None:
    """Put boundary Steiner vertices that were moved onto their original edge back
    at their inverse-projected position where the move turned a triangle
    clockwise (a sliver at a small input angle near a long, curved edge)."""
    keep = np.ones(len(moved), bool)
    for _ in range(16):
        undo = keep & np.isin(moved, T[~_counter_clockwise(out, T)])
        if not undo.any():
            return
        out[moved[undo]] = inverse[undo]
        keep &= ~undo


def _boundary_ends(T: np.ndarray, is_input: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For every vertex on a boundary edge between two input vertices (a split
    input segment): the input vertices before and after it along the boundary;
    -1 elsewhere. Boundary edges are those of one triangle (counter-clockwise
    around the domain); chains are followed by pointer doubling."""
    n = len(is_input)
    E = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    _, inverse, count = np.unique(np.sort(E, axis=1), axis=0, return_inverse=True,
                                  return_counts=True)
    src, dst = E[count[inverse.ravel()] == 1].T
    after, before = np.arange(n), np.arange(n)
    after[src[~is_input[src]]] = dst[~is_input[src]]
    before[dst[~is_input[dst]]] = src[~is_input[dst]]
    for _ in range(max(int(n).bit_length(), 1)):
        after, before = after[after], before[before]
    ok = ~is_input & is_input[after] & is_input[before]
    return np.where(ok, before, -1), np.where(ok, after, -1)


def _are_input_edges(A: np.ndarray, B: np.ndarray, geoms: np.ndarray) -> np.ndarray:
    """For each pair of points (rows of ``A`` and ``B``): whether they are the two
    ends of one ring edge of ``geoms`` (either direction; exact coordinates). Points
    that ``repair`` added are not, so a vertex between them is not on an input edge."""
    rings = shapely.get_rings(shapely.get_parts(geoms))
    coords, ring = shapely.get_coordinates(rings, return_index=True)
    points, ids = np.unique(_as_complex(coords), return_inverse=True)
    ids = ids.ravel()
    n = len(points)
    same_ring = ring[1:] == ring[:-1]
    i, j = ids[:-1][same_ring], ids[1:][same_ring]
    edges = np.unique(np.concatenate([i * n + j, j * n + i]))
    ia, ib = _find_rows(A, points), _find_rows(B, points)
    return (ia >= 0) & (ib >= 0) & (ia != ib) & np.isin(ia * n + ib, edges)


def _as_complex(xy: np.ndarray) -> np.ndarray:
    """(x, y) rows as complex numbers: sortable and comparable as one value."""
    c = np.empty(len(xy), np.complex128)
    c.real, c.imag = xy[:, 0], xy[:, 1]
    return c


def _find_rows(keys: np.ndarray, table) -> np.ndarray:
    """For each (x, y) row of ``keys`` a row of ``table`` ((m, 2), or (m,) complex)
    with the same coordinates (exact equality), or -1."""
    t = table if np.iscomplexobj(table) else _as_complex(table)
    k = _as_complex(keys)
    if not len(t):
        return np.full(len(k), -1, np.int64)
    order = np.argsort(t, kind="stable")
    ts = t[order]
    pos = np.minimum(np.searchsorted(ts, k), len(ts) - 1)
    return np.where(ts[pos] == k, order[pos], -1).astype(np.int64)


# ------------------------------------------------------------------------- result
@dataclass
class GeoMesh:
    """The triangles of a layer as flat arrays (what :func:`triangulate` builds its
    outputs from; ``output="mesh"`` returns it).

    Attributes
    ----------
    source : GeoDataFrame
        The features as read (index, attributes, CRS).
    vertices : (n, 2) float64
        Mesh vertices in the source CRS (input vertices with their original
        coordinates, bit for bit).
    z : (n,) float64 or None
        Z of every vertex when the layer has Z (0 for features without Z).
    triangles : (k, 3) int64
        Counter-clockwise (in the meshing CRS), grouped by feature.
    position : (k,) int64
        The source row (0-based position) of each triangle.
    part : (k,) int64
        The polygon (of a MultiPolygon) each triangle lies in.
    offsets : (g + 1,) int64
        Triangles of row ``i`` are ``triangles[offsets[i]:offsets[i + 1]]``.
    errors : dict
        Row position -> CDTError of the features skipped with ``errors="skip"``.
    mesh_crs : pyproj.CRS or None
        The CRS the meshing was done in (None: the source CRS).
    batch : MeshBatch
        The engine's result (vertices in the meshing CRS).
    workers : int or None
        Threads for making the outputs (the triangle Polygons), as meshed with.
    """

    source: GeoDataFrame
    vertices: NDArray[np.float64]
    z: NDArray[np.float64] | None
    triangles: NDArray[np.int64]
    position: NDArray[np.int64]
    part: NDArray[np.int64]
    offsets: NDArray[np.int64]
    errors: dict[int, CDTError] = field(default_factory=dict)
    mesh_crs: pyproj.CRS | None = None
    batch: MeshBatch | None = None
    workers: int | None = None

    def __len__(self) -> int:
        return len(self.triangles)

    @property
    def feature_has_z(self) -> NDArray[np.bool_]:
        """(g,) bool: which source features have Z."""
        return shapely.has_z(np.asarray(self.source.geometry.array, dtype=object))

    def boundary_edges(self) -> NDArray[np.int64]:
        """(s, 2) vertex pairs of the edges used by one triangle only: the pieces of
        the polygons' rings (the segments), for valid polygons."""
        T = self.triangles
        e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
        uniq, count = np.unique(e, axis=0, return_counts=True)
        return uniq[count == 1]

    def feature_mesh(self, i: int) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
        """Row ``i`` alone: ``(vertices, triangles)`` with only its vertices,
        (m, 3) when the feature has Z, else (m, 2)."""
        T = self.triangles[self.offsets[i]:self.offsets[i + 1]]
        used, local = np.unique(T, return_inverse=True)
        V = self.vertices[used]
        if self.z is not None and self.feature_has_z[i]:
            V = np.column_stack([V, self.z[used]])
        return V, local.reshape(-1, 3)

    def triangle_polygons(self) -> NDArray[np.object_]:
        """One shapely Polygon per triangle (counter-clockwise closed shell; 3D
        for features with Z), built from flat coordinate arrays in one call per
        dimension and thread (``shapely.from_ragged_array``: about twice as fast
        as ``shapely.polygons``, which builds a LinearRing first; on
        :attr:`workers` threads for large layers)."""
        corners = self.triangles[:, [0, 1, 2, 0]]
        if self.z is None:
            return triangle_polygons(self.vertices, corners, self.workers)
        out = np.empty(len(corners), dtype=object)
        has_z = self.feature_has_z[self.position]
        out[~has_z] = triangle_polygons(self.vertices, corners[~has_z], self.workers)
        out[has_z] = triangle_polygons(np.column_stack([self.vertices, self.z]), corners[has_z],
                                       self.workers)
        return out

    def to_geodataframe(self) -> GeoDataFrame:
        """One row per triangle (see :func:`triangulate`)."""
        import geopandas

        src = self.source
        name = src.geometry.name
        table = src.drop(columns=[name]).iloc[self.position].reset_index(drop=True)
        ids = _id_column_names(table.columns)
        table.insert(0, ids[0], src.index.to_numpy()[self.position])
        table.insert(1, ids[1], self.position)
        table.insert(2, ids[2], self.part)
        geometry = geopandas.GeoSeries(self.triangle_polygons(), crs=src.crs, name=name)
        out = geopandas.GeoDataFrame(table, geometry=geometry, crs=src.crs)
        if self.errors:
            out.attrs["cdt_errors"] = {_plain(src.index[i]): f"{type(e).__name__}: {e}"
                                       for i, e in self.errors.items()}
        return out

    def to_arrow(self) -> pyarrow.Table:
        """One row per triangle, as :meth:`to_geodataframe` has them, in a
        ``pyarrow.Table`` whose geometry column is GeoArrow (``geoarrow.polygon``,
        interleaved ``xy`` or ``xyz`` coordinates, the CRS as PROJJSON in the
        field's extension metadata), built from the mesh arrays without a
        shapely object per triangle. A layer with Z gives ``xyz``, z 0 for its
        features without Z (as :attr:`z`); another geometry column of the layer
        is kept as WKB (``geoarrow.wkb``), and the labels of a MultiIndex (as
        ``explode`` makes) as a struct of its levels. ``geopandas.GeoDataFrame.from_arrow``
        reads it back (``geometry=`` names the triangles' column when there are
        two), and the table carries GeoParquet's ``geo`` metadata:
        ``pyarrow.parquet.write_table`` writes it as a GeoParquet file.

        >>> import geopandas, shapely
        >>> layer = geopandas.GeoDataFrame({"id": [7]}, geometry=[shapely.box(0, 0, 2, 2)])
        >>> table = triangulate(layer, output="mesh").to_arrow()
        >>> table.column_names, table.num_rows
        (['feature', 'position', 'part', 'id', 'geometry'], 2)
        >>> table.field("geometry").metadata[b"ARROW:extension:name"]
        b'geoarrow.polygon'
        """
        import geopandas
        import pandas

        pa = require("pyarrow", "GeoArrow output", extra="gis")
        src = self.source
        name = src.geometry.name
        features = pandas.DataFrame(src.drop(columns=[name]))   # one row per feature...
        ids = _id_column_names(features.columns)
        features.insert(0, ids[1], np.arange(len(src)))
        other_geometries = {c: features[c].array.crs for c in features.columns
                            if isinstance(features[c].dtype, geopandas.array.GeometryDtype)}
        for c in other_geometries:                             # (a second geometry column: WKB)
            features[c] = shapely.to_wkb(np.asarray(features[c].array, dtype=object))
        table = pa.Table.from_pandas(features, preserve_index=False).take(self.position)  # ...per triangle
        for c, crs in other_geometries.items():
            j = table.schema.get_field_index(c)
            table = table.set_column(j, _geoarrow_field(pa, c, table.schema.field(c).type,
                                                        "geoarrow.wkb", crs), table.column(j))
        table = table.add_column(0, ids[0], _index_labels(pa, src.index).take(self.position))
        table = table.add_column(2, ids[2], pa.array(self.part))
        geometry, field_ = _geoarrow_polygons(pa, self.vertices, self.z, self.triangles, src.crs, name)
        table = table.append_column(field_, geometry)
        geo_metadata = _geoparquet_metadata(name, src.crs, self.z is not None, other_geometries)
        return table.replace_schema_metadata({**(table.schema.metadata or {}),
                                              b"geo": json.dumps(geo_metadata).encode()})

    def to_trimesh(self) -> list[trimesh.Trimesh | None]:
        """One ``trimesh.Trimesh`` per source row (None without triangles); z is
        the vertex z for features with Z, else 0."""
        import trimesh

        out: list[trimesh.Trimesh | None] = []
        for i in range(len(self.offsets) - 1):
            if self.offsets[i] == self.offsets[i + 1]:
                out.append(None)
                continue
            V, T = self.feature_mesh(i)
            if V.shape[1] == 2:
                V = np.column_stack([V, np.zeros(len(V))])
            out.append(trimesh.Trimesh(V, T, process=False))
        return out


def _index_labels(pa: Any, index: Any) -> Any:
    """A layer's index labels as an Arrow array; a MultiIndex (``explode`` makes
    one) as a struct of its levels (named, or ``level_0``, ``level_1``...)."""
    if index.nlevels == 1:
        return pa.Array.from_pandas(index.to_series(index=None))
    names = [n if n is not None else f"level_{i}" for i, n in enumerate(index.names)]
    return pa.StructArray.from_arrays(
        [pa.Array.from_pandas(index.get_level_values(i).to_series(index=None))
         for i in range(index.nlevels)], names=names)


def _geoarrow_polygons(pa: Any, V: NDArray[np.float64], z: NDArray[np.float64] | None,
                       T: NDArray[np.int64], crs: Any, name: str) -> tuple[Any, Any]:
    """The triangles as a GeoArrow ``geoarrow.polygon`` array (one closed
    counter-clockwise ring each, interleaved coordinates; the field names of
    the GeoArrow specification: ``rings``, ``vertices``, ``xy``/``xyz``) and
    its field. Offsets are 32-bit up to 2**31 coordinates, 64-bit beyond."""
    k = len(T)
    corners = T[:, [0, 1, 2, 0]].reshape(-1)
    xy = V[corners] if z is None else np.column_stack([V[corners], z[corners]])
    dims = "xy" if z is None else "xyz"
    offsets_type = np.int32 if 4 * k < 2 ** 31 else np.int64
    list_array = pa.ListArray if offsets_type is np.int32 else pa.LargeListArray
    list_type = pa.list_ if offsets_type is np.int32 else pa.large_list
    coords = pa.FixedSizeListArray.from_arrays(pa.array(np.ascontiguousarray(xy).reshape(-1)),
                                               type=pa.list_(pa.field(dims, pa.float64()), len(dims)))
    rings = list_array.from_arrays(pa.array(np.arange(0, 4 * k + 1, 4, dtype=offsets_type)), coords,
                                   type=list_type(pa.field("vertices", coords.type)))
    polygons = list_array.from_arrays(pa.array(np.arange(k + 1, dtype=offsets_type)), rings,
                                      type=list_type(pa.field("rings", rings.type)))
    return polygons, _geoarrow_field(pa, name, polygons.type, "geoarrow.polygon", crs)


def _geoarrow_field(pa: Any, name: str, type_: Any, extension: str, crs: Any) -> Any:
    """A field of GeoArrow extension type ``extension`` (by its field metadata),
    the CRS as PROJJSON."""
    metadata = {"crs": crs.to_json_dict(), "crs_type": "projjson"} if crs is not None else {}
    return pa.field(name, type_, metadata={b"ARROW:extension:name": extension.encode(),
                                           b"ARROW:extension:metadata": json.dumps(metadata).encode()})


def _geoparquet_metadata(name: str, crs: Any, has_z: bool,
                         wkb_columns: dict[str, Any]) -> dict[str, Any]:
    """The ``geo`` metadata of GeoParquet 1.1 for a column of GeoArrow polygons
    (and other geometry columns as WKB): written with the table, the file is
    GeoParquet (``geopandas.read_parquet``)."""
    def crs_of(c: Any) -> Any:
        return c.to_json_dict() if c is not None else None
    columns: dict[str, Any] = {name: {"encoding": "polygon", "crs": crs_of(crs),
                                      "geometry_types": ["Polygon Z" if has_z else "Polygon"]}}
    for column, column_crs in wkb_columns.items():
        columns[column] = {"encoding": "WKB", "geometry_types": [], "crs": crs_of(column_crs)}
    return {"version": "1.1.0", "primary_column": name, "columns": columns}


def _id_column_names(columns) -> tuple[str, ...]:
    """``feature``, ``position``, ``part``, or all three with a ``cdt_`` prefix when
    a source column already has one of these names."""
    if any(c in columns for c in ID_COLUMNS):
        return tuple(f"cdt_{c}" for c in ID_COLUMNS)
    return ID_COLUMNS


_register_accessor()


# ------------------------------------------------------------------ terrain
from .terrain import grid, tin  # noqa: E402,F401  (terrain from spot heights: adapters/terrain.py)
