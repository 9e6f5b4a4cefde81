"""How every kernel is compiled, and what keeps first use short.

:func:`kernel` is ``numba.njit`` with the options every kernel shares: cached
on disk, no C-callable wrapper (nothing here takes a kernel's address, and
numba would otherwise lower and code-generate one for every compilation), and
without the GIL: a call from Python releases it on entry, so threads run
kernels side by side (nothing in a kernel touches Python objects or shared
state: every workspace is allocated per call).

numba compiles a function once per distinct tuple of argument types, and links
every callee's code into each caller's library, where it is optimised and
code-generated again. So, in the kernels:

* call kernels with typed values, not literals: ``f(a, 0)`` and ``f(a, 1)``
  compile ``f`` twice (``np.int64(0)``, ``np.bool_(False)`` or a variable do not);
* the intermediate stages with a single caller (``build_mesh``, ``build``,
  ``insert_vertices``, ``insert_all_segments``, ``insert_one``, ``refine_store``,
  ``refine_run``) are ``inline="always"``, so that the kernels below them are
  not code-generated once more for them; so is the route itself
  (``pipeline.cdt_route``), which its two entries (one call from Python, the
  batch loop) would otherwise both link whole. Small helpers are plain kernels:
  numba copies and re-types an inlined function's IR at each call site, which
  costs more than compiling it once (inlining every kernel with a single caller
  made first use 50% slower; the quad-edge helpers of :mod:`.divide` inlined at
  their ~150 call sites cost 3-4 s of a first ``delaunay``), and LLVM inlines
  them anyway. The exceptions are the helpers of the insertion and flip loops
  with many array arguments (``kernel.orient``, ``lifted_test``,
  ``edge_is_illegal``, ``mesh.flip``, ``locate``'s steps): LLVM leaves some of
  them as calls, which made a 50,000-vertex polygon 17% slower;
* copy with loops (:func:`.arrays.copy_rows`), not slice assignment, which
  compiles numba's broadcasting and its string-formatted errors;
* the exact predicates' slow stages are called by symbol (:mod:`.predicates`),
  so that callers link the fast filter only.
"""
from __future__ import annotations

from numba import njit


def kernel(*signature, **options):
    """Decorator: ``numba.njit(*signature, cache=True, no_cfunc_wrapper=True, nogil=True,
    **options)``."""
    return njit(*signature, cache=True, no_cfunc_wrapper=True, nogil=True, **options)
