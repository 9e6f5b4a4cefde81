"""The voronoi_polygons drop-in of the shapely adapter against the real
shapely/GEOS (no mocks): the same cells (site by site), edges, envelope,
options, element-wise forms and degenerate cases."""
import warnings

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

import cdt_plugin  # noqa: E402
from cdt_plugin.adapters import shapely as sa  # noqa: E402

REL = 1e-9      # GEOS builds the cells from frame triangles: its corners differ in the last bits


def _points(n, seed=0, scale=100.0):
    return np.random.default_rng(seed).uniform(0, scale, (n, 2))


def _cells(gc):
    assert gc.geom_type == "GeometryCollection"
    cells = np.asarray(gc.geoms, dtype=object)
    assert (shapely.get_type_id(cells) == shapely.GeometryType.POLYGON).all()
    return cells


def _site_of_cell(cells, sites):
    """For every cell, the one site inside it (-1 if none or several)."""
    site, cell = shapely.STRtree(cells).query(shapely.points(sites), predicate="within")
    owner = np.full(len(cells), -1)
    count = np.bincount(cell, minlength=len(cells))
    owner[cell] = site
    owner[count != 1] = -1
    return owner


def _assert_same_cell(a, b):
    """Two polygons equal up to GEOS's rounding (symmetric difference)."""
    assert shapely.symmetric_difference(a, b).area <= REL * b.area, (a, b)


def _assert_cells_like_geos(ours, geos, sites):
    """Cell i of ``ours`` holds site i (input order); it equals GEOS's cell
    holding the same site; shells are clockwise, closed, 2D, as GEOS's."""
    mine, theirs = _cells(ours), _cells(geos)
    assert len(mine) == len(theirs) == len(sites)
    assert (_site_of_cell(mine, sites) == np.arange(len(sites))).all()
    where = np.argsort(_site_of_cell(theirs, sites))
    for a, b in zip(mine, theirs[where]):
        _assert_same_cell(a, b)
    rings = shapely.get_exterior_ring(mine)
    assert not shapely.is_ccw(rings).any() and shapely.is_closed(rings).all()
    assert not shapely.has_z(mine).any() and shapely.is_valid(mine).all()
    assert ours.bounds == pytest.approx(geos.bounds, rel=1e-12, abs=1e-12)
    assert sum(c.area for c in mine) == pytest.approx(shapely.box(*geos.bounds).area, rel=1e-12)


def _segments(mls):
    """(k, 4) segments (x0, y0, x1, y1), each with its ends in lexicographic order."""
    assert mls.geom_type == "MultiLineString"
    lines = np.asarray(mls.geoms, dtype=object)
    assert (shapely.get_num_coordinates(lines) == 2).all()
    xy = shapely.get_coordinates(lines).reshape(-1, 2, 2)
    swap = (xy[:, 0, 0] > xy[:, 1, 0]) | ((xy[:, 0, 0] == xy[:, 1, 0]) & (xy[:, 0, 1] > xy[:, 1, 1]))
    xy[swap] = xy[swap, ::-1]
    return xy.reshape(-1, 4)


def _assert_same_segments(a, b, scale):
    """The same set of segments, ends within ``REL * scale``."""
    sa_, sb = _segments(a), _segments(b)
    assert len(sa_) == len(sb)
    if not len(sa_):
        return
    d = np.abs(sa_[:, None, :] - sb[None, :, :]).max(axis=2)
    nearest = d.argmin(axis=1)
    assert d[np.arange(len(sa_)), nearest].max() <= REL * scale
    assert len(set(nearest.tolist())) == len(sb)          # one to one


# ----------------------------------------------------------------- generic points
@pytest.mark.parametrize("n", [50, 500])
def test_cells_match_geos_on_random_points(n):
    xy = _points(n, seed=n)
    g = shapely.MultiPoint(xy)
    ours = sa.voronoi_polygons(g)
    _assert_cells_like_geos(ours, shapely.voronoi_polygons(g), xy)
    # the same diagram as the engine's, cut to the envelope
    vor = cdt_plugin.delaunay(xy).voronoi()
    assert ours.bounds == pytest.approx(vor.envelope(), rel=1e-12)
    for a, b in zip(_cells(ours), vor.to_shapely()):
        assert a.equals(b)
    # ordered=True: GEOS's cells in the input order, polygon by polygon
    ordered = shapely.voronoi_polygons(g, ordered=True)
    for a, b in zip(_cells(sa.voronoi_polygons(g, ordered=True)), _cells(ordered)):
        _assert_same_cell(a, b)


def test_cells_are_a_coverage_like_geos():
    """Neighbouring cells share their corners exactly, as GEOS's do: a valid
    coverage, whose union is exactly the envelope."""
    xy = _points(500, seed=3)
    g = shapely.MultiPoint(xy)
    geos = shapely.voronoi_polygons(g)
    assert shapely.coverage_is_valid(_cells(geos))
    ours = sa.voronoi_polygons(g)
    assert ours.bounds == geos.bounds == cdt_plugin.delaunay(xy).voronoi().envelope()
    cells = _cells(ours)
    assert shapely.coverage_is_valid(cells)
    assert shapely.coverage_union_all(cells).equals(shapely.box(*ours.bounds))


def test_polygon_and_line_vertices_are_the_sites():
    rng = np.random.default_rng(11)
    ring = np.column_stack([np.cos(np.linspace(0, 6, 25)), np.sin(np.linspace(0, 6, 25))]) * 10
    ring += rng.uniform(-0.5, 0.5, ring.shape)
    for g in (shapely.Polygon(ring), shapely.LineString(ring),
              shapely.GeometryCollection([shapely.Polygon(ring), shapely.Point(30, 1)])):
        sites = cdt_plugin.delaunay(shapely.get_coordinates(g)).vertices     # distinct, first appearance
        _assert_cells_like_geos(sa.voronoi_polygons(g), shapely.voronoi_polygons(g), sites)


def test_3d_input_gives_2d_cells_like_geos():
    xyz = np.column_stack([_points(30, seed=4), np.arange(30.0)])
    g = shapely.MultiPoint(xyz)
    ours, geos = sa.voronoi_polygons(g), shapely.voronoi_polygons(g)
    assert not shapely.has_z(ours) and not shapely.has_z(geos)
    _assert_cells_like_geos(ours, geos, xyz[:, :2])


@pytest.mark.parametrize("extend_to", [shapely.box(-500, -20, 300, 400), shapely.Point(1000, 50),
                                       shapely.LineString([(0, 0), (-300, -900)]),
                                       shapely.box(40, 40, 60, 60), shapely.Polygon()])
def test_extend_to_grows_the_envelope_like_geos(extend_to):
    xy = _points(200, seed=7)
    g = shapely.MultiPoint(xy)
    ours, geos = sa.voronoi_polygons(g, extend_to=extend_to), shapely.voronoi_polygons(g, extend_to=extend_to)
    _assert_cells_like_geos(ours, geos, xy)
    envelope = cdt_plugin.delaunay(xy).voronoi().envelope()
    if extend_to.is_empty or shapely.box(*envelope).contains(extend_to):
        assert ours.bounds == envelope                  # never shrinks
    scale = max(abs(v) for v in ours.bounds)
    _assert_same_segments(sa.voronoi_polygons(g, extend_to=extend_to, only_edges=True),
                          shapely.voronoi_polygons(g, extend_to=extend_to, only_edges=True), scale)


def test_ordered_keeps_the_input_order_and_merges_duplicates():
    xy = _points(40, seed=9)
    perm = np.random.default_rng(1).permutation(40)
    g = shapely.MultiPoint(xy[perm])
    for ordered in (False, True):     # always the input order
        cells = _cells(sa.voronoi_polygons(g, ordered=ordered))
        assert (_site_of_cell(cells, xy[perm]) == np.arange(40)).all()
    for a, b in zip(_cells(sa.voronoi_polygons(g, ordered=True)), _cells(shapely.voronoi_polygons(g, ordered=True))):
        _assert_same_cell(a, b)
    # repeated vertices: GEOS refuses ordered=True; here they merge, first appearance counts
    dup = shapely.MultiPoint(np.concatenate([xy[:5], xy[[3, 0]], xy[5:]]))
    with pytest.raises(shapely.errors.GEOSException):
        shapely.voronoi_polygons(dup, ordered=True)
    cells = _cells(sa.voronoi_polygons(dup, ordered=True))
    assert (_site_of_cell(cells, xy) == np.arange(40)).all()
    _assert_cells_like_geos(sa.voronoi_polygons(dup), shapely.voronoi_polygons(dup), xy)


@pytest.mark.parametrize("n", [50, 500])
def test_only_edges_match_geos(n):
    xy = _points(n, seed=n + 1)
    g = shapely.MultiPoint(xy)
    ours, geos = sa.voronoi_polygons(g, only_edges=True), shapely.voronoi_polygons(g, only_edges=True)
    _assert_same_segments(ours, geos, scale=300.0)
    # every edge is a side shared by two cells: its ends and middle are on both cells' boundaries
    sides = shapely.boundary(_cells(sa.voronoi_polygons(g)))
    ends = _segments(ours).reshape(-1, 2, 2)
    for at in (ends[:, 0], ends[:, 1], ends.mean(axis=1)):
        near, _ = shapely.STRtree(sides).query(shapely.points(at), predicate="dwithin", distance=1e-9 * 300)
        assert (np.bincount(near, minlength=len(at)) >= 2).all()
    assert len(ours.geoms) <= len(cdt_plugin.delaunay(xy).voronoi().ridge_points)


# --------------------------------------------------------------------- degenerate
def test_grid_cells_are_exact_squares():
    """4 x 4 grid: every Voronoi vertex is where four cells meet, one vertex
    (the two triangles of each square fuse); the inner cells are unit squares,
    and every cell has GEOS's area."""
    xy = np.array([(x, y) for x in range(4) for y in range(4)], float)
    g = shapely.MultiPoint(xy)
    ours, geos = sa.voronoi_polygons(g), shapely.voronoi_polygons(g)
    cells = _cells(ours)
    assert (_site_of_cell(cells, xy) == np.arange(16)).all()
    theirs = _cells(geos)[np.argsort(_site_of_cell(_cells(geos), xy))]
    assert shapely.area(cells) == pytest.approx(shapely.area(theirs), rel=1e-12)
    for i, (x, y) in enumerate(xy):
        if 0 < x < 3 and 0 < y < 3:
            assert shapely.equals_exact(shapely.normalize(cells[i]),
                                        shapely.normalize(shapely.box(x - 0.5, y - 0.5, x + 0.5, y + 0.5)), 1e-12)
            assert shapely.get_num_coordinates(cells[i]) == 5
    assert sorted(set(np.round(shapely.area(cells), 12))) == [1.0, 3.5, 12.25]   # envelope [-3, 6]^2
    edges = sa.voronoi_polygons(g, only_edges=True)
    assert len(edges.geoms) == 24                    # 2 x 3 inner sides, 12 rays: each once
    assert shapely.coverage_is_valid(cells)


def test_cocircular_sites_meet_at_one_point():
    """Twelve sites exactly on a circle: one Voronoi vertex, the centre, shared
    by every cell and edge; 64 sites on a circle up to rounding: valid cells,
    each holding its site (GEOS's cells there are not: it turns some inside out)."""
    pts = np.array([(5, 0), (4, 3), (3, 4), (0, 5), (-3, 4), (-4, 3), (-5, 0), (-4, -3), (-3, -4), (0, -5),
                    (3, -4), (4, -3)], float)
    g = shapely.MultiPoint(pts)
    ours = sa.voronoi_polygons(g)
    _assert_cells_like_geos(ours, shapely.voronoi_polygons(g), pts)
    cells = _cells(ours)
    assert all([0.0, 0.0] in shapely.get_coordinates(c).tolist() for c in cells)
    assert shapely.coverage_is_valid(cells)
    edges = _segments(sa.voronoi_polygons(g, only_edges=True)).reshape(-1, 2, 2)
    assert len(edges) == 12 and all([0.0, 0.0] in e.tolist() for e in edges)
    assert set(map(tuple, edges.reshape(-1, 2).tolist())) <= set(map(tuple, shapely.get_coordinates(cells).tolist()))
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    cells = _cells(sa.voronoi_polygons(shapely.MultiPoint(ring)))
    assert shapely.is_valid(cells).all() and shapely.within(shapely.points(ring), cells).all()
    assert shapely.area(cells).sum() == pytest.approx(36.0, rel=1e-12)


@pytest.mark.parametrize("coords", [
    [(0, 0), (1, 0), (2, 0)], [(2, 0), (0, 0), (1, 0)], [(0, 0), (0, 1)], [(0, 0), (1, 0)],
    [(0, 0), (1, 1), (2, 2)], [(3, -1), (0, 5), (1, 3), (2, 1), (1, 3)], [(0.5, 7), (0.5, -2), (0.5, 0.25)],
    [(0, 0), (1e-3, 2e-3), (10, 20), (7, 14)]], ids=str)
def test_collinear_sites_give_strips_like_geos(coords):
    g = shapely.MultiPoint(coords)
    sites = cdt_plugin.delaunay(np.array(coords, float)).vertices
    ours, geos = sa.voronoi_polygons(g), shapely.voronoi_polygons(g)
    _assert_cells_like_geos(ours, geos, sites)
    scale = max(abs(v) for v in ours.bounds)
    _assert_same_segments(sa.voronoi_polygons(g, only_edges=True), shapely.voronoi_polygons(g, only_edges=True),
                          scale)
    line = shapely.voronoi_polygons(shapely.LineString(coords))
    _assert_cells_like_geos(sa.voronoi_polygons(shapely.LineString(coords)), line, sites)


def test_fewer_than_two_sites_give_empty_like_geos():
    for g in (shapely.Point(2, 2), shapely.MultiPoint(), shapely.Polygon(), shapely.GeometryCollection(),
              shapely.MultiPoint([(1, 1), (1, 1), (1, 1)]), shapely.LineString()):
        for only_edges in (False, True):
            ours = sa.voronoi_polygons(g, only_edges=only_edges)
            geos = shapely.voronoi_polygons(g, only_edges=only_edges)
            assert ours.is_empty and geos.is_empty and ours.geom_type == geos.geom_type
            assert ours.geom_type == ("MultiLineString" if only_edges else "GeometryCollection")
    assert sa.voronoi_polygons(None) is None
    assert sa.voronoi_polygons(None, only_edges=True) is None


# ---------------------------------------------------------------------- tolerance
def test_tolerance_snaps_like_geos():
    # shapely's own example
    g = shapely.MultiPoint([(2, 2), (4, 2), (4.2, 2)])
    ours, geos = sa.voronoi_polygons(g, tolerance=0.5, only_edges=True), \
        shapely.voronoi_polygons(g, tolerance=0.5, only_edges=True)
    _assert_same_segments(ours, geos, 5.0)
    _assert_cells_like_geos(sa.voronoi_polygons(g, tolerance=0.5), shapely.voronoi_polygons(g, tolerance=0.5),
                            np.array([(2, 2), (4, 2)], float))
    # the envelope is that of all the vertices, snapped or not (GEOS)
    g = shapely.MultiPoint([(0, 0), (10, 0), (0, 10), (10.4, 10.4), (10, 10)])
    ours, geos = sa.voronoi_polygons(g, tolerance=1), shapely.voronoi_polygons(g, tolerance=1)
    assert ours.bounds == geos.bounds == (-10.4, -10.4, 20.8, 20.8)
    _assert_cells_like_geos(ours, geos, np.array([(0, 0), (10, 0), (0, 10), (10, 10)], float))
    # all snapped into one: the envelope itself, as GEOS
    g = shapely.MultiPoint([(0, 0), (0.1, 0)])
    ours, geos = sa.voronoi_polygons(g, tolerance=1), shapely.voronoi_polygons(g, tolerance=1)
    assert len(ours.geoms) == len(geos.geoms) == 1 and ours.equals(geos)
    assert sa.voronoi_polygons(g, tolerance=1, only_edges=True).is_empty
    # separated clusters: one site each (the lexicographically first; GEOS, which checks a
    # new vertex only against the ends of the edge it locates, keeps some more), the cells
    # of those sites in the envelope of all the vertices
    rng = np.random.default_rng(5)
    centres = np.array([(x, y) for x in range(0, 100, 20) for y in range(0, 100, 20)], float) + \
        rng.uniform(-3, 3, (25, 2))
    xy = np.concatenate([centres + rng.uniform(-0.2, 0.2, (25, 2)) for _ in range(3)])
    g = shapely.MultiPoint(xy)
    ours = sa.voronoi_polygons(g, tolerance=1.0)
    first = [min(range(k, 75, 25), key=lambda i: tuple(xy[i])) for k in range(25)]
    kept = xy[np.sort(first)]                        # in input order
    assert len(shapely.voronoi_polygons(g, tolerance=1.0).geoms) > 25
    _assert_cells_like_geos(ours, shapely.voronoi_polygons(shapely.MultiPoint(kept),
                                                           extend_to=shapely.box(*ours.bounds)), kept)
    assert ours.bounds == pytest.approx(shapely.voronoi_polygons(g).bounds, rel=1e-12)
    # zero tolerance: only exact duplicates merge
    _assert_cells_like_geos(sa.voronoi_polygons(g, tolerance=0.0), shapely.voronoi_polygons(g), xy)


# ------------------------------------------------------------------ element-wise
def test_elementwise_like_shapely():
    a, b = shapely.MultiPoint(_points(20, seed=1)), shapely.MultiPoint(_points(30, seed=2))
    grid = np.array([[a, None, b], [shapely.Point(0, 0), b, a]], dtype=object)
    out, ref = sa.voronoi_polygons(grid), shapely.voronoi_polygons(grid)
    assert isinstance(out, np.ndarray) and out.shape == ref.shape == (2, 3)
    for res, geos, geom in zip(out.ravel(), ref.ravel(), grid.ravel()):
        if geom is None:
            assert res is None and geos is None
        elif geos.is_empty:                          # the Point
            assert res.is_empty and res.geom_type == "GeometryCollection"
        else:
            _assert_cells_like_geos(res, geos, shapely.get_coordinates(geom))
            assert res.equals(sa.voronoi_polygons(geom))
    as_list = sa.voronoi_polygons([a, None])
    assert isinstance(as_list, np.ndarray) and as_list.shape == (2,) and as_list[1] is None
    zero_d = sa.voronoi_polygons(np.array(a))
    assert isinstance(zero_d, shapely.Geometry) and isinstance(shapely.voronoi_polygons(np.array(a)), shapely.Geometry)
    empty = sa.voronoi_polygons([])
    assert isinstance(empty, np.ndarray) and empty.shape == (0,)


def test_options_broadcast_like_shapely():
    g = shapely.MultiPoint(_points(25, seed=6))
    for kwargs in ({"only_edges": [False, True]}, {"tolerance": [[0.0], [1.0]], "only_edges": [False, True, False]},
                   {"extend_to": [None, shapely.box(-500, -500, 500, 500)]}, {"ordered": [True, False]}):
        out, ref = sa.voronoi_polygons(g, **kwargs), shapely.voronoi_polygons(g, **kwargs)
        assert out.shape == ref.shape
        for res, geos in zip(out.ravel(), ref.ravel()):
            assert res.geom_type == geos.geom_type
            if res.geom_type == "MultiLineString":
                _assert_same_segments(res, geos, 1000.0)
            else:
                assert len(res.geoms) == len(geos.geoms) and res.bounds == pytest.approx(geos.bounds, rel=1e-12)
    out = sa.voronoi_polygons([g, g, None], extend_to=[None, shapely.box(-500, -500, 500, 500), shapely.Point(0, 0)])
    assert out[0].bounds != out[1].bounds == (-500, -500, 500, 500) and out[2] is None


def test_series_and_geoseries_keep_their_index():
    pd = pytest.importorskip("pandas")
    gpd = pytest.importorskip("geopandas")
    a, b = shapely.MultiPoint(_points(20, seed=1)), shapely.box(0, 0, 2, 1)
    series = pd.Series([a, None, b], index=["x", "y", "z"])
    geoseries = gpd.GeoSeries(series.values, index=series.index, crs="EPSG:32633")
    for s in (series, geoseries):
        res = sa.voronoi_polygons(s)
        assert type(res) is type(s) is type(shapely.voronoi_polygons(s))
        assert res.index.tolist() == ["x", "y", "z"] and res["y"] is None
        assert res["x"].equals(sa.voronoi_polygons(a)) and res["z"].equals(sa.voronoi_polygons(b))
        edges = sa.voronoi_polygons(s, only_edges=True)
        assert type(edges) is type(s) and edges.index.tolist() == ["x", "y", "z"]
    assert sa.voronoi_polygons(geoseries).crs == geoseries.crs


# -------------------------------------------------------------------- bad input
def test_bad_input_raises():
    g = shapely.MultiPoint(_points(10))
    for bad in (np.nan, np.inf):
        coords = shapely.MultiPoint([(0, 0), (1, bad), (2, 3)])
        with pytest.raises(shapely.errors.GEOSException):      # GEOS: an exception too
            shapely.voronoi_polygons(coords)
        with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match="row 1"):
            sa.voronoi_polygons(coords)
        with pytest.raises(cdt_plugin.NonFiniteCoordinateError, match="^geometry 1: "):
            sa.voronoi_polygons([g, coords], only_edges=True)
    for bad in (-1.0, [0.0, -2.0]):
        with pytest.raises(cdt_plugin.CDTError, match="tolerance must be >= 0"):
            sa.voronoi_polygons(g, tolerance=bad)
    assert sa.voronoi_polygons(g, tolerance=np.nan) is None      # as shapely's
    with pytest.raises(cdt_plugin.CDTError, match="tolerance must be a number"):
        sa.voronoi_polygons(g, tolerance="1m")
    with pytest.raises(cdt_plugin.CDTError, match="only_edges must be True or False"):
        sa.voronoi_polygons(g, only_edges="yes")
    with pytest.raises(cdt_plugin.CDTError, match="ordered must be True or False"):
        sa.voronoi_polygons(g, ordered=2)
    with pytest.raises(TypeError, match="ufunc keyword arguments are not supported \\(out, where\\)"):
        sa.voronoi_polygons(g, where=True, out=None)
    with pytest.raises(TypeError, match="incorrect type: str"):
        sa.voronoi_polygons([g, "POINT (0 0)"])
    with pytest.raises(TypeError, match="incorrect type: str"):
        sa.voronoi_polygons(g, extend_to="POINT (0 0)")
    with pytest.raises(cdt_plugin.InputShapeError, match="cannot be broadcast together"):
        sa.voronoi_polygons([g, g], tolerance=[0, 0, 0])


@pytest.mark.parametrize("scale", [1e-300, 1e-150, 1.0, 1e150, 1e300])
def test_polygon_clip_tiles_the_region_at_any_overall_scale(scale):
    # GEOS is given everything scaled by a power of two to the region's size
    P = np.random.default_rng(3).random((60, 2)) * scale
    region = shapely.affinity.scale(shapely.Point(0.5, 0.5).buffer(0.7), scale, scale, origin=(0, 0))
    cells = cdt_plugin.delaunay(P).voronoi(clip=region).to_shapely()
    unit = lambda g: shapely.transform(g, lambda c: c / scale)     # areas at unit scale
    assert sum(unit(c).area for c in cells) == pytest.approx(unit(region).area, rel=REL)
    inside = shapely.contains_xy(unit(region), P[:, 0] / scale, P[:, 1] / scale)
    assert inside.sum() > 40
    for c, p in zip(cells[inside], P[inside]):
        assert shapely.intersects(unit(c), shapely.Point(p / scale))


def test_polygon_clip_of_sites_too_close_for_geos_raises_a_range_error():
    # sites 1e-200 apart beside a region of size 5: GEOS's cells came out overlapping
    P = np.random.default_rng(7).random((50, 2)) * 1e-200
    tri = cdt_plugin.delaunay(P)
    with pytest.raises(cdt_plugin.CoordinateRangeError, match="too close for GEOS") as err:
        tri.voronoi(clip=shapely.Point(0, 0).buffer(3))
    a, b = err.value.rows
    assert np.hypot(*(tri.vertices[a] - tri.vertices[b])) < 1e-200
    # a box is cut by cdt_plugin itself: its cells tile it
    cells = tri.voronoi(clip=(-3.0, -3.0, 3.0, 3.0)).to_shapely()
    assert sum(c.area for c in cells) == pytest.approx(36.0, rel=REL)


def _cells_at_unit(cells, k):
    return np.array(shapely.transform(cells, lambda c: np.ldexp(c, -k)).geoms)


@pytest.mark.parametrize("k", [-1000, -600, 0, 600, 1000])
@pytest.mark.parametrize("flatness", [1e-6, 1e-10, 1e-14, 1e-16, 1e-18])
def test_nearly_collinear_sites_give_three_cells_at_every_scale(k, flatness):
    # three sites ~100 apart, the third off the line of the others by `flatness` of their
    # distance: the Voronoi vertex lies ~1/flatness away (beyond the doubles at 2**1000,
    # where the diagram's vertex is inf but the cells, cut to the envelope, are not)
    rng = np.random.default_rng(int(-np.log10(flatness)))
    for _ in range(20):
        a, b = rng.random(2) * 100, rng.random(2) * 100
        c = a + rng.uniform(-1, 2) * (b - a) + flatness * np.array([a[1] - b[1], b[0] - a[0]])
        sites = np.array([a, b, c])
        with warnings.catch_warnings():
            warnings.simplefilter("error")          # no overflow or invalid-value warning either
            cells = _cells_at_unit(sa.voronoi_polygons(shapely.MultiPoint(np.ldexp(sites, k))), k)
        assert len(cells) == 3 and shapely.is_valid(cells).all()
        assert np.isfinite(shapely.bounds(cells)).all() and (shapely.area(cells) > 0).all()
        owners = [int(np.flatnonzero(shapely.intersects_xy(cells, *s))[0]) for s in sites]
        assert sorted(owners) == [0, 1, 2]
        envelope = shapely.envelope(shapely.union_all(cells))
        assert shapely.area(cells).sum() == pytest.approx(shapely.area(envelope), rel=1e-9)
        geos = np.array(shapely.voronoi_polygons(shapely.MultiPoint(sites)).geoms)
        assert sorted(shapely.area(cells)) == pytest.approx(sorted(shapely.area(geos)), rel=1e-6, abs=1e-6)


def test_a_centre_that_rounds_to_nan_is_computed_again():
    # the floating-point determinant of these three sites rounds to 0: the centre is
    # redone in double-double, not left NaN (which gave three empty cells)
    sites = [[8.92167096469092, 18.79677956483793], [63.24193172808431, 65.83868337883321],
             [83.3987733539855, 83.294715283573]]
    tri = cdt_plugin.delaunay(sites)
    assert len(tri.triangles) == 1 and np.isfinite(tri.voronoi().vertices).all()
    cells = np.array(sa.voronoi_polygons(shapely.MultiPoint(sites)).geoms)
    geos = np.array(shapely.voronoi_polygons(shapely.MultiPoint(sites)).geoms)
    assert (shapely.area(cells) > 0).all()
    assert sorted(shapely.area(cells)) == pytest.approx(sorted(shapely.area(geos)), rel=1e-6)


@pytest.mark.parametrize("k, offset", [(-1000, 0.0), (0, 0.0), (1000, 0.0), (0, 1e9), (0, 1e15)])
def test_collinear_sites_give_strips_at_every_magnitude(k, offset):
    # exactly on one line (small integers, so the offset keeps them there): parallel strips,
    # the same as GEOS's at unit scale and no offset, moved and scaled exactly
    coords = np.array([[0, 0], [3, 1], [-6, -2], [12, 4], [9, 3]], float)
    g = shapely.MultiPoint(np.ldexp(coords + offset, k))
    cells = _cells_at_unit(sa.voronoi_polygons(g), k)
    geos = np.array(shapely.voronoi_polygons(shapely.MultiPoint(coords)).geoms)
    assert len(cells) == 5 and shapely.is_valid(cells).all() and (shapely.area(cells) > 0).all()
    moved = shapely.transform(cells, lambda c: c - offset)
    rounding = np.spacing(offset) * 42 * 4       # (each corner rounded, on a box 42 high)
    for cell, site in zip(moved, coords):
        assert cell.contains(shapely.Point(site))
        theirs = geos[shapely.contains_xy(geos, *site)][0]
        assert shapely.symmetric_difference(cell, theirs).area <= REL * theirs.area + rounding
