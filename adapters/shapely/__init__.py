"""shapely adapter: constrained Delaunay triangulation of shapely geometries.

Data flow (DESIGN.md): shapely geometry -> validate (GEOS ``is_valid`` at unit size) ->
:class:`cdt_plugin.PLC` -> :func:`cdt_plugin.triangulate` -> Triangulation ->
shapely output (:func:`to_shapely`).

* :func:`triangulate` -- one geometry gives one Triangulation; an array or list of
  geometries (shapely 2 style) gives a list of Triangulations, in order. Polygonal
  input is validated with GEOS first, on the geometry scaled by a power of two to
  unit size where GEOS's arithmetic would not be exact (:mod:`.validity`: the same
  verdict at every magnitude); invalid polygons raise
  :class:`cdt_plugin.InvalidGeometryError` naming the reason, point and rings, or
  are repaired with ``repair=True``.
* :func:`to_shapely` -- a Triangulation as a GeometryCollection of triangle
  Polygons, in the form ``shapely.constrained_delaunay_triangles`` returns.
* :func:`constrained_delaunay_triangles` -- a drop-in for
  ``shapely.constrained_delaunay_triangles`` returning the exact CDT (GEOS ear-clips
  and then runs a capped number of Delaunay flip passes, so on large polygons it can
  stop short of the CDT); ``repair=`` as in :func:`triangulate`.
* :func:`delaunay_triangles` -- a drop-in for ``shapely.delaunay_triangles``: the
  Delaunay triangulation of all the vertices of any geometry (``tolerance``,
  ``only_edges``), with exact predicates.
* :func:`voronoi_polygons` -- a drop-in for ``shapely.voronoi_polygons``: the
  Voronoi cells (or edges) of all the vertices of any geometry, cut to GEOS's
  envelope (``tolerance``, ``extend_to``, ``only_edges``, ``ordered``); one cell
  per distinct vertex, in input order; exact predicates decide the combinatorics.

The drop-ins are element-wise as shapely's functions are: an array of geometries
in, an array of the same shape out (a pandas Series or GeoSeries keeps its index),
``None`` gives ``None``.

One module per job, the public names re-exported here: :mod:`.reading` (shapely
geometries in: validation, repair, :func:`triangulate`, :func:`triangulate_batch`),
:mod:`.validity` (GEOS's validity and repair at unit size, the error messages),
:mod:`.building` (geometries out: :func:`to_shapely`), :mod:`.cells` (the Voronoi
cells as Polygons, which :class:`cdt_plugin.Voronoi` asks for) and :mod:`.dropins`
(shapely's functions).

Polygons and MultiPolygons (also in arrays) are read straight from GEOS coordinate
arrays, vectorised over the whole input, by the engine's one reader of them
(:func:`cdt_plugin.plc.shapely_polygon_rings`); other geometry types go through
``__geo_interface__`` (:meth:`cdt_plugin.PLC.from_geo_interface`). Both give the same PLC.
"""
from __future__ import annotations

from cdt_plugin.adapters import claim_modules_names
from cdt_plugin.optional import missing

try:
    import shapely  # noqa: F401  (the library, not this package: imports are absolute)
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.shapely", extra="shapely") from exc

# the public API (__all__), and beside it the services the engine calls
# (cells_to_polygons, clip_cells_to_polygon), triangle_polygons, Repair and the size constants
from cdt_plugin.adapters.shapely.building import (POLYGON_PIECE, POLYGONS_PER_THREAD,  # noqa: F401
                                                  to_shapely, triangle_polygons)
from cdt_plugin.adapters.shapely.cells import (GEOS_RANGE, cells_to_polygons,  # noqa: F401
                                               clip_cells_to_polygon)
from cdt_plugin.adapters.shapely.dropins import (constrained_delaunay_triangles, delaunay_triangles,
                                                 voronoi_polygons)
from cdt_plugin.adapters.shapely.reading import (Repair, plc_from_shapely, triangulate,  # noqa: F401
                                                 triangulate_batch)

__all__ = ["triangulate", "triangulate_batch", "to_shapely", "constrained_delaunay_triangles",
           "delaunay_triangles", "voronoi_polygons", "plc_from_shapely"]

claim_modules_names(globals())
