"""Certificates on a finished triangulation (output arrays only): every triangle's
exact orientation, the Delaunay Lemma (2.3) check that every interior edge is locally Delaunay, its weighted
analogue, and the uniqueness test of Theorem 2.11."""
from __future__ import annotations

import numpy as np

from .jit import entry, kernel
from .predicates import incircle, incircle_weighted, orient2d
from .query import OUTSIDE, walk


@entry
def orientation_signs(x, y, triangles):
    """Exact orientation sign of every triangle (+1 counter-clockwise, 0 flat)."""
    out = np.empty(triangles.shape[0], np.int64)
    for k in range(triangles.shape[0]):
        a, b, c = triangles[k, 0], triangles[k, 1], triangles[k, 2]
        r = orient2d(x[a], y[a], x[b], y[b], x[c], y[c])
        out[k] = 1 if r > 0 else (-1 if r < 0 else 0)
    return out


@kernel
def opposite_vertex(triangles, neighbors, k, m):
    """The vertex of triangle ``m`` opposite its shared edge with ``k``."""
    for j in range(3):
        if neighbors[m, j] == k:
            return triangles[m, j]
    return -1


@entry
def edge_lifted_values(vx, vy, vw, weighted, triangles, neighbors):
    """For every interior edge (listed once): the sign of the exact lifted test of
    the far vertex against the near triangle (> 0: not locally Delaunay,
    0: cocircular / lifted-coplanar tie). Returns (k, j, sign) rows."""
    out = np.empty((3 * triangles.shape[0], 3), np.int64)
    n = 0
    for k in range(triangles.shape[0]):
        a = triangles[k, 0]
        b = triangles[k, 1]
        c = triangles[k, 2]
        for j in range(3):
            m = neighbors[k, j]
            if m < 0 or m < k:
                continue
            d = opposite_vertex(triangles, neighbors, k, m)
            if weighted:
                r = incircle_weighted(vx[a], vy[a], vw[a], vx[b], vy[b], vw[b],
                                      vx[c], vy[c], vw[c], vx[d], vy[d], vw[d])
            else:
                r = incircle(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c], vx[d], vy[d])
            out[n, 0] = k
            out[n, 1] = j
            out[n, 2] = 1 if r > 0 else (-1 if r < 0 else 0)
            n += 1
    return out[:n]


@kernel
def locate_in_arrays(vx, vy, triangles, neighbors, px, py, start=0):
    """Triangle containing point (px, py) (closed), by a visibility walk over
    ``neighbors`` from triangle ``start``; -1 if outside the triangulation."""
    t, code, _ = walk(triangles, neighbors, vx, vy, px, py, start)
    return -1 if code == OUTSIDE else t


@entry
def locate_all(vx, vy, triangles, neighbors, px, py):
    """:func:`locate_in_arrays` for many points, each walk starting where the
    previous one ended (nearby points in a row walk a few steps)."""
    out = np.full(px.shape[0], -1, np.int64)
    k = 0
    for i in range(px.shape[0]):
        out[i] = locate_in_arrays(vx, vy, triangles, neighbors, px[i], py[i], k)
        if out[i] >= 0:
            k = out[i]
    return out


@entry
def submerged_ok(vx, vy, vw, triangles, neighbors, sx, sy, sw):
    """For each submerged point: 1 if its lifted point lies on or above the lifted
    triangulation (so leaving it out is right), else 0."""
    ok = np.zeros(sx.shape[0], np.int8)
    for i in range(sx.shape[0]):
        k = locate_in_arrays(vx, vy, triangles, neighbors, sx[i], sy[i], np.int64(0))
        if k < 0:
            continue
        a = triangles[k, 0]
        b = triangles[k, 1]
        c = triangles[k, 2]
        r = incircle_weighted(vx[a], vy[a], vw[a], vx[b], vy[b], vw[b],
                              vx[c], vy[c], vw[c], sx[i], sy[i], sw[i])
        ok[i] = 1 if r <= 0 else 0
    return ok
