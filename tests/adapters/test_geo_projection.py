"""``project=`` on valid lon/lat polygons whose rings touch: the mesh mapped back to
the layer's CRS is a valid triangulation of the polygon there (checked exactly)."""
from __future__ import annotations

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyproj")

from cdt_plugin import InvalidGeometryError  # noqa: E402
from cdt_plugin.adapters import geo  # noqa: E402
from cdt_plugin.adapters.geo.projection import unfold, with_touching_vertices  # noqa: E402
from checker import assert_valid  # noqa: E402


def diamond(lon: float, lat: float, r: float = 0.25) -> list[tuple[float, float]]:
    return [(lon, lat - r), (lon + r, lat), (lon, lat + r), (lon - r, lat)]


def hole_on_shell(lon: float, lat: float, r: float = 0.25) -> shapely.Polygon:
    """A diamond whose triangular hole touches the middle of its south-east edge:
    the touching vertex lies exactly on that edge in lon/lat (dyadic coordinates),
    but off its straight image in any projection."""
    h = r / 2
    return shapely.Polygon(diamond(lon, lat, r),
                           [[(lon + h, lat - h), (lon, lat), (lon, lat - h)]])


def holes_touching(lon: float, lat: float, r: float = 0.25) -> shapely.Polygon:
    """Two holes, one's vertex in the middle of the other's edge."""
    h = r / 4
    return shapely.Polygon(diamond(lon, lat, r),
                           [[(lon - h, lat - h), (lon + h, lat - h), (lon, lat)],
                            [(lon, lat - h), (lon + h, lat - 2 * h), (lon - h, lat - 2 * h)]])


def parts_touching(lon: float, lat: float, r: float = 0.25) -> shapely.MultiPolygon:
    """Two parts of a MultiPolygon: a corner of one in the middle of the other's edge."""
    return shapely.MultiPolygon([shapely.Polygon(diamond(lon, lat, r)),
                                 shapely.Polygon([(lon + r / 2, lat - r / 2),
                                                  (lon + r, lat - r), (lon + 1.5 * r, lat - r / 2)])])


def thin(lon: float, lat: float) -> shapely.Polygon:
    """A sliver 1/4 degree long and 1/1024 degree wide, with a hole on its edge."""
    d, h = 1 / 1024, 1 / 8
    return shapely.Polygon([(lon - h, lat), (lon + h, lat), (lon + h, lat + d), (lon - h, lat + d)],
                           [[(lon, lat), (lon + d, lat + d / 2), (lon - d, lat + d / 2)]])


SHAPES = {"hole on shell": hole_on_shell, "holes touching": holes_touching,
          "parts touching": parts_touching, "thin": thin}
PLACES = {"mid-latitude": (15.0, 45.25), "near the north pole": (45.0, 83.5),
          "near the south pole": (-100.0, -79.5), "across a UTM zone edge": (18.0, 50.0)}


def verify_mapped_back(mesh, i: int, geometry) -> None:
    """Feature ``i`` in the layer's CRS: every input vertex kept bit for bit, every
    triangle counter-clockwise (exactly), a simplicial complex bounded by the
    polygon's ring pieces (every edge exempt from the Delaunay test: the mesh is
    Delaunay in the meshing CRS, not in degrees), and the triangles' area the polygon's."""
    V, T = mesh.feature_mesh(i)
    V = V[:, :2]
    assert {tuple(p) for p in shapely.get_coordinates(geometry).tolist()} <= \
        {tuple(p) for p in V.tolist()}
    edges = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1),
                      axis=0)
    assert_valid(V, T, segments=edges, domain="segments")
    area = shapely.area(shapely.polygons(V[T[:, [0, 1, 2, 0]]])).sum()
    assert area == pytest.approx(geometry.area, rel=1e-12)


@pytest.mark.parametrize("place", PLACES)
@pytest.mark.parametrize("shape", SHAPES)
def test_valid_touching_rings_mesh_through_utm(shape, place):
    geometry = SHAPES[shape](*PLACES[place])
    assert geometry.is_valid
    layer = gpd.GeoDataFrame({"name": [shape]}, geometry=[geometry], crs="EPSG:4326")
    mesh = geo.triangulate(layer, project="utm", output="mesh", max_area=2e7)
    assert mesh.mesh_crs.is_projected and not mesh.errors
    verify_mapped_back(mesh, 0, geometry)


@pytest.mark.parametrize("project", ["aeqd", "EPSG:3035"])
def test_valid_touching_rings_mesh_through_a_named_crs(project):
    geometries = [f(15.0, 45.25) for f in SHAPES.values()]
    layer = gpd.GeoDataFrame(geometry=geometries, crs="EPSG:4326", index=list(SHAPES))
    mesh = geo.triangulate(layer, project=project, output="mesh", min_angle=25)
    for i, geometry in enumerate(geometries):
        verify_mapped_back(mesh, i, geometry)
    frame = geo.triangulate(layer, project=project, min_angle=25)        # output="geodataframe"
    assert list(frame["feature"].unique()) == list(SHAPES)
    assert len(frame) == len(mesh.triangles)
    assert (shapely.get_coordinates(frame.geometry.array) ==
            mesh.vertices[mesh.triangles[:, [0, 1, 2, 0]]].reshape(-1, 2)).all()
    assert bool(frame.geometry.exterior.is_ccw.all())


def test_touching_vertices_are_inserted_exactly():
    geometry = hole_on_shell(15.0, 45.25)
    noded = with_touching_vertices(np.array([geometry, shapely.box(0, 0, 1, 1), None]))
    shell = shapely.get_coordinates(noded[0].exterior).tolist()
    assert shell == [[15.0, 45.0], [15.125, 45.125], [15.25, 45.25], [15.0, 45.5], [14.75, 45.25],
                     [15.0, 45.0]]
    assert noded[0].equals(geometry) and noded[1] is not None and noded[2] is None
    plain = np.array([shapely.box(0, 0, 1, 1)])
    assert with_touching_vertices(plain) is plain            # nothing touches: the same array


def test_unfold_flips_only_inside_a_polygon():
    V = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    T = np.array([[0, 1, 2], [0, 2, 3]])                      # (0, 1, 2) flat
    flipped = unfold(V, T, np.zeros(2, int), np.zeros(2, int))
    assert_valid(V, flipped, segments=np.array([[0, 1], [1, 2], [2, 3], [3, 0], [1, 3]]),
                 domain="segments")
    # across two parts (or features) the shared edge is a ring edge: not flipped
    assert (unfold(V, T, np.zeros(2, int), np.array([0, 1])) == T).all()
    assert (unfold(V, T, np.array([0, 1]), np.zeros(2, int)) == T).all()


def test_a_polygon_invalid_in_its_own_crs_is_refused_and_skipped_by_name():
    # made in UTM and moved to lon/lat vertex by vertex: the hole's vertex, on the shell's
    # edge in UTM, lies a hair outside it in lon/lat (GEOS: "Self-intersection")
    made = shapely.Polygon([(0, 0), (12, 0), (12, 12), (0, 12)], [[(0, 6), (5, 4), (5, 8)]])
    utm = gpd.GeoSeries([shapely.affinity.translate(made, 500_200.0, 5_000_000.0)], crs=32633)
    bent = utm.to_crs(4326).iloc[0]
    assert not bent.is_valid
    good = hole_on_shell(15.0, 45.25)
    layer = gpd.GeoDataFrame(geometry=[good, bent], crs="EPSG:4326", index=["good", "bent"])
    with pytest.raises(InvalidGeometryError, match="feature bent"):
        geo.triangulate(layer, output="mesh")                 # unprojected: the same verdict
    with pytest.raises(geo.ProjectionError, match=r"feature bent: .*not valid in 'WGS 84'"):
        geo.triangulate(layer, project="utm", output="mesh")
    with pytest.warns(geo.SkippedFeaturesWarning, match=r"1 feature\(s\) .*\(bent\)"):
        frame = geo.triangulate(layer, project="utm", errors="skip")
    assert set(frame["feature"]) == {"good"}
    assert "not valid in 'WGS 84'" in frame.attrs["cdt_errors"]["bent"]
    with pytest.warns(geo.SkippedFeaturesWarning):
        mesh = geo.triangulate(layer, project="utm", errors="skip", output="mesh")
    verify_mapped_back(mesh, 0, good)
