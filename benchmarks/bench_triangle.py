"""The ``triangle`` drop-in: ``cdt_plugin.triangle.triangulate`` against the ``triangle``
package's ``triangulate``, the same dictionaries and switch strings in, dictionaries out.

Workloads, each with the switches ``p``, ``pq30`` and ``pq30a<area>``:

* ``data-*`` — Triangle's sample PSLGs (every ``.poly`` of ``../shared/corpus/triangle/``
  that has triangles, read with ``cdt_plugin.triangle.load``), one call each, summed;
  ``<area>`` = the sample's domain area / 2000;
* ``pslg-*`` — a 100,000-vertex PSLG: C1 of ``bench_cdt.py`` with 87,200 outer vertices
  and 200 holes of 64 vertices; ``<area>`` = its domain area / 200,000;
* ``mesh-ra`` — ``r`` with a bare ``a``: Triangle's ``p`` mesh of that PSLG (100,398
  triangles) refined with one bound per triangle (its area times a seeded uniform factor
  in [0.3, 1]: an adaptive step that refines everywhere, some triangles three times);
* ``square-p`` — one unit square per call (the per-call overhead of the dictionaries).

Both peers run in one worker process per workload, interleaved round-robin
(``harness.py``); the table gives the median time and the ratio to Triangle in the same
run (the machine is shared and noisy: only same-run ratios compare). The goals (issue
44): at most 1.2x Triangle on every row, 1.0x for ``mesh-ra``. Areas are written without an exponent
(Triangle does not read one; ``cdt_plugin.switches`` refuses it).

``BENCH_TRIANGLE_SUFFIX`` (environment) is appended to every switch string on both sides:
``B`` (no boundary markers) measures the meshing alone.

Usage (from the repository root)::

    python benchmarks/bench_triangle.py               # 3 rounds, a few minutes
    python benchmarks/bench_triangle.py --workloads square-p,data-p --no-memory

Options are ``harness.py``'s (``--repeat``, ``--only``, ``--workloads``, ``--no-memory``,
``--no-cold``, ``--out``...); the table is ``benchmarks/results/triangle.md``.

This module must not import numba or cdt_plugin at import time (harness.py's cold start).
"""
from __future__ import annotations

import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import Impl, Suite, Workload, main  # noqa: E402

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "corpus",
                      "triangle")
SUFFIX = os.environ.get("BENCH_TRIANGLE_SUFFIX", "")
SWITCHES = ("p", "pq30", "pq30a")


def _switches(base: str, area: float) -> str:
    return base + (np.format_float_positional(area, trim="-") if base.endswith("a") else "") + SUFFIX


def _areas(V: np.ndarray, T: np.ndarray) -> np.ndarray:
    (ax, ay), (bx, by), (cx, cy) = (V[T[:, i]].T for i in range(3))
    return np.abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) / 2


def _domain_area(data: dict) -> float:
    """The area inside the segments (rings oriented, holes clockwise) or of the mesh."""
    import triangle
    mesh = triangle.triangulate(data, "pQ")
    if "triangles" not in mesh:            # (box.poly: its hole takes everything)
        return 0.0
    return float(_areas(mesh["vertices"], mesh["triangles"]).sum())


def samples(base: str):
    """Triangle's sample PSLGs that have triangles, with their switch strings."""
    def make() -> list[tuple[dict, str]]:
        from cdt_plugin import triangle as tr
        out = []
        for path in sorted(glob.glob(os.path.join(CORPUS, "*.poly"))):
            data = tr.load(CORPUS, os.path.basename(path)[:-5])
            area = _domain_area(data) if "segments" in data else 0.0
            if area > 0:
                out.append((data, _switches(base, area / 2000)))
        return out
    return make


def pslg(base: str):
    def make() -> list[tuple[dict, str]]:
        from bench_cdt import star_with_holes
        star = star_with_holes(87_200)
        data = {"vertices": star["V"], "segments": star["S"], "holes": star["H"]}
        return [(data, _switches(base, _domain_area(data) / 200_000))]
    return make


def refinement() -> list[tuple[dict, str]]:
    import triangle
    from bench_cdt import star_with_holes
    star = star_with_holes(87_200)
    mesh = triangle.triangulate({"vertices": star["V"], "segments": star["S"], "holes": star["H"]},
                                "pQ")
    V, T = mesh["vertices"], mesh["triangles"]
    area = _areas(V, T)
    factor = np.random.default_rng(44).uniform(0.3, 1.0, len(T))
    data = {"vertices": V, "triangles": T, "triangle_max_area": (area * factor)[:, None]}
    return [(data, "ra" + SUFFIX)]


def square() -> list[tuple[dict, str]]:
    return [({"vertices": np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float),
              "segments": np.array([[0, 1], [1, 2], [2, 3], [3, 0]], np.int32)}, "p" + SUFFIX)]


WORKLOADS = [
    *[Workload(f"data-{s}", f"Triangle's sample PSLGs, `{s}`", samples(s), size=1000)
      for s in SWITCHES],
    *[Workload(f"pslg-{s}", f"PSLG 100,000 v (C1 87,200 + 200x64 holes), `{s}`", pslg(s),
               size=100_000) for s in SWITCHES],
    Workload("mesh-ra", "mesh of 100,398 triangles, `ra` (one bound per triangle)", refinement,
             size=100_000),
    Workload("square-p", "unit square, `p`, one per call", square, size=4, number=400, memory=False),
]


def setup_with(module: str):
    def setup():
        import importlib
        triangulate = importlib.import_module(module).triangulate

        def run(items):
            return [triangulate(data, switches) for data, switches in items]
        return run
    return setup


def count(results) -> int:
    return sum(len(r.get("triangles", ())) for r in results)


IMPLS = [
    Impl("triangle", "Triangle (triangle.triangulate)", setup_with("triangle"), count,
         timed="triangulate(dict, switches), dict of arrays out", dist="triangle"),
    Impl("ours", "cdt_plugin.triangle.triangulate", setup_with("cdt_plugin.triangle"), count,
         timed="the same call through the drop-in, dict of arrays out", dist="cdt-plugin",
         numba_cold_start=True, package="cdt_plugin"),
]

SUITE = Suite(
    name="triangle",
    title="The triangle drop-in against the triangle package",
    workloads=WORKLOADS,
    impls=IMPLS,
    reference="triangle",
    script=os.path.abspath(__file__),
    cold_workload="square-p",
    quick_max_size=1000,
    notes=[f"Switch suffix on both sides: `{SUFFIX}`." if SUFFIX else
           "Switches as shown (Triangle's defaults: markers in the output)."],
)

if __name__ == "__main__":
    sys.exit(main(SUITE))
