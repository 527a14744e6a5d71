"""A kernel that shows whether a block's threads share one ``cuda.shared.array`` (test_cuda_grid.py).

Imported only where ``numba.cuda`` may be imported (on a GPU or under the simulator): the kernel
uses the module-level name ``cuda``, which the simulator swaps inside kernels.
"""

from numba import cuda, int32

T = 32


@cuda.jit
def block_sum(out):
    """Each thread stores t + 1 in the block's shared array, then sums the whole array: every
    thread must find T (T + 1) / 2."""
    s = cuda.shared.array(T, int32)
    t = cuda.threadIdx.x
    s[t] = t + 1
    cuda.syncthreads()
    acc = 0
    for j in range(T):
        acc += s[j]
    out[cuda.blockIdx.x * T + t] = acc


def wrong_sums(blocks=2):
    """Launch `block_sum` and count the threads whose sum is wrong."""
    import numpy as np

    out = np.zeros(blocks * T, np.int64)
    block_sum[blocks, T](out)
    return int(np.count_nonzero(out != T * (T + 1) // 2))


THREADS_SEEN = set()  # the Python threads that ran `grid_index` (simulator only: kernels run as Python)


def _barrier_free(kernel):
    from shoal.backends.simulator import barrier_free

    return barrier_free(kernel)


@_barrier_free
@cuda.jit
def grid_index(out, dims):
    """out[i] = i for every thread of a 1D launch; dims[i] = (block x, thread x, blockDim x)."""
    i = cuda.grid(1)
    if i < out.shape[0]:
        out[i] = i
        dims[i, 0] = cuda.blockIdx.x
        dims[i, 1] = cuda.threadIdx.x
        dims[i, 2] = cuda.blockDim.x
    _note_thread()  # plain Python: this kernel is for the simulator only


def _note_thread():
    import threading

    THREADS_SEEN.add(threading.get_ident())


@_barrier_free
@cuda.jit
def wrongly_marked(out):
    """Marked barrier-free, yet it waits at a barrier: the simulator must refuse it."""
    cuda.syncthreads()
    out[cuda.grid(1)] = 1


@cuda.jit
def barrier_count(out):
    """Every thread gets the number of threads with t % 3 == 0 (11 of 32): ``syncthreads_count``."""
    t = cuda.threadIdx.x
    out[t] = cuda.syncthreads_count(t % 3 == 0)


@cuda.jit
def fails_at(out, bad):
    """Thread `bad` fails between two barriers; the others wait at the second one (simulator only)."""
    t = cuda.threadIdx.x
    out[t] = 1
    cuda.syncthreads()
    if t == bad:
        raise ValueError("thread failed on purpose")
    cuda.syncthreads()
    out[t] = 2
