"""The ``triangle`` package's plotting helpers, with matplotlib: :func:`plot` draws
one of its dictionaries on an axes, :func:`compare` and :func:`comparev` two of them
side by side or one above the other (the input and the mesh, typically).

>>> import matplotlib; matplotlib.use("Agg")
>>> import matplotlib.pyplot as plt
>>> from cdt_plugin import triangle as tr
>>> A = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
>>> tr.compare(plt, A, tr.triangulate(A, "pq"))
>>> len(plt.gcf().axes)
2
"""
from __future__ import annotations

from typing import Any

import numpy as np


def plot(ax: Any, **kw: Any) -> None:
    """Draw the dictionary ``kw`` on ``ax``: vertices (with ``labels=True`` their
    numbers, with ``markers=True`` their markers), segments in red, triangles,
    holes as crosses, edges, region points and triangle attributes."""
    ax.set_aspect("equal")
    xy = np.asarray(kw["vertices"], dtype=float)
    ax.scatter(xy[:, 0], xy[:, 1], color="k", s=8)
    if kw.get("labels"):
        for i, (x, y) in enumerate(xy):
            ax.text(x, y, str(i))
    if kw.get("markers") and "vertex_markers" in kw:
        for (x, y), m in zip(xy, np.ravel(kw["vertex_markers"])):
            ax.text(x, y, str(m))
    if "triangles" in kw:
        corners = np.asarray(kw["triangles"])[:, :3]
        ax.triplot(xy[:, 0], xy[:, 1], corners, "k-", lw=0.5)
    for key, style in (("segments", {"color": "r", "lw": 2}), ("edges", {"color": "k", "lw": 0.5})):
        if key in kw:
            lines = xy[np.asarray(kw[key])]
            for (x0, y0), (x1, y1) in lines:
                ax.plot([x0, x1], [y0, y1], **style)
    if "holes" in kw:
        h = np.asarray(kw["holes"], dtype=float)
        ax.scatter(h[:, 0], h[:, 1], marker="x", color="r")
    if "regions" in kw:
        r = np.asarray(kw["regions"], dtype=float)
        ax.scatter(r[:, 0], r[:, 1], marker="*", color="b")
        for x, y, attribute, *_ in r:
            ax.text(x, y, f" {attribute:g}", color="b", va="center")
    if "triangle_attributes" in kw and "triangles" in kw:
        centres = xy[np.asarray(kw["triangles"])[:, :3]].mean(axis=1)
        for (x, y), a in zip(centres, np.asarray(kw["triangle_attributes"])[:, 0]):
            ax.text(x, y, f" {a:g}", color="m", va="center")
    ax.get_xaxis().set_visible(False)
    ax.get_yaxis().set_visible(False)


def compare(plt: Any, A: dict, B: dict, figsize: tuple[float, float] = (6, 3)) -> None:
    """``A`` and ``B`` side by side on a new figure of ``plt``, on the same scale."""
    _pair(plt, A, B, figsize, (121, 122), "sharey")


def comparev(plt: Any, A: dict, B: dict, figsize: tuple[float, float] = (3, 6)) -> None:
    """``A`` above ``B`` on a new figure of ``plt``, on the same scale."""
    _pair(plt, A, B, figsize, (211, 212), "sharex")


def _pair(plt: Any, A: dict, B: dict, figsize: tuple[float, float], grid: tuple[int, int],
          share: str) -> None:
    plt.figure(figsize=figsize)
    first = plt.subplot(grid[0])
    plot(first, **A)
    limits = first.axis()
    second = plt.subplot(grid[1], **{share: first})
    plot(second, **B)
    second.axis(limits)
    plt.tight_layout()
