"""Random shapely polygons that are valid or invalid by a hair, for the tests
of validity and of the drop-ins' one-polygon path."""
from __future__ import annotations

import numpy as np
import shapely


def random_polygon(rng):
    """A random polygon of the kinds that are valid or not by a hair: a jagged
    shell, holes that are small and inside, or cross it, lie outside, touch it at a
    vertex or an edge, nest, or repeat points; coordinates on a coarse grid so that
    touching and collinear cases happen."""
    n = int(rng.integers(3, 12))
    angle = np.sort(rng.random(n)) * 2 * np.pi
    radius = rng.integers(2, 9, n)
    shell = np.round(np.column_stack([radius * np.cos(angle), radius * np.sin(angle)]))
    holes = []
    for _ in range(int(rng.integers(0, 4))):
        centre = rng.integers(-9, 10, 2)
        size = rng.integers(1, 4)
        k = int(rng.integers(3, 6))
        a = np.sort(rng.random(k)) * 2 * np.pi
        holes.append(np.round(centre + size * np.column_stack([np.cos(a), np.sin(a)])))
    if rng.random() < 0.2 and len(holes):          # a hole through a shell vertex
        holes[0][0] = shell[int(rng.integers(n))]
    if rng.random() < 0.1:                          # a repeated point
        shell = np.insert(shell, 1, shell[1], axis=0)
    return shapely.Polygon(shell, holes)
