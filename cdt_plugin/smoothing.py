"""Smoothing a mesh (ODT, Lloyd): the driver of :meth:`Triangulation.smooth`.

Smoothing moves the Steiner points of a mesh to improve the shape of its
triangles while keeping their sizes; it adds and removes nothing. Each
iteration is one sweep of the compiled kernels of
:mod:`cdt_plugin._core.smooth` over the vertices, then the flip algorithm
(Sec. 2.5; never across a segment, the boundary or between regions), so the
result is constrained Delaunay again (Lemma 2.14). What moves and how:

* input vertices never move; a Steiner point on a segment (or on the boundary)
  slides along it, between its neighbours there (``on_segments=False``: it
  stays); a crossing of segments stays; every other Steiner point moves
  freely inside its star;
* ``method="odt"`` (optimal Delaunay triangulation) moves a vertex to the mean
  of the circumcentres of its triangles weighted by area and density,
  ``"lloyd"`` to the centroid of its Voronoi cell (cut to its triangles)
  weighted by density;
* the density is ``1 / size**2``: ``size=None`` takes each vertex's own size,
  the mean length of its edges before smoothing (a graded mesh stays graded);
  a number is a uniform size; a callable ``size(x, y)`` over arrays is
  evaluated once per iteration at every vertex;
* a move is kept only if no triangle of the vertex's star turns over (exact
  orientation), the smallest angle of the star does not fall (with
  ``min_angle``: it may fall, but not below that bound), and the sum of the
  star's radius ratios does not fall; otherwise half and a quarter of the
  move are tried. So the mesh's smallest angle never falls (flips only raise
  it, Prop. 2.7), nor does its mean radius ratio through the moves.

``tri.stats["smoothing"]`` (made on first access) compares before and after:
the smallest angle, the mean and quantiles of the radius ratio ``2 r / R``
(1 for an equilateral triangle), their histograms, and with a size field the
ratio of each triangle's longest edge to the size at its centroid.

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4]], min_angle=25, max_area=0.1)
>>> smooth = tri.smooth("odt", 5)
>>> bool((smooth.vertices[:4] == tri.vertices[:4]).all()), smooth.is_delaunay()
(True, True)
>>> s = smooth.stats["smoothing"]
>>> s["after"]["min_angle"] >= s["before"]["min_angle"], s["after"]["mean_radius_ratio"] > s["before"]["mean_radius_ratio"]
(True, True)
"""
from __future__ import annotations

import functools
import math
import numbers
import time
from typing import Any, Callable, NamedTuple, Optional, Union

import numpy as np
from numpy.typing import NDArray

from ._core.gradation import triangle_measures
from .errors import CDTError
from .fields import ConstantSize, as_size_field, size_values
from .report import ANGLE_BINS, triangle_quality
from .validate import exact_range

__all__ = ["METHODS", "SmoothOptions", "check_smooth", "smooth", "smooth_keyword",
           "mesh_quality", "DEFAULT_ITERATIONS"]

#: The smoothing methods.
METHODS = ("odt", "lloyd")
#: Iterations when only the method is named (``triangulate(smooth="odt")``).
DEFAULT_ITERATIONS = 10
#: Histogram bins of the radius ratio.
RATIO_BINS = np.linspace(0.0, 1.0, 11)
#: Quantiles reported of the radius ratio and of the size ratio.
QUANTILES = (0.01, 0.1, 0.5, 0.9, 0.99)

SizeField = Union[None, float, Callable[[NDArray[np.float64], NDArray[np.float64]], Any]]


class SmoothOptions(NamedTuple):
    """The checked options of :func:`smooth`."""

    method: str = "odt"
    iterations: int = DEFAULT_ITERATIONS
    size: SizeField = None
    on_segments: bool = True
    min_angle: Optional[float] = None


def check_smooth(method: str = "odt", iterations: int = DEFAULT_ITERATIONS, size: SizeField = None,
                 on_segments: bool = True, min_angle: float | None = None) -> SmoothOptions:
    """The options of :func:`smooth`, checked before any work: a
    :class:`CDTError` naming the keyword and the value that is wrong.

    >>> check_smooth("lloyd", 3).method
    'lloyd'
    >>> check_smooth("laplace")
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.CDTError: method must be one of 'odt', 'lloyd', got 'laplace'
    """
    if not isinstance(method, str) or method not in METHODS:
        raise CDTError(f"method must be one of {', '.join(map(repr, METHODS))}, got {method!r}")
    if isinstance(iterations, bool) or not isinstance(iterations, numbers.Integral) or iterations < 0:
        raise CDTError(f"iterations must be a whole number >= 0, got {iterations!r}")
    if size is not None:        # the one size field type (a background mesh too)
        field = as_size_field(size)
        size = field.value if isinstance(field, ConstantSize) else field
    if not isinstance(on_segments, (bool, np.bool_)):
        raise CDTError(f"on_segments must be True or False, got {on_segments!r}")
    if min_angle is not None and (isinstance(min_angle, bool) or not isinstance(min_angle, numbers.Real)
                                  or not 0 < min_angle < 60):
        raise CDTError(f"min_angle must be a number of degrees between 0 and 60, got {min_angle!r}")
    return SmoothOptions(method, int(iterations), size, bool(on_segments),
                         None if min_angle is None else float(min_angle))


def smooth_keyword(value: Any) -> SmoothOptions | None:
    """``triangulate``'s ``smooth=``: None (no smoothing), a method name
    (:data:`DEFAULT_ITERATIONS` iterations of it) or a number of ODT
    iterations; checked before any work.

    >>> smooth_keyword(None), smooth_keyword("lloyd").iterations, smooth_keyword(3).method
    (None, 10, 'odt')
    """
    if value is None:
        return None
    if isinstance(value, str):
        return check_smooth(value)
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return check_smooth("odt", int(value))
    raise CDTError(f"smooth must be None, 'odt', 'lloyd' or a number of iterations, got {value!r}")


def smooth(tri: Any, method: str = "odt", iterations: int = DEFAULT_ITERATIONS, *,
           size: SizeField = None, on_segments: bool = True,
           min_angle: float | None = None) -> Any:
    """``tri`` (a :class:`~cdt_plugin.Triangulation`) smoothed (see the
    module's notes): a new triangulation of the same class, its vertices in the same order (input vertices where they
    were), the same segments (as vertex pairs, with their ``segment_ids``),
    regions, markers and attributes (a moved vertex's attributes interpolated
    anew as the result's ``tags`` say), triangles changed by flips;
    ``below_min_angle``: with ``min_angle``, the triangles below it (else
    none); ``stats["smoothing"]`` the comparison."""
    options = check_smooth(method, iterations, size, on_segments, min_angle)
    t0 = time.perf_counter()
    if tri.weights is not None:
        raise CDTError("smooth takes unweighted triangulations (a weighted vertex's place is "
                       "part of its power diagram)")
    from ._core import smooth as kernels     # (loaded on first use: import cdt_plugin stays fast)
    V0 = np.asarray(tri.vertices, np.float64)
    T0 = np.ascontiguousarray(tri.triangles, np.int64)
    N0 = np.ascontiguousarray(tri.neighbors, np.int64)
    n, k = len(V0), len(T0)
    sx, sy, _, shift = exact_range(V0[:, 0].copy(), V0[:, 1].copy(), None, "vertices")
    x, y = np.array(sx, np.float64), np.array(sy, np.float64)   # (the sweeps move them in place)
    store, twin, cons = kernels.smoothing_store(T0, N0, _edge_codes(tri, T0, N0), n)
    mesh = (store, twin, cons, k)
    steiner = np.zeros(n, np.bool_)
    steiner[np.asarray(tri.steiner, np.int64)] = True
    role, chain, ends = kernels.vertex_roles(store[:3 * k], twin, cons, n, steiner, options.on_segments)
    moved, flips = _sweeps(kernels, mesh, x, y, shift, (role, chain, ends), options)
    T, N, C = kernels.smoothed_arrays(store[:3 * k], twin, cons)
    V = np.column_stack([x, y]) * 2.0 ** -shift if shift else np.column_stack([x, y])
    done = {"method": options.method, "iterations": options.iterations, "sweeps": len(moved),
            "moved": moved, "flips": flips, "free_vertices": int((role == kernels.FREE).sum()),
            "sliding_vertices": int((role == kernels.SLIDES).sum()),
            "seconds": time.perf_counter() - t0}
    below = np.empty(0, np.int64)
    if options.min_angle is not None:
        below = np.flatnonzero(triangle_quality(V, T)["angles"].min(axis=1) < options.min_angle)
    out = type(tri)(V, T, N, tri.vertex_map, functools.partial(
                        _stats, dict(tri.stats), done, V0, T0, options.size), constrained=C,
                    regions=_per_slot(tri.regions), segments=tri.segments,
                    segment_ids=tri.segment_ids, steiner=tri.steiner, below_min_angle=below,
                    region_attributes=_per_slot(tri.region_attributes))
    out.tags = tri.tags
    return out


def _sweeps(kernels: Any, mesh: tuple, x: NDArray[np.float64], y: NDArray[np.float64], shift: int,
            roles: tuple, options: SmoothOptions) -> tuple[list[int], int]:
    """The iterations: a sweep, then the flips, until ``options.iterations`` or
    a sweep that moves nothing. ``mesh``: the store ``(tri, twin, cons, k)``
    (``k`` triangles, then the ghosts), ``x, y`` the coordinates times
    ``2**shift`` (moved in place), ``roles`` what
    :func:`cdt_plugin._core.smooth.vertex_roles` says. Returns the vertices
    moved in each sweep and the number of flips."""
    store, twin, cons, k = mesh
    role, chain, ends = roles
    n = len(x)
    method = kernels.ODT if options.method == "odt" else kernels.LLOYD
    floor2 = math.inf if options.min_angle is None else math.sin(math.radians(options.min_angle)) ** 2
    field = options.size
    h = kernels.mean_edge_lengths(store[:3 * k], twin, x, y) if field is None else np.empty(0)
    moved: list[int] = []
    flips = 0
    active = role != kernels.FIXED        # (then: the vertices whose stars changed)
    went = np.zeros(n, np.bool_)          # the vertices that moved in a sweep
    for _ in range(options.iterations if active.any() and k else 0):
        if callable(field):
            h = np.ascontiguousarray(size_values(field, x * 2.0 ** -shift, y * 2.0 ** -shift))
        count = int(kernels.smooth_sweep(store[:3 * k], x, y, h, role, chain, ends, method, floor2,
                                         active, went))
        if not moved:     # the first flips test every edge: the mesh may not be constrained Delaunay
            went[:] = True
        moved.append(count)
        done = int(kernels.restore_delaunay(store, twin, cons, x, y, n, k, went, active))
        if done < 0:
            raise CDTError("internal error: the flips after a smoothing sweep did not end; "
                           "please report this mesh")
        flips += done
        if count == 0:
            break
    return moved, flips


def _edge_codes(tri: Any, T: NDArray[np.int64], N: NDArray[np.int64]) -> NDArray[np.int32]:
    """The label of each edge (row ``t``, opposite corner ``j``) for
    :func:`cdt_plugin._core.smooth.smoothing_store`: a segment piece's, the
    boundary's, between two regions, or none (flippable)."""
    from ._core.smooth import BOUNDARY_EDGE, REGION_EDGE, SEGMENT_BASE
    code = np.zeros(T.shape, np.int32)
    regions = np.asarray(tri.regions, np.int64)
    across = np.where(N >= 0, regions[np.maximum(N, 0)], regions[:, None])
    code[across != regions[:, None]] = REGION_EDGE
    code[N < 0] = BOUNDARY_EDGE
    C = np.asarray(tri.constrained, bool)
    if C.any():
        pieces = np.asarray(tri.segments, np.int64).reshape(-1, 2)
        n = len(tri.vertices)
        keys = np.minimum(pieces[:, 0], pieces[:, 1]) * n + np.maximum(pieces[:, 0], pieces[:, 1])
        order = np.argsort(keys)
        t, j = np.nonzero(C)
        a, b = T[t, (j + 1) % 3], T[t, (j + 2) % 3]
        at = np.minimum(np.searchsorted(keys[order], np.minimum(a, b) * n + np.maximum(a, b)),
                        len(keys) - 1)
        code[t, j] = SEGMENT_BASE + np.asarray(tri.segment_ids, np.int64)[order[at]] + 1
    return code


def _per_slot(values: NDArray[Any] | None) -> NDArray[Any] | None:
    """A per-triangle array of the result: flips keep each triangle's slot and
    never cross between regions, so the same values (a copy)."""
    return None if values is None else np.array(values)


def mesh_quality(V: NDArray[np.float64], T: NDArray[np.int64], size: SizeField = None) -> dict[str, Any]:
    """The figures ``stats["smoothing"]`` compares: smallest angle (degrees),
    mean and quantiles of the radius ratio ``2 r / R``, the histograms of
    angles (:data:`cdt_plugin.report.ANGLE_BINS`) and radius ratios, and with
    a size field the quantiles of longest edge / size at the centroid.

    >>> q = mesh_quality(np.array([[0, 0], [1, 0], [0.5, 3 ** 0.5 / 2]]), np.array([[0, 1, 2]]))
    >>> round(q["min_angle"], 9), round(q["mean_radius_ratio"], 9)
    (60.0, 1.0)
    """
    if len(T) == 0:
        return {"triangles": 0}
    q = triangle_quality(V, T)
    ratio = np.where(np.isfinite(q["circumradius"]), 2.0 * q["inradius"] / q["circumradius"], 0.0)
    out: dict[str, Any] = {
        "triangles": len(T), "min_angle": float(q["angles"].min()),
        "mean_radius_ratio": float(ratio.mean()), "min_radius_ratio": float(ratio.min()),
        "radius_ratio_quantiles": dict(zip(QUANTILES, np.quantile(ratio, QUANTILES).tolist())),
        "radius_ratio_histogram": {"bins": RATIO_BINS.tolist(),
                                   "counts": np.histogram(ratio, RATIO_BINS)[0].tolist()},
        "angle_histogram": {"bins": ANGLE_BINS.tolist(),
                            "counts": np.histogram(q["angles"].ravel(), ANGLE_BINS)[0].tolist()}}
    if size is not None:
        cx, cy, _, longest = triangle_measures(np.ascontiguousarray(V, np.float64),
                                               np.ascontiguousarray(T, np.int64))
        h = size_values(size, cx, cy) if callable(size) else np.full(len(T), float(size))
        r = longest / h
        out["size_ratio_quantiles"] = dict(zip(QUANTILES, np.quantile(r, QUANTILES).tolist()))
    return out


def _stats(stats: dict[str, Any], done: dict[str, Any], V0: NDArray[np.float64], T0: NDArray[np.int64],
           size: SizeField, tri: Any) -> dict[str, Any]:
    """The result's stats: ``stats`` (the mesh's) with ``smoothing``, ``done``
    and the figures before and after (made on first access)."""
    stats["smoothing"] = {**done, "before": mesh_quality(V0, T0, size),
                          "after": mesh_quality(tri.vertices, tri.triangles, size)}
    return stats
