"""shapely adapter: constrained Delaunay triangulation of shapely geometries.

Data flow (DESIGN.md): shapely geometry -> validate (GEOS ``is_valid``) ->
:class:`cdt_plugin.PLC` -> :func:`cdt_plugin.triangulate` -> Triangulation ->
shapely output (:func:`to_shapely`).

* :func:`triangulate` -- one geometry gives one Triangulation; an array or list of
  geometries (shapely 2 style) gives a list of Triangulations, in order. Polygonal
  input is validated with GEOS first; invalid polygons raise
  :class:`cdt_plugin.InvalidGeometryError` carrying GEOS's reason, or are repaired
  with ``repair=True``.
* :func:`to_shapely` -- a Triangulation as a GeometryCollection of triangle
  Polygons, in the form ``shapely.constrained_delaunay_triangles`` returns.
* :func:`constrained_delaunay_triangles` -- a drop-in for
  ``shapely.constrained_delaunay_triangles`` returning the exact CDT (GEOS ear-clips
  and then runs a capped number of Delaunay flip passes, so on large polygons it can
  stop short of the CDT); ``repair=`` as in :func:`triangulate`.
* :func:`delaunay_triangles` -- a drop-in for ``shapely.delaunay_triangles``: the
  Delaunay triangulation of all the vertices of any geometry (``tolerance``,
  ``only_edges``), with exact predicates.
* :func:`voronoi_polygons` -- a drop-in for ``shapely.voronoi_polygons``: the
  Voronoi cells (or edges) of all the vertices of any geometry, cut to GEOS's
  envelope (``tolerance``, ``extend_to``, ``only_edges``, ``ordered``); one cell
  per distinct vertex, in input order; exact predicates decide the combinatorics.

The drop-ins are element-wise as shapely's functions are: an array of geometries
in, an array of the same shape out (a pandas Series or GeoSeries keeps its index),
``None`` gives ``None``.

Polygons and MultiPolygons (also in arrays) are read straight from GEOS coordinate
arrays, vectorised over the whole input; other geometry types go through
``__geo_interface__`` (:meth:`cdt_plugin.PLC.from_geo_interface`). Both give the same PLC.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cdt_plugin.optional import missing

try:
    import shapely
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.shapely", extra="shapely") from exc

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError, InvalidGeometryError, PLC, TooFewPointsError
from cdt_plugin.batch import (CHUNK, MeshBatch, check_batch_options, geometry_plc,
                              triangulate_rings)
from cdt_plugin.parallel import map_ordered, resolve_workers
from cdt_plugin.validate import as_points

if TYPE_CHECKING:
    import pandas

#: ``repair=``: False, True, "linework" or "structure" (see :func:`triangulate`).
Repair = bool | str

__all__ = ["triangulate", "triangulate_batch", "to_shapely", "constrained_delaunay_triangles",
           "delaunay_triangles", "voronoi_polygons", "plc_from_shapely"]

# GEOS type ids (shapely.GeometryType)
_POINT, _LINESTRING, _LINEARRING, _POLYGON, _MULTIPOINT, _MULTILINESTRING, _MULTIPOLYGON, _COLLECTION = range(8)
_POLYGONAL = (_LINEARRING, _POLYGON, _MULTIPOLYGON)   # types whose rings bound a domain
# per type id + 1 (missing is -1): whether GEOS validity is checked (polygonal, collections);
# a lookup, since np.isin costs tens of microseconds on a one-geometry call
_CHECKED_FOR_VALIDITY = np.isin(np.arange(-1, 8), _POLYGONAL + (_COLLECTION,))
_EMPTY_COLLECTION = shapely.GeometryCollection()    # geometries are immutable: one serves all
_EMPTY_MULTILINESTRING = shapely.MultiLineString()
_REPAIR_METHODS = {True: "linework", "linework": "linework", "structure": "structure"}
_VECTORISED_FROM = 16    # polygons read as flat ring arrays from this many on (else one by one)


# --------------------------------------------------------------------------- input
def triangulate(geometry: Any, *, repair: Repair = False, **options: Any
                ) -> cdt_plugin.Triangulation | list[cdt_plugin.Triangulation | None] | pandas.Series:
    """Constrained Delaunay triangulation of a shapely geometry (or of each geometry
    of an array).

    Parameters
    ----------
    geometry : shapely.Geometry, or array_like of shapely.Geometry
        Polygon (with holes), MultiPolygon, LinearRing (a polygon without holes),
        GeometryCollection, LineString / MultiLineString (segments that must be
        edges), Point / MultiPoint (vertices). The rings of polygons give shells
        and holes exactly, whatever their winding; ``tri.regions`` is the index of
        the polygon (within the geometry) each triangle lies in. An array, list or
        tuple of geometries gives a list of Triangulations in the same (flattened)
        order, a pandas Series or GeoSeries a Series of them with its index;
        ``None`` entries give ``None``.
    repair : bool or {"linework", "structure"}
        ``False`` (default): a polygon that GEOS finds invalid (bow-tie,
        self-touching ring, hole crossing or outside its shell, ...) raises
        :class:`cdt_plugin.InvalidGeometryError` whose message carries GEOS's
        reason (``shapely.is_valid_reason``, formerly ``explain_validity``).
        ``True`` or ``"linework"``: invalid polygonal geometries (and the invalid
        polygonal members of a GeometryCollection) are replaced by
        ``shapely.make_valid(g, method="linework")`` (shapely's default; a bow-tie
        becomes two triangles, a hole crossing its shell becomes the symmetric
        difference), keeping only the polygonal parts of the result (collapsed
        lines and points are dropped). ``"structure"``: ``make_valid(g,
        method="structure", keep_collapsed=False)`` (shell minus holes).
        Valid geometries are never changed.
    **options
        Passed to :func:`cdt_plugin.triangulate` (``intersections``, ``keep_hull``,
        ``holes``, ``regions``, ``algorithm``, ``max_steiner``).

    Returns
    -------
    Triangulation, or list of (Triangulation or None) for array input.

    Raises
    ------
    cdt_plugin.InvalidGeometryError
        An invalid polygon (without ``repair``), or nothing polygonal left after repair.
    cdt_plugin.TooFewPointsError
        An empty geometry. For array input the message starts with
        ``geometry i:`` and the exception has an ``index`` attribute.
    cdt_plugin.CDTError
        Any other engine error (crossing constraint lines, ...).

    Examples
    --------
    >>> import shapely
    >>> from cdt_plugin.adapters.shapely import triangulate
    >>> poly = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 3), (3, 3), (3, 1)]])
    >>> tri = triangulate(poly)
    >>> len(tri.triangles), tri.is_delaunay()
    (8, True)
    >>> [len(t.triangles) for t in triangulate([poly, shapely.box(0, 0, 1, 1)])]
    [8, 2]
    """
    method = _repair_method(repair)
    if _plain_polygon(geometry):
        return cdt_plugin.triangulate(geometry, **options)
    if _is_array_input(geometry):
        arr = np.asarray(geometry, dtype=object).ravel()
        out = _triangulate_many(arr, method, options, indexed=True)
        if hasattr(geometry, "iloc"):     # a pandas Series: a Series of Triangulations, same index
            values = np.empty(len(out), dtype=object)
            values[:] = out
            return _like_input(values, geometry)
        return out
    if geometry is None:
        raise InputShapeError("expected a shapely geometry, got None")
    return _triangulate_many(np.array([geometry], dtype=object), method, options, indexed=False)[0]


def plc_from_shapely(geometry: shapely.Geometry | None, *, repair: Repair = False) -> PLC | None:
    """The :class:`cdt_plugin.PLC` of one shapely geometry, validated (and repaired)
    as in :func:`triangulate`; z coordinates, if any, are carried in ``plc.z``.
    ``None`` gives ``None``.

    >>> import shapely
    >>> plc = plc_from_shapely(shapely.box(0, 0, 2, 1))
    >>> plc.vertices.shape, plc.segments.shape
    ((4, 2), (4, 2))
    """
    method = _repair_method(repair)
    arr = np.array([geometry], dtype=object)
    return _plcs(arr, method, indexed=False)[0]


def triangulate_batch(geometries: Any, *, repair: Repair = False, errors: str = "raise",
                      progress: bool = False, **options: Any) -> MeshBatch:
    """Mesh many polygonal geometries in one call (the GIS batch path).

    Every Polygon / MultiPolygon of ``geometries`` is one PLC (a MultiPolygon's
    parts together); the triangles of all of them come back in one
    :class:`cdt_plugin.batch.MeshBatch`, with the input position of each
    triangle's geometry in ``batch.geometry``. Much faster than a loop of
    :func:`triangulate` calls on many small polygons.

    Parameters
    ----------
    geometries : array_like of shapely geometries
        Polygons and MultiPolygons (with Z or not); a GeometryCollection
        contributes its polygonal members. ``None``, empty and non-polygonal
        geometries get no triangles.
    repair : bool or {"linework", "structure"}
        As in :func:`triangulate`: invalid polygons raise (or are skipped with
        ``errors="skip"``) unless repaired with ``shapely.make_valid``.
    errors : {"raise", "skip"}
        A geometry that cannot be meshed raises a :class:`cdt_plugin.CDTError`
        whose message starts ``geometry i:`` (attribute ``index``), or is left
        without triangles and recorded in ``batch.errors``.
    progress : bool
        A tqdm progress bar over the geometries.
    **options
        ``workers`` (threads; default: every core for a large batch, see
        :func:`cdt_plugin.batch.triangulate_rings`), and the options of
        :func:`cdt_plugin.triangulate` (``min_angle``, ``max_area``,
        ``intersections``, ...).

    Examples
    --------
    >>> import shapely
    >>> polys = [shapely.box(0, 0, 1, 1), None, shapely.Polygon([(0, 0), (2, 0), (1, 1)])]
    >>> b = triangulate_batch(polys)
    >>> len(b), b.geometry.tolist(), b.offsets.tolist()
    (3, [0, 0, 2], [0, 2, 2, 3])
    """
    workers = check_batch_options(errors=errors, **options)[2]
    method = _repair_method(repair)
    arr = np.array(geometries, dtype=object).ravel() if _is_array_input(geometries) else \
        np.array([geometries], dtype=object)
    ok = shapely.is_valid_input(arr)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise _fail(InputShapeError, f"expected a shapely geometry, got {type(arr[i]).__name__}",
                    i, True)
    arr = arr.copy()
    arr[shapely.is_missing(arr)] = shapely.Polygon()
    _collections_to_polygonal(arr)
    types = shapely.get_type_id(arr)
    arr[(types != _POLYGON) & (types != _MULTIPOLYGON)] = shapely.Polygon()
    failed: dict[int, CDTError] = {}
    invalid = np.flatnonzero(~_is_valid(arr, workers))
    for i in map(int, invalid):
        try:
            arr[i] = _repair_or_raise(arr[i], int(types[i]), method, i, True)
        except CDTError as e:
            if errors == "raise":
                raise
            failed[i] = e
            arr[i] = shapely.Polygon()
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom, _ = \
        _polygon_rings_on_threads(arr, workers)
    for i in map(int, np.flatnonzero(bad_geom)):   # not reachable from GEOS-valid polygons
        err = _fail(InvalidGeometryError, "a ring has fewer than three distinct points or zero area",
                    i, True)
        if errors == "raise":
            raise err
        failed[i] = err
    if len(failed):
        drop = np.zeros(len(arr), bool)
        drop[list(failed)] = True
        arr[drop] = shapely.Polygon()
        xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, _, _ = \
            _polygon_rings_on_threads(arr, workers)
    bar = None
    if progress:
        from tqdm.auto import tqdm
        bar = tqdm(total=len(arr), unit="geom", desc="meshing")
    try:
        batch = triangulate_rings(xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole, z=z,
                                  errors=errors, progress=bar.update if bar else None, **options)
    finally:
        if bar is not None:
            bar.close()
    batch.errors.update(failed)
    batch.stats["failed"] = len(batch.errors)
    return batch


def _in_slices(fn: Any, arr: NDArray[np.object_], workers: int | None) -> list[Any]:
    """``[fn(slice) for slice of arr]``: one slice, or for a large batch one
    slice per thread of the batch's, run on those threads (GEOS runs without
    the GIL), as the meshing is."""
    threads = resolve_workers(workers, len(arr) // CHUNK)
    bounds = np.linspace(0, len(arr), threads + 1).astype(np.int64)
    return map_ordered(lambda k: fn(arr[bounds[k]:bounds[k + 1]]), range(threads), threads)


def _is_valid(arr: NDArray[np.object_], workers: int | None) -> NDArray[np.bool_]:
    """``shapely.is_valid`` of every geometry (on the batch's threads)."""
    return np.concatenate(_in_slices(shapely.is_valid, arr, workers))


def _polygon_rings_on_threads(arr: NDArray[np.object_], workers: int | None) -> tuple[Any, ...]:
    """:func:`_polygon_rings` of the batch in slices on its threads, joined:
    the arrays one call gives."""
    pieces = _in_slices(_polygon_rings, arr, workers)
    if len(pieces) == 1:
        return pieces[0]
    xys, zs, ring_starts, geom_ring_starts, ring_polys, ring_holes, bads, has_zs = zip(*pieces)
    vertex0 = np.cumsum([0] + [len(xy) for xy in xys])
    ring0 = np.cumsum([0] + [len(r) - 1 for r in ring_starts])
    has_z = np.concatenate(has_zs)
    z = None
    if has_z.any():        # (NaN for a slice without Z, as get_coordinates gives a 2D geometry)
        z = np.concatenate([np.full(len(xy), np.nan) if zk is None else zk for xy, zk in zip(xys, zs)])
    return (np.concatenate(xys),
            z,
            np.concatenate([r[:-1] + v for r, v in zip(ring_starts, vertex0)] + [vertex0[-1:]]),
            np.concatenate([g[:-1] + r for g, r in zip(geom_ring_starts, ring0)] + [ring0[-1:]]),
            np.concatenate(ring_polys), np.concatenate(ring_holes), np.concatenate(bads), has_z)


def _repair_method(repair: Repair | None) -> str | None:
    if repair is False or repair is None:
        return None
    try:
        return _REPAIR_METHODS[repair]
    except (KeyError, TypeError):
        raise CDTError(f"repair must be False, True, 'linework' or 'structure', got {repair!r}") from None


def _plain_polygon(geometry: Any) -> bool:
    """One valid, non-empty, 2D shapely Polygon: what most single calls pass. It
    goes straight to the engine, which reads it with the same reader the
    element-wise path uses, without that path's array set-up (about half of a
    small drop-in call)."""
    return (type(geometry) is shapely.Polygon and not geometry.is_empty
            and not geometry.has_z and geometry.is_valid)


def _is_array_input(geometry: Any) -> bool:
    """A collection of geometries (list, tuple, NumPy array, pandas Series,
    GeoSeries, GeometryArray: anything with ``__array__``), not one geometry."""
    if geometry is None or isinstance(geometry, shapely.Geometry):
        return False
    return isinstance(geometry, (list, tuple, np.ndarray)) or hasattr(geometry, "__array__")


def _like_input(values: np.ndarray, geometry: Any) -> Any:
    """Element-wise results in the input's container, as shapely's functions give
    them: a pandas Series (or GeoSeries) keeps its index, a GeoSeries of
    geometries also its class and CRS; anything else gets the NumPy array."""
    index = getattr(geometry, "index", None)
    if index is None or not hasattr(geometry, "iloc"):
        return values
    geometries = len(values) == 0 or all(v is None or isinstance(v, shapely.Geometry) for v in values)
    if hasattr(geometry, "crs") and geometries:
        return type(geometry)(values, index=index, crs=geometry.crs)
    import pandas as pd        # (installed: the input is a pandas object)
    return pd.Series(values, index=index, dtype=object)


def _triangulate_many(arr: NDArray[np.object_], method: str | None, options: dict[str, Any],
                      indexed: bool) -> list[cdt_plugin.Triangulation | None]:
    plcs = _plcs(arr, method, indexed)
    out: list[cdt_plugin.Triangulation | None] = []
    for i, plc in enumerate(plcs):
        if plc is None:
            out.append(None)
            continue
        try:
            out.append(cdt_plugin.triangulate(plc, **options))
        except CDTError as e:
            raise _with_index(e, i, indexed)
    return out


def _with_index(e: CDTError, i: int, indexed: bool | np.ndarray) -> CDTError:
    if indexed is not False:
        if not isinstance(indexed, bool):   # an array of positions in the caller's input
            i = int(indexed[i])
        e.args = (f"geometry {i}: {e.args[0] if e.args else ''}",) + tuple(e.args[1:])
        e.index = i
    return e


def _fail(cls: type[CDTError], message: str, i: int, indexed: bool | np.ndarray) -> CDTError:
    return _with_index(cls(message), i, indexed)


def _plcs(arr: NDArray[np.object_], method: str | None,
          indexed: bool | np.ndarray) -> list[PLC | None]:
    """Validate (and repair) a 1-D object array of geometries and read each into a PLC.
    Validation is one vectorised GEOS call for the whole array."""
    missing = shapely.is_missing(arr)
    ok = shapely.is_valid_input(arr)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise _fail(InputShapeError, f"expected a shapely geometry, got {type(arr[i]).__name__}",
                    i, indexed)
    types = shapely.get_type_id(arr)
    arr = arr.copy()
    # --- validity of polygonal input (GeometryCollections: their polygonal members)
    idx = np.flatnonzero(_CHECKED_FOR_VALIDITY[types + 1])
    if len(idx):
        valid = shapely.is_valid(arr[idx])
        for i in map(int, idx[~valid]):
            arr[i] = _repair_or_raise(arr[i], int(types[i]), method, i, indexed)
        if (~valid).any():
            types = shapely.get_type_id(arr)
    empty = shapely.is_empty(arr) & ~missing
    if empty.any():
        i = int(np.flatnonzero(empty)[0])
        raise _fail(TooFewPointsError, f"the geometry is empty ({shapely.to_wkt(arr[i])}): "
                    "nothing to triangulate", i, indexed)
    plcs: list[PLC | None] = [None] * len(arr)
    polygons = np.flatnonzero((types == _POLYGON) | (types == _MULTIPOLYGON))
    if len(polygons) >= _VECTORISED_FROM:   # fewer: the arrays' set-up costs more than it saves
        for g, plc in zip(polygons, _polygon_plcs(arr[polygons])):
            plcs[g] = plc
    for i in map(int, np.flatnonzero(~missing)):
        if plcs[i] is None:   # other types, a few polygons, or a degenerate ring (reported or kept)
            try:
                plcs[i] = PLC.from_geo_interface(arr[i])
            except CDTError as e:
                raise _with_index(e, i, indexed)
    return plcs


def _invalid_message(geom: shapely.Geometry) -> str:
    return f"{geom.geom_type} is not valid: {shapely.is_valid_reason(geom)}"


def _repair_or_raise(geom: shapely.Geometry, type_id: int, method: str | None, i: int,
                     indexed: bool | np.ndarray) -> shapely.Geometry:
    if type_id == _COLLECTION:
        parts = _flat_parts(geom)
        ptypes = shapely.get_type_id(parts)
        poly = np.isin(ptypes, _POLYGONAL)
        bad = np.flatnonzero(poly & ~shapely.is_valid(parts))
        if not len(bad):
            # the members are valid one by one (GEOS checks them separately)
            return geom
        if method is None:
            raise _fail(InvalidGeometryError, f"member {int(bad[0])} of the GeometryCollection: "
                        f"{_invalid_message(parts[bad[0]])}; pass repair=True to repair it with "
                        "shapely.make_valid", i, indexed)
        parts = parts.copy()
        for b in bad:
            parts[b] = _make_valid_polygonal(parts[b], method)
        parts = parts[~shapely.is_empty(parts)]
        return shapely.GeometryCollection(list(parts))
    if method is None:
        raise _fail(InvalidGeometryError, f"{_invalid_message(geom)}; pass repair=True to repair "
                    "it with shapely.make_valid", i, indexed)
    if type_id == _LINEARRING:
        geom = shapely.Polygon(geom)
    fixed = _make_valid_polygonal(geom, method)
    if fixed.is_empty:
        raise _fail(InvalidGeometryError, f"{_invalid_message(geom)}, and shapely.make_valid "
                    "leaves no polygonal part (it collapses to lines or points)", i, indexed)
    return fixed


def _collections_to_polygonal(flat: NDArray[np.object_]) -> None:
    """Replace each GeometryCollection of ``flat`` (in place) by its polygonal
    members as one MultiPolygon (an empty Polygon when it has none)."""
    for i in np.flatnonzero(shapely.get_type_id(flat) == _COLLECTION):
        parts = _flat_parts(flat[i])
        ptypes = shapely.get_type_id(parts)
        polys = parts[(ptypes == _POLYGON) | (ptypes == _MULTIPOLYGON)]
        flat[i] = shapely.MultiPolygon(list(shapely.get_parts(polys))) if len(polys) else shapely.Polygon()


def _flat_parts(geom: shapely.Geometry) -> NDArray[np.object_]:
    """The non-collection members of a (nested) GeometryCollection."""
    parts = shapely.get_parts(geom)
    while (shapely.get_type_id(parts) == _COLLECTION).any():
        parts = shapely.get_parts(parts)
    return parts


def _make_valid_polygonal(geom: shapely.Geometry, method: str) -> shapely.Geometry:
    if method == "structure":
        fixed = shapely.make_valid(geom, method="structure", keep_collapsed=False)
    else:
        fixed = shapely.make_valid(geom)
    parts = _flat_parts(fixed) if fixed.geom_type != "Polygon" else np.array([fixed], object)
    ptypes = shapely.get_type_id(parts)
    polys = shapely.get_parts(parts[(ptypes == _POLYGON) | (ptypes == _MULTIPOLYGON)])
    polys = polys[~shapely.is_empty(polys)]
    if len(polys) == 1:
        return polys[0]
    return shapely.MultiPolygon(list(polys))


def _polygon_plcs(geoms: NDArray[np.object_]) -> list[PLC | None]:
    """PLCs of a 1-D array of non-empty Polygons / MultiPolygons, vectorised:
    one GEOS call each for parts, rings and coordinates, then NumPy. The result
    equals ``PLC.from_geo_interface`` of each geometry (same vertex order, segments,
    rings, polygon numbering). Geometries with a degenerate ring get ``None``."""
    rings = _polygon_rings(geoms)
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom, has_z = rings
    return [None if bad_geom[g] else
            geometry_plc(xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole,
                         z if has_z[g] else None, g)
            for g in range(len(geoms))]


def _polygon_rings(geoms):
    """Flat ring arrays of a 1-D array of Polygons / MultiPolygons (empty parts
    dropped): ``xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole,
    bad_geom, has_z``. ``z`` is None when no geometry has Z; ``bad_geom`` marks
    geometries with a ring of fewer than three points.

    The coordinates come in one GEOS call. Most geometries of a layer are
    Polygons without holes, whose one ring is all of their coordinates; only
    the others are taken apart into ring objects (which GEOS makes one by one,
    holding the GIL: on a layer of 100,000 polygons that was half of this
    function's time, and it did not run faster on threads)."""
    n = len(geoms)
    has_z = shapely.has_z(geoms)
    coords = shapely.get_coordinates(geoms, include_z=bool(has_z.any()))
    simple = (shapely.get_type_id(geoms) == _POLYGON) & (shapely.get_num_interior_rings(geoms) == 0)
    n_coords = shapely.get_num_coordinates(geoms)
    s_geom = np.flatnonzero(simple & (n_coords > 0))
    others = np.flatnonzero(~simple)
    parts, part_geom = shapely.get_parts(geoms[others], return_index=True)
    keep = ~shapely.is_empty(parts)
    parts, part_geom = parts[keep], others[part_geom[keep]]
    part_start = np.searchsorted(part_geom, part_geom, side="left")
    part_local = np.arange(len(parts)) - part_start                  # polygon number in its geometry
    rings, ring_part = shapely.get_rings(parts, return_index=True)
    # every ring in geometry order, the order of the coordinates
    ring_geom = np.concatenate([s_geom, part_geom[ring_part]])
    by = np.argsort(ring_geom, kind="stable")
    ring_geom = ring_geom[by]
    ring_len = np.concatenate([n_coords[s_geom], shapely.get_num_coordinates(rings)])[by]
    ring_is_hole = np.concatenate([np.zeros(len(s_geom), bool),
                                   np.r_[False, ring_part[1:] == ring_part[:-1]]])[by]   # exterior first
    ring_poly = np.concatenate([np.zeros(len(s_geom), np.int64), part_local[ring_part]])[by]
    # drop each ring's closing point
    closed_start = np.zeros(len(ring_len) + 1, np.int64)
    np.cumsum(ring_len, out=closed_start[1:])
    kept = np.ones(len(coords), bool)
    kept[closed_start[1:] - 1] = False
    coords = coords[kept]
    ring_start = closed_start - np.arange(len(ring_len) + 1)
    # (a ring of zero area is found exactly, at any scale, by the route, which
    # hands its geometry to the single call for the precise error)
    bad_ring = ring_len - 1 < 3
    geom_ring_start = np.searchsorted(ring_geom, np.arange(n + 1)).astype(np.int64)
    bad_geom = np.zeros(n, bool)
    bad_geom[ring_geom[bad_ring]] = True
    xy = np.ascontiguousarray(coords[:, :2])
    z = coords[:, 2].copy() if has_z.any() else None
    return xy, z, ring_start, geom_ring_start, ring_poly, ring_is_hole, bad_geom, has_z


# -------------------------------------------------------------------------- output
def to_shapely(tri: cdt_plugin.Triangulation, *, z: ArrayLike | None = None,
               ccw: bool = False) -> shapely.GeometryCollection:
    """The triangles of ``tri`` as a ``shapely.GeometryCollection`` of Polygons, in the
    form ``shapely.constrained_delaunay_triangles`` returns: one Polygon per
    triangle (in ``tri.triangles`` order), each a closed 4-point shell, clockwise
    like GEOS's output (``ccw=True`` for counter-clockwise shells, the order of
    ``tri.triangles``); no triangles give ``GEOMETRYCOLLECTION EMPTY``.

    Parameters
    ----------
    tri : cdt_plugin.Triangulation
    z : float or (n,) array, optional
        A z coordinate for every vertex (a scalar for all): the polygons are 3D.
    ccw : bool
        Orientation of the triangle shells (default ``False``: clockwise, as GEOS).

    Examples
    --------
    >>> import shapely, cdt_plugin
    >>> gc = to_shapely(cdt_plugin.triangulate(shapely.box(0, 0, 1, 1)))
    >>> gc.geom_type, len(gc.geoms), bool(shapely.is_ccw(gc.geoms[0].exterior))
    ('GeometryCollection', 2, False)
    """
    T = np.asarray(tri.triangles)
    V = np.asarray(tri.vertices, dtype=np.float64)
    if z is not None:
        zz = np.broadcast_to(np.asarray(z, dtype=np.float64), (len(V),))
        V = np.column_stack([V, zz])
    order = [0, 1, 2, 0] if ccw else [0, 2, 1, 0]
    polys = triangle_polygons(V, T[:, order]) if len(T) else np.empty(0, object)
    return shapely.geometrycollections(polys)


#: Triangles per thread worth starting one for when making their polygons
POLYGONS_PER_THREAD = 50_000
#: At most this many triangles' rings are gathered at once when making their polygons
POLYGON_PIECE = 1_000_000


def triangle_polygons(vertices: NDArray[np.float64], corners: NDArray[np.int64],
                      workers: int | None = 1) -> NDArray[np.object_]:
    """One Polygon per row of ``corners`` ``(k, 4)``: the closed ring of those
    rows of ``vertices`` ``(n, 2)`` or ``(n, 3)``, made by one vectorised call
    (``shapely.from_ragged_array``) per piece of at most ``POLYGON_PIECE``
    rings, gathered piece by piece (never all the rings at once), on ``workers``
    threads (None: every core) for large ``k`` (GEOS makes the polygons without
    the GIL: two threads took 0.67 s for 2 million, one 1.47 s).

    >>> import numpy as np
    >>> triangle_polygons(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2, 0]])).tolist()
    [<POLYGON ((0 0, 1 0, 0 1, 0 0))>]
    """
    k = len(corners)
    threads = resolve_workers(workers, k // POLYGONS_PER_THREAD)
    pieces = max(threads, -(-k // POLYGON_PIECE))     # (a piece's rings: at most 64 MB in 2D)
    bounds = [k * i // pieces for i in range(pieces + 1)]
    parts = map_ordered(lambda i: _ring_polygons(vertices[corners[bounds[i]:bounds[i + 1]]]),
                        range(pieces), threads)
    return parts[0] if pieces == 1 else np.concatenate(parts)


def _ring_polygons(rings: NDArray[np.float64]) -> NDArray[np.object_]:
    """Polygons from closed rings of four corners, ``(k, 4, 2)`` or ``(k, 4, 3)``."""
    k = len(rings)
    return shapely.from_ragged_array(
        shapely.GeometryType.POLYGON, np.ascontiguousarray(rings.reshape(4 * k, rings.shape[2])),
        (np.arange(0, 4 * k + 1, 4, dtype=np.int64), np.arange(k + 1, dtype=np.int64)))


def _vertex_z(tri: cdt_plugin.Triangulation, plc_z: NDArray[np.float64]) -> NDArray[np.float64]:
    """z of every output vertex from the PLC's z (NaN for Steiner vertices)."""
    z = np.full(len(tri.vertices), np.nan)
    vm = np.asarray(tri.vertex_map)
    ok = vm >= 0
    z[vm[ok]] = plc_z[ok]
    return z


# ------------------------------------------------------------------ Voronoi cells
def cells_to_polygons(offsets: NDArray[np.int64], xy: NDArray[np.float64]) -> NDArray[np.object_]:
    """One Polygon per cell from flat counter-clockwise rings (not closed):
    cell ``i`` is ``xy[offsets[i]:offsets[i + 1]]``, an empty Polygon where it
    is empty (:attr:`cdt_plugin.Voronoi.cell_xy`). Vectorised
    (``shapely.from_ragged_array``).

    >>> import numpy as np
    >>> cells_to_polygons(np.array([0, 3, 3]), np.array([[0.0, 0], [1, 0], [0, 1]])).tolist()
    [<POLYGON ((0 0, 1 0, 0 1, 0 0))>, <POLYGON EMPTY>]
    """
    sizes = np.diff(offsets)
    full = sizes > 0
    # close each ring: its first corner again after its last
    coords = np.insert(xy, offsets[1:][full], xy[offsets[:-1][full]], axis=0)
    ring_offsets = np.concatenate([[0], np.cumsum(sizes[full] + 1)]).astype(np.int64)
    polygon_offsets = np.concatenate([[0], np.cumsum(full)]).astype(np.int64)
    return shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords, (ring_offsets, polygon_offsets))


def clip_cells_to_polygon(vor: cdt_plugin.Voronoi, clip: Any) -> NDArray[np.object_]:
    """Every cell of ``vor`` cut to a polygonal geometry ``clip`` (a Polygon
    or MultiPolygon, any object with ``__geo_interface__``): the cells are
    cut to its bounding box first, exactly as a box clip does, then intersected
    with it by GEOS. One Polygon or MultiPolygon per site (a non-convex region
    can cut a cell in pieces), an empty Polygon where nothing is left.
    Raises :class:`cdt_plugin.ClipRegionError` for a non-polygonal, invalid or
    empty region, or one that contains none of the sites, and
    :class:`cdt_plugin.CoordinateRangeError` when two sites are too close for
    GEOS beside the region's coordinates (:data:`GEOS_RANGE`)."""
    from cdt_plugin.errors import ClipRegionError
    geom = clip if isinstance(clip, shapely.Geometry) else shapely.geometry.shape(clip) \
        if hasattr(clip, "__geo_interface__") else None
    if geom is None or shapely.get_type_id(geom) not in (_POLYGON, _MULTIPOLYGON):
        raise ClipRegionError(f"clip must be a box (xmin, ymin, xmax, ymax) or a Polygon / "
                              f"MultiPolygon, got {type(clip).__name__}")
    if geom.is_empty or not geom.is_valid:
        raise ClipRegionError(f"clip polygon is {'empty' if geom.is_empty else 'invalid'}: "
                              f"{shapely.is_valid_reason(geom)}")
    # GEOS works on everything scaled by a power of two (exact) to the region's size
    e = _geos_exponent(vor, geom)
    region = _scaled(geom, -e)
    shapely.prepare(region)
    if not shapely.intersects(region, _scaled(shapely.points(vor.points), -e)).any():
        raise ClipRegionError(f"the clip polygon contains none of the {len(vor.points)} points")
    boxed = vor.clipped(tuple(geom.bounds))
    assert boxed.cell_offsets is not None and boxed.cell_xy is not None
    cells = shapely.intersection(_scaled(cells_to_polygons(boxed.cell_offsets, boxed.cell_xy), -e), region)
    return _polygonal_parts(_scaled(cells, e))


def _scaled(geometry: Any, k: int) -> Any:
    """``geometry`` (one or an array) with every coordinate times ``2**k``: exact."""
    return shapely.transform(geometry, lambda xy: np.ldexp(xy, k)) if k else geometry


#: GEOS intersects in doubles: the closest sites' distance, relative to the
#: clip region's coordinates, at least 2**-510 (squares of such differences
#: stay normal doubles; below, cells a few such distances wide came out of GEOS
#: overlapping or empty)
GEOS_RANGE = 510


def _geos_exponent(vor: cdt_plugin.Voronoi, geom: Any) -> int:
    """The power of two that brings the clip region's coordinates near 1 for
    GEOS (exact scaling: any overall scale works), or a
    :class:`cdt_plugin.CoordinateRangeError` when the closest two sites are
    too close for GEOS beside the region's coordinates."""
    from cdt_plugin.errors import CoordinateRangeError
    top = float(np.abs(np.asarray(geom.bounds)).max())
    e = int(np.frexp(top)[1]) if top > 0 else 0
    pts = vor.points
    a, b = vor.ridge_points.T            # neighbouring cells (the closest two sites are among them)
    gap = np.hypot(pts[a, 0] - pts[b, 0], pts[a, 1] - pts[b, 1])
    k = int(np.argmin(gap))
    if np.ldexp(gap[k], -e) < 2.0 ** -GEOS_RANGE:
        raise CoordinateRangeError(
            f"sites {int(a[k])} {pts[a[k]].tolist()} and {int(b[k])} {pts[b[k]].tolist()} are "
            f"{gap[k]:.3g} apart, beside clip coordinates up to {top:.3g}: too close for GEOS to "
            f"intersect their cells with the clip polygon in doubles (at most 2**{GEOS_RANGE} "
            "between them); clip with a box (xmin, ymin, xmax, ymax), which cdt_plugin cuts itself "
            "at any scale, or clip the points' own neighbourhood", rows=(int(a[k]), int(b[k])))
    return e


def _polygonal_parts(geoms: NDArray[np.object_]) -> NDArray[np.object_]:
    """Each geometry as a Polygon or MultiPolygon: the polygons of a collection
    (an intersection that also touches the region along a line or at a point),
    an empty Polygon where there are none."""
    out = geoms.copy()
    types = shapely.get_type_id(geoms)
    for i in np.flatnonzero(~np.isin(types, (_POLYGON, _MULTIPOLYGON))):
        parts = shapely.get_parts(geoms[i])
        parts = parts[shapely.get_type_id(parts) == _POLYGON]
        out[i] = (shapely.Polygon() if not len(parts) else parts[0] if len(parts) == 1
                  else shapely.multipolygons(parts))
    return out


# ------------------------------------------------------------------------ drop-ins
# shapely's element-wise form: an array of geometries in, an array of the same shape
# out (a pandas Series keeps its index), None gives None, one geometry gives one.
def _geometry_array(geometry: Any) -> np.ndarray:
    """``geometry`` as a NumPy object array: 0-d for one geometry (or None)."""
    if _is_array_input(geometry):
        return np.asarray(geometry, dtype=object)
    arr = np.empty((), dtype=object)
    arr[()] = geometry
    return arr


def _check_geometries(flat: np.ndarray) -> None:
    """shapely's TypeError for anything that is neither a geometry nor None."""
    ok = shapely.is_valid_input(flat)
    if not ok.all():
        bad = flat[np.flatnonzero(~ok)[0]]
        raise TypeError(f"one of the arguments is of incorrect type: {type(bad).__name__} "
                        "(expected shapely geometries or None)")


def _reject_ufunc_kwargs(name: str, kwargs: dict) -> None:
    """shapely's functions are ufuncs and take NumPy ufunc keywords (``out``,
    ``where``, ...); the drop-ins are not ufuncs and say so."""
    if kwargs:
        raise TypeError(f"{name}: ufunc keyword arguments are not supported "
                        f"({', '.join(sorted(kwargs))})")


def _elementwise_output(out: np.ndarray, shape: tuple, geometry: Any) -> Any:
    """The flat results in the form shapely returns them: one geometry for a
    scalar (or 0-d) call, else an array of ``shape``, or the input's pandas
    container (same index) when it has that shape."""
    values = out.reshape(shape)
    if values.ndim == 0:
        return values[()]
    if hasattr(geometry, "iloc") and np.shape(geometry) == shape:
        return _like_input(values, geometry)
    return values


def constrained_delaunay_triangles(geometry: Any, *, repair: bool | str = False, **kwargs: Any) -> Any:
    """Drop-in for ``shapely.constrained_delaunay_triangles`` (same signature, same
    output form) returning the exact constrained Delaunay triangulation.

    Parameters
    ----------
    geometry : Geometry or array_like
        One geometry, or an array / list / pandas Series / GeoSeries of them.
    repair : bool or {"linework", "structure"}
        As in :func:`triangulate`: ``False`` (default) raises on an invalid
        polygon; otherwise it is replaced by ``shapely.make_valid(...)`` first
        (same code path as :func:`triangulate`).
    **kwargs
        shapely's version takes NumPy ufunc keyword arguments; they are not
        supported here (a ``TypeError`` names them).

    Returns
    -------
    GeometryCollection or array of GeometryCollections (same shape as the input;
    a pandas Series or GeoSeries in gives one out, with its index)
        * GeometryCollection of clockwise triangle Polygons (closed 4-point
          shells, z kept for 3D input), given polygonal input (Polygon,
          MultiPolygon, or the polygonal members of a GeometryCollection);
        * empty GeometryCollection, given empty or non-polygonal input;
        * ``None`` for ``None``.

    Raises
    ------
    cdt_plugin.InvalidGeometryError
        An invalid polygon without ``repair`` (GEOS raises or returns a
        triangulation of the invalid rings), with GEOS's validity reason; for
        array input the message starts ``geometry i:`` (attribute ``index``).
    TypeError
        An element that is not a geometry, or ufunc keyword arguments.

    Examples
    --------
    >>> import shapely
    >>> constrained_delaunay_triangles(shapely.Polygon([(10, 10), (20, 40), (90, 90), (90, 10), (10, 10)]))
    <GEOMETRYCOLLECTION (POLYGON ((10 10, 20 40, 90 10, 10 10)), POLYGON ((20 40...>
    >>> constrained_delaunay_triangles(shapely.MultiPoint([(50, 30), (51, 30), (60, 30)]))
    <GEOMETRYCOLLECTION EMPTY>
    >>> bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    >>> [len(gc.geoms) for gc in constrained_delaunay_triangles([bowtie, None, shapely.box(0, 0, 1, 1)],
    ...                                                         repair=True) if gc is not None]
    [2, 2]
    """
    _reject_ufunc_kwargs("constrained_delaunay_triangles", kwargs)
    method = _repair_method(repair)
    if _plain_polygon(geometry):
        return to_shapely(cdt_plugin.triangulate(geometry))
    arr = _geometry_array(geometry)
    flat = arr.ravel().copy()
    _check_geometries(flat)
    _collections_to_polygonal(flat)
    types = shapely.get_type_id(flat)
    polygonal = ((types == _POLYGON) | (types == _MULTIPOLYGON)) & ~shapely.is_empty(flat)
    out = np.empty(len(flat), dtype=object)
    out[~shapely.is_missing(flat)] = _EMPTY_COLLECTION
    idx = np.flatnonzero(polygonal)
    indexed = arr.ndim > 0
    if len(idx):
        plcs = _plcs(flat[idx], method, indexed=idx if indexed else False)
        for i, plc in zip(idx, plcs):
            assert plc is not None      # (only a missing geometry has none: these are polygons)
            try:
                tri = cdt_plugin.triangulate(plc)
            except CDTError as e:
                raise _with_index(e, int(i), indexed)
            out[i] = to_shapely(tri, z=_vertex_z(tri, plc.z) if plc.z is not None else None)
    return _elementwise_output(out, arr.shape, geometry)


def delaunay_triangles(geometry: Any, tolerance: ArrayLike = 0.0, only_edges: ArrayLike = False,
                       **kwargs: Any) -> Any:
    """Drop-in for ``shapely.delaunay_triangles`` (same signature, same output
    form): the Delaunay triangulation of all the vertices of a geometry, with
    exact predicates (:func:`cdt_plugin.delaunay`).

    Parameters
    ----------
    geometry : Geometry or array_like
        Any geometry (points, lines, polygons, collections): all of its vertices
        are triangulated, nothing is a constraint. An array / list / pandas
        Series / GeoSeries gives the results element-wise.
    tolerance : float or array_like, default 0.0
        Snap vertices closer than this together. Exact duplicates are always
        merged (the first one kept, z included). With ``tolerance > 0`` the
        vertices are taken in lexicographic (x, y) order and a vertex is dropped
        when its (floating-point Euclidean) distance to a vertex kept before it
        is less than ``tolerance``: so no two output vertices are closer than
        ``tolerance`` and every dropped vertex is within it of a kept one. GEOS
        applies the same rule only against the vertices of the edge its point
        location ends at, so on clusters it may keep a point that is dropped
        here. A negative or NaN tolerance raises :class:`cdt_plugin.CDTError`
        (GEOS treats a negative one as 0 and returns None for NaN).
    only_edges : bool or array_like, default False
        A MultiLineString of the edges instead of the triangles.
    **kwargs
        shapely's version takes NumPy ufunc keyword arguments; they are not
        supported here (a ``TypeError`` names them).

    Returns
    -------
    GeometryCollection / MultiLineString, or an array of them (the broadcast shape
    of the three arguments; a pandas Series or GeoSeries in gives one out, with
    its index)
        * GeometryCollection of counter-clockwise triangle Polygons (closed
          4-point shells, as GEOS returns them for this function; z kept for 3D
          input), empty for fewer than three distinct or all-collinear vertices;
        * with ``only_edges``, a MultiLineString of two-point LineStrings: the
          triangles' edges, or the chain along the line for collinear vertices
          (empty for fewer than two distinct vertices);
        * ``None`` for ``None``.

    Examples
    --------
    >>> import shapely
    >>> points = shapely.MultiPoint([(50, 30), (60, 30), (100, 100)])
    >>> delaunay_triangles(points)
    <GEOMETRYCOLLECTION (POLYGON ((50 30, 60 30, 100 100, 50 30)))>
    >>> len(delaunay_triangles(shapely.box(0, 0, 1, 1), only_edges=True).geoms)
    5
    >>> delaunay_triangles(shapely.MultiPoint([(50, 30), (51, 30), (60, 30), (100, 100)]), tolerance=2)
    <GEOMETRYCOLLECTION (POLYGON ((50 30, 60 30, 100 100, 50 30)))>
    >>> delaunay_triangles([shapely.LineString([(0, 0), (1, 0), (2, 0)]), None], only_edges=True)
    array([<MULTILINESTRING ((0 0, 1 0), (1 0, 2 0))>, None], dtype=object)
    """
    _reject_ufunc_kwargs("delaunay_triangles", kwargs)
    arr = _geometry_array(geometry)
    tol, edges = _tolerance_array(tolerance), _only_edges_array(only_edges)
    try:
        arr, tol, edges = np.broadcast_arrays(arr, tol, edges)
    except ValueError:
        raise InputShapeError(f"geometry, tolerance and only_edges cannot be broadcast together "
                              f"(shapes {np.shape(arr)}, {np.shape(tol)}, {np.shape(edges)})") from None
    flat, tol, edges = arr.ravel(), tol.ravel(), edges.ravel()
    _check_geometries(flat)
    coords, owner = shapely.get_coordinates(flat, include_z=True, return_index=True)
    start = np.searchsorted(owner, np.arange(len(flat) + 1))
    has_z = shapely.has_z(flat)
    indexed = arr.ndim > 0
    out = np.empty(len(flat), dtype=object)
    for i in np.flatnonzero(~shapely.is_missing(flat)):
        xyz = coords[start[i]:start[i + 1]]
        try:
            out[i] = _delaunay_of_vertices(xyz if has_z[i] else xyz[:, :2], tol[i], edges[i])
        except CDTError as e:
            raise _with_index(e, int(i), indexed)
    return _elementwise_output(out, arr.shape, geometry)


def _tolerance_array(tolerance: ArrayLike) -> np.ndarray:
    try:
        tol = np.asarray(tolerance, dtype=np.float64)
    except (TypeError, ValueError):
        raise CDTError(f"tolerance must be a number >= 0 (or an array of them), got {tolerance!r}") \
            from None
    bad = ~(tol >= 0)
    if bad.any():
        raise CDTError(f"tolerance must be >= 0 (the distance under which vertices are snapped "
                       f"together), got {float(tol[bad].ravel()[0])!r}")
    return tol


def _only_edges_array(only_edges: ArrayLike, name: str = "only_edges") -> np.ndarray:
    flags = np.asarray(only_edges)
    if flags.dtype != bool and not (flags.dtype.kind in "iu" and np.isin(flags, (0, 1)).all()):
        raise CDTError(f"{name} must be True or False (or an array of them), got {only_edges!r}")
    return flags.astype(bool)


def _delaunay_of_vertices(xyz: np.ndarray, tolerance: float, only_edges: bool) -> shapely.Geometry:
    """GEOS's output form of the Delaunay triangulation of the points ``xyz``
    ((n, 2), or (n, 3) with z)."""
    if tolerance > 0 and len(xyz):
        xyz = xyz[_snapped(as_points(xyz[:, :2]), tolerance)]   # (NaN, inf: the engine's error)
    if not len(xyz):
        return _EMPTY_MULTILINESTRING if only_edges else _EMPTY_COLLECTION
    tri = cdt_plugin.delaunay(xyz[:, :2])
    z = _first_z(tri, xyz[:, 2]) if xyz.shape[1] == 3 else None
    if not only_edges:
        return to_shapely(tri, z=z, ccw=True)
    V = tri.vertices if z is None else np.column_stack([tri.vertices, z])
    if not len(tri.edges):
        return _EMPTY_MULTILINESTRING
    return shapely.multilinestrings(shapely.linestrings(V[tri.edges]))


def _first_z(tri: cdt_plugin.Triangulation, z: np.ndarray) -> np.ndarray:
    """z of every output vertex: that of the first input point merged into it."""
    _, first = np.unique(tri.vertex_map, return_index=True)
    return z[first]


def _snapped(xy: np.ndarray, tolerance: float) -> np.ndarray:
    """Positions of the points kept by snapping with ``tolerance``: in
    lexicographic (x, y) order (input order among equal points), a point is
    dropped when it is closer than ``tolerance`` to a point kept before it."""
    n = len(xy)
    points = shapely.points(xy)
    a, b = shapely.STRtree(points).query(points, predicate="dwithin", distance=tolerance)
    rank = np.empty(n, np.int64)
    rank[np.lexsort((xy[:, 1], xy[:, 0]))] = np.arange(n)
    close = (rank[b] < rank[a]) & (np.hypot(*(xy[a] - xy[b]).T) < tolerance)
    a, b = a[close], b[close]                   # b comes before a and is within tolerance
    order = np.argsort(rank[a], kind="stable")
    a, b = a[order], b[order]
    first = np.flatnonzero(np.r_[True, a[1:] != a[:-1]]) if len(a) else np.zeros(0, np.int64)
    keep = np.ones(n, bool)
    for s, e in zip(first, np.r_[first[1:], len(a)]):     # points with an earlier close one
        keep[a[s]] = not keep[b[s:e]].any()
    return np.flatnonzero(keep)


def voronoi_polygons(geometry: Any, tolerance: ArrayLike = 0.0, extend_to: Any = None,
                     only_edges: ArrayLike = False, ordered: ArrayLike = False, **kwargs: Any) -> Any:
    """Drop-in for ``shapely.voronoi_polygons`` (same signature, same output
    form): the Voronoi diagram of all the vertices of a geometry, dual to their
    exact Delaunay triangulation (:meth:`cdt_plugin.Triangulation.voronoi`).

    Parameters
    ----------
    geometry : Geometry or array_like
        Any geometry (points, lines, polygons, collections): every vertex is a
        site. An array / list / pandas Series / GeoSeries gives the results
        element-wise.
    tolerance : float or array_like, default 0.0
        Snap vertices closer than this together, as in
        :func:`delaunay_triangles` (lexicographic order, a vertex closer than
        ``tolerance`` to one kept before it is dropped). Exact duplicates are
        always merged. A negative or NaN tolerance raises
        :class:`cdt_plugin.CDTError`.
    extend_to : Geometry or array_like, optional
        The cells are cut to GEOS's envelope: the bounding box of the vertices
        (all of them, snapped or not) grown by its larger side on every side
        (:meth:`cdt_plugin.Voronoi.envelope`), grown further to include the
        bounding box of ``extend_to`` when given (it never shrinks).
    only_edges : bool or array_like, default False
        A MultiLineString of the Voronoi edges (two-point LineStrings, rays cut
        at the envelope) instead of the cells.
    ordered : bool or array_like, default False
        Accepted for shapely's signature: the cells are always in the order of
        the input vertices (first appearance of each distinct vertex; with
        ``tolerance``, of the kept ones). Where GEOS raises for ``ordered=True``
        on repeated vertices (or vertices snapped together), they are merged
        here and their first appearance counts.
    **kwargs
        shapely's version takes NumPy ufunc keyword arguments; they are not
        supported here (a ``TypeError`` names them).

    Returns
    -------
    GeometryCollection / MultiLineString, or an array of them (the broadcast shape
    of the five arguments; a pandas Series or GeoSeries in gives one out, with
    its index)
        * GeometryCollection of Polygons (clockwise closed shells, 2D, as GEOS
          returns them), one per distinct vertex in input order, covering the
          envelope; empty for fewer than two distinct vertices (one Polygon, the
          envelope, when ``tolerance`` snaps them all into one, as GEOS). Four
          or more exactly cocircular vertices (a grid) give one Voronoi vertex,
          decided with exact predicates; vertices all on one line give
          parallel strips;
        * with ``only_edges``, a MultiLineString of the edges (the cells'
          shared sides), empty for fewer than two sites;
        * ``None`` for ``None``.

    Raises
    ------
    cdt_plugin.NonFiniteCoordinateError
        A NaN or infinite coordinate (GEOS raises ``GEOSException``); for array
        input the message starts ``geometry i:`` (attribute ``index``).
    TypeError
        An element that is not a geometry, or ufunc keyword arguments.

    Examples
    --------
    >>> import shapely
    >>> points = shapely.MultiPoint([(2, 2), (4, 2)])
    >>> voronoi_polygons(points)
    <GEOMETRYCOLLECTION (POLYGON ((0 0, 0 4, 3 4, 3 0, 0 0)), POLYGON ((3 0, 3 4...>
    >>> voronoi_polygons(points, only_edges=True)
    <MULTILINESTRING ((3 4, 3 0))>
    >>> voronoi_polygons(points, extend_to=shapely.LineString([(0, 0), (10, 10)]), only_edges=True)
    <MULTILINESTRING ((3 10, 3 0))>
    >>> voronoi_polygons(shapely.MultiPoint([(2, 2), (4, 2), (4.2, 2)]), tolerance=0.5, only_edges=True)
    <MULTILINESTRING ((3 4.2, 3 -0.2))>
    >>> grid = shapely.MultiPoint([(x, y) for x in range(4) for y in range(4)])
    >>> sorted({round(cell.area, 12) for cell in voronoi_polygons(grid).geoms})
    [1.0, 3.5, 12.25]
    >>> voronoi_polygons([shapely.Point(2, 2), None])
    array([<GEOMETRYCOLLECTION EMPTY>, None], dtype=object)
    """
    _reject_ufunc_kwargs("voronoi_polygons", kwargs)
    arr, ext = _geometry_array(geometry), _geometry_array(extend_to)
    tol = _tolerance_array(tolerance)
    edges, order = _only_edges_array(only_edges), _only_edges_array(ordered, "ordered")
    try:
        arr, tol, ext, edges, _ = np.broadcast_arrays(arr, tol, ext, edges, order)
    except ValueError:
        raise InputShapeError(f"geometry, tolerance, extend_to, only_edges and ordered cannot be broadcast "
                              f"together (shapes {np.shape(arr)}, {np.shape(tol)}, {np.shape(ext)}, "
                              f"{np.shape(edges)}, {np.shape(order)})") from None
    flat, tol, ext, edges = arr.ravel(), tol.ravel(), ext.ravel(), edges.ravel()
    _check_geometries(flat)
    _check_geometries(ext)
    extent = shapely.bounds(ext)                 # NaN for None or an empty geometry
    coords, owner = shapely.get_coordinates(flat, return_index=True)
    start = np.searchsorted(owner, np.arange(len(flat) + 1))
    indexed = arr.ndim > 0
    out = np.empty(len(flat), dtype=object)
    for i in np.flatnonzero(~shapely.is_missing(flat)):
        try:
            out[i] = _voronoi_of_vertices(coords[start[i]:start[i + 1]], tol[i], extent[i], edges[i])
        except CDTError as e:
            raise _with_index(e, int(i), indexed)
    return _elementwise_output(out, arr.shape, geometry)


def _voronoi_of_vertices(xy: np.ndarray, tolerance: float, extent: np.ndarray,
                         only_edges: bool) -> shapely.Geometry:
    """GEOS's output form of the Voronoi diagram of the points ``xy`` (n, 2),
    cut to GEOS's envelope grown to ``extent`` (a bounds row, NaN for none)."""
    empty = _EMPTY_MULTILINESTRING if only_edges else _EMPTY_COLLECTION
    if not len(xy):
        return empty
    xy = as_points(xy)                                   # NaN, inf: NonFiniteCoordinateError
    if not (xy != xy[0]).any():                          # fewer than two distinct vertices
        return empty
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    grow = float((hi - lo).max())
    lo, hi = np.fmin(lo - grow, extent[:2]), np.fmax(hi + grow, extent[2:])
    box = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    sites = xy[_snapped(xy, tolerance)] if tolerance > 0 else xy
    tri = cdt_plugin.delaunay(sites)
    if len(tri.vertices) < 2:                            # all snapped into one: the whole envelope
        return empty if only_edges else shapely.geometrycollections([shapely.box(*box, ccw=False)])
    if not len(tri.triangles):
        return _collinear_voronoi(tri.vertices, box, only_edges)
    vor = tri.voronoi(clip=box)
    assert vor.cell_offsets is not None and vor.cell_xy is not None
    if only_edges:
        return _cell_edges(vor.cell_offsets, vor.cell_xy, box)
    offsets = vor.cell_offsets
    cell = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    backwards = offsets[cell] + offsets[cell + 1] - 1 - np.arange(len(cell))   # clockwise, as GEOS
    return shapely.geometrycollections(cells_to_polygons(offsets, vor.cell_xy[backwards]))


def _cell_edges(offsets: np.ndarray, xy: np.ndarray, box: tuple[float, float, float, float]
                ) -> shapely.MultiLineString:
    """The Voronoi edges inside ``box`` from the cells cut to it: every side of
    a cell that is not on the box, once (the two cells that share it list it
    with the same corners, in opposite directions)."""
    sizes = np.diff(offsets)
    nxt = np.arange(len(xy)) + 1
    nxt[offsets[1:][sizes > 0] - 1] = offsets[:-1][sizes > 0]      # each ring's last corner to its first
    p, q = xy, xy[nxt]
    xmin, ymin, xmax, ymax = box
    on_side = (((p[:, 0] == q[:, 0]) & ((p[:, 0] == xmin) | (p[:, 0] == xmax)))
               | ((p[:, 1] == q[:, 1]) & ((p[:, 1] == ymin) | (p[:, 1] == ymax))))
    first = (p[:, 0] < q[:, 0]) | ((p[:, 0] == q[:, 0]) & (p[:, 1] < q[:, 1]))
    keep = ~on_side & first
    return _multilinestring(p[keep], q[keep])


def _collinear_voronoi(sites: np.ndarray, box: tuple[float, float, float, float],
                       only_edges: bool) -> shapely.Geometry:
    """Parallel strips: the Voronoi diagram of ``sites`` (distinct, all on one
    line, at least two) cut to ``box``. Along the line the sites are in
    lexicographic (x, y) order, exactly; each pair of neighbours is separated by
    its perpendicular bisector, a chord of the box."""
    order = np.lexsort((sites[:, 1], sites[:, 0]))
    s = sites[order]
    along = s[1:] - s[:-1]
    normal = np.column_stack([along[:, 1], -along[:, 0]])
    big = np.full(len(s) - 1, np.inf)
    a, b, _ = _clip_lines((s[1:] + s[:-1]) / 2, normal, -big, big, box)   # the midpoints are inside
    if only_edges:
        return _multilinestring(a, b)
    m = len(s)
    xmin, ymin, xmax, ymax = box
    corners = np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    nearest = np.argmin(((corners[:, None, :] - s[None, :, :]) ** 2).sum(axis=2), axis=1)
    # each strip: the ends of its one or two chords and the box corners nearest its site
    points = np.concatenate([a, b, a, b, corners])
    owner = np.concatenate([np.arange(m - 1), np.arange(m - 1), np.arange(1, m), np.arange(1, m), nearest])
    by_owner = np.argsort(owner, kind="stable")
    hulls = shapely.convex_hull(shapely.multipoints(points[by_owner], indices=owner[by_owner]))
    cells = np.empty(m, dtype=object)
    cells[order] = hulls                                # back to the sites' order
    ccw = shapely.is_ccw(shapely.get_exterior_ring(cells))
    cells[ccw] = shapely.reverse(cells[ccw])
    return shapely.geometrycollections(cells)


def _clip_lines(p0: np.ndarray, step: np.ndarray, t0: np.ndarray, t1: np.ndarray,
                box: tuple[float, float, float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lines ``p0 + t * step`` for ``t0 <= t <= t1`` (infinite bounds for rays
    and lines) cut to ``box`` (Liang-Barsky, vectorised): the ends ``a``, ``b``
    and whether anything of positive length is left. An end on the box's
    boundary gets that side's coordinate exactly."""
    lo, hi = np.array(box[:2]), np.array(box[2:])
    t0, t1 = t0.astype(np.float64).copy(), t1.astype(np.float64).copy()
    a_side = np.full((len(p0), 2), np.nan)     # the box side each end lies on, per axis
    b_side = np.full((len(p0), 2), np.nan)
    ok = np.ones(len(p0), bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for k in range(2):
            flat = step[:, k] == 0
            ok &= ~(flat & ((p0[:, k] < lo[k]) | (p0[:, k] > hi[k])))
            forward = step[:, k] > 0
            enter_at = np.where(forward, lo[k], hi[k])
            leave_at = np.where(forward, hi[k], lo[k])
            enter = np.where(flat, -np.inf, (enter_at - p0[:, k]) / step[:, k])
            leave = np.where(flat, np.inf, (leave_at - p0[:, k]) / step[:, k])
            later = enter > t0
            t0 = np.where(later, enter, t0)
            a_side[later] = np.nan
            a_side[later, k] = enter_at[later]
            sooner = leave < t1
            t1 = np.where(sooner, leave, t1)
            b_side[sooner] = np.nan
            b_side[sooner, k] = leave_at[sooner]
    ok &= t0 < t1
    t0, t1 = np.where(ok, t0, 0.0), np.where(ok, t1, 0.0)
    a = np.where(np.isnan(a_side), p0 + t0[:, None] * step, a_side)
    b = np.where(np.isnan(b_side), p0 + t1[:, None] * step, b_side)
    ok &= (a != b).any(axis=1)
    return a, b, ok


def _multilinestring(a: np.ndarray, b: np.ndarray) -> shapely.MultiLineString:
    if not len(a):
        return _EMPTY_MULTILINESTRING
    return shapely.multilinestrings(shapely.linestrings(np.stack([a, b], axis=1)))
