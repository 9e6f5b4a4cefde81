"""Quality report of a triangulation, and its comparison with another one.

The figures are those of the chapter's optimality results: a constrained
Delaunay triangulation maximises the minimum angle, minimises the largest
circumdisk and minimises the largest min-containment disk (Def. 1.20: the
smallest closed disk that includes the triangle) among all triangulations of the
same PLC (Theorem 2.8 for point sets, Theorem 2.17 for PLCs). ``report(tri,
against=...)`` computes the same figures for another triangulation of the same
input (earcut's, trimesh's, your own) and shows them side by side, which makes
those theorems visible.

Metrics (angles, radii) are floating point: they are measurements. The
certificate is exact: every edge shared by two triangles that is not a segment
(piece) is tested with the exact incircle predicate (Delaunay Lemma 2.3,
Constrained Delaunay Lemma 2.14), and exactly cocircular edges are counted
(Theorem 2.11: the triangulation is unique if there are none).

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 1], [1, 2], [2, 3], [3, 0]])
>>> rep = tri.report()
>>> rep.triangles, rep.min_angle, rep.non_delaunay_edges, rep.cocircular_edges, rep.unique
(2, 45.0, 0, 1, False)
>>> theirs = ([[0, 0], [4, 0], [4, 4], [0, 4]], [[0, 1, 2], [0, 2, 3]])
>>> rep = tri.report(against=theirs)
>>> rep.against.min_angle, rep.comparison["min_angle_not_smaller"]
(45.0, True)
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, fields
from typing import Any, Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core.certify import edge_lifted_values, orientation_signs
from ._core.gradation import triangle_measures
from .errors import CDTError, InputShapeError, SizeFieldError
from .fields import check_sizing, triangle_sizes
from .optional import require
from .plc import geojson_parts
from .types import GeometryLike, MeshLike, TriangulationLike
from .validate import as_index, as_mesh, exact_range, near_unit

__all__ = ["Report", "report", "compare", "mesh_report", "triangle_quality", "mesh_neighbors",
           "earcut", "size_ratios", "ANGLE_BINS"]

#: Default angle histogram bins: 10 degrees wide, 0 to 180.
ANGLE_BINS = np.arange(0.0, 181.0, 10.0)

#: Relative tolerance for the float rounding of a metric when comparing two meshes.
RTOL = 1e-9


@dataclass
class Report:
    """Quality figures of one triangulation (and optionally of another, ``against``).

    Counts: ``input_vertices`` (points given), ``merged_duplicates`` (exact
    duplicates merged into one vertex), ``steiner_vertices`` (vertices that are no
    input point), ``vertices`` (distinct vertices used by the triangles),
    ``triangles``, ``segments`` (input segments) and ``segment_edges`` (mesh
    edges on segments). Angles in degrees, each worst value with the index of
    its triangle (a row of ``triangles``). ``unique`` is None when the mesh is not
    (constrained) Delaunay. ``flips`` and ``seconds`` come from ``tri.stats``
    (None for a bare mesh). ``degenerate_triangles``: triangles of zero area
    (never in our output; their edges count as not locally Delaunay).
    ``flips`` counts the Delaunay flips of construction and refinement.
    """

    name: str
    input_vertices: int | None
    merged_duplicates: int | None
    steiner_vertices: int | None
    vertices: int
    triangles: int
    segments: int | None
    segment_edges: int | None
    min_angle: float | None
    min_angle_triangle: int | None
    max_angle: float | None
    max_angle_triangle: int | None
    max_circumradius: float | None
    max_circumradius_triangle: int | None
    max_min_containment_radius: float | None
    max_min_containment_triangle: int | None
    max_radius_edge_ratio: float | None
    mean_radius_edge_ratio: float | None
    mean_inradius: float | None
    non_delaunay_edges: int
    cocircular_edges: int
    unique: bool | None
    degenerate_triangles: int
    flips: int | None
    seconds: float | None
    angle_bins: NDArray[np.float64] = field(repr=False)
    angle_counts: NDArray[np.int64] = field(repr=False)
    against: Report | None = field(default=None, repr=False)
    comparison: dict[str, Any] | None = field(default=None, repr=False)

    # ------------------------------------------------------------ conversions
    def to_dict(self) -> dict[str, Any]:
        """Plain Python values (JSON-ready): every figure, the histogram as
        ``{"bins": edges, "counts": counts}``, and ``against`` / ``comparison``
        when present."""
        out: dict[str, Any] = {}
        for f in fields(self):
            if f.name in ("angle_bins", "angle_counts", "against", "comparison"):
                continue
            out[f.name] = _plain(getattr(self, f.name))
        out["angle_histogram"] = {"bins": [float(b) for b in self.angle_bins],
                                  "counts": [int(c) for c in self.angle_counts]}
        if self.against is not None:
            out["against"] = self.against.to_dict()
            out["comparison"] = {k: _plain(v) for k, v in (self.comparison or {}).items()}
        return out

    def to_json(self, **kwargs: Any) -> str:
        """:meth:`to_dict` as JSON (keywords go to :func:`json.dumps`, default indent 2)."""
        kwargs.setdefault("indent", 2)
        return json.dumps(self.to_dict(), **kwargs)

    def __str__(self) -> str:
        return _table(self)


# ---------------------------------------------------------------- per triangle
def triangle_quality(vertices: ArrayLike, triangles: ArrayLike) -> dict[str, NDArray[np.float64]]:
    """Per-triangle measurements, vectorised (float64, one row per triangle).

    Returns a dict with ``angles`` (k, 3) in degrees (angle at each corner),
    ``circumradius``, ``min_containment_radius`` (Def. 1.20: the circumradius of
    a non-obtuse triangle, half the longest edge of an obtuse one), ``inradius``
    (area over semiperimeter), ``shortest_edge`` and ``radius_edge_ratio``
    (circumradius over shortest edge). A zero-area triangle has infinite
    circumradius and radius-edge ratio.

    >>> q = triangle_quality([[0, 0], [4, 0], [0, 3], [2, 1]], [[0, 1, 2], [0, 1, 3]])
    >>> q["angles"][0].round(4).tolist(), q["circumradius"].round(12).tolist()
    ([90.0, 36.8699, 53.1301], [2.5, 2.5])
    >>> q["min_containment_radius"].tolist()   # the second triangle is obtuse
    [2.5, 2.0]
    """
    V = np.asarray(vertices, dtype=np.float64)[:, :2]
    T = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    V, e = near_unit(V)     # products of three sides: at a scale near 1, lengths scaled back
    # Sort each triangle's corners by (x, y), so that the same triangle gives
    # bit-identical figures in any mesh and any corner order.
    rot = _lexicographic_corners(V[T])
    P = V[np.take_along_axis(T, rot, axis=1)]         # (k, 3, 2)
    nxt, prv = P[:, [1, 2, 0]], P[:, [2, 0, 1]]
    sides = np.hypot(*(prv - nxt).transpose(2, 0, 1))  # side j is opposite corner j
    # twice the area, from the corner opposite the longest side: its two edges are
    # the shortest, which keeps the cancellation of a sliver's cross product small
    apex = np.argmax(sides, axis=1)[:, None, None]
    a = np.take_along_axis(P, apex, axis=1)[:, 0]
    u = np.take_along_axis(nxt, apex, axis=1)[:, 0] - a
    w = np.take_along_axis(prv, apex, axis=1)[:, 0] - a
    area2 = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
    dot = np.einsum("kij,kij->ki", nxt - P, prv - P)
    angles = np.empty_like(dot)
    np.put_along_axis(angles, rot, np.degrees(np.arctan2(area2[:, None], dot)), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        circumradius = np.where(area2 > 0, sides.prod(axis=1) / (2.0 * area2), np.inf)
        sq = sides ** 2
        longest = sq.max(axis=1)
        obtuse = longest > sq.sum(axis=1) - longest
        containment = np.where(obtuse, np.sqrt(longest) / 2.0, circumradius)
        perimeter = sides.sum(axis=1)
        inradius = np.where(perimeter > 0, area2 / np.where(perimeter > 0, perimeter, 1.0), 0.0)
        shortest = sides.min(axis=1)
        ratio = np.where(shortest > 0, circumradius / np.where(shortest > 0, shortest, 1.0), np.inf)
    if e:
        circumradius, containment, inradius, shortest = (
            np.ldexp(v, e) for v in (circumradius, containment, inradius, shortest))
    return {"angles": angles, "circumradius": circumradius, "min_containment_radius": containment,
            "inradius": inradius, "shortest_edge": shortest, "radius_edge_ratio": ratio}


#: The quantiles of longest edge / size that :func:`size_ratios` reports.
SIZE_QUANTILES = {"min": 0.0, "q01": 0.01, "q05": 0.05, "q25": 0.25, "median": 0.5, "q75": 0.75,
                  "q95": 0.95, "q99": 0.99}


def size_ratios(tri: TriangulationLike, size: Any, *, growth: float | None = None,
                min_size: float | None = None) -> dict[str, Any]:
    """How a mesh meets a size field: the distribution of each triangle's
    longest edge over the field at its centroid (``size``, ``growth`` and
    ``min_size`` as :func:`cdt_plugin.triangulate` takes them, the field
    graded on this mesh as there). Keys: ``triangles``, the quantiles
    ``min``, ``q01``, ``q05``, ``q25``, ``median``, ``q75``, ``q95``,
    ``q99``, then ``max`` and ``mean``, and the counts ``over_1_5`` (longer
    than 1.5 times the size: ``triangulate(size=...)`` leaves none) and
    ``under_0_5`` (shorter than half of it).

    >>> import cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], size=0.1, min_angle=30)
    >>> r = size_ratios(tri, 0.1)
    >>> r["over_1_5"], 0.9 < r["median"] < 1.1
    (0, True)
    """
    sizing = check_sizing(size, None, growth, min_size)
    if sizing is None or sizing.size is None:
        raise SizeFieldError("size_ratios needs the size field the mesh is compared with (size=)")
    V = np.ascontiguousarray(tri.vertices, np.float64)
    T = np.ascontiguousarray(tri.triangles, np.int64)
    cx, cy, _, longest = triangle_measures(V, T)
    ratio = longest / triangle_sizes(V, T, sizing.size, sizing.growth, sizing.min_size, (cx, cy))
    out: dict[str, Any] = {"triangles": len(T)}
    if len(T) == 0:
        return out
    for name, q in SIZE_QUANTILES.items():
        out[name] = float(np.quantile(ratio, q))
    out.update(max=float(ratio.max()), mean=float(ratio.mean()), over_1_5=int((ratio > 1.5).sum()),
               under_0_5=int((ratio < 0.5).sum()))
    return out


def mesh_neighbors(triangles: ArrayLike) -> tuple[NDArray[np.int64], int]:
    """Neighbours of an indexed triangle mesh, vectorised: ``neighbors[t, j]`` is
    the triangle sharing the edge opposite corner ``j`` of ``t`` (-1: boundary).
    Edges in more than two triangles (non-manifold) get -1 on every side; their
    number is returned too.

    >>> nb, nonmanifold = mesh_neighbors([[0, 1, 2], [0, 2, 3]])
    >>> nb.tolist(), nonmanifold
    ([[-1, 1, -1], [-1, -1, 0]], 0)
    """
    T = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    k = len(T)
    a, b = T[:, [1, 2, 0]].ravel(), T[:, [2, 0, 1]].ravel()   # half-edge 3t+j: opposite corner j
    n = int(T.max(initial=-1)) + 1
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    start = np.r_[True, sk[1:] != sk[:-1]] if len(sk) else np.zeros(0, bool)
    run = np.cumsum(start) - 1
    run_len = np.bincount(run) if len(run) else np.zeros(0, np.int64)
    first = np.flatnonzero(start & (run_len[run] == 2))
    h1, h2 = order[first], order[first + 1]
    nb = np.full(3 * k, -1, np.int64)
    nb[h1], nb[h2] = h2 // 3, h1 // 3
    return nb.reshape(k, 3), int((run_len > 2).sum())


def _lexicographic_corners(P) -> np.ndarray:
    """The corners (0, 1, 2) of each triangle of ``P`` (k, 3, 2) sorted by (x, y)."""
    by_y = np.argsort(P[..., 1], axis=1, kind="stable")
    x = np.take_along_axis(P[..., 0], by_y, axis=1)
    return np.take_along_axis(by_y, np.argsort(x, axis=1, kind="stable"), axis=1)


# ----------------------------------------------------------------- topology
def _edge_keys(pairs, n) -> np.ndarray:
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    return np.minimum(pairs[:, 0], pairs[:, 1]) * n + np.maximum(pairs[:, 0], pairs[:, 1])


def _count_signs(signs, flat=None) -> tuple[int, int, bool | None]:
    """(not locally Delaunay, cocircular, unique) from (k, j, sign) rows;
    rows touching a ``flat`` triangle count as not locally Delaunay."""
    bad = signs[:, 2] > 0
    if flat is not None:
        bad |= flat[signs[:, 0]] | flat[signs[:, 3]]
    non_delaunay = int(bad.sum())
    cocircular = int(((signs[:, 2] == 0) & ~bad).sum())
    return non_delaunay, cocircular, (cocircular == 0) if non_delaunay == 0 else None


def _mesh_certificate(V, T, segments) -> tuple[int, int, bool | None, int, int | None]:
    """Exact certificate of a bare mesh (duplicate positions already merged):
    triangles made counter-clockwise, neighbours by shared index pairs, edges in
    ``segments`` exempt. Returns (non-Delaunay, cocircular, unique, flat count,
    number of segments that are mesh edges or None)."""
    x, y, _, _ = exact_range(V[:, 0].copy(), V[:, 1].copy(), None, "mesh vertices")
    sign = orientation_signs(x, y, T) if len(T) else np.zeros(0, np.int64)
    T = np.where((sign < 0)[:, None], T[:, [0, 2, 1]], T)
    N, _ = mesh_neighbors(T)
    raw = edge_lifted_values(x, y, np.zeros(len(V)), False, T, N)
    on_segments = None
    if segments is not None:
        n = len(V)
        seg_keys = np.unique(_edge_keys(segments, n))
        edge_keys = np.unique(_edge_keys(np.column_stack([T[:, [1, 2, 0]].ravel(),
                                                          T[:, [2, 0, 1]].ravel()]), n))
        on_segments = int(np.isin(seg_keys, edge_keys).sum())
        a, b = T[raw[:, 0], (raw[:, 1] + 1) % 3], T[raw[:, 0], (raw[:, 1] + 2) % 3]
        raw = raw[~np.isin(_edge_keys(np.column_stack([a, b]), n), seg_keys)]
    other = N[raw[:, 0], raw[:, 1]]
    flat = sign == 0
    rows = np.column_stack([raw, other])
    return (*_count_signs(rows, flat), int(flat.sum()), on_segments)


def _triangulation_certificate(tri) -> tuple[int, int, bool | None]:
    s = tri._edge_signs()   # interior non-segment edges, exact (weighted: lifted test)
    other = tri.neighbors[s[:, 0], s[:, 1]]
    return _count_signs(np.column_stack([s, other]))


# ------------------------------------------------------------------ reports
def _figures(V, T, bins) -> dict[str, Any]:
    """The metric fields of a Report from vertices and triangles."""
    out: dict[str, Any] = dict.fromkeys(
        ["min_angle", "min_angle_triangle", "max_angle", "max_angle_triangle", "max_circumradius",
         "max_circumradius_triangle", "max_min_containment_radius", "max_min_containment_triangle",
         "max_radius_edge_ratio", "mean_radius_edge_ratio", "mean_inradius"])
    bins = np.asarray(bins, dtype=np.float64)
    out["angle_bins"] = bins
    if len(T) == 0:
        out["angle_counts"] = np.zeros(len(bins) - 1, np.int64)
        return out
    q = triangle_quality(V, T)
    smallest, largest = q["angles"].min(axis=1), q["angles"].max(axis=1)
    for key, where, values, pick in (
            ("min_angle", "min_angle_triangle", smallest, np.argmin),
            ("max_angle", "max_angle_triangle", largest, np.argmax),
            ("max_circumradius", "max_circumradius_triangle", q["circumradius"], np.argmax),
            ("max_min_containment_radius", "max_min_containment_triangle",
             q["min_containment_radius"], np.argmax)):
        t = int(pick(values))
        out[key], out[where] = float(values[t]), t
    out["max_radius_edge_ratio"] = float(q["radius_edge_ratio"].max())
    out["mean_radius_edge_ratio"] = float(q["radius_edge_ratio"].mean())
    out["mean_inradius"] = float(q["inradius"].mean())
    out["angle_counts"] = np.histogram(q["angles"].ravel(), bins=bins)[0].astype(np.int64)
    return out


def _report_of_triangulation(tri, name, bins) -> Report:
    T = np.asarray(tri.triangles, np.int64)
    V = np.asarray(tri.vertices, np.float64)
    stats = tri.stats or {}
    non_delaunay, cocircular, unique = (_triangulation_certificate(tri) if len(T) else (0, 0, None))
    n_input = stats.get("input_points", len(tri.vertex_map))
    return Report(
        name=name, input_vertices=int(n_input), merged_duplicates=int(stats.get("duplicates", 0)),
        steiner_vertices=int(len(tri.steiner)), vertices=int(len(np.unique(T))) if len(T) else len(V),
        triangles=len(T), segments=_int_or_none(stats.get("input_segments")),
        segment_edges=int(len(tri.segments)), non_delaunay_edges=non_delaunay,
        cocircular_edges=cocircular, unique=unique, degenerate_triangles=0,
        flips=None if "flips" not in stats else int(stats["flips"]) + int(stats.get("refinement_flips", 0)),
        seconds=_float_or_none(stats.get("seconds")),
        **_figures(V, T, bins))


def mesh_report(vertices: ArrayLike, triangles: ArrayLike, *, segments: ArrayLike | None = None,
                name: str = "mesh", bins: ArrayLike = ANGLE_BINS) -> Report:
    """The same figures as :func:`report` for a bare triangle mesh (any winding).

    ``vertices`` (n, 2) (or (n, 3): x and y are used), ``triangles`` (k, 3)
    indices, ``segments`` (s, 2) index pairs exempt from the Delaunay test.
    Vertices at exactly the same position are merged first (``merged_duplicates``)
    so that triangles meeting there are neighbours; unused vertices are ignored.

    >>> rep = mesh_report([[0, 0], [4, 0], [4, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]])
    >>> rep.triangles, rep.non_delaunay_edges, rep.unique
    (2, 0, False)
    >>> mesh_report([[0, 0], [4, 0], [4, 1], [0, 1]], [[0, 1, 3], [1, 2, 3]]).cocircular_edges
    1
    """
    V, T = as_mesh(vertices, triangles)
    S = None if segments is None else as_index(segments, "segments", 2, len(V))
    used = np.unique(T)
    uniq, inverse = np.unique(V[used], axis=0, return_inverse=True)
    merged = np.full(len(V), -1, np.int64)
    merged[used] = inverse.ravel()
    Tm = merged[T]
    if S is not None:
        S = merged[S]
        S = S[(S >= 0).all(axis=1)]
    non_delaunay, cocircular, unique, flat, on_segments = _mesh_certificate(uniq, Tm, S)
    return Report(
        name=name, input_vertices=len(V), merged_duplicates=int(len(used) - len(uniq)),
        steiner_vertices=None, vertices=len(uniq), triangles=len(T),
        segments=None if S is None else len(S), segment_edges=on_segments,
        non_delaunay_edges=non_delaunay, cocircular_edges=cocircular, unique=unique,
        degenerate_triangles=flat, flips=None, seconds=None, **_figures(V, T, bins))


def report(tri: TriangulationLike, against: MeshLike | None = None, *, name: str = "cdt_plugin",
           against_name: str = "against", bins: ArrayLike = ANGLE_BINS) -> Report:
    """Quality report of a :class:`~cdt_plugin.Triangulation` (``tri.report()``).

    With ``against`` — another triangulation of the same input: a
    ``(vertices, triangles)`` pair, a Triangulation, or anything with
    ``vertices`` and ``faces`` (a ``trimesh.Trimesh``) — the same figures are
    computed for it (:func:`mesh_report`; the edges that are our segment pieces
    are its segments) and ``str(report)`` shows both side by side.
    ``report.comparison`` then says whether both use the same vertex positions
    (nothing dropped) and have as many triangles, whether the theorem applies
    (that, and no Steiner points) and, for the three optimality criteria
    of Theorem 2.8 / 2.17, whether ours is at least as good (within a relative
    ``RTOL`` of float rounding). ``bins``: angle histogram edges in degrees.

    >>> import cdt_plugin
    >>> kite = [[0, 0], [2, -1], [4, 0], [2, 3]]
    >>> tri = cdt_plugin.triangulate(kite, [[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> rep = tri.report(against=(kite, [[0, 1, 2], [0, 2, 3]]), against_name="mine")
    >>> rep.non_delaunay_edges, rep.against.non_delaunay_edges
    (0, 1)
    >>> round(rep.min_angle, 2), round(rep.against.min_angle, 2), rep.comparison["theorem_applies"]
    (33.69, 26.57, True)
    """
    ours = _report_of_triangulation(tri, name, bins)
    if against is None:
        return ours
    V, T = against_arrays(against)
    seg_xy = np.asarray(tri.vertices, np.float64)[np.asarray(tri.segments, np.int64)]
    pieces = _indices_of(V, seg_xy.reshape(-1, 2)).reshape(-1, 2)
    theirs = mesh_report(V, T, segments=pieces[(pieces >= 0).all(axis=1)], name=against_name,
                         bins=bins)
    ours.against = theirs
    ours.comparison = _comparison(tri, ours, theirs, V, T)
    return ours


def compare(tri: TriangulationLike, against: MeshLike, *, against_name: str = "against",
            **kwargs: Any) -> Report:
    """:func:`report` of ``tri`` side by side with ``against`` (required here)."""
    if against is None:
        raise CDTError("compare needs a triangulation to compare with (against=...)")
    return report(tri, against, against_name=against_name, **kwargs)


def _comparison(tri, ours: Report, theirs: Report, V, T) -> dict[str, Any]:
    T0 = np.asarray(tri.triangles, np.int64)
    mine = np.unique(np.asarray(tri.vertices, np.float64)[np.unique(T0)], axis=0)
    other = np.unique(V[np.unique(T)], axis=0)
    same = bool(mine.shape == other.shape and np.array_equal(mine, other))
    # With the same vertices and domain every triangulation has as many triangles
    # (Euler's formula); fewer means a vertex inside an edge (earcut across
    # collinear points): not a triangulation, so the theorem says nothing.
    same_count = ours.triangles == theirs.triangles
    out: dict[str, Any] = {"same_vertices": same, "same_triangle_count": same_count,
                           "theorem_applies": same and same_count and ours.steiner_vertices == 0}
    checks = (("min_angle_not_smaller", "min_angle", 1),
              ("max_circumradius_not_larger", "max_circumradius", -1),
              ("max_min_containment_not_larger", "max_min_containment_radius", -1))
    for key, attr, sense in checks:
        a, b = getattr(ours, attr), getattr(theirs, attr)
        out[key] = None if a is None or b is None else bool(
            sense * (a - b) >= -RTOL * max(abs(a), abs(b)) or (np.isinf(b) and sense < 0))
    return out


# --------------------------------------------------------------- peers
def earcut(geometry: GeometryLike) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """mapbox_earcut's triangulation of a polygonal geometry (anything with
    ``__geo_interface__``, or the GeoJSON-like mapping: Polygon, MultiPolygon,
    GeometryCollection, Feature, FeatureCollection), for comparisons. Each
    polygon's rings are passed to earcut as they are (closing point dropped);
    returns ``(vertices (n, 2), triangles (k, 3))`` over the concatenated rings.
    Needs ``mapbox-earcut``.

    >>> v, t = earcut({"type": "Polygon", "coordinates": [[(0, 0), (4, 0), (4, 4), (0, 4), (0, 0)]]})
    >>> v.shape, t.shape
    ((4, 2), (2, 3))
    """
    mapbox_earcut = require("mapbox_earcut", "comparing with earcut")
    verts, tris, base = [], [], 0
    for rings in _polygons(getattr(geometry, "__geo_interface__", geometry)):
        xy = [_open_ring(r) for r in rings]
        xy = [r for r in xy if len(r)]
        if not xy:
            continue
        pts = np.concatenate(xy)
        ends = np.cumsum([len(r) for r in xy]).astype(np.uint32)
        idx = np.asarray(mapbox_earcut.triangulate_float64(pts, ends), np.int64).reshape(-1, 3)
        verts.append(pts)
        tris.append(idx + base)
        base += len(pts)
    if not verts:
        raise InputShapeError("earcut needs polygonal input (Polygon or MultiPolygon rings)")
    return np.concatenate(verts), np.concatenate(tris)


def _polygons(gi: Any) -> Iterator[Any]:
    """Rings of every polygon in a GeoJSON-like mapping, polygon by polygon
    (:func:`cdt_plugin.plc.geojson_parts`, features opened); nothing for
    anything else."""
    if not (isinstance(gi, dict) and "type" in gi):
        return
    for kind, coords in geojson_parts(gi, features=True):
        if kind == "Polygon":
            yield coords
        elif kind == "MultiPolygon":
            yield from coords


def _open_ring(ring) -> np.ndarray:
    xy = np.asarray(ring, dtype=np.float64).reshape(-1, np.shape(ring)[-1] if len(ring) else 2)[:, :2]
    if len(xy) > 1 and (xy[0] == xy[-1]).all():
        xy = xy[:-1]
    return np.ascontiguousarray(xy)


# ------------------------------------------------------------ input checks
def against_arrays(against: MeshLike) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """(vertices, triangles) of a pair, a Triangulation or a trimesh-like object."""
    if isinstance(against, (tuple, list)):
        if len(against) == 2:
            return as_mesh(*against)
    elif hasattr(against, "triangles") and hasattr(against, "vertex_map"):
        return as_mesh(against.vertices, against.triangles)
    elif hasattr(against, "faces") and hasattr(against, "vertices"):
        return as_mesh(against.vertices, against.faces)
    raise InputShapeError("against must be (vertices, triangles), a Triangulation or a mesh "
                          f"with vertices and faces, got {type(against).__name__}")


def _indices_of(V, points) -> np.ndarray:
    """Index of each of ``points`` among the rows of ``V`` (exact match), -1 if absent."""
    if len(points) == 0:
        return np.empty(0, np.int64)
    both = np.concatenate([V, points])
    _, inverse = np.unique(both, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    where = np.full(inverse.max() + 1, -1, np.int64)
    where[inverse[: len(V)][::-1]] = np.arange(len(V))[::-1]   # first row of each position
    return where[inverse[len(V):]]


# ---------------------------------------------------------------- printing
def _plain(v):
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (np.floating, float)):
        return float(v) if np.isfinite(v) else str(float(v))
    if isinstance(v, np.bool_):
        return bool(v)
    return v


def _int_or_none(v) -> int | None:
    return None if v is None else int(v)


def _float_or_none(v) -> float | None:
    return None if v is None else float(v)


def _fmt(v, digits: int = 6) -> str:
    if v is None:
        return "-"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return f"{int(v):,}"
    return f"{float(v):.{digits}g}"


def _at(value, triangle) -> str:
    return _fmt(value) + ("" if triangle is None else f" (#{triangle})")


def _rows(r: Report) -> list[tuple[str, str]]:
    return [
        ("vertices: input", _fmt(r.input_vertices)),
        ("  merged duplicates", _fmt(r.merged_duplicates)),
        ("  Steiner", _fmt(r.steiner_vertices)),
        ("  in triangles", _fmt(r.vertices)),
        ("triangles", _fmt(r.triangles)),
        ("segments: input / edges", f"{_fmt(r.segments)} / {_fmt(r.segment_edges)}"),
        ("min angle (deg)", _at(r.min_angle, r.min_angle_triangle)),
        ("max angle (deg)", _at(r.max_angle, r.max_angle_triangle)),
        ("largest circumdisk radius", _at(r.max_circumradius, r.max_circumradius_triangle)),
        ("largest min-containment radius",
         _at(r.max_min_containment_radius, r.max_min_containment_triangle)),
        ("radius-edge ratio: max / mean",
         f"{_fmt(r.max_radius_edge_ratio, 4)} / {_fmt(r.mean_radius_edge_ratio, 4)}"),
        ("mean inradius", _fmt(r.mean_inradius)),
        ("degenerate triangles", _fmt(r.degenerate_triangles)),
        ("non-Delaunay non-segment edges", _fmt(r.non_delaunay_edges)),
        ("cocircular edges", _fmt(r.cocircular_edges)),
        ("unique", _fmt(r.unique)),
        ("flips", _fmt(r.flips)),
        ("time (s)", _fmt(r.seconds, 4)),
    ]


def _histogram_rows(reports) -> list[tuple[str, list[str]]]:
    counts = np.array([r.angle_counts for r in reports])
    nonzero = np.flatnonzero(counts.sum(axis=0))
    if len(nonzero) == 0:
        return []
    bins = reports[0].angle_bins
    return [(f"  {bins[i]:g}-{bins[i + 1]:g}", [_fmt(int(c)) for c in counts[:, i]])
            for i in range(nonzero[0], nonzero[-1] + 1)]


def _table(r: Report) -> str:
    reports = [r] if r.against is None else [r, r.against]
    same_bins = all(np.array_equal(x.angle_bins, r.angle_bins) for x in reports)
    columns = [dict(_rows(x)) for x in reports]
    labels = [label for label, _ in _rows(r)]
    body = [(label, [c[label] for c in columns]) for label in labels]
    if same_bins:
        body.append(("angle histogram (deg)", ["" for _ in reports]))
        body.extend(_histogram_rows(reports))
    width = max(len(label) for label, _ in body) + 2
    colw = [max(len(x.name), *(len(cells[i]) for _, cells in body)) + 2 for i, x in enumerate(reports)]
    lines = ["quality report".ljust(width) + "".join(x.name.rjust(w) for x, w in zip(reports, colw))]
    lines += [(label.ljust(width) + "".join(c.rjust(w) for c, w in zip(cells, colw))).rstrip()
              for label, cells in body]
    if r.comparison is not None:
        lines.append(_verdict(r.comparison))
    return "\n".join(lines)


def _verdict(c: dict[str, Any]) -> str:
    if not c["theorem_applies"]:
        why = ("the vertex sets differ" if not c["same_vertices"] else
               "Steiner points" if c["same_triangle_count"] else
               "different triangle counts: not a triangulation of the same domain")
        return f"Theorem 2.17 comparison: not applicable ({why})"
    parts = [("min angle not smaller", c["min_angle_not_smaller"]),
             ("largest circumdisk not larger", c["max_circumradius_not_larger"]),
             ("largest min-containment disk not larger", c["max_min_containment_not_larger"])]
    return "Theorem 2.17 (same vertices): " + "; ".join(f"{k}: {_fmt(v)}" for k, v in parts)
