"""Solids from a layer (``cdt_plugin.adapters.geo.extrude``) against the real geopandas,
pyproj and trimesh: watertight, consistently wound, volume = area x height, attributes
and CRS kept, the ``.glb`` read back by trimesh; the caps verified by the exact checker."""
from __future__ import annotations

import io
import json
import warnings

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
trimesh = pytest.importorskip("trimesh")
pytest.importorskip("pyproj")

import cdt_plugin.adapters.trimesh as ct
from cdt_plugin.adapters import geo
from cdt_plugin.adapters.geo.extruding import json_safe
from cdt_plugin.solids import split_pinches
from checker import assert_valid

from cdt_plugin import InvalidGeometryError, NoPolygonsError

X0, Y0 = 500_000.0, 5_000_000.0          # UTM 33N, metres

COURTYARD = shapely.Polygon([(0, 0), (30, 0), (30, 20), (0, 20)],
                            [[(5, 5), (5, 15), (25, 15), (25, 5)]])
# two holes touching at (10, 10): the boundary passes there twice
TWO_HOLES = shapely.Polygon([(0, 0), (20, 0), (20, 20), (0, 20)],
                            [[(4, 4), (4, 10), (10, 10), (10, 4)],
                             [(10, 10), (10, 16), (16, 16), (16, 10)]])
# a hole touching its shell at (0, 6)
HOLE_ON_SHELL = shapely.Polygon([(0, 0), (12, 0), (12, 12), (0, 12)], [[(0, 6), (5, 4), (5, 8)]])
# three holes meeting at (10, 10); two parts of a MultiPolygon touching at (5, 5)
THREE_HOLES = shapely.Polygon([(0, 0), (20, 0), (20, 20), (0, 20)],
                              [[(10, 10), (6, 4), (14, 4)], [(10, 10), (16, 12), (12, 16)],
                               [(10, 10), (8, 16), (4, 12)]])
TOUCHING_PARTS = shapely.MultiPolygon([shapely.box(0, 0, 5, 5), shapely.box(5, 5, 10, 10)])
L_SHAPE = shapely.Polygon([(0, 0), (20, 0), (20, 8), (8, 8), (8, 20), (0, 20)])
TWO_PARTS = shapely.MultiPolygon([shapely.box(-10, 0, -4, 4), COURTYARD])
FOOTPRINTS = [shapely.box(0, 0, 12, 9), L_SHAPE, COURTYARD, TWO_HOLES, HOLE_ON_SHELL, TWO_PARTS]


def city(**columns) -> gpd.GeoDataFrame:
    """The footprints moved to UTM coordinates, one block apart, with attributes."""
    geoms = [shapely.affinity.translate(g, X0 + 50 * k, Y0) for k, g in enumerate(FOOTPRINTS)]
    data = {"name": ["box", "L", "courtyard", "two holes", "hole on shell", "two parts"],
            "height": [12.5, 30.0, 7.25, 18.0, 3.0, 21.0],
            "base": [0.0, 2.0, -3.5, 0.0, 10.0, 1.0],
            "storeys": np.array([4, 10, 2, 6, 1, 7], dtype=np.int64),
            "built": gpd.pd.to_datetime(["1901-05-01", None, "1972-01-01", "2001-03-04",
                                         "1999-09-09", "2020-02-02"]),
            "rating": [np.nan, 1.5, 2.0, np.inf, 4.0, 5.0], **columns}
    return gpd.GeoDataFrame(data, geometry=geoms, crs="EPSG:32633",
                            index=[f"b{k}" for k in range(len(geoms))])


def local_volume(mesh) -> float:
    """The solid's volume computed near the origin (trimesh's sums lose digits at UTM offsets)."""
    moved = mesh.copy()
    moved.apply_translation(-mesh.vertices[0])
    return float(moved.volume)


def cap(mesh, z: float):
    """The faces of ``mesh`` at height ``z`` as a 2D triangulation, the copies of a
    pinch vertex made one point again (so the exact checker sees the footprint's mesh)."""
    V = np.asarray(mesh.vertices)
    F = np.asarray(mesh.faces)
    flat = F[(V[F][:, :, 2] == z).all(axis=1)]
    points, inverse = np.unique(V[:, :2], axis=0, return_inverse=True)
    T = inverse.ravel()[flat]
    return points, (T if doubled_areas(points, T).sum() > 0 else T[:, ::-1])


def doubled_areas(P, T):
    u, v = P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


def assert_solid(mesh, footprint, height, base):
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.is_volume                         # outward normals, a closed 2-manifold
    assert local_volume(mesh) == pytest.approx(footprint.area * height, rel=1e-9)
    z = np.unique(mesh.vertices[:, 2])
    assert z.tolist() == [base, base + height]
    for level in z:                               # both caps: the footprint's CDT
        points, T = cap(mesh, level)
        assert_valid(points, T, domain="segments",
                     segments=_ring_edges(points, footprint))
        assert doubled_areas(points, T).sum() / 2 == pytest.approx(footprint.area, rel=1e-12)


def _ring_edges(points, footprint):
    index = {tuple(p): k for k, p in enumerate(points.tolist())}
    edges = []
    for ring in shapely.get_rings(shapely.get_parts(footprint)):
        ids = [index[tuple(p)] for p in shapely.get_coordinates(ring).tolist()]
        edges += list(zip(ids[:-1], ids[1:]))
    return np.array(edges)


# ------------------------------------------------------------------ solids
def test_every_solid_watertight_with_volume_area_times_height():
    layer = city()
    solids = geo.extrude(layer, height="height", base="base")
    assert len(solids) == len(layer)
    for mesh, footprint, h, b in zip(solids, layer.geometry, layer["height"], layer["base"]):
        assert isinstance(mesh, trimesh.Trimesh)
        assert_solid(mesh, footprint, h, b)


def test_attributes_kept_json_safe():
    layer = city()
    solids = geo.extrude(layer, height="height")
    first, second = solids[0].metadata, solids[1].metadata
    assert first == {"feature": "b0", "name": "box", "height": 12.5, "base": 0.0, "storeys": 4,
                     "built": "1901-05-01T00:00:00", "rating": None}
    assert second["built"] is None and solids[3].metadata["rating"] is None      # NaT, inf
    assert type(first["storeys"]) is int
    json.loads(json.dumps([m.metadata for m in solids], allow_nan=False))


def test_pinch_points_split_like_the_trimesh_adapter():
    """Two or three holes touching at a vertex, a hole touching the shell, two parts
    touching at a corner: the same solid (vertices and faces as coordinates) as
    extrude_triangulation builds one by one."""
    for footprint in (TWO_HOLES, HOLE_ON_SHELL, THREE_HOLES, TOUCHING_PARTS):
        layer = gpd.GeoDataFrame({"h": [5.0]}, geometry=[footprint])
        (mesh,) = geo.extrude(layer, height="h")
        assert_solid(mesh, footprint, 5.0, 0.0)
        V, F = geo.triangulate(layer, output="mesh").feature_mesh(0)
        reference = ct.extrude_triangulation(V, F, 5.0)
        assert reference.is_watertight
        assert len(mesh.vertices) == len(reference.vertices) > 2 * len(V)    # one copy per fan
        assert _face_set(mesh) == _face_set(reference)


def _face_set(mesh):
    corners = np.asarray(mesh.vertices)[np.asarray(mesh.faces)]
    return {tuple(map(tuple, np.roll(f, -int(np.lexsort(f.T[::-1])[0]), axis=0))) for f in corners}


def test_split_pinches_leaves_a_plain_mesh_alone():
    V = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    T = np.array([[0, 1, 2], [0, 2, 3]])
    V2, T2 = split_pinches(V, T)
    assert V2 is V and T2 is T


def test_merged_mesh_and_crs():
    layer = city()
    merged = geo.extrude(layer, height="height", base="base", output="merged")
    assert merged.is_watertight and merged.is_winding_consistent
    assert merged.body_count == len(layer) + 1                 # the MultiPolygon: two bodies
    expected = float((layer.area * layer["height"]).sum())
    assert local_volume(merged) == pytest.approx(expected, rel=1e-9)
    assert merged.metadata["crs"] == layer.crs.to_wkt()
    solids = geo.extrude(layer, height="height", output="solids")
    assert solids.crs == layer.crs and solids.source is layer
    assert len(solids.vertices) == len(merged.vertices)


def test_scene_written_to_glb_and_read_back(tmp_path):
    layer = city()
    scene = geo.extrude(layer, height="height", base="base", output="scene")
    assert sorted(scene.graph.nodes_geometry) == sorted(layer.index)
    path = tmp_path / "city.glb"
    summary = geo.extrude(layer, height="height", base="base", output="solids").write(path)
    assert summary.startswith(f"wrote {path}: 6 solid(s)")
    back = trimesh.load(path)
    assert isinstance(back, trimesh.Scene)
    assert sorted(back.graph.nodes_geometry) == sorted(layer.index)
    assert back.metadata["crs"] == layer.crs.to_wkt()
    edges = back.graph.transforms.edge_data
    for node in back.graph.nodes_geometry:
        parent = back.graph.transforms.parents[node]
        extras = edges[(parent, node)]["metadata"]
        row = layer.loc[node]
        assert extras["feature"] == node and extras["name"] == row["name"]
        assert extras["height"] == row["height"] and extras["storeys"] == row["storeys"]
        transform, geometry = back.graph[node]
        mesh = back.geometry[geometry].copy()
        mesh.apply_transform(transform)                # float32 vertices, float64 translation
        footprint = row.geometry
        assert mesh.is_watertight
        assert np.abs(mesh.bounds[0, :2] - footprint.bounds[:2]).max() < 1e-3
        assert local_volume(mesh) == pytest.approx(footprint.area * row["height"], rel=1e-5)


def test_glb_extras_are_standard_json(tmp_path):
    path = tmp_path / "city.glb"
    geo.extrude(city(), height="height", output="solids").write(path)
    data = path.read_bytes()
    length = int.from_bytes(data[12:16], "little")            # the JSON chunk of the GLB
    header = json.loads(data[20:20 + length], parse_constant=_refuse)
    nodes = [n for n in header["nodes"] if "extras" in n]
    assert len(nodes) == 6 and {n["name"] for n in nodes} == {f"b{k}" for k in range(6)}


def _refuse(name):
    raise AssertionError(f"non-standard JSON constant {name} in the glTF header")


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".stl", ".off"])
def test_write_one_merged_mesh(tmp_path, suffix):
    layer = city()
    path = tmp_path / f"city{suffix}"
    solids = geo.extrude(layer, height="height", output="solids")
    solids.write(path)
    # as written: STL has no shared vertices (a triangle soup), the others share them
    # (and keep the copies of a pinch vertex apart, which merging would undo)
    back = trimesh.load(path, force="mesh", process=suffix == ".stl")
    assert len(back.faces) == len(solids.faces)
    if suffix != ".stl":
        assert len(back.vertices) == len(solids.vertices) and back.is_watertight
    volume = float((layer.area * layer["height"]).sum())
    assert local_volume(back) == pytest.approx(volume, rel=1e-9 if suffix in (".obj", ".off") else 1e-4)


def test_geographic_layer_projected_like_triangulate():
    layer = city().to_crs("EPSG:4326")
    with pytest.warns(geo.GeographicCRSWarning):
        geo.extrude(layer.iloc[:1], height="height")
    solids = geo.extrude(layer, height="height", project="utm", output="solids")
    assert solids.crs == layer.estimate_utm_crs() and solids.crs.to_epsg() == 32633
    # the same meshing CRS as geo.triangulate picks (the hole touching its shell left out:
    # mapping its triangles back to degrees folds one, which extrude does not do)
    assert geo.triangulate(layer.drop(index="b4"), project="utm", output="mesh").mesh_crs == solids.crs
    projected = layer.to_crs(solids.crs)
    for i, (footprint, h) in enumerate(zip(projected.geometry, layer["height"])):
        V, F = solids.solid(i)
        solid = trimesh.Trimesh(V, F, process=False)
        assert solid.is_watertight
        # the footprint's own vertices, as geo.triangulate projects them, bit for bit
        corners = {tuple(p) for p in shapely.get_coordinates(footprint).tolist()}
        assert corners <= {tuple(p) for p in V[:, :2].tolist()}
        assert local_volume(solid) == pytest.approx(footprint.area * h, rel=1e-9)


# ------------------------------------------------------------------ heights
def test_height_number_array_and_base_column():
    layer = city()
    a = geo.extrude(layer, height=4.0, base="base", output="solids")
    b = geo.extrude(layer, height=np.full(len(layer), 4.0), base=layer["base"], output="solids")
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    for i, base in enumerate(layer["base"]):
        V, _ = a.solid(i)
        assert sorted(set(V[:, 2])) == [base, base + 4.0]


@pytest.mark.parametrize("height, base, words", [
    ("floors", 0.0, ["height='floors'", "no such attribute column", "name, height"]),
    ("name", 0.0, ["height='name'", "not numeric"]),
    ("height", "missing", ["base='missing'", "no such attribute column"]),
    (-1.0, 0.0, ["positive and finite", "6 feature(s)", "feature b0 (-1.0)", "and 1 more"]),
    (0.0, 0.0, ["positive and finite"]),
    ([1, 2, 3], 0.0, ["one number per feature (6)", "(3,)"]),
    ("text", 0.0, ["no such attribute column"]),
    (True, 0.0, ["must be a number"]),
    ({"a": 1}, 0.0, ["must be a number"]),
    (5.0, np.inf, ["base must be finite"]),
])
def test_bad_heights_named_before_any_work(height, base, words):
    layer = city()
    layer.loc["b2", "geometry"] = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])   # invalid
    with pytest.raises(geo.HeightError) as info:
        geo.extrude(layer, height=height, base=base)
    for word in words:
        assert word in str(info.value)


def test_nan_and_negative_height_name_the_feature():
    layer = city()
    layer.loc["b3", "height"] = np.nan
    with pytest.raises(geo.HeightError, match=r"1 feature\(s\) are not: feature b3 \(nan\)") as info:
        geo.extrude(layer, height="height")
    assert info.value.feature == "b3" and info.value.index == 3
    layer.loc["b3", "height"] = -2.0
    with pytest.raises(geo.HeightError, match=r"feature b3 \(-2.0\)"):
        geo.extrude(layer, height="height")


# ------------------------------------------------------------------ features
def test_points_and_lines_named_or_skipped():
    layer = city()
    layer.loc["b1", "geometry"] = shapely.Point(X0, Y0)
    layer.loc["b4", "geometry"] = shapely.LineString([(X0, Y0), (X0 + 5, Y0)])
    with pytest.raises(geo.NotPolygonalError, match="feature b1: no polygon to extrude .*Point"):
        geo.extrude(layer, height="height")
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"2 feature\(s\) .*\(b1, b4\)"):
        solids = geo.extrude(layer, height="height", errors="skip", output="solids")
    out = solids.to_trimesh()
    assert out[1] is None and out[4] is None and all(out[k] is not None for k in (0, 2, 3, 5))
    assert sorted(solids.errors) == [1, 4]
    assert isinstance(solids.errors[1], InvalidGeometryError)
    assert len(solids.to_scene().graph.nodes_geometry) == 4


def test_invalid_polygon_named_or_skipped():
    layer = city()
    layer.loc["b2", "geometry"] = shapely.Polygon([(X0, Y0), (X0 + 2, Y0 + 2), (X0 + 2, Y0),
                                                   (X0, Y0 + 2)])
    with pytest.raises(InvalidGeometryError, match="^feature b2:"):
        geo.extrude(layer, height="height")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", geo.SkippedFeaturesWarning)
        out = geo.extrude(layer, height="height", errors="skip")
    assert out[2] is None and out[3].is_watertight


def test_no_polygons_and_bad_output():
    points = gpd.GeoDataFrame({"h": [1.0]}, geometry=[shapely.Point(0, 0)])
    with pytest.raises(NoPolygonsError):
        geo.extrude(points, height="h")
    with pytest.raises(geo.CDTError, match="output must be one of"):
        geo.extrude(city(), height="height", output="glb")
    with pytest.raises(geo.CDTError, match="expected one of .glb"):
        geo.extrude(city(), height="height", output="solids").write("city.dxf")


def test_json_safe_values():
    import pandas

    assert json_safe(np.float64("nan")) is None and json_safe(pandas.NA) is None
    assert json_safe(np.bool_(True)) is True and json_safe(np.int32(7)) == 7
    assert json_safe(shapely.Point(1, 2)) == "POINT (1 2)"
    assert json_safe([np.int8(1), float("inf")]) == [1, None]
    assert json_safe(pandas.Timestamp("2020-01-02", tz="UTC")) == "2020-01-02T00:00:00+00:00"


def test_layer_assign_pairs_rows_with_their_solids():
    layer = city()
    with_solids = layer.assign(solid=geo.extrude(layer, height="height"))
    assert [m.metadata["feature"] for m in with_solids["solid"]] == list(layer.index)


def test_glb_bytes_round_trip_in_memory():
    scene = geo.extrude(city(), height="height", output="scene")
    back = trimesh.load(io.BytesIO(scene.export(file_type="glb")), file_type="glb")
    assert len(back.graph.nodes_geometry) == 6


def test_example_city_blocks(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    png = tmp_path / "city.png"
    done = subprocess.run([sys.executable, str(root / "examples" / "city_blocks.py"), str(png)],
                          capture_output=True, text=True, cwd=root, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "8 solids" in done.stdout and "all watertight" in done.stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_scene_node_names_unique_when_labels_repeat():
    layer = city()
    layer.index = ["a", "a", "b", "c", "c", "d"]
    scene = geo.extrude(layer, height="height", output="scene")
    assert sorted(scene.graph.nodes_geometry) == ["a#0", "a#1", "b#2", "c#3", "c#4", "d#5"]
