"""How kernels are compiled (cdt_plugin._core.jit): a declared signature is
compiled once, on first use, and every caller's arguments are converted to it;
internal kernels have no CPython wrapper (a Python call goes to a twin that
has one), entries do."""
import os

import numpy as np
from numba import njit, types

import cdt_plugin
from cdt_plugin._core import predicates
from cdt_plugin._core import jit
from cdt_plugin._core.jit import DeclaredKernel, Kernel, entry, kernel
from cdt_plugin._core.prefetch import PREFETCH, prefetch


@kernel("int64(int64)")
def plus_one(e):
    return e + 1


@kernel("float64(float64, float64)")
def half_sum(a, b):
    return (a + b) / 2


@entry("float64(float64, float64)")
def half_difference(a, b):
    return (a - b) / 2


@entry
def times_two(x):
    return 2 * x


@kernel
def times_three(x):
    return 3 * x


@njit
def call_times_three(x):
    return times_three(x) + 1


@njit
def call_with_mixed_types(a):
    # a literal, an int32 and an int64: numba would compile three specialisations
    return plus_one(3) + plus_one(np.int32(a)) + plus_one(a)


def test_kernel_opens_its_disk_cache_on_first_compilation():
    assert isinstance(times_two, Kernel) and not times_two.cache_opened
    assert times_two(np.int64(21)) == 42
    assert times_two.cache_opened and os.path.isdir(times_two.stats.cache_path)


def test_entry_is_called_from_python_with_its_own_compilation():
    assert times_two.twin is None and times_two(np.int64(4)) == 8
    assert times_two.twin is None and times_two.signatures == [(types.int64,)]


def test_internal_kernel_is_compiled_without_wrapper_for_compiled_callers():
    assert not times_three.cache_opened
    assert call_times_three(np.int64(2)) == 7
    assert times_three.cache_opened and times_three.signatures == [(types.int64,)]
    assert times_three.twin is None                  # no Python call yet
    assert times_three.targetoptions["no_cpython_wrapper"]
    assert "no_cpython_wrapper" not in times_two.targetoptions


def test_python_call_of_internal_kernel_goes_to_an_uncached_twin_and_is_recorded():
    before = list(times_three.signatures)
    assert times_three(np.int64(5)) == 15 and times_three(2.5) == 7.5
    twin = times_three.twin
    assert isinstance(twin, Kernel) and "no_cpython_wrapper" not in twin.targetoptions
    assert twin.cache_opened and type(twin._cache).__name__ == "NullCache"   # never cached
    assert sorted(map(str, twin.signatures)) == ["(float64,)", "(int64,)"]
    assert times_three.signatures == before           # the internal compilations are untouched
    assert (f"{__name__}.times_three", os.path.abspath(__file__),
            "test_python_call_of_internal_kernel_goes_to_an_uncached_twin_and_is_recorded") \
        in jit.PYTHON_CALLERS


def test_declared_kernel_compiles_on_first_use_only():
    assert isinstance(half_difference, DeclaredKernel)
    assert half_difference.signatures == []          # nothing compiled at definition
    assert half_difference(3, 2) == 0.5              # from Python: ints converted to float64
    assert half_difference.signatures == [(types.float64, types.float64)]
    assert isinstance(half_sum, DeclaredKernel) and half_sum.signatures == []
    assert half_sum(1, 2) == 1.5                     # internal: its twin, declared too
    assert half_sum.twin.signatures == [(types.float64, types.float64)]
    assert half_sum.signatures == []


def test_declared_kernel_converts_arguments_of_every_caller():
    assert call_with_mixed_types(np.int64(5)) == 4 + 6 + 6
    assert plus_one.signatures == [(types.int64,)]
    assert plus_one(np.int32(7)) == 8 and plus_one(True) == 2
    assert plus_one.signatures == [(types.int64,)]


def test_predicates_compile_once_and_take_integers_as_doubles():
    cdt_plugin.triangulate([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]],
                           min_angle=25)
    cdt_plugin.delaunay(np.random.default_rng(1).random((50, 2)), weights=np.zeros(50))
    declared = [k for k in vars(predicates).values() if isinstance(k, DeclaredKernel)]
    assert len(declared) >= 30
    assert all(len(k.signatures) <= 1 for k in declared)
    assert predicates.orient2d(0, 0, 1, 0, 0, 1) == predicates.orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) > 0
    assert len(predicates.orient2d.signatures) == 1


def test_kernels_compile_with_flags_read_once_and_equal_to_numbas():
    from numba.core.compiler import Flags
    assert type(times_two._compiler) is jit._KernelCompiler      # (entries and kernels alike)
    assert type(times_three._compiler) is jit._KernelCompiler
    plain = Flags()
    times_two.targetdescr.options.parse_as_flags(plain, times_two.targetoptions)
    flags = times_two._compiler._customize_flags(Flags(plain))
    assert type(flags) is jit.KernelFlags and flags.nrt and flags.release_gil
    assert flags == plain and plain == flags and hash(flags) == hash(plain)
    copy = jit.KernelFlags(flags)
    assert copy == flags and hash(copy) == hash(flags)
    copy.boundscheck = not flags.boundscheck             # setting an option: read anew
    assert copy != flags and copy != plain
    copy.discard("boundscheck")
    assert copy == flags
    copy.nrt = False
    assert copy != flags
    del copy.nrt                                         # back to numba's default (no NRT)
    assert not copy.nrt and copy != flags and copy == Flags(copy)


def test_kernels_write_their_disk_cache_one_process_at_a_time(tmp_path):
    """A process that compiles a kernel waits for the lock of the cache directory
    before writing the cache (numba's index and data files), and writes it once
    the lock is free."""
    import subprocess
    import sys
    (tmp_path / "locked_kernel.py").write_text(
        "from cdt_plugin._core.jit import entry\n\n\n@entry\ndef plus_one(x):\n    return x + 1\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}

    def run(code):
        return subprocess.Popen([sys.executable, "-c", f"import locked_kernel as m; {code}"],
                                env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    out, err = run("m.plus_one.enable_caching(); print(m.plus_one._cache.cache_path)").communicate(timeout=300)
    directory = out.strip()
    assert directory, err
    with jit.cache_lock(directory) as locked:
        assert locked
        child = run("print(m.plus_one(41))")
        try:
            child.wait(timeout=10)          # (compiling one line takes well under a second)
        except subprocess.TimeoutExpired:
            pass
        assert child.poll() is None, child.communicate()
        assert not [n for n in os.listdir(directory) if n.endswith((".nbi", ".nbc"))]
    out, err = child.communicate(timeout=300)
    assert child.returncode == 0 and out.strip() == "42", err
    assert [n for n in os.listdir(directory) if "plus_one" in n and n.endswith(".nbi")]
    assert jit.LOCK_NAME in os.listdir(directory)
    loaded = run("print(m.plus_one(1), sum(m.plus_one.stats.cache_hits.values()))")
    out, err = loaded.communicate(timeout=300)
    assert out.split() == ["2", "1"], err             # a new process loads what it wrote


APART_MODULE = '''
import numpy as np
from cdt_plugin._core.jit import F8, entry, f8, kernel


@kernel(apart=True, ahead=(F8,), returns=f8)
def total(a):
    s = 0.0
    for v in a:
        s += v
    return s


@entry
def twice_total(a):
    return 2.0 * total(a)
'''

APART_REPORT = '''
import json, numpy as np
import apart_kernels as m
from cdt_plugin._core import jit
value = m.twice_total(np.arange(4.0))
stage = next(iter(m.total.overloads.values()))
caller = next(iter(m.twice_total.overloads.values()))
symbol = stage.fndesc.mangled_name
print(json.dumps({"value": value, "uid": stage.fndesc.uid,
                  "caller_defines": [f.name for f in caller.library._final_module.functions
                                     if not f.is_declaration and f.name == symbol],
                  "needs": [s[3] for s in jit.needed_stages(caller.library)], "symbol": symbol,
                  "hits": [sum(k.stats.cache_hits.values()) for k in (m.total, m.twice_total)],
                  "misses": [sum(k.stats.cache_misses.values()) for k in (m.total, m.twice_total)]}))
'''


def _run_child(tmp_path, code, module=APART_MODULE):
    """``code`` run in a new process that imports ``module`` as ``apart_kernels``,
    with its own numba cache (kept between runs in ``tmp_path``)."""
    import subprocess
    import sys
    (tmp_path / "apart_kernels.py").write_text(module)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=300, check=False)


def _run_apart(tmp_path, code, module=APART_MODULE):
    """The JSON ``code`` prints last, run by :func:`_run_child` (which must succeed)."""
    import json
    proc = _run_child(tmp_path, code, module)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_stage_compiled_apart_is_called_by_a_symbol_every_process_names_alike(tmp_path):
    """A kernel declared apart is compiled once: its caller's library declares it
    and calls it by its symbol (numba would link and code-generate it again), the
    symbol carries the fixed number, not a per-process count, and the caller's
    cache entry lists it; a new process loads both from the cache."""
    first = _run_apart(tmp_path, APART_REPORT)
    assert first["value"] == 12.0 and first["uid"] == jit.APART_UID
    assert first["caller_defines"] == [] and first["needs"] == [first["symbol"]]
    assert first["misses"] == [1, 1] and first["hits"] == [0, 0]
    second = _run_apart(tmp_path, APART_REPORT)
    assert second["value"] == 12.0 and second["symbol"] == first["symbol"]
    assert second["hits"] == [1, 1] and second["misses"] == [0, 0]


def test_cached_caller_whose_stage_symbol_is_missing_compiles_again(tmp_path):
    """Where a stage's symbol is not defined once the stages are loaded, the caller's
    cache entry is not loaded (LLVM would stop the process on the unresolved
    symbol): it compiles again."""
    _run_apart(tmp_path, APART_REPORT)
    patch = ("from llvmlite import binding as ll\n"
             "ll.address_of_symbol = lambda name: None\n")
    out = _run_apart(tmp_path, patch + APART_REPORT)
    assert out["value"] == 12.0
    assert out["hits"] == [1, 0] and out["misses"] == [0, 1]


LATE_REPORT = '''
import json, numpy as np
import apart_kernels as m
from cdt_plugin._core import jit
jit.helper_compiling = lambda kernel, args: kernel is m.total    # (as while a helper compiles it)
seen = []
load_late_stages = jit.load_late_stages
def spy():
    seen.extend((s.kernel.py_func.__name__, s.loaded, type(m.total.overloads[s.args]).__name__)
                for s in jit.LATE)
    load_late_stages()
jit.load_late_stages = spy
value = m.twice_total(np.arange(4.0))
stage = m.total.overloads[(jit.F8,)]
caller = next(iter(m.twice_total.overloads.values()))
module = caller.library._final_module
pointer = jit.pointer_name("apart_kernels", "total", (jit.F8,))
print(json.dumps({"value": value, "late": seen, "left": len(jit.LATE),
                  "pointer_in_caller": any(g.name == pointer for g in module.global_variables),
                  "caller_names_stage": any(f.name == stage.fndesc.mangled_name for f in module.functions),
                  "needs": [s[3] for s in jit.needed_stages(caller.library)], "pointer": pointer,
                  "hits": [sum(k.stats.cache_hits.values()) for k in (m.total, m.twice_total)],
                  "misses": [sum(k.stats.cache_misses.values()) for k in (m.total, m.twice_total)]}))
'''


def test_stage_the_helper_is_compiling_is_linked_late_and_loaded_before_its_caller_runs(tmp_path):
    """A caller typed while the helper process compiles its stage does not wait: it
    calls the stage through the stage's pointer, and the stage is loaded before the
    caller can be called from Python (here compiled in this process: no helper). Its
    cache entry lists the pointer; a new process loads caller and stage, and the
    pointer is filled there too."""
    first = _run_apart(tmp_path, LATE_REPORT)
    assert first["late"] == [["total", False, "LateStage"]] and first["left"] == 0
    assert first["value"] == 12.0
    assert first["pointer_in_caller"] and not first["caller_names_stage"]
    assert first["needs"] == [first["pointer"]]
    assert first["misses"] == [1, 1]
    second = _run_apart(tmp_path, APART_REPORT)     # (no helper: nothing is linked late)
    assert second["value"] == 12.0 and second["hits"] == [1, 1] and second["misses"] == [0, 0]


FAILED_LOAD = '''
import json, numpy as np
import apart_kernels as m
from cdt_plugin._core import jit
jit.helper_compiling = lambda kernel, args: kernel is m.total    # (as while a helper compiles it)
def fail(sig):
    raise RuntimeError("no stage")
m.total.compile = fail                  # (the stage cannot be loaded or compiled)
said = []
for _ in range(2):
    try:
        m.twice_total(np.arange(4.0))
    except RuntimeError as exc:
        said.append(str(exc))
del m.total.compile
print(json.dumps({"said": said, "value": m.twice_total(np.arange(4.0)), "left": len(jit.LATE)}))
'''


def test_callers_of_a_stage_that_fails_to_load_do_not_run(tmp_path):
    """While a stage linked late cannot be loaded, no entry compiled meanwhile is
    published: each call raises the error again (none runs a caller whose pointer
    leads nowhere); once it loads, they run."""
    out = _run_apart(tmp_path, FAILED_LOAD)
    assert out["said"] == ["no stage", "no stage"]
    assert out["value"] == 12.0 and out["left"] == 0


def test_stage_linked_late_that_compiles_here_may_publish_the_entries_it_calls(tmp_path):
    """When the helper fails, the route compiles the stage linked late itself, just
    before its own entry is published; an entry the stage calls is published in
    that compilation, and must not load the stage again (numba would refuse to
    compile it re-entrantly)."""
    nested = APART_MODULE.replace('''    s = 0.0
    for v in a:''', '''    s = first(a) - a[0]
    for v in a:''') + '''

@entry
def first(a):
    return a[0]
'''
    out = _run_apart(tmp_path, LATE_REPORT, nested)
    assert out["value"] == 12.0 and out["late"] == [["total", False, "LateStage"]] and out["left"] == 0


def test_stage_pointer_leads_to_an_error_until_the_stage_is_loaded():
    """A stage's pointer is never null: until the stage is loaded it leads to
    numba's function for unresolved calls (a call raises), then to the stage."""
    from numba.core.runtime import rtsys
    pointer = jit.stage_pointer(jit.pointer_name(__name__, "nothing", (types.int64,)))
    assert pointer.value == rtsys.library.get_pointer_to_function("nrt_unresolved_abort")


def test_stage_linked_late_must_return_what_it_declares(tmp_path):
    """A stage whose declared ``returns`` is not the type numba infers is refused when
    it is loaded (its callers were typed against the declaration)."""
    wrong = (APART_MODULE.replace("returns=f8", "returns=types.int64")
             .replace("import numpy as np", "import numpy as np\nfrom numba import types"))
    code = ("import numpy as np, apart_kernels as m\nfrom cdt_plugin._core import jit\n"
            "jit.helper_compiling = lambda kernel, args: True\nm.twice_total(np.arange(4.0))\n")
    proc = _run_child(tmp_path, code, wrong)
    assert proc.returncode != 0 and "total returns float64, not its declared returns=int64" in proc.stderr


def test_load_stages_says_whether_each_symbol_is_defined():
    stage = (__name__, "plus_one", (types.int64,), "no such symbol")
    assert jit.load_stages(()) and not jit.load_stages((stage,))


def test_an_entry_cannot_be_compiled_apart():
    import pytest
    with pytest.raises(TypeError, match="cannot be compiled apart"):
        entry(apart=True)(lambda x: x)


def test_routes_come_from_the_cache_without_numbas_compiler_set_up():
    """A new process whose routes all come from the cache does not set up numba's
    compiler (refreshing its registries imports all of numba's implementations, and
    scipy to probe for BLAS: 0.1-0.2 s of such a process): cached code needs numba's
    runtime only, and no kernel calls numba's array maths (its cached code would
    import them all the same)."""
    import json
    import subprocess
    import sys

    from cdt_plugin.warmup import compile_routes
    compile_routes()          # (the cache filled, as by `cdt-plugin compile`)
    code = ("import json, sys\nfrom cdt_plugin.warmup import compile_routes\ncompile_routes()\n"
            "print(json.dumps([m for m in ('numba.np.arraymath', 'numba.np.linalg') if m in sys.modules]))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                          check=False)
    assert proc.returncode == 0, proc.stderr
    assert "compiling" not in proc.stderr, proc.stderr        # every route loaded
    assert json.loads(proc.stdout.strip().splitlines()[-1]) == []


@njit
def prefetch_then_sum(a):
    total = 0.0
    for i in range(a.shape[0]):
        prefetch(a, min(i + 8, a.shape[0] - 1))
        total += a[i]
    return total


def test_prefetch_is_a_hint_that_changes_no_value():
    a = np.arange(100.0)
    assert prefetch_then_sum(a) == 4950.0 and (a == np.arange(100.0)).all()
    if PREFETCH is not None:             # (this LLVM emits it: it is in the code)
        llvm = next(iter(prefetch_then_sum.inspect_llvm().values()))
        assert "llvm.prefetch" in llvm
