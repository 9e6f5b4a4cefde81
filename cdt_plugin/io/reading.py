"""The readers of Triangle's ``.node``, ``.poly``, ``.ele``, ``.edge`` and ``.neigh``
files (the formats and the lexical rules: :mod:`cdt_plugin.io`); every index they
return is zero-based."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError
from .records import EdgeData, EleData, NodeData, PolyData, Records

# ----------------------------------------------------------------------------------------
# section parsers
# ----------------------------------------------------------------------------------------

def _parse_nodes(recs: Records) -> tuple[NodeData, int]:
    """Parse a node header and its vertex lines; returns (NodeData, header line)."""
    lineno, head = recs.next("the node header '<#vertices> <dim> <#attributes> <#markers>'")
    n = recs.count(lineno, head[0], "number of vertices")
    if len(head) > 1:
        dim = recs.int_(lineno, head[1], "dimension")
        if dim != 2:
            raise recs.error(lineno, f"dimension must be 2, got {dim}")
    nattr = recs.count(lineno, head[2], "number of attributes") if len(head) > 2 else 0
    nmark = recs.flag(lineno, head, 3, "number of boundary markers")
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
            first = recs.first_number(ln, toks[0], "vertex")
        elif num != first + i:
            raise recs.error(ln, f"vertex number {num} out of sequence (expected {first + i})")
        verts[i, 0] = recs.float_(ln, toks[1], f"x of vertex {num}")
        verts[i, 1] = recs.float_(ln, toks[2], f"y of vertex {num}")
        for a in range(min(nattr, len(toks) - 3)):
            attrs[i, a] = recs.float_(ln, toks[3 + a], f"attribute {a + 1} of vertex {num}")
        if marks is not None and len(toks) > 3 + nattr:
            marks[i] = recs.int_(ln, toks[3 + nattr], f"boundary marker of vertex {num}")
    return NodeData(verts, attrs, marks, first), lineno


def _vertex(recs: Records, ln: int, tok: str, what: str, first: int, n: int | None) -> int:
    """The zero-based vertex number ``tok`` (numbering from ``first``; with ``n``
    vertices, or any number of them when ``n`` is None)."""
    z = recs.int_(ln, tok, what) - first
    if z < 0 or (n is not None and z >= n):
        hi = f"{first + n - 1}" if n is not None else "..."
        raise recs.error(ln, f"{what} is {z + first}, out of range: vertices are numbered "
                             f"{first}..{hi}")
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
    recs = Records(path)
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
    recs = Records(path)
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
    m = recs.count(ln, head[0], "number of segments")
    smark = recs.flag(ln, head, 1, "number of segment boundary markers")
    segs = np.empty((m, 2), dtype=np.int64)
    smarks = np.zeros(m, dtype=np.int64) if smark else None
    for j in range(m):
        ln, toks = recs.next_of(m, j, "segments")
        recs.need(ln, toks, 3, "index endpoint endpoint")
        num = recs.int_(ln, toks[0], "the segment number")
        segs[j, 0] = _vertex(recs, ln, toks[1], f"segment {num}'s first endpoint", first, n)
        segs[j, 1] = _vertex(recs, ln, toks[2], f"segment {num}'s second endpoint", first, n)
        if smarks is not None and len(toks) > 3:
            smarks[j] = recs.int_(ln, toks[3], f"boundary marker of segment {num}")

    holes = np.zeros((0, 2), dtype=np.float64)
    if not recs.at_end():
        ln, head = recs.next("the hole count")
        h = recs.count(ln, head[0], "number of holes")
        holes = np.empty((h, 2), dtype=np.float64)
        for j in range(h):
            ln, toks = recs.next_of(h, j, "holes")
            recs.need(ln, toks, 3, "index x y")
            holes[j, 0] = recs.float_(ln, toks[1], f"x of hole {toks[0]}")
            holes[j, 1] = recs.float_(ln, toks[2], f"y of hole {toks[0]}")

    regions = np.zeros((0, 4), dtype=np.float64)
    if not recs.at_end():
        ln, head = recs.next("the region count")
        r = recs.count(ln, head[0], "number of regions")
        regions = np.empty((r, 4), dtype=np.float64)
        for j in range(r):
            ln, toks = recs.next_of(r, j, "regions")
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
    recs = Records(path)
    ln0, head = recs.next("the header '<#triangles> <nodes per triangle> <#attributes>'")
    k = recs.count(ln0, head[0], "number of triangles")
    npt = recs.int_(ln0, head[1], "nodes per triangle") if len(head) > 1 else 3
    if npt not in (3, 6):
        raise recs.error(ln0, f"nodes per triangle must be 3 or 6, got {npt}")
    nattr = recs.count(ln0, head[2], "number of attributes") if len(head) > 2 else 0
    tris = np.empty((k, npt), dtype=np.int64)
    attrs = np.zeros((k, nattr), dtype=np.float64)
    base = first_index
    for i in range(k):
        ln, toks = recs.next_of(k, i, "triangles")
        recs.need(ln, toks, 1 + npt, "index " + " ".join(f"n{c + 1}" for c in range(npt)))
        num = recs.int_(ln, toks[0], "the triangle number")
        if base is None:                # the first record, with no base given
            base = recs.first_number(ln, toks[0], "triangle")
        for c in range(npt):
            tris[i, c] = _vertex(recs, ln, toks[1 + c], f"corner {c + 1} of triangle {num}", base,
                                 n_vertices)
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
    recs = Records(path)
    ln0, head = recs.next("the header '<#edges> <#boundary markers>'")
    m = recs.count(ln0, head[0], "number of edges")
    emark = recs.flag(ln0, head, 1, "number of boundary markers")
    edges = np.empty((m, 2), dtype=np.int64)
    marks = np.zeros(m, dtype=np.int64) if emark else None
    base = first_index
    for i in range(m):
        ln, toks = recs.next_of(m, i, "edges")
        recs.need(ln, toks, 3, "index endpoint endpoint")
        num = recs.int_(ln, toks[0], "the edge number")
        if base is None:                # the first record, with no base given
            base = recs.first_number(ln, toks[0], "edge")
        for c in range(2):
            edges[i, c] = _vertex(recs, ln, toks[1 + c], f"endpoint {c + 1} of edge {num}", base,
                                  n_vertices)
        if marks is not None and len(toks) > 3:
            marks[i] = recs.int_(ln, toks[3], f"boundary marker of edge {num}")
    recs.expect_end(f"the {m} edges")
    return EdgeData(edges, marks, 1 if base is None else base)


def read_neigh(path: str | os.PathLike[str], first_index: int | None = None) -> NDArray[np.int64]:
    """Read a Triangle ``.neigh`` file: (k, 3) int64 zero-based triangle indices, -1 for none.

    Neighbour j of a triangle is the one opposite its corner j.
    """
    recs = Records(path)
    ln0, head = recs.next("the header '<#triangles> <#neighbors per triangle>'")
    k = recs.count(ln0, head[0], "number of triangles")
    if len(head) > 1:
        nn = recs.int_(ln0, head[1], "neighbours per triangle")
        if nn != 3:
            raise recs.error(ln0, f"neighbours per triangle must be 3, got {nn}")
    out = np.empty((k, 3), dtype=np.int64)
    base = first_index
    for i in range(k):
        ln, toks = recs.next_of(k, i, "triangles")
        recs.need(ln, toks, 4, "index n1 n2 n3")
        num = recs.int_(ln, toks[0], "the triangle number")
        if base is None:                # the first record, with no base given
            base = recs.first_number(ln, toks[0], "triangle")
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
