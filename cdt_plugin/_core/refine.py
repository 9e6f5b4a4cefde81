"""Quality meshing by Delaunay refinement (Sec. 2.10.1, Def. 2.12).

Ruppert's algorithm as Triangle runs it, on the half-edge store of a finished
constrained Delaunay triangulation:

* a segment piece is *encroached* when a vertex of a triangle beside it (on a
  side inside the domain) lies strictly inside its diametral circle; encroached
  pieces are split first;
* a *bad* triangle (smallest angle below ``min_angle`` or area above its
  bound) gets a new vertex at its off-centre (Üngör: on the bisector of its
  shortest edge, no farther than needed for the bound) or circumcentre —
  unless that point encroaches a piece (the pieces are split instead and the
  triangle waits) or lies across a segment (that segment is split);
* pieces are split at their midpoint, or, next to an input vertex, at a
  power-of-two distance from it (Ruppert's concentric shells), and a skinny
  triangle whose short edge joins two such shell points around a small input
  angle is left alone (Shewchuk's rule, as in Triangle): both keep the
  algorithm from cascading around small input angles.

With ``conforming`` a piece is also split while it is not locally Delaunay
(seen from either side, inside the domain or not), until every segment is a
union of Delaunay edges and the whole triangulation is Delaunay.

Every topological decision uses the exact predicates; new points are computed
in floating point. A point on a segment is placed along the *input* segment
(``A + t (B - A)``) so it lies on it up to one rounding, however deep the
splitting goes, and it is accepted only if the four triangles around it keep
their orientation exactly; a piece that cannot be split that way is frozen
(``cons < 0``), as are boundary pieces under ``split_boundary=False``.

Triangle labels ``lab`` travel with the triangles: the region of an inside
triangle (>= -1), or the triangle of the mesh it came from when an existing
mesh is refined (:mod:`.remesh`), or ``OUT``. Flips never cross a segment and
the domain is bounded by segments (hull edges are made segments first), so
the two triangles of a flip always share their label (an existing mesh's
edges between triangles with different area bounds are made segments too).
"""
from __future__ import annotations

import math
from collections import namedtuple
from typing import NamedTuple

import numpy as np

from .arrays import copy_rows
from .flips import flip_to_delaunay, push_outer_edges
from .insertion import legalize
from .jit import F8, I64, I64_2, STORE, Tuple, i8, kernel
from .kernel import edge_is_illegal, orient
from .locate import solid_step
from .options import REFINE_OPTIONS
from .predicates import CCW_ERRBOUND_A, incircle, orient2d
from .mesh import canonical_slots, flip, grow_store, nxt, prv, split_edge, split_triangle
from .scaling import on_grid
from .status import (FINISHED, HEAP_FULL, INSIDE, LIMIT, NEED_ROOM, ON_EDGE, ON_VERTEX,  # noqa: F401
                     PIECES_FULL, WALK_BLOCKED, WALK_FAILED)

OUT = -2            # label of a triangle outside the domain (ghosts too)

# counters (``counts`` array)
C_STEINER = 0       # vertices inserted
C_SEG_SPLITS = 1    # of which on segments
C_SKIPPED = 2       # bad triangles left alone (small input angle, frozen segments)
C_FROZEN = 3        # pieces found too short to split in floating point
C_FLIPS = 4
C_ATTEMPTS = 5      # bad triangles taken from the queue (live ones)
C_DEFERRED = 6      # of which waited for encroached segments to be split
C_UNREPAIRED = 7    # segment splits whose flip repair ran out of stack (a final pass flips)

# a piece queued to be split even if nothing encroaches it by then (NumPy scalars, not
# literals: a literal argument would compile queue_piece once per value)
FORCED = np.int64(1)
NOT_FORCED = np.int64(0)


# ---------------------------------------------------------------- geometry
@kernel
def sin2_min_angle(x, y, a, b, c):
    """Squared sine of the smallest angle of triangle ``a b c`` (the quality
    key: smaller is worse), and twice its area."""
    ux = x[b] - x[a]
    uy = y[b] - y[a]
    vx = x[c] - x[b]
    vy = y[c] - y[b]
    wx = x[a] - x[c]
    wy = y[a] - y[c]
    la = ux * ux + uy * uy
    lb = vx * vx + vy * vy
    lc = wx * wx + wy * wy
    d = ux * (-wy) - uy * (-wx)            # twice the signed area
    # the smallest angle is opposite the shortest edge; sin = d / (product of the others)
    if la <= lb and la <= lc:
        den = lb * lc
    elif lb <= lc:
        den = la * lc
    else:
        den = la * lb
    if den <= 0.0:
        return 0.0, d
    return d * d / den, d


@kernel
def area_bound(area_of_label, label):
    """The area bound of triangles labelled ``label`` (``area_of_label[label + 1]``;
    0, none, past its end)."""
    i = label + 1
    return area_of_label[i] if i < area_of_label.shape[0] else 0.0


@kernel
def shortest_edge2(x, y, a, b, c):
    return min((x[b] - x[a]) ** 2 + (y[b] - y[a]) ** 2, (x[c] - x[b]) ** 2 + (y[c] - y[b]) ** 2,
               (x[a] - x[c]) ** 2 + (y[a] - y[c]) ** 2)


@kernel
def is_bad(x, y, a, b, c, params, label):
    """Whether the triangle, labelled ``label``, breaks the angle or the area
    bound of ``params`` (:class:`RefineParameters`); and its key."""
    key, d = sin2_min_angle(x, y, a, b, c)
    angle_bad = key < params.sin2_bound
    bound = area_bound(params.area_of_label, label)
    area_bad = bound > 0.0 and 0.5 * d > bound
    # the queue key: shortest edges first, in buckets of 2^(1/4) in length
    # (Triangle's 4096 queues), first come first served inside a bucket
    return angle_bad, area_bad, np.floor(2.0 * np.log2(shortest_edge2(x, y, a, b, c)))


@kernel
def encroaches(x, y, a, b, px, py, lens):
    """Whether the point encroaches ``a b``: it sees the piece at an angle of
    more than 90 degrees (strictly inside the diametral circle; ``lens == 0``)
    or, in quality mode, of at least ``180 - 2 min_angle`` (inside the
    diametral lens, Triangle's default: ``lens = cos^2(2 min_angle)``), which
    splits fewer segments."""
    ax = x[a] - px
    ay = y[a] - py
    bx = x[b] - px
    by = y[b] - py
    dot = ax * bx + ay * by
    if dot >= 0.0:
        return False
    return lens == 0.0 or dot * dot >= lens * (ax * ax + ay * ay) * (bx * bx + by * by)


@kernel
def steiner_point(x, y, a, b, c, offconstant):
    """Circumcentre of counter-clockwise ``a b c``, pulled in to the off-centre
    on the bisector of the shortest edge when ``offconstant > 0`` and the
    circumcentre lies farther from that edge (Üngör's off-centres, Triangle's
    rule with its constant)."""
    ax = x[a]
    ay = y[a]
    bx = x[b] - ax
    by = y[b] - ay
    cx = x[c] - ax
    cy = y[c] - ay
    lb = bx * bx + by * by
    lc = cx * cx + cy * cy
    d = 2.0 * (bx * cy - by * cx)
    if d == 0.0:   # a sliver whose float cross product cancels: the exact sign's value
        d = 2.0 * orient2d(x[a], y[a], x[b], y[b], x[c], y[c])
        if d == 0.0:
            return np.nan, np.nan
    ox = (cy * lb - by * lc) / d          # circumcentre relative to a
    oy = (bx * lc - cx * lb) / d
    if offconstant > 0.0:
        # shortest edge p -> q in counter-clockwise order, relative to a
        la = (cx - bx) * (cx - bx) + (cy - by) * (cy - by)   # b -> c
        if lb <= lc and lb <= la:
            px, py, qx, qy = 0.0, 0.0, bx, by
        elif la <= lc:
            px, py, qx, qy = bx, by, cx, cy
        else:
            px, py, qx, qy = cx, cy, 0.0, 0.0
        mx = 0.5 * (px + qx)
        my = 0.5 * (py + qy)
        # inward normal of p -> q (towards the third vertex), as long as the edge
        nx = -(qy - py)
        ny = qx - px
        fx = mx + offconstant * nx
        fy = my + offconstant * ny
        if (fx - mx) ** 2 + (fy - my) ** 2 < (ox - mx) ** 2 + (oy - my) ** 2:
            ox = fx
            oy = fy
    return ax + ox, ay + oy


# ------------------------------------------------------------ priority queue
# Bad triangles wait in bucket queues, as in Triangle: one FIFO list per bucket
# of the shortest edge's length (``is_bad``'s key: 2^(1/4) steps), the smallest
# bucket served first. Push and pop are O(1). ``Q`` is the tuple of arrays
# ``(items, next, free, head, tail)``: entry ``s`` is ``items[s] = (t, a, b, c)``
# and links to ``next[s]``; ``head``/``tail`` of each bucket (-1: empty); freed
# entries are stacked in ``free``. ``qs`` holds ``[top, nfree, lowest bucket
# that may be non-empty, entries queued]``.
NBUCKETS = 4400    # keys floor(2 log2(edge^2)) of finite doubles lie in -2148..2047
BUCKET0 = 2200     # the bucket of key 0


@kernel
def bucket_of(key):
    if not key > -BUCKET0:          # -inf (a zero-length edge) and NaN first
        return 0
    if key >= NBUCKETS - 1 - BUCKET0:
        return NBUCKETS - 1
    return int(key) + BUCKET0


@kernel
def queue_reset(Q, qs):
    """Empty the queue."""
    head, tail = Q[3], Q[4]
    for b in range(head.shape[0]):
        head[b] = -1
        tail[b] = -1
    qs[0] = 0
    qs[1] = 0
    qs[2] = NBUCKETS
    qs[3] = 0


@kernel
def queue_triangle(Q, qs, key, t, a, b, c):
    """Put triangle ``t = (a, b, c)`` at the back of bucket ``key``. Returns
    False when the queue is full (nothing queued)."""
    items, nxt_, free, head, tail = Q
    if qs[1] > 0:
        qs[1] -= 1
        s = free[qs[1]]
    elif qs[0] < items.shape[0]:
        s = qs[0]
        qs[0] += 1
    else:
        return False
    items[s, 0] = t
    items[s, 1] = a
    items[s, 2] = b
    items[s, 3] = c
    nxt_[s] = -1
    k = bucket_of(key)
    if tail[k] < 0:
        head[k] = s
    else:
        nxt_[tail[k]] = s
    tail[k] = s
    if k < qs[2]:
        qs[2] = k
    qs[3] += 1
    return True


@kernel
def queue_pop(Q, qs):
    """Take the oldest entry of the smallest non-empty bucket (the queue must
    not be empty); returns its index in ``Q[0]``, valid until the next push."""
    items, nxt_, free, head, tail = Q
    k = qs[2]
    while head[k] < 0:
        k += 1
    qs[2] = k
    s = head[k]
    head[k] = nxt_[s]
    if head[k] < 0:
        tail[k] = -1
    free[qs[1]] = s
    qs[1] += 1
    qs[3] -= 1
    return s


@kernel
def centroid(x, y, a, b, c):
    """The centroid of triangle ``a b c`` in floating point, the same for any
    order of its corners (each coordinate summed smallest first)."""
    return _mean3(x[a], x[b], x[c]), _mean3(y[a], y[b], y[c])


@kernel
def _mean3(p, q, r):
    lo, hi = min(p, q), max(p, q)
    if r < lo:
        lo, r = r, lo
    elif r > hi:
        hi, r = r, hi
    return ((lo + r) + hi) / 3.0       # r: the middle one


@kernel
def beyond(x, y, u, v, px, py):
    """Whether the point lies strictly right of ``u -> v`` (exact: the
    floating-point filter of :func:`.predicates.orient2d` inline, the call
    where it cannot decide)."""
    left = (x[u] - px) * (y[v] - py)
    right = (y[u] - py) * (x[v] - px)
    det = left - right
    bound = CCW_ERRBOUND_A * (abs(left) + abs(right))
    if det > bound:
        return False
    if -det > bound:
        return True
    return orient2d(x[u], y[u], x[v], y[v], px, py) < 0


@kernel
def holds(x, y, home, h, px, py):
    """Whether triangle ``h`` of ``home`` (counter-clockwise) holds the point,
    its edges included (exact); else the first corner ``j`` whose opposite
    edge has the point strictly outside, as ``-1 - j``."""
    a = home[h, 0]
    b = home[h, 1]
    c = home[h, 2]
    if beyond(x, y, b, c, px, py):
        return -1
    if beyond(x, y, c, a, px, py):
        return -2
    if beyond(x, y, a, b, px, py):
        return -3
    return 0


@kernel
def in_fans(x, y, home, home_nb, h, px, py):
    """A triangle of ``home`` around a corner of triangle ``h`` (turning both
    ways round it, up to 64 triangles each) that holds the point; -1 if none."""
    for i in range(3):
        v = home[h, i]
        for side in range(1, 3):     # across the edge opposite corner c + side: one at v
            g = h
            for _ in range(64):
                c = 0
                while home[g, c] != v:
                    c += 1
                g = home_nb[g, (c + side) % 3]
                if g < 0 or g == h:
                    break
                if holds(x, y, home, g, px, py) == 0:
                    return g
    return -1


@kernel
def home_of(x, y, home, home_nb, start, px, py):
    """The triangle of the mesh ``home`` (rows of corners, counter-clockwise,
    ``home_nb[h, j]`` the neighbour across the edge opposite corner ``j``, -1
    none) that holds the point ``(px, py)``, its edges included: a visibility
    walk from triangle ``start``, leaving by the edges in turn (so it cannot
    circle for ever in a triangulation that is not Delaunay); where it meets
    the boundary (a domain that is not convex), the triangles around the
    corners of the last one (:func:`in_fans`); then a scan of every triangle.
    ``start`` when no triangle holds the point (a centroid rounded off a thin
    triangle at the boundary)."""
    h = start
    turn = start
    for _ in range(64 + home.shape[0] // 16):
        r = holds(x, y, home, h, px, py)
        if r == 0:
            return h
        j = -1 - r
        turn += 1
        for k in range(3):           # another edge the point is beyond, from a turning start
            i = (turn + k) % 3
            if i != j:
                u = home[h, (i + 1) % 3]
                v = home[h, (i + 2) % 3]
                if home_nb[h, i] >= 0 and beyond(x, y, u, v, px, py):
                    j = i
                    break
        if home_nb[h, j] < 0:
            g = in_fans(x, y, home, home_nb, h, px, py)
            if g >= 0:
                return g
            break
        h = home_nb[h, j]
    for g in range(home.shape[0]):
        if holds(x, y, home, g, px, py) == 0:
            return g
    return start


@kernel
def queue_if_bad(tri, x, y, lab, params, Q, qs, t, located):
    """Queue triangle ``t`` if it is inside the domain and breaks a bound.
    With a mesh of origin (``params.home``, :func:`home_of`), ``t``'s label is
    first made the triangle of that mesh that holds its centroid, unless
    ``located`` (three corners a slot) shows the slot holds the triangle it
    held when last located. Returns False when the queue is full."""
    L = lab[t]
    if L == OUT:
        return True
    a = np.int64(tri[3 * t])     # (int64 as in refine_loop: one compilation of the tests)
    b = np.int64(tri[3 * t + 1])
    c = np.int64(tri[3 * t + 2])
    if params.home.shape[0] > 0 and (located[3 * t] != a or located[3 * t + 1] != b
                                     or located[3 * t + 2] != c):
        px, py = centroid(x, y, a, b, c)
        L = home_of(x, y, params.home, params.home_nb, L, px, py)
        lab[t] = L
        located[3 * t] = a
        located[3 * t + 1] = b
        located[3 * t + 2] = c
    angle_bad, area_bad, key = is_bad(x, y, a, b, c, params, L)
    if angle_bad or area_bad:
        return queue_triangle(Q, qs, key, t, a, b, c)
    return True


@kernel
def queue_piece(tri, sq, sn, g, forced):
    """Put the segment piece of half-edge ``g`` on the split stack (``forced``:
    split it even if no triangle vertex encroaches it by then). Returns the
    stack's size (-1: the stack is full)."""
    if sn == sq.shape[0]:
        return -1
    sq[sn, 0] = g
    sq[sn, 1] = tri[g]
    sq[sn, 2] = tri[nxt(g)]
    sq[sn, 3] = forced
    return sn + 1


# ------------------------------------------------------------------ tests
@kernel
def piece_needs_split(tri, twin, x, y, inf, lab, conforming, lens, h):
    """Whether constrained half-edge ``h`` is encroached: a triangle vertex
    beside it (inside the domain, or anywhere with ``conforming``) lies strictly
    in its diametral circle; with ``conforming`` also when it is not locally
    Delaunay (exact test)."""
    a = tri[h]
    b = tri[nxt(h)]
    g = twin[h]
    p = tri[prv(h)]
    d = tri[prv(g)]
    if p != inf and (conforming or lab[h // 3] != OUT) and encroaches(x, y, a, b, x[p], y[p], lens):
        return True
    if d != inf and (conforming or lab[g // 3] != OUT) and encroaches(x, y, a, b, x[d], y[d], lens):
        return True
    if conforming and p != inf and d != inf and a != inf and b != inf:
        return edge_is_illegal(x, y, x, False, inf, a, b, p, d)
    return False


PRECISION_FLOOR = 2.0 ** -44   # an edge shorter than this times its coordinates is at the limit


@kernel
def below_precision(x, y, u, v):
    """Whether edge ``u v`` is shorter than :data:`PRECISION_FLOOR` times its
    largest coordinate: splitting it, or refining a triangle with it, only adds
    points that rounding puts next to each other, and near zero coordinates
    (where doubles are dense) such splits go on until the exact predicates
    underflow. Refinement leaves such edges alone, as Triangle does at the
    limit of precision."""
    m = max(abs(x[u]), abs(y[u]), abs(x[v]), abs(y[v])) * PRECISION_FLOOR
    return (x[u] - x[v]) ** 2 + (y[u] - y[v]) ** 2 < m * m


@kernel
def at_small_input_angle(x, y, vseg, seg_ends, nv0, a, b, c, sin2_bound):
    """Shewchuk's rule (as in Triangle): leave a skinny triangle alone when its
    shortest edge joins Steiner vertices on two segments that share an endpoint,
    lie at the same distance from it (concentric shells around a small input
    angle) and span an angle there smaller than the bound (``sin2_bound`` is
    its squared sine): splitting it would only cascade. A wider angle, up to a
    nearly straight boundary vertex, excuses nothing."""
    ab = (x[b] - x[a]) ** 2 + (y[b] - y[a]) ** 2
    bc = (x[c] - x[b]) ** 2 + (y[c] - y[b]) ** 2
    ca = (x[a] - x[c]) ** 2 + (y[a] - y[c]) ** 2
    if ab <= bc and ab <= ca:
        p, q = a, b
    elif bc <= ca:
        p, q = b, c
    else:
        p, q = c, a
    if p < nv0 or q < nv0:
        return False
    s1 = vseg[p]
    s2 = vseg[q]
    if s1 <= 0 or s2 <= 0 or s1 == s2:
        return False
    for i in range(2):
        for j in range(2):
            o = seg_ends[s1 - 1, i]
            if o == seg_ends[s2 - 1, j]:
                d1 = (x[p] - x[o]) ** 2 + (y[p] - y[o]) ** 2
                d2 = (x[q] - x[o]) ** 2 + (y[q] - y[o]) ** 2
                if 0.998 * d2 < d1 < 1.002 * d2:
                    # cos of the angle at o, against cos of the bound (both below 90 degrees)
                    dot = (x[p] - x[o]) * (x[q] - x[o]) + (y[p] - y[o]) * (y[q] - y[o])
                    return dot > 0.0 and dot * dot > (1.0 - sin2_bound) * d1 * d2
    return False


# ------------------------------------------------------------- operations


@kernel
def walk_to(tri, twin, cons, x, y, t, q, limit):
    """Visibility walk from triangle ``t`` to vertex ``q`` that never crosses a
    segment. Returns ``(code, e)`` as :func:`locate` does, or
    ``(WALK_BLOCKED, segment half-edge)`` when a segment is in the way."""
    came = -1
    for step in range(limit):
        ek, code, e = solid_step(tri, x, y, t, q, step, came)
        if ek < 0:
            return code, e
        if cons[ek] != 0:
            return WALK_BLOCKED, ek
        came = twin[ek]
        t = came // 3
    return WALK_FAILED, -1


@kernel
def cavity_encroached(mesh, h, on_edge, q, mark, stamp, bstack, enc, lens):
    """The segment pieces that new vertex ``q`` (located at half-edge ``h``)
    would encroach: those bounding its cavity, the triangles whose circumdisk
    holds ``q``, grown from the triangle(s) containing it without crossing a
    segment. Fills ``enc``; returns how many. ``mesh`` is ``(tri, twin, cons,
    x, y, inf)``."""
    tri, twin, cons, x, y, inf = mesh
    n = 0
    sp = np.int64(0)
    t0 = h // 3
    mark[t0] = stamp
    bstack[sp] = t0
    sp += 1
    if on_edge:
        t1 = twin[h] // 3
        mark[t1] = stamp
        bstack[sp] = t1
        sp += 1
    px = x[q]
    py = y[q]
    while sp > 0:
        sp -= 1
        t = bstack[sp]
        for k in range(3):
            e = 3 * t + k
            if cons[e] != 0:
                if n < enc.shape[0] and encroaches(x, y, tri[e], tri[nxt(e)], px, py, lens):
                    enc[n] = e
                    n += 1
                continue
            m = twin[e] // 3
            if mark[m] == stamp:
                continue
            a = tri[3 * m]
            b = tri[3 * m + 1]
            c = tri[3 * m + 2]
            if a == inf or b == inf or c == inf:
                continue
            if incircle(x[a], y[a], x[b], y[b], x[c], y[c], x[q], y[q]) > 0:
                mark[m] = stamp
                bstack[sp] = m
                sp += 1
    return n


@kernel
def param_on(x, y, A, B, v):
    """Parameter of vertex ``v`` along segment ``A -> B`` (0 at A, 1 at B)."""
    if v == A:
        return 0.0
    if v == B:
        return 1.0
    dx = x[B] - x[A]
    dy = y[B] - y[A]
    n = dx * dx + dy * dy
    if n == 0.0:   # underflow on a segment of subnormal length
        return 0.5
    return ((x[v] - x[A]) * dx + (y[v] - y[A]) * dy) / n


@kernel
def place_on_piece(x, y, seg_ends, sid, u, v, shell_at, q):
    """Write into vertex ``q`` the split point of piece ``u v`` of segment
    ``sid``: the midpoint, or with ``shell_at`` (``u`` or ``v``) the point at
    the power-of-two distance from that end nearest the middle (Ruppert's
    concentric shells: pieces at a small angle get split at equal radii).
    Placed along the input segment, so it lies on it up to one rounding."""
    A = seg_ends[sid - 1, 0]
    B = seg_ends[sid - 1, 1]
    tu = param_on(x, y, A, B, u)
    tv = param_on(x, y, A, B, v)
    if shell_at >= 0:
        tc, to = (tu, tv) if shell_at == u else (tv, tu)
        length = np.sqrt((x[v] - x[u]) ** 2 + (y[v] - y[u]) ** 2)
        shell = 1.0
        while length > 3.0 * shell:
            shell *= 2.0
        while length < 1.5 * shell:
            shell *= 0.5
        tm = tc + (shell / length) * (to - tc)
    else:
        tm = 0.5 * (tu + tv)
    x[q] = on_grid(x[A] + tm * (x[B] - x[A]))
    y[q] = on_grid(y[A] + tm * (y[B] - y[A]))


@kernel
def shell_centre(tri, twin, cons, lab, e):
    """Triangle's rule: when exactly one end of piece ``e`` meets another
    segment inside a domain triangle beside it (the two span an angle there),
    split on the concentric shells around that end; else (-1) at the midpoint."""
    f = twin[e]
    se = lab[e // 3] != OUT
    sf = lab[f // 3] != OUT
    at_u = (se and cons[prv(e)] != 0) or (sf and cons[nxt(f)] != 0)
    at_v = (se and cons[nxt(e)] != 0) or (sf and cons[prv(f)] != 0)
    if at_u and not at_v:
        return tri[e]
    if at_v and not at_u:
        return tri[f]
    return -1


@kernel
def split_piece(mesh, ntri, q, e, lab, segments, work, counts, conforming):
    """Split the segment piece of half-edge ``e`` at new vertex ``q``, then
    restore the constrained Delaunay property by flips. A split that would
    invert a triangle of the domain, or of a piece below
    :func:`below_precision` (the piece is at the limit of floating point),
    freezes the piece instead. Returns ``(done, ntri, slot of a triangle at q)``.

    Only the sides in the domain count (unless ``conforming``, which makes the
    whole triangulation Delaunay): ``q`` lies on the piece up to rounding, and
    beside a nearly straight boundary vertex the triangle outside can be
    thinner than that (Triangle has no triangles outside when it refines).
    Such an outside triangle may invert; no walk or flip enters it (walks stop
    at segments, flips need two counter-clockwise triangles).

    ``mesh`` is ``(tri, twin, cons, x, y, inf)``, ``segments`` ``(seg_ends,
    vseg, nv0)`` and ``work`` the flips' buffers ``(stack, fc, no_sub)``, as
    in :func:`refine_loop`."""
    tri, twin, cons, x, y, inf = mesh
    seg_ends, vseg, nv0 = segments
    stack = work[0]
    sid = cons[e]
    u = tri[e]
    v = tri[nxt(e)]
    f = twin[e]
    c = tri[prv(e)]
    d = tri[prv(f)]
    place_on_piece(x, y, seg_ends, sid, u, v, shell_centre(tri, twin, cons, lab, e), q)
    # each side: its two new triangles are counter-clockwise (ghosts: nothing to check)
    c_side = c != inf and orient(x, y, c, u, q) > 0 and orient(x, y, v, c, q) > 0
    d_side = d != inf and orient(x, y, d, v, q) > 0 and orient(x, y, u, d, q) > 0
    ok = not below_precision(x, y, np.int64(u), np.int64(v))
    if c != inf and not c_side and (conforming or lab[e // 3] != OUT):
        ok = False
    if d != inf and not d_side and (conforming or lab[f // 3] != OUT):
        ok = False
    if not ok:
        cons[e] = -sid
        cons[f] = -sid
        counts[C_FROZEN] += 1
        return False, ntri, -1
    t1 = e // 3
    t2 = f // 3
    ntri = split_edge(tri, twin, cons, e, q, ntri)
    lab[ntri - 2] = lab[t1]
    lab[ntri - 1] = lab[t2]
    vseg[q] = sid
    # flip on sides with counter-clockwise triangles only: a hull piece split at
    # a rounded point may leave the hull non-convex by an ulp, and its ghosts
    # must stay as they are; an inverted sliver outside the domain is left too
    sp = np.int64(0)
    if c_side:
        stack[0] = 3 * t1
        stack[1] = 3 * (ntri - 2)
        sp = 2
    if d_side:
        stack[sp] = 3 * t2
        stack[sp + 1] = 3 * (ntri - 1)
        sp += 2
    _legalize(mesh, q, sp, work, counts)
    # q lies on the piece only up to rounding: Lawson's argument (the new
    # edges at q are locally Delaunay) holds for a point exactly on the edge,
    # so q's edges to c and d are tested, and flipped with whatever follows
    ok, slot = flip_edges_at(mesh, q, t1, c if c_side else inf, d if d_side else inf, stack,
                             counts)
    if not ok:
        counts[C_UNREPAIRED] += 1
    counts[C_SEG_SPLITS] += 1
    return True, ntri, slot


@kernel
def flip_edges_at(mesh, q, slot, c, d, stack, counts):
    """Flip the edges from ``q`` (in triangle ``slot``) to ``c`` and ``d``
    if they are not locally Delaunay, and then every edge around a flip that
    is not, until none is left (ghost triangles are left alone). Returns
    ``(done, slot of a triangle at q)``; not done if ``stack`` ran out (the
    repair stopped short)."""
    tri, twin, cons, x, y, inf = mesh
    e = 3 * slot
    while tri[e] != q:
        e += 1
    sp = np.int64(0)
    e0 = e
    while True:                      # the half-edges out of q
        v = tri[nxt(e)]
        if (v == c or v == d) and v != inf:
            stack[sp] = e
            sp += 1
        e = twin[prv(e)]
        if e == e0 or sp == 2:
            break
    while sp > 0:
        sp -= 1
        e = stack[sp]
        f = twin[e]
        if cons[e] != 0:
            continue
        a = tri[e]
        b = tri[f]
        p = tri[prv(e)]
        g = tri[prv(f)]
        if a == inf or b == inf or p == inf or g == inf:
            continue
        if not edge_is_illegal(x, y, x, False, inf, a, b, p, g):
            continue
        # at the limit of precision the quadrilateral may be degenerate: flip
        # only into two strictly counter-clockwise triangles
        if orient(x, y, p, a, g) <= 0 or orient(x, y, p, g, b) <= 0:
            continue
        flip(tri, twin, cons, e)   # (p, a, g) stays in e's slot, (p, g, b) in f's
        counts[C_FLIPS] += 1
        if slot == e // 3 or slot == f // 3:
            slot = f // 3 if q == b else e // 3
        if sp + 4 > stack.shape[0]:
            return False, slot
        sp = push_outer_edges(stack, sp, e, f)
    return True, slot


@kernel
def _legalize(mesh, q, sp, work, counts):
    """Flip from the ``sp`` half-edges on ``work[0]`` (the stack), counting the flips."""
    x = mesh[3]
    stack, fc, no_sub = work
    fc[0] = 0
    legalize(mesh, (x, np.bool_(False)), q, stack, sp, np.bool_(False), no_sub, fc)
    counts[C_FLIPS] += fc[0]


@kernel
def insert_free(mesh, ntri, q, code, h, lab, work, counts):
    """Insert vertex ``q`` located at ``(code, h)`` (inside a triangle or on a
    non-segment edge) and flip (``mesh`` and ``work`` as in :func:`split_piece`).
    Returns ``(slot of a triangle at q, ntri)``."""
    tri, twin, cons = mesh[0], mesh[1], mesh[2]
    stack = work[0]
    t = h // 3
    if code == INSIDE:
        ntri = split_triangle(tri, twin, cons, t, q, ntri)
        lab[ntri - 2] = lab[t]
        lab[ntri - 1] = lab[t]
        stack[0] = 3 * t
        stack[1] = 3 * (ntri - 2)
        stack[2] = 3 * (ntri - 1)
        sp = 3
    else:
        t2 = twin[h] // 3
        ntri = split_edge(tri, twin, cons, h, q, ntri)
        lab[ntri - 2] = lab[t]
        lab[ntri - 1] = lab[t2]
        stack[0] = 3 * t
        stack[1] = 3 * t2
        stack[2] = 3 * (ntri - 2)
        stack[3] = 3 * (ntri - 1)
        sp = 4
    _legalize(mesh, q, sp, work, counts)
    return t, ntri


# ------------------------------------------------------------- main loop
RefineBuffers = namedtuple("RefineBuffers",
                           "hitems hnext hfree qhead qtail qstate sq mark bstack stack enc fc no_sub "
                           "located")


class RefineParameters(NamedTuple):
    """What the refinement loop reads, derived once from the :class:`RefineOptions`
    by :func:`refine_store`."""

    sin2_bound: float               # squared sine of the angle bound (0: none)
    offconstant: float              # the off-centre constant (0: circumcentres)
    lens: float                     # the diametral lens (:func:`encroaches`; 0: circles)
    conforming: bool                # split pieces that are not locally Delaunay too
    max_new: int                    # Steiner points the loop may insert
    area_of_label: np.ndarray       # area bound per triangle label (:func:`area_bound`)
    home: np.ndarray                # the mesh the labels name, to relocate them (:func:`home_of`)
    home_nb: np.ndarray             # its neighbours (empty ``home``: labels stay with their slots)


@kernel(_nrt=False)
def refine_loop(mesh, ntri, nv, lab, segments, params, counts, buffers):
    """Refine until no piece is encroached and no triangle is bad (or is
    excused: small input angle, frozen segments). ``mesh`` is ``(tri, twin,
    cons, x, y, inf)``, ``segments`` ``(seg_ends, vseg, nv0)`` (each segment's
    ends, the segment each Steiner vertex on one lies on, the first Steiner
    vertex), ``params`` a :class:`RefineParameters`. Work queues are rebuilt
    from a scan on entry and whenever they run dry after progress, so nothing
    is lost when a flip moves a queued half-edge. Returns ``(status, ntri,
    nv)``: FINISHED, NEED_ROOM (grow the arrays, call again), HEAP_FULL or
    PIECES_FULL (grow that queue, call again) or LIMIT (``params.max_new``
    vertices inserted). ``buffers`` is a :class:`RefineBuffers`: the loop
    allocates nothing, so it is compiled without reference counting
    (``_nrt=False``), which is a fifth of its time otherwise."""
    tri, twin, cons, x, y, inf = mesh
    seg_ends, vseg, nv0 = segments
    conforming, lens, max_new = params.conforming, params.lens, params.max_new
    sq, mark = buffers.sq, buffers.mark
    Q = (buffers.hitems, buffers.hnext, buffers.hfree, buffers.qhead, buffers.qtail)
    qs = buffers.qstate
    hitems = buffers.hitems
    queue_reset(Q, qs)
    bstack, enc = buffers.bstack, buffers.enc
    work = (buffers.stack, buffers.fc, buffers.no_sub)     # the flips' buffers
    cap_tri = tri.shape[0] // 3
    sn = np.int64(0)   # (typed: a literal argument compiles the callee once more)
    stamp = 0
    for t in range(mark.shape[0]):
        stamp = max(stamp, mark[t])
    walk_limit = 64 + 4 * ntri
    scanned_at = -1
    while True:
        if sn == 0 and qs[3] == 0:
            if scanned_at == counts[C_STEINER]:
                return FINISHED, ntri, nv
            scanned_at = counts[C_STEINER]
            # scan everything: bad triangles and encroached pieces
            for t in range(ntri):
                if not queue_if_bad(tri, x, y, lab, params, Q, qs, t, buffers.located):
                    return HEAP_FULL, ntri, nv
            for e in range(3 * ntri):
                if cons[e] > 0 and e < twin[e] and piece_needs_split(tri, twin, x, y, inf, lab,
                                                                     conforming, lens, e):
                    sn = queue_piece(tri, sq, sn, e, NOT_FORCED)
                    if sn < 0:
                        return PIECES_FULL, ntri, nv
            continue
        if nv + 1 >= inf or ntri + 2 > cap_tri:
            return NEED_ROOM, ntri, nv
        if counts[C_STEINER] >= max_new:
            return LIMIT, ntri, nv
        q = nv
        if sn > 0:
            sn -= 1
            e = sq[sn, 0]
            if tri[e] != sq[sn, 1] or tri[nxt(e)] != sq[sn, 2] or cons[e] <= 0:
                continue  # stale (the scan will find it again) or frozen
            if sq[sn, 3] == 0 and not piece_needs_split(tri, twin, x, y, inf, lab, conforming, lens, e):
                continue
            done, ntri, slot = split_piece(mesh, ntri, q, e, lab, segments, work, counts,
                                           conforming)
            if not done:
                continue
        else:
            s = queue_pop(Q, qs)
            t = hitems[s, 0]
            a = hitems[s, 1]
            b = hitems[s, 2]
            c = hitems[s, 3]
            if tri[3 * t] != a or tri[3 * t + 1] != b or tri[3 * t + 2] != c or lab[t] == OUT:
                continue  # stale
            angle_bad, area_bad, key = is_bad(x, y, a, b, c, params, lab[t])
            counts[C_ATTEMPTS] += 1
            if not area_bad and at_small_input_angle(x, y, vseg, seg_ends, nv0, a, b, c,
                                                     params.sin2_bound):
                counts[C_SKIPPED] += 1
                continue
            if below_precision(x, y, a, b) or below_precision(x, y, b, c) or below_precision(x, y, c, a):
                counts[C_SKIPPED] += 1
                continue
            px, py = steiner_point(x, y, a, b, c, params.offconstant)
            if not (np.isfinite(px) and np.isfinite(py)):
                counts[C_SKIPPED] += 1
                continue
            x[q] = on_grid(px)
            y[q] = on_grid(py)
            code, h = walk_to(tri, twin, cons, x, y, t, q, walk_limit)
            if code == WALK_FAILED or code == ON_VERTEX:
                counts[C_SKIPPED] += 1
                continue
            nenc = 0
            if code == WALK_BLOCKED or (code == ON_EDGE and cons[h] != 0):
                enc[0] = h
                nenc = 1
            else:
                stamp += 1
                nenc = cavity_encroached(mesh, h, code == ON_EDGE, q, mark, stamp, bstack, enc,
                                         lens)
            if nenc > 0:
                pushed = 0
                for i in range(nenc):
                    g = enc[i]
                    if cons[g] > 0:
                        sn = queue_piece(tri, sq, sn, g, FORCED)
                        if sn < 0:
                            return PIECES_FULL, ntri, nv
                        pushed += 1
                if pushed > 0:   # try again after the pieces are split
                    counts[C_DEFERRED] += 1
                    if not queue_triangle(Q, qs, key, t, a, b, c):
                        return HEAP_FULL, ntri, nv
                    continue
                if code == WALK_BLOCKED or code == ON_EDGE:
                    # behind (or on) a frozen segment: a triangle that is too
                    # large still gets its centroid (its children are a third
                    # of it, so this ends); a skinny one is left as it is
                    if not area_bad:
                        counts[C_SKIPPED] += 1
                        continue
                    x[q] = on_grid((x[a] + x[b] + x[c]) / 3.0)
                    y[q] = on_grid((y[a] + y[b] + y[c]) / 3.0)
                    code, h = walk_to(tri, twin, cons, x, y, t, q, walk_limit)
                    if code != INSIDE and (code != ON_EDGE or cons[h] != 0):
                        counts[C_SKIPPED] += 1
                        continue
                # only frozen pieces are encroached: insert anyway (Triangle's -Y)
            slot, ntri = insert_free(mesh, ntri, q, code, h, lab, work, counts)
        nv += 1
        counts[C_STEINER] += 1
        # queue what the new vertex's star needs
        e0 = 3 * slot
        while tri[e0] != q:
            e0 += 1
        e = e0
        while True:
            t = e // 3
            if not queue_if_bad(tri, x, y, lab, params, Q, qs, t, buffers.located):
                return HEAP_FULL, ntri, nv
            for k in range(3):
                g = 3 * t + k
                if cons[g] > 0 and piece_needs_split(tri, twin, x, y, inf, lab, conforming, lens, g):
                    sn = queue_piece(tri, sq, sn, g, NOT_FORCED)
                    if sn < 0:
                        return PIECES_FULL, ntri, nv
            e = twin[prv(e)]
            if e == e0:
                break


@kernel
def hull_pieces(tri, twin, cons, lab, ntri, inf, first_id):
    """Make every convex-hull edge of an inside triangle a segment (ids from
    ``first_id``), so refinement splits it like any boundary segment. Returns
    the new segments' endpoints."""
    out = np.empty((ntri + 3, 2), np.int64)
    n = 0
    for e in range(3 * ntri):
        if cons[e] != 0 or lab[e // 3] == OUT:
            continue
        f = twin[e]
        if tri[3 * (f // 3)] == inf or tri[3 * (f // 3) + 1] == inf or tri[3 * (f // 3) + 2] == inf:
            cons[e] = first_id + n
            cons[f] = first_id + n
            out[n, 0] = tri[e]
            out[n, 1] = tri[nxt(e)]
            n += 1
    return out[:n]


@kernel
def freeze_boundary(tri, twin, cons, lab, ntri):
    """``split_boundary=False``: freeze the pieces with the outside on one side."""
    for e in range(3 * ntri):
        if cons[e] > 0 and (lab[e // 3] == OUT) != (lab[twin[e] // 3] == OUT):
            cons[e] = -cons[e]
            cons[twin[e]] = -cons[twin[e]]


@kernel
def freeze_segments(cons, ntri):
    """``split_segments=False`` (Triangle's -YY): freeze every piece."""
    for e in range(3 * ntri):
        if cons[e] > 0:
            cons[e] = -cons[e]


@kernel(apart=True, ahead=(STORE, I64, I64_2, REFINE_OPTIONS, F8, i8, i8, I64, i8, Tuple((I64_2, I64_2))),
        returns=Tuple((i8, I64, I64, I64_2, STORE, I64)))
def refine_store(store, lab, seg_ends, refinement, area_of_label, max_new, room, vseg, nv0,
                 home):
    """Refine the store ``(tri, twin, cons, x, y, w, inf, ntri, nv)`` whose
    triangle labels are ``lab`` as ``refinement`` (a :class:`RefineOptions`:
    its ``min_angle``, ``conforming``, ``split_boundary`` and ``split_segments``) asks, with the
    area bound of each label in ``area_of_label`` (:func:`area_bound`; the
    caller derives it from ``refinement.max_area`` and the region seeds), at
    most ``max_new`` Steiner points, and room for at least ``room`` vertices
    from the start (more is made by doubling). ``seg_ends`` (mesh ids of each
    segment's ends) gains the hull edges made segments. Frozen pieces are
    unfrozen on return. Returns ``(status, counts, lab, seg_ends, (tri, twin,
    cons, x, y, w, inf, ntri, nv), vseg)``. ``vseg`` is the segment id of each
    vertex from ``nv0`` on that a refinement placed on a segment (0: none), as a
    previous call returned it, or empty (and ``nv0`` -1) for a store no
    refinement has touched: Shewchuk's rule around small input angles reads it
    (:func:`at_small_input_angle`). ``home`` is ``(triangles, neighbours)`` of
    the mesh whose triangles the labels are (store ids), each triangle's label
    then becoming the one that holds its centroid (:func:`queue_if_bad`), or
    two empty arrays (labels stay with their slots)."""
    tri, twin, cons, x, y, w, inf, ntri, nv = store
    min_angle, conforming = refinement.min_angle, refinement.conforming
    if nv0 < 0:
        nv0 = nv
    # the same refined mesh for any order of the input vertices and segments and
    # any segment direction: slots in canonical order (refinement scans them),
    # each segment from its smaller end (split points are placed along it)
    ntri, old = canonical_slots(tri, twin, cons, ntri)
    lab = _permuted(lab, old)
    seg_ends = seg_ends.copy()
    for s in range(seg_ends.shape[0]):
        if seg_ends[s, 0] > seg_ends[s, 1]:
            seg_ends[s, 0], seg_ends[s, 1] = seg_ends[s, 1], seg_ends[s, 0]
    seg_ends = with_hull_pieces(tri, twin, cons, lab, ntri, inf, seg_ends)
    if not refinement.split_segments:
        freeze_segments(cons, ntri)
    elif not refinement.split_boundary:
        freeze_boundary(tri, twin, cons, lab, ntri)
    sin2_bound, offconstant = 0.0, 0.0
    if min_angle > 0:
        theta = math.radians(min_angle)
        sin2_bound = math.sin(theta) ** 2
        # Triangle's off-centre constant, 0.475 cot(theta / 2); 0 (plain circumcentres) when
        # theta is so small that cos(theta) rounds to 1: the off-centre lies past the circumcentre
        cos_theta = math.cos(theta)
        offconstant = 0.475 * math.sqrt((1.0 + cos_theta) / (1.0 - cos_theta)) if cos_theta < 1.0 else 0.0
    # diametral lenses for quality meshing, circles for conforming Delaunay
    lens = 0.0 if conforming else math.cos(2 * math.radians(min_angle)) ** 2
    room = max(room, STEINER_ROOM * nv0 + 64)   # at least the usual few Steiner points per vertex
    if inf < room:
        tri, twin, cons, x, y, w, inf = grow_store(tri, twin, cons, x, y, w, inf, nv, room)
    lab = _grown(lab, tri.shape[0] // 3, np.int64(OUT))
    vseg = _grown(vseg, inf + 1, np.int64(0))
    counts = np.zeros(8, np.int64)
    params = RefineParameters(sin2_bound, offconstant, lens, conforming, max_new, area_of_label,
                              home[0], home[1])
    heap, pieces = max(1024, ntri), np.int64(256)
    while True:
        status, ntri, nv, heap, pieces = refine_run((tri, twin, cons, x, y, inf), ntri, nv, lab,
                                                    (seg_ends, vseg, nv0), params, counts,
                                                    heap, pieces)
        if status != NEED_ROOM:
            break
        tri, twin, cons, x, y, w, inf = grow_store(tri, twin, cons, x, y, w, inf, nv, np.int64(0))
        lab = _grown(lab, tri.shape[0] // 3, np.int64(OUT))
        vseg = _grown(vseg, inf + 1, np.int64(0))
    for e in range(cons.shape[0]):
        cons[e] = abs(cons[e])
    if counts[C_UNREPAIRED]:   # (never seen: a repair needs a stack as deep as the mesh)
        counts[C_FLIPS] += flip_to_delaunay(tri, twin, cons, x, y, x, np.bool_(False), inf, ntri)
    return status, counts, lab, seg_ends, (tri, twin, cons, x, y, w, inf, ntri, nv), vseg


@kernel
def with_hull_pieces(tri, twin, cons, lab, ntri, inf, seg_ends):
    """``seg_ends`` followed by the hull edges that :func:`hull_pieces` makes segments."""
    hull = hull_pieces(tri, twin, cons, lab, ntri, inf, seg_ends.shape[0] + 1)
    return np.concatenate((seg_ends, hull))


STEINER_ROOM = 4   # vertex room refinement starts with, per input vertex

@kernel(inline="always")
def refine_run(mesh, ntri, nv, lab, segments, params, counts, heap, pieces):
    """:func:`refine_loop` with its work arrays: a queue of ``heap`` bad
    triangles and a stack of ``pieces`` segment pieces, doubled (and the loop
    called again) when one runs full. Returns ``(status, ntri, nv, heap,
    pieces)``; NEED_ROOM asks the caller to grow the mesh and call again."""
    tri, inf = mesh[0], mesh[5]
    cap_tri = tri.shape[0] // 3
    while True:
        buffers = RefineBuffers(
            np.empty((heap, 4), np.int64), np.empty(heap, np.int64), np.empty(heap, np.int64),
            np.empty(NBUCKETS, np.int64), np.empty(NBUCKETS, np.int64), np.zeros(4, np.int64),
            np.empty((pieces, 4), np.int64),        # e, u, v, forced
            np.zeros(cap_tri, np.int64), np.empty(cap_tri + 8, np.int64), np.empty(inf + 16, np.int64),
            np.empty(64, np.int64), np.zeros(2, np.int64), np.zeros(1, np.int8),
            np.full(3 * cap_tri if params.home.shape[0] > 0 else 0, -1, np.int32))
        status, ntri, nv = refine_loop(mesh, ntri, nv, lab, segments, params, counts, buffers)
        if status == HEAP_FULL:
            heap *= 2
        elif status == PIECES_FULL:
            pieces *= 2
        else:
            return status, ntri, nv, heap, pieces


@kernel
def _permuted(lab, old):
    """Slot labels after :func:`.mesh.canonical_slots`: new slot ``i`` was ``old[i]``."""
    out = np.full(lab.shape[0], OUT, np.int64)
    for i in range(old.shape[0]):
        out[i] = lab[old[i]]
    return out


@kernel
def _grown(a, n, fill):
    """``a`` lengthened to ``n`` with ``fill`` (``a`` itself when long enough)."""
    if a.shape[0] >= n:
        return a
    b = np.full(n, fill, a.dtype)
    copy_rows(b, a, a.shape[0])
    return b


@kernel
def count_below(vertices, triangles, sin2_bound):
    """Indices of the triangles whose smallest angle is below the bound, by
    the test the refinement itself uses."""
    x, y = vertices[:, 0].copy(), vertices[:, 1].copy()
    out = np.empty(triangles.shape[0], np.int64)
    n = 0
    for t in range(triangles.shape[0]):
        key, _ = sin2_min_angle(x, y, triangles[t, 0], triangles[t, 1], triangles[t, 2])
        if key < sin2_bound:
            out[n] = t
            n += 1
    return out[:n]
