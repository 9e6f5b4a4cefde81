"""Refining to a size field: rounds of per-triangle area bounds.

A size field (:mod:`cdt_plugin.fields`) is evaluated where the mesh is, not
where refinement puts its points: compiled refinement never calls back into
Python. So :func:`refine_to_size` works in rounds. Each round evaluates the
field (and the area field of a callable ``max_area``) once, vectorised, at
every triangle's centroid (with ``growth``: at the vertices too, limited over
the mesh, :func:`cdt_plugin.fields.graded_sizes`), turns it into one area
bound per triangle, and refines the triangles that break it through
:meth:`~cdt_plugin.Triangulation.refine` with those bounds (which goes on
from the store of the round before, and gives each new triangle the bound of
the triangle that holds its centroid), until no triangle breaks it.

A size ``h`` at a centroid asks for an area of at most ``SIZE_AREA * h**2``
and a longest edge of at most ``EDGE_RATIO * h``. ``SIZE_AREA`` is measured
(not the equilateral triangle's ``0.433``): a Delaunay refinement to an area
bound makes triangles of about 0.6 of the bound, of various shapes, so the
bound that puts the median of longest edge / size near 1 is larger. Each
round takes a triangle at most ``STEP`` times smaller, so that large
triangles are not refined all at once by the size at their centroid. An area
field is a strict bound, as Triangle's ``-a``.

It ends: a triangle that breaks a bound is refined to at most its bound (and
one whose longest edge alone is too long, to half its area), so every round
shrinks what it rejects; a field that goes to zero meets the double-precision
limit (:func:`check_splittable`, or a round that adds no point: refinement
leaves alone the edges too short to split) or the Steiner cap, all three
:class:`~cdt_plugin.errors.RefinementLimitError` with the mesh so far.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.pipeline import AREA_STEINER_CAP
from .errors import CDTError, RefinementLimitError
from ._core.gradation import triangle_measures
from .fields import EQUILATERAL, Sizing, check_sizing, graded_sizes, size_values, triangle_sizes
from .options import MeshOptions

#: Area bound per squared size, measured: with the equilateral triangle's 0.433 the median
#: of longest edge / size was 0.94 on a constant field (0.86 on a point source), with 0.49
#: it is 1.00 (0.99-1.01), the largest ratio 1.46-1.50 after the longest-edge check.
SIZE_AREA = 0.49
#: A triangle whose longest edge is longer than this many times the size is refined.
EDGE_RATIO = 1.5
#: A round refines a triangle to at most 1/STEP of its area, so that the field is seen
#: anew (on the smaller triangles) before the last step: its children take the bound of
#: the triangle that holds their centroid, and a large triangle's bound is its centroid's
#: size, too small for its far side. On a point source (42,000 triangles, min_angle 30)
#: STEP 16 took 6 rounds against 4 in one step, with 42,000 triangles against 50,000, the
#: 5% quantile of longest edge / size 0.74 against 0.45, in 0.65x the time (STEP 4: 11
#: rounds, 2x the time; 64: 5 rounds, 0.37 the 1% quantile).
STEP = 16.0
#: Steiner points the rounds may add without ``max_steiner``: per input vertex, plus
#: this many, plus 8 per expected triangle (at most AREA_STEINER_CAP), as triangulate's.
STEINER_PER_VERTEX, STEINER_BASE = 100, 100_000


def refine_to_size(tri: Any, sizing: Sizing, *, max_area: float | None = None,
                   max_steiner: int | None = None, first: bool = False,
                   **refine_options: Any) -> Any:
    """Refine ``tri`` (a :class:`~cdt_plugin.Triangulation`) until every
    triangle meets ``sizing`` (module notes) and ``max_area`` (a number);
    ``refine_options`` (``min_angle``, ``conforming_delaunay``,
    ``split_boundary``, ``split_segments``) go to every round, ``max_steiner``
    caps the Steiner points of all rounds together, ``first`` refines once
    even when the sizes are met (for the other options).
    ``stats["size_rounds"]`` counts the rounds.

    >>> import cdt_plugin
    >>> from cdt_plugin.fields import check_sizing
    >>> tri = cdt_plugin.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> fine = refine_to_size(tri, check_sizing(size=lambda x, y: 0.05 + 0.2 * x), min_angle=25)
    >>> fine.stats["size_rounds"] > 0, len(fine.triangles) > 100
    (True, True)
    """
    n0 = len(tri.vertices) - len(tri.steiner)
    base = np.inf if max_area is None else float(max_area)
    expected = 0.0
    rounds = 0
    while True:
        V, T = tri.vertices, tri.triangles
        cx, cy, areas, longest = triangle_measures(V, T)
        bound, too_long = round_bounds(tri, sizing, cx, cy, longest)
        bound = np.fmin(bound, base)
        too_large = areas > bound
        bad = too_large | too_long
        if not bad.any() and not (first and rounds == 0):
            tri.stats["size_rounds"] = rounds
            return tri
        bad_ids = np.flatnonzero(bad)
        check_splittable(tri, bad_ids, areas, "the size field",
                         "a field that vanishes needs a floor: min_size=")
        with np.errstate(over="ignore", divide="ignore"):
            expected = max(expected, float((areas / bound).sum()))
        cap = max_steiner
        if cap is None:
            cap = STEINER_PER_VERTEX * n0 + STEINER_BASE + int(min(8 * expected, AREA_STEINER_CAP))
        added = len(tri.steiner)
        if added >= cap and len(bad_ids):
            raise RefinementLimitError(
                f"the size field still asks to refine {len(bad_ids)} triangles after {added} "
                f"Steiner points (max_steiner={cap}); raise max_steiner, or floor the field "
                f"(min_size=) (triangle {int(bad_ids[0])} {corners(V, T, int(bad_ids[0]))})",
                triangulation=tri)
        edge_only = too_long & ~too_large
        bound[edge_only] = areas[edge_only] / 2.0
        bound = np.maximum(bound, areas / STEP)     # (the field seen anew before the last step)
        try:
            refined = tri.refine(max_area=np.where(np.isfinite(bound), bound, 0.0),
                                 max_steiner=cap - added, **refine_options)
        except RefinementLimitError as exc:
            raise RefinementLimitError(
                f"the size field still asks to refine triangles after max_steiner={cap} Steiner "
                f"points ({rounds + 1} rounds); raise max_steiner, or floor the field (min_size=) "
                "(the mesh so far is in this error's .triangulation)",
                triangulation=exc.triangulation) from exc
        check_progress(refined, V, T, bad_ids, areas, "the size field",
                       "a field that vanishes needs a floor: min_size=")
        tri = refined
        rounds += 1


def refine_sized(tri: Any, *, max_area: Any, max_steiner: int | None, size: Any,
                 growth: float | None, min_size: float | None, **options: Any) -> Any:
    """:meth:`Triangulation.refine <cdt_plugin.Triangulation.refine>` with a
    size field: every keyword checked, then :func:`refine_to_size`."""
    area = None if callable(max_area) else max_area
    if area is not None and np.ndim(area) > 0:
        raise CDTError("max_area per triangle (an array) does not combine with a size field: "
                       "give max_area as a number or a callable f(x, y) -> areas")
    MeshOptions.check(max_area=area, max_steiner=max_steiner, **options)
    sizing = check_sizing(size, max_area, growth, min_size)
    assert sizing is not None
    return refine_to_size(tri, sizing, max_area=area, max_steiner=max_steiner, first=True, **options)


def round_bounds(tri: Any, sizing: Sizing, cx: NDArray[np.float64], cy: NDArray[np.float64],
                 longest: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The area bound of each triangle of ``tri`` (centroids ``cx, cy``,
    longest edges ``longest``; inf: no bound) and whether its longest edge is
    too long for the size at its centroid."""
    h = np.full(len(cx), np.inf)
    if sizing.size is not None:
        h = triangle_sizes(tri.vertices, tri.triangles, sizing.size, sizing.growth, sizing.min_size,
                           (cx, cy))
    bound = SIZE_AREA * h * h
    too_long = longest > EDGE_RATIO * h
    if sizing.area is not None:
        area = size_values(sizing.area, cx, cy, name="max_area")
        if sizing.growth is not None:     # graded as the size of an equilateral triangle
            h_area = np.sqrt(area / EQUILATERAL)
            area = EQUILATERAL * graded_sizes(tri.vertices, tri.triangles, None, h_area, sizing.growth) ** 2
        bound = np.fmin(bound, area)
    return bound, too_long


def check_splittable(tri: Any, bad: NDArray[np.int64], areas: NDArray[np.float64], what: str,
                     remedy: str) -> None:
    """Raise :class:`~cdt_plugin.errors.RefinementLimitError` if a triangle
    that ``what`` rejects (``bad``) is too small to split in double precision
    (its area within a few rounding units of its corners' magnitude squared),
    saying the ``remedy``."""
    V, T = tri.vertices, tri.triangles
    scale = np.abs(V[T[bad]]).max(axis=(1, 2))
    floor = (64 * np.finfo(np.float64).eps * np.maximum(scale, np.finfo(np.float64).tiny)) ** 2
    tiny = bad[areas[bad] <= floor]
    if len(tiny):
        t = int(tiny[0])
        raise RefinementLimitError(
            f"{what} rejects triangle {t} {corners(V, T, t)} of area {float(areas[t])!r}, too small to "
            f"split in double precision ({remedy})", triangulation=tri)


def check_progress(refined: Any, V: NDArray[np.float64], T: NDArray[np.int64],
                   bad: NDArray[np.int64], areas: NDArray[np.float64], what: str, remedy: str) -> None:
    """Raise :class:`~cdt_plugin.errors.RefinementLimitError` if a round that
    asked to refine the triangles ``bad`` of the mesh ``V, T`` added no point
    (``refined``): refinement leaves alone the edges too short to split, and
    the rounds would go on for ever."""
    if len(refined.vertices) == len(V) and len(bad):
        t = int(bad[0])
        raise RefinementLimitError(
            f"{what} asks to refine {len(bad)} triangles that refinement cannot split further, "
            f"at the limit of double precision (triangle {t} {corners(V, T, t)}, area "
            f"{float(areas[t])!r}); {remedy}", triangulation=refined)


def corners(V: NDArray[np.float64], T: NDArray[np.int64], t: int) -> str:
    """Triangle ``t``'s corners, for a message."""
    return "(" + ", ".join(f"({float(V[i, 0])!r}, {float(V[i, 1])!r})" for i in T[t]) + ")"
