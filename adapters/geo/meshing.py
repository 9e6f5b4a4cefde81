"""Meshing every polygon of a layer (:func:`triangulate`): read, project, one
batch call, back to the layer's CRS."""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from cdt_plugin import CDTError, NoPolygonsError
from cdt_plugin.batch import check_batch_options
from cdt_plugin.optional import require
from cdt_plugin.adapters.geo.errors import (ProjectionError, describe, feature_errors,
                                            is_geographic, relabel, warn_geographic,
                                            warn_skipped)
from cdt_plugin.adapters.geo.projection import (ProjectLike, centred, counter_clockwise,
                                                fold_cause, layer_extent, project_geometries,
                                                restore, target_crs, unfold)
from cdt_plugin.adapters.geo.results import GeoMesh
from cdt_plugin.adapters.geo.sizing import LayerSizing, check_layer_sizing, layer_size
from cdt_plugin.adapters.layers import LayerLike, read
from cdt_plugin.adapters.shapely import Repair, triangulate_batch
from cdt_plugin.adapters.shapely.reading import COLLECTION, MULTIPOLYGON, POLYGON

if TYPE_CHECKING:
    import pyarrow
    import trimesh
    from geopandas import GeoDataFrame

OUTPUTS = ("geodataframe", "geoarrow", "trimesh", "mesh")


AUTO_PROGRESS_FEATURES = 5000       # progress=None: a bar above this many features (on a tty)


def triangulate(data: LayerLike, *, output: str = "geodataframe", project: ProjectLike = None,
                repair: Repair = False, errors: str = "raise", progress: bool | None = None,
                layer: str | int | None = None, size: Any = None, size_near: Any = None,
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
        ``"skip"``: a feature that cannot be meshed (invalid, not meshable,
        or with coordinates that do not project) gets no triangles; the errors
        are in ``result.attrs["cdt_errors"]`` (feature label -> ``"ErrorClass:
        message"``, JSON-safe so that ``to_parquet`` still works; the exceptions
        themselves in ``GeoMesh.errors``) and a :class:`SkippedFeaturesWarning` says
        how many.
    progress : bool or None
        A tqdm bar over the features; None: when there are more than
        ``AUTO_PROGRESS_FEATURES`` features and stderr is a terminal.
    layer : str or int, optional
        The layer of a multi-layer file (GeoPackage).
    size : number, callable, Triangulation or str, optional
        A size field (target edge length, in the meshing CRS's units: see
        :func:`cdt_plugin.triangulate`) for every feature, or the name of a
        numeric column: one size per feature (NaN: none for that feature).
        With a size the features are meshed one by one.
    size_near : tuple, mapping, field, or a list of them, optional
        Sizes near other layers (:func:`cdt_plugin.size_near`): each a tuple
        ``(geometries, size_min, size_max, distance[, growth])``, a mapping of
        ``size_near``'s keywords, or a field made by ``size_near``. The
        geometries may be a GeoDataFrame, GeoSeries or a path (reprojected to
        the meshing CRS when both have a CRS), or anything ``size_near`` takes
        (in the meshing CRS). With ``size``, the smallest of all at every point.
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
        ``project=`` without a CRS, with a geographic CRS, or a feature whose
        coordinates do not project or whose triangles turn clockwise when mapped
        back (a feature split at the antimeridian; ``errors="skip"`` skips such
        features).

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

    Finer along a river (a line layer), coarser away from it:

    >>> river = geopandas.GeoSeries([shapely.LineString([(0, 1), (2, 1)])])
    >>> graded = triangulate(layer, size=0.5, size_near=(river, 0.1, 0.5, 0.5))
    >>> near = graded.geometry.centroid.y.sub(1).abs() < 0.1
    >>> bool(graded[near].area.mean() < graded[~near].area.mean() / 4)
    True
    """
    if output not in OUTPUTS:
        raise CDTError(f"output must be one of {OUTPUTS}, got {output!r}")
    if output == "trimesh":
        require("trimesh", "output='trimesh'")     # before any work
    if output == "geoarrow":
        require("pyarrow", "output='geoarrow'", extra="gis")
    sizing = check_layer_sizing(size, size_near)
    frame = read(data, layer=layer)
    mesh = mesh_layer(frame, project=project, repair=repair, errors=errors, progress=progress,
                      options=options, require_polygons=True, warn=True, sizing=sizing)
    if output == "mesh":
        return mesh
    if output == "trimesh":
        return mesh.to_trimesh()
    if output == "geoarrow":
        return mesh.to_arrow()
    return mesh.to_geodataframe()


def mesh_layer(frame: GeoDataFrame, *, project: ProjectLike, repair: Repair, errors: str,
               progress: Any, options: dict[str, Any], require_polygons: bool,
               warn: bool, sizing: LayerSizing | None = None, map_back: bool = True) -> GeoMesh:
    """Mesh the features of ``frame`` (one batch call) into a :class:`GeoMesh`,
    refined to ``sizing`` (in the meshing CRS) when given. With ``map_back=False``
    the vertices stay in the meshing CRS (``mesh_crs``), for a caller that keeps
    them there (:func:`~cdt_plugin.adapters.geo.extrude`)."""
    check_batch_options(errors=errors, **options)
    geoms = np.asarray(frame.geometry.array, dtype=object)
    if require_polygons:
        _require_polygons(geoms)
    extent = layer_extent(geoms, is_geographic(frame.crs)) if centred(project) else None
    target = target_crs(project, frame.crs, extent)
    if warn and target is None and is_geographic(frame.crs):
        warn_geographic(frame.crs)
    if sizing is not None:
        options = {**options, "size": layer_size(frame, sizing, target or frame.crs)}
    unprojected: dict[int, CDTError] = {}
    meshed = geoms
    if target is not None:
        meshed, unprojected = project_geometries(geoms, frame, target, errors)
        if unprojected:       # (no triangles, and no coordinates to map back to)
            geoms = geoms.copy()
            geoms[list(unprojected)] = shapely.Polygon()
    meshed = _uniform_z(meshed)
    if progress is None:
        progress = len(geoms) > AUTO_PROGRESS_FEATURES and sys.stderr.isatty()
    try:
        batch = triangulate_batch(meshed, repair=repair, errors=errors, progress=bool(progress),
                                  **options)
    except CDTError as e:
        if e.index is None:
            raise
        raise relabel(e, e.index, frame, target) from None
    failed: dict[int, CDTError] = {int(i): relabel(e, int(i), frame, target)
                                   for i, e in batch.errors.items()}
    failed.update(unprojected)
    T, position, part, vertices = batch.triangles, batch.geometry, batch.region, batch.vertices
    if target is not None and map_back:
        vertices = restore(vertices, T, geoms, meshed, target, frame.crs)
        T = unfold(vertices, T, position, part)
        folded = _folded_features(vertices, T, position, frame, target, errors)
        if folded:
            failed.update(folded)
            keep = ~np.isin(position, list(folded))
            T, position, part = T[keep], position[keep], part[keep]
    if warn and failed:
        warn_skipped(failed, frame)
    offsets = np.searchsorted(position, np.arange(len(geoms) + 1)).astype(np.int64)
    return GeoMesh(frame, vertices, batch.z, T, position, part, offsets, failed, target, batch,
                   options.get("workers"))


def _folded_features(V, T, position, frame, target, errors) -> dict:
    """Features with triangles that are no longer counter-clockwise once mapped back
    to the layer's CRS: a ProjectionError each (raised at once with ``errors="raise"``)."""
    rows, counts = np.unique(position[~counter_clockwise(V, T)], return_counts=True)
    count = dict(zip(rows.tolist(), counts.tolist()))
    return feature_errors(ProjectionError, frame, count, lambda i: (
        f"{count[i]} of its triangles turn clockwise when mapped back from {target.name!r} to "
        f"{frame.crs.name!r}: {fold_cause(frame.geometry.iloc[i], frame.crs)}"), errors)


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
                              f"({describe(geoms)})")


def _polygonal(geoms: np.ndarray) -> np.ndarray:
    """Per geometry: a non-empty Polygon / MultiPolygon, or a GeometryCollection with one."""
    types = shapely.get_type_id(geoms)
    out = np.isin(types, (POLYGON, MULTIPOLYGON)) & ~shapely.is_empty(geoms)
    rows = np.flatnonzero(types == COLLECTION)
    if len(rows):
        parts, where = shapely.get_parts(geoms[rows], return_index=True)
        ok = np.isin(shapely.get_type_id(parts), (POLYGON, MULTIPOLYGON)) & ~shapely.is_empty(parts)
        out[rows[where[ok]]] = True
    return out
