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
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from .errors import FileFormatError, InputShapeError, NonFiniteCoordinateError
from .plc import PLC, as_plc
from .triangulation import Triangulation
from .validate import as_index, as_xy

__all__ = [
    "NodeData", "PolyData", "EleData", "EdgeData",
    "read_node", "read_poly", "read_ele", "read_edge", "read_neigh",
    "write_node", "write_poly", "write_ele", "write_edge", "write_neigh", "write_triangulation",
    "WRITE_FIRST_INDEX",
]

#: The vertex number the writers start from (Triangle's default numbering).
WRITE_FIRST_INDEX = 1


# ----------------------------------------------------------------------------------------
# result types
# ----------------------------------------------------------------------------------------

@dataclass
class NodeData:
    """Contents of a ``.node`` file (or the node section of a ``.poly``)."""
    vertices: NDArray[np.float64]      # (n, 2)
    attributes: NDArray[np.float64]    # (n, a) (a may be 0)
    markers: NDArray[np.int64] | None  # (n,), or None when the header says 0 markers
    first_index: int                   # 0 or 1: the numbering base of the file


@dataclass
class PolyData:
    """Contents of a ``.poly`` file. All indices are zero-based."""
    vertices: NDArray[np.float64]              # (n, 2)
    attributes: NDArray[np.float64]            # (n, a)
    markers: NDArray[np.int64] | None          # (n,) or None
    segments: NDArray[np.int64]                # (m, 2), zero-based
    segment_markers: NDArray[np.int64] | None  # (m,) or None
    holes: NDArray[np.float64]                 # (h, 2) hole seed points
    regions: NDArray[np.float64]               # (r, 4): x, y, attribute, max_area
    first_index: int                           # numbering base of the file (0 or 1)
    node_path: Path | None = None              # the .node file the vertices came from, if any

    def to_plc(self) -> PLC:
        """The file's PLC (vertices, segments, holes, region seeds), ready for
        :func:`cdt_plugin.triangulate`. Hole points are kept as Triangle uses them
        (triangles reachable from outside the segments are removed too), and a
        region's positive maximum area bounds its triangles.

        >>> import os, tempfile, cdt_plugin
        >>> path = os.path.join(tempfile.mkdtemp(), "square.poly")
        >>> write_poly(path, [[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
        >>> tri = cdt_plugin.triangulate(read_poly(path).to_plc())
        >>> len(tri.triangles), tri.is_delaunay()
        (2, True)
        """
        return as_plc(self.vertices, self.segments, self.holes,
                      self.regions if len(self.regions) else None)

    @property
    def vertex_attributes(self) -> NDArray[np.float64]:
        return self.attributes

    @property
    def vertex_markers(self) -> NDArray[np.int64] | None:
        return self.markers


@dataclass
class EleData:
    """Contents of a ``.ele`` file (zero-based vertex indices)."""
    triangles: NDArray[np.int64]     # (k, 3) or (k, 6)
    attributes: NDArray[np.float64]  # (k, a)
    first_index: int


@dataclass
class EdgeData:
    """Contents of a ``.edge`` file (zero-based vertex indices)."""
    edges: NDArray[np.int64]           # (m, 2)
    markers: NDArray[np.int64] | None  # (m,) or None
    first_index: int


# ----------------------------------------------------------------------------------------
# lexical layer
# ----------------------------------------------------------------------------------------

class _Records:
    """The records (non-blank, comment-stripped lines) of one file, with line numbers."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.name = self.path.name
        try:
            with open(self.path, "r", encoding="utf-8", errors="replace") as f:
                text = f.read()
        except OSError as exc:
            raise FileFormatError(f"{self.path}: cannot read file ({exc.strerror})") from exc
        recs: list[tuple[int, list[str]]] = []
        for lineno, line in enumerate(text.splitlines(), start=1):
            toks = line.split("#", 1)[0].split()
            if toks:
                recs.append((lineno, toks))
        self.recs = recs
        self.nlines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        self.pos = 0

    # -- errors ---------------------------------------------------------------------------
    def error(self, lineno: int | None, msg: str) -> FileFormatError:
        where = f"{self.name} line {lineno}" if lineno is not None else self.name
        err = FileFormatError(f"{where}: {msg}")
        err.path = self.path
        err.line = lineno
        return err

    # -- cursor ---------------------------------------------------------------------------
    def at_end(self) -> bool:
        return self.pos >= len(self.recs)

    def next(self, what: str) -> tuple[int, list[str]]:
        if self.pos >= len(self.recs):
            raise self.error(None, f"unexpected end of file: expected {what}")
        rec = self.recs[self.pos]
        self.pos += 1
        return rec

    def expect_end(self, after: str) -> None:
        if self.pos < len(self.recs):
            lineno, toks = self.recs[self.pos]
            raise self.error(lineno, f"unexpected extra record {' '.join(toks)!r} after {after}")

    # -- fields ---------------------------------------------------------------------------
    def need(self, lineno: int, toks: list[str], n: int, what: str) -> None:
        if len(toks) < n:
            raise self.error(lineno, f"expected {n} numbers ({what}), got {len(toks)}")

    def int_(self, lineno: int, tok: str, what: str) -> int:
        try:
            return int(tok)
        except ValueError:
            pass
        try:
            v = float(tok) if "_" not in tok else math.nan
        except ValueError:
            v = math.nan
        if math.isfinite(v) and v == int(v):
            return int(v)
        raise self.error(lineno, f"expected an integer for {what}, got {tok!r}")

    def float_(self, lineno: int, tok: str, what: str) -> float:
        # float() keeps exponents ("2.86e-05" is 2.86e-05). Python also accepts "1_000",
        # which no C strtod does: reject it rather than guess.
        try:
            if "_" in tok:
                raise ValueError
            v = float(tok)
        except ValueError:
            raise self.error(lineno, f"expected a number for {what}, got {tok!r}") from None
        if not math.isfinite(v):
            raise self.error(lineno, f"{what} is not finite ({tok!r})")
        return v


def _count(recs: _Records, lineno: int, tok: str, what: str) -> int:
    n = recs.int_(lineno, tok, what)
    if n < 0:
        raise recs.error(lineno, f"{what} must be >= 0, got {n}")
    return n


def _flag(recs: _Records, lineno: int, toks: list[str], k: int, what: str) -> int:
    if len(toks) <= k:
        return 0
    v = recs.int_(lineno, toks[k], what)
    if v not in (0, 1):
        raise recs.error(lineno, f"{what} must be 0 or 1, got {v}")
    return v


def _first_number(recs: _Records, lineno: int, tok: str, what: str) -> int:
    first = recs.int_(lineno, tok, what)
    if first not in (0, 1):
        raise recs.error(lineno, f"the first {what} must be numbered 0 or 1, got {first}")
    return first


# ----------------------------------------------------------------------------------------
# section parsers
# ----------------------------------------------------------------------------------------

def _parse_nodes(recs: _Records) -> tuple[NodeData, int]:
    """Parse a node header and its vertex lines; returns (NodeData, header line)."""
    lineno, head = recs.next("the node header '<#vertices> <dim> <#attributes> <#markers>'")
    n = _count(recs, lineno, head[0], "number of vertices")
    if len(head) > 1:
        dim = recs.int_(lineno, head[1], "dimension")
        if dim != 2:
            raise recs.error(lineno, f"dimension must be 2, got {dim}")
    nattr = _count(recs, lineno, head[2], "number of attributes") if len(head) > 2 else 0
    nmark = _flag(recs, lineno, head, 3, "number of boundary markers")
    verts = np.empty((n, 2), dtype=np.float64)
    attrs = np.zeros((n, nattr), dtype=np.float64)
    marks = np.zeros(n, dtype=np.int64) if nmark else None
    first = 0
    for i in range(n):
        try:
            ln, toks = recs.next(f"{n} vertex lines (got {i})")
        except FileFormatError:
            raise recs.error(None, f"unexpected end of file: the header (line {lineno}) "
                                   f"declares {n} vertices, found {i}") from None
        recs.need(ln, toks, 3, "index x y")
        num = recs.int_(ln, toks[0], "the vertex number")
        if i == 0:
            first = _first_number(recs, ln, toks[0], "vertex")
        elif num != first + i:
            raise recs.error(ln, f"vertex number {num} out of sequence (expected {first + i})")
        verts[i, 0] = recs.float_(ln, toks[1], f"x of vertex {num}")
        verts[i, 1] = recs.float_(ln, toks[2], f"y of vertex {num}")
        for a in range(min(nattr, len(toks) - 3)):
            attrs[i, a] = recs.float_(ln, toks[3 + a], f"attribute {a + 1} of vertex {num}")
        if marks is not None and len(toks) > 3 + nattr:
            marks[i] = recs.int_(ln, toks[3 + nattr], f"boundary marker of vertex {num}")
    return NodeData(verts, attrs, marks, first), lineno


def _endpoint(recs: _Records, ln: int, tok: str, what: str, first: int, n: int) -> int:
    v = recs.int_(ln, tok, what)
    z = v - first
    if not 0 <= z < n:
        raise recs.error(ln, f"{what} is {v}, out of range: vertices are numbered "
                             f"{first}..{first + n - 1}")
    return z


# ----------------------------------------------------------------------------------------
# readers
# ----------------------------------------------------------------------------------------

def read_node(path: str | os.PathLike[str]) -> NodeData:
    """Read a Triangle ``.node`` file.

    >>> nd = read_node("spiral.node")          # doctest: +SKIP
    >>> nd.vertices.shape, nd.first_index       # doctest: +SKIP
    ((15, 2), 1)
    """
    recs = _Records(path)
    nd, _ = _parse_nodes(recs)
    recs.expect_end(f"the {nd.vertices.shape[0]} vertices")
    return nd


def read_poly(path: str | os.PathLike[str]) -> PolyData:
    """Read a Triangle ``.poly`` file (segments zero-based).

    ``regions`` is (r, 4): x, y, regional attribute, maximum area. As in ``triangle.c``, a
    region line with a single value after x and y uses it for both the attribute and the
    maximum area (that is how ``la.poly`` gives its area bounds); a negative or zero maximum
    area means "no constraint" to Triangle.
    """
    recs = _Records(path)
    nd, _ = _parse_nodes(recs)
    node_path = None
    if nd.vertices.shape[0] == 0:
        node_path = Path(path).with_suffix(".node")
        if not node_path.exists():
            raise recs.error(None, f"declares 0 vertices but {node_path.name} "
                                   "(where they should then be) does not exist")
        nd = read_node(node_path)
    n = nd.vertices.shape[0]
    first = nd.first_index

    ln, head = recs.next("the segment header '<#segments> <#boundary markers>'")
    m = _count(recs, ln, head[0], "number of segments")
    smark = _flag(recs, ln, head, 1, "number of segment boundary markers")
    segs = np.empty((m, 2), dtype=np.int64)
    smarks = np.zeros(m, dtype=np.int64) if smark else None
    for j in range(m):
        try:
            ln, toks = recs.next("segment line")
        except FileFormatError:
            raise recs.error(None, f"unexpected end of file: {m} segments declared, "
                                   f"found {j}") from None
        recs.need(ln, toks, 3, "index endpoint endpoint")
        num = recs.int_(ln, toks[0], "the segment number")
        segs[j, 0] = _endpoint(recs, ln, toks[1], f"segment {num}'s first endpoint", first, n)
        segs[j, 1] = _endpoint(recs, ln, toks[2], f"segment {num}'s second endpoint", first, n)
        if smarks is not None and len(toks) > 3:
            smarks[j] = recs.int_(ln, toks[3], f"boundary marker of segment {num}")

    holes = np.zeros((0, 2), dtype=np.float64)
    if not recs.at_end():
        ln, head = recs.next("the hole count")
        h = _count(recs, ln, head[0], "number of holes")
        holes = np.empty((h, 2), dtype=np.float64)
        for j in range(h):
            try:
                ln, toks = recs.next("hole line")
            except FileFormatError:
                raise recs.error(None, f"unexpected end of file: {h} holes declared, "
                                       f"found {j}") from None
            recs.need(ln, toks, 3, "index x y")
            holes[j, 0] = recs.float_(ln, toks[1], f"x of hole {toks[0]}")
            holes[j, 1] = recs.float_(ln, toks[2], f"y of hole {toks[0]}")

    regions = np.zeros((0, 4), dtype=np.float64)
    if not recs.at_end():
        ln, head = recs.next("the region count")
        r = _count(recs, ln, head[0], "number of regions")
        regions = np.empty((r, 4), dtype=np.float64)
        for j in range(r):
            try:
                ln, toks = recs.next("region line")
            except FileFormatError:
                raise recs.error(None, f"unexpected end of file: {r} regions declared, "
                                       f"found {j}") from None
            recs.need(ln, toks, 4, "index x y attribute [max_area]")
            label = toks[0]
            regions[j, 0] = recs.float_(ln, toks[1], f"x of region {label}")
            regions[j, 1] = recs.float_(ln, toks[2], f"y of region {label}")
            regions[j, 2] = recs.float_(ln, toks[3], f"attribute of region {label}")
            regions[j, 3] = (recs.float_(ln, toks[4], f"maximum area of region {label}")
                             if len(toks) > 4 else regions[j, 2])
    recs.expect_end("the regions section")
    return PolyData(nd.vertices, nd.attributes, nd.markers, segs, smarks, holes, regions,
                    first, node_path)


def read_ele(path: str | os.PathLike[str], first_index: int | None = None,
             n_vertices: int | None = None) -> EleData:
    """Read a Triangle ``.ele`` file; vertex indices are returned zero-based.

    The numbering base is ``first_index`` if given (the base of the matching ``.node``),
    else the number of the first triangle (Triangle numbers everything from the same base).
    With ``n_vertices`` the corners are also range-checked.
    """
    recs = _Records(path)
    ln0, head = recs.next("the header '<#triangles> <nodes per triangle> <#attributes>'")
    k = _count(recs, ln0, head[0], "number of triangles")
    npt = recs.int_(ln0, head[1], "nodes per triangle") if len(head) > 1 else 3
    if npt not in (3, 6):
        raise recs.error(ln0, f"nodes per triangle must be 3 or 6, got {npt}")
    nattr = _count(recs, ln0, head[2], "number of attributes") if len(head) > 2 else 0
    tris = np.empty((k, npt), dtype=np.int64)
    attrs = np.zeros((k, nattr), dtype=np.float64)
    base = first_index
    for i in range(k):
        try:
            ln, toks = recs.next("triangle line")
        except FileFormatError:
            raise recs.error(None, f"unexpected end of file: {k} triangles declared, "
                                   f"found {i}") from None
        recs.need(ln, toks, 1 + npt, "index " + " ".join(f"n{c + 1}" for c in range(npt)))
        num = recs.int_(ln, toks[0], "the triangle number")
        if base is None:                # the first record, with no base given
            base = _first_number(recs, ln, toks[0], "triangle")
        for c in range(npt):
            v = recs.int_(ln, toks[1 + c], f"corner {c + 1} of triangle {num}") - base
            if v < 0 or (n_vertices is not None and v >= n_vertices):
                hi = f"{base + n_vertices - 1}" if n_vertices is not None else "..."
                raise recs.error(ln, f"corner {c + 1} of triangle {num} is {v + base}, out "
                                     f"of range: vertices are numbered {base}..{hi}")
            tris[i, c] = v
        for a in range(min(nattr, len(toks) - 1 - npt)):
            attrs[i, a] = recs.float_(ln, toks[1 + npt + a], f"attribute {a + 1} of triangle {num}")
    recs.expect_end(f"the {k} triangles")
    return EleData(tris, attrs, 1 if base is None else base)


def read_edge(path: str | os.PathLike[str], first_index: int | None = None,
              n_vertices: int | None = None) -> EdgeData:
    """Read a Triangle ``.edge`` file; endpoints are returned zero-based.

    Only triangulation edge files (both endpoints vertices) are accepted, not the Voronoi
    ``.v.edge`` files whose rays have a ``-1`` endpoint and a direction.
    """
    recs = _Records(path)
    ln0, head = recs.next("the header '<#edges> <#boundary markers>'")
    m = _count(recs, ln0, head[0], "number of edges")
    emark = _flag(recs, ln0, head, 1, "number of boundary markers")
    edges = np.empty((m, 2), dtype=np.int64)
    marks = np.zeros(m, dtype=np.int64) if emark else None
    base = first_index
    for i in range(m):
        try:
            ln, toks = recs.next("edge line")
        except FileFormatError:
            raise recs.error(None, f"unexpected end of file: {m} edges declared, "
                                   f"found {i}") from None
        recs.need(ln, toks, 3, "index endpoint endpoint")
        num = recs.int_(ln, toks[0], "the edge number")
        if base is None:                # the first record, with no base given
            base = _first_number(recs, ln, toks[0], "edge")
        for c in range(2):
            v = recs.int_(ln, toks[1 + c], f"endpoint {c + 1} of edge {num}") - base
            if v < 0 or (n_vertices is not None and v >= n_vertices):
                hi = f"{base + n_vertices - 1}" if n_vertices is not None else "..."
                raise recs.error(ln, f"endpoint {c + 1} of edge {num} is {v + base}, out "
                                     f"of range: vertices are numbered {base}..{hi}")
            edges[i, c] = v
        if marks is not None and len(toks) > 3:
            marks[i] = recs.int_(ln, toks[3], f"boundary marker of edge {num}")
    recs.expect_end(f"the {m} edges")
    return EdgeData(edges, marks, 1 if base is None else base)


def read_neigh(path: str | os.PathLike[str], first_index: int | None = None) -> NDArray[np.int64]:
    """Read a Triangle ``.neigh`` file: (k, 3) int64 zero-based triangle indices, -1 for none.

    Neighbour j of a triangle is the one opposite its corner j.
    """
    recs = _Records(path)
    ln0, head = recs.next("the header '<#triangles> <#neighbors per triangle>'")
    k = _count(recs, ln0, head[0], "number of triangles")
    if len(head) > 1:
        nn = recs.int_(ln0, head[1], "neighbours per triangle")
        if nn != 3:
            raise recs.error(ln0, f"neighbours per triangle must be 3, got {nn}")
    out = np.empty((k, 3), dtype=np.int64)
    base = first_index
    for i in range(k):
        try:
            ln, toks = recs.next("neighbour line")
        except FileFormatError:
            raise recs.error(None, f"unexpected end of file: {k} triangles declared, "
                                   f"found {i}") from None
        recs.need(ln, toks, 4, "index n1 n2 n3")
        num = recs.int_(ln, toks[0], "the triangle number")
        if base is None:                # the first record, with no base given
            base = _first_number(recs, ln, toks[0], "triangle")
        for c in range(3):
            v = recs.int_(ln, toks[1 + c], f"neighbour {c + 1} of triangle {num}")
            if v == -1:
                out[i, c] = -1
                continue
            z = v - base
            if not 0 <= z < k:
                raise recs.error(ln, f"neighbour {c + 1} of triangle {num} is {v}, out of "
                                     f"range: triangles are numbered {base}..{base + k - 1}"
                                     " (-1 for none)")
            out[i, c] = z
    recs.expect_end(f"the {k} triangles")
    return out


# ----------------------------------------------------------------------------------------
# writers
# ----------------------------------------------------------------------------------------

def _fmt(x: float) -> str:
    return repr(float(x))


def _opt_rows(a: ArrayLike | None, n: int, what: str, dtype: DTypeLike) -> NDArray[Any] | None:
    if a is None:
        return None
    arr = np.asarray(a, dtype=dtype)
    if arr.shape[:1] != (n,):
        raise InputShapeError(f"{what} must have {n} rows, got shape {arr.shape}")
    return arr


def _node_lines(vertices: ArrayLike, attributes: ArrayLike | None,
                markers: ArrayLike | None) -> list[str]:
    v = as_xy(vertices, "vertices", empty=True)
    n = v.shape[0]
    attrs = _opt_rows(attributes, n, "attributes", np.float64)
    if attrs is not None and attrs.ndim == 1:
        attrs = attrs[:, None]
    marks = _opt_rows(markers, n, "markers", np.int64)
    na = 0 if attrs is None else attrs.shape[1]
    lines = [f"{n} 2 {na} {0 if marks is None else 1}"]
    f0 = WRITE_FIRST_INDEX
    for i in range(n):
        parts = [str(i + f0), _fmt(v[i, 0]), _fmt(v[i, 1])]
        if attrs is not None:
            parts.extend(_fmt(x) for x in attrs[i])
        if marks is not None:
            parts.append(str(int(marks[i])))
        lines.append(" ".join(parts))
    return lines


def _write(path: str | os.PathLike[str], lines: list[str], kind: str) -> None:
    header = f"# {kind} written by cdt_plugin.io (numbering from {WRITE_FIRST_INDEX})"
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(header + "\n" + "\n".join(lines) + "\n")


def _mesh_array(data: ArrayLike | Triangulation, name: str) -> ArrayLike:
    """``data.<name>`` when ``data`` is a :class:`~cdt_plugin.Triangulation`, else ``data``."""
    return getattr(data, name) if isinstance(data, Triangulation) else data


def write_node(path: str | os.PathLike[str], vertices: ArrayLike | Triangulation,
               attributes: ArrayLike | None = None, markers: ArrayLike | None = None) -> None:
    """Write a ``.node`` file, vertices numbered from 1; floats round-trip exactly.
    ``vertices``: an (n, 2) array or a Triangulation (its vertices).

    >>> import os, tempfile, cdt_plugin
    >>> path = os.path.join(tempfile.mkdtemp(), "tri.node")
    >>> write_node(path, cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]]))
    >>> read_node(path).vertices.tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    _write(path, _node_lines(_mesh_array(vertices, "vertices"), attributes, markers),
           "Triangle .node")


def write_poly(path: str | os.PathLike[str], vertices: ArrayLike | Triangulation,
               segments: ArrayLike | None = None, holes: ArrayLike | None = None,
               regions: ArrayLike | None = None, segment_markers: ArrayLike | None = None,
               attributes: ArrayLike | None = None, markers: ArrayLike | None = None) -> None:
    """Write a ``.poly`` file (vertices inline, numbered from 1).

    ``segments`` are zero-based in memory; ``regions`` rows are (x, y, attribute, max_area),
    a NaN max_area is written as -1 (no constraint, in Triangle's reading). ``vertices``
    may be a Triangulation: its vertices and (unless given) its segment pieces are
    written, as Triangle writes its output ``.poly``.

    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "seg.poly")
    >>> write_poly(path, [[0, 0], [1, 0]], [[0, 1]])
    >>> read_poly(path).segments.tolist()
    [[0, 1]]
    """
    if segments is None:
        segments = _mesh_array(vertices, "segments")
        if segments is vertices:
            raise InputShapeError("write_poly needs segments (or a Triangulation)")
    lines = _node_lines(_mesh_array(vertices, "vertices"), attributes, markers)
    n = int(lines[0].split()[0])
    s = as_index(segments, "segments", 2, n)
    smarks = _opt_rows(segment_markers, s.shape[0], "segment_markers", np.int64)
    f0 = WRITE_FIRST_INDEX
    lines.append(f"{s.shape[0]} {0 if smarks is None else 1}")
    for j in range(s.shape[0]):
        row = f"{j + f0} {s[j, 0] + f0} {s[j, 1] + f0}"
        if smarks is not None:
            row += f" {int(smarks[j])}"
        lines.append(row)
    h = as_xy(holes if holes is not None else np.zeros((0, 2)), "holes", empty=True)
    lines.append(str(h.shape[0]))
    for j in range(h.shape[0]):
        lines.append(f"{j + f0} {_fmt(h[j, 0])} {_fmt(h[j, 1])}")
    if regions is not None:
        r = np.asarray(regions, dtype=np.float64)
        if r.size == 0:
            r = np.zeros((0, 4))
        if r.ndim != 2 or r.shape[1] not in (3, 4):
            raise InputShapeError(f"regions must have shape (r, 4), got {r.shape}")
        if not np.isfinite(r[:, :3]).all():
            raise NonFiniteCoordinateError("regions: x, y and attribute must be finite")
        lines.append(str(r.shape[0]))
        for j in range(r.shape[0]):
            area = r[j, 3] if r.shape[1] == 4 and np.isfinite(r[j, 3]) else -1.0
            lines.append(f"{j + f0} {_fmt(r[j, 0])} {_fmt(r[j, 1])} {_fmt(r[j, 2])} {_fmt(area)}")
    _write(path, lines, "Triangle .poly")


def write_ele(path: str | os.PathLike[str], triangles: ArrayLike | Triangulation,
              attributes: ArrayLike | None = None) -> None:
    """Write a ``.ele`` file (triangles and corners numbered from 1). ``triangles``: a
    (k, 3) or (k, 6) index array or a Triangulation (its triangles).

    >>> import os, tempfile, cdt_plugin
    >>> path = os.path.join(tempfile.mkdtemp(), "tri.ele")
    >>> write_ele(path, cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]]))
    >>> read_ele(path).triangles.tolist()
    [[0, 1, 2]]
    """
    t = np.asarray(_mesh_array(triangles, "triangles"))
    cols = t.shape[1] if t.ndim == 2 and t.shape[1] in (3, 6) else 3
    t = as_index(t, "triangles", cols)
    if (t < 0).any():
        raise InputShapeError("triangles contain negative vertex indices")
    attrs = _opt_rows(attributes, t.shape[0], "attributes", np.float64)
    if attrs is not None and attrs.ndim == 1:
        attrs = attrs[:, None]
    na = 0 if attrs is None else attrs.shape[1]
    f0 = WRITE_FIRST_INDEX
    lines = [f"{t.shape[0]} {cols} {na}"]
    for i in range(t.shape[0]):
        parts = [str(i + f0)] + [str(int(x) + f0) for x in t[i]]
        if attrs is not None:
            parts.extend(_fmt(x) for x in attrs[i])
        lines.append(" ".join(parts))
    _write(path, lines, "Triangle .ele")


def write_edge(path: str | os.PathLike[str], edges: ArrayLike | Triangulation,
               markers: ArrayLike | None = None) -> None:
    """Write a ``.edge`` file (edges and endpoints numbered from 1). ``edges``: an (m, 2)
    index array or a Triangulation (every edge of its triangles)."""
    e = as_index(_mesh_array(edges, "edges"), "edges", 2)
    if (e < 0).any():
        raise InputShapeError("edges contain negative vertex indices")
    marks = _opt_rows(markers, e.shape[0], "markers", np.int64)
    f0 = WRITE_FIRST_INDEX
    lines = [f"{e.shape[0]} {0 if marks is None else 1}"]
    for i in range(e.shape[0]):
        row = f"{i + f0} {e[i, 0] + f0} {e[i, 1] + f0}"
        if marks is not None:
            row += f" {int(marks[i])}"
        lines.append(row)
    _write(path, lines, "Triangle .edge")


def write_neigh(path: str | os.PathLike[str], neighbors: ArrayLike | Triangulation) -> None:
    """Write a ``.neigh`` file (triangles numbered from 1, -1 for no neighbour).
    ``neighbors``: a (k, 3) array (column j: across the edge opposite corner j, as
    Triangle numbers them) or a Triangulation (its neighbours)."""
    nb = as_index(_mesh_array(neighbors, "neighbors"), "neighbors", 3)
    k = nb.shape[0]
    if ((nb < -1) | (nb >= k)).any():
        raise InputShapeError(f"neighbors must be -1 or in 0..{k - 1}")
    f0 = WRITE_FIRST_INDEX
    lines = [f"{k} 3"]
    for i in range(k):
        lines.append(" ".join([str(i + f0)] + [str(int(x) + f0) if x >= 0 else "-1"
                                                for x in nb[i]]))
    _write(path, lines, "Triangle .neigh")


def write_triangulation(path: str | os.PathLike[str], tri: Triangulation,
                        attributes: ArrayLike | None = None) -> list[Path]:
    """Write a Triangulation as Triangle writes its output: ``<base>.node``,
    ``<base>.ele`` (with ``attributes`` per triangle, if given) and ``<base>.poly``
    (its segment pieces), ``<base>`` being ``path`` without its extension. Returns
    the three paths.

    >>> import os, tempfile, cdt_plugin
    >>> base = os.path.join(tempfile.mkdtemp(), "square")
    >>> tri = cdt_plugin.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> [p.name for p in write_triangulation(base + ".ele", tri)]
    ['square.node', 'square.ele', 'square.poly']
    >>> read_ele(base + ".ele").triangles.shape
    (2, 3)
    """
    base = Path(path).with_suffix("")
    paths = [base.with_suffix(s) for s in (".node", ".ele", ".poly")]
    write_node(paths[0], tri)
    write_ele(paths[1], tri, attributes=attributes)
    write_poly(paths[2], tri)
    return paths
