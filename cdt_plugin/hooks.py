"""The conversion hooks: THE one place where the engine calls the adapters.

Nothing in ``cdt_plugin`` below the adapters imports ``cdt_plugin.adapters``
(at module level or inside a function) except this module (the command line,
on top of everything, may; ``tests/tools/test_layout.py`` holds both): the ``to_*``
conversions of a result to a host library's object
(:meth:`Triangulation.to_trimesh`, ``to_open3d``, ``to_shapely``) and the
GEOS services the Voronoi diagram asks for (a cut to a polygon, cells as
polygons) hand over to the adapters here, each importing its adapter when
called: the host library loads only for the process that asks for it.

The results are passed as they are (``Any``: the adapters take the result
classes, which sit above this module).

>>> import cdt_plugin
>>> from cdt_plugin import hooks
>>> tri = cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1], [1, 1]])
>>> hooks.to_shapely(tri).geom_type, len(hooks.to_shapely(tri).geoms)   # as tri.to_shapely() does
('GeometryCollection', 2)
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    import open3d
    import shapely
    import trimesh

__all__ = ["cells_to_polygons", "clip_cells_to_polygon", "to_open3d", "to_shapely", "to_trimesh"]


def to_trimesh(tri: Any, z: float | None = None, **kwargs: Any) -> trimesh.Trimesh:
    """``tri`` as a flat ``trimesh.Trimesh`` (:func:`cdt_plugin.adapters.trimesh.to_trimesh`)."""
    from cdt_plugin.adapters.trimesh import to_trimesh as convert
    return convert(tri, z=z, **kwargs)


def to_open3d(tri: Any, z: ArrayLike | None = None) -> open3d.geometry.TriangleMesh:
    """``tri`` as an Open3D mesh (:func:`cdt_plugin.adapters.open3d.to_open3d`)."""
    from cdt_plugin.adapters.open3d import to_open3d as convert
    return convert(tri, z=z)


def to_shapely(tri: Any) -> shapely.GeometryCollection:
    """``tri``'s triangles as shapely Polygons (:func:`cdt_plugin.adapters.shapely.to_shapely`)."""
    from cdt_plugin.adapters.shapely import to_shapely as convert
    return convert(tri)


def clip_cells_to_polygon(vor: Any, clip: Any) -> NDArray[np.object_]:
    """Every cell of the Voronoi diagram ``vor`` cut to the polygon ``clip`` by GEOS
    (:func:`cdt_plugin.adapters.shapely.clip_cells_to_polygon`)."""
    from cdt_plugin.adapters.shapely import clip_cells_to_polygon as clip_cells
    return clip_cells(vor, clip)


def cells_to_polygons(offsets: NDArray[np.int64], xy: NDArray[np.float64]) -> NDArray[np.object_]:
    """One shapely Polygon per cell of flat rings
    (:func:`cdt_plugin.adapters.shapely.cells_to_polygons`)."""
    from cdt_plugin.adapters.shapely import cells_to_polygons as polygons
    return polygons(offsets, xy)
