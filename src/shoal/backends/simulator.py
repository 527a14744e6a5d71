"""Numba's CUDA simulator, made safe for kernels with shared memory, and faster.

Under ``NUMBA_ENABLE_CUDASIM=1`` each GPU thread of a block is a Python thread,
and ``cuda.shared.array`` is ``FakeCUDAShared.array`` (numba-cuda 0.30): it
looks the calling line up in a dict and, if absent, allocates an array and
stores it -- a check-then-set with no lock, and a slow one (it builds a
traceback to find the line). Two threads of one block that both reach the
check before either stores get two different arrays, so their "shared" memory
is not shared: a block scan then adds up half the block, and the radix sort of
`shoal.neighbours.cuda_grid` writes two particles to one slot (seen as a 2-rank
simulated run that lost 10 particle ids and doubled 10 others, 2 runs in 8
with a 0.1 ms GIL switch interval; rarer at the default 5 ms, never on a GPU).

`guard_shared_allocation` wraps that method in a lock, so the first thread
allocates and every other thread of the block gets the same array. It is
idempotent and does nothing outside the simulator.

The simulator also starts (and joins) a new Python thread per GPU thread of
every block of every launch and busy-polls them from the launching thread,
which makes a launch slow, and very slow on a loaded machine. Two remedies,
`run_barrier_free_blocks`:

* Most of shoal's kernels are one independent thread per particle or row, with
  no barrier and no shared memory: any order of their threads is a valid CUDA
  schedule, including one after another. `barrier_free` marks such a kernel,
  and the simulator then runs a marked kernel's blocks thread by thread in the
  launching thread (the same kernel source through the same fake ``cuda``
  module: thread and block indices, atomics, local arrays); a marked kernel
  that calls ``syncthreads`` fails with an error that says so.
* The other kernels (the radix sort's, with shared memory and barriers) run on
  a persistent pool of threads, one per GPU thread of a block (`_BlockPool`),
  which wait at a condition variable (`_BlockBarrier`) instead of being polled.

`prepare` does both; `shoal.backends.cuda` and `shoal.neighbours.cuda_grid`
call it on import.
"""

from __future__ import annotations

import os
import queue
import sys
import threading

import numpy as np

_LOCK = threading.Lock()


def guard_shared_allocation():
    """Make the simulator's ``cuda.shared.array`` allocate once per block under a lock.

    The replacement keeps the simulator's contract (one array per calling source line and
    launch, ``shape == 0`` for the dynamic shared memory) and finds the calling line from the
    caller's frame rather than a whole traceback. Returns True if the simulator is active (and
    now guarded), False otherwise.
    """
    if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":
        return False
    from numba.cuda.simulator import kernelapi

    types, numpy_support = kernelapi.types, kernelapi.numpy_support  # the ones the simulator itself uses

    shared = kernelapi.FakeCUDAShared
    if getattr(shared.array, "_shoal_guarded", False):
        return True
    unguarded = shared.array

    def array(self, shape, dtype, alignment=None):
        if alignment is not None or shape == 0:  # an error, or the dynamic buffer: no lookup
            return unguarded(self, shape, dtype, alignment)
        frame = sys._getframe(1)
        caller = (frame.f_code.co_filename, frame.f_lineno)
        with _LOCK:
            res = self._allocations.get(caller)
            if res is None:
                if isinstance(dtype, types.Type):
                    dtype = numpy_support.as_dtype(dtype)
                res = self._allocations[caller] = kernelapi.np.empty(shape, dtype)
        return res

    array._shoal_guarded = True
    array.unguarded = unguarded  # for the test that shows the race (tests/test_cuda_grid.py)
    shared.array = array
    return True


def barrier_free(kernel):
    """Mark a ``cuda.jit`` kernel as free of barriers and shared memory (decorator; returns
    `kernel`). Only the simulator reads the mark (`run_barrier_free_blocks`); on a GPU it does
    nothing."""
    if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1":
        kernel.fn._shoal_barrier_free = True  # the simulator's FakeCUDAKernel wraps the Python function
    return kernel


class _NoBarrier:
    def syncthreads(self):
        raise RuntimeError("a kernel marked barrier_free (shoal.backends.simulator) called syncthreads")

    syncthreads_count = syncthreads_and = syncthreads_or = syncthreads


class _BlockAborted(RuntimeError):
    """Raised at a barrier in the threads of a block where another thread failed."""


def _thread_id(tid, block_dim):
    """The linear index of thread `tid` in a block of `block_dim` (x fastest), as the simulator's."""
    bx, by = (tuple(block_dim) + (1, 1))[:2]
    return tid.x + bx * (tid.y + by * tid.z)


def _located(e, tid, bid):
    """`e` again with the simulator's prefix naming the thread and block it came from."""
    return type(e)(f"tid={list(tid)} ctaid={list(bid)}: {e}").with_traceback(e.__traceback__)


class _BlockBarrier:
    """``syncthreads`` for the threads of one simulated block: a reusable barrier whose party
    shrinks as threads finish (a thread that returned is not waited for, as the simulator's own
    manager does), and that any thread's exception breaks (the others then stop)."""

    def __init__(self, parties):
        self.parties = parties
        self.count = 0
        self.generation = 0
        self.broken = False
        self.cv = threading.Condition()
        self.state = []  # the values of syncthreads_count / _and / _or

    def _release(self):
        self.count = 0
        self.generation += 1
        self.cv.notify_all()

    def wait(self):
        with self.cv:
            if self.broken:
                raise _BlockAborted("another thread of the block failed")
            generation = self.generation
            self.count += 1
            if self.count == self.parties:
                self._release()
                return
            while generation == self.generation and not self.broken:
                self.cv.wait()
            if self.broken:
                raise _BlockAborted("another thread of the block failed")

    def leave(self, failed):
        with self.cv:
            self.parties -= 1
            if failed:
                self.broken = True
                self.cv.notify_all()
            elif self.parties and self.count == self.parties:
                self._release()

    def reduce(self, value, op):
        with self.cv:
            self.state.append(value)
        self.wait()
        result = op(self.state)
        self.wait()
        with self.cv:
            self.state.clear()
        self.wait()
        return result


class _BlockPool:
    """Persistent Python threads, one per GPU thread of a block, that run the blocks of kernels with
    barriers: the simulator's own launcher starts (and joins) a new thread per GPU thread for every
    block of every launch and polls them from the launching thread, which cost 1 ms a thread on a
    loaded 2-core machine; here a block's threads wait at a condition variable, and the launching
    thread sleeps until they are done."""

    def __init__(self, size):
        self.size = size
        self.jobs = [queue.SimpleQueue() for _ in range(size)]
        self.done = queue.SimpleQueue()
        for k in range(size):
            threading.Thread(target=self._work, args=(k,), daemon=True, name=f"shoal-cudasim-{k}").start()

    def _work(self, k):
        me = threading.current_thread()
        jobs = self.jobs[k]
        while True:
            f, args, barrier, tid, bid, thread_id = jobs.get()
            me.threadIdx, me.blockIdx, me.thread_id = tid, bid, thread_id
            me.syncthreads = barrier.wait
            me.syncthreads_count = lambda v: barrier.reduce(v, lambda s: sum(1 for x in s if x))
            me.syncthreads_and = lambda v: barrier.reduce(v, lambda s: int(all(s)))
            me.syncthreads_or = lambda v: barrier.reduce(v, lambda s: int(any(s)))
            error = None
            try:
                f(*args)
            except BaseException as e:  # reported by the launching thread
                error = (e, tid)
            barrier.leave(error is not None)
            self.done.put(error)

    def run(self, f, block_dim, grid_point, args, Dim3):
        points = list(np.ndindex(*block_dim))
        barrier = _BlockBarrier(len(points))
        bid = Dim3(*grid_point)
        for k, point in enumerate(points):
            tid = Dim3(*point)
            self.jobs[k].put((f, args, barrier, tid, bid, _thread_id(tid, block_dim)))
        errors = [e for e in (self.done.get() for _ in points) if e is not None]
        if errors:  # the failing thread's own error, not the others' `_BlockAborted`
            e, tid = ([e for e in errors if not isinstance(e[0], _BlockAborted)] or errors)[0]
            raise _located(e, tid, bid) from None


_POOLS = {}


def run_barrier_free_blocks():
    """Make the simulator run each block of a `barrier_free` kernel in the launching thread, one
    GPU thread after the other, and the blocks of other kernels on a persistent pool of threads
    (`_BlockPool`) (see the module docstring). Returns True if the simulator is active, False
    otherwise."""
    if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":
        return False
    from numba.cuda.simulator import kernel as simkernel

    manager = simkernel.BlockManager
    if getattr(manager.run, "_shoal_barrier_free", False):
        return True
    Dim3 = simkernel.Dim3
    names = ("threadIdx", "blockIdx", "thread_id", "syncthreads", "syncthreads_count", "syncthreads_and",
             "syncthreads_or")
    no_barrier = _NoBarrier()

    def run(self, grid_point, *args):
        if not getattr(self._f, "_shoal_barrier_free", False):
            size = int(np.prod(self._block_dim))
            with _LOCK:
                if size not in _POOLS:
                    _POOLS[size] = _BlockPool(size)
            return _POOLS[size].run(self._f, self._block_dim, grid_point, args, Dim3)
        me = threading.current_thread()
        saved = {k: me.__dict__[k] for k in names if k in me.__dict__}
        me.blockIdx = Dim3(*grid_point)
        for k in names[3:]:
            setattr(me, k, getattr(no_barrier, k))
        try:
            for point in np.ndindex(*self._block_dim):
                tid = Dim3(*point)
                me.threadIdx = tid
                me.thread_id = _thread_id(tid, self._block_dim)
                try:
                    self._f(*args)
                except Exception as e:  # the simulator's message: which thread of which block
                    raise _located(e, tid, me.blockIdx) from None
        finally:
            for k in names:
                me.__dict__.pop(k, None)
            me.__dict__.update(saved)

    run._shoal_barrier_free = True
    manager.run = run
    return True


def prepare():
    """`guard_shared_allocation` and `run_barrier_free_blocks` (nothing outside the simulator)."""
    guard_shared_allocation()
    run_barrier_free_blocks()
