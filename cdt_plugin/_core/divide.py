"""Divide-and-conquer Delaunay triangulation (Guibas and Stolfi 1985).

The points, sorted lexicographically, are split in halves by vertical cuts; each
half is triangulated recursively and the two are merged by walking up the seam
from their lower common tangent, deleting the edges of either half whose
circumdisks the seam's new triangles violate. It needs no point location and no
insertion order, which makes it the fastest route for large inputs (it is also
Triangle's default).

The in-circle decisions use the same exact, symbolically perturbed lifted test
as the incremental route (``kernel.lifted_test``), so both give the same
triangles on every input, cocircular or not.

Edges live in a quad-edge store (Guibas and Stolfi): quad-edge ``q`` owns the
four directed edges ``4q .. 4q+3`` (``4q`` and ``4q+2`` are the two primal
directions, the odd ones their duals); ``onext[e]`` is the next edge
counter-clockwise around the origin of ``e``; ``org[e]`` the origin vertex.
The finished subdivision is converted to the half-edge triangle store of
:mod:`mesh`, ghost triangles included.
"""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel
from .kernel import lifted_test
from .predicates import orient2d
from .mesh import IDX
from .prefetch import prefetch

QUAD_SLACK = 8   # quad-edges beyond 3 per point that a subdivision may take


@kernel("int64(int64)", forceinline=True)
def rot(e):
    return (e & ~3) | ((e + 1) & 3)


@kernel(forceinline=True)
def sym(e):
    return e ^ 2


@kernel(forceinline=True)
def rot_inv(e):
    return (e & ~3) | ((e + 3) & 3)


@kernel(forceinline=True)
def lnext(onext, e):
    """The next edge counter-clockwise around the left face of ``e``."""
    return rot(onext[rot_inv(e)])


@kernel("int64(int32[::1], int64)", forceinline=True)
def oprev(onext, e):
    """The next edge clockwise around the origin of ``e``."""
    return rot(onext[rot(e)])


@kernel("void(int32[::1], int64, int64)", forceinline=True)
def splice(onext, a, b):
    """Guibas and Stolfi's splice: joins or separates the origin rings of
    ``a`` and ``b`` (and, dually, their left faces)."""
    alpha = rot(onext[a])
    beta = rot(onext[b])
    t = onext[a]
    onext[a] = onext[b]
    onext[b] = t
    t = onext[alpha]
    onext[alpha] = onext[beta]
    onext[beta] = t


@kernel(forceinline=True)
def make_edge(onext, org, free, nfree, top, a, b):
    """A new isolated edge ``a -> b``; returns ``(edge, nfree, top)``."""
    if nfree > 0:
        nfree -= 1
        q = free[nfree]
    else:
        q = top
        top += 1
    e = 4 * q
    onext[e] = e
    onext[e + 1] = e + 3
    onext[e + 2] = e + 2
    onext[e + 3] = e + 1
    org[e] = a
    org[e + 2] = b
    return e, nfree, top


@kernel("int64(int32[::1], int32[::1], int32[::1], int64, int64)", forceinline=True)
def delete_edge(onext, org, free, nfree, e):
    """Disconnect ``e`` from the subdivision and recycle its quad-edge."""
    splice(onext, e, oprev(onext, e))
    s = e ^ 2
    splice(onext, s, oprev(onext, s))
    org[e & ~3] = -1               # marks a free quad-edge
    free[nfree] = e >> 2
    return nfree + 1


@kernel(forceinline=True)
def ccw(x, y, a, b, c):
    # orient2d itself, not kernel.orient: through orient (declared int64 indices) the
    # merge loop's int32 indices were widened first, and delaunay 1e6 took ~4% longer
    return orient2d(x[a], y[a], x[b], y[b], x[c], y[c]) > 0


@kernel(forceinline=True)
def in_circle(x, y, w, a, b, c, d):
    """Whether ``d`` lies in the (perturbed) circumdisk of counter-clockwise
    ``(a, b, c)``; a repeated vertex is never inside."""
    if d == a or d == b or d == c:
        return False
    return lifted_test(x, y, w, False, a, b, c, d) > 0


@kernel(_nrt=False)
def select(a, b, lo, hi, k):
    """Reorder slots ``lo..hi-1`` of ``a`` (and ``b`` along with it) so that the
    values before slot ``k`` are smaller than those from ``k`` on (quickselect
    with median-of-three pivots; the values are distinct). Only which values
    end up on each side matters to the subdivision, not their order there.

    The partition is Lomuto's without branches: every slot is swapped, and
    the boundary moves by the comparison. Hoare's, with a branch on each
    comparison that the processor mispredicted half the time, made this
    the largest part of divide and conquer after the merges (a quarter of
    its time); this one takes about half as long."""
    hi -= 1
    while hi - lo > 8:
        mid = (lo + hi) // 2
        # the median of a[lo], a[mid] and a[hi] to hi: the pivot
        if a[mid] < a[lo]:
            swap_slots(a, b, mid, lo)
        if a[hi] < a[lo]:
            swap_slots(a, b, hi, lo)
        if a[mid] < a[hi]:
            swap_slots(a, b, mid, hi)
        pivot = a[hi]
        j = lo
        for i in range(lo, hi):          # a[lo:j] < pivot <= a[j:i]
            u = a[i]
            v = b[i]
            a[i] = a[j]
            b[i] = b[j]
            a[j] = u
            b[j] = v
            j += u < pivot
        swap_slots(a, b, hi, j)
        if j > k:
            hi = j - 1
        elif j < k:
            lo = j + 1
        else:
            return
    # at most nine slots left: sort them
    for i in range(lo + 1, hi + 1):
        j = i
        while j > lo and a[j] < a[j - 1]:
            swap_slots(a, b, j, j - 1)
            j -= 1


@kernel(forceinline=True)
def swap_slots(a, b, i, j):
    """Swap slots ``i`` and ``j`` of ``a`` and of ``b``."""
    a[i], a[j] = a[j], a[i]
    b[i], b[j] = b[j], b[i]


@kernel(forceinline=True)
def vertex_less(x, y, a, b, axis):
    if axis == 0:
        return x[a] < x[b] or (x[a] == x[b] and y[a] < y[b])
    return y[a] < y[b] or (y[a] == y[b] and x[a] > x[b])


@kernel(_nrt=False)
def hull_extreme(onext, org, x, y, f, axis, largest):
    """The hull vertex first (``largest``: last) in the frame of ``axis``,
    found by walking the hull from ``f``'s origin: given and returned as the
    edge out of a hull vertex with the outer face on its left (clockwise along
    the hull). Along a convex hull the order of a frame rises once and falls
    once (it is a perturbed linear function), so the walk goes one way while
    the next vertex comes first, and stops at the extreme, usually well
    before it has been round the whole hull."""
    g = lnext(onext, f)                       # the next hull vertex clockwise
    clockwise = vertex_less(x, y, org[g], org[f], axis) != largest
    if not clockwise:
        g = onext[f] ^ 2                      # the next one counter-clockwise (lprev)
    while vertex_less(x, y, org[g], org[f], axis) != largest:
        f = g
        g = lnext(onext, f) if clockwise else onext[f] ^ 2
    return f


@kernel(_nrt=False)
def in_frame(onext, org, x, y, ldo, rdo, axis):
    """``(ldo, rdo)`` of a triangulation (the counter-clockwise hull edge out of
    its first vertex, the clockwise one out of its last) moved to the frame of
    ``axis`` from the other frame."""
    first = hull_extreme(onext, org, x, y, oprev(onext, ldo), axis, np.bool_(False))
    return onext[first], hull_extreme(onext, org, x, y, rdo, axis, np.bool_(True))


@kernel(_nrt=False, apart=True)
def guibas_stolfi(points, u, r, quads, work, lo, hi, axis, base):
    """Delaunay triangulation of the distinct vertices ``u[lo:hi]`` (at least
    two; ids in lexicographic order of their ``points``, ``(x, y, w)``) in the
    quad-edge arrays ``quads``, ``(onext, org, free)`` (:func:`quad_store`),
    with the ``work`` stacks ``(stack, results)`` (:func:`work_stacks`), by divide and conquer with
    cuts alternately vertical and horizontal (Dwyer's variant, which keeps the
    subproblems square), the first cut along ``axis`` (0: vertical). ``r[k]``
    ranks vertex ``u[k]`` in the order of the horizontal cuts (only their order
    within ``lo:hi`` matters), reordered along with ``u``. Quad-edges are taken
    from ``base`` up, freed ones recycled through the stack ``free``. Returns
    ``(ldo, rdo, the quad-edge after the last one taken, number left on the
    free stack)``: ``ldo`` the counter-clockwise hull edge out of the leftmost
    vertex, ``rdo`` the clockwise one out of the rightmost. Every triangulation
    made on the way keeps these two (as Triangle does): a horizontal cut walks
    from them to its halves' bottom and top vertices and back, where a walk
    round each half's whole hull was 5-10% of the time on points along
    curves, whose subproblems have most of their points on their hulls."""
    x, y = points[0], points[1]
    onext, org, free = quads
    stack, results = work
    nfree = np.int64(0)
    top = np.int64(base)
    rp = 0
    stack[0] = lo
    stack[1] = hi
    stack[2] = axis
    stack[3] = 0
    sp = 1
    while sp > 0:
        sp -= 1
        lo = stack[4 * sp]
        hi = stack[4 * sp + 1]
        axis = stack[4 * sp + 2]
        state = stack[4 * sp + 3]
        size = hi - lo
        if size <= 3:                          # (sorted in the frame of vertical cuts)
            select(u, r, lo, hi, lo)
        if size == 2:
            a, nfree, top = make_edge(onext, org, free, nfree, top, u[lo], u[lo + 1])
            results[2 * rp] = a
            results[2 * rp + 1] = a ^ 2
            rp += 1
        elif size == 3:
            s1 = u[lo]
            s2 = u[lo + 1]
            s3 = u[lo + 2]
            a, nfree, top = make_edge(onext, org, free, nfree, top, s1, s2)
            b, nfree, top = make_edge(onext, org, free, nfree, top, s2, s3)
            splice(onext, a ^ 2, b)
            if ccw(x, y, s1, s2, s3):
                c, nfree, top = connect(onext, org, free, nfree, top, b, a)
                results[2 * rp] = a
                results[2 * rp + 1] = b ^ 2
            elif ccw(x, y, s1, s3, s2):
                c, nfree, top = connect(onext, org, free, nfree, top, b, a)
                results[2 * rp] = c ^ 2
                results[2 * rp + 1] = c
            else:                              # collinear: a chain of two edges
                results[2 * rp] = a
                results[2 * rp + 1] = b ^ 2
            rp += 1
        elif state == 0:
            mid = (lo + hi) // 2
            if axis == 0:
                select(u, r, lo, hi, mid)
            else:
                select(r, u, lo, hi, mid)
            stack[4 * sp + 3] = 1             # revisit to merge
            stack[4 * sp + 4] = mid
            stack[4 * sp + 5] = hi
            stack[4 * sp + 6] = 1 - axis
            stack[4 * sp + 7] = 0
            stack[4 * sp + 8] = lo
            stack[4 * sp + 9] = mid
            stack[4 * sp + 10] = 1 - axis
            stack[4 * sp + 11] = 0
            sp += 3
        else:
            rp -= 2
            ldo = results[2 * rp]
            ldi = results[2 * rp + 1]
            rdi = results[2 * rp + 2]
            rdo = results[2 * rp + 3]
            if axis == 1:     # a horizontal cut: its halves' ends, bottom and top
                ldo, ldi = in_frame(onext, org, x, y, ldo, ldi, axis)
                rdi, rdo = in_frame(onext, org, x, y, rdi, rdo, axis)
            ldo, rdo, nfree, top = merge(points, quads, nfree, top, ldo, ldi, rdi, rdo)
            if axis == 1:     # back to the left and right ends
                ldo, rdo = in_frame(onext, org, x, y, ldo, rdo, np.int64(0))
            results[2 * rp] = ldo
            results[2 * rp + 1] = rdo
            rp += 1
    return results[0], results[1], top, nfree


@kernel(forceinline=True)
def connect(onext, org, free, nfree, top, a, b):
    """A new edge from the destination of ``a`` to the origin of ``b``, with
    the left faces of ``a`` and ``b`` on its left."""
    e, nfree, top = make_edge(onext, org, free, nfree, top, org[a ^ 2], org[b])
    splice(onext, e, lnext(onext, a))
    splice(onext, e ^ 2, b)
    return e, nfree, top


@kernel(_nrt=False)
def merge(points, quads, nfree, top, ldo, ldi, rdi, rdo):
    """Merge two adjacent triangulations along their seam (Guibas and Stolfi;
    ``points`` and ``quads`` as in :func:`guibas_stolfi`)."""
    x, y, w = points
    onext, org, free = quads
    # the lower common tangent
    while True:
        if ccw(x, y, org[rdi], org[ldi], org[ldi ^ 2]):          # leftof(org rdi, ldi)
            ldi = lnext(onext, ldi)
        elif ccw(x, y, org[ldi], org[rdi ^ 2], org[rdi]):        # rightof(org ldi, rdi)
            rdi = onext[rdi ^ 2]                                  # rprev
        else:
            break
    basel, nfree, top = connect(onext, org, free, nfree, top, rdi ^ 2, ldi)
    if org[ldi] == org[ldo]:
        ldo = basel ^ 2
    if org[rdi] == org[rdo]:
        rdo = basel
    while True:
        bo = org[basel]
        bd = org[basel ^ 2]
        lcand = onext[basel ^ 2]
        lvalid = ccw(x, y, org[lcand ^ 2], bd, bo)
        if lvalid:
            while True:
                nxt = onext[lcand]
                if not in_circle(x, y, w, bd, bo, org[lcand ^ 2], org[nxt ^ 2]):
                    break
                nfree = delete_edge(onext, org, free, nfree, lcand)
                lcand = nxt
        rcand = oprev(onext, basel)
        rvalid = ccw(x, y, org[rcand ^ 2], bd, bo)
        if rvalid:
            while True:
                nxt = oprev(onext, rcand)
                if not in_circle(x, y, w, bd, bo, org[rcand ^ 2], org[nxt ^ 2]):
                    break
                nfree = delete_edge(onext, org, free, nfree, rcand)
                rcand = nxt
        if not lvalid and not rvalid:
            break
        if not lvalid or (rvalid and in_circle(x, y, w, org[lcand ^ 2], org[lcand],
                                               org[rcand], org[rcand ^ 2])):
            basel, nfree, top = connect(onext, org, free, nfree, top, rcand, basel ^ 2)
        else:
            basel, nfree, top = connect(onext, org, free, nfree, top, basel ^ 2, lcand ^ 2)
    return ldo, rdo, nfree, top


#: How many quad-edges ahead :func:`number_faces` asks for the slots it will read
PREFETCH_QUADS = 64


@kernel(_nrt=False)
def number_faces(onext, org, nquad, ldo):
    """First pass of the conversion to the half-edge store: the half-edge of
    every primal directed edge ``e`` goes to ``org[e + 1]``, the slot of its
    dual, which divide and conquer leaves at -1. Triangles are numbered in the
    order of their first quad-edge, then one ghost per hull edge along the hull.
    Returns ``(triangles and ghosts, the first ghost)``. The next edge of a
    face is a slot anywhere in ``onext``: those of the quad-edge
    :data:`PREFETCH_QUADS` on are asked for ahead (at 100,000 points the pass
    took 3.6 ms instead of 6.3)."""
    outer = ldo ^ 2                 # the outer face lies left of the reversed hull edges
    e = outer
    while True:
        org[e + 1] = -2
        e = lnext(onext, e)
        if e == outer:
            break
    ntri = 0
    for q in range(nquad):
        ahead = q + PREFETCH_QUADS
        if ahead < nquad and org[4 * ahead] >= 0:
            for a in (4 * ahead, 4 * ahead + 2):
                f = lnext(onext, a)
                prefetch(onext, rot_inv(f))
                prefetch(org, f + 1)
        if org[4 * q] < 0:
            continue
        for e in (4 * q, 4 * q + 2):
            if org[e + 1] != -1:
                continue
            f = lnext(onext, e)
            g = lnext(onext, f)
            org[e + 1] = 3 * ntri
            org[f + 1] = 3 * ntri + 1
            org[g + 1] = 3 * ntri + 2
            ntri += 1
    first = ntri
    e = outer
    while True:
        org[e + 1] = 3 * ntri
        ntri += 1
        e = lnext(onext, e)
        if e == outer:
            break
    return ntri, first


@kernel(_nrt=False)
def write_store(org, nquad, ntri, first, inf, tri, twin):
    """Second pass: the triangles and their twins from the half-edges that
    :func:`number_faces` put in ``org`` (``onext`` is not read, so ``tri`` and
    ``twin`` may take its memory)."""
    for q in range(nquad):
        if org[4 * q] < 0:
            continue
        for e in (4 * q, 4 * q + 2):
            h = org[e + 1]
            tri[h] = org[e]
            twin[h] = org[(e ^ 2) + 1]
    # ghost g = (v, u, inf) on hull edge v -> u; u begins the next hull edge
    ghosts = ntri - first
    for k in range(ghosts):
        g = first + k
        h = first + (k + 1) % ghosts
        tri[3 * g + 1] = tri[3 * h]
        tri[3 * g + 2] = inf
        twin[3 * g + 1] = 3 * h + 2
        twin[3 * h + 2] = 3 * g + 1


@kernel
def mark_duplicates(x, y, m, dup):
    """Distinct vertices of lexicographically sorted ``0..m-1``; ``dup[k]`` is set to
    the first vertex equal to ``k`` when ``k`` repeats it."""
    u = np.empty(m, IDX)
    nu = 0
    for k in range(m):
        if nu > 0 and x[k] == x[u[nu - 1]] and y[k] == y[u[nu - 1]]:
            dup[k] = u[nu - 1]
        else:
            u[nu] = k
            nu += 1
    return u[:nu]


@kernel
def build_divide_sorted(x, y, w, m, inf, dup, cap, with_cons, horizontal):
    """Delaunay triangulation of the mesh vertices ``0..m-1`` (lexicographically
    sorted, not all collinear) by divide and conquer, in the half-edge store with
    room for at least ``cap`` triangles: ``(tri, twin, cons, ntri)``.
    ``horizontal``: the vertices in the order of horizontal cuts, by (y, -x)."""
    u, r = cut_ranks(x, y, m, dup, horizontal)
    return build_subdivision(x, y, w, u, r, inf, cap, with_cons)


@entry
def cut_ranks(x, y, m, dup, horizontal):
    """Duplicates marked, and the vertices and ranks :func:`guibas_stolfi` cuts:
    ``(u, r)``, the distinct vertices and each one's rank in the order of
    horizontal cuts (a repeated point is adjacent to its first copy there too, so
    skipping it keeps the ranks)."""
    u = mark_duplicates(x, y, m, dup)
    nu = u.shape[0]
    slot = np.empty(m, IDX)
    for k in range(nu):
        slot[u[k]] = k
    r = np.empty(nu, IDX)
    rank = 0
    for k in horizontal:
        if dup[k] < 0:
            r[slot[k]] = rank
            rank += 1
    return u, r


@entry
def build_subdivision(x, y, w, u, r, inf, cap, with_cons):
    """The subdivision of the distinct vertices ``u`` (ranks ``r``, see
    :func:`cut_ranks`) in the half-edge store (:func:`store_subdivision`)."""
    nu = u.shape[0]
    onext, org, free = quad_store(nu)
    stack, results = work_stacks(nu)
    first = np.int64(0)         # (typed, not literal: see jit.py)
    ldo, _, used, _ = guibas_stolfi((x, y, w), u, r, (onext, org, free), (stack, results), first,
                                    nu, first, first)
    return store_subdivision(onext, org, used, ldo, inf, cap, with_cons)


@entry
def quad_store(n):
    """Empty quad-edge arrays ``(onext, org, free)`` for the subdivision of
    ``n`` points, or of two halves of them side by side (:func:`right_base`);
    a free quad-edge has ``org`` -1, and so has every dual edge."""
    nquad = 3 * n + 2 * QUAD_SLACK
    return np.empty(4 * nquad, IDX), np.full(4 * nquad, -1, IDX), np.empty(nquad, IDX)


@kernel
def work_stacks(n):
    """The work stacks of :func:`guibas_stolfi` for ``n`` points."""
    depth = 8 + 2 * int(np.log2(n + 1))
    return np.empty(4 * 3 * depth, np.int64), np.empty(2 * depth, np.int64)


@kernel(apart=True)
def store_subdivision(onext, org, used, ldo, inf, cap, with_cons):
    """The subdivision in the half-edge store with room for at least ``cap``
    triangles: ``(tri, twin, cons, ntri)``. Where they fit, ``tri`` and
    ``twin`` take over the memory of ``onext``, which the second pass no longer
    reads: converting then needs no memory of its own (a point set with few
    repeated points and no room asked for beyond its triangles)."""
    ntri, first = number_faces(onext, org, used, ldo)
    room = max(cap, ntri)
    if 6 * room <= onext.shape[0]:
        tri = onext[:3 * room]
        twin = onext[3 * room:6 * room]
    else:
        tri = np.empty(3 * room, IDX)
        twin = np.empty(3 * room, IDX)
    write_store(org, used, ntri, first, inf, tri, twin)
    for e in range(3 * ntri, 3 * room):
        tri[e] = -1
        twin[e] = -1
    cons = np.zeros(3 * room if with_cons else 0, IDX)
    return tri, twin, cons, ntri


# ---- the same subdivision from two threads ----------------------------------------
# The first cut's halves are built apart (build_half) and joined (join_halves) with the
# quad-edges renumbered as one thread would have numbered them, so the triangles come
# out in the very same order: any number of threads gives the same arrays.

@entry
def split_halves(x, y, m, dup):
    """Duplicates marked, and the first (vertical) cut of the distinct vertices
    made as :func:`guibas_stolfi` makes it: ``(u, mid)``, the halves
    ``u[:mid]`` and ``u[mid:]`` (their ranks are set by the caller)."""
    u = mark_duplicates(x, y, m, dup)
    mid = u.shape[0] // 2
    select(u, np.empty(u.shape[0], IDX), 0, u.shape[0], mid)
    return u, mid


@entry
def right_base(mid):
    """The first quad-edge of the right half when the left one has ``mid``
    points: the left half takes fewer."""
    return 3 * mid + QUAD_SLACK


@entry
def build_half(points, u, r, lo, hi, quads, base):
    """One half ``u[lo:hi]`` of the first cut, triangulated in the shared
    quad-edge arrays from quad-edge ``base`` on (0 for the left half,
    :func:`right_base` for the right one), with its own free stack (``quads``
    is ``(onext, org, free)``). Returns ``(nfree, top, ldo, rdo)`` (see
    :func:`guibas_stolfi`)."""
    ldo, rdo, top, nfree = guibas_stolfi(points, u, r, quads, work_stacks(hi - lo), lo, hi,
                                         np.int64(1), base)
    return nfree, top, ldo, rdo


@kernel(forceinline=True)
def moved_quad(free, nfree, top, i):
    """The quad-edge that one thread gives the right half's ``i``-th: the left
    half's freed ones first, last freed first, then new ones after ``top``."""
    return free[nfree - 1 - i] if i < nfree else top + i - nfree


@entry
def join_halves(points, quads, base, left, right, inf, cap, with_cons):
    """Move the right half down to the quad-edges one thread gives it (after the
    left half, one thread's right half takes the left half's freed quad-edges,
    last freed first, then new ones; its own freed ones stack on top), merge
    the halves and store the result (see :func:`store_subdivision`). The free
    stacks are ``free[:base]`` and ``free[base:]``; ``left`` and ``right`` are
    what :func:`build_half` returned for each half, ``(nfree, top, ldo, ldi)``
    and ``(r_nfree, r_top, rdi, rdo)``: the halves' hull edges at their ends."""
    onext, org, free = quads
    nfree, top, ldo, ldi = left
    r_nfree, r_top, rdi, rdo = right
    count = r_top - base
    taken = min(nfree, count)
    # in place, in order: quad-edge base + i goes to moved(i) <= base + i, never
    # onto one still to move (the left half's free stack is read, not changed)
    for i in range(count):
        q = base + i
        t = moved_quad(free, nfree, top, i)
        for j in range(4):
            e = onext[4 * q + j]
            onext[4 * t + j] = 4 * moved_quad(free, nfree, top, (e >> 2) - base) + (e & 3)
            org[4 * t + j] = org[4 * q + j]
    rdi = 4 * moved_quad(free, nfree, top, (rdi >> 2) - base) + (rdi & 3)
    rdo = 4 * moved_quad(free, nfree, top, (rdo >> 2) - base) + (rdo & 3)
    # the right half's free stack, renumbered, then moved onto what is left of the left's
    for i in range(r_nfree):
        free[base + i] = moved_quad(free, nfree, top, free[base + i] - base)
    nfree -= taken
    for i in range(r_nfree):
        free[nfree + i] = free[base + i]
    nfree += r_nfree
    top += count - taken
    ldo, rdo, nfree, top = merge(points, (onext, org, free), nfree, top, ldo, ldi, rdi, rdo)
    return store_subdivision(onext, org, top, ldo, inf, cap, with_cons)
