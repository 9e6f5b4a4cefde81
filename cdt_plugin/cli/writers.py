"""Writing the command's results: mesh files (trimesh), GeoJSON and Triangle's
files of the per-feature meshes, layers (GeoPackage, GeoParquet, GeoJSON), and
the ``--plot`` image."""
from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from .. import io
from ..fem import gmsh_tags_only
from .formats import FEM_FORMATS, GEOJSON_FORMATS, MESH_FORMATS, TRIANGLE_FORMATS, import_for, \
    suffix_name
from .readers import Feature
from .terminal import CLIError

if TYPE_CHECKING:
    import pyarrow
    from geopandas import GeoDataFrame

    from ..adapters.geo import GeoMesh
    from ..report import Report
    from ..triangulation import Triangulation

LAYER_ROWS = 50_000       # triangles per GeoPackage / GeoParquet write (and progress step)

Progress = Callable[[int], object]


def check_output(path: Path, extrude: float | None) -> str:
    """The output's extension, or CLIError for an unknown format, ``--extrude``
    to a format without solids or a missing directory."""
    suffix = path.suffix.lower()
    known = MESH_FORMATS + GEOJSON_FORMATS + TRIANGLE_FORMATS + FEM_FORMATS + (".gpkg", ".parquet")
    if suffix not in known:
        raise CLIError(f"{path}: unknown output format {suffix_name(path)!r}; expected one "
                       f"of {', '.join(known)}")
    if extrude is not None and suffix not in MESH_FORMATS:
        raise CLIError(f"--extrude makes a solid: write it to a mesh format "
                       f"({', '.join(MESH_FORMATS)}), not {suffix}")
    if extrude is not None and not (np.isfinite(extrude) and extrude != 0):
        raise CLIError(f"--extrude needs a finite nonzero height, got {extrude}")
    check_directory(path)
    return suffix


def check_directory(path: Path) -> None:
    """CLIError when the directory ``path`` is to be written in does not exist."""
    if not path.parent.exists():
        raise CLIError(f"{path}: the directory {path.parent} does not exist")


def write_output(path: Path, features: Sequence[Feature], tris: Sequence[Triangulation],
                 combined: Triangulation, extrude: float | None = None) -> str:
    """Write the mesh to ``path`` (format by extension); returns a one-line summary."""
    path = Path(path)
    suffix = check_output(path, extrude)
    if suffix in MESH_FORMATS:
        import_for("trimesh", f"writing {suffix}")
        from ..adapters.trimesh import extrude_triangulation
        mesh = combined.to_trimesh(remove_unreferenced=True)
        if extrude is not None:
            mesh = extrude_triangulation(mesh.vertices[:, :2], mesh.faces, extrude)
        # OBJ and OFF are text: 17 decimals keep the coordinates (trimesh's
        # PLY, STL and GLB writers store float32)
        digits: dict[str, Any] = {"digits": 17} if suffix in (".obj", ".off") else {}
        mesh.export(path, **digits)
        return f"wrote {path}: {len(mesh.vertices):,} vertices, {len(mesh.faces):,} triangles"
    if suffix in GEOJSON_FORMATS:
        shapely = import_for("shapely", "writing GeoJSON")
        from ..adapters.shapely import to_shapely
        out = {"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {**f.properties, "triangles": len(t.triangles)},
             "geometry": shapely.geometry.mapping(to_shapely(t, ccw=True))}
            for f, t in zip(features, tris)]}
        path.write_text(json.dumps(out), encoding="utf-8")
        return f"wrote {path}: {len(tris)} feature(s), {len(combined.triangles):,} triangles"
    if suffix in FEM_FORMATS:
        return write_fem(path, combined)
    base = path.with_suffix("")
    io.write_triangulation(path, combined, attributes=combined.regions if len(tris) > 1 else None)
    return (f"wrote {base}.node/.ele/.poly: {len(combined.vertices):,} vertices, "
            f"{len(combined.triangles):,} triangles, {len(combined.segments):,} segment edges")


def write_fem(path: Path, tri: Triangulation) -> str:
    """Write ``tri`` for finite-element codes through meshio
    (:meth:`~cdt_plugin.Triangulation.to_meshio`): ``.msh`` as gmsh 4.1 with the
    tags only (:func:`~cdt_plugin.fem.gmsh_tags_only`), or 2.2 when 4.1 cannot
    give every tagged entity a node of its own; ``.vtu``;
    ``.xdmf`` with its arrays in an HDF5 file beside it (``.h5``, needs h5py).
    Returns a one-line summary."""
    meshio = import_for("meshio", f"writing {path.suffix.lower()}")
    mesh = tri.to_meshio()
    suffix, version = path.suffix.lower(), ""
    if suffix == ".msh":
        mesh = gmsh_tags_only(mesh)
        entities = "gmsh:dim_tags" in mesh.point_data
        version = "gmsh 4.1" if entities else "gmsh 2.2"
        meshio.write(path, mesh, file_format="gmsh" if entities else "gmsh22")
    elif suffix == ".xdmf":
        import_for("h5py", "writing .xdmf")
        meshio.write(path, mesh, file_format="xdmf")
        version = f"and {path.with_suffix('.h5').name}"
    else:
        mesh.points = np.column_stack([mesh.points, np.zeros(len(mesh.points))])   # VTK's 3D
        meshio.write(path, mesh, file_format="vtu")
    lines = sum(len(block.data) for block in mesh.cells if block.type == "line")
    return (f"wrote {path}{f' ({version})' if version else ''}: {len(tri.vertices):,} vertices, "
            f"{len(tri.triangles):,} triangles, {lines:,} segment edges")


def write_layer(path: Path, triangles: GeoDataFrame | pyarrow.Table, mesh: GeoMesh,
                progress: Progress | None = None) -> str:
    """Write the triangles of ``mesh`` (a GeoDataFrame, or for ``.parquet`` its
    GeoArrow table, :meth:`~cdt_plugin.adapters.geo.GeoMesh.to_arrow`) with
    :func:`write_frame`. ``progress``: called with the number of triangles written
    since the last call. Returns a one-line summary."""
    path = Path(path)
    write_frame(path, triangles, progress)
    meshed = int(np.count_nonzero(np.diff(mesh.offsets)))
    return f"wrote {path}: {meshed} feature(s), {len(triangles):,} triangles"


def write_frame(path: Path, frame: GeoDataFrame | pyarrow.Table,
                progress: Progress | None = None) -> None:
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
        from ..adapters.geo import write_geojson
        write_geojson(frame, path, progress=progress)


def _write_parquet(path: Path, table: GeoDataFrame | pyarrow.Table,
                   progress: Progress | None = None) -> None:
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


def check_plot(path: Path) -> None:
    """CLIError when ``--plot`` cannot be drawn: no matplotlib, or no such directory."""
    import_for("matplotlib", "--plot")
    check_directory(path)


def save_plot(path: Path, combined: Triangulation, against: Any = None,
              against_name: str = "against") -> None:
    """Draw the mesh (and the ``--against`` one) and its angle histogram to ``path``."""
    _off_screen()
    from ..plot import save
    save(combined, path, against=against, against_name=against_name)


def save_layer_plot(path: Path, mesh: GeoMesh, rep: Report) -> None:
    """Draw a layer's triangles and their angle histogram to ``path``."""
    _off_screen()
    import matplotlib.pyplot as plt

    from ..plot import histogram, plot
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


def _off_screen() -> None:
    """matplotlib draws to files only (no window, no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
