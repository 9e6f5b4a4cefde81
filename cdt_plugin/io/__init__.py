"""Readers and writers for Shewchuk's Triangle file formats.

The formats (https://www.cs.cmu.edu/~quake/triangle.html, "File formats"):

``.node``  ``<#vertices> <dim=2> <#attributes> <#boundary markers 0|1>``, then one line per
           vertex: ``<vertex#> <x> <y> [attributes...] [marker]``.
``.poly``  a ``.node`` section (``#vertices`` may be 0: the vertices are then read from the
           ``.node`` file of the same base name), then ``<#segments> <#markers 0|1>`` and
           ``<seg#> <endpoint> <endpoint> [marker]`` lines, then ``<#holes>`` and
           ``<hole#> <x> <y>`` lines, then optionally ``<#regions>`` and
           ``<region#> <x> <y> <attribute> [<max area>]`` lines.
``.ele``   ``<#triangles> <nodes per triangle 3|6> <#attributes>``, then
           ``<tri#> <n1> <n2> <n3> [<n4> <n5> <n6>] [attributes...]``.
``.edge``  ``<#edges> <#boundary markers 0|1>``, then ``<edge#> <endpoint> <endpoint> [marker]``.
``.neigh`` ``<#triangles> <#neighbours per triangle = 3>``, then ``<tri#> <n1> <n2> <n3>``
           (``-1``: no neighbour).

Lexical rules, as in Triangle: fields are separated by white space, ``#`` starts a comment
that runs to the end of the line, blank lines are skipped, each record is one line. Vertex
numbering starts at the first vertex's number, which must be 0 or 1; every file that refers
to vertices (segments, triangles, edges) uses the same base. Everything this module returns
is ZERO-BASED.

Where Triangle is lenient we are lenient in the same way (missing attributes or markers on
a vertex line read as 0, extra trailing fields on a line are ignored, a missing hole section
in a ``.poly`` means no holes, a region line with only one value after x y uses it both as
attribute and as maximum area, exactly as ``triangle.c`` does). Where Triangle would silently
produce garbage we raise :class:`~cdt_plugin.errors.FileFormatError` naming the file, the
line and what was expected: too few fields, unparsable numbers, non-finite coordinates, a
first vertex number other than 0/1, vertex numbers out of sequence, indices out of range,
truncated files and unexpected extra records.

Numbers are parsed with :func:`float` (never a hand-written parser: Triangle's own ``-a``
switch parsing drops exponents, ``2.86e-05`` becoming 2.86). Writers emit ``repr`` of each
float, which round-trips bit for bit, and number everything from 1 (Triangle's default).

One module per job, the public names re-exported here: :mod:`.records` (what the readers
return, and the lexical layer they share), :mod:`.reading` (``read_*``), :mod:`.writing`
(``write_*``).
"""
from __future__ import annotations

from .reading import read_edge, read_ele, read_neigh, read_node, read_poly
from .records import EdgeData, EleData, NodeData, PolyData
from .writing import (
    WRITE_FIRST_INDEX,
    write_edge,
    write_ele,
    write_neigh,
    write_node,
    write_off,
    write_poly,
    write_triangulation,
    write_voronoi,
)

__all__ = [
    "NodeData", "PolyData", "EleData", "EdgeData",
    "read_node", "read_poly", "read_ele", "read_edge", "read_neigh",
    "write_node", "write_poly", "write_ele", "write_edge", "write_neigh", "write_triangulation",
    "write_voronoi", "write_off",
    "WRITE_FIRST_INDEX",
]
