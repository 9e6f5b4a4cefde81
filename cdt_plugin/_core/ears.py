"""A simple ring triangulated by ear clipping, exactly: where the drop-ins'
route for a small polygon without holes (:mod:`.plain`) starts, before the
flip algorithm makes the triangulation constrained Delaunay (Sec. 2.10.3).

For a polygon of a few dozen vertices the Delaunay triangulation of its
vertices, which the general route builds first and then cuts the ring's
segments into, is most of the work; and the general route's point is that it
takes any PLC. A simple ring needs none of it: every ring of three or more
vertices that no two of its edges meet but neighbours at their shared vertex
has an ear (a vertex whose triangle with its two neighbours holds no other
vertex of the ring, closed), and cutting it off leaves a simple ring. The
tests are :func:`.kernel.orient`'s, exact; the ring must be in the predicates'
range (:mod:`.scaling`).
"""
from __future__ import annotations

import numpy as np

from .jit import kernel
from .kernel import orient
from .mesh import DEAD, IDX

#: The half-edge slots of one dead triangle after the real ones: the twin of
#: every half-edge on the ring, which a flip next to the ring relinks into and
#: nothing reads (the ring's edges are segments: never flipped)
SINK_TRIANGLES = 1


@kernel(_nrt=False, inline="always")
def within(x, y, p, q, r):
    """Whether vertex ``r`` lies in the closed box of ``p`` and ``q`` (for three
    collinear vertices: on the segment ``p-q``)."""
    return (min(x[p], x[q]) <= x[r] <= max(x[p], x[q])
            and min(y[p], y[q]) <= y[r] <= max(y[p], y[q]))


@kernel(_nrt=False, inline="always")
def segments_meet(x, y, p, q, r, s):
    """Whether the closed segments ``p-q`` and ``r-s`` have a point in common (exact)."""
    o1 = np.sign(orient(x, y, p, q, r))
    o2 = np.sign(orient(x, y, p, q, s))
    if o1 * o2 > 0:            # (r and s on one side of p-q: most pairs end here)
        return False
    o3 = np.sign(orient(x, y, r, s, p))
    o4 = np.sign(orient(x, y, r, s, q))
    if o3 * o4 > 0:
        return False
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return ((o1 == 0 and within(x, y, p, q, r)) or (o2 == 0 and within(x, y, p, q, s))
            or (o3 == 0 and within(x, y, r, s, p)) or (o4 == 0 and within(x, y, r, s, q)))


@kernel
def ring_is_simple(x, y):
    """Whether the closed ring of vertices ``0..n-1`` (n >= 3) is simple: no
    edge of zero length, no two neighbouring edges folding onto each other, no
    two other edges meeting (closed segments; so no repeated vertex, no vertex
    on another edge). A simple ring encloses an area: three vertices on a line
    fold. The pairs of edges whose boxes overlap are found by a sweep over the
    edges in order of their left ends."""
    n = x.shape[0]
    left = np.empty(n)
    for i in range(n):
        left[i] = min(x[i], x[i + 1 if i + 1 < n else 0])
    order = np.argsort(left)
    boxes = np.empty((n, 4))        # each edge's box, in the sweep's order
    for k in range(n):
        p = order[k]
        q = p + 1 if p + 1 < n else 0
        boxes[k, 0] = left[p]
        boxes[k, 1] = max(x[p], x[q])
        boxes[k, 2] = min(y[p], y[q])
        boxes[k, 3] = max(y[p], y[q])
    return edges_apart(x, y, order, boxes)


@kernel(_nrt=False)
def edges_apart(x, y, order, boxes):
    """:func:`ring_is_simple` after its allocations (without reference counting:
    each array it passes to a call would otherwise cost two atomic operations):
    edge ``order[k]`` (from vertex ``order[k]`` to the next) has the box
    ``boxes[k]`` (x from, x to, y from, y to), ``boxes[:, 0]`` ascending."""
    n = x.shape[0]
    for i in range(n):
        a = i - 1 if i > 0 else n - 1
        c = i + 1 if i + 1 < n else 0
        if x[i] == x[c] and y[i] == y[c]:
            return False
        if orient(x, y, a, i, c) == 0 and (within(x, y, a, i, c) or within(x, y, i, c, a)):
            return False
    for k in range(n):
        p = order[k]
        q = p + 1 if p + 1 < n else 0
        right, ylo, yhi = boxes[k, 1], boxes[k, 2], boxes[k, 3]
        for m in range(k + 1, n):
            if boxes[m, 0] > right:
                break
            if boxes[m, 3] < ylo or boxes[m, 2] > yhi:
                continue
            r = order[m]
            s = r + 1 if r + 1 < n else 0
            if r == q or s == p:
                continue       # (neighbours were checked above)
            if segments_meet(x, y, p, q, r, s):
                return False
    return True


@kernel
def counter_clockwise(x, y):
    """Whether the simple ring of vertices ``0..n-1`` runs counter-clockwise:
    the turn at its lexicographically smallest vertex, a corner of the convex
    hull, which a simple ring turns strictly."""
    n = x.shape[0]
    low = 0
    for i in range(1, n):
        if x[i] < x[low] or (x[i] == x[low] and y[i] < y[low]):
            low = i
    return orient(x, y, (low + n - 1) % n, low, (low + 1) % n) > 0


@kernel(_nrt=False, inline="always")
def is_ear(x, y, a, i, c, blockers, nblockers):
    """Whether ``i`` (between ``a`` and ``c`` on the ring, counter-clockwise) is
    an ear: a strictly convex corner whose closed triangle holds no other
    vertex of the ring; and how many vertices it looked at. Only the corners
    that are not strictly convex (``blockers[:nblockers]``) need a look: of the
    vertices in the triangle, the farthest from ``a-c`` has both its edges
    going back towards ``a-c`` (nothing crosses ``a-i`` or ``i-c``), with the
    polygon on the side of ``i``, so it is reflex or straight."""
    if orient(x, y, a, i, c) <= 0:
        return False, 1
    xlo, xhi = min(x[a], x[i], x[c]), max(x[a], x[i], x[c])
    ylo, yhi = min(y[a], y[i], y[c]), max(y[a], y[i], y[c])
    for k in range(nblockers):
        v = blockers[k]
        if v == a or v == c or x[v] < xlo or x[v] > xhi or y[v] < ylo or y[v] > yhi:
            continue
        if (orient(x, y, a, i, v) >= 0 and orient(x, y, i, c, v) >= 0
                and orient(x, y, c, a, v) >= 0):
            return False, k + 2
    return True, nblockers + 1


@kernel
def ear_store(x, y, forward, max_work):
    """The triangles of the simple ring of vertices ``0..n-1``, cut off ear by
    ear, as a half-edge store for the flip algorithm (:mod:`.mesh`): ``(done,
    tri, twin, cons)``, the ``n - 2`` triangles counter-clockwise, followed by
    the sink (:data:`SINK_TRIANGLES`); the ring's half-edges are segments
    (``cons`` 1). The ring runs counter-clockwise when ``forward``, else
    backwards. ``done`` is False when the ear tests looked at ``max_work``
    vertices without finishing (the caller then takes the general route: a
    spiral, whose only ears are at its ends, takes a quadratic number)."""
    n = x.shape[0]
    k = n - 2
    tri = np.empty(3 * (k + SINK_TRIANGLES), IDX)
    twin = np.empty(3 * (k + SINK_TRIANGLES), IDX)
    cons = np.zeros(3 * (k + SINK_TRIANGLES), IDX)
    ring = (np.empty(n, np.int64), np.empty(n, np.int64), np.full(n, -1, np.int64),
            np.empty(n, np.int64), np.full(n, -1, np.int64))
    done = cut_ears(x, y, forward, max_work, (tri, twin, cons), ring)
    return done, tri, twin, cons


@kernel(_nrt=False)
def cut_ears(x, y, forward, max_work, store, ring):
    """:func:`ear_store` after its allocations (without reference counting, as
    :func:`edges_apart`): ``store`` the ``(tri, twin, cons)`` to fill, ``ring``
    the work arrays ``(after, before, across, blockers, slot)``; whether it
    found the triangulation."""
    tri, twin, cons = store
    after, before, across, blockers, slot = ring
    n = x.shape[0]
    sink = 3 * (n - 2)
    for e in range(sink, tri.shape[0]):
        tri[e] = DEAD
        twin[e] = sink
    step = 1 if forward else n - 1
    for v in range(n):
        after[v] = (v + step) % n
        before[v] = (v + n - step) % n
    # across[v]: the half-edge across ring edge v -> after[v] (-1: the outside). blockers:
    # the corners that are not strictly convex, each at its slot; cutting ears off only
    # narrows the corners beside them, so a convex one stays convex and leaves the list
    nblockers = 0
    for v in range(n):
        if orient(x, y, before[v], v, after[v]) <= 0:
            blockers[nblockers] = v
            slot[v] = nblockers
            nblockers += 1
    i = 0
    left = n
    misses = 0
    work = 0
    t = 0
    while left > 3:
        a = before[i]
        c = after[i]
        ear, looked = is_ear(x, y, a, i, c, blockers, nblockers)
        work += looked
        if work > max_work:
            return False
        if not ear:
            misses += 1
            if misses > left:
                return False
            i = c
            continue
        add_triangle(tri, twin, cons, t, a, i, c, across[a], across[i], sink)
        across[a] = 3 * t + 2              # the new ring edge a -> c: c -> a of triangle t across it
        after[a] = c
        before[c] = a
        if slot[a] >= 0 and orient(x, y, before[a], a, c) > 0:
            nblockers = drop_blocker(blockers, slot, nblockers, a)
        if slot[c] >= 0 and orient(x, y, a, c, after[c]) > 0:
            nblockers = drop_blocker(blockers, slot, nblockers, c)
        t += 1
        left -= 1
        misses = 0
        # (on past c: ears cut every other corner make a zig-zag along a convex stretch,
        # not a fan, which the flips then change far less: a star of 60, 26 flips, not 57)
        i = after[c]
    a = before[i]
    c = after[i]
    add_triangle(tri, twin, cons, t, a, i, c, across[a], across[i], sink)
    put_twin(twin, cons, 3 * t + 2, across[c], sink)
    return True


@kernel(_nrt=False, inline="always")
def drop_blocker(blockers, slot, nblockers, v):
    """Vertex ``v`` out of ``blockers[:nblockers]`` (the last one takes its
    slot); returns the new count."""
    k = slot[v]
    last = blockers[nblockers - 1]
    blockers[k] = last
    slot[last] = k
    slot[v] = -1
    return nblockers - 1


@kernel(_nrt=False, inline="always")
def add_triangle(tri, twin, cons, t, a, i, c, across_ai, across_ic, sink):
    """Triangle ``t = (a, i, c)``, its edges ``a -> i`` and ``i -> c`` linked
    to what lies across them (:func:`put_twin`)."""
    tri[3 * t] = a
    tri[3 * t + 1] = i
    tri[3 * t + 2] = c
    put_twin(twin, cons, 3 * t, across_ai, sink)
    put_twin(twin, cons, 3 * t + 1, across_ic, sink)


@kernel(_nrt=False, inline="always")
def put_twin(twin, cons, e, across, sink):
    """Half-edge ``e`` linked to ``across``, or (-1: the ring's own edge) a
    segment whose twin is the sink."""
    if across >= 0:
        twin[e] = across
        twin[across] = e
    else:
        twin[e] = sink
        cons[e] = 1
