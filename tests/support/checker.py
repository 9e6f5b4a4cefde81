"""An independent, exact checker for (constrained, weighted) Delaunay triangulations.

This module is the test suite's referee. It imports nothing from ``cdt_plugin``: it is
numpy plus exact rational arithmetic, and it verifies a triangulation from scratch.

Exactness. Every geometric decision (orientation, incircle, lifted power test, hull,
collinearity, betweenness, area) is exact. Predicates are evaluated vectorised in floating
point with a rigorous error bound (Shewchuk's static bounds for orient2d and incircle, a
much more generous one for the weighted test), and rows the filter cannot decide, or whose
magnitudes could underflow/overflow, are recomputed exactly. The exact path converts every
coordinate to an integer after multiplying by a common power of two (a float is a dyadic
rational, so ``x * 2**D`` is an integer for D large enough): this is arithmetic in
``fractions.Fraction`` with a common denominator, done with Python ints in numpy object
arrays. Areas are reported as ``Fraction``.

Vocabulary (Cheng, Dey & Shewchuk, *Delaunay Mesh Generation*, ch. 2): an edge is
*locally Delaunay* (Def. 2.4) if it is a boundary edge or the opposite vertex of one of its
triangles is not strictly inside the circumcircle of the other; a triangulation all of
whose edges are locally Delaunay is Delaunay (Delaunay Lemma, 2.3). In a CDT the segments
are exempt (Constrained Delaunay Lemma, 2.14). For weighted points (Sec. 2.8) the test is
on the lifted points ``(x, y, x^2 + y^2 - w)``: the opposite lifted vertex must not lie
strictly below the plane of the lifted triangle (locally regular).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Dict, Iterable, List, Optional, Set, Tuple

import numpy as np

__all__ = ["CheckReport", "check_triangulation", "assert_valid", "check_collinear_edges",
           "canonical_triangles", "orient2d_exact", "incircle_exact"]

_EPS = 2.0 ** -53
_CCW_ERRBOUND_A = (3.0 + 16.0 * _EPS) * _EPS          # Shewchuk 1997, orient2d
_ICC_ERRBOUND_A = (10.0 + 96.0 * _EPS) * _EPS         # Shewchuk 1997, incircle
_WEIGHTED_ERRBOUND = 1e-12                            # >> any rounding error of the lifted test
# The float filter is only trusted when every nonzero coordinate difference lies in
# [2^-200, 2^200] (and weight differences in [2^-400, 2^400]): then no product of up to
# four factors can underflow or overflow, so the relative error bounds are rigorous.
_LO, _HI = 2.0 ** -200, 2.0 ** 200
_WLO, _WHI = 2.0 ** -400, 2.0 ** 400

_MAX_MESSAGES_PER_KIND = 25


# ----------------------------------------------------------------------------------------
# report
# ----------------------------------------------------------------------------------------

@dataclass
class CheckReport:
    """Result of a check. ``problems`` are human-readable messages naming indices;
    ``kinds`` counts problems per category (e.g. ``"orientation"``, ``"not_delaunay"``),
    including those whose messages were elided; ``counts`` holds statistics."""
    ok: bool = True
    problems: List[str] = field(default_factory=list)
    kinds: Dict[str, int] = field(default_factory=dict)
    counts: Dict[str, object] = field(default_factory=dict)

    def add(self, kind: str, msg: str) -> None:
        self.ok = False
        c = self.kinds.get(kind, 0)
        self.kinds[kind] = c + 1
        if c < _MAX_MESSAGES_PER_KIND:
            self.problems.append(f"[{kind}] {msg}")

    def finish(self) -> "CheckReport":
        for kind, c in self.kinds.items():
            if c > _MAX_MESSAGES_PER_KIND:
                self.problems.append(f"[{kind}] ... and {c - _MAX_MESSAGES_PER_KIND} more")
        return self

    def __str__(self) -> str:
        head = "OK" if self.ok else f"{sum(self.kinds.values())} problem(s) {self.kinds}"
        lines = [f"CheckReport: {head}; counts {self.counts}"]
        lines += ["  " + p for p in self.problems[:50]]
        return "\n".join(lines)


# ----------------------------------------------------------------------------------------
# exact arithmetic
# ----------------------------------------------------------------------------------------

def _dyadic(values: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Exact decomposition x = M * 2**E with integer M (|M| < 2**53) for finite floats."""
    m, e = np.frexp(values)
    M = np.ldexp(m, 53).astype(np.int64)        # exact: m has 53 significant bits
    E = e.astype(np.int64) - 53
    E[M == 0] = 0
    return M, E


class _Exact:
    """Integer images of the coordinates (and weights): X = x * 2**D, W = w * 2**(2D).

    Orientation and (lifted) incircle determinants computed from these are the exact
    determinants times a positive power of two, so their signs are exact.
    """

    def __init__(self, points: np.ndarray, weights: Optional[np.ndarray]):
        Mx, Ex = _dyadic(points[:, 0])
        My, Ey = _dyadic(points[:, 1])
        D = int(max(0, -min(Ex.min(initial=0), Ey.min(initial=0))))
        if weights is not None:
            Mw, Ew = _dyadic(weights)
            D = max(D, (int(max(0, -Ew.min(initial=0))) + 1) // 2)
        self.D = D
        self.X = np.array([int(a) << int(b + D) for a, b in zip(Mx.tolist(), Ex.tolist())],
                          dtype=object)
        self.Y = np.array([int(a) << int(b + D) for a, b in zip(My.tolist(), Ey.tolist())],
                          dtype=object)
        self.W = None
        if weights is not None:
            self.W = np.array([int(a) << int(b + 2 * D)
                               for a, b in zip(Mw.tolist(), Ew.tolist())], dtype=object)

    def orient(self, a, b, c) -> np.ndarray:
        """Sign (-1, 0, 1) of orient2d for index arrays a, b, c."""
        det = self.orient_value(a, b, c)
        return np.array([(v > 0) - (v < 0) for v in det], dtype=np.int64)

    def orient_value(self, a, b, c) -> np.ndarray:
        X, Y = self.X, self.Y
        return (X[a] - X[c]) * (Y[b] - Y[c]) - (Y[a] - Y[c]) * (X[b] - X[c])

    def incircle(self, a, b, c, d) -> np.ndarray:
        """Sign of incircle(a, b, c, d) (> 0: d strictly inside the circle of CCW a, b, c);
        with weights, of the lifted power test (> 0: lifted d strictly below the plane)."""
        X, Y = self.X, self.Y
        adx, ady = X[a] - X[d], Y[a] - Y[d]
        bdx, bdy = X[b] - X[d], Y[b] - Y[d]
        cdx, cdy = X[c] - X[d], Y[c] - Y[d]
        alift = adx * adx + ady * ady
        blift = bdx * bdx + bdy * bdy
        clift = cdx * cdx + cdy * cdy
        if self.W is not None:
            W = self.W
            alift = alift - (W[a] - W[d])
            blift = blift - (W[b] - W[d])
            clift = clift - (W[c] - W[d])
        det = (alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy)
               + clift * (adx * bdy - bdx * ady))
        return np.array([(v > 0) - (v < 0) for v in det], dtype=np.int64)


def _in_range(*diffs: np.ndarray, lo=_LO, hi=_HI) -> np.ndarray:
    ok = np.ones(diffs[0].shape, dtype=bool)
    for d in diffs:
        ad = np.abs(d)
        ok &= (ad == 0) | ((ad >= lo) & (ad <= hi))
    return ok


def _orient_filter(P: np.ndarray, a, b, c) -> Tuple[np.ndarray, np.ndarray]:
    """Float orient2d signs and a mask of rows where the sign is certain
    (overflow and NaN, far outside the filter's range, are never sure)."""
    with np.errstate(all="ignore"):
        acx = P[a, 0] - P[c, 0]
        bcx = P[b, 0] - P[c, 0]
        acy = P[a, 1] - P[c, 1]
        bcy = P[b, 1] - P[c, 1]
        left = acx * bcy
        right = acy * bcx
        det = left - right
        bound = _CCW_ERRBOUND_A * (np.abs(left) + np.abs(right))
        sure = (np.abs(det) > bound) & _in_range(acx, bcx, acy, bcy)
        return np.sign(np.nan_to_num(det)).astype(np.int64), sure


def _orient_signs(P: np.ndarray, ex: "_Lazy", a, b, c, stats: Dict) -> np.ndarray:
    a, b, c = (np.asarray(v, dtype=np.int64) for v in (a, b, c))
    s, sure = _orient_filter(P, a, b, c)
    if not sure.all():
        idx = np.flatnonzero(~sure)
        s[idx] = ex.get().orient(a[idx], b[idx], c[idx])
        stats["exact_fallbacks"] = stats.get("exact_fallbacks", 0) + len(idx)
    return s


def _incircle_signs(P: np.ndarray, w: Optional[np.ndarray], ex: "_Lazy", a, b, c, d,
                    stats: Dict) -> np.ndarray:
    a, b, c, d = (np.asarray(v, dtype=np.int64) for v in (a, b, c, d))
    with np.errstate(all="ignore"):
        adx, ady = P[a, 0] - P[d, 0], P[a, 1] - P[d, 1]
        bdx, bdy = P[b, 0] - P[d, 0], P[b, 1] - P[d, 1]
        cdx, cdy = P[c, 0] - P[d, 0], P[c, 1] - P[d, 1]
        bdxcdy, cdxbdy = bdx * cdy, cdx * bdy
        cdxady, adxcdy = cdx * ady, adx * cdy
        adxbdy, bdxady = adx * bdy, bdx * ady
        alift = adx * adx + ady * ady
        blift = bdx * bdx + bdy * bdy
        clift = cdx * cdx + cdy * cdy
        sure = _in_range(adx, ady, bdx, bdy, cdx, cdy)
        if w is None:
            det = (alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy)
                   + clift * (adxbdy - bdxady))
            perm = ((np.abs(bdxcdy) + np.abs(cdxbdy)) * alift
                    + (np.abs(cdxady) + np.abs(adxcdy)) * blift
                    + (np.abs(adxbdy) + np.abs(bdxady)) * clift)
            bound = _ICC_ERRBOUND_A * perm
        else:
            dwa, dwb, dwc = w[a] - w[d], w[b] - w[d], w[c] - w[d]
            sure &= _in_range(dwa, dwb, dwc, lo=_WLO, hi=_WHI)
            det = ((alift - dwa) * (bdxcdy - cdxbdy) + (blift - dwb) * (cdxady - adxcdy)
                   + (clift - dwc) * (adxbdy - bdxady))
            perm = ((np.abs(bdxcdy) + np.abs(cdxbdy)) * (alift + np.abs(dwa))
                    + (np.abs(cdxady) + np.abs(adxcdy)) * (blift + np.abs(dwb))
                    + (np.abs(adxbdy) + np.abs(bdxady)) * (clift + np.abs(dwc)))
            bound = _WEIGHTED_ERRBOUND * perm
        sure &= np.abs(det) > bound
        s = np.sign(np.nan_to_num(det)).astype(np.int64)
    if not sure.all():
        idx = np.flatnonzero(~sure)
        s[idx] = ex.get().incircle(a[idx], b[idx], c[idx], d[idx])
        stats["exact_fallbacks"] = stats.get("exact_fallbacks", 0) + len(idx)
    return s


class _Lazy:
    """Builds the integer images only if some row needs the exact path."""

    def __init__(self, points, weights):
        self.points, self.weights, self._ex = points, weights, None

    def get(self) -> _Exact:
        if self._ex is None:
            self._ex = _Exact(self.points, self.weights)
        return self._ex


def orient2d_exact(a, b, c) -> int:
    """Exact sign of the orientation of three 2D points (+1: counter-clockwise)."""
    fa = [Fraction(float(v)) for v in (*a, *b, *c)]
    ax, ay, bx, by, cx, cy = fa
    det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)
    return (det > 0) - (det < 0)


def incircle_exact(a, b, c, d) -> int:
    """Exact sign of incircle (+1: d strictly inside the circle through CCW a, b, c)."""
    ax, ay, bx, by, cx, cy, dx, dy = (Fraction(float(v)) for v in (*a, *b, *c, *d))
    adx, ady, bdx, bdy, cdx, cdy = ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy
    det = ((adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
           + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
           + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady))
    return (det > 0) - (det < 0)


# ----------------------------------------------------------------------------------------
# exact convex hull (monotone chain keeping collinear boundary points)
# ----------------------------------------------------------------------------------------

def _convex_hull(P: np.ndarray, idx: np.ndarray, ex: _Lazy, stats: Dict) -> Optional[List[int]]:
    """CCW convex hull of the (distinct) points P[idx], every point on the hull boundary
    included (collinear ones too). Returns None if the points are all collinear.

    Andrew's monotone chain, popping only on strict right turns, with exact orientation.
    Points certainly strictly inside the polygon of extreme points (Akl-Toussaint) are
    discarded first; that only speeds things up.
    """
    if len(idx) < 3:
        return None
    Q = P[idx]
    ext = np.unique(idx[[np.argmin(Q[:, 0]), np.argmax(Q[:, 0]), np.argmin(Q[:, 1]),
                         np.argmax(Q[:, 1]), np.argmin(Q[:, 0] + Q[:, 1]),
                         np.argmax(Q[:, 0] + Q[:, 1]), np.argmin(Q[:, 0] - Q[:, 1]),
                         np.argmax(Q[:, 0] - Q[:, 1])]])
    if len(ext) >= 3 and len(idx) > 64:
        poly = _monotone_hull(P, ext, ex, stats)
        if poly is not None and len(poly) >= 3:
            inside = np.ones(len(idx), dtype=bool)
            for u, v in zip(poly, poly[1:] + poly[:1]):
                s, sure = _orient_filter(P, np.full(len(idx), u), np.full(len(idx), v), idx)
                inside &= sure & (s > 0)
            idx = idx[~inside]
    return _monotone_hull(P, idx, ex, stats)


def _monotone_hull(P, idx, ex, stats) -> Optional[List[int]]:
    order = idx[np.lexsort((P[idx, 1], P[idx, 0]))]
    pts = [int(i) for i in order]
    xy = {i: (float(P[i, 0]), float(P[i, 1])) for i in pts}
    nz = np.abs(P[idx][P[idx] != 0])
    plain = nz.size == 0 or (nz.min() >= 2.0 ** -140 and nz.max() <= 2.0 ** 190)

    def orient(i, j, k) -> int:
        ax, ay = xy[i]
        bx, by = xy[j]
        cx, cy = xy[k]
        acx, bcx, acy, bcy = ax - cx, bx - cx, ay - cy, by - cy
        left, right = acx * bcy, acy * bcx
        det = left - right
        if abs(det) > _CCW_ERRBOUND_A * (abs(left) + abs(right)) and (plain or all(
                v == 0.0 or _LO <= abs(v) <= _HI for v in (acx, bcx, acy, bcy))):
            return 1 if det > 0 else -1
        stats["exact_fallbacks"] = stats.get("exact_fallbacks", 0) + 1
        return int(ex.get().orient(np.array([i]), np.array([j]), np.array([k]))[0])

    def chain(seq):
        h: List[int] = []
        for p in seq:
            while len(h) >= 2 and orient(h[-2], h[-1], p) < 0:
                h.pop()
            h.append(p)
        return h

    if len(pts) < 3:
        return None
    lower = chain(pts)
    if len(lower) == len(pts) and all(orient(pts[0], pts[-1], p) == 0 for p in pts[1:-1]):
        return None     # all collinear
    upper = chain(pts[::-1])
    return lower[:-1] + upper[:-1]


def _segment_walk_ok(ex: _Exact, i: int, j: int, c: int, k: int) -> bool:
    """Is k on the closed segment ij, exactly collinear, strictly further from i than c?"""
    X, Y = ex.X, ex.Y
    dx, dy = X[j] - X[i], Y[j] - Y[i]
    kx, ky = X[k] - X[i], Y[k] - Y[i]
    if dx * ky - dy * kx != 0:
        return False
    tk = dx * kx + dy * ky
    tc = dx * (X[c] - X[i]) + dy * (Y[c] - Y[i])
    return tc < tk <= dx * dx + dy * dy


# ----------------------------------------------------------------------------------------
# vertex links
# ----------------------------------------------------------------------------------------

def _link_components(V: np.ndarray, U: np.ndarray, W: np.ndarray, n: int) -> np.ndarray:
    """Number of connected components of each vertex's link.

    Link edge e = (v: u -> w) comes from a triangle (v, u, w). Requires that the directed
    edges are unique, so that each link is a disjoint union of paths and cycles; then the
    components are (link edges with no predecessor) + (cycles). Cycles are found by pointer
    doubling, vectorised.
    """
    m = len(V)
    key = V * n + U
    order = np.argsort(key, kind="stable")
    skey = key[order]

    def lookup(q):
        pos = np.searchsorted(skey, q)
        pos = np.minimum(pos, m - 1)
        hit = skey[pos] == q
        return np.where(hit, order[pos], -1)

    succ = lookup(V * n + W)
    # predecessor of (v: u -> w) is a link edge (v: x -> u), i.e. one whose W is u.
    wkey = np.sort(V * n + W)
    pos = np.minimum(np.searchsorted(wkey, key), m - 1)
    has_pred = wkey[pos] == key

    comps = np.zeros(n, dtype=np.int64)
    np.add.at(comps, V[~has_pred], 1)

    nxt = succ.copy()
    reach_end = succ < 0
    lab = np.arange(m)
    rounds = int(np.ceil(np.log2(m + 1))) + 1
    for _ in range(rounds):
        live = nxt >= 0
        tgt = nxt[live]
        new_end = reach_end.copy()
        new_end[live] |= reach_end[tgt]
        new_lab = lab.copy()
        new_lab[live] = np.minimum(lab[live], lab[tgt])
        new_nxt = nxt.copy()
        new_nxt[live] = nxt[tgt]
        reach_end, lab, nxt = new_end, new_lab, new_nxt
    on_cycle = ~reach_end
    heads = on_cycle & (lab == np.arange(m))
    np.add.at(comps, V[heads], 1)
    return comps


# ----------------------------------------------------------------------------------------
# the check
# ----------------------------------------------------------------------------------------

def _fmt_pt(P, i) -> str:
    return f"({float(P[i, 0])!r}, {float(P[i, 1])!r})"


def check_triangulation(points, triangles, *, segments=None, weights=None, domain="hull",
                        submerged: Iterable[int] = (), require_all_vertices: bool = True,
                        exempt_segments: bool = True) -> CheckReport:
    """Verify a triangulation exactly and from scratch.

    Parameters
    ----------
    points : (n, 2) float array, the output vertices.
    triangles : (k, 3) int array; every triangle must be counter-clockwise.
    segments : (m, 2) int array of vertex index pairs that must appear as an edge or as a
        chain of collinear edges through vertices lying exactly on the segment. Segment
        edges (and pieces) are exempt from the Delaunay test (Lemma 2.14).
    weights : (n,) float array: check local regularity of the lifted points
        ``(x, y, x^2 + y^2 - w)`` instead of local Delaunayhood.
    domain : ``"hull"``: the triangles must tile the convex hull of the vertices they use
        (boundary edges are exactly the hull boundary pieces, exact areas agree).
        ``"segments"``: the domain is bounded by segments (CDT with holes/exterior removed):
        the hull tests are skipped, instead every boundary edge must be a segment or a
        piece of one. The union of triangles is then not compared with any region.
    submerged : vertex indices that must NOT be used (weighted points that are not vertices
        of the regular triangulation, or vertices deliberately left out). Each must lie in
        a triangle (domain "hull"); with weights, its lifted point must not lie strictly
        below the lifted triangle containing it (else it had to be a vertex, Sec. 2.8).
    require_all_vertices : every vertex not in ``submerged`` must be used by a triangle.
    exempt_segments : with False, segment edges must be locally Delaunay too (a
        conforming Delaunay triangulation, Def. 2.12).

    Checks: (1) index validity and strictly positive exact orientation; (2) simplicial
    complex: no duplicate triangles, each undirected edge used by at most two triangles and
    then in opposite directions, every vertex link a single path or cycle, no two used
    vertices at the same position; (3) domain (see above); (4) vertex coverage; (5) segments
    present; (6) every interior non-segment edge locally Delaunay (Def. 2.4; cocircular
    ties allowed) or locally regular with weights.
    """
    rep = CheckReport()
    stats: Dict[str, object] = rep.counts
    P = np.asarray(points, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 2:
        rep.add("input", f"points must have shape (n, 2), got {P.shape}")
        return rep.finish()
    n = P.shape[0]
    T = np.asarray(triangles)
    if T.size == 0:
        T = np.zeros((0, 3), dtype=np.int64)
    if T.ndim != 2 or T.shape[1] != 3 or not np.issubdtype(T.dtype, np.integer):
        rep.add("input", f"triangles must be an integer array of shape (k, 3), got "
                         f"{T.dtype} {T.shape}")
        return rep.finish()
    T = T.astype(np.int64)
    k = T.shape[0]
    stats["triangles"] = k
    stats["vertices"] = n
    w = None
    if weights is not None:
        w = np.asarray(weights, dtype=np.float64).reshape(-1)
        if w.shape[0] != n:
            rep.add("input", f"weights must have {n} entries, got {w.shape[0]}")
            return rep.finish()
        if not np.isfinite(w).all():
            rep.add("input", f"weights not finite at {np.flatnonzero(~np.isfinite(w))[:10].tolist()}")
            return rep.finish()
    bad = ~np.isfinite(P).all(axis=1)
    if bad.any():
        rep.add("input", f"non-finite coordinates at vertices {np.flatnonzero(bad)[:10].tolist()}")
        return rep.finish()
    sub = np.zeros(n, dtype=bool)
    sub_list = [int(s) for s in submerged]
    for s in sub_list:
        if not 0 <= s < n:
            rep.add("input", f"submerged index {s} out of range 0..{n - 1}")
            return rep.finish()
    sub[sub_list] = True
    ex = _Lazy(P, w)

    # -- (1) triangle validity and orientation -------------------------------------------
    out = ((T < 0) | (T >= n)).any(axis=1)
    for t in np.flatnonzero(out):
        rep.add("index", f"triangle {t} {T[t].tolist()} has a vertex index out of range 0..{n - 1}")
    if out.any():
        return rep.finish()
    rep_vert = (T[:, 0] == T[:, 1]) | (T[:, 1] == T[:, 2]) | (T[:, 0] == T[:, 2])
    for t in np.flatnonzero(rep_vert):
        rep.add("index", f"triangle {t} {T[t].tolist()} repeats a vertex")
    if rep_vert.any():
        return rep.finish()
    osign = _orient_signs(P, ex, T[:, 0], T[:, 1], T[:, 2], stats)
    for t in np.flatnonzero(osign <= 0):
        what = "clockwise" if osign[t] < 0 else "degenerate (zero area)"
        rep.add("orientation", f"triangle {t} {T[t].tolist()} is {what}: "
                               + ", ".join(_fmt_pt(P, i) for i in T[t]))

    # -- (2) simplicial complex ----------------------------------------------------------
    if k:
        srt = np.sort(T, axis=1)
        tkey = (srt[:, 0] * n + srt[:, 1]) * n + srt[:, 2] if n < 2_000_000 else None
        if tkey is not None:
            _, first, cnt = np.unique(tkey, return_index=True, return_counts=True)
            for f in first[cnt > 1]:
                dups = np.flatnonzero(tkey == tkey[f]).tolist()
                rep.add("duplicate_triangle", f"triangles {dups} have the same vertices "
                                              f"{srt[f].tolist()}")
        else:  # pragma: no cover - huge inputs
            _, first, cnt = np.unique(srt, axis=0, return_index=True, return_counts=True)
            for f, c in zip(first[cnt > 1], cnt[cnt > 1]):
                rep.add("duplicate_triangle", f"triangle {f} {srt[f].tolist()} appears {c} times")
    src = T.reshape(-1)
    dst = T[:, [1, 2, 0]].reshape(-1)
    opp = T[:, [2, 0, 1]].reshape(-1)
    tid = np.repeat(np.arange(k), 3)
    dkey = src * n + dst
    dorder = np.argsort(dkey, kind="stable")
    sdkey = dkey[dorder]
    directed_unique = True
    if len(sdkey) > 1:
        same = np.flatnonzero(sdkey[1:] == sdkey[:-1])
        if len(same):
            directed_unique = False
            for s in same:
                e1, e2 = dorder[s], dorder[s + 1]
                rep.add("edge_orientation",
                        f"directed edge ({src[e1]}, {dst[e1]}) is used by triangles {tid[e1]} "
                        f"and {tid[e2]} in the same direction (inconsistent orientation or overlap)")
    ukey = np.minimum(src, dst) * n + np.maximum(src, dst)
    uk, ucnt = np.unique(ukey, return_counts=True)
    for key in uk[ucnt > 2]:
        ts = tid[ukey == key].tolist()
        rep.add("nonmanifold_edge", f"edge ({key // n}, {key % n}) is used by {len(ts)} "
                                    f"triangles {ts}")
    # twins
    rkey = dst * n + src
    if len(sdkey):
        pos = np.minimum(np.searchsorted(sdkey, rkey), len(sdkey) - 1)
        has_twin = sdkey[pos] == rkey
        twin = np.where(has_twin, dorder[pos], -1)
    else:
        has_twin = np.zeros(0, dtype=bool)
        twin = np.zeros(0, dtype=np.int64)
    used = np.zeros(n, dtype=bool)
    used[src] = True
    stats["vertices_used"] = int(used.sum())
    stats["boundary_edges"] = int((~has_twin).sum())
    stats["interior_edges"] = int((has_twin & (src < dst)).sum())

    if directed_unique and k and domain == "hull":
        # (a domain bounded by segments may pinch at a vertex: several fans there.
        # Callers check such results as a subset of a full-hull triangulation.)
        comps = _link_components(src, dst, opp, n)
        for v in np.flatnonzero(used & (comps != 1)):
            rep.add("nonmanifold_vertex", f"vertex {v} {_fmt_pt(P, v)} has a link of "
                                          f"{comps[v]} components (its star is not one fan)")
    # coincident used vertices
    ui = np.flatnonzero(used)
    if len(ui) > 1:
        o = ui[np.lexsort((P[ui, 1], P[ui, 0]))]
        eq = (P[o[1:], 0] == P[o[:-1], 0]) & (P[o[1:], 1] == P[o[:-1], 1])
        for s in np.flatnonzero(eq):
            rep.add("coincident_vertices", f"vertices {o[s]} and {o[s + 1]} are both used and "
                                           f"coincide at {_fmt_pt(P, o[s])}")

    # -- (4) vertex coverage -------------------------------------------------------------
    for v in np.flatnonzero(used & sub):
        rep.add("submerged_used", f"vertex {v} {_fmt_pt(P, v)} is submerged but used by a triangle")
    if require_all_vertices:
        for v in np.flatnonzero(~used & ~sub):
            rep.add("unused_vertex", f"vertex {v} {_fmt_pt(P, v)} is used by no triangle")

    # -- (5) segments --------------------------------------------------------------------
    seg_edge_keys = np.zeros(0, dtype=np.int64)
    if segments is not None:
        S = np.asarray(segments)
        if S.size == 0:
            S = np.zeros((0, 2), dtype=np.int64)
        if S.ndim != 2 or S.shape[1] != 2 or not np.issubdtype(S.dtype, np.integer):
            rep.add("input", f"segments must be an integer array of shape (m, 2), got {S.shape}")
        else:
            S = S.astype(np.int64)
            seg_edge_keys = _check_segments(rep, P, ex, S, src, dst, ukey, n, stats)

    # -- (3) domain ----------------------------------------------------------------------
    bnd = ~has_twin
    if domain == "hull":
        if k:
            _check_hull(rep, P, ex, T, src[bnd], dst[bnd], used, sub, stats)
    elif domain == "segments":
        bkeys = ukey[bnd]
        ok = np.isin(bkeys, seg_edge_keys)
        for e in np.flatnonzero(bnd)[~ok]:
            rep.add("boundary_not_segment", f"boundary edge ({src[e]}, {dst[e]}) of triangle "
                                            f"{tid[e]} is not a segment or piece of one")
    else:
        raise ValueError(f"domain must be 'hull' or 'segments', got {domain!r}")

    # -- submerged vertices: inside the triangulation, and (weighted) really submerged ---
    if k and sub.any():
        _check_submerged(rep, P, w, ex, T, np.flatnonzero(sub), domain, stats)

    # -- (6) locally Delaunay / locally regular ------------------------------------------
    inner = np.flatnonzero(has_twin & (src < dst))
    if len(seg_edge_keys) and exempt_segments:
        inner = inner[~np.isin(ukey[inner], seg_edge_keys)]
    if len(inner):
        a, b, c = src[inner], dst[inner], opp[inner]
        d = opp[twin[inner]]
        s = _incircle_signs(P, w, ex, a, b, c, d, stats)
        stats["delaunay_checked_edges"] = int(len(inner))
        stats["cocircular_ties"] = int((s == 0).sum())
        name = "not_regular" if w is not None else "not_delaunay"
        for j in np.flatnonzero(s > 0):
            e = inner[j]
            rep.add(name, f"edge ({a[j]}, {b[j]}) between triangles {tid[e]} and "
                          f"{tid[twin[e]]} is not locally {'regular' if w is not None else 'Delaunay'}: "
                          f"vertex {d[j]} {_fmt_pt(P, d[j])} is strictly inside the "
                          f"{'power circle' if w is not None else 'circumcircle'} of "
                          f"({a[j]}, {b[j]}, {c[j]})")
    else:
        stats["delaunay_checked_edges"] = 0
        stats["cocircular_ties"] = 0
    return rep.finish()


def _check_segments(rep, P, ex, S, src, dst, ukey, n, stats) -> np.ndarray:
    """Check every segment is an edge or a chain of collinear edges; return the keys of
    all edges that are segments or segment pieces."""
    m = S.shape[0]
    stats["segments"] = m
    bad = ((S < 0) | (S >= n)).any(axis=1)
    for j in np.flatnonzero(bad):
        rep.add("segment_index", f"segment {j} {S[j].tolist()} refers to a vertex out of range")
    zero = ~bad & (S[:, 0] == S[:, 1])
    for j in np.flatnonzero(zero):
        rep.add("segment_degenerate", f"segment {j} {S[j].tolist()} has equal endpoints")
    good = np.flatnonzero(~bad & ~zero)
    skeys = np.minimum(S[good, 0], S[good, 1]) * n + np.maximum(S[good, 0], S[good, 1])
    uniq_edges = np.unique(ukey)
    present = np.isin(skeys, uniq_edges)
    keys = [skeys[present]]
    missing = good[~present]
    stats["segments_split"] = 0
    if len(missing):
        # adjacency (CSR) of the undirected edge graph
        a = np.concatenate([src, dst])
        b = np.concatenate([dst, src])
        order = np.argsort(a, kind="stable")
        a, b = a[order], b[order]
        starts = np.searchsorted(a, np.arange(n + 1))
        exact = ex.get()
        pieces = []
        for j in missing:
            i, t = int(S[j, 0]), int(S[j, 1])
            c = i
            chain = [i]
            while c != t:
                nbrs = np.unique(b[starts[c]:starts[c + 1]])
                nxt = [int(q) for q in nbrs if _segment_walk_ok(exact, i, t, c, int(q))]
                if not nxt:
                    break
                # the nearest vertex on the segment beyond c (vertices are distinct)
                if len(nxt) > 1:
                    dx, dy = exact.X[t] - exact.X[i], exact.Y[t] - exact.Y[i]
                    nxt.sort(key=lambda q: dx * (exact.X[q] - exact.X[i]) + dy * (exact.Y[q] - exact.Y[i]))
                c = nxt[0]
                chain.append(c)
            if c != t:
                rep.add("missing_segment",
                        f"segment {j} ({i}, {t}) {_fmt_pt(P, i)}-{_fmt_pt(P, t)} is not an edge "
                        f"nor a chain of collinear edges (chain {chain} stops at vertex {c})")
            else:
                stats["segments_split"] += 1
                for p, q in zip(chain[:-1], chain[1:]):
                    pieces.append(min(p, q) * n + max(p, q))
        keys.append(np.asarray(pieces, dtype=np.int64))
    return np.unique(np.concatenate(keys)) if keys else np.zeros(0, dtype=np.int64)


def _check_hull(rep, P, ex, T, bsrc, bdst, used, sub, stats) -> None:
    """Boundary edges == CCW convex hull pieces; exact area of triangles == hull area."""
    idx = np.flatnonzero(used)
    hull = _convex_hull(P, idx, ex, stats)
    if hull is None:
        rep.add("hull", "the used vertices are all collinear but there are triangles")
        return
    stats["hull_vertices"] = len(hull)
    expected = set(zip(hull, hull[1:] + hull[:1]))
    got = set(zip(bsrc.tolist(), bdst.tolist()))
    for (u, v) in sorted(expected - got):
        rep.add("hull_not_covered", f"convex hull edge ({u}, {v}) {_fmt_pt(P, u)}-{_fmt_pt(P, v)} "
                                    "is not a boundary edge of the triangulation")
    for (u, v) in sorted(got - expected):
        rep.add("boundary_not_hull", f"boundary edge ({u}, {v}) {_fmt_pt(P, u)}-{_fmt_pt(P, v)} "
                                     "is not on the convex hull (a hole, gap or T-junction)")
    # exact areas (twice the area, scaled by 4**D)
    exact = ex.get()
    dbl = exact.orient_value(T[:, 0], T[:, 1], T[:, 2]).sum() if len(T) else 0
    h = np.asarray(hull, dtype=np.int64)
    h2 = np.roll(h, -1)
    hull_dbl = (exact.X[h] * exact.Y[h2] - exact.X[h2] * exact.Y[h]).sum()
    scale = Fraction(1, 2 * 4 ** exact.D)
    tri_area, hull_area = Fraction(int(dbl)) * scale, Fraction(int(hull_dbl)) * scale
    stats["area"] = tri_area
    stats["hull_area"] = hull_area
    if tri_area != hull_area:
        rep.add("area", f"total triangle area {float(tri_area)!r} != convex hull area "
                        f"{float(hull_area)!r} (exact difference {tri_area - hull_area})")


def _check_submerged(rep, P, w, ex, T, subs, domain, stats) -> None:
    """Each submerged vertex must lie in some triangle (closed); with weights its lifted
    point must not lie strictly below the plane of that lifted triangle (otherwise it
    should have been a vertex of the regular triangulation, Sec. 2.8)."""
    X, Y = P[T, 0], P[T, 1]
    lo_x, hi_x, lo_y, hi_y = X.min(axis=1), X.max(axis=1), Y.min(axis=1), Y.max(axis=1)
    for v in subs:
        x, y = P[v]
        cand = np.flatnonzero((lo_x <= x) & (x <= hi_x) & (lo_y <= y) & (y <= hi_y))
        inside = np.ones(len(cand), dtype=bool)
        for j in range(3):
            a, b = T[cand, j], T[cand, (j + 1) % 3]
            inside &= _orient_signs(P, ex, a, b, np.full(len(cand), v), stats) >= 0
        cand = cand[inside]
        if len(cand) == 0:
            if domain == "hull":
                rep.add("submerged_outside", f"submerged vertex {v} {_fmt_pt(P, v)} lies "
                                             "outside the triangulation")
            continue
        if w is None:
            continue
        t = cand[:1]
        s = _incircle_signs(P, w, ex, T[t, 0], T[t, 1], T[t, 2], np.array([v]), stats)
        if s[0] > 0:
            rep.add("not_submerged", f"vertex {v} {_fmt_pt(P, v)} is left out but its lifted "
                                     f"point lies strictly below the lifted triangle {int(t[0])} "
                                     f"{T[t[0]].tolist()}: it must be a vertex")


def assert_valid(points, triangles, **kwargs) -> CheckReport:
    """Run :func:`check_triangulation`; raise AssertionError listing the first problems."""
    rep = check_triangulation(points, triangles, **kwargs)
    if not rep.ok:
        raise AssertionError(f"invalid triangulation: {rep.kinds}\n  "
                             + "\n  ".join(rep.problems[:10]))
    return rep


# ----------------------------------------------------------------------------------------
# all-collinear input and order-independent comparison
# ----------------------------------------------------------------------------------------

def check_collinear_edges(points, edges) -> CheckReport:
    """All-collinear input (Sec. 2.1: no triangles, only edges): the points must be exactly
    collinear and distinct, and the edges the n - 1 edges joining consecutive points in
    order along the line (each point covered)."""
    rep = CheckReport()
    P = np.asarray(points, dtype=np.float64)
    E = np.asarray(edges)
    if E.size == 0:
        E = np.zeros((0, 2), dtype=np.int64)
    n = P.shape[0]
    rep.counts.update(vertices=n, edges=int(E.shape[0]))
    if P.ndim != 2 or P.shape[1] != 2 or not np.isfinite(P).all():
        rep.add("input", "points must be a finite (n, 2) array")
        return rep.finish()
    if E.ndim != 2 or E.shape[1] != 2 or ((E < 0) | (E >= n)).any():
        rep.add("input", f"edges must be (m, 2) indices in 0..{n - 1}")
        return rep.finish()
    order = np.lexsort((P[:, 1], P[:, 0]))
    ex = _Lazy(P, None)
    stats: Dict = rep.counts
    eq = (P[order[1:], 0] == P[order[:-1], 0]) & (P[order[1:], 1] == P[order[:-1], 1])
    for s in np.flatnonzero(eq):
        rep.add("coincident_vertices", f"vertices {order[s]} and {order[s + 1]} coincide")
    if n >= 3:
        a, b = order[0], order[-1]
        rest = order[1:-1]
        s = _orient_signs(P, ex, np.full(len(rest), a), np.full(len(rest), b), rest, stats)
        for v in rest[s != 0]:
            rep.add("not_collinear", f"vertex {v} {_fmt_pt(P, v)} is not on the line through "
                                     f"vertices {a} and {b}")
    expected = {(min(p, q), max(p, q)) for p, q in zip(order[:-1].tolist(), order[1:].tolist())}
    got_list = [(min(int(p), int(q)), max(int(p), int(q))) for p, q in E]
    got = set(got_list)
    if len(got) != len(got_list):
        rep.add("duplicate_edge", "some edges are repeated")
    for e in sorted(expected - got):
        rep.add("missing_edge", f"edge {e} between consecutive collinear points is missing")
    for e in sorted(got - expected):
        rep.add("extra_edge", f"edge {e} does not join consecutive points along the line")
    return rep.finish()


def canonical_triangles(points, triangles) -> Set[Tuple[Tuple[float, float], ...]]:
    """The triangles as a set of sorted coordinate triples: compares two triangulations
    independently of vertex numbering, triangle order and corner rotation."""
    P = np.asarray(points, dtype=np.float64)
    T = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    out = set()
    for t in T:
        out.add(tuple(sorted((float(P[i, 0]) + 0.0, float(P[i, 1]) + 0.0) for i in t)))
    return out


def check_steiner_segments(in_points, in_segments, out_points, vertex_map, pieces, piece_ids,
                           ulps: int = 4, partial: bool = False,
                           snapped_inputs: bool = False) -> CheckReport:
    """Refined output against its input PLC: every input segment ``s`` is the chain of the
    pieces with ``piece_ids == s``, from its first to its last endpoint, through vertices
    in strictly increasing order along it; each chain vertex that is an input point lies
    exactly on the segment, and each other (Steiner) vertex lies within ``ulps`` units in
    the last place of the segment's largest coordinate magnitude of the exact segment
    (the rounding of ``A + t (B - A)``) and strictly between its ends. Exact arithmetic.

    ``partial``: pieces outside the kept domain are not listed, so a segment's pieces
    may be any part of its chain: none, or paths along it in order that do not overlap
    (that the listed ones are all that border the domain is the domain check's job).

    ``snapped_inputs``: an input point in a chain may lie within ``ulps`` of the
    segment, like a Steiner point (a crossing whose nearest double is that input
    point, met where segments cross within rounding of each other)."""
    rep = CheckReport()
    P = np.asarray(in_points, np.float64)
    V = np.asarray(out_points, np.float64)
    vm = np.asarray(vertex_map, np.int64)
    S = np.asarray(in_segments, np.int64).reshape(-1, 2)
    pieces = np.asarray(pieces, np.int64).reshape(-1, 2)
    piece_ids = np.asarray(piece_ids, np.int64)
    is_input = np.zeros(len(V), bool)
    if not snapped_inputs:
        is_input[vm[vm >= 0]] = True
    first: Dict[Tuple[int, int], int] = {}
    for s, (a, b) in enumerate(S):
        A, B = vm[a], vm[b]
        if A == B:
            continue
        # a repeated segment is merged into its first occurrence
        owner = first.setdefault((min(A, B), max(A, B)), s)
        mine = pieces[piece_ids == owner]
        if partial:
            _check_partial_chain(rep, s, int(A), int(B), mine, V, is_input, ulps)
            continue
        if len(mine) == 0:
            rep.add("segment_missing", f"segment {s} has no pieces in the output")
            continue
        adj: Dict[int, List[int]] = {}
        for u, v in mine.tolist():
            adj.setdefault(u, []).append(v)
            adj.setdefault(v, []).append(u)
        chain, prev, cur = [int(A)], -1, int(A)
        while cur != B:
            nxt_ = [w for w in adj.get(cur, []) if w != prev]
            if len(nxt_) != 1 or len(chain) > len(mine) + 1:
                rep.add("segment_chain", f"the pieces of segment {s} do not form one path from "
                                         f"vertex {A} to vertex {B} (stuck at {cur})")
                break
            prev, cur = cur, nxt_[0]
            chain.append(cur)
        else:
            if len(chain) != len(mine) + 1:
                rep.add("segment_chain", f"segment {s} has pieces off its path")
        place = _along(rep, s, int(A), int(B), V, is_input, ulps)
        last = Fraction(0)
        for v in chain[1:-1]:
            t = place(v)
            if not last < t < 1:
                rep.add("segment_order", f"vertex {v} is out of order along segment {s}")
            last = t
    return rep.finish()


def _along(rep, s, A, B, V, is_input, ulps):
    """``place(v)``: the exact parameter of vertex ``v`` along segment ``s`` (A -> B), after
    checking that it lies on the segment (exactly for an input point, within ``ulps``
    for a Steiner point)."""
    ax, ay, bx, by = (Fraction(float(c)) for c in (V[A, 0], V[A, 1], V[B, 0], V[B, 1]))
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    scale = max(abs(float(c)) for c in (V[A, 0], V[A, 1], V[B, 0], V[B, 1]))
    tol = Fraction(ulps) * Fraction(float(np.spacing(scale if scale > 0 else 1.0)))

    def place(v):
        if v in (A, B):
            return Fraction(0 if v == A else 1)
        px, py = Fraction(float(V[v, 0])) - ax, Fraction(float(V[v, 1])) - ay
        cross = dx * py - dy * px
        if is_input[v]:
            if cross != 0:
                rep.add("off_segment", f"input vertex {v} on segment {s} is not exactly on it")
        elif cross * cross > tol * tol * L2:
            rep.add("off_segment", f"Steiner vertex {v} {_fmt_pt(V, v)} lies "
                                   f"{float(abs(cross)) / float(L2) ** 0.5:.3g} off segment {s}, "
                                   f"more than {ulps} ulps")
        return (dx * px + dy * py) / L2
    return place


def _check_partial_chain(rep, s, A, B, mine, V, is_input, ulps):
    """The listed pieces of segment ``s`` lie on it, in order, without overlapping."""
    place = _along(rep, s, A, B, V, is_input, ulps)
    spans = sorted(sorted((place(int(u)), place(int(v)))) for u, v in mine.tolist())
    end = Fraction(0)
    for lo, hi in spans:
        if not (0 <= lo < hi <= 1) or lo < end:
            rep.add("segment_order", f"the pieces of segment {s} overlap or leave it")
            return
        end = hi


def check_empty_circumcircles(points, triangles) -> CheckReport:
    """Every triangle is Delaunay (Def. 2.4 / 2.12): no vertex strictly inside its
    circumcircle. Floating-point screen for candidates, exact signs to decide."""
    rep = CheckReport()
    P = np.asarray(points, np.float64)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    bx, by = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    cx, cy = c[:, 0] - a[:, 0], c[:, 1] - a[:, 1]
    d = 2 * (bx * cy - by * cx)
    ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d
    uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d
    centre = np.column_stack([a[:, 0] + ux, a[:, 1] + uy])
    r2 = ux * ux + uy * uy
    for t in range(len(T)):
        dist2 = ((P - centre[t]) ** 2).sum(axis=1)
        for v in np.flatnonzero(dist2 < r2[t] * (1 + 1e-6)):
            if v in T[t]:
                continue
            if incircle_exact(P[T[t, 0]], P[T[t, 1]], P[T[t, 2]], P[v]) > 0:
                rep.add("not_delaunay", f"vertex {v} {_fmt_pt(P, v)} is inside the circumcircle "
                                        f"of triangle {t} {T[t].tolist()}")
    return rep.finish()
