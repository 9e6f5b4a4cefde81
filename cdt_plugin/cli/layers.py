"""Layer in, layer out: the GIS adapter's jobs (:mod:`cdt_plugin.adapters.geo`)
run with the command's options, their warnings printed as ``cdt-plugin:
warning:`` lines and their errors naming the feature and the command's options."""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from ..errors import CDTError
from ..report import Report, mesh_report
from .formats import LAYER_OUTPUTS
from .meshing import near_layers, triangulate_options
from .readers import feature_label, is_layer, read_layer
from .terminal import CLIError, progress_bar, warn
from .writers import check_plot, save_layer_plot, write_layer

if TYPE_CHECKING:
    from geopandas import GeoDataFrame

    from ..adapters.geo import GeoMesh


def is_layer_job(args: argparse.Namespace) -> bool:
    """Layer in, layer out: meshed with the GIS adapter (one batch call)."""
    return Path(args.output).suffix.lower() in LAYER_OUTPUTS and is_layer(Path(args.input))


def mesh_layer(args: argparse.Namespace, output: Path) -> int:
    """The ``mesh`` command for a layer: its triangles written as a layer."""
    if args.intersections == "split":
        raise CLIError("--intersections split is for the per-feature formats: layer output "
                       "validates polygons (pass --repair to repair invalid ones)")
    if getattr(args, "smooth", None) is not None:
        raise CLIError("--smooth is for the per-feature formats: layer output meshes the "
                       "features in batches, which do not smooth")
    if args.plot is not None:
        check_plot(args.plot)
    with progress_bar(args.progress, "reading", "file", 1) as step:
        frame = read_layer(Path(args.input), args.layer)
        if step is not None:
            step(1)
    options = triangulate_options(args)
    near = near_layers(args)     # (reprojected to the meshing CRS by the adapter)
    if near:
        options["size_near"] = near
    mesh = _triangulate_layer(frame, args, options)
    # GeoParquet is written from the GeoArrow table: no shapely Polygon per triangle
    triangles = mesh.to_arrow() if output.suffix.lower() == ".parquet" else mesh.to_geodataframe()
    with progress_bar(args.progress, "writing", "triangle", len(triangles)) as step:
        print(write_layer(output, triangles, mesh, step))
    if args.report or args.plot is not None:
        rep = layer_report(mesh)
        if args.report:
            print(rep)
        if args.plot is not None:
            save_layer_plot(args.plot, mesh, rep)
    return 0


def _triangulate_layer(frame: GeoDataFrame, args: argparse.Namespace,
                       options: dict[str, Any]) -> GeoMesh:
    """:func:`cdt_plugin.adapters.geo.triangulate` (``output="mesh"``) with the
    command's options; its warnings become ``cdt-plugin: warning:`` lines."""
    from ..adapters import geo
    progress = layer_progress(args, frame)
    return run_on_layer(frame, args.input, "meshed", lambda: geo.triangulate(
        frame, output="mesh", project=args.project, repair=args.repair, errors=args.errors,
        progress=progress, workers=args.workers, **options))


def layer_progress(args: argparse.Namespace, frame: GeoDataFrame) -> bool:
    """``--progress`` / ``--no-progress``, or by default a bar on a terminal."""
    return args.progress if args.progress is not None else len(frame) > 1 and sys.stderr.isatty()


def run_on_layer(frame: GeoDataFrame, source: Any, done: str, call: Callable[[], Any]) -> Any:
    """``call()`` (a GIS adapter's job on ``frame`` whose result has ``errors``, row ->
    CDTError, with ``errors="skip"``): its errors naming the feature and the command's
    options, a warning line per skipped feature, an error when all were skipped, the
    geographic-CRS warning with the command's option names."""
    from ..adapters import geo
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = call()
        except CDTError as exc:
            raise CLIError(layer_error(exc, frame)) from None
    for i in sorted(result.errors):
        warn(f"skipped {layer_error(result.errors[i], frame)}")
    if result.errors and len(result.errors) == len(frame):
        raise CLIError(f"{source}: no feature could be {done} ({len(frame)} skipped)")
    for w in caught:
        if issubclass(w.category, geo.GeographicCRSWarning):
            warn(str(w.message).replace("pass project='utm', 'aeqd' or a projected CRS",
                                        "pass --project utm or --project aeqd"))
    return result


def voronoi_layer(points: GeoDataFrame, boundary: GeoDataFrame | None,
                  args: argparse.Namespace) -> GeoDataFrame:
    """:func:`cdt_plugin.adapters.geo.voronoi` with the command's options; its
    warnings become ``cdt-plugin: warning:`` lines, its errors name the feature."""
    from ..adapters import geo
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            cells = geo.voronoi(points, boundary, weights=args.weights)
        except CDTError as exc:
            raise CLIError(layer_error(exc, points)) from None
    for w in caught:           # every warning as one line; the geographic one with a CLI hint
        warn(str(w.message).replace("e.g. points.to_crs(points.estimate_utm_crs())",
                                    "e.g. with ogr2ogr -t_srs"))
    return cells


def layer_error(exc: CDTError, frame: GeoDataFrame) -> str:
    """The adapter's message with the feature's name and the command's option names."""
    message = str(exc).replace("pass repair=True to repair it with shapely.make_valid",
                               "pass --repair to repair it with shapely.make_valid")
    prefix = f"feature {exc.feature}:"
    if exc.index is not None and message.startswith(prefix):
        message = f"{feature_label(frame, exc.index)}:{message[len(prefix):]}"
    return message


def layer_report(mesh: GeoMesh) -> Report:
    """The quality report of a layer's triangles, in the CRS they were meshed in
    (segments: the polygons' boundary edges)."""
    V = mesh.batch.vertices
    rep = mesh_report(V, mesh.triangles, segments=mesh.boundary_edges(), name="cdt_plugin")
    steiner = mesh.batch.stats.get("steiner")
    if steiner is not None:
        rep.steiner_vertices, rep.input_vertices = int(steiner), len(V) - int(steiner)
    rep.seconds = mesh.batch.stats.get("seconds")
    return rep
