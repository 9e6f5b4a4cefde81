"""GIS adapter: mesh every polygon of a layer (GeoDataFrame, GeoJSON, Shapefile,
GeoPackage) in one call, keeping attributes, CRS and Z.

Data flow (DESIGN.md): a layer -> :class:`geopandas.GeoDataFrame` (:func:`read`)
-> optional projection (pyproj) -> ONE call of
:func:`cdt_plugin.adapters.shapely.triangulate_batch` (one PLC per feature: a
Polygon with its holes, or a MultiPolygon's parts together) -> :class:`GeoMesh`
(flat arrays in the layer's CRS) -> a GeoDataFrame of triangles, or one
``trimesh.Trimesh`` per feature.

* :func:`triangulate` -- the whole layer on one machine.
* :func:`triangulate_dask` -- a dask-geopandas GeoDataFrame, partition by partition
  (``map_partitions``), on any Dask cluster.
* :func:`extrude` -- every polygon of a layer extruded into a watertight solid (a
  height column or number, a base), as trimesh meshes, one merged mesh or a
  ``trimesh.Scene`` with one node per feature (``.glb`` with the attributes).
* :func:`voronoi` -- the Voronoi cell (the power diagram's, with weights) of every
  point of a point layer, clipped to a boundary polygon or layer; one row per point.
* ``gdf.cdt.triangulate(...)`` / ``gs.cdt.triangulate(...)`` -- :func:`triangulate` as
  a method of a GeoDataFrame or GeoSeries (:class:`CDTAccessor`, a pandas accessor
  registered when this module is imported).

One module per job, the public names re-exported here: :mod:`.meshing`
(:func:`triangulate`), :mod:`.extruding` (:func:`extrude`), :mod:`.voronoi_cells` (:func:`voronoi`), :mod:`.dask_frames`
(:func:`triangulate_dask`), :mod:`.accessor` (``.cdt``), :mod:`.projection`
(``project=``), :mod:`.results` (:class:`GeoMesh`, GeoArrow), :mod:`.errors` (the
warnings and errors); reading and writing layers (:func:`read`,
:func:`write_geojson`) is :mod:`cdt_plugin.adapters.layers`, shared with
:mod:`cdt_plugin.adapters.terrain` (:func:`tin`, :func:`grid`).

Coordinates. Projected CRSs (UTM: 1e5 to 1e7 metres) need nothing special: the
engine decides every topological question with exact predicates on the coordinates
as given, so they are neither shifted nor scaled (a shift ``x - x0`` rounds). In a
geographic CRS (longitude, latitude) the triangulation would be Delaunay, and
``min_angle`` / ``max_area`` measured, in degree space: :class:`GeographicCRSWarning`
says so unless ``project=`` is given. ``project="utm"`` meshes in the UTM zone of the
data (``estimate_utm_crs`` at its bounding box's centre), ``"aeqd"`` in an
azimuthal equidistant projection centred at the bounding box's centre (for
lon/lat data the box takes the shortest longitude arc, so data across the
antimeridian is centred where it lies), a CRS (anything
``pyproj.CRS.from_user_input`` takes) in that projected CRS. The mesh is then mapped
back: every input vertex gets back its original coordinates exactly (bit for bit);
a Steiner vertex on a boundary edge goes to the same fraction of the original edge
(so the triangles still tile the original polygons, and neighbours sharing a border
stay seamless), and the other Steiner vertices are inverse-projected. The triangles
are constrained Delaunay (and meet ``min_angle``) in the meshing CRS. Vertices on
another ring's edge (touching rings) are inserted into that edge first, and a triangle
that turns flat or clockwise when mapped back is mended by an edge flip. A feature whose
triangles still would not stay counter-clockwise in the layer's CRS (one split at the
antimeridian, whose parts meet in the projection, or one too far from the
projection's centre, or one valid only in the meshing CRS) raises
:class:`ProjectionError` (or is skipped).

Z. Polygons with Z keep it: input vertices keep their own z, Steiner and
intersection vertices get z interpolated linearly along their segment or inside
their triangle (:mod:`cdt_plugin.lift`), so the triangles form a 2.5D surface
(the triangle polygons are then 3D). Features without Z in the same layer give 2D
triangles.

>>> import geopandas, shapely
>>> layer = geopandas.GeoDataFrame({"name": ["square", "triangle"]}, crs="EPSG:32633",
...     geometry=[shapely.box(500000, 5000000, 500004, 5000004),
...               shapely.Polygon([(500010, 5000000), (500012, 5000000), (500011, 5000001)])])
>>> tris = triangulate(layer)
>>> tris[["feature", "position", "part", "name"]].values.tolist()
[[0, 0, 0, 'square'], [0, 0, 0, 'square'], [1, 1, 0, 'triangle']]
>>> tris.crs.to_epsg(), bool(tris.area.sum() == layer.area.sum())
(32633, True)
"""
from __future__ import annotations

from cdt_plugin.adapters import claim_modules_names
from cdt_plugin.optional import missing

try:
    import shapely  # noqa: F401
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.geo", extra="gis") from exc

# one module per job; the public API (__all__) and the names users reach through it
from cdt_plugin.adapters.geo.accessor import CDTAccessor
from cdt_plugin.adapters.geo.dask_frames import triangulate_dask
from cdt_plugin.adapters.geo.errors import (
    GeographicCRSWarning,
    HeightError,
    NotGeographicError,
    NotPolygonalError,
    ProjectionError,
    SkippedFeaturesWarning,
)
from cdt_plugin.adapters.geo.extruding import EXTRUDE_OUTPUTS, GeoSolids, HeightLike, extrude  # noqa: F401
from cdt_plugin.adapters.geo.meshing import AUTO_PROGRESS_FEATURES, OUTPUTS, triangulate  # noqa: F401
from cdt_plugin.adapters.geo.projection import ProjectLike  # noqa: F401
from cdt_plugin.adapters.geo.results import ID_COLUMNS, GeoMesh  # noqa: F401
from cdt_plugin.adapters.geo.voronoi_cells import BoundaryLike, voronoi  # noqa: F401
from cdt_plugin.adapters.layers import GEOJSON_ROWS, LayerLike, read, write_geojson  # noqa: F401
from cdt_plugin.adapters.terrain import grid, tin  # noqa: F401  (terrain from spot heights)

from cdt_plugin import CDTError, NoPolygonsError  # noqa: F401  (re-exported)

__all__ = ["triangulate", "triangulate_dask", "voronoi", "read", "write_geojson", "GeoMesh",
           "GeographicCRSWarning", "SkippedFeaturesWarning", "NoPolygonsError", "ProjectionError",
           "NotGeographicError", "CDTAccessor", "extrude", "GeoSolids", "HeightError",
           "NotPolygonalError"]

claim_modules_names(globals())
