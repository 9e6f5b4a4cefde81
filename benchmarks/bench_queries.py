"""Point location, interpolation and live edits: cdt_plugin against scipy and against itself.

Workloads (seeded, ``numpy.random.default_rng``, uniform random points in the unit square):

* ``q-1e6``  — ``P``: 100,000 points, ``Q``: 1,000,000 query points, ``f``: values of a
  smooth function at ``P`` (the goals' workload);
* ``q-1e5``  — the same with 100,000 queries (the ``--quick`` stand-in; run only with
  ``--quick`` or when named in ``--workloads``);
* ``edit``   — ``A``: 100,000 points, ``B``: 100,000 more, ``C``: 10,000 more,
  ``ids``: 10,000 distinct random vertex ids of ``DynamicCDT(A)`` (10%).

Implementations, interleaved round-robin in one worker process per workload
(``harness.py``); on the query workloads the triangulation is inside every timed span:

* ``ours_locate``    — ``cdt_plugin.delaunay(P).locate(Q)``;
* ``scipy_locate``   — ``scipy.spatial.Delaunay(P).find_simplex(Q)`` (marked slow);
* ``ours_linear``    — ``cdt_plugin.delaunay(P).interpolate(f, Q)`` (``method="linear"``);
* ``scipy_linear``   — ``scipy.interpolate.LinearNDInterpolator(P, f)(Q)`` (marked slow);
* ``ours_natural``   — ``cdt_plugin.delaunay(P).interpolate(f, Q, method="natural")``;
* ``ours_insert``    — ``dyn.insert_points(B)`` on a fresh ``dyn = DynamicCDT(A)``;
* ``rebuild_insert`` — ``cdt_plugin.delaunay(A ∪ B)`` (the 200,000 rows stacked untimed);
* ``ours_loop``      — ``for p in C: dyn.insert_points(p)`` on a fresh ``DynamicCDT(A)``,
  one numpy row per call;
* ``ours_remove``    — ``dyn.remove_vertices(ids)`` on a fresh ``DynamicCDT(A)``;
* ``rebuild_remove`` — ``cdt_plugin.delaunay`` of the 90,000 points left (selected untimed).

A fresh ``DynamicCDT(A)`` is built outside every timed span: the workload's warm-up step
builds the first one of each kind, and after each timed call the untimed count step
(``Impl.count``, which the harness runs right after the call) builds the next one. A span
that finds none ready builds its own and the run says so (WARNING).

``scipy_locate`` and ``scipy_linear`` take 15-25 s per call on ``q-1e6`` here: they get
``--slow-repeat`` rounds there (default 2). ``cdt_plugin.delaunay`` runs with its default
``workers`` (both cores from 50,000 points); Qhull runs on one. Ratios are taken in the
same run. The goals (issue #19): locate and linear interpolation, build included, at most
0.1x scipy's ``find_simplex`` and ``LinearNDInterpolator``; ``natural`` at most 10x
``linear``; ``insert_points`` of 1e5 points into 1e5 at most 1.5x building the final
2e5-point triangulation from scratch; one point per call in a Python loop at most 10 µs
per point; removing 10% of the vertices at most the time of a rebuild.

Checks, once per workload on the first timed result of each implementation (not timed):
our ``locate`` puts the same queries outside (-1) as ``find_simplex``; our linear
interpolant is within 1e-12 of scipy's where both are defined, and NaN at the same
queries (so is ``natural``); after ``insert_points(B)`` the snapshot
``dyn.triangulation()`` has 200,000 vertices, ``dyn.vertices[ids]`` equals ``B`` and
``is_delaunay()`` holds, with as many triangles as ``delaunay(A ∪ B)``; after the loop
110,000 vertices and Delaunay; after the removal 90,000 vertices, Delaunay, with as many
triangles as the rebuild. A failure is a WARNING line under the table, and so is a change
to a source file of cdt_plugin or of the adapters while the run goes on.

Usage (from the repository root)::

    python benchmarks/bench_queries.py --quick --no-cold     # smoke test: q-1e5 + edit, 1 round, ~1-2 min
    python benchmarks/bench_queries.py                       # full run: q-1e6 + edit, 3 rounds, 5-8 minutes
    python benchmarks/bench_queries.py --write-readme        # full run + the README summary rows
    python benchmarks/bench_queries.py --only ours_insert,rebuild_insert --workloads edit --no-memory

Options: ``--repeat R`` (rounds, default 3; 1 with ``--quick``), ``--slow-repeat R``
(scipy's rounds on q-1e6, default 2), ``--only``, ``--workloads``, ``--timeout S`` per
call, ``--setup-timeout S`` (input, import + warm-up, numba compilation included),
``--no-memory`` (skip the peak-memory processes), ``--no-cold`` (skip the cold / cached
start of ``ours_locate`` on q-1e6: numba compilation of the Delaunay and query kernels),
``--out PATH.md`` (a .json with the raw numbers is written beside it; default
``benchmarks/results/queries.md``, ``queries-quick.md`` with ``--quick``).

This module must not import numba or cdt_plugin at import time: the cold-start
measurement re-runs it as a fresh worker and times the import (the query workloads'
input and warm-up steps use numpy only; the edit workload's warm-up builds
``DynamicCDT`` objects, so no cold start is measured on it).
"""
from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import (  # noqa: E402
    README,
    REPO_ROOT,
    WORKER_FLAG,
    Impl,
    Suite,
    Workload,
    command_line,
    fmt_s,
    machine_info,
    measure_cold,
    measure_memory,
    measure_times,
    changed_sources,
    select_by_name,
    short_reason,
    sources_state,
    write_results,
)
from harness import main as harness_main  # noqa: E402

GOAL_LOCATE_SCIPY = 0.1     # delaunay + locate / Delaunay + find_simplex
GOAL_LINEAR_SCIPY = 0.1     # delaunay + interpolate linear / LinearNDInterpolator
GOAL_NATURAL_LINEAR = 10.0  # natural / linear (ours)
GOAL_INSERT_REBUILD = 1.5   # insert_points(B) into DynamicCDT(A) / delaunay(A ∪ B)
GOAL_LOOP_US = 10.0         # one point per insert_points call: µs per point
GOAL_REMOVE_REBUILD = 1.0   # remove_vertices(10%) / delaunay(the rest)
LINEAR_ATOL = 1e-12

N_POINTS = 100_000
N_INSERT = 100_000
N_LOOP = 10_000
N_REMOVE = 10_000
WARMUP_POINTS = 50_000      # cdt_plugin.delaunay.PARALLEL_POINTS (not imported here: see the docstring)

# ----------------------------------------------------------------------------- workloads


def smooth(P: np.ndarray) -> np.ndarray:
    """The interpolated function: smooth, values of order 1."""
    x, y = P[:, 0], P[:, 1]
    return np.sin(3.0 * x) * np.cos(2.0 * y) + 0.5 * x * y


class QueryData:
    """P (n, 2) triangulated, Q (m, 2) queries, f (n,) values at P."""

    def __init__(self, P: np.ndarray, Q: np.ndarray) -> None:
        self.P = np.ascontiguousarray(P, dtype=np.float64)
        self.Q = np.ascontiguousarray(Q, dtype=np.float64)
        self.f = np.ascontiguousarray(smooth(self.P))

    def __len__(self) -> int:
        return len(self.Q)


def queries(n: int, m: int, seed: int):
    def make() -> QueryData:
        rng = np.random.default_rng(seed)
        P = rng.uniform(0.0, 1.0, (n, 2))
        Q = rng.uniform(0.0, 1.0, (m, 2))
        return QueryData(P, Q)
    return make


def query_warmup(data: QueryData) -> QueryData:
    """Warm-up input: 50,000 of the points (``delaunay``'s two-thread path) and 20,000 of
    the queries, numpy only (the cold start times the import after this step)."""
    k = min(WARMUP_POINTS, len(data.P))
    idx = np.sort(np.random.default_rng(0).choice(len(data.P), k, replace=False))
    return QueryData(data.P[idx], data.Q[: min(20_000, len(data.Q))])


KINDS = ("ours_insert", "ours_loop", "ours_remove")


class EditData:
    """A, B, C, ids (see the docstring), the untimed inputs of the rebuilds, and one
    ready ``DynamicCDT(A)`` per kind of edit (built outside the timed spans)."""

    def __init__(self, A, B, C, ids, main: bool) -> None:
        self.A = np.ascontiguousarray(A, dtype=np.float64)
        self.B = np.ascontiguousarray(B, dtype=np.float64)
        self.C = np.ascontiguousarray(C, dtype=np.float64)
        self.ids = np.ascontiguousarray(ids, dtype=np.int64)
        self.AB = np.ascontiguousarray(np.vstack([self.A, self.B]))
        keep = np.ones(len(self.A), bool)
        keep[self.ids] = False     # DynamicCDT(A) gives row i of A the vertex id i (checked below)
        self.rest = np.ascontiguousarray(self.A[keep])
        self.main = main
        self._ready: dict[str, Any] = {}
        self.built_in_span = 0

    def __len__(self) -> int:
        return len(self.A)

    def fresh(self, kind: str):
        import cdt_plugin
        return cdt_plugin.DynamicCDT(self.A)

    def refill(self, kind: str) -> None:
        """Untimed: get the next round's DynamicCDT(A) ready."""
        self._ready[kind] = None            # let the old one go first
        self._ready[kind] = self.fresh(kind)

    def take(self, kind: str):
        dyn = self._ready.pop(kind, None)
        if dyn is None:
            if self.main:
                self.built_in_span += 1
            dyn = self.fresh(kind)
        return dyn


def edits(n: int, n_insert: int, n_loop: int, n_remove: int, seed: int):
    def make() -> EditData:
        rng = np.random.default_rng(seed)
        A = rng.uniform(0.0, 1.0, (n, 2))
        B = rng.uniform(0.0, 1.0, (n_insert, 2))
        C = rng.uniform(0.0, 1.0, (n_loop, 2))
        ids = rng.choice(n, n_remove, replace=False)
        return EditData(A, B, C, ids, main=True)
    return make


def edit_warmup(data: EditData) -> EditData:
    """Warm-up input: 60,000 points of A (the rebuilds of the warm-up take ``delaunay``'s
    two-thread path too), 6,000 of B, 200 of C, 6,000 removals. Also gets one
    ``DynamicCDT(A)`` of each kind ready for the first timed round (this imports
    cdt_plugin: no cold start on this workload)."""
    k = min(60_000, len(data.A))
    rng = np.random.default_rng(0)
    warm = EditData(data.A[:k], data.B[: k // 10], data.C[:200],
                    rng.choice(k, k // 10, replace=False), main=False)
    for kind in KINDS:
        data.refill(kind)
    return warm


WORKLOADS = [
    Workload("q-1e5", "1e5 points, 1e5 queries", queries(N_POINTS, 100_000, 3001), query_warmup, N_POINTS),
    Workload("q-1e6", "1e5 points, 1e6 queries", queries(N_POINTS, 1_000_000, 3002), query_warmup,
             N_POINTS, large=True),
    Workload("edit", "live edits on 1e5 points", edits(N_POINTS, N_INSERT, N_LOOP, N_REMOVE, 3003),
             edit_warmup, N_POINTS),
]
QUICK_ONLY = {"q-1e5"}          # the full run skips it unless named in --workloads
GROUP = {"q-1e5": "query", "q-1e6": "query", "edit": "edit"}

# ----------------------------------------------------------------------------- implementations


def setup_ours_locate():
    import cdt_plugin

    def run(d: QueryData):
        return cdt_plugin.delaunay(d.P).locate(d.Q)
    return run


def setup_scipy_locate():
    from scipy.spatial import Delaunay

    def run(d: QueryData):
        return Delaunay(d.P).find_simplex(d.Q)
    return run


def setup_ours_interpolate(method: str):
    def setup():
        import cdt_plugin

        def run(d: QueryData):
            return cdt_plugin.delaunay(d.P).interpolate(d.f, d.Q, method=method)
        return run
    return setup


def setup_scipy_linear():
    from scipy.interpolate import LinearNDInterpolator

    def run(d: QueryData):
        return LinearNDInterpolator(d.P, d.f)(d.Q)
    return run


class Edited:
    """What an edit span returns: the edited DynamicCDT and where it came from."""

    def __init__(self, data: EditData, kind: str, dyn, ids=None) -> None:
        self.data, self.kind, self.dyn, self.ids = data, kind, dyn, ids


def setup_ours_insert():
    def run(d: EditData):
        dyn = d.take("ours_insert")
        return Edited(d, "ours_insert", dyn, dyn.insert_points(d.B))
    return run


def setup_ours_loop():
    def run(d: EditData):
        dyn = d.take("ours_loop")
        for p in d.C:
            dyn.insert_points(p)
        return Edited(d, "ours_loop", dyn)
    return run


def setup_ours_remove():
    def run(d: EditData):
        dyn = d.take("ours_remove")
        dyn.remove_vertices(d.ids)
        return Edited(d, "ours_remove", dyn)
    return run


def setup_rebuild(attr: str):
    def setup():
        import cdt_plugin

        def run(d: EditData):
            return cdt_plugin.delaunay(getattr(d, attr))
        return run
    return setup


def count_inside_simplex(s) -> int:
    return int(np.count_nonzero(np.asarray(s) >= 0))


def count_finite(v) -> int:
    return int(np.count_nonzero(np.isfinite(v)))


def count_edited(r: Edited) -> int:
    """Vertices after the edit; then, untimed, the next round's DynamicCDT(A)."""
    n = len(r.dyn)
    if r.data.main:                  # (the warm-up's own input builds in its untimed call)
        r.data.refill(r.kind)
    return n


def count_vertices(tri) -> int:
    return len(tri.vertices)


# Results of the first round, kept in the worker to compare implementations with each
# other (a worker runs one workload; a worker restarted after a failure starts empty).
_STASH: dict[str, dict[str, np.ndarray]] = {}


def _stash(kind: str, name: str, arr: np.ndarray) -> dict[str, np.ndarray]:
    got = _STASH.setdefault(kind, {})
    got[name] = arr
    return got


def _digest(mask: np.ndarray) -> str:
    return hashlib.sha1(np.flatnonzero(mask).astype(np.int64).tobytes()).hexdigest()[:12]


def extras_locate(name: str, peer: str):
    def extras(d: QueryData, s) -> dict:
        outside = np.asarray(s) < 0
        out: dict[str, Any] = {"queries": len(d.Q), "outside": int(outside.sum()), "outside_sha1": _digest(outside)}
        got = _stash("outside", name, outside)
        if peer in got:
            out["vs"] = peer
            out["outside_mismatch"] = int(np.count_nonzero(got[peer] != outside))
        return out
    return extras


def extras_linear(name: str, peer: str):
    def extras(d: QueryData, v) -> dict:
        v = np.asarray(v, dtype=np.float64).reshape(-1)
        nan = np.isnan(v)
        out: dict[str, Any] = {"queries": len(d.Q), "nan": int(nan.sum())}
        got = _stash("linear", name, v)
        if peer in got:
            w = got[peer]
            both = ~(nan | np.isnan(w))
            out["vs"] = peer
            out["nan_mismatch"] = int(np.count_nonzero(nan != np.isnan(w)))
            out["max_abs_diff"] = float(np.max(np.abs(v[both] - w[both]))) if both.any() else 0.0
        return out
    return extras


def extras_natural(d: QueryData, v) -> dict:
    v = np.asarray(v, dtype=np.float64).reshape(-1)
    nan = np.isnan(v)
    out: dict[str, Any] = {"queries": len(d.Q), "nan": int(nan.sum())}
    lin = _STASH.get("linear", {}).get("ours_linear")
    if lin is not None:
        out["vs"] = "ours_linear"
        out["nan_mismatch"] = int(np.count_nonzero(nan != np.isnan(lin)))
    return out


def extras_edited(d: EditData, r: Edited) -> dict:
    snap = r.dyn.triangulation()
    expected = {"ours_insert": len(d.A) + len(d.B), "ours_loop": len(d.A) + len(d.C),
                "ours_remove": len(d.A) - len(d.ids)}[r.kind]
    out: dict[str, Any] = {"vertices": len(snap.vertices), "expected": expected,
                           "triangles": len(snap.triangles), "delaunay": bool(snap.is_delaunay()),
                           "built_in_span": d.built_in_span}
    if r.kind == "ours_insert":
        out["ids_ok"] = bool(r.ids is not None and len(r.ids) == len(d.B)
                             and np.array_equal(r.dyn.vertices[r.ids], d.B))
    if r.kind == "ours_remove":
        # the rebuild's input (A less rows ids) must be what the removal left
        out["same_points"] = bool(np.array_equal(r.dyn.vertices, d.rest))
    out["ok"] = bool(out["vertices"] == expected and out["delaunay"] and out.get("ids_ok", True)
                     and out.get("same_points", True))
    return out


def extras_rebuild(d: EditData, tri) -> dict:
    return {"vertices": len(tri.vertices), "triangles": len(tri.triangles)}


IMPLS = [
    Impl("ours_locate", "cdt_plugin delaunay + locate", setup_ours_locate, count_inside_simplex,
         timed="delaunay(P).locate(Q)", dist="cdt-plugin", numba_cold_start=True, package="cdt_plugin",
         extras=extras_locate("ours_locate", "scipy_locate")),
    Impl("scipy_locate", "scipy Delaunay + find_simplex", setup_scipy_locate, count_inside_simplex,
         timed="Delaunay(P).find_simplex(Q)", slow=True, dist="scipy",
         extras=extras_locate("scipy_locate", "ours_locate")),
    Impl("ours_linear", "cdt_plugin delaunay + interpolate linear", setup_ours_interpolate("linear"),
         count_finite, timed="delaunay(P).interpolate(f, Q)",
         extras=extras_linear("ours_linear", "scipy_linear")),
    Impl("scipy_linear", "scipy LinearNDInterpolator", setup_scipy_linear, count_finite,
         timed="LinearNDInterpolator(P, f)(Q)", slow=True,
         extras=extras_linear("scipy_linear", "ours_linear")),
    Impl("ours_natural", "cdt_plugin delaunay + interpolate natural", setup_ours_interpolate("natural"),
         count_finite, timed="delaunay(P).interpolate(f, Q, method=\"natural\")", extras=extras_natural),
    Impl("ours_insert", "DynamicCDT.insert_points(1e5 points)", setup_ours_insert, count_edited,
         timed="dyn.insert_points(B), dyn = DynamicCDT(A) built untimed", extras=extras_edited),
    Impl("rebuild_insert", "cdt_plugin delaunay(A ∪ B), 2e5 points", setup_rebuild("AB"), count_vertices,
         timed="delaunay(AB), AB = vstack(A, B) untimed", extras=extras_rebuild),
    Impl("ours_loop", "DynamicCDT.insert_points, one point per call", setup_ours_loop, count_edited,
         timed="for p in C: dyn.insert_points(p) (10,000 calls), dyn = DynamicCDT(A) built untimed",
         extras=extras_edited),
    Impl("ours_remove", "DynamicCDT.remove_vertices(10%)", setup_ours_remove, count_edited,
         timed="dyn.remove_vertices(ids) (10,000 ids), dyn = DynamicCDT(A) built untimed",
         extras=extras_edited),
    Impl("rebuild_remove", "cdt_plugin delaunay(the rest), 9e4 points", setup_rebuild("rest"), count_vertices,
         timed="delaunay(rest), rest = the 90,000 points left, selected untimed", extras=extras_rebuild),
]
IMPL_GROUP = {"ours_locate": "query", "scipy_locate": "query", "ours_linear": "query",
              "scipy_linear": "query", "ours_natural": "query", "ours_insert": "edit",
              "rebuild_insert": "edit", "ours_loop": "edit", "ours_remove": "edit", "rebuild_remove": "edit"}

SUITE = Suite(
    name="queries",
    title="Point location, interpolation and live edits",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="scipy_locate",
    script=os.path.abspath(__file__),
    cold_workload="q-1e6",
)

# ----------------------------------------------------------------------------- checks


def checks(results: dict) -> list[str]:
    warnings = []
    labels = {i.name: i.label for i in IMPLS}
    for wname, row in results["workloads"].items():
        ex = {name: c.get("extras") for name, c in row.items() if c.get("extras") and not c.get("error")}
        for name, e in ex.items():
            if e.get("error"):
                warnings.append(f"{wname}: {labels[name]}: the check failed: {e['error']}")
        ex = {name: e for name, e in ex.items() if not e.get("error")}
        for name, e in ex.items():
            if e.get("outside_mismatch"):
                warnings.append(f"{wname}: locate and find_simplex disagree on which queries are outside for "
                                f"{e['outside_mismatch']:,d} queries")
            if e.get("nan_mismatch"):
                warnings.append(f"{wname}: {labels[name]} and {labels[e['vs']]} are NaN at different queries "
                                f"({e['nan_mismatch']:,d})")
            if e.get("max_abs_diff") is not None and not e["max_abs_diff"] <= LINEAR_ATOL:
                warnings.append(f"{wname}: our linear interpolant differs from LinearNDInterpolator's by up to "
                                f"{e['max_abs_diff']:.3g} (> {LINEAR_ATOL:g})")
            if name in KINDS:
                if e.get("vertices") != e.get("expected"):
                    warnings.append(f"{wname}: {labels[name]}: the snapshot has {e.get('vertices')} vertices, "
                                    f"expected {e.get('expected')}")
                if e.get("delaunay") is False:
                    warnings.append(f"{wname}: {labels[name]}: the snapshot is not Delaunay")
                if e.get("ids_ok") is False:
                    warnings.append(f"{wname}: {labels[name]}: dyn.vertices[ids] is not B")
                if e.get("same_points") is False:
                    warnings.append(f"{wname}: {labels[name]}: the vertices left are not the rebuild's input")
                if e.get("built_in_span"):
                    warnings.append(f"{wname}: {e['built_in_span']} timed edit span(s) had to build their own "
                                    "DynamicCDT(A) (their times include it)")
        for ours, ref in (("ours_insert", "rebuild_insert"), ("ours_remove", "rebuild_remove")):
            if ours in ex and ref in ex and ex[ours].get("triangles") != ex[ref].get("triangles"):
                warnings.append(f"{wname}: {labels[ours]}: {ex[ours].get('triangles')} triangles, "
                                f"the rebuild {ex[ref].get('triangles')}")
    if results.get("sources_changed"):
        warnings.append("source files changed during the run (rows measured before and after may time "
                        "different code): " + ", ".join(results["sources_changed"]))
    cold = results.get("cold") or {}
    if cold.get("warning"):
        warnings.append(f"cold start: {cold['warning']}")
    return list(dict.fromkeys(warnings))

# ----------------------------------------------------------------------------- report


def _ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}x" if a and b else "n/a"


def _verdict(a: float | None, b: float | None, goal: float) -> str:
    if not (a and b):
        return "n/a"
    return "met" if a <= goal * b else "not met"


def _items(wl_name: str, impl: str) -> tuple[int, str] | None:
    """(number of items, item) a row's time is divided by in the µs column."""
    if GROUP[wl_name] == "query":
        return (1_000_000 if wl_name == "q-1e6" else 100_000), "query"
    return {"ours_insert": (N_INSERT, "inserted point"), "rebuild_insert": (N_INSERT, "inserted point"),
            "ours_loop": (N_LOOP, "inserted point"), "ours_remove": (N_REMOVE, "removed vertex"),
            "rebuild_remove": (N_REMOVE, "removed vertex")}.get(impl)


def _check_cell(name: str, c: dict) -> str:
    ex = c.get("extras")
    if c.get("error"):
        return "-"
    if not ex:
        return "n/a"
    if ex.get("error"):
        return "check failed"
    if name in ("ours_locate", "scipy_locate"):
        text = f"{ex['outside']:,d} outside"
        if "outside_mismatch" in ex:
            text += "; same as peer" if ex["outside_mismatch"] == 0 else f"; {ex['outside_mismatch']:,d} DIFFER"
        return text
    if name in ("ours_linear", "scipy_linear", "ours_natural"):
        parts = [f"{ex['nan']:,d} NaN"]
        if "max_abs_diff" in ex:
            parts.append(f"max diff to peer {ex['max_abs_diff']:.1e}")
        if ex.get("nan_mismatch"):
            parts.append(f"{ex['nan_mismatch']:,d} NaN DIFFER")
        elif "nan_mismatch" in ex:
            parts.append("NaN where linear is")
        return "; ".join(parts)
    if name in KINDS:
        parts = [f"{ex['vertices']:,d} vertices" + ("" if ex["vertices"] == ex["expected"] else " WRONG"),
                 "Delaunay" if ex["delaunay"] else "NOT DELAUNAY", f"{ex['triangles']:,d} triangles"]
        return "; ".join(parts)
    if name.startswith("rebuild"):
        return f"{ex['triangles']:,d} triangles"
    return "-"


def _goal_rows(results: dict) -> list[str]:
    rows = []
    for wl in WORKLOADS:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        m = {n: (c.get("median") if not c.get("error") else None) for n, c in row.items()}
        if GROUP[wl.name] == "query":
            pairs = [("locate, build included", "ours_locate", "scipy_locate", GOAL_LOCATE_SCIPY),
                     ("interpolate linear, build included", "ours_linear", "scipy_linear", GOAL_LINEAR_SCIPY),
                     ("interpolate natural / linear", "ours_natural", "ours_linear", GOAL_NATURAL_LINEAR)]
        else:
            pairs = [("insert_points(1e5) into 1e5 / build 2e5 from scratch", "ours_insert", "rebuild_insert",
                      GOAL_INSERT_REBUILD),
                     ("remove_vertices(10%) / rebuild", "ours_remove", "rebuild_remove", GOAL_REMOVE_REBUILD)]
        for what, a, b, goal in pairs:
            if a not in row and b not in row:
                continue
            rows.append(f"| {wl.label} | {what} | {fmt_s(m.get(a))} | {fmt_s(m.get(b))} | "
                        f"{_ratio(m.get(a), m.get(b))} | <= {goal:g}x | {_verdict(m.get(a), m.get(b), goal)} |")
        if GROUP[wl.name] == "edit" and "ours_loop" in row:
            t = m.get("ours_loop")
            us = t / N_LOOP * 1e6 if t else None
            rows.append(f"| {wl.label} | one point per insert_points call (µs per point / 10 µs) | "
                        f"{f'{us:.2f} µs' if us else 'n/a'} | {GOAL_LOOP_US:g} µs | "
                        f"{_ratio(us, GOAL_LOOP_US)} | <= 1x | {_verdict(us, GOAL_LOOP_US, 1.0)} |")
    return rows


def render(results: dict, info: dict, args_line: str) -> str:
    v = ", ".join(f"{k} {val}" for k, val in info["versions"].items() if val)
    lines = [
        f"Machine: {info['cpu_count']} CPUs ({info['cpus_usable']} usable)"
        + (f", {info['cpu_model']}" if info["cpu_model"] else "")
        + f"; {v}; {info['date']}. Command: `{args_line}`"
        + (" (mode: quick)" if results["mode"] == "quick" else "") + ".",
        "",
        "| workload | implementation | median s | µs per item | count | check | peak MB |",
        "|---|---|---:|---:|---:|---|---:|",
    ]
    notes: list[str] = []
    present = set()
    for wl in WORKLOADS:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        for impl in IMPLS:
            c = row.get(impl.name)
            if c is None:
                continue
            present.add(impl.name)
            if c.get("error"):
                notes.append(f"{wl.label} / {impl.label}: {c['error']}")
            if c.get("peak_mb") is None and c.get("mem_error") and not c.get("error"):
                notes.append(f"{wl.label} / {impl.label} memory: {c['mem_error']}")
            med = None if c.get("error") else c.get("median")
            items = _items(wl.name, impl.name)
            per = f"{med / items[0] * 1e6:.3g}" if med and items else "n/a"
            count = f"{c['count']:,d}" if c.get("count") is not None else "n/a"
            mem = f"{c['peak_mb']:.1f}" if c.get("peak_mb") is not None else "n/a"
            lines.append(f"| {wl.label} | {impl.label} | {fmt_s(med)} | {per} | {count} | "
                         f"{_check_cell(impl.name, c)} | {mem} |")

    lines += ["", ("Against the goals (issue #19; ratios of medians in this run; the query goals are stated "
                   "for 1e6 queries in a 1e5-point triangulation):"), "",
              "| workload | goal | ours | reference | ratio | goal | verdict |",
              "|---|---|---:|---:|---:|---|---|"]
    lines += _goal_rows(results)
    lines.append("")

    cold = results.get("cold")
    if cold:
        impl = SUITE.impl(cold["impl"])
        wl = SUITE.workload(cold["workload"])
        warm = results["workloads"].get(wl.name, {}).get(impl.name, {}).get("median")
        parts = [f"cold {fmt_s(cold['cold_s'])} s" if "cold_s" in cold
                 else f"cold n/a ({cold.get('cold_s_error')})"]
        if "cached_s" in cold:
            parts.append(f"cached start {fmt_s(cold['cached_s'])} s")
        parts.append(f"warm {fmt_s(warm)} s" if warm else "warm n/a")
        lines += [f"{impl.label} start-up on {wl.label}: " + "; ".join(parts)
                  + (f" (warning: {cold['warning']})" if cold.get("warning") else "")
                  + ". Cold = new process, empty numba cache (`NUMBA_CACHE_DIR` = fresh temp dir), import + "
                  "first call (compilation of the Delaunay and point-location kernels included); cached start = "
                  "new process, filled cache, import + first call; warm = in-process median (the table).", ""]

    impls = [i for i in IMPLS if i.name in present]
    spans = "; ".join(f"{i.label}: {i.timed}" for i in impls)
    methods = sorted({c.get("mem_method") for row in results["workloads"].values()
                      for c in row.values() if c.get("mem_method")})
    large = [w.label for w in WORKLOADS if w.large and w.name in results["workloads"]]
    slow = [i.label for i in impls if i.slow]
    lines.append(
        f"Median of {results['repeat']} interleaved round(s) per workload"
        + (f" ({', '.join(slow)}: {results['slow_repeat']} round(s) on {', '.join(large)})"
           if results["slow_repeat"] < results["repeat"] and slow and large else "")
        + ", one worker process per workload, input generation not timed, the triangulation inside every "
        "query span (`delaunay` with its default workers: both cores from 50,000 points; Qhull runs on one); "
        "a fresh `DynamicCDT(A)` built untimed before every edit span. "
        + ("Peak MB = extra resident memory of one call in a fresh process (peak minus the baseline after "
           "imports, input and warm-up, the edit's `DynamicCDT(A)` included in the baseline; MiB; method: "
           + ", ".join(methods) + ")."
           if methods else "Peak memory not measured.")
        + " Timed spans: " + spans + ". µs per item: the median divided by the queries, the points inserted "
        "(the rebuild of A ∪ B too) or the vertices removed (the rebuild of the rest too). Count: queries "
        "inside the hull (locate: triangle found; interpolate: finite value), vertices after the edit or of "
        "the rebuild. Check (untimed, first result): locate's outside queries against find_simplex's, the "
        f"linear interpolants against each other (at most {LINEAR_ATOL:g} apart) and natural's NaN against "
        "linear's; the snapshot `dyn.triangulation()` of each edit: vertex count, `is_delaunay()`, triangles "
        "as many as the rebuild's."
        + (" The machine is shared (2 CPUs, other processes running): read the same-run ratios."
           if info["cpu_count"] <= 2 else ""))
    if notes:
        lines += [""] + [f"- n/a: {n}" for n in notes]
    if results.get("warnings"):
        lines += [""] + [f"- WARNING: {w}" for w in results["warnings"]]
    return "\n".join(lines) + "\n"

# ----------------------------------------------------------------------------- driver


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _parse(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=SUITE.title)
    p.add_argument("--quick", action="store_true",
                   help="smoke test: q-1e5 (1e5 queries) and edit, 1 round")
    p.add_argument("--repeat", type=int, default=None, help="interleaved rounds per workload (default 3)")
    p.add_argument("--slow-repeat", type=int, default=2,
                   help="rounds for scipy on the q-1e6 workload (default 2: 15-25 s per call)")
    p.add_argument("--only", default=None,
                   help="comma-separated implementations: " + ",".join(i.name for i in IMPLS))
    p.add_argument("--workloads", default=None,
                   help="comma-separated workloads: " + ",".join(w.name for w in WORKLOADS)
                   + " (default: q-1e6,edit; q-1e5,edit with --quick)")
    p.add_argument("--timeout", type=float, default=120.0, help="seconds allowed per timed call (default 120)")
    p.add_argument("--setup-timeout", type=float, default=600.0,
                   help="seconds allowed for input + import + warm-up, e.g. numba compilation (default 600)")
    p.add_argument("--no-memory", action="store_true", help="skip the peak-memory processes")
    p.add_argument("--no-cold", action="store_true", help="skip the cold / cached start-up of cdt_plugin")
    p.add_argument("--out", default=None,
                   help="markdown output (a .json with raw numbers is written beside it); "
                   "default benchmarks/results/queries.md (queries-quick.md with --quick)")
    p.add_argument("--write-readme", action="store_true",
                   help="regenerate the README's benchmark summary rows from the stored results")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == [WORKER_FLAG]:                 # a timing / memory / cold worker (harness.py)
        return harness_main(SUITE, argv)
    args = _parse(argv)
    t_start = time.perf_counter()
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)
    slow_repeat = min(repeat, max(args.slow_repeat, 1))
    impls = select_by_name(args.only, IMPLS, "implementation(s)")
    workloads = select_by_name(args.workloads, WORKLOADS, "workload(s)")
    if args.quick:
        workloads = [w for w in workloads if not w.large]
    elif not args.workloads:
        workloads = [w for w in workloads if w.name not in QUICK_ONLY]
    workloads = [w for w in workloads if any(IMPL_GROUP[i.name] == GROUP[w.name] for i in impls)]
    if not workloads:
        raise SystemExit("no workload left for these implementations (--only / --workloads / --quick)")
    info = machine_info(SUITE)
    _log(f"{SUITE.title}: {len(workloads)} workload(s), {len(impls)} implementation(s), {repeat} round(s); "
         f"{info['cpu_count']} CPUs; python {info['versions']['python']}")
    results: dict[str, Any] = {
        "suite": SUITE.name, "mode": "quick" if args.quick else "full", "repeat": repeat,
        "slow_repeat": slow_repeat, "machine": info, "argv": argv, "workloads": {},
    }

    sources_before = sources_state()
    cold_wl = SUITE.workload(SUITE.cold_workload)
    cold_impl = next((i for i in impls if i.numba_cold_start), None)
    if cold_impl is not None and not args.no_cold and cold_wl in workloads:
        _log("cold start:")
        results["cold"] = measure_cold(SUITE, cold_impl, cold_wl, args.setup_timeout + args.timeout)

    for wl in workloads:
        _log(f"{wl.label}:")
        active = [i for i in impls if IMPL_GROUP[i.name] == GROUP[wl.name]]
        repeats = {i.name: (slow_repeat if wl.large and i.slow else repeat) for i in active}
        cells = measure_times(SUITE, wl, active, repeats, args.timeout, args.setup_timeout)
        if not args.no_memory and wl.memory:
            for impl in active:
                if cells[impl.name].error is None:
                    measure_memory(SUITE, wl, impl, cells[impl.name], args.timeout, args.setup_timeout)
        results["workloads"][wl.name] = {
            name: {"median": c.median, "times": c.times, "count": c.count, "peak_mb": c.peak_mb,
                   "mem_method": c.mem_method, "error": c.error, "mem_error": c.mem_error,
                   "extras": c.extras}
            for name, c in cells.items()}
        for name, c in cells.items():
            if c.extras:
                _log(f"  {wl.name:<14} {name:<14} check {c.extras}")

    results["sources_changed"] = changed_sources(sources_before, sources_state())
    try:
        results["warnings"] = checks(results)
    except Exception as exc:
        results["warnings"] = [f"the checks failed: {short_reason(exc)}"]
    for w in results["warnings"]:
        _log(f"WARNING: {w}")

    md = render(results, info, command_line(SUITE, argv))
    results["elapsed_s"] = time.perf_counter() - t_start
    ours_failed = sorted({f"{w}/{n}" for w, cells in results["workloads"].items()
                          for n, c in cells.items() if not n.startswith("scipy") and c.get("error")})
    if args.write_readme and ours_failed:
        # a table of n/a rows for our own columns is never what the README should show
        _log(f"NOT updating {README}: cdt_plugin failed on {', '.join(ours_failed)}")
        args.write_readme = False
        write_results(SUITE, results, md, args)
        return 1
    return write_results(SUITE, results, md, args)


if __name__ == "__main__":
    sys.exit(main())
