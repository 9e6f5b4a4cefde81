"""``triangulate_rings(size=...)``: the batch path meshes geometries one by one and
refines each to its size field (one for all, or one per geometry), as
``triangulate(size=...)`` does; checked exactly; a wrong count of fields named."""
from __future__ import annotations

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin.batch import triangulate_rings
from cdt_plugin.errors import CDTError, SizeFieldError
from tests.support.checker import assert_valid

# a unit square and a triangle beside it
XY = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [3, 0], [2, 1.0]])
RINGS = dict(ring_start=[0, 4, 7], geom_ring_start=[0, 1, 2], ring_polygon=[0, 0],
             ring_is_hole=[False, False])
RING_SIZES = (4, 3)


def geometry_mesh(batch, g):
    V, T = batch.mesh(g)
    e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    assert_valid(V, T, segments=uniq[count == 1], domain="segments")
    return V, T


@pytest.mark.parametrize("size", [0.1, cdt_plugin.size_near([[0.0, 0.0]], 0.05, 0.3, distance=2.0)])
def test_one_field_for_all_is_what_triangulate_makes(size):
    batch = triangulate_rings(XY, **RINGS, size=size, min_angle=25)
    starts = [0, 4]
    for g in range(2):
        V, T = geometry_mesh(batch, g)
        ring = XY[starts[g]:starts[g] + RING_SIZES[g]].tolist()
        polygon = {"type": "Polygon", "coordinates": [ring + ring[:1]]}
        single = cdt_plugin.triangulate(polygon, size=size, min_angle=25)
        assert sorted(map(tuple, V.tolist())) == sorted(map(tuple, single.vertices.tolist()))
        assert len(T) == len(single.triangles)


def test_one_field_per_geometry():
    batch = triangulate_rings(XY, **RINGS, size=[None, 0.05])
    assert len(geometry_mesh(batch, 0)[1]) == 2                 # not refined
    V, T = geometry_mesh(batch, 1)
    P = V[T]
    assert np.linalg.norm(P - np.roll(P, -1, axis=1), axis=2).max() <= 1.5 * 0.05
    assert batch.stats["fallback"] == 2


def test_bad_sizes_are_named():
    with pytest.raises(CDTError, match="size has 3 size fields for 2 geometries"):
        triangulate_rings(XY, **RINGS, size=[0.1, 0.1, 0.1])
    with pytest.raises(SizeFieldError, match="size must be a positive finite length, got 0"):
        triangulate_rings(XY, **RINGS, size=[0.1, 0])
    with pytest.raises(SizeFieldError, match="growth must be a finite number > 1"):
        triangulate_rings(XY, **RINGS, size=0.1, growth=0.9)
