"""Snap rounding of crossing segments: hot pixels (``intersections="split"``).

A crossing point of two segments is rarely a double. Rounding it moves the
pieces of both segments off their lines, and a moved piece can cross a third
segment where the input did not, whose rounded crossing moves more pieces: one
crossing at a time, rounded crossings need not converge, and where they end
depends on the order of the segments.

Snap rounding (Hobby 1999; Guibas and Marimont 1998) rounds them all at once.
The plane is tiled by *pixels*, one around each pair of doubles ``(cx, cy)``:
the points that round to it, ``[cx - below, cx + above) x [cy - below,
cy + above)`` per axis, half of the gap to the neighbouring doubles (or to the
neighbouring multiples of ``2**LOW``, :mod:`.scaling`). A pixel is *hot* when
it holds an input vertex or the exact crossing of two input segments (the
crossing's rounded point is its centre). Each segment then becomes the chain
through the centres of the hot pixels it meets, in the order it meets them.
The chains meet only at hot-pixel centres or along shared pieces (which the
segment insertion merges), and no chain turns back: the pixels form a grid, so
the centres a segment meets are monotone in both coordinates. The result
depends on the set of segments only, not on their order or direction.

Where the grid changes its spacing (at powers of two) the chains can still
cross in rare cases: later rounds add those crossings as hot pixels and snap
the pieces again (:func:`snap_plan`); segment insertion splits whatever might
be left.

Every decision is exact: the crossings by :func:`.kernel.orient`, whether a
segment meets a pixel by the exact sign of the orientation of its corners
(a double-double stage, then :func:`.predicates.orient_offset_exact`, the
corners being midpoints between doubles). A uniform grid of buckets finds
the candidate pairs and pixels. The route calls :func:`snap_route` only for
inputs whose segments cross, so that only they compile and run this module.
"""
from __future__ import annotations

import math

import numpy as np

from .arrays import append, copy_rows
from .jit import entry, kernel
from .ordering import lexicographic_order_compiled
from .predicates import (EPSILON, orient_expansion, two_diff, two_one_sum, two_product,
                         orient_offset_exact)
from .scaling import GRID, ON_GRID_ABOVE, fit_shift, on_grid, scaled
from .segments import crosses, intersection_point
from .status import ROUTE_OK, ROUTE_STEINER_LIMIT

ROUNDS = 8     # snap rounds at most (one suffices on a uniform grid of pixels)


# ------------------------------------------------------------------ pixels
@kernel
def pixel_halves(c):
    """``(below, above)``: how far the pixel around coordinate ``c`` reaches on
    either side, half the gap to the next coordinate the engine can place."""
    if abs(c) < ON_GRID_ABOVE:
        return 0.5 * GRID, 0.5 * GRID
    return 0.5 * (c - np.nextafter(c, -np.inf)), 0.5 * (np.nextafter(c, np.inf) - c)


@kernel
def sign_beyond(v, c, h):
    """The sign of ``v - (c + h)``, exactly (``c + h`` need not be a double)."""
    d, e = two_diff(v, c)
    x2, x1, x0 = two_one_sum(d, e, -h)
    top = x2 if x2 != 0.0 else (x1 if x1 != 0.0 else x0)
    return 1 if top > 0.0 else (-1 if top < 0.0 else 0)


@kernel
def centre_orientation(ax, ay, bx, by, cx, cy):
    """orient2d(a, b, c) to about twice double precision, for the corners of
    the pixel around ``c``, which lie within rounding of the line: ``(s, rest,
    size, dx, dxl, dy, dyl)`` with the value ``s + rest`` (``s`` exact, the
    difference of the exact products of the leading differences), ``size`` the
    sum of the magnitudes of the terms in ``rest``, and the exact differences
    ``b - a = (dx + dxl, dy + dyl)``."""
    dx, dxl = two_diff(bx, ax)
    dy, dyl = two_diff(by, ay)
    uh, ul = two_diff(cy, ay)
    vh, vl = two_diff(cx, ax)
    p1, e1 = two_product(dx, uh)
    p2, e2 = two_product(dy, vh)
    s, t = two_diff(p1, p2)
    t1, t2, t3 = dx * ul, dxl * uh, dxl * ul
    t4, t5, t6 = dy * vl, dyl * vh, dyl * vl
    rest = t + e1 - e2 + t1 + t2 + t3 - t4 - t5 - t6
    size = (abs(t) + abs(e1) + abs(e2) + abs(t1) + abs(t2) + abs(t3) + abs(t4) + abs(t5)
            + abs(t6))
    return s, rest, size, dx, dxl, dy, dyl


@kernel
def corner_side(ax, ay, bx, by, cx, cy, ox, oy, high_x, high_y, base, w, n0):
    """The side of line ``a -> b`` (+1 left, -1 right, 0 on it) of the pixel
    corner ``(cx + ox, cy + oy)``, exact. The pixel is half-open: a corner on
    its high side stands for the points just inside, so where the line passes
    exactly through it, the sign is that of a point moved inwards (left by far
    more than down). ``base``: :func:`centre_orientation`, whose sum with the
    offset's terms decides unless the corner lies within about 2**-100 of the
    line's reach; then the exact sum, with the centre's exact orientation in
    the workspace ``w`` (160 doubles, filled once ``n0 >= 0``). Returns
    ``(side, n0)``."""
    s, rest, size, dx, dxl, dy, dyl = base
    o1, o2, o3, o4 = dx * oy, dxl * oy, dy * ox, dyl * ox       # exact: powers of two
    val = s + (rest + ((o1 + o2) - (o3 + o4)))
    bound = 32.0 * EPSILON * (abs(s) + size + abs(o1) + abs(o2) + abs(o3) + abs(o4))
    side = 1 if val > bound else (-1 if val < -bound else 0)
    if side == 0:
        if n0 < 0:
            n0 = orient_expansion(w, 0, ax, ay, bx, by, cx, cy)
        e = orient_offset_exact(w, n0, ax, ay, bx, by, ox, oy)
        side = 1 if e > 0.0 else (-1 if e < 0.0 else 0)
    if side == 0 and high_x and by != ay:
        side = 1 if by > ay else -1
    if side == 0 and high_y and bx != ax:
        side = 1 if bx < ax else -1
    return side, n0


@kernel
def meets_pixel(ax, ay, bx, by, cx, cy, w):
    """Whether segment ``a b`` meets the pixel around ``(cx, cy)``, exactly:
    the segment's box meets the pixel, and the pixel's corners are not all
    strictly on one side of its line (``w``: workspace of 160 doubles)."""
    blx, bhx = pixel_halves(cx)
    bly, bhy = pixel_halves(cy)
    # quick answers for the many pixels a segment passes by: beyond the neighbouring
    # doubles (cx - 2 blx is the next double below cx), or the line farther from the
    # centre than the pixel reaches, with room for the float orientation's rounding
    if max(ax, bx) < cx - 2.0 * blx or min(ax, bx) > cx + 2.0 * bhx:
        return False
    if max(ay, by) < cy - 2.0 * bly or min(ay, by) > cy + 2.0 * bhy:
        return False
    dx = bx - ax
    dy = by - ay
    d = dx * (cy - ay) - dy * (cx - ax)
    reach = abs(dx) * max(bly, bhy) + abs(dy) * max(blx, bhx)
    if abs(d) > reach + 8.0 * EPSILON * (abs(dx) * abs(cy - ay) + abs(dy) * abs(cx - ax) + reach):
        return False
    if sign_beyond(max(ax, bx), cx, -blx) < 0 or sign_beyond(min(ax, bx), cx, bhx) >= 0:
        return False
    if sign_beyond(max(ay, by), cy, -bly) < 0 or sign_beyond(min(ay, by), cy, bhy) >= 0:
        return False
    base = centre_orientation(ax, ay, bx, by, cx, cy)
    n0 = np.int64(-1)
    s0, n0 = corner_side(ax, ay, bx, by, cx, cy, -blx, -bly, False, False, base, w, n0)
    s1, n0 = corner_side(ax, ay, bx, by, cx, cy, bhx, -bly, True, False, base, w, n0)
    s2, n0 = corner_side(ax, ay, bx, by, cx, cy, -blx, bhy, False, True, base, w, n0)
    s3, n0 = corner_side(ax, ay, bx, by, cx, cy, bhx, bhy, True, True, base, w, n0)
    if s0 > 0 and s1 > 0 and s2 > 0 and s3 > 0:
        return False
    return not (s0 < 0 and s1 < 0 and s2 < 0 and s3 < 0)


# ------------------------------------------------------------------ buckets
@kernel
def make_grid(x, y, items):
    """A bucket grid over the box of ``x, y`` with about ``items`` cells:
    ``(x0, y0, cell width, cell height, columns, rows, margin)``. ``margin``
    exceeds every pixel and the rounding of the walk along a segment."""
    x0, x1, y0, y1 = np.inf, -np.inf, np.inf, -np.inf
    big = 0.0
    for i in range(x.shape[0]):
        x0 = min(x0, x[i])
        x1 = max(x1, x[i])
        y0 = min(y0, y[i])
        y1 = max(y1, y[i])
        big = max(big, abs(x[i]), abs(y[i]))
    w = x1 - x0
    h = y1 - y0
    cells = max(items, 1)
    if w > 0 and h > 0:
        gx = max(1, min(cells, int(math.sqrt(cells * w / h))))
        gy = max(1, min(cells, cells // gx))
    elif w > 0:
        gx, gy = cells, 1
    else:
        gx, gy = 1, max(cells, 1) if h > 0 else 1
    cw = w / gx if w > 0 else 1.0
    ch = h / gy if h > 0 else 1.0
    # ulp(big) <= big 2**-52: a pixel reaches half an ulp, a column's edge as
    # segment_cells computes it is within a few ulps of the one cell_of places points by,
    # and the walk's y there is off by a few ulps of the largest coordinate; 8 ulps
    # covers each (segment_cells widens the columns by it too, so a steep segment's y
    # range holds the points cell_of puts on either side of an edge). The margin was
    # 2**-40 (4096 ulps): for a drawing 120 wide at 1e15 from the origin, 900 units, which
    # put every piece in every bucket and tested all pairs in each, for minutes.
    margin = big * 2.0 ** -49 + GRID
    return x0, y0, cw, ch, np.int64(gx), np.int64(gy), margin


@kernel
def cell_of(v, v0, size, g):
    """The bucket index of coordinate ``v`` on one axis, clamped to the grid."""
    t = (v - v0) / size
    if not t > 0.0:
        return np.int64(0)
    if t >= g:
        return g - 1
    return min(np.int64(t), g - 1)


@kernel
def segment_cells(ax, ay, bx, by, grid, out):
    """The buckets that segment ``a b``, widened by the grid's margin, passes
    through: column by column, the rows its line spans there. Writes them to
    ``out`` while it has room; returns how many there are (none twice)."""
    x0, y0, cw, ch, gx, gy, margin = grid
    lox, hix = min(ax, bx) - margin, max(ax, bx) + margin
    loy, hiy = min(ay, by) - margin, max(ay, by) + margin
    c0, c1 = cell_of(lox, x0, cw, gx), cell_of(hix, x0, cw, gx)
    k = 0
    for c in range(c0, c1 + 1):
        ylo, yhi = loy, hiy
        if c0 != c1 and bx != ax:
            slope = (by - ay) / (bx - ax)
            xl = max(lox, x0 + c * cw - margin)
            xr = min(hix, x0 + (c + 1) * cw + margin)
            yl = ay + (xl - ax) * slope
            yr = ay + (xr - ax) * slope
            ylo = max(min(yl, yr) - margin, loy)
            yhi = min(max(yl, yr) + margin, hiy)
        for r in range(cell_of(ylo, y0, ch, gy), cell_of(yhi, y0, ch, gy) + 1):
            if k < out.shape[0]:
                out[k] = r * gx + c
            k += 1
    return k


@kernel
def cells_of(ax, ay, bx, by, grid, buf):
    """:func:`segment_cells` into ``buf``, grown when too small: ``(cells, buf)``."""
    k = segment_cells(ax, ay, bx, by, grid, buf)
    if k > buf.shape[0]:
        buf = np.empty(2 * k, np.int64)
        k = segment_cells(ax, ay, bx, by, grid, buf)
    return k, buf


@kernel
def bucket_segments(x, y, pieces, grid):
    """The pieces (rows ``u, v, segment``) by bucket: those of bucket ``c`` are
    ``items[start[c]:start[c + 1]]``."""
    ncell = grid[4] * grid[5]
    start = np.zeros(ncell + 2, np.int64)
    buf = np.empty(64, np.int64)
    for i in range(pieces.shape[0]):
        a, b = pieces[i, 0], pieces[i, 1]
        k, buf = cells_of(x[a], y[a], x[b], y[b], grid, buf)
        for j in range(k):
            start[buf[j] + 2] += 1
    for c in range(ncell):
        start[c + 2] += start[c + 1]
    items = np.empty(start[ncell + 1], np.int64)
    for i in range(pieces.shape[0]):
        a, b = pieces[i, 0], pieces[i, 1]
        k, buf = cells_of(x[a], y[a], x[b], y[b], grid, buf)
        for j in range(k):
            items[start[buf[j] + 1]] = i
            start[buf[j] + 1] += 1
    return start, items


@kernel
def bucket_points(x, y, ids, grid):
    """Points ``ids`` by the bucket of their position: ``(start, items)``."""
    x0, y0, cw, ch, gx, gy, _ = grid
    ncell = gx * gy
    start = np.zeros(ncell + 2, np.int64)
    cell = np.empty(ids.shape[0], np.int64)
    for k in range(ids.shape[0]):
        v = ids[k]
        cell[k] = cell_of(y[v], y0, ch, gy) * gx + cell_of(x[v], x0, cw, gx)
        start[cell[k] + 2] += 1
    for c in range(ncell):
        start[c + 2] += start[c + 1]
    items = np.empty(ids.shape[0], np.int64)
    for k in range(ids.shape[0]):
        items[start[cell[k] + 1]] = ids[k]
        start[cell[k] + 1] += 1
    return start, items


# ------------------------------------------------------------------ crossings
@kernel
def boxes_meet(x, y, a, b, c, d):
    """Whether the boxes of segments ``a b`` and ``c d`` meet."""
    return (max(x[a], x[b]) >= min(x[c], x[d]) and max(x[c], x[d]) >= min(x[a], x[b])
            and max(y[a], y[b]) >= min(y[c], y[d]) and max(y[c], y[d]) >= min(y[a], y[b]))


@kernel
def crossing_pairs(x, y, nv, pieces):
    """Every pair ``i < j`` of pieces (rows ``u, v, segment`` over vertices
    ``0..nv-1``) whose interiors cross at one point (exact), once each, sorted."""
    m = pieces.shape[0]
    grid = make_grid(x[:nv], y[:nv], m)
    start, items = bucket_segments(x, y, pieces, grid)
    keys = np.empty(16, np.int64)
    nk = 0
    for c in range(start.shape[0] - 2):
        for p in range(start[c], start[c + 1]):
            i = items[p]
            for q in range(p + 1, start[c + 1]):
                j = items[q]
                a, b, u, v = pieces[i, 0], pieces[i, 1], pieces[j, 0], pieces[j, 1]
                if a == u or a == v or b == u or b == v:     # (pieces of one chain)
                    continue
                if not boxes_meet(x, y, a, b, u, v) or not crosses(x, y, a, b, u, v):
                    continue
                keys, nk = append(keys, nk, min(i, j) * m + max(i, j))
    # sorted, once each (a pair meets in every bucket both pieces pass through);
    # keys below 2**53 are exact as doubles, for the compiled sort the route has already
    fkeys = np.empty(nk)
    for k in range(nk):
        fkeys[k] = keys[k]
    order = lexicographic_order_compiled(fkeys, np.zeros(nk))
    pairs = np.empty((nk, 2), np.int64)
    npairs = 0
    for r in range(nk):
        key = keys[order[r]]
        if r > 0 and key == keys[order[r - 1]]:
            continue
        pairs[npairs, 0] = key // m
        pairs[npairs, 1] = key % m
        npairs += 1
    return pairs[:npairs]


# ------------------------------------------------------------------ hot pixels
@kernel
def distinct_points(x, y, nv):
    """The first of the vertices ``0..nv-1`` at each position."""
    order = lexicographic_order_compiled(x[:nv].copy(), y[:nv].copy())   # stable: at one position, the lowest id first
    keep = np.empty(nv, np.int64)
    k = 0
    for r in range(nv):
        i = order[r]
        if r > 0 and x[i] == x[order[r - 1]] and y[i] == y[order[r - 1]]:
            continue
        keep[k] = i
        k += 1
    return keep[:k]


@kernel
def add_points(x, y, nv, cx, cy):
    """Append the points ``cx, cy`` that are not at a vertex ``0..nv-1`` yet
    (each position once) to ``x, y`` (grown as needed). Returns ``(x, y, nv)``."""
    k = cx.shape[0]
    ax = np.empty(nv + k)
    ay = np.empty(nv + k)
    copy_rows(ax, x, nv)
    copy_rows(ay, y, nv)
    copy_rows(ax[nv:], cx, k)
    copy_rows(ay[nv:], cy, k)
    if x.shape[0] < nv + k:
        grown_x = np.empty(2 * (nv + k))
        grown_y = np.empty(2 * (nv + k))
        copy_rows(grown_x, x, nv)
        copy_rows(grown_y, y, nv)
        x, y = grown_x, grown_y
    old = nv
    for i in distinct_points(ax, ay, old + k):
        if i >= old:          # (a vertex at the same position comes first)
            x[nv] = ax[i]
            y[nv] = ay[i]
            nv += 1
    return x, y, nv


@kernel
def along_order(ax, ay, bx, by, hx, hy):
    """The order in which segment ``a -> b`` meets pixels centred at ``hx, hy``:
    by column in the direction of travel, then by row (the pixels form a grid)."""
    sx = 1.0 if bx > ax else (-1.0 if bx < ax else 0.0)
    sy = 1.0 if by > ay else (-1.0 if by < ay else 0.0)
    return lexicographic_order_compiled(sx * hx, sy * hy)


@kernel
def snap_pieces(x, y, nv, pieces):
    """Each piece ``u v`` as the chain through the centres of the hot pixels it
    meets (one around each vertex ``0..nv-1``), in the order it meets them:
    the new pieces, rows ``u, v, segment``, each chain in order."""
    hot = distinct_points(x, y, nv)
    grid = make_grid(x[:nv], y[:nv], hot.shape[0])
    start, items = bucket_points(x, y, hot, grid)
    out = np.empty((pieces.shape[0] + 16, 3), np.int64)
    nout = 0
    buf = np.empty(64, np.int64)
    met = np.empty(16, np.int64)
    w = np.empty(160)
    for r in range(pieces.shape[0]):
        a, b, s = pieces[r, 0], pieces[r, 1], pieces[r, 2]
        ax, ay, bx, by = x[a], y[a], x[b], y[b]
        k, buf = cells_of(ax, ay, bx, by, grid, buf)
        nm = 0
        for t in range(k):
            c = buf[t]
            for p in range(start[c], start[c + 1]):
                h = items[p]
                hx, hy = x[h], y[h]
                if (hx == ax and hy == ay) or (hx == bx and hy == by):
                    continue
                if not meets_pixel(ax, ay, bx, by, hx, hy, w):
                    continue
                met, nm = append(met, nm, h)
        mx = np.empty(nm)
        my = np.empty(nm)
        for t in range(nm):
            mx[t] = x[met[t]]
            my[t] = y[met[t]]
        order = along_order(ax, ay, bx, by, mx, my)
        if nout + nm + 1 > out.shape[0]:
            grown2 = np.empty((2 * (nout + nm + 1), 3), np.int64)
            copy_rows(grown2, out, nout)
            out = grown2
        u = a
        for t in range(nm + 1):
            v = met[order[t]] if t < nm else b
            out[nout, 0] = u
            out[nout, 1] = v
            out[nout, 2] = s
            nout += 1
            u = v
    return out[:nout]


@kernel
def canonical_new_points(x, y, n, nv, pieces):
    """Renumber the new points ``n..nv-1`` in (x, y) order, in place (``x, y``
    and ``pieces``), so that the plan does not depend on the order of the
    rounds' discoveries."""
    k = nv - n
    order = lexicographic_order_compiled(x[n:nv].copy(), y[n:nv].copy())
    new_id = np.empty(k, np.int64)
    nx = np.empty(k)
    ny = np.empty(k)
    for r in range(k):
        new_id[order[r]] = n + r
        nx[r] = x[n + order[r]]
        ny[r] = y[n + order[r]]
    for i in range(pieces.shape[0]):
        for j in range(2):
            if pieces[i, j] >= n:
                pieces[i, j] = new_id[pieces[i, j] - n]
    return nx, ny


@kernel
def snap_plan(x, y, n, segs, use):
    """Snap-round segments ``use`` (rows of ``segs``, vertex ids ``< n`` into
    ``x, y``). Returns ``(new_x, new_y, pieces, pairs)``: the new points
    (ids ``n, n + 1, ...``, in (x, y) order), the chains as pieces ``(u, v,
    segment)`` in segment order, each chain from its first end to its last,
    and the crossing pairs of segments (the first round's). With no crossing
    the pieces are empty: the segments are used as they are.

    The first round snaps the input segments through the pixels of the
    vertices and of their rounded crossings. Where the pixels' spacing changes
    (at powers of two) two chains can still cross; each later round adds those
    crossings as hot pixels and snaps the pieces again (iterated snap
    rounding), up to :data:`ROUNDS` rounds; segment insertion splits what
    might be left."""
    pieces = np.empty((segs.shape[0], 3), np.int64)
    m = 0
    for s in range(segs.shape[0]):
        if use[s]:
            pieces[m, 0] = segs[s, 0]
            pieces[m, 1] = segs[s, 1]
            pieces[m, 2] = s
            m += 1
    pieces = pieces[:m]
    X = np.empty(n + 16)
    Y = np.empty(n + 16)
    copy_rows(X, x, n)
    copy_rows(Y, y, n)
    nv = n
    first_pairs = np.empty((0, 2), np.int64)
    for round_ in range(ROUNDS):
        pairs = crossing_pairs(X, Y, nv, pieces)
        np_ = pairs.shape[0]
        if round_ == 0:
            if np_ == 0:
                return np.empty(0), np.empty(0), np.empty((0, 3), np.int64), pairs
            first_pairs = np.empty((np_, 2), np.int64)
            for k in range(np_):
                first_pairs[k, 0] = pieces[pairs[k, 0], 2]
                first_pairs[k, 1] = pieces[pairs[k, 1], 2]
        if np_ == 0:
            break
        cx = np.empty(np_)
        cy = np.empty(np_)
        for k in range(np_):
            i, j = pairs[k, 0], pairs[k, 1]
            px, py = intersection_point(X, Y, pieces[i, 0], pieces[i, 1], pieces[j, 0], pieces[j, 1])
            cx[k] = on_grid(px)
            cy[k] = on_grid(py)
        X, Y, nv = add_points(X, Y, nv, cx, cy)
        pieces = snap_pieces(X, Y, nv, pieces)
    new_x, new_y = canonical_new_points(X, Y, n, nv, pieces)
    return new_x, new_y, pieces, first_pairs


# ------------------------------------------------------------------ the entry point
@kernel
def steiner_limit(max_steiner, m):
    """The cap on crossing points that segment insertion places one at a time
    for ``m`` segments: ``max_steiner``, or by default ``10 m + 1000`` (rounded
    one at a time, crossings can keep making new ones; snap rounding's are
    counted before anything is built and are not capped by default)."""
    return max_steiner if max_steiner >= 0 else 10 * m + 1000


@kernel
def segment_has_length(x, y, segs):
    """Whether each segment's ends lie apart."""
    out = np.empty(segs.shape[0], np.bool_)
    for i in range(segs.shape[0]):
        a, b = segs[i, 0], segs[i, 1]
        out[i] = x[a] != x[b] or y[a] != y[b]
    return out


@entry
def snap_route(px, py, segs, max_steiner):
    """The snap-rounded crossings of segments ``segs`` over points ``px, py``
    (input ids), for :func:`.pipeline.cdt_route`'s ``snapped``, compiled
    apart from it: only inputs whose segments cross pay for it. In the
    route's power-of-two scale (:mod:`.scaling`), the new points returned in
    the input's (exact both ways). Returns ``(status, info, new_x, new_y,
    chains)``; ROUTE_STEINER_LIMIT with ``info = (segment id, other segment id,
    max_steiner, points needed)`` (1-based ids) when the new points exceed
    ``max_steiner`` (-1: no cap)."""
    info = np.zeros(4, np.int64)
    shift, _, _ = fit_shift(px, py, np.empty(0))     # (in range: the route checked)
    if shift != 0:
        px = scaled(px, shift)
        py = scaled(py, shift)
    new_x, new_y, chains, pairs = snap_plan(px, py, px.shape[0], segs,
                                            segment_has_length(px, py, segs))
    if 0 <= max_steiner < new_x.shape[0]:     # (by default every crossing: finitely many)
        info[0] = pairs[0, 0] + 1
        info[1] = pairs[0, 1] + 1
        info[2] = max_steiner
        info[3] = new_x.shape[0]
        return ROUTE_STEINER_LIMIT, info, new_x, new_y, chains
    if shift != 0:
        new_x = scaled(new_x, -shift)
        new_y = scaled(new_y, -shift)
    return ROUTE_OK, info, new_x, new_y, chains
