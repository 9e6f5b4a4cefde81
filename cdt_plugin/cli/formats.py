"""The file formats the command line reads and writes (by extension), and the
optional packages they and the options need."""
from __future__ import annotations

import argparse
import importlib.util
from pathlib import Path
from typing import Any

from ..optional import MissingPackageError, missing, require
from .terminal import CLIError

MESH_FORMATS = (".ply", ".obj", ".stl", ".glb", ".off")
GEOJSON_FORMATS = (".geojson", ".json")
TRIANGLE_FORMATS = (".node", ".ele", ".poly")
GIS_FORMATS = (".shp", ".gpkg", ".parquet")
FEM_FORMATS = (".msh", ".vtu", ".xdmf")          # finite-element meshes, written by meshio
INPUT_FORMATS = (".poly", ".node", ".geojson", ".json", ".wkt") + GIS_FORMATS
LAYER_OUTPUTS = (".gpkg", ".parquet") + GEOJSON_FORMATS
GRID_OUTPUTS = (".tif", ".tiff", ".npy")


def suffix_name(path: Path) -> str:
    """The extension of ``path`` in lower case, or ``(no extension)`` (for messages)."""
    return path.suffix.lower() or "(no extension)"


def import_for(module: str, purpose: str) -> Any:
    """Import an optional package, or raise :class:`CLIError` naming the extra that brings it."""
    try:
        return require(module, purpose)
    except MissingPackageError as exc:
        raise CLIError(str(exc)) from None


def check_packages(args: argparse.Namespace) -> None:
    """The optional packages the options need, checked before anything is read or
    compiled (a missing one is an error naming the extra that brings it)."""
    needs = []
    output = getattr(args, "output", None)
    if output is not None:
        suffix = Path(output).suffix.lower()
        if suffix in MESH_FORMATS:
            needs.append(("trimesh", f"writing {suffix}"))
        elif suffix in GEOJSON_FORMATS:
            needs.append(("shapely", "writing GeoJSON"))
        elif suffix in FEM_FORMATS:
            needs.append(("meshio", f"writing {suffix}"))
            if suffix == ".xdmf":
                needs.append(("h5py", "writing .xdmf"))
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
