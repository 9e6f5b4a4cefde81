"""Drop-ins for shapely's functions: :func:`constrained_delaunay_triangles`,
:func:`delaunay_triangles` and :func:`voronoi_polygons`, element-wise as
shapely's are (an array of geometries in, an array of the same shape out; a
pandas Series or GeoSeries keeps its index; ``None`` gives ``None``)."""
from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

import cdt_plugin
from cdt_plugin import CDTError, InputShapeError
from cdt_plugin._core.ordering import SMALL_SORT
from cdt_plugin.merging import close_point_representatives
from cdt_plugin.plain import plain_mesh
from cdt_plugin.validate import as_points

_EMPTY_COLLECTION = shapely.GeometryCollection()    # geometries are immutable: one serves all
from cdt_plugin.adapters.shapely.building import (PolygonRecords, mesh_records, plain_triangles,
                                                  polygon_collection, to_shapely, triangle_records)
from cdt_plugin.adapters.shapely.cells import cells_to_polygons
from cdt_plugin.adapters.shapely.validity import scaled
from cdt_plugin.adapters.shapely.reading import (MULTIPOLYGON, POLYGON, collections_to_polygonal,
                                                 geometry_plcs, is_array_input, like_input,
                                                 mesh_if_plainly_valid, repair_method, with_index)



_EMPTY_MULTILINESTRING = shapely.MultiLineString()


def _vertex_z(tri: cdt_plugin.Triangulation, plc_z: NDArray[np.float64]) -> NDArray[np.float64]:
    """z of every output vertex from the PLC's z (NaN for Steiner vertices)."""
    z = np.full(len(tri.vertices), np.nan)
    vm = np.asarray(tri.vertex_map)
    ok = vm >= 0
    z[vm[ok]] = plc_z[ok]
    return z


# shapely's element-wise form: an array of geometries in, an array of the same shape
# out (a pandas Series keeps its index), None gives None, one geometry gives one.
def _geometry_array(geometry: Any) -> np.ndarray:
    """``geometry`` as a NumPy object array: 0-d for one geometry (or None)."""
    if is_array_input(geometry):
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


def _positional_deprecated(names: list[str]) -> Any:
    """shapely's own warning for arguments passed by position that it wants by
    keyword (shapely 2.1 and later, which warn so; earlier ones do not)."""
    try:
        from shapely.decorators import deprecate_positional
    except ImportError:
        return lambda fn: fn
    return deprecate_positional(names, category=DeprecationWarning)


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
        return like_input(values, geometry)
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
          each Polygon is meshed on its own, as GEOS does, so the parts of a
          MultiPolygon may overlap or share edges (each part must be valid);
        * empty GeometryCollection, given empty or non-polygonal input;
        * ``None`` for ``None``.

    Raises
    ------
    cdt_plugin.InvalidGeometryError
        An invalid polygon without ``repair`` (GEOS raises or returns a
        triangulation of the invalid rings), with the reason, point and rings
        (decided exactly at every magnitude, as in :func:`triangulate`); for
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
    method = repair_method(repair)
    plain = plain_triangles(geometry)
    if plain is not None:
        return plain
    if type(geometry) is shapely.Polygon and shapely.get_num_coordinates(geometry) >= SMALL_SORT:
        tri = mesh_if_plainly_valid(geometry)      # (a large one: a small one was refused just now)
        if tri is not None:
            return to_shapely(tri)
    arr = _geometry_array(geometry)
    flat = arr.ravel().copy()
    _check_geometries(flat)
    collections_to_polygonal(flat)
    types = shapely.get_type_id(flat)
    polygonal = ((types == POLYGON) | (types == MULTIPOLYGON)) & ~shapely.is_empty(flat)
    out = np.empty(len(flat), dtype=object)
    out[~shapely.is_missing(flat)] = _EMPTY_COLLECTION
    idx = np.flatnonzero(polygonal)
    indexed = arr.ndim > 0
    if len(idx):
        # each Polygon of a MultiPolygon on its own, as GEOS meshes them: parts that
        # overlap give overlapping triangles, each part's validity is its own
        parts, owner = shapely.get_parts(flat[idx], return_index=True)
        solid = ~shapely.is_empty(parts)
        parts, owner = parts[solid], idx[owner[solid]]
        # a Polygon that the one-polygon path takes is meshed as a single call meshes it
        # (the same triangles in the same order); the others the general way
        part_records: list[PolygonRecords | None] = []
        for part in parts:
            mesh = plain_mesh(part)
            part_records.append(None if mesh is None else mesh_records(*mesh))
        general = np.array([j for j, r in enumerate(part_records) if r is None], dtype=np.int64)
        plcs = geometry_plcs(parts[general], method, indexed=owner[general] if indexed else False)
        for j, plc in zip(general, plcs):
            assert plc is not None      # (only a missing geometry has none: these are polygons)
            try:
                # (in x, y as GEOS: a polygon with Z need not be planar; z goes on afterwards)
                tri = cdt_plugin.triangulate(dataclasses.replace(plc, z=None))
            except CDTError as e:
                raise with_index(e, int(owner[j]), indexed)
            part_records[j] = triangle_records(tri, z=_vertex_z(tri, plc.z) if plc.z is not None else None)
        records: list[list[PolygonRecords]] = [[] for _ in range(len(flat))]
        for i, r in zip(owner, part_records):
            assert r is not None
            records[i].append(r)
        for i in idx:
            out[i] = polygon_collection(records[i])
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
        here. A NaN tolerance gives None, as in shapely; a negative one
        raises :class:`cdt_plugin.CDTError` (GEOS treats it as 0).
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
        if np.isnan(tol[i]):
            continue
        xyz = coords[start[i]:start[i + 1]]
        try:
            out[i] = _delaunay_of_vertices(xyz if has_z[i] else xyz[:, :2], tol[i], edges[i])
        except CDTError as e:
            raise with_index(e, int(i), indexed)
    return _elementwise_output(out, arr.shape, geometry)


def _tolerance_array(tolerance: ArrayLike) -> np.ndarray:
    try:
        tol = np.asarray(tolerance, dtype=np.float64)
    except (TypeError, ValueError):
        raise CDTError(f"tolerance must be a number >= 0 (or an array of them), got {tolerance!r}") \
            from None
    bad = tol < 0                  # (NaN gives None, as shapely's functions return)
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
    """Positions of the points kept by snapping with ``tolerance``: the
    engine's ``merge_distance`` rule (in lexicographic (x, y) order, input
    order among equal points, a point is dropped when it is closer than
    ``tolerance`` to a point kept before it)."""
    return np.flatnonzero(close_point_representatives(xy, tolerance) == np.arange(len(xy)))


@_positional_deprecated(["extend_to", "only_edges", "ordered"])
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
        always merged. A NaN tolerance gives None, as in shapely; a negative
        one raises :class:`cdt_plugin.CDTError`.
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
    for i in np.flatnonzero(~shapely.is_missing(flat) & ~np.isnan(tol)):
        try:
            out[i] = _voronoi_of_vertices(coords[start[i]:start[i + 1]], tol[i], extent[i], edges[i])
        except CDTError as e:
            raise with_index(e, int(i), indexed)
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
    its perpendicular bisector, a chord of the box. Far from unit scale the
    strips are made near it and scaled back, exactly by a power of two (GEOS's
    convex hulls square the coordinates)."""
    e = int(np.frexp(np.abs(np.asarray(box)).max())[1])
    if not -64 <= e <= 64:
        near = _collinear_voronoi(np.ldexp(sites, -e), tuple(np.ldexp(box, -e).tolist()), only_edges)
        return scaled(near, e)
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
