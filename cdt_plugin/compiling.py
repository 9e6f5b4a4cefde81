"""First use: the engine is compiled by numba the first time each route runs,
then cached on disk (``__pycache__`` beside the sources, or ``NUMBA_CACHE_DIR``).

While a route compiles, one line on stderr says so, through the
``cdt_plugin`` logger (silence it with
``logging.getLogger("cdt_plugin").setLevel(logging.ERROR)``).
:func:`cdt_plugin.warmup.compile_routes` (the ``cdt-plugin compile`` command)
compiles every route ahead of time, for Docker images, CI and Dask workers.
On two cores or more, a second process compiles the largest stages of the
constrained Delaunay route meanwhile (see "a helper process" below;
``CDT_PLUGIN_COMPILE_HELPER=0`` keeps to one process).

>>> from cdt_plugin.compiling import ROUTES
>>> sorted(ROUTES)
['batch', 'delaunay', 'dynamic', 'query', 'refine', 'split', 'triangulate', 'voronoi', 'weighted']
"""
from __future__ import annotations

import atexit
import glob
import logging
import os
import subprocess
import sys
import threading
import time
import types

from numba.core import config, event

from ._core import jit

logger = logging.getLogger("cdt_plugin")

# what is compiling, for the message: the routes' entry points, else the module
_ENTRY_NAMES = {
    "cdt_route": "the constrained Delaunay route (triangulate)",
    "cdt_route_packed": "the constrained Delaunay route (triangulate)",
    "route_points_for_threads": "the constrained Delaunay route on two threads (triangulate)",
    "mesh_geometries": "the batch route (triangulate_rings)",
    "plain_ring_faces": "the one-polygon route of the drop-ins (trimesh's triangulate_polygon)",
    "plain_polygon_faces": "the one-polygon route of the drop-ins (trimesh's triangulate_polygon)",
    "plain_ring_collection": "the one-polygon route of the drop-ins (shapely's "
                             "constrained_delaunay_triangles)",
    "plain_polygon_collection": "the one-polygon route of the drop-ins (shapely's "
                                "constrained_delaunay_triangles)",
    "build_mesh": "the Delaunay route (delaunay)",
    "snap_route": "snap rounding of crossing segments (intersections='split')",
}
_MODULE_NAMES = {"cdt_plugin._core.predicates": "the exact predicates",
                 "cdt_plugin._core.dual": "the Voronoi diagram (voronoi, delaunay_subdivision)",
                 "cdt_plugin._core.query": "point location and interpolation (locate, interpolate)",
                 "cdt_plugin._core.dynamic": "the live triangulation (DynamicCDT)"}


def cache_dir() -> str:
    """Where numba keeps the compiled engine: ``NUMBA_CACHE_DIR``, or the
    ``__pycache__`` folders of the installed package."""
    configured: str = config.CACHE_DIR  # type: ignore[attr-defined]  # (numba sets its options at run time)
    if configured:
        return configured
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "**", "__pycache__")


class _CompileNotice(event.Listener):
    """Says that it is compiling: once per burst of compilation of a cdt_plugin
    function called from outside (``delaunay``, ``triangulate``, an adapter, the
    CLI: the outermost cdt_plugin frame), whatever the number of kernels it
    compiles; once per route or module for a kernel called directly (an import,
    a test); and, at INFO level, how long each compilation took. A burst: the
    compilations less than ``BURST`` seconds apart (a first ``delaunay`` compiles
    eight entries one after the other)."""

    BURST = 1.0

    def __init__(self) -> None:
        self.depth = 0
        self.start = 0.0
        self.what = ""
        self.said: set[str] = set()
        self.call = ""              # the public call said last
        self.end = -1e300           # when the last compilation ended (perf_counter)

    def on_start(self, ev: event.Event) -> None:
        dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
        py_func = getattr(dispatcher, "py_func", None)
        module = getattr(py_func, "__module__", "") or ""
        if self.depth == 0 and not module.startswith("cdt_plugin"):
            return
        self.depth += 1
        if self.depth == 1:
            name = getattr(py_func, "__name__", "")
            self.what = _ENTRY_NAMES.get(name) or _MODULE_NAMES.get(module) or f"{module}.{name}"
            self.start = time.perf_counter()
            frame = _public_call()
            if frame is not None:
                helper.start()
                call = _call_name(frame)
                if call == self.call and self.start - self.end < self.BURST:
                    return
                self.call = call
                what = f"the engine for {call}"
            elif self.what in self.said:
                return
            else:
                self.said.add(self.what)
                what = self.what
            logger.warning("cdt_plugin: compiling %s with numba (once: it is cached in %s; "
                           "`cdt-plugin compile` does every route ahead of time)",
                           what, cache_dir())

    def on_end(self, ev: event.Event) -> None:
        if self.depth == 0:
            return
        self.depth -= 1
        if self.depth == 0:
            self.end = time.perf_counter()
            logger.info("cdt_plugin: compiled %s in %.1f s", self.what, self.end - self.start)


def _public_call() -> types.FrameType | None:
    """The outermost frame of a cdt_plugin function outside the compiled core on
    the current stack (the call a user made), or None (an import, a kernel
    called directly)."""
    frame: types.FrameType | None = sys._getframe(1)
    found = None
    while frame is not None:
        module = frame.f_globals.get("__name__", "")
        if (module.startswith("cdt_plugin") and frame.f_code.co_name != "<module>"   # (an import)
                and not module.startswith(("cdt_plugin._core", "cdt_plugin.compiling",
                                           "cdt_plugin.warmup"))):
            found = frame
        frame = frame.f_back
    return found


def _call_name(frame: types.FrameType) -> str:
    """How the message names a call: ``triangulate()``, ``Triangulation.voronoi()``,
    the CLI."""
    if frame.f_globals.get("__name__") in ("cdt_plugin.cli", "cdt_plugin.__main__"):
        return "the cdt-plugin command"
    return f"{getattr(frame.f_code, 'co_qualname', frame.f_code.co_name)}()"


_notice = _CompileNotice()
event.register("numba:compile", _notice)


# ------------------------------------------------------------ a helper process on first use
# numba compiles on one core. When a cold process first compiles a route for a public
# call, a second process compiles the constrained Delaunay route's largest stages into
# the disk cache (the cache is written under a lock, :class:`~cdt_plugin._core.jit.LockedCache`),
# in the order of HELPER_STAGES; the route loads each one the helper has compiled
# instead of compiling it (a stage compiled apart: nothing of it is compiled again),
# links late the one it is compiling (typed against its declared return type, called
# through a pointer that is filled when it is loaded, before the route first runs:
# :class:`~cdt_plugin._core.jit.LateStage`), or waits for it if it declares none, and
# claims the rest, which the helper then skips. Each stage declares the argument
# types the route gives it (``ahead=``); a caller with other types compiles it
# itself. The helper starts at a first ``delaunay`` as well: most scripts
# triangulate next, and the cache keeps what it compiled.
HELPER_ENV = "CDT_PLUGIN_COMPILE_HELPER"       # "0": no helper process
# The helper's order. The exact predicates' circle-test and crossing stages first: a
# first ``delaunay`` needs the circle test a few seconds in (it compiles orient2d's
# itself). Then the constrained route's, which needs them in the order polygon_rings
# (before the route), build_mesh, insert_all_segments, classify, refine_store,
# cdt_arrays: the route compiles build_mesh itself while the helper compiles the
# stages after it, and classify while the helper compiles refinement, which the route
# links late (first use measured 33.6 s waiting for refinement, 27 s linking it late;
# 36 s with the helper taking build_mesh early or refinement first).
HELPER_STAGES = (
    "cdt_plugin._core.predicates._incircle_slow",
    "cdt_plugin._core.predicates._incircle_weighted_slow",
    "cdt_plugin._core.predicates._crossing_coordinate",
    "cdt_plugin._core.rings.polygon_rings",
    "cdt_plugin._core.pipeline.insert_all_segments",
    "cdt_plugin._core.refine.refine_store",
    "cdt_plugin._core.output.cdt_arrays",
    "cdt_plugin._core.pipeline.classify",
    "cdt_plugin._core.construct.build_mesh",
)


def _stage(name: str) -> jit.Kernel:
    module, _, qualname = name.rpartition(".")
    return jit.kernel_at(module, qualname)


def _usable_cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _stage_name(kernel) -> str:
    return f"{kernel.py_func.__module__}.{kernel.py_func.__qualname__}"


class _Helper:
    """The helper process of this one (at most one, started by the first
    compilation for a public call when a stage it compiles is not in the cache).
    It says ``start NAME`` and ``done NAME`` for each stage; it is told ``mine
    NAME`` for each stage this process compiles itself."""

    WAIT_LIMIT = 300.0      # seconds to wait for one stage before compiling it here

    def __init__(self) -> None:
        self.started = False
        self.proc: subprocess.Popen | None = None
        self.pid = -1                        # the process that started it
        self.state: dict[str, str] = {}      # stage -> "pending", "start", "done" or "mine"
        self.ended = False
        self.changed = threading.Condition()

    def allowed(self) -> bool:
        return (os.environ.get(HELPER_ENV, "1") != "0" and _usable_cpus() >= 2
                and bool(sys.executable))

    def start(self) -> None:
        if self.started or not self.allowed():
            return
        self.started = True
        try:
            self._spawn()
        except Exception:       # never stop a compilation over its helper: it compiles alone
            self.proc, self.state = None, {}

    def _spawn(self) -> None:
        stages = {n: _stage(n) for n in HELPER_STAGES}
        names = [n for n, k in stages.items() if not k.overloads and not k.in_cache(k.ahead)]
        if not names:
            return
        env = {**os.environ, HELPER_ENV: "0",
               "PYTHONPATH": os.pathsep.join([os.path.dirname(_PACKAGE),     # this very package
                                              *filter(None, [os.environ.get("PYTHONPATH")])])}
        code = "import sys; from cdt_plugin.compiling import compile_ahead; compile_ahead(sys.argv[1:])"
        try:
            self.proc = subprocess.Popen([sys.executable, "-c", code, *names], env=env, text=True,
                                         stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         stderr=subprocess.DEVNULL)
        except OSError:          # (an interpreter that cannot start another)
            return
        self.state, self.pid = dict.fromkeys(names, "pending"), os.getpid()
        threading.Thread(target=self._listen, args=(self.proc,), daemon=True,
                         name="cdt_plugin compile helper").start()
        atexit.register(self.stop)
        logger.info("cdt_plugin: a second process compiles %s", ", ".join(names))

    def _listen(self, proc: subprocess.Popen) -> None:
        """Follows what the helper says, until it ends (then reaps it)."""
        try:
            for line in proc.stdout or ():
                what, _, name = line.strip().partition(" ")
                with self.changed:
                    if self.state.get(name) != "mine":
                        self.state[name] = what
                    self.changed.notify_all()
        except (OSError, ValueError):
            pass
        with self.changed:
            self.ended = True
            self.changed.notify_all()
        proc.wait()

    def wait_for(self, kernel, sig) -> None:
        """Before ``kernel`` compiles here for ``sig``: if the helper is compiling
        it, wait until it has (numba then loads it from the cache); if the helper has
        not begun it, claim it."""
        args = tuple(getattr(sig, "args", sig))                  # (a declared signature: its arguments)
        if not self._has(kernel, args):
            return
        name = _stage_name(kernel)
        t0 = time.perf_counter()
        with self.changed:
            while self.state[name] == "start" and not self.ended:
                left = self.WAIT_LIMIT - (time.perf_counter() - t0)
                if left <= 0:            # (a helper that hangs: compile it here)
                    self.state[name] = "pending"
                    break
                self.changed.wait(left)
            if self.state[name] != "pending":
                if self.state[name] == "done":
                    logger.info("cdt_plugin: waited %.1f s for the second process's %s",
                                time.perf_counter() - t0, name)
                return
            self.state[name] = "mine"
        try:
            if self.proc is not None and self.proc.stdin is not None:
                self.proc.stdin.write(f"mine {name}\n")
                self.proc.stdin.flush()
        except (OSError, ValueError):      # (it ended)
            pass

    def compiling(self, kernel, args: tuple) -> bool:
        """Whether the helper is compiling ``kernel`` for ``args`` now: a route that
        reaches it links it late instead of waiting (:class:`~cdt_plugin._core.jit.LateStage`)."""
        with self.changed:
            return self._has(kernel, args) and self.state[_stage_name(kernel)] == "start"

    def _has(self, kernel, args: tuple) -> bool:
        """Whether ``kernel`` for ``args`` is one of this process's helper's stages
        (not in a fork of it, not for other argument types)."""
        return (os.getpid() == self.pid and args == kernel.ahead
                and _stage_name(kernel) in self.state)

    def stop(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()


def compile_ahead(names: list[str]) -> None:
    """The helper process: compile each named stage for the argument types its
    route gives it, into the disk cache, saying when it starts and ends each;
    skip those the parent claims (read from stdin) before it gets to them."""
    logging.getLogger("cdt_plugin").setLevel(logging.ERROR)
    claimed: set[str] = set()

    def listen() -> None:
        for line in sys.stdin:
            what, _, name = line.strip().partition(" ")
            if what == "mine":
                claimed.add(name)
    threading.Thread(target=listen, daemon=True).start()
    for name in names:
        if name in claimed:
            continue
        print("start", name, flush=True)
        kernel = _stage(name)
        kernel.compile(kernel.ahead)
        print("done", name, flush=True)


helper = _Helper()
jit.await_helper = helper.wait_for
jit.helper_compiling = helper.compiling


# ------------------------------------------------------------ a cache older than the sources
# numba checks a cached function against its own source file only: a cached route keeps
# the machine code of kernels from other files that have changed since (an upgrade, an
# edit), and would run it. The sources' sizes and times are kept beside the cache; when
# they differ, the engine's cache files are removed before any is loaded.
_MARK = "cdt_plugin-sources.txt"
_PACKAGE = os.path.dirname(os.path.abspath(__file__))


def _source_stamp() -> str:
    names = sorted(n for n in os.listdir(os.path.join(_PACKAGE, "_core")) if n.endswith(".py"))
    files = [os.path.join("_core", n) for n in names]      # every kernel lives in _core
    lines = []
    for rel in files:
        st = os.stat(os.path.join(_PACKAGE, rel))
        lines.append(f"{rel} {st.st_size} {st.st_mtime_ns}")
    return "\n".join(lines) + "\n"


def _cache_path(py_file: str) -> str | None:
    """The directory numba caches ``py_file``'s functions in (its own locators)."""
    from numba.core import caching
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")   # (named so before 0.61)
    for cls in impl._locator_classes:
        locator = cls.from_function(_cache_path, py_file)
        if locator is not None:
            return locator.get_cache_path()
    return None


def drop_stale_cache() -> bool:
    """Remove the engine's numba cache files when the sources changed since they were
    written (see above). Returns whether it removed them. Best effort: a cache it
    cannot read or write is left to numba."""
    try:
        stamp = _source_stamp()
        core = _cache_path(os.path.join(_PACKAGE, "_core", "pipeline.py"))
        if core is None:
            return False
        mark = os.path.join(core, _MARK)
        try:
            with open(mark) as fh:
                if fh.read() == stamp:
                    return False
        except OSError:
            pass
        stale = glob.glob(os.path.join(core, "*.nb[ic]"))
        for path in stale:
            try:
                os.remove(path)
            except OSError:
                pass
        os.makedirs(core, exist_ok=True)
        tmp = f"{mark}.{os.getpid()}"
        with open(tmp, "w") as fh:
            fh.write(stamp)
        os.replace(tmp, mark)        # (atomic: processes starting together read a whole mark)
        return bool(stale)
    except Exception:                # never stop an import over the cache
        return False


drop_stale_cache()


# ------------------------------------------------------------ every route, ahead of time
#: The routes that ``cdt-plugin compile`` compiles, by name (:mod:`cdt_plugin.warmup`
#: runs each one's public calls).
ROUTES = ("delaunay", "weighted", "triangulate", "refine", "split", "batch", "voronoi", "query",
          "dynamic")
