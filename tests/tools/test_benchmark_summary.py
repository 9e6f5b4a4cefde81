"""The README's benchmark summary is what ``benchmarks/summary.py`` makes from the stored
results, row for row: never typed by hand, never stale after a benchmark run."""
from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))

import summary


def test_readme_summary_is_generated():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert summary.with_summary(readme) == readme


def test_summary_has_five_rows_against_the_peers():
    rows = [line for line in summary.summary_table().splitlines()[2:] if line.startswith("|")]
    assert len(rows) == 5
    header = summary.summary_table().splitlines()[0]
    assert all(peer in header for peer in ("Triangle", "earcut", "GEOS"))
    for line in rows:                           # every row has our time and a peer's
        cells = [c.strip() for c in line.strip("|").split("|")]
        assert re.fullmatch(r"[\d.]+ (s|ms|µs)", cells[1]), line
        assert any(re.fullmatch(r"[\d.]+ (s|ms|µs)", c) for c in cells[2:5]), line
        link = re.search(r"\]\((docs/benchmarks/\w+\.md)\)", cells[5]).group(1)
        assert (ROOT / link).is_file(), link


def test_summary_rows_come_from_the_results():
    (_, suite, times), *_ = summary.summary_rows()
    assert suite == "delaunay"
    assert times["Triangle"] == summary.json_medians("delaunay", "d1-1e6", {"Triangle": "triangle"})["Triangle"]
    assert summary.duration(0.0000607) == "60.7 µs" and summary.duration(1.08) == "1.08 s"
