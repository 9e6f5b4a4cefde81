"""``cdt-plugin extrude``: the polygons of a layer as solids
(:func:`cdt_plugin.adapters.geo.extrude`), written as a glTF scene with one node per
feature or as one merged mesh."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .formats import (
    GEOJSON_FORMATS,
    GIS_FORMATS,
    check_packages,
    import_for,
    suffix_name,
)
from .layers import layer_progress, run_on_layer
from .readers import read_layer
from .terminal import CLIError, progress_bar
from .writers import check_directory

SCENE_OUTPUTS = (".glb", ".gltf")
MERGED_OUTPUTS = (".ply", ".obj", ".stl", ".off")


def add_extrude_command(sub: argparse._SubParsersAction[argparse.ArgumentParser],
                        epilog: str, progress_options: Any, workers: Any) -> None:
    """The ``extrude`` subcommand and its options."""
    command = sub.add_parser(
        "extrude", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=epilog,
        help="extrude the polygons of a layer into solids (.glb city models)",
        description="Extrude every Polygon / MultiPolygon of LAYER into a watertight solid "
                    "from --base to --base + --height, and write the solids: .glb/.gltf (a "
                    "scene, one node per feature named by its index, its attributes as the "
                    "node's extras) or one merged mesh (.ply, .obj, .stl, .off).")
    command.add_argument("input", metavar="LAYER",
                         help="polygon layer: .gpkg, .shp, .parquet, .geojson/.json")
    command.add_argument("-o", "--output", required=True, type=Path, metavar="OUTPUT",
                         help="output: .glb or .gltf (one node per feature), or .ply, .obj, "
                              ".stl, .off (one merged mesh; PLY and STL hold float32 "
                              "coordinates, OBJ and OFF 17 decimals)")
    command.add_argument("--height", required=True, type=_column_or_number, metavar="COLUMN|H",
                         help="each solid's vertical extent: a numeric column of LAYER, or one "
                              "number for all (positive)")
    command.add_argument("--base", type=_column_or_number, default=0.0, metavar="COLUMN|Z",
                         help="the z of each solid's bottom: a numeric column or a number "
                              "(default 0)")
    command.add_argument("--layer", metavar="NAME",
                         help="the layer of a multi-layer input (GeoPackage): name or number")
    command.add_argument("--project", metavar="utm|aeqd|CRS",
                         help="extrude in the layer's UTM zone, an azimuthal equidistant "
                              "projection centred on it, or a projected CRS (e.g. EPSG:32633): "
                              "the solids' coordinates are in that CRS (for lon/lat layers)")
    command.add_argument("--repair", action="store_true",
                         help="repair invalid polygons with shapely.make_valid instead of failing")
    command.add_argument("--errors", choices=("raise", "skip"), default="raise",
                         help="a feature that cannot be extruded (invalid, not a polygon): stop "
                              "with its error (default), or leave it out and name it on stderr")
    command.add_argument("--workers", type=workers, metavar="N",
                         help="threads to mesh on (default: every core for many features)")
    progress_options(command, "always show a progress bar over the features (default: on a "
                              "terminal)")
    command.set_defaults(func=extrude_command)


def _column_or_number(text: str) -> str | float:
    """``--height`` / ``--base``: a number, or else a column name."""
    try:
        return float(text)
    except ValueError:
        return text


def extrude_command(args: argparse.Namespace) -> int:
    """``cdt-plugin extrude``: the layer's solids written to OUTPUT."""
    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix not in SCENE_OUTPUTS + MERGED_OUTPUTS:
        raise CLIError(f"{output}: extrude writes {', '.join(SCENE_OUTPUTS)} (one node per "
                       f"feature) or {', '.join(MERGED_OUTPUTS)} (one merged mesh), got "
                       f"{suffix_name(output)!r}")
    source = Path(args.input)
    if source.suffix.lower() not in GIS_FORMATS + GEOJSON_FORMATS:
        raise CLIError(f"{source}: LAYER must be a layer: expected one of "
                       f"{', '.join(GIS_FORMATS + GEOJSON_FORMATS)}, got {suffix_name(source)!r}")
    check_directory(output)
    check_packages(args)
    import_for("geopandas", "cdt-plugin extrude")
    with progress_bar(args.progress, "reading", "file", 1) as step:
        frame = read_layer(source, args.layer)
        if step is not None:
            step(1)
    from ..adapters import geo
    progress = layer_progress(args, frame)
    solids = run_on_layer(frame, source, "extruded", lambda: geo.extrude(
        frame, height=args.height, base=args.base, output="solids", project=args.project,
        repair=args.repair, errors=args.errors, progress=progress, workers=args.workers))
    with progress_bar(args.progress, "writing", "file", 1) as step:
        print(solids.write(output))
        if step is not None:
            step(1)
    return 0
