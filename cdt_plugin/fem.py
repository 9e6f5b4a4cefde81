"""Finite-element meshes of a triangulation: :meth:`cdt_plugin.Triangulation.to_meshio`
(a ``meshio.Mesh``, for gmsh's ``.msh``, VTK's ``.vtu``, XDMF and the other formats
meshio writes) and :meth:`cdt_plugin.Triangulation.to_skfem` (a scikit-fem mesh with
named boundaries and subdomains).

The tags follow the markers of :mod:`cdt_plugin.markers`:

* a **segment piece** (a row of ``tri.segments``) is a ``line`` cell (``line3`` for
  six-node triangles) whose gmsh *physical* tag is its segment marker;
* a **triangle** is a ``triangle`` cell (``triangle6``) whose physical tag is its
  region attribute when every one is a whole number (Triangle's ``-A``), else its
  region index + 1 (1 for a mesh without regions; :func:`gmsh_physical`);
* cells are grouped by physical tag, one cell block per tag (in the order of the
  triangulation inside each block), each block one gmsh *geometrical* entity
  (numbered from 1 per dimension), as gmsh's format 4.1 wants.

>>> import cdt_plugin
>>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 2], [0, 2]], [[0, 1], [1, 2], [2, 3], [3, 0]],
...                              segment_markers=[3, 3, 5, 5])
>>> mesh = tri.to_meshio()
>>> [(block.type, len(block.data)) for block in mesh.cells]
[('triangle', 2), ('line', 2), ('line', 2)]
>>> [tags.tolist() for tags in mesh.cell_data["gmsh:physical"]]
[[1, 1], [3, 3], [5, 5]]
>>> sorted(tri.to_skfem().boundaries)
['marker_3', 'marker_5']
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Dict, List, Tuple

import numpy as np
from numpy.typing import NDArray

from .errors import MeshExportError
from .optional import require
from .quadratic import edge_rows

if TYPE_CHECKING:
    import meshio
    import skfem

__all__ = ["gmsh_physical", "gmsh_tags_only", "to_meshio", "to_skfem"]

_INT_MIN, _INT_MAX = -2 ** 31, 2 ** 31 - 1        # gmsh's tags are C ints

#: Names given to scikit-fem: ``{name: a marker or region id, or a list of them}``.
Names = Mapping[str, Any]


def to_meshio(tri: Any, quadratic: bool = False) -> meshio.Mesh:
    """The triangulation ``tri`` as a ``meshio.Mesh`` (see the module's notes).

    Cell data, one array per cell block: ``gmsh:physical`` and ``gmsh:geometrical``
    (the tags gmsh's readers and writers use), and under plain names ``region``
    (``tri.regions``; -1 on lines), ``marker`` (the segment markers; 0 on triangles)
    and, when the triangulation has them, ``region_attribute`` (NaN on lines). Point
    data: ``vertex_markers``, one ``vertex_attribute_<j>`` per attribute column
    (``j`` from 1: gmsh takes 1, 3 or 9 components per field) and ``gmsh:dim_tags``,
    the entity of each node that meshio's gmsh 4.1 writer needs: it is left out when
    no assignment gives every entity a node of its own (a coarse mesh with more
    differently marked sides than vertices), and such a mesh is written as msh 2.2
    (``file_format="gmsh22"``), which tags every element by itself.

    ``quadratic``: six-node triangles and three-node lines (the midpoint nodes of
    :meth:`~cdt_plugin.Triangulation.quadratic` after the vertices).
    """
    _check_quadratic(quadratic)
    _need_triangles(tri, "to_meshio")
    meshio = require("meshio", "Triangulation.to_meshio")
    points, triangles, lines, point_data = _nodes_and_cells(tri, quadratic)
    regions = np.asarray(tri.regions, np.int64)
    markers = np.asarray(tri.segment_markers, np.int64)
    plain_triangles = {"region": regions, "marker": np.zeros(len(regions), np.int64)}
    plain_lines = {"region": np.full(len(lines), -1, np.int64), "marker": markers}
    if tri.region_attributes is not None:
        plain_triangles["region_attribute"] = np.asarray(tri.region_attributes, np.float64)
        plain_lines["region_attribute"] = np.full(len(lines), np.nan)
    kinds = ("triangle6", "line3") if quadratic else ("triangle", "line")
    blocks = (_blocks(kinds[0], 2, triangles, gmsh_physical(tri), plain_triangles)
              + _blocks(kinds[1], 1, lines, markers, plain_lines))
    cell_data = {name: [block[3][name] for block in blocks] for name in blocks[0][3]}
    dim_tags = _node_entities(len(points), blocks)
    if dim_tags is not None:
        point_data["gmsh:dim_tags"] = dim_tags
    return meshio.Mesh(points, [(kind, data) for kind, _, data, _ in blocks],
                       point_data=point_data, cell_data=cell_data)


def _nodes_and_cells(tri: Any, quadratic: bool) -> tuple[NDArray[np.float64], NDArray[np.int64],
                                                          NDArray[np.int64], Dict[str, NDArray[Any]]]:
    """The nodes, triangle cells and line cells (in meshio's node order) and the
    point data (markers, attribute columns) of ``tri``: its vertices and
    triangles, or the six-node mesh of :meth:`~cdt_plugin.Triangulation.quadratic`."""
    segments = np.asarray(tri.segments, np.int64).reshape(-1, 2)
    if quadratic:
        qm = tri.quadratic()
        base = qm.to_meshio()                  # (meshio's node order of triangle6)
        points, triangles = base.points, base.cells[0].data
        lines = np.column_stack([segments, len(tri.vertices) + edge_rows(qm.edges, segments)])
        point_data = {"vertex_markers": qm.vertex_markers}
        attributes = qm.vertex_attributes
    else:
        points, triangles, lines = np.asarray(tri.vertices, np.float64), tri.triangles, segments
        point_data = {"vertex_markers": tri.vertex_markers}
        attributes = tri.vertex_attributes
    for j in range(0 if attributes is None else attributes.shape[1]):
        point_data[f"vertex_attribute_{j + 1}"] = attributes[:, j]
    return points, triangles, lines, point_data


def gmsh_tags_only(mesh: meshio.Mesh) -> meshio.Mesh:
    """``mesh`` (from :func:`to_meshio`) with gmsh's tags as its only data: the cell
    data ``gmsh:physical`` and ``gmsh:geometrical`` and the point data
    ``gmsh:dim_tags``. What a ``.msh`` file should hold: gmsh shows data fields as
    post-processing views, and meshio 5.3 reads the fields of a msh 2.2 file with
    several cell blocks back wrongly and, with NumPy 2, writes ASCII fields that it
    cannot read.

    >>> import cdt_plugin
    >>> tri = cdt_plugin.triangulate([[0, 0], [2, 0], [0, 2]], [[0, 1], [1, 2], [2, 0]])
    >>> sorted(gmsh_tags_only(tri.to_meshio()).cell_data)
    ['gmsh:geometrical', 'gmsh:physical']
    """
    meshio = require("meshio", "fem.gmsh_tags_only")
    for name in ("gmsh:physical", "gmsh:geometrical"):
        for block, tags in zip(mesh.cells, mesh.cell_data.get(name, [])):
            if len(tags) and not (tags.min() >= _INT_MIN and tags.max() <= _INT_MAX):
                bad = tags[(tags < _INT_MIN) | (tags > _INT_MAX)][0]
                raise MeshExportError(f"{name} tag {bad} of a {block.type} cell does not fit "
                                      "gmsh's 32-bit tags: mark with smaller numbers")
    return meshio.Mesh(mesh.points, mesh.cells,
                       point_data={k: v for k, v in mesh.point_data.items() if k.startswith("gmsh:")},
                       cell_data={k: v for k, v in mesh.cell_data.items() if k.startswith("gmsh:")})


def gmsh_physical(tri: Any) -> NDArray[np.int64]:
    """The gmsh physical tag of each triangle of ``tri``: its region attribute when
    every one is a whole number of 32 bits, else its region index + 1 (gmsh counts from 1), and
    for a triangle in no region one more than the largest of those (a mesh without
    regions: 1 everywhere; every tag positive, as gmsh's physical groups are).

    >>> import cdt_plugin
    >>> square = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 0], [1, 2]]
    >>> sides = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    >>> tri = cdt_plugin.triangulate(square, sides, regions=[[0.5, 1, 7], [1.5, 1, 9]])
    >>> gmsh_physical(tri).tolist()
    [7, 7, 9, 9]
    """
    values = tri.region_attributes
    if values is not None:
        values = np.asarray(values, np.float64)
        if (np.abs(values) <= _INT_MAX).all() and (values == np.round(values)).all():
            return values.astype(np.int64)
    regions = np.asarray(tri.regions, np.int64)
    tags = regions + 1
    tags[regions < 0] = tags.max(initial=0) + 1        # (no region at all: every tag 1)
    return tags


Block = Tuple[str, int, NDArray[np.int64], Dict[str, NDArray[Any]]]


def _blocks(kind: str, dim: int, cells: NDArray[np.int64], tags: NDArray[np.int64],
            plain: Dict[str, NDArray[Any]]) -> List[Block]:
    """One block ``(kind, dim, cells, cell data)`` per distinct tag, in tag order,
    the cells in their order (geometrical entities numbered 1, 2, ... per ``dim``)."""
    out: List[Block] = []
    for entity, tag in enumerate(np.unique(tags), start=1):
        rows = np.flatnonzero(tags == tag)
        data = {"gmsh:physical": np.full(len(rows), tag, np.int64),
                "gmsh:geometrical": np.full(len(rows), entity, np.int64),
                **{name: values[rows] for name, values in plain.items()}}
        out.append((kind, dim, np.ascontiguousarray(cells[rows], np.int64), data))
    return out


def _node_entities(n: int, blocks: List[Block]) -> NDArray[np.int64] | None:
    """``(dim, entity)`` of every node such that each block's entity holds at least
    one node of its cells (meshio's msh 4.1 writer lists only the entities that hold
    nodes, and reads a block of an unlisted entity as an error), or None when there
    is no such assignment. Lines claim their nodes over triangles; a block left
    without a node gets one by a bipartite matching of blocks to distinct nodes
    (augmenting paths: the blocks are few)."""
    owner = np.zeros(n, np.int64)           # (a node in no cell: the first block's)
    for b, block in enumerate(blocks):
        owner[block[2].ravel()] = b
    held, first = np.unique(owner, return_index=True)
    chosen = dict(zip(first.tolist(), held.tolist()))      # node -> the block it is kept for
    nodes: Dict[int, List[int]] = {}                      # (each block's, when first needed)
    if not all(_augment(b, blocks, nodes, chosen, set())
               for b in np.setdiff1d(np.arange(len(blocks)), held).tolist()):
        return None
    for v, b in chosen.items():
        owner[v] = b
    entity = np.array([(block[1], block[3]["gmsh:geometrical"][0]) for block in blocks], np.int64)
    return entity[owner]


def _augment(b: int, blocks: List[Block], nodes: Dict[int, List[int]], chosen: Dict[int, int],
             seen: set[int]) -> bool:
    """Keep a node for block ``b``: a free one of its nodes, or one whose block
    can be moved to another node in turn (Kuhn's augmenting path). ``nodes``:
    the distinct nodes of the blocks asked so far."""
    if b not in nodes:
        nodes[b] = np.unique(blocks[b][2]).tolist()
    for v in nodes[b]:
        if v in seen:
            continue
        seen.add(v)
        if v not in chosen or _augment(chosen[v], blocks, nodes, chosen, seen):
            chosen[v] = b
            return True
    return False


def to_skfem(tri: Any, quadratic: bool = False, *, boundaries: Names | None = None,
             subdomains: Names | None = None) -> skfem.Mesh:
    """The triangulation ``tri`` as a scikit-fem mesh: ``skfem.MeshTri`` (``MeshTri2``,
    six-node triangles, with ``quadratic``), with named boundaries and subdomains.

    The nodes are the vertices that are corners of triangles, in their order (a
    vertex in no triangle would leave a linear system singular), then for
    ``MeshTri2`` the edge midpoints; element ``k`` is ``tri.triangles[k]``.

    Parameters
    ----------
    boundaries : mapping of str to int or list of ints, optional
        Facet sets by marker: ``{"inlet": 3, "walls": [1, 2]}`` names the edges
        whose marker (``tri.edge_markers``: a segment's marker, 1 on the rest of the
        boundary) is one of those given. Default: ``"marker_<m>"`` for every nonzero
        marker ``m``.
    subdomains : mapping of str to int or list of ints, optional
        Element sets by region: ``{"steel": 0}`` names the triangles of region 0
        (``tri.regions``). Default: ``"region_<r>"`` for every region ``r >= 0``.

    Raises
    ------
    MeshExportError
        A malformed mapping, a marker or region no edge or triangle has, or a
        triangulation without triangles.
    """
    _check_quadratic(quadratic)
    wanted_boundaries = _check_names(boundaries, "boundaries")
    wanted_subdomains = _check_names(subdomains, "subdomains")
    _need_triangles(tri, "to_skfem")
    skfem = require("skfem", "Triangulation.to_skfem")
    edge_markers = np.asarray(tri.edge_markers, np.int64)
    regions = np.asarray(tri.regions, np.int64)
    facet_sets = _named_sets(wanted_boundaries, edge_markers, "boundaries", "marker_", "edge",
                             "marker", nonzero=True)
    element_sets = _named_sets(wanted_subdomains, regions, "subdomains", "region_", "triangle",
                               "region", nonzero=False)
    T = np.asarray(tri.triangles, np.int64)
    used = np.unique(T)
    new = np.full(len(tri.vertices), -1, np.int64)
    new[used] = np.arange(len(used))
    corners = np.asarray(tri.vertices, np.float64)[used]
    if quadratic:
        qm = tri.quadratic()
        mid = len(used) + np.arange(len(qm.edges))
        renumber = np.concatenate([new, mid])
        nodes = np.concatenate([corners, qm.vertices[len(tri.vertices):]])
        # scikit-fem's six-node order: corners, then midpoints of edges 01, 12, 02
        mesh = skfem.MeshTri2(np.ascontiguousarray(nodes.T),
                              np.ascontiguousarray(renumber[qm.triangles[:, [0, 1, 2, 5, 3, 4]]].T))
    else:
        mesh = skfem.MeshTri1(np.ascontiguousarray(corners.T), np.ascontiguousarray(new[T].T))
    edges = new[np.asarray(tri.edges, np.int64)]
    facet_rows = edge_rows(edges, np.asarray(mesh.facets, np.int64).T)
    facets = {name: np.flatnonzero(np.isin(facet_rows, rows)) for name, rows in facet_sets.items()}
    return mesh.with_boundaries(facets).with_subdomains(element_sets)


# ------------------------------------------------------------------ checks and helpers
def _check_quadratic(quadratic: Any) -> None:
    if not isinstance(quadratic, (bool, np.bool_)):
        raise MeshExportError(f"quadratic must be True or False, got {quadratic!r}")


def _need_triangles(tri: Any, what: str) -> None:
    if len(tri.triangles) == 0:
        raise MeshExportError(f"{tri!r} has no triangles (all-collinear input, or nothing inside "
                              f"the domain): {what} needs at least one")


def _check_names(names: Names | None, what: str) -> Dict[str, NDArray[np.int64]] | None:
    """``{name: the ids asked}`` of a mapping of names to an integer or a list of
    integers, or MeshExportError naming the entry that is not."""
    if names is None:
        return None
    if not isinstance(names, Mapping):
        raise MeshExportError(f"{what} must be a mapping of names to markers, got "
                              f"{type(names).__name__}")
    out = {}
    for name, ids in names.items():
        if not isinstance(name, str) or not name:
            raise MeshExportError(f"{what}: names must be non-empty strings, got {name!r}")
        items = list(ids) if isinstance(ids, Sequence) or isinstance(ids, np.ndarray) else [ids]
        if not items or not all(isinstance(i, (int, np.integer)) and not isinstance(i, bool)
                                for i in items):
            raise MeshExportError(f"{what}[{name!r}] must be an integer or a non-empty list of "
                                  f"integers, got {ids!r}")
        out[name] = np.array(items, np.int64)
    return out


def _named_sets(wanted: Dict[str, NDArray[np.int64]] | None, values: NDArray[np.int64],
                what: str, prefix: str, item: str, label: str,
                nonzero: bool) -> Dict[str, NDArray[np.int64]]:
    """The rows of ``values`` (one per edge or triangle) named: those whose value
    is among each name's ids, or one set per value present (``prefix<value>``;
    nonzero values, or values >= 0)."""
    present = np.unique(values)
    if wanted is None:
        keep = present != 0 if nonzero else present >= 0
        return {f"{prefix}{v}": np.flatnonzero(values == v) for v in present[keep]}
    for name, ids in wanted.items():
        absent = ids[~np.isin(ids, present)]
        if len(absent):
            raise MeshExportError(
                f"{what}[{name!r}]: no {item} has {label} {int(absent[0])} (the {label}s present: "
                f"{', '.join(map(str, present.tolist()))})")
    return {name: np.flatnonzero(np.isin(values, ids)) for name, ids in wanted.items()}
