"""Reading shapely geometries: validation (GEOS ``is_valid`` at unit size,
:mod:`.validity`) and repair, the
PLC of a geometry, one Triangulation per geometry (:func:`triangulate`) or a
whole batch in one compiled call (:func:`triangulate_batch`)."""
from __future__ import annotations

import time
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import NDArray

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError, InvalidGeometryError, PLC, TooFewPointsError
from cdt_plugin.cdt import triangulate_plc
from cdt_plugin.batch import CHUNK, MeshBatch, check_batch_options, geometry_plc, triangulate_rings
from cdt_plugin.parallel import map_ordered, resolve_workers
from cdt_plugin.options import MeshOptions
from cdt_plugin.plc import as_plc, ring_markers, shapely_polygon_rings
import cdt_plugin.adapters.shapely.validity as validity

if TYPE_CHECKING:
    import pandas


#: ``repair=``: False, True, "linework" or "structure" (see :func:`triangulate`).
Repair = bool | str


# GEOS type ids (shapely.GeometryType)
POINT, LINESTRING, LINEARRING, POLYGON, MULTIPOINT, MULTILINESTRING, MULTIPOLYGON, COLLECTION = range(8)


_POLYGONAL = (LINEARRING, POLYGON, MULTIPOLYGON)   # types whose rings bound a domain


# per type id + 1 (missing is -1): whether GEOS validity is checked (polygonal, collections);
# a lookup, since np.isin costs tens of microseconds on a one-geometry call
_CHECKED_FOR_VALIDITY = np.isin(np.arange(-1, 8), _POLYGONAL + (COLLECTION,))


_REPAIR_METHODS = {True: "linework", "linework": "linework", "structure": "structure"}


_VECTORISED_FROM = 16    # polygons read as flat ring arrays from this many on (else one by one)


def triangulate(geometry: Any, *, repair: Repair = False, markers: Any = None, **options: Any
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
        ``False`` (default): a polygon that is invalid by GEOS's rules (bow-tie,
        self-touching ring, hole crossing or outside its shell, ...) raises
        :class:`cdt_plugin.InvalidGeometryError` whose message gives GEOS's
        reason, the point and the ring(s) through it. Validity is decided at
        unit size (:mod:`.validity`), so the verdict is the same at every
        magnitude. An EMPTY hole is dropped (named in ``stats["empty_rings"]``).
        ``True`` or ``"linework"``: invalid polygonal geometries (and the invalid
        polygonal members of a GeometryCollection) are replaced by
        ``shapely.make_valid(g, method="linework")`` at unit size (shapely's default; a bow-tie
        becomes two triangles, a hole crossing its shell becomes the symmetric
        difference), keeping only the polygonal parts of the result (collapsed
        lines and points are dropped). ``"structure"``: ``make_valid(g,
        method="structure", keep_collapsed=False)`` (shell minus holes).
        Valid geometries are never changed.
    markers : int, or {"exterior": int, "holes": int}, optional
        Boundary markers of the polygons' rings (their segment markers, see
        :func:`cdt_plugin.plc.ring_markers`; ``tri.segment_markers``,
        ``tri.vertex_markers``...). For array input also one such value per
        geometry (e.g. a column of a GeoDataFrame: markers from an attribute).
    **options
        Passed to :func:`cdt_plugin.triangulate` (``intersections``, ``keep_hull``,
        ``holes``, ``regions``, ``algorithm``, ``max_steiner``). With
        ``merge_distance``, validity is decided on the geometry with its close
        points merged (:func:`.validity.merged`), as it is meshed.

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
    method = repair_method(repair)
    if markers is None and not options:
        tri = mesh_if_plainly_valid(geometry)
        if tri is not None:
            return tri
    elif markers is None and not options.get("merge_distance") and plain_polygon(geometry):
        return cdt_plugin.triangulate(geometry, **options)
    if is_array_input(geometry):
        arr = np.asarray(geometry, dtype=object).ravel()
        out = _triangulate_many(arr, method, options, indexed=True, markers=_per_geometry(markers, len(arr)))
        if hasattr(geometry, "iloc"):     # a pandas Series: a Series of Triangulations, same index
            values = np.empty(len(out), dtype=object)
            values[:] = out
            return like_input(values, geometry)
        return out
    if geometry is None:
        raise InputShapeError("expected a shapely geometry, got None")
    return _triangulate_many(np.array([geometry], dtype=object), method, options, indexed=False,
                             markers=None if markers is None else [markers])[0]


def _per_geometry(markers: Any, n: int) -> list[Any] | None:
    """The ``markers`` of each of ``n`` geometries: one value for all, or one each
    (a sequence, array or Series)."""
    if markers is None:
        return None
    if isinstance(markers, (int, np.integer, Mapping)):
        return [markers] * n
    values = list(markers)
    if len(values) != n:
        raise InputShapeError(f"markers must be one value for all geometries or one per geometry "
                              f"({n}), got {len(values)}")
    return values


def plc_from_shapely(geometry: shapely.Geometry | None, *, repair: Repair = False) -> PLC | None:
    """The :class:`cdt_plugin.PLC` of one shapely geometry, validated (and repaired)
    as in :func:`triangulate`; z coordinates, if any, are carried in ``plc.z``.
    ``None`` gives ``None``.

    >>> import shapely
    >>> plc = plc_from_shapely(shapely.box(0, 0, 2, 1))
    >>> plc.vertices.shape, plc.segments.shape
    ((4, 2), (4, 2))
    """
    method = repair_method(repair)
    arr = np.array([geometry], dtype=object)
    return geometry_plcs(arr, method, indexed=False)[0]


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
    method = repair_method(repair)
    arr = np.array(geometries, dtype=object).ravel() if is_array_input(geometries) else \
        np.array([geometries], dtype=object)
    _check_input(arr, True)
    arr = arr.copy()
    arr[shapely.is_missing(arr)] = shapely.Polygon()
    collections_to_polygonal(arr)
    types = shapely.get_type_id(arr)
    arr[(types != POLYGON) & (types != MULTIPOLYGON)] = shapely.Polygon()
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
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom, _, empty = \
        layer_rings_on_threads(arr, workers)
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
        xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, _, _, empty = \
            layer_rings_on_threads(arr, workers)
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
    if len(empty):
        batch.stats["empty_rings"] = _empty_rings_by_geometry(empty)
    return batch


def _in_slices(fn: Any, arr: NDArray[np.object_], workers: int | None) -> list[Any]:
    """``[fn(slice) for slice of arr]``: one slice, or for a large batch one
    slice per thread of the batch's, run on those threads (GEOS runs without
    the GIL), as the meshing is."""
    threads = resolve_workers(workers, len(arr) // CHUNK)
    bounds = np.linspace(0, len(arr), threads + 1).astype(np.int64)
    return map_ordered(lambda k: fn(arr[bounds[k]:bounds[k + 1]]), range(threads), threads)


def _is_valid(arr: NDArray[np.object_], workers: int | None) -> NDArray[np.bool_]:
    """:func:`.validity.is_valid` of every geometry (on the batch's threads)."""
    return np.concatenate(_in_slices(validity.is_valid, arr, workers))


def layer_rings_on_threads(arr: NDArray[np.object_], workers: int | None) -> tuple[Any, ...]:
    """:func:`layer_rings` of the batch in slices on its threads, joined:
    the arrays one call gives."""
    pieces = _in_slices(layer_rings, arr, workers)
    if len(pieces) == 1:
        return pieces[0]
    xys, zs, ring_starts, geom_ring_starts, ring_polys, ring_holes, bads, has_zs, empties = zip(*pieces)
    vertex0 = np.cumsum([0] + [len(xy) for xy in xys])
    geom0 = np.cumsum([0] + [len(b) for b in bads])
    ring0 = np.cumsum([0] + [len(r) - 1 for r in ring_starts])
    has_z = np.concatenate(has_zs)
    z = None
    if has_z.any():        # (NaN for a slice without Z, as get_coordinates gives a 2D geometry)
        z = np.concatenate([np.full(len(xy), np.nan) if zk is None else zk for xy, zk in zip(xys, zs)])
    return (np.concatenate(xys),
            z,
            np.concatenate([r[:-1] + v for r, v in zip(ring_starts, vertex0)] + [vertex0[-1:]]),
            np.concatenate([g[:-1] + r for g, r in zip(geom_ring_starts, ring0)] + [ring0[-1:]]),
            np.concatenate(ring_polys), np.concatenate(ring_holes), np.concatenate(bads), has_z,
            np.concatenate([e + [g, 0, 0] for e, g in zip(empties, geom0)]))


def repair_method(repair: Repair | None) -> str | None:
    if repair is False or repair is None:
        return None
    try:
        return _REPAIR_METHODS[repair]
    except (KeyError, TypeError):
        raise CDTError(f"repair must be False, True, 'linework' or 'structure', got {repair!r}") from None


def mesh_if_plainly_valid(geometry: Any) -> cdt_plugin.Triangulation | None:
    """The engine's mesh of one non-empty 2D shapely Polygon, without options,
    when the mesh itself shows the polygon valid; None otherwise (the caller
    then takes the general path, whose exact validity check names the defect).

    What most single calls pass is a valid polygon, and the engine decides its
    structure exactly at every magnitude: it raises where rings cross or a hole
    lies outside its shell or inside another hole, and counts the vertices that
    repeat or lie on other rings' edges. Rings that are simple and pairwise
    disjoint, with every hole inside the shell and none inside another, make a
    valid polygon, whose constrained triangulation without Steiner points has
    ``n + 2h - 2`` triangles (``n`` vertices, ``h`` holes): so GEOS's validity
    test, the largest cost of a call after the mesh itself, is not needed.
    Anything else (a ring touching itself or another, a repeated point, an
    EMPTY hole) goes the general way, valid or not."""
    if type(geometry) is not shapely.Polygon:
        return None
    t0 = time.perf_counter()      # (stats["seconds"] counts the reading, as triangulate's does)
    try:       # (what cdt_plugin.triangulate(geometry) does, without its option checks)
        plc = as_plc(geometry)
        if plc.z is not None or plc.empty_rings or plc.ring_is_hole is None:
            return None
        tri = triangulate_plc(plc, _NO_OPTIONS, t0=t0, workers=None)
    except CDTError:
        return None
    s = tri.stats
    if s["duplicates"] or s["vertices_on_segments"] or s["merged_overlaps"] or s["duplicate_segments"]:
        return None
    holes = len(plc.ring_is_hole) - 1      # (the PLC of one Polygon: its shell, then its holes)
    return tri if len(tri.triangles) == len(plc.vertices) + 2 * holes - 2 else None


_NO_OPTIONS = MeshOptions.check()       # (cdt_plugin.triangulate's, without keywords)


def plain_polygon(geometry: Any) -> bool:
    """One valid, non-empty, 2D shapely Polygon: what most single calls pass. It
    goes straight to the engine, which reads it with the same reader the
    element-wise path uses, without that path's array set-up (about half of a
    small drop-in call)."""
    return (type(geometry) is shapely.Polygon and not geometry.is_empty
            and not geometry.has_z and validity.at_home(geometry) and geometry.is_valid)


def is_array_input(geometry: Any) -> bool:
    """A collection of geometries (list, tuple, NumPy array, pandas Series,
    GeoSeries, GeometryArray: anything with ``__array__``), not one geometry."""
    if geometry is None or isinstance(geometry, shapely.Geometry):
        return False
    return isinstance(geometry, (list, tuple, np.ndarray)) or hasattr(geometry, "__array__")


def like_input(values: np.ndarray, geometry: Any) -> Any:
    """Element-wise results in the input's container, as shapely's functions give
    them: a pandas Series (or GeoSeries) keeps its index, a GeoSeries of
    geometries also its class and CRS; anything else gets the NumPy array."""
    index = getattr(geometry, "index", None)
    if index is None or not hasattr(geometry, "iloc"):
        return values
    geometries = len(values) == 0 or all(v is None or isinstance(v, shapely.Geometry) for v in values)
    if hasattr(geometry, "crs") and geometries:
        return type(geometry)(values, index=index, crs=geometry.crs)
    import pandas as pd  # (installed: the input is a pandas object)
    return pd.Series(values, index=index, dtype=object)


def _triangulate_many(arr: NDArray[np.object_], method: str | None, options: dict[str, Any],
                      indexed: bool, markers: list[Any] | None = None) -> list[cdt_plugin.Triangulation | None]:
    merge = options.get("merge_distance")      # (checked first: validity is decided after merging)
    merge = MeshOptions.check(merge_distance=merge).merge_distance if merge is not None else None
    plcs = geometry_plcs(arr, method, indexed, merge_distance=merge)
    out: list[cdt_plugin.Triangulation | None] = []
    for i, plc in enumerate(plcs):
        if plc is None:
            out.append(None)
            continue
        try:
            if markers is not None:
                plc.segment_markers = ring_markers(plc, markers[i])
            out.append(cdt_plugin.triangulate(plc, **options))
        except CDTError as e:
            raise with_index(e, i, indexed)
    return out


def with_index(e: CDTError, i: int, indexed: bool | np.ndarray) -> CDTError:
    if indexed is not False:
        if not isinstance(indexed, bool):   # an array of positions in the caller's input
            i = int(indexed[i])
        e.args = (f"geometry {i}: {e.args[0] if e.args else ''}",) + tuple(e.args[1:])
        e.index = i
    return e


def _fail(cls: type[CDTError], message: str, i: int, indexed: bool | np.ndarray) -> CDTError:
    return with_index(cls(message), i, indexed)


def _check_input(arr: NDArray[np.object_], indexed: bool | np.ndarray) -> None:
    """:class:`InputShapeError` for the first element of ``arr`` that is not a
    shapely geometry (None, a missing geometry, is one)."""
    ok = shapely.is_valid_input(arr)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise _fail(InputShapeError, f"expected a shapely geometry, got {type(arr[i]).__name__}",
                    i, indexed)


def geometry_plcs(arr: NDArray[np.object_], method: str | None,
          indexed: bool | np.ndarray, merge_distance: float | None = None) -> list[PLC | None]:
    """Validate (and repair) a 1-D object array of geometries and read each into a PLC.
    Validation is one vectorised GEOS call for the whole array; with
    ``merge_distance``, of the geometries with their close points merged
    (:func:`.validity.merged`), as the engine will mesh them."""
    missing = shapely.is_missing(arr)
    _check_input(arr, indexed)
    types = shapely.get_type_id(arr)
    arr = arr.copy()
    # --- validity of polygonal input (GeometryCollections: their polygonal members)
    idx = np.flatnonzero(_CHECKED_FOR_VALIDITY[types + 1])
    if len(idx):
        checked = arr[idx] if merge_distance is None else validity.merged(arr[idx], merge_distance)
        valid = validity.is_valid(checked)
        for k, i in zip(np.flatnonzero(~valid), map(int, idx[~valid])):
            try:
                arr[i] = _repair_or_raise(checked[k], int(types[i]), method, i, indexed)
            except InvalidGeometryError as e:
                if merge_distance is not None:
                    e.args = (f"{e.args[0]} (its points closer than merge_distance={merge_distance!r} "
                              "merged, as they are meshed)",)
                raise
        if (~valid).any():
            types = shapely.get_type_id(arr)
    empty = shapely.is_empty(arr) & ~missing
    if empty.any():
        i = int(np.flatnonzero(empty)[0])
        raise _fail(TooFewPointsError, f"the geometry is empty ({shapely.to_wkt(arr[i])}): "
                    "nothing to triangulate", i, indexed)
    plcs: list[PLC | None] = [None] * len(arr)
    polygons = np.flatnonzero((types == POLYGON) | (types == MULTIPOLYGON))
    if len(polygons) >= _VECTORISED_FROM:   # fewer: the arrays' set-up costs more than it saves
        for g, plc in zip(polygons, _polygon_plcs(arr[polygons])):
            plcs[g] = plc
    for i in map(int, np.flatnonzero(~missing)):
        if plcs[i] is None:   # other types, a few polygons, or a degenerate ring (reported or kept)
            try:
                plcs[i] = PLC.from_geo_interface(arr[i])
            except CDTError as e:
                raise with_index(e, i, indexed)
    return plcs


def _invalid_message(geom: shapely.Geometry) -> str:
    return validity.reason(geom)


def _repair_or_raise(geom: shapely.Geometry, type_id: int, method: str | None, i: int,
                     indexed: bool | np.ndarray) -> shapely.Geometry:
    if type_id == COLLECTION:
        parts = _flat_parts(geom)
        ptypes = shapely.get_type_id(parts)
        poly = np.isin(ptypes, _POLYGONAL)
        bad = np.flatnonzero(poly & ~validity.is_valid(parts))
        if not len(bad):
            # the members are valid one by one (GEOS checks them separately)
            return geom
        if method is None:
            raise _fail(InvalidGeometryError, f"member {int(bad[0])} of the GeometryCollection: "
                        f"{_invalid_message(parts[bad[0]])}; pass repair=True to repair it with "
                        "shapely.make_valid", i, indexed)
        parts = parts.copy()
        for b in bad:
            parts[b] = _make_valid_polygonal(parts[b], method, i, indexed)
        parts = parts[~shapely.is_empty(parts)]
        return shapely.GeometryCollection(list(parts))
    if method is None:
        raise _fail(InvalidGeometryError, f"{_invalid_message(geom)}; pass repair=True to repair "
                    "it with shapely.make_valid", i, indexed)
    if type_id == LINEARRING:
        geom = shapely.Polygon(geom)
    fixed = _make_valid_polygonal(geom, method, i, indexed)
    if fixed.is_empty:
        raise _fail(InvalidGeometryError, f"{_invalid_message(geom)}, and shapely.make_valid "
                    "leaves no polygonal part (it collapses to lines or points)", i, indexed)
    return fixed


def collections_to_polygonal(flat: NDArray[np.object_]) -> None:
    """Replace each GeometryCollection of ``flat`` (in place) by its polygonal
    members as one MultiPolygon (an empty Polygon when it has none)."""
    for i in np.flatnonzero(shapely.get_type_id(flat) == COLLECTION):
        parts = _flat_parts(flat[i])
        ptypes = shapely.get_type_id(parts)
        polys = parts[(ptypes == POLYGON) | (ptypes == MULTIPOLYGON)]
        flat[i] = shapely.MultiPolygon(list(shapely.get_parts(polys))) if len(polys) else shapely.Polygon()


def _flat_parts(geom: shapely.Geometry) -> NDArray[np.object_]:
    """The non-collection members of a (nested) GeometryCollection."""
    parts = shapely.get_parts(geom)
    while (shapely.get_type_id(parts) == COLLECTION).any():
        parts = shapely.get_parts(parts)
    return parts


def _make_valid_polygonal(geom: shapely.Geometry, method: str, i: int,
                          indexed: bool | np.ndarray) -> shapely.Geometry:
    """The polygonal parts of ``make_valid(geom)`` (at unit size: the same
    repair at every scale); InvalidGeometryError when GEOS cannot repair it."""
    try:
        if method == "structure":
            fixed = validity.make_valid(geom, method="structure", keep_collapsed=False)
        else:
            fixed = validity.make_valid(geom)
    except shapely.errors.GEOSException as exc:
        raise _fail(InvalidGeometryError, f"{_invalid_message(geom)}, and shapely.make_valid "
                    f"cannot repair it ({exc}); mesh it with intersections='split' instead "
                    "(even-odd depth)", i, indexed) from exc
    parts = _flat_parts(fixed) if fixed.geom_type != "Polygon" else np.array([fixed], object)
    ptypes = shapely.get_type_id(parts)
    polys = shapely.get_parts(parts[(ptypes == POLYGON) | (ptypes == MULTIPOLYGON)])
    polys = polys[~shapely.is_empty(polys)]
    if len(polys) == 1:
        return polys[0]
    return shapely.MultiPolygon(list(polys))


def _polygon_plcs(geoms: NDArray[np.object_]) -> list[PLC | None]:
    """PLCs of a 1-D array of non-empty Polygons / MultiPolygons, vectorised:
    one GEOS call each for parts, rings and coordinates, then NumPy. The result
    equals ``PLC.from_geo_interface`` of each geometry (same vertex order, segments,
    rings, polygon numbering). Geometries with a degenerate ring get ``None``."""
    rings = layer_rings(geoms)
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom, has_z, empty = rings
    plcs = [None if bad_geom[g] else
            geometry_plc(xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole,
                         z if has_z[g] else None, g)
            for g in range(len(geoms))]
    for g, names in _empty_rings_by_geometry(empty).items():
        plc = plcs[g]
        if plc is not None:
            plc.empty_rings = names
    return plcs


def _empty_rings_by_geometry(empty: NDArray[np.int64]) -> dict[int, list[tuple[int, int]]]:
    """Rows ``(geometry, polygon, ring)`` of the EMPTY rings dropped, as
    ``{geometry: [(polygon, ring), ...]}`` (``stats["empty_rings"]``)."""
    out: dict[int, list[tuple[int, int]]] = {}
    for g, p, r in empty.tolist():
        out.setdefault(g, []).append((p, r))
    return out


def layer_rings(geoms: NDArray[np.object_]) -> tuple[Any, ...]:
    """Flat ring arrays of a 1-D array of Polygons / MultiPolygons (empty parts
    and EMPTY rings dropped), read by :func:`cdt_plugin.plc.shapely_polygon_rings`:
    ``xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom,
    has_z, empty``, ``empty`` the rows ``(geometry, polygon, ring)`` of the EMPTY rings.
    ``z`` is None when no geometry has Z; ``bad_geom`` marks geometries with a
    ring of fewer than three points (a ring of zero area is found exactly, at
    any scale, by the route, which hands its geometry to the single call for
    the precise error)."""
    xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole = \
        shapely_polygon_rings(shapely, geoms)
    sizes = np.diff(ring_start)
    ring_geom = np.repeat(np.arange(len(geoms)), np.diff(geom_ring_start))
    empty = np.empty((0, 3), np.int64)
    if (sizes == 0).any():   # EMPTY rings (holes without points): dropped, as GEOS does
        drop = sizes == 0
        first = np.flatnonzero(~ring_is_hole)            # each polygon's shell
        shell_of = first[np.searchsorted(first, np.arange(len(sizes)), side="right") - 1]
        empty = np.column_stack([ring_geom, ring_polygon, np.arange(len(sizes)) - shell_of])[drop]
        ring_start = np.append(ring_start[:-1][~drop], ring_start[-1])
        geom_ring_start = geom_ring_start - np.concatenate([[0], np.cumsum(np.bincount(
            ring_geom[drop], minlength=len(geoms)))])
        ring_polygon, ring_is_hole, ring_geom = ring_polygon[~drop], ring_is_hole[~drop], ring_geom[~drop]
        sizes = sizes[~drop]
    bad_geom = np.zeros(len(geoms), bool)
    bad_geom[ring_geom[sizes < 3]] = True
    return (xy, z, ring_start, geom_ring_start, ring_polygon, ring_is_hole, bad_geom,
            shapely.has_z(geoms), empty)
