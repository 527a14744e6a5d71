"""The CUDA cell grid gives exactly the CPU grid's sort: same permutation,
same sorted cells, same cell_start, same reordered arrays.

The tests need a GPU or Numba's CUDA simulator. The simulator must be
chosen before `numba.cuda` is first imported, which in a normal `pytest`
run has already happened (or may happen) in another test module, so when
this process has neither a GPU nor the simulator, `test_simulator_run`
runs this file again in a child `pytest` with ``NUMBA_ENABLE_CUDASIM=1``
(the child sees the variable and so never starts another child). The
simulator runs each CUDA thread as a Python thread: the particle sets are
a few hundred particles and the whole child run takes well under a minute.
"""

from __future__ import annotations


import numpy as np
import pytest

from shoal.errors import InputError
from shoal.neighbours import CellGrid

from cuda_support import HAVE_CUDA, needs_cuda, run_module_under_simulator  # noqa: E402,F401


def test_simulator_run():
    """Run this module under the CUDA simulator in a child process."""
    run_module_under_simulator(__file__, "test_simulator_run")


# ---------------------------------------------------------------------------
# helpers


def _particles(dim, n, seed, lo, hi, dtype=np.float64):
    """Random positions over a box 10 % larger than [lo, hi) (so some are
    outside), with coincident particles, one on lo, one NaN, one inf."""
    rng = np.random.default_rng(seed)
    span = hi - lo
    pos = (lo - 0.05 * span) + rng.random((n, dim)) * 1.1 * span
    pos[:4] = pos[10:14]  # coincident: ties broken by particle index
    pos[20] = lo
    pos[21] = np.nan
    pos[22, 0] = np.inf
    pos[23] = hi  # the box is half-open
    return pos.astype(dtype)


def _cpu(pos, n, lo, hi, support, cps, capacity, extra):
    """Bin and reorder on the CPU; returns the grid and the reordered arrays."""
    grid = CellGrid(lo, hi, support, cps, capacity)
    arrays = [pos.copy()] + [a.copy() for a in extra]
    scratch = {(a.dtype.str, 0 if a.ndim == 1 else a.shape[1]): np.empty_like(a) for a in arrays}
    n_active = grid.bin(arrays[0], n)
    grid.reorder(arrays, n, scratch)
    return grid, n_active, arrays


def _assert_same_sort(cgrid, grid, n):
    np.testing.assert_array_equal(cgrid.perm_d.copy_to_host()[:n], grid.perm[:n])
    np.testing.assert_array_equal(cgrid.cell_d.copy_to_host()[:n], grid.cell[:n])
    np.testing.assert_array_equal(cgrid.cell_start_d.copy_to_host(), grid.cell_start)
    assert cgrid.n_active == grid.n_active


def _case(dim):
    lo = np.array([-0.13, 0.02, 0.5])[:dim]
    hi = lo + np.array([0.41, 0.23, 0.3])[:dim]
    return lo, hi, 0.0742  # support: no simple ratio with the box


# ---------------------------------------------------------------------------
# tests on the device (GPU or simulator)


@needs_cuda
@pytest.mark.parametrize("cps", [1, 2])
@pytest.mark.parametrize("dim", [2, 3])
def test_bin_and_reorder_equal_cpu(dim, cps):
    from numba import cuda

    from shoal.neighbours.cuda_grid import CudaCellGrid

    lo, hi, support = _case(dim)
    n = 300
    capacity = n + 17  # arrays longer than n: the tail is left alone
    pos = _particles(dim, capacity, 100 * dim + cps, lo, hi)
    rng = np.random.default_rng(dim + cps)
    rho = rng.random(capacity).astype(np.float32)
    ids = np.arange(capacity, dtype=np.int32)
    vel = rng.standard_normal((capacity, 3)).astype(np.float32)
    grid, n_active, expected = _cpu(pos, n, lo, hi, support, cps, capacity, [rho, ids, vel])

    cgrid = CudaCellGrid(lo, hi, support, cps, capacity)
    assert (cgrid.ncell, cgrid.gdims, cgrid.cell_size) == (grid.ncell, grid.gdims, grid.cell_size)
    np.testing.assert_array_equal(cgrid.gdims_arr.copy_to_host(), grid.gdims_arr)
    assert cgrid.gdims_arr.dtype == np.int64
    arrays = [cuda.to_device(a) for a in (pos, rho, ids, vel)]
    assert cgrid.bin(arrays[0], n) == n_active
    assert 0 < n_active < n - 3  # some particles left the domain
    _assert_same_sort(cgrid, grid, n)
    assert (cgrid.cell, cgrid.cell_start, cgrid.perm) == (cgrid.cell_d, cgrid.cell_start_d, cgrid.perm_d)
    cgrid.reorder(arrays, n, cgrid.make_scratch(arrays))
    for a_d, a in zip(arrays, expected):
        np.testing.assert_array_equal(a_d.copy_to_host(), a)


@needs_cuda
def test_small_blocks_rebin_float32():
    """Several radix blocks and a two-level prefix sum (32-thread blocks,
    3 radix passes over 2210 cells), float32 positions, then a second
    binning of the reordered particles (buffers reused)."""
    from numba import cuda

    from shoal.neighbours.cuda_grid import CudaCellGrid

    dim, cps = 3, 3
    lo, hi, support = _case(dim)
    n = 260
    pos = _particles(dim, n, 5, lo, hi, dtype=np.float32)
    ids = np.arange(n, dtype=np.int32)
    grid, n_active, (spos, sids) = _cpu(pos, n, lo, hi, support, cps, n, [ids])
    cgrid = CudaCellGrid(lo, hi, support, cps, n, block_size=32)
    assert cgrid._passes == 3 and len(cgrid._scan_aux) >= 2
    pos_d, ids_d = cuda.to_device(pos), cuda.to_device(ids)
    assert cgrid.bin(pos_d, n, read_back=False) is None
    _assert_same_sort(cgrid, grid, n)
    scratch = cgrid.make_scratch([pos_d, ids_d])
    cgrid.reorder([pos_d, ids_d], n, scratch)
    np.testing.assert_array_equal(pos_d.copy_to_host(), spos)
    np.testing.assert_array_equal(ids_d.copy_to_host(), sids)
    # once sorted, a second binning keeps the order (perm is the identity)
    grid.bin(spos, n)
    cgrid.bin(pos_d, n)
    _assert_same_sort(cgrid, grid, n)
    np.testing.assert_array_equal(grid.perm[:n], np.arange(n))


@needs_cuda
def test_prefix_sum_across_tiles():
    from numba import cuda

    from shoal.neighbours.cuda_grid import CudaCellGrid

    cgrid = CudaCellGrid([0.0, 0.0], [1.0, 1.0], 0.5, 1, 4200, block_size=32)  # tile of 128 counters
    rng = np.random.default_rng(3)
    for m in (1, 127, 128, 129, 2100):
        a = rng.integers(0, 50, m).astype(np.int32)
        a_d = cuda.to_device(a)
        cgrid._exclusive_scan(a_d, m)
        np.testing.assert_array_equal(a_d.copy_to_host(), np.r_[0, np.cumsum(a)[:-1]])


@needs_cuda
def test_empty_and_all_outside():
    from numba import cuda

    from shoal.neighbours.cuda_grid import CudaCellGrid

    lo, hi, support = _case(2)
    cgrid = CudaCellGrid(lo, hi, support, 1, 40)
    assert cgrid.n_active == 0  # before any binning
    np.testing.assert_array_equal(cgrid.cell_start_d.copy_to_host(), 0)
    pos = np.full((40, 2), 7.0)
    pos_d = cuda.to_device(pos)
    assert cgrid.bin(pos_d, 0) == 0
    np.testing.assert_array_equal(cgrid.cell_start_d.copy_to_host(), 0)
    assert cgrid.bin(pos_d, 40) == 0
    grid, _, _ = _cpu(pos, 40, lo, hi, support, 1, 40, [])
    _assert_same_sort(cgrid, grid, 40)
    with pytest.raises(ValueError, match="capacity"):
        cgrid.bin(pos_d, 41)
    with pytest.raises(InputError, match="must exceed"):
        CudaCellGrid([0.0, 0.0], [1.0, 0.0], 0.1, 2, 10)
    with pytest.raises(ValueError, match="block_size"):
        CudaCellGrid(lo, hi, support, 1, 40, block_size=48)
    assert cgrid.nbytes >= 4 * (cgrid.ncell + 2) + 16 * 40


@needs_cuda
@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")  # sums of uninitialised arrays
def test_simulator_threads_share_one_shared_array(monkeypatch):
    """Under Numba's CUDA simulator a block's threads get one ``cuda.shared.array`` (guarded by
    `shoal.backends.simulator`): each thread stores t + 1 and sums the array, 528 for 32 threads.

    The simulator's own allocation is an unlocked check-then-set: threads that check before the
    first one stores get arrays of their own. Here the allocation waits (up to 2 s) for a second
    thread to arrive in it, to make the race certain rather than a matter of timing: unguarded, two
    threads then hold different arrays and sum partial ones (seen in a real run as a radix sort that
    lost particles, 2 runs in 8, and once in 400 launches of this kernel at full speed); guarded, the
    second thread waits at the lock and finds the first one's array. On a GPU there is no simulator
    to guard, and the kernel must simply give 528."""
    import inspect
    import threading

    from simulator_shared import wrong_sums

    from shoal.backends.simulator import guard_shared_allocation

    if not guard_shared_allocation():
        assert wrong_sums() == 0
        return
    from numba.cuda.simulator import kernelapi

    real = kernelapi.np
    entered = []
    second = threading.Event()

    class WaitingEmpty:
        def __getattr__(self, name):
            return getattr(real, name)

        @staticmethod
        def empty(*args, **kw):
            entered.append(1)
            if len(entered) >= 2:
                second.set()
            second.wait(2.0)  # guarded, no second thread comes (it waits at the lock): go on after 2 s
            return real.empty(*args, **kw)

    monkeypatch.setattr(kernelapi, "np", WaitingEmpty())
    assert wrong_sums() == 0
    assert not second.is_set()  # one thread at a time in the allocation
    entered.clear()
    guarded = kernelapi.FakeCUDAShared.array
    monkeypatch.setattr(kernelapi.FakeCUDAShared, "array", guarded.unguarded)
    unguarded_wrong = wrong_sums()
    monkeypatch.setattr(kernelapi.FakeCUDAShared, "array", guarded)
    print(f"threads with a wrong sum: {unguarded_wrong} of 64 unguarded, 0 guarded")
    if "lock" not in inspect.getsource(guarded.unguarded).lower():  # numba-cuda's code as of 0.30
        assert second.is_set() and unguarded_wrong > 0, "two threads in the allocation did not give two arrays"


@needs_cuda
def test_simulator_runs_barrier_free_kernels_in_the_launching_thread():
    """Under the simulator a kernel marked `barrier_free` runs each block's threads one after the
    other in the launching thread (`shoal.backends.simulator`), with the indices of a real launch
    (3 blocks of 32 threads: every element written once by its own thread); a marked kernel that
    waits at a barrier is refused with a message naming the mark, not run out of order."""
    import threading

    from simulator_shared import THREADS_SEEN, grid_index, wrongly_marked

    from shoal.backends.simulator import run_barrier_free_blocks

    if not run_barrier_free_blocks():
        pytest.skip("a GPU: there is no simulator to check")
    n = 90
    out = np.full(n, -1, np.int64)
    dims = np.full((n, 3), -1, np.int64)
    THREADS_SEEN.clear()
    grid_index[3, 32](out, dims)
    np.testing.assert_array_equal(out, np.arange(n))
    np.testing.assert_array_equal(dims[:, 0], np.arange(n) // 32)
    np.testing.assert_array_equal(dims[:, 1], np.arange(n) % 32)
    assert np.all(dims[:, 2] == 32)
    assert THREADS_SEEN == {threading.get_ident()}
    with pytest.raises(RuntimeError, match="barrier_free"):
        wrongly_marked[1, 32](np.zeros(32, np.int64))


@needs_cuda
def test_simulator_pool_runs_barriers_and_reports_a_failing_thread():
    """Kernels with barriers run on `shoal.backends.simulator`'s pool of threads: a barrier count is
    right (11 of 32 threads with t % 3 == 0), a thread that fails between two barriers is reported by
    its index while the block's other threads stop at the barrier instead of waiting for ever, and
    the pool runs the next launch as before."""
    from simulator_shared import barrier_count, fails_at, wrong_sums

    from shoal.backends.simulator import run_barrier_free_blocks

    if not run_barrier_free_blocks():
        pytest.skip("a GPU: there is no simulator to check")
    out = np.zeros(32, np.int64)
    barrier_count[1, 32](out)
    assert np.all(out == 11)
    with pytest.raises(ValueError, match=r"tid=\[7, 0, 0\] ctaid=\[0, 0, 0\]: thread failed on purpose"):
        fails_at[1, 32](np.zeros(32, np.int64), 7)
    assert wrong_sums(blocks=3) == 0
