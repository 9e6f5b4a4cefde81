"""All cores: every kernel releases the GIL, concurrent calls from threads give
the results of sequential ones, and the batch path gives the same triangles
with any number of workers (issue: all cores). Every mesh is checked by the
exact checker."""
from __future__ import annotations

import inspect
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import shapely
from numba.core.registry import CPUDispatcher

import cdt_plugin
import cdt_plugin._core as core
from cdt_plugin import CDTError
from cdt_plugin.adapters.shapely import triangulate_batch
from cdt_plugin.adapters.shapely.reading import layer_rings as _polygon_rings
from cdt_plugin.batch import MIN_CHUNK, geometry_chunks, geometry_plc, triangulate_rings
from cdt_plugin.parallel import check_workers, map_ordered, resolve_workers

from checker import assert_valid, canonical_triangles, check_triangulation
from helpers import domain_segments


def _kernels():
    import importlib
    import pkgutil
    for info in pkgutil.iter_modules(core.__path__):
        module = importlib.import_module(f"cdt_plugin._core.{info.name}")
        for name, value in inspect.getmembers(module, lambda v: isinstance(v, CPUDispatcher)):
            if value.__module__ == module.__name__:
                yield f"{module.__name__}.{name}", value


def test_every_kernel_releases_the_gil():
    kernels = dict(_kernels())
    assert len(kernels) > 100
    held = [name for name, k in kernels.items() if not k.targetoptions.get("nogil")]
    assert held == []


def _star(n, r0=1.0, r1=0.45, holes=0):
    a = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    r = np.where(np.arange(2 * n) % 2 == 0, r0, r1)
    shell = np.column_stack([r * np.cos(a), r * np.sin(a)])
    rings = [0.05 * np.column_stack([np.cos(a[::4]), np.sin(a[::4])]) + [0.2 * (k - 1), 0]
             for k in range(holes)]
    return shapely.Polygon(shell, [ring[::-1] for ring in rings])


def _jobs():
    rng = np.random.default_rng(7)
    jobs = []
    for n in (3000, 20_000, 50_000):
        pts = rng.random((n, 2))
        jobs.append(("delaunay", pts, {}))
    grid = np.array([[i, j] for i in range(40) for j in range(40)], float)   # cocircular ties
    jobs.append(("delaunay", grid, {}))
    for holes in (0, 2):
        jobs.append(("triangulate", _star(60, holes=holes), {}))
        jobs.append(("triangulate", _star(200, holes=holes), {"min_angle": 30}))
    jobs.append(("triangulate", _star(30), {"max_area": 0.001}))
    return jobs


def _run(job):
    kind, data, options = job
    if kind == "delaunay":
        return cdt_plugin.delaunay(data, **options)
    return cdt_plugin.triangulate(data, **options)


def test_concurrent_calls_give_the_sequential_results():
    jobs = _jobs() * 3
    sequential = [_run(j) for j in jobs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        concurrent = list(pool.map(_run, jobs))
    for job, a, b in zip(jobs, sequential, concurrent):
        assert np.array_equal(a.vertices, b.vertices)
        assert np.array_equal(a.triangles, b.triangles)
        assert np.array_equal(a.segments, b.segments)
    for job, tri in zip(jobs[:len(_jobs())], concurrent):
        if job[0] == "delaunay":
            assert_valid(tri.vertices, tri.triangles, domain="hull")
        else:
            assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def _layer():
    """Ring arrays (as :func:`triangulate_rings` takes them) of polygons of every
    kind the batch meets: plain, with holes, refined in the compiled loop, empty,
    and bow ties, which fall back to the one-by-one route and are skipped."""
    bowtie = (np.array([[0, 0], [2, 2], [2, 0], [0, 2.0]]), [0, 4], [0], [False])
    xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole = [], [0], [0], [], []
    for i in range(3 * MIN_CHUNK):
        if i % 50 == 7:
            parts = bowtie
        elif i % 70 == 3:
            parts = (np.empty((0, 2)), [0], [], [])
        else:
            star = shapely.affinity.translate(_star(5 + i % 40, holes=i % 3), xoff=3.0 * i)
            p_xy, _, p_rs, _, p_rp, p_rh, _, _, _ = _polygon_rings(np.array([star], object))
            parts = (p_xy, p_rs, p_rp, p_rh)
        p_xy, p_rs, p_rp, p_rh = parts
        ring_start.extend((np.asarray(p_rs[1:]) + ring_start[-1]).tolist())
        geom_ring_start.append(geom_ring_start[-1] + len(p_rp))
        xy.append(p_xy)
        ring_polygon.extend(p_rp)
        ring_is_hole.extend(p_rh)
    return np.concatenate(xy), ring_start, geom_ring_start, ring_polygon, ring_is_hole


@pytest.mark.parametrize("options", [{}, {"min_angle": 25}])
def test_the_batch_gives_the_same_triangles_with_any_number_of_workers(options):
    layer = _layer()
    one = triangulate_rings(*layer, workers=1, errors="skip", **options)
    assert one.stats["fallback"] > 0 and len(one.errors) > 0
    if options:
        assert one.stats["steiner"] > 0
    for workers in (2, 3, None):
        many = triangulate_rings(*layer, workers=workers, errors="skip", **options)
        for name in ("vertices", "triangles", "geometry", "region", "offsets"):
            assert np.array_equal(getattr(one, name), getattr(many, name)), (workers, name)
        assert list(many.errors) == list(one.errors)
    xy, ring_start, geom_ring_start, ring_polygon, ring_is_hole = layer
    for g in range(0, len(geom_ring_start) - 1, 11):
        if g in many.errors or geom_ring_start[g] == geom_ring_start[g + 1]:
            continue
        V, T = many.mesh(g)
        plc = geometry_plc(xy, np.asarray(ring_start), np.asarray(geom_ring_start),
                           np.asarray(ring_polygon), np.asarray(ring_is_hole), None, g)
        tri = cdt_plugin.triangulate(plc, **options)
        assert canonical_triangles(V, T) == canonical_triangles(tri.vertices, tri.triangles)
        assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")


def test_chunks_cover_every_geometry_once():
    for ng in (0, 1, 63, 64, 500, 4096 * 3 + 5):
        for threads in (1, 2, 7):
            chunks = geometry_chunks(ng, threads)
            covered = [g for g0, g1 in chunks for g in range(g0, g1)]
            assert covered == list(range(ng))
            if threads > 1 and ng >= 4 * threads * MIN_CHUNK:
                assert len(chunks) >= 4 * threads


def test_progress_counts_every_geometry_with_threads():
    counts = []
    xy = np.array([[0, 0], [1, 0], [1, 1.0]])
    ng = 4 * MIN_CHUNK
    b = triangulate_rings(np.tile(xy, (ng, 1)) + np.repeat(np.arange(ng), 3)[:, None],
                          np.arange(0, 3 * ng + 1, 3), np.arange(ng + 1), np.zeros(ng, int),
                          np.zeros(ng, bool), workers=2, progress=counts.append)
    assert len(b.triangles) == ng and sum(counts) == ng and len(counts) > 1


@pytest.mark.parametrize("bad", [0, -1, 1.5, "2", True])
def test_bad_workers_are_named_before_any_work(bad):
    with pytest.raises(CDTError, match="workers must be None or a whole number >= 1"):
        check_workers(bad)
    with pytest.raises(CDTError, match="workers must be"):
        triangulate_batch([shapely.box(0, 0, 1, 1), "not a geometry"], workers=bad)


def test_workers_take_numpy_integers_and_never_exceed_the_tasks():
    assert check_workers(np.int64(3)) == 3
    assert resolve_workers(8, 3) == 3
    assert resolve_workers(None, 0) == 1
    assert resolve_workers(2, 10) == 2


def test_map_ordered_keeps_order_and_stops_on_an_error():
    assert map_ordered(lambda v: v * v, range(50), 3) == [v * v for v in range(50)]
    started = []

    def work(v):
        started.append(v)
        if v == 2:
            raise ValueError("two")
        time.sleep(0.01)
        return v

    with pytest.raises(ValueError, match="two"):
        map_ordered(work, range(300), 2)
    assert len(started) < 300          # the pieces not started were cancelled


def _point_sets():
    rng = np.random.default_rng(11)
    yield rng.random((5000, 2))
    yield np.array([[i, j] for i in range(30) for j in range(30)], float)          # cocircular
    grid = np.round(rng.random((3000, 2)) * 20) / 3                                  # duplicates
    yield np.concatenate([grid, grid[:500]])
    yield np.column_stack([rng.integers(0, 4, 2000), rng.random(2000)])             # 4 lines
    yield rng.normal(size=(4000, 2)) * [1e-3, 1e3]                                   # anisotropic
    t = np.sort(rng.random(3000)) * 2 * np.pi                                       # a curve: halves
    yield np.column_stack([np.cos(t), np.sin(t)]) * (1 + 0.2 * np.sin(5 * t))[:, None]  # all hull
    yield np.column_stack([rng.random(2000), rng.integers(0, 3, 2000)])             # 3 rows
    for n in (9, 10, 11, 17, 64, 257):
        yield rng.random((n, 2))


def test_delaunay_on_two_threads_gives_the_arrays_of_one(monkeypatch):
    monkeypatch.setattr(_delaunay_module(), "PARALLEL_POINTS", 8)     # the split path on small sets too
    for points in _point_sets():
        one = cdt_plugin.delaunay(points, workers=1)
        two = cdt_plugin.delaunay(points, workers=2)
        for name in ("vertices", "triangles", "neighbors", "vertex_map"):
            assert np.array_equal(getattr(one, name), getattr(two, name)), (len(points), name)
        assert_valid(two.vertices, two.triangles, domain="hull")
    with pytest.raises(CDTError, match="workers must be"):
        cdt_plugin.delaunay(points, workers=0)


def test_delaunay_above_the_threshold_on_two_threads():
    points = np.random.default_rng(5).random((_delaunay_module().PARALLEL_POINTS + 1000, 2))
    one = cdt_plugin.delaunay(points, workers=1)
    two = cdt_plugin.delaunay(points)
    assert np.array_equal(one.triangles, two.triangles)
    assert np.array_equal(one.neighbors, two.neighbors)
    assert two.is_delaunay()


def _delaunay_module():
    import importlib
    return importlib.import_module("cdt_plugin.delaunay")     # (the package exports the function)


def _plcs():
    """Inputs for triangulate: (vertices, segments, options)."""
    rng = np.random.default_rng(17)
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    outer = np.column_stack([(1 + 0.3 * np.sin(5 * t)) * np.cos(t), (1 + 0.3 * np.sin(5 * t)) * np.sin(t)])
    hole = 0.2 * np.column_stack([np.cos(-t[::8]), np.sin(-t[::8])])
    V = np.concatenate([outer, hole + [0.3, 0.1], hole + [-0.3, -0.1]])
    S = np.concatenate([_ring(0, 400), _ring(400, 50), _ring(450, 50)])
    yield V, S, {"holes": [[0.3, 0.1], [-0.3, -0.1]]}
    yield V, S, {"holes": [[0.3, 0.1], [-0.3, -0.1]], "min_angle": 25.0}
    yield V, S, {"keep_hull": True}
    inner = rng.random((300, 2)) - 0.5
    yield np.concatenate([V, inner, inner[:40]]), S, {}                 # free points, repeated
    P = rng.random((200, 2))
    yield P, rng.integers(0, 200, (60, 2)), {"intersections": "split"}   # crossing segments
    grid = np.array([[i, j] for i in range(25) for j in range(25)], float)
    yield grid, np.array([[0, 624], [24, 600]]), {"intersections": "split"}
    yield np.column_stack([np.arange(50.0), np.zeros(50)]), np.array([[0, 49]]), {}   # collinear


def _ring(start, k):
    return np.column_stack([start + np.arange(k), start + (np.arange(k) + 1) % k])


def test_triangulate_on_two_threads_gives_the_arrays_of_one(monkeypatch):
    """The Delaunay stage of triangulate is built with the first cut's halves
    on two threads (above a size: lowered here), then the route goes on from
    it: every output array equals one thread's, with holes, refinement, the
    hull kept, repeated points, crossings split and snap-rounded, and all
    points on a line."""
    import importlib
    monkeypatch.setattr(importlib.import_module("cdt_plugin.cdt"), "PARALLEL_VERTICES", 8)
    names = ("vertices", "triangles", "neighbors", "constrained", "segments", "segment_ids",
             "vertex_map", "regions")
    for V, S, options in _plcs():
        one = cdt_plugin.triangulate(V, S, workers=1, **options)
        two = cdt_plugin.triangulate(V, S, workers=2, **options)
        for name in names:
            assert np.array_equal(getattr(one, name), getattr(two, name)), (len(V), options, name)
        if len(two.triangles):
            domain = "hull" if options.get("keep_hull") else "segments"
            rep = check_triangulation(two.vertices, two.triangles, segments=domain_segments(two),
                                      domain=domain, require_all_vertices=domain == "hull")
            assert rep.ok, str(rep)
    with pytest.raises(CDTError, match="workers must be"):
        cdt_plugin.triangulate(V, S, workers=0)


def test_triangulate_above_the_threshold_on_two_threads():
    import importlib
    n = importlib.import_module("cdt_plugin.cdt").PARALLEL_VERTICES + 2000
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = np.column_stack([(1 + 0.2 * np.sin(9 * t)) * np.cos(t), (1 + 0.2 * np.sin(9 * t)) * np.sin(t)])
    one = cdt_plugin.triangulate(V, _ring(0, n), workers=1)
    two = cdt_plugin.triangulate(V, _ring(0, n))
    assert np.array_equal(one.triangles, two.triangles) and np.array_equal(one.neighbors, two.neighbors)
    rep = check_triangulation(two.vertices, two.triangles, segments=two.segments, domain="segments")
    assert rep.ok, str(rep)
