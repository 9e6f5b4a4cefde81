"""Store sanity check for the half-edge store of ``cdt_plugin._core.mesh``
(spade's ``sanity_check`` of its DCEL, in plain Python and NumPy).

This module imports nothing from the engine: it reads the documented layout
from scratch. Triangle ``t`` owns half-edges ``3t, 3t+1, 3t+2``; ``tri[e]`` is
the origin of half-edge ``e`` (it runs to ``tri[nxt(e)]``), ``twin[e]`` the
opposite half-edge, ``cons[e]`` the 1-based segment id (0: none; the array may
be empty); ghost triangles share the infinite vertex ``inf``; a dead triangle
has ``tri[3t] == DEAD``.

:func:`store_defects` lists every broken invariant, :func:`sanity_check`
raises on the first list that is not empty. :func:`to_arrays` and
:func:`check_store` hand the solid triangles to the exact checker
(``tests/checker.py``) for orientation and the (constrained) Delaunay property.
"""
from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np

from checker import assert_valid

DEAD = -2   # mesh.DEAD, restated: this module reads the layout, it does not import it

__all__ = ["DEAD", "StoreDefect", "store_defects", "sanity_check", "live_triangles",
           "solid_slots", "ghost_slots", "to_arrays", "constrained_pairs", "check_store",
           "nxt", "prv"]


class StoreDefect(AssertionError):
    """A store that breaks its invariants; ``defects`` lists every one found."""

    def __init__(self, defects: List[str]):
        self.defects = defects
        super().__init__(f"{len(defects)} store defect(s):\n  " + "\n  ".join(defects[:20]))


def nxt(e: int) -> int:
    return e - 2 if e % 3 == 2 else e + 1


def prv(e: int) -> int:
    return e + 2 if e % 3 == 0 else e - 1


def _arrays(tri, twin, cons, ntri):
    tri = np.asarray(tri).astype(np.int64)
    twin = np.asarray(twin).astype(np.int64)
    cons = np.asarray(cons).astype(np.int64)
    return tri, twin, cons, int(ntri)


def live_triangles(tri, ntri) -> List[int]:
    """Triangle slots ``0..ntri-1`` that are not dead."""
    tri = np.asarray(tri)
    return [t for t in range(int(ntri)) if tri[3 * t] != DEAD]


def ghost_slots(tri, ntri, inf) -> List[int]:
    tri = np.asarray(tri)
    return [t for t in live_triangles(tri, ntri) if inf in tri[3 * t:3 * t + 3].tolist()]


def solid_slots(tri, ntri, inf) -> List[int]:
    tri = np.asarray(tri)
    return [t for t in live_triangles(tri, ntri) if inf not in tri[3 * t:3 * t + 3].tolist()]


def store_defects(tri, twin, cons, ntri, inf) -> List[str]:
    """Every broken store invariant, as messages naming slots (empty: a sane store).

    Checked: array sizes; live triangles have three distinct vertices in
    ``0..inf``; every live half-edge has a twin in another live triangle,
    ``twin[twin[e]] == e`` and the twins run in opposite directions; ``cons``
    (if present) is non-negative, equal on both halves of an edge and zero on
    edges at ``inf``; every ghost has exactly one ``inf`` and the ghosts form
    one closed ring (the link of ``inf`` is a single cycle through every ghost,
    at least three of them); the link of every real vertex is a single cycle;
    Euler's formula for the sphere closed by ``inf`` (V - E + F = 2).
    """
    tri, twin, cons, ntri = _arrays(tri, twin, cons, ntri)
    inf = int(inf)
    out: List[str] = []
    if ntri < 0 or 3 * ntri > tri.shape[0] or 3 * ntri > twin.shape[0]:
        return [f"size: ntri={ntri} does not fit tri ({tri.shape[0]}) / twin ({twin.shape[0]})"]
    has_cons = cons.shape[0] > 0
    if has_cons and cons.shape[0] < 3 * ntri:
        return [f"size: cons has {cons.shape[0]} entries, fewer than 3*ntri={3 * ntri}"]
    live = np.zeros(ntri, bool)
    for t in range(ntri):
        live[t] = tri[3 * t] != DEAD
    if not live.any():
        return ["empty: no live triangle"]

    # -- triangles: vertex range, no repeated vertex ---------------------------------
    for t in np.flatnonzero(live):
        vs = tri[3 * t:3 * t + 3].tolist()
        if any(v < 0 or v > inf for v in vs):
            out.append(f"vertex: triangle {t} {vs} has a vertex outside 0..inf={inf}")
        if len(set(vs)) != 3:
            out.append(f"repeat: triangle {t} {vs} repeats a vertex")
    if out:
        return out

    # -- twins ---------------------------------------------------------------------
    for t in np.flatnonzero(live):
        for e in range(3 * t, 3 * t + 3):
            f = twin[e]
            if not 0 <= f < 3 * ntri:
                out.append(f"twin: half-edge {e} has no twin ({f})")
                continue
            if not live[f // 3]:
                out.append(f"dead: half-edge {e} twins {f} in dead triangle {f // 3}")
                continue
            if f // 3 == e // 3:
                out.append(f"twin: half-edge {e} twins {f} in its own triangle")
            if twin[f] != e:
                out.append(f"twin: twin[twin[{e}]] = {twin[f]}, not {e}")
            if tri[e] != tri[nxt(f)] or tri[nxt(e)] != tri[f]:
                out.append(f"direction: half-edge {e} ({tri[e]}->{tri[nxt(e)]}) and its twin "
                           f"{f} ({tri[f]}->{tri[nxt(f)]}) do not run in opposite directions")
            if has_cons:
                if cons[e] < 0:
                    out.append(f"cons: half-edge {e} has negative segment id {cons[e]}")
                if cons[e] != cons[f]:
                    out.append(f"cons: half-edge {e} has segment {cons[e]}, its twin {f} {cons[f]}")
                if cons[e] != 0 and (tri[e] == inf or tri[nxt(e)] == inf):
                    out.append(f"cons: half-edge {e} at the infinite vertex is on segment {cons[e]}")
    if out:
        return out

    # -- ghosts: one inf each, one closed ring around the hull ---------------------
    ghosts = [t for t in np.flatnonzero(live) if inf in tri[3 * t:3 * t + 3].tolist()]
    succ = {}          # hull edge u -> v of each ghost (outside on its left)
    for t in ghosts:
        vs = tri[3 * t:3 * t + 3].tolist()
        if vs.count(inf) != 1:
            out.append(f"ghost: triangle {t} {vs} has {vs.count(inf)} infinite vertices")
            continue
        k = vs.index(inf)
        u, v = vs[(k + 1) % 3], vs[(k + 2) % 3]
        if u in succ:
            out.append(f"ghost ring: vertex {u} starts two hull edges (ghosts {succ[u][1]} and {t})")
        succ[u] = (v, t)
    if len(ghosts) < 3:
        out.append(f"ghost ring: {len(ghosts)} ghost triangles, a closed hull needs at least 3")
    if out:
        return out
    u0 = next(iter(succ))
    u, seen = u0, 0
    while True:
        seen += 1
        if u not in succ or seen > len(succ):
            break
        u = succ[u][0]
        if u == u0:
            break
    if u != u0 or seen != len(succ):
        out.append(f"ghost ring: the link of inf is not one cycle through all {len(succ)} ghosts "
                   f"(the cycle from vertex {u0} closes after {seen})")

    # -- every vertex link a single cycle, Euler characteristic --------------------
    leaving = {}
    for t in np.flatnonzero(live):
        for e in range(3 * t, 3 * t + 3):
            leaving.setdefault(int(tri[e]), []).append(e)
    for v, es in leaving.items():
        e0 = es[0]
        e, n = e0, 0
        while True:
            n += 1
            e = int(twin[prv(e)])          # the next half-edge leaving v, counter-clockwise
            if e == e0 or n > len(es):
                break
        if n != len(es):
            out.append(f"vertex link: the triangles around vertex {v} form more than one fan "
                       f"({n} of {len(es)} reached from half-edge {e0})")
    nf = int(live.sum())
    ne = 3 * nf // 2
    if 3 * nf % 2 or len(leaving) - ne + nf != 2:
        out.append(f"euler: V - E + F = {len(leaving)} - {ne} + {nf} != 2")
    return out


def sanity_check(tri, twin, cons, ntri, inf) -> dict:
    """Raise :class:`StoreDefect` unless the store keeps every invariant of
    :func:`store_defects`. Returns counts (solid, ghost, dead triangles, and the
    hull vertices in ghost-ring order) for tests to assert on."""
    defects = store_defects(tri, twin, cons, ntri, inf)
    if defects:
        raise StoreDefect(defects)
    tri = np.asarray(tri)
    solid = solid_slots(tri, ntri, inf)
    ghosts = ghost_slots(tri, ntri, inf)
    return {"solid": len(solid), "ghosts": len(ghosts),
            "dead": int(ntri) - len(solid) - len(ghosts),
            "vertices": sorted({int(v) for t in solid for v in tri[3 * t:3 * t + 3]})}


def to_arrays(tri, ntri, inf, x, y, slots: Optional[List[int]] = None,
              with_ids: bool = False) -> Tuple[np.ndarray, ...]:
    """The solid triangles of a store (or only ``slots``) as ``(vertices,
    triangles)`` for the exact checker: the vertices they use, renumbered in
    increasing mesh id, and the triangles in those ids (as stored, so an
    orientation error in the store is an orientation error here). With
    ``with_ids`` also the mesh id of each vertex."""
    tri = np.asarray(tri).astype(np.int64)
    if slots is None:
        slots = solid_slots(tri, ntri, inf)
    T = np.array([tri[3 * t:3 * t + 3] for t in slots], np.int64).reshape(-1, 3)
    ids = np.unique(T)
    new = {int(v): i for i, v in enumerate(ids)}
    V = np.column_stack([np.asarray(x, float)[ids], np.asarray(y, float)[ids]])
    Tn = np.array([[new[int(v)] for v in row] for row in T], np.int64).reshape(-1, 3)
    return (V, Tn, ids) if with_ids else (V, Tn)


def constrained_pairs(tri, cons, ntri) -> dict:
    """``{(u, v): segment id}`` (u < v, mesh ids) of every constrained edge."""
    tri, cons = np.asarray(tri), np.asarray(cons)
    out = {}
    if cons.shape[0] == 0:
        return out
    for t in live_triangles(tri, ntri):
        for e in range(3 * t, 3 * t + 3):
            if cons[e] != 0:
                u, v = int(tri[e]), int(tri[nxt(e)])
                out[(min(u, v), max(u, v))] = int(cons[e])
    return out


def check_store(tri, twin, cons, ntri, inf, x, y, *, constrained=True, weights=None,
                **checker_kw):
    """:func:`sanity_check` plus the exact checker on the solid triangles (with
    the constrained edges as segments when ``constrained``: they are exempt from
    the Delaunay test and must be edges; ``weights`` by mesh id for the weighted
    test). Returns the sanity counts."""
    counts = sanity_check(tri, twin, cons, ntri, inf)
    V, T, ids = to_arrays(tri, ntri, inf, x, y, with_ids=True)
    if weights is not None:
        checker_kw["weights"] = np.asarray(weights, float)[ids]
    if constrained and np.asarray(cons).shape[0] > 0:
        pos = {int(v): i for i, v in enumerate(ids)}
        segs = [(pos[u], pos[v]) for (u, v) in constrained_pairs(tri, cons, ntri)
                if u in pos and v in pos]
        if segs:
            checker_kw.setdefault("segments", np.array(segs, np.int64))
    counts["report"] = assert_valid(V, T, **checker_kw)
    return counts
