"""Projections of a layer for meshing (``project=``): the meshing CRS, the
layer into it, and the mesh back, input vertices bit for bit.

A projection moves vertices but keeps edges straight, so a vertex that lies
exactly on another ring's edge in the layer's CRS (a hole touching its shell, two
holes or two parts touching) would land a hair off that edge in the meshing CRS.
Such vertices are first inserted into the edges they lie on (in the layer's
coordinates, exactly), so both CRSs see the same touching rings. Mapped back, a
thin triangle may still turn flat or clockwise (its corners were collinear in
the layer's CRS, or the map back bends it); :func:`unfold` flips such a
triangle's edge with its neighbour's where that makes both counter-clockwise
(exactly, in the layer's CRS). What cannot be unfolded that way is a feature
that is not valid in the layer's own CRS (checked by the caller)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Union

import numpy as np
import shapely

from cdt_plugin._core.certify import orientation_signs
from cdt_plugin.adapters.geo.errors import ProjectionError, feature_errors
from cdt_plugin.adapters.shapely.reading import MULTIPOLYGON, POLYGON

if TYPE_CHECKING:
    import pyproj
    from geopandas import GeoDataFrame

#: What ``project=`` takes: None, "utm", "aeqd", or a projected CRS (a ``pyproj.CRS``
#: or what ``pyproj.CRS.from_user_input`` reads: "EPSG:32633", 32633, WKT, ...).
ProjectLike = Union[str, int, "pyproj.CRS", None]


def layer_extent(geoms: np.ndarray, geographic: bool) -> np.ndarray:
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


def centred(project: ProjectLike) -> bool:
    """Whether ``project`` is centred on the data (``"utm"`` or ``"aeqd"``)."""
    return isinstance(project, str) and project in ("utm", "aeqd")


def target_crs(project: ProjectLike, crs: Any, extent: np.ndarray | None) -> Any:
    """The projected CRS to mesh in (None: mesh in the layer's own CRS)."""
    if project is None:
        return None
    import pyproj

    if centred(project):
        if crs is None:
            raise ProjectionError(f"project={project!r} needs the layer's CRS: the layer has "
                                  "none (set it with gdf.set_crs(...))")
        if extent is None or not len(extent):
            raise ProjectionError(f"project={project!r} needs coordinates to centre the "
                                  "projection on: the layer has none")
        lon, lat = _centre(extent, crs)
        try:      # (pyproj's errors, and geopandas' RuntimeError when no UTM zone fits)
            return _utm_crs(crs, lon, lat) if project == "utm" else _aeqd_crs(crs, lon, lat)
        except RuntimeError as exc:
            raise ProjectionError(f"project={project!r}: no such CRS centred at lon {lon!r}, "
                                  f"lat {lat!r} of the layer's CRS {crs.name!r} ({exc})") from exc
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


def project_geometries(geoms: np.ndarray, frame: GeoDataFrame, target: Any,
                       errors: str = "raise") -> tuple[np.ndarray, dict[int, ProjectionError]]:
    """The geometries in ``target`` (same coordinate count and order, z kept),
    and the features whose coordinates do not project to finite values: a
    :class:`ProjectionError` each, raised at once with ``errors="raise"``;
    with ``"skip"`` such a feature becomes an empty Polygon (no triangles)."""
    import pyproj

    try:
        forward = pyproj.Transformer.from_crs(frame.crs, target, always_xy=True)
    except pyproj.exceptions.ProjError as exc:
        raise ProjectionError(f"no transformation from {frame.crs.name!r} to {target.name!r} "
                              f"({exc})") from exc
    geoms = with_touching_vertices(geoms)
    try:
        projected = shapely.transform(geoms, _xy_transform(forward), include_z=None)
    except pyproj.exceptions.ProjError:     # one by one, to name the features that fail
        projected = np.array([_projected_or_none(g, forward) for g in geoms], dtype=object)
    counts = shapely.get_num_coordinates(projected)
    finite = np.isfinite(shapely.get_coordinates(projected)).all(axis=1)
    feature = np.repeat(np.arange(len(geoms)), counts)
    bad = np.zeros(len(geoms), bool)
    bad[feature[~finite]] = True
    bad |= shapely.is_missing(projected) & ~shapely.is_missing(geoms)
    failed = feature_errors(ProjectionError, frame, map(int, np.flatnonzero(bad)), lambda i:
                            f"coordinates do not project to finite values in {target.name!r}",
                            errors)
    if failed:
        projected = projected.copy()
        projected[bad] = shapely.Polygon()
    return projected, failed


def _projected_or_none(geometry: Any, forward: Any) -> Any:
    """One geometry in the target CRS, or None when pyproj fails on it."""
    import pyproj

    if geometry is None:
        return None
    try:
        return shapely.transform(geometry, _xy_transform(forward), include_z=None)
    except pyproj.exceptions.ProjError:
        return None


def restore(V: np.ndarray, T: np.ndarray, geoms: np.ndarray, projected: np.ndarray, target: Any,
            crs: Any) -> np.ndarray:
    """Mesh vertices back in the layer's CRS. A vertex at the projected position of
    an input coordinate gets that input coordinate, exactly. A Steiner vertex on a
    boundary edge goes to the same fraction of the original edge (so the triangles
    tile the original polygon), unless that inverts one of its triangles; the
    other Steiner vertices are inverse-projected."""
    import pyproj

    back = pyproj.Transformer.from_crs(target, crs, always_xy=True)
    original = shapely.get_coordinates(with_touching_vertices(geoms))     # (as projected)
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
        undo = keep & np.isin(moved, T[~counter_clockwise(out, T)])
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


def counter_clockwise(V: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Per triangle: whether it turns counter-clockwise (exact orientation; flat
    triangles do not). A check of the mapped-back output, never a meshing decision."""
    return _orientations(V, T) > 0


def fold_cause(geometry: Any, crs: Any) -> str:
    """Why a feature's triangles still fold once mapped back to ``crs`` (after
    :func:`unfold`): the feature is not valid there (its rings cross in the layer's
    own coordinates, though not in the meshing CRS), or the projection bends it."""
    try:
        reason = shapely.is_valid_reason(geometry)
    except shapely.errors.GEOSException:
        reason = "Valid Geometry"
    if reason != "Valid Geometry":
        return (f"it is not valid in {crs.name!r} ({reason}), only in the meshing CRS; "
                "repair it in its own CRS (shapely.make_valid)")
    return ("parts split at the antimeridian meet in the projection, or the feature lies too "
            "far from the projection's centre; mesh it unprojected or in a CRS where it is in "
            "one piece")


def _orientations(V: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Exact orientation sign of each triangle (+1 counter-clockwise, 0 flat, -1)."""
    if not len(T):
        return np.zeros(0, np.int64)
    return orientation_signs(np.ascontiguousarray(V[:, 0], np.float64),
                             np.ascontiguousarray(V[:, 1], np.float64),
                             np.ascontiguousarray(T, np.int64))


def unfold(V: np.ndarray, T: np.ndarray, position: np.ndarray, part: np.ndarray) -> np.ndarray:
    """The triangles ``T`` with edges flipped where a triangle is flat or clockwise
    in the mapped-back coordinates ``V`` and flipping an edge it shares with a
    triangle of the same polygon (so not a ring edge) makes both counter-clockwise
    (exact orientations). Flips keep the union of the two triangles, so the
    triangles still tile the polygon. ``T`` itself when every triangle turns
    counter-clockwise; triangles that no flip repairs stay as they are.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    >>> T = np.array([[0, 1, 2], [0, 2, 3]])          # (0, 1, 2) is flat
    >>> unfold(V, T, np.zeros(2, int), np.zeros(2, int)).tolist()
    [[1, 2, 3], [1, 3, 0]]
    """
    sign = _orientations(V, T)
    bad = np.flatnonzero(sign <= 0)
    if not len(bad):
        return T
    T = T.copy()
    rows = np.flatnonzero(np.isin(position, position[bad]))     # the folded features only
    across = {(int(T[t, j]), int(T[t, (j + 1) % 3])): int(t) for t in rows for j in range(3)}
    pending = [int(t) for t in bad]
    while pending:
        left = [t for t in pending if not _flip_out(V, T, t, across, position, part)]
        if len(left) == len(pending):
            break
        pending = left
    return T


def _flip_out(V, T, t, across, position, part) -> bool:
    """Flip one edge of the folded triangle ``t`` (see :func:`unfold`); whether it did."""
    for j in range(3):
        c, a, b = (int(T[t, (j + k) % 3]) for k in range(3))
        u = across.get((b, a))
        if u is None or position[u] != position[t] or part[u] != part[t]:
            continue
        d = int(next(v for v in T[u] if v != a and v != b))
        new = np.array([[c, a, d], [c, d, b]])
        if (_orientations(V, new) <= 0).any():
            continue
        for tri in (T[t], T[u]):
            for k in range(3):
                del across[(int(tri[k]), int(tri[(k + 1) % 3]))]
        T[t], T[u] = new
        for s in (t, u):
            for k in range(3):
                across[(int(T[s, k]), int(T[s, (k + 1) % 3]))] = s
        return True
    return False


def with_touching_vertices(geoms: np.ndarray) -> np.ndarray:
    """The geometries with every polygon vertex that lies exactly inside an edge of
    another ring of the same feature inserted into that edge (``geoms`` itself when
    there is none). Only features with two rings or more can have one; candidates
    come from bounding boxes, the decision is exact."""
    polygonal = np.isin(shapely.get_type_id(geoms), (POLYGON, MULTIPOLYGON))
    chosen = geoms.copy()
    chosen[~polygonal] = None               # (only polygons' rings can touch)
    parts, feature_of_part = shapely.get_parts(chosen, return_index=True)
    rings, part_of_ring = shapely.get_rings(parts, return_index=True)
    if len(rings) == len(np.unique(feature_of_part[part_of_ring])):
        return geoms                        # one ring per feature: nothing can touch
    feature_of_ring = feature_of_part[part_of_ring]
    xy, ring_of = shapely.get_coordinates(rings, return_index=True)
    first = np.r_[True, ring_of[1:] != ring_of[:-1]]
    edge_start = np.flatnonzero(~np.r_[ring_of[1:] != ring_of[:-1], True])   # i -> i + 1
    segments = shapely.linestrings(np.stack([xy[edge_start], xy[edge_start + 1]], axis=1))
    vertex = np.flatnonzero(~first)           # each ring's vertices once (closing point)
    tree = shapely.STRtree(segments)
    v, e = tree.query(shapely.points(xy[vertex]))
    v, e = vertex[v], edge_start[e]
    same = (feature_of_ring[ring_of[v]] == feature_of_ring[ring_of[e]]) & (ring_of[v] != ring_of[e])
    v, e = v[same], e[same]
    P, A, B = xy[v], xy[e], xy[e + 1]
    inside = ~(P == A).all(axis=1) & ~(P == B).all(axis=1)
    v, e = v[inside], e[inside]
    flat = _orientations(np.concatenate([xy[v], xy[e], xy[e + 1]]),
                         np.arange(3 * len(v)).reshape(3, -1).T) == 0 if len(v) else v
    v, e = v[flat], e[flat]
    if not len(v):
        return geoms
    return _insert(geoms, rings, part_of_ring, feature_of_part, v, e)


def _insert(geoms, rings, part_of_ring, feature_of_part, v, e) -> np.ndarray:
    """The features of ``geoms`` with vertex ``v[k]`` inserted after coordinate
    ``e[k]`` (rows of the rings' coordinates), in order along each edge."""
    xyz, ring_of = shapely.get_coordinates(rings, include_z=True, return_index=True)
    has_z = shapely.has_z(rings)
    ends = np.searchsorted(ring_of, np.arange(len(rings) + 1))
    added: dict[int, list[int]] = {}
    for vi, ei in zip(v.tolist(), e.tolist()):
        added.setdefault(ei, []).append(vi)
    out = np.array(geoms, dtype=object)
    for f in np.unique(feature_of_part[part_of_ring[ring_of[e]]]):
        polygons = []
        for p in np.flatnonzero(feature_of_part == f):
            new_rings = []
            for r in np.flatnonzero(part_of_ring == p):
                rows = []
                for i in range(ends[r], ends[r + 1]):
                    rows.append(i)
                    rows.extend(_along(xyz, i, added.get(i, [])))
                ring = xyz[rows] if has_z[r] else xyz[rows, :2]
                new_rings.append(ring)
            polygons.append(shapely.Polygon(new_rings[0], new_rings[1:]))
        out[f] = polygons[0] if shapely.get_type_id(geoms[f]) == POLYGON else \
            shapely.MultiPolygon(polygons)
    return out


def _along(xyz: np.ndarray, i: int, points: list[int]) -> list[int]:
    """``points`` (rows of ``xyz`` on the edge from row ``i`` to ``i + 1``) sorted
    from ``i`` onwards, once each position (exact comparisons)."""
    if not points:
        return []
    dx, dy = np.sign(xyz[i + 1, :2] - xyz[i, :2])
    key = {(float(xyz[p, 0]), float(xyz[p, 1])): p for p in points}
    return [key[k] for k in sorted(key, key=lambda k: (k[0] * (dx or 1), k[1] * (dy or 1)))]
