"""Moving points: a triangulation that follows them, and values sampled at fixed probes.

    python examples/moving_points.py [out/moving_points.png]

Left: 600 points advected by a swirl (a vortex centred in the unit square, fastest
half-way out). Each step moves every point a little and restores the Delaunay
property with :meth:`cdt_plugin.Triangulation.move_vertices` (edge flips, Sec. 2.5;
a rebuild if a triangle inverted); a tracer carried by the points (their starting
height) is sampled at a fixed 9 x 9 grid of probes with Sibson's natural neighbour
interpolation (:meth:`cdt_plugin.Triangulation.interpolate`).

Right: a flow from left to right through a channel with an obstacle (a segment loop
kept as constraints) in a :class:`cdt_plugin.DynamicCDT`: each step moves the points,
inserts new ones at the inlet and removes those that left at the outlet.

Prints the flips per step and checks every triangulation (Delaunay, the snapshot
equal to a triangulation from scratch) as it goes.
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import cdt_plugin

STEPS = 40


def swirl(P: np.ndarray) -> np.ndarray:
    """Velocity of the vortex at points ``P``."""
    d = P - 0.5
    r = np.hypot(d[:, 0], d[:, 1])
    speed = 4 * r * np.exp(-((r / 0.25) ** 2))
    return np.column_stack([-d[:, 1], d[:, 0]]) * speed[:, None]


def advect(rng: np.random.Generator):
    """The swirl: returns the final triangulation, the tracer and the probe samples."""
    P = rng.random((600, 2))
    tracer = P[:, 1].copy()
    tri = cdt_plugin.delaunay(P)
    probes = np.stack(np.meshgrid(np.linspace(0.1, 0.9, 9), np.linspace(0.1, 0.9, 9)), -1).reshape(-1, 2)
    samples = []
    for step in range(STEPS):
        P = P + 0.15 * swirl(P)
        flips = tri.move_vertices(P)
        assert tri.is_delaunay()
        samples.append(tri.interpolate(tracer, probes, method="natural"))
        if step % 10 == 0:
            print(f"swirl step {step:2d}: {flips} flips, rebuilt: {tri.stats['rebuilt']}")
    return tri, tracer, probes, np.array(samples)


def channel(rng: np.random.Generator) -> cdt_plugin.DynamicCDT:
    """The channel flow in a live triangulation with an obstacle."""
    corners = [[0, 0], [3, 0], [3, 1], [0, 1]]
    obstacle = [[1.2, 0.4], [1.5, 0.4], [1.5, 0.6], [1.2, 0.6]]
    dyn = cdt_plugin.DynamicCDT(corners + obstacle)
    fixed = set(range(8))
    dyn.insert_segments([[4, 5], [5, 6], [6, 7], [7, 4]])
    free = list(dyn.insert_points(rng.random((300, 2)) * [3, 1]))
    for step in range(STEPS):
        ids = np.array([i for i in free if i not in fixed])
        xy = dyn.vertices[np.searchsorted(dyn.vertex_ids, ids)]
        new = xy + [0.05, 0.0] + rng.normal(0, 0.004, xy.shape)
        new[:, 1] = np.clip(new[:, 1], 0.001, 0.999)
        # points that would enter the obstacle or leave at the outlet go
        gone = (new[:, 0] >= 2.999) | ((new[:, 0] > 1.19) & (new[:, 0] < 1.51) & (new[:, 1] > 0.39) & (new[:, 1] < 0.61))
        dyn.remove_vertices(ids[gone])
        stay = ids[~gone]
        dyn.move_vertices(stay, new[~gone])
        inlet = np.column_stack([rng.random(8) * 0.05, rng.random(8)])
        free = list(stay) + list(dyn.insert_points(inlet))
        if step % 10 == 0:
            tri = dyn.triangulation()
            assert tri.is_delaunay()
            fresh = cdt_plugin.triangulate(dyn.vertices, dyn.segments, keep_hull=True)
            assert len(fresh.triangles) == len(tri.triangles)
            print(f"channel step {step:2d}: {len(dyn)} vertices, {len(tri.triangles)} triangles")
    return dyn


def main(out: str = "examples/moving_points.png") -> None:
    rng = np.random.default_rng(7)
    tri, tracer, probes, samples = advect(rng)
    dyn = channel(rng)
    drift = np.nanmax(np.abs(samples[-1] - samples[0]))
    print(f"tracer at the probes changed by up to {drift:.2f} over {STEPS} steps")
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(13, 4.6), gridspec_kw={"width_ratios": [1, 2.2]})
    ax0.tripcolor(tri.vertices[:, 0], tri.vertices[:, 1], tri.triangles, tracer, shading="gouraud",
                  cmap="viridis")
    ax0.triplot(tri.vertices[:, 0], tri.vertices[:, 1], tri.triangles, lw=0.3, color="white")
    ax0.plot(probes[:, 0], probes[:, 1], "r.", ms=3)
    ax0.set_title(f"swirl after {STEPS} steps (move_vertices); probes in red")
    snap = dyn.triangulation()
    V = snap.vertices
    ax1.triplot(V[:, 0], V[:, 1], snap.triangles, lw=0.4, color="0.3")
    for a, b in snap.segments:
        ax1.plot(V[[a, b], 0], V[[a, b], 1], "r-", lw=1.5)
    ax1.set_title(f"channel flow in a DynamicCDT: {len(dyn)} vertices, obstacle segments in red")
    for ax in (ax0, ax1):
        ax.set_aspect("equal")
        ax.set_axis_off()
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110, bbox_inches="tight")
    print("wrote", out)


if __name__ == "__main__":
    main(*sys.argv[1:])
