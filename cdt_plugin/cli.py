"""The ``cdt-plugin`` command line (also ``python -m cdt_plugin``).

``cdt-plugin mesh INPUT -o OUTPUT`` triangulates a file and writes the mesh;
``cdt-plugin report INPUT`` prints the quality report; ``cdt-plugin voronoi POINTS
-o OUTPUT`` writes the Voronoi cell of every point of a point layer. Inputs: Triangle's
``.poly`` / ``.node``, GeoJSON (``.geojson`` / ``.json``: a geometry, a Feature or
a FeatureCollection, one mesh per feature; a bare JSON array of rings is read as
one polygon, earcut's fixture format), ``.wkt``, and GIS layers ``.shp`` /
``.gpkg`` (read with pyogrio; ``--layer`` picks a GeoPackage layer) / ``.parquet``
(GeoParquet). Outputs, by
extension: ``.ply``, ``.obj``, ``.stl``, ``.glb``, ``.off`` (written by trimesh;
its PLY, STL and GLB writers store float32 coordinates, OBJ and OFF are written
with 17 decimals), ``.geojson`` / ``.json`` (a FeatureCollection of triangles per
input feature) and Triangle's ``.node`` / ``.ele`` / ``.poly`` (all three are
written).

Layers in, layers out: from a ``.shp``, ``.gpkg``, ``.parquet`` or ``.geojson`` layer
(or a ``.json`` Feature/FeatureCollection), ``.gpkg``, ``.parquet`` (GeoParquet,
written from GeoArrow arrays: the fastest) and ``.geojson`` / ``.json`` output is a
layer of triangles, one Polygon feature per triangle carrying the source
feature's attributes, its index (``feature``), row number and part, in the source
CRS (:func:`cdt_plugin.adapters.geo.triangulate`, one batch call for all
features). ``--project utm|aeqd|CRS`` meshes a geographic layer in metres and maps
the triangles back (input vertices exactly).

Voronoi cells: ``cdt-plugin voronoi POINTS --boundary AREA -o CELLS`` reads a point
layer (``.shp``, ``.gpkg``, ``.geojson`` / ``.json``) and writes a ``.gpkg`` or
``.geojson`` / ``.json`` layer with one feature per point, its attributes and the
point's Voronoi cell as the geometry, clipped to the union of the polygons of the
``--boundary`` layer (reprojected to the points' CRS) or, without it, to the points'
bounding box grown by its larger side; ``--weights COLUMN`` makes it a power
diagram (:func:`cdt_plugin.adapters.geo.voronoi`). Where a non-convex boundary cuts
a cell in pieces it is a MultiPolygon (and a GeoPackage then stores every cell as
one); an empty cell (a submerged weighted point, a point whose cell misses the
boundary) is an empty geometry, null in GeoJSON.

Errors are one line on stderr (``cdt-plugin: error: ...``) and exit status 1;
command-line usage errors exit with 2.

>>> main(["report", "--help"])      # doctest: +ELLIPSIS
usage: cdt-plugin report [-h] ...
...
0
"""
from __future__ import annotations

import argparse
import inspect
import json
import os
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from .errors import CDTError, NoPolygonsError
from .optional import MissingPackageError, missing, require

if TYPE_CHECKING:
    import pyarrow
    from geopandas import GeoDataFrame

    from .adapters.geo import GeoMesh
    from .report import Report
    from .triangulation import Triangulation

__all__ = ["main", "build_parser", "read_input", "read_layer", "is_layer", "triangulate_features",
           "concatenate", "write_output", "write_layer", "layer_report", "Feature"]

MESH_FORMATS = (".ply", ".obj", ".stl", ".glb", ".off")
GEOJSON_FORMATS = (".geojson", ".json")
TRIANGLE_FORMATS = (".node", ".ele", ".poly")
GIS_FORMATS = (".shp", ".gpkg", ".parquet")
INPUT_FORMATS = (".poly", ".node", ".geojson", ".json", ".wkt") + GIS_FORMATS
LAYER_OUTPUTS = (".gpkg", ".parquet") + GEOJSON_FORMATS
NAME_COLUMNS = ("name", "NAME", "admin")
MANY_FEATURES = 16        # features per thread worth starting one for
LAYER_ROWS = 50_000       # triangles per GeoPackage / GeoParquet write (and progress step)

EXAMPLES = """\
examples:
  cdt-plugin mesh letter.poly -o letter.ply
  cdt-plugin mesh countries.geojson -o countries.geojson --report
  cdt-plugin mesh countries.shp -o triangles.gpkg --project aeqd --min-angle 25 --repair --errors skip
  cdt-plugin mesh regions.gpkg --layer parcels -o parcels_mesh.gpkg
  cdt-plugin mesh countries.geojson -o countries.glb --extrude 0.5
  cdt-plugin mesh shape.wkt -o shape.stl --extrude 2 --plot shape.png
  cdt-plugin mesh A.poly -o A.ele --min-angle 30 --max-area 0.01
  cdt-plugin voronoi shops.gpkg --boundary city.gpkg -o cells.gpkg
  cdt-plugin voronoi stations.shp --boundary country.geojson --weights power -o cells.geojson
  cdt-plugin tin points.gpkg --breaklines lines.gpkg -o dem.tif --resolution 10
  cdt-plugin report polygon.json --against earcut
  cdt-plugin report polygon.geojson --against other_mesh.obj --json
"""


class CLIError(Exception):
    """A problem with the command's input or options: printed as one line."""


@dataclass
class Feature:
    """One thing to triangulate: a geometry (shapely, or a GeoJSON mapping) or PLC
    arrays (Triangle files), with its GeoJSON properties."""
    name: str
    geometry: Any = None
    arrays: dict[str, Any] = field(default_factory=dict)
    properties: dict[str, Any] = field(default_factory=dict)


# ------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The argument parser (subcommands ``mesh``, ``report``, ``voronoi``, ``tin`` and ``compile``)."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(
        prog="cdt-plugin", formatter_class=fmt, epilog=EXAMPLES,
        description="Constrained Delaunay triangulation of polygon and PSLG files: "
                    "mesh them, report their quality, compare with other meshes.")
    from . import __version__
    parser.add_argument("--version", action="version", version=f"cdt-plugin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="{mesh,report,voronoi,tin,compile}", required=True)

    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("input", metavar="INPUT",
                        help="input file: .poly/.node (Triangle), .geojson/.json, .wkt, "
                             ".shp/.gpkg/.parquet (GIS layers)")
    common.add_argument("--layer", metavar="NAME",
                        help="the layer of a multi-layer input (GeoPackage): name or number")
    common.add_argument("--min-angle", type=float, metavar="A",
                        help="quality refinement: smallest angle in degrees (Steiner points added)")
    common.add_argument("--max-area", type=float, metavar="S",
                        help="quality refinement: largest triangle area")
    common.add_argument("--intersections", choices=("raise", "split"), default="raise",
                        help="crossing segments: report them (default), or split them at the "
                             "crossing (polygons are then not validated: even-odd inside)")
    common.add_argument("--repair", action="store_true",
                        help="repair invalid polygons with shapely.make_valid instead of failing")
    common.add_argument("--errors", choices=("raise", "skip"), default="raise",
                        help="a feature that cannot be meshed: stop with its error (default), or "
                             "leave it out and name it and the reason on stderr (as the Python "
                             "API's errors='skip')")
    common.add_argument("--plot", metavar="PNG", type=Path,
                        help="also draw the mesh and its angle histogram to this image")
    common.add_argument("--workers", type=_workers_arg, metavar="N",
                        help="threads to mesh on (default: every core for many features; "
                             "the result is the same for any number)")
    _progress_options(common, "always show a progress bar over the features (default: on a terminal)")

    mesh = sub.add_parser("mesh", parents=[common], formatter_class=fmt, epilog=EXAMPLES,
                          help="triangulate INPUT and write the mesh",
                          description="Triangulate INPUT (constrained Delaunay, optionally "
                                      "refined) and write the mesh to OUTPUT.")
    mesh.add_argument("-o", "--output", required=True, type=Path, metavar="OUTPUT",
                      help="output file: .ply .obj .stl .glb .off (trimesh), .geojson/.json, "
                           ".node/.ele/.poly (Triangle: all three written), .gpkg, .parquet; "
                           "from a layer (.shp/.gpkg/.parquet/.geojson) .gpkg, .parquet "
                           "(GeoParquet, the fastest) and .geojson get one feature per "
                           "triangle with the source attributes")
    mesh.add_argument("--extrude", type=float, metavar="H",
                      help="extrude the mesh into a watertight solid of height H (mesh formats)")
    mesh.add_argument("--report", action="store_true", help="also print the quality report")
    mesh.add_argument("--project", metavar="utm|aeqd|CRS",
                      help="layer output: mesh in the layer's UTM zone, in an azimuthal "
                           "equidistant projection centred on it, or in a projected CRS "
                           "(e.g. EPSG:32633), and map the triangles back to the layer's CRS "
                           "(for lon/lat layers: angles and areas in metres)")
    mesh.set_defaults(func=_cmd_mesh)

    rep = sub.add_parser("report", parents=[common], formatter_class=fmt, epilog=EXAMPLES,
                         help="print the quality report of INPUT's triangulation",
                         description="Triangulate INPUT and print its quality report "
                                     "(angles, circumdisks, Delaunay certificate).")
    rep.add_argument("--against", metavar="earcut|MESH",
                     help="compare with mapbox_earcut's triangulation of the same polygons, or "
                          "with a mesh file (anything trimesh loads; x and y are used; PLY, STL "
                          "and GLB hold float32 coordinates, so use OBJ or OFF to compare with "
                          "the same vertices)")
    rep.add_argument("--json", action="store_true", help="print the report as JSON")
    rep.set_defaults(func=_cmd_report)

    vor = sub.add_parser("voronoi", formatter_class=fmt, epilog=EXAMPLES,
                         help="write the Voronoi cell of every point of a point layer",
                         description="The Voronoi cell (power cell with --weights) of every point "
                                     "of POINTS, clipped to --boundary, written as a layer with one "
                                     "feature per point and its attributes, in the points' CRS.")
    vor.add_argument("input", metavar="POINTS",
                     help="point layer: .gpkg, .shp, .parquet, .geojson/.json (Point geometries)")
    vor.add_argument("-o", "--output", required=True, type=Path, metavar="OUTPUT",
                     help="output layer: .gpkg, .parquet or .geojson/.json, one feature per point")
    vor.add_argument("--boundary", type=Path, metavar="AREA",
                     help="polygon layer to clip the cells to (.gpkg, .shp, .parquet, .geojson/.json: the "
                          "union of its polygons, reprojected to the points' CRS); default: the "
                          "points' bounding box grown by its larger side, as GEOS does")
    vor.add_argument("--layer", metavar="NAME",
                     help="the layer of a multi-layer POINTS file (GeoPackage): name or number")
    vor.add_argument("--boundary-layer", metavar="NAME",
                     help="the layer of a multi-layer --boundary file: name or number")
    vor.add_argument("--weights", metavar="COLUMN",
                     help="power diagram: the points' weights are this numeric column (a point "
                          "that claims no area gets an empty cell)")
    _progress_options(vor, "always show progress bars (default: on a terminal)")
    vor.set_defaults(func=_cmd_voronoi)

    tin = sub.add_parser("tin", formatter_class=fmt, epilog=EXAMPLES,
                         help="terrain from spot heights and breaklines: a TIN layer or a DEM",
                         description="The TIN (constrained Delaunay triangulation) of the spot "
                                     "heights in POINTS, with --breaklines as segments, clipped "
                                     "to --boundary; written as a layer of 3D triangles (.gpkg, "
                                     ".geojson), or sampled on a grid of --resolution as a GeoTIFF "
                                     "(.tif, needs rasterio) or a NumPy array (.npy).")
    tin.add_argument("input", metavar="POINTS",
                     help="point layer: .gpkg, .shp, .parquet, .geojson/.json (Point Z, or --z COLUMN)")
    tin.add_argument("-o", "--output", required=True, type=Path, metavar="OUTPUT",
                     help="output: .gpkg, .parquet or .geojson/.json (the TIN), .tif or .npy (the grid)")
    tin.add_argument("--breaklines", type=Path, metavar="LINES",
                     help="line layer (LineString Z) the surface must follow")
    tin.add_argument("--boundary", type=Path, metavar="AREA",
                     help="polygon layer: the TIN covers its union only")
    tin.add_argument("--z", metavar="COLUMN", help="the heights are this numeric column of POINTS")
    tin.add_argument("--resolution", type=float, metavar="SIZE",
                     help="cell size of the grid (.tif, .npy), in the layer's units")
    tin.add_argument("--method", choices=("linear", "natural"), default="linear",
                     help="interpolation on the grid (default: linear)")
    tin.set_defaults(func=_cmd_tin)

    from .compiling import ROUTES
    comp = sub.add_parser("compile", formatter_class=fmt,
                          help="compile every route ahead of time (Docker images, CI, Dask workers)",
                          description="Compile the engine's routes with numba now and fill the "
                                      "cache, so that no later process compiles; prints the "
                                      "seconds per route (a filled cache loads in well under one).")
    comp.add_argument("routes", nargs="*", metavar="ROUTE",
                      help=f"routes to compile (default: all of {', '.join(sorted(ROUTES))})")
    comp.set_defaults(func=_cmd_compile)
    return parser


def _workers_arg(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}")
    return value


def _progress_options(parser: argparse.ArgumentParser, always: str) -> None:
    """``--progress`` / ``--no-progress`` (default None: a bar on a terminal)."""
    bar = parser.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None, help=always)
    bar.add_argument("--no-progress", dest="progress", action="store_false",
                     help="never show a progress bar")


# ------------------------------------------------------------------- reading
def read_input(path: Path, layer: str | None = None) -> list[Feature]:
    """The features of an input file (see the module docstring for formats);
    ``layer``: the layer of a multi-layer GIS file."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in INPUT_FORMATS:
        raise CLIError(f"{path}: unknown input format {suffix or '(no extension)'!r}; "
                       f"expected one of {', '.join(INPUT_FORMATS)}")
    if not path.exists():
        raise CLIError(f"{path}: no such file")
    if suffix in GIS_FORMATS:
        return _require_polygons(path, _layer_features(path, read_layer(path, layer)))
    if layer is not None:
        raise CLIError(f"--layer applies to GIS layers (.gpkg, .shp), not {suffix}")
    from . import io
    if suffix == ".poly":
        return [Feature(path.name, arrays={"vertices": io.read_poly(path).to_plc()})]
    if suffix == ".node":
        return [Feature(path.name, arrays={"vertices": io.read_node(path).vertices})]
    if suffix == ".wkt":
        shapely = _import("shapely", "reading WKT")
        try:
            geometry = shapely.from_wkt(path.read_text(encoding="utf-8").strip())
        except shapely.errors.GEOSException as exc:
            raise CLIError(f"{path}: not valid WKT ({exc})") from None
        return _require_polygons(path, [Feature(path.name, geometry=geometry)])
    return _require_polygons(path, _read_json(path))


def _geometry_type(geometry: Any) -> str:
    """The GeoJSON type name of a geometry (a GeoJSON mapping or a shapely geometry)."""
    if isinstance(geometry, dict):
        return str(geometry.get("type"))
    return "empty " + geometry.geom_type if geometry.is_empty else geometry.geom_type


def _is_polygonal(geometry: Any) -> bool:
    """A Polygon or MultiPolygon, or a GeometryCollection holding one."""
    if isinstance(geometry, dict) and geometry.get("type") == "GeometryCollection":
        return any(_is_polygonal(g) for g in geometry.get("geometries") or [] if g)
    if not isinstance(geometry, dict) and geometry.geom_type == "GeometryCollection":
        return any(_is_polygonal(g) for g in geometry.geoms)
    return _geometry_type(geometry) in ("Polygon", "MultiPolygon")


def _require_polygons(path: Path, features: list[Feature]) -> list[Feature]:
    """``features`` unchanged, or NoPolygonsError when none of them is polygonal
    (a Point-only GeoJSON would otherwise give an empty mesh)."""
    if any(_is_polygonal(f.geometry) for f in features):
        return features
    kinds: dict = {}
    for f in features:
        kinds[_geometry_type(f.geometry)] = kinds.get(_geometry_type(f.geometry), 0) + 1
    held = ", ".join(f"{n} {kind}" for kind, n in sorted(kinds.items()))
    raise NoPolygonsError(f"{path}: no Polygon or MultiPolygon feature to triangulate "
                          f"({len(features)} feature(s): {held}); a point set goes in a .node file")


def _read_json(path: Path) -> list[Feature]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise CLIError(f"{path}: not valid JSON ({exc})") from None
    if isinstance(data, list):     # earcut's fixtures: [shell, hole, ...] rings
        data = {"type": "Polygon", "coordinates": data}
    if not isinstance(data, dict) or "type" not in data:
        raise CLIError(f"{path}: expected GeoJSON (a geometry, Feature or FeatureCollection) "
                       "or a JSON array of rings")
    if data["type"] == "FeatureCollection":
        raw = data.get("features") or []
    elif data["type"] == "Feature":
        raw = [data]
    else:
        raw = [{"type": "Feature", "geometry": data, "properties": {}}]
    features = []
    for i, feat in enumerate(raw):
        props = (feat.get("properties") if isinstance(feat, dict) else None) or {}
        name = props.get("name") or props.get("NAME") or props.get("admin")
        label = f"feature {i}" + (f" ({name})" if name else "") if len(raw) > 1 else path.name
        if isinstance(feat, dict) and feat.get("geometry"):    # null geometry: nothing to mesh
            features.append(Feature(label, geometry=feat["geometry"], properties=props))
    if not features:
        raise CLIError(f"{path}: no geometry to triangulate")
    return features


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
    _import("geopandas", f"reading {Path(path).suffix} layers")
    from .adapters.geo import read
    which = int(layer) if layer is not None and layer.isdigit() else layer
    try:
        return read(path, layer=which)
    except FileNotFoundError:
        raise CLIError(f"{path}: no such file") from None
    except Exception as exc:           # pyogrio's DataSourceError, DataLayerError, ...
        if isinstance(exc, CDTError):
            raise
        raise CLIError(f"{path}: cannot read it as a GIS layer ({exc})") from None


def _layer_features(path: Path, frame: GeoDataFrame) -> list[Feature]:
    """The rows of a GeoDataFrame with a geometry, as Features (for the per-feature formats)."""
    features = []
    table = frame.drop(columns=[frame.geometry.name])
    for i, (label, geometry) in enumerate(zip(frame.index, frame.geometry)):
        if geometry is None or geometry.is_empty:
            continue
        properties = {k: v for k, v in table.iloc[i].items()}
        features.append(Feature(_feature_label(frame, i) if len(frame) > 1 else path.name,
                                geometry=geometry, properties=properties))
    if not features:
        raise CLIError(f"{path}: no geometry to triangulate")
    return features


def _feature_label(frame: GeoDataFrame, i: int) -> str:
    """``feature <index label> (<name>)`` for row ``i`` of a layer."""
    label = frame.index[i]
    label = label.item() if isinstance(label, np.generic) else label
    column = next((c for c in NAME_COLUMNS if c in frame.columns), None)
    name = frame[column].iloc[i] if column is not None else None
    return f"feature {label}" + (f" ({name})" if isinstance(name, str) and name else "")


def _shapely_geometry(feature: Feature) -> Any:
    """The feature's geometry as a shapely geometry (GeoJSON mappings are converted)."""
    if not isinstance(feature.geometry, dict):
        return feature.geometry
    shapely = _import("shapely", "validating GeoJSON polygons")
    try:
        return shapely.geometry.shape(feature.geometry)
    except (ValueError, TypeError, KeyError, AttributeError, IndexError,
            shapely.errors.ShapelyError) as exc:
        raise CLIError(f"{feature.name}: not a valid GeoJSON geometry ({exc}); "
                       "--intersections split meshes its rings as they are") from None


def _import(module: str, purpose: str) -> Any:
    try:
        return require(module, purpose)
    except MissingPackageError as exc:
        raise CLIError(str(exc)) from None


def _check_packages(args: argparse.Namespace) -> None:
    """The optional packages the options need, checked before anything is read or
    compiled (a missing one is an error naming the extra that brings it)."""
    import importlib.util
    needs = []
    output = getattr(args, "output", None)
    if output is not None:
        suffix = Path(output).suffix.lower()
        if suffix in MESH_FORMATS:
            needs.append(("trimesh", f"writing {suffix}"))
        elif suffix in GEOJSON_FORMATS:
            needs.append(("shapely", "writing GeoJSON"))
        elif suffix == ".gpkg":
            needs.append(("geopandas", "writing .gpkg"))
        elif suffix == ".parquet":
            needs += [("geopandas", "writing .parquet"), ("pyarrow", "writing .parquet")]
    if args.command == "voronoi":
        needs.append(("geopandas", "cdt-plugin voronoi"))
    if getattr(args, "plot", None) is not None:
        needs.append(("matplotlib", "--plot"))
    against = getattr(args, "against", None)
    if against == "earcut":
        needs.append(("mapbox_earcut", "--against earcut"))
    elif against:
        needs.append(("trimesh", "--against MESH"))
    for module, purpose in needs:
        if importlib.util.find_spec(module) is None:
            raise CLIError(str(missing(module, purpose)))


# --------------------------------------------------------------- meshing
def _options(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword options for triangulate; refinement options only when given."""
    options: dict[str, Any] = {"intersections": args.intersections}
    asked = {k: v for k, v in (("min_angle", args.min_angle), ("max_area", args.max_area))
             if v is not None}
    if asked:
        from . import triangulate
        accepted = inspect.signature(triangulate).parameters
        missing = [k for k in asked if k not in accepted]
        if missing:
            raise CLIError("refinement options need a cdt_plugin whose triangulate() accepts "
                           f"{', '.join(missing)} (quality refinement is not in this version)")
        options.update(asked)
    return options


def triangulate_features(features: Sequence[Feature], options: dict[str, Any], *,
                         repair: bool = False, progress: bool | None = None,
                         workers: int | None = None,
                         errors: str = "raise") -> list[Triangulation | CLIError]:
    """Triangulate each feature (a progress bar over many features when ``progress``
    is True, or None and stderr is a terminal), on ``workers`` threads (default:
    every core when there are many features). Errors name the feature; with
    ``errors="skip"`` a feature that fails has its ``CLIError`` in its place in the
    list instead of stopping the others."""
    from .parallel import map_ordered, resolve_workers
    bar = _bar(progress, "triangulating", "feature", len(features)) if len(features) > 1 else None
    try:
        return map_ordered(lambda feature: _triangulate_feature(feature, features, options, repair,
                                                                errors),
                           features, resolve_workers(workers, len(features) // MANY_FEATURES),
                           done=None if bar is None else lambda *_: bar.update(1))
    finally:
        if bar is not None:
            bar.close()


def _triangulate_feature(feature: Feature, features: Sequence[Feature], options: dict[str, Any],
                         repair: bool, errors: str = "raise") -> Triangulation | CLIError:
    from . import triangulate
    # Geometry goes through the shapely adapter (GEOS validity check, optional
    # repair) unless crossings are to be split: the engine then meshes the rings
    # as they are, by even-odd depth where they cross.
    validate = repair or options.get("intersections") != "split"
    try:
        if feature.geometry is not None and validate:
            from .adapters.shapely import triangulate as triangulate_geometry
            return triangulate_geometry(_shapely_geometry(feature), repair=repair, **options)
        if feature.geometry is not None:
            return triangulate(feature.geometry, **options)
        return triangulate(**feature.arrays, **options)
    except CDTError as exc:
        message = str(exc).replace(
            "pass repair=True to repair it with shapely.make_valid",
            "pass --repair to repair it with shapely.make_valid, or --intersections split "
            "to mesh its rings as they are")
        if errors == "skip":
            return CLIError(f"{feature.name}: {message}")
        raise CLIError(f"{feature.name}: {message}" if len(features) > 1 else message) from None


def concatenate(tris: Sequence[Triangulation]) -> Triangulation:
    """One Triangulation holding several (vertices, triangles, segments offset;
    ``regions`` = the index of the triangulation each triangle came from; numeric
    ``stats`` summed). One input is returned as it is.

    >>> import cdt_plugin
    >>> a = cdt_plugin.triangulate([[0, 0], [1, 0], [0, 1]], [[0, 1], [1, 2], [2, 0]])
    >>> both = concatenate([a, a])
    >>> both.triangles.tolist(), both.regions.tolist(), both.is_delaunay()
    ([[0, 1, 2], [3, 4, 5]], [0, 1], True)
    """
    from .triangulation import Triangulation
    if len(tris) == 1:
        return tris[0]
    voff = np.cumsum([0] + [len(t.vertices) for t in tris])
    toff = np.cumsum([0] + [len(t.triangles) for t in tris])
    soff = np.cumsum([0] + [t.stats.get("input_segments", 0) for t in tris])
    shift = lambda a, off: np.where(a >= 0, a + off, -1)  # noqa: E731
    out = Triangulation(
        np.vstack([t.vertices for t in tris]),
        np.vstack([t.triangles + o for t, o in zip(tris, voff)]).astype(np.int64),
        np.vstack([shift(t.neighbors, o) for t, o in zip(tris, toff)]).astype(np.int64),
        np.concatenate([shift(t.vertex_map, o) for t, o in zip(tris, voff)]),
        _sum_stats([t.stats for t in tris]))
    out.constrained = np.vstack([t.constrained for t in tris])
    out.segments = np.vstack([t.segments + o for t, o in zip(tris, voff)]).astype(np.int64)
    out.segment_ids = np.concatenate([shift(t.segment_ids, o) for t, o in zip(tris, soff)])
    out.steiner = np.concatenate([t.steiner + o for t, o in zip(tris, voff)]).astype(np.int64)
    out.regions = np.repeat(np.arange(len(tris)), [len(t.triangles) for t in tris])
    return out


def _sum_stats(stats: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key in stats[0]:
        values = [s.get(key) for s in stats]
        if all(isinstance(v, bool) for v in values):
            out[key] = all(values)
        elif all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            out[key] = sum(values)
    return out


# ------------------------------------------------------------------ writing
def _check_output(path: Path, extrude: float | None) -> str:
    suffix = path.suffix.lower()
    known = MESH_FORMATS + GEOJSON_FORMATS + TRIANGLE_FORMATS + (".gpkg", ".parquet")
    if suffix not in known:
        raise CLIError(f"{path}: unknown output format {suffix or '(no extension)'!r}; expected one "
                       f"of {', '.join(known)}")
    if extrude is not None and suffix not in MESH_FORMATS:
        raise CLIError(f"--extrude makes a solid: write it to a mesh format "
                       f"({', '.join(MESH_FORMATS)}), not {suffix}")
    if extrude is not None and not (np.isfinite(extrude) and extrude != 0):
        raise CLIError(f"--extrude needs a finite nonzero height, got {extrude}")
    if not path.parent.exists():
        raise CLIError(f"{path}: the directory {path.parent} does not exist")
    return suffix


def write_output(path: Path, features: Sequence[Feature], tris: Sequence[Triangulation],
                 combined: Triangulation, extrude: float | None = None) -> str:
    """Write the mesh to ``path`` (format by extension); returns a one-line summary."""
    path = Path(path)
    suffix = _check_output(path, extrude)
    if suffix in MESH_FORMATS:
        _import("trimesh", f"writing {suffix}")
        from .adapters.trimesh import extrude_triangulation
        mesh = combined.to_trimesh(remove_unreferenced=True)
        if extrude is not None:
            mesh = extrude_triangulation(mesh.vertices[:, :2], mesh.faces, extrude)
        # OBJ and OFF are text: 17 decimals keep the coordinates (trimesh's
        # PLY, STL and GLB writers store float32)
        digits: dict[str, Any] = {"digits": 17} if suffix in (".obj", ".off") else {}
        mesh.export(path, **digits)
        return f"wrote {path}: {len(mesh.vertices):,} vertices, {len(mesh.faces):,} triangles"
    if suffix in GEOJSON_FORMATS:
        shapely = _import("shapely", "writing GeoJSON")
        from .adapters.shapely import to_shapely
        out = {"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {**f.properties, "triangles": len(t.triangles)},
             "geometry": shapely.geometry.mapping(to_shapely(t, ccw=True))}
            for f, t in zip(features, tris)]}
        path.write_text(json.dumps(out), encoding="utf-8")
        return f"wrote {path}: {len(tris)} feature(s), {len(combined.triangles):,} triangles"
    from . import io
    base = path.with_suffix("")
    io.write_triangulation(path, combined, attributes=combined.regions if len(tris) > 1 else None)
    return (f"wrote {base}.node/.ele/.poly: {len(combined.vertices):,} vertices, "
            f"{len(combined.triangles):,} triangles, {len(combined.segments):,} segment edges")


def write_layer(path: Path, triangles: GeoDataFrame | pyarrow.Table, mesh: GeoMesh,
                progress: Callable[[int], object] | None = None) -> str:
    """Write the triangles of ``mesh`` (a GeoDataFrame, or for ``.parquet`` its
    GeoArrow table, :meth:`~cdt_plugin.adapters.geo.GeoMesh.to_arrow`) with
    ``_write_frame``. ``progress``: called with the number of triangles written
    since the last call. Returns a one-line summary."""
    path = Path(path)
    _write_frame(path, triangles, progress)
    meshed = int(np.count_nonzero(np.diff(mesh.offsets)))
    return f"wrote {path}: {meshed} feature(s), {len(triangles):,} triangles"


def _write_frame(path: Path, frame: GeoDataFrame | pyarrow.Table,
                 progress: Callable[[int], object] | None = None) -> None:
    """Write a GeoDataFrame as a GeoPackage (``.gpkg``, with pyogrio, appended
    ``LAYER_ROWS`` rows at a time), GeoParquet (``.parquet``; a pyarrow Table with
    GeoParquet's metadata is written ``LAYER_ROWS`` rows per row group) or GeoJSON
    (:func:`cdt_plugin.adapters.geo.write_geojson`); every way the coordinates
    read back bit for bit. An existing file is replaced. ``progress``: called with
    the number of rows written since the last call."""
    path = Path(path)
    if path.suffix.lower() == ".parquet":
        _write_parquet(path, frame, progress)
    elif path.suffix.lower() == ".gpkg":
        if path.exists():
            path.unlink()
        for i in range(0, max(len(frame), 1), LAYER_ROWS):      # appended in pieces
            part = frame.iloc[i:i + LAYER_ROWS]
            with warnings.catch_warnings():    # a layer without a CRS (.node, .poly in) is fine
                warnings.filterwarnings("ignore", message="'crs' was not provided")
                part.to_file(path, driver="GPKG", engine="pyogrio", mode="a" if i else "w")
            if progress is not None:
                progress(len(part))
    else:
        from .adapters.geo import write_geojson
        write_geojson(frame, path, progress=progress)


def _write_parquet(path: Path, table: GeoDataFrame | pyarrow.Table,
                   progress: Callable[[int], object] | None = None) -> None:
    """GeoParquet: a GeoDataFrame by geopandas (WKB geometry), a pyarrow Table
    as it is, ``LAYER_ROWS`` rows per row group."""
    import pyarrow.parquet
    if not isinstance(table, pyarrow.Table):           # a GeoDataFrame
        table.to_parquet(path)
        if progress is not None:
            progress(len(table))
        return
    with pyarrow.parquet.ParquetWriter(path, table.schema) as writer:
        for i in range(0, max(len(table), 1), LAYER_ROWS):
            part = table.slice(i, LAYER_ROWS)
            writer.write_table(part)
            if progress is not None:
                progress(len(part))


def _bar(show: bool | None, desc: str, unit: str, total: int) -> Any:
    """A tqdm bar on stderr (``show`` None: when stderr is a terminal), or None."""
    if show is False or show is None and not sys.stderr.isatty():
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr)


# ------------------------------------------------------------ layers (GIS)
def _layer_job(args: argparse.Namespace) -> bool:
    """Layer in, layer out: meshed with the GIS adapter (one batch call)."""
    return Path(args.output).suffix.lower() in LAYER_OUTPUTS and is_layer(Path(args.input))


def _mesh_layer(args: argparse.Namespace, output: Path) -> int:
    if args.intersections == "split":
        raise CLIError("--intersections split is for the per-feature formats: layer output "
                       "validates polygons (pass --repair to repair invalid ones)")
    if args.plot is not None:
        _check_plot(args.plot)
    reading = _bar(args.progress, "reading", "file", 1)
    frame = read_layer(Path(args.input), args.layer)
    if reading is not None:
        reading.update(1)
        reading.close()
    mesh = _triangulate_layer(frame, args, _options(args))
    # GeoParquet is written from the GeoArrow table: no shapely Polygon per triangle
    triangles = mesh.to_arrow() if output.suffix.lower() == ".parquet" else mesh.to_geodataframe()
    writing = _bar(args.progress, "writing", "triangle", len(triangles))
    try:
        print(write_layer(output, triangles, mesh, None if writing is None else writing.update))
    finally:
        if writing is not None:
            writing.close()
    if args.report or args.plot is not None:
        rep = layer_report(mesh)
        if args.report:
            print(rep)
        if args.plot is not None:
            _save_layer_plot(args.plot, mesh, rep)
    return 0


def _triangulate_layer(frame: GeoDataFrame, args: argparse.Namespace,
                       options: dict[str, Any]) -> GeoMesh:
    """:func:`cdt_plugin.adapters.geo.triangulate` (``output="mesh"``) with the
    command's options; its warnings become ``cdt-plugin: warning:`` lines."""
    from .adapters import geo
    progress = args.progress if args.progress is not None else len(frame) > 1 and sys.stderr.isatty()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            mesh = geo.triangulate(frame, output="mesh", project=args.project, repair=args.repair,
                                   errors=args.errors, progress=progress, workers=args.workers,
                                   **options)
        except CDTError as exc:
            raise CLIError(_layer_error(exc, frame)) from None
    for i in sorted(mesh.errors):
        _warn(f"skipped {_layer_error(mesh.errors[i], frame)}")
    if mesh.errors and len(mesh.errors) == len(frame):
        raise CLIError(f"{args.input}: no feature could be meshed ({len(frame)} skipped)")
    for w in caught:
        if issubclass(w.category, geo.GeographicCRSWarning):
            message = str(w.message).replace("pass project='utm', 'aeqd' or a projected CRS",
                                             "pass --project utm or --project aeqd")
            _warn(message)
    return mesh


def _warn(message: str) -> None:
    print(f"cdt-plugin: warning: {' '.join(message.split())}", file=sys.stderr)


def _layer_error(exc: CDTError, frame: GeoDataFrame) -> str:
    """The adapter's message with the feature's name and the command's option names."""
    message = str(exc).replace("pass repair=True to repair it with shapely.make_valid",
                               "pass --repair to repair it with shapely.make_valid")
    prefix = f"feature {exc.feature}:"
    if exc.index is not None and message.startswith(prefix):
        message = f"{_feature_label(frame, exc.index)}:{message[len(prefix):]}"
    return message


def layer_report(mesh: GeoMesh) -> Report:
    """The quality report of a layer's triangles, in the CRS they were meshed in
    (segments: the polygons' boundary edges)."""
    from .report import mesh_report
    V = mesh.batch.vertices
    rep = mesh_report(V, mesh.triangles, segments=mesh.boundary_edges(), name="cdt_plugin")
    steiner = mesh.batch.stats.get("steiner")
    if steiner is not None:
        rep.steiner_vertices, rep.input_vertices = int(steiner), len(V) - int(steiner)
    rep.seconds = mesh.batch.stats.get("seconds")
    return rep


def _save_layer_plot(path: Path, mesh: GeoMesh, rep: Report) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from .plot import histogram, plot
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 5.5), width_ratios=[3, 2])
    try:
        # no circumcircles: at map scale a sliver's circle is huge (and slow to dash)
        plot((mesh.batch.vertices, mesh.triangles), axes[0], circumcircles=False,
             title=f"cdt_plugin: {len(mesh.triangles):,} triangles")
        histogram(rep, axes[1])
        fig.tight_layout()
        fig.savefig(path, dpi=120)
    finally:
        plt.close(fig)


# ----------------------------------------------------------------- commands
def _mesh_all(args: argparse.Namespace) -> tuple[list[Feature], list[Triangulation], Triangulation]:
    if getattr(args, "project", None) is not None:
        raise CLIError("--project applies to layer output (.gpkg or .geojson from a .shp, .gpkg "
                       "or .geojson layer)")
    features = read_input(Path(args.input), args.layer)
    options = _options(args)
    if args.plot is not None:
        _check_plot(args.plot)
    tris = triangulate_features(features, options, repair=args.repair, progress=args.progress,
                                workers=args.workers, errors=args.errors)
    for skipped in tris:
        if isinstance(skipped, CLIError):
            _warn(f"skipped {skipped}")
    kept = [(f, t) for f, t in zip(features, tris) if not isinstance(t, CLIError)]
    if not kept:
        raise CLIError(f"{args.input}: no feature could be meshed ({len(tris)} skipped)")
    meshed = [t for _, t in kept]
    return [f for f, _ in kept], meshed, concatenate(meshed)


def _check_plot(path: Path) -> None:
    _import("matplotlib", "--plot")
    if not path.parent.exists():
        raise CLIError(f"{path}: the directory {path.parent} does not exist")


def _save_plot(path: Path, combined: Triangulation, against: Any = None,
               against_name: str = "against") -> None:
    import matplotlib
    matplotlib.use("Agg")
    from .plot import save
    save(combined, path, against=against, against_name=against_name)


def _cmd_mesh(args: argparse.Namespace) -> int:
    output = Path(args.output)
    _check_output(output, args.extrude)
    _check_packages(args)
    if _layer_job(args):
        return _mesh_layer(args, output)
    if output.suffix.lower() in (".gpkg", ".parquet"):
        raise CLIError(f"{output}: {output.suffix.lower()} output needs a GIS layer input (.shp, "
                       ".gpkg, .parquet, .geojson, or a .json Feature or FeatureCollection)")
    features, tris, combined = _mesh_all(args)
    print(write_output(output, features, tris, combined, args.extrude))
    if args.report:
        print(combined.report())
    if args.plot is not None:
        _save_plot(args.plot, combined)
    return 0


def _against(spec: str, features: Sequence[Feature]) -> tuple[Any, str]:
    """(vertices, triangles, name) of the ``--against`` triangulation."""
    if spec == "earcut":
        if any(f.geometry is None for f in features):
            raise CLIError("--against earcut needs polygon input (.geojson, .json or .wkt)")
        from .report import earcut
        _import("mapbox_earcut", "--against earcut")
        collection = {"type": "GeometryCollection", "geometries": [f.geometry for f in features]}
        return earcut(collection), "earcut"
    path = Path(spec)
    if not path.exists():
        raise CLIError(f"--against {spec}: expected 'earcut' or an existing mesh file")
    trimesh = _import("trimesh", "--against MESH")
    mesh = trimesh.load(path, force="mesh", process=False)
    return (np.asarray(mesh.vertices), np.asarray(mesh.faces)), path.name


def _cmd_report(args: argparse.Namespace) -> int:
    _check_packages(args)
    features, tris, combined = _mesh_all(args)
    against, name = _against(args.against, features) if args.against else (None, "against")
    rep = combined.report(against=against, against_name=name)
    print(rep.to_json() if args.json else rep)
    if args.plot is not None:
        _save_plot(args.plot, combined, against, name)
    return 0


def _cmd_voronoi(args: argparse.Namespace) -> int:
    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix not in LAYER_OUTPUTS:
        raise CLIError(f"{output}: voronoi writes a layer: expected one of "
                       f"{', '.join(LAYER_OUTPUTS)}, got {suffix or '(no extension)'!r}")
    if not output.parent.exists():
        raise CLIError(f"{output}: the directory {output.parent} does not exist")
    _check_packages(args)
    inputs = [(Path(args.input), args.layer, "POINTS")]
    if args.boundary is not None:
        inputs.append((Path(args.boundary), args.boundary_layer, "--boundary"))
    elif args.boundary_layer is not None:
        raise CLIError("--boundary-layer needs --boundary")
    layer_formats = GIS_FORMATS + GEOJSON_FORMATS
    for k, (path, _, what) in enumerate(inputs):
        allowed = layer_formats + ((".node",) if k == 0 else ())
        if path.suffix.lower() not in allowed:
            got = path.suffix.lower() or "(no extension)"
            raise CLIError(f"{path}: {what} must be a layer: expected one of "
                           f"{', '.join(allowed)}, got {got!r}")
        if path.suffix.lower() == ".node" and args.layer is not None:
            raise CLIError(f"--layer applies to GIS layers (.gpkg, .shp), not {path.name}")
    reading = _bar(args.progress, "reading", "file", len(inputs))
    try:
        frames = []
        for path, layer, _ in inputs:
            frames.append(_node_points(path) if path.suffix.lower() == ".node" else read_layer(path, layer))
            if reading is not None:
                reading.update(1)
    finally:
        if reading is not None:
            reading.close()
    points = frames[0]
    boundary = frames[1] if len(frames) > 1 else None
    cells = _voronoi_layer(points, boundary, args)
    writing = _bar(args.progress, "writing", "cell", len(cells))
    try:
        _write_frame(output, cells, None if writing is None else writing.update)
    finally:
        if writing is not None:
            writing.close()
    geoms = np.asarray(cells.geometry.array, dtype=object)
    shapely = _import("shapely", "cdt-plugin voronoi")
    empty = int((shapely.is_missing(geoms) | shapely.is_empty(geoms)).sum())
    print(f"wrote {output}: {len(cells):,} cell(s)" + (f", {empty:,} empty" if empty else ""))
    return 0


def _node_points(path: Path) -> GeoDataFrame:
    """A Triangle ``.node`` file as a point layer without a CRS: its node numbers
    (``node``), attributes (``attribute_1``...) and boundary markers (``marker``)."""
    geopandas = _import("geopandas", "cdt-plugin voronoi")
    shapely = _import("shapely", "cdt-plugin voronoi")
    from . import io
    if not path.exists():
        raise CLIError(f"{path}: no such file")
    nodes = io.read_node(path)
    columns: dict[str, Any] = {"node": np.arange(len(nodes.vertices)) + nodes.first_index}
    for j in range(nodes.attributes.shape[1]):
        columns[f"attribute_{j + 1}"] = nodes.attributes[:, j]
    if nodes.markers is not None:
        columns["marker"] = nodes.markers
    return geopandas.GeoDataFrame(columns, geometry=shapely.points(nodes.vertices))


def _voronoi_layer(points: GeoDataFrame, boundary: GeoDataFrame | None,
                   args: argparse.Namespace) -> GeoDataFrame:
    """:func:`cdt_plugin.adapters.geo.voronoi` with the command's options; its
    warnings become ``cdt-plugin: warning:`` lines, its errors name the feature."""
    from .adapters import geo
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            cells = geo.voronoi(points, boundary, weights=args.weights)
        except CDTError as exc:
            raise CLIError(_layer_error(exc, points)) from None
    for w in caught:           # every warning as one line; the geographic one with a CLI hint
        _warn(str(w.message).replace("e.g. points.to_crs(points.estimate_utm_crs())",
                                     "e.g. with ogr2ogr -t_srs"))
    return cells


def _cmd_tin(args: argparse.Namespace) -> int:
    output = Path(args.output)
    suffix = output.suffix.lower()
    grids = (".tif", ".tiff", ".npy")
    if suffix not in LAYER_OUTPUTS + grids:
        raise CLIError(f"{output}: tin writes a layer ({', '.join(LAYER_OUTPUTS)}) or a grid "
                       f"({', '.join(grids)}), got {suffix or '(no extension)'!r}")
    if suffix in grids and (args.resolution is None or not args.resolution > 0):
        raise CLIError(f"{output}: a grid needs --resolution (a positive cell size)")
    if not output.parent.exists():
        raise CLIError(f"{output}: the directory {output.parent} does not exist")
    _check_packages(args)
    if suffix in (".tif", ".tiff"):
        _import("rasterio", "cdt-plugin tin -o *.tif")
    from .adapters import geo
    layers = [read_layer(Path(p), None) if p is not None else None
              for p in (args.input, args.breaklines, args.boundary)]
    try:
        surface = geo.tin(layers[0], layers[1], layers[2], z=args.z)
        if suffix in LAYER_OUTPUTS:
            _write_frame(output, surface, None)
            print(f"wrote {output}: {len(surface):,} triangle(s)")
            return 0
        dem, _ = geo.grid(surface, args.resolution, args.method,
                          path=output if suffix != ".npy" else None)
    except CDTError as exc:
        raise CLIError(str(exc)) from None
    if suffix == ".npy":
        np.save(output, dem)
    print(f"wrote {output}: {dem.shape[0]} x {dem.shape[1]} cells from {len(surface):,} triangle(s)")
    return 0


def _cmd_compile(args: argparse.Namespace) -> int:
    import logging
    import time

    from .compiling import cache_dir
    from .warmup import compile_routes
    logging.getLogger("cdt_plugin").setLevel(logging.ERROR)   # this command says it itself
    t0 = time.perf_counter()
    compile_routes(args.routes or None, report=print)
    print(f"all in {time.perf_counter() - t0:.1f} s; cached in {cache_dir()}")
    return 0


# --------------------------------------------------------------------- main
def _fail(message: str) -> int:
    line = " ".join(str(message).split())
    print(f"cdt-plugin: error: {line}", file=sys.stderr)
    return 1


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 error, 2 usage)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:          # --help, --version, usage errors
        return int(exc.code or 0)
    try:
        return args.func(args)
    except BrokenPipeError:            # the reader went away (| head): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except KeyboardInterrupt:
        _fail("interrupted")
        return 130
    except (CLIError, CDTError) as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        return _fail(f"{where}{exc.strerror or exc}")
    except (ValueError, TypeError, ImportError) as exc:
        return _fail(str(exc) or type(exc).__name__)
    except Exception as exc:           # never a traceback
        return _fail(f"unexpected {type(exc).__name__}: {exc}")


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
