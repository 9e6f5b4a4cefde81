"""The size test of ``triangulate(..., suitable=)`` and ``sizing.refine_until_suitable``
(Triangle's ``-u``, vectorised): every triangle of the result passes the test, the
other bounds still hold, the mesh is checked exactly, and a test that never passes
ends with a named error."""
from __future__ import annotations

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin.errors import CDTError, RefinementLimitError
from cdt_plugin.sizing import refine_until_suitable, triangle_areas
from tests.support.checker import assert_valid, check_steiner_segments

SQUARE = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
RING = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def fine_near_corner(org, dest, apex, area):
    """Small triangles near (4, 4), large ones far from it."""
    centre = (org + dest + apex) / 3
    return area <= 0.002 + 0.05 * ((centre - 4) ** 2).sum(1)


def verdict(tri, test):
    V, T = tri.vertices, tri.triangles
    return np.asarray(test(V[T[:, 0]], V[T[:, 1]], V[T[:, 2]], triangle_areas(V, T)))


@pytest.mark.parametrize("min_angle", [None, 25])
def test_every_triangle_passes_and_the_mesh_is_exact(min_angle):
    tri = cdt_plugin.triangulate(SQUARE, RING, suitable=fine_near_corner, min_angle=min_angle)
    assert verdict(tri, fine_near_corner).all()
    assert tri.stats["size_test_rounds"] >= 1
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    rep = check_steiner_segments(SQUARE, RING, tri.vertices, tri.vertex_map, tri.segments,
                                 tri.segment_ids)
    assert rep.ok, str(rep)
    if min_angle:
        V, T = tri.vertices, tri.triangles
        P = V[T]
        angles = []
        for i in range(3):
            u, v = P[:, (i + 1) % 3] - P[:, i], P[:, (i + 2) % 3] - P[:, i]
            angles.append(np.degrees(np.arccos((u * v).sum(1) / np.hypot(*u.T) / np.hypot(*v.T))))
        assert np.min(angles) >= min_angle - 1e-9
    # graded: the triangles near the corner are smaller than far from it
    areas = triangle_areas(tri.vertices, tri.triangles)
    centre = tri.vertices[tri.triangles].mean(1)
    near = ((centre - 4) ** 2).sum(1) < 0.25
    assert areas[near].max() < areas[~near].max() / 10


def test_max_area_and_the_test_together():
    tri = cdt_plugin.triangulate(SQUARE, RING, suitable=fine_near_corner, max_area=0.5)
    assert verdict(tri, fine_near_corner).all() and triangle_areas(tri.vertices, tri.triangles).max() <= 0.5
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def test_refining_an_existing_mesh_keeps_its_vertices():
    base = cdt_plugin.Triangulation.from_triangles(SQUARE, [[0, 1, 2], [0, 2, 3]])
    fine = refine_until_suitable(base, fine_near_corner, min_angle=20)
    assert fine.vertices[:4].tolist() == SQUARE.tolist() and verdict(fine, fine_near_corner).all()
    assert_valid(fine.vertices, fine.triangles, domain="hull")


def test_a_test_that_never_passes_ends_with_a_named_error():
    never = lambda org, dest, apex, area: np.zeros(len(area), bool)   # noqa: E731
    with pytest.raises(RefinementLimitError, match="size test") as err:
        cdt_plugin.triangulate(SQUARE, RING, suitable=never, max_steiner=2000)
    partial = err.value.triangulation
    assert partial is not None
    assert_valid(partial.vertices, partial.triangles, segments=partial.segments, domain="segments")


@pytest.mark.parametrize("bad, message", [
    (3, "callable"),
    (lambda o, d, a, area: np.ones(len(area) + 1, bool), "one boolean per triangle"),
    (lambda o, d, a, area: "yes", "one boolean per triangle"),
])
def test_bad_size_tests_are_named(bad, message):
    with pytest.raises(CDTError, match=message):
        cdt_plugin.triangulate(SQUARE, RING, suitable=bad)
