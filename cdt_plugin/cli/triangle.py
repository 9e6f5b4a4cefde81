"""``cdt-plugin triangle``: Triangle's own command line, ``triangle [-switches] input``.

The input is read as the Triangle program reads it: ``input.node`` (without ``p`` or
``r``), ``input.poly`` (``p``), or ``input.node`` with ``input.ele`` (``r``; plus
``input.poly`` with ``rp`` and ``input.area`` with a bare ``a``). A ``.node``, ``.poly``
or ``.ele`` ending on the name is dropped. The mesh is made by
:func:`cdt_plugin.triangle.triangulate` with the same switches, and written as Triangle
writes it: ``input.1.node`` and ``input.1.ele``, ``input.1.poly`` (with ``p`` or ``c``),
``input.1.edge`` (``e``), ``input.1.neigh`` (``n``), ``input.1.v.node`` and
``input.1.v.edge`` (``v``: the Voronoi diagram, dual of the mesh) and ``input.1.off``
(``g``, Geomview's format). ``N``, ``E`` and ``P`` leave out the ``.node``, ``.ele`` and
``.poly`` files, ``B`` the boundary markers; ``I`` names the output files as the input
(no iteration number); ``z`` numbers from zero. An input named ``x.1`` gives ``x.2``.
``Q`` prints nothing; otherwise each file read and written is named, and ``V`` adds
the mesh's statistics.
"""
from __future__ import annotations

import argparse
import re
from pathlib import Path
from typing import Any

import numpy as np

from .. import triangle as tr
from ..errors import FileFormatError
from ..io import write_edge, write_ele, write_neigh, write_node, write_off, write_poly, write_voronoi
from ..report import mesh_neighbors
from ..switches import Switches, read_switches
from .terminal import CLIError

_EXTENSIONS = (".node", ".poly", ".ele")


def triangle_command(args: argparse.Namespace) -> int:
    """Run ``cdt-plugin triangle``: read, mesh and write as the Triangle program."""
    text = "".join(w[1:] for w in args.words if w.startswith("-"))
    inputs = [w for w in args.words if not w.startswith("-")]
    if "h" in text or not inputs:        # (Triangle's -h, or no input: the help)
        args.parser.print_help()
        return 0 if "h" in text else 2
    if len(inputs) > 1:
        raise CLIError(f"one input file, got {len(inputs)}: {' '.join(inputs)}")
    switches = read_switches(text)
    name = _base_name(inputs[0])
    say = (lambda line: None) if switches.quiet else print
    data = _read_input(name, switches, say)
    # N, E, P and B choose the files and their columns: the mesh is made whole
    out = tr.triangulate(data, re.sub("[NEPB]", "", text))
    _write_output(out, _output_name(name, switches), switches, say)
    if switches.verbose and not switches.quiet:
        _print_statistics(out)
    return 0


def _base_name(text: str) -> Path:
    """The input's name without a ``.node``, ``.poly`` or ``.ele`` ending."""
    for ext in _EXTENSIONS:
        if text.endswith(ext):
            return Path(text[: -len(ext)])
    return Path(text)


def _read_input(name: Path, s: Switches, say) -> dict[str, Any]:
    """The input files the switches ask for, read into the drop-in's dict."""
    wanted: dict[str, Path] = {}
    if s.refine:
        wanted = {"node": _with(name, ".node"), "ele": _with(name, ".ele")}
        if s.pslg:
            wanted["poly"] = _with(name, ".poly")
        if s.area_from_input:
            wanted["area"] = _with(name, ".area")
    elif s.pslg:
        wanted = {"poly": _with(name, ".poly")}
    else:
        wanted = {"node": _with(name, ".node")}
    texts = {}
    for kind, path in wanted.items():
        if not path.is_file():
            raise FileFormatError(f"{path}: no such file (the switches {s.text!r} read a "
                                  f".{kind} file)")
        say(f"Opening {path}.")
        texts[kind] = path.read_text()
    if "poly" in texts and "node" not in texts and _counts_no_vertices(texts["poly"]):
        texts["node"] = _with(name, ".node").read_text()   # (a .poly may keep them there)
    return tr.loads(**texts)


def _counts_no_vertices(poly: str) -> bool:
    """Whether a ``.poly`` file's header says 0 vertices (they are then in the
    ``.node`` file of the same name)."""
    for line in poly.splitlines():
        fields = line.split("#", 1)[0].split()
        if fields:
            return fields[0] == "0"
    return False


def _with(name: Path, ext: str) -> Path:
    return name.with_name(name.name + ext)


def _output_name(name: Path, s: Switches) -> Path:
    """``x`` -> ``x.1``, ``x.3`` -> ``x.4``; with ``I`` the input's own name."""
    if s.no_iteration_numbers:
        return name
    m = re.fullmatch(r"(.*)\.(\d+)", name.name)
    if m:
        return name.with_name(f"{m.group(1)}.{int(m.group(2)) + 1}")
    return name.with_name(name.name + ".1")


def _write_output(out: dict[str, Any], base: Path, s: Switches, say) -> None:
    """The files Triangle writes for switches ``s`` (module docstring)."""
    first = 0 if s.zero_index else 1
    marked = not s.no_markers

    def written(ext: str) -> Path:
        path = _with(base, ext)
        say(f"Writing {path}.")
        return path

    def markers(key: str) -> Any:
        return _flat(out.get(key)) if marked else None

    vertices = out.get("vertices", np.empty((0, 2)))
    if not s.no_nodes:
        write_node(written(".node"), vertices, out.get("vertex_attributes"),
                   markers("vertex_markers"), first_index=first)
    triangles = out.get("triangles", np.empty((0, 3), np.int32))
    if not s.no_elements:
        write_ele(written(".ele"), triangles, out.get("triangle_attributes"), first_index=first)
    if (s.pslg or s.convex_hull) and not s.no_poly:
        write_poly(written(".poly"), vertices, out.get("segments", np.empty((0, 2), np.int32)),
                   out.get("holes"), out.get("regions"), markers("segment_markers"),
                   first_index=first)
    if s.edges:
        write_edge(written(".edge"), out.get("edges", np.empty((0, 2), np.int32)),
                   markers("edge_markers"), first_index=first)
    if s.neighbors:
        write_neigh(written(".neigh"), out.get("neighbors", np.empty((0, 3), np.int32)),
                    first_index=first)
    if s.voronoi:
        points, edges, rays = _voronoi_of_mesh(vertices, triangles, out.get("neighbors"))
        write_voronoi(written(".v.node"), written(".v.edge"), points, edges, rays,
                      first_index=first)
    if s.geomview:
        write_off(written(".off"), vertices, triangles)


def _flat(markers: Any) -> Any:
    return None if markers is None else np.asarray(markers).reshape(-1)


def _voronoi_of_mesh(vertices: Any, triangles: Any, neighbors: Any):
    """The Voronoi diagram Triangle's ``v`` writes: the dual of the mesh, a
    point per triangle (its circumcentre), an edge per interior edge of the
    mesh, a ray per boundary edge (from its triangle's circumcentre, outward,
    perpendicular to the edge)."""
    V = np.asarray(vertices, float)
    T = np.asarray(triangles)[:, :3].astype(np.int64)
    nb = mesh_neighbors(T)[0] if neighbors is None else np.asarray(neighbors, np.int64)
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    d = 2.0 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    bb = ((b - a) ** 2).sum(1)
    cc = ((c - a) ** 2).sum(1)
    ux = ((c[:, 1] - a[:, 1]) * bb - (b[:, 1] - a[:, 1]) * cc) / d
    uy = ((b[:, 0] - a[:, 0]) * cc - (c[:, 0] - a[:, 0]) * bb) / d
    centres = np.column_stack([a[:, 0] + ux, a[:, 1] + uy])
    t = np.repeat(np.arange(len(T)), 3)
    j = np.tile(np.arange(3), len(T))
    other = nb[t, j]
    inner = (other >= 0) & (t < other)
    edges = np.column_stack([t[inner], other[inner]])
    hull = other < 0
    p, q = T[t[hull], (j[hull] + 1) % 3], T[t[hull], (j[hull] + 2) % 3]
    direction = np.column_stack([V[q, 1] - V[p, 1], V[p, 0] - V[q, 0]])   # right of p -> q: outward
    return centres, edges, (t[hull], direction)


def _print_statistics(out: dict[str, Any]) -> None:
    print("Statistics:")
    if "vertices" in out:
        print(f"  Mesh vertices: {len(out['vertices'])}")
    if "triangles" in out:
        print(f"  Mesh triangles: {len(out['triangles'])}")
    if "segments" in out:
        print(f"  Mesh exterior boundary and segment edges: {len(out['segments'])}")
    if "edges" in out:
        print(f"  Mesh edges: {len(out['edges'])}")


def add_triangle_command(sub: argparse._SubParsersAction) -> None:
    """The ``triangle`` subcommand: switches (one or more words starting with
    ``-``), then the input file."""
    # (no option prefix: every -word is Triangle's switches, -h included)
    cmd = sub.add_parser(
        "triangle", prefix_chars="+", add_help=False,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        usage="cdt-plugin triangle [-prq__a__uAcDjevngBPNEIOXzo_YS__iFlsCQVh] INPUT",
        help="Triangle's command line: cdt-plugin triangle -pq30a0.1 A.poly",
        description=re.sub(r"``|:func:`|`", "", __doc__ or ""))
    cmd.add_argument("words", nargs="+", metavar="[-SWITCHES] INPUT",
                     help="Triangle's switches, e.g. -pq30a0.1 (one word or several), then the "
                          "input's name: x, x.node, x.poly or x.ele")
    cmd.set_defaults(func=triangle_command, parser=cmd)
