"""The fuzz driver (tests/support/fuzz.py) in CI: a quick run over every
family; long runs from the command line (``python tests/support/fuzz.py
--count 10000``). A failure names its reproducer."""
from __future__ import annotations

import io

import pytest

import fuzz


@pytest.mark.parametrize("family", fuzz.FAMILIES)
def test_fuzz_quick(family):
    out = io.StringIO()
    failures = fuzz.run(150, (family,), seed=2026, stop=False, out=out)
    assert not failures, out.getvalue()


def test_fuzz_command_line_reports_its_cases(capsys):
    assert fuzz.main(["--count", "8"]) == 0
    assert "8 cases (delaunay, cdt, split, refine, near, voronoi, query, dynamic), seed 0: 0 failed" in capsys.readouterr().out
    assert fuzz.main(["--family", "split", "--case", "3"]) == 0
