"""The documentation site builds with warnings as errors (broken links and cross-references,
pages missing from the nav, griffe's docstring checks), as CI builds it. Runs wherever
mkdocs is installed (the ``docs`` extra); CI also builds it in a fresh environment with
that extra alone (``.ci/extras_smoke.py docs``)."""
from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(importlib.util.find_spec("mkdocs") is None, reason="needs the docs extra (mkdocs)")
def test_docs_build_strict(tmp_path):
    before = set(ROOT.iterdir())
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path)],
                         cwd=ROOT, capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stderr[-4000:]
    assert (tmp_path / "getting-started" / "index.html").exists()
    page = (tmp_path / "benchmarks" / "delaunay" / "index.html").read_text(encoding="utf-8")
    assert "D1 uniform 1e6" in page                   # the table the benchmark script wrote
    assert set(ROOT.iterdir()) == before
