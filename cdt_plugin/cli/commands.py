"""The five commands: ``mesh``, ``report``, ``voronoi``, ``tin`` and ``compile``.
Each takes the parsed arguments and returns the exit status; a problem is a
:class:`~cdt_plugin.cli.terminal.CLIError`."""
from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..compiling import cache_dir
from ..warmup import compile_routes
from ..errors import CDTError
from ..triangulation import Triangulation
from .formats import GEOJSON_FORMATS, GIS_FORMATS, GRID_OUTPUTS, LAYER_OUTPUTS, check_packages, \
    import_for, suffix_name
from .layers import is_layer_job, mesh_layer, voronoi_layer
from .meshing import concatenate, triangulate_features, triangulate_options, with_sizes_near
from .readers import Feature, read_input, read_layer, read_node_layer
from .terminal import CLIError, progress_bar, warn
from .writers import check_directory, check_output, check_plot, save_plot, write_frame, \
    write_output


def mesh_command(args: argparse.Namespace) -> int:
    """``cdt-plugin mesh``: triangulate INPUT and write the mesh."""
    output = Path(args.output)
    check_output(output, args.extrude)
    check_packages(args)
    if is_layer_job(args):
        return mesh_layer(args, output)
    if output.suffix.lower() in (".gpkg", ".parquet"):
        raise CLIError(f"{output}: {output.suffix.lower()} output needs a GIS layer input (.shp, "
                       ".gpkg, .parquet, .geojson, or a .json Feature or FeatureCollection)")
    features, tris, combined = _mesh_all(args)
    print(write_output(output, features, tris, combined, args.extrude))
    if args.report:
        print(combined.report())
    if args.plot is not None:
        save_plot(args.plot, combined)
    return 0


def report_command(args: argparse.Namespace) -> int:
    """``cdt-plugin report``: print the quality report of INPUT's triangulation."""
    check_packages(args)
    features, tris, combined = _mesh_all(args)
    against, name = _against(args.against, features) if args.against else (None, "against")
    rep = combined.report(against=against, against_name=name)
    print(rep.to_json() if args.json else rep)
    if args.plot is not None:
        save_plot(args.plot, combined, against, name)
    return 0


def _mesh_all(args: argparse.Namespace) -> tuple[list[Feature], list[Triangulation], Triangulation]:
    """The features of a per-feature input, their meshes (those that failed left
    out with ``--errors skip``) and the meshes joined."""
    if getattr(args, "project", None) is not None:
        raise CLIError("--project applies to layer output (.gpkg or .geojson from a .shp, .gpkg "
                       "or .geojson layer)")
    features = read_input(Path(args.input), args.layer)
    options = with_sizes_near(triangulate_options(args), args)
    if args.plot is not None:
        check_plot(args.plot)
    tris = triangulate_features(features, options, repair=args.repair, progress=args.progress,
                                workers=args.workers, errors=args.errors)
    for skipped in tris:
        if isinstance(skipped, CLIError):
            warn(f"skipped {skipped}")
    kept = [(f, t) for f, t in zip(features, tris) if not isinstance(t, CLIError)]
    if not kept:
        raise CLIError(f"{args.input}: no feature could be meshed ({len(tris)} skipped)")
    meshed = [t for _, t in kept]
    return [f for f, _ in kept], meshed, concatenate(meshed)


def _against(spec: str, features: Sequence[Feature]) -> tuple[Any, str]:
    """(vertices, triangles, name) of the ``--against`` triangulation."""
    if spec == "earcut":
        if any(f.geometry is None for f in features):
            raise CLIError("--against earcut needs polygon input (.geojson, .json or .wkt)")
        from ..report import earcut
        import_for("mapbox_earcut", "--against earcut")
        collection = {"type": "GeometryCollection", "geometries": [f.geometry for f in features]}
        return earcut(collection), "earcut"
    path = Path(spec)
    if not path.exists():
        raise CLIError(f"--against {spec}: expected 'earcut' or an existing mesh file")
    trimesh = import_for("trimesh", "--against MESH")
    loaded = trimesh.load(path, force="mesh", process=False)
    return (np.asarray(loaded.vertices), np.asarray(loaded.faces)), path.name


def voronoi_command(args: argparse.Namespace) -> int:
    """``cdt-plugin voronoi``: write the Voronoi cell of every point of a point layer."""
    output = Path(args.output)
    if output.suffix.lower() not in LAYER_OUTPUTS:
        raise CLIError(f"{output}: voronoi writes a layer: expected one of "
                       f"{', '.join(LAYER_OUTPUTS)}, got {suffix_name(output)!r}")
    check_directory(output)
    check_packages(args)
    inputs = [(Path(args.input), args.layer, "POINTS")]
    if args.boundary is not None:
        inputs.append((Path(args.boundary), args.boundary_layer, "--boundary"))
    elif args.boundary_layer is not None:
        raise CLIError("--boundary-layer needs --boundary")
    for k, (path, _, what) in enumerate(inputs):
        allowed = GIS_FORMATS + GEOJSON_FORMATS + ((".node",) if k == 0 else ())
        if path.suffix.lower() not in allowed:
            raise CLIError(f"{path}: {what} must be a layer: expected one of "
                           f"{', '.join(allowed)}, got {suffix_name(path)!r}")
        if path.suffix.lower() == ".node" and args.layer is not None:
            raise CLIError(f"--layer applies to GIS layers (.gpkg, .shp), not {path.name}")
    with progress_bar(args.progress, "reading", "file", len(inputs)) as step:
        frames = []
        for path, layer, _ in inputs:
            frames.append(read_node_layer(path) if path.suffix.lower() == ".node"
                          else read_layer(path, layer))
            if step is not None:
                step(1)
    cells = voronoi_layer(frames[0], frames[1] if len(frames) > 1 else None, args)
    with progress_bar(args.progress, "writing", "cell", len(cells)) as step:
        write_frame(output, cells, step)
    geoms = np.asarray(cells.geometry.array, dtype=object)
    shapely = import_for("shapely", "cdt-plugin voronoi")
    empty = int((shapely.is_missing(geoms) | shapely.is_empty(geoms)).sum())
    print(f"wrote {output}: {len(cells):,} cell(s)" + (f", {empty:,} empty" if empty else ""))
    return 0


def tin_command(args: argparse.Namespace) -> int:
    """``cdt-plugin tin``: the TIN of spot heights and breaklines, as a layer or a grid."""
    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix not in LAYER_OUTPUTS + GRID_OUTPUTS:
        raise CLIError(f"{output}: tin writes a layer ({', '.join(LAYER_OUTPUTS)}) or a grid "
                       f"({', '.join(GRID_OUTPUTS)}), got {suffix_name(output)!r}")
    if suffix in GRID_OUTPUTS and (args.resolution is None or not args.resolution > 0):
        raise CLIError(f"{output}: a grid needs --resolution (a positive cell size)")
    check_directory(output)
    check_packages(args)
    if suffix in (".tif", ".tiff"):
        import_for("rasterio", "cdt-plugin tin -o *.tif")
    from ..adapters import geo
    layers = [read_layer(Path(p), None) if p is not None else None
              for p in (args.input, args.breaklines, args.boundary)]
    try:
        surface = geo.tin(layers[0], layers[1], layers[2], z=args.z)
        if suffix in LAYER_OUTPUTS:
            write_frame(output, surface, None)
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


def compile_command(args: argparse.Namespace) -> int:
    """``cdt-plugin compile``: compile the routes now and fill numba's cache."""
    logging.getLogger("cdt_plugin").setLevel(logging.ERROR)   # this command says it itself
    t0 = time.perf_counter()
    compile_routes(args.routes or None, report=print)
    print(f"all in {time.perf_counter() - t0:.1f} s; cached in {cache_dir()}")
    return 0
