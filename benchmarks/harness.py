"""Shared benchmark machinery: interleaved timing, peak memory, cold start, tables.

A benchmark file (``bench_delaunay.py``, later ``bench_cdt.py`` ...) declares a
:class:`Suite` of :class:`Workload` objects (how to make the input) and
:class:`Impl` objects (how one implementation turns that input into its native
output), then calls :func:`main`. Everything else lives here:

* **Timing.** Each workload runs in its own worker subprocess. The worker builds the
  input once (not timed), sets every implementation up and warms it up on a small
  input (imports, numba compilation or cache load: not timed), then runs the
  implementations round-robin (A B C D A B C D ...) for ``repeat`` rounds, timing
  only the call with ``time.perf_counter`` (garbage collector collected before and
  disabled during the call). The table shows the median. Ratios are taken to the
  reference implementation (Triangle) measured in the same run, because the machines
  are noisy and only same-run ratios compare. Peers marked ``slow`` get ``--slow-repeat``
  rounds (default 1) on the workloads marked ``large``, to keep a full run short.
* **Timeouts and failures.** The parent enforces a per-call timeout. A call that
  times out or crashes the worker (a segfault in a C extension, say) kills the
  worker; that implementation is reported as "n/a" with the reason and the worker
  is restarted for the others. A peer that is not installed or raises is "n/a" too.
  The benchmark never crashes because a peer does.
* **Peak memory.** Each (implementation, workload) runs once more in a fresh
  subprocess: build the input, set up and warm up, ``gc.collect()``, read the current
  resident set size (baseline), reset the kernel's high-water mark
  (``/proc/self/clear_refs`` = 5, Linux >= 4.0), run the call once, read ``VmHWM``.
  Peak MB = (VmHWM - baseline) / 2**20: the extra resident memory the call needed at
  its peak, output included, input and libraries excluded. Where the high-water mark
  cannot be reset, ``resource.getrusage(RUSAGE_SELF).ru_maxrss`` after the call minus
  the same figure before it is used instead (it can under-report when the warm-up
  peaked higher); the table says which method was used.
* **Small inputs.** A workload with ``number`` > 1 times ``number`` back-to-back calls per
  round and reports the mean per call (like ``timeit``); ``memory=False`` skips its
  peak-memory subprocesses (pointless for inputs of a few hundred points).
* **Extra columns and checks.** An implementation's ``extras(data, result)`` returns
  untimed measures of its output (a minimum angle, say), computed once per workload on
  the result of its first timed call; the suite's ``columns`` list which keys the table
  shows. The suite's ``checks(results)`` returns warning lines (a triangle count that
  differs from the reference, say), printed and appended to the table.
* **Cold start** (numba projects): a fresh subprocess with ``NUMBA_CACHE_DIR`` set to
  an empty temporary directory times ``import`` + first call (compilation included);
  a second fresh subprocess with the now-filled cache times the cached start.

The worker talks to the parent over its original stdout, one JSON object per line;
its fd 1 is redirected to stderr so that anything a C library prints cannot corrupt
the protocol.
"""
from __future__ import annotations

import argparse
import datetime as _dt
import gc
import json
import os
import platform
import resource
import selectors
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any, Callable

from summary import write_readme as write_summary

REPO_ROOT = Path(__file__).resolve().parent.parent
README = REPO_ROOT / "README.md"
WORKER_FLAG = "--_worker"


# ----------------------------------------------------------------------------- model


@dataclass
class Workload:
    """One benchmark input. ``make()`` builds it (never timed)."""

    name: str                                   # short id used on the command line
    label: str                                  # what the table shows
    make: Callable[[], Any]
    warmup: Callable[[Any], Any] | None = None  # small input of the same kind; default: the input
    size: int = 0                               # number of input points (for --quick / large)
    large: bool = False                         # slow peers are skipped here with --skip-slow-peers
    description: str = ""
    number: int = 1                             # calls per timed sample (mean per call reported)
    memory: bool = True                         # measure peak memory (skip for tiny inputs)
    impls: tuple[str, ...] = ()                 # only these implementations run here (default: all)
    rounds: int = 0                             # rounds here (default: the suite's)


@dataclass
class Impl:
    """One implementation. ``setup()`` imports it and returns ``run(data) -> result``."""

    name: str                                   # short id used with --only
    label: str                                  # what the table shows
    setup: Callable[[], Callable[[Any], Any]]
    count: Callable[[Any], int]                 # triangles (or other size) of a result
    timed: str = ""                             # one line: what the timed call covers
    slow: bool = False                          # skipped on large workloads with --skip-slow-peers
    dist: str | None = None                     # distribution name, for the version line
    numba_cold_start: bool = False              # measure cold/cached start in fresh processes
    package: str | None = None                  # top-level package (sources watched during cold start)
    extras: Callable[[Any, Any], dict] | None = None  # (data, result) -> {key: value}, untimed, once


@dataclass
class Suite:
    name: str                                   # also the results file: results/<name>.md
    title: str
    workloads: list[Workload]
    impls: list[Impl]
    reference: str                              # impl name the ratios are taken to
    script: str                                 # the benchmark file (re-run as the worker)
    cold_workload: str | None = None            # workload name for the cold-start line
    quick_max_size: int = 100_000
    extra_versions: list[str] = field(default_factory=list)
    columns: list[tuple[str, str, str]] = field(default_factory=list)  # (extras key, header, format)
    checks: Callable[[dict], list[str]] | None = None  # results -> warning lines
    notes: list[str] = field(default_factory=list)  # fixed lines printed under the table

    def workload(self, name: str) -> Workload:
        return next(w for w in self.workloads if w.name == name)

    def impl(self, name: str) -> Impl:
        return next(i for i in self.impls if i.name == name)


def all_threads_label() -> str:
    """"N threads": the threads a divide-and-conquer call uses by default (two at
    most today, one on a single core). Counted here, not by importing
    cdt_plugin: the suites' modules must not import numba (cold-start figures)."""
    n = min(2, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)
    return f"{n} thread{'s' if n > 1 else ''}"


def select_by_name(spec: str | None, items: list, what: str) -> list:
    """The ``items`` named in a comma-separated ``spec`` (all of them for none),
    in their own order; SystemExit naming any unknown name (``--only``,
    ``--workloads``)."""
    if not spec:
        return items
    wanted = [s.strip() for s in spec.split(",") if s.strip()]
    unknown = set(wanted) - {i.name for i in items}
    if unknown:
        raise SystemExit(f"unknown {what} {sorted(unknown)}; known: {[i.name for i in items]}")
    return [i for i in items if i.name in wanted]


def short_reason(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}".strip()
    text = " ".join(text.split())
    return text if len(text) <= 160 else text[:157] + "..."


# ----------------------------------------------------------------------------- worker side


class _Channel:
    """The worker's protocol channel: the original stdout; fd 1 goes to stderr."""

    def __init__(self) -> None:
        sys.stdout.flush()
        self._fd = os.dup(1)
        os.dup2(2, 1)
        sys.stdout = sys.stderr

    def send(self, **event: Any) -> None:
        os.write(self._fd, (json.dumps(event) + "\n").encode())


def _proc_status_kib(key: str) -> int | None:
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def _reset_hwm() -> bool:
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def _timed_call(run: Callable[[Any], Any], data: Any, number: int = 1) -> tuple[float, Any]:
    """Seconds per call (mean of ``number`` back-to-back calls) and the last result."""
    gc.collect()
    gc.disable()
    try:
        t0 = time.perf_counter()
        for _ in range(number - 1):
            run(data)
        result = run(data)
        t1 = time.perf_counter()
    finally:
        gc.enable()
    return (t1 - t0) / number, result


def _setup(chan: _Channel, impl: Impl, warm: Any) -> Callable[[Any], Any] | None:
    chan.send(event="setup", impl=impl.name)
    try:
        run = impl.setup()
        result = run(warm)
        impl.count(result)
        del result
    except Exception as exc:  # a peer that is missing or broken is reported, not fatal
        chan.send(event="setup_error", impl=impl.name, reason=short_reason(exc))
        return None
    chan.send(event="setup_ok", impl=impl.name)
    return run


def _worker(suite: Suite, spec: dict) -> None:
    chan = _Channel()
    mode = spec["mode"]
    wl = suite.workload(spec["workload"])
    data = wl.make()
    warm = wl.warmup(data) if wl.warmup is not None else data

    if mode == "time":
        remaining: dict[str, int] = spec["remaining"]
        runners = {}
        for name in remaining:
            run = _setup(chan, suite.impl(name), warm)
            if run is not None:
                runners[name] = run
        for rnd in range(max(remaining.values(), default=0)):
            for name in list(runners):
                if remaining[name] <= rnd:
                    continue
                impl = suite.impl(name)
                chan.send(event="start", impl=name, round=rnd)
                try:
                    seconds, result = _timed_call(runners[name], data, max(wl.number, 1))
                    count = int(impl.count(result))
                except Exception as exc:
                    chan.send(event="error", impl=name, reason=short_reason(exc))
                    del runners[name]
                    continue
                extra: dict[str, Any] = {}
                if rnd == 0 and impl.extras is not None:
                    try:
                        extra["extras"] = impl.extras(data, result)
                    except Exception as exc:
                        extra["extras"] = {"error": short_reason(exc)}
                del result
                chan.send(event="result", impl=name, seconds=seconds, count=count, **extra)
        chan.send(event="done")

    elif mode == "mem":
        impl = suite.impl(spec["impl"])
        run = _setup(chan, impl, warm)
        if run is None:
            chan.send(event="done")
            return
        gc.collect()
        chan.send(event="start", impl=impl.name, round=0)
        base_rss = _proc_status_kib("VmRSS")
        if base_rss is not None and _reset_hwm():
            method = "VmHWM"
            result = run(data)
            peak = _proc_status_kib("VmHWM")
            extra_kib = (peak or 0) - base_rss
        else:
            method = "ru_maxrss"
            before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
            result = run(data)
            extra_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
        count = int(impl.count(result))
        del result
        chan.send(event="mem", impl=impl.name, peak_mb=max(extra_kib, 0) / 1024.0,
                  method=method, count=count)
        chan.send(event="done")

    elif mode == "cold":
        # numba (and the package) must not have been imported yet: the timed span is
        # import + first call. The input above is built with numpy only.
        impl = suite.impl(spec["impl"])
        preloaded = "numba" in sys.modules   # would make "cold" too kind: reported
        gc.collect()
        chan.send(event="start", impl=impl.name, round=0)
        t0 = time.perf_counter()
        run = impl.setup()
        result = run(data)
        seconds = time.perf_counter() - t0
        count = int(impl.count(result))
        chan.send(event="cold", impl=impl.name, seconds=seconds, count=count,
                  numba_preloaded=preloaded)
        chan.send(event="done")
    else:
        raise SystemExit(f"unknown worker mode {mode!r}")


# ----------------------------------------------------------------------------- parent side


class _WorkerProc:
    """A worker subprocess whose protocol lines are read with deadlines."""

    def __init__(self, suite: Suite, spec: dict, env: dict | None = None) -> None:
        self._stderr = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(
            [sys.executable, suite.script, WORKER_FLAG, json.dumps(spec)],
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=self._stderr,
            env=env, cwd=str(REPO_ROOT),
        )
        self._sel = selectors.DefaultSelector()
        self._sel.register(self.proc.stdout, selectors.EVENT_READ)
        self._buf = b""

    def next_event(self, timeout: float) -> dict | None | str:
        """The next event; None at end of stream; "timeout" when the deadline passes."""
        deadline = time.monotonic() + timeout
        while b"\n" not in self._buf:
            left = deadline - time.monotonic()
            if left <= 0 or not self._sel.select(left):
                return "timeout"
            chunk = os.read(self.proc.stdout.fileno(), 65536)
            if not chunk:
                return None
            self._buf += chunk
        line, self._buf = self._buf.split(b"\n", 1)
        return json.loads(line)

    def stderr_tail(self) -> str:
        self._stderr.seek(0)
        lines = [ln for ln in self._stderr.read().decode(errors="replace").splitlines() if ln.strip()]
        return lines[-1].strip()[:160] if lines else ""

    def close(self, kill: bool = False) -> int | None:
        if kill and self.proc.poll() is None:
            self.proc.kill()
        try:
            rc = self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self.proc.stdout.close()
        self._stderr.close()
        self._sel.close()
        return rc


def _run_worker(suite: Suite, spec: dict, on_event: Callable[[dict], None],
                timeout: float, setup_timeout: float, env: dict | None = None) -> tuple[str | None, str]:
    """Run one worker to completion, calling ``on_event`` for each event.

    Returns (impl that was running when the worker failed, reason), or (None, "") on
    success. The impl is None too when the worker failed outside any impl's call.
    """
    w = _WorkerProc(suite, spec, env)
    current: str | None = None
    wait, phase = setup_timeout, "input generation"
    try:
        while True:
            ev = w.next_event(wait)
            if ev == "timeout":
                w.close(kill=True)
                return current, f"timed out ({phase} > {wait:g} s)"
            if ev is None:
                rc = w.proc.wait()
                tail = w.stderr_tail()
                w.close()
                how = f"exit code {rc}"
                if rc is not None and rc < 0:
                    try:
                        how = f"killed by {signal.Signals(-rc).name}"
                    except ValueError:
                        pass
                return current, f"worker died ({how}){': ' + tail if tail else ''}"
            assert isinstance(ev, dict)
            kind = ev["event"]
            if kind == "done":
                w.close()
                return None, ""
            if kind == "setup":
                current, wait, phase = ev["impl"], setup_timeout, "import + warm-up"
            elif kind == "start":
                current, wait, phase = ev["impl"], timeout, "call"
            on_event(ev)
    except BaseException:
        w.close(kill=True)
        raise


@dataclass
class Cell:
    """Everything measured for one (workload, impl)."""

    times: list[float] = field(default_factory=list)
    count: int | None = None
    peak_mb: float | None = None
    mem_method: str | None = None
    error: str | None = None
    mem_error: str | None = None
    extras: dict | None = None

    @property
    def median(self) -> float | None:
        return statistics.median(self.times) if self.times else None


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def measure_times(suite: Suite, wl: Workload, impls: list[Impl], repeats: dict[str, int],
                  timeout: float, setup_timeout: float, env: dict | None = None) -> dict[str, Cell]:
    """Interleaved rounds: impl ``name`` runs in the first ``repeats[name]`` rounds
    (in worker processes with the environment ``env``; default this one's)."""
    cells = {i.name: Cell() for i in impls}
    remaining = {i.name: repeats[i.name] for i in impls}

    def on_event(ev: dict) -> None:
        name = ev.get("impl")
        kind = ev["event"]
        if kind in ("setup_error", "error"):
            cells[name].error = ev["reason"]
            remaining.pop(name, None)
            _log(f"  {wl.name:<14} {name:<10} n/a: {ev['reason']}")
        elif kind == "result":
            cells[name].times.append(ev["seconds"])
            cells[name].count = ev["count"]
            if "extras" in ev:
                cells[name].extras = ev["extras"]
            remaining[name] -= 1
            if remaining[name] <= 0:
                remaining.pop(name)
            _log(f"  {wl.name:<14} {name:<10} {ev['seconds']:9.4f} s  {ev['count']:>10,d} triangles")

    while remaining:
        spec = {"mode": "time", "workload": wl.name, "remaining": dict(remaining)}
        failed, reason = _run_worker(suite, spec, on_event, timeout, setup_timeout, env)
        if failed is None and not reason:
            break
        victims = [failed] if failed in remaining else list(remaining)
        for name in victims:
            cells[name].error = reason
            remaining.pop(name, None)
            _log(f"  {wl.name:<14} {name:<10} n/a: {reason}")
    return cells


def measure_memory(suite: Suite, wl: Workload, impl: Impl, cell: Cell,
                   timeout: float, setup_timeout: float) -> None:
    def on_event(ev: dict) -> None:
        if ev["event"] == "mem":
            cell.peak_mb, cell.mem_method = ev["peak_mb"], ev["method"]
            if cell.count is None:
                cell.count = ev["count"]
        elif ev["event"] == "setup_error":
            cell.mem_error = ev["reason"]

    spec = {"mode": "mem", "workload": wl.name, "impl": impl.name}
    failed, reason = _run_worker(suite, spec, on_event, timeout, setup_timeout)
    if reason:
        cell.mem_error = reason
    _log(f"  {wl.name:<14} {impl.name:<10} peak "
         + (f"{cell.peak_mb:.1f} MB ({cell.mem_method})" if cell.peak_mb is not None
            else f"n/a: {cell.mem_error}"))


def measure_cold(suite: Suite, impl: Impl, wl: Workload, timeout: float) -> dict:
    """import + first call with an empty numba cache, then again with the filled cache."""
    out: dict[str, Any] = {"workload": wl.name, "impl": impl.name}
    before = _sources_mtime(impl.package)
    cache = tempfile.mkdtemp(prefix="numba-cold-")
    try:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for key in ("cold_s", "cached_s"):
            got: dict = {}
            spec = {"mode": "cold", "workload": wl.name, "impl": impl.name}
            _, reason = _run_worker(suite, spec, lambda ev: got.update(ev), timeout, timeout, env)
            if reason or "seconds" not in got:
                out[key + "_error"] = reason or "no result"
                _log(f"  cold start {key}: n/a: {out[key + '_error']}")
                break
            out[key] = got["seconds"]
            if got.get("numba_preloaded"):
                out["warning"] = "numba was imported before the timed span"
            _log(f"  {key.replace('_s', '')} start (import + first call, {wl.name}): {got['seconds']:.2f} s")
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    if before is not None and _sources_mtime(impl.package) != before:
        out["warning"] = f"{impl.package} sources changed during the measurement (numba cache invalidated)"
        _log(f"  WARNING: {out['warning']}")
    return out


def _sources_mtime(package: str | None) -> float | None:
    """Newest mtime of the package's .py files, found without importing it."""
    if not package:
        return None
    import importlib.util
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        return None
    root = Path(list(spec.submodule_search_locations)[0])
    return max((p.stat().st_mtime for p in root.rglob("*.py")), default=None)


# ----------------------------------------------------------------------------- reporting


def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def machine_info(suite: Suite) -> dict:
    cpu_model = ""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu_model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()
    versions = {"python": platform.python_version()}
    for dist in ["numpy", "numba"] + suite.extra_versions + [i.dist for i in suite.impls if i.dist]:
        if dist not in versions:
            versions[dist] = _version(dist)
    return {
        "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu_count": os.cpu_count(),
        "cpus_usable": usable,
        "cpu_model": cpu_model,
        "platform": platform.platform(),
        "versions": versions,
    }


def fmt_s(x: float | None) -> str:
    if x is None:
        return "n/a"
    if x >= 100:
        return f"{x:.0f}"
    if x >= 1:
        return f"{x:.2f}"
    return f"{x:.3g}" if x >= 0.001 else f"{x:.2g}"


def render_markdown(suite: Suite, results: dict, info: dict, args_line: str) -> str:
    ref = suite.reference
    ref_label = suite.impl(ref).label
    v = info["versions"]
    vers = ", ".join(f"{k} {val}" for k, val in v.items() if val)
    lines = [
        f"Machine: {info['cpu_count']} CPUs ({info['cpus_usable']} usable)"
        + (f", {info['cpu_model']}" if info["cpu_model"] else "")
        + f"; {vers}; {info['date']}. Command: `{args_line}`"
        + (f" (mode: {results['mode']})" if results.get("mode") != "full" else "") + ".",
        "",
        f"| workload | implementation | median s | ratio to {ref_label} | triangles | "
        + "".join(f"{head} | " for _, head, _ in suite.columns) + "peak MB |",
        "|---|---|---:|---:|---:|" + "---:|" * len(suite.columns) + "---:|",
    ]
    notes: list[str] = []
    for wl in suite.workloads:
        row = results["workloads"].get(wl.name)
        if row is None:
            continue
        ref_med = row.get(ref, {}).get("median")
        for impl in suite.impls:
            c = row.get(impl.name)
            if c is None:
                continue
            if c.get("error"):
                med = "n/a"
                notes.append(f"{wl.label} / {impl.label}: {c['error']}")
            else:
                med = fmt_s(c["median"])
            ratio = (f"{c['median'] / ref_med:.2f}x" if c.get("median") and ref_med else "n/a")
            tris = f"{c['count']:,d}" if c.get("count") is not None else "n/a"
            mem = f"{c['peak_mb']:.1f}" if c.get("peak_mb") is not None else "n/a"
            if c.get("peak_mb") is None and c.get("mem_error") and not c.get("error"):
                notes.append(f"{wl.label} / {impl.label} memory: {c['mem_error']}")
            if c.get("peak_mb") is None and not wl.memory:
                mem = "-"
            extra_cells = "".join(f"{_fmt_extra(c.get('extras'), key, fmt)} | "
                                  for key, _, fmt in suite.columns)
            lines.append(f"| {wl.label} | {impl.label} | {med} | {ratio} | {tris} | {extra_cells}{mem} |")
    lines.append("")
    cold = results.get("cold")
    if cold:
        impl = suite.impl(cold["impl"])
        wl = suite.workload(cold["workload"])
        warm = results["workloads"].get(wl.name, {}).get(impl.name, {}).get("median")
        parts = []
        parts.append(f"cold {fmt_s(cold['cold_s'])} s" if "cold_s" in cold
                     else f"cold n/a ({cold.get('cold_s_error')})")
        if "cached_s" in cold:
            parts.append(f"cached start {fmt_s(cold['cached_s'])} s")
        parts.append(f"warm {fmt_s(warm)} s" if warm else "warm n/a")
        lines.append(
            f"{impl.label} start-up on {wl.label}: " + "; ".join(parts)
            + (f" (warning: {cold['warning']})" if cold.get("warning") else "") + ". Cold = new process, "
            "empty numba cache (`NUMBA_CACHE_DIR` = fresh temp dir), import + first call "
            "(compilation included); cached start = new process, filled cache, import + first "
            "call; warm = in-process median after warm-up (the table).")
        lines.append("")
    methods = sorted({c.get("mem_method") for row in results["workloads"].values()
                      for c in row.values() if c.get("mem_method")})
    present = {name for row in results["workloads"].values() for name in row}
    spans = "; ".join(f"{i.label}: {i.timed}" for i in suite.impls if i.timed and i.name in present)
    lines.append(
        f"Median of {results['repeat']} interleaved round(s) per workload"
        + (f" ({', '.join(results['slow'])}: {results['slow_repeat']} round(s) on "
           f"{', '.join(results['large'])})"
           if results["slow_repeat"] < results["repeat"] and results["slow"] and results["large"] else "")
        + ", one worker process per workload, input generation not timed. "
        + ("Peak MB = extra resident memory of one call in a fresh process (peak minus the "
           "baseline after imports, input and warm-up; MiB; method: " + ", ".join(methods) + ")."
           if methods else "Peak memory not measured.") + (f" Timed spans: {spans}." if spans else ""))
    for wl in suite.workloads:
        if wl.name in results["workloads"] and (wl.impls or wl.rounds):
            shown = [suite.impl(n).label for n in wl.impls if n in results["workloads"][wl.name]]
            said = ([f"only {'; '.join(shown)}"] if wl.impls else []) + (
                [f"{min(results['repeat'], wl.rounds)} round(s)"] if wl.rounds else [])
            lines[-1] += f" {wl.label}: {' / '.join(said)}."
    if any(not wl.memory for wl in suite.workloads if wl.name in results["workloads"]) and methods:
        lines[-1] += " Peak MB \"-\": not measured (tiny input)."
    if notes:
        lines.append("")
        lines.extend(f"- n/a: {n}" for n in notes)
    if suite.notes:
        lines.append("")
        lines.extend(f"- {n}" for n in suite.notes)
    if results.get("warnings"):
        lines.append("")
        lines.extend(f"- WARNING: {w}" for w in results["warnings"])
    return "\n".join(lines) + "\n"


def _fmt_extra(extras: dict | None, key: str, fmt: str) -> str:
    if not extras or extras.get(key) is None:
        return "n/a"
    value = extras[key]
    return format(value, fmt) if isinstance(value, (int, float)) else str(value)


# ----------------------------------------------------------------------------- driver


def _parse(suite: Suite, argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=suite.title)
    p.add_argument("--quick", action="store_true",
                   help=f"smoke test: only workloads with <= {suite.quick_max_size:,d} points, 1 repeat")
    p.add_argument("--repeat", type=int, default=None, help="interleaved rounds per workload (default 3)")
    p.add_argument("--only", default=None,
                   help="comma-separated implementations: " + ",".join(i.name for i in suite.impls))
    p.add_argument("--workloads", default=None,
                   help="comma-separated workloads: " + ",".join(w.name for w in suite.workloads))
    p.add_argument("--slow-repeat", type=int, default=1,
                   help="rounds for the peers marked slow on the large workloads (default 1; "
                   "they are 5-35x slower than the reference, one round keeps the full run short)")
    p.add_argument("--skip-slow-peers", action="store_true",
                   help="skip peers marked slow (" + ",".join(i.name for i in suite.impls if i.slow)
                   + ") on the large workloads")
    p.add_argument("--timeout", type=float, default=120.0, help="seconds allowed per timed call (default 120)")
    p.add_argument("--setup-timeout", type=float, default=600.0,
                   help="seconds allowed for import + warm-up, e.g. numba compilation (default 600)")
    p.add_argument("--no-memory", action="store_true", help="skip the peak-memory subprocesses")
    p.add_argument("--no-cold", action="store_true", help="skip the cold-start measurement")
    p.add_argument("--out", default=None,
                   help=f"markdown output (a .json with raw numbers is written beside it); "
                   f"default benchmarks/results/{suite.name}.md (…-quick.md with --quick)")
    p.add_argument("--write-readme", action="store_true",
                   help="regenerate the README's benchmark summary rows from the stored results")
    return p.parse_args(argv)


def main(suite: Suite, argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == [WORKER_FLAG]:
        _worker(suite, json.loads(argv[1]))
        return 0
    args = _parse(suite, argv)
    t_start = time.perf_counter()
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)

    impls = suite.impls
    if args.only:
        wanted = [s.strip() for s in args.only.split(",") if s.strip()]
        unknown = set(wanted) - {i.name for i in suite.impls}
        if unknown:
            raise SystemExit(f"unknown implementation(s) {sorted(unknown)}; known: {[i.name for i in suite.impls]}")
        impls = [i for i in suite.impls if i.name in wanted]
    workloads = suite.workloads
    if args.workloads:
        wanted = [s.strip() for s in args.workloads.split(",") if s.strip()]
        unknown = set(wanted) - {w.name for w in suite.workloads}
        if unknown:
            raise SystemExit(f"unknown workload(s) {sorted(unknown)}; known: {[w.name for w in suite.workloads]}")
        workloads = [w for w in suite.workloads if w.name in wanted]
    if args.quick:
        workloads = [w for w in workloads if w.size <= suite.quick_max_size]

    info = machine_info(suite)
    _log(f"{suite.title}: {len(workloads)} workload(s) x {len(impls)} implementation(s), "
         f"{repeat} round(s); {info['cpu_count']} CPUs; python {info['versions']['python']}")
    results: dict[str, Any] = {
        "suite": suite.name, "mode": "quick" if args.quick else "full", "repeat": repeat,
        "slow_repeat": min(repeat, max(args.slow_repeat, 1)),
        "slow": [i.label for i in impls if i.slow],
        "large": [w.label for w in workloads if w.large],
        "machine": info, "argv": argv, "workloads": {},
    }

    cold_impl = next((i for i in impls if i.numba_cold_start), None)
    if cold_impl is not None and suite.cold_workload and not args.no_cold:
        _log("cold start:")
        results["cold"] = measure_cold(suite, cold_impl, suite.workload(suite.cold_workload),
                                       args.setup_timeout + args.timeout)

    for wl in workloads:
        _log(f"{wl.label}:")
        runs_here = [i for i in impls if not wl.impls or i.name in wl.impls]
        active = [i for i in runs_here if not (args.skip_slow_peers and wl.large and i.slow)]
        rounds = min(repeat, wl.rounds) if wl.rounds else repeat
        repeats = {i.name: (min(rounds, max(args.slow_repeat, 1)) if wl.large and i.slow else rounds)
                   for i in active}
        cells = measure_times(suite, wl, active, repeats, args.timeout, args.setup_timeout)
        if not args.no_memory and wl.memory:
            for impl in active:
                if cells[impl.name].error is None:
                    measure_memory(suite, wl, impl, cells[impl.name], args.timeout, args.setup_timeout)
        for impl in runs_here:
            if impl not in active:
                cells[impl.name] = Cell(error="skipped (--skip-slow-peers)")
        results["workloads"][wl.name] = {
            name: {"median": c.median, "times": c.times, "count": c.count, "peak_mb": c.peak_mb,
                   "mem_method": c.mem_method, "error": c.error, "mem_error": c.mem_error,
                   "extras": c.extras}
            for name, c in cells.items()
        }

    args_line = command_line(suite, argv)
    if suite.checks is not None:
        try:
            results["warnings"] = list(suite.checks(results))
        except Exception as exc:
            results["warnings"] = [f"the checks failed: {short_reason(exc)}"]
        for w in results["warnings"]:
            _log(f"WARNING: {w}")
    md = render_markdown(suite, results, info, args_line)
    results["elapsed_s"] = time.perf_counter() - t_start

    return write_results(suite, results, md, args)


def command_line(suite: Suite, argv: list[str]) -> str:
    """The command that made a table, as the table shows it: the script and its
    options, less where the output goes (``--out``, ``--write-readme``)."""
    shown, skip = [], False
    for a in argv:
        if skip:
            skip = False
        elif a == "--out":
            skip = True
        elif a != "--write-readme" and not a.startswith("--out="):
            shown.append(a)
    return " ".join(["python", os.path.relpath(suite.script, REPO_ROOT)] + shown)


def results_path(suite: Suite, args: argparse.Namespace) -> Path:
    """The suite's results file: ``--out``, else ``results/<suite>.md``
    (``-quick`` with ``--quick``)."""
    return Path(args.out) if args.out else (
        REPO_ROOT / "benchmarks" / "results" / (suite.name + ("-quick" if args.quick else "") + ".md"))


def write_results(suite: Suite, results: dict, md: str, args: argparse.Namespace) -> int:
    """Write ``results/<suite>.md`` and ``.json`` (``-quick`` with ``--quick``; the
    documentation's benchmark pages include the .md), and with ``--write-readme`` the
    README's summary rows (``summary.py``), unless cdt_plugin's own column failed
    somewhere. Returns the exit status."""
    out = results_path(suite, args)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(f"# {suite.title}\n\n{md}")
    out.with_suffix(".json").write_text(json.dumps(results, indent=1) + "\n")
    _log(f"wrote {out} and {out.with_suffix('.json')}")
    ours_failed = [w for w, cells in results["workloads"].items()
                   if "ours" in cells and cells["ours"]["error"]]
    if args.write_readme and ours_failed:
        # a table of n/a rows for our own column is never what the README should show
        _log(f"NOT updating {README}: cdt_plugin failed on {', '.join(ours_failed)}")
        return 1
    if args.write_readme:
        write_summary()
        _log(f"updated the benchmark summary in {README} (benchmarks/summary.py)")
    print(md)
    _log(f"total {results['elapsed_s']:.0f} s")
    return 0


# ----------------------------------------------------------------------------- sources
def sources_state() -> dict[str, float]:
    """mtime of each .py file of cdt_plugin and of the adapters (``adapters/``,
    installed as ``cdt_plugin.adapters``), found without importing cdt_plugin."""
    import importlib.util
    spec = importlib.util.find_spec("cdt_plugin")
    roots = [Path(p) for p in (spec.submodule_search_locations or [])] if spec else []
    roots.append(REPO_ROOT / "adapters")
    return {os.path.relpath(f, REPO_ROOT): f.stat().st_mtime
            for root in roots if root.is_dir() for f in sorted(root.rglob("*.py"))}


def changed_sources(before: dict[str, float], after: dict[str, float]) -> list[str]:
    return sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
