"""First use with an empty numba cache: while the constrained Delaunay route
compiles, a second process compiles its largest stages into the cache, and the
route loads those from there, waits for the one it is compiling, and compiles the
rest itself (cdt_plugin.compiling)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import cdt_plugin
from cdt_plugin import compiling
from checker import check_triangulation

STAR = np.array([[np.cos(2 * np.pi * k / 12) * (1 if k % 2 else 0.5),
                  np.sin(2 * np.pi * k / 12) * (1 if k % 2 else 0.5)] for k in range(12)])
RING = np.column_stack([np.arange(12), (np.arange(12) + 1) % 12])

CHILD = """
import json, logging, sys
import numpy as np
logging.basicConfig(level=logging.INFO, stream=sys.stderr)
import cdt_plugin
from cdt_plugin import compiling
V, S = np.array(json.loads(sys.argv[1])), np.array(json.loads(sys.argv[2]))
tri = cdt_plugin.triangulate(V, S, min_angle=30)
stages = {n: compiling._stage(n) for n in compiling.HELPER_STAGES}
print(json.dumps({"state": compiling.helper.state,
                  "hits": {n: sum(k.stats.cache_hits.values()) for n, k in stages.items()},
                  "misses": {n: sum(k.stats.cache_misses.values()) for n, k in stages.items()},
                  "vertices": tri.vertices.tolist(), "triangles": tri.triangles.tolist()}))
"""


@pytest.mark.skipif(compiling._usable_cpus() < 2, reason="the helper needs a second core")
def test_cold_route_loads_the_stages_a_second_process_compiled(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env.pop(compiling.HELPER_ENV, None)
    proc = subprocess.run([sys.executable, "-c", CHILD, json.dumps(STAR.tolist()), json.dumps(RING.tolist())],
                          env=env, capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert "a second process compiles" in proc.stderr, proc.stderr
    state, hits, misses = out["state"], out["hits"], out["misses"]
    assert "done" in state.values(), proc.stderr
    for name, said in state.items():   # compiled by the helper: loaded here (polygon_rings: not called)
        assert said != "done" or misses[name] == 0, (name, proc.stderr)
    route = [n for n in compiling.HELPER_STAGES if not n.endswith("polygon_rings")]
    assert all(hits[n] + misses[n] == 1 for n in route), out      # each route stage once
    tri = cdt_plugin.triangulate(STAR, RING, min_angle=30)
    assert np.array_equal(out["vertices"], tri.vertices) and np.array_equal(out["triangles"], tri.triangles)
    rep = check_triangulation(tri.vertices, tri.triangles, segments=tri.segments, domain="segments",
                              require_all_vertices=False)
    assert rep.ok, str(rep)


def test_helper_is_off_by_environment_or_on_one_core(monkeypatch):
    monkeypatch.delenv(compiling.HELPER_ENV, raising=False)
    monkeypatch.setattr(compiling, "_usable_cpus", lambda: 2)
    assert compiling._Helper().allowed()
    monkeypatch.setenv(compiling.HELPER_ENV, "0")
    assert not compiling._Helper().allowed()
    monkeypatch.delenv(compiling.HELPER_ENV)
    monkeypatch.setattr(compiling, "_usable_cpus", lambda: 1)
    helper = compiling._Helper()
    assert not helper.allowed()
    helper.start()
    assert helper.proc is None and not helper.state


def test_stages_compiled_ahead_name_the_argument_types_their_route_gives_them():
    """The helper compiles each stage for its declared ``ahead`` types: they must be
    those the route calls it with (a polygon in, refinement on), else the route
    compiles its own and the helper's work is lost. A stage compiled apart declares
    the type it returns for them (``returns``), which a route linking it late is
    typed against: it must be the one numba infers."""
    from shapely.geometry import Polygon

    from cdt_plugin._core import jit
    cdt_plugin.triangulate(Polygon(STAR), min_angle=30)
    for name in compiling.HELPER_STAGES:
        stage = compiling._stage(name)
        assert isinstance(stage, jit.Kernel) and stage.ahead in stage.overloads, name
        if stage.apart and not isinstance(stage, jit.DeclaredKernel):
            assert stage.returns == stage.overloads[stage.ahead].signature.return_type, name


def test_route_links_late_only_the_stage_the_helper_is_compiling(monkeypatch):
    """A route that reaches a stage the helper is compiling links it late (does not
    wait for it); one the helper has not begun, or with other argument types, or in
    another process (a fork), it does not."""
    from cdt_plugin._core import refine
    helper = compiling._Helper()
    stage, name = refine.refine_store, "cdt_plugin._core.refine.refine_store"
    helper.pid = os.getpid()
    helper.state = {name: "start"}
    assert helper.compiling(stage, stage.ahead)
    assert not helper.compiling(stage, stage.ahead[:-1])
    for said in ("pending", "done", "mine"):
        helper.state[name] = said
        assert not helper.compiling(stage, stage.ahead)
    helper.state[name], helper.pid = "start", -1
    assert not helper.compiling(stage, stage.ahead)
