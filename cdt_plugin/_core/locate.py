"""Point location by walking (visibility walk over real and ghost triangles)."""
from __future__ import annotations

from .borrow import unowned
from .jit import kernel
from .kernel import orient
from .mesh import DEAD, ghost_hull_edge, is_ghost, nxt, prv

from .status import INSIDE, ON_EDGE, ON_VERTEX  # noqa: F401  (the codes locate returns)


@kernel(inline='always')
def same_point(x, y, i, j):
    return x[i] == x[j] and y[i] == y[j]


@kernel
def strictly_between(x, y, u, v, q):
    """For ``q`` on the line ``u v``: whether it lies strictly between them."""
    if x[u] != x[v]:
        return (x[u] < x[q] < x[v]) or (x[v] < x[q] < x[u])
    return (y[u] < y[q] < y[v]) or (y[v] < y[q] < y[u])


@kernel
def beyond_second(x, y, u, v, q):
    """For ``q`` on the line ``u v`` outside the segment: whether it is past ``v``."""
    if x[u] != x[v]:
        return (x[q] > x[v]) if x[u] < x[v] else (x[q] < x[v])
    return (y[q] > y[v]) if y[u] < y[v] else (y[q] < y[v])


@kernel
def classify_in_solid(tri, x, y, t, q, o0, o1, o2):
    """Where ``q`` lies in solid triangle ``t`` given the three edge orientations
    (all >= 0): strictly inside, on one edge, or on a vertex."""
    e = 3 * t
    zeros = 0
    for o in (o0, o1, o2):
        if o == 0:
            zeros += 1
    if zeros == 0:
        return INSIDE, e
    if zeros == 1:
        if o0 == 0:
            return ON_EDGE, e
        if o1 == 0:
            return ON_EDGE, e + 1
        return ON_EDGE, e + 2
    for k in range(3):
        if same_point(x, y, tri[e + k], q):
            return ON_VERTEX, e + k
    return ON_VERTEX, -1  # unreachable for a valid triangle


@kernel
def locate_in_ghost(tri, x, y, inf, t, q):
    """Test ``q`` against ghost ``t``. Returns ``(code, half-edge)``, or
    ``(-1, half-edge to cross)`` when ``q`` is elsewhere."""
    e = ghost_hull_edge(tri, t, inf)
    u = tri[e]
    v = tri[nxt(e)]
    o = orient(x, y, u, v, q)
    if o > 0:
        return INSIDE, e
    if o < 0:
        return -1, e
    if same_point(x, y, u, q):
        return ON_VERTEX, e
    if same_point(x, y, v, q):
        return ON_VERTEX, nxt(e)
    if strictly_between(x, y, u, v, q):
        return ON_EDGE, e
    if beyond_second(x, y, u, v, q):
        return -1, nxt(e)   # cross v -> inf into the next ghost
    return -1, prv(e)       # cross inf -> u into the previous ghost


@kernel
def locate(tri, twin, x, y, inf, q, start, ntri):
    """Locate vertex ``q``'s position starting from triangle ``start``.

    Returns ``(code, e)`` with code INSIDE / ON_EDGE / ON_VERTEX (see above).
    A ghost triangle contains the points strictly outside its hull edge.
    Falls back to a scan of every triangle if the walk runs unusually long
    (it cannot cycle in a Delaunay triangulation, but the fallback makes the
    routine safe on any valid triangulation).
    """
    tri, twin, x, y = unowned(tri), unowned(twin), unowned(x), unowned(y)   # (see insertion.legalize)
    t = start
    came = -1
    limit = 64 + 4 * ntri
    for step in range(limit):
        if is_ghost(tri, t, inf):
            code, e = locate_in_ghost(tri, x, y, inf, t, q)
            if code >= 0:
                return code, e
            came = twin[e]
            t = came // 3
            continue
        ek, code, e = solid_step(tri, x, y, t, q, step, came)
        if ek < 0:
            return code, e
        came = twin[ek]
        t = came // 3
    return locate_by_scan(tri, x, y, inf, q, ntri)


@kernel(inline='always')
def solid_step(tri, x, y, t, q, step, came):
    """One step of the visibility walk in solid triangle ``t`` (entered through
    half-edge ``came``): ``(ek, -1, -1)`` when ``q`` lies beyond edge ``ek``,
    else ``(-1, code, e)``, where ``q`` lies in ``t`` (see :func:`locate`). The
    first edge tested rotates with ``step`` so the walk cannot cycle."""
    e = 3 * t
    r = (q + step) % 3
    o0 = 1.0
    o1 = 1.0
    o2 = 1.0
    for k in range(3):
        s = (r + k) % 3
        ek = e + s
        if ek == came:
            continue
        o = orient(x, y, tri[ek], tri[nxt(ek)], q)
        if o < 0:
            return ek, -1, -1
        if s == 0:
            o0 = o
        elif s == 1:
            o1 = o
        else:
            o2 = o
    code, e = classify_in_solid(tri, x, y, t, q, o0, o1, o2)
    return -1, code, e


@kernel
def locate_by_scan(tri, x, y, inf, q, ntri):
    """Brute-force location over every live triangle (the walk's safety net)."""
    for t in range(ntri):
        if tri[3 * t] == DEAD:
            continue
        if is_ghost(tri, t, inf):
            code, e = locate_in_ghost(tri, x, y, inf, t, q)
            if code >= 0:
                return code, e
            continue
        e = 3 * t
        o0 = orient(x, y, tri[e], tri[e + 1], q)
        o1 = orient(x, y, tri[e + 1], tri[e + 2], q)
        o2 = orient(x, y, tri[e + 2], tri[e], q)
        if o0 >= 0 and o1 >= 0 and o2 >= 0:
            return classify_in_solid(tri, x, y, t, q, o0, o1, o2)
    return -1, -1
