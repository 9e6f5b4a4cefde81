"""The README and the documentation tell the truth: every code block runs, and shows what
it prints.

Each page (README.md, every ``docs/**/*.md``) is one test. Its blocks run in order, as a
reader runs them, in one namespace, from a fresh temporary directory laid out like the
repository's (the corpus is ``../shared/corpus`` from it), so nothing they write is left
behind; the test also checks that the repository root gains no file.

* A ```python block runs as written. A ```text block right after it (blank lines between
  allowed) is what it prints, compared in full, line by line, runs of spaces counting as
  one and blank lines left out. The one wildcard is ``...``: a line that is only ``...``
  stands for any run of lines (a table's rows left out), and ``...`` inside a line for any
  text (timings and addresses only).
* A ```bash block holds command lines of the CLI (``cdt-plugin ...`` or ``python -m
  cdt_plugin ...``, comments allowed), each run in-process; it must exit 0 and write the
  outputs it names (a valid mesh for Triangle's formats, a PNG for ``--plot``, a report or
  JSON when asked).
* ``<!-- docs-test: skip (reason) -->`` before a block leaves it out (installs, long runs):
  the reason is required.
* A block that needs an optional library (its imports, or the keys of ``NEEDS``) that
  cannot be imported stops its page there (skipped, the blocks before it checked); the
  ``test`` extra installs them all. Pages put such blocks (Open3D) last.
"""
from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import logging
import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest
from checker import assert_valid
from corpus import corpus_dir

from cdt_plugin import cli
from cdt_plugin import io as tio

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
CORPUS = corpus_dir()
FENCE = re.compile(r"^\s*```(\w*)\s*$")
SKIP = re.compile(r"<!--\s*docs-test:\s*skip\s*\((.+)\)\s*-->")

#: Optional modules a page needs when it contains the key (besides its own imports).
NEEDS = {"cdt_plugin.plot": "matplotlib", "tri.plot(": "matplotlib", "report import earcut": "mapbox_earcut",
         "adapters import geo": "geopandas", "cdt_trimesh": "trimesh", "to_open3d": "open3d",
         "to_parquet": "pyarrow", "--plot": "matplotlib", "--against earcut": "mapbox_earcut",
         ".gpkg": "geopandas", ".geojson": "geopandas", "--against": "trimesh", ".obj": "trimesh",
         ".glb": "trimesh", "dask_geopandas": "distributed", "to_meshio": "meshio",
         "to_skfem": "skfem", ".msh": "meshio", ".vtu": "meshio", ".xdmf": "h5py"}


@dataclass
class Block:
    where: str               # page:line of the opening fence
    lang: str
    code: str
    skip: str | None = None  # the reason, for a block marked to be skipped
    output: str | None = None  # the ```text block that follows a python block


def page_blocks(text: str, name: str) -> list[Block]:
    """The fenced blocks of a page, in order; a ```text block right after a ```python
    block becomes that block's ``output``."""
    lines, blocks, skip, i = text.splitlines(), [], None, 0
    last_end = -2
    while i < len(lines):
        marker = SKIP.search(lines[i])
        if marker:
            skip = marker.group(1).strip()
        fence = FENCE.match(lines[i])
        if fence:
            start, body, i = i, [], i + 1
            while not FENCE.match(lines[i]) or FENCE.match(lines[i]).group(1):
                body.append(lines[i])
                i += 1
            indent = min((len(b) - len(b.lstrip()) for b in body if b.strip()), default=0)
            code = "\n".join(b[indent:] for b in body)
            follows = blocks and blocks[-1].lang == "python" and blocks[-1].output is None and \
                not any(x.strip() for x in lines[last_end + 1:start])
            if fence.group(1) == "text" and follows:
                blocks[-1].output = code
            else:
                blocks.append(Block(f"{name}:{start + 1}", fence.group(1), code, skip))
            skip, last_end = None, i
        i += 1
    return blocks


def command_lines(code: str) -> list[list[str]]:
    """The argv (after the program) of each command line of a bash block; any other
    command is an error (mark the block to skip it, with a reason)."""
    out = []
    for line in code.splitlines():
        argv = shlex.split(line.lstrip("$ "), comments=True)
        if not argv:
            continue
        if argv[:1] == ["cdt-plugin"]:
            out.append(argv[1:])
        elif argv[:3] == ["python", "-m", "cdt_plugin"]:
            out.append(argv[3:])
        else:
            raise AssertionError(f"not a cdt-plugin command line (mark the block to skip): {line}")
    return out


def _same_line(expected: str, printed: str) -> bool:
    """Equal up to runs of spaces; ``...`` inside the expected line matches any text."""
    pattern = r"\s+".join(".*".join(map(re.escape, word.split("..."))) for word in expected.split())
    return re.fullmatch(pattern, printed.strip()) is not None


def output_matches(expected: str, printed: str) -> bool:
    """Whether ``printed`` is ``expected``, line for line, blank lines left out; an
    expected line ``...`` stands for any run of printed lines."""
    want = [line.strip() for line in expected.splitlines() if line.strip()]
    got = [line for line in printed.splitlines() if line.strip()]

    def match(i: int, j: int) -> bool:
        if i == len(want):
            return j == len(got)
        if want[i] == "...":
            return any(match(i + 1, k) for k in range(j, len(got) + 1))
        return j < len(got) and _same_line(want[i], got[j]) and match(i + 1, j + 1)

    return match(0, 0)


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


def _missing(code: str) -> list[str]:
    """The optional modules ``code`` needs that cannot be imported (not installed, or, as
    Open3D without its system libraries, installed but unusable)."""
    modules = set(re.findall(r"^\s*(?:import|from)\s+([A-Za-z_]\w*)", code, flags=re.MULTILINE))
    modules |= {m for key, m in NEEDS.items() if key in code}
    missing = []
    for module in sorted(modules - {"cdt_plugin"}):
        try:
            importlib.import_module(module)
        except ImportError:
            missing.append(module)
    return missing


def run_python(block: Block, namespace: dict) -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block.code, f"<{block.where}>", "exec"), namespace)  # noqa: S102  (the page's own code)
    if block.output is not None:
        assert any(line.strip() not in ("", "...") for line in block.output.splitlines()), (
            f"{block.where}: an output of wildcards only shows nothing")
        assert output_matches(block.output, out.getvalue()), (
            f"{block.where} shows:\n{block.output}\nit prints:\n{out.getvalue()}")


def run_bash(block: Block, cwd: Path) -> None:
    for argv in command_lines(block.code):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = cli.main(argv)
        assert status == 0, f"{block.where}: cdt-plugin {' '.join(argv)}: exit {status}\n{err.getvalue()}"
        assert "Traceback" not in err.getvalue()
        check_outputs(argv, out.getvalue(), cwd)


@pytest.fixture
def workspace(tmp_path):
    """A working directory from which the corpus is ``../shared/corpus``."""
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "corpus").symlink_to(CORPUS, target_is_directory=True)
    (tmp_path / "repo").mkdir()
    return tmp_path / "repo"


@pytest.mark.skipif(not CORPUS.exists(), reason="corpus not found")
@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_page_blocks(page, workspace, monkeypatch):
    blocks = page_blocks(page.read_text(encoding="utf-8"), str(page.relative_to(ROOT)))
    if importlib.util.find_spec("matplotlib") is not None:
        import matplotlib
        matplotlib.use("Agg")
    before = set(ROOT.iterdir())
    monkeypatch.chdir(workspace)
    namespace = {"__name__": "__docs__"}
    level = logging.getLogger("cdt_plugin").level
    skipped = None
    try:
        for block in blocks:
            if block.skip is not None or block.lang not in ("python", "bash", "sh", "console"):
                continue
            missing = _missing(block.code)
            if missing:     # this block and the rest of the page, which may build on it
                skipped = f"{block.where} and after: needs {', '.join(missing)}"
                break
            if block.lang == "python":
                run_python(block, namespace)
            else:
                run_bash(block, workspace)
    finally:
        logging.getLogger("cdt_plugin").setLevel(level)
        if importlib.util.find_spec("matplotlib") is not None:
            import matplotlib.pyplot as plt
            plt.close("all")
    assert set(ROOT.iterdir()) == before, "the blocks left files in the repository root"
    if skipped:
        pytest.skip(skipped)


# ------------------------------------------------------------------------ the conventions
def test_output_matcher():
    printed = "quality report   a\nx 1\n\ny 2\nz 3\ntime (s)  0.5123\nend 4\n"
    assert output_matches("quality report a\nx   1\n...\nz 3\ntime (s)  ...\nend 4", printed)
    assert not output_matches("quality report a\nx 1", printed)             # the whole output
    assert not output_matches("quality report a\nx 2\n...", printed)
    assert not output_matches("quality report a\nx 1\nz 3\n...", printed)   # no line skipped unasked
    assert output_matches("...\nend 4", printed)


def test_page_blocks_parse():
    text = ("x\n```python\nprint(1)\n```\n\n```text\n1\n```\n"
            "<!-- docs-test: skip (installs) -->\n```bash\npip install x\n```\n```text\nalone\n```\n")
    blocks = page_blocks(text, "p")
    assert [(b.lang, b.output, b.skip) for b in blocks] == [
        ("python", "1", None), ("bash", None, "installs"), ("text", None, None)]
    with pytest.raises(AssertionError, match="not a cdt-plugin command line"):
        command_lines("pip install x")


def test_every_page_block_is_run_or_skipped_with_a_reason():
    """Each page has its blocks parsed; bash blocks that are not skipped are CLI lines
    only, and the README and docs hold enough of both kinds to be worth the name."""
    python = cli_count = 0
    for page in PAGES:
        for block in page_blocks(page.read_text(encoding="utf-8"), str(page.relative_to(ROOT))):
            if block.skip is None and block.lang in ("bash", "sh", "console"):
                cli_count += len(command_lines(block.code))
            python += block.lang == "python" and block.skip is None
    assert python >= 20 and cli_count >= 8


def test_cli_lines_name_corpus_files():
    """Every input a command line names exists (in the corpus or made by an earlier line
    of its page): the lines run as written, nothing to invent first."""
    for page in PAGES:
        made: set[str] = set()
        for block in page_blocks(page.read_text(encoding="utf-8"), str(page.relative_to(ROOT))):
            if block.skip is not None or block.lang not in ("bash", "sh", "console"):
                continue
            for argv in command_lines(block.code):
                if argv[0] in ("mesh", "report", "voronoi", "tin"):
                    assert argv[1] in made or (CORPUS / argv[1].removeprefix("../shared/corpus/")).exists(), argv
                against = _option(argv, "--against")
                assert against in (None, "earcut") or against in made, argv
                output = _option(argv, "-o", "--output")
                if output:
                    made |= {output} | {str(Path(output).with_suffix(s)) for s in (".node", ".ele", ".poly")}
