"""A user's size test over the triangles (Triangle's ``-u``), evaluated vectorised.

Triangle's ``-u`` calls a C function, ``triunsuitable(org, dest, apex, area)``,
compiled into the program, once per triangle while it refines. Here the test is a
Python callable over arrays, ``suitable(org, dest, apex, area)`` with ``org``,
``dest``, ``apex`` the corners (k, 2) of every triangle (counter-clockwise) and
``area`` (k,) their areas, returning which are good enough (k booleans). It is
called once per round on the whole mesh, never once per triangle from compiled
code: :func:`refine_until_suitable` refines the triangles it rejects (each to at
most half its area, with the mesh's other bounds kept) through
:meth:`~cdt_plugin.Triangulation.refine`, which goes on from where the last
round was, until every triangle passes.

It ends: each round at least halves every rejected triangle, and a triangle
too small to split in double precision, or more Steiner points than the cap,
raise :class:`~cdt_plugin.errors.RefinementLimitError` naming it, with the mesh
so far.
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from .errors import CDTError, RefinementLimitError
from .grading import check_progress, check_splittable, corners
from .refining import triangle_areas
from .triangulation import Triangulation

#: ``suitable(org, dest, apex, area) -> (k,) bool``: which triangles are good enough.
SizeTest = Callable[[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                     NDArray[np.float64]], Any]

#: Steiner points the rounds may add without ``max_steiner``: per input vertex, plus this
#: many (the default cap of :func:`cdt_plugin.triangulate`'s refinement).
STEINER_PER_VERTEX, STEINER_BASE = 100, 100_000


def check_size_test(suitable: object) -> None:
    """A :class:`CDTError` unless ``suitable`` is None or callable (checked before
    any work starts)."""
    if suitable is not None and not callable(suitable):
        raise CDTError(f"suitable must be a callable suitable(org, dest, apex, area) -> "
                       f"booleans, got {suitable!r} ({type(suitable).__name__})")


def refine_until_suitable(tri: Triangulation, suitable: SizeTest, *,
                          max_area: float | None = None, max_steiner: int | None = None,
                          **refine_options: Any) -> Triangulation:
    """Refine ``tri`` until ``suitable`` accepts every triangle (module notes).

    ``refine_options`` (``min_angle``, ``conforming_delaunay``, ``split_boundary``,
    ``split_segments``) go to every round of :meth:`Triangulation.refine`, as
    does ``max_area`` (a bound for every triangle); ``max_steiner`` caps the
    Steiner points of all rounds together. ``stats["size_test_rounds"]``
    counts the rounds.

    >>> import cdt_plugin
    >>> from cdt_plugin.sizing import refine_until_suitable, triangle_areas
    >>> tri = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4]])
    >>> small_near_origin = lambda org, dest, apex, area: area <= 0.01 + 0.1 * (org ** 2).sum(1)
    >>> fine = refine_until_suitable(tri, small_near_origin, min_angle=20)
    >>> V, T = fine.vertices, fine.triangles
    >>> bool(small_near_origin(V[T[:, 0]], V[T[:, 1]], V[T[:, 2]], triangle_areas(V, T)).all())
    True
    """
    n0 = len(tri.vertices)
    cap = max_steiner if max_steiner is not None else STEINER_PER_VERTEX * n0 + STEINER_BASE
    base = np.nan if max_area is None else float(max_area)
    rounds = 0
    while True:
        V, T = tri.vertices, tri.triangles
        areas = triangle_areas(V, T)
        ok = _verdict(suitable(V[T[:, 0]], V[T[:, 1]], V[T[:, 2]], areas), len(T))
        if ok.all():
            tri.stats["size_test_rounds"] = rounds
            return tri
        bad = np.flatnonzero(~ok)
        check_splittable(tri, bad, areas, "the size test", "the test must accept every "
                         "triangle of some size, as Triangle's triunsuitable must")
        added = len(tri.vertices) - n0
        if added >= cap:
            raise RefinementLimitError(
                f"the size test still rejects {len(bad)} triangles after {added} Steiner points "
                f"(max_steiner={cap}); raise max_steiner or relax the test (triangle {int(bad[0])} "
                f"{corners(V, T, int(bad[0]))})", triangulation=tri)
        bounds = np.full(len(T), base)
        bounds[bad] = np.fmin(areas[bad] / 2.0, base)
        try:
            refined = tri.refine(max_area=bounds, max_steiner=cap - added, **refine_options)
        except RefinementLimitError as exc:
            raise RefinementLimitError(
                f"the size test still rejects triangles after max_steiner={cap} Steiner points "
                f"({rounds + 1} rounds); raise max_steiner or relax the test (the mesh so far is "
                "in this error's .triangulation)", triangulation=exc.triangulation) from exc
        check_progress(refined, V, T, bad, areas, "the size test", "the test must accept every "
                       "triangle of some size, as Triangle's triunsuitable must")
        tri = refined
        rounds += 1


def _verdict(answer: Any, k: int) -> NDArray[np.bool_]:
    """The size test's answer as (k,) booleans, or the error saying what it gave."""
    ok = np.asarray(answer)
    if ok.shape == () and k == 1:
        ok = ok.reshape(1)
    if ok.shape != (k,) or ok.dtype.kind not in "bui":
        raise CDTError(f"suitable must return one boolean per triangle, ({k},), got "
                       f"{ok.dtype} {ok.shape}")
    return ok.astype(bool)
