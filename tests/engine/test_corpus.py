"""Every real input in ../shared/corpus triangulates correctly (exact checker), or
raises the documented error for its defect under intersections="raise" and
succeeds under "split"."""
from __future__ import annotations

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin import OverlappingSegmentsError, SegmentIntersectionError
from checker import canonical_triangles, check_triangulation

try:
    from corpus import iter_plcs, read_stats_table
    PLCS = list(iter_plcs())
    TABLE = read_stats_table()
except FileNotFoundError:  # pragma: no cover - corpus not beside the repo
    PLCS, TABLE = [], {}


def _row(plc):
    return TABLE.get(plc.name.split("#")[0], {})


def _has_defect(plc) -> bool:
    """Crossings or overlaps listed for the file in the corpus README."""
    row = _row(plc)
    return row.get("cross", "0") != "0" or row.get("overlap", "0") != "0"


def _check(plc, tri, split):
    """Exact check: the whole-hull CDT (every vertex, every segment or its pieces,
    every other edge locally Delaunay) and the domain as a subset of it."""
    full = cdt_plugin.triangulate(plc.vertices, plc.segments, keep_hull=True,
                                  intersections="split" if split else "raise")
    if len(full.triangles) == 0:
        return
    if split:
        segs = full.segments
    else:
        vm = full.vertex_map[plc.segments]
        segs = vm[vm[:, 0] != vm[:, 1]]
    rep = check_triangulation(full.vertices, full.triangles, segments=segs, domain="hull")
    assert rep.ok, str(rep)
    assert full.is_delaunay()
    assert canonical_triangles(tri.vertices, tri.triangles) <= canonical_triangles(full.vertices, full.triangles)


@pytest.mark.parametrize("plc", PLCS, ids=[p.name for p in PLCS])
def test_corpus_input(plc):
    holes = plc.holes if plc.kind == "triangle-poly" else None
    try:
        tri = cdt_plugin.triangulate(plc.vertices, plc.segments, holes=holes)
        split = False
    except (SegmentIntersectionError, OverlappingSegmentsError) as err:
        assert plc.kind == "geojson" or _has_defect(plc), f"{plc.name} raised but has no listed defect: {err}"
        assert len(err.segments) == 2
        tri = cdt_plugin.triangulate(plc.vertices, plc.segments, holes=holes, intersections="split")
        split = True
    else:
        assert not (plc.kind != "geojson" and _has_defect(plc) and _row(plc).get("cross", "0") != "0"), \
            f"{plc.name} has crossing segments but did not raise"
    _check(plc, tri, split)
    # every input vertex is accounted for
    assert (tri.vertex_map >= 0).all()
    row = _row(plc)
    if plc.kind == "triangle-poly" and row.get("tri -p", "").isdigit():
        assert len(tri.triangles) == int(row["tri -p"])   # Triangle's -p convention
    if plc.kind == "earcut" and row.get("n+2h-2", "-").isdigit():
        assert len(tri.triangles) == int(row["n+2h-2"])   # any triangulation of a valid polygon
