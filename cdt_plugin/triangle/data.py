"""Triangle's files as the ``triangle`` package's dictionaries: :func:`load`,
:func:`loads`, :func:`get_data`, :func:`show_data`, read with :mod:`cdt_plugin.io`.

The keys are the package's: ``vertices`` (float64), ``vertex_attributes`` and
``vertex_markers`` ((n, 1) int32) when the file has them, ``segments``,
``segment_markers``, ``holes``, ``regions`` from a ``.poly``, ``triangles`` and
``triangle_attributes`` from a ``.ele``, ``triangle_max_area`` (k, 1) from a
``.area``, ``edges`` (and ``edge_markers``) from a ``.edge``, ``triangle_neighbors``
from a ``.neigh``; indices zero-based. Where the package misreads a file we read it
as Triangle does: a region line is ``x y attribute max_area`` (the package puts the
attribute in the area column and 0 in the attribute column), a file numbered from 1
is renumbered from 0 whichever files are given, an edge file without rays is read
(the package fails on it); a malformed file raises
:class:`~cdt_plugin.errors.FileFormatError` naming the file and the line.

We do not ship Triangle's sample files (their license is not ours):
:func:`get_data` reads them from the folder named by the environment variable
``CDT_TRIANGLE_DATA``, else from the installed ``triangle`` package's ``data`` folder.
"""
from __future__ import annotations

import importlib.util
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import SampleDataError
from ..io import read_edge, read_ele, read_neigh, read_node, read_poly
from ..io.records import Records

#: The environment variable naming a folder of Triangle's sample files.
DATA_VARIABLE = "CDT_TRIANGLE_DATA"
EXTENSIONS = ("node", "ele", "poly", "area", "edge", "neigh")


def load(directory: str | os.PathLike[str], name: str) -> dict[str, NDArray[Any]]:
    """The files ``directory/name.{node,ele,poly,area,edge,neigh}`` that exist, as one
    dictionary (``triangle.load``).

    >>> import os, tempfile
    >>> from cdt_plugin import triangle as tr
    >>> folder = tempfile.mkdtemp()
    >>> with open(os.path.join(folder, "tri.node"), "w") as f:
    ...     _ = f.write("3 2 0 1\\n1 0 0 5\\n2 1 0 0\\n3 0 1 0\\n")
    >>> data = tr.load(folder, "tri")
    >>> data["vertices"].tolist(), data["vertex_markers"].tolist()
    ([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [[5], [0], [0]])
    """
    base = Path(directory) / name
    path = {ext: base.with_name(f"{base.name}.{ext}") for ext in EXTENSIONS}
    data: dict[str, NDArray[Any]] = {}
    first, n = 0, None
    if path["node"].exists():
        node = read_node(path["node"])
        first, n = node.first_index, len(node.vertices)
        _vertices(data, node)
    if path["poly"].exists():
        poly = read_poly(path["poly"])
        first, n = poly.first_index, len(poly.vertices)
        _vertices(data, poly)
        _put(data, "segments", poly.segments.astype(np.intc))
        if poly.segment_markers is not None:
            _put(data, "segment_markers", _column(poly.segment_markers))
        _put(data, "holes", poly.holes)
        _put(data, "regions", poly.regions)
    if path["ele"].exists():
        ele = read_ele(path["ele"], first if n is not None else None, n)
        _put(data, "triangles", ele.triangles.astype(np.intc))
        if ele.attributes.shape[1]:
            _put(data, "triangle_attributes", ele.attributes)
    if path["area"].exists():
        _put(data, "triangle_max_area", _read_area(path["area"]))
    if path["edge"].exists():
        if _has_rays(path["edge"]):
            _voronoi_edges(data, path["edge"], first)
        else:
            edge = read_edge(path["edge"], first if n is not None else None, n)
            _put(data, "edges", edge.edges.astype(np.intc))
            if edge.markers is not None:
                _put(data, "edge_markers", _column(edge.markers))
    if path["neigh"].exists():
        _put(data, "triangle_neighbors", read_neigh(path["neigh"], first).astype(np.intc))
    return data


def loads(node: str | None = None, ele: str | None = None, poly: str | None = None,
          area: str | None = None, edge: str | None = None,
          neigh: str | None = None) -> dict[str, NDArray[Any]]:
    """The same dictionary as :func:`load` from the files' texts (``triangle.loads``).

    >>> from cdt_plugin import triangle as tr
    >>> data = tr.loads(poly="3 2 0 0\\n0 0 0\\n1 1 0\\n2 0 1\\n3 0\\n0 0 1\\n1 1 2\\n2 2 0\\n0\\n")
    >>> data["segments"].tolist()
    [[0, 1], [1, 2], [2, 0]]
    """
    texts = {"node": node, "ele": ele, "poly": poly, "area": area, "edge": edge, "neigh": neigh}
    with tempfile.TemporaryDirectory() as folder:
        for ext, text in texts.items():
            if text:
                Path(folder, f"data.{ext}").write_text(text)
        return load(folder, "data")


def get_data(name: str) -> dict[str, NDArray[Any]]:
    """One of Triangle's samples (``A``, ``box``, ``dots``, ``ell``, ``face``, ``la``...)
    as a dictionary (``triangle.get_data``), from :func:`data_dir`.

    Raises :class:`~cdt_plugin.errors.SampleDataError` naming where it looked when
    there is no file ``name.*`` there.
    """
    folder = data_dir()
    if not any(Path(folder, f"{name}.{ext}").exists() for ext in EXTENSIONS):
        raise SampleDataError(f"no Triangle sample {name!r} ({name}.node, {name}.poly...) in "
                              f"{folder}")
    return load(folder, name)


def data_dir() -> str:
    """The folder of Triangle's sample files: ``$CDT_TRIANGLE_DATA``, else the
    installed ``triangle`` package's ``data`` folder; else
    :class:`~cdt_plugin.errors.SampleDataError` saying how to point to them."""
    folder = os.environ.get(DATA_VARIABLE)
    if folder:
        if not Path(folder).is_dir():
            raise SampleDataError(f"{DATA_VARIABLE}={folder!r} is not a folder")
        return folder
    spec = importlib.util.find_spec("triangle")
    if spec is not None and spec.origin is not None:
        folder = str(Path(spec.origin).parent / "data")
        if Path(folder).is_dir():
            return folder
    raise SampleDataError("Triangle's sample files are not shipped with cdt_plugin (their "
                          f"license is not ours): set {DATA_VARIABLE} to a folder holding them "
                          "(A.poly, dots.node...), or install the triangle package, whose data "
                          "folder is then read")


def show_data(name: str) -> None:
    """Plot the sample ``name`` with matplotlib and show it (``triangle.show_data``)."""
    from ..optional import require
    plt = require("matplotlib.pyplot", "show_data")
    from .plot import plot
    plot(plt.axes(), **get_data(name))
    plt.show()


def _vertices(data: dict[str, NDArray[Any]], nodes: Any) -> None:
    _put(data, "vertices", nodes.vertices)
    if nodes.attributes.shape[1]:
        _put(data, "vertex_attributes", nodes.attributes)
    if nodes.markers is not None:
        _put(data, "vertex_markers", _column(nodes.markers))


def _column(markers: NDArray[np.int64]) -> NDArray[np.intc]:
    return markers.astype(np.intc).reshape(-1, 1)


def _put(data: dict[str, NDArray[Any]], key: str, value: NDArray[Any]) -> None:
    if len(value):          # (the package leaves out what a file has none of)
        data[key] = value


def _has_rays(path: Path) -> bool:
    """Whether an ``.edge`` file is a Voronoi diagram's (``-v``): a ray's second
    endpoint is ``-1``, followed by its direction."""
    return any(len(toks) >= 5 and toks[2] == "-1" for _, toks in Records(path).recs[1:])


def _voronoi_edges(data: dict[str, NDArray[Any]], path: Path, first: int) -> None:
    """A Voronoi ``.edge`` file (``<edge#> <v1> <v2>``, a ray ``<edge#> <v1> -1 <dx>
    <dy>``) as the package reads it: ``edges`` (finite), ``ray_origins`` (r, 1) and
    ``ray_directions`` (r, 2)."""
    recs = Records(path)
    ln, head = recs.next("the header '<#edges> <#boundary markers>'")
    m = recs.count(ln, head[0], "number of edges")
    edges, origins, directions = [], [], []
    for i in range(m):
        ln, toks = recs.next_of(m, i, "edges")
        recs.need(ln, toks, 3, "index endpoint endpoint")
        a, b = (recs.int_(ln, t, f"an endpoint of edge {toks[0]}") for t in toks[1:3])
        if b == -1:
            recs.need(ln, toks, 5, "index endpoint -1 dx dy")
            origins.append(a - first)
            directions.append([recs.float_(ln, t, f"the direction of ray {toks[0]}")
                               for t in toks[3:5]])
        else:
            edges.append([a - first, b - first])
    recs.expect_end(f"the {m} edges")
    _put(data, "edges", np.array(edges, np.intc).reshape(-1, 2))
    _put(data, "ray_origins", np.array(origins, np.intc).reshape(-1, 1))
    _put(data, "ray_directions", np.array(directions, np.float64).reshape(-1, 2))


def _read_area(path: Path) -> NDArray[np.float64]:
    """A ``.area`` file: ``<#triangles>``, then ``<triangle#> <maximum area>`` (<= 0:
    no bound), as a (k, 1) column."""
    recs = Records(path)
    ln, head = recs.next("the header '<#triangles>'")
    k = recs.count(ln, head[0], "number of triangles")
    out = np.empty((k, 1))
    for i in range(k):
        ln, toks = recs.next_of(k, i, "triangles")
        recs.need(ln, toks, 2, "index max_area")
        out[i, 0] = recs.float_(ln, toks[1], f"maximum area of triangle {toks[0]}")
    recs.expect_end(f"the {k} areas")
    return out
