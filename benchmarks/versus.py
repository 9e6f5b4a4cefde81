"""The working tree against an earlier commit, side by side in one run.

A change that should not make anything slower (a restructuring, say) is judged by
timing the code before and after it on the same workloads in the same run, since
the machines drift by 10-20% between runs. This script takes one benchmark suite
(``small``, ``delaunay``, ``cdt``, ``voronoi``, ``queries``: the files
``bench_<suite>.py`` that declare a ``SUITE``), extracts ``cdt_plugin`` and its
adapters at the base commit into a temporary folder, and for each workload runs the
suite's timing worker (``harness.py``) in turns: one round on this tree, one round on
the base commit, and so on. Each round is a new worker process with the same
workload and implementations, so the peers (Triangle, ...) are timed beside both,
and each side's ratio to the suite's reference is taken within its own process.

Usage (from the repository root)::

    python benchmarks/versus.py small --base HEAD~3
    python benchmarks/versus.py delaunay --base main --workloads uniform_1e5 --only ours,triangle
    python benchmarks/versus.py cdt --base v0.1.0 --rounds 4 --repeat 3

The base side imports the extracted package through ``PYTHONPATH`` (so its own numba
cache, compiled in its first worker's warm-up, is not timed); the implementations
and workloads are this tree's, so the public calls they make must exist at both
commits. The table goes to ``benchmarks/results/<suite>-versus.md`` (with a .json of
the raw rounds beside it) and to standard output.
"""
from __future__ import annotations

import argparse
import importlib
import json
import os
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import REPO_ROOT, Suite, machine_info, measure_times, select_by_name  # noqa: E402

SUITES = ("small", "delaunay", "cdt", "voronoi", "queries")


def extract_base(rev: str, into: Path) -> str:
    """``cdt_plugin`` at commit ``rev`` laid out as installed (``adapters/`` as
    ``cdt_plugin/adapters``) under ``into``; returns the commit's full hash."""
    commit = subprocess.run(["git", "rev-parse", "--verify", f"{rev}^{{commit}}"], cwd=REPO_ROOT,
                            capture_output=True, text=True, check=True).stdout.strip()
    archive = into / "base.tar"
    subprocess.run(["git", "archive", "--format=tar", "-o", str(archive), commit, "cdt_plugin", "adapters"],
                   cwd=REPO_ROOT, check=True)
    with tarfile.open(archive) as tar:
        tar.extractall(into, filter="data")
    archive.unlink()
    (into / "adapters").rename(into / "cdt_plugin" / "adapters")
    return commit


def check_base_is_imported(env: dict, root: Path) -> None:
    """Stop unless a process with ``env`` imports ``cdt_plugin`` and its adapters from ``root``."""
    where = subprocess.run([sys.executable, "-c", "import cdt_plugin, cdt_plugin.adapters as a; "
                            "print(cdt_plugin.__file__); print(a.__file__)"],
                           env=env, cwd=root, capture_output=True, text=True).stdout.split()
    if len(where) != 2 or not all(Path(w).resolve().is_relative_to(root.resolve()) for w in where):
        raise SystemExit(f"the base commit's package is not the one imported (got {where})")


def side_by_side(suite: Suite, workloads, impls, rounds: int, repeat: int, base_env: dict,
                 timeout: float, setup_timeout: float) -> dict:
    """``{workload: {impl: {"head": [s...], "base": [s...]}}}``: ``rounds`` turns of
    one worker on this tree then one on the base, ``repeat`` interleaved rounds in each."""
    out: dict = {}
    for wl in workloads:
        print(f"{wl.label}:", file=sys.stderr, flush=True)
        row: dict = {i.name: {"head": [], "base": [], "error": None} for i in impls}
        for _ in range(rounds):
            for side, env in (("head", None), ("base", base_env)):
                cells = measure_times(suite, wl, impls, {i.name: repeat for i in impls},
                                      timeout, setup_timeout, env=env)
                for name, cell in cells.items():
                    row[name][side].extend(cell.times)
                    row[name]["error"] = row[name]["error"] or cell.error
        out[wl.name] = row
    return out


def _median(times: list[float]) -> float | None:
    return statistics.median(times) if times else None


def _fmt(seconds: float | None) -> str:
    if seconds is None:
        return "n/a"
    return f"{seconds * 1e6:.1f} us" if seconds < 1e-3 else f"{seconds:.4g} s"


def _ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}x" if a and b else "n/a"


def render(suite: Suite, results: dict, base: str, head: str, info: dict, command: str) -> str:
    """The markdown table: per workload and implementation, each side's median, the
    ratio of this tree to the base, and each side's ratio to the suite's reference."""
    ref = suite.reference
    ref_label = suite.impl(ref).label
    lines = [f"This tree ({head}) against commit {base[:10]}, side by side. Machine: {info['cpu_count']} CPUs"
             f"{', ' + info['cpu_model'] if info['cpu_model'] else ''}; {info['date']}. "
             f"Command: `{command}`.", "",
             f"| workload | implementation | base median | this tree median | this tree / base | "
             f"base / {ref_label} | this tree / {ref_label} |",
             "|---|---|---:|---:|---:|---:|---:|"]
    notes = []
    for wl in suite.workloads:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        ref_head = _median(row.get(ref, {}).get("head", []))
        ref_base = _median(row.get(ref, {}).get("base", []))
        for impl in suite.impls:
            cell = row.get(impl.name)
            if cell is None or impl.name == ref:
                continue
            if cell["error"]:
                notes.append(f"{wl.label} / {impl.label}: {cell['error']}")
            b, h = _median(cell["base"]), _median(cell["head"])
            lines.append(f"| {wl.label} | {impl.label} | {_fmt(b)} | {_fmt(h)} | {_ratio(h, b)} | "
                         f"{_ratio(b, ref_base)} | {_ratio(h, ref_head)} |")
    lines += ["", f"Each side: median of {results['rounds']} turn(s) x {results['repeat']} interleaved "
              "round(s), each turn a new worker process on that side (this tree, then the base), the "
              f"reference ({ref_label}) timed in every worker beside it."]
    lines += [f"- n/a: {n}" for n in notes]
    return "\n".join(lines) + "\n"


def _head_name() -> str:
    described = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=REPO_ROOT,
                               capture_output=True, text=True).stdout.strip()
    return described or "working tree"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("suite", choices=SUITES)
    p.add_argument("--base", required=True, help="the commit to compare with (any git revision)")
    p.add_argument("--workloads", default=None, help="comma-separated workloads (default: all)")
    p.add_argument("--only", default=None, help="comma-separated implementations (default: all); "
                   "the suite's reference is always added")
    p.add_argument("--rounds", type=int, default=3, help="turns per side and workload (default 3)")
    p.add_argument("--repeat", type=int, default=3, help="interleaved rounds in each turn (default 3)")
    p.add_argument("--timeout", type=float, default=120.0, help="seconds allowed per timed call")
    p.add_argument("--setup-timeout", type=float, default=900.0,
                   help="seconds allowed for import + warm-up (the base compiles on its first turn)")
    p.add_argument("--out", default=None, help="markdown output (default benchmarks/results/<suite>-versus.md)")
    args = p.parse_args(argv)

    module = importlib.import_module(f"bench_{args.suite}")
    suite: Suite = module.SUITE
    workloads = select_by_name(args.workloads, suite.workloads, "workload(s)")
    impls = select_by_name(args.only, suite.impls, "implementation(s)")
    if suite.reference not in {i.name for i in impls}:
        impls = [suite.impl(suite.reference), *impls]
    info = machine_info(suite)
    tmp = Path(tempfile.mkdtemp(prefix="cdt-versus-"))
    try:
        base = extract_base(args.base, tmp)
        base_env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [str(tmp), *filter(None, [os.environ.get("PYTHONPATH")])]))
        check_base_is_imported(base_env, tmp)
        rows = side_by_side(suite, workloads, impls, args.rounds, args.repeat, base_env,
                            args.timeout, args.setup_timeout)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    results = {"suite": suite.name, "base": base, "head": _head_name(), "rounds": args.rounds,
               "repeat": args.repeat, "machine": info, "workloads": rows}
    shown = [a for a in (argv if argv is not None else sys.argv[1:])]
    command = " ".join(["python", "benchmarks/versus.py", *shown])
    md = render(suite, results, base, results["head"], info, command)
    out = Path(args.out) if args.out else REPO_ROOT / "benchmarks" / "results" / f"{suite.name}-versus.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(f"# {suite.title}: against an earlier commit\n\n{md}")
    out.with_suffix(".json").write_text(json.dumps(results, indent=1) + "\n")
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
