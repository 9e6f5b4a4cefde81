"""One small polygon per call, as a trimesh / shapely user meets it.

The other benchmarks time large inputs, where the compiled kernels dominate. A user
who reaches cdt_plugin through ``trimesh.creation.triangulate_polygon`` or
``shapely.constrained_delaunay_triangles`` instead calls it once per polygon, on
polygons of a few to a few hundred vertices, in a process that has just started.
What they meet is the fixed cost of a call (argument checks, reading the shapely
geometry, building the output object) and the cost of the first call (numba
compilation, or loading numba's cache). This file measures both.

Warm timings, one shapely polygon per call (built deterministically):

* ``square``   — ``shapely.box(0, 0, 1, 1)``, 4 vertices;
* ``star12``   — a star of 12 vertices, radii alternating 1 and 0.5;
* ``star60``   — the same with 60 vertices;
* ``star60h2`` — star60 with 2 holes (regular 8-gons of radius 0.12 centred at
  (+-0.2, 0): inside the inner radius, apart from each other);
* ``star400h4`` — a star of 400 vertices with 4 holes (8-gons of radius 0.1 centred
  0.2 from the origin on the axes).

Implementations, interleaved round-robin in one worker process per polygon (``harness.py``):

* ``ours``          — ``cdt_plugin.triangulate(polygon)``, the shapely polygon passed directly;
* ``ours_trimesh``  — ``cdt_plugin.adapters.trimesh.triangulate_polygon(polygon)`` (trimesh drop-in);
* ``ours_shapely``  — ``cdt_plugin.adapters.shapely.constrained_delaunay_triangles(polygon)``
  (shapely drop-in);
* ``ours_delaunay`` — ``cdt_plugin.delaunay(V)`` on the polygon's vertices (every ring's
  vertices, closing points dropped): the floor of a call without segments or shapely;
* ``triangle``      — Triangle, ``triangle.triangulate({vertices, segments, holes}, "pQ")`` on
  arrays prepared once outside the timed call; the reference of the ratios;
* ``geos``          — ``shapely.constrained_delaunay_triangles(polygon)`` (GEOS, shapely >= 2.1);
* ``trimesh_earcut`` — ``trimesh.creation.triangulate_polygon(polygon, engine="earcut")``
  (polygon in, as a trimesh user calls it; ear clipping, not Delaunay);
* ``earcut``        — ``mapbox_earcut.triangulate_float64(V, ring_ends)`` on prepared arrays.

Each round times ``number`` back-to-back calls (hundreds for the small polygons) and
reports the mean per call; the table gives the median over the rounds in
microseconds, and the ratio of ``cdt_plugin.triangulate`` to Triangle and to earcut.
The goal (the issue): every row at most 1.0x Triangle's time, the square at most
30 us; stretch: at most 2x earcut. A second table sets the drop-ins against what
they replace (issue #47): the shapely drop-in at most 1.5x ``cdt_plugin.triangulate``
at every size and at most 1.0x GEOS from 60 vertices up (below, its ratio to GEOS is
reported), the trimesh drop-in at most 1.2x ``cdt_plugin.triangulate``; both also
against Triangle.

First use, each case a new Python process (``NUMBA_CACHE_DIR`` = a fresh temporary
directory for the empty-cache cases):

* empty cache: ``import cdt_plugin`` alone; import + first ``delaunay`` of 100 random
  points; import + first ``triangulate`` of the square; import + first
  ``triangulate(star12, min_angle=30)`` (2 Steiner points: the refinement really runs);
  all of them in one process (goal: at most 30 s); the same all-in-one case with
  ``CDT_PLUGIN_COMPILE_HELPER=0`` first (numba compiling on one core only: no second
  process compiles route stages);
* filled cache (the same directory again, after the all-in-one case filled it): import
  alone; import + first ``triangulate`` of the square (goal: at most 0.5 s); all; and
  import + first ``triangulate`` again with scipy absent, as after a fresh ``pip install
  cdt-plugin`` (numba imports scipy, when installed, to probe for BLAS: about 0.1 s).

The package's bytecode is compiled first (``PYTHONPYCACHEPREFIX``), as pip does at
install time. The child times its phases with ``time.perf_counter`` and prints them as JSON; the
parent times the whole child by wall clock (interpreter start, numpy and shapely
imports, exit included).

Usage (from the repository root)::

    python benchmarks/bench_small.py --quick          # smoke: 3 rounds, first use all-in-one + cached, ~3 min
    python benchmarks/bench_small.py                  # full run, ~8 minutes on 2 cores (6 of them compiling)
    python benchmarks/bench_small.py --write-readme   # full run + the README summary rows
    python benchmarks/bench_small.py --only ours,triangle --workloads square --no-cold
    python benchmarks/bench_small.py --keep-first-use  # warm tables anew, first use kept from the file

Options: ``--repeat R`` (rounds, default 15; 3 with ``--quick``), ``--only``,
``--workloads``, ``--timeout S`` per timed sample, ``--setup-timeout S`` (import +
warm-up, and each first-use child), ``--no-cold`` (skip the first-use processes),
``--keep-first-use`` (skip them and keep the first-use rows of the results file written
before, with the date of the run that measured them),
``--out PATH.md`` (a .json with the raw numbers is written beside it; default
``benchmarks/results/small.md``, ``small-quick.md`` with ``--quick``).

This module must not import numba or cdt_plugin at import time: the first-use
children re-run it and time the import.
"""
from __future__ import annotations

import time

_T_MODULE = time.perf_counter()   # the first-use child's clock starts here

import argparse  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any, Callable  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import (REPO_ROOT, WORKER_FLAG, Impl, Suite, Workload,  # noqa: E402
                     command_line, machine_info, measure_times, results_path, select_by_name,
                     short_reason, write_results)
from harness import main as harness_main  # noqa: E402

FIRST_USE_FLAG = "--_first-use"
DEFAULT_REPEAT, QUICK_REPEAT = 15, 3

# ----------------------------------------------------------------------------- polygons


@dataclass(frozen=True)
class Shape:
    name: str
    label: str
    n_outer: int          # 0: the unit square
    n_holes: int
    number: int           # calls per timed sample (about 0.1 s for the slowest peer)

    @property
    def n_vertices(self) -> int:
        return (self.n_outer or 4) + 8 * self.n_holes


SHAPES = [
    Shape("square", "square (4 v)", 0, 0, 400),
    Shape("star12", "star 12 v", 12, 0, 400),
    Shape("star60", "star 60 v", 60, 0, 300),
    Shape("star60h2", "star 60 v + 2 holes (76 v)", 60, 2, 200),
    Shape("star400h4", "star 400 v + 4 holes (432 v)", 400, 4, 60),
]


def star(n: int, n_holes: int = 0):
    """A star of n vertices (radii alternating 1 and 0.5) with n_holes regular 8-gons."""
    import shapely
    t = 2 * np.pi * np.arange(n) / n
    r = np.where(np.arange(n) % 2 == 0, 1.0, 0.5)
    shell = np.column_stack([r * np.cos(t), r * np.sin(t)])
    hole_r = 0.12 if n_holes <= 2 else 0.1
    s = 2 * np.pi * np.arange(8) / 8
    holes = []
    for k in range(n_holes):
        a = 2 * np.pi * k / n_holes
        centre = 0.2 * np.array([np.cos(a), np.sin(a)])
        holes.append(centre + hole_r * np.column_stack([np.cos(s), np.sin(s)]))
    return shapely.Polygon(shell, holes)


def make_polygon(shape: Shape):
    import shapely
    return shapely.box(0, 0, 1, 1) if shape.n_outer == 0 else star(shape.n_outer, shape.n_holes)


def polygon_input(polygon) -> dict:
    """The polygon and the arrays the array peers take, made once (never timed)."""
    import shapely
    rings = [polygon.exterior, *polygon.interiors]
    coords = [np.asarray(r.coords)[:-1] for r in rings]           # closing points dropped
    V = np.ascontiguousarray(np.concatenate(coords), dtype=np.float64)
    ends = np.cumsum([len(c) for c in coords])
    S = np.concatenate([np.column_stack([np.arange(e - len(c), e), np.roll(np.arange(e - len(c), e), -1)])
                        for c, e in zip(coords, ends)]).astype(np.int32)
    H = np.array([shapely.Polygon(r).representative_point().coords[0] for r in polygon.interiors],
                 dtype=np.float64).reshape(-1, 2)
    pslg = {"vertices": V, "segments": S}
    if len(H):
        pslg["holes"] = H                     # an empty holes array crashes triangle
    return {"polygon": polygon, "V": V, "ends": ends.astype(np.uint32), "pslg": pslg,
            "expected": len(V) + 2 * len(H) - 2}     # triangles of any triangulation without Steiner points


def workload(shape: Shape) -> Workload:
    return Workload(shape.name, shape.label, lambda: polygon_input(make_polygon(shape)),
                    size=shape.n_vertices, number=shape.number, memory=False)


WORKLOADS = [workload(s) for s in SHAPES]

# ----------------------------------------------------------------------------- implementations


def setup_ours() -> Callable[[dict], Any]:
    import cdt_plugin
    triangulate = cdt_plugin.triangulate
    return lambda d: triangulate(d["polygon"])


def setup_ours_trimesh() -> Callable[[dict], Any]:
    from cdt_plugin.adapters.trimesh import triangulate_polygon
    return lambda d: triangulate_polygon(d["polygon"])


def setup_ours_shapely() -> Callable[[dict], Any]:
    from cdt_plugin.adapters.shapely import constrained_delaunay_triangles
    return lambda d: constrained_delaunay_triangles(d["polygon"])


def setup_ours_delaunay() -> Callable[[dict], Any]:
    import cdt_plugin
    delaunay = cdt_plugin.delaunay
    return lambda d: delaunay(d["V"])


def setup_triangle() -> Callable[[dict], Any]:
    import triangle
    triangulate = triangle.triangulate
    return lambda d: triangulate(d["pslg"], "pQ")


def setup_geos() -> Callable[[dict], Any]:
    import shapely
    if not hasattr(shapely, "constrained_delaunay_triangles"):
        raise ImportError(f"shapely {shapely.__version__} has no constrained_delaunay_triangles (need 2.1)")
    cdt = shapely.constrained_delaunay_triangles
    return lambda d: cdt(d["polygon"])


def setup_trimesh_earcut() -> Callable[[dict], Any]:
    import mapbox_earcut  # noqa: F401  (trimesh's earcut engine; fail here, not in the timed call)
    import trimesh
    triangulate_polygon = trimesh.creation.triangulate_polygon
    return lambda d: triangulate_polygon(d["polygon"], engine="earcut")


def setup_earcut() -> Callable[[dict], Any]:
    import mapbox_earcut
    triangulate = mapbox_earcut.triangulate_float64
    return lambda d: triangulate(d["V"], d["ends"])


def count_geoms(result) -> int:
    import shapely
    return int(shapely.get_num_geometries(result))


IMPLS = [
    Impl("ours", "cdt_plugin.triangulate", setup_ours, lambda t: len(t.triangles),
         timed="triangulate(polygon), shapely Polygon in, Triangulation out",
         dist="cdt-plugin", package="cdt_plugin"),
    Impl("ours_trimesh", "trimesh drop-in", setup_ours_trimesh, lambda r: len(r[1]),
         timed="cdt_plugin.adapters.trimesh.triangulate_polygon(polygon), (vertices, faces) out"),
    Impl("ours_shapely", "shapely drop-in", setup_ours_shapely, count_geoms,
         timed="cdt_plugin.adapters.shapely.constrained_delaunay_triangles(polygon), "
         "GeometryCollection of triangles out"),
    Impl("ours_delaunay", "cdt_plugin.delaunay (vertices)", setup_ours_delaunay,
         lambda t: len(t.triangles),
         timed="delaunay(V) on the ring vertices, no segments (convex hull: other triangle counts)"),
    Impl("triangle", "Triangle", setup_triangle, lambda r: len(r["triangles"]),
         timed="triangulate({vertices, segments, holes}, 'pQ') on prepared arrays, dict of arrays out",
         dist="triangle"),
    Impl("geos", "GEOS", setup_geos, count_geoms,
         timed="shapely.constrained_delaunay_triangles(polygon), GeometryCollection out",
         dist="shapely"),
    Impl("trimesh_earcut", "earcut via trimesh", setup_trimesh_earcut, lambda r: len(r[1]),
         timed="trimesh.creation.triangulate_polygon(polygon, engine='earcut'), (vertices, faces) out",
         dist="trimesh"),
    Impl("earcut", "earcut (arrays)", setup_earcut, lambda idx: len(idx) // 3,
         timed="mapbox_earcut.triangulate_float64(V, ring ends) on prepared arrays, index array out",
         dist="mapbox_earcut"),
]

SUITE = Suite(
    name="small",                    # results/small.md, included by docs/benchmarks/small.md
    title="Small polygons, one per call: warm per-call time and first use",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="triangle",
    script=os.path.abspath(__file__),
)

GOAL_TRIANGLE = 1.0        # every row at most Triangle's time
GOAL_SQUARE_US = 30.0      # ... and the square at most 30 us
STRETCH_EARCUT = 2.0       # stretch: at most 2x earcut
GOAL_DROPIN_OURS = 1.5     # the shapely drop-in: at most 1.5x cdt_plugin.triangulate ...
GOAL_DROPIN_GEOS = 1.0     # ... and at most GEOS's time from GEOS_FROM vertices up
GEOS_FROM = 60
GOAL_TRIMESH_OURS = 1.2    # the trimesh drop-in: at most 1.2x cdt_plugin.triangulate
GOAL_COLD_S = 30.0         # import + delaunay + triangulate + refinement, empty cache
GOAL_CACHED_S = 0.5        # import + first small triangulate, filled cache
HELPER_ENV = "CDT_PLUGIN_COMPILE_HELPER"   # cdt_plugin.compiling's switch ("0": one process)

# ----------------------------------------------------------------------------- first use


FIRST_STEPS = {            # step -> what the child calls (shown in the table)
    "delaunay": "delaunay(100 random points)",
    "triangulate": "triangulate(square)",
    "min_angle": "triangulate(star12, min_angle=30)",
}
ALL_STEPS = ["delaunay", "triangulate", "min_angle"]


def _first_use_child(steps: list[str], without_scipy: bool = False) -> None:
    """Runs in a new process: import cdt_plugin, then the first call of each step.
    ``without_scipy``: as in an environment without scipy (numba imports it, when
    present, to probe for BLAS: about 0.1 s of every import; cdt_plugin does not
    need it, so a fresh ``pip install cdt-plugin`` has none)."""
    import shapely
    if without_scipy:
        assert "scipy" not in sys.modules
        sys.modules["scipy"] = None      # type: ignore[assignment]  # (import scipy now raises ImportError)
    numba_preloaded = "numba" in sys.modules
    inputs = {"delaunay": np.random.default_rng(0).uniform(0.0, 1.0, (100, 2)),
              "triangulate": shapely.box(0, 0, 1, 1), "min_angle": star(12)}
    phases: list[tuple[str, float]] = [("prelude", time.perf_counter() - _T_MODULE)]
    t0 = time.perf_counter()
    import cdt_plugin
    phases.append(("import", time.perf_counter() - t0))
    for step in steps:
        t0 = time.perf_counter()
        if step == "delaunay":
            out = cdt_plugin.delaunay(inputs[step])
        elif step == "triangulate":
            out = cdt_plugin.triangulate(inputs[step])
        else:
            out = cdt_plugin.triangulate(inputs[step], min_angle=30)
        phases.append((step, time.perf_counter() - t0))
        assert len(out.triangles) > 0
    print(json.dumps({"phases": phases, "numba_preloaded": numba_preloaded}), flush=True)


def _run_child(steps: list[str], cache: str, timeout: float, pycache: str,
               without_scipy: bool = False, one_process: bool = False) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPYCACHEPREFIX=pycache)
    env.pop(HELPER_ENV, None)
    if one_process:
        env[HELPER_ENV] = "0"                    # no second process compiles route stages
    env.pop("PYTHONDONTWRITEBYTECODE", None)     # bytecode as pip installs it (see _compile_bytecode)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, os.path.abspath(__file__), FIRST_USE_FLAG, json.dumps(steps),
                               json.dumps(without_scipy)],
                              env=env, cwd=str(REPO_ROOT), stdin=subprocess.DEVNULL,
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timed out (> {timeout:g} s)"}
    wall = time.perf_counter() - t0
    lines = proc.stdout.strip().splitlines()
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr.strip().splitlines() or [""])[-1][:160]
        return {"error": f"child failed (exit code {proc.returncode}){': ' + tail if tail else ''}"}
    out = json.loads(lines[-1])
    out["wall_s"] = wall
    out["calls_s"] = sum(s for name, s in out["phases"] if name != "prelude")   # import + first calls
    return out


def _dir_size(path: str) -> tuple[int, int]:
    files = [p for p in Path(path).rglob("*") if p.is_file()]
    return len(files), sum(p.stat().st_size for p in files)


def _compile_bytecode(pycache: str) -> None:
    """The package's Python bytecode, compiled into ``pycache`` before the children
    run: pip writes it at install time, so a user's first import does not compile
    Python source (an environment with PYTHONDONTWRITEBYTECODE would, every time)."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(REPO_ROOT / "cdt_plugin")],
                   env=dict(os.environ, PYTHONPYCACHEPREFIX=pycache), check=True,
                   stdin=subprocess.DEVNULL, capture_output=True)


def measure_first_use(quick: bool, timeout: float) -> list[dict]:
    """Each case a new process; the empty-cache cases each get a fresh NUMBA_CACHE_DIR,
    the filled-cache cases reuse the all-in-one case's directory."""
    pycache = tempfile.mkdtemp(prefix="pyc-small-")
    _compile_bytecode(pycache)
    empty = [[], ["delaunay"], ["triangulate"], ["min_angle"], ALL_STEPS]
    if quick:
        empty = [ALL_STEPS]
    filled = [[], ["triangulate"], ALL_STEPS]
    rows: list[dict] = []
    dirs: list[str] = []
    try:
        dirs.append(tempfile.mkdtemp(prefix="numba-small-"))
        rows.append({"cache": "empty", "steps": ALL_STEPS, "one_process": True,
                     **_run_child(ALL_STEPS, dirs[-1], timeout, pycache, one_process=True)})
        _log_first_use(rows[-1])
        for steps in empty:
            dirs.append(tempfile.mkdtemp(prefix="numba-small-"))
            rows.append({"cache": "empty", "steps": steps, **_run_child(steps, dirs[-1], timeout, pycache)})
            _log_first_use(rows[-1])
        filled_dir = dirs[-1]              # the all-in-one case's: every kernel compiled and cached
        if "error" not in rows[-1]:
            files, size = _dir_size(filled_dir)
            for steps in filled:
                rows.append({"cache": "filled", "steps": steps, "cache_files": files, "cache_bytes": size,
                             **_run_child(steps, filled_dir, timeout, pycache)})
                _log_first_use(rows[-1])
            rows.append({"cache": "filled", "steps": ["triangulate"], "without_scipy": True,
                         **_run_child(["triangulate"], filled_dir, timeout, pycache, without_scipy=True)})
            _log_first_use(rows[-1])
    finally:
        for d in dirs + [pycache]:
            shutil.rmtree(d, ignore_errors=True)
    return rows


def _case_label(steps: list[str], without_scipy: bool = False, one_process: bool = False) -> str:
    return ("import cdt_plugin" + "".join(f" + {FIRST_STEPS[s]}" for s in steps)
            + (", scipy absent (cdt_plugin's dependencies only)" if without_scipy else "")
            + (f", one process ({HELPER_ENV}=0)" if one_process else ""))


def _row_label(row: dict) -> str:
    return _case_label(row["steps"], row.get("without_scipy", False), row.get("one_process", False))


def _log_first_use(row: dict) -> None:
    what = f"  first use, {row['cache']} cache, {_row_label(row)}:"
    if "error" in row:
        _log(f"{what} n/a: {row['error']}")
    else:
        _log(f"{what} {row['calls_s']:.2f} s in the child, {row['wall_s']:.2f} s wall")

# ----------------------------------------------------------------------------- checks


def checks(results: dict, data: dict[str, dict]) -> list[str]:
    """Every triangulation of the polygon without Steiner points has n + 2h - 2 triangles."""
    warnings = []
    labels = {i.name: i.label for i in IMPLS}
    for name, row in results["workloads"].items():
        expected = data[name]["expected"]
        for impl, c in row.items():
            if impl != "ours_delaunay" and c.get("count") is not None and c["count"] != expected:
                warnings.append(f"{name}: {labels[impl]} gives {c['count']} triangles, "
                                f"expected n + 2h - 2 = {expected}")
    for row in results.get("first_use", []):
        if row.get("numba_preloaded"):
            warnings.append(f"first use ({_case_label(row['steps'])}): numba imported before the timed span")
    return warnings

# ----------------------------------------------------------------------------- report


def _us(seconds: float | None) -> str:
    if seconds is None:
        return "n/a"
    us = seconds * 1e6
    return f"{us:.0f}" if us >= 100 else f"{us:.1f}" if us >= 10 else f"{us:.2f}"


def _ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}x" if a and b else "n/a"


def _verdict(ok: bool | None) -> str:
    return "n/a" if ok is None else ("met" if ok else "not met")


def render(results: dict, info: dict, args_line: str) -> str:
    v = ", ".join(f"{k} {val}" for k, val in info["versions"].items() if val)
    impls = [i for i in IMPLS if any(i.name in row for row in results["workloads"].values())]
    med = {w: {i: c.get("median") for i, c in row.items()} for w, row in results["workloads"].items()}
    lines = [
        f"Machine: {info['cpu_count']} CPUs ({info['cpus_usable']} usable)"
        + (f", {info['cpu_model']}" if info["cpu_model"] else "")
        + f"; {v}; {info['date']}. Command: `{args_line}`"
        + (" (mode: quick)" if results["mode"] == "quick" else "") + ".",
        "",
        "Warm, one polygon per call: median microseconds per call.",
        "",
        "| polygon | vertices | triangles | " + " | ".join(i.label for i in impls) + " |",
        "|---|---:|---:|" + "---:|" * len(impls),
    ]
    notes: list[str] = []
    for shape in SHAPES:
        row = results["workloads"].get(shape.name)
        if row is None:
            continue
        tris = row.get("triangle", {}).get("count") or row.get("ours", {}).get("count")
        cells = []
        for i in impls:
            c = row.get(i.name, {})
            cells.append(_us(c.get("median")))
            if c.get("error"):
                notes.append(f"{shape.label} / {i.label}: {c['error']}")
        lines.append(f"| {shape.label} | {shape.n_vertices} | {tris if tris is not None else 'n/a'} | "
                     + " | ".join(cells) + " |")

    lines += ["", f"cdt_plugin.triangulate against the goal (at most {GOAL_TRIANGLE:.1f}x Triangle, the square "
              f"at most {GOAL_SQUARE_US:g} us) and the stretch (at most {STRETCH_EARCUT:.1f}x earcut, both "
              "columns):", "",
              "| polygon | cdt_plugin.triangulate us | / Triangle | goal | / earcut via trimesh | "
              "/ earcut (arrays) | stretch |",
              "|---|---:|---:|---|---:|---:|---|"]
    for shape, m in _measured(med):
        ours, tri = m.get("ours"), m.get("triangle")
        goal = None if not (ours and tri) else (
            ours <= GOAL_TRIANGLE * tri and (shape.name != "square" or ours * 1e6 <= GOAL_SQUARE_US))
        ecs = [m.get("trimesh_earcut"), m.get("earcut")]
        stretch = None if not (ours and any(ecs)) else all(ours <= STRETCH_EARCUT * e for e in ecs if e)
        lines.append(f"| {shape.label} | {_us(ours)} | {_ratio(ours, tri)} | {_verdict(goal)} | "
                     f"{_ratio(ours, ecs[0])} | {_ratio(ours, ecs[1])} | {_verdict(stretch)} |")

    lines += dropin_lines(med)

    first = results.get("first_use")
    if first:
        if results.get("first_use_from"):
            lines += ["", f"First use was not run again here (`--keep-first-use`): the rows of the run of "
                      f"{results['first_use_from']}, which measured it."]
        lines += ["", "First use, each case a new process (`NUMBA_CACHE_DIR` = a fresh temporary directory for "
                  "the empty-cache cases; the filled-cache cases reuse the all-in-one case's directory):", "",
                  "| numba cache | case | phases in the child (s) | import + calls s | child wall s | goal |",
                  "|---|---|---|---:|---:|---|"]
        for r in first:
            if "error" in r:
                lines.append(f"| {r['cache']} | {_row_label(r)} | n/a: {r['error']} | n/a | n/a | |")
                continue
            phases = ", ".join(f"{name} {s:.2f}" for name, s in r["phases"])
            goal = ""
            if r["cache"] == "empty" and r["steps"] == ALL_STEPS and not r.get("one_process"):
                goal = f"<= {GOAL_COLD_S:g} s: {_verdict(r['calls_s'] <= GOAL_COLD_S)}"
            elif r["cache"] == "filled" and r["steps"] == ["triangulate"]:
                goal = f"<= {GOAL_CACHED_S:g} s: {_verdict(r['calls_s'] <= GOAL_CACHED_S)}"
            lines.append(f"| {r['cache']} | {_row_label(r)} | "
                         f"{phases} | {r['calls_s']:.2f} | "
                         f"{r['wall_s']:.2f} | {goal} |")
        cached = next((r for r in first if r["cache"] == "filled" and "cache_files" in r), None)
        if cached:
            lines += ["", f"The filled cache: {cached['cache_files']} files, "
                      f"{cached['cache_bytes'] / 2**20:.1f} MiB."]

    spans = "; ".join(f"{i.label}: {i.timed}" for i in impls if i.timed)
    numbers = ", ".join(f"{s.name} {s.number}" for s in SHAPES if s.name in results["workloads"])
    lines += ["", f"Warm: median of {results['repeat']} interleaved rounds, one worker process per polygon, "
              f"after a warm-up call; each round times back-to-back calls ({numbers}) and gives the mean per "
              f"call (garbage collector off during the round). Ratios are taken in the same run. "
              f"Timed spans: {spans}. Triangles: Triangle's count (every peer but cdt_plugin.delaunay, which "
              "triangulates the convex hull of the vertices, must give n + 2h - 2)."]
    if first:
        lines[-1] += (" First use: phases timed with `time.perf_counter` in the child (prelude = the "
                      "benchmark module, numpy, shapely and the inputs, before `import cdt_plugin`; not in "
                      "\"import + calls\", which the goals are judged on); child wall = the parent's clock "
                      "around the whole child (interpreter start and exit included); the package's Python "
                      "bytecode is compiled beforehand, as pip does at install time. scipy absent: the "
                      "child makes `import scipy` fail before importing cdt_plugin, as in an environment "
                      "with cdt_plugin's dependencies only (numba imports scipy, when installed, to probe "
                      "for BLAS; scipy is here for the peers of other benchmarks). An empty-cache child "
                      "that compiles a route for a public call starts a second process, which compiles "
                      "the constrained Delaunay route's largest stages into the cache meanwhile (two "
                      "cores here); "
                      f"one process: {HELPER_ENV}=0, no second process.")
    if notes:
        lines += [""] + [f"- n/a: {n}" for n in notes]
    if results.get("warnings"):
        lines += [""] + [f"- WARNING: {w}" for w in results["warnings"]]
    return "\n".join(lines) + "\n"

def _measured(med: dict[str, dict[str, float | None]]) -> list[tuple[Shape, dict[str, float | None]]]:
    """The polygons of this run, in table order, with their medians by implementation."""
    return [(shape, med[shape.name]) for shape in SHAPES if shape.name in med]


def dropin_lines(med: dict[str, dict[str, float | None]]) -> list[str]:
    """The drop-ins against what they replace (issue #47): the shapely drop-in
    against cdt_plugin.triangulate, GEOS and Triangle, the trimesh drop-in
    against cdt_plugin.triangulate and Triangle, each row judged on its goal."""
    lines = ["", f"The drop-ins against what they replace: the shapely drop-in at most "
             f"{GOAL_DROPIN_OURS:.1f}x cdt_plugin.triangulate at every size and at most {GOAL_DROPIN_GEOS:.1f}x "
             f"GEOS from {GEOS_FROM} vertices up (below, GEOS's few microseconds are out of reach of a "
             "compiled call from Python: the ratio is reported, not judged); the trimesh drop-in at most "
             f"{GOAL_TRIMESH_OURS:.1f}x cdt_plugin.triangulate:", "",
             "| polygon | shapely drop-in us | / cdt_plugin.triangulate | / GEOS | / Triangle | goal | "
             "trimesh drop-in us | / cdt_plugin.triangulate | / Triangle | goal |",
             "|---|---:|---:|---:|---:|---|---:|---:|---:|---|"]
    for shape, m in _measured(med):
        ours, shp, trm = m.get("ours"), m.get("ours_shapely"), m.get("ours_trimesh")
        geos, tri = m.get("geos"), m.get("triangle")
        shp_goal = None if not (shp and ours) else shp <= GOAL_DROPIN_OURS * ours
        if shp_goal is not None and shape.n_vertices >= GEOS_FROM:
            shp_goal = None if not geos else shp_goal and shp <= GOAL_DROPIN_GEOS * geos
        trm_goal = None if not (trm and ours) else trm <= GOAL_TRIMESH_OURS * ours
        lines.append(f"| {shape.label} | {_us(shp)} | {_ratio(shp, ours)} | {_ratio(shp, geos)} | "
                     f"{_ratio(shp, tri)} | {_verdict(shp_goal)} | {_us(trm)} | {_ratio(trm, ours)} | "
                     f"{_ratio(trm, tri)} | {_verdict(trm_goal)} |")
    return lines

# ----------------------------------------------------------------------------- driver


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _parse(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=SUITE.title)
    p.add_argument("--quick", action="store_true",
                   help=f"smoke test: {QUICK_REPEAT} rounds; first use only all-in-one + cached")
    p.add_argument("--repeat", type=int, default=None,
                   help=f"interleaved rounds per polygon (default {DEFAULT_REPEAT})")
    p.add_argument("--only", default=None,
                   help="comma-separated implementations: " + ",".join(i.name for i in IMPLS))
    p.add_argument("--workloads", default=None,
                   help="comma-separated polygons: " + ",".join(w.name for w in WORKLOADS))
    p.add_argument("--timeout", type=float, default=120.0, help="seconds allowed per timed round (default 120)")
    p.add_argument("--setup-timeout", type=float, default=600.0,
                   help="seconds allowed for import + warm-up, and for each first-use process (default 600)")
    p.add_argument("--no-cold", action="store_true", help="skip the first-use processes")
    p.add_argument("--keep-first-use", action="store_true",
                   help="skip the first-use processes and keep the first-use rows of the results file "
                   "written before (its .json), saying so: the warm tables are new, the file complete")
    p.add_argument("--out", default=None,
                   help="markdown output (a .json with raw numbers is written beside it); "
                   "default benchmarks/results/small.md (small-quick.md with --quick)")
    p.add_argument("--write-readme", action="store_true",
                   help="regenerate the README's benchmark summary rows from the stored results")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == [WORKER_FLAG]:                 # a timing worker (harness.py)
        return harness_main(SUITE, argv)
    if argv[:1] == [FIRST_USE_FLAG]:              # a first-use child
        _first_use_child(json.loads(argv[1]), json.loads(argv[2]))
        return 0
    args = _parse(argv)
    t_start = time.perf_counter()
    repeat = args.repeat if args.repeat is not None else (QUICK_REPEAT if args.quick else DEFAULT_REPEAT)
    impls = select_by_name(args.only, IMPLS, "implementation(s)")
    workloads = select_by_name(args.workloads, WORKLOADS, "polygon(s)")
    info = machine_info(SUITE)
    _log(f"{SUITE.title}: {len(workloads)} polygon(s) x {len(impls)} implementation(s), {repeat} round(s); "
         f"{info['cpu_count']} CPUs; python {info['versions']['python']}")
    results: dict[str, Any] = {"suite": SUITE.name, "mode": "quick" if args.quick else "full",
                               "repeat": repeat, "machine": info, "argv": argv, "workloads": {}}

    for wl in workloads:
        _log(f"{wl.label}:")
        cells = measure_times(SUITE, wl, impls, {i.name: repeat for i in impls},
                              args.timeout, args.setup_timeout)
        results["workloads"][wl.name] = {
            name: {"median": c.median, "times": c.times, "count": c.count, "error": c.error,
                   "number": wl.number} for name, c in cells.items()}
    if args.keep_first_use:
        earlier = json.loads(results_path(SUITE, args).with_suffix(".json").read_text())
        results["first_use"] = earlier["first_use"]
        results["first_use_from"] = earlier.get("first_use_from") or earlier["machine"]["date"]
    elif not args.no_cold:
        _log("first use (new processes):")
        results["first_use"] = measure_first_use(args.quick, args.setup_timeout)

    data = {s.name: polygon_input(make_polygon(s)) for s in SHAPES}
    try:
        results["warnings"] = checks(results, data)
    except Exception as exc:
        results["warnings"] = [f"the checks failed: {short_reason(exc)}"]
    for w in results["warnings"]:
        _log(f"WARNING: {w}")

    args_line = command_line(SUITE, argv)
    md = render(results, info, args_line)
    results["elapsed_s"] = time.perf_counter() - t_start

    return write_results(SUITE, results, md, args)


if __name__ == "__main__":
    sys.exit(main())
