"""The README's benchmark summary: five rows against Triangle, earcut and GEOS.

The rows are made from the stored results of the benchmark scripts
(``benchmarks/results/*.json`` and ``*.md``), never typed: ``python benchmarks/summary.py``
writes them between ``<!-- bench:summary:start -->`` and ``<!-- bench:summary:end -->`` in
README.md, and every script's ``--write-readme`` does the same after its run. The full
tables are the files in ``benchmarks/results/``, which the documentation's benchmark pages
include as they are.

Every figure is one thread against one thread (the peers run on one): the median time of
one call, in seconds or microseconds.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
README = HERE.parent / "README.md"
START, END = "<!-- bench:summary:start -->", "<!-- bench:summary:end -->"
#: the documentation page of each suite (it includes the full table), linked from its row
PAGE = "docs/benchmarks/{}.md"
COLUMNS = ("cdt_plugin", "Triangle", "earcut", "GEOS")


def json_medians(suite: str, workload: str, impls: dict[str, str]) -> dict[str, float]:
    """``{column: median seconds}`` of ``impls`` (column -> implementation name) in one
    workload of ``results/<suite>.json``; a missing or failed implementation is left out."""
    cells = json.loads((RESULTS / f"{suite}.json").read_text())["workloads"][workload]
    return {column: cells[name]["median"] for column, name in impls.items()
            if name in cells and cells[name].get("median") is not None}


def markdown_rows(suite: str) -> list[dict[str, str]]:
    """The rows of the first table of ``results/<suite>.md``, keyed by its header."""
    lines = (RESULTS / f"{suite}.md").read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("|"))
    header = [cell.strip() for cell in lines[first].strip("|").split("|")]
    rows = []
    for line in lines[first + 2:]:
        if not line.startswith("|"):
            break
        rows.append(dict(zip(header, (cell.strip() for cell in line.strip("|").split("|")))))
    return rows


def markdown_cell(suite: str, match: dict[str, str], column: str) -> float:
    """The number in ``column`` of the one row of ``results/<suite>.md`` whose cells
    equal ``match``."""
    (row,) = [r for r in markdown_rows(suite) if all(r.get(k) == v for k, v in match.items())]
    return float(row[column].rstrip("x").replace(",", ""))


def gis_seconds() -> dict[str, float]:
    """The batch of polygons: our batch path, GEOS and trimesh's earcut loop, one thread."""
    rows = {r["implementation"]: float(r["seconds"]) for r in markdown_rows("gis")}
    return {"cdt_plugin": rows["cdt_plugin triangulate_batch (arrays), 1 thread"],
            "earcut": rows["trimesh earcut loop"],
            "GEOS": rows["shapely.constrained_delaunay_triangles (GEOS)"]}


def summary_rows() -> list[tuple[str, str, dict[str, float]]]:
    """``(job, suite, {column: seconds})`` of the five rows."""
    return [
        ("Delaunay triangulation, 10^6 random points", "delaunay",
         json_medians("delaunay", "d1-1e6", {"cdt_plugin": "ours", "Triangle": "triangle",
                                             "GEOS": "geos"})),
        ("Polygon with 200 holes, 112,800 vertices", "cdt",
         json_medians("cdt", "c1-1e5", {"cdt_plugin": "ours", "Triangle": "triangle",
                                        "earcut": "earcut", "GEOS": "geos"})),
        ("Quality mesh (`-q30`), 10k-vertex polygon with 200 holes", "refine",
         {"cdt_plugin": markdown_cell("refine", {"workload": "R2 star 10k + 200 holes",
                                                 "switches": "`pq30`"}, "ours s"),
          "Triangle": markdown_cell("refine", {"workload": "R2 star 10k + 200 holes",
                                               "switches": "`pq30`"}, "Triangle s")}),
        ("One small polygon per call (76 vertices, 2 holes)", "small",
         json_medians("small", "star60h2", {"cdt_plugin": "ours", "Triangle": "triangle",
                                            "earcut": "earcut", "GEOS": "geos"})),
        ("100,316 GIS polygons in one batch", "gis", gis_seconds()),
    ]


def duration(seconds: float) -> str:
    """Three significant digits, in s, ms or µs."""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale or unit == "µs":
            return f"{seconds / scale:.3g} {unit}"
    raise AssertionError("unreachable")


def summary_table() -> str:
    """The five rows as a Markdown table, with a link to each full table."""
    lines = ["| job (one thread) | " + " | ".join(COLUMNS) + " | full table |",
             "|---|" + "---:|" * len(COLUMNS) + "---|"]
    for job, suite, times in summary_rows():
        cells = [duration(times[c]) if c in times else "-" for c in COLUMNS]
        lines.append(f"| {job} | " + " | ".join(cells) + f" | [{suite}]({PAGE.format(suite)}) |")
    return "\n".join(lines) + "\n"


def with_summary(text: str) -> str:
    """``text`` (the README) with the summary rows between its markers."""
    pattern = re.compile(re.escape(START) + r".*?" + re.escape(END), re.DOTALL)
    if len(pattern.findall(text)) != 1:
        raise SystemExit(f"README.md must hold {START} ... {END} once")
    return pattern.sub(lambda _m: f"{START}\n{summary_table()}{END}", text)


def write_readme() -> None:
    """Rewrite the README's summary rows from the stored results."""
    README.write_text(with_summary(README.read_text(encoding="utf-8")), encoding="utf-8")


if __name__ == "__main__":
    write_readme()
    print(summary_table(), end="")
