"""The options of a constrained Delaunay triangulation, checked once: :class:`MeshOptions`.

:func:`cdt_plugin.triangulate` checks its keywords into a :class:`MeshOptions`
(:meth:`MeshOptions.check`) before any work starts; the batch path
(:func:`cdt_plugin.batch.triangulate_rings`), the command line (through
``triangulate``'s keywords) and the compile command pass that one record down
unchanged. The compiled route reads it as a
:class:`cdt_plugin._core.options.RouteOptions` (:meth:`MeshOptions.route`).

>>> from cdt_plugin.options import MeshOptions
>>> options = MeshOptions.check(min_angle=30)
>>> options.algorithm, options.refines, options.route().refinement.min_angle
('divide', True, 30.0)
"""
from __future__ import annotations

import functools
import numbers
import warnings
from typing import NamedTuple

import numpy as np

from ._core.construct import ALGORITHM_CODES
from ._core.options import RefineOptions, RouteOptions, plain
from .errors import CDTError, RefinementRangeError, RefinementRangeWarning

ALGORITHMS = ("auto", "divide", "incremental", "flip")
INTERSECTIONS = ("raise", "split")
#: The largest ``min_angle`` (degrees) accepted without a :class:`RefinementRangeWarning`.
#: Delaunay refinement is proven to finish up to about 20.7 degrees (Ruppert's bound,
#: ``arcsin(1 / (2 sqrt 2))``), and Triangle's documentation reports it finishes in
#: practice up to about 33.8 degrees; above it, it may run until ``max_steiner``.
TERMINATING_MIN_ANGLE = 34.0
#: ``min_angle`` must be below this: no triangle's smallest angle exceeds 60 degrees,
#: and only an equilateral triangle (which floating point cannot make) reaches it.
IMPOSSIBLE_MIN_ANGLE = 60.0


class MeshOptions(NamedTuple):
    """:func:`cdt_plugin.triangulate`'s options, checked: build it with
    :meth:`check` (the fields are those keywords; ``algorithm`` is resolved,
    ``"auto"`` never appears). Immutable; a named tuple, as cheap to make as
    the small calls it serves need."""

    intersections: str = "raise"
    algorithm: str = "divide"
    keep_hull: bool = False
    min_angle: float | None = None
    max_area: float | None = None
    conforming_delaunay: bool = False
    split_boundary: bool = True
    max_steiner: int | None = None
    split_segments: bool = True
    merge_distance: float | None = None

    @classmethod
    def check(cls, *, intersections: str = "raise", algorithm: str = "auto",
              keep_hull: bool = False, min_angle: float | None = None,
              max_area: float | None = None, conforming_delaunay: bool = False,
              split_boundary: bool = True, max_steiner: int | None = None,
              split_segments: bool = True,
              merge_distance: float | None = None) -> MeshOptions:
        """The options of :func:`cdt_plugin.triangulate`'s keywords, or the
        :class:`CDTError` naming the first one that is wrong. A ``min_angle``
        above :data:`TERMINATING_MIN_ANGLE` gives a :class:`RefinementRangeWarning`;
        one not below :data:`IMPOSSIBLE_MIN_ANGLE` raises :class:`RefinementRangeError`.
        ``merge_distance`` 0 is stored as None (exact duplicates only, the default)."""
        if intersections not in INTERSECTIONS:
            raise CDTError(f"intersections must be one of {INTERSECTIONS}, got {intersections!r}")
        algorithm = resolve_algorithm(algorithm, False)
        if min_angle is not None:
            check_min_angle(min_angle)
        if max_area is not None and not (np.isfinite(_real(max_area, "max_area")) and max_area > 0):
            raise CDTError(f"max_area must be a positive number, got {max_area!r}")
        if max_steiner is not None and not (np.isfinite(_real(max_steiner, "max_steiner"))
                                            and max_steiner >= 0 and max_steiner == int(max_steiner)):
            raise CDTError(f"max_steiner must be a whole number >= 0, got {max_steiner!r}")
        if merge_distance is not None and not (np.isfinite(_real(merge_distance, "merge_distance"))
                                               and merge_distance >= 0):
            raise CDTError(f"merge_distance must be a finite number >= 0, got {merge_distance!r}")
        return cls(intersections, algorithm, bool(keep_hull),
                   None if min_angle is None else float(min_angle),
                   None if max_area is None else float(max_area), bool(conforming_delaunay),
                   bool(split_boundary), None if max_steiner is None else int(max_steiner),
                   bool(split_segments), float(merge_distance) if merge_distance else None)

    @property
    def split(self) -> bool:
        """Whether crossing segments are split (``intersections="split"``)."""
        return self.intersections == "split"

    @property
    def steiner_cap(self) -> int:
        """``max_steiner`` as the compiled route takes it (-1: the default cap)."""
        return -1 if self.max_steiner is None else self.max_steiner

    @property
    def refines(self) -> bool:
        """Whether the options ask for Delaunay refinement (a region seed's
        area bound may ask for it too: :meth:`route`'s ``refine``)."""
        return bool(self.min_angle or self.max_area is not None or self.conforming_delaunay)

    def route(self, *, use_seeds: bool = False, refine: bool | None = None) -> RouteOptions:
        """The options as the compiled route reads them, for an input with
        (``use_seeds``) or without hole or region seeds; ``refine`` (default:
        :attr:`refines`) runs refinement."""
        return RouteOptions(
            algorithm=ALGORITHM_CODES[self.algorithm], split=self.split, keep_hull=self.keep_hull,
            use_seeds=bool(use_seeds),
            max_steiner=self.steiner_cap,
            refine=self.refines if refine is None else bool(refine),
            refinement=RefineOptions(min_angle=self.min_angle or 0.0, max_area=self.max_area or 0.0,
                                     conforming=self.conforming_delaunay,
                                     split_boundary=self.split_boundary,
                                     split_segments=self.split_segments))

    def route_args(self, *, use_seeds: bool = False, refine: bool | None = None) -> tuple:
        """:meth:`route` as a call of the compiled route from Python passes it
        (:func:`cdt_plugin._core.options.plain`)."""
        return _route_args(self, bool(use_seeds), self.refines if refine is None else bool(refine))


# (kept: making the named tuples anew was 1.9 us of a square's 23 us triangulate)
@functools.lru_cache(maxsize=64)
def _route_args(options: MeshOptions, use_seeds: bool, refine: bool) -> tuple:
    return plain(options.route(use_seeds=use_seeds, refine=refine))


@functools.lru_cache(maxsize=64)
def route_plan(options: MeshOptions, use_seeds: bool, seeds_refine: bool) -> tuple[bool, tuple]:
    """``(refine, route_args)`` of a call of the compiled route: whether it
    refines (the options ask for it, or ``seeds_refine``: a region seed's area
    bound does) and :meth:`MeshOptions.route_args` for an input with
    (``use_seeds``) or without hole or region seeds. Cached: a small call makes
    no Python call for it (cProfile counted four before)."""
    refine = options.refines or seeds_refine
    return refine, _route_args(options, use_seeds, refine)


@functools.lru_cache(maxsize=256, typed=True)
def checked_options(intersections: str, algorithm: str, keep_hull: bool, min_angle: float | None,
                    max_area: float | None, conforming_delaunay: bool, split_boundary: bool,
                    max_steiner: int | None, split_segments: bool = True,
                    merge_distance: float | None = None) -> MeshOptions:
    """:meth:`MeshOptions.check` of :func:`cdt_plugin.triangulate`'s keywords,
    by position, cached: the checks run once per set of values (``typed``:
    ``True`` is not taken for ``1``, nor ``1`` for ``1.0``; an error is not
    cached). Unhashable values, and a ``min_angle`` whose check warns (so that
    every call warns, not the first only), raise :class:`TypeError`: call
    :meth:`MeshOptions.check`, which names them or warns."""
    if min_angle is not None and min_angle > TERMINATING_MIN_ANGLE:
        raise TypeError("not cached: the check of this min_angle warns")
    return MeshOptions.check(intersections=intersections, algorithm=algorithm, keep_hull=keep_hull,
                             min_angle=min_angle, max_area=max_area,
                             conforming_delaunay=conforming_delaunay,
                             split_boundary=split_boundary, max_steiner=max_steiner,
                             split_segments=split_segments, merge_distance=merge_distance)


def check_min_angle(min_angle: object) -> None:
    """Raise :class:`RefinementRangeError` for a ``min_angle`` no triangle can
    meet (or :class:`CDTError` for one that is not a number), and warn
    (:class:`RefinementRangeWarning`) above the range where refinement is known
    to finish."""
    angle = _real(min_angle, "min_angle")
    if not (np.isfinite(angle) and 0 <= angle < IMPOSSIBLE_MIN_ANGLE):
        why = (f": no triangle has a smallest angle of {IMPOSSIBLE_MIN_ANGLE:g} degrees or more "
               f"(refinement is proven to finish up to 20.7, and finishes in practice up to about "
               f"{TERMINATING_MIN_ANGLE:g})" if angle >= IMPOSSIBLE_MIN_ANGLE else "")
        raise RefinementRangeError(
            f"min_angle must be in [0, {IMPOSSIBLE_MIN_ANGLE:g}) degrees, got {min_angle!r}{why}")
    if angle > TERMINATING_MIN_ANGLE:
        warnings.warn(
            f"min_angle={min_angle!r} is above the range where Delaunay refinement is known to "
            f"finish (proven up to 20.7 degrees, in practice up to about {TERMINATING_MIN_ANGLE:g}): "
            "it may add Steiner points until max_steiner and raise RefinementLimitError",
            RefinementRangeWarning, stacklevel=4)


def resolve_algorithm(algorithm: str, weighted: bool) -> str:
    """The route ``"auto"`` stands for: divide and conquer, or incremental
    insertion for weighted points (which divide and conquer does not take)."""
    if algorithm not in ALGORITHMS:
        raise CDTError(f"algorithm must be one of {ALGORITHMS}, got {algorithm!r}")
    if weighted and algorithm == "flip":
        raise CDTError("algorithm='flip' is for unweighted points: the flip algorithm can get "
                       "stuck on weighted points (Sec. 2.8); use algorithm='incremental'")
    if weighted and algorithm == "divide":
        raise CDTError("algorithm='divide' is for unweighted points; use algorithm='incremental' "
                       "for weighted Delaunay")
    if algorithm == "auto":
        return "incremental" if weighted else "divide"
    return algorithm


def _real(value: object, name: str) -> float:
    """``value`` as a float if it is a real number (not a bool, not a string),
    else a :class:`CDTError` naming the option."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise CDTError(f"{name} must be a number, got {value!r} ({type(value).__name__})")
    return float(value)
