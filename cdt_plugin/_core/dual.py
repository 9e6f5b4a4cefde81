"""The dual of a Delaunay triangulation (Sec. 2.2, Fig. 2.3): the faces of the
Delaunay subdivision (triangles whose shared edge is a cocircular tie fused
into one convex polygon), the ring of faces around each vertex (its Voronoi
cell, Sec. 2.2; its power cell for a weighted triangulation, Sec. 2.8), the
face centres, and the cells clipped to a convex polygon.

Triangles are output arrays: ``triangles[t]`` counter-clockwise and
``neighbors[t, j]`` across the edge opposite vertex ``j``, that is the edge
from ``triangles[t, j + 1]`` to ``triangles[t, j + 2]`` (indices mod 3).
Every combinatorial decision was made before (the fused flags come from the
exact lifted test) or is made here with the exact ``orient2d``; the centres
and clipped corners are floating-point constructions.
"""
from __future__ import annotations

import numpy as np

from .borrow import unowned
from .jit import entry, kernel
from .mesh import DEAD, is_ghost, is_solid, nxt, prv
from .predicates import incircle, incircle_weighted, orient2d


@kernel
def corner_of(triangles, t, v):
    """The corner of triangle ``t`` at vertex ``v`` (-1 if ``v`` is not on it)."""
    for j in range(3):
        if triangles[t, j] == v:
            return j
    return -1


@kernel
def back_corner(neighbors, u, t):
    """The corner of triangle ``u`` whose opposite edge it shares with ``t``."""
    for j in range(3):
        if neighbors[u, j] == t:
            return j
    return -1


@entry
def fuse_ties(vx, vy, vw, weighted, triangles, neighbors, fused, lo, hi):
    """The exact lifted test across the interior edges of triangles
    ``lo:hi`` (each edge from its smaller triangle; Lemma 2.3, Sec. 2.8 with
    weights): sets ``fused[t, j]`` on both sides of each cocircular
    (lifted-coplanar) edge. Returns the first edge that is not locally
    Delaunay, as ``3 t + j``, or -1. Ranges may run on threads side by side:
    each writes only the flags of its own edges."""
    bad = -1
    for t in range(lo, hi):
        a = triangles[t, 0]
        b = triangles[t, 1]
        c = triangles[t, 2]
        for j in range(3):
            u = neighbors[t, j]
            if u < t:                    # the hull, or seen from the other side
                continue
            i = back_corner(neighbors, u, t)
            r = lifted_test(vx, vy, vw, weighted, a, b, c, triangles[u, i])
            if r == 0:
                fused[t, j] = True
                fused[u, i] = True
            elif r > 0 and bad < 0:
                bad = 3 * t + j
    return bad


@kernel(inline='always')
def lifted_test(vx, vy, vw, weighted, a, b, c, d):
    """The exact lifted test of ``d`` against the counter-clockwise ``a, b, c``
    (incircle; the power test with weights): > 0 if ``d`` is inside, 0 on
    the circle (a tie)."""
    if weighted:
        return incircle_weighted(vx[a], vy[a], vw[a], vx[b], vy[b], vw[b],
                                 vx[c], vy[c], vw[c], vx[d], vy[d], vw[d])
    return incircle(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c], vx[d], vy[d])


@entry
def triangle_faces(triangles, ring, lo, hi):
    """The faces of triangles ``lo:hi`` where none is fused (face ``t`` is
    triangle ``t``): each its vertices from the smallest, into ``ring[3 t:]``."""
    for t in range(lo, hi):
        put_triangle(triangles, t, ring, 3 * t)


@kernel
def put_triangle(triangles, t, ring, at):
    """Triangle ``t``'s vertices, counter-clockwise from its smallest, into ``ring[at:at + 3]``."""
    for j in range(3):
        ring[at + j] = triangles[t, j]
    rotate_to_min(ring, at, at + 3)


@entry
def subdivision_faces(triangles, neighbors, fused):
    """The faces of the Delaunay subdivision: the triangles joined across
    ``fused`` edges (both sides flagged). Returns ``(face_of, offsets, ring)``:
    each triangle's face, and each face's boundary as counter-clockwise vertex
    ids from its smallest id, ``ring[offsets[f]:offsets[f + 1]]``. Faces are
    numbered in order of their first triangle."""
    k = triangles.shape[0]
    face_of = np.full(k, -1, np.int64)
    offsets = np.zeros(k + 1, np.int64)
    ring = np.empty(3 * k, np.int64)     # a face of m triangles has m + 2 <= 3m corners
    stack = np.empty(k, np.int64)
    members = np.empty(k, np.int64)
    nf = 0
    nr = 0
    for t0 in range(k):
        if face_of[t0] >= 0:
            continue
        face_of[t0] = nf
        if not (fused[t0, 0] or fused[t0, 1] or fused[t0, 2]):
            put_triangle(triangles, t0, ring, nr)    # a face of its own (the common case)
            nr += 3
            nf += 1
            offsets[nf] = nr
            continue
        stack[0] = t0
        top = 1
        nm = 0
        while top > 0:                   # the face's triangles
            top -= 1
            t = stack[top]
            members[nm] = t
            nm += 1
            for j in range(3):
                u = neighbors[t, j]
                if fused[t, j] and u >= 0 and face_of[u] < 0:
                    face_of[u] = nf
                    stack[top] = u
                    top += 1
        ts = -1
        js = -1
        for i in range(nm):              # a boundary edge to start from
            for j in range(3):
                if not fused[members[i], j]:
                    ts = members[i]
                    js = j
                    break
            if ts >= 0:
                break
        start = nr
        t = ts
        j = js
        for _ in range(3 * nm + 3):      # walk the boundary counter-clockwise
            ring[nr] = triangles[t, (j + 1) % 3]
            nr += 1
            j = (j + 1) % 3              # the next edge of t, from the same vertex on
            while fused[t, j]:           # interior to the face: go round that vertex
                u = neighbors[t, j]
                j = (back_corner(neighbors, u, t) + 1) % 3
                t = u
            if t == ts and j == js:
                break
        rotate_to_min(ring, start, nr)
        nf += 1
        offsets[nf] = nr
    return face_of, offsets[: nf + 1], ring[:nr]


@kernel
def rotate_to_min(ring, lo, hi):
    """Rotate ``ring[lo:hi]`` in place so that it starts at its smallest value."""
    m = lo
    for i in range(lo + 1, hi):
        if ring[i] < ring[m]:
            m = i
    if m == lo:
        return
    reverse(ring, lo, m)
    reverse(ring, m, hi)
    reverse(ring, lo, hi)


@kernel
def reverse(a, lo, hi):
    """Reverse ``a[lo:hi]`` in place."""
    hi -= 1
    while lo < hi:
        a[lo], a[hi] = a[hi], a[lo]
        lo += 1
        hi -= 1


@entry
def ring_offsets(triangles, neighbors, nv):
    """``(offsets, first, hull, pinched)``: where each vertex's ring starts in
    the flat ring array (room for its triangles and, on the hull, the -1 that
    ends its cell), the first triangle it is on (the one whose range walks
    round it), whether it is on the hull, and the smallest vertex with two
    outgoing hull edges (the domain pinched there: not a convex one), or ``nv``."""
    offsets = np.zeros(nv + 1, np.int64)
    first = np.full(nv, -1, np.int64)
    hull = np.zeros(nv, np.bool_)
    pinched = nv
    for t in range(triangles.shape[0]):
        for j in range(3):
            v = triangles[t, j]
            offsets[v + 1] += 1
            if first[v] < 0:
                first[v] = t
            if neighbors[t, (j + 2) % 3] < 0:        # the hull edge v -> triangles[t, j + 1]
                if hull[v]:
                    pinched = min(pinched, v)
                hull[v] = True
                offsets[v + 1] += 1
    for v in range(nv):
        offsets[v + 1] += offsets[v]
    return offsets, first, hull, pinched


@entry
def vertex_rings(vx, vy, triangles, neighbors, offsets, first, ring, hull, lo, hi):
    """Fill ``ring`` with the triangles around each vertex whose first
    triangle is in ``lo:hi``, counter-clockwise; a hull vertex's (``hull``)
    from the one after its outgoing hull edge to the one before its incoming
    one, then -1 (the vertex's cell when no triangles are fused, in scipy's
    form). Returns the smallest such hull vertex where the boundary turns
    right (exact ``orient2d``: the triangles do not cover a convex domain), or
    ``len(vx)``. Vertices are visited in triangle order, which keeps the walks'
    memory close together."""
    k = triangles.shape[0]
    reflex = vx.shape[0]
    for t0 in range(lo, hi):
        for j0 in range(3):
            v = triangles[t0, j0]
            if first[v] != t0:
                continue
            t = t0
            j = j0
            if hull[v]:
                for _ in range(k):       # back to the outgoing hull edge
                    u = neighbors[t, (j + 2) % 3]
                    if u < 0:
                        break
                    j = corner_of(triangles, u, v)
                    t = u
            a = triangles[t, (j + 1) % 3]
            n = offsets[v]
            end = offsets[v + 1] - 1 if hull[v] else offsets[v + 1]
            start = t
            while n < end:               # counter-clockwise round v
                ring[n] = t
                n += 1
                u = neighbors[t, (j + 1) % 3]
                if u < 0 or u == start:
                    break
                j = corner_of(triangles, u, v)
                t = u
            if n != end:                 # (two fans round v: not a planar triangulation)
                reflex = min(reflex, v)
            elif hull[v]:
                ring[n] = -1
                b = triangles[t, (j + 2) % 3]
                if v < reflex and orient2d(vx[b], vy[b], vx[v], vy[v], vx[a], vy[a]) < 0:
                    reflex = v
    return reflex


@entry
def store_ties(vx, vy, vw, weighted, tri, twin, tid, centres, err, redo, lo, hi):
    """The exact lifted test (Lemma 2.3, Sec. 2.8 with weights) across each
    interior edge of the store's triangles ``lo:hi`` (each edge once, from its
    earlier triangle), and :func:`mark_if_close` for the centres of the two
    triangles (output rows ``tid``). Returns ``(bad, ties)``: the first
    half-edge that is not locally Delaunay (-1: none) and how many edges are
    cocircular ties (then triangles must be fused: the general route)."""
    # (one loop per value of the flag: tested inside the loop, it made the loop several times slower)
    if weighted:
        return ties_in_range(vx, vy, vw, True, tri, twin, tid, (centres, err, redo), lo, hi)
    return ties_in_range(vx, vy, vw, False, tri, twin, tid, (centres, err, redo), lo, hi)


@kernel(inline='always')
def ties_in_range(vx, vy, vw, weighted, tri, twin, tid, marks, lo, hi):
    """:func:`store_ties`' loop (``marks``: :func:`mark_if_close`'s ``(centres, err, redo)``)."""
    centres, err, redo = marks
    bad = -1
    ties = 0
    for t in range(lo, hi):
        f = tid[t]
        if f < 0:
            continue
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        for e in range(3 * t, 3 * t + 3):
            h = twin[e]
            g = tid[h // 3]
            if g < f:                    # the hull, or seen from the other side
                continue
            s = lifted_test(vx, vy, vw, weighted, a, b, c, tri[prv(h)])
            if s == 0:
                ties += 1
            elif s > 0 and bad < 0:
                bad = e
            mark_if_close(centres, err, redo, f, g)
    return bad, ties


@entry
def store_rings(tri, ntri, inf, nv):
    """The rings of a Delaunay triangulation's half-edge store (ghost
    triangles closing it round the infinite vertex ``inf``): ``(offsets,
    start)``. Vertex ``v``'s cell has room ``offsets[v]:offsets[v + 1]``: its
    triangles and, on the hull, the -1 that ends the cell. ``start[v]`` is the
    half-edge its walk leaves by: its first in the store (so the walk starts
    at its first triangle), -1 if it is on none; on the hull ``-2 - g`` for
    its ghost half-edge ``g`` to ``inf``, the last of its two ghosts before
    its outgoing hull edge."""
    offsets = np.zeros(nv + 1, np.int64)
    start = np.full(nv, -1, tri.dtype)       # (the store's index type: half as large)
    for t in range(ntri):
        if tri[3 * t] == DEAD:
            continue
        ghost = is_ghost(tri, t, inf)
        for e in range(3 * t, 3 * t + 3):
            v = tri[e]
            if v == inf:
                continue
            if not ghost:
                offsets[v + 1] += 1
                if start[v] == -1:
                    start[v] = e
            elif tri[nxt(e)] == inf:     # v -> inf: room for the -1
                offsets[v + 1] += 1
                start[v] = -2 - e        # (the hull's start wins)
    for v in range(nv):
        offsets[v + 1] += offsets[v]
    return offsets, start


@entry
def solid_rows(tri, ntri, inf):
    """The output row of each real triangle of the store (-1: ghost or
    dead), as ``store_triangles`` numbers them (the store's index type: half
    the memory of ``solid_ids``' rows)."""
    tid = np.empty(ntri, tri.dtype)
    k = 0
    for t in range(ntri):
        if not is_solid(tri[3 * t], tri[3 * t + 1], tri[3 * t + 2], inf):
            tid[t] = -1
        else:
            tid[t] = k
            k += 1
    return tid


#: Walks :func:`store_cells` takes a step of in turn
LANES = 8


@entry
def store_cells(vx, vy, tri, twin, tid, offsets, start, cells, hull, lo, hi):
    """The cells of vertices ``lo:hi`` where no triangles are fused: each
    vertex's ring of triangles (output rows: the Voronoi vertices)
    counter-clockwise from the store, ``twin`` across each edge into ``v``;
    a hull cell ends with -1 after its ghosts. Returns the smallest vertex in
    ``lo:hi`` that is on no triangle, whose walk does not close as the counts
    say, or whose boundary turns right (exact ``orient2d``: not a convex
    domain), or ``len(vx)``.

    Each step of a walk waits for the load of the one before; :data:`LANES`
    walks (of the next vertices) take a step each in turn, so that the memory
    serves several at once: at a million points the cells take about a third
    less time."""
    bad = vx.shape[0]
    vs = np.full(LANES, -1, np.int64)    # per lane: its vertex (-1: the lane is free),
    es = np.empty(LANES, np.int64)       # the half-edge it is at,
    firsts = np.empty(LANES, np.int64)   # the one it left by,
    lasts = np.empty(LANES, np.int64)    # the last one out of a real triangle,
    ns = np.empty(LANES, np.int64)       # and where it writes next
    next_v = lo
    busy = True
    while busy:
        busy = False
        for k in range(LANES):
            if vs[k] < 0:                # a free lane starts the next vertex's walk
                if next_v >= hi:
                    continue
                busy = True
                v = next_v
                next_v += 1
                e = start[v]
                hull[v] = e < -1
                if e < -1:
                    e = twin[prv(-2 - e)]    # the outgoing hull edge: after the ghosts
                if e < 0 or offsets[v] == offsets[v + 1]:
                    bad = min(bad, v)
                    continue
                vs[k] = v
                es[k] = e
                firsts[k] = e
                lasts[k] = e
                ns[k] = offsets[v]
            busy = True
            v = vs[k]
            e = es[k]
            i = tid[e // 3]
            cells[ns[k]] = i
            ns[k] += 1
            if i >= 0:
                lasts[k] = e
                es[k] = twin[prv(e)]
            if i < 0 or ns[k] == offsets[v + 1]:
                if not walk_closes(vx, vy, tri, offsets, hull, v, ns[k], i, es[k], firsts[k], lasts[k]):
                    bad = min(bad, v)
                vs[k] = -1
    return bad


@kernel
def walk_closes(vx, vy, tri, offsets, hull, v, n, i, e, first, last):
    """Whether vertex ``v``'s walk (:func:`store_cells`) ended as its counts
    say (written up to ``n``, the last cell ``i``, at half-edge ``e``): back at its
    ``first`` half-edge inside, at its ghosts on the hull, where its boundary
    does not turn right (``last``: the last half-edge out of ``v``)."""
    if n != offsets[v + 1] or (i < 0) != hull[v]:
        return False
    if not hull[v]:
        return e == first
    a = tri[nxt(first)]
    b = tri[prv(last)]
    return orient2d(vx[b], vy[b], vx[v], vy[v], vx[a], vy[a]) >= 0


@kernel
def cell_ring(triangles, offsets, ring, hull, face_of, v, faces, across):
    """Vertex ``v``'s Voronoi cell into ``faces[:m]``: the faces around it,
    counter-clockwise, consecutive repeats (triangles of one face) merged; a
    hull vertex's cell ends with -1, where it is open to infinity (scipy's
    form). ``across[i]``: the vertex across the side from face ``i`` to the
    next (the ridge it lies on; not made when ``across`` is empty). An interior
    vertex's cell starts where a face starts, so its last face is not the
    first again. Returns ``m``."""
    # (borrowed views: the helper in the loop's branches counted references per vertex)
    triangles, offsets, ring, hull = unowned(triangles), unowned(offsets), unowned(ring), unowned(hull)
    face_of, faces, across = unowned(face_of), unowned(faces), unowned(across)
    lo = offsets[v]
    d = offsets[v + 1] - lo - (1 if hull[v] else 0)      # (a hull ring ends with -1)
    s0 = 0
    if not hull[v]:
        for k in range(d):
            if face_of[ring[lo + k]] != face_of[ring[lo + (k - 1) % d]]:
                s0 = k
                break
    n = 0
    for k in range(d):
        t = ring[lo + (s0 + k) % d]
        f = face_of[t]
        if n == 0 or faces[n - 1] != f:
            faces[n] = f
            n += 1
        if across.shape[0] > 0:
            across[n - 1] = triangles[t, (corner_of(triangles, t, v) + 2) % 3]
    if hull[v]:
        faces[n] = -1
        if across.shape[0] > 0:
            across[n] = -1
        n += 1
    return n


@entry
def cell_rings(triangles, offsets, ring, hull, face_of, cells, sizes, lo, hi):
    """The cell of each vertex ``v`` in ``lo:hi`` (:func:`cell_ring`) into
    ``cells`` from ``offsets[v]`` (room for its ring: at least its length),
    and its length into ``sizes``."""
    cells = unowned(cells)               # (its slices then count no references)
    no_ridges = np.empty(0, np.int64)
    for v in range(lo, hi):
        sizes[v] = cell_ring(triangles, offsets, ring, hull, face_of, v, cells[offsets[v]:],
                             no_ridges)


@entry
def pack_cells(slots, cells, sizes, out_offsets, out, lo, hi):
    """The cells of the vertices in ``lo:hi`` moved from their room in
    ``cells`` (:func:`cell_rings`) to ``out`` at ``out_offsets``."""
    for v in range(lo, hi):
        for i in range(sizes[v]):
            out[out_offsets[v] + i] = cells[slots[v] + i]


@kernel
def cell_scratch(offsets, lo, hi):
    """Room for the cell of any vertex in ``lo:hi``: (faces, across)."""
    deg = 0
    for v in range(lo, hi):
        deg = max(deg, offsets[v + 1] - offsets[v])
    return np.empty(deg + 1, np.int64), np.empty(deg + 1, np.int64)


@entry
def face_centres(vx, vy, vw, offsets, ring, out, err, lo, hi):
    """The centre of each face in ``lo:hi`` into ``out``: the circumcentre
    (power centre with weights, Sec. 2.8) of three of its vertices spread round
    it (any three give the same point, these the best-conditioned), relative to
    the first of them; ``err``: a bound on its rounding error.

    Nearly cocircular triangles have centres a rounding error apart in plain
    doubles, which could put a cell's corners in the wrong order (a cell that
    crosses itself): :func:`mark_close` finds them and :func:`redo_centres`
    computes them again in double-double arithmetic, in which they keep their
    true order."""
    for f in range(lo, hi):
        a, b, c = face_triple(offsets, ring, f)
        put_centre(vx, vy, vw, True, a, b, c, out, err, f)


@entry
def triangle_centres(vx, vy, vw, weighted, triangles, out, err, lo, hi):
    """:func:`face_centres` where no triangles are fused: face ``t`` is
    triangle ``t`` (listed from its smallest vertex, as its face would be)."""
    if weighted:                         # (one loop per value of the flag: see store_ties)
        for t in range(lo, hi):
            put_centre(vx, vy, vw, True, triangles[t, 0], triangles[t, 1], triangles[t, 2], out, err, t)
    else:
        for t in range(lo, hi):
            put_centre(vx, vy, vw, False, triangles[t, 0], triangles[t, 1], triangles[t, 2], out, err, t)


@kernel(inline='always')
def put_centre(vx, vy, vw, weighted, a, b, c, out, err, f):
    """The circumcentre (power centre if ``weighted``) of ``a, b, c`` relative
    to ``a`` into ``out[f]``, a bound on its rounding error into ``err[f]``
    (NaN and an infinite bound if it rounds to a line)."""
    bx = vx[b] - vx[a]
    by = vy[b] - vy[a]
    cx = vx[c] - vx[a]
    cy = vy[c] - vy[a]
    lb = bx * bx + by * by
    lc = cx * cx + cy * cy
    if weighted:
        lb -= vw[b] - vw[a]
        lc -= vw[c] - vw[a]
    d = 2.0 * (bx * cy - by * cx)
    if d == 0.0:                         # so flat that it rounds to a line: redone exactly below
        out[f, 0] = np.nan
        out[f, 1] = np.nan
        err[f] = np.inf
        return
    out[f, 0] = vx[a] + (cy * lb - by * lc) / d
    out[f, 1] = vy[a] + (bx * lc - cx * lb) / d
    size = max(abs(bx), abs(by), abs(cx), abs(cy), np.sqrt(abs(lb)), np.sqrt(abs(lc)))
    near = max(abs(vx[a]), abs(vy[a]), size)
    err[f] = 2.0 ** -46 * (size * size * near / abs(d)) + 2.0 ** -52 * (abs(out[f, 0]) + abs(out[f, 1]))


@entry
def mark_close(triangles, neighbors, face_of, centres, err, redo, lo, hi):
    """Flag in ``redo`` both faces of every edge of triangles ``lo:hi`` whose
    centres are close (:func:`mark_if_close`)."""
    for t in range(lo, hi):
        f = face_of[t]
        for j in range(3):
            u = neighbors[t, j]
            if u < t or face_of[u] == f:
                continue
            mark_if_close(centres, err, redo, f, face_of[u])


@kernel
def mark_if_close(centres, err, redo, f, g):
    """Flag faces ``f`` and ``g`` in ``redo`` if their centres are closer than
    a few times their error bounds (or not finite)."""
    gap = max(abs(centres[f, 0] - centres[g, 0]), abs(centres[f, 1] - centres[g, 1]))
    if not gap > 8.0 * (err[f] + err[g]):        # (NaN too: a degenerate face)
        redo[f] = True
        redo[g] = True


@entry
def redo_centres(vx, vy, vw, offsets, ring, centres, redo, lo, hi):
    """The flagged centres of faces ``lo:hi`` (and any that rounding left
    undefined) again, in double-double arithmetic."""
    for f in range(lo, hi):
        if redo[f] or not (np.isfinite(centres[f, 0]) and np.isfinite(centres[f, 1])):
            a, b, c = face_triple(offsets, ring, f)
            centres[f, 0], centres[f, 1] = centre_dd(vx, vy, vw, a, b, c)


@kernel
def face_triple(offsets, ring, f):
    """Three vertices spread round face ``f``: its first, a third and two
    thirds of the way round (a triangle's three)."""
    lo = offsets[f]
    m = offsets[f + 1] - lo
    return ring[lo], ring[lo + m // 3], ring[lo + (2 * m) // 3]


@kernel
def centre_dd(vx, vy, vw, a, b, c):
    """The circumcentre (power centre) of ``a, b, c`` in double-double
    arithmetic, rounded to doubles."""
    bx, bxl = two_diff(vx[b], vx[a])
    by, byl = two_diff(vy[b], vy[a])
    cx, cxl = two_diff(vx[c], vx[a])
    cy, cyl = two_diff(vy[c], vy[a])
    wb, wbl = two_diff(vw[b], vw[a])
    wc, wcl = two_diff(vw[c], vw[a])
    # lb = |b - a|^2 - (w_b - w_a), lc alike, d = 2 (bx cy - by cx)
    lb, lbl = dd_sub(*dd_add(*dd_mul(bx, bxl, bx, bxl), *dd_mul(by, byl, by, byl)), wb, wbl)
    lc, lcl = dd_sub(*dd_add(*dd_mul(cx, cxl, cx, cxl), *dd_mul(cy, cyl, cy, cyl)), wc, wcl)
    d, dl = dd_sub(*dd_mul(bx, bxl, cy, cyl), *dd_mul(by, byl, cx, cxl))
    d, dl = 2.0 * d, 2.0 * dl
    ux, uxl = dd_div(*dd_sub(*dd_mul(cy, cyl, lb, lbl), *dd_mul(by, byl, lc, lcl)), d, dl)
    uy, uyl = dd_div(*dd_sub(*dd_mul(bx, bxl, lc, lcl), *dd_mul(cx, cxl, lb, lbl)), d, dl)
    return dd_add(vx[a], 0.0, ux, uxl)[0], dd_add(vy[a], 0.0, uy, uyl)[0]


# double-double arithmetic (a value is hi + lo, |lo| <= ulp(hi) / 2): Dekker, Knuth
@kernel
def two_sum(a, b):
    """``(s, e)``: ``s + e == a + b`` exactly, ``s = fl(a + b)``."""
    s = a + b
    bv = s - a
    return s, (a - (s - bv)) + (b - bv)


@kernel
def two_diff(a, b):
    """``(s, e)``: ``s + e == a - b`` exactly, ``s = fl(a - b)``."""
    return two_sum(a, -b)


@kernel
def split(a):
    """Dekker's split of ``a`` into two halves of 26 bits."""
    c = 134217729.0 * a                  # 2**27 + 1
    hi = c - (c - a)
    return hi, a - hi


@kernel
def two_prod(a, b):
    """``(p, e)``: ``p + e == a * b`` exactly, ``p = fl(a * b)``."""
    p = a * b
    ah, al = split(a)
    bh, bl = split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@kernel
def dd_add(ah, al, bh, bl):
    s, e = two_sum(ah, bh)
    e += al + bl
    hi = s + e
    return hi, e - (hi - s)


@kernel
def dd_sub(ah, al, bh, bl):
    return dd_add(ah, al, -bh, -bl)


@kernel
def dd_mul(ah, al, bh, bl):
    p, e = two_prod(ah, bh)
    e += ah * bl + al * bh
    hi = p + e
    return hi, e - (hi - p)


@kernel
def dd_div(ah, al, bh, bl):
    q1 = ah / bh
    rh, rl = dd_sub(ah, al, *dd_mul(q1, 0.0, bh, bl))
    q2 = rh / bh
    rh, rl = dd_sub(rh, rl, *dd_mul(q2, 0.0, bh, bl))
    q3 = rh / bh
    hi, lo = dd_add(q1, 0.0, q2, 0.0)
    return dd_add(hi, lo, q3, 0.0)


BOTTOM = -2       # labels of the clip box's sides (y = ymin, x = xmax, y = ymax, x = xmin):
RIGHT = -3        # side s is label -2 - s, counter-clockwise from the bottom
TOP = -4
LEFT = -5


@entry
def clip_cells(vx, vy, vw, triangles, offsets, ring, hull, face_of, centres,
               xmin, ymin, xmax, ymax, lo, hi):
    """Each vertex's cell cut to the box ``[xmin, xmax] x [ymin, ymax]``.

    A cell whose face centres all lie in the box is its ring of face centres.
    Any other (one with a centre outside the box, or unbounded) is the box cut
    by the half-plane of each of its ridges in turn, the points nearer to its
    vertex than to the one across (power distance with weights): the
    half-plane is given exactly by the two vertices, so a ridge whose ends lie
    far beyond the box (nearly collinear vertices, whose face centres are
    1e17 away and rounded by more than a cell is wide there) cuts the box where
    it crosses it, not between rounded far points. Where a ridge crosses a side
    of the box, the point is computed from the ridge's two vertices (their
    bisector), the same in both cells; where it meets the next ridge of the
    ring inside the box, the corner is their face centre, the one the
    neighbouring cells use. So the cells form an exact coverage of the box.
    Returns the cells of vertices ``lo:hi`` as ``(offsets, xy)`` (offsets from
    0): counter-clockwise rings, not closed, empty where nothing is left."""
    nv = hi - lo
    faces, across = cell_scratch(offsets, lo, hi)
    ridges = np.empty(faces.shape[0] + 1, np.int64)
    corner = np.empty(faces.shape[0] + 1, np.int64)
    cap = 2 * faces.shape[0] + 32
    ax = np.empty(cap)
    ay = np.empty(cap)
    al = np.empty(cap, np.int64)
    bx = np.empty(cap)
    by = np.empty(cap)
    bl = np.empty(cap, np.int64)
    box = np.array([ymin, xmax, ymax, xmin])             # side s lies on coordinate box[s]
    sites, cell, spare = (vx, vy, vw), (ax, ay, al), (bx, by, bl)
    out_offsets = np.zeros(nv + 1, np.int64)
    out = np.empty((8 * nv + 2 * (offsets[hi] - offsets[lo]) + 16, 2))
    n = 0
    for v in range(lo, hi):
        na = cell_ring(triangles, offsets, ring, hull, face_of, v, faces, across)
        if hull[v]:
            na -= 1                                      # (the -1 for infinity)
        inside = not hull[v]
        lo_x, lo_y, hi_x, hi_y = np.inf, np.inf, -np.inf, -np.inf
        for p in range(na):
            ax[p] = centres[faces[p], 0]
            ay[p] = centres[faces[p], 1]
            inside = inside and xmin <= ax[p] <= xmax and ymin <= ay[p] <= ymax
            lo_x, hi_x = min(lo_x, ax[p]), max(hi_x, ax[p])
            lo_y, hi_y = min(lo_y, ay[p]), max(hi_y, ay[p])
        if not hull[v] and (hi_x < xmin or lo_x > xmax or hi_y < ymin or lo_y > ymax):
            na = 0                                       # a bounded cell beyond one side of the box
        elif not inside and na > 0:
            k = ridge_ring(triangles, offsets, ring, hull[v], v, faces, across, na, ridges, corner)
            na = box_corners(cell, xmin, ymin, xmax, ymax)
            for r in range(k):
                na = cut_ridge(sites, v, cell, spare, na, ridges, corner, k, r, centres, box)
            na = drop_repeats(ax, ay, na)
        if na < 3:
            na = 0
        for p in range(na):
            out[n, 0] = ax[p]
            out[n, 1] = ay[p]
            n += 1
        out_offsets[v - lo + 1] = n
    return out_offsets, out[:n]


@kernel
def ridge_ring(triangles, offsets, ring, on_hull, v, faces, across, na, ridges, corner):
    """Vertex ``v``'s ridges counter-clockwise into ``ridges[:k]`` (the
    vertex across each), and into ``corner[r]`` the face where ridge ``r``
    meets ridge ``r + 1`` (-1 between the last and the first ridges of an
    unbounded cell, which meet only at infinity), from its ring of ``na`` faces
    ``faces`` and ``across`` (:func:`cell_ring`). Returns ``k``."""
    if not on_hull:                                      # face p + 1 between across[p] and across[p + 1]
        for p in range(na):
            ridges[p] = across[p]
            corner[p] = faces[(p + 1) % na]
        return na
    t = ring[offsets[v]]                                 # the first triangle: hull edge v -> a, the ray in
    ridges[0] = triangles[t, (corner_of(triangles, t, v) + 1) % 3]
    for p in range(na):                                  # face p between ridges p and p + 1
        ridges[p + 1] = across[p]
        corner[p] = faces[p]
    corner[na] = -1
    return na + 1


@kernel
def box_corners(cell, xmin, ymin, xmax, ymax):
    """The box's corners counter-clockwise into ``cell`` (see :func:`cut_ridge`),
    each side labelled with the side it lies on; returns 4."""
    ax, ay, al = cell
    ax[0], ay[0], al[0] = xmin, ymin, BOTTOM
    ax[1], ay[1], al[1] = xmax, ymin, RIGHT
    ax[2], ay[2], al[2] = xmax, ymax, TOP
    ax[3], ay[3], al[3] = xmin, ymax, LEFT
    return 4


@kernel
def cut_ridge(sites, v, cell, spare, na, ridges, corner, k, r, centres, box):
    """Cut vertex ``v``'s convex polygon ``cell``, ``(ax, ay, al)``: corners
    ``(ax, ay)[:na]``, side ``p`` from corner ``p`` to ``p + 1`` labelled
    ``al[p]`` (the vertex across the ridge it lies on, or a box side), to the
    half-plane of ridge ``ridges[r]`` (the points no farther from ``v``, power
    distance with weights), in place (one Sutherland-Hodgman step; ``spare``
    is room for another such polygon); returns its new size. A point on the
    ridge is kept. The new side along the ridge is labelled with it."""
    ax, ay, al = cell
    bx, by, bl = spare
    u = ridges[r]
    outside = False
    for p in range(na):
        if power_gap(sites, v, u, ax[p], ay[p]) > 0.0:
            outside = True
            break
    if not outside:
        return na
    nb = 0
    gq = power_gap(sites, v, u, ax[0], ay[0])
    for p in range(na):
        q = p + 1 if p + 1 < na else 0
        gp = gq
        gq = power_gap(sites, v, u, ax[q], ay[q])
        if gp <= 0.0:
            bx[nb] = ax[p]
            by[nb] = ay[p]
            bl[nb] = u if gp == 0.0 and gq > 0.0 else al[p]     # (on the ridge, leaving: along it)
            nb += 1
        if (gp < 0.0 and gq > 0.0) or (gp > 0.0 and gq < 0.0):
            bx[nb], by[nb] = meet(sites, v, u, al[p], ax[p], ay[p], ax[q], ay[q], gp, gq,
                                  ridges, corner, k, r, centres, box)
            bl[nb] = u if gp < 0.0 else al[p]            # leaving: along the ridge; entering: on
            nb += 1
    for p in range(nb):
        ax[p] = bx[p]
        ay[p] = by[p]
        al[p] = bl[p]
    return nb


@kernel
def power_gap(sites, v, u, x, y):
    """Half of (power distance of ``(x, y)`` to ``v``) minus (to ``u``):
    negative on ``v``'s side of their ridge. Computed from the pair in
    increasing order and negated for the other, so both cells decide a point
    alike."""
    vx, vy, vw = sites
    i, j = min(u, v), max(u, v)
    g = ((vx[j] - vx[i]) * (x - 0.5 * (vx[i] + vx[j])) + (vy[j] - vy[i]) * (y - 0.5 * (vy[i] + vy[j]))
         - 0.5 * (vw[i] - vw[j]))
    return g if v == i else -g


@kernel
def meet(sites, v, u, w, px, py, qx, qy, gp, gq, ridges, corner, k, r, centres, box):
    """Where ridge ``u`` (``ridges[r]``) crosses the side ``p -> q`` of
    ``v``'s polygon, which lies on ``w`` (a vertex across a ridge or a box
    side, :func:`cut_ridge`); ``gp``, ``gq``: the ends' :func:`power_gap`, of
    opposite signs. On a box side: from the bisector of ``v`` and ``u``
    (:func:`crossing`). On the ridge before or after ``u`` in the ring: their
    face centre, if it lies in the box. Else interpolated between ``p`` and ``q``."""
    if w < 0:
        s = -2 - w
        vertical = s % 2 == 0                            # bottom and top: the line y = box[s]
        other = crossing(sites, v, u, px, py, qx, qy, gp, gq, vertical, box[s])
        return (other, box[s]) if vertical else (box[s], other)
    f = corner[r] if ridges[(r + 1) % k] == w else -1
    if f < 0 and ridges[(r - 1) % k] == w:               # (two ridges meet at a face and at infinity)
        f = corner[(r - 1) % k]
    if f >= 0:
        cx = centres[f, 0]
        cy = centres[f, 1]
        if box[3] <= cx <= box[1] and box[0] <= cy <= box[2]:
            return cx, cy
    t = gp / (gp - gq)
    return px + t * (qx - px), py + t * (qy - py)


@kernel
def drop_repeats(ax, ay, na):
    """Remove corners equal to the one before them (cyclically) from
    ``(ax, ay)[:na]``; returns the new size."""
    m = 0
    for p in range(na):
        if m > 0 and ax[p] == ax[m - 1] and ay[p] == ay[m - 1]:
            continue
        ax[m] = ax[p]
        ay[m] = ay[p]
        m += 1
    while m > 1 and ax[m - 1] == ax[0] and ay[m - 1] == ay[0]:
        m -= 1
    return m


@kernel
def crossing(sites, v, u, px, py, qx, qy, gp, gq, vertical, bound):
    """The other coordinate where ridge ``u`` of ``v``'s cell meets the
    box side ``p -> q`` on the line ``x = bound`` (``y`` when ``vertical``),
    kept between ``p`` and ``q``: from the bisector of ``v`` and ``u`` (power
    bisector with weights) through their midpoint, with the pair in increasing
    order, so both cells get the same point; interpolated by the ends'
    :func:`power_gap` ``gp``, ``gq`` where the ridge runs along the line (a
    rounding error's crossing)."""
    vx, vy, vw = sites
    i, j = min(u, v), max(u, v)
    nx = vx[j] - vx[i]
    ny = vy[j] - vy[i]
    mx = 0.5 * (vx[i] + vx[j])
    my = 0.5 * (vy[i] + vy[j])
    rhs = 0.5 * (vw[i] - vw[j])          # n . (x - m) = (w_i - w_j) / 2
    if vertical and nx != 0.0:
        value = mx + (rhs - ny * (bound - my)) / nx
    elif not vertical and ny != 0.0:
        value = my + (rhs - nx * (bound - mx)) / ny
    else:
        value = np.nan
    if not np.isfinite(value):
        t = gp / (gp - gq)
        value = px + t * (qx - px) if vertical else py + t * (qy - py)
    lo_, hi_ = (min(px, qx), max(px, qx)) if vertical else (min(py, qy), max(py, qy))
    return min(max(value, lo_), hi_)
