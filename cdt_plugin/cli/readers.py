"""Reading the command's inputs, one reader per kind: Triangle's ``.poly`` and
``.node`` (:mod:`cdt_plugin.io`), WKT (shapely), GeoJSON or earcut's JSON ring
arrays, and GIS layers (:func:`cdt_plugin.adapters.geo.read`)."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from .. import io
from ..errors import CDTError, InputShapeError, NoPolygonsError
from ..plc import geojson_features, geojson_parts
from .formats import GIS_FORMATS, INPUT_FORMATS, import_for, suffix_name
from .terminal import CLIError

if TYPE_CHECKING:
    from geopandas import GeoDataFrame

NAME_COLUMNS = ("name", "NAME", "admin")


@dataclass
class Feature:
    """One thing to triangulate: a geometry (shapely, or a GeoJSON mapping) or PLC
    arrays (Triangle files), with its GeoJSON properties."""
    name: str
    geometry: Any = None
    arrays: dict[str, Any] = field(default_factory=dict)
    properties: dict[str, Any] = field(default_factory=dict)


def read_input(path: Path, layer: str | None = None) -> list[Feature]:
    """The features of an input file (see :mod:`cdt_plugin.cli` for formats);
    ``layer``: the layer of a multi-layer GIS file."""
    path = Path(path)
    suffix = _input_suffix(path)
    if suffix in GIS_FORMATS:
        return _require_polygons(path, _layer_features(path, read_layer(path, layer)))
    if layer is not None:
        raise CLIError(f"--layer applies to GIS layers (.gpkg, .shp), not {suffix}")
    features = _READERS[suffix](path)
    if suffix in (".poly", ".node"):          # PLC arrays: no geometry type to check
        return features
    return _require_polygons(path, features)


def _input_suffix(path: Path, what: str = "") -> str:
    """The suffix of an input file that exists and has a format we read, or the
    error naming it (``what``: the option it was given to, if any)."""
    suffix = path.suffix.lower()
    if suffix not in INPUT_FORMATS:
        raise CLIError(f"{what}{path}: unknown input format {suffix_name(path)!r}; "
                       f"expected one of {', '.join(INPUT_FORMATS)}")
    if not path.exists():
        raise CLIError(f"{what}{path}: no such file")
    return suffix


def _read_poly(path: Path) -> list[Feature]:
    poly = io.read_poly(path)           # (the markers tag the boundaries of .msh, .vtu, .xdmf)
    return [Feature(path.name, arrays={"vertices": poly.to_plc(), "vertex_markers": poly.markers,
                                       "segment_markers": poly.segment_markers})]


def _read_node(path: Path) -> list[Feature]:
    return [Feature(path.name, arrays={"vertices": io.read_node(path).vertices})]


def _read_wkt(path: Path) -> list[Feature]:
    shapely = import_for("shapely", "reading WKT")
    try:
        geometry = shapely.from_wkt(path.read_text(encoding="utf-8").strip())
    except shapely.errors.GEOSException as exc:
        raise CLIError(f"{path}: not valid WKT ({exc})") from None
    return [Feature(path.name, geometry=geometry)]


def _read_json(path: Path) -> list[Feature]:
    """A GeoJSON geometry, Feature or FeatureCollection (one Feature each; a null
    geometry is left out), or earcut's ``[shell, hole, ...]`` ring arrays (one Polygon)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise CLIError(f"{path}: not valid JSON ({exc})") from None
    if isinstance(data, list):
        data = {"type": "Polygon", "coordinates": data}
    try:
        raw = geojson_features(data)        # the engine's one GeoJSON walker
    except (InputShapeError, AttributeError):
        raise CLIError(f"{path}: expected GeoJSON (a geometry, Feature or FeatureCollection) "
                       "or a JSON array of rings") from None
    features = []
    for i, feat in enumerate(raw):
        props = (feat.get("properties") if isinstance(feat, dict) else None) or {}
        name = next((props[c] for c in NAME_COLUMNS if props.get(c)), None)
        label = f"feature {i}" + (f" ({name})" if name else "") if len(raw) > 1 else path.name
        if isinstance(feat, dict) and feat.get("geometry"):
            features.append(Feature(label, geometry=feat["geometry"], properties=props))
    if not features:
        raise CLIError(f"{path}: no geometry to triangulate")
    return features


_READERS: dict[str, Callable[[Path], list[Feature]]] = {
    ".poly": _read_poly, ".node": _read_node, ".wkt": _read_wkt,
    ".geojson": _read_json, ".json": _read_json}


def _geometry_type(geometry: Any) -> str:
    """The GeoJSON type name of a geometry (a GeoJSON mapping or a shapely geometry)."""
    if isinstance(geometry, dict):
        return str(geometry.get("type"))
    return "empty " + geometry.geom_type if geometry.is_empty else geometry.geom_type


def _is_polygonal(geometry: Any) -> bool:
    """A Polygon or MultiPolygon, or a GeometryCollection holding one."""
    if isinstance(geometry, dict):
        return "type" in geometry and any(kind in ("Polygon", "MultiPolygon")
                                          for kind, _ in geojson_parts(geometry))
    if geometry.geom_type == "GeometryCollection":
        return any(_is_polygonal(g) for g in geometry.geoms)
    return _geometry_type(geometry) in ("Polygon", "MultiPolygon")


def _require_polygons(path: Path, features: list[Feature]) -> list[Feature]:
    """``features`` unchanged, or NoPolygonsError when none of them is polygonal
    (a Point-only GeoJSON would otherwise give an empty mesh)."""
    if any(_is_polygonal(f.geometry) for f in features):
        return features
    kinds: dict[str, int] = {}
    for f in features:
        kinds[_geometry_type(f.geometry)] = kinds.get(_geometry_type(f.geometry), 0) + 1
    held = ", ".join(f"{n} {kind}" for kind, n in sorted(kinds.items()))
    raise NoPolygonsError(f"{path}: no Polygon or MultiPolygon feature to triangulate "
                          f"({len(features)} feature(s): {held}); a point set goes in a .node file")


def read_geometries(path: Path, layer: str | None, option: str) -> Any:
    """The geometries of a file given to ``option`` (``--size-near``), for
    :func:`cdt_plugin.size_near`: a GIS layer as a GeoDataFrame, a Triangle ``.poly``
    as its PLC (segments and points), a ``.node`` file's points, a ``.wkt`` geometry,
    GeoJSON geometries; any geometry type."""
    path = Path(path)
    suffix = _input_suffix(path, f"{option} ")
    if is_layer(path):
        return read_layer(path, layer)
    if layer is not None:
        raise CLIError(f"{option} {path}: a layer ({layer!r}) applies to GIS layers (.gpkg, .shp)")
    return [f.geometry if f.geometry is not None else f.arrays["vertices"]
            for f in _READERS[suffix](path)]


def is_layer(path: Path) -> bool:
    """Whether ``path`` is a GIS layer: .shp, .gpkg, .geojson, or a .json Feature or
    FeatureCollection (not a bare geometry or earcut's ring arrays)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in GIS_FORMATS + (".geojson",):
        return True
    if suffix != ".json" or not path.exists():
        return False
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError):
        return False
    return isinstance(data, dict) and data.get("type") in ("Feature", "FeatureCollection")


def read_layer(path: Path, layer: str | None = None) -> GeoDataFrame:
    """A GIS layer as a GeoDataFrame (geopandas + pyogrio); ``layer``: a name, or a
    number given as digits."""
    import_for("geopandas", f"reading {Path(path).suffix} layers")
    from ..adapters.geo import read
    which = int(layer) if layer is not None and layer.isdigit() else layer
    try:
        return read(path, layer=which)
    except FileNotFoundError:
        raise CLIError(f"{path}: no such file") from None
    except Exception as exc:           # pyogrio's DataSourceError, DataLayerError, ...
        if isinstance(exc, CDTError):
            raise
        raise CLIError(f"{path}: cannot read it as a GIS layer ({exc})") from None


def read_node_layer(path: Path) -> GeoDataFrame:
    """A Triangle ``.node`` file as a point layer without a CRS: its node numbers
    (``node``), attributes (``attribute_1``...) and boundary markers (``marker``)."""
    geopandas = import_for("geopandas", "cdt-plugin voronoi")
    shapely = import_for("shapely", "cdt-plugin voronoi")
    if not path.exists():
        raise CLIError(f"{path}: no such file")
    nodes = io.read_node(path)
    columns: dict[str, Any] = {"node": np.arange(len(nodes.vertices)) + nodes.first_index}
    for j in range(nodes.attributes.shape[1]):
        columns[f"attribute_{j + 1}"] = nodes.attributes[:, j]
    if nodes.markers is not None:
        columns["marker"] = nodes.markers
    return geopandas.GeoDataFrame(columns, geometry=shapely.points(nodes.vertices))


def _layer_features(path: Path, frame: GeoDataFrame) -> list[Feature]:
    """The rows of a GeoDataFrame with a geometry, as Features (for the per-feature formats)."""
    features = []
    table = frame.drop(columns=[frame.geometry.name])
    for i, geometry in enumerate(frame.geometry):
        if geometry is None or geometry.is_empty:
            continue
        properties = {k: v for k, v in table.iloc[i].items()}
        features.append(Feature(feature_label(frame, i) if len(frame) > 1 else path.name,
                                geometry=geometry, properties=properties))
    if not features:
        raise CLIError(f"{path}: no geometry to triangulate")
    return features


def feature_label(frame: GeoDataFrame, i: int) -> str:
    """``feature <index label> (<name>)`` for row ``i`` of a layer."""
    label = frame.index[i]
    label = label.item() if isinstance(label, np.generic) else label
    column = next((c for c in NAME_COLUMNS if c in frame.columns), None)
    name = frame[column].iloc[i] if column is not None else None
    return f"feature {label}" + (f" ({name})" if isinstance(name, str) and name else "")
