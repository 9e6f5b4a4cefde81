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

Solids: ``cdt-plugin extrude BUILDINGS --height COLUMN|H [--base COLUMN|Z] -o city.glb``
extrudes every polygon of a layer into a watertight solid
(:func:`cdt_plugin.adapters.geo.extrude`) and writes a glTF scene (``.glb`` /
``.gltf``: one node per feature, named by its index, its attributes as the node's
extras) or one merged mesh (``.ply``, ``.obj``, ``.stl``, ``.off``).

Errors are one line on stderr (``cdt-plugin: error: ...``) and exit status 1;
command-line usage errors exit with 2.

The package, top down: :mod:`~cdt_plugin.cli.parser` (the options),
:mod:`~cdt_plugin.cli.commands` (five commands), :mod:`~cdt_plugin.cli.extruding` (``extrude``),
:mod:`~cdt_plugin.cli.triangle` (Triangle's own command line), :mod:`~cdt_plugin.cli.layers`
(layer jobs through :mod:`cdt_plugin.adapters.geo`), :mod:`~cdt_plugin.cli.meshing`
(per-feature meshing), :mod:`~cdt_plugin.cli.readers` and :mod:`~cdt_plugin.cli.writers`
(one reader per input kind; the outputs), :mod:`~cdt_plugin.cli.formats` (extensions and
the optional packages they need) and :mod:`~cdt_plugin.cli.terminal` (errors, warnings
and progress bars on stderr).

>>> main(["report", "--help"])      # doctest: +ELLIPSIS
usage: cdt-plugin report [-h] ...
...
0
"""
from __future__ import annotations

import os
import sys
from typing import Sequence

from ..errors import CDTError
from .layers import layer_report
from .meshing import concatenate, triangulate_features
from .parser import build_parser
from .readers import Feature, is_layer, read_input, read_layer
from .terminal import CLIError, fail
from .writers import write_layer, write_output

__all__ = ["main", "build_parser", "read_input", "read_layer", "is_layer", "triangulate_features",
           "concatenate", "write_output", "write_layer", "layer_report", "Feature"]


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
        fail("interrupted")
        return 130
    except (CLIError, CDTError) as exc:
        return fail(str(exc))
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        return fail(f"{where}{exc.strerror or exc}")
    except (ValueError, TypeError, ImportError) as exc:
        return fail(str(exc) or type(exc).__name__)
    except Exception as exc:           # never a traceback
        return fail(f"unexpected {type(exc).__name__}: {exc}")
