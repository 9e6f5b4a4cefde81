"""GIS adapter (``cdt_plugin.adapters.geo``) against the real geopandas, pyogrio,
pyproj, trimesh and dask.distributed (no mocks). Every mesh is verified by the
exact checker; the command line and the examples run as subprocesses."""
from __future__ import annotations

import doctest
import importlib
import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyogrio")
pytest.importorskip("pyproj")

from cdt_plugin import InvalidGeometryError  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402
from cdt_plugin.adapters.layers import json_value  # noqa: E402

from checker import assert_valid, canonical_triangles  # noqa: E402
from corpus import corpus_dir  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
LOWRES = corpus_dir() / "gis" / "naturalearth_lowres.geojson"
needs_corpus = pytest.mark.skipif(not LOWRES.exists(), reason="corpus not found")
CENTRAL_EUROPE = ["Germany", "Poland", "Czechia", "Austria", "Switzerland", "Hungary", "Slovakia"]

# lon/lat layers warn (tested below); elsewhere the warning is expected noise
pytestmark = pytest.mark.filterwarnings("ignore::cdt_plugin.adapters.geo.GeographicCRSWarning")


@pytest.fixture(scope="module")
def countries():
    return gpd.read_file(LOWRES)


# ------------------------------------------------------------------ helpers
def input_segments(V, geometry) -> np.ndarray:
    """The ring edges of ``geometry`` as index pairs into ``V`` (exact coordinates);
    a KeyError means an input vertex is missing from the mesh."""
    index = {(x, y): k for k, (x, y) in enumerate(np.asarray(V)[:, :2].tolist())}
    segments = []
    for ring in shapely.get_rings(shapely.get_parts(geometry)):
        ids = [index[(x, y)] for x, y in shapely.get_coordinates(ring).tolist()]
        segments += [(a, b) for a, b in zip(ids[:-1], ids[1:]) if a != b]
    return np.array(segments, dtype=np.int64)


def boundary_edges(T) -> np.ndarray:
    """Edges used by one triangle: the segment pieces of a refined polygon mesh."""
    e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    return uniq[count == 1]


def verify_feature(mesh, i, geometry, refined=False):
    """The exact checker on feature ``i`` of a GeoMesh: a simplicial complex, bounded
    by segments, every other edge locally Delaunay; unrefined: every input vertex
    present and every input ring edge an edge."""
    V, T = mesh.feature_mesh(i)
    segments = boundary_edges(T) if refined else input_segments(V, geometry)
    return assert_valid(V[:, :2], T, segments=segments, domain="segments")


def min_angles(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    out = []
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = q - p, r - p
        out.append(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(axis=1)))
    return np.degrees(np.min(out, axis=0))


def triangle_sets(triangles, key="position") -> dict:
    """Per feature (by ``key`` column) the set of triangles as sorted coordinate triples."""
    corners = shapely.get_coordinates(triangles.geometry.array).reshape(-1, 4, 2)[:, :3]
    out: dict = {}
    for k, tri in zip(triangles[key].tolist(), corners.tolist()):
        out.setdefault(k, set()).add(tuple(sorted(map(tuple, tri))))
    return out


def feature_areas(triangles, n) -> np.ndarray:
    return np.bincount(triangles["position"].to_numpy(), minlength=n,
                       weights=shapely.area(triangles.geometry.array))


def run_cli(*args, check=True):
    """``python -m cdt_plugin ARGS`` in a fresh process (``check``: it must succeed)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "cdt_plugin", *map(str, args)], capture_output=True,
                          text=True, env=env, timeout=300)
    assert "Traceback" not in proc.stderr, proc.stderr
    assert proc.returncode == 0 or not check, proc.stderr
    return proc


# -------------------------------------------------------------------- tests
def test_docstring_examples():
    result = doctest.testmod(geo)
    assert result.attempted >= 15 and result.failed == 0


@needs_corpus
def test_countries_keep_attributes_crs_and_features(countries):
    mesh = geo.triangulate(countries, output="mesh")
    tris = mesh.to_geodataframe()
    attrs = [c for c in countries.columns if c != "geometry"]
    assert list(tris.columns) == ["feature", "position", "part", *attrs, "geometry"]
    assert tris.crs == countries.crs and len(tris) == 9791
    pos = tris["position"].to_numpy()
    assert (tris["feature"].to_numpy() == countries.index.to_numpy()[pos]).all()
    for column in attrs:
        assert tris[column].reset_index(drop=True).equals(
            countries[column].iloc[pos].reset_index(drop=True)), column
    source = countries.geometry.to_numpy()
    parts = shapely.get_num_geometries(source)
    assert (tris["part"].to_numpy() < parts[pos]).all()
    assert (np.diff(pos) >= 0).all() and set(pos) == set(range(len(countries)))
    triangles = tris.geometry.to_numpy()
    assert shapely.covers(source[pos], triangles).all()           # every triangle in its feature
    assert shapely.is_ccw(shapely.get_exterior_ring(triangles)).all()
    np.testing.assert_allclose(feature_areas(tris, len(countries)), shapely.area(source), rtol=1e-9)
    for i, geometry in enumerate(source):                          # the exact checker, every country
        verify_feature(mesh, i, geometry)



def _bits(geometries, include_z):
    return shapely.get_coordinates(np.asarray(geometries, dtype=object), include_z=include_z)


@needs_corpus
def test_geoarrow_output_is_the_geodataframe_without_shapely_objects(countries, tmp_path):
    """output="geoarrow": the rows, columns, CRS and coordinates (bit for bit) of the
    GeoDataFrame output, read back by geopandas and through a GeoParquet file."""
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    layer = countries[countries["continent"] == "Africa"].set_index("name")   # South Africa: a hole
    mesh = geo.triangulate(layer, output="mesh")
    table = geo.triangulate(layer, output="geoarrow")
    frame = mesh.to_geodataframe()
    assert isinstance(table, pa.Table) and table.num_rows == len(frame) == len(mesh)
    assert table.column_names == list(frame.columns)
    field = table.schema.field("geometry")
    assert field.metadata[b"ARROW:extension:name"] == b"geoarrow.polygon"
    assert json.loads(field.metadata[b"ARROW:extension:metadata"])["crs"] == layer.crs.to_json_dict()
    back = gpd.GeoDataFrame.from_arrow(table)
    assert back.crs == layer.crs
    for column in frame.columns.drop("geometry"):
        assert back[column].tolist() == frame[column].tolist(), column
    assert not back.has_z.any()
    assert np.array_equal(_bits(back.geometry, False), _bits(frame.geometry, False))
    assert shapely.is_ccw(shapely.get_exterior_ring(back.geometry.to_numpy())).all()
    for i, geometry in enumerate(layer.geometry.to_numpy()):        # the exact checker
        verify_feature(mesh, i, geometry)
    pq.write_table(table, tmp_path / "triangles.parquet")
    again = gpd.read_parquet(tmp_path / "triangles.parquet")
    assert np.array_equal(_bits(again.geometry, False), _bits(frame.geometry, False))


def test_geoarrow_output_with_z_and_renamed_id_columns():
    """A layer with Z gives xyz coordinates (z 0 for a feature without Z, as GeoMesh.z);
    source columns named like the id columns move them to cdt_*; a MultiPolygon's part
    and a missing geometry are kept as in the GeoDataFrame output."""
    pa = pytest.importorskip("pyarrow")
    surface = shapely.Polygon([(x, y, plane(x, y)) for x, y in [(0, 0), (4, 0), (4, 3), (0, 3)]])
    parts = shapely.MultiPolygon([shapely.box(10, 0, 11, 1), shapely.box(12, 0, 13, 1)])
    layer = gpd.GeoDataFrame({"part": ["a", "b", "c"]}, geometry=[surface, None, parts],
                             crs="EPSG:32633")
    mesh = geo.triangulate(layer, output="mesh", max_area=1.0)
    table = mesh.to_arrow()
    assert table.column_names == ["cdt_feature", "cdt_position", "cdt_part", "part", "geometry"]
    assert pa.types.is_fixed_size_list(table.schema.field("geometry").type.value_type.value_type)
    back = gpd.GeoDataFrame.from_arrow(table)
    frame = mesh.to_geodataframe()
    for column in ["cdt_feature", "cdt_position", "cdt_part", "part"]:
        assert back[column].tolist() == frame[column].tolist(), column
    xyz = _bits(back.geometry, True)
    on_surface = np.repeat(back["cdt_position"].to_numpy() == 0, 4)
    assert np.array_equal(xyz[:, :2], _bits(frame.geometry, False))
    np.testing.assert_allclose(xyz[on_surface, 2], plane(xyz[on_surface, 0], xyz[on_surface, 1]),
                               rtol=1e-12, atol=1e-12)
    assert (xyz[~on_surface, 2] == 0).all()
    assert sorted(set(back["cdt_part"][back["cdt_position"] == 2])) == [0, 1]
    verify_feature(mesh, 0, surface, refined=True)



def test_geoarrow_output_keeps_every_attribute_type(tmp_path):
    """Dates, categories, missing values and a second geometry column (WKB, its own CRS)
    come back from the GeoArrow table and from its GeoParquet file as the GeoDataFrame
    output has them; a MultiIndex's labels as a struct of its levels."""
    pytest.importorskip("pyarrow")
    import pandas as pd
    import pyarrow.parquet as pq
    layer = gpd.GeoDataFrame(
        {"when": pd.to_datetime(["2020-01-01", None]), "kind": pd.Categorical(["a", "b"]),
         "note": ["x", None],
         "centroid": gpd.GeoSeries([shapely.Point(1, 1), None], crs="EPSG:4326")},
        geometry=[shapely.box(0, 0, 2, 2), shapely.box(3, 3, 4, 5)], crs="EPSG:3857",
        index=pd.MultiIndex.from_tuples([("a", 0), ("a", 1)], names=["region", None]))  # (explode's)
    mesh = geo.triangulate(layer, output="mesh")
    expected = mesh.to_geodataframe()
    pq.write_table(mesh.to_arrow(), tmp_path / "t.parquet")
    for back in (gpd.GeoDataFrame.from_arrow(mesh.to_arrow(), geometry="geometry"),
                 gpd.read_parquet(tmp_path / "t.parquet")):
        assert list(back.columns) == list(expected.columns)
        assert [(f["region"], f["level_1"]) for f in back["feature"]] == expected["feature"].tolist()
        assert back["when"].tolist() == expected["when"].tolist()
        assert back["kind"].tolist() == ["a", "a", "b", "b"] == expected["kind"].tolist()
        assert back["note"].tolist() == expected["note"].tolist()
        assert back["centroid"].array.crs == layer["centroid"].crs
        assert back["centroid"].tolist() == expected["centroid"].tolist()
        assert back.crs == layer.crs and back.geometry.name == "geometry"
        assert np.array_equal(_bits(back.geometry, False), _bits(expected.geometry, False))
    for i, geometry in enumerate(layer.geometry.to_numpy()):        # the exact checker
        verify_feature(mesh, i, geometry)

def test_geoarrow_output_needs_pyarrow_before_any_work(monkeypatch):
    import importlib
    real = importlib.import_module

    def without_pyarrow(name, *args):
        if name == "pyarrow":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return real(name, *args)

    monkeypatch.setattr(importlib, "import_module", without_pyarrow)
    from cdt_plugin.optional import MissingPackageError
    with pytest.raises(MissingPackageError, match=r"needs pyarrow: pip install 'cdt-plugin\[gis\]'"):
        geo.triangulate({"type": "no layer at all"}, output="geoarrow")

@needs_corpus
def test_geojson_dict_path_geopackage_and_shapefile_inputs(tmp_path, countries):
    layer = countries[countries["continent"] == "Africa"]          # South Africa has a hole
    expected = triangle_sets(geo.triangulate(layer))
    geo.write_geojson(layer, tmp_path / "africa.geojson")
    layer.to_file(tmp_path / "africa.gpkg", layer="africa")
    countries.head(3).to_file(tmp_path / "africa.gpkg", layer="other")
    layer.to_file(tmp_path / "africa.shp")
    inputs = {"dict": (json.loads(layer.to_json()), None),
              "geojson": (str(tmp_path / "africa.geojson"), None),
              "gpkg": (tmp_path / "africa.gpkg", "africa"),
              "shp": (tmp_path / "africa.shp", None)}
    for kind, (data, name) in inputs.items():
        tris = geo.triangulate(data, layer=name)
        assert tris.crs.to_epsg() == 4326, kind
        assert triangle_sets(tris) == expected, kind                # same triangles, feature by feature
        names = tris.groupby("position")["name"].first()
        assert names.tolist() == layer["name"].tolist(), kind       # attributes kept
        assert "pop_est" in tris and "gdp_md_est" in tris, kind


def plane(x, y):
    return 0.25 * x - 0.5 * y + 3.0


def test_z_kept_on_input_vertices_and_interpolated_on_steiner_vertices():
    shell = [(0, 0), (8, 0), (8, 6), (4, 9), (0, 6)]
    hole = [(2, 2), (2, 4), (4, 4), (4, 2)]
    lift = lambda ring: [(x, y, plane(x, y)) for x, y in ring]  # noqa: E731
    surface = shapely.Polygon(lift(shell), [lift(hole)])
    layer = gpd.GeoDataFrame({"id": [1, 2]}, geometry=[surface, shapely.box(20, 0, 22, 2)],
                             crs="EPSG:32633")
    mesh = geo.triangulate(layer, output="mesh", max_area=0.5)
    tris = mesh.to_geodataframe()
    assert tris.has_z.tolist() == [p == 0 for p in tris["position"]]
    V, T = mesh.feature_mesh(0)
    assert V.shape[1] == 3
    given = {tuple(p) for p in shapely.get_coordinates(surface, include_z=True).tolist()}
    is_input = np.array([tuple(v) in given for v in V.tolist()])
    assert is_input.sum() == len(given)                             # input vertices keep x, y, z
    assert (~is_input).sum() > 20                                    # Steiner vertices, z interpolated
    np.testing.assert_allclose(V[~is_input, 2], plane(V[~is_input, 0], V[~is_input, 1]),
                               rtol=1e-12, atol=1e-12)
    xyz = shapely.get_coordinates(tris.geometry.array[tris["position"] == 0], include_z=True)
    np.testing.assert_allclose(xyz[:, 2], plane(xyz[:, 0], xyz[:, 1]), rtol=1e-12, atol=1e-12)
    verify_feature(mesh, 0, surface, refined=True)
    areas = feature_areas(tris, 2)
    np.testing.assert_allclose(areas, [surface.area, 4.0], rtol=1e-12)
    assert shapely.area(mesh.triangle_polygons()).max() <= 0.5 * (1 + 1e-12)
    surface_mesh, flat_mesh = geo.triangulate(layer, output="trimesh", max_area=0.5)
    np.testing.assert_allclose(surface_mesh.vertices[:, 2],
                               plane(surface_mesh.vertices[:, 0], surface_mesh.vertices[:, 1]),
                               rtol=1e-12, atol=1e-12)
    assert (flat_mesh.vertices[:, 2] == 0).all()


def grid_polygon() -> shapely.Polygon:
    """A wavy 48-gon with a square hole, every coordinate on the 2^-10 grid in [0, 1000]."""
    t = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)
    r = 400.0 + 40.0 * np.sin(5.0 * t)
    shell = np.round(np.column_stack([500 + r * np.cos(t), 500 + r * np.sin(t)]) * 1024) / 1024
    return shapely.Polygon(shell, [[(450, 450), (450, 550.5), (550.25, 550.5), (550.25, 450)]])


@pytest.mark.parametrize("offset", [(5e5, 5e6), (3e5, 9.5e6)])
def test_utm_scale_meshes_like_unit_scale(offset):
    unit = grid_polygon()
    far = shapely.transform(unit, lambda c: c + offset)            # exact: the grid survives
    assert np.array_equal(shapely.get_coordinates(far) - offset, shapely.get_coordinates(unit))
    near_layer = gpd.GeoDataFrame(geometry=[unit])
    far_layer = gpd.GeoDataFrame(geometry=[far], crs="EPSG:32633")
    a = geo.triangulate(near_layer, output="mesh")
    b = geo.triangulate(far_layer, output="mesh")
    assert np.array_equal(b.vertices, b.batch.vertices)             # no translation, no rounding
    assert canonical_triangles(b.vertices - offset, b.triangles) == \
        canonical_triangles(a.vertices, a.triangles)
    verify_feature(a, 0, unit)
    verify_feature(b, 0, far)                                        # exact, on the raw UTM values
    refined = geo.triangulate(far_layer, output="mesh", min_angle=25)
    V, T = refined.feature_mesh(0)
    assert len(T) > 2 * len(b.triangles)
    assert min_angles(V - offset, T).min() >= 25 * (1 - 1e-9)
    verify_feature(refined, 0, far, refined=True)
    assert shapely.area(refined.triangle_polygons()).sum() == pytest.approx(far.area, rel=1e-9)


@needs_corpus
def test_geographic_crs_warns_unless_projected(countries):
    layer = countries[countries["name"].isin(CENTRAL_EUROPE)]
    with pytest.warns(geo.GeographicCRSWarning, match=r"geographic.*degrees.*project='utm'") as record:
        geo.triangulate(layer)
    assert record[0].filename == __file__                            # points at the caller
    with warnings.catch_warnings():
        warnings.simplefilter("error", geo.GeographicCRSWarning)
        geo.triangulate(layer, project="aeqd")
        geo.triangulate(layer.to_crs("EPSG:3035"))                   # projected
        geo.triangulate(layer.set_crs(None, allow_override=True))    # no CRS: raw coordinates


@needs_corpus
@pytest.mark.parametrize("project", ["utm", "aeqd", "EPSG:3035"])
def test_projection_round_trip_keeps_input_coordinates(countries, project):
    layer = countries[countries["name"].isin(CENTRAL_EUROPE)]
    mesh = geo.triangulate(layer, output="mesh", project=project, min_angle=25)
    assert mesh.mesh_crs.is_projected
    if project == "utm":
        assert mesh.mesh_crs.to_epsg() == 32633
    original = {tuple(p) for p in shapely.get_coordinates(layer.geometry.array).tolist()}
    V = mesh.vertices
    is_input = np.array([tuple(v) in original for v in V.tolist()])
    assert {tuple(v) for v in V[is_input].tolist()} == original      # every lon/lat back, bit for bit
    assert (~is_input).sum() > 100                                    # Steiner vertices, inverse-projected
    tris = mesh.to_geodataframe()
    corners = {tuple(p) for p in shapely.get_coordinates(tris.geometry.array).tolist()}
    assert original <= corners
    # in the meshing CRS: checked exactly, areas equal the projected polygons'
    projected = layer.to_crs(mesh.mesh_crs).geometry.to_numpy()
    for i, geometry in enumerate(projected):
        Vi, Ti = mesh.batch.mesh(i)
        assert_valid(Vi, Ti, segments=boundary_edges(Ti), domain="segments")
        area = shapely.area(shapely.polygons(Vi[Ti[:, [0, 1, 2, 0]]])).sum()
        assert area == pytest.approx(geometry.area, rel=1e-9)
    # back in lon/lat: a Steiner vertex is on its feature's boundary (a split edge,
    # moved to the same fraction of the original edge) or inverse-projected
    steiner = np.flatnonzero(~is_input)
    feature_of = np.zeros(len(V), np.int64)
    feature_of[mesh.triangles.ravel()] = np.repeat(mesh.position, 3)
    rings = shapely.boundary(layer.geometry.to_numpy())[feature_of[steiner]]
    on_boundary = shapely.distance(rings, shapely.points(V[steiner])) < 1e-12
    forward = gpd.GeoSeries(shapely.points(V[steiner]), crs=layer.crs).to_crs(mesh.mesh_crs)
    moved = np.hypot(*(shapely.get_coordinates(forward.array) - mesh.batch.vertices[steiner]).T)
    # metres; EPSG:3035 is on ETRS89: the datum shift's round trip is good to 0.4 mm
    assert on_boundary.sum() > 20 and (moved[~on_boundary] < 1e-3).all()
    assert shapely.is_ccw(shapely.get_exterior_ring(tris.geometry.array)).all()
    np.testing.assert_allclose(feature_areas(tris, len(layer)), shapely.area(layer.geometry.array),
                               rtol=1e-12)                           # they tile the lon/lat polygons


@needs_corpus
def test_feature_split_at_the_antimeridian_cannot_be_projected(countries):
    fiji = countries[countries["name"].isin(["Fiji", "New Zealand"])]   # Fiji: parts at +-180
    with pytest.raises(geo.ProjectionError, match=r"^feature 0: \d+ of its triangles turn clockwise "
                       r"when mapped back from 'Azimuthal equidistant centred at lon 17\d\.\d+"):
        geo.triangulate(fiji, project="aeqd", repair=True)
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"\(0\)"):
        tris = geo.triangulate(fiji, project="aeqd", repair=True, errors="skip")
    assert set(tris["name"]) == {"New Zealand"} and list(tris.attrs["cdt_errors"]) == [0]
    assert shapely.is_ccw(shapely.get_exterior_ring(tris.geometry.array)).all()
    unprojected = geo.triangulate(fiji)                 # in lon/lat the parts stay apart
    np.testing.assert_allclose(feature_areas(unprojected, 2), shapely.area(fiji.geometry.array),
                               rtol=1e-12)


def test_invalid_feature_is_named_and_skip_records_it():
    bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    layer = gpd.GeoDataFrame({"v": [1, 2, 3]}, index=["a", "bow", "c"],
                             geometry=[shapely.box(0, 0, 1, 1), bowtie, shapely.box(3, 0, 4, 1)])
    with pytest.raises(InvalidGeometryError, match=r"^feature bow: Polygon is not valid: "
                                                   r"Self-intersection.*repair=True") as info:
        geo.triangulate(layer)
    assert info.value.feature == "bow" and info.value.index == 1
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"^1 feature\(s\) could not be meshed .*\(bow\)"):
        tris = geo.triangulate(layer, errors="skip")
    assert tris["feature"].tolist() == ["a", "a", "c", "c"] and tris["v"].tolist() == [1, 1, 3, 3]
    assert tris.attrs["cdt_errors"]["bow"].startswith("InvalidGeometryError: feature bow: Polygon")
    assert list(tris.attrs["cdt_errors"]) == ["bow"] and json.dumps(tris.attrs)   # to_parquet-safe
    with pytest.warns(geo.SkippedFeaturesWarning):
        mesh = geo.triangulate(layer, errors="skip", output="mesh")
    assert isinstance(mesh.errors[1], InvalidGeometryError) and mesh.errors[1].feature == "bow"
    repaired = geo.triangulate(layer, repair=True, output="mesh")
    assert repaired.to_geodataframe()["feature"].tolist().count("bow") == 2   # two triangles
    verify_feature(repaired, 0, layer.geometry.iloc[0])


def test_layers_without_polygons_are_a_clear_error():
    layer = gpd.GeoDataFrame(geometry=[shapely.Point(0, 0), shapely.LineString([(0, 0), (1, 1)]),
                                       None, shapely.Polygon()])
    with pytest.raises(geo.NoPolygonsError, match=r"no Polygon or MultiPolygon feature to "
                       r"triangulate \(4 feature\(s\): 1 LineString, 1 None, 1 Point, 1 empty Polygon\)"):
        geo.triangulate(layer)
    with pytest.raises(geo.NoPolygonsError, match="the layer is empty"):
        geo.triangulate({"type": "FeatureCollection", "features": []})
    mixed = gpd.GeoDataFrame(geometry=[shapely.Point(0, 0), shapely.box(0, 0, 1, 1)])
    meshes = geo.triangulate(mixed, output="trimesh")
    assert meshes[0] is None and len(meshes[1].faces) == 2


def test_projection_errors():
    square = gpd.GeoDataFrame(geometry=[shapely.box(0, 0, 1, 1)])
    for project in ("utm", "aeqd", "EPSG:32633"):
        with pytest.raises(geo.ProjectionError, match="needs the layer's CRS"):
            geo.triangulate(square, project=project)
    lonlat = square.set_crs("EPSG:4326")
    with pytest.raises(geo.ProjectionError, match="'WGS 84' is not a projected CRS"):
        geo.triangulate(lonlat, project="EPSG:4326")
    with pytest.raises(geo.ProjectionError, match="project must be 'utm', 'aeqd' or a projected CRS"):
        geo.triangulate(lonlat, project="mercator please")
    with pytest.raises(geo.CDTError, match="output must be one of"):
        geo.triangulate(lonlat, output="svg")


def test_trimesh_output_one_mesh_per_feature():
    trimesh = pytest.importorskip("trimesh")
    holed = shapely.Polygon([(0, 0), (10, 0), (10, 8), (0, 8)], [[(2, 2), (2, 5), (6, 5), (6, 2)]])
    islands = shapely.MultiPolygon([shapely.box(20, 0, 21, 1), shapely.box(23, 0, 25, 3)])
    layer = gpd.GeoDataFrame({"name": ["holed", "point", "islands"]}, crs="EPSG:32633",
                             geometry=[holed, shapely.Point(5, 5), islands])
    meshes = geo.triangulate(layer, output="trimesh")
    assert len(meshes) == 3 and meshes[1] is None
    for m, geometry in ((meshes[0], holed), (meshes[2], islands)):
        assert isinstance(m, trimesh.Trimesh)
        assert m.area == pytest.approx(geometry.area, rel=1e-12)
        assert (m.vertices[:, 2] == 0).all() and (m.face_normals[:, 2] > 0).all()   # ccw from +z
        assert_valid(m.vertices[:, :2], m.faces, segments=input_segments(m.vertices, geometry),
                     domain="segments")


@needs_corpus
def test_dask_local_cluster_matches_single_machine(countries):
    dask_geopandas = pytest.importorskip("dask_geopandas")
    distributed = pytest.importorskip("distributed")
    single = geo.triangulate(countries)                   # also compiles / loads the numba cache
    # Russia (split at the antimeridian) folds; Antarctica's folds unfold by edge flips
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"1 feature\(s\) .*\(18\)"):
        single_aeqd = geo.triangulate(countries, project="aeqd", repair=True, errors="skip")
    ddf = dask_geopandas.from_geopandas(countries, npartitions=4)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster):
        with pytest.warns(geo.GeographicCRSWarning):
            lazy = geo.triangulate_dask(ddf)
        assert isinstance(lazy, dask_geopandas.GeoDataFrame)
        assert lazy.npartitions == 4                      # two per worker thread already: kept
        assert list(lazy.columns) == list(single.columns)
        result = lazy.compute()
        result_aeqd = geo.triangulate_dask(ddf, project="aeqd", repair=True, errors="skip").compute()
    for ours, reference in ((result, single), (result_aeqd, single_aeqd)):
        assert ours.crs == reference.crs and len(ours) == len(reference)
        assert triangle_sets(ours, "feature") == triangle_sets(reference, "feature")
        names = ours.groupby("feature")["name"].first()
        assert names.to_dict() == countries["name"][names.index].to_dict()
    assert len(result["feature"].unique()) == len(countries) == len(result_aeqd["feature"].unique()) + 1



@needs_corpus
def test_dask_splits_a_frame_made_in_one_piece(countries):
    """By default a frame with fewer partitions than two per worker (here: one, on the
    threaded scheduler) is split so that every core has work; npartitions= chooses; the
    triangles are those of the single-machine call whatever the partitions."""
    dask_geopandas = pytest.importorskip("dask_geopandas")
    from cdt_plugin.parallel import available_cores
    layer = countries[countries["continent"] == "Africa"]
    single = geo.triangulate(layer)
    ddf = dask_geopandas.from_geopandas(layer, npartitions=1)
    lazy = geo.triangulate_dask(ddf)
    assert lazy.npartitions == max(2, 2 * available_cores())
    assert triangle_sets(lazy.compute(scheduler="threads"), "feature") == triangle_sets(single, "feature")
    three = geo.triangulate_dask(ddf, npartitions=np.int64(3))
    assert three.npartitions == 3
    assert triangle_sets(three.compute(scheduler="sync"), "feature") == triangle_sets(single, "feature")
    mesh = geo.triangulate(layer, output="mesh")
    for i, geometry in enumerate(layer.geometry.to_numpy()):        # the exact checker
        verify_feature(mesh, i, geometry)
    for bad in (0, 2.5, True):
        with pytest.raises(geo.CDTError, match="npartitions must be None or a whole number"):
            geo.triangulate_dask(ddf, npartitions=bad)

@needs_corpus
@pytest.mark.filterwarnings("ignore::cdt_plugin.adapters.geo.SkippedFeaturesWarning")
def test_workers_give_the_same_layer(countries, monkeypatch):
    one = geo.triangulate(countries, workers=1, min_angle=20, errors="skip")
    assert len(one.attrs["cdt_errors"]) > 0       # one feature cannot meet 20 degrees in lon/lat
    # the triangle Polygons made on threads too (from 500 triangles a thread here), in
    # pieces of at most 700 triangles' rings
    adapter = importlib.import_module("cdt_plugin.adapters.shapely.building")
    monkeypatch.setattr(adapter, "POLYGONS_PER_THREAD", 500)
    monkeypatch.setattr(adapter, "POLYGON_PIECE", 700)
    for workers in (1, 2, 3, None):
        many = geo.triangulate(countries, workers=workers, min_angle=20, errors="skip")
        assert many.equals(one) and many.attrs == one.attrs
        assert np.array_equal(shapely.get_coordinates(many.geometry.array),
                              shapely.get_coordinates(one.geometry.array))
    mesh = geo.triangulate(countries, workers=3, min_angle=20, errors="skip", output="mesh")
    assert mesh.workers == 3 and len(mesh) // 500 >= 3
    with pytest.raises(geo.CDTError, match="workers must be"):
        geo.triangulate(countries, workers=0)


def _reference_geojson(frame) -> dict:
    """What ``json`` makes of geopandas' own feature dicts (the writer before
    it formatted column by column), with JSON's null for NaN and infinity."""
    text = json.dumps(frame.to_geo_dict(na="null", drop_id=True), default=json_value)
    return json.loads(text, parse_constant=lambda name: None)


def test_geojson_writer_matches_json_of_the_feature_dicts(tmp_path):
    import pandas as pd
    tri = [(0.0, -0.0), (1 / 3, 0.1 + 0.2), (-1e-300, 7e22), (0.0, -0.0)]
    tri_z = [(x, y, z) for (x, y), z in zip(tri, (1.5, -0.0, 2e-8, 1.5))]
    geometries = [shapely.Polygon(tri), shapely.Polygon(tri_z), shapely.box(0, 0, 2, 1), None,
                  shapely.Polygon(), shapely.MultiPolygon([shapely.box(0, 0, 1, 1)]),
                  shapely.Polygon(tri), shapely.Point(1, 2),
                  shapely.Polygon([(0, 0), (4, 0), (0, 4)], [[(1, 1), (1, 2), (2, 1)]])]
    n = len(geometries)
    frame = gpd.GeoDataFrame({
        "int": np.arange(n) - 3,
        "float": [0.1, np.nan, np.inf, -0.0, 1e300, 2.5, 0.1, -np.inf, 3.0],
        "text": ["a", None, "ü \"quoted\"", "a", "", "b", "a", "c", "d"],
        "flag": [True, False] * 4 + [True],
        "when": pd.to_datetime(["2020-01-02"] * 4 + [None] + ["1999-12-31T23:59:59"] * 4,
                               format="ISO8601"),
        "mixed": [1, "one", 1.5, None, [1, 2], {"k": "v"}, 1, (3,), np.int32(4)],
        "ünï code": np.float32([1.5, np.nan, 2, 3, 4, 5, 6, 7, 8]),
    }, geometry=geometries, crs="EPSG:3857")
    path = tmp_path / "layer.geojson"
    written = []
    geo.write_geojson(frame, path, progress=written.append)
    assert sum(written) == n
    got = json.loads(path.read_text(encoding="utf-8"))
    assert got["features"] == _reference_geojson(frame)["features"]
    assert got["crs"] == {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3857"}}
    back = gpd.read_file(path)
    assert back.crs.to_epsg() == 3857
    assert shapely.equals_exact(back.geometry.values[:3], frame.geometry.values[:3], 0).all()
    coords = np.array(got["features"][0]["geometry"]["coordinates"][0])
    assert np.signbit(coords[[0, 3], 1]).all()                        # -0.0 kept, not 0.0


@needs_corpus
def test_geojson_writer_of_a_triangle_layer_reads_back_exactly(tmp_path, countries):
    tris = geo.triangulate(countries[countries["continent"] == "Europe"], min_angle=25)
    path = tmp_path / "europe.geojson"
    geo.write_geojson(tris, path)
    assert json.loads(path.read_text()) == _reference_geojson(tris)
    back = gpd.read_file(path)
    assert back.drop(columns="geometry").values.tolist() == \
        tris.drop(columns="geometry").values.tolist()
    assert shapely.equals_exact(back.geometry.values, tris.geometry.values, 0).all()


@needs_corpus
def test_cli_geopackage_to_geopackage(tmp_path, countries):
    layer = countries[countries["name"].isin(CENTRAL_EUROPE)]
    src, out = tmp_path / "europe.gpkg", tmp_path / "triangles.gpkg"
    countries.head(2).to_file(src, layer="first")
    layer.to_file(src, layer="central")
    proc = run_cli("mesh", src, "--layer", "central", "-o", out, "--project", "utm",
                   "--min-angle", "25", "--no-progress")
    expected = geo.triangulate(gpd.read_file(src, layer="central"), project="utm", min_angle=25)
    assert proc.stdout.strip() == f"wrote {out}: 7 feature(s), {len(expected):,} triangles"
    assert "warning" not in proc.stderr
    back = gpd.read_file(out)
    assert back.crs == layer.crs and len(back) == len(expected)
    assert list(back.columns) == list(expected.columns)
    assert back.groupby("position")["name"].first().tolist() == layer["name"].tolist()
    assert back["feature"].tolist() == expected["feature"].tolist()
    assert triangle_sets(back) == triangle_sets(expected)             # GeoPackage: exact doubles


@needs_corpus
def test_cli_geojson_to_geojson(tmp_path, countries):
    layer = countries[countries["continent"] == "South America"]
    src, out = tmp_path / "south_america.geojson", tmp_path / "triangles.geojson"
    geo.write_geojson(layer, src)
    proc = run_cli("mesh", src, "-o", out, "--progress")
    assert "13/13" in proc.stderr and "meshing" in proc.stderr
    assert "cdt-plugin: warning: the layer's CRS (WGS 84) is geographic" in proc.stderr
    assert "--project utm" in proc.stderr
    expected = geo.triangulate(layer)
    assert proc.stdout.strip() == f"wrote {out}: 13 feature(s), {len(expected):,} triangles"
    back = gpd.read_file(out)
    assert back.crs.to_epsg() == 4326
    assert back.groupby("position")["name"].first().tolist() == layer["name"].tolist()
    assert back["pop_est"].tolist() == expected["pop_est"].tolist()
    assert triangle_sets(back) == triangle_sets(expected)             # coordinates exact
    assert shapely.is_ccw(shapely.get_exterior_ring(back.geometry.array)).all()



@needs_corpus
def test_cli_geoparquet_in_and_out(tmp_path, countries):
    """GeoParquet both ways: a .parquet layer is read, the triangles are written from the
    GeoArrow table in row groups (the progress bar counts them), and read back they are
    the GeoDataFrame output, coordinates exact; a voronoi layer is written too."""
    pytest.importorskip("pyarrow")
    layer = countries[countries["continent"] == "South America"]
    src, out = tmp_path / "south_america.parquet", tmp_path / "triangles.parquet"
    layer.to_parquet(src)
    proc = run_cli("mesh", src, "-o", out, "--progress")
    expected = geo.triangulate(layer)
    assert proc.stdout.strip() == f"wrote {out}: 13 feature(s), {len(expected):,} triangles"
    assert f"{len(expected)}/{len(expected)}" in proc.stderr and "writing" in proc.stderr
    back = gpd.read_parquet(out)
    assert back.crs == layer.crs and list(back.columns) == list(expected.columns)
    assert back["feature"].tolist() == expected["feature"].tolist()
    assert back["pop_est"].tolist() == expected["pop_est"].tolist()
    assert triangle_sets(back) == triangle_sets(expected)             # coordinates exact
    mesh = geo.triangulate(layer, output="mesh")
    for i, geometry in enumerate(layer.geometry.to_numpy()):        # the exact checker
        verify_feature(mesh, i, geometry)

    points = gpd.GeoDataFrame({"id": range(4)}, crs="EPSG:32633",
                              geometry=gpd.points_from_xy([0, 4, 0, 4], [0, 0, 3, 3.5]))
    points.to_parquet(tmp_path / "points.parquet")
    run_cli("voronoi", tmp_path / "points.parquet", "-o", tmp_path / "cells.parquet")
    cells = gpd.read_parquet(tmp_path / "cells.parquet")
    assert cells["id"].tolist() == [0, 1, 2, 3] and cells.crs == points.crs
    assert shapely.contains(cells.geometry.array, points.geometry.array).all()


def test_cli_geoparquet_refuses_a_layer_name_and_non_layer_input(tmp_path):
    pytest.importorskip("pyarrow")
    layer = gpd.GeoDataFrame({"id": [1]}, geometry=[shapely.box(0, 0, 1, 1)], crs="EPSG:32633")
    layer.to_parquet(tmp_path / "one.parquet")
    proc = run_cli("mesh", tmp_path / "one.parquet", "--layer", "x", "-o", tmp_path / "t.gpkg",
                   check=False)
    assert proc.returncode == 1 and "a GeoParquet file holds one layer" in proc.stderr
    (tmp_path / "square.wkt").write_text("POLYGON ((0 0, 1 0, 1 1, 0 1, 0 0))")
    proc = run_cli("mesh", tmp_path / "square.wkt", "-o", tmp_path / "t.parquet", check=False)
    assert proc.returncode == 1 and ".parquet output needs a GIS layer input" in proc.stderr

def run_example(*args):
    env = dict(os.environ, CDT_CORPUS=str(corpus_dir()),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=300, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


@needs_corpus
def test_example_gis_countries_quick(tmp_path):
    png = tmp_path / "countries.png"
    out = run_example(ROOT / "examples" / "gis_countries.py", png, "--quick")
    assert "37 countries" in out and f"wrote {png}" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_example_geojson_roundtrip(tmp_path):
    out = run_example(ROOT / "examples" / "geojson_roundtrip.py", tmp_path)
    assert "input vertices exact: True" in out and "attributes kept: True" in out
    assert (tmp_path / "triangles.geojson").exists()


# ------------------------------------------------------ pandas accessor (issue #17)
def _accessor_layer():
    holed = shapely.Polygon([(0, 0), (10, 0), (10, 8), (0, 8)], [[(2, 2), (2, 5), (6, 5), (6, 2)]])
    islands = shapely.MultiPolygon([shapely.box(20, 0, 21, 1), shapely.box(23, 0, 25, 3)])
    return gpd.GeoDataFrame({"name": ["holed", "point", "islands"], "v": [1.5, 2.5, 3.5]},
                            index=["h", "p", "i"], crs="EPSG:32633",
                            geometry=[holed, shapely.Point(5, 5), islands])


def test_accessor_is_registered_through_pandas_and_inherited_by_geopandas():
    import pandas as pd
    assert "cdt" in pd.DataFrame._accessors and "cdt" in pd.Series._accessors
    # geopandas has no registry of its own: its classes inherit pandas' accessors
    assert not any("accessor" in name.lower() for name in dir(gpd))
    assert gpd.GeoDataFrame.cdt is pd.DataFrame.cdt is geo.CDTAccessor
    assert gpd.GeoSeries.cdt is pd.Series.cdt is geo.CDTAccessor
    layer = _accessor_layer()
    assert isinstance(layer.cdt, geo.CDTAccessor) and isinstance(layer.geometry.cdt, geo.CDTAccessor)


@pytest.mark.parametrize("options", [{}, {"max_area": 0.5}, {"min_angle": 28, "workers": 1}])
def test_accessor_gives_what_triangulate_gives(options):
    layer = _accessor_layer()
    series = layer.geometry
    for data in (layer, series):
        expected = geo.triangulate(data, **options)
        got = data.cdt.triangulate(**options)
        assert isinstance(got, gpd.GeoDataFrame) and got.equals(expected)
        assert got.crs == expected.crs == layer.crs and got.attrs == expected.attrs
        assert got["feature"].tolist() == expected["feature"].tolist()
        assert set(got["feature"]) == {"h", "i"}
        mesh = data.cdt.triangulate(output="mesh", **options)
        reference = geo.triangulate(data, output="mesh", **options)
        assert np.array_equal(mesh.vertices, reference.vertices)
        assert np.array_equal(mesh.triangles, reference.triangles)
        assert np.array_equal(mesh.offsets, reference.offsets)
        for i in (0, 2):                      # the exact checker on every meshed feature
            verify_feature(mesh, i, layer.geometry.iloc[i], refined=bool(options))
        if "min_angle" in options:
            V, T = mesh.feature_mesh(0)
            assert min_angles(V, T).min() >= options["min_angle"] * (1 - 1e-9)
        meshes = data.cdt.triangulate(output="trimesh", **options)
        assert meshes[1] is None and [len(m.faces) for m in (meshes[0], meshes[2])] == \
            [len(mesh.feature_mesh(i)[1]) for i in (0, 2)]
    # a GeoSeries keeps its attributes out, as geo.triangulate(series) does
    assert "name" in layer.cdt.triangulate() and "name" not in series.cdt.triangulate()


def test_accessor_passes_errors_warnings_and_projection_through():
    bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    layer = gpd.GeoDataFrame({"v": [1, 2]}, index=["ok", "bow"], crs="EPSG:32633",
                             geometry=[shapely.box(0, 0, 1, 1), bowtie])
    with pytest.raises(InvalidGeometryError, match=r"^feature bow: Polygon is not valid"):
        layer.cdt.triangulate()
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"\(bow\)") as record:
        skipped = layer.cdt.triangulate(errors="skip")
    assert record[0].filename == __file__                      # points at the caller's line
    assert skipped["feature"].tolist() == ["ok", "ok"] and list(skipped.attrs["cdt_errors"]) == ["bow"]
    repaired = layer.geometry.cdt.triangulate(repair=True, output="mesh")
    assert repaired.offsets.tolist() == [0, 2, 4]
    verify_feature(repaired, 0, layer.geometry.iloc[0])
    verify_feature(repaired, 1, shapely.make_valid(bowtie))
    with pytest.raises(geo.CDTError, match="output must be one of"):
        layer.cdt.triangulate(output="svg")
    lonlat = gpd.GeoSeries([shapely.box(10, 50, 10.01, 50.01)], crs="EPSG:4326")
    with pytest.warns(geo.GeographicCRSWarning) as record:
        lonlat.cdt.triangulate()
    assert record[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error", geo.GeographicCRSWarning)
        mesh = lonlat.cdt.triangulate(project="utm", output="mesh")
    assert mesh.mesh_crs.to_epsg() == 32632
    Vi, Ti = mesh.batch.mesh(0)
    assert_valid(Vi, Ti, segments=boundary_edges(Ti), domain="segments")


def test_accessor_on_pandas_objects_without_geometry_is_a_clear_error():
    import pandas as pd
    layer = _accessor_layer()
    cases = {"got a pandas DataFrame with no geometry; make one with geopandas.GeoDataFrame": pd.DataFrame({"x": [1]}),
             "got a pandas Series with no geometry; make one with geopandas.GeoSeries": pd.Series([1, 2]),
             "the GeoDataFrame has no active geometry column \\(columns: \\['x'\\]\\)": gpd.GeoDataFrame({"x": [1]}),
             "got a pandas DataFrame with no geometry": layer[["name", "v"]]}
    for message, frame in cases.items():
        with pytest.raises(geo.NotGeographicError, match=message) as info:
            frame.cdt.triangulate()
        assert isinstance(info.value, AttributeError) and isinstance(info.value, geo.CDTError)
        assert not hasattr(frame, "cdt")


def test_no_polygons_error_is_the_engine_error():
    import cdt_plugin.errors
    assert geo.NoPolygonsError is cdt_plugin.errors.NoPolygonsError is cdt_plugin.NoPolygonsError
    assert issubclass(geo.NoPolygonsError, cdt_plugin.CDTError)
