"""The flip algorithm (Sec. 2.5): flip edges that are not locally Delaunay until
none is left. Used after the lexicographic triangulation and after vertices move.
"""
from __future__ import annotations

import numpy as np

from .arrays import copy_rows
from .borrow import unowned
from .jit import entry, kernel
from .kernel import edge_is_illegal
from .mesh import DEAD, flip, prv


@entry
def flip_to_delaunay(tri, twin, cons, x, y, w, weighted, inf, ntri, max_flips=-1):
    """Run the flip algorithm with an edge stack over every edge of the
    triangulation; edges on segments (``cons``) are never flipped, which makes
    it the modified flip algorithm of Sec. 2.10.3. Returns the number of flips
    (Prop. 2.5 bounds it by O(n^2)), or -1 when ``max_flips`` (if >= 0) is
    exceeded."""
    m = 3 * ntri
    stack = np.empty(m + 16, np.int64)
    sp = np.int64(0)
    for e in range(m):
        if tri[3 * (e // 3)] == DEAD:
            continue
        if e < twin[e]:
            stack[sp] = e
            sp += 1
    return flip_from_stack((tri, twin, cons, x, y, inf), (w, weighted), stack, sp, np.int64(max_flips))


@kernel
def flip_from_stack(mesh, weights, stack, sp, max_flips):
    """The flip loop: pop an edge, flip it if it is not locally Delaunay (and not
    a segment), push the four outer edges of its quadrilateral. ``mesh`` is
    ``(tri, twin, cons, x, y, inf)``, ``weights`` ``(w, weighted)`` (see :mod:`.mesh`).

    No "queued" flags: a flip rewrites the half-edge slots of two triangles, so
    a flag per slot would go stale. Pushing duplicates is harmless (each pop
    re-tests whatever edge sits in that slot now) and keeps the invariant that
    every edge not on the stack is locally Delaunay.
    """
    tri, twin, cons, x, y, inf = mesh
    w, weighted = weights
    # (views that own nothing: the calls in the loop pass them without reference counting)
    tri, twin, cons, x, y, w = unowned(tri), unowned(twin), unowned(cons), unowned(x), unowned(y), unowned(w)
    flips = 0
    while sp > 0:
        sp -= 1
        e = stack[sp]
        f = twin[e]
        if cons.shape[0] > 0 and cons[e] != 0:
            continue
        a = tri[e]
        b = tri[f]
        p = tri[prv(e)]
        d = tri[prv(f)]
        if not edge_is_illegal(x, y, w, weighted, inf, a, b, p, d):
            continue
        if flips == max_flips:
            return -1
        flip(tri, twin, cons, e)
        flips += 1
        if sp + 4 > stack.shape[0]:
            bigger = np.empty(2 * stack.shape[0] + 8, np.int64)
            copy_rows(bigger, stack, sp)
            stack = bigger
        sp = push_outer_edges(stack, sp, e, f)
    return flips


@kernel(inline="always")
def push_outer_edges(stack, sp, e, f):
    """After ``flip(e)`` (``f`` its old twin): push the four outer edges of the
    quadrilateral (the stack must have room). Returns the new stack size."""
    t1 = 3 * (e // 3)
    t2 = 3 * (f // 3)
    stack[sp] = t1
    stack[sp + 1] = t1 + 1
    stack[sp + 2] = t2 + 1
    stack[sp + 3] = t2 + 2
    return sp + 4
