"""How every kernel is compiled, and what keeps first use short.

:func:`kernel` is ``numba.njit`` with the options every kernel shares: cached
on disk, and no C-callable wrapper (nothing here takes a kernel's address, and
numba would otherwise lower and code-generate one for every compilation).

numba compiles a function once per distinct tuple of argument types, and links
every callee's code into each caller's library, where it is optimised and
code-generated again. So, in the kernels:

* call kernels with typed values, not literals: ``f(a, 0)`` and ``f(a, 1)``
  compile ``f`` twice (``np.int64(0)``, ``np.bool_(False)`` or a variable do not);
* a wrapper with a single caller is ``inline="always"``, so that its callees are
  not code-generated once more for it; small helpers with many callers are not
  (inlining re-runs numba's front end at every call site; LLVM inlines them);
* copy with loops (:func:`.arrays.copy_rows`), not slice assignment, which
  compiles numba's broadcasting and its string-formatted errors;
* the exact predicates' slow stages are called by symbol (:mod:`.predicates`),
  so that callers link the fast filter only.
"""
from __future__ import annotations

from numba import njit


def kernel(*signature, **options):
    """Decorator: ``numba.njit(*signature, cache=True, no_cfunc_wrapper=True, **options)``."""
    return njit(*signature, cache=True, no_cfunc_wrapper=True, **options)
