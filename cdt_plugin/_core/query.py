"""Queries on a finished triangulation: point location and interpolation.

The triangles are given as ``T`` (k, 3) vertex ids, counter-clockwise, and ``N``
(k, 3) with ``N[t, j]`` the triangle across the edge opposite corner ``j``
(-1 on the boundary). They must cover a convex region (the caller completes a
non-convex domain with the triangles of its complement in the convex hull;
``own[t]`` is then the domain triangle's id, or -1 for a filler triangle), so
that a visibility walk always reaches the query or a hull edge it lies beyond.

Coordinates: ``x, y`` the vertices', ``qx, qy`` the query points' (both
scaled by the same power of two into the exact predicates' range).
"""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel
from .predicates import double_double, orient_expansion, incircle, orient2d

INSIDE = 0
ON_EDGE = 1
ON_VERTEX = 2
OUTSIDE = -1

AREAS_OK = 0      # stolen_areas: the natural neighbour coordinates are good
NOT_STAR = 1      # the cavity is not a disk the point sees whole (a segment is in the way)
IMPRECISE = 2     # far circumcentres cancelled the areas' digits


@kernel
def classify(o0, o1, o2):
    """``(code, j)`` for a point with edge orientations ``o_j >= 0`` in a triangle:
    inside; on edge ``j`` (the edge opposite corner ``j``); on corner ``j``."""
    zeros = (o0 == 0) + (o1 == 0) + (o2 == 0)
    if zeros == 0:
        return INSIDE, 0
    if zeros == 1:
        return ON_EDGE, 0 if o0 == 0 else (1 if o1 == 0 else 2)
    # two edges through the point meet at the corner that is on neither
    if o0 != 0:
        return ON_VERTEX, 0
    if o1 != 0:
        return ON_VERTEX, 1
    return ON_VERTEX, 2


@kernel
def walk(T, N, x, y, px, py, t):
    """Visibility walk from triangle ``t`` to point ``(px, py)`` (exact
    orientations).

    Returns ``(t, code, j)``: the triangle and :func:`classify`'s code, or
    ``OUTSIDE`` with ``t, j`` the boundary edge that ``q`` lies strictly beyond.
    The first edge tested rotates with the step (a walk cannot cycle then, in
    practice); a walk that runs unusually long falls back to a scan.
    """
    came = -1
    for step in range(64 + 4 * T.shape[0]):
        r = step % 3
        moved = False
        o0 = 1.0
        o1 = 1.0
        o2 = 1.0
        for k in range(3):
            j = (r + k) % 3
            nb = N[t, j]
            if nb == came and nb >= 0:
                continue     # q is strictly on this side of the edge we crossed
            a = T[t, (j + 1) % 3]
            b = T[t, (j + 2) % 3]
            oj = orient2d(x[a], y[a], x[b], y[b], px, py)
            if oj < 0:
                if nb < 0:
                    return t, OUTSIDE, j
                came = t
                t = nb
                moved = True
                break
            if j == 0:
                o0 = oj
            elif j == 1:
                o1 = oj
            else:
                o2 = oj
        if not moved:
            code, j = classify(o0, o1, o2)
            return t, code, j
    return scan(T, x, y, px, py)


@kernel
def scan(T, x, y, px, py):
    """Brute-force location (the walk's safety net): the first triangle that
    contains ``q``, or ``(-1, OUTSIDE, 0)``."""
    for t in range(T.shape[0]):
        a = T[t, 0]
        b = T[t, 1]
        c = T[t, 2]
        o0 = orient2d(x[b], y[b], x[c], y[c], px, py)
        o1 = orient2d(x[c], y[c], x[a], y[a], px, py)
        o2 = orient2d(x[a], y[a], x[b], y[b], px, py)
        if o0 >= 0 and o1 >= 0 and o2 >= 0:
            code, j = classify(o0, o1, o2)
            return t, code, j
    return -1, OUTSIDE, 0


@entry
def locate_all(T, N, own, first_at, x, y, qx, qy, order):
    """Locate every query ``order[i]`` (walking from the previous hit, so spatially
    sorted queries walk little). Returns ``(found, where, code, j)`` per query:
    ``found`` the domain triangle (-1 outside the domain), chosen
    deterministically when the query is on an edge or a vertex (the smallest id
    among the domain triangles that contain it: ``first_at[v]`` is that for
    vertex ``v``); ``where, code, j`` the walk's triangle and its position there."""
    m = order.shape[0]
    found = np.full(m, -1, np.int64)
    where = np.full(m, -1, np.int64)
    codes = np.full(m, OUTSIDE, np.int64)
    js = np.zeros(m, np.int64)
    if T.shape[0] == 0:
        return found, where, codes, js
    t = 0
    for i in order:
        s, code, j = walk(T, N, x, y, qx[i], qy[i], t)
        if s < 0:
            continue
        t = s
        where[i] = s
        codes[i] = code
        js[i] = j
        if code == INSIDE:
            found[i] = own[s]
        elif code == ON_EDGE:
            a = own[s]
            nb = N[s, j]
            b = own[nb] if nb >= 0 else -1
            found[i] = a if b < 0 or (0 <= a < b) else b
        elif code == ON_VERTEX:
            found[i] = first_at[T[s, j]]
    return found, where, codes, js


@kernel
def area2(ax, ay, bx, by, cx, cy):
    """Twice the signed area of (a, b, c) to a relative error below 1e-7: in
    floating point, or from the exact determinant when the two products cancel
    (a sliver, a point nearly on an edge)."""
    left = (bx - ax) * (cy - ay)
    right = (by - ay) * (cx - ax)
    det = left - right
    if abs(det) >= 1e-8 * (abs(left) + abs(right)):
        return det
    w = np.empty(80)
    n = orient_expansion(w, 0, ax, ay, bx, by, cx, cy)
    hi, _ = double_double(w, 8, n)
    return hi


@kernel
def linear_weights(x, y, a, b, c, qx, qy):
    """Barycentric coordinates of point ``(qx, qy)`` in triangle ``(a, b, c)``
    (which holds it): three sub-areas accurate in slivers too, rounding below
    zero clamped to zero."""
    la = max(area2(qx, qy, x[b], y[b], x[c], y[c]), 0.0)
    lb = max(area2(x[a], y[a], qx, qy, x[c], y[c]), 0.0)
    lc = max(area2(x[a], y[a], x[b], y[b], qx, qy), 0.0)
    d = la + lb + lc
    return la / d, lb / d, lc / d


@kernel
def add_weighted(out, i, values, v, lam):
    for c in range(values.shape[1]):
        out[i, c] += lam * values[v, c]


@entry
def interpolate_linear(T, x, y, qx, qy, found, values):
    """Linear interpolation of vertex ``values`` (n, c) at every located query
    (NaN where ``found`` is -1). A query on a vertex gets its value exactly."""
    m = found.shape[0]
    out = np.full((m, values.shape[1]), np.nan)
    for i in range(m):
        t = found[i]
        if t >= 0:
            put_linear(out, i, T, x, y, qx[i], qy[i], t, values)
    return out


@kernel
def put_linear(out, i, T, x, y, qx, qy, t, values):
    """Row ``i`` of ``out``: the linear interpolant in triangle ``t`` at ``(qx, qy)``
    (a vertex's own value exactly when the point is that vertex)."""
    a = T[t, 0]
    b = T[t, 1]
    c = T[t, 2]
    for v in (a, b, c):
        if x[v] == qx and y[v] == qy:
            for col in range(values.shape[1]):
                out[i, col] = values[v, col]
            return
    la, lb, lc = linear_weights(x, y, a, b, c, qx, qy)
    for col in range(values.shape[1]):
        out[i, col] = 0.0
    add_weighted(out, i, values, a, la)
    add_weighted(out, i, values, b, lb)
    add_weighted(out, i, values, c, lc)


@kernel
def put_on_edge(out, i, x, y, a, b, qx, qy, values):
    """Row ``i`` of ``out``: the linear interpolant along edge ``a b`` at a point
    strictly inside it (two weights in [0, 1], the others exactly zero)."""
    dx = x[b] - x[a]
    dy = y[b] - y[a]
    s = ((qx - x[a]) * dx + (qy - y[a]) * dy) / (dx * dx + dy * dy)
    s = min(1.0, max(0.0, s))
    for col in range(values.shape[1]):
        out[i, col] = 0.0
    add_weighted(out, i, values, a, 1.0 - s)
    add_weighted(out, i, values, b, s)


@kernel(forceinline=True)
def circumcentre(ax, ay, bx, by, cx, cy):
    """Circumcentre of (a, b, c), coordinates relative to any origin (the
    caller puts the query at the origin for accuracy)."""
    bx -= ax
    by -= ay
    cx -= ax
    cy -= ay
    d = 2.0 * (bx * cy - by * cx)
    if d == 0.0:
        return np.nan, np.nan     # a sliver flat in floating point: the caller sees NaN areas
    b2 = bx * bx + by * by
    c2 = cx * cx + cy * cy
    return ax + (cy * b2 - by * c2) / d, ay + (bx * c2 - cx * b2) / d


@entry
def interpolate_natural(T, N, blocked, x, y, qx, qy, found, where, codes, js, values):
    """Sibson's natural neighbour interpolation at every located query.

    The query's cavity (the triangles whose circumcircle holds it strictly,
    reached without crossing a ``blocked`` edge: a segment, the domain's
    boundary, an edge that is not locally Delaunay) is what inserting it would
    retriangulate; the area its new Voronoi cell takes from each cavity vertex's
    cell, over the cell's area, is that vertex's coordinate. Both areas come
    from circumcentres: the new cell's corners are the centres of the fan
    (query, a, b) over the cavity's boundary edges, and the part taken from
    vertex v is bounded by two of them and the centres of the cavity triangles
    around v. A query on a vertex gets its value; one on a blocked edge (where
    the cell is unbounded or split) the linear interpolant along that edge.
    Returns ``(out, fallbacks)``: the values, and how many queries fell back to
    the linear interpolant because a segment hid part of their cavity and
    because rounding spoilt their areas (see :func:`stolen_areas`).
    """
    m = found.shape[0]
    k = T.shape[0]
    ncol = values.shape[1]
    out = np.full((m, ncol), np.nan)
    stamp = np.zeros(k, np.int64)       # cavity membership: query number + 1
    stack = np.empty(k, np.int64)
    cavity = np.empty(k, np.int64)
    nv = x.shape[0]
    edge_at = np.full(nv, -1, np.int64)  # boundary edge leaving vertex v
    edge_stamp = np.zeros(nv, np.int64)
    ea = np.empty(k + 3, np.int64)      # boundary edges: a -> b in triangle et
    eb = np.empty(k + 3, np.int64)
    et = np.empty(k + 3, np.int64)
    area = np.empty(k + 3)
    fallbacks = np.zeros(2, np.int64)
    for i in range(m):
        t0 = found[i]
        if t0 < 0:
            continue
        px = qx[i]
        py = qy[i]
        s = where[i]
        if codes[i] == ON_VERTEX:
            put_linear(out, i, T, x, y, px, py, s, values)
            continue
        if codes[i] == ON_EDGE and blocked[s, js[i]]:
            put_on_edge(out, i, x, y, T[s, (js[i] + 1) % 3], T[s, (js[i] + 2) % 3], px, py, values)
            continue
        # the cavity, flooded from the walk's triangle
        mark = i + 1
        stamp[s] = mark
        stack[0] = s
        sp = 1
        nc = 0
        while sp > 0:
            sp -= 1
            t = stack[sp]
            cavity[nc] = t
            nc += 1
            for j in range(3):
                nb = N[t, j]
                if blocked[t, j] or stamp[nb] == mark:
                    continue
                if incircle(x[T[nb, 0]], y[T[nb, 0]], x[T[nb, 1]], y[T[nb, 1]],
                            x[T[nb, 2]], y[T[nb, 2]], px, py) > 0:
                    stamp[nb] = mark
                    stack[sp] = nb
                    sp += 1
        # its boundary edges, each vertex leaving by one
        ne = 0
        disk = True
        for c in range(nc):
            t = cavity[c]
            for j in range(3):
                nb = N[t, j]
                if not blocked[t, j] and stamp[nb] == mark:
                    continue
                a = T[t, (j + 1) % 3]
                if edge_stamp[a] == mark:
                    disk = False
                edge_stamp[a] = mark
                edge_at[a] = ne
                ea[ne] = a
                eb[ne] = T[t, (j + 2) % 3]
                et[ne] = t
                ne += 1
        verdict = NOT_STAR
        if disk:
            verdict = stolen_areas(T, N, x, y, px, py, ea, eb, et, ne, edge_at, edge_stamp, mark, area)
        if verdict != AREAS_OK:
            fallbacks[verdict - 1] += 1
            put_linear(out, i, T, x, y, px, py, s, values)
            continue
        total = 0.0
        for e in range(ne):
            total += area[e]
        for col in range(ncol):
            out[i, col] = 0.0
        for e in range(ne):
            add_weighted(out, i, values, ea[e], area[e] / total)
    return out, fallbacks


@kernel
def stolen_areas(T, N, x, y, qx, qy, ea, eb, et, ne, edge_at, edge_stamp, mark, area):
    """``area[e]``: the area that query ``q``'s new Voronoi cell takes from the
    cell of ``ea[e]`` (shoelace over the polygon: centre of (q, previous vertex,
    v), centres of the cavity triangles around v in order, centre of (q, v,
    next vertex)), coordinates relative to ``q``. Returns ``AREAS_OK``;
    ``NOT_STAR`` if the cavity is not a disk that the point sees whole (a
    segment hides part of it); ``IMPRECISE`` if rounding spoilt the areas (the
    coordinates do not give back the point). The caller falls back to the
    linear interpolant for both."""
    prev = np.full(ne, -1, np.int64)
    for e in range(ne):
        b = eb[e]
        if edge_stamp[b] != mark:
            return NOT_STAR
        prev[edge_at[b]] = e
        a = ea[e]
        if orient2d(x[a], y[a], x[b], y[b], qx, qy) <= 0:
            return NOT_STAR     # a segment hides part of the cavity: it is not star-shaped
    total = 0.0
    for e in range(ne):
        p = prev[e]
        if p < 0:
            return NOT_STAR
        v = ea[e]
        u = ea[p]
        w = eb[e]
        gx, gy = circumcentre(0.0, 0.0, x[u] - qx, y[u] - qy, x[v] - qx, y[v] - qy)
        hx, hy = circumcentre(0.0, 0.0, x[v] - qx, y[v] - qy, x[w] - qx, y[w] - qy)
        # shoelace: g, then the old centres around v from et[p] to et[e], then h
        acc = 0.0
        lx = gx
        ly = gy
        t = et[p]
        for _ in range(T.shape[0]):
            c0 = T[t, 0]
            c1 = T[t, 1]
            c2 = T[t, 2]
            cx, cy = circumcentre(x[c0] - qx, y[c0] - qy, x[c1] - qx, y[c1] - qy,
                                  x[c2] - qx, y[c2] - qy)
            acc += lx * cy - ly * cx
            lx = cx
            ly = cy
            if t == et[e]:
                break
            pv = 0 if c0 == v else (1 if c1 == v else 2)
            t = N[t, (pv + 2) % 3]
            if t < 0:
                return NOT_STAR
        acc += lx * hy - ly * hx
        acc += hx * gy - hy * gx
        area[e] = -0.5 * acc      # (the polygon turns clockwise: v's old centres lie beyond g, h)
        total += area[e]
    if not total > 0.0:
        return IMPRECISE
    for e in range(ne):
        if area[e] < 0.0:
            # rounding at a nearly cocircular vertex: a hair below zero is zero
            if area[e] < -1e-9 * total:
                return IMPRECISE
            area[e] = 0.0
    # the coordinates must give back the point: far centres (slivers, points
    # nearly on a line) can cancel every digit of the areas
    rx = 0.0
    ry = 0.0
    extent = 0.0
    for e in range(ne):
        dx = x[ea[e]] - qx
        dy = y[ea[e]] - qy
        rx += area[e] * dx
        ry += area[e] * dy
        extent = max(extent, abs(dx), abs(dy))
    return AREAS_OK if abs(rx) + abs(ry) <= 1e-10 * extent * total else IMPRECISE


@entry
def convex_disk(T, N, x, y):
    """Whether the triangles cover one convex polygon: their boundary is a single
    loop (each vertex leaves by at most one boundary edge, one walk round
    visits every boundary edge) that never turns right (exact)."""
    succ = np.full(x.shape[0], -1, np.int64)
    nb = 0
    start = -1
    for t in range(T.shape[0]):
        for j in range(3):
            if N[t, j] < 0:
                a = T[t, (j + 1) % 3]
                if succ[a] >= 0:
                    return False
                succ[a] = T[t, (j + 2) % 3]
                start = a
                nb += 1
    if start < 0:
        return False
    v = start
    for count in range(1, nb + 1):
        w = succ[v]
        u = succ[w] if w >= 0 else -1
        if u < 0 or orient2d(x[v], y[v], x[w], y[w], x[u], y[u]) < 0:
            return False
        v = w
        if v == start:
            return count == nb
    return False
