"""Mesh smoothing: sweeps that move the free vertices of a triangulation (ODT, Lloyd).

The mesh is a half-edge store in :mod:`.mesh`'s layout, made from a result's
arrays by :func:`smoothing_store`: its ``k`` triangles, then a ghost triangle
across each boundary edge, so that every half-edge of the mesh has a twin (a
flip links the outer edges of its quadrilateral to theirs); the ghosts are not
linked to each other and never flip. ``cons`` labels the edges that never flip
(:data:`FLIPPABLE` the others): :data:`REGION_EDGE` (between triangles of
different regions), :data:`BOUNDARY_EDGE` (the domain's boundary where it is
no segment) and ``SEGMENT_BASE + id + 1`` for a piece of segment ``id`` (-1: a
piece of the boundary): the flip algorithm of :mod:`.flips` skips them all, so
after each sweep :func:`restore_delaunay` makes the mesh constrained Delaunay
again (Sec. 2.5, 2.10.3) with every segment and the boundary kept.

:func:`vertex_roles` says which vertex may move: a Steiner vertex on no such
edge moves freely (:data:`FREE`); one with exactly two, of the same segment
(or both on the boundary), slides along the line through the ends of its
chain of pieces (:data:`SLIDES`); every other vertex stays (:data:`FIXED`).

:func:`smooth_sweep` visits the movable vertices in order (Gauss-Seidel) and
moves each toward its target:

* ODT (optimal Delaunay triangulation, Chen & Xu; Alliez et al.): the mean of
  the circumcentres of its star's triangles weighted by their area times the
  density ``1 / h**2`` (``h`` the size at the triangle: the mean of its
  corners');
* Lloyd (centroidal Voronoi): the centroid of its Voronoi cell cut to its star
  (in each triangle, the part nearer to it than to the other two corners),
  weighted by the same density.

A vertex on a segment goes to the one-dimensional analogue between its two
neighbours along the chain (ODT: where the two pieces' lengths are in the
ratio of their sizes; Lloyd: the centroid of the segment between the midpoints),
then onto the line through the chain's ends. A move is tried whole, then a
half and a quarter of the way, and kept only if every triangle of the star
stays counter-clockwise (exact orientation), the smallest angle of the star
does not go below its value before the move (or below ``min(before, bound)``
with an angle bound), and the sum of the star's radius ratios does not fall.
"""
from __future__ import annotations

import math

import numpy as np

from .flips import flip_from_stack
from .jit import entry, kernel
from .kernel import orient
from .output import min_first

FLIPPABLE = 0
REGION_EDGE = 1
BOUNDARY_EDGE = 2
SEGMENT_BASE = 3            # ``cons`` of a piece of segment ``id``: SEGMENT_BASE + id + 1

FIXED = 0
FREE = 1
SLIDES = 2

ODT = 0
LLOYD = 1

_STEPS = (1.0, 0.5, 0.25)   # the fractions of a move that are tried


@entry
def smoothing_store(T, N, code, inf):
    """``(tri, twin, cons)``: the half-edge store of counter-clockwise triangles
    ``T`` with neighbours ``N`` (``N[t, j]`` across the edge opposite corner
    ``j``, -1: none) and ``code[t, j]`` the label of that edge. Half-edge
    ``3t + i`` runs from ``T[t, i]`` to ``T[t, i + 1]`` (opposite corner
    ``i + 2``). After the ``k`` triangles, a ghost triangle ``(b, a, inf)``
    across each boundary edge ``a -> b`` (:mod:`.mesh`'s flips link the
    outer edges of a flip to their twins, which must exist); ghosts never
    flip (a boundary edge is never flippable), and the kernels below take
    the store's first ``3 k`` entries of ``tri`` as the mesh."""
    k = T.shape[0]
    g = 0
    for t in range(k):
        for j in range(3):
            if N[t, j] < 0:
                g += 1
    tri = np.empty(3 * (k + g), np.int32)
    twin = np.full(3 * (k + g), -1, np.int32)
    cons = np.zeros(3 * (k + g), np.int32)
    ghost = k
    for t in range(k):
        for i in range(3):
            e = 3 * t + i
            tri[e] = T[t, i]
            cons[e] = code[t, (i + 2) % 3]
            u = N[t, (i + 2) % 3]
            a = T[t, i]
            b = T[t, (i + 1) % 3]
            if u < 0:
                tri[3 * ghost] = b
                tri[3 * ghost + 1] = a
                tri[3 * ghost + 2] = inf
                cons[3 * ghost] = cons[e]
                twin[e] = 3 * ghost
                twin[3 * ghost] = e
                ghost += 1
                continue
            for m in range(3):
                if T[u, m] == b and T[u, (m + 1) % 3] == a:
                    twin[e] = 3 * u + m
    return tri, twin, cons


@entry
def vertex_roles(tri, twin, cons, n, steiner, on_segments):
    """``(role, chain, ends)`` of the ``n`` vertices: each one's :data:`FIXED`,
    :data:`FREE` or :data:`SLIDES`; for a sliding vertex its two neighbours
    along its chain of pieces and the chain's two ends (the first vertex each
    way that does not slide), -1 elsewhere. ``steiner`` (n,) bool: the
    vertices that may move at all; ``on_segments`` False: none slides."""
    count = np.zeros(n, np.int64)
    label = np.full(n, -1, np.int64)
    chain = np.full((n, 2), -1, np.int64)
    mixed = np.zeros(n, np.bool_)
    for e in range(tri.shape[0]):
        if cons[e] == FLIPPABLE or (twin[e] >= 0 and twin[e] < e):
            continue                     # (an edge inside: listed from its smaller half-edge)
        a = tri[e]
        b = tri[e + 1] if e % 3 != 2 else tri[e - 2]
        note_edge(count, label, chain, mixed, a, b, cons[e])
        note_edge(count, label, chain, mixed, b, a, cons[e])
    role = np.zeros(n, np.int8)
    for v in range(n):
        if not steiner[v]:
            continue
        if count[v] == 0:
            role[v] = FREE
        elif (on_segments and count[v] == 2 and not mixed[v] and label[v] >= BOUNDARY_EDGE
              and chain[v, 0] != chain[v, 1]):
            role[v] = SLIDES
    ends = np.full((n, 2), -1, np.int64)
    for v in range(n):
        if role[v] != SLIDES or ends[v, 0] >= 0:
            continue
        first = walk_chain(role, chain, ends, v, chain[v, 0], n, np.int64(-1), np.int64(-1))
        last = walk_chain(role, chain, ends, v, chain[v, 1], n, np.int64(-1), np.int64(-1))
        if first < 0 or last < 0:        # (a closed loop of sliding vertices: none moves)
            first = last = np.int64(-1)
        ends[v, 0] = first
        ends[v, 1] = last
        walk_chain(role, chain, ends, v, chain[v, 0], n, first, last)
        walk_chain(role, chain, ends, v, chain[v, 1], n, first, last)
    for v in range(n):
        if role[v] == SLIDES and ends[v, 0] < 0:
            role[v] = FIXED
    return role, chain, ends


@kernel
def note_edge(count, label, chain, mixed, v, w, code):
    """Count the unflippable edge ``v``-``w`` (label ``code``) at ``v``."""
    if count[v] < 2:
        chain[v, count[v]] = w
    if label[v] >= 0 and label[v] != code:
        mixed[v] = True
    label[v] = code
    count[v] += 1


@kernel
def walk_chain(role, chain, ends, v, w, n, first, last):
    """Walk from ``v`` through its neighbour ``w`` along the chain to the first
    vertex that does not slide, and return it (-1 after ``n`` steps: a closed
    loop); with ``first >= 0``, give every sliding vertex passed the ends
    ``first, last``."""
    prev = v
    cur = w
    for _ in range(n + 1):
        if role[cur] != SLIDES:
            return cur
        if first >= 0:
            ends[cur, 0] = first
            ends[cur, 1] = last
        step = chain[cur, 1] if chain[cur, 0] == prev else chain[cur, 0]
        prev = cur
        cur = step
    return np.int64(-1)


@kernel(inline="always")
def triangle_quality(ax, ay, bx, by, cx, cy):
    """``(sin^2 of the smallest angle, radius ratio 2 r / R)`` of triangle ``a, b, c``."""
    a2 = (bx - cx) ** 2 + (by - cy) ** 2
    b2 = (cx - ax) ** 2 + (cy - ay) ** 2
    c2 = (ax - bx) ** 2 + (ay - by) ** 2
    cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    prod = a2 * b2 * c2
    if cross <= 0.0 or prod <= 0.0:
        return 0.0, 0.0
    shortest = min(a2, b2, c2)
    sin2 = cross * cross * shortest / prod       # (the smallest angle faces the shortest side)
    perimeter = math.sqrt(a2) + math.sqrt(b2) + math.sqrt(c2)
    return sin2, 4.0 * cross * cross / (perimeter * math.sqrt(prod))


@kernel(inline="always")
def density(h, a, b, c):
    """``1 / h**2`` at triangle ``a, b, c`` (``h`` empty: 1)."""
    if h.shape[0] == 0:
        return 1.0
    s = (h[a] + h[b] + h[c]) / 3.0
    return 1.0 / (s * s)


@kernel(inline="always")
def clip_half_plane(px, py, m, qx, qy, nx, ny, limit):
    """The polygon ``px, py`` (``m`` corners) cut to ``nx * x + ny * y <= limit``,
    written to ``qx, qy``; returns its number of corners (Sutherland-Hodgman)."""
    k = 0
    for i in range(m):
        j = (i + 1) % m
        si = nx * px[i] + ny * py[i] - limit
        sj = nx * px[j] + ny * py[j] - limit
        if si <= 0.0:
            qx[k] = px[i]
            qy[k] = py[i]
            k += 1
        if (si < 0.0 < sj) or (sj < 0.0 < si):
            f = si / (si - sj)
            qx[k] = px[i] + f * (px[j] - px[i])
            qy[k] = py[i] + f * (py[j] - py[i])
            k += 1
    return k


@kernel(_nrt=False)
def free_target(x, y, h, tri, first, star, v, method, px, py, qx, qy):
    """The target of free vertex ``v`` (ODT or Lloyd, module notes), relative to
    it: ``(dx, dy, ok)``. ``px .. qy``: scratch room for the clipped cells."""
    vx = x[v]
    vy = y[v]
    sw = 0.0
    sx = 0.0
    sy = 0.0
    for s in range(first[v], first[v + 1]):
        e = star[s]
        b = tri[e + 1] if e % 3 != 2 else tri[e - 2]
        c = tri[e - 1] if e % 3 != 0 else tri[e + 2]
        bx = x[b] - vx
        by = y[b] - vy
        cx = x[c] - vx
        cy = y[c] - vy
        d = 2.0 * (bx * cy - by * cx)
        if d <= 0.0:
            continue
        rho = density(h, v, b, c)
        if method == ODT:
            b2 = bx * bx + by * by
            c2 = cx * cx + cy * cy
            w = d * rho                                   # (the area, times 4)
            sx += w * (cy * b2 - by * c2) / d
            sy += w * (bx * c2 - cx * b2) / d
            sw += w
            continue
        # Lloyd: the part of the triangle nearer to v than to b and c
        px[0] = 0.0
        py[0] = 0.0
        px[1] = bx
        py[1] = by
        px[2] = cx
        py[2] = cy
        m = clip_half_plane(px, py, 3, qx, qy, bx, by, 0.5 * (bx * bx + by * by))
        m = clip_half_plane(qx, qy, m, px, py, cx, cy, 0.5 * (cx * cx + cy * cy))
        area2 = 0.0
        mx = 0.0
        my = 0.0
        for i in range(m):
            j = (i + 1) % m
            f = px[i] * py[j] - px[j] * py[i]
            area2 += f
            mx += (px[i] + px[j]) * f
            my += (py[i] + py[j]) * f
        if area2 <= 0.0:
            continue
        sx += rho * mx / 3.0          # (rho * area * centroid: the shoelace sums, halved twice)
        sy += rho * my / 3.0
        sw += rho * area2
    if sw <= 0.0:
        return 0.0, 0.0, False
    return sx / sw, sy / sw, True


@kernel(_nrt=False)
def slide_target(x, y, h, chain, v, method):
    """The target of sliding vertex ``v`` between its chain neighbours (module notes)."""
    a = chain[v, 0]
    b = chain[v, 1]
    ha = hv = hb = 1.0
    if h.shape[0] > 0:
        ha = h[a]
        hv = h[v]
        hb = h[b]
    h1 = 0.5 * (ha + hv)
    h2 = 0.5 * (hv + hb)
    if method == ODT:       # piece lengths in the ratio h1 : h2
        return ((x[a] * h2 + x[b] * h1) / (h1 + h2), (y[a] * h2 + y[b] * h1) / (h1 + h2))
    l1 = 0.5 * math.hypot(x[v] - x[a], y[v] - y[a]) / (h1 * h1)
    l2 = 0.5 * math.hypot(x[b] - x[v], y[b] - y[v]) / (h2 * h2)
    if l1 + l2 <= 0.0:
        return x[v], y[v]
    # centroid of [m1, v] and [v, m2] (m the midpoints), each weighted by length / h^2
    c1x = 0.5 * (0.5 * (x[a] + x[v]) + x[v])
    c1y = 0.5 * (0.5 * (y[a] + y[v]) + y[v])
    c2x = 0.5 * (x[v] + 0.5 * (x[v] + x[b]))
    c2y = 0.5 * (y[v] + 0.5 * (y[v] + y[b]))
    return (l1 * c1x + l2 * c2x) / (l1 + l2), (l1 * c1y + l2 * c2y) / (l1 + l2)


@kernel(_nrt=False)
def star_quality(x, y, tri, first, star, v):
    """``(valid, smallest sin^2, sum of radius ratios)`` over ``v``'s star;
    ``valid``: every triangle counter-clockwise (exact)."""
    low = math.inf
    total = 0.0
    for s in range(first[v], first[v + 1]):
        e = star[s]
        b = tri[e + 1] if e % 3 != 2 else tri[e - 2]
        c = tri[e - 1] if e % 3 != 0 else tri[e + 2]
        if orient(x, y, v, b, c) <= 0.0:
            return False, 0.0, 0.0
        q, r = triangle_quality(x[v], y[v], x[b], y[b], x[c], y[c])
        low = min(low, q)
        total += r
    return True, low, total


@kernel(_nrt=False)
def try_move(x, y, tri, first, star, v, tx, ty, floor2, slide, P, Q):
    """Move ``v`` toward ``(tx, ty)``: the whole way, a half or a quarter, the
    first that keeps its star valid and no worse (module notes); a sliding
    vertex is put on the line ``P``-``Q`` (vertex ids). Returns whether it moved."""
    vx = x[v]
    vy = y[v]
    ok, low, total = star_quality(x, y, tri, first, star, v)
    if not ok:
        return False
    need = min(low, floor2)
    t0 = 0.0
    t1 = 0.0
    dx = 0.0
    dy = 0.0
    if slide:
        dx = x[Q] - x[P]
        dy = y[Q] - y[P]
        ll = dx * dx + dy * dy
        if ll <= 0.0:
            return False
        t0 = ((vx - x[P]) * dx + (vy - y[P]) * dy) / ll
        t1 = ((tx - x[P]) * dx + (ty - y[P]) * dy) / ll
    for f in _STEPS:
        if slide:
            t = t0 + f * (t1 - t0)
            nx = x[P] + t * dx
            ny = y[P] + t * dy
        else:
            nx = vx + f * (tx - vx)
            ny = vy + f * (ty - vy)
        if nx == vx and ny == vy:
            return False
        x[v] = nx
        y[v] = ny
        ok, new_low, new_total = star_quality(x, y, tri, first, star, v)
        if ok and new_low >= need and new_total >= total:
            return True
    x[v] = vx
    y[v] = vy
    return False


@entry
def smooth_sweep(tri, x, y, h, role, chain, ends, method, floor2, active, moved):
    """One Gauss-Seidel sweep over the movable vertices that are ``active``
    (module notes), in place on ``x, y``; ``h`` the size at each vertex (empty:
    uniform), ``floor2`` sin^2 of the angle bound that a star may fall to
    (``inf``: none, a star's smallest angle never falls). Sets ``moved`` for
    the vertices that moved and returns their number. (A vertex whose star has
    not changed since it last stayed put would stay put again: its target and
    its tests are the same, so :func:`restore_delaunay` leaves it inactive.)"""
    n = x.shape[0]
    first = np.zeros(n + 1, np.int64)
    for e in range(tri.shape[0]):
        first[tri[e] + 1] += 1
    for v in range(n):
        first[v + 1] += first[v]
    fill = first[:n].copy()
    star = np.empty(tri.shape[0], np.int64)      # the half-edges out of each vertex
    for e in range(tri.shape[0]):
        v = tri[e]
        star[fill[v]] = e
        fill[v] += 1
    px = np.empty(8)
    py = np.empty(8)
    qx = np.empty(8)
    qy = np.empty(8)
    count = 0
    for v in range(n):
        moved[v] = False
        if not active[v]:
            continue
        if role[v] == FREE:
            dx, dy, ok = free_target(x, y, h, tri, first, star, v, method, px, py, qx, qy)
            moved[v] = ok and try_move(x, y, tri, first, star, v, x[v] + dx, y[v] + dy, floor2,
                                       False, np.int64(0), np.int64(0))
        elif role[v] == SLIDES:
            tx, ty = slide_target(x, y, h, chain, v, method)
            moved[v] = try_move(x, y, tri, first, star, v, tx, ty, floor2, True, ends[v, 0], ends[v, 1])
        if moved[v]:
            count += 1
    return count


@entry
def restore_delaunay(tri, twin, cons, x, y, inf, k, moved, active):
    """The flip algorithm (:func:`.flips.flip_from_stack`) from the edges of the
    triangles with a ``moved`` corner, the others being locally Delaunay
    already (or from every edge, when every vertex counts as moved: a mesh
    not yet known to be constrained Delaunay). Sets ``active`` for the corners
    of every triangle that has a moved corner or that a flip changed: the
    vertices whose stars changed (``k`` triangles, then the ghosts). Returns
    the number of flips, -1 past the bound of :func:`.flips.flip_from_stack`
    (never met: the mesh is a valid triangulation, and each flip lowers the
    lifted surface, Prop. 2.5)."""
    before = tri[:3 * k].copy()
    near = np.zeros(k, np.bool_)              # the triangles with a moved corner
    for t in range(k):
        near[t] = moved[tri[3 * t]] or moved[tri[3 * t + 1]] or moved[tri[3 * t + 2]]
    stack = np.empty(3 * k + 16, np.int64)
    sp = np.int64(0)
    for e in range(3 * k):         # each edge of those once (from its smaller half-edge, or its only near one)
        if near[e // 3] and cons[e] == FLIPPABLE and (e < twin[e] or not near[twin[e] // 3]):
            stack[sp] = e
            sp += 1
    flips = flip_from_stack((tri, twin, cons, x, y, inf), (x, False), stack, sp, np.int64(20 * k + 1000))
    for v in range(active.shape[0]):
        active[v] = False
    for t in range(k):
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        if (moved[a] or moved[b] or moved[c] or a != before[3 * t] or b != before[3 * t + 1]
                or c != before[3 * t + 2]):
            active[a] = True
            active[b] = True
            active[c] = True
    return flips


@entry
def mean_edge_lengths(tri, twin, x, y):
    """Each vertex's mean edge length (1 for a vertex on no edge)."""
    n = x.shape[0]
    total = np.zeros(n)
    count = np.zeros(n)
    for e in range(tri.shape[0]):
        if twin[e] >= 0 and twin[e] < e:
            continue                     # (listed from the smaller half-edge)
        a = tri[e]
        b = tri[e + 1] if e % 3 != 2 else tri[e - 2]
        d = math.hypot(x[a] - x[b], y[a] - y[b])
        total[a] += d
        total[b] += d
        count[a] += 1.0
        count[b] += 1.0
    for v in range(n):
        total[v] = total[v] / count[v] if count[v] > 0 and total[v] > 0 else 1.0
    return total


@entry
def smoothed_arrays(tri, twin, cons):
    """``(triangles, neighbors, constrained)`` of the store's triangles ``tri``
    (its first ``3 k`` entries, without the ghosts), each triangle
    listed from its smallest vertex id; ``constrained``: the segment pieces."""
    k = tri.shape[0] // 3
    T = np.empty((k, 3), np.int64)
    N = np.empty((k, 3), np.int64)
    C = np.empty((k, 3), np.bool_)
    for t in range(k):
        r = min_first(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2])
        for j in range(3):
            i = (j + r) % 3              # corner j of the output is corner i of the store
            T[t, j] = tri[3 * t + i]
            e = 3 * t + (i + 1) % 3      # the half-edge opposite corner i
            N[t, j] = twin[e] // 3 if 0 <= twin[e] < tri.shape[0] else -1   # (a ghost: none)
            C[t, j] = cons[e] >= SEGMENT_BASE
    return T, N, C
