"""Borrowed array views for the compiled hot loops.

numba reference-counts every array it passes to a function that is not
inlined, and every array variable an inlined helper binds: each is an atomic
increment and decrement of the array's memory-info block. In the insertion,
walking and flipping loops that is most of the work (perf: about 60% of the
time of an insertion in ``NRT_incref``/``NRT_decref``).

:func:`unowned` returns a view of an array with a null memory-info pointer,
on which numba's reference counting is a no-op. A compiled entry point
rebinds its array arguments to such views before its loop (segment insertion;
the insertion and refinement loops allocate nothing and are compiled with
``_nrt=False`` instead, which removes the reference counting altogether); the caller's
arrays own the memory and outlive the call, so nothing is freed early. An
unowned view must never be returned or stored beyond the call that made it,
and only *arguments* may be rebound to views: numba frees a local array right
after the last use of its variable, so ``a = unowned(np.empty(n))`` would
leave a view of freed memory.
"""
from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def unowned(typingctx, arr):
    """A view of ``arr`` (same data, shape and strides) that owns nothing."""
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        src = context.make_array(arr)(context, builder, value=args[0])
        dst = context.make_array(arr)(context, builder)
        for name in ("nitems", "itemsize", "data", "shape", "strides", "parent"):
            setattr(dst, name, getattr(src, name))
        dst.meminfo = cgutils.get_null_value(dst.meminfo.type)
        return dst._getvalue()

    return arr(arr), codegen
