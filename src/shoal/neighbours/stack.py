"""A fixed-size int32 buffer on the stack of a Numba CPU function.

`row_buffer()` returns a 1D int32 array of `ROW_CAP` elements whose storage
is an ``alloca`` in the calling function's entry block: no heap allocation
and no reference counting, so it may be called in a per-particle function
that runs inside a parallel loop. Its content is undefined until written.
CPU only (the CUDA target has no such intrinsic here; the GPU gather does
not compact its rows).
"""

from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

ROW_CAP = 128
"""Elements of the buffer: the candidates of one stencil row handled at a time
(a row of 5 cells holds about 30-60 particles at the usual dp = h / 1.3)."""


@intrinsic
def row_buffer(typingctx):
    """``row_buffer()`` -> int32[ROW_CAP] on the stack (see the module docstring)."""
    arrty = types.Array(types.int32, 1, "C")

    def codegen(context, builder, sig, args):
        n = context.get_constant(types.intp, ROW_CAP)
        data = cgutils.alloca_once(builder, ir.IntType(32), size=n)
        ary = context.make_array(arrty)(context, builder)
        itemsize = context.get_constant(types.intp, 4)
        context.populate_array(ary, data=data, shape=[n], strides=[itemsize], itemsize=itemsize,
                               meminfo=None)
        return ary._getvalue()

    return arrty(), codegen


# A fixed name instead of the random uuid an intrinsic gets: the kernels that call it pickle it into
# Numba's cache key (through the dispatchers they close over), which must be the same in every process.
row_buffer._set_uuid("shoal.neighbours.stack.row_buffer")
