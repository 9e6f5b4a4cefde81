"""Which triangles of a constrained triangulation are inside the domain.

A flood fill over the triangles that stops at segments (and counts them):
starting outside the convex hull at depth 0, crossing a segment adds one
(DESIGN.md, Regions). The default keeps odd depths (a loop inside a loop is a
hole, an island inside it is solid again, whatever the windings). Triangle's
convention instead keeps everything not reachable from outside and eats from
hole seed points; region seed points paint their flood region.
"""
from __future__ import annotations

import numpy as np

from .certify import locate_in_arrays
from .jit import kernel
from .mesh import DEAD, is_ghost


NO_POLYGON = -1
POLYGON_CONFLICT = -2


@kernel
def segment_rings(first, seg_ring):
    """The rings that run along each segment, as lists per segment id ``sid``
    (1-based): ``rings[start[sid]:start[sid + 1]]``. ``first[i]`` is the
    segment that input segment ``i`` was merged into (-1: dropped), ``seg_ring``
    its ring (-1 free; empty: no rings)."""
    m = first.shape[0]
    start = np.zeros(m + 2, np.int64)
    if seg_ring.shape[0] == 0:
        return start, np.empty(0, np.int64)
    for i in range(m):
        if first[i] >= 0 and seg_ring[i] >= 0:
            start[first[i] + 2] += 1
    for s in range(2, m + 2):
        start[s] += start[s - 1]
    rings = np.empty(start[m + 1], np.int64)
    fill = start.copy()
    for i in range(m):
        if first[i] >= 0 and seg_ring[i] >= 0:
            rings[fill[first[i] + 1]] = seg_ring[i]
            fill[first[i] + 1] += 1
    return start, rings


@kernel
def polygon_across(label, rings, a, b, ring_polygon):
    """The polygon on the far side of a segment along which run the rings
    ``rings[a:b]``, seen from a side in polygon ``label`` (NO_POLYGON: in
    none). Crossing a ring of the polygon one is in leaves it (into the polygon
    sharing that edge, if any); crossing from outside enters the ring's
    polygon; free segments (no ring) change nothing. POLYGON_CONFLICT when the
    rings cannot bound disjoint polygons there: two polygons entered at once
    (the same ring twice, overlapping polygons), or a ring of another polygon
    crossed inside one."""
    if a == b:
        return label
    mine = -1
    for k in range(a, b):
        if ring_polygon[rings[k]] == label:
            mine = k
            break
    if label != NO_POLYGON and mine < 0:
        return POLYGON_CONFLICT
    left = b - a - (1 if mine >= 0 else 0)
    if left == 0:
        return NO_POLYGON
    if left > 1:
        return POLYGON_CONFLICT
    other = a if a != mine else a + 1       # the one ring that is not ours
    return ring_polygon[rings[other]]


@kernel
def segment_depths(tri, twin, cons, ntri, inf, mult, seg_start, seg_rings, ring_polygon):
    """Depth of every triangle (ghosts 0): the fewest segments crossed to reach
    it from outside the hull, the segment id crossed to enter its component
    (``entry``, 0 at depth 0) and the polygon it lies in (``label``, by
    :func:`polygon_across` from the side it was reached from; ``seg_start`` /
    ``seg_rings`` as :func:`segment_rings` makes them). ``mult[sid]`` is how
    many input segments lie on segment ``sid`` (repeated segments are merged
    into one) and crossing it adds that many, so a ring given twice encloses
    nothing under the parity rule. Levels are flooded in increasing depth."""
    depth = np.full(ntri, -1, np.int64)
    entry = np.zeros(ntri, np.int64)
    label = np.full(ntri, NO_POLYGON, np.int64)
    cur = np.empty(ntri, np.int64)
    ncons = 1                                    # each constrained half-edge waits once at most
    for e in range(3 * ntri):
        if cons[e] != 0:
            ncons += 1
    pend = np.empty(ncons, np.int64)             # triangles behind a segment
    pend_depth = np.empty(ncons, np.int64)
    pend_sid = np.empty(ncons, np.int64)
    pend_label = np.empty(ncons, np.int64)
    npend = 0
    nc = 0
    for t in range(ntri):
        if tri[3 * t] != DEAD and is_ghost(tri, t, inf):
            depth[t] = 0
            cur[nc] = t
            nc += 1
    level = 0
    while True:
        i = 0
        while i < nc:            # flood this level; `cur` grows as it goes
            t = cur[i]
            i += 1
            for k in range(3):
                e = 3 * t + k
                m = twin[e] // 3
                if depth[m] >= 0:
                    continue
                if cons[e] == 0:
                    depth[m] = level
                    entry[m] = entry[t]
                    label[m] = label[t]
                    cur[nc] = m
                    nc += 1
                else:
                    pend[npend] = m
                    pend_depth[npend] = level + mult[cons[e]]
                    pend_sid[npend] = cons[e]
                    pend_label[npend] = label[t]
                    npend += 1
        level = -1               # the next level: the shallowest waiting triangle
        for j in range(npend):
            if depth[pend[j]] < 0 and (level < 0 or pend_depth[j] < level):
                level = pend_depth[j]
        if level < 0:
            return depth, entry, label
        nc = 0
        keep = 0
        for j in range(npend):
            m = pend[j]
            if depth[m] >= 0:
                continue
            if pend_depth[j] == level:
                depth[m] = level
                entry[m] = pend_sid[j]
                sid = pend_sid[j]
                across = polygon_across(pend_label[j], seg_rings, seg_start[sid],
                                        seg_start[sid + 1], ring_polygon)
                # (a conflict is reported by the caller's check of every segment)
                label[m] = across if across != POLYGON_CONFLICT else NO_POLYGON
                cur[nc] = m
                nc += 1
            else:
                pend[keep] = m
                pend_depth[keep] = pend_depth[j]
                pend_sid[keep] = pend_sid[j]
                pend_label[keep] = pend_label[j]
                keep += 1
        npend = keep


@kernel
def flood(neighbors, cflag, start, label, value):
    """Paint ``label = value`` over the triangles reachable from ``start``
    without crossing a segment (``cflag[t, j] != 0``: the edge opposite vertex
    ``j`` of triangle ``t`` lies on one)."""
    flood_with(neighbors, cflag, start, label, value, np.empty(label.shape[0], np.int64))


@kernel
def flood_with(neighbors, cflag, start, label, value, stack):
    """:func:`flood` with a caller's stack (room for every triangle)."""
    label[start] = value
    stack[0] = start
    sp = 1
    while sp > 0:
        sp -= 1
        t = stack[sp]
        for j in range(3):
            m = neighbors[t, j]
            if m < 0 or cflag[t, j] != 0 or label[m] == value:
                continue
            label[m] = value
            stack[sp] = m
            sp += 1


@kernel
def flood_seeds(vx, vy, triangles, neighbors, cflag, px, py, allowed, label, values):
    """Flood from each seed point ``(px[i], py[i])`` in turn, painting
    ``values[i]`` from the triangle that contains it, if that triangle is
    ``allowed`` (seeds outside the triangulation are skipped; a later seed
    repaints an earlier one's region). Each point location walks from the
    previous seed's triangle, so seeds given in a coherent order walk little."""
    stack = np.empty(label.shape[0], np.int64)
    k0 = np.int64(0)
    for i in range(px.shape[0]):
        k = locate_in_arrays(vx, vy, triangles, neighbors, px[i], py[i], k0)
        if k < 0:
            continue
        k0 = k
        if allowed[k]:
            flood_with(neighbors, cflag, k, label, values[i], stack)
