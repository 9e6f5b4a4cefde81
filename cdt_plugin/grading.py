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
bound makes triangles of about half the bound and longest edges about 1.3
times the equilateral edge of their area, so the bound that puts the median
of longest edge / size near 1 is larger. An area field is a strict bound, as
Triangle's ``-a``.

It ends: a triangle that breaks a bound is refined to at most its bound (and
one whose longest edge alone is too long, to half its area), so every round
shrinks what it rejects; a field that goes to zero meets the double-precision
limit (:func:`check_splittable`) or the Steiner cap, both
:class:`~cdt_plugin.errors.RefinementLimitError` with the mesh so far.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.pipeline import AREA_STEINER_CAP
from .errors import CDTError, RefinementLimitError
from ._core.gradation import triangle_measures
from .fields import EQUILATERAL, ConstantSize, Sizing, check_sizing, graded_sizes, size_values
from .options import MeshOptions

#: Area bound per squared size (measured: the median of longest edge / size near 1).
SIZE_AREA = EQUILATERAL
#: A triangle whose longest edge is longer than this many times the size is refined.
EDGE_RATIO = 1.5
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
        try:
            tri = tri.refine(max_area=np.where(np.isfinite(bound), bound, 0.0),
                             max_steiner=cap - added, **refine_options)
        except RefinementLimitError as exc:
            raise RefinementLimitError(
                f"the size field still asks to refine triangles after max_steiner={cap} Steiner "
                f"points ({rounds + 1} rounds); raise max_steiner, or floor the field (min_size=) "
                "(the mesh so far is in this error's .triangulation)",
                triangulation=exc.triangulation) from exc
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
    h = triangle_sizes(tri, sizing, cx, cy)
    bound = SIZE_AREA * h * h
    too_long = longest > EDGE_RATIO * h
    if sizing.area is not None:
        area = size_values(sizing.area, cx, cy, name="max_area")
        if sizing.growth is not None:     # graded as the size of an equilateral triangle
            h_area = np.sqrt(area / EQUILATERAL)
            area = EQUILATERAL * graded_sizes(tri.vertices, tri.triangles, None, h_area, sizing.growth) ** 2
        bound = np.fmin(bound, area)
    return bound, too_long


def triangle_sizes(tri: Any, sizing: Sizing, cx: NDArray[np.float64] | None = None,
                   cy: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """The size field of ``sizing`` at each triangle's centroid (``cx, cy``
    when known), floored at its ``min_size`` and limited by its ``growth``
    (inf without a size field)."""
    V, T = tri.vertices, tri.triangles
    if sizing.size is None:
        return np.full(len(T), np.inf)
    if cx is None or cy is None:
        cx, cy = triangle_measures(V, T)[:2]
    h = size_values(sizing.size, cx, cy, sizing.min_size)
    if sizing.growth is None or isinstance(sizing.size, ConstantSize):
        return h
    at_vertices = size_values(sizing.size, V[:, 0], V[:, 1], sizing.min_size)
    return graded_sizes(V, T, at_vertices, h, sizing.growth)


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
            f"{what} rejects triangle {t} {corners(V, T, t)} of area {areas[t]!r}, too small to "
            f"split in double precision ({remedy})", triangulation=tri)


def corners(V: NDArray[np.float64], T: NDArray[np.int64], t: int) -> str:
    """Triangle ``t``'s corners, for a message."""
    return "(" + ", ".join(f"({float(V[i, 0])!r}, {float(V[i, 1])!r})" for i in T[t]) + ")"
