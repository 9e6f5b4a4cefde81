"""Software prefetch for the compiled loops that follow links at random.

A loop that reads a far slot each iteration (the next edge of a face, say)
waits for that load before the iteration after it can start. :func:`prefetch`
asks the memory for a slot some iterations ahead, so that the loads of
several iterations are under way at once. It is a hint: it never faults and
changes no value, and the loops keep their index in bounds regardless. Under
an LLVM older than 17 (numba before 0.62), which may still use typed
pointers, whose intrinsic has another name, it compiles to nothing.
"""
from __future__ import annotations

from llvmlite import binding, ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


#: The intrinsic as LLVM 17 and later name it (opaque pointers only); None: not emitted
PREFETCH = "llvm.prefetch.p0" if binding.llvm_version_info >= (17,) else None


@intrinsic
def prefetch(typingctx, arr, i):
    """Start loading ``arr[i]`` into the cache (for reading and writing; a
    1-D array and an index in bounds)."""
    if not isinstance(arr, types.Array) or arr.ndim != 1 or not isinstance(i, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        if PREFETCH is None:
            return context.get_dummy_value()
        a = context.make_array(arr)(context, builder, value=args[0])
        ptr = cgutils.get_item_pointer(context, builder, arr, a, [args[1]], wraparound=False)
        byte_ptr = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [byte_ptr, i32, i32, i32]), PREFETCH)
        # (write: the slot is about to be written; locality 3: keep it in every cache level; data)
        builder.call(fn, [builder.bitcast(ptr, byte_ptr), i32(1), i32(3), i32(1)])
        return context.get_dummy_value()

    return types.void(arr, i), codegen
