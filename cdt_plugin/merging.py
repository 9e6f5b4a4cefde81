"""Input points closer than ``merge_distance`` merged before meshing.

:func:`close_point_representatives` applies the rule of
:mod:`cdt_plugin._core.merge` (lexicographic order; a point closer than the
distance to a point kept before it goes to the nearest such point);
:func:`merge_close_points` applies it to a :class:`~cdt_plugin.plc.PLC` by
moving each merged point onto its representative, so that the engine merges
them as exact duplicates: ``tri.vertex_map`` then names the output vertex of
every input point, a segment whose ends merged has zero length (dropped, and
named in ``stats["zero_length_segments"]``), segments made equal are merged
(``stats["duplicate_segments"]``). Hole and region seeds do not move.

>>> import numpy as np
>>> xy = np.array([[0.0, 0.0], [1.0, 0.0], [1e-9, 0.0], [1.0, 1.0]])
>>> close_point_representatives(xy, 1e-6).tolist()
[0, 1, 0, 3]
"""
from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from ._core.merge import close_representatives
from ._core.ordering import SMALL_SORT, lexicographic_order
from .plc import PLC


def close_point_representatives(xy: NDArray[np.float64], distance: float) -> NDArray[np.int64]:
    """The representative of every point of ``xy`` (n, 2) (its own index when
    kept) for merging points closer than ``distance`` (> 0)."""
    return _representatives(xy, distance)[0]


def _representatives(xy: NDArray[np.float64], distance: float) -> tuple[NDArray[np.int64], int]:
    """:func:`close_point_representatives`, and how many points move (exact
    duplicates, which the engine merges anyway, are not counted): one
    compiled call (the grid's cells, made there, were most of a small call's
    time in NumPy), after NumPy's sort for many points."""
    order = _SORTED_THERE
    if len(xy) >= SMALL_SORT:
        order = lexicographic_order(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]))
    return close_representatives(np.ascontiguousarray(xy, dtype=np.float64), order, float(distance))


_SORTED_THERE = np.empty(0, np.int64)     # (few points: sorted in the compiled call)


def merge_close_points(plc: PLC, distance: float) -> tuple[PLC, int]:
    """``plc`` with every point closer than ``distance`` to its representative
    (:func:`close_point_representatives`) moved onto it, and the number of
    points moved (exact duplicates, which the engine merges anyway, are not
    counted). Segments, rings, seeds, markers and attributes are kept as they
    are (the engine merges the moved points as exact duplicates)."""
    rep, count = _representatives(plc.vertices, distance)
    if count == 0:
        return plc, 0
    return dataclasses.replace(plc, vertices=plc.vertices[rep]), count
