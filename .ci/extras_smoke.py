"""One small real call per extra, run inside a fresh virtual environment that has only
``cdt-plugin[EXTRA]`` installed (``.ci/check-extras``). Each check asserts on its result,
so a missing dependency or a broken adapter fails here."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np


def core():
    import importlib
    import importlib.util

    import cdt_plugin
    for name in ("shapely", "trimesh", "open3d", "geo"):      # packaged, importable with the extra
        assert importlib.util.find_spec(f"cdt_plugin.adapters.{name}") is not None, name
    # the adapters split into packages ship whole (looked up as files: importing one
    # of their modules would import the package, which needs its extra)
    adapters = Path(importlib.util.find_spec("cdt_plugin.adapters").submodule_search_locations[0])
    for module in ("layers.py", "geo/meshing.py", "geo/results.py", "shapely/reading.py",
                   "shapely/dropins.py"):
        assert (adapters / module).is_file(), module
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    assert len(tri.triangles) == 2 and tri.is_delaunay()
    # the engine's own subpackages ship whole: Triangle's file formats round-trip (cdt_plugin.io)
    from cdt_plugin import io
    with tempfile.TemporaryDirectory() as d:
        io.write_triangulation(Path(d, "square.ele"), tri)
        assert io.read_poly(Path(d, "square.poly")).to_plc().segments.shape == (4, 2)
        assert io.read_ele(Path(d, "square.ele")).triangles.tolist() == tri.triangles.tolist()
    # an adapter whose package is not installed names the extra to install
    for name, package, extra in (("shapely", "shapely", "shapely"), ("trimesh", "trimesh", "trimesh"),
                                 ("open3d", "open3d", "open3d"), ("geo", "shapely", "gis")):
        if importlib.util.find_spec(package) is not None:
            continue
        try:
            importlib.import_module(f"cdt_plugin.adapters.{name}")
        except ImportError as exc:
            assert f"pip install 'cdt-plugin[{extra}]'" in str(exc), exc
        else:
            raise AssertionError(f"cdt_plugin.adapters.{name} imported without {package}")


def shapely_():
    import shapely
    from cdt_plugin.adapters.shapely import constrained_delaunay_triangles
    out = constrained_delaunay_triangles(shapely.box(0, 0, 2, 2).difference(shapely.box(0.5, 0.5, 1, 1)))
    assert abs(shapely.area(out) - 3.75) < 1e-12, shapely.area(out)


def trimesh_():
    import shapely
    import trimesh
    from cdt_plugin.adapters import trimesh as adapter
    path = trimesh.load_path(shapely.box(0, 0, 2, 2).difference(shapely.box(0.5, 0.5, 1, 1)))
    plc = adapter.from_path2d(path)                       # Path2D needs networkx
    assert len(plc.segments) == 8, len(plc.segments)
    solids = adapter.extrude_path(path, 1.0)
    assert len(solids) == 1 and solids[0].is_watertight and abs(solids[0].volume - 3.75) < 1e-12


def open3d_():
    import open3d
    from cdt_plugin import triangulate
    from cdt_plugin.adapters.open3d import from_lineset, to_open3d
    ls = open3d.geometry.LineSet(open3d.utility.Vector3dVector([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]),
                                 open3d.utility.Vector2iVector([[0, 1], [1, 2], [2, 3], [3, 0]]))
    mesh = to_open3d(triangulate(from_lineset(ls)))
    assert len(mesh.triangles) == 2 and abs(mesh.get_surface_area() - 1.0) < 1e-12


def gis():
    import geopandas
    import shapely
    from cdt_plugin.adapters import geo
    frame = geopandas.GeoDataFrame({"name": ["a", "b"]},
                                   geometry=[shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 2)],
                                   crs="EPSG:3857")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "layer.geojson")
        frame.to_file(path)                                   # pyogrio
        tris = geo.triangulate(path, min_angle=20)
    assert abs(tris.area.sum() - 3.0) < 1e-9 and set(tris["name"]) == {"a", "b"}
    projected = geo.triangulate(frame.to_crs("EPSG:4326"), project="utm")   # pyproj
    assert len(projected) >= 4
    table = geo.triangulate(frame, output="geoarrow")                       # pyarrow
    back = geopandas.GeoDataFrame.from_arrow(table)
    assert len(back) == 4 and abs(back.area.sum() - 3.0) < 1e-12 and back.crs == frame.crs


def dask():
    import dask_geopandas
    import geopandas
    import shapely
    from cdt_plugin.adapters import geo
    frame = geopandas.GeoDataFrame(geometry=[shapely.box(i, 0, i + 1, 1) for i in range(4)],
                                   crs="EPSG:3857")
    lazy = geo.triangulate_dask(dask_geopandas.from_geopandas(frame, npartitions=2))
    tris = lazy.compute(scheduler="threads")
    assert len(tris) == 8 and abs(tris.area.sum() - 4.0) < 1e-12


def plot():
    import matplotlib
    matplotlib.use("Agg")
    import cdt_plugin
    tri = cdt_plugin.delaunay(np.random.default_rng(0).uniform(size=(50, 2)))
    ax = tri.plot()
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "mesh.png")
        ax.figure.savefig(out)
        assert os.path.getsize(out) > 1000


def cli():
    poly = {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]]]}
    with tempfile.TemporaryDirectory() as d:
        src, out = os.path.join(d, "square.geojson"), os.path.join(d, "square.ply")
        with open(src, "w") as f:
            json.dump(poly, f)
        subprocess.run(["cdt-plugin", "mesh", src, "-o", out, "--min-angle", "25"], check=True)
        import trimesh
        mesh = trimesh.load(out)
        assert abs(mesh.area - 16.0) < 1e-9, mesh.area


def fem():
    import meshio
    import cdt_plugin
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                                 segment_markers=[1, 2, 3, 4], max_area=0.5)
    with tempfile.TemporaryDirectory() as d:
        for name, fmt in (("m.msh", "gmsh"), ("m.vtu", "vtu"), ("m.xdmf", "xdmf")):  # (xdmf: h5py)
            meshio.write(os.path.join(d, name), tri.to_meshio(), file_format=fmt)
            back = meshio.read(os.path.join(d, name))
            assert sum(len(b.data) for b in back.cells if b.type == "triangle") == len(tri.triangles)
    mesh = tri.to_skfem()
    assert sorted(mesh.boundaries) == ["marker_1", "marker_2", "marker_3", "marker_4"], mesh


def bench():
    import manifold3d  # noqa: F401  (trimesh's engine, a peer)
    import mapbox_earcut
    import pythoncdt  # noqa: F401  (artem-ogre/CDT)
    import scipy.spatial
    import shapely
    import triangle
    import gmsh  # noqa: F401  (the sizing benchmark's peer)
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    assert len(triangle.triangulate({"vertices": square}, "Q")["triangles"]) == 2
    assert len(scipy.spatial.Delaunay(square).simplices) == 2
    assert len(mapbox_earcut.triangulate_float64(square, np.array([4], np.uint32))) == 6
    assert shapely.get_num_geometries(shapely.delaunay_triangles(shapely.multipoints(square))) == 2


def docs():
    # the documentation site, as CI builds it: warnings (griffe's docstring checks, broken
    # links and cross-references) are errors; built into a temporary folder, from the repo
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as site:
        subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", site],
                       cwd=repo, check=True)
        with open(os.path.join(site, "api", "adapters.shapely", "index.html"), encoding="utf-8") as f:
            page = f.read()
        assert 'id="cdt_plugin.adapters.shapely.triangulate"' in page   # adapters/ documented as installed
        for page in ("getting-started", "guides/quality", "gallery", "benchmarks/delaunay",
                     "development"):
            assert os.path.exists(os.path.join(site, *page.split("/"), "index.html")), page


def test():
    import hypothesis  # noqa: F401
    import pytest  # noqa: F401
    for check in (shapely_, trimesh_, open3d_, gis, dask, plot, fem):
        check()


CHECKS = {"core": core, "shapely": shapely_, "trimesh": trimesh_, "open3d": open3d_, "gis": gis,
          "dask": dask, "plot": plot, "cli": cli, "fem": fem, "bench": bench, "test": test, "docs": docs,
          "all": lambda: [c() for c in (shapely_, trimesh_, gis, dask, plot, cli, fem)]}

if __name__ == "__main__":
    extra = sys.argv[1]
    core()
    CHECKS[extra]()
    print(f"extra [{extra}]: ok")
