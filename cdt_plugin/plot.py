"""Pictures of a triangulation with matplotlib (the ``plot`` extra).

matplotlib is imported only when a function here is called, so the engine
keeps working without it.

* :func:`plot` draws the triangles (holes and the outside stay empty), the
  segments in bold and the worst triangles (smallest minimum angle) filled, with
  their circumcircles;
* :func:`histogram` draws the angle histogram of the quality report, with the
  ``against`` triangulation's histogram overlaid when given;
* :func:`figure` puts them side by side (and the ``against`` mesh between them)
  and :func:`save` writes that to a file (what ``cdt-plugin ... --plot out.png`` does).

>>> import matplotlib; matplotlib.use("Agg")
>>> import cdt_plugin
>>> from cdt_plugin.plot import plot, histogram
>>> tri = cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]],
...                              [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
>>> ax = tri.plot(worst=1)
>>> len(ax.collections), len(ax.patches)          # triangles, segments, worst fill; 1 circle
(3, 1)
>>> ax = histogram(tri)
>>> sum(int(p.get_height()) for p in ax.patches)    # every angle of the 8 triangles
24
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .optional import require
from .report import ANGLE_BINS, Report, against_arrays, mesh_report, report as quality_report, triangle_quality
from .types import MeshLike, TriangulationLike

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot", "histogram", "figure", "save"]

FACE = "#dbe7f3"
EDGE = "#4a6fa5"
SEGMENT = "#111111"
WORST = "#e4572e"


def _pyplot() -> Any:
    return require("matplotlib.pyplot", "plotting")


def _axes(ax: Axes | None) -> Axes:
    if ax is None:
        _, ax = _pyplot().subplots()
    return ax


def plot(tri: MeshLike, ax: Axes | None = None, *, worst: int = 3, circumcircles: bool = True,
         face_color: str = FACE,
         edge_color: str = EDGE, segment_color: str = SEGMENT, segment_width: float = 2.5,
         worst_color: str = WORST, linewidth: float = 0.5, title: str | None = None) -> Axes:
    """Draw a triangulation on ``ax`` (a new figure's Axes if None) and return the Axes.

    ``tri``: a Triangulation, or another mesh as a ``(vertices, triangles)`` pair
    or an object with ``vertices`` and ``faces`` (drawn without segments).

    Triangles are filled with ``face_color`` and outlined with ``edge_color``:
    only the triangles, so holes and the outside of the domain stay empty.
    Segment pieces (``tri.segments``) are drawn ``segment_width`` wide. The
    ``worst`` triangles by minimum angle are filled with ``worst_color`` and,
    with ``circumcircles``, get their circumcircle drawn (dashed). The aspect
    ratio is equal (angles look like angles).
    """
    ax = _axes(ax)                  # (first: imports matplotlib, or names the extra)
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.patches import Circle

    V, T, S = _mesh_parts(tri)
    ax.add_collection(PolyCollection(V[T], facecolors=face_color, edgecolors=edge_color,
                                     linewidths=linewidth, zorder=1))
    ax.add_collection(LineCollection(V[S], colors=segment_color, linewidths=segment_width,
                                     capstyle="round", zorder=3))
    if worst and len(T):
        q = triangle_quality(V, T)
        picked = np.argsort(q["angles"].min(axis=1), kind="stable")[:worst]
        ax.add_collection(PolyCollection(V[T[picked]], facecolors=worst_color, edgecolors=worst_color,
                                         linewidths=linewidth, alpha=0.85, zorder=2))
        if circumcircles:
            for t in picked:
                center = _circumcenter(V[T[t]])
                if np.isfinite(center).all():
                    xy = (float(center[0]), float(center[1]))
                    ax.add_patch(Circle(xy, q["circumradius"][t], fill=False, color=worst_color,
                                        linestyle="--", linewidth=1.0, zorder=4))
    if len(V):
        used = V[np.unique(T)] if len(T) else V
        lo, hi = used.min(axis=0), used.max(axis=0)
        pad = 0.03 * max(float((hi - lo).max()), 1e-300)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_title(title if title is not None else f"{len(T):,} triangles, {len(S):,} segment edges")
    return ax


def _mesh_parts(mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices (n, 2), triangles and segment edges of a Triangulation, of a
    ``(vertices, triangles)`` pair or of a mesh with ``vertices`` and ``faces``."""
    if hasattr(mesh, "vertex_map"):
        V, T, S = mesh.vertices, mesh.triangles, mesh.segments
    else:
        V, T = against_arrays(mesh)
        S = np.empty((0, 2), np.int64)
    return (np.asarray(V, dtype=np.float64)[:, :2], np.asarray(T, dtype=np.int64),
            np.asarray(S, dtype=np.int64).reshape(-1, 2))


def _circumcenter(P) -> np.ndarray:
    """Circumcentre of one triangle (3, 2), relative to its first corner for accuracy."""
    b, c = P[1] - P[0], P[2] - P[0]
    d = 2.0 * (b[0] * c[1] - b[1] * c[0])
    if d == 0:
        return np.array([np.inf, np.inf])
    bb, cc = b @ b, c @ c
    return P[0] + np.array([c[1] * bb - b[1] * cc, b[0] * cc - c[0] * bb]) / d


def histogram(tri_or_report: Union[TriangulationLike, Report, Tuple[ArrayLike, ArrayLike]],
              ax: Axes | None = None, *, against: MeshLike | None = None,
              against_name: str = "against", bins: ArrayLike = ANGLE_BINS) -> Axes:
    """Angle histogram (degrees, all three angles of every triangle) on ``ax``.

    ``tri_or_report``: a Triangulation, a :class:`~cdt_plugin.report.Report`
    (with ``against`` inside, drawn as an outline) or ``(vertices, triangles)``.
    ``against``: another triangulation to overlay (when a Triangulation is given).
    Returns the Axes.
    """
    rep = _as_report(tri_or_report, against, against_name, bins)
    ax = _axes(ax)
    edges = np.asarray(rep.angle_bins)
    ax.bar(edges[:-1], rep.angle_counts, width=np.diff(edges), align="edge", color=FACE,
           edgecolor=EDGE, label=rep.name)
    if rep.against is not None:
        other = rep.against
        ax.stairs(other.angle_counts, np.asarray(other.angle_bins), color=WORST, linewidth=2.0,
                  label=other.name)
    ax.set_xlabel("angle (degrees)")
    ax.set_ylabel("angles")
    ax.set_xlim(edges[0], edges[-1])
    ax.legend()
    ax.set_title("angle histogram")
    return ax


def _as_report(obj, against, against_name, bins) -> Report:
    if isinstance(obj, Report):
        return obj
    if hasattr(obj, "vertex_map"):
        return quality_report(obj, against, against_name=against_name, bins=bins)
    return mesh_report(*obj, bins=bins)


def figure(tri: TriangulationLike, *, against: MeshLike | None = None, against_name: str = "against",
           worst: int = 3, size: tuple[float, float] | None = None, **plot_kwargs: Any) -> Figure:
    """A Figure with the triangulation (left), the ``against`` triangulation (middle,
    when given, drawn the same way) and the angle histogram (right)."""
    plt = _pyplot()
    panels = 2 if against is None else 3
    size = size or ((12.0, 5.5) if against is None else (17.0, 5.5))
    fig, axes = plt.subplots(1, panels, figsize=size, width_ratios=[3] * (panels - 1) + [2])
    plot(tri, axes[0], worst=worst, title=f"cdt_plugin: {len(tri.triangles):,} triangles",
         **plot_kwargs)
    if against is not None:
        theirs = _mesh_parts(against)
        plot(against, axes[1], worst=worst, title=f"{against_name}: {len(theirs[1]):,} triangles",
             **plot_kwargs)
        axes[1].set_xlim(axes[0].get_xlim())
        axes[1].set_ylim(axes[0].get_ylim())
    histogram(tri, axes[-1], against=against, against_name=against_name)
    fig.tight_layout()
    return fig


def save(tri: TriangulationLike, path: str | os.PathLike[str], *, against: MeshLike | None = None,
         against_name: str = "against", dpi: int = 120, **kwargs: Any) -> None:
    """Write :func:`figure` to ``path`` (format from the extension: .png, .svg, .pdf)."""
    plt = _pyplot()
    fig = figure(tri, against=against, against_name=against_name, **kwargs)
    try:
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
