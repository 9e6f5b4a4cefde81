"""The writers of Triangle's file formats: every vertex, triangle and edge numbered
from :data:`WRITE_FIRST_INDEX` (Triangle's default), every float written as its
``repr`` (which reads back bit for bit)."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from ..errors import InputShapeError, NonFiniteCoordinateError
from ..triangulation import Triangulation
from ..validate import as_index, as_xy

#: The vertex number the writers start from (Triangle's default numbering).
WRITE_FIRST_INDEX = 1


def _fmt(x: float) -> str:
    return repr(float(x))


def _opt_rows(a: ArrayLike | None, n: int, what: str, dtype: DTypeLike) -> NDArray[Any] | None:
    if a is None:
        return None
    arr = np.asarray(a, dtype=dtype)
    if arr.shape[:1] != (n,):
        raise InputShapeError(f"{what} must have {n} rows, got shape {arr.shape}")
    return arr


def _attribute_rows(attributes: ArrayLike | None, n: int) -> NDArray[np.float64] | None:
    """``attributes`` as (n, a) float64 (one attribute may be given as (n,)), or None."""
    attrs = _opt_rows(attributes, n, "attributes", np.float64)
    if attrs is not None and attrs.ndim == 1:
        attrs = attrs[:, None]
    return attrs


def _edge_lines(edges: NDArray[np.int64], markers: NDArray[np.int64] | None,
                f0: int = WRITE_FIRST_INDEX) -> list[str]:
    """The lines of a ``.edge`` file, which are also the segment section of a ``.poly``:
    ``<#edges> <#markers 0|1>``, then ``<#> <endpoint> <endpoint> [marker]``, numbered
    from ``f0``."""
    _check_first(f0)
    lines = [f"{edges.shape[0]} {0 if markers is None else 1}"]
    for i in range(edges.shape[0]):
        row = f"{i + f0} {edges[i, 0] + f0} {edges[i, 1] + f0}"
        if markers is not None:
            row += f" {int(markers[i])}"
        lines.append(row)
    return lines


def _node_lines(vertices: ArrayLike, attributes: ArrayLike | None,
                markers: ArrayLike | None, f0: int = WRITE_FIRST_INDEX) -> list[str]:
    _check_first(f0)
    v = as_xy(vertices, "vertices", empty=True)
    n = v.shape[0]
    attrs = _attribute_rows(attributes, n)
    marks = _opt_rows(markers, n, "markers", np.int64)
    na = 0 if attrs is None else attrs.shape[1]
    lines = [f"{n} 2 {na} {0 if marks is None else 1}"]
    for i in range(n):
        parts = [str(i + f0), _fmt(v[i, 0]), _fmt(v[i, 1])]
        if attrs is not None:
            parts.extend(_fmt(x) for x in attrs[i])
        if marks is not None:
            parts.append(str(int(marks[i])))
        lines.append(" ".join(parts))
    return lines


def _check_first(f0: int) -> None:
    if f0 not in (0, 1):
        raise InputShapeError(f"first_index must be 0 or 1 (Triangle's numberings), got {f0!r}")


def _write(path: str | os.PathLike[str], lines: list[str], kind: str,
           f0: int = WRITE_FIRST_INDEX) -> None:
    header = f"# {kind} written by cdt_plugin.io (numbering from {f0})"
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(header + "\n" + "\n".join(lines) + "\n")


def _mesh_array(data: ArrayLike | Triangulation, name: str) -> ArrayLike:
    """``data.<name>`` when ``data`` is a :class:`~cdt_plugin.Triangulation`, else ``data``."""
    return getattr(data, name) if isinstance(data, Triangulation) else data


def write_node(path: str | os.PathLike[str], vertices: ArrayLike | Triangulation,
               attributes: ArrayLike | None = None, markers: ArrayLike | None = None, *,
               first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a ``.node`` file, vertices numbered from ``first_index`` (1, Triangle's
    default, or 0 as its ``-z``); floats round-trip exactly.
    ``vertices``: an (n, 2) array or a Triangulation (its vertices).

    >>> import os, tempfile, cdt_plugin
    >>> from cdt_plugin.io import read_node
    >>> path = os.path.join(tempfile.mkdtemp(), "tri.node")
    >>> write_node(path, cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]]))
    >>> read_node(path).vertices.tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    _write(path, _node_lines(_mesh_array(vertices, "vertices"), attributes, markers, first_index),
           "Triangle .node", first_index)


def write_poly(path: str | os.PathLike[str], vertices: ArrayLike | Triangulation,
               segments: ArrayLike | None = None, holes: ArrayLike | None = None,
               regions: ArrayLike | None = None, segment_markers: ArrayLike | None = None,
               attributes: ArrayLike | None = None, markers: ArrayLike | None = None, *,
               first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a ``.poly`` file (vertices inline, numbered from ``first_index``: 1 or 0).

    ``segments`` are zero-based in memory; ``regions`` rows are (x, y, attribute, max_area),
    a NaN max_area is written as -1 (no constraint, in Triangle's reading). ``vertices``
    may be a Triangulation: its vertices and (unless given) its segment pieces are
    written, as Triangle writes its output ``.poly``.

    >>> import os, tempfile
    >>> from cdt_plugin.io import read_poly
    >>> path = os.path.join(tempfile.mkdtemp(), "seg.poly")
    >>> write_poly(path, [[0, 0], [1, 0]], [[0, 1]])
    >>> read_poly(path).segments.tolist()
    [[0, 1]]
    """
    if segments is None:
        segments = _mesh_array(vertices, "segments")
        if segments is vertices:
            raise InputShapeError("write_poly needs segments (or a Triangulation)")
    f0 = first_index
    lines = _node_lines(_mesh_array(vertices, "vertices"), attributes, markers, f0)
    n = int(lines[0].split()[0])
    s = as_index(segments, "segments", 2, n)
    smarks = _opt_rows(segment_markers, s.shape[0], "segment_markers", np.int64)
    lines += _edge_lines(s, smarks, f0)
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
    _write(path, lines, "Triangle .poly", f0)


def write_ele(path: str | os.PathLike[str], triangles: ArrayLike | Triangulation,
              attributes: ArrayLike | None = None, *, first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a ``.ele`` file (triangles and corners numbered from ``first_index``: 1
    or 0). ``triangles``: a
    (k, 3) or (k, 6) index array or a Triangulation (its triangles).

    >>> import os, tempfile, cdt_plugin
    >>> from cdt_plugin.io import read_ele
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
    attrs = _attribute_rows(attributes, t.shape[0])
    na = 0 if attrs is None else attrs.shape[1]
    f0 = first_index
    _check_first(f0)
    lines = [f"{t.shape[0]} {cols} {na}"]
    for i in range(t.shape[0]):
        parts = [str(i + f0)] + [str(int(x) + f0) for x in t[i]]
        if attrs is not None:
            parts.extend(_fmt(x) for x in attrs[i])
        lines.append(" ".join(parts))
    _write(path, lines, "Triangle .ele", f0)


def write_edge(path: str | os.PathLike[str], edges: ArrayLike | Triangulation,
               markers: ArrayLike | None = None, *, first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a ``.edge`` file (edges and endpoints numbered from ``first_index``: 1 or
    0). ``edges``: an (m, 2)
    index array or a Triangulation (every edge of its triangles)."""
    e = as_index(_mesh_array(edges, "edges"), "edges", 2)
    if (e < 0).any():
        raise InputShapeError("edges contain negative vertex indices")
    marks = _opt_rows(markers, e.shape[0], "markers", np.int64)
    _write(path, _edge_lines(e, marks, first_index), "Triangle .edge", first_index)


def write_neigh(path: str | os.PathLike[str], neighbors: ArrayLike | Triangulation, *,
                first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a ``.neigh`` file (triangles numbered from ``first_index``: 1 or 0; -1 for
    no neighbour).
    ``neighbors``: a (k, 3) array (column j: across the edge opposite corner j, as
    Triangle numbers them) or a Triangulation (its neighbours)."""
    nb = as_index(_mesh_array(neighbors, "neighbors"), "neighbors", 3)
    k = nb.shape[0]
    if ((nb < -1) | (nb >= k)).any():
        raise InputShapeError(f"neighbors must be -1 or in 0..{k - 1}")
    f0 = first_index
    _check_first(f0)
    lines = [f"{k} 3"]
    for i in range(k):
        lines.append(" ".join([str(i + f0)] + [str(int(x) + f0) if x >= 0 else "-1"
                                                for x in nb[i]]))
    _write(path, lines, "Triangle .neigh", f0)


def write_triangulation(path: str | os.PathLike[str], tri: Triangulation,
                        attributes: ArrayLike | None = None, *, markers: bool = False,
                        order: int = 1) -> list[Path]:
    """Write a Triangulation as Triangle writes its output: ``<base>.node``,
    ``<base>.ele`` (with ``attributes`` per triangle, if given) and ``<base>.poly``
    (its segment pieces), ``<base>`` being ``path`` without its extension. Returns
    the three paths.

    The vertices' attributes go in the ``.node`` file when the triangulation has
    them (``tri.vertex_attributes``); ``markers``: the boundary markers of the
    vertices and segment pieces too (``tri.vertex_markers``,
    ``tri.segment_markers``), as Triangle writes them unless ``-B``. ``order=2``:
    six-node triangles (Triangle's ``-o2``, :meth:`Triangulation.quadratic`), the
    edges' midpoints in the ``.node`` file after the vertices.

    >>> import os, tempfile, cdt_plugin
    >>> from cdt_plugin.io import read_ele, read_node
    >>> base = os.path.join(tempfile.mkdtemp(), "square")
    >>> tri = cdt_plugin.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> [p.name for p in write_triangulation(base + ".ele", tri)]
    ['square.node', 'square.ele', 'square.poly']
    >>> read_ele(base + ".ele").triangles.shape
    (2, 3)
    >>> paths = write_triangulation(base, tri, markers=True, order=2)
    >>> read_ele(paths[1]).triangles.shape, read_node(paths[0]).markers.tolist()
    ((2, 6), [1, 1, 1, 1, 1, 1, 0, 1, 1])
    """
    if order not in (1, 2):
        raise InputShapeError(f"order must be 1 or 2 (six-node triangles), got {order!r}")
    base = Path(path).with_suffix("")
    paths = [base.with_suffix(s) for s in (".node", ".ele", ".poly")]
    mesh = tri.quadratic() if order == 2 else tri
    write_node(paths[0], mesh.vertices, mesh.vertex_attributes,
               mesh.vertex_markers if markers else None)
    write_ele(paths[1], mesh.triangles, attributes=attributes)
    write_poly(paths[2], tri.vertices, tri.segments,
               segment_markers=tri.segment_markers if markers else None)
    return paths


def write_voronoi(node_path: str | os.PathLike[str], edge_path: str | os.PathLike[str],
                  points: ArrayLike, edges: ArrayLike, rays: tuple[ArrayLike, ArrayLike], *,
                  first_index: int = WRITE_FIRST_INDEX) -> None:
    """Write a Voronoi diagram as Triangle's ``-v`` does: its vertices to a ``.v.node``
    file, its edges to a ``.v.edge`` file, where a finite edge is ``<#> <v1> <v2>`` and
    a ray ``<#> <v1> -1 <dx> <dy>`` (from vertex ``v1`` in the direction ``(dx, dy)``).
    ``edges`` (m, 2) and ``rays`` ``(origins (r,), directions (r, 2))`` are zero-based;
    everything is numbered from ``first_index``.

    >>> import os, tempfile
    >>> from cdt_plugin.io import read_node
    >>> d = tempfile.mkdtemp()
    >>> write_voronoi(os.path.join(d, "a.v.node"), os.path.join(d, "a.v.edge"), [[0.5, 0.5]],
    ...               [], ([0, 0], [[0, -1], [1, 1]]))
    >>> open(os.path.join(d, "a.v.edge")).read().splitlines()[1:]
    ['2 0', '1 1 -1 0.0 -1.0', '2 1 -1 1.0 1.0']
    """
    f0 = first_index
    _check_first(f0)
    pts = as_xy(points, "points", empty=True)
    e = as_index(np.asarray(edges, np.int64).reshape(-1, 2), "edges", 2, pts.shape[0])
    origin = as_index(np.asarray(rays[0], np.int64).reshape(-1, 1), "ray origins", 1,
                      pts.shape[0]).reshape(-1)
    direction = np.asarray(rays[1], np.float64).reshape(-1, 2)
    if len(direction) != len(origin) or not np.isfinite(direction).all():
        raise InputShapeError("rays must be one finite direction per origin")
    _write(node_path, _node_lines(pts, None, None, f0), "Triangle .v.node", f0)
    lines = [f"{len(e) + len(origin)} 0"]
    lines += [f"{i + f0} {e[i, 0] + f0} {e[i, 1] + f0}" for i in range(len(e))]
    lines += [f"{len(e) + j + f0} {origin[j] + f0} -1 {_fmt(direction[j, 0])} {_fmt(direction[j, 1])}"
              for j in range(len(origin))]
    _write(edge_path, lines, "Triangle .v.edge", f0)


def write_off(path: str | os.PathLike[str], vertices: ArrayLike, triangles: ArrayLike) -> None:
    """Write a mesh in Geomview's Object File Format as Triangle's ``-g`` does: ``OFF``,
    the counts, each vertex as ``x y 0``, each triangle as ``3 a b c`` (numbered from 0:
    the format's rule; six-node triangles give their corners).

    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "t.off")
    >>> write_off(path, [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    >>> open(path).read().splitlines()
    ['OFF', '3 1 0', '0.0 0.0 0.0', '1.0 0.0 0.0', '0.0 1.0 0.0', '3 0 1 2']
    """
    v = as_xy(vertices, "vertices", empty=True)
    t = np.asarray(triangles)
    t = as_index(t[:, :3] if t.ndim == 2 and t.shape[1] == 6 else t, "triangles", 3, v.shape[0])
    lines = ["OFF", f"{v.shape[0]} {t.shape[0]} 0"]
    lines += [f"{_fmt(x)} {_fmt(y)} 0.0" for x, y in v]
    lines += [f"3 {a} {b} {c}" for a, b, c in t]
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
