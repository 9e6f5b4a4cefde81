"""Fuzz driver: random inputs of every family through the engine, each result
checked from scratch by the exact checker.

Run from the repository root::

    python tests/support/fuzz.py --count 10000            # every family, seed 0
    python tests/support/fuzz.py --count 500 --family split --seed 7

Each case is drawn from its own seed (``seed * 1_000_003 + case``), so a
failure prints a one-line reproducer (``--family F --case N --seed S``).

Families and what is checked for each case:

``delaunay``
    random, gridded (cocircular), clustered and duplicated points, at a random
    power-of-two scale over the whole double range, any algorithm, sometimes
    weighted: a valid (weighted) Delaunay triangulation, no input point lost
    (``vertex_map``), the same triangles for a permuted input and at unit scale.
``cdt``
    star-shaped polygons with holes and free points inside: a valid constrained
    Delaunay triangulation of the domain, every input point kept, the same
    triangles for permuted vertices, permuted and reversed segments.
``split``
    segment soups on a small grid and at random, ``intersections="split"``:
    valid, every input segment the chain of its pieces (Steiner points on it up
    to rounding), every input vertex on a segment splitting it, the same
    triangles for permuted and reversed segments.
``near``
    segments crossing within rounding of each other (fans through nearly one
    point, nearly parallel, nearly collinear), ``intersections="split"``: a
    valid mesh with every segment the chain of its pieces (snap rounding), the
    same triangles for permuted and reversed segments.
``voronoi``
    the ``delaunay`` family's points and points on one circle, sometimes
    weighted, at a random power-of-two scale: every face of the Delaunay
    subdivision strictly convex and cocircular (lifted-coplanar), exactly; the
    cells cut to a box an exact coverage of it (every side inside the box shared,
    reversed, bit for bit), their areas summing to the box's, and sample points
    in the cell of their nearest (least power) site.
``query``
    the ``delaunay`` family's points (unweighted) and polygons with holes, queries
    at random, on vertices, on edge midpoints and on a half-grid: ``locate``
    gives the smallest id of the triangles that hold each point exactly (-1
    when none does); the natural neighbour coordinates are non-negative, sum to
    one and reproduce the point; both interpolants reproduce a linear function.
``dynamic``
    random edit sequences on a small grid (points, segments, removals, moves;
    ``intersections`` raise or split): after each edit the snapshot is valid,
    Delaunay, and the same triangles as ``triangulate`` of the vertices and
    segments from scratch; a failed edit changes nothing.
``refine``
    polygons with holes, ``min_angle`` up to 30 and area bounds: valid,
    constrained Delaunay, segments chained, every triangle meeting the bounds
    or listed in ``below_min_angle``.

Any ``CDTError`` other than the documented ones for the family counts as a
failure, and so does any other exception.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import cdt_plugin  # noqa: E402
from cdt_plugin import RefinementLimitError  # noqa: E402
from cdt_plugin.report import triangle_quality  # noqa: E402
from checker import (canonical_triangles, check_steiner_segments, check_triangulation,  # noqa: E402
                     incircle_exact, orient2d_exact)
from helpers import verify  # noqa: E402

FAMILIES = ("delaunay", "cdt", "split", "refine", "near", "voronoi", "query", "dynamic")


class FuzzFailure(AssertionError):
    pass


def _require(ok, what):
    if not ok:
        raise FuzzFailure(what)


def _check(rep, what):
    _require(rep.ok, f"{what}: {rep}")


# ---------------------------------------------------------------- inputs
def random_points(rng) -> np.ndarray:
    n = int(rng.integers(3, 80))
    kind = rng.integers(4)
    if kind == 0:
        P = rng.random((n, 2))
    elif kind == 1:                       # a grid: cocircular quadruples everywhere
        k = int(rng.integers(2, 8))
        P = rng.integers(0, k, (n, 2)).astype(float)
    elif kind == 2:                       # clusters, with exact duplicates
        centres = rng.random((3, 2))
        P = centres[rng.integers(0, 3, n)] + rng.normal(0, 1e-6, (n, 2))
        P[rng.random(n) < 0.2] = P[0]
    else:                                 # nearly collinear
        t = rng.random(n)
        P = np.column_stack([t, 0.5 * t + rng.integers(-2, 3, n) * 2.0 ** -50])
    return P


def star(rng, n, r0=0.5, r1=1.0) -> np.ndarray:
    """A star-shaped polygon: ``n`` vertices at radii ``r0..r1``, angular gaps
    below 60 degrees for ``n >= 9`` (so it contains the disc of radius 0.43)."""
    angles = (np.arange(n) + 0.5 * rng.random(n)) * 2 * np.pi / n
    radii = r0 + (r1 - r0) * rng.random(n)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


def polygon_with_holes(rng):
    """A star polygon (radii 0.5..1), up to 4 small square holes in distinct
    cells of a grid inside radius 0.34, and a few free points: vertices,
    segments, whether there are holes."""
    outer = star(rng, int(rng.integers(9, 40)))
    V = [outer]
    S = [[(i, (i + 1) % len(outer)) for i in range(len(outer))]]
    cells = rng.permutation(16)[: int(rng.integers(0, 5))]
    for c in cells:
        cx, cy = -0.25 + 0.125 * (c % 4) + 0.0625, -0.25 + 0.125 * (c // 4) + 0.0625
        h = 0.01 + 0.04 * rng.random()
        sq = np.array([[cx - h, cy - h], [cx + h, cy - h], [cx + h, cy + h], [cx - h, cy + h]])
        base = sum(len(v) for v in V)
        V.append(sq)
        S.append([(base + i, base + (i + 1) % 4) for i in range(4)])
    free = rng.random((int(rng.integers(0, 6)), 2)) * 0.6 - 0.3
    V.append(free)
    return np.vstack(V), np.array([s for ring in S for s in ring], np.int64), len(cells) > 0


def segment_soup(rng):
    """Segments among few grid points or random points (crossings, overlaps,
    vertices on segments), or up to 30 segments with their own random ends."""
    if rng.random() < 0.25:
        m = int(rng.integers(2, 31))
        return rng.random((2 * m, 2)), np.arange(2 * m).reshape(m, 2)
    n = int(rng.integers(3, 16))
    if rng.random() < 0.5:
        P = rng.integers(0, 6, (n, 2)).astype(float)
    else:
        P = rng.random((n, 2))
    m = int(rng.integers(1, 3 * n))
    S = rng.integers(0, n, (m, 2))
    return P, S


def near_crossings(rng):
    """Segments that cross within rounding of each other: fans through nearly
    one point, nearly parallel or nearly collinear segments."""
    kind = int(rng.integers(0, 3))
    m = int(rng.integers(3, 31))
    if kind == 0:                                        # a fan through nearly one point
        c = rng.random(2) + float(rng.choice([0.0, 1e-17, 1e-15, 1e-10])) * rng.standard_normal((m, 2))
        angle = rng.random(m) * np.pi
        d = np.column_stack([np.cos(angle), np.sin(angle)])
        L = 1 + rng.random(m) * float(rng.choice([1, 100, 1e4]))
        P = np.empty((2 * m, 2))
        P[0::2] = c - d * L[:, None]
        P[1::2] = c + d * (L * rng.random(m))[:, None]
        return P, np.arange(2 * m).reshape(m, 2)
    if kind == 1:                                        # nearly parallel
        angle = rng.random() * np.pi + float(rng.choice([1e-6, 1e-10, 1e-14, 1e-16])) * rng.standard_normal(m)
        c = rng.random((m, 2))
        d = np.column_stack([np.cos(angle), np.sin(angle)]) * (rng.random(m) * 2 + 0.1)[:, None]
        return np.vstack([c - d, c + d])[np.arange(2 * m).reshape(2, m).T.ravel()], np.arange(2 * m).reshape(m, 2)
    n = int(rng.integers(3, 20))                         # nearly collinear points, segments among them
    t = rng.random(n) * 10 - 5
    k = rng.integers(-3, 4, n) * float(rng.choice([0.0, 2.0 ** -52, 1e-15]))
    P = np.vstack([np.column_stack([t, (rng.random() * 4 - 2) * t + rng.random() + k]),
                   rng.random((int(rng.integers(0, 6)), 2)) * 10 - 5])
    return P, rng.integers(0, len(P), (m, 2))


# ---------------------------------------------------------------- checks
def _same(a, b, what):
    _require(canonical_triangles(a.vertices, a.triangles) == canonical_triangles(b.vertices, b.triangles),
             f"{what}: different triangles")


def check_delaunay(rng):
    P = random_points(rng)
    algorithm = str(rng.choice(["divide", "incremental", "flip"]))
    weights = None
    if rng.random() < 0.2:
        algorithm = "incremental"
        weights = rng.random(len(P)) * 1e-3
    e = int(rng.integers(-1000, 1000)) if weights is None else int(rng.integers(-300, 300))
    span = np.abs(P).max()
    if span == 0 or not np.isfinite(np.ldexp(span, e)):
        e = 0
    S = np.ldexp(P, e)
    if not np.array_equal(np.ldexp(S, -e), P):      # rounded (subnormal): unscaled input only
        e, S = 0, P
    W = None if weights is None else np.ldexp(weights, 2 * e)
    tri = cdt_plugin.delaunay(S, W, algorithm=algorithm)
    verify(S, tri, W, exact_submerged=len(P) <= 30)
    _require(tri.is_delaunay(), "is_delaunay() is False")
    perm = rng.permutation(len(P))
    other = cdt_plugin.delaunay(S[perm], None if W is None else W[perm], algorithm=algorithm)
    _same(tri, other, "permuted points")
    if e:
        unit = cdt_plugin.delaunay(P, weights, algorithm=algorithm)
        _require(np.array_equal(unit.triangles, tri.triangles), f"scale 2**{e}: different triangles")


def check_cdt(rng):
    V, S, _ = polygon_with_holes(rng)
    algorithm = str(rng.choice(["auto", "incremental", "flip"]))
    tri = cdt_plugin.triangulate(V, S, algorithm=algorithm)
    _check_cdt_result(V, S, tri)
    V2, S2 = permuted(rng, V, S)
    _same(tri, cdt_plugin.triangulate(V2, S2, algorithm=algorithm), "permuted and reversed input")


def _check_cdt_result(V, S, tri):
    T = tri.triangles
    edges = {frozenset(e) for t in T.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    inside = np.array([frozenset(p) in edges for p in tri.segments.tolist()], bool)
    _check(check_triangulation(tri.vertices, T, segments=tri.segments[inside].reshape(-1, 2),
                               domain="segments", require_all_vertices=False), "constrained Delaunay")
    _require(np.array_equal(tri.vertices[tri.vertex_map], V), "an input vertex moved or was lost")
    _require(tri.is_delaunay(), "is_delaunay() is False")


def check_split(rng):
    P, S = segment_soup(rng)
    try:
        tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
    except cdt_plugin.CDTError as exc:
        _require("still cross" not in str(exc), f"split did not converge: {exc}")
        raise
    if tri.stats.get("collinear"):
        _require(len(tri.triangles) == 0, "collinear input gave triangles")
        return
    _check(check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull"),
           "split CDT")
    # (merged segments' pieces carry one of their ids: the others' chains have gaps there)
    merged = bool(tri.stats["merged_overlaps"] or tri.stats["duplicate_segments"])
    _check(check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments,
                                  tri.segment_ids, partial=merged), "segment chains")
    _require(np.array_equal(tri.vertices[tri.vertex_map], P), "an input vertex moved or was lost")
    check_vertices_split_segments(P, S, tri)
    order = rng.permutation(len(S))
    S2 = S[order].copy()
    flip = rng.random(len(S2)) < 0.5
    S2[flip] = S2[flip][:, ::-1]
    other = cdt_plugin.triangulate(P, S2, intersections="split", keep_hull=True)
    _same(tri, other, "permuted and reversed segments")


def check_near(rng):
    """Near-concurrent and nearly collinear crossings: snap rounding gives a
    valid mesh in which every segment is the chain of its pieces (through the
    centres of the pixels it meets: an input point may lie within rounding of
    the segment, like a Steiner point), the same for permuted and reversed
    segments."""
    P, S = near_crossings(rng)
    tri = cdt_plugin.triangulate(P, S, intersections="split", keep_hull=True)
    if tri.stats.get("collinear"):
        return
    _check(check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="hull"),
           "split CDT")
    # (merged segments' pieces carry one of their ids: the others' chains have gaps there)
    merged = bool(tri.stats["merged_overlaps"] or tri.stats["duplicate_segments"])
    _check(check_steiner_segments(P, S, tri.vertices, tri.vertex_map, tri.segments,
                                  tri.segment_ids, snapped_inputs=True, partial=merged),
           "segment chains")
    _require(np.array_equal(tri.vertices[tri.vertex_map], P), "an input vertex moved or was lost")
    S2 = S[rng.permutation(len(S))].copy()
    flip = rng.random(len(S2)) < 0.5
    S2[flip] = S2[flip][:, ::-1]
    other = cdt_plugin.triangulate(P, S2, intersections="split", keep_hull=True)
    _same(tri, other, "permuted and reversed segments")


CIRCLE = np.array([[5, 0], [4, 3], [3, 4], [0, 5], [-3, 4], [-4, 3], [-5, 0], [-4, -3], [-3, -4],
                   [0, -5], [3, -4], [4, -3]], float)      # exactly on the circle of radius 5


def check_voronoi(rng):
    P = random_points(rng) if rng.random() < 0.8 else \
        CIRCLE[rng.permutation(12)[:int(rng.integers(3, 13))]] + rng.integers(-3, 4, 2)
    weights = rng.random(len(P)) * 1e-3 if rng.random() < 0.2 else None
    e = int(rng.integers(-300, 300))
    P = np.ldexp(P, e)
    W = None if weights is None else np.ldexp(weights, 2 * e)
    tri = cdt_plugin.delaunay(P, W)
    if not len(tri.triangles):
        try:
            tri.voronoi()
        except cdt_plugin.CollinearPointsError:
            return
        raise FuzzFailure("no triangles, but no CollinearPointsError")
    V, w = tri.vertices, tri.weights
    for face in tri.delaunay_subdivision():
        for i in range(len(face)):
            _require(orient2d_exact(V[face[i - 2]], V[face[i - 1]], V[face[i]]) > 0,
                     f"face {face.tolist()} is not strictly convex")
        for d in face[3:]:
            _require(_lifted_test(V, w, *face[:3], d) == 0, f"face {face.tolist()} is not cocircular")
    lo, hi = V.min(axis=0), V.max(axis=0)
    grow = (hi - lo) * (rng.random(2) - 0.3)            # sometimes inside the points' box
    box = (float(lo[0] - grow[0]), float(lo[1] - grow[1]), float(hi[0] + grow[0]), float(hi[1] + grow[1]))
    if not (box[0] < box[2] and box[1] < box[3]):
        return
    try:
        vor = tri.voronoi(clip=box)
    except cdt_plugin.ClipRegionError:
        inside = (V[:, 0] >= box[0]) & (V[:, 0] <= box[2]) & (V[:, 1] >= box[1]) & (V[:, 1] <= box[3])
        _require(not inside.any(), "ClipRegionError for a box holding points")
        return
    _check_coverage(vor, box)
    if rng.random() < 0.3:
        _check_polygon_clip(tri, e, rng)
    # (at unit scale, where squares neither overflow nor underflow: the scale is a power of two)
    U, cells = np.ldexp(V, -e), [np.ldexp(vor.cell(i), -e) for i in range(len(V))]
    wu = None if w is None else np.ldexp(w, -2 * e)
    q = np.column_stack([rng.uniform(box[0], box[2], 20), rng.uniform(box[1], box[3], 20)])
    for x in np.ldexp(q, -e):
        power = ((U - x) ** 2).sum(axis=1) - (0 if wu is None else wu)
        near = np.flatnonzero(power <= power.min() + 1e-9 * max(1.0, abs(power.min())))
        _require(any(_holds(cells[i], x) for i in near), f"sample {x.tolist()} in no nearest cell")


def _check_polygon_clip(tri, e, rng) -> None:
    """Cells clipped to a polygon (a disc round a random point of the points'
    box, through GEOS) tile it, at unit scale; or the documented errors: no
    point in it, or two sites too close for GEOS beside its coordinates."""
    try:
        import shapely
    except ImportError:
        return
    U = np.ldexp(tri.vertices, -e)
    lo, hi = U.min(axis=0), U.max(axis=0)
    centre = lo + (hi - lo) * rng.random(2)
    disc = shapely.Point(*centre).buffer(float(max(hi - lo)) * (0.1 + rng.random()), 16)
    region = shapely.transform(disc, lambda c: np.ldexp(c, e))
    try:
        cells = tri.voronoi(clip=region).to_shapely()
    except cdt_plugin.ClipRegionError:
        _require(not shapely.contains_xy(disc, U[:, 0], U[:, 1]).any(), "ClipRegionError for a disc holding points")
        return
    except cdt_plugin.CoordinateRangeError as err:
        a, b = err.rows
        gap = np.hypot(*(U[a] - U[b]))
        _require(gap < 2.0 ** -500 * np.abs(disc.bounds).max(), f"CoordinateRangeError for sites {gap} apart")
        return
    area = sum(shapely.transform(c, lambda xy: np.ldexp(xy, -e)).area for c in cells)
    _require(abs(area - disc.area) <= 1e-9 * disc.area, f"polygon-clipped cells cover {area} of {disc.area}")


def _lifted_test(V, w, a, b, c, d) -> int:
    """Exact incircle (weighted: the lifted orientation) of d against a, b, c."""
    if w is None:
        return incircle_exact(V[a], V[b], V[c], V[d])
    from fractions import Fraction
    rows = []
    for v in (a, b, c):
        dx, dy = Fraction(float(V[v, 0])) - Fraction(float(V[d, 0])), Fraction(float(V[v, 1])) - Fraction(float(V[d, 1]))
        lift = (Fraction(float(V[v, 0])) ** 2 + Fraction(float(V[v, 1])) ** 2 - Fraction(float(w[v]))
                - Fraction(float(V[d, 0])) ** 2 - Fraction(float(V[d, 1])) ** 2 + Fraction(float(w[d])))
        rows.append((dx, dy, lift))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    return (det > 0) - (det < 0)


def _check_coverage(vor, box) -> None:
    """The clipped cells tile the box exactly: sides inside it shared, reversed."""
    xmin, ymin, xmax, ymax = box
    edges = set()
    area = 0.0
    for i in range(len(vor.points)):
        ring = [tuple(p) for p in vor.cell(i).tolist()]
        if ring:
            r = np.array(ring) - ring[0]
            area += 0.5 * float(np.dot(r[:, 0], np.roll(r[:, 1], -1)) - np.dot(np.roll(r[:, 0], -1), r[:, 1]))
        for p, q in zip(ring, ring[1:] + ring[:1]):
            _require(xmin <= p[0] <= xmax and ymin <= p[1] <= ymax, f"corner {p} outside the box")
            if not ((p[0] == q[0] and p[0] in (xmin, xmax)) or (p[1] == q[1] and p[1] in (ymin, ymax))):
                _require((p, q) not in edges, f"side {p}-{q} in two cells the same way")
                edges.add((p, q))
    _require(all((q, p) in edges for p, q in edges), "a side inside the box is not shared")
    full = (xmax - xmin) * (ymax - ymin)
    _require(abs(area - full) <= 1e-9 * full, f"cells cover {area} of the box's {full}")


def _holds(ring, x) -> bool:
    if not len(ring):
        return False
    b = np.roll(ring, -1, axis=0)
    cross = (b[:, 0] - ring[:, 0]) * (x[1] - ring[:, 1]) - (b[:, 1] - ring[:, 1]) * (x[0] - ring[:, 0])
    return bool((cross >= -1e-9 * np.hypot(b[:, 0] - ring[:, 0], b[:, 1] - ring[:, 1])
                 * max(1.0, np.abs(ring).max())).all())


def _holders(tri, p):
    """The triangles holding ``p`` (closed), exactly."""
    V = tri.vertices
    return [t for t, (a, b, c) in enumerate(tri.triangles.tolist())
            if orient2d_exact(V[a], V[b], p) >= 0 and orient2d_exact(V[b], V[c], p) >= 0
            and orient2d_exact(V[c], V[a], p) >= 0]


def check_query(rng):
    if rng.random() < 0.5:
        P = np.unique(random_points(rng), axis=0)
        tri = cdt_plugin.delaunay(P)
    else:
        V, S, _ = polygon_with_holes(rng)
        tri = cdt_plugin.triangulate(V, S)
    if len(tri.triangles) == 0:
        return
    V, T = tri.vertices, tri.triangles
    lo, hi = V.min(axis=0), V.max(axis=0)
    pad = (hi - lo) * 0.1
    k = min(len(T), 20)
    Q = np.concatenate([rng.uniform(lo - pad, hi + pad, (30, 2)), V[rng.integers(0, len(V), 10)],
                        (V[T[:k, 0]] + V[T[:k, 1]]) / 2,
                        np.round(rng.uniform(lo, hi, (10, 2)) * 2) / 2])
    found = tri.locate(Q)
    for p, t in zip(Q, found.tolist()):
        holders = _holders(tri, p)
        _require(t == (min(holders) if holders else -1), f"locate {p.tolist()}: {t}, holders {holders}")
    inside = found >= 0
    W = tri.interpolate(np.eye(len(V)), Q[inside], method="natural")
    scale = max(float(np.abs(V).max()), 1e-300)
    _require(bool((W >= 0).all()), f"natural coordinates below zero: {W.min()}")
    _require(np.abs(W.sum(axis=1) - 1).max() < 1e-9, "natural coordinates do not sum to one")
    _require(np.abs(W @ V - Q[inside]).max() < 1e-8 * scale, "natural coordinates miss the point")
    f = 1.5 + 2 * V[:, 0] - 3 * V[:, 1]
    for method in ("linear", "natural"):
        out = tri.interpolate(f, Q, method=method)
        _require(bool((np.isnan(out) == ~inside).all()), f"{method}: NaN where the point is inside")
        want = 1.5 + 2 * Q[inside, 0] - 3 * Q[inside, 1]
        _require(np.abs(out[inside] - want).max() < 1e-8 * max(1.0, scale), f"{method}: not linear")


def check_dynamic(rng):
    k = int(rng.integers(2, 9))
    grid = lambda m: rng.integers(0, k, (m, 2)).astype(float)  # noqa: E731
    split = bool(rng.random() < 0.5)
    dyn = cdt_plugin.DynamicCDT(grid(int(rng.integers(0, 8))), intersections="split" if split else "raise")
    for _ in range(int(rng.integers(1, 10))):
        ids, sids = dyn.vertex_ids, dyn.segment_ids
        before = (dyn.vertices.copy(), dyn.segments.copy())
        op = int(rng.integers(5))
        try:
            if op == 0 or len(ids) < 2:
                dyn.insert_points(grid(int(rng.integers(1, 6))))
            elif op == 1:
                a, b = rng.choice(ids, 2, replace=False)
                dyn.insert_segments([[a, b]])
            elif op == 2:
                dyn.remove_vertices(rng.choice(ids, int(rng.integers(1, 3)), replace=False))
            elif op == 3 and len(sids):
                dyn.remove_segments([rng.choice(sids)])
            else:
                dyn.move_vertices([rng.choice(ids)], grid(1))
        except cdt_plugin.CDTError:
            _require(np.array_equal(dyn.vertices, before[0]) and np.array_equal(dyn.segments, before[1]),
                     "a failed edit changed the triangulation")
        tri = dyn.triangulation()
        V, S = dyn.vertices, dyn.segments
        if len(tri.triangles):
            # split crossings are rounded: the pieces (edges) are the segments then
            S_check = tri.segments if split else S
            _check(check_triangulation(V, tri.triangles, segments=S_check if len(S_check) else None,
                                       domain="hull"), "snapshot")
            if split and len(S):
                # pieces follow their segments up to rounding (partial: an edge where two
                # segments overlap carries one of their ids, as in triangulate)
                rows = np.searchsorted(dyn.segment_ids, tri.segment_ids)
                _check(check_steiner_segments(V, S, V, np.arange(len(V)), tri.segments, rows,
                                              snapped_inputs=True, partial=True), "segment pieces")
            _require(tri.is_delaunay(), "snapshot not Delaunay")
        if len(V) >= 3:
            # with "split" the crossing points are derived: the live vertices
            # less them, and the segments, snap-rounded by triangulate give the same mesh
            keep = np.ones(len(V), bool)
            keep[tri.steiner] = False
            rows = np.cumsum(keep) - 1
            _require(bool(keep[S].all()) if len(S) else True, "a segment ends at a crossing point")
            fresh = cdt_plugin.triangulate(V[keep], rows[S] if len(S) else None, keep_hull=True,
                                           intersections="split" if split else "raise")
            _same(tri, fresh, "snapshot against triangulate")


def check_vertices_split_segments(P, S, tri) -> None:
    """Every input vertex exactly on an input segment ends a piece of it (or of
    a segment on the same line, into which a repeated or overlapping one was
    merged)."""
    P, S = np.asarray(P, np.float64), np.asarray(S, np.int64).reshape(-1, 2)
    for v, k in vertices_on_segments(P, S):
        same_line = [j for j in range(len(S)) if collinear(P, S[k], S[j])]
        _require(tri.vertex_map[v] in tri.segments[np.isin(tri.segment_ids, same_line)],
                 f"vertex {v} lies on segment {k} but does not split it")


def collinear(P, s, t) -> bool:
    """Whether both ends of segment ``t`` lie on the line of segment ``s`` (exact)."""
    from fractions import Fraction
    (ax, ay), (bx, by) = (tuple(map(Fraction, P[i])) for i in s)
    return all((bx - ax) * (Fraction(P[v][1]) - ay) == (by - ay) * (Fraction(P[v][0]) - ax) for v in t)


def vertices_on_segments(P, S):
    """(vertex, segment) with the vertex exactly on the open segment (exact)."""
    from fractions import Fraction
    Q = [(Fraction(x), Fraction(y)) for x, y in P.tolist()]
    out = []
    for k, (a, b) in enumerate(S.tolist()):
        (ax, ay), (bx, by) = Q[a], Q[b]
        if Q[a] == Q[b]:
            continue
        for v, (vx, vy) in enumerate(Q):
            if (vx, vy) in (Q[a], Q[b]) or (bx - ax) * (vy - ay) != (by - ay) * (vx - ax):
                continue
            if min(ax, bx) <= vx <= max(ax, bx) and min(ay, by) <= vy <= max(ay, by):
                out.append((v, k))
    return out


def check_refine(rng):
    V, S, _ = polygon_with_holes(rng)
    min_angle = float(rng.choice([0.0, 20.0, 25.0, 30.0]))
    max_area = float(rng.choice([0.0, 0.01, 0.05])) or None
    if not min_angle and max_area is None:
        max_area = 0.02
    try:
        tri = cdt_plugin.triangulate(V, S, min_angle=min_angle or None, max_area=max_area,
                                     max_steiner=20_000)
    except RefinementLimitError as exc:
        raise FuzzFailure(f"refinement did not finish: {exc}") from None
    _check_cdt_result(V, S, tri)
    _check(check_steiner_segments(V, S, tri.vertices, tri.vertex_map, tri.segments, tri.segment_ids),
           "segment chains")
    q = triangle_quality(tri.vertices, tri.triangles)
    if min_angle:
        low = np.flatnonzero(q["angles"].min(axis=1) < min_angle * (1 - 1e-9))
        _require(set(low.tolist()) <= set(tri.below_min_angle.tolist()),
                 f"{len(set(low.tolist()) - set(tri.below_min_angle.tolist()))} triangles below "
                 f"{min_angle} degrees not listed in below_min_angle")
    if max_area:
        a, b, c = (tri.vertices[tri.triangles[:, j]] for j in range(3))
        area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
        _require(area.max() <= max_area * (1 + 1e-12), f"a triangle of area {area.max()} > {max_area}")
    V2, S2 = permuted(rng, V, S)
    other = cdt_plugin.triangulate(V2, S2, min_angle=min_angle or None, max_area=max_area,
                                   max_steiner=20_000)
    _same(tri, other, "refined, permuted and reversed input")


def permuted(rng, V, S):
    """The same PLC with its vertices and segments in random order and each
    segment in a random direction."""
    perm = rng.permutation(len(V))
    S2 = np.argsort(perm)[S][rng.permutation(len(S))]
    flip = rng.random(len(S2)) < 0.5
    S2[flip] = S2[flip][:, ::-1]
    return V[perm], S2


CHECKS = {"delaunay": check_delaunay, "cdt": check_cdt, "split": check_split, "refine": check_refine,
          "near": check_near, "voronoi": check_voronoi, "query": check_query, "dynamic": check_dynamic}


def run_case(family: str, case: int, seed: int = 0) -> None:
    """One case; raises on any failure."""
    rng = np.random.default_rng(seed * 1_000_003 + case * 7 + FAMILIES.index(family))
    CHECKS[family](rng)


def run(count: int, families=FAMILIES, seed: int = 0, stop: bool = True, out=sys.stdout) -> list:
    """``count`` cases spread over ``families``; returns the failures as
    ``(family, case, message)`` (stops at the first unless ``stop`` is False)."""
    failures = []
    for case in range(count):
        family = families[case % len(families)]
        try:
            run_case(family, case, seed)
        except Exception as exc:    # noqa: BLE001 - every failure is reported with its reproducer
            failures.append((family, case, f"{type(exc).__name__}: {exc}"))
            print(f"FAIL --family {family} --case {case} --seed {seed}: {type(exc).__name__}: {exc}",
                  file=out)
            if stop:
                break
    return failures


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--family", default=",".join(FAMILIES))
    ap.add_argument("--case", type=int, default=None, help="run this one case (a reproducer)")
    ap.add_argument("--keep-going", action="store_true", help="report every failure")
    args = ap.parse_args(argv)
    families = tuple(args.family.split(","))
    if args.case is not None:
        run_case(families[0], args.case, args.seed)
        print("ok")
        return 0
    t0 = time.perf_counter()
    failures = run(args.count, families, args.seed, stop=not args.keep_going)
    print(f"{args.count} cases ({', '.join(families)}), seed {args.seed}: {len(failures)} failed "
          f"in {time.perf_counter() - t0:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
