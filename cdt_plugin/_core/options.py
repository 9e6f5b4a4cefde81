"""The options of the constrained Delaunay route as the compiled kernels read them.

:class:`RouteOptions` (with its :class:`RefineOptions`) is a named tuple of
scalars: kernels read it by field (``options.split``,
``options.refinement.min_angle``). :class:`cdt_plugin.options.MeshOptions`
checks :func:`cdt_plugin.triangulate`'s keywords and builds it.

A call from Python passes it as a plain tuple (:func:`plain`) and the entry
names it again (:func:`named`): numba types a plain tuple of scalars in its C
dispatcher, a named tuple in Python, which cost about 0.9 us per named tuple
(1.7 us nested) on a call of about 23 us (a square's ``triangulate``).
"""
from __future__ import annotations

from typing import NamedTuple

from numba import typeof

from .construct import DIVIDE
from .jit import kernel


class RefineOptions(NamedTuple):
    """What Delaunay refinement is asked for (:mod:`.refine`)."""

    min_angle: float = 0.0          # degrees; 0: no angle bound
    max_area: float = 0.0           # 0: no global area bound (region seeds may bound theirs)
    conforming: bool = False        # split segments until every triangle is Delaunay
    split_boundary: bool = True     # False: no Steiner point on the domain boundary
    split_segments: bool = True     # False: no Steiner point on any segment (Triangle's -YY)


class RouteOptions(NamedTuple):
    """What one run of the constrained Delaunay route (:mod:`.pipeline`) is asked for."""

    algorithm: int = DIVIDE         # a construction code (:data:`.construct.ALGORITHM_CODES`)
    split: bool = False             # insert the crossings of segments (else report them)
    keep_hull: bool = False         # keep every triangle of the convex hull
    use_seeds: bool = False         # hole or region seeds were given: Triangle's rule of the domain
    max_steiner: int = -1           # cap on Steiner points; -1: the default cap
    refine: bool = False            # run Delaunay refinement
    refinement: RefineOptions = RefineOptions()


#: The numba type of :class:`RouteOptions` (a stage's declared arguments, ``ahead=``).
ROUTE_OPTIONS = typeof(RouteOptions())
#: The numba type of :class:`RefineOptions`.
REFINE_OPTIONS = typeof(RefineOptions())


def plain(options: RouteOptions) -> tuple:
    """``options`` as the plain (nested) tuple that a call from Python passes."""
    return (*options[:-1], tuple(options.refinement))


@kernel(forceinline=True)
def named(options):
    """The :class:`RouteOptions` of a plain tuple from :func:`plain`."""
    return RouteOptions(*options[:-1], RefineOptions(*options[-1]))
