"""Watertight solids of the exact volume through every trimesh function that
triangulates, with our engine registered in trimesh, and through ours.

The polygons are written by others: glyph outlines of the fonts matplotlib ships
(letters, digits and the dingbats of DejaVu Sans: stars, snowflakes, flowers,
gears), the same glyphs with a hole touching another hole or the shell at a
vertex (the pinch points where trimesh's own extrusion, sweep and slicing leave
edges in four faces), CAD-like outlines whose corners are written twice a
rounding error apart, and trimesh's own 2D shapes.
"""
import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
shapely = pytest.importorskip("shapely")
pytest.importorskip("matplotlib")
from matplotlib import font_manager  # noqa: E402
from matplotlib.ft2font import FT2Font  # noqa: E402
from matplotlib.textpath import TextPath  # noqa: E402

import cdt_plugin.adapters.trimesh as ct  # noqa: E402

from checker import assert_valid  # noqa: E402

HEIGHT = 2.5
CUT = np.array([0.6, -0.3, 1.0])         # an oblique plane's normal for slice_plane


# ------------------------------------------------------------------- the polygons
def _font_characters(font: FT2Font) -> str:
    """The characters of the font among letters, digits, signs and the
    miscellaneous symbols and dingbats (U+2600..U+27BF)."""
    codes = [*range(0x21, 0x7F), *range(0x2600, 0x27C0)]
    have = font.get_charmap()
    return "".join(chr(c) for c in codes if c in have)


def _glyph(char: str, prop: font_manager.FontProperties) -> list:
    """The glyph's filled polygons (even-odd fill of its outline rings)."""
    rings = [r for r in TextPath((0, 0), char, size=100, prop=prop).to_polygons() if len(r) >= 4]
    shape = shapely.GeometryCollection()
    for ring in rings:
        shape = shapely.symmetric_difference(shape, shapely.make_valid(shapely.Polygon(ring)))
    return [p for p in shapely.get_parts(shape)
            if p.geom_type == "Polygon" and p.is_valid and p.area > 1.0]


def _glyphs_with_holes() -> list:
    prop = font_manager.FontProperties(family="DejaVu Sans")
    font = FT2Font(font_manager.findfont(prop))
    return [p for char in _font_characters(font) for p in _glyph(char, prop) if p.interiors]


def _notch(polygon, corner, inside) -> "shapely.Polygon | None":
    """``polygon`` with a new triangular hole that has ``corner`` (a vertex of
    one of its rings) as a vertex and points into ``inside`` (a pinch point:
    the new hole touches that ring there), or None where none fits."""
    for size in (4.0, 2.0, 1.0, 0.5):
        for angle in np.linspace(0, 2 * np.pi, 12, endpoint=False):
            tip = np.array(corner) + size * np.array([np.cos(angle), np.sin(angle)])
            side = size * 0.4 * np.array([-np.sin(angle), np.cos(angle)])
            hole = shapely.Polygon([corner, tuple(tip + side), tuple(tip - side)])
            if not inside.contains(shapely.Polygon([tip + side, tip - side,
                                                   (np.array(corner) + tip) / 2])):
                continue
            notched = shapely.Polygon(polygon.exterior.coords,
                                      [*[r.coords for r in polygon.interiors], hole.exterior.coords])
            if notched.is_valid:
                return notched
    return None


def _touching(polygons: list) -> list:
    """Glyphs with a hole touching another hole, and with a hole touching the shell."""
    out = []
    for polygon in polygons:
        solid = shapely.Polygon(polygon.exterior.coords, [r.coords for r in polygon.interiors])
        for ring in (polygon.interiors[0], polygon.exterior):
            corner = ring.coords[len(ring.coords) // 3]
            notched = _notch(polygon, corner, solid)
            if notched is not None:
                out.append(notched)
    return out


def _near_duplicates(polygon):
    """Every third corner written twice, the copy 1e-12..3e-12 of the size along the edge."""
    def doubled(ring):
        points = np.asarray(ring.coords)[:-1]
        out = []
        for i, p in enumerate(points):
            out.append(tuple(p))
            if i % 3 == 0:
                out.append(tuple(p + (points[(i + 1) % len(points)] - p) * 1e-12 * (1 + i % 3)))
        return out
    return shapely.Polygon(doubled(polygon.exterior), [doubled(r) for r in polygon.interiors])


def _synthetic() -> list:
    """Pinch points by construction: two holes touching at a vertex, a hole touching
    the shell, a shell touching itself (a hole open to a point)."""
    square = [(0, 0), (10, 0), (10, 10), (0, 10)]
    return [shapely.Polygon(square, [[(2, 2), (5, 5), (2, 5)], [(5, 5), (8, 8), (8, 5)]]),
            shapely.Polygon(square, [[(5, 0), (6, 2), (4, 2)]]),
            shapely.Polygon(square, [[(0, 5), (3, 4), (3, 6)], [(3, 4), (5, 2), (5, 4)]]),
            shapely.Polygon([(0, 0), (10, 0), (10, 10), (5, 5), (3, 10), (0, 10)],
                            [[(5, 5), (6, 3), (4, 3)]])]


def _trimesh_shapes() -> list:
    """trimesh's own 2D shapes (and a section of its annulus), as its Path2D gives their polygons."""
    from trimesh.path import creation
    paths = [creation.rectangle([[0, 0], [3, 2]]),
             creation.circle(radius=2.0, center=[1, 1]),
             creation.circle_pattern(pattern_radius=5.0, circle_radius=1.0, count=6),
             trimesh.creation.annulus(r_min=1.0, r_max=3.0, height=2.0)
             .section([0, 0, 1], [0, 0, 0]).to_2D()[0]]
    frame = trimesh.load_path(shapely.box(0, 0, 10, 8).difference(shapely.box(2, 2, 8, 6)))
    return [p for path in [*paths, frame] for p in path.polygons_full if p is not None]


@pytest.fixture(scope="module")
def polygons():
    glyphs = _glyphs_with_holes()
    assert len(glyphs) > 200                       # letters, digits and dingbats with holes
    touching = _touching(glyphs[::4])
    assert len(touching) > 40
    cad = [_near_duplicates(p) for p in glyphs[1::12]]
    chosen = glyphs + touching + cad + _synthetic() + _trimesh_shapes()
    assert all(p.is_valid for p in chosen)
    return chosen


def _pinched(polygon) -> bool:
    """Whether the polygon's boundary passes a point twice."""
    points = np.concatenate([np.asarray(r.coords)[:-1] for r in [polygon.exterior, *polygon.interiors]])
    return len(np.unique(points, axis=0)) < len(points)


def test_the_polygons_have_pinch_points_and_near_duplicates(polygons):
    """The checks below would prove little without the hard cases in them."""
    assert sum(map(_pinched, polygons)) > 40
    pytest.importorskip("mapbox_earcut")
    open_by_trimesh = [p for p in polygons if _pinched(p)
                       and not trimesh.creation.extrude_polygon(p, HEIGHT, engine="earcut").is_watertight]
    assert len(open_by_trimesh) > 20           # trimesh's own extrusion leaves them open


# ------------------------------------------------------------------------ the checks
def _check_solid(mesh, volume, what):
    assert mesh.is_watertight and mesh.is_winding_consistent, what
    assert mesh.volume == pytest.approx(volume, rel=1e-9), what


def _check_flat(vertices, faces, area, what):
    """A 2D triangulation that covers the area and extrudes into a watertight solid."""
    _check_solid(ct.extrude_triangulation(vertices, faces, HEIGHT), area * HEIGHT, what)


def _triangulate(polygon):
    v, f = trimesh.creation.triangulate_polygon(polygon)
    _check_flat(v, f, polygon.area, "trimesh.creation.triangulate_polygon")


def _extrude(polygon):
    solid = trimesh.creation.extrude_polygon(polygon, HEIGHT)
    _check_solid(solid, polygon.area * HEIGHT, "trimesh.creation.extrude_polygon")


def _sweep(polygon):
    straight = trimesh.creation.sweep_polygon(polygon, [[0, 0, 0], [0, 0, 1], [0, 0, HEIGHT]])
    _check_solid(straight, polygon.area * HEIGHT, "sweep_polygon")
    bent = trimesh.creation.sweep_polygon(polygon, [[0, 0, 0], [0, 0, 50], [30, 0, 120]])
    assert bent.is_watertight and bent.is_winding_consistent and bent.volume > 0, "bent sweep"


def _path_triangulate(polygon):
    path = trimesh.load_path(polygon)
    area = sum(p.area for p in path.polygons_full)
    assert area == pytest.approx(polygon.area, rel=1e-9)
    v, f = path.triangulate()
    _check_flat(v, f, area, "Path2D.triangulate")


def _slice(polygon):
    solid = trimesh.creation.extrude_polygon(polygon, HEIGHT)
    top = solid.slice_plane([0, 0, HEIGHT / 3], [0, 0, 1], cap=True)
    _check_solid(top, polygon.area * HEIGHT * 2 / 3, "slice_plane(cap=True), level")
    centre = np.array([*polygon.representative_point().coords[0], HEIGHT / 2])
    up = solid.slice_plane(centre, CUT, cap=True)
    down = solid.slice_plane(centre, -CUT, cap=True)
    for part in (up, down):
        assert part.is_watertight and part.is_winding_consistent, "slice_plane(cap=True), oblique"
    assert up.volume + down.volume == pytest.approx(solid.volume, rel=1e-9)


HOSTED = {"triangulate_polygon": _triangulate, "extrude_polygon": _extrude,
          "sweep_polygon": _sweep, "Path2D.triangulate": _path_triangulate,
          "slice_plane": _slice}


@pytest.mark.parametrize("name", HOSTED)
def test_trimesh_functions_give_watertight_solids_of_the_exact_volume(polygons, name):
    check = HOSTED[name]
    # slicing costs the most: every other polygon of the hard cases and a few glyphs
    chosen = polygons if name != "slice_plane" else [p for k, p in enumerate(polygons)
                                                      if _pinched(p) or k % 4 == 0]
    with ct.registered(default=True):
        for polygon in chosen:
            check(polygon)
    with ct.registered():                          # the engine named, in any case
        solid = trimesh.creation.extrude_polygon(chosen[-1], HEIGHT, engine="CDT_plugin")
    _check_solid(solid, chosen[-1].area * HEIGHT, name)


def test_path_extrude_is_ours_whether_touched_inside_or_after_the_block(polygons):
    hard = [p for p in polygons if _pinched(p)]
    with ct.registered(default=True):
        inside = [trimesh.load_path(p).extrude(HEIGHT) for p in hard]
        for part in inside[::2]:                 # half of them touched inside the block
            assert len(part.faces)
    assert trimesh.primitives.Extrusion is not ct.Extrusion     # trimesh's class stays trimesh's
    for polygon, parts in zip(hard, inside):
        parts = parts if isinstance(parts, list) else [parts]
        for part in parts:
            assert isinstance(part, trimesh.primitives.Extrusion) and type(part) is ct.Extrusion
            _check_solid(part, part.primitive.polygon.area * HEIGHT, "Path2D.extrude")
        assert sum(part.volume for part in parts) == pytest.approx(polygon.area * HEIGHT, rel=1e-9)
    moved = inside[0] if not isinstance(inside[0], list) else inside[0][0]
    moved.primitive.height = 2 * HEIGHT            # rebuilt after the block: still ours
    _check_solid(moved, moved.primitive.polygon.area * 2 * HEIGHT, "Extrusion rebuilt")


def test_sections_through_touching_holes_mesh_exactly(polygons):
    """A section of a solid with touching holes is a Path2D whose loops touch;
    trimesh's loop search joins or splits rings there, path_polygons does not,
    and Path2D.extrude / Path2D.triangulate use it under the registration."""
    hard = [p for p in polygons if _pinched(p)][::3]
    wrong = 0
    for polygon in hard:
        solid = ct.extrude_polygon(polygon, HEIGHT)
        path = solid.section([0, 0, 1], [0, 0, HEIGHT / 2]).to_2D()[0]
        theirs = [p for p in path.polygons_full if p is not None]
        wrong += len(theirs) != 1 or abs(theirs[0].area - polygon.area) > 1e-9 * polygon.area
        mine = ct.path_polygons(path)
        assert len(mine) == 1 and mine[0].is_valid
        assert len(mine[0].interiors) == len(polygon.interiors)
        assert mine[0].area == pytest.approx(polygon.area, rel=1e-9)
        with ct.registered(default=True):
            parts = path.extrude(HEIGHT)
            v, f = path.triangulate()
        parts = parts if isinstance(parts, list) else [parts]
        assert len(parts) == 1
        _check_solid(parts[0], polygon.area * HEIGHT, "Path2D.extrude of a section")
        _check_flat(v, f, polygon.area, "Path2D.triangulate of a section")
        _check_solid(ct.extrude_path(path, HEIGHT)[0], polygon.area * HEIGHT, "extrude_path")
    assert wrong > 5                               # trimesh's own polygons are wrong on some


def test_ours_directly(polygons):
    for polygon in polygons:
        _check_solid(ct.extrude_polygon(polygon, HEIGHT), polygon.area * HEIGHT, "extrude_polygon")
        swept = ct.sweep_polygon(polygon, [[0, 0, 0], [0, 0, HEIGHT]])
        _check_solid(swept, polygon.area * HEIGHT, "sweep_polygon")
    for polygon in [p for p in polygons if _pinched(p)]:
        solid = ct.extrude_polygon(polygon, HEIGHT)
        part = ct.slice_plane(solid, [0, 0, HEIGHT / 4], [0, 0, -1])
        _check_solid(part, polygon.area * HEIGHT / 4, "slice_plane")


def test_the_triangulations_are_valid(polygons):
    """The exact checker on the triangulations trimesh receives (a subsample)."""
    with ct.registered(default=True):
        for polygon in polygons[::10]:
            v, f = trimesh.creation.triangulate_polygon(polygon, merge_distance=0)
            index = {p: i for i, p in enumerate(map(tuple, v.tolist()))}
            segments = [(index[a], index[b]) for ring in [polygon.exterior, *polygon.interiors]
                        for a, b in zip(ring.coords[:-1], ring.coords[1:])]
            assert_valid(v, f, domain="segments", segments=np.array(segments))


def test_refined_caps_keep_their_steiner_points():
    """trimesh's sweep cannot cap a triangulation with interior points; ours can."""
    ring = shapely.Point(0, 0).buffer(5).difference(shapely.Point(0, 0).buffer(2))
    with ct.registered():
        solid = trimesh.creation.sweep_polygon(ring, [[0, 0, 0], [0, 0, 3]], engine="cdt_plugin",
                                               max_area=0.5)
    _check_solid(solid, ring.area * 3, "refined sweep")
    assert len(solid.vertices) > 2 * len(ring.exterior.coords) + 2 * len(ring.interiors[0].coords)


# ---------------------------------------------------------------- other engines
@pytest.mark.parametrize("engine", ["earcut", "manifold", "triangle"])
def test_other_engines_keep_trimeshs_own_behaviour(engine):
    pytest.importorskip({"earcut": "mapbox_earcut", "manifold": "manifold3d",
                         "triangle": "triangle"}[engine])
    polygon = _synthetic()[1]
    path = [[0, 0, 0], [0, 0, 1], [1, 0, 2]]

    def run():
        solid = trimesh.creation.extrude_polygon(polygon, HEIGHT, engine=engine)
        swept = trimesh.creation.sweep_polygon(polygon, path, engine=engine)
        cut = solid.slice_plane([0, 0, 1], [0.1, 0, 1], cap=True, engine=engine)
        return [(m.vertices, m.faces) for m in (solid, swept, cut)]

    theirs = run()
    with ct.registered():
        hosted = run()
    for (v0, f0), (v1, f1) in zip(theirs, hosted):
        assert np.array_equal(v0, v1) and np.array_equal(f0, f1)
    with ct.registered():                              # no default: Path2D.extrude is trimesh's
        part = trimesh.load_path(polygon).extrude(HEIGHT)
    assert type(part) is trimesh.primitives.Extrusion


def test_a_mesh_split_at_seams_is_sliced_by_trimeshs_own_step():
    """Not watertight by index (every face its own vertices): nothing to keep by
    index, so the capped slice is trimesh's (its merge first), capped by our engine."""
    annulus = trimesh.creation.annulus(r_min=1.0, r_max=2.0, height=2.0)     # z in [-1, 1]
    soup = trimesh.Trimesh(annulus.triangles.reshape(-1, 3),
                           np.arange(3 * len(annulus.faces)).reshape(-1, 3), process=False)
    assert not soup.is_watertight
    with ct.registered(default=True):
        part = soup.slice_plane([0, 0, 0.5], [0, 0, 1], cap=True)
    _check_solid(part, annulus.volume / 4, "slice_plane(cap=True) of a soup")
