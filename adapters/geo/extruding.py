"""Solids from a layer (:func:`extrude`): every polygonal feature meshed in one
batch call (as :func:`~cdt_plugin.adapters.geo.triangulate`) and extruded into a
watertight solid, the whole layer at once with NumPy (:class:`GeoSolids`)."""
from __future__ import annotations

import datetime
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Union

import numpy as np
from cdt_plugin.adapters.geo.errors import (
    HeightError,
    NotPolygonalError,
    describe,
    feature_errors,
    plain,
    warn_skipped,
)
from cdt_plugin.adapters.geo.meshing import mesh_layer
from cdt_plugin.adapters.geo.projection import ProjectLike
from cdt_plugin.adapters.layers import LayerLike, read
from cdt_plugin.adapters.shapely import Repair
from numpy.typing import ArrayLike, NDArray

from cdt_plugin import CDTError
from cdt_plugin.optional import require
from cdt_plugin.solids import boundary_edges, split_pinches

if TYPE_CHECKING:
    import pyproj
    import trimesh
    from geopandas import GeoDataFrame

#: What ``height=`` and ``base=`` take: a column name, one number, or one number per feature.
HeightLike = Union[str, float, ArrayLike]

EXTRUDE_OUTPUTS = ("trimesh", "merged", "scene", "solids")
MERGED_FORMATS = (".ply", ".obj", ".stl", ".off")          # one merged mesh
SCENE_FORMATS = (".glb", ".gltf")                           # one node per feature


def extrude(data: LayerLike, height: HeightLike, *, base: HeightLike = 0.0,
            output: str = "trimesh", project: ProjectLike = None, repair: Repair = False,
            errors: str = "raise", progress: bool | None = None, layer: str | int | None = None,
            **options: Any) -> list[trimesh.Trimesh | None] | trimesh.Trimesh | trimesh.Scene | GeoSolids:
    """Extrude every polygonal feature of a layer into a watertight solid.

    Each Polygon or MultiPolygon (holes included) is triangulated as
    :func:`~cdt_plugin.adapters.geo.triangulate` does it, all features in ONE batch
    call (on every core for a large layer), and the whole layer is extruded at
    once with NumPy: a bottom cap at z = ``base``, a top cap at z = ``base +
    height`` and two wall triangles per boundary edge, built by vertex index (no
    merging by a tolerance). A vertex where a feature's boundary passes twice (a
    hole touching its shell or another hole at a point) gets one copy per fan of
    triangles, so the solid stays a closed 2-manifold, as in
    :func:`cdt_plugin.adapters.trimesh.extrude_triangulation`. Every solid is
    watertight, consistently wound with outward normals, and its volume is its
    footprint's area times its height. The footprints' z (Polygon Z) is not used.

    Parameters
    ----------
    data : GeoDataFrame, GeoSeries, GeoJSON dict, or path
        See :func:`~cdt_plugin.adapters.geo.read`.
    height : str, number or array-like
        The solids' vertical extent (positive, finite): the name of a numeric
        column, one number for all, or one number per feature. For OpenStreetMap's
        ``height`` / ``min_height`` (both measured from the ground) pass
        ``height=layer["height"] - layer["min_height"], base="min_height"``.
    base : str, number or array-like, default 0
        The z of each solid's bottom (finite; a column name, a number, or one per
        feature).
    output : {"trimesh", "merged", "scene", "solids"}
        ``"trimesh"``: a list with one ``trimesh.Trimesh`` per row of the layer
        (None for a feature skipped with ``errors="skip"``), in row order, so that
        ``layer.assign(solid=...)`` pairs them with their rows; each mesh's
        ``metadata`` holds the row's attributes (JSON-safe) and its index label
        (``"feature"``). ``"merged"``: one ``Trimesh`` of all solids. ``"scene"``: a
        ``trimesh.Scene`` with one node per solid (see :meth:`GeoSolids.to_scene`),
        which ``scene.export("city.glb")`` writes with the attributes as node
        ``extras``. ``"solids"``: the :class:`GeoSolids` arrays (all the others
        are made from them).
    project : None, "utm", "aeqd", or a projected CRS
        As in :func:`~cdt_plugin.adapters.geo.triangulate`, but the solids stay
        in the meshing CRS (heights are in metres, so should x and y be): with
        ``project=``, the solids' coordinates are in that CRS; without it, in the
        layer's (a geographic layer warns, :class:`GeographicCRSWarning`).
    repair, errors, progress, layer, **options
        As in :func:`~cdt_plugin.adapters.geo.triangulate`. ``errors="skip"``
        also skips a feature that is not polygonal (a point, a line, an empty
        or missing geometry), which otherwise raises :class:`NotPolygonalError`.
        ``workers``, ``min_angle``, ``max_area``... reach the triangulation.

    Raises
    ------
    HeightError
        ``height`` / ``base``: a missing or non-numeric column, a height that is
        not positive and finite, a base that is not finite (checked before any
        meshing; the message names the column and the features).
    NotPolygonalError
        A feature without a polygon (``errors="raise"``; found by the meshing: a
        feature without triangles that did not fail).
    NoPolygonsError, cdt_plugin.InvalidGeometryError, ProjectionError
        As in :func:`~cdt_plugin.adapters.geo.triangulate`, naming the feature.

    Examples
    --------
    >>> import geopandas, shapely
    >>> blocks = geopandas.GeoDataFrame(
    ...     {"name": ["hall", "yard"], "height": [12.0, 6.0]}, crs="EPSG:32633",
    ...     geometry=[shapely.box(500000, 5000000, 500020, 5000010),
    ...               shapely.box(500030, 5000000, 500060, 5000030).difference(
    ...                   shapely.box(500040, 5000010, 500050, 5000020))])
    >>> hall, yard = extrude(blocks, height="height")
    >>> bool(hall.is_watertight), float(hall.volume), hall.metadata["name"]
    (True, 2400.0, 'hall')
    >>> bool(yard.is_watertight), float(yard.volume)      # (900 - 100) m2 x 6 m
    (True, 4800.0)
    >>> scene = extrude(blocks, height="height", output="scene")
    >>> sorted(scene.graph.nodes_geometry)
    ['0', '1']
    """
    if output not in EXTRUDE_OUTPUTS:
        raise CDTError(f"output must be one of {EXTRUDE_OUTPUTS}, got {output!r}")
    require("trimesh", "cdt_plugin.adapters.geo.extrude", extra="trimesh")     # before any work
    frame = read(data, layer=layer)
    top, bottom = layer_heights(frame, height, base)
    mesh = mesh_layer(frame, project=project, repair=repair, errors=errors, progress=progress,
                      options=options, require_polygons=True, warn=True, map_back=False)
    failed = dict(mesh.errors)
    failed.update(_not_polygonal(frame, mesh.offsets, failed, errors))
    solids = extrude_mesh(frame, mesh.vertices, mesh.triangles, mesh.position, bottom, top,
                          crs=mesh.mesh_crs or frame.crs, errors=failed)
    if output == "solids":
        return solids
    if output == "merged":
        return solids.merged()
    if output == "scene":
        return solids.to_scene()
    return solids.to_trimesh()


def layer_heights(frame: GeoDataFrame, height: HeightLike,
                  base: HeightLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(top, bottom) z per row: ``base + height`` and ``base``, checked (HeightError)."""
    h = _column_values(frame, height, "height")
    b = _column_values(frame, base, "base")
    _check_values(frame, h, height, "height", lambda v: np.isfinite(v) & (v > 0),
                  "positive and finite")
    _check_values(frame, b, base, "base", np.isfinite, "finite")
    return b + h, b


def _column_values(frame: GeoDataFrame, value: HeightLike, name: str) -> NDArray[np.float64]:
    """One float per row from a column name, a number or an array-like."""
    import pandas

    if isinstance(value, str):
        if value not in frame.columns or value == frame.geometry.name:
            columns = [c for c in frame.columns if c != frame.geometry.name]
            raise HeightError(f"{name}={value!r}: the layer has no such attribute column "
                              f"(its columns: {', '.join(map(str, columns)) or 'none'})")
        column = frame[value]
        if not (pandas.api.types.is_numeric_dtype(column.dtype)
                and not pandas.api.types.is_bool_dtype(column.dtype)):
            raise HeightError(f"{name}={value!r}: the column is not numeric "
                              f"(dtype {column.dtype}); convert it, e.g. with "
                              "pandas.to_numeric")
        return column.to_numpy(dtype=np.float64, na_value=np.nan)
    if isinstance(value, (bool, np.bool_)):
        raise HeightError(f"{name} must be a number, a column name or one number per "
                          f"feature, got {value!r}")
    try:
        values = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise HeightError(f"{name} must be a number, a column name or one number per "
                          f"feature, got {type(value).__name__} {value!r:.80}") from None
    if values.ndim == 0:
        return np.full(len(frame), float(values))
    if values.shape != (len(frame),):
        raise HeightError(f"{name}: expected one number per feature ({len(frame)}), got an "
                          f"array of shape {values.shape}")
    return values


def _check_values(frame: GeoDataFrame, values: NDArray[np.float64], given: HeightLike,
                  name: str, ok: Any, wanted: str) -> None:
    """HeightError naming the rows whose value is not ``ok`` (the first five)."""
    bad = np.flatnonzero(~ok(values))
    if not len(bad):
        return
    what = f"{name}={given!r}" if isinstance(given, str) else name
    shown = ", ".join(f"feature {plain(frame.index[i])} ({float(values[i])!r})" for i in bad[:5])
    more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
    e = HeightError(f"{what} must be {wanted}: {len(bad)} feature(s) are not: {shown}{more}")
    e.index, e.feature = int(bad[0]), plain(frame.index[bad[0]])
    raise e


def _not_polygonal(frame: GeoDataFrame, offsets: NDArray[np.int64], failed: dict[int, CDTError],
                   errors: str) -> dict[int, CDTError]:
    """The rows without triangles that did not fail: no polygon (a point, a line, an
    empty or missing geometry). NotPolygonalError for the first; with
    ``errors="skip"`` the errors of all of them (a SkippedFeaturesWarning says so)."""
    bad = [i for i in map(int, np.flatnonzero(offsets[1:] == offsets[:-1])) if i not in failed]
    if not bad:
        return {}
    geoms = np.asarray(frame.geometry.array, dtype=object)
    out = feature_errors(NotPolygonalError, frame, bad, lambda i: "no polygon to extrude "
                         f"({describe(geoms[i:i + 1]).split(': ', 1)[1]})", errors)
    warn_skipped(out, frame, "have no polygon to extrude and no solid", "")
    return out


@dataclass
class GeoSolids:
    """The solids of a layer as flat arrays, grouped by feature (what :func:`extrude`
    builds its outputs from; ``output="solids"`` returns it).

    Attributes
    ----------
    source : GeoDataFrame
        The features as read (index, attributes).
    vertices : (n, 3) float64
        Every solid's vertices, feature after feature, in :attr:`crs`.
    faces : (m, 3) int64
        Triangles (outward normals), feature after feature; indices into ``vertices``.
    vertex_offsets, face_offsets : (g + 1,) int64
        Row ``i``'s solid is ``vertices[vertex_offsets[i]:vertex_offsets[i + 1]]``
        and ``faces[face_offsets[i]:face_offsets[i + 1]]`` (none for a skipped row).
    crs : pyproj.CRS or None
        The CRS of the coordinates: the meshing CRS (``project=``) or the layer's.
    errors : dict
        Row position -> CDTError of the features skipped with ``errors="skip"``.
    """

    source: GeoDataFrame
    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    vertex_offsets: NDArray[np.int64]
    face_offsets: NDArray[np.int64]
    crs: pyproj.CRS | None = None
    errors: dict[int, CDTError] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.face_offsets) - 1

    def solid(self, i: int) -> tuple[NDArray[np.float64], NDArray[np.int64]] | None:
        """Row ``i``'s solid as ``(vertices, faces)`` of its own, or None."""
        f0, f1 = self.face_offsets[i], self.face_offsets[i + 1]
        if f0 == f1:
            return None
        v0, v1 = self.vertex_offsets[i], self.vertex_offsets[i + 1]
        return self.vertices[v0:v1], self.faces[f0:f1] - v0

    def attributes(self) -> list[dict[str, Any]]:
        """Per row: its attribute columns and its index label (``"feature"``, unless
        a column has that name), every value JSON-safe (:func:`json_safe`)."""
        src = self.source
        table = src.drop(columns=[src.geometry.name])
        columns = [str(c) for c in table.columns]
        values = [[json_safe(v) for v in table[c].tolist()] for c in table.columns]
        labels = [json_safe(v) for v in src.index.tolist()]
        key = "feature" if "feature" not in columns else "cdt_feature"
        return [{key: labels[i], **{c: col[i] for c, col in zip(columns, values)}}
                for i in range(len(src))]

    def to_trimesh(self) -> list[trimesh.Trimesh | None]:
        """One ``Trimesh`` per row (None for a skipped row), its attributes as
        ``metadata``."""
        import trimesh

        out: list[trimesh.Trimesh | None] = []
        for i, attributes in enumerate(self.attributes()):
            solid = self.solid(i)
            out.append(None if solid is None else
                       trimesh.Trimesh(solid[0], solid[1], process=False, metadata=attributes))
        return out

    def merged(self) -> trimesh.Trimesh:
        """All solids as one ``Trimesh`` (no vertex shared between solids); its
        ``metadata`` holds the CRS (``"crs"``, WKT) when there is one."""
        import trimesh

        return trimesh.Trimesh(self.vertices, self.faces, process=False,
                               metadata=self._scene_metadata())

    def to_scene(self) -> trimesh.Scene:
        """A ``trimesh.Scene`` with one node per solid, named by its row's index
        label (``str(label)``; ``label#position`` where labels repeat), whose
        metadata are the row's attributes (JSON-safe, so that a ``.glb`` export
        writes them as the node's ``extras`` and trimesh reads them back). Each
        solid's geometry is stored relative to its lowest corner (x and y of its
        bounding box's minimum, z = 0) and the node's transform translates it
        there: glTF stores vertices as float32 (centimetres lost at UTM
        coordinates), the node's translation as a JSON number (exact). The
        scene's metadata holds the CRS (``"crs"``, WKT) when there is one."""
        import trimesh

        scene = trimesh.Scene(metadata=self._scene_metadata())
        labels = [str(plain(v)) for v in self.source.index]
        unique = len(set(labels)) == len(labels)
        for i, attributes in enumerate(self.attributes()):
            solid = self.solid(i)
            if solid is None:
                continue
            V, F = solid
            origin = np.array([V[:, 0].min(), V[:, 1].min(), 0.0])
            name = labels[i] if unique else f"{labels[i]}#{i}"
            mesh = trimesh.Trimesh(V - origin, F, process=False)
            scene.add_geometry(mesh, node_name=name, geom_name=name,
                               transform=trimesh.transformations.translation_matrix(origin),
                               metadata=attributes)
        return scene

    def write(self, path: str | Path) -> str:
        """Write ``.glb`` / ``.gltf`` (:meth:`to_scene`) or one merged mesh ``.ply``,
        ``.obj``, ``.stl``, ``.off`` (:meth:`merged`; PLY and STL hold float32
        coordinates, OBJ and OFF are written with 17 decimals). Returns a summary."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in SCENE_FORMATS + MERGED_FORMATS:
            raise CDTError(f"{path}: expected one of {', '.join(SCENE_FORMATS + MERGED_FORMATS)}")
        if suffix in SCENE_FORMATS:
            self.to_scene().export(path)
        else:
            digits: dict[str, Any] = {"digits": 17} if suffix in (".obj", ".off") else {}
            self.merged().export(path, **digits)
        solids = int((np.diff(self.face_offsets) > 0).sum())
        return (f"wrote {path}: {solids:,} solid(s), {len(self.vertices):,} vertices, "
                f"{len(self.faces):,} triangles")

    def _scene_metadata(self) -> dict[str, Any]:
        return {"crs": self.crs.to_wkt()} if self.crs is not None else {}


def json_safe(value: Any) -> Any:
    """``value`` as something ``json.dumps`` writes as standard JSON and reads back
    the same: NumPy scalars as Python numbers, NaN, infinities, None, NaT and
    ``pandas.NA`` as None, dates and times as ISO 8601 text, bytes as hex, other
    objects (a geometry, a Decimal) as their ``str``.

    >>> import numpy as np, pandas
    >>> [json_safe(v) for v in (np.int64(3), np.float32(0.5), float("nan"), pandas.NaT,
    ...                         pandas.Timestamp("2024-05-01 12:00"), b"\\x01", True)]
    [3, 0.5, None, None, '2024-05-01T12:00:00', '01', True]
    """
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, (datetime.date, datetime.time)):
        import pandas

        return None if value is pandas.NaT else value.isoformat()
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).hex()
    try:
        import pandas

        if pandas.isna(value):
            return None
    except (TypeError, ValueError):      # (arrays, lists: not one missing value)
        pass
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    return str(value)


def extrude_mesh(source: GeoDataFrame, V: NDArray[np.float64], T: NDArray[np.int64],
                 position: NDArray[np.int64], bottom: NDArray[np.float64],
                 top: NDArray[np.float64], *, crs: Any = None,
                 errors: dict[int, CDTError] | None = None) -> GeoSolids:
    """The solids of the triangles ``T`` (counter-clockwise, grouped by ``position``,
    the row of each; vertices ``V`` (n, 2) not shared between rows) extruded from
    z = ``bottom[row]`` to ``top[row]``: all rows at once."""
    g = len(source)
    V, T = split_pinches(V, T)
    V, T, row = _compact(V, T, position)
    n = len(V)
    counts = np.bincount(row, minlength=g)
    start = np.concatenate([[0], np.cumsum(counts)])          # vertices of each row in V
    # row r's solid: its vertices at z = bottom (indices v + start[r]), then at z = top
    shift = start[row]
    lower, upper = np.arange(n) + shift, np.arange(n) + shift + counts[row]
    out = np.empty((2 * n, 3))
    out[lower, :2], out[lower, 2] = V, bottom[row]
    out[upper, :2], out[upper, 2] = V, top[row]
    i, j = boundary_edges(T, n).T
    # the domain lies left of i -> j: (i, j, j') and (i, j', i') face outwards
    walls = np.concatenate([np.column_stack([lower[i], lower[j], upper[j]]),
                            np.column_stack([lower[i], upper[j], upper[i]])])
    faces = np.concatenate([lower[T[:, ::-1]], upper[T], walls])
    face_row = np.concatenate([row[T[:, 0]], row[T[:, 0]], row[i], row[i]])
    order = np.argsort(face_row, kind="stable")
    face_counts = np.bincount(face_row, minlength=g)
    return GeoSolids(source, out, faces[order], 2 * start,
                     np.concatenate([[0], np.cumsum(face_counts)]), crs, dict(errors or {}))


def _compact(V: NDArray[np.float64], T: NDArray[np.int64],
             position: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.int64],
                                                   NDArray[np.int64]]:
    """Only the vertices the triangles use, ordered by row (``position``); returns
    the vertices, the renumbered triangles and each vertex's row."""
    row = np.full(len(V), -1, np.int64)
    row[T] = position[:, None]
    used = np.flatnonzero(row >= 0)
    used = used[np.argsort(row[used], kind="stable")]
    new = np.empty(len(V), np.int64)
    new[used] = np.arange(len(used))
    return V[used], new[T], row[used]
