"""Finite-element output (cdt_plugin.fem): meshio meshes written and read back as gmsh
4.1 and 2.2, VTU and XDMF with the same cells and tags (the .msh files also read
without meshio, line by line), scikit-fem meshes whose named facets and elements are
the marked edges and the regions, the bad options named, and the Poisson example's
convergence order."""
from __future__ import annotations

import importlib.util
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from checker import assert_valid

import cdt_plugin
from cdt_plugin import MeshExportError
from cdt_plugin.fem import _node_entities, gmsh_physical, gmsh_tags_only

meshio = pytest.importorskip("meshio")
skfem = pytest.importorskip("skfem")

ROOT = Path(__file__).resolve().parents[2]
SQUARE = [[0, 0], [2, 0], [2, 2], [0, 2]]
SIDES = [[0, 1], [1, 2], [2, 3], [3, 0]]


def checked(*args, require_all_vertices=True, **kwargs):
    """``cdt_plugin.triangulate`` with its result verified by the exact checker."""
    tri = cdt_plugin.triangulate(*args, **kwargs)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments",
                 require_all_vertices=require_all_vertices)
    return tri


@pytest.fixture(scope="module")
def plate():
    """A square plate with a square hole, two regions with attributes 7 and 9 (split
    by the line x = 1), sides marked 3 (bottom), 4 (right), 5 (top), 6 (left), the
    hole 8, refined: every kind of tag, and nodes to spare for gmsh 4.1."""
    V = [[0, 0], [1, 0], [2, 0], [2, 2], [1, 2], [0, 2], [1.3, 0.8], [1.7, 0.8], [1.7, 1.2],
         [1.3, 1.2]]
    S = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4], [6, 7], [7, 8], [8, 9], [9, 6]]
    marks = [3, 3, 4, 5, 5, 6, 0, 8, 8, 8, 8]
    return checked(V, S, holes=[[1.5, 1.0]], regions=[[0.5, 1, 7], [1.2, 0.2, 9]],
                   segment_markers=marks, vertex_attributes=np.array(V)[:, 0] * 2,
                   max_area=0.05, min_angle=25)


def cell_tags(points, mesh, kind):
    """``Counter`` of (cell as a set of node coordinates, physical tag) over the
    blocks of ``kind``: comparable across files that number the nodes differently."""
    out = Counter()
    P = np.asarray(points)[:, :2]
    for block, tags in zip(mesh.cells, mesh.cell_data["gmsh:physical"]):
        if block.type == kind:
            for cell, tag in zip(block.data, tags):
                out[(frozenset(map(tuple, P[cell].tolist())), int(tag))] += 1
    return out


def expected_tags(tri, quadratic=False):
    """What the cells of ``tri`` should be, computed from the triangulation itself."""
    V = tri.vertices
    lines = Counter((frozenset(map(tuple, V[s].tolist())), int(m))
                    for s, m in zip(tri.segments, tri.segment_markers))
    triangles = Counter((frozenset(map(tuple, V[t].tolist())), int(p))
                        for t, p in zip(tri.triangles, gmsh_physical(tri)))
    return lines, triangles


# ------------------------------------------------------------------------------ to_meshio
def test_meshio_cells_and_tags(plate):
    mesh = plate.to_meshio()
    lines, triangles = expected_tags(plate)
    # corners only: the triangle cells are the triangulation's (the midpoints are dropped)
    assert cell_tags(mesh.points, mesh, "line") == lines
    assert cell_tags(mesh.points, mesh, "triangle") == triangles
    assert {t for (_, t) in triangles} == {7, 9}                   # the region attributes
    assert {t for (_, t) in lines} == {0, 3, 4, 5, 6, 8}
    types = [b.type for b in mesh.cells]
    assert types == ["triangle"] * 2 + ["line"] * 6               # one block per tag
    for name in ("gmsh:physical", "gmsh:geometrical", "region", "marker", "region_attribute"):
        assert [len(a) for a in mesh.cell_data[name]] == [len(b.data) for b in mesh.cells]
    regions = np.concatenate(mesh.cell_data["region"][:2])
    attributes = np.concatenate(mesh.cell_data["region_attribute"][:2])
    physical = np.concatenate(mesh.cell_data["gmsh:physical"][:2])
    assert np.array_equal(attributes, physical) and set(regions) == {0, 1}
    assert np.isnan(np.concatenate(mesh.cell_data["region_attribute"][2:])).all()
    assert np.array_equal(mesh.point_data["vertex_markers"], plate.vertex_markers)
    assert np.allclose(mesh.point_data["vertex_attribute_1"], plate.vertices[:, 0] * 2)


def test_physical_of_triangles_without_whole_attributes():
    # no regions: 1; regions without whole-number attributes: index + 1
    assert set(gmsh_physical(checked(SQUARE, SIDES))) == {1}
    V = SQUARE + [[1, 0], [1, 2]]
    S = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    tri = checked(V, S, regions=[[0.5, 1, 0.5], [1.5, 1, 2.5]])
    assert sorted(set(gmsh_physical(tri))) == [1, 2]
    assert np.array_equal(gmsh_physical(tri), tri.regions + 1)
    # a segment-bounded part without a seed (region -1): one more than the largest
    tri = checked(V, S, regions=[[0.5, 1, 0.5]])
    assert set(tri.regions) == {-1, 0}
    assert np.array_equal(gmsh_physical(tri), np.where(tri.regions < 0, 2, 1))


def test_gmsh_entities_hold_a_node_each(plate):
    mesh = plate.to_meshio()
    dim_tags = mesh.point_data["gmsh:dim_tags"]
    for block, entity in zip(mesh.cells, mesh.cell_data["gmsh:geometrical"]):
        held = np.flatnonzero((dim_tags == (block.dim, entity[0])).all(axis=1))
        assert np.isin(held, block.data).any(), (block.type, entity[0])


def test_gmsh_entities_by_augmenting_path():
    # four differently marked sides and one triangle block on five nodes: the lines
    # claim the corners (one side gets none), the centre must go to the triangles
    # and a corner to the side without one
    tri = checked(SQUARE + [[1, 1.2]], SIDES, segment_markers=[1, 2, 3, 4])
    mesh = tri.to_meshio()
    dim_tags = mesh.point_data["gmsh:dim_tags"]
    assert len(np.unique(dim_tags, axis=0)) == len(mesh.cells) == 5
    for block, entity in zip(mesh.cells, mesh.cell_data["gmsh:geometrical"]):
        held = np.flatnonzero((dim_tags == (block.dim, entity[0])).all(axis=1))
        assert np.isin(held, block.data).any()


def test_gmsh_entities_impossible():
    # five blocks on four nodes: no assignment; msh 2.2 still carries every tag
    tri = checked(SQUARE, SIDES, segment_markers=[1, 2, 3, 4])
    mesh = tri.to_meshio()
    assert "gmsh:dim_tags" not in mesh.point_data
    blocks = [(b.type, b.dim, b.data, {"gmsh:geometrical": g}) for b, g in
              zip(mesh.cells, mesh.cell_data["gmsh:geometrical"])]
    assert _node_entities(len(mesh.points), blocks) is None


@pytest.mark.parametrize("binary", [False, True])
def test_gmsh41_round_trip(plate, tmp_path, binary):
    # (meshio 5.3 writes ASCII data fields that it cannot read with NumPy 2: tags only)
    mesh = plate.to_meshio() if binary else gmsh_tags_only(plate.to_meshio())
    path = tmp_path / "plate.msh"
    meshio.write(path, mesh, file_format="gmsh", binary=binary)
    back = meshio.read(path)
    lines, triangles = expected_tags(plate)
    assert cell_tags(back.points, back, "line") == lines
    assert cell_tags(back.points, back, "triangle") == triangles
    if not binary:
        assert gmsh41_line_tags(path) == Counter(t for (_, t) in lines.elements())


@pytest.mark.parametrize("binary", [False, True])
def test_gmsh22_round_trip(plate, tmp_path, binary):
    # meshio 5.3 reads a 2.2 file's ElementData wrongly when it has several cell
    # blocks: the tags alone, as the command line writes them
    path = tmp_path / "plate.msh"
    meshio.write(path, gmsh_tags_only(plate.to_meshio()), file_format="gmsh22", binary=binary)
    back = meshio.read(path)
    lines, triangles = expected_tags(plate)
    assert np.array_equal(back.points[:, :2], plate.vertices)       # same node numbers
    assert cell_tags(back.points, back, "line") == lines
    assert cell_tags(back.points, back, "triangle") == triangles
    if not binary:
        assert gmsh22_line_tags(path, plate.vertices) == lines


def gmsh22_line_tags(path, V):
    """The 2-node line elements of an ASCII msh 2.2 file, read line by line:
    ``elm-number 1 ntags physical geometrical node node``."""
    text = path.read_text().split("$Elements\n")[1].split("$EndElements")[0].split("\n")
    out = Counter()
    for row in text[1:]:
        f = row.split()
        if f and f[1] == "1":
            ntags = int(f[2])
            nodes = [int(i) - 1 for i in f[3 + ntags:]]
            out[(frozenset(map(tuple, V[nodes].tolist())), int(f[3]))] += 1
    return out


def gmsh41_line_tags(path):
    """Physical tag of each line element of an ASCII msh 4.1 file, read line by line:
    the curves' physical tags from ``$Entities``, the elements' curves from the
    ``$Elements`` blocks."""
    text = path.read_text()
    entities = text.split("$Entities\n")[1].split("$EndEntities")[0].split("\n")
    counts = [int(c) for c in entities[0].split()]
    curves = entities[1 + counts[0]:1 + counts[0] + counts[1]]
    physical = {}
    for row in curves:
        f = row.split()
        if int(f[7]):
            physical[int(f[0])] = int(f[8])
    elements = text.split("$Elements\n")[1].split("$EndElements")[0].split("\n")
    out, i = Counter(), 1
    while i < len(elements) and elements[i].strip():
        dim, tag, _, n = map(int, elements[i].split())
        if dim == 1:
            out[physical[tag]] += n
        i += n + 1
    return out


def test_vtu_round_trip(plate, tmp_path):
    path = tmp_path / "plate.vtu"
    mesh = plate.to_meshio()
    meshio.write(path, mesh)
    back = meshio.read(path)
    assert np.array_equal(back.points[:, :2], plate.vertices)
    # (VTK reads the blocks of one cell type back as one block)
    assert [b.type for b in back.cells] == ["triangle", "line"]
    for k, kind in enumerate(("triangle", "line")):
        rows = [i for i, b in enumerate(mesh.cells) if b.type == kind]
        assert np.array_equal(back.cells[k].data, np.concatenate([mesh.cells[i].data for i in rows]))
        for name in ("gmsh:physical", "region", "marker", "region_attribute"):
            assert np.array_equal(back.cell_data[name][k], np.concatenate(
                [mesh.cell_data[name][i] for i in rows]), equal_nan=True), name
    assert np.array_equal(back.point_data["vertex_markers"], plate.vertex_markers)


def test_xdmf_round_trip(plate, tmp_path):
    pytest.importorskip("h5py")
    path = tmp_path / "plate.xdmf"
    mesh = plate.to_meshio()
    meshio.write(path, mesh)
    back = meshio.read(path)
    assert np.array_equal(back.points[:, :2], plate.vertices)
    lines, triangles = expected_tags(plate)
    assert cell_tags(back.points, back, "line") == lines
    assert cell_tags(back.points, back, "triangle") == triangles
    assert np.array_equal(back.point_data["vertex_markers"], plate.vertex_markers)


def test_quadratic_meshio(plate, tmp_path):
    mesh = plate.to_meshio(quadratic=True)
    assert [b.type for b in mesh.cells] == ["triangle6"] * 2 + ["line3"] * 6
    P = mesh.points
    for block in mesh.cells:
        if block.type == "line3":       # ends, then the midpoint node of the piece
            assert np.array_equal(P[block.data[:, 2]], (P[block.data[:, 0]] + P[block.data[:, 1]]) / 2)
    corners = [(b.data[:, :2], t) for b, t in zip(mesh.cells, mesh.cell_data["gmsh:physical"])
               if b.type == "line3"]
    lines, _ = expected_tags(plate)
    assert Counter((frozenset(map(tuple, P[c].tolist())), int(m))
                   for cells, tags in corners for c, m in zip(cells, tags)) == lines
    path = tmp_path / "plate2.msh"
    meshio.write(path, mesh, file_format="gmsh")
    back = meshio.read(path)
    assert [b.type for b in back.cells] == [b.type for b in mesh.cells]
    assert sorted(map(tuple, back.points[:, :2].tolist())) == sorted(map(tuple, P.tolist()))


# ------------------------------------------------------------------------------- to_skfem
def facet_coordinates(mesh, facets):
    p = mesh.p.T
    return {frozenset(map(tuple, p[mesh.facets[:, f]].tolist())) for f in facets}


def test_skfem_boundaries_and_subdomains(plate):
    mesh = plate.to_skfem()
    assert isinstance(mesh, skfem.MeshTri1)
    E, M = plate.edges, plate.edge_markers
    marked = {m: {frozenset(map(tuple, plate.vertices[e].tolist())) for e in E[M == m]}
              for m in np.unique(M[M != 0])}
    assert sorted(mesh.boundaries) == sorted(f"marker_{m}" for m in marked)
    for m, edges in marked.items():
        assert facet_coordinates(mesh, mesh.boundaries[f"marker_{m}"]) == edges
    for r in (0, 1):
        assert np.array_equal(mesh.subdomains[f"region_{r}"], np.flatnonzero(plate.regions == r))
    # element k is triangle k; named sets
    assert np.allclose(np.sort(mesh.p.T[mesh.t.T], axis=1), np.sort(plate.vertices[plate.triangles], axis=1))
    named = plate.to_skfem(boundaries={"hole": 8, "outer": [3, 4, 5, 6]}, subdomains={"steel": 1})
    assert facet_coordinates(named, named.boundaries["hole"]) == marked[8]
    assert facet_coordinates(named, named.boundaries["outer"]) == set().union(
        *(marked[m] for m in (3, 4, 5, 6)))
    assert sorted(named.subdomains) == ["steel"]
    # the marked facets are the boundary facets: outer sides and the hole
    assert set(named.boundary_facets()) == set(named.boundaries["hole"]) | set(named.boundaries["outer"])


def test_skfem_quadratic(plate):
    mesh = plate.to_skfem(quadratic=True)
    assert isinstance(mesh, skfem.MeshTri2)
    assert mesh.nvertices == len(plate.vertices) and mesh.nelements == len(plate.triangles)
    # every edge's node at its midpoint, where scikit-fem numbers it (after the vertices)
    p, facets = mesh.p, mesh.facets
    assert np.array_equal(mesh.doflocs[:, mesh.nvertices:], (p[:, facets[0]] + p[:, facets[1]]) / 2)
    # so that a quadratic function is interpolated exactly by P2
    basis = skfem.Basis(mesh, skfem.ElementTriP2(), intorder=6)
    f = lambda x, y: x * x - 3 * x * y + 2 * y   # noqa: E731
    u = basis.interpolate(f(*basis.doflocs))
    error = skfem.Functional(lambda w: (w["u"] - f(*w.x)) ** 2).assemble(basis, u=u)
    assert error < 1e-24
    assert facet_coordinates(mesh, mesh.boundaries["marker_8"]) == facet_coordinates(
        plate.to_skfem(), plate.to_skfem().boundaries["marker_8"])


def test_skfem_leaves_out_vertices_in_no_triangle():
    # a vertex inside the hole is in no triangle: a P1 system would be singular
    tri = checked([[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2], [1.5, 1.5]],
                  [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
                  holes=[[1.2, 1.5]], require_all_vertices=False)
    used = np.unique(tri.triangles)
    assert len(used) < len(tri.vertices)
    mesh = tri.to_skfem()
    assert np.array_equal(mesh.p.T, tri.vertices[used])
    assert len(tri.to_meshio().points) == len(tri.vertices)     # meshio keeps every vertex


# --------------------------------------------------------------------------------- errors
@pytest.mark.parametrize("call, message", [
    (lambda t: t.to_meshio(quadratic="yes"), "quadratic must be True or False"),
    (lambda t: t.to_skfem(quadratic=2), "quadratic must be True or False"),
    (lambda t: t.to_skfem(boundaries=[3]), "boundaries must be a mapping"),
    (lambda t: t.to_skfem(boundaries={3: 3}), "names must be non-empty strings"),
    (lambda t: t.to_skfem(boundaries={"a": 1.5}), r"boundaries\['a'\] must be an integer"),
    (lambda t: t.to_skfem(boundaries={"a": True}), r"boundaries\['a'\] must be an integer"),
    (lambda t: t.to_skfem(boundaries={"a": []}), r"boundaries\['a'\] must be an integer"),
    (lambda t: t.to_skfem(boundaries={"a": 7}), r"boundaries\['a'\]: no edge has marker 7 "
                                                r"\(the markers present: 0, 1, 3\)"),
    (lambda t: t.to_skfem(subdomains={"a": 2}), r"subdomains\['a'\]: no triangle has region 2"),
])
def test_bad_options_named(call, message):
    tri = checked(SQUARE, SIDES, segment_markers=[3, 0, 0, 0], max_area=0.5)
    with pytest.raises(MeshExportError, match=message):
        call(tri)


def test_no_triangles_named():
    tri = cdt_plugin.triangulate([[0, 0], [1, 1], [2, 2]])
    for call in (tri.to_meshio, tri.to_skfem):
        with pytest.raises(MeshExportError, match="has no triangles"):
            call()


# ------------------------------------------------------------------- the Poisson example
def test_poisson_example_converges_at_second_order():
    pytest.importorskip("shapely")
    spec = importlib.util.spec_from_file_location("poisson_skfem", ROOT / "examples" / "poisson_skfem.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    rows, rate = example.convergence((0.004, 0.001, 0.00025))
    errors = [error for _, _, error in rows]
    assert errors[0] > errors[1] > errors[2] > 0
    assert rate > 1.8, rows


def test_tags_beyond_32_bits_named(tmp_path):
    tri = checked(SQUARE, SIDES, segment_markers=[2 ** 31, 1, 1, 1], max_area=0.5)
    mesh = tri.to_meshio()
    assert max(t.max() for t in mesh.cell_data["gmsh:physical"]) == 2 ** 31   # meshio keeps it
    with pytest.raises(MeshExportError, match="tag 2147483648 of a line cell does not fit"):
        gmsh_tags_only(mesh)
    # region attributes too large for a tag are not tags: the regions number the triangles
    V = SQUARE + [[1, 0], [1, 2]]
    S = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    tri = checked(V, S, regions=[[0.5, 1, 1e12], [1.5, 1, 3]])
    assert np.array_equal(gmsh_physical(tri), tri.regions + 1)


@pytest.mark.parametrize("fmt", ["gmsh", "gmsh22"])
def test_gmsh_reads_the_physical_groups(plate, tmp_path, fmt):
    # gmsh itself (the bench extra's package) sees every physical group with its elements
    gmsh = pytest.importorskip("gmsh")
    path = tmp_path / "plate.msh"
    meshio.write(path, gmsh_tags_only(plate.to_meshio()), file_format=fmt)
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.open(str(path))
        counts = Counter()
        for dim, tag in gmsh.model.getPhysicalGroups():
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                counts[(dim, tag)] += sum(len(t) for t in gmsh.model.mesh.getElements(dim, entity)[1])
    finally:
        gmsh.finalize()
    lines, triangles = expected_tags(plate)
    want = Counter({(1, t): n for t, n in Counter(t for (_, t) in lines.elements()).items()})
    want.update({(2, t): n for t, n in Counter(t for (_, t) in triangles.elements()).items()})
    if fmt == "gmsh22":            # msh 2.2: physical tag 0 is no physical group
        del want[(1, 0)]
    assert counts == want
