"""CUDA backend: the same per-particle physics, one GPU thread per particle.

The functions of `shoal.physics` and `shoal.timestepping.updates` are
compiled a second time with ``numba.cuda.jit(device=True)`` from the same
source (no second copy of the physics); this module only decides how loops
run: a kernel launch over the particles (`make_for_each`), device
reductions for the time step and the stability check, and device-resident
arrays for the whole run. Host copies happen only for outputs, probes and
the one scalar per step (dt) that the host needs.

Requires the optional dependency ``numba-cuda`` (``pip install shoal[cuda]``)
and an NVIDIA GPU with its driver. Without a GPU the kernels can run
through Numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``), slowly: that is
how the parity tests run in CI.
"""

from __future__ import annotations

import functools
import math
import os
import warnings
from types import SimpleNamespace

import numpy as np

from ..errors import InputError
from ..physics.identity import shared_loop
from ..physics.spec import FLUID, MOVING
from .loops import attach_loops, row_columns

from .simulator import barrier_free, prepare

try:  # a module-level name: the CUDA simulator swaps the global `cuda` inside kernels
    from numba import cuda
except Exception:  # pragma: no cover - numba-cuda missing
    cuda = None
else:
    prepare()  # under the simulator only: see shoal.backends.simulator
    # The small launches are by design (a reduction's last pass over its block partials, the few
    # thousand particles of a moving wall, the probes); numba-cuda warns on every launch of under 128
    # blocks, which filled the terminal of each GPU run (seen on an H200). The kernels over all the
    # particles are launched on thousands of blocks.
    warnings.filterwarnings("ignore", message=r"Grid size \d+ will likely result in GPU under-utilization")

THREADS = 128

MAX_REGISTERS_ENV = "SHOAL_CUDA_MAX_REGISTERS"
"""The environment variable that caps the registers a thread of the loop kernels may use (`max_registers`)."""


def max_registers():
    """The register cap of the loop kernels (`make_for_each`) from ``SHOAL_CUDA_MAX_REGISTERS``: None (the
    compiler's choice) when it is unset, empty or 0, else a whole number from 16 to 255.

    An SM of compute capability 7.0-9.0 holds 65,536 registers and 2,048 threads, allocated to a warp in
    multiples of 256 (8 a thread): at 128 threads a block, a kernel of 104-112 registers a thread runs 4 blocks
    an SM (25 % occupancy), of 64 registers 8 (50 %). Fewer registers let more warps hide the memory latency
    of the neighbour loop, at the price of values the compiler then recomputes or spills to local memory
    (ptxas's report: `benchmarks/rates_registers.py`); which cap is fastest is measured on the GPU
    (`benchmarks/device/check.sh regs`). Read when a kernel is first built in a process; the CUDA simulator
    ignores it."""
    raw = os.environ.get(MAX_REGISTERS_ENV, "").strip()
    if raw in ("", "0"):
        return None
    try:
        n = int(raw)
    except ValueError:
        n = 0
    if not 16 <= n <= 255:
        raise InputError(f"{MAX_REGISTERS_ENV}={raw!r}: give a whole number of registers from 16 to 255, "
                         "or 0 (or leave it unset) for the compiler's choice")
    return n


def cuda_status():
    """(available, message): whether the CUDA backend can run here, and why not."""
    if cuda is None:
        return False, "numba-cuda is not installed; pip install 'shoal[cuda]'"
    if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1":
        return True, "CUDA simulator (NUMBA_ENABLE_CUDASIM=1): kernels run as Python, for testing only"
    try:
        if not cuda.is_available():
            return False, "no CUDA driver or GPU found (numba.cuda.is_available() is False)"
        devs = [f"{d.name.decode() if isinstance(d.name, bytes) else d.name}" for d in cuda.gpus]
        return True, f"{len(devs)} device(s): {', '.join(devs)}"
    except Exception as exc:  # pragma: no cover
        return False, f"CUDA initialisation failed: {exc}"


def cuda_device_jit(fn):
    """Decorator for shared per-particle functions on CUDA (device functions)."""
    return cuda.jit(device=True)(fn)


def make_for_each(fn):
    """Return ``run(n, args)``: one thread per particle calls ``fn(i, *args)``.

    One kernel per identity of `fn` in a process (`shoal.physics.identity.shared_loop`): schemes
    sharing a device function share its kernel, compiled by NVVM once."""
    return shared_loop(fn, _build_for_each)


def _build_for_each(fn):
    cap = None if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1" else max_registers()

    @barrier_free
    @(cuda.jit(max_registers=cap) if cap else cuda.jit)
    def kernel(n, args):
        i = cuda.grid(1)
        if i < n:
            fn(i, *args)

    def run(n, args):
        if n > 0:
            kernel[(n + THREADS - 1) // THREADS, THREADS](n, args)

    run.kernel = kernel
    return run


@functools.lru_cache(maxsize=None)
def _loops_for(spec):
    """The loop kernels of `attach_loops` for `spec` (a namespace), built once per process and shared
    by every `CUDABackend` of that scheme. Kernels are not cached on disk, so each new set of closures
    would be compiled again by NVVM at its first launch (a fraction of a second per kernel, tens of
    kernels a scheme): a process that builds several models of one scheme (a parameter sweep, the
    parity tests on a GPU) compiles them once. Kernels that another scheme builds alike are shared
    too (`make_for_each`)."""
    ns = SimpleNamespace()
    attach_loops(ns, cuda_device_jit, make_for_each, spec, "cuda")
    return ns


@functools.lru_cache(maxsize=None)
def _reductions():
    @barrier_free
    @cuda.jit
    def accel2(n, ace, kind, out):
        i = cuda.grid(1)
        if i < n:
            a2 = ace[i, 0] * ace[i, 0]
            for d in range(1, ace.shape[1]):
                a2 += ace[i, d] * ace[i, d]
            if kind[i] != FLUID:
                a2 = a2 - a2  # zero in the working precision
            out[i] = a2

    @barrier_free
    @cuda.jit
    def first_bad(n, pos, vel, rho, kind, rho_lo, rho_hi, out):
        # out[0]: smallest bad index (n if none); out[1]: its code
        i = cuda.grid(1)
        if i < n:
            r = rho[i]
            code = 0
            if not math.isfinite(r):
                code = 1
            for d in range(pos.shape[1]):
                if not (math.isfinite(pos[i, d]) and math.isfinite(vel[i, d])):
                    code = 1
            if code == 0 and kind[i] == FLUID and (r < rho_lo or r > rho_hi):
                code = 2
            if code:
                cuda.atomic.min(out, 0, i)

    @cuda.reduce
    def max_reduce(a, b):
        return max(a, b)

    return accel2, first_bad, max_reduce


@functools.lru_cache(maxsize=None)
def _body_kernels():
    @barrier_free
    @cuda.jit
    def zero_rows(out):
        i = cuda.grid(1)
        if i < out.shape[0]:
            for c in range(out.shape[1]):
                out[i, c] = 0.0

    @barrier_free
    @cuda.jit
    def body_sums(n, pos, force, kind, idp, motion_of, ghost, use_ghost, row, centres, out):
        # the CPU's `body_sums` with atomic adds (float64): the same sums, in an order that varies
        i = cuda.grid(1)
        if i < n and kind[i] == MOVING and not (use_ghost and ghost[i] != 0):
            j = row[motion_of[idp[i]]]
            if j >= 0:
                dim = pos.shape[1]
                fx = float(force[i, 0])
                fz = float(force[i, dim - 1])
                rx = pos[i, 0] - centres[j, 0]
                rz = pos[i, dim - 1] - centres[j, 2]
                if dim == 3:
                    fy = float(force[i, 1])
                    ry = pos[i, 1] - centres[j, 1]
                    cuda.atomic.add(out, (j, 1), fy)
                    cuda.atomic.add(out, (j, 3), ry * fz - rz * fy)
                    cuda.atomic.add(out, (j, 5), rx * fy - ry * fx)
                cuda.atomic.add(out, (j, 0), fx)
                cuda.atomic.add(out, (j, 2), fz)
                cuda.atomic.add(out, (j, 4), rz * fx - rx * fz)

    return zero_rows, body_sums


@functools.lru_cache(maxsize=None)
def _row_kernels():
    """Kernels that move rows of particle arrays to and from a float64 buffer (`pack_rows`): one
    thread per row (halos are small; the CUDA simulator runs a Python thread per GPU thread)."""
    @barrier_free
    @cuda.jit
    def pack_1d(a, rows, k, out, col):
        i = cuda.grid(1)
        if i < k:
            out[i, col] = a[rows[i]]

    @barrier_free
    @cuda.jit
    def pack_2d(a, rows, k, out, col):
        i = cuda.grid(1)
        if i < k:
            r = rows[i]
            for d in range(a.shape[1]):
                out[i, col + d] = a[r, d]

    @barrier_free
    @cuda.jit
    def unpack_1d(a, buf, rows, k, col):
        i = cuda.grid(1)
        if i < k:
            a[rows[i]] = buf[i, col]

    @barrier_free
    @cuda.jit
    def unpack_2d(a, buf, rows, k, col):
        i = cuda.grid(1)
        if i < k:
            r = rows[i]
            for d in range(a.shape[1]):
                a[r, d] = buf[i, col + d]

    @barrier_free
    @cuda.jit
    def zero_1d(a, rows, k):
        i = cuda.grid(1)
        if i < k:
            a[rows[i]] = 0

    @barrier_free
    @cuda.jit
    def zero_2d(a, rows, k):
        i = cuda.grid(1)
        if i < k:
            r = rows[i]
            for d in range(a.shape[1]):
                a[r, d] = 0

    return {"pack": (pack_1d, pack_2d), "unpack": (unpack_1d, unpack_2d), "zero": (zero_1d, zero_2d)}


def _launch(count):
    """(blocks, threads) of a row kernel over `count` rows: blocks of 32 under the simulator (it
    starts a Python thread per GPU thread, idle ones included; same results), THREADS on a GPU."""
    t = 32 if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1" else THREADS
    return (count + t - 1) // t, t


class CUDABackend:
    """Compiled CUDA kernels for one scheme specialisation, on device arrays."""

    name = "cuda"
    #: the particle arrays live on the device (copy them with `to_host` / `copy_into`)
    host_memory = False

    def __init__(self, spec):
        ok, why = cuda_status()
        if not ok:
            raise InputError(f"backend 'cuda' is not available here: {why}; use --backend cpu")
        self._cuda = cuda
        self.spec = spec
        max_registers()  # a bad cap is refused here, in one line, before anything is compiled
        for name, value in vars(_loops_for(spec)).items():  # compiled once per process and scheme
            setattr(self, name, value)
        self._accel2, self._first_bad, self._max = _reductions()
        self._rows = None  # the row kernels, built on first use (MPI runs only)
        self._a2 = None
        self._bad = cuda.device_array(1, dtype=np.int64)
        self.compile_seconds = 0.0
        self._seen = set()

    @staticmethod
    def threads():
        return THREADS

    def timed(self, kernel, n, args):
        import time

        first = id(kernel) not in self._seen
        t0 = time.perf_counter()
        kernel(n, args)
        if first:
            self._cuda.synchronize()
            self.compile_seconds += time.perf_counter() - t0
            self._seen.add(id(kernel))

    # -- reductions
    def dt_terms(self, n, ace, mu_max, kind):
        """(max |a|^2 over fluid particles, max viscous term) on the device."""
        if n == 0:
            return 0.0, 0.0
        if self._a2 is None or self._a2.shape[0] < len(kind):
            self._a2 = self._cuda.device_array(len(kind), dtype=ace.dtype)
        self._accel2[(n + THREADS - 1) // THREADS, THREADS](n, ace, kind, self._a2)
        return float(self._max(self._a2[:n])), float(self._max(mu_max[:n]))

    def body_sums(self, n, pos, force, kind, idp, motion_of, ghost, use_ghost, row, centres, out):
        """(F, T) of each floating body into the device array `out` (`shoal.backends.cpu.body_sums`)."""
        zero_rows, sums = _body_kernels()
        zero_rows[1, max(32, out.shape[0])](out)
        if n > 0:
            sums[(n + THREADS - 1) // THREADS, THREADS](n, pos, force, kind, idp, motion_of, ghost, bool(use_ghost),
                                                        row, centres, out)

    def find_bad(self, n, pos, vel, rho, kind, rho_lo, rho_hi):
        """(index, code) of the first unstable particle, or (-1, 0)."""
        if n == 0:
            return -1, 0
        self._bad.copy_to_device(np.array([n], dtype=np.int64))
        F = self.spec.float_type
        self._first_bad[(n + THREADS - 1) // THREADS, THREADS](n, pos, vel, rho, kind, F(rho_lo), F(rho_hi),
                                                               self._bad)
        i = int(self._bad.copy_to_host()[0])
        if i >= n:
            return -1, 0
        r = float(rho[i: i + 1].copy_to_host()[0])
        p = pos[i: i + 1].copy_to_host()
        v = vel[i: i + 1].copy_to_host()
        code = 1 if not (np.isfinite(r) and np.all(np.isfinite(p)) and np.all(np.isfinite(v))) else 2
        return i, code

    # -- arrays live on the device
    def asarray(self, a):
        return self._cuda.to_device(np.ascontiguousarray(a))

    def zeros(self, shape, dtype):
        return self._cuda.to_device(np.zeros(shape, dtype=dtype))

    def copy(self, a):
        out = self._cuda.device_array(a.shape, dtype=a.dtype)
        out.copy_to_device(a)
        return out

    @staticmethod
    def to_host(a, start, stop):
        return a[start:stop].copy_to_host()

    @staticmethod
    def copy_into(dst, src, n):
        """Rows 0..n of the device array `dst` from `src` (a host or device array)."""
        if n > 0:
            dst[:n].copy_to_device(src[:n])

    @staticmethod
    def copy_to_host(dst, src, n):
        """Rows 0..n of the host array `dst` (C-contiguous) from the device array `src`."""
        if n > 0:
            src[:n].copy_to_host(dst[:n])

    # -- rows of particle arrays in a float64 buffer (the MPI halo, `shoal.parallel`)
    def _row_kernel(self, kind, a):
        if self._rows is None:
            self._rows = _row_kernels()
        return self._rows[kind][0 if a.ndim == 1 else 1]

    def pack_rows(self, arrays, rows, k, out):
        """Write rows ``rows[:k]`` of each of `arrays` side by side into ``out[:k]``, on the device
        (see `shoal.backends.cpu.CPUBackend.pack_rows`; `rows` and `out` are device arrays)."""
        if k == 0:
            return
        for a, c, _ in row_columns(arrays):
            self._row_kernel("pack", a)[_launch(k)](a, rows, k, out, c)

    def unpack_rows(self, arrays, buf, rows, k):
        """Write ``buf[:k]`` into rows ``rows[:k]`` of each of `arrays`, on the device (the inverse
        of `pack_rows`; each value converted to its array's dtype)."""
        if k == 0:
            return
        for a, c, _ in row_columns(arrays):
            self._row_kernel("unpack", a)[_launch(k)](a, buf, rows, k, c)

    def zero_rows(self, arrays, rows, k):
        """Set rows ``rows[:k]`` of each of `arrays` to zero, on the device."""
        if k == 0:
            return
        for a in arrays:
            self._row_kernel("zero", a)[_launch(k)](a, rows, k)

    @staticmethod
    def make_grid(lo, hi, support, cells_per_support, capacity, periodic=None):
        from ..neighbours.cuda_grid import CudaCellGrid

        # the simulator runs a Python thread per CUDA thread and is slow at barriers:
        # small blocks there (same kernels, same results), 256 on a GPU
        block = 32 if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1" else 256
        return CudaCellGrid(lo, hi, support, cells_per_support, capacity, block_size=block, periodic=periodic)
