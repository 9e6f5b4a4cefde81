"""The batch path (cdt_plugin.batch and the shapely adapter's triangulate_batch):
the compiled loop gives exactly the triangles of one cdt_plugin.triangulate call per
geometry, every geometry passes the exact checker, and everything the compiled loop
leaves aside (duplicate vertices, crossings, refinement) takes the general route."""
from __future__ import annotations

import doctest

import numpy as np
import pytest
import shapely

import cdt_plugin
import cdt_plugin.batch as batch
from cdt_plugin import InvalidGeometryError, SegmentIntersectionError
from cdt_plugin.adapters.shapely import triangulate_batch
from cdt_plugin.adapters.shapely.reading import layer_rings as _polygon_rings

from checker import assert_valid, canonical_triangles
from corpus import corpus_dir


def test_doctests():
    assert doctest.testmod(batch).failed == 0
    import cdt_plugin.lift as lift
    assert doctest.testmod(lift).failed == 0


def _ring_segments(geom):
    """Input vertices and ring segments of one polygonal geometry (closing points dropped)."""
    xy, _, ring_start, _, _, _, _, _, _ = _polygon_rings(np.array([geom], object))
    segs = []
    for r in range(len(ring_start) - 1):
        i = np.arange(ring_start[r], ring_start[r + 1])
        segs.append(np.column_stack([i, np.roll(i, -1)]))
    return xy, np.concatenate(segs)


def _vertex_starts(geoms):
    """Index in the batch's vertices of each geometry's first vertex."""
    _, _, ring_start, geom_ring_start, _, _, _, _, _ = _polygon_rings(np.asarray(geoms, object))
    return ring_start[geom_ring_start]


def _verify_geometry(b, i, geom, v0):
    """Geometry i of batch b (its vertices start at v0): exact checker on its own
    triangles, same triangles as one cdt_plugin.triangulate call, and the polygon's
    area tiled (up to rounding)."""
    T = b.triangles[b.offsets[i]:b.offsets[i + 1]]
    xy, segs = _ring_segments(geom)
    assert np.array_equal(b.vertices[v0:v0 + len(xy)], xy)
    local = T - v0
    assert local.min() >= 0 and local.max() < len(xy)
    assert_valid(xy, local, segments=segs, domain="segments")
    one = cdt_plugin.triangulate(xy, segs)
    assert canonical_triangles(xy, local) == canonical_triangles(one.vertices, one.triangles)
    if len(one.vertices) == len(xy):     # no duplicates: the very same rows, same rotation
        assert set(map(tuple, local.tolist())) == set(map(tuple, one.triangles.tolist()))
    P = xy[local]
    area = 0.5 * np.abs((P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1])
                        - (P[:, 2, 0] - P[:, 0, 0]) * (P[:, 1, 1] - P[:, 0, 1])).sum()
    assert area == pytest.approx(geom.area, rel=1e-9)


@pytest.fixture(scope="module")
def countries():
    path = corpus_dir() / "gis" / "naturalearth_lowres.geojson"
    if not path.exists():
        pytest.skip("corpus not present")
    import json
    feats = json.loads(path.read_text())["features"]
    geoms = np.array([shapely.geometry.shape(f["geometry"]) for f in feats], dtype=object)
    return shapely.make_valid(geoms)


def test_countries_match_one_by_one_and_pass_the_checker(countries):
    b = triangulate_batch(countries)
    assert len(b) == len(countries)
    assert b.stats["fallback"] < len(countries) // 10     # most go through the compiled loop
    assert not b.errors
    assert (np.diff(b.geometry) >= 0).all()
    starts = _vertex_starts(countries)
    for i, g in enumerate(countries):
        _verify_geometry(b, i, g, starts[i])
        if g.geom_type == "MultiPolygon":    # regions number the parts
            T = b.region[b.offsets[i]:b.offsets[i + 1]]
            assert set(T.tolist()) <= set(range(len(g.geoms)))


def test_chunk_boundaries_do_not_change_the_result(countries, monkeypatch):
    want = triangulate_batch(countries[:40])
    monkeypatch.setattr(batch, "CHUNK", 7)
    got = triangulate_batch(countries[:40])
    assert np.array_equal(got.offsets, want.offsets)
    for i in range(40):
        a = got.triangles[got.offsets[i]:got.offsets[i + 1]]
        w = want.triangles[want.offsets[i]:want.offsets[i + 1]]
        assert canonical_triangles(got.vertices, a) == canonical_triangles(want.vertices, w)


def test_fallback_geometries_hole_touching_shell_and_touching_parts():
    touching_hole = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0, 0), (2, 1), (1, 2)]])
    touching_parts = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(1, 1, 2, 2)])
    repeated_point = shapely.Polygon([(0, 0), (3, 0), (3, 0), (3, 3), (0, 3)])
    geoms = [touching_hole, touching_parts, repeated_point, shapely.box(5, 5, 6, 7)]
    assert all(shapely.is_valid(geoms))
    b = triangulate_batch(geoms)
    assert b.stats["fallback"] == 0           # duplicate vertices are merged in the compiled route too
    for i, g in enumerate(geoms):
        T = b.triangles[b.offsets[i]:b.offsets[i + 1]]
        one = cdt_plugin.triangulate(g)
        assert canonical_triangles(b.vertices, T) == canonical_triangles(one.vertices, one.triangles)
        assert_valid(one.vertices, one.triangles, segments=one.segments, domain="segments")


def test_empty_and_missing_geometries_get_no_triangles():
    geoms = [None, shapely.Polygon(), shapely.box(0, 0, 1, 1), shapely.LineString([(0, 0), (1, 1)]),
             shapely.GeometryCollection([shapely.Point(0, 0), shapely.box(2, 2, 3, 3)])]
    b = triangulate_batch(geoms)
    assert b.offsets.tolist() == [0, 0, 0, 2, 2, 4]
    assert b.geometry.tolist() == [2, 2, 4, 4]


def _bowtie_arrays():
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1],          # geometry 0: a square
                   [0, 0], [2, 2], [2, 0], [0, 2.0]])        # geometry 1: a bow-tie
    return xy, [0, 4, 8], [0, 1, 2], [0, 0], [False, False]


def test_crossing_ring_raises_with_the_geometry_index():
    xy, rs, grs, rp, rh = _bowtie_arrays()
    with pytest.raises(SegmentIntersectionError, match=r"geometry 1: segments \d \(.*\) and \d .* cross at about \(1\.0, 1\.0\)") as e:
        batch.triangulate_rings(xy, rs, grs, rp, rh)
    assert e.value.index == 1


def test_errors_skip_and_split():
    xy, rs, grs, rp, rh = _bowtie_arrays()
    b = batch.triangulate_rings(xy, rs, grs, rp, rh, errors="skip")
    assert list(b.errors) == [1] and isinstance(b.errors[1], SegmentIntersectionError)
    # regression: skipped errors had no index (geo.triangulate's relabelling failed on them)
    assert b.errors[1].index == 1 and str(b.errors[1]).startswith("geometry 1: segments")
    assert b.offsets.tolist() == [0, 2, 2]
    s = batch.triangulate_rings(xy, rs, grs, rp, rh, intersections="split")
    assert s.stats["steiner"] == 1 and s.vertices[-1].tolist() == [1.0, 1.0]
    T = s.triangles[s.offsets[1]:s.offsets[2]]
    assert len(T) == 2 and (T == len(s.vertices) - 1).any(axis=1).all()


def test_hole_outside_its_shell_is_an_invalid_geometry_error():
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [3, 3], [4, 3], [4, 4.0]])
    with pytest.raises(InvalidGeometryError, match="geometry 0: a hole of polygon 0"):
        batch.triangulate_rings(xy, [0, 4, 7], [0, 2], [0, 0], [False, True])


def test_invalid_shapely_polygon_names_its_index_unless_repaired_or_skipped():
    bow = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    geoms = [shapely.box(0, 0, 1, 1), bow]
    with pytest.raises(InvalidGeometryError, match="geometry 1: Polygon is not valid: Self-intersection") as e:
        triangulate_batch(geoms)
    assert e.value.index == 1
    assert list(triangulate_batch(geoms, errors="skip").errors) == [1]
    fixed = triangulate_batch(geoms, repair=True)
    assert fixed.offsets.tolist() == [0, 2, 4]


def test_refinement_options_run_in_the_compiled_loop_and_meet_the_bounds():
    geoms = [shapely.Polygon([(0, 0), (10, 0), (10, 1), (0, 1)]),
             shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 3), (3, 3), (3, 1)]])]
    b = triangulate_batch(geoms, min_angle=30, max_area=0.5)
    assert b.stats["fallback"] == 0 and b.stats["steiner"] > 0
    for i, g in enumerate(geoms):
        V, T = b.mesh(i)
        P = V[T]
        e = np.linalg.norm(P[:, [1, 2, 0]] - P[:, [2, 0, 1]], axis=2)
        cosines = [(e[:, (j + 1) % 3] ** 2 + e[:, (j + 2) % 3] ** 2 - e[:, j] ** 2)
                   / (2 * e[:, (j + 1) % 3] * e[:, (j + 2) % 3]) for j in range(3)]
        angle = np.degrees(np.arccos(np.clip(np.max(cosines, axis=0), -1, 1)))
        assert angle.min() >= 30 - 1e-9
        tri = cdt_plugin.triangulate(g, min_angle=30, max_area=0.5)
        assert canonical_triangles(V, T) == canonical_triangles(tri.vertices, tri.triangles)
        assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def test_z_is_kept_on_input_vertices_and_interpolated_on_steiner_vertices():
    def plane(x, y):
        return 2.0 * x - 0.5 * y + 7.0

    shell = [(x, y, plane(x, y)) for x, y in [(0, 0), (6, 0), (6, 4), (0, 4)]]
    hole = [(x, y, plane(x, y)) for x, y in [(2, 1), (2, 3), (4, 3), (4, 1)]]
    geoms = [shapely.Polygon(shell, [hole]), shapely.Polygon([(10, 0, 1), (11, 0, 1), (10, 1, 1)])]
    plain = triangulate_batch(geoms)
    assert len(plain.z) == 11                     # 8 + 3 ring vertices, no Steiner points
    assert np.array_equal(plain.z[:8], plane(plain.vertices[:8, 0], plain.vertices[:8, 1]))
    assert np.array_equal(plain.z[8:], [1.0, 1.0, 1.0])
    b = triangulate_batch(geoms[:1], max_area=0.2, min_angle=25)
    assert b.stats["steiner"] > 20
    V, T = b.mesh(0)
    assert V.shape[1] == 3
    np.testing.assert_allclose(V[:, 2], plane(V[:, 0], V[:, 1]), rtol=0, atol=1e-12)


def test_two_d_polygons_in_a_three_d_batch_get_nan_z():
    geoms = [shapely.Polygon([(0, 0, 5), (4, 0, 5), (4, 4, 5), (0, 4, 5)]), shapely.box(10, 0, 14, 4)]
    b = triangulate_batch(geoms, max_area=0.5)
    assert b.stats["steiner"] > 0
    V0, _ = b.mesh(0)
    V1, _ = b.mesh(1)
    assert np.all(V0[:, 2] == 5.0)
    assert np.isnan(V1[:, 2]).all()


def test_progress_bar_counts_every_geometry(capsys):
    b = triangulate_batch([shapely.box(i, 0, i + 1, 1) for i in range(30)] + [None], progress=True)
    assert len(b) == 31
    assert "31/31" in capsys.readouterr().err


def test_unknown_option_is_a_clear_error():
    with pytest.raises(cdt_plugin.CDTError, match="unknown option 'colour'"):
        triangulate_batch([shapely.box(0, 0, 1, 1)], colour="red")


def test_hole_seeds_as_an_array_go_one_by_one_like_single_calls():
    """Regression: a NumPy array of hole seeds was tested for truth (ValueError)."""
    xy = np.array([[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2.0]])
    segs_free = batch.triangulate_rings(xy, [0, 4, 8], [0, 2], [0, 0], [False, False],
                                        holes=np.array([[1.5, 1.5]]), intersections="split")
    tri = cdt_plugin.triangulate(batch.geometry_plc(xy, np.array([0, 4, 8]), np.array([0, 2]),
                                                    np.array([0, 0]), np.array([False, False]), None, 0),
                                 holes=[[1.5, 1.5]], intersections="split")
    assert segs_free.stats["fallback"] == 1
    assert canonical_triangles(segs_free.vertices, segs_free.triangles) == \
        canonical_triangles(tri.vertices, tri.triangles)
    assert len(tri.triangles) == 8
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def test_the_batch_and_the_single_call_check_the_options_into_one_record():
    """The options of a batch are checked, before any work, into the record a single
    ``triangulate`` builds from the same keywords; the seeds stay apart."""
    from cdt_plugin.batch import check_batch_options
    from cdt_plugin.options import MeshOptions
    keywords = {"min_angle": 25, "keep_hull": True, "max_steiner": 10.0, "intersections": "split"}
    options, seeds, workers = check_batch_options(workers=1, holes=[[0.5, 0.5]], **keywords)
    assert options == MeshOptions.check(**keywords)
    assert (options.min_angle, options.max_steiner, options.split) == (25.0, 10, True)
    assert seeds == {"holes": [[0.5, 0.5]]} and workers == 1
    with pytest.raises(cdt_plugin.CDTError, match="min_angle must be in"):
        check_batch_options(min_angle=60)
