"""First use with an empty numba cache: while the constrained Delaunay route
compiles, a second process compiles two of its stages into the cache, and the
route loads them from there (cdt_plugin.compiling)."""
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
from cdt_plugin._core import pipeline, refine
V, S = np.array(json.loads(sys.argv[1])), np.array(json.loads(sys.argv[2]))
tri = cdt_plugin.triangulate(V, S, min_angle=30)
print(json.dumps({"hits": [sum(k.stats.cache_hits.values()) for k in (pipeline.classify, refine.refine_loop)],
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
    assert out["hits"] == [1, 1], proc.stderr      # both loaded from the helper's compilations
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
    assert helper.proc is None and not helper.pending


def test_stages_compiled_ahead_name_their_route_argument_types():
    from cdt_plugin._core import jit
    for name in compiling.HELPER_STAGES:
        stage = compiling._stage(name)
        assert isinstance(stage, jit.Kernel) and len(stage.ahead) == stage.py_func.__code__.co_argcount
