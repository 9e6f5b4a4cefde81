"""How every kernel is compiled, and what keeps first use short.

:func:`kernel` is ``numba.njit`` with the options every kernel shares: cached
on disk (the cache opened when the kernel is first compiled or loaded,
:class:`Kernel`), no C-callable wrapper (nothing here takes a kernel's address, and
numba would otherwise lower and code-generate one for every compilation), no
CPython wrapper (only compiled code calls it), and without the GIL. An
:func:`entry` is a kernel that Python code calls (the routes, and what the
public modules call directly): it has numba's CPython wrapper, which unboxes
the arguments and releases the GIL on entry, so threads run entries side by
side (nothing in a kernel touches Python objects or shared state: every
workspace is allocated per call). Lowering, optimising and code-generating a
wrapper for each of the ~200 internal kernels was about a tenth of first use.
A test may call an internal kernel from Python all the same: the call goes to
a twin compiled with the wrapper, not cached (:meth:`Kernel._compile_for_args`);
every such call is recorded in :data:`PYTHON_CALLERS`, where the test suite
requires that none comes from outside the tests (an entry not marked as one).
Kernels compile with :class:`KernelFlags`, numba's flags with their values read
once (numba reads them all at every typed call of an overloaded function), and
processes write their disk cache one at a time (:class:`LockedCache`).

numba compiles a function once per distinct tuple of argument types, and links
every callee's code into each caller's library, where it is optimised and
code-generated again. So, in the kernels:

* call kernels with typed values, not literals: ``f(a, 0)`` and ``f(a, 1)``
  compile ``f`` twice (``np.int64(0)``, ``np.bool_(False)`` or a variable do not,
  but a variable that holds a literal on one path does: ``lo = 0`` before a loop
  that sets ``lo = start[s]`` compiled ``sort_ids`` once more);
  a small kernel that many callers give mixed integer types (``int32`` from the
  store, ``int64``, literals) declares its signature instead (``@kernel("void(int32[::1],
  int64)")``: a :class:`DeclaredKernel`, compiled once, arguments converted);
* the large stages that run once per call are compiled apart (``apart=True``,
  see "stages compiled apart" below: callers link a declaration and call them by
  symbol): the route itself (``pipeline.cdt_route``, which its two entries, one
  call from Python and the batch loop, would otherwise each link whole), the
  Delaunay construction (``construct.build_mesh``), segment insertion
  (``pipeline.insert_all_segments``), refinement (``refine.refine_store``), the
  domain (``pipeline.classify``), the output arrays (``output.cdt_arrays``),
  divide and conquer
  (``divide.guibas_stolfi``, ``divide.store_subdivision``) and the exact
  predicates' slow stages (:mod:`.predicates`), so that callers link the fast
  filter only; one that the helper process of a first use is compiling is linked
  late (``returns=`` its declared return type: see "stages linked late" below);
* the other intermediate stages with a single caller (``build``,
  ``insert_vertices``, ``insert_one``, ``refine_run``, ``route_points``) are
  ``inline="always"``, so that the kernels below them are not code-generated
  once more for them. Small helpers are not: numba
  copies and re-types an inlined function's IR at each call site, which costs
  more than compiling it once (inlining every kernel with a single caller made
  first use 50% slower). Those in hot loops are ``forceinline=True`` instead
  (compiled once; LLVM inlines them at every call site): the quad-edge helpers
  of :mod:`.divide`, whose ~150 numba-inlined call sites cost 3 s of a first
  ``delaunay``, and left as plain calls made it 5% slower; so is
  ``kernel.orient`` (37 call sites), with a declared signature. The other
  helpers of the insertion and flip loops (``lifted_test``,
  ``edge_is_illegal``, ``mesh.flip``, ``locate``'s steps) stay
  ``inline="always"``: with ``forceinline`` a 50,000-vertex polygon took 5%
  longer (numba folds their literal arguments before LLVM sees them);
* copy with loops (:func:`.arrays.copy_rows`), not slice assignment, which
  compiles numba's broadcasting and its string-formatted errors.
"""
from __future__ import annotations

import contextlib
import ctypes
import hashlib
import importlib
import itertools
import os
import pickle
import sys
from typing import Callable, Iterator

from llvmlite import binding as ll
from llvmlite import ir as llvmir
from numba import types
from numba.core import cgutils, sigutils, typing
from numba.core.bytecode import FunctionIdentity
from numba.core.caching import FunctionCache
from numba.core.compiler import Flags
from numba.core.compiler_lock import global_compiler_lock
from numba.core.dispatcher import _FunctionCompiler
from numba.core.registry import CPUDispatcher, cpu_target
from numba.core.runtime import rtsys

_OPTIONS = {"nopython": True, "no_cfunc_wrapper": True, "nogil": True}

# numba's types of the scalars and C-contiguous arrays kernels take, for the argument
# types they declare
i8, f8, b1 = types.int64, types.float64, types.boolean
I32, I64, I64_2, F8, F8_2, B1 = (types.int32[::1], types.int64[::1], types.int64[:, ::1],
                                 types.float64[::1], types.float64[:, ::1], types.boolean[::1])
I8, B1_2 = types.int8[::1], types.boolean[:, ::1]
Tuple = types.Tuple           # (a stage's declared return type: ``returns=Tuple((i8, I64))``)
# the half-edge store as stages hand it back: tri, twin, cons, x, y, w, ntri, n, cap
STORE = types.Tuple((I32, I32, I32, F8, F8, F8, i8, i8, i8))

# (kernel, calling file, calling function) of every Python call of an internal kernel
PYTHON_CALLERS: set[tuple[str, str, str]] = set()


def kernel(*signature, **options):
    """Decorator: a compiled kernel that compiled code calls,
    ``numba.njit(cache=True, no_cfunc_wrapper=True, no_cpython_wrapper=True,
    nogil=True, **options)`` (a :class:`Kernel`); with a signature, a
    :class:`DeclaredKernel` of it. ``ahead=`` a tuple of numba types: the
    arguments its route calls it with (:attr:`Kernel.ahead`); ``returns=`` the
    numba type it returns for them (:attr:`Kernel.returns`)."""
    return _decorator(signature, {**_OPTIONS, "no_cpython_wrapper": True, **options})


def entry(*signature, **options):
    """Decorator: a kernel that Python code calls (:func:`kernel` with numba's
    CPython wrapper)."""
    if options.get("apart"):
        # (numba finds a cached entry's CPython wrapper through the definitions of the
        # code it links into callers, which for a stage compiled apart are none)
        raise TypeError("an entry cannot be compiled apart: make it a kernel that an entry calls")
    return _decorator(signature, {**_OPTIONS, **options})


def _decorator(signature, options):
    if len(signature) == 1 and callable(signature[0]) and not hasattr(signature[0], "args"):
        return _decorator((), options)(signature[0])          # bare @kernel
    ahead = options.pop("ahead", None)
    returns = options.pop("returns", None)
    apart = options.pop("apart", False)
    if apart:       # (numba would otherwise take these from the first caller: see APART_OPTIONS)
        options = {**APART_OPTIONS, **options}

    def make(py_func):
        if not signature:
            compiled = Kernel(py_func=py_func, locals={}, targetoptions=options)
        else:
            compiled = DeclaredKernel(py_func=py_func, locals={}, targetoptions=options)
            compiled.declared = signature
        compiled.ahead, compiled.returns = ahead, returns
        compiled.apart = compiled._compiler.apart = apart
        return compiled
    return make


# Called with a kernel that has ``ahead`` argument types and the signature it is asked
# for, before it compiles: waits while a helper process compiles it, or claims it
# (set by :mod:`cdt_plugin.compiling`).
await_helper: Callable[[Kernel, tuple], None] | None = None
# Whether a helper process is compiling this kernel for these argument types now (set by
# :mod:`cdt_plugin.compiling`): a stage compiled apart is then linked late (:class:`LateStage`).
helper_compiling: Callable[[Kernel, tuple], bool] | None = None


class KernelFlags(Flags):
    """numba's compile flags, with their values read once. While a function
    compiles, numba looks up every typed call of an overloaded function
    (``np.empty``, ``len``, ``min``, ...) in a cache keyed by the flags of that
    function, hashing and comparing them anew each time: reading each of ~45
    options, some 100,000 times in a first use (about 7% of it). Here the values
    are read once, until an option is set; hash and equality are numba's."""

    __slots__ = ("_memo",)

    def _snapshot(self) -> dict:
        try:
            return self._memo
        except AttributeError:
            memo = self.values()
            object.__setattr__(self, "_memo", memo)
            return memo

    def _forget(self) -> None:
        try:
            object.__delattr__(self, "_memo")
        except AttributeError:
            pass

    def __setattr__(self, name, value):
        self._forget()
        super().__setattr__(name, value)

    def __delattr__(self, name):
        self._forget()
        super().__delattr__(name)

    def discard(self, name):
        self._forget()
        super().discard(name)

    def __hash__(self):
        return _FLAGS_HASH

    def __eq__(self, other):
        if isinstance(other, KernelFlags):
            return self is other or self._snapshot() == other._snapshot()
        return super().__eq__(other)


_FLAGS_HASH = hash(Flags())     # numba's hash of any flags (of the option names)


class _KernelCompiler(_FunctionCompiler):
    """numba's compiler of a dispatcher's function, with :class:`KernelFlags`;
    for a kernel compiled apart, under a symbol that is the same in every process."""

    apart = False

    def _customize_flags(self, flags):
        return KernelFlags(super()._customize_flags(flags))

    def _compile_core(self, args, return_type):
        if not self.apart:
            return super()._compile_core(args, return_type)
        # numba names a compilation after the function, its argument types and a
        # number it counts per process; the first number drawn is the function's own
        counter = FunctionIdentity._unique_ids
        FunctionIdentity._unique_ids = itertools.chain([APART_UID], counter)
        try:
            return super()._compile_core(args, return_type)
        finally:
            FunctionIdentity._unique_ids = counter


class LockedCache(FunctionCache):
    """numba's disk cache of a kernel, written by one process at a time (an
    exclusive lock on a file in the cache directory; reading takes none).
    numba saves a compilation by reading the function's index, naming a data
    file after the entries it found, writing the index and then that file. Two
    processes that compile different signatures of one function at once (cold
    Dask workers, a process pool, parallel test workers) can pick the same data
    file, and leave an index entry that names the other signature's machine
    code, which a later process would load and run (numba issue #10128 reports
    the segmentation faults). A reader never sees a half-written file: numba
    replaces each one whole. Each entry also lists the stages compiled apart that
    its code calls, which are loaded first (see "stages compiled apart" below)."""

    def load_overload(self, sig, target_context):
        # numba refreshes the target's registries before each load, which the first
        # time imports all of numba's implementations (and scipy, to probe for BLAS):
        # 0.1-0.2 s of a new process whose routes all come from the cache. Cached code
        # needs numba's runtime only; a compilation refreshes the registries itself.
        rtsys.initialize(target_context)
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)

    def _save_overload(self, sig, data):
        if not self._enabled or not self._impl.check_cachable(data):
            return
        self._impl.locator.ensure_cache_path()
        key = self._index_key(sig, data.codegen)
        payload = (_STAGES_TAG, needed_stages(data.library), self._impl.reduce(data))
        with cache_lock(self._cache_path):
            self._cache_file.save(key, payload)

    def _load_overload(self, sig, target_context):
        if not self._enabled:
            return None
        data = self._cache_file.load(self._index_key(sig, target_context.codegen()))
        if not (isinstance(data, tuple) and len(data) == 3 and data[0] == _STAGES_TAG):
            return None
        _, stages, payload = data
        if not load_stages(stages):
            return None
        cres = self._impl.rebuild(target_context, payload)
        cres.library._cdt_stages = stages
        return cres


# ------------------------------------------------------------ stages compiled apart
# numba links the code of every kernel a function calls into that function's library,
# where LLVM optimises and code-generates it again: the route's library held every
# stage's code a second time, and each entry that calls the route a third. A kernel
# declared ``apart=True`` (a large stage that runs once per call) is compiled once:
# its callers link a declaration of it and call it by its symbol, which is registered
# with LLVM when it is compiled or loaded. The symbol is the same in every process
# (numba's per-process number in it is fixed, :data:`APART_UID`), so code cached by
# one process calls a stage compiled by another (the helper process of a first use).
# A cache entry lists the stages its code calls (:func:`needed_stages`); they are
# loaded before it, and an entry whose stage symbol is missing is compiled again
# rather than loaded (LLVM would stop the process on an unresolved symbol). So code
# that calls a stage is cached by a :class:`Kernel` only: numba's own ``cache=True``
# would load it without its stages (the tests' compiled loops are entries too).
APART_UID = 0            # (numba counts from 1)
# The options a callee takes from the function compiling it unless it sets them (numba's
# CPU target): a stage compiled apart sets them, so that it compiles alike whoever
# calls it first (an ``_nrt=False`` caller would deny its allocations reference counting).
APART_OPTIONS = {"_nrt": True, "fastmath": False, "error_model": "python", "forceinline": False}
_STAGES_TAG = "cdt_plugin-stages-1"      # the form of a cache entry: (tag, stages, numba's data)


def needed_stages(library) -> tuple:
    """The stages compiled apart that ``library``'s code calls, at any depth:
    ``(module, qualname, argument types, symbol)`` each."""
    got = getattr(library, "_cdt_stages", None)
    if got is not None:
        return got
    found = {}
    for lib in getattr(library, "_linking_libraries", ()):
        stage = getattr(lib, "_cdt_stage", None)
        if stage is not None:
            found[stage[3]] = stage
        for each in needed_stages(lib):
            found[each[3]] = each
    library._cdt_stages = tuple(found.values())
    return library._cdt_stages


def kernel_at(module: str, qualname: str) -> Kernel:
    """The kernel defined as ``qualname`` in ``module`` (imported if need be)."""
    found = importlib.import_module(module)
    for part in qualname.split("."):
        found = getattr(found, part)
    return found


def load_stages(stages) -> bool:
    """Load (or compile) each stage; whether every one's symbol is then defined."""
    for module, qualname, args, symbol in stages:
        kernel_at(module, qualname).compile(args)
        if not ll.address_of_symbol(symbol):
            return False
    return True


def expose(cres) -> None:
    """A stage compiled apart, just compiled or loaded: callers link a declaration
    of it only, and its symbol is registered with LLVM."""
    lib, fndesc = cres.library, cres.fndesc
    name = fndesc.mangled_name
    if getattr(lib, "_cdt_stage", None) is None:
        # (a stage loaded from the cache has its declaration already: numba's cached bitcode)
        if lib._shared_module is None:
            ctx = cres.target_context
            mod = ctx.codegen()._create_empty_module(name)
            fnty = ctx.call_conv.get_function_type(fndesc.restype, fndesc.argtypes)
            cgutils.get_or_insert_function(mod, fnty, name)
            lib._shared_module = ll.parse_assembly(str(mod))
        lib._cdt_stage = (fndesc.modname, fndesc.qualname, tuple(cres.signature.args), name)
    # (numba's own lookup says 0 for code loaded from the cache)
    address = lib.codegen._engine.get_function_address(name)
    ll.add_symbol(name, address)
    # (callers linked late call it through its pointer)
    stage_pointer(pointer_name(fndesc.modname, fndesc.qualname, cres.signature.args)).value = address


# ------------------------------------------------------------ stages linked late
# A caller needs a stage's code only when it runs: its typing needs the stage's
# signature, and its code can call the stage through a pointer that is filled in later
# (as numba calls a function recursively). So when a route reaches a stage compiled
# apart that the helper process is compiling (a first use), it does not wait: it is
# typed against the stage's declared return type (``returns=``), calls the stage
# through the stage's pointer (a :class:`LateStage`) and goes on compiling. The stage
# is loaded (waited for, or compiled here if the helper failed) before any entry
# compiled meanwhile can be called (:func:`load_late_stages`). Every stage compiled
# apart has its pointer (:func:`pointer_name`), filled when it is compiled or loaded, so
# code cached by a caller linked late finds it in any later process.

def pointer_name(module: str, qualname: str, args: tuple) -> str:
    """The symbol of the pointer to a stage's code for argument types ``args``."""
    digest = hashlib.sha1(repr(tuple(args)).encode()).hexdigest()[:16]
    return f"cdt_plugin.stage${module}.{qualname}${digest}"


_POINTERS: dict[str, ctypes.c_void_p] = {}     # symbol -> the pointer's memory


def stage_pointer(name: str) -> ctypes.c_void_p:
    """The pointer ``name``, registered with LLVM the first time; until the stage
    is loaded it leads to numba's function for unresolved calls, which raises
    ``RuntimeError`` in its caller."""
    pointer = _POINTERS.get(name)
    if pointer is None:
        rtsys.initialize(cpu_target.target_context)     # (done already when compiling or loading)
        unresolved = rtsys.library.get_pointer_to_function("nrt_unresolved_abort")
        pointer = _POINTERS[name] = ctypes.c_void_p(unresolved)
        ll.add_symbol(name, ctypes.addressof(pointer))
    return pointer


class LateStage:
    """Stands for the compilation of a stage compiled apart that another process is
    compiling: what numba's typing and lowering of a caller read of a compilation
    (its signature, the key and the code of its call), made from the stage's declared
    types. :meth:`load` loads the stage itself."""

    objectmode = False

    def __init__(self, kernel: Kernel, args: tuple):
        self.kernel, self.args = kernel, args
        self.signature = typing.signature(kernel.returns, *args)
        func = kernel.py_func
        self.pointer = pointer_name(func.__module__, func.__qualname__, args)
        stage_pointer(self.pointer)
        self.entry_point = self.library = self       # (numba's key of the call; what callers link)
        # (a caller's cache entry lists it; a later process loads it first, and its pointer)
        self._cdt_stage = (func.__module__, func.__qualname__, args, self.pointer)
        self._linking_libraries: tuple = ()
        self._reload_init: set = set()
        self.loaded = False
        kernel.targetctx._defns[self].append(self.lower_call, args)
        LATE.append(self)

    def lower_call(self, context, builder, sig, args):
        """A call of the stage in a caller's code: through its pointer."""
        context.add_linking_libs([self])
        fnty = context.call_conv.get_function_type(sig.return_type, sig.args)
        try:
            cell = builder.module.get_global(self.pointer)
        except KeyError:
            cell = llvmir.GlobalVariable(builder.module, fnty.as_pointer(), name=self.pointer)
            cell.linkage = "external"
        status, result = context.call_conv.call_function(builder, builder.load(cell), sig.return_type,
                                                         sig.args, args)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return result

    def _ensure_finalized(self) -> None:
        pass                                  # (nothing to finalise: callers link no code of it)

    def _get_module_for_linking(self):
        return ll.parse_assembly("")

    def load(self) -> None:
        """Load the stage (after waiting for the helper) or compile it, in place of this
        stand-in; its pointer then leads to it."""
        if self.loaded:
            return
        kernel, args = self.kernel, self.args
        if kernel.overloads.get(args) is self:
            del kernel.overloads[args]
        kernel.compile(args)
        got = kernel.overloads[args].signature.return_type
        if got != kernel.returns:
            raise TypeError(f"{kernel.py_func.__qualname__} returns {got}, not its declared "
                            f"returns={kernel.returns}")
        self.loaded = True


# stages linked late and not loaded yet
LATE: list[LateStage] = []


def load_late_stages() -> None:
    """Load every stage linked late (before code that calls one runs). A stage
    compiled here may publish entries it calls meanwhile: they load the others."""
    while LATE:
        stage = LATE.pop(0)
        try:
            stage.load()
        except BaseException:
            LATE.insert(0, stage)         # (still pending: no entry is published)
            raise


LOCK_NAME = "cdt_plugin.lock"


@contextlib.contextmanager
def cache_lock(directory: str) -> Iterator[bool]:
    """Holds the exclusive lock of the cache ``directory`` (yields True), or,
    where the file cannot be locked (a read-only cache, a file system without
    locks), yields False and lets numba write as it would alone."""
    try:
        os.makedirs(directory, exist_ok=True)
        handle = open(os.path.join(directory, LOCK_NAME), "a+b")
    except OSError:
        yield False
        return
    with handle:
        try:
            _lock(handle)
        except OSError:
            yield False
            return
        try:
            yield True
        finally:
            _unlock(handle)


if os.name == "nt":
    import msvcrt

    def _lock(handle) -> None:
        handle.seek(0)
        msvcrt.locking(handle.fileno(), msvcrt.LK_LOCK, 1)   # (retries for 10 s, then OSError)

    def _unlock(handle) -> None:
        handle.seek(0)
        msvcrt.locking(handle.fileno(), msvcrt.LK_UNLCK, 1)
else:
    import fcntl

    def _lock(handle) -> None:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX)

    def _unlock(handle) -> None:
        fcntl.flock(handle.fileno(), fcntl.LOCK_UN)


class Kernel(CPUDispatcher):
    """``numba.njit(cache=True)`` whose disk cache (a :class:`LockedCache`) is
    opened when it is first compiled or loaded, not when it is defined: a
    process whose routes load
    from the cache never opens the caches of the ~300 kernels inside them
    (their cached code contains them), about 15 ms of ``import cdt_plugin``.
    Without the CPython wrapper, its compilations are kept from numba's
    dispatch of Python calls, which go to :attr:`twin` instead."""

    cache_opened = False
    twin: Kernel | None = None      # the same function with the wrapper, for Python calls
    # the argument types its route calls it with, which a helper process compiles it
    # for while the route compiles (a first use, :mod:`cdt_plugin.compiling`); a caller
    # with other types compiles it for those
    ahead: tuple | None = None
    returns = None          # the type it returns for ``ahead`` (a stage that can be linked late)
    apart = False

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if type(self._compiler) is _FunctionCompiler:
            self._compiler.__class__ = _KernelCompiler

    def enable_caching(self):
        self._cache = LockedCache(self.py_func)

    def compile(self, sig):
        with global_compiler_lock:   # (reentrant: numba's own compile takes it too)
            late = self.overloads.get(tuple(sigutils.normalize_signature(sig)[0]))
            if isinstance(late, LateStage):
                late.load()
            if self.ahead is not None and await_helper is not None and not self.overloads:
                await_helper(self, sig)
            self.open_cache()
            return super().compile(sig)

    def get_call_template(self, args, kws):
        """numba's typing of a call from compiled code, which compiles the kernel for
        the call's types (or loads it); a stage that the helper process is compiling
        is linked late instead (:class:`LateStage`)."""
        if not self.apart or self.returns is None:
            return super().get_call_template(args, kws)
        pysig, folded = self._compiler.fold_argument_types(args, kws)
        folded = tuple(folded)
        with global_compiler_lock:
            late = self.overloads.get(folded)
            if (late is None and not self.overloads and helper_compiling is not None
                    and helper_compiling(self, folded)):
                late = self.overloads[folded] = LateStage(self, folded)
        if not isinstance(late, LateStage):
            return super().get_call_template(args, kws)
        name = self.py_func.__name__      # (numba's template, without compiling)
        template = typing.make_concrete_template(f"CallTemplate({name})", key=name,
                                                 signatures=self.nopython_signatures)
        return template, pysig, folded, {}

    def open_cache(self) -> None:
        if not self.cache_opened:
            self.cache_opened = True
            self.enable_caching()

    def in_cache(self, sig) -> bool:
        """Whether the disk cache holds a compilation for the argument types ``sig``
        (read from its index; nothing is loaded)."""
        self.open_cache()
        try:
            key = self._cache._index_key(sig, self.targetctx.codegen())
            return key in self._cache._cache_file._load_index()
        except (OSError, EOFError, ValueError, AttributeError, pickle.UnpicklingError):
            return False         # (an unreadable index, numba's internals changed: as not there)

    @property
    def for_python(self) -> bool:
        return not self.targetoptions.get("no_cpython_wrapper")

    def add_overload(self, cres):
        if self.apart:
            expose(cres)
        if self.for_python:
            load_late_stages()    # (before Python can call it: its code may call one)
        if self.for_python:
            super().add_overload(cres)
        else:   # (numba's C dispatcher would call the missing wrapper)
            self.overloads[tuple(cres.signature.args)] = cres

    def _compile_for_args(self, *args, **kws):
        """A call from Python that numba's dispatcher has no compilation for:
        compiled as numba does for an entry; for an internal kernel, handed to
        its twin (which numba then calls with the arguments)."""
        if self.for_python:
            return super()._compile_for_args(*args, **kws)
        caller = sys._getframe(1).f_code
        PYTHON_CALLERS.add((f"{self.py_func.__module__}.{self.py_func.__qualname__}",
                            os.path.abspath(caller.co_filename), caller.co_name))
        with global_compiler_lock:
            if self.twin is None:
                options = {k: v for k, v in self.targetoptions.items() if k != "no_cpython_wrapper"}
                twin = type(self)(py_func=self.py_func, locals={}, targetoptions=options)
                twin.cache_opened = True     # (its cache files would be this kernel's)
                twin.declared = getattr(self, "declared", ())
                self.twin = twin
        return self.twin


class DeclaredKernel(Kernel):
    """A kernel compiled for its declared signature only, as
    ``numba.njit(signature)``, but on first use rather than when its module is
    imported: a new process whose routes all load from the cache then never
    loads it at all (their cached code contains it), which saves about 5 ms
    per kernel at ``import cdt_plugin`` (the exact predicates: 40 of them).
    Callers' arguments are converted to the declared types, never compiled
    for others (numba would otherwise specialise on every literal argument,
    and would evaluate a predicate given integers in overflowing int64)."""

    declared: tuple = ()     # the signatures

    def in_cache(self, sig) -> bool:
        return all(Kernel.in_cache(self, each) for each in self.declared)   # (numba's key: the signature)

    def compile(self, sig):
        with global_compiler_lock:
            if not self.overloads:
                for each in self.declared:
                    super().compile(each)
                if self.for_python:
                    # Python calls with other argument types: converted by numba's
                    # dispatcher, not compiled (an internal kernel's go to its twin)
                    self.disable_compile()
            # compiled callers' arguments: converted by numba's typing
            return next(iter(self.overloads.values())).entry_point
