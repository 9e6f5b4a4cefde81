"""The meshing functions of the ``triangle`` package: :func:`triangulate`,
:func:`delaunay`, :func:`convex_hull`, :func:`voronoi`.

:func:`triangulate` takes and returns the package's dictionaries:

input keys
    ``vertices`` (n, 2); ``vertex_markers`` (n, 1); ``vertex_attributes`` (n, k);
    ``segments`` (m, 2); ``segment_markers`` (m, 1); ``holes`` (h, 2); ``regions``
    (r, 4) ``x, y, attribute, max_area``; and for ``r`` ``triangles`` (k, 3) or (k, 6),
    ``triangle_attributes`` (k, a), ``triangle_max_area`` (k, 1). ``neighbors``,
    ``edges`` and ``edge_markers`` are accepted and not read (as Triangle does).
    Lists or arrays of any real or integer dtype.
output keys
    the same, float64 coordinates and attributes, int32 indices and markers (markers
    as (n, 1) columns), plus ``neighbors`` (``n``), ``edges`` and ``edge_markers``
    (``e``). A key is absent where Triangle leaves it out: an empty result (no
    triangles, no segments), and what ``B`` (markers), ``P`` (segments, holes,
    regions), ``N`` (vertices, their markers and attributes) and ``E`` (triangles)
    drop; ``holes`` and ``regions`` are the input's, with ``p``.

What differs from Triangle: every predicate is exact at every magnitude (no ``X``),
malformed input raises a named :class:`~cdt_plugin.errors.CDTError` where Triangle
crashes, loops or skips (NaN or infinite coordinates, indices out of range, fewer
than three vertices, a switch Triangle would misread), and the numbering of Steiner
points and the order of the triangles are ours. Duplicate vertices are kept in the
output (Triangle's numbering), in no triangle.

Switches that change nothing here: ``Q``, ``I``, ``g`` (Triangle's console and
files; ``V`` adds a report of what was done, :func:`report`), ``z`` (every index
is zero-based, as the package always asks), ``X`` (our arithmetic stays exact),
``F``, ``l``, ``s`` (how Triangle builds the same mesh: our divide and conquer
gives the same constrained Delaunay triangulation), ``v`` (the package's
``triangulate`` drops Triangle's Voronoi output too: use :func:`voronoi`).
``C`` checks the result with the exact certificate (Lemma 2.14) and raises
:class:`~cdt_plugin.errors.NotDelaunayError` if it fails; ``i`` uses incremental
insertion; ``u`` applies the size test the package compiles in
(:func:`sample_size_test`).
"""
from __future__ import annotations

import sys
from typing import Any, Mapping, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..cdt import triangulate as cdt_triangulate
from ..delaunay import delaunay as cdt_delaunay
from ..markers import make_tags
from ..errors import InputShapeError, NotDelaunayError, RefinementLimitError, TooFewPointsError
from ..sizing import refine_until_suitable
from ..switches import Switches, read_switches
from ..triangulation import Triangulation
from ..validate import as_array, as_points, real_array

#: A dictionary of the ``triangle`` package: Triangle's lists by name (:data:`KEYS`).
TriangleDict = Mapping[str, Any]
#: The keys of the package's dictionaries (Triangle's lists), in its order.
KEYS = ("vertices", "vertex_attributes", "vertex_markers", "triangles", "triangle_max_area",
        "triangle_attributes", "segments", "segment_markers", "holes", "regions", "neighbors",
        "edges", "edge_markers")
_KEYSET = frozenset(KEYS)
_NO_HOLES = np.empty((0, 2))
_I32 = np.int32
_NO_ROWS = np.empty(0, np.int64)
_NO_SEGMENTS = np.empty((0, 2), np.int64)


def triangulate(tri: TriangleDict, opts: str = "") -> dict[str, NDArray[Any]]:
    """Triangulate the dictionary ``tri`` with Triangle's switches ``opts``, as
    ``triangle.triangulate`` does (which prepends ``Qz``: so do we).

    Parameters
    ----------
    tri : dict
        The input (keys: see :mod:`cdt_plugin.triangle.tri`); ``vertices`` is required.
    opts : str
        Triangle's switches (:mod:`cdt_plugin.switches`): ``p`` a PSLG, ``q`` ``a``
        ``D`` ``Y`` ``YY`` ``S`` bounds, ``r`` refine ``tri["triangles"]``, ``e``
        ``n`` ``A`` ``o2`` ``j`` ``c`` outputs...

    Returns
    -------
    dict
        Triangle's output keys (module docstring).

    >>> from cdt_plugin import triangle as tr
    >>> t = tr.triangulate({"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "a0.2")
    >>> len(t["vertices"]), t["vertex_markers"].shape, t["triangles"].dtype
    (9, (9, 1), dtype('int32'))
    """
    s = read_switches(opts)
    _check_keys(tri)
    if s.refine:
        return _output(*_refined(tri, s), tri=tri, s=s)
    if s.pslg and not s.convex_hull and not len(tri.get("segments", ())):
        return _eaten(tri, s)
    mesh = _meshed(tri, s)
    return _output(mesh, _region_attributes(mesh, s), tri=tri, s=s)


def _check_keys(tri: TriangleDict) -> None:
    if isinstance(tri, Mapping) and _KEYSET.issuperset(tri) and "vertices" in tri:
        return                 # (the common case in one look-up of each key)
    if not isinstance(tri, Mapping):
        raise InputShapeError(f"triangulate takes a dict of arrays (keys {', '.join(KEYS)}), "
                              f"got {type(tri).__name__}")
    unknown = [k for k in tri if k not in KEYS]
    if unknown:
        raise InputShapeError(f"unknown key {unknown[0]!r} in the input dict: the keys are "
                              f"{', '.join(KEYS)}")
    if "vertices" not in tri:
        raise InputShapeError("the input dict has no 'vertices'")


def _column(a: ArrayLike | None, name: str) -> NDArray[Any] | None:
    """An (n, 1) marker column (or (n,)) as the (n,) the engine takes (which checks
    its length and values)."""
    return None if a is None else as_array(a, name).reshape(-1)


def _meshed(tri: TriangleDict, s: Switches) -> Triangulation:
    """``p``, ``c``, quality switches: one call of :func:`cdt_plugin.triangulate`."""
    segments = holes = regions = None
    if s.pslg:
        segments = tri.get("segments")
        # (holes given, even none: the triangles outside the segments are removed, as
        # Triangle removes them; depth parity would keep an unholed nested polygon's)
        holes = _NO_HOLES if s.no_holes else tri.get("holes", _NO_HOLES)
        regions = _regions(tri.get("regions"), s)
    marks = _marks(tri, s, segments is not None)
    vertices = tri["vertices"]
    keywords = _keywords(s)
    smallest = _smallest_area(s, regions)
    if smallest and s.max_steiner is None:
        vertices = as_points(vertices, "vertices")      # (checked before it is measured)
        keywords = {**keywords, "max_steiner": _steiner_cap(vertices, smallest)}
    if s.user_test:
        keywords = {**keywords, "suitable": sample_size_test}
    try:
        mesh = cdt_triangulate(vertices, segments, holes=holes, regions=regions, **keywords, **marks)
    except RefinementLimitError as stop:
        mesh = _stopped_at_s(stop, s)
    if len(mesh.vertex_map) < 3:     # (checked after the engine's checks of the array)
        raise TooFewPointsError(f"Triangle needs at least three vertices, got {len(mesh.vertex_map)}")
    return mesh


def _stopped_at_s(stop: RefinementLimitError, s: Switches) -> Triangulation:
    """The mesh where ``S<n>`` stopped refinement (Triangle returns it as it is); the
    error itself where our own cap stopped it (Triangle has none: it would go on)."""
    if s.max_steiner is None or not isinstance(stop.triangulation, Triangulation):
        raise stop
    return stop.triangulation


def _smallest_area(s: Switches, regions: NDArray[np.float64] | None) -> float | None:
    """The smallest area bound of ``a<area>`` and (bare ``a``) the regions', or None."""
    bounds = [s.max_area] if s.max_area else []
    if regions is not None and s.area_from_input:
        positive = regions[:, 3][regions[:, 3] > 0]
        bounds += [float(positive.min())] if len(positive) else []
    return min(bounds) if bounds else None


def _steiner_cap(vertices: NDArray[np.float64], max_area: float) -> int:
    """The cap on Steiner points with ``a<area>`` and no ``S``: Triangle has none,
    and the engine's default (at most a million for the area bound) would stop a
    fine mesh Triangle makes; eight points per ``max_area`` of the bounding box
    (a triangle of the mesh is larger than ``max_area / 8`` where it meets the
    bound) plus the engine's allowance for the angle bound."""
    box = float(np.prod(np.ptp(vertices, axis=0)))
    return 100 * len(vertices) + 100_000 + int(min(8 * box / max_area, 2.0 ** 62))


def _eaten(tri: TriangleDict, s: Switches) -> dict[str, NDArray[Any]]:
    """``p`` with no segments and no ``c``: Triangle removes every triangle (nothing
    stops the removal that starts at the convex hull) and returns the vertices."""
    vertices = as_points(tri["vertices"], "vertices")
    if len(vertices) < 3:
        raise TooFewPointsError(f"Triangle needs at least three vertices, got {len(vertices)}")
    n = len(vertices)
    tags = make_tags(n, _NO_SEGMENTS, tri.get("vertex_markers"), None, tri.get("vertex_attributes"))
    out: dict[str, NDArray[Any]] = {}
    if not s.no_nodes and not s.jettison:
        out["vertices"] = vertices
        if tags is not None and tags.vertex_attributes is not None:
            _put(out, "vertex_attributes", tags.vertex_attributes)
        if not s.no_markers:      # (the input's markers, else 0: no triangle, no boundary)
            given = None if tags is None else tags.vertex_markers
            out["vertex_markers"] = _i32(np.zeros(n, _I32) if given is None else given)
    _copy_holes_regions(out, tri, s)
    return out


def _regions(given: ArrayLike | None, s: Switches) -> NDArray[np.float64] | None:
    """The regions as the engine reads them: a region's maximum area (4th column)
    bounds it only with a bare ``a``, as in Triangle."""
    regions = None if given is None else real_array(given, "regions")
    if regions is None or len(regions) == 0:
        return None
    return regions if s.area_from_input else regions[:, :3]


def _keywords(s: Switches) -> dict[str, Any]:
    """:meth:`Switches.keywords`, made once per switch string (a string's hash is
    kept by Python: a look-up, where hashing the record would cost a microsecond)."""
    found = _KEYWORDS.get(s.text)
    if found is None:
        found = _KEYWORDS[s.text] = s.keywords()
    return found


_KEYWORDS: dict[str, dict[str, Any]] = {}


def _refined(tri: TriangleDict, s: Switches) -> tuple[Triangulation, NDArray[np.float64] | None]:
    """``r``: the input mesh (``triangles``; with ``p`` its ``segments``) refined with
    the quality switches; a bare ``a`` reads ``triangle_max_area`` (<= 0: no bound),
    combined with ``a<area>`` by the smaller bound, as in Triangle."""
    if "triangles" not in tri:
        raise InputShapeError("the switch 'r' refines tri['triangles'], which is missing")
    triangles = np.asarray(tri["triangles"])
    if triangles.ndim == 2 and triangles.shape[1] == 6:
        triangles = triangles[:, :3]      # (a six-node mesh: its corners)
    segments = tri.get("segments") if s.pslg else None
    base = Triangulation.from_triangles(tri["vertices"], triangles, segments=segments,
                                        **_marks(tri, s, segments is not None))
    attributes = tri.get("triangle_attributes")
    if not s.quality and not s.conforming_delaunay:
        return base, _carried_attributes(base, base, attributes)
    max_area, smallest = _area_bounds(tri, s)
    kw = _keywords(s)
    steiner = s.max_steiner
    if steiner is None and smallest:
        steiner = _steiner_cap(base.vertices, smallest)
    try:
        mesh = base.refine(min_angle=s.min_angle, max_area=max_area,
                           conforming_delaunay=s.conforming_delaunay,
                           split_boundary=kw.get("split_boundary", True),
                           split_segments=kw.get("split_segments", True),
                           max_steiner=steiner)
        if s.user_test:
            mesh = refine_until_suitable(mesh, sample_size_test, min_angle=s.min_angle,
                                         conforming_delaunay=s.conforming_delaunay,
                                         split_boundary=kw.get("split_boundary", True),
                                         split_segments=kw.get("split_segments", True),
                                         max_steiner=steiner)
    except RefinementLimitError as stop:
        mesh = _stopped_at_s(stop, s)
    return mesh, _carried_attributes(base, mesh, attributes)


def sample_size_test(org: NDArray[np.float64], dest: NDArray[np.float64], apex: NDArray[np.float64],
                     area: NDArray[np.float64]) -> NDArray[np.bool_]:
    """The size test ``u`` applies: the sample ``triunsuitable`` of ``triangle.c``,
    which the ``triangle`` package compiles in (a triangle is too large when its
    longest edge squared exceeds ``0.05 (x^2 + y^2) + 0.02`` at its first
    corner), vectorised (:mod:`cdt_plugin.sizing`). Which corner is first is
    Triangle's orientation of the moment there, corner 0 here: the meshes
    differ, the test they pass is the same. For a test of your own, pass
    ``suitable=`` to :func:`cdt_plugin.triangulate`.

    >>> import numpy as np
    >>> org, dest, apex = np.array([[0.0, 0.0], [1, 1]]), np.array([[0.05, 0], [2, 1]]), np.array([[0, 0.05], [1, 2]])
    >>> sample_size_test(org, dest, apex, np.array([0.00125, 0.5])).tolist()   # small near the origin
    [True, False]
    """
    longest = np.maximum.reduce([((dest - org) ** 2).sum(1), ((apex - dest) ** 2).sum(1),
                                 ((org - apex) ** 2).sum(1)])
    return longest <= 0.05 * (org ** 2).sum(1) + 0.02


def _marks(tri: TriangleDict, s: Switches, segments: bool) -> dict[str, Any]:
    """The markers and attributes of the input, as the engine's keywords (no markers
    with ``B``; segment markers only where segments are read)."""
    marks: dict[str, Any] = {}
    if not s.no_markers:
        if "vertex_markers" in tri:
            marks["vertex_markers"] = _column(tri["vertex_markers"], "vertex_markers")
        if segments and "segment_markers" in tri:
            marks["segment_markers"] = _column(tri["segment_markers"], "segment_markers")
    if "vertex_attributes" in tri:
        marks["vertex_attributes"] = tri["vertex_attributes"]
    return marks


def _area_bounds(tri: TriangleDict, s: Switches) -> tuple[Any, float | None]:
    """``r``'s area bound (a number, one per triangle with a bare ``a``: the smaller
    of ``triangle_max_area`` and ``a<area>``, <= 0 none) and its smallest positive value."""
    if not (s.area_from_input and "triangle_max_area" in tri):
        return s.max_area, s.max_area
    bound = np.asarray(tri["triangle_max_area"], dtype=np.float64).reshape(-1)
    if s.max_area is not None:
        bound = np.where(bound > 0, np.minimum(bound, s.max_area), s.max_area)
    positive = bound[bound > 0]
    return bound, float(positive.min()) if len(positive) else s.max_area


def _output(mesh: Triangulation, triangle_attributes: NDArray[np.float64] | None, *,
            tri: TriangleDict, s: Switches) -> dict[str, NDArray[Any]]:
    """Triangle's output dictionary of ``mesh``, with the keys ``s`` asks for (after
    ``C``'s check; ``V``'s line on stderr)."""
    if s.check and not mesh.is_delaunay():
        raise NotDelaunayError(f"the mesh of {s.text!r} fails its constrained Delaunay "
                               f"certificate at edges {mesh.non_delaunay_edges()[:5].tolist()}")
    if s.verbose:
        print(report(mesh, s), file=sys.stderr)
    nodes = mesh.quadratic() if s.order == 2 else mesh      # (the same names of both)
    vertices, triangles = nodes.vertices, nodes.triangles
    vertex_markers = None if s.no_markers or s.no_nodes else nodes.vertex_markers
    attributes = (nodes.vertex_attributes if "vertex_attributes" in tri and not s.no_nodes
                  else None)
    edges = mesh.edges if s.edges else None
    segments = segment_markers = None
    if (s.pslg or s.convex_hull) and not s.no_poly:
        segments, segment_markers = _segments(mesh, s)
    renumber = _renumbering(mesh, s, len(vertices))
    out: dict[str, NDArray[Any]] = {}
    if not s.no_nodes:
        keep = renumber.rows if renumber is not None else None
        _put(out, "vertices", vertices if keep is None else vertices[keep])
        if attributes is not None:
            _put(out, "vertex_attributes", attributes if keep is None else attributes[keep])
        if vertex_markers is not None:
            _put(out, "vertex_markers", _i32(vertex_markers if keep is None else vertex_markers[keep]))
    if not s.no_elements and len(triangles):
        _put(out, "triangles", _i32(triangles, renumber))
        if triangle_attributes is not None:
            _put(out, "triangle_attributes", triangle_attributes)
    if s.neighbors and len(triangles):
        _put(out, "neighbors", mesh.neighbors.astype(_I32))
    if segments is not None:
        _put(out, "segments", _i32(segments, renumber))
        if segment_markers is not None:
            _put(out, "segment_markers", _i32(segment_markers))
    _copy_holes_regions(out, tri, s)
    if edges is not None and len(edges):
        _put(out, "edges", _i32(edges, renumber))
        if not s.no_markers:
            _put(out, "edge_markers", _i32(mesh.edge_markers))
    return out


def _copy_holes_regions(out: dict[str, NDArray[Any]], tri: TriangleDict,
                        s: Switches) -> None:
    """With ``p`` (and no ``P``) Triangle's output has the input's holes and regions."""
    if s.pslg and not s.no_poly:
        for key in ("holes", "regions"):
            if key in tri and len(tri[key]):
                out[key] = np.asarray(tri[key], dtype=np.float64)


def _put(out: dict[str, NDArray[Any]], key: str, value: NDArray[Any]) -> None:
    if len(value):
        out[key] = value


def _i32(a: NDArray[Any], renumber: _Renumbering | None = None) -> NDArray[np.int32]:
    """Indices (through ``renumber``) or markers as Triangle's int32, markers as a column."""
    if renumber is not None:
        a = renumber.number[a]
    a = a.astype(_I32)
    return a.reshape(-1, 1) if a.ndim == 1 else a


class _Renumbering(NamedTuple):
    """Triangle's vertex numbers where they are not the engine's: ``number[i]`` is
    the output number of the engine's vertex ``i``, ``rows[j]`` the engine's vertex
    that output vertex ``j`` is."""
    number: NDArray[np.int64]
    rows: NDArray[np.int64]


def _renumbering(mesh: Triangulation, s: Switches, n_out: int) -> _Renumbering | None:
    """How the engine's ``n_out`` vertices become Triangle's: None when they are the
    same (the common case: no duplicate input vertex, no ``j``). Triangle keeps a
    duplicate vertex, in no triangle; ``j`` drops the vertices no triangle uses."""
    n_in = len(mesh.vertex_map)
    distinct = len(mesh.vertices) - len(mesh.steiner)
    if distinct == n_in and not s.jettison:
        return None
    rows = number = np.arange(n_out)
    if distinct < n_in:
        rows = np.concatenate([mesh.vertex_map, np.arange(distinct, n_out)])
        number = np.concatenate([_input_numbers(mesh)[:distinct],
                                 np.arange(n_in, n_in + n_out - distinct)])
    if s.jettison:
        used = np.zeros(n_out, bool)
        used[mesh.triangles] = True
        kept = used[rows] & (number[rows] == np.arange(len(rows)))    # (not a duplicate)
        renumbered = np.full(len(rows), -1)
        renumbered[kept] = np.arange(int(kept.sum()))
        rows, number = rows[kept], renumbered[number]
    return _Renumbering(number, rows)


def _segments(mesh: Triangulation, s: Switches) -> tuple[NDArray[np.int64], NDArray[np.int64] | None]:
    """The output segments (every piece; with ``c`` also the hull edges that are
    not pieces, as Triangle encloses the hull with segments) and their markers."""
    segments = mesh.segments
    markers = None if s.no_markers else mesh.segment_markers
    if s.convex_hull:
        t, nb = mesh.triangles, mesh.neighbors
        k, j = np.nonzero((nb < 0) & ~mesh.constrained)
        if len(k):
            hull = np.column_stack([t[k, (j + 1) % 3], t[k, (j + 2) % 3]])
            segments = np.concatenate([segments, hull])
            if markers is not None:
                markers = np.concatenate([markers, np.ones(len(hull), markers.dtype)])
    return segments, markers


def _region_attributes(mesh: Triangulation, s: Switches) -> NDArray[np.float64] | None:
    """``A`` with ``p``: each triangle's regional attribute, (k, 1) (0 outside every
    region, as in Triangle); None without ``A`` or without regions."""
    if not (s.region_attributes and s.pslg) or mesh.region_attributes is None:
        return None
    return np.nan_to_num(mesh.region_attributes, nan=0.0).reshape(-1, 1)


def _carried_attributes(base: Triangulation, mesh: Triangulation,
                        attributes: ArrayLike | None) -> NDArray[np.float64] | None:
    """``r``: the input's ``triangle_attributes`` on the refined triangles, each
    taking those of the input triangle that holds its centroid (refinement splits
    the input triangles; a triangle of a flip across two input triangles with
    different attributes takes the one its centroid lies in)."""
    if attributes is None:
        return None
    values = np.asarray(attributes, dtype=np.float64).reshape(len(base.triangles), -1)
    if mesh is base:
        return values
    centroids = mesh.vertices[mesh.triangles].mean(axis=1)
    return values[base.locate(centroids)]


def report(mesh: Triangulation, s: Switches) -> str:
    """What ``V`` prints: the switches read and the mesh made."""
    return (f"cdt_plugin.triangle: switches {s.text!r}: {len(mesh.vertices)} vertices "
            f"({len(mesh.steiner)} Steiner points), {len(mesh.triangles)} triangles, "
            f"{len(mesh.segments)} segment pieces; engine keywords {s.keywords()}")


def delaunay(pts: ArrayLike) -> NDArray[np.int32]:
    """The Delaunay triangles of the points ``pts``, (k, 3) int32 (``triangle.delaunay``).

    >>> from cdt_plugin import triangle as tr
    >>> tr.delaunay([[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]).shape
    (4, 3)
    """
    mesh = _points(pts)
    return _i32(mesh.triangles, _Renumbering(_input_numbers(mesh), _NO_ROWS))


def convex_hull(pts: ArrayLike) -> NDArray[np.int32]:
    """The convex hull of ``pts`` as (h, 2) int32 segments (``triangle.convex_hull``).

    >>> from cdt_plugin import triangle as tr
    >>> tr.convex_hull([[0, 0], [0, 1], [1, 1], [1, 0]]).shape
    (4, 2)
    """
    mesh = _points(pts)
    t, nb = mesh.triangles, mesh.neighbors
    k, j = np.nonzero(nb < 0)
    hull = np.column_stack([t[k, (j + 1) % 3], t[k, (j + 2) % 3]])
    return _i32(hull, _Renumbering(_input_numbers(mesh), _NO_ROWS))


def voronoi(pts: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.int32],
                                     NDArray[np.int32], NDArray[np.float64]]:
    """The Voronoi diagram of ``pts`` as ``triangle.voronoi`` gives it: the Voronoi
    vertices (f, 2), the finite edges (e, 2) between them, and the rays: the vertex
    each starts at and its direction (the outward normal of its hull edge, as long
    as the edge). Cocircular points give one Voronoi vertex here (Triangle repeats it
    once per triangle).

    >>> from cdt_plugin import triangle as tr
    >>> points, edges, ray_origin, ray_direct = tr.voronoi(
    ...     [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]])
    >>> sorted(points.tolist())
    [[0.0, 0.5], [0.5, 0.0], [0.5, 1.0], [1.0, 0.5]]
    >>> len(edges), len(ray_origin), sorted(np.abs(ray_direct).sum(axis=1).tolist())
    (4, 4, [1.0, 1.0, 1.0, 1.0])
    """
    mesh = _points(pts)
    vor = mesh.voronoi()
    ends, sites = vor.ridge_vertices, vor.ridge_points
    finite = (ends >= 0).all(axis=1)
    xy = mesh.vertices
    a, b = xy[sites[~finite, 0]], xy[sites[~finite, 1]]
    length = np.hypot(*(b - a).T)[:, None]
    directions = vor.ridge_directions[~finite] * length
    return (vor.vertices, ends[finite].astype(_I32), ends[~finite].max(axis=1).astype(_I32),
            directions)


def _points(pts: ArrayLike) -> Triangulation:
    """The Delaunay triangulation of a point set, three points at least."""
    points = as_points(pts, "pts")
    if len(points) < 3:
        raise TooFewPointsError(f"Triangle needs at least three vertices, got {len(points)}")
    return cdt_delaunay(points)


def _input_numbers(mesh: Triangulation) -> NDArray[np.int64]:
    """The input number of each of the engine's vertices (the first of duplicates)."""
    n_in = len(mesh.vertex_map)
    first = np.empty(len(mesh.vertices), np.int64)
    first[mesh.vertex_map[::-1]] = np.arange(n_in - 1, -1, -1)
    return first


__all__ = ["triangulate", "delaunay", "convex_hull", "voronoi", "KEYS", "report"]
