"""The meshes of a layer (:class:`GeoMesh`): flat arrays in the layer's CRS, as
a GeoDataFrame of triangles, GeoArrow (a pyarrow Table) or trimesh meshes."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import NDArray

from cdt_plugin import CDTError
from cdt_plugin.batch import MeshBatch
from cdt_plugin.optional import require
from cdt_plugin.adapters.geo.errors import plain
from cdt_plugin.adapters.shapely import triangle_polygons

if TYPE_CHECKING:
    import pyarrow
    import pyproj
    import trimesh
    from geopandas import GeoDataFrame

ID_COLUMNS = ("feature", "position", "part")


@dataclass
class GeoMesh:
    """The triangles of a layer as flat arrays (what :func:`triangulate` builds its
    outputs from; ``output="mesh"`` returns it).

    Attributes
    ----------
    source : GeoDataFrame
        The features as read (index, attributes, CRS).
    vertices : (n, 2) float64
        Mesh vertices in the source CRS (input vertices with their original
        coordinates, bit for bit).
    z : (n,) float64 or None
        Z of every vertex when the layer has Z (0 for features without Z).
    triangles : (k, 3) int64
        Counter-clockwise where the vertices are (the source CRS when mapped back:
        a triangle that a projection folds is repaired by an edge flip), grouped by feature.
    position : (k,) int64
        The source row (0-based position) of each triangle.
    part : (k,) int64
        The polygon (of a MultiPolygon) each triangle lies in.
    offsets : (g + 1,) int64
        Triangles of row ``i`` are ``triangles[offsets[i]:offsets[i + 1]]``.
    errors : dict
        Row position -> CDTError of the features skipped with ``errors="skip"``.
    mesh_crs : pyproj.CRS or None
        The CRS the meshing was done in (None: the source CRS).
    batch : MeshBatch
        The engine's result (vertices in the meshing CRS).
    workers : int or None
        Threads for making the outputs (the triangle Polygons), as meshed with.
    """

    source: GeoDataFrame
    vertices: NDArray[np.float64]
    z: NDArray[np.float64] | None
    triangles: NDArray[np.int64]
    position: NDArray[np.int64]
    part: NDArray[np.int64]
    offsets: NDArray[np.int64]
    errors: dict[int, CDTError] = field(default_factory=dict)
    mesh_crs: pyproj.CRS | None = None
    batch: MeshBatch | None = None
    workers: int | None = None

    def __len__(self) -> int:
        return len(self.triangles)

    @property
    def feature_has_z(self) -> NDArray[np.bool_]:
        """(g,) bool: which source features have Z."""
        return shapely.has_z(np.asarray(self.source.geometry.array, dtype=object))

    def boundary_edges(self) -> NDArray[np.int64]:
        """(s, 2) vertex pairs of the edges used by one triangle only: the pieces of
        the polygons' rings (the segments), for valid polygons."""
        T = self.triangles
        e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
        uniq, count = np.unique(e, axis=0, return_counts=True)
        return uniq[count == 1]

    def feature_mesh(self, i: int) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
        """Row ``i`` alone: ``(vertices, triangles)`` with only its vertices,
        (m, 3) when the feature has Z, else (m, 2)."""
        T = self.triangles[self.offsets[i]:self.offsets[i + 1]]
        used, local = np.unique(T, return_inverse=True)
        V = self.vertices[used]
        if self.z is not None and self.feature_has_z[i]:
            V = np.column_stack([V, self.z[used]])
        return V, local.reshape(-1, 3)

    def triangle_polygons(self) -> NDArray[np.object_]:
        """One shapely Polygon per triangle (counter-clockwise closed shell; 3D
        for features with Z), built from flat coordinate arrays in one call per
        dimension and thread (``shapely.from_ragged_array``: about twice as fast
        as ``shapely.polygons``, which builds a LinearRing first; on
        :attr:`workers` threads for large layers)."""
        corners = self.triangles[:, [0, 1, 2, 0]]
        if self.z is None:
            return triangle_polygons(self.vertices, corners, self.workers)
        out = np.empty(len(corners), dtype=object)
        has_z = self.feature_has_z[self.position]
        out[~has_z] = triangle_polygons(self.vertices, corners[~has_z], self.workers)
        out[has_z] = triangle_polygons(np.column_stack([self.vertices, self.z]), corners[has_z],
                                       self.workers)
        return out

    def to_geodataframe(self) -> GeoDataFrame:
        """One row per triangle (see :func:`triangulate`)."""
        import geopandas

        src = self.source
        name = src.geometry.name
        table = src.drop(columns=[name]).iloc[self.position].reset_index(drop=True)
        ids = _id_column_names(table.columns)
        table.insert(0, ids[0], src.index.to_numpy()[self.position])
        table.insert(1, ids[1], self.position)
        table.insert(2, ids[2], self.part)
        geometry = geopandas.GeoSeries(self.triangle_polygons(), crs=src.crs, name=name)
        out = geopandas.GeoDataFrame(table, geometry=geometry, crs=src.crs)
        if self.errors:
            out.attrs["cdt_errors"] = {plain(src.index[i]): f"{type(e).__name__}: {e}"
                                       for i, e in self.errors.items()}
        return out

    def to_arrow(self) -> pyarrow.Table:
        """One row per triangle, as :meth:`to_geodataframe` has them, in a
        ``pyarrow.Table`` whose geometry column is GeoArrow (``geoarrow.polygon``,
        interleaved ``xy`` or ``xyz`` coordinates, the CRS as PROJJSON in the
        field's extension metadata), built from the mesh arrays without a
        shapely object per triangle. A layer with Z gives ``xyz``, z 0 for its
        features without Z (as :attr:`z`); another geometry column of the layer
        is kept as WKB (``geoarrow.wkb``), and the labels of a MultiIndex (as
        ``explode`` makes) as a struct of its levels. ``geopandas.GeoDataFrame.from_arrow``
        reads it back (``geometry=`` names the triangles' column when there are
        two), and the table carries GeoParquet's ``geo`` metadata:
        ``pyarrow.parquet.write_table`` writes it as a GeoParquet file.

        >>> import geopandas, shapely
        >>> from cdt_plugin.adapters.geo import triangulate
        >>> layer = geopandas.GeoDataFrame({"id": [7]}, geometry=[shapely.box(0, 0, 2, 2)])
        >>> table = triangulate(layer, output="mesh").to_arrow()
        >>> table.column_names, table.num_rows
        (['feature', 'position', 'part', 'id', 'geometry'], 2)
        >>> table.field("geometry").metadata[b"ARROW:extension:name"]
        b'geoarrow.polygon'
        """
        import geopandas
        import pandas

        pa = require("pyarrow", "GeoArrow output", extra="gis")
        src = self.source
        name = src.geometry.name
        features = pandas.DataFrame(src.drop(columns=[name]))   # one row per feature...
        ids = _id_column_names(features.columns)
        features.insert(0, ids[1], np.arange(len(src)))
        other_geometries = {c: features[c].array.crs for c in features.columns
                            if isinstance(features[c].dtype, geopandas.array.GeometryDtype)}
        for c in other_geometries:                             # (a second geometry column: WKB)
            features[c] = shapely.to_wkb(np.asarray(features[c].array, dtype=object))
        table = pa.Table.from_pandas(features, preserve_index=False).take(self.position)  # ...per triangle
        for c, crs in other_geometries.items():
            j = table.schema.get_field_index(c)
            table = table.set_column(j, _geoarrow_field(pa, c, table.schema.field(c).type,
                                                        "geoarrow.wkb", crs), table.column(j))
        table = table.add_column(0, ids[0], _index_labels(pa, src.index).take(self.position))
        table = table.add_column(2, ids[2], pa.array(self.part))
        geometry, field_ = _geoarrow_polygons(pa, self.vertices, self.z, self.triangles, src.crs, name)
        table = table.append_column(field_, geometry)
        geo_metadata = _geoparquet_metadata(name, src.crs, self.z is not None, other_geometries)
        return table.replace_schema_metadata({**(table.schema.metadata or {}),
                                              b"geo": json.dumps(geo_metadata).encode()})

    def to_trimesh(self) -> list[trimesh.Trimesh | None]:
        """One ``trimesh.Trimesh`` per source row (None without triangles); z is
        the vertex z for features with Z, else 0."""
        import trimesh

        out: list[trimesh.Trimesh | None] = []
        for i in range(len(self.offsets) - 1):
            if self.offsets[i] == self.offsets[i + 1]:
                out.append(None)
                continue
            V, T = self.feature_mesh(i)
            if V.shape[1] == 2:
                V = np.column_stack([V, np.zeros(len(V))])
            out.append(trimesh.Trimesh(V, T, process=False))
        return out


def _index_labels(pa: Any, index: Any) -> Any:
    """A layer's index labels as an Arrow array; a MultiIndex (``explode`` makes
    one) as a struct of its levels (named, or ``level_0``, ``level_1``...)."""
    if index.nlevels == 1:
        return pa.Array.from_pandas(index.to_series(index=None))
    names = [n if n is not None else f"level_{i}" for i, n in enumerate(index.names)]
    return pa.StructArray.from_arrays(
        [pa.Array.from_pandas(index.get_level_values(i).to_series(index=None))
         for i in range(index.nlevels)], names=names)


def _geoarrow_polygons(pa: Any, V: NDArray[np.float64], z: NDArray[np.float64] | None,
                       T: NDArray[np.int64], crs: Any, name: str) -> tuple[Any, Any]:
    """The triangles as a GeoArrow ``geoarrow.polygon`` array (one closed
    counter-clockwise ring each, interleaved coordinates; the field names of
    the GeoArrow specification: ``rings``, ``vertices``, ``xy``/``xyz``) and
    its field. Offsets are 32-bit up to 2**31 coordinates, 64-bit beyond."""
    k = len(T)
    corners = T[:, [0, 1, 2, 0]].reshape(-1)
    xy = V[corners] if z is None else np.column_stack([V[corners], z[corners]])
    dims = "xy" if z is None else "xyz"
    offsets_type = np.int32 if 4 * k < 2 ** 31 else np.int64
    list_array = pa.ListArray if offsets_type is np.int32 else pa.LargeListArray
    list_type = pa.list_ if offsets_type is np.int32 else pa.large_list
    coords = pa.FixedSizeListArray.from_arrays(pa.array(np.ascontiguousarray(xy).reshape(-1)),
                                               type=pa.list_(pa.field(dims, pa.float64()), len(dims)))
    rings = list_array.from_arrays(pa.array(np.arange(0, 4 * k + 1, 4, dtype=offsets_type)), coords,
                                   type=list_type(pa.field("vertices", coords.type)))
    polygons = list_array.from_arrays(pa.array(np.arange(k + 1, dtype=offsets_type)), rings,
                                      type=list_type(pa.field("rings", rings.type)))
    return polygons, _geoarrow_field(pa, name, polygons.type, "geoarrow.polygon", crs)


def _geoarrow_field(pa: Any, name: str, type_: Any, extension: str, crs: Any) -> Any:
    """A field of GeoArrow extension type ``extension`` (by its field metadata),
    the CRS as PROJJSON."""
    metadata = {"crs": crs.to_json_dict(), "crs_type": "projjson"} if crs is not None else {}
    return pa.field(name, type_, metadata={b"ARROW:extension:name": extension.encode(),
                                           b"ARROW:extension:metadata": json.dumps(metadata).encode()})


def _geoparquet_metadata(name: str, crs: Any, has_z: bool,
                         wkb_columns: dict[str, Any]) -> dict[str, Any]:
    """The ``geo`` metadata of GeoParquet 1.1 for a column of GeoArrow polygons
    (and other geometry columns as WKB): written with the table, the file is
    GeoParquet (``geopandas.read_parquet``)."""
    def crs_of(c: Any) -> Any:
        return c.to_json_dict() if c is not None else None
    columns: dict[str, Any] = {name: {"encoding": "polygon", "crs": crs_of(crs),
                                      "geometry_types": ["Polygon Z" if has_z else "Polygon"]}}
    for column, column_crs in wkb_columns.items():
        columns[column] = {"encoding": "WKB", "geometry_types": [], "crs": crs_of(column_crs)}
    return {"version": "1.1.0", "primary_column": name, "columns": columns}


def _id_column_names(columns) -> tuple[str, ...]:
    """``feature``, ``position``, ``part``, or all three with a ``cdt_`` prefix when
    a source column already has one of these names."""
    if any(c in columns for c in ID_COLUMNS):
        return tuple(f"cdt_{c}" for c in ID_COLUMNS)
    return ID_COLUMNS
