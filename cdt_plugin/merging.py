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

from ._core.merge import merge_representatives
from ._core.ordering import lexicographic_order
from .plc import PLC

#: Cells are at least this fraction of the points' extent wide, so that the cell
#: numbers (below 2**48) are exact whatever the distance: the rounding of
#: ``(x - xmin) / width`` then moves a point by far less than half a cell.
_CELL_FLOOR = 2.0 ** -48


def close_point_representatives(xy: NDArray[np.float64], distance: float) -> NDArray[np.int64]:
    """The representative of every point of ``xy`` (n, 2) (its own index when
    kept) for merging points closer than ``distance`` (> 0)."""
    x, y = np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1])
    if len(x) == 0:
        return np.empty(0, np.int64)
    span = max(float(np.ptp(x)), float(np.ptp(y)))
    width = max(2.0 * distance, span * _CELL_FLOOR)
    return merge_representatives(x, y, lexicographic_order(x, y), _cell_numbers(x, width),
                                 _cell_numbers(y, width), float(distance),
                                 1 << (2 * len(x)).bit_length())


def _cell_numbers(v: NDArray[np.float64], width: float) -> NDArray[np.int64]:
    with np.errstate(over="ignore", invalid="ignore"):   # (a span beyond float64: one cell)
        q = np.nan_to_num((v - v.min()) / width, nan=0.0, posinf=2.0 ** 50)
    return np.floor(np.clip(q, 0.0, 2.0 ** 50)).astype(np.int64)


def merge_close_points(plc: PLC, distance: float) -> tuple[PLC, int]:
    """``plc`` with every point closer than ``distance`` to its representative
    (:func:`close_point_representatives`) moved onto it, and the number of
    points moved (exact duplicates, which the engine merges anyway, are not
    counted). Segments, rings, seeds, markers and attributes are kept as they
    are (the engine merges the moved points as exact duplicates)."""
    rep = close_point_representatives(plc.vertices, distance)
    count = int((plc.vertices[rep] != plc.vertices).any(axis=1).sum())
    if count == 0:
        return plc, 0
    return dataclasses.replace(plc, vertices=plc.vertices[rep]), count
