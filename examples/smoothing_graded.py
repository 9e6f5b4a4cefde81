"""A graded mesh before and after smoothing, plotted to PNG.

    python examples/smoothing_graded.py [out/smoothing.png]

A plate with a hole and a slit, meshed at 25 degrees with a size that is fine at
the hole (0.03) and grows linearly away from it (Triangle's ``-u`` size test,
``suitable=``), then smoothed by 10 ODT iterations
(:meth:`cdt_plugin.Triangulation.smooth`, the mesh's own sizes as the density).
Prints the smallest angle, the mean radius ratio and the size ratio before and
after, and checks the guarantees (input vertices unmoved, constrained Delaunay,
smallest angle not lower). Draws both meshes, each triangle coloured by its radius
ratio (2 r / R: 1 for an equilateral triangle), and the two histograms.
"""
from __future__ import annotations

import io
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cdt_plugin  # noqa: E402
from cdt_plugin.report import triangle_quality  # noqa: E402
from cdt_plugin.smoothing import mesh_quality  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
CENTRE, RADIUS = np.array([1.2, 1.0]), 0.35


def size(x, y):
    """Target edge length: 0.03 on the hole, growing by 0.25 per unit away from it."""
    return 0.03 + 0.25 * np.maximum(np.hypot(x - CENTRE[0], y - CENTRE[1]) - RADIUS, 0.0)


def plate() -> tuple[np.ndarray, list[list[int]]]:
    """A 4 x 2 plate with a round hole and a slit (an interior segment)."""
    t = np.linspace(0.0, 2.0 * np.pi, 40, endpoint=False)
    hole = CENTRE + RADIUS * np.column_stack([np.cos(t), np.sin(t)])
    pts = np.vstack([[[0, 0], [4, 0], [4, 2], [0, 2]], hole, [[2.4, 0.6], [3.4, 1.4]]])
    segs = [[i, (i + 1) % 4] for i in range(4)] + [[4 + i, 4 + (i + 1) % 40] for i in range(40)]
    return pts, segs + [[44, 45]]


def small_enough(org, dest, apex, area):
    c = (org + dest + apex) / 3
    return area <= np.sqrt(3) / 4 * size(c[:, 0], c[:, 1]) ** 2


def main(argv) -> int:
    out = Path(argv[1]) if len(argv) > 1 else REPO_ROOT / "out" / "smoothing.png"
    pts, segs = plate()
    graded = cdt_plugin.triangulate(pts, segs, holes=[CENTRE], min_angle=25, suitable=small_enough)
    smooth = graded.smooth("odt", 10)
    s = smooth.stats["smoothing"]
    fixed = np.setdiff1d(np.arange(len(pts)), graded.steiner)
    assert np.array_equal(smooth.vertices[fixed], graded.vertices[fixed]) and smooth.is_delaunay()
    assert s["after"]["min_angle"] >= s["before"]["min_angle"]
    before, after = (mesh_quality(t.vertices, t.triangles, size) for t in (graded, smooth))
    print(f"{len(graded.triangles)} triangles, {len(graded.steiner)} Steiner points, "
          f"{s['free_vertices']} free and {s['sliding_vertices']} on segments")
    for name, q in (("before", before), ("after", after)):
        print(f"{name:>6}: min angle {q['min_angle']:.2f} deg, mean radius ratio "
              f"{q['mean_radius_ratio']:.4f}, longest edge / size (median) "
              f"{q['size_ratio_quantiles'][0.5]:.3f}")

    fig, axes = plt.subplot_mosaic([["before", "after"], ["hist", "hist"]], height_ratios=[1.25, 1],
                                   layout="constrained", figsize=(12, 6.6))
    for tri, key, name, q in ((graded, "before", "graded mesh", before),
                              (smooth, "after", "smoothed: ODT, 10 iterations", after)):
        ax = axes[key]
        art = ax.tripcolor(tri.vertices[:, 0], tri.vertices[:, 1], tri.triangles,
                           facecolors=mesh_radius_ratios(tri),
                           cmap="viridis", vmin=0.5, vmax=1.0, edgecolors="0.2", linewidth=0.15)
        for a, b in tri.segments:
            ax.plot(tri.vertices[[a, b], 0], tri.vertices[[a, b], 1], color="tab:red", linewidth=0.8)
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title(f"{name}\nmin angle {q['min_angle']:.1f}°, mean radius ratio {q['mean_radius_ratio']:.3f}")
    fig.colorbar(art, ax=[axes["before"], axes["after"]], shrink=0.8, label="radius ratio 2r/R")
    ax = axes["hist"]
    bins = np.linspace(0.5, 1.0, 26)
    for tri, name in ((graded, "before"), (smooth, "after")):
        ax.hist(mesh_radius_ratios(tri), bins=bins, histtype="step", linewidth=1.5, label=name)
    ax.set_xlabel("radius ratio 2r/R")
    ax.set_ylabel("triangles")
    ax.legend()
    out.parent.mkdir(parents=True, exist_ok=True)
    save_small(fig, out)
    print(f"wrote {out}")
    return 0


def save_small(fig, out: Path) -> None:
    """The figure as a PNG of 128 colours (a fifth of the size of matplotlib's)."""
    from PIL import Image         # (matplotlib's own dependency)
    buffer = io.BytesIO()
    fig.savefig(buffer, dpi=80)
    Image.open(buffer).convert("RGB").quantize(colors=128).save(out, optimize=True)


def mesh_radius_ratios(tri) -> np.ndarray:
    """2 r / R of every triangle, from the report's measurements."""
    q = triangle_quality(tri.vertices, tri.triangles)
    return 2 * q["inradius"] / q["circumradius"]


if __name__ == "__main__":
    sys.exit(main(sys.argv))
