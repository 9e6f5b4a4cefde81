"""The README tells the truth: every ```python block runs as written, on its own, and
every command line of its ```bash blocks (``cdt-plugin ...`` / ``python -m cdt_plugin ...``)
exits 0 with the outputs it claims; a ```text block printed by the python block before it
(the quality report) is what that block prints today, so it cannot go stale.

Each python block runs in a fresh namespace, in-process (one import of the package for all
blocks), from a temporary working directory laid out like the repository's: the corpus is
``../shared/corpus`` from it, as from the repository root. A block needing an optional
library is skipped only when that library is missing (the ``test`` extra installs them all).
"""
from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import logging
import re
import shlex
from pathlib import Path

import pytest
from checker import assert_valid
from corpus import corpus_dir

from cdt_plugin import cli
from cdt_plugin import io as tio

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
CORPUS = corpus_dir()
needs_corpus = pytest.mark.skipif(not CORPUS.exists(), reason="corpus not found")

#: Optional modules a block needs when it contains the key (besides its own imports).
NEEDS = {"cdt_plugin.plot": "matplotlib", "tri.plot(": "matplotlib", "report import earcut": "mapbox_earcut",
         "adapters import geo": "geopandas", "cdt_trimesh": "trimesh", "cdt_o3d": "open3d",
         "to_parquet": "pyarrow", "--plot": "matplotlib", "--against earcut": "mapbox_earcut",
         ".gpkg": "geopandas", ".geojson": "geopandas", "--against": "trimesh", ".obj": "trimesh",
         ".glb": "trimesh"}


def readme_blocks(text: str | None = None) -> list[tuple[str, str, str]]:
    """``(id, language, code)`` of every fenced block; id = the heading it is under and
    its number among that heading's blocks of the same language."""
    lines = (README.read_text(encoding="utf-8") if text is None else text).splitlines()
    blocks, heading, counts, i = [], "top", {}, 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("#"):
            heading = re.sub(r"[^a-z0-9]+", "-", line.lstrip("#").strip().lower()).strip("-")
        fence = re.match(r"^\s*```(\w+)\s*$", line)
        if fence:
            body, i = [], i + 1
            while not re.match(r"^\s*```\s*$", lines[i]):
                body.append(lines[i])
                i += 1
            indent = min((len(b) - len(b.lstrip()) for b in body if b.strip()), default=0)
            lang = fence.group(1)
            counts[heading, lang] = counts.get((heading, lang), 0) + 1
            blocks.append((f"{heading}-{counts[heading, lang]}", lang,
                           "\n".join(b[indent:] for b in body)))
        i += 1
    return blocks


def cli_lines(blocks) -> list[tuple[str, list[str]]]:
    """``(id, argv)`` of every command line of the bash/console blocks (pip lines excluded)."""
    out = []
    for block_id, lang, code in blocks:
        if lang not in ("bash", "console", "sh"):
            continue
        for n, line in enumerate(code.splitlines(), 1):
            argv = shlex.split(line.lstrip("$ "), comments=True)
            if argv[:1] == ["cdt-plugin"]:
                out.append((f"{block_id}-line{n}", argv[1:]))
            elif argv[:3] == ["python", "-m", "cdt_plugin"]:
                out.append((f"{block_id}-line{n}", argv[3:]))
    return out


def python_blocks(blocks) -> list[tuple[str, str, str | None]]:
    """``(id, code, table)`` of every python block; ``table`` is the ```text block right
    after it (what it prints, e.g. the quality report), else None."""
    return [(block_id, code, blocks[k + 1][2] if k + 1 < len(blocks) and blocks[k + 1][1] == "text"
             else None) for k, (block_id, lang, code) in enumerate(blocks) if lang == "python"]


BLOCKS = readme_blocks()
PYTHON = python_blocks(BLOCKS)
CLI = cli_lines(BLOCKS)


def _skip_missing(code: str) -> None:
    """Skip when a module the code needs is not installed (and only then)."""
    modules = set(re.findall(r"^\s*(?:import|from)\s+([A-Za-z_]\w*)", code, flags=re.MULTILINE))
    modules |= {m for key, m in NEEDS.items() if key in code}
    for module in sorted(modules - {"cdt_plugin"}):
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"needs {module}")


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """A working directory from which the corpus is ``../shared/corpus``."""
    top = tmp_path_factory.mktemp("readme")
    (top / "shared").mkdir()
    (top / "shared" / "corpus").symlink_to(CORPUS, target_is_directory=True)
    (top / "repo").mkdir()
    return top / "repo"


@pytest.fixture(autouse=True)
def _agg_backend():
    if importlib.util.find_spec("matplotlib") is not None:
        import matplotlib
        matplotlib.use("Agg")
    yield
    if importlib.util.find_spec("matplotlib") is not None:
        import matplotlib.pyplot as plt
        plt.close("all")


def run_block(code: str, cwd: Path, monkeypatch) -> str:
    """Run ``code`` in a fresh namespace from ``cwd``; returns what it printed."""
    monkeypatch.chdir(cwd)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "<README block>", "exec"), {"__name__": "__readme__"})
    return out.getvalue()


# ------------------------------------------------------------------------ python blocks
@needs_corpus
@pytest.mark.filterwarnings("ignore::UserWarning")       # geopandas: area in a geographic CRS
@pytest.mark.parametrize("code,table", [(c, t) for _, c, t in PYTHON], ids=[i for i, _, _ in PYTHON])
def test_python_block_runs(code, table, workspace, monkeypatch):
    """The block runs; what it prints contains the ```text block shown after it."""
    _skip_missing(code)
    printed = run_block(code, workspace, monkeypatch)
    if table is not None:
        assert table_matches(table, printed), f"README shows:\n{table}\nthe code prints:\n{printed}"


def _same_line(expected: str, printed: str) -> bool:
    """Equal up to spacing; a timing row is compared by its label only."""
    if expected.startswith("time (s)"):
        return printed.startswith("time (s)")
    return expected.split() == printed.split()


def table_matches(expected: str, printed: str) -> bool:
    """Whether ``printed`` contains ``expected`` line for line; an expected line
    starting with ``...`` stands for any run of printed lines."""
    want = [line for line in expected.splitlines() if line.strip()]
    got = [line.strip() for line in printed.splitlines()]
    starts = [i for i, line in enumerate(got) if _same_line(want[0].strip(), line)]
    for start in starts:
        i, ok = start, True
        for k, line in enumerate(want):
            line = line.strip()
            if line.startswith("..."):
                nxt = want[k + 1].strip() if k + 1 < len(want) else None
                while i < len(got) and nxt is not None and not _same_line(nxt, got[i]):
                    i += 1
                continue
            if i >= len(got) or not _same_line(line, got[i]):
                ok = False
                break
            i += 1
        if ok:
            return True
    return False


def test_table_matcher():
    printed = "head\nquality report   a\nx 1\ny 2\nz 3\ntime (s)  0.5\nend 4\n"
    assert table_matches("quality report a\nx   1\n  ...  left out\nz 3\ntime (s)  9.9\nend 4",
                         printed)
    assert not table_matches("quality report a\nx 2", printed)
    assert not table_matches("quality report a\nx 1\nz 3", printed)


def test_readme_has_blocks():
    assert len(PYTHON) >= 8 and len(CLI) >= 8
    assert any(t is not None and t.startswith("quality report") for _, _, t in PYTHON)


# ------------------------------------------------------------------------ command lines
def _option(argv: list[str], *names: str) -> str | None:
    for name in names:
        if name in argv:
            return argv[argv.index(name) + 1]
    return None


def check_outputs(argv: list[str], stdout: str, cwd: Path) -> None:
    """The outputs a command line claims: its -o file(s) (a valid mesh for Triangle's
    formats), its --plot image, its printed report or JSON."""
    output = _option(argv, "-o", "--output")
    if output is not None:
        path = cwd / output
        if path.suffix in (".node", ".ele", ".poly"):
            base = path.with_suffix("")
            V = tio.read_node(base.with_suffix(".node")).vertices
            T = tio.read_ele(base.with_suffix(".ele")).triangles
            S = tio.read_poly(base.with_suffix(".poly")).segments
            assert len(T)
            assert_valid(V, T, segments=S, domain="segments")
        else:
            assert path.stat().st_size > 0, path
        assert f"wrote {output}" in stdout or f"wrote {Path(output).with_suffix('')}" in stdout
    plot = _option(argv, "--plot")
    if plot is not None:
        assert (cwd / plot).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    if "--json" in argv:
        assert json.loads(stdout)["triangles"] > 0
    elif "--report" in argv or argv[0] == "report":
        assert "quality report" in stdout and "non-Delaunay non-segment edges" in stdout


@pytest.fixture(scope="module")
def cli_state():
    return {"done": set()}


@needs_corpus
@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("k", range(len(CLI)), ids=[i for i, _ in CLI])
def test_cli_line_runs(k, workspace, cli_state, monkeypatch, capsys):
    """Each line from the same working directory, in the README's order (a line may
    use an earlier one's output: the earlier lines are run first when selected alone)."""
    monkeypatch.chdir(workspace)
    level = logging.getLogger("cdt_plugin").level
    try:
        for j in range(k + 1):
            if j in cli_state["done"]:
                continue
            argv = CLI[j][1]
            _skip_missing(" ".join(argv))
            capsys.readouterr()
            status = cli.main(argv)
            out, err = capsys.readouterr()
            assert status == 0, f"cdt-plugin {' '.join(argv)}: exit {status}\n{err}"
            assert "Traceback" not in err
            check_outputs(argv, out, workspace)
            cli_state["done"].add(j)
    finally:
        logging.getLogger("cdt_plugin").setLevel(level)


def test_cli_lines_name_corpus_files():
    """Every input a README command line names exists (in the corpus or made by an
    earlier line): the lines run as written, nothing to invent first."""
    made: set[str] = set()
    for _, argv in CLI:
        if argv[0] in ("mesh", "report"):
            assert argv[1].startswith("../shared/corpus/") or argv[1] in made, argv
            assert (CORPUS / argv[1].removeprefix("../shared/corpus/")).exists() or argv[1] in made
        against = _option(argv, "--against")
        assert against in (None, "earcut") or against in made, argv
        output = _option(argv, "-o", "--output")
        if output:
            made |= {output} | {str(Path(output).with_suffix(s)) for s in (".node", ".ele", ".poly")}
