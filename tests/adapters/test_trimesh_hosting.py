"""The trimesh adapter where trimesh drives, with the real trimesh: engine names in
any case, unknown options named, an empty polygon a named error, near-duplicate
points merged as trimesh merges them (``trimesh.tol.merge``), and SVG/DXF drawings
read by ``trimesh.load_path`` meshed through the adapter."""
import io

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
import cdt_plugin.adapters.trimesh as ct  # noqa: E402
from cdt_plugin import CDTError, NoPolygonsError  # noqa: E402

from checker import assert_valid  # noqa: E402

TRIMESH_TRIANGULATE = trimesh.creation.triangulate_polygon
# everything register() may replace, as trimesh has it before any test
TRIMESH_OWN = {(module, name): getattr(module, name) for module, name in
               [(trimesh.creation, "triangulate_polygon"), (trimesh.creation, "extrude_polygon"),
                (trimesh.creation, "sweep_polygon"), (trimesh.intersections, "slice_mesh_plane"),
                (trimesh.path.Path2D, "extrude"), (trimesh.path.Path2D, "triangulate")]}
L_SHAPE = shapely.Polygon([(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)])


@pytest.fixture(autouse=True)
def trimesh_left_unpatched():
    """Every test leaves trimesh as it found it."""
    yield
    leaked = [f"{module.__name__}.{name}" for (module, name), own in TRIMESH_OWN.items()
              if getattr(module, name) is not own]
    ct.unregister()
    for (module, name), own in TRIMESH_OWN.items():
        setattr(module, name, own)
    assert not leaked, f"a test left trimesh patched: {leaked}"


@pytest.mark.parametrize("default", [False, True])
def test_unregister_restores_every_replaced_attribute(default):
    ct.register(default=default)
    replaced = [key for key, own in TRIMESH_OWN.items() if getattr(*key) is not own]
    assert len(replaced) == 5 + default         # Path2D.extrude only with default
    ct.register(default=not default)            # again: only the default changes
    ct.unregister()
    assert all(getattr(*key) is own for key, own in TRIMESH_OWN.items())
    with pytest.raises(RuntimeError):
        with ct.registered(default=True):
            raise RuntimeError("the block fails")
    assert all(getattr(*key) is own for key, own in TRIMESH_OWN.items())


def _check_solid(mesh, polygon, height):
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(polygon.area * abs(height), rel=1e-9)


def _check_triangles(vertices, faces, polygon):
    assert_valid(np.asarray(vertices, float), np.asarray(faces), domain="segments",
                 segments=_ring_segments(vertices, polygon))
    a, b, c = (np.asarray(vertices)[np.asarray(faces)[:, k]] for k in range(3))
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]).sum()
    assert area == pytest.approx(polygon.area, rel=1e-12)


def _ring_segments(vertices, polygon):
    """The polygon's ring edges as index pairs into ``vertices``."""
    index = {tuple(v): i for i, v in enumerate(np.asarray(vertices).tolist())}
    segments = []
    for ring in [polygon.exterior, *polygon.interiors]:
        coords = [index[tuple(p)] for p in np.asarray(ring.coords)[:-1].tolist()]
        segments += [(coords[i], coords[(i + 1) % len(coords)]) for i in range(len(coords))]
    return np.array(segments)


# -------------------------------------------------------------- engine names in any case
@pytest.mark.parametrize("name", ["cdt_plugin", "CDT_Plugin", "CDT_PLUGIN"])
def test_engine_name_in_any_case(name):
    with ct.registered():
        v, f = trimesh.creation.triangulate_polygon(L_SHAPE, engine=name)
        solid = trimesh.creation.extrude_polygon(L_SHAPE, 2.0, engine=name)
    assert np.array_equal(v, ct.triangulate_polygon(L_SHAPE)[0])
    _check_triangles(v, f, L_SHAPE)
    _check_solid(solid, L_SHAPE, 2.0)


def test_trimesh_engine_names_in_any_case_under_the_registration():
    pytest.importorskip("mapbox_earcut")
    theirs = TRIMESH_TRIANGULATE(L_SHAPE, engine="earcut")
    with ct.registered():
        mine = trimesh.creation.triangulate_polygon(L_SHAPE, engine="EarCut")
    assert np.array_equal(mine[0], theirs[0]) and np.array_equal(mine[1], theirs[1])


# ------------------------------------------------------------------- unknown options
def test_unknown_options_are_named():
    with ct.registered():
        with pytest.raises(CDTError, match=r"unknown option 'min_angel'"):
            trimesh.creation.extrude_polygon(L_SHAPE, 1.0, engine="cdt_plugin", min_angel=30)
        with pytest.raises(CDTError, match=r"unknown options 'colour', 'foo'"):
            trimesh.creation.triangulate_polygon(L_SHAPE, engine="cdt_plugin", foo=1, colour=2)
    with pytest.raises(CDTError, match="'foo'"):
        ct.extrude_polygon(L_SHAPE, 1.0, foo=1)


def test_trimesh_constructor_options_go_through_and_ours_reach_the_engine():
    with ct.registered():
        solid = trimesh.creation.extrude_polygon(L_SHAPE, 1.5, engine="cdt_plugin",
                                                 process=False, validate=True, max_area=0.05)
    _check_solid(solid, L_SHAPE, 1.5)
    top = solid.vertices[:, 2] == 1.5
    assert top.sum() > 40          # max_area reached the engine: many Steiner points


# ----------------------------------------------------------------------- empty input
@pytest.mark.parametrize("empty", [shapely.Polygon(), None, shapely.MultiPolygon()])
def test_empty_polygon_through_the_registration_is_a_named_error(empty):
    with ct.registered():
        with pytest.raises(NoPolygonsError, match="empty polygon"):
            trimesh.creation.triangulate_polygon(empty, engine="cdt_plugin")
        with pytest.raises(NoPolygonsError):
            trimesh.creation.extrude_polygon(empty, 1.0, engine="CDT_plugin")
    with ct.registered(default=True):
        with pytest.raises(NoPolygonsError):
            trimesh.creation.sweep_polygon(shapely.Polygon(), [[0, 0, 0], [0, 0, 1]])


def test_empty_polygon_through_the_adapter():
    v, f = ct.triangulate_polygon(shapely.Polygon())      # trimesh's convention: empty arrays
    assert v.shape == (0, 2) and f.shape == (0, 3)
    with pytest.raises(NoPolygonsError, match="nothing to extrude"):
        ct.extrude_polygon(shapely.Polygon(), 1.0)


# ------------------------------------------------------- near-duplicates: trimesh's rule
def _cad_outline():
    """A 12-gon whose corners are each given twice, the copy 1e-12..1.2e-11 along
    the edge (points a rounding error apart, as CAD exports write them)."""
    angles = np.linspace(0, 2 * np.pi, 13)[:-1]
    corners = np.column_stack([np.cos(angles), np.sin(angles)]) * 10 + 3.3
    ring = []
    for i, p in enumerate(corners):
        ring += [tuple(p), tuple(p + (corners[(i + 1) % 12] - p) * 1e-12 * (1 + i))]
    return shapely.Polygon(ring), corners


def test_near_duplicates_merged_as_trimesh_merges_them():
    polygon, corners = _cad_outline()
    assert polygon.is_valid
    v, f = ct.triangulate_polygon(polygon)
    assert len(v) == 12 and len(f) == 10
    assert np.abs(np.sort(v, axis=0) - np.sort(corners, axis=0)).max() < trimesh.tol.merge
    pytest.importorskip("triangle")
    theirs, _ = TRIMESH_TRIANGULATE(polygon, engine="triangle")    # trimesh's Triangle wrapper
    assert len(theirs) == len(v)
    assert np.abs(np.sort(theirs, axis=0) - np.sort(v, axis=0)).max() < trimesh.tol.merge
    solid = ct.extrude_polygon(polygon, 2.0)
    assert len(solid.vertices) == 24
    _check_solid(solid, polygon, 2.0)
    with ct.registered():       # trimesh's extrusion, our engine: the same solid
        hosted = trimesh.creation.extrude_polygon(polygon, 2.0, engine="cdt_plugin")
    _check_solid(hosted, polygon, 2.0)


def test_merge_distance_follows_trimesh_tol_merge_and_can_be_turned_off(monkeypatch):
    polygon, _ = _cad_outline()
    assert len(ct.triangulate_polygon(polygon, merge_distance=0)[0]) == 24
    monkeypatch.setattr(trimesh.tol, "merge", 1.2e-11)       # read at each call
    assert len(ct.triangulate_polygon(polygon)[0]) == 24 - 2   # the two copies closer than that
    v, f = ct.triangulate_polygon(polygon, merge_distance=0)
    _check_triangles(v, f, polygon)


# ---------------------------------------------------------------- SVG and DXF drawings
SVG = """<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">
  <path d="M 10 10 L 90 10 L 90 90 L 10 90 Z M 30 30 L 30 70 L 70 70 L 70 30 Z"/>
  <path d="M 120 10 C 150 0 170 40 140 60 Z"/>
</svg>"""


def test_svg_drawing_loaded_by_trimesh_and_meshed_through_the_adapter(tmp_path):
    pytest.importorskip("lxml")
    pytest.importorskip("svg.path")
    source = tmp_path / "drawing.svg"
    source.write_text(SVG)
    path = trimesh.load_path(source)
    polygons = path.polygons_full
    assert len(polygons) == 2 and len(polygons[0].interiors) == 1      # a frame and a curve
    solids = ct.extrude_path(path, 2.0)
    for solid, polygon in zip(solids, polygons):
        _check_solid(solid, polygon, 2.0)
    tri = cdt_plugin.triangulate(ct.from_path2d(path))
    assert_valid(tri.vertices, tri.triangles, domain="segments", segments=tri.segments)
    assert sum(p.area for p in polygons) == pytest.approx(80 * 80 - 40 * 40 + polygons[1].area)
    # the DXF of the same drawing (trimesh's own reader, nothing more to install)
    dxf = trimesh.load_path(io.BytesIO(path.export(file_type="dxf").encode()), file_type="dxf")
    assert len(dxf.polygons_full) == 2
    for solid, polygon in zip(ct.extrude_path(dxf, 1.0), dxf.polygons_full):
        _check_solid(solid, polygon, 1.0)
