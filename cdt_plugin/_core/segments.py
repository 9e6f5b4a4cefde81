"""Segment insertion into a constrained Delaunay triangulation (Sec. 2.10).

A segment ``a b`` that is not an edge is inserted by walking from ``a`` to
``b`` through the triangles it crosses, flipping the crossed edges until the
segment is an edge (Sloan 1993: the cavity of Sec. 2.10.1 is retriangulated
by flips, which also copes with edges dangling into the cavity), then
restoring the constrained Delaunay property inside the cavity with flips that
never flip a segment (Lemma 2.14). A vertex exactly on the segment splits it
there (T-junction).
A segment that crosses another segment stops the walk and is reported; the
caller either raises or inserts the intersection point and splits both.

Work items are *tasks* ``(a, b, segment id)`` on a queue, so splitting a
segment just queues its pieces. ``cons[e]`` holds the 1-based segment id of a
constrained half-edge.
"""
from __future__ import annotations

import numpy as np

from .borrow import unowned
from .jit import entry, kernel
from .kernel import orient
from .insertion import insert_vertex
from .locate import ON_VERTEX, locate
from .flips import flip_from_stack
from .mesh import DEAD, flip, nxt, prv
from .ordering import sort_ids
from .predicates import crossing_point as exact_crossing
from .scaling import NO_FIT, fit_shift, on_grid
from .status import (ALL_DONE, BUFFERS_TOO_SMALL, CROSSING, DONE, LOCATE_FAILED, LOST,  # noqa: F401
                     NEED_EDGE_ROOM, NEED_VERTEX_ROOM, ON_INPUT, OVERLAP, SPLIT_AT, STOP_CROSSING,
                     STOP_LIMIT, STOP_OVERLAP, TASK_LOST)



@kernel
def forward(x, y, a, b, v):
    """For ``v`` exactly on the line ``a b``: whether it lies ahead of ``a``
    towards ``b`` (strictly)."""
    if x[a] != x[b]:
        return (x[v] > x[a]) if x[b] > x[a] else (x[v] < x[a])
    return (y[v] > y[a]) if y[b] > y[a] else (y[v] < y[a])


@kernel
def on_input_segment(x, y, A, B, a, b, v):
    """For a piece ``a b`` of input segment ``A B`` whose ends are not both
    exactly on it (a crossing point rounded off the line): whether vertex
    ``v`` lies exactly on ``A B`` strictly between ``a`` and ``b``. Such a
    vertex splits the segment although it may lie off the piece by a rounding
    error. Positions along the segment are compared on its longer axis, where
    they are monotone (exact comparisons)."""
    if orient(x, y, A, B, v) != 0:
        return False
    if abs(x[B] - x[A]) >= abs(y[B] - y[A]):
        lo, hi, t = min(x[a], x[b]), max(x[a], x[b]), x[v]
    else:
        lo, hi, t = min(y[a], y[b]), max(y[a], y[b]), y[v]
    return lo < t < hi


@kernel
def off_input_line(x, y, A, B, a, b):
    """Whether piece ``a b`` of input segment ``A B`` does not lie on it exactly
    (an end that is ``A`` or ``B`` is on it: no predicate, whose exact stage a
    zero determinant would reach, for the ends of an unsplit segment)."""
    return ((a != A and a != B and orient(x, y, A, B, a) != 0)
            or (b != A and b != B and orient(x, y, A, B, b) != 0))


@kernel
def vertex_edge(tri, twin, x, y, inf, v, hint, ntri):
    """A half-edge whose origin is vertex ``v``, found by locating ``v``."""
    code, e = locate(tri, twin, x, y, inf, v, hint, ntri)
    if code != ON_VERTEX or tri[e] != v:
        return -1
    return e


@kernel
def vertex_edges(tri, ntri, nv):
    """A half-edge leaving each vertex ``0..nv-1`` (-1: none), from one pass
    over the triangles: a start for the look around a segment's first end."""
    vedge = np.full(nv, -1, np.int64)
    for e in range(3 * ntri):
        v = tri[e]
        if 0 <= v < nv and tri[3 * (e // 3)] != DEAD:
            vedge[v] = e
    return vedge


@kernel
def by_smaller_end(pairs, m, nv):
    """Rows ``0..m-1`` of the vertex pairs ``pairs`` grouped by their smaller
    vertex (a counting sort; rows in order inside a group): those of vertex
    ``a`` are ``group[start[a]:start[a + 1]]``. Pairs of one vertex are left out."""
    start = np.zeros(nv + 2, np.int64)
    for i in range(m):
        if pairs[i, 0] != pairs[i, 1]:
            start[min(pairs[i, 0], pairs[i, 1]) + 2] += 1
    for v in range(nv):
        start[v + 2] += start[v + 1]
    group = np.empty(m, np.int64)
    for i in range(m):
        if pairs[i, 0] != pairs[i, 1]:
            a = min(pairs[i, 0], pairs[i, 1])
            group[start[a + 1]] = i
            start[a + 1] += 1
    return start, group


@kernel
def mark_present(tri, twin, cons, ntri, nv, tasks, ntask):
    """Constrain at once every task ``a b`` that is an unconstrained edge
    already (most segments of a fine boundary are Delaunay edges), by one pass
    over the half-edges rather than a look around each segment's end; the
    other tasks stay queued in their order. Returns their number."""
    start, group = by_smaller_end(tasks, ntask, nv)
    done = np.zeros(ntask, np.bool_)
    for e in range(3 * ntri):
        u = tri[e]
        v = tri[nxt(e)]
        if u < 0 or u >= v or v >= nv or cons[e] != 0 or tri[3 * (e // 3)] == DEAD:
            continue
        for k in range(start[u], start[u + 1]):
            i = group[k]
            if max(tasks[i, 0], tasks[i, 1]) == v:
                cons[e] = tasks[i, 2]
                cons[twin[e]] = tasks[i, 2]
                done[i] = True
                break
    kept = 0
    for i in range(ntask):
        if not done[i]:
            tasks[kept, 0] = tasks[i, 0]
            tasks[kept, 1] = tasks[i, 1]
            tasks[kept, 2] = tasks[i, 2]
            kept += 1
    return kept


@kernel
def edge_from(tri, twin, x, y, inf, v, hint, ntri, vedge):
    """A half-edge leaving ``v``: ``vedge[v]`` while it still does (flips and
    splits reassign half-edges), else found by locating ``v``."""
    if v < vedge.shape[0]:
        e = vedge[v]
        if e >= 0 and tri[e] == v and tri[3 * (e // 3)] != DEAD:
            return e
    return vertex_edge(tri, twin, x, y, inf, np.int64(v), hint, ntri)


@kernel
def first_crossing(mesh, a, b, e0, ends, off_line):
    """Look around ``a`` (``e0`` leaves ``a``) for the way towards ``b`` in
    ``mesh`` (``(tri, twin, cons, x, y, inf)``, see :mod:`.mesh`).

    Returns ``(kind, e)``: ``(DONE, a->b)`` if the edge exists; ``(SPLIT_AT,
    a->v)`` if a neighbour ``v`` lies on the open segment (or, for a piece
    ``off_line`` of its input segment ``ends = (A, B)``, on that:
    :func:`on_input_segment`); else ``(CROSSING, u->w)``: the first edge the
    segment crosses, ``u`` right and ``w`` left of ``a -> b``.
    """
    tri, twin, x, y, inf = mesh[0], mesh[1], mesh[3], mesh[4], mesh[5]
    A, B = ends
    e = e0
    for _ in range(tri.shape[0]):
        u = tri[nxt(e)]
        w = tri[prv(e)]
        if u == b:
            return DONE, e
        if u != inf and w != inf:
            ou = orient(x, y, a, b, u)
            if ou == 0 and forward(x, y, a, b, u):
                return SPLIT_AT, e
            if off_line and on_input_segment(x, y, A, B, a, b, u):
                return SPLIT_AT, e
            ow = orient(x, y, a, b, w)
            if ow == 0 and forward(x, y, a, b, w):
                return SPLIT_AT, prv(e)  # w -> a; its twin leaves a towards w
            if off_line and on_input_segment(x, y, A, B, a, b, w):
                return SPLIT_AT, prv(e)
            if ou < 0 and ow > 0:
                return CROSSING, nxt(e)
        e = twin[prv(e)]  # next triangle counter-clockwise around a
        if e == e0:
            break
    return -1, -1


@kernel
def crossed_edges(mesh, a, b, h, buf, ends, off_line):
    """Walk from crossing half-edge ``h`` (``u -> w``) towards ``b``, recording
    every crossed edge (``qu, qw, qh`` of ``buf``: endpoints and half-edge) and
    every crossed triangle (``slots``; ``buf`` is :func:`make_buffers`'). Stops
    at ``b`` or at the first vertex on the segment. Nothing is modified.

    Returns ``(end vertex, crossed edges, triangles, constrained half-edge hit
    or -1, or -2 when the end is a vertex on the input segment ``ends`` but off
    this piece: see :func:`first_crossing`)``.
    """
    tri, twin, cons, x, y = mesh[0], mesh[1], mesh[2], mesh[3], mesh[4]
    qu, qw, qh, slots = buf[0], buf[1], buf[2], buf[3]
    A, B = ends
    k = 0
    slots[0] = h // 3
    ns = 1
    while True:
        if cons[h] != 0:
            return -1, k, ns, h
        qu[k] = tri[h]
        qw[k] = tri[nxt(h)]
        qh[k] = h
        k += 1
        g = twin[h]                  # w -> u in (w, u, v)
        v = tri[prv(g)]
        slots[ns] = g // 3
        ns += 1
        if v == b:
            return v, k, ns, -1
        o = orient(x, y, a, b, v)
        if o == 0:
            return v, k, ns, -1
        if off_line and on_input_segment(x, y, A, B, a, b, v):
            return v, k, ns, -2
        h = nxt(g) if o > 0 else prv(g)


@kernel
def find_edge_near(tri, twin, x, y, inf, u, w, hint, ntri):
    """Half-edge ``u -> w`` (locating ``u`` from triangle ``hint``), or -1."""
    e0 = vertex_edge(tri, twin, x, y, inf, np.int64(u), hint, ntri)
    if e0 < 0:
        return -1
    e = e0
    while True:
        if tri[nxt(e)] == w:
            return e
        e = twin[prv(e)]
        if e == e0:
            return -1


@kernel
def flip_in_segment(mesh, ntri, a, b, buf, k, hint):
    """Flip the ``k`` crossed edges on ``buf``'s queue (:func:`crossed_edges`)
    until none crosses segment ``a b`` (Sloan 1993):
    a crossed edge with a convex quadrilateral is flipped, and its new diagonal
    goes back on the (circular) queue if it still crosses; an edge that cannot
    be flipped yet goes back too. Returns False if the loop (finite in theory)
    ran away."""
    tri, twin, cons, x, y, inf = mesh
    qu, qw, qh = buf[0], buf[1], buf[2]
    head = 0
    size = k
    cap = qu.shape[0]
    budget = 64 * (k + 4) * (k + 4)
    while size > 0:
        budget -= 1
        if budget < 0:
            return False
        u = qu[head]
        w = qw[head]
        h = qh[head]
        head = (head + 1) % cap
        size -= 1
        if tri[h] != u or tri[nxt(h)] != w:  # the slot was rewritten by a flip
            h = find_edge_near(tri, twin, x, y, inf, u, w, hint, ntri)
            if h < 0:
                return False
        p = tri[prv(h)]
        f = twin[h]
        d = tri[prv(f)]
        tail = (head + size) % cap
        if orient(x, y, p, u, d) > 0 and orient(x, y, p, d, w) > 0:
            flip(tri, twin, cons, h)
            op = orient(x, y, a, b, p)
            od = orient(x, y, a, b, d)
            if (op > 0 and od < 0) or (op < 0 and od > 0):
                qu[tail] = p
                qw[tail] = d
                qh[tail] = 3 * (f // 3)    # p -> d, slot 0 of (p, d, w)
                size += 1
        else:
            qu[tail] = u
            qw[tail] = w
            qh[tail] = h
            size += 1
    return True


@kernel(inline="always")
def insert_one(mesh, ntri, a, b, sid, ends, hint, buf, vedge):
    """Make ``a -> b`` (or its first piece, up to a vertex on it) a constrained
    edge of ``mesh`` with id ``sid``, a piece of input segment ``ends = (A,
    B)``, then restore the
    constrained Delaunay property around it with flips that never flip a
    segment (Lemma 2.14).

    Returns ``(kind, info, hint)``: DONE (``info`` = end vertex: ``b`` or a
    vertex on the segment), ON_INPUT (``info`` = a vertex on the input segment
    but off this piece, whose ends were rounded off it: nothing done, the
    piece is to be split there), OVERLAP (``info`` = the half-edge already on
    another segment) or CROSSING (``info`` = the constrained half-edge
    crossed); TASK_LOST on an internal failure, BUFFERS_TOO_SMALL if the walk
    buffers are too small.
    """
    tri, twin, cons, x, y, inf = mesh
    A, B = ends
    qu, slots, stack = buf[0], buf[3], buf[4]
    e0 = edge_from(tri, twin, x, y, inf, a, hint, ntri, vedge)
    if e0 < 0:
        return TASK_LOST, -1, hint
    off_line = off_input_line(x, y, A, B, a, b)
    kind, e = first_crossing(mesh, a, b, e0, ends, off_line)
    if kind == DONE or kind == SPLIT_AT:
        if kind == SPLIT_AT and tri[e] != a:
            e = twin[e]
        v = tri[nxt(e)]
        if cons[e] != 0 and cons[e] != sid:
            return OVERLAP, e, e // 3
        cons[e] = sid
        cons[twin[e]] = sid
        return DONE, v, e // 3
    if kind < 0:
        return TASK_LOST, -1, hint
    if qu.shape[0] < ntri + 3:  # room for the longest possible walk
        return BUFFERS_TOO_SMALL, -1, hint
    end, k, ns, hit = crossed_edges(mesh, a, b, e, buf, ends, off_line)
    if hit >= 0:
        return CROSSING, hit, hint
    if hit == -2:
        return ON_INPUT, end, hint
    if not flip_in_segment(mesh, ntri, a, end, buf, k, slots[0]):
        return TASK_LOST, -1, hint
    s = find_edge_near(tri, twin, x, y, inf, a, end, slots[0], ntri)
    if s < 0:
        return TASK_LOST, -1, hint
    cons[s] = sid
    cons[twin[s]] = sid
    # the crossed triangles' slots now hold the new triangles: re-check their edges
    sp = np.int64(0)
    for i in range(ns):
        for j in range(3):
            stack[sp] = 3 * slots[i] + j
            sp += 1
    flip_from_stack(mesh, (x, np.bool_(False)), stack, sp, np.int64(-1))
    return DONE, end, slots[0]


@kernel
def crosses(x, y, p0, p1, q0, q1):
    """Whether segments ``p0 p1`` and ``q0 q1`` cross at a point inside both
    (signs compared, not multiplied: a product of tiny values underflows)."""
    return (opposite(orient(x, y, q0, q1, p0), orient(x, y, q0, q1, p1))
            and opposite(orient(x, y, p0, p1, q0), orient(x, y, p0, p1, q1)))


@kernel
def opposite(a, b):
    return (a > 0 and b < 0) or (a < 0 and b > 0)


@kernel
def crossing_point(x, y, a, b, u, v, s0, s1, t0, t1):
    """Where piece ``a b`` of segment ``s0 s1`` crosses piece ``u v`` of segment
    ``t0 t1`` (the pieces cross inside both). Computed on the input segments
    when they cross too, so that the point does not drift as pieces are split;
    on the pieces when rounding of earlier points has made the pieces cross
    where the input segments do not (or are collinear)."""
    if crosses(x, y, s0, s1, t0, t1):
        return intersection_point(x, y, np.int64(s0), np.int64(s1), np.int64(t0), np.int64(t1))
    return intersection_point(x, y, np.int64(a), np.int64(b), np.int64(u), np.int64(v))


@entry
def intersection_point(x, y, p0, p1, q0, q1):
    """The crossing point of segments ``p0 p1`` and ``q0 q1`` (known to cross):
    each coordinate the double nearest to the exact crossing (exact when it is
    a double), the same for any order and direction of the two segments
    (:func:`.predicates.crossing_point`), and within both boxes."""
    if orient(x, y, q0, q1, p0) == orient(x, y, q0, q1, p1):
        # not a crossing (parallel): no point on both; the callers avoid this
        return 0.5 * (x[p0] + x[p1]), 0.5 * (y[p0] + y[p1])
    px, py = exact_crossing(x[p0], y[p0], x[p1], y[p1], x[q0], y[q0], x[q1], y[q1])
    lo = max(min(x[p0], x[p1]), min(x[q0], x[q1]))
    hi = min(max(x[p0], x[p1]), max(x[q0], x[q1]))
    px = min(max(px, lo), hi)
    lo = max(min(y[p0], y[p1]), min(y[q0], y[q1]))
    hi = min(max(y[p0], y[p1]), max(y[q0], y[q1]))
    py = min(max(py, lo), hi)
    return px, py


@entry
def split_crossing(x, y, p0, p1, q0, q1):
    """The crossing of segments ``p0 p1`` and ``q0 q1`` (known to cross) of
    the points ``x, y``, placed as ``intersections="split"`` places it: in the
    route's power-of-two scale of all the points (:mod:`.scaling`),
    :func:`intersection_point` rounded to the grid (:func:`.scaling.on_grid`),
    scaled back. Exact at every magnitude, where the crossing computed on the
    unscaled doubles overflows (NaN from about 1e120) or underflows; the point
    an error names."""
    shift, _, _ = fit_shift(x, y, np.empty(0))
    if shift == NO_FIT:     # (the route stops on the range first; kept for any other caller)
        shift = 0
    s = 2.0 ** shift        # a normal double: |shift| <= MAX_SHIFT
    ends = (p0, p1, q0, q1)
    X = np.empty(4)
    Y = np.empty(4)
    for i in range(4):
        X[i] = x[ends[i]] * s
        Y[i] = y[ends[i]] * s
    px, py = intersection_point(X, Y, np.int64(0), np.int64(1), np.int64(2), np.int64(3))
    back = 2.0 ** -shift
    return on_grid(px) * back, on_grid(py) * back


@kernel("int64(int64[:, ::1], int64, int64, int64, int64)")
def push_task(tasks, ntask, a, b, sid):
    """Queue segment piece ``a b`` of segment ``sid`` (nothing if ``a == b``)."""
    if a == b:
        return ntask
    tasks[ntask, 0] = a
    tasks[ntask, 1] = b
    tasks[ntask, 2] = sid
    return ntask + 1




@kernel
def make_buffers(n):
    """Work arrays for :func:`insert_one`, sized for walks through ``n`` triangles:
    the crossed-edge queue (endpoints, half-edge), the crossed triangles, and a
    flip stack."""
    return (np.empty(n + 3, np.int64), np.empty(n + 3, np.int64), np.empty(n + 3, np.int64),
            np.empty(n + 3, np.int64), np.empty(3 * (n + 3), np.int64))


@kernel
def insert_segments(mesh, ntri, nv, tasks, ntask, seg_ends, split, max_steiner, report, work):
    """Process the segment tasks ``tasks[:ntask]`` (rows ``a, b, sid``; LIFO)
    in ``mesh`` (``(tri, twin, cons, x, y, inf)``, see :mod:`.mesh`).

    ``seg_ends[sid - 1]`` are the original endpoints of segment ``sid`` (for
    intersection points). With ``split`` False a crossing or an overlap stops
    the loop (``info`` names the two segment ids); with ``split`` True the
    crossing point is inserted as a Steiner vertex ``nv`` (room permitting),
    both segments are split there, and overlaps are merged.
    ``report`` is ``(counts, info)``, ``counts``: [T-junction splits, merged
    overlaps, Steiner points]; ``work`` is ``(stack, buf)``: the flip stack of
    a vertex insertion (at least ``inf + 16``) and :func:`make_buffers`'.
    Returns ``(status, ntri, nv, ntask)``; on NEED_* the unfinished task is back
    on the queue so the caller can grow the arrays and call again.
    """
    tri, twin, cons, x, y, inf = mesh
    counts, info = report
    stack, buf = work
    tri, twin, cons, x, y = unowned(tri), unowned(twin), unowned(cons), unowned(x), unowned(y)
    mesh = (tri, twin, cons, x, y, inf)
    unweighted = (x, np.bool_(False))       # (weights are read only when weighted)
    tasks, seg_ends, counts, info, stack = (unowned(tasks), unowned(seg_ends), unowned(counts),
                                            unowned(info), unowned(stack))
    buf = (unowned(buf[0]), unowned(buf[1]), unowned(buf[2]), unowned(buf[3]), unowned(buf[4]))
    hint = np.int64(0)
    ntask = mark_present(tri, twin, cons, ntri, nv, tasks, ntask)
    vedge = vertex_edges(tri, ntri, nv)
    crossings = 0
    flip_counts = np.zeros(2, np.int64)
    no_weights = np.zeros(1, np.int8)
    while ntask > 0:
        ntask -= 1
        a = tasks[ntask, 0]
        b = tasks[ntask, 1]
        sid = tasks[ntask, 2]
        kind, res, hint = insert_one(mesh, ntri, a, b, sid, (seg_ends[sid - 1, 0], seg_ends[sid - 1, 1]),
                                     hint, buf, vedge)
        if kind == BUFFERS_TOO_SMALL:
            ntask += 1
            return NEED_EDGE_ROOM, ntri, nv, ntask
        if kind < 0:
            info[0] = sid
            return LOST, ntri, nv, ntask
        if kind == DONE:
            if res != b:
                counts[0] += 1
                tasks[ntask, 0] = res
                tasks[ntask, 1] = b
                tasks[ntask, 2] = sid
                ntask += 1
            continue
        if kind == ON_INPUT:
            if ntask + 2 > tasks.shape[0]:
                ntask += 1
                return NEED_VERTEX_ROOM, ntri, nv, ntask
            counts[0] += 1
            ntask = push_task(tasks, ntask, res, b, sid)
            ntask = push_task(tasks, ntask, a, res, sid)
            continue
        if kind == OVERLAP:
            if not split:
                info[0] = sid
                info[1] = cons[res]
                info[2] = tri[res]
                info[3] = tri[nxt(res)]
                return STOP_OVERLAP, ntri, nv, ntask
            counts[1] += 1
            v = tri[nxt(res)]
            if v != b:
                tasks[ntask, 0] = v
                tasks[ntask, 1] = b
                tasks[ntask, 2] = sid
                ntask += 1
            continue
        # a crossing with the segment of constrained half-edge `res`
        other = cons[res]
        u = tri[res]
        v2 = tri[nxt(res)]
        if not split:
            info[0] = sid
            info[1] = other
            info[2] = u
            info[3] = v2
            return STOP_CROSSING, ntri, nv, ntask
        crossings += 1
        if counts[2] >= max_steiner or crossings > 4 * max_steiner + 64:
            # (the second bound: crossings whose points round onto existing
            # vertices add no vertex; it makes a livelock impossible)
            info[0] = sid
            info[1] = other
            return STOP_LIMIT, ntri, nv, ntask
        if nv >= inf or ntri + 2 > tri.shape[0] // 3 or ntask + 4 > tasks.shape[0]:
            ntask += 1
            return NEED_VERTEX_ROOM, ntri, nv, ntask
        px, py = crossing_point(x, y, a, b, u, v2, seg_ends[sid - 1, 0], seg_ends[sid - 1, 1],
                                seg_ends[other - 1, 0], seg_ends[other - 1, 1])
        x[nv] = on_grid(px)
        y[nv] = on_grid(py)
        code, p, ntri, hint = insert_vertex(mesh, unweighted, nv, hint, ntri, np.bool_(False),
                                            no_weights, flip_counts, stack)
        if code == LOCATE_FAILED:
            info[0] = sid
            return LOST, ntri, nv, ntask
        if p == nv:
            nv += 1
            counts[2] += 1
        # the crossed piece u-v2 of `other` must now pass through p
        e = find_edge_near(tri, twin, x, y, inf, np.int64(u), np.int64(v2), hint, ntri)
        if e >= 0 and cons[e] == other and p != u and p != v2:
            cons[e] = 0
            cons[twin[e]] = 0
            fstack = buf[4]
            fstack[0] = e  # no longer a segment: it may need a flip now
            flip_from_stack(mesh, unweighted, fstack, np.int64(1), np.int64(-1))
            ntask = push_task(tasks, ntask, u, p, other)
            ntask = push_task(tasks, ntask, p, v2, other)
        # (p may be a or b itself when the crossing rounds onto an end: then
        # only the other segment was rerouted, and a b is tried again)
        ntask = push_task(tasks, ntask, p, b, sid)
        ntask = push_task(tasks, ntask, a, p, sid)
    return ALL_DONE, ntri, nv, ntask


# ------------------------------------------------------------------ after splitting
@kernel("UniTuple(float64, 2)(float64[::1], float64[::1], int64, int64, int64)")
def along_key(x, y, A, B, v):
    """Where vertex ``v`` lies along segment ``A -> B``: ``(position on the
    major axis, position on the other)``, each oriented from ``A`` (exact
    comparisons of coordinates; the pieces of a segment follow it in order when
    their keys do)."""
    dx = x[B] - x[A]
    dy = y[B] - y[A]
    if abs(dy) > abs(dx):
        return y[v] * (1.0 if dy > 0 else -1.0), x[v] * (-1.0 if dx < 0 else 1.0)
    return x[v] * (1.0 if dx > 0 else -1.0), y[v] * (-1.0 if dy < 0 else 1.0)


@kernel
def key_less(a0, a1, b0, b1):
    return a0 < b0 or (a0 == b0 and a1 < b1)


@kernel
def pieces_out_of_order(tri, cons, ntri, x, y, seg_ends):
    """After splitting: whether every segment's pieces (the constrained edges
    with its id) lie along it between its ends in order, none overlapping
    another or turning back (gaps allowed: merged overlaps carry one id).
    Returns ``(bad pieces, segment id, u, v)`` naming the first bad piece in
    (segment, position) order, ``(0, -1, -1, -1)`` when all are in order."""
    m = 0
    for e in range(3 * ntri):
        if cons[e] != 0 and tri[3 * (e // 3)] != DEAD and tri[e] < tri[nxt(e)]:
            m += 1
    sid = np.empty(m, np.int64)
    lo0 = np.empty(m)
    lo1 = np.empty(m)
    hi0 = np.empty(m)
    hi1 = np.empty(m)
    pu = np.empty(m, np.int64)
    pv = np.empty(m, np.int64)
    bad = np.zeros(m, np.bool_)
    k = 0
    for e in range(3 * ntri):
        u = tri[e]
        v = tri[nxt(e)]
        if cons[e] == 0 or tri[3 * (e // 3)] == DEAD or u >= v:
            continue
        s = cons[e]
        A = seg_ends[s - 1, 0]
        B = seg_ends[s - 1, 1]
        p0, p1 = along_key(x, y, A, B, u)
        q0, q1 = along_key(x, y, A, B, v)
        if key_less(q0, q1, p0, p1):
            p0, p1, q0, q1 = q0, q1, p0, p1
        a0, a1 = along_key(x, y, A, B, A)
        b0, b1 = along_key(x, y, A, B, B)
        sid[k], lo0[k], lo1[k], hi0[k], hi1[k], pu[k], pv[k] = s, p0, p1, q0, q1, u, v
        bad[k] = key_less(p0, p1, a0, a1) or key_less(b0, b1, q0, q1)
        k += 1
    # by segment (counting sort), then by start (the route's compiled sort)
    nseg = seg_ends.shape[0]
    start = np.zeros(nseg + 2, np.int64)
    for i in range(m):
        start[sid[i] + 1] += 1
    for s in range(nseg + 1):
        start[s + 1] += start[s]
    order = np.empty(m, np.int64)
    for i in range(m):
        order[start[sid[i]]] = i
        start[sid[i]] += 1
    tmp = np.empty(m, np.int64)
    lo = np.int64(0)     # (a literal 0 would compile sort_ids once more)
    for s in range(1, nseg + 1):           # start[s] is now where segment s's pieces end
        sort_ids(order, lo, start[s], lo0, lo1, tmp)
        lo = start[s]
    for r in range(1, m):
        i = order[r - 1]
        j = order[r]
        if sid[i] == sid[j] and key_less(lo0[j], lo1[j], hi0[i], hi1[i]):
            bad[j] = True                  # it starts before the previous piece ends
    nbad = 0
    first = -1
    for r in range(m):
        if bad[order[r]]:
            nbad += 1
            if first < 0:
                first = order[r]
    if first < 0:
        return np.int64(0), np.int64(-1), np.int64(-1), np.int64(-1)
    return np.int64(nbad), sid[first], pu[first], pv[first]
