"""A drop-in for the ``triangle`` package (Python bindings of Shewchuk's Triangle):
``from cdt_plugin import triangle as tr`` where a program had ``import triangle as tr``.

The same functions with the same signatures and dictionaries (keys, dtypes, shapes,
which keys are present for each switch): :func:`triangulate`, :func:`delaunay`,
:func:`convex_hull`, :func:`voronoi` (:mod:`.tri`), :func:`load`, :func:`loads`,
:func:`get_data`, :func:`show_data` (:mod:`.data`), :func:`plot`, :func:`compare`,
:func:`comparev` (:mod:`.plot`, with matplotlib). The switches are read by
:func:`cdt_plugin.switches.read_switches` (every switch of Triangle 1.6); the guide
"Coming from Triangle" has the table of what each does here.

>>> from cdt_plugin import triangle as tr
>>> t = tr.triangulate({"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]],
...                     "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}, "p")
>>> sorted(t), t["triangles"].dtype, t["triangles"].shape
(['segment_markers', 'segments', 'triangles', 'vertex_markers', 'vertices'], dtype('int32'), (2, 3))
"""
from __future__ import annotations

from .data import get_data, load, loads, show_data
from .plot import compare, comparev, plot
from .tri import convex_hull, delaunay, triangulate, voronoi

__all__ = ["triangulate", "delaunay", "convex_hull", "voronoi", "load", "loads", "get_data",
           "show_data", "plot", "compare", "comparev"]
