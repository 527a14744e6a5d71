"""Fixed-size buffers on the stack of a Numba CPU function.

`row_buffer()` returns a 1D int32 array of `ROW_CAP` elements, `term_buffer_f32()` and
`term_buffer_f64()` a 2D (`TERMS`, `ROW_CAP`) array of floats; their storage is an ``alloca`` in
the calling function's entry block: no heap allocation and no reference counting, so they may be
called in a per-particle function that runs inside a parallel loop. Their content is undefined
until written. CPU only (the CUDA target has no such intrinsic here; the GPU gather does not
compact its rows).
"""

from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

ROW_CAP = 256
"""Elements of a buffer: the candidates handled at a time (the neighbours of a particle in 3D at
h = 1.3 dp, about 120, or at h = sqrt(3) dp, about 170, fit in one buffer)."""


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


TERMS = 8
"""Rows of a term buffer: the most values one pair contributes (the rates' accumulator)."""


def make_term_buffer(dtype, name, rows=TERMS):
    """An intrinsic returning a (rows, ROW_CAP) C-ordered array of `dtype` (a Numba type) on the stack,
    with the fixed cache name `name` (see `row_buffer`; each distinct buffer needs its own name)."""
    arrty = types.Array(dtype, 2, "C")

    @intrinsic
    def term_buffer(typingctx):
        def codegen(context, builder, sig, args):
            llty = context.get_data_type(dtype)
            n = context.get_constant(types.intp, rows * ROW_CAP)
            data = cgutils.alloca_once(builder, llty, size=n)
            ary = context.make_array(arrty)(context, builder)
            size = context.get_abi_sizeof(llty)
            itemsize = context.get_constant(types.intp, size)
            context.populate_array(ary, data=data,
                                   shape=[context.get_constant(types.intp, rows),
                                          context.get_constant(types.intp, ROW_CAP)],
                                   strides=[context.get_constant(types.intp, size * ROW_CAP), itemsize],
                                   itemsize=itemsize, meminfo=None)
            return ary._getvalue()

        return arrty(), codegen

    term_buffer._set_uuid(name)
    return term_buffer


term_buffer_f32 = make_term_buffer(types.float32, "shoal.neighbours.stack.term_buffer_f32")
term_buffer_f64 = make_term_buffer(types.float64, "shoal.neighbours.stack.term_buffer_f64")

TERMS_BOTH = 11
"""Rows of a term buffer of `half_sweep`: the most values one pair contributes to both its particles
(`shoal.physics.mutual`)."""

both_buffer_f32 = make_term_buffer(types.float32, "shoal.neighbours.stack.both_buffer_f32", TERMS_BOTH)
both_buffer_f64 = make_term_buffer(types.float64, "shoal.neighbours.stack.both_buffer_f64", TERMS_BOTH)
