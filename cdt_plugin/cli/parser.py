"""The argument parser of the command line: the seven subcommands, their options
and the examples shown by ``--help``."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import NamedTuple

from .. import __version__
from ..compiling import ROUTES
from ..errors import CDTError
from ..nearness import check_near
from .commands import compile_command, mesh_command, report_command, tin_command, voronoi_command
from .extruding import add_extrude_command
from .triangle import add_triangle_command

EXAMPLES = """\
examples:
  cdt-plugin mesh letter.poly -o letter.ply
  cdt-plugin mesh countries.geojson -o countries.geojson --report
  cdt-plugin mesh countries.shp -o triangles.gpkg --project aeqd --min-angle 25 --repair --errors skip
  cdt-plugin mesh regions.gpkg --layer parcels -o parcels_mesh.gpkg
  cdt-plugin mesh countries.geojson -o countries.glb --extrude 0.5
  cdt-plugin mesh shape.wkt -o shape.stl --extrude 2 --plot shape.png
  cdt-plugin mesh A.poly -o A.ele --min-angle 30 --max-area 0.01
  cdt-plugin mesh A.poly -o A.msh --min-angle 30 --max-area 0.01   (gmsh, tagged by the markers)
  cdt-plugin mesh lake.gpkg -o lake_mesh.gpkg --size 200 --size-near rivers.gpkg:20:200:1000
  cdt-plugin voronoi shops.gpkg --boundary city.gpkg -o cells.gpkg
  cdt-plugin voronoi stations.shp --boundary country.geojson --weights power -o cells.geojson
  cdt-plugin extrude buildings.gpkg --height height -o city.glb
  cdt-plugin extrude buildings.shp --height 12 --base ground --project utm -o city.obj
  cdt-plugin tin points.gpkg --breaklines lines.gpkg -o dem.tif --resolution 10
  cdt-plugin report polygon.json --against earcut
  cdt-plugin report polygon.geojson --against other_mesh.obj --json
  cdt-plugin triangle -pq30a0.1 A.poly        (Triangle's own command line: writes A.1.node, A.1.ele...)
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (subcommands ``mesh``, ``report``, ``voronoi``, ``tin``, ``extrude``,
    ``triangle`` and ``compile``)."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(
        prog="cdt-plugin", formatter_class=fmt, epilog=EXAMPLES,
        description="Constrained Delaunay triangulation of polygon and PSLG files: "
                    "mesh them, report their quality, compare with other meshes.")
    parser.add_argument("--version", action="version", version=f"cdt-plugin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="{mesh,report,voronoi,tin,extrude,triangle,compile}", required=True)

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
    common.add_argument("--size", type=float, metavar="H",
                        help="size field: target edge length H everywhere (every triangle's "
                             "longest edge at most 1.5 H; in the meshing CRS's units)")
    common.add_argument("--size-near", type=size_near_arg, action="append",
                        metavar="PATH[:LAYER]:MIN:MAX:DIST",
                        help="size MIN on the geometries of PATH (points, lines, polygon "
                             "boundaries; LAYER: of a multi-layer file), growing linearly to MAX "
                             "at distance DIST from them; repeatable, and with --size the "
                             "smallest of all at every point")
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
                           ".node/.ele/.poly (Triangle: all three written), .msh (gmsh), "
                           ".vtu, .xdmf (finite-element codes, tagged by the markers; meshio), "
                           ".gpkg, .parquet; "
                           "from a layer (.shp/.gpkg/.parquet/.geojson) .gpkg, .parquet "
                           "(GeoParquet, the fastest) and .geojson get one feature per "
                           "triangle with the source attributes")
    mesh.add_argument("--merge-distance", type=float, metavar="D",
                      help="merge input points closer than D before meshing (lexicographic "
                           "order: a point goes to the nearest point kept before it)")
    mesh.add_argument("--smooth", choices=("odt", "lloyd"),
                      help="smooth the mesh after refinement: 10 iterations of ODT or Lloyd, "
                           "moving Steiner points only (per-feature inputs)")
    mesh.add_argument("--extrude", type=float, metavar="H",
                      help="extrude the mesh into a watertight solid of height H (mesh formats)")
    mesh.add_argument("--report", action="store_true", help="also print the quality report")
    mesh.add_argument("--project", metavar="utm|aeqd|CRS",
                      help="layer output: mesh in the layer's UTM zone, in an azimuthal "
                           "equidistant projection centred on it, or in a projected CRS "
                           "(e.g. EPSG:32633), and map the triangles back to the layer's CRS "
                           "(for lon/lat layers: angles and areas in metres)")
    mesh.set_defaults(func=mesh_command)

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
    rep.set_defaults(func=report_command)

    vor = _points_command(
        sub, "voronoi", help="write the Voronoi cell of every point of a point layer",
        description="The Voronoi cell (power cell with --weights) of every point of POINTS, "
                    "clipped to --boundary, written as a layer with one feature per point and "
                    "its attributes, in the points' CRS.",
        points="point layer: .gpkg, .shp, .parquet, .geojson/.json (Point geometries)",
        output="output layer: .gpkg, .parquet or .geojson/.json, one feature per point")
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
    vor.set_defaults(func=voronoi_command)

    tin = _points_command(
        sub, "tin", help="terrain from spot heights and breaklines: a TIN layer or a DEM",
        description="The TIN (constrained Delaunay triangulation) of the spot heights in POINTS, "
                    "with --breaklines as segments, clipped to --boundary; written as a layer of "
                    "3D triangles (.gpkg, .geojson), or sampled on a grid of --resolution as a "
                    "GeoTIFF (.tif, needs rasterio) or a NumPy array (.npy).",
        points="point layer: .gpkg, .shp, .parquet, .geojson/.json (Point Z, or --z COLUMN)",
        output="output: .gpkg, .parquet or .geojson/.json (the TIN), .tif or .npy (the grid)")
    tin.add_argument("--breaklines", type=Path, metavar="LINES",
                     help="line layer (LineString Z) the surface must follow")
    tin.add_argument("--boundary", type=Path, metavar="AREA",
                     help="polygon layer: the TIN covers its union only")
    tin.add_argument("--z", metavar="COLUMN", help="the heights are this numeric column of POINTS")
    tin.add_argument("--resolution", type=float, metavar="SIZE",
                     help="cell size of the grid (.tif, .npy), in the layer's units")
    tin.add_argument("--method", choices=("linear", "natural"), default="linear",
                     help="interpolation on the grid (default: linear)")
    tin.set_defaults(func=tin_command)

    add_extrude_command(sub, EXAMPLES, _progress_options, _workers_arg)
    add_triangle_command(sub)

    comp = sub.add_parser("compile", formatter_class=fmt,
                          help="compile every route ahead of time (Docker images, CI, Dask workers)",
                          description="Compile the engine's routes with numba now and fill the "
                                      "cache, so that no later process compiles; prints the "
                                      "seconds per route (a filled cache loads in well under one).")
    comp.add_argument("routes", nargs="*", metavar="ROUTE",
                      help=f"routes to compile (default: all of {', '.join(sorted(ROUTES))})")
    comp.set_defaults(func=compile_command)
    return parser


def _points_command(sub: argparse._SubParsersAction[argparse.ArgumentParser], name: str, *,
                    help: str, description: str, points: str,
                    output: str) -> argparse.ArgumentParser:
    """The subcommand ``name`` of a point layer POINTS, written to ``-o OUTPUT``."""
    command = sub.add_parser(name, formatter_class=argparse.RawDescriptionHelpFormatter,
                             epilog=EXAMPLES, help=help, description=description)
    command.add_argument("input", metavar="POINTS", help=points)
    command.add_argument("-o", "--output", required=True, type=Path, metavar="OUTPUT", help=output)
    return command


class NearSpec(NamedTuple):
    """One ``--size-near PATH[:LAYER]:MIN:MAX:DIST``, its numbers checked."""
    path: Path
    layer: str | None
    size_min: float
    size_max: float
    distance: float


def size_near_arg(text: str) -> NearSpec:
    """``--size-near PATH[:LAYER]:MIN:MAX:DIST`` (the last three are numbers; PATH may
    hold colons when it names a file that exists, as a drive letter does).

    >>> size_near_arg("rivers.gpkg:5:100:1000")
    NearSpec(path=PosixPath('rivers.gpkg'), layer=None, size_min=5.0, size_max=100.0, distance=1000.0)
    >>> size_near_arg("water.gpkg:rivers:5:100:1000").layer
    'rivers'
    >>> size_near_arg("rivers.gpkg:5:1:1000")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: size_near: size_max must be >= size_min, got size_max=1.0 < size_min=5.0
    """
    parts = text.rsplit(":", 3)
    if len(parts) != 4 or not parts[0]:
        raise argparse.ArgumentTypeError(f"expected PATH[:LAYER]:MIN:MAX:DIST, got {text!r}")
    numbers = []
    for name, value in zip(("MIN", "MAX", "DIST"), parts[1:]):
        try:
            numbers.append(float(value))
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number in PATH[:LAYER]:MIN:MAX:DIST, "
                                             f"got {value!r} in {text!r}") from None
    try:
        low, high, distance, _ = check_near(*numbers)
    except CDTError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    path, layer = parts[0], None
    if ":" in path and not Path(path).exists():
        path, layer = path.rsplit(":", 1)
    return NearSpec(Path(path), layer or None, low, high, float(distance))     # type: ignore[arg-type]


def _workers_arg(text: str) -> int:
    """``--workers N``: a whole number >= 1 (anything else is a usage error)."""
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
