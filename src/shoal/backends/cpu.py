"""CPU backend: per-particle physics run by Numba ``prange`` loops.

Every per-particle function of `shoal.physics` and `shoal.timestepping`
is compiled with `numba.njit` and called from one parallel loop over the
particles in cell order (`for_each`). Compiled kernels are cached on disk
(``cache=True``), one per distinct kernel: schemes that build a kernel alike share it
(`shoal.physics.identity`).
"""

from __future__ import annotations

import hashlib
import time

import numba
import numpy as np

from ..faults import reached
from ..neighbours.grid import CellGrid
from ..neighbours.half_sweep import COLOURS, deal_tiles, tile_counter
from ..physics.identity import shared_loop
from ..physics.spec import FLUID, MOVING
from .loops import attach_loops, row_columns

# Fast-math flags that keep NaN/inf semantics (NaN checks must still work).
# No "reassoc": with it, a kernel compiled in this process and the same kernel
# loaded from Numba's on-disk cache gave different rounding (a 2D dam break
# differed by 2e-7 m after 2,461 steps), which broke bitwise restart of a run
# first started on a cold cache; without it both are bitwise equal (tested in
# tests/test_determinism.py), at no measurable cost on the 3D benchmark.
# (a dict, not a set: its pickle is deterministic, which the on-disk cache key needs)
FASTMATH = {"nsz": True, "arcp": True, "contract": True, "afn": True}

_CALLED = set()
"""Loop kernels that have run in this process (compiled or loaded from the cache): `CPUBackend.timed`."""


def cpu_jit(fn):
    """Decorator for shared per-particle functions on the CPU.

    ``error_model="numpy"``: a division by zero gives inf or NaN (which the run's checks report
    with the particle) instead of a test and a branch to raise Python's ZeroDivisionError at every
    division; that branch kept LLVM from vectorising the pair loop (`shoal.neighbours.gather`)."""
    return numba.njit(fastmath=FASTMATH, _nrt=False, error_model="numpy")(fn)


def make_for_each(fn):
    """Return ``run(n, args)`` calling ``fn(i, *args)`` for i < n in parallel.

    One loop kernel per identity of `fn` in a process (`shoal.physics.identity.shared_loop`): the
    schemes that share a per-particle function share its loop, compiled or loaded once.

    Each kernel gets its own entry in Numba's on-disk cache (a qualified name made from `fn`'s
    name and content identity, `cache_name`), so that kernels that differ never share an index
    file. Under one shared name, every kernel of every scheme went into one index file, and two
    processes compiling different kernels at once on one cache directory (MPI ranks, a parameter
    sweep) could both take the same data file for different kernels: a later process then loaded
    the other scheme's machine code (3D still water lost its particles). Schemes whose kernel is
    the same (same identity) do share its entry, as they should: the machine code is the same.
    """
    return shared_loop(fn, _build_for_each)


def _build_for_each(fn):
    # np.uint64(i): Numba types the loop body twice, first as a plain loop (i an int64), then as
    # the parallel loop's body (i a uint64); without the cast `fn` and every function it passes i
    # on to were compiled for both, and only the uint64 one ran (a sixth of the suite's compile
    # time). With it the same uint64 code as before is compiled, once.
    def run(n, args):
        for i in numba.prange(n):
            fn(np.uint64(i), *args)
    run.__qualname__ = cache_name(fn)
    return numba.njit(parallel=True, cache=True, fastmath=FASTMATH, _nrt=False)(run)


def cache_name(fn):
    """``for_each_<function>_<16 hex digits>``: the qualified name of `fn`'s loop kernel, from the
    stable name (``_uuid``, its content identity) `shoal.physics.identity.named` gives each compiled
    function."""
    name = getattr(fn, "py_func", fn).__name__
    digest = hashlib.sha1(str(fn._uuid).encode()).hexdigest()[:16]
    return f"for_each_{name}_{digest}"


def _build_mutual_sweep(tile):
    # the threads sweep the tiles dealt to them (`shoal.neighbours.half_sweep`), colour after colour: a
    # parallel loop of `threads` iterations, one a thread
    def run(n, args, threads, cost, colour_of, order, starts, wet):
        (pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph, mu_max, tau, planes,
         ptable, vwall, idp, ghosts, gid0) = args
        n_tiles = colour_of.shape[0]
        for i in numba.prange(n):
            tile(0, np.uint64(i), pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph,
                 mu_max, planes, ptable, tau, vwall, cost, colour_of, wet)
        for t in numba.prange(n_tiles):
            tile(1, np.uint64(t), pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph,
                 mu_max, planes, ptable, tau, vwall, cost, colour_of, wet)
        deal_tiles(colour_of, threads, cost, order, starts)
        for colour in range(COLOURS):
            base = colour * (threads + 1)
            for t in numba.prange(threads):
                for k in range(starts[base + t], starts[base + t + 1]):
                    tile(2, np.uint64(order[k]), pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr,
                         ace, drho, xsph, mu_max, planes, ptable, tau, vwall, cost, colour_of, wet)

    digest = hashlib.sha1(str(tile._uuid).encode()).hexdigest()[:16]
    run.__qualname__ = f"mutual_sweep_{digest}"
    return numba.njit(parallel=True, cache=True, fastmath=FASTMATH, _nrt=False)(run)


class MutualRates:
    """The CPU's ``rates`` a pair at a time (`shoal.physics.mutual`): ``rates(n, args)`` with the
    arguments of the per-particle rates, each pair evaluated once and its terms added to both
    particles, the grid's tiles swept colour by colour (`shoal.neighbours.half_sweep`). Holds the
    tiles' work arrays (a few numbers a tile, allocated when the grid or the thread count changes)."""

    def __init__(self, tile, spec):
        self.kernel = shared_loop(tile, _build_mutual_sweep)
        self.tile_count = tile_counter(spec)
        self._key = None

    def __getattr__(self, name):
        # the compiled kernel's attributes (``signatures``, empty before its first call: `CPUBackend.timed`;
        # ``py_func``, whose name is the kernel's on-disk cache name)
        if name == "kernel":
            raise AttributeError(name)
        return getattr(self.kernel, name)

    def __call__(self, n, args):
        threads = numba.get_num_threads()
        dims = tuple(int(d) for d in args[8][:3])
        if self._key != (dims, threads):
            self._key = (dims, threads)
            n_tiles = self.tile_count(dims)
            self._cost = np.zeros(n_tiles + threads)
            self._colour = np.zeros(n_tiles, np.int64)
            self._order = np.zeros(3 * n_tiles + threads, np.int64)
            self._starts = np.zeros(COLOURS * (threads + 1), np.int64)
            self._wet = np.zeros(n_tiles, np.uint8)
        self.kernel(n, args, threads, self._cost, self._colour, self._order, self._starts, self._wet)


@numba.njit(parallel=True, cache=True)
def dt_terms(n, ace, mu_max, kind):
    """max |a|^2 over fluid particles and max |h v.r/(r^2+eta^2)|."""
    amax = 0.0
    vm = 0.0
    dim = ace.shape[1]
    for i in numba.prange(n):
        if kind[i] == FLUID:
            a2 = 0.0
            for d in range(dim):
                a2 += float(ace[i, d]) ** 2
            amax = max(amax, a2)
            vm = max(vm, float(mu_max[i]))
    return amax, vm


@numba.njit(parallel=True, cache=True)
def split_positions(n, pos, lo, out):
    """The compact gather's split coordinates (`shoal.neighbours.gather.make_gather`) of the first n
    particles, one coordinate a row: with v = pos[i, d] - lo[d] (float64), out[d, i] = float32(v) (the
    high part) and out[dim + d, i] = float32(v - out[d, i]) (the low part); their sum holds v to about
    2^-48 v."""
    dim = pos.shape[1]
    for i in numba.prange(n):
        for d in range(dim):
            v = pos[i, d] - lo[d]
            hi = np.float32(v)
            out[d, i] = hi
            out[dim + d, i] = np.float32(v - np.float64(hi))


@numba.njit(cache=True)
def bad_code(i, pos, vel, rho, kind, rho_lo, rho_hi):
    """0 if particle i's state is sane, 1 if its position, velocity or density is not finite, 2 if it is
    a fluid particle with a density outside [rho_lo, rho_hi]."""
    r = rho[i]
    if not np.isfinite(r):
        return 1
    for d in range(pos.shape[1]):
        if not (np.isfinite(pos[i, d]) and np.isfinite(vel[i, d])):
            return 1
    if kind[i] == FLUID and (r < rho_lo or r > rho_hi):
        return 2
    return 0


@numba.njit(parallel=True, cache=True)
def find_bad(n, pos, vel, rho, kind, rho_lo, rho_hi):
    """First particle with a non-finite state or a density outside
    [rho_lo, rho_hi] (fluid only), or -1; and a code: 1 NaN/inf, 2 density (`bad_code`).
    Every step runs it: the threads scan the particles together (the lowest bad index wins)."""
    first = n
    for i in numba.prange(n):
        if bad_code(i, pos, vel, rho, kind, rho_lo, rho_hi) != 0:
            first = min(first, i)
    if first == n:
        return -1, 0
    return first, bad_code(first, pos, vel, rho, kind, rho_lo, rho_hi)


@numba.njit(cache=True)
def body_sums(n, pos, force, kind, idp, motion_of, ghost, use_ghost, row, centres, out):
    """out[j] = (F, T) of floating body j: F = sum F_b, T = sum (x_b - c_j) x F_b over its moving boundary
    particles b (`row[motion_of[id]]` = j), ghosts left out when `use_ghost` (`Model.floating_loads`).
    A serial sum in particle order: the same order gives the same bits (bitwise resume)."""
    dim = pos.shape[1]
    out[:, :] = 0.0
    for i in range(n):
        if kind[i] != MOVING or (use_ghost and ghost[i] != 0):
            continue
        j = row[motion_of[idp[i]]]
        if j < 0:
            continue
        if dim == 3:
            fx, fy, fz = float(force[i, 0]), float(force[i, 1]), float(force[i, 2])
            rx, ry, rz = pos[i, 0] - centres[j, 0], pos[i, 1] - centres[j, 1], pos[i, 2] - centres[j, 2]
            out[j, 1] += fy
            out[j, 3] += ry * fz - rz * fy
            out[j, 5] += rx * fy - ry * fx
        else:  # (x, z) stored; the torque is about y
            fx, fz = float(force[i, 0]), float(force[i, 1])
            rx, rz = pos[i, 0] - centres[j, 0], pos[i, 1] - centres[j, 2]
        out[j, 0] += fx
        out[j, 2] += fz
        out[j, 4] += rz * fx - rx * fz


class CPUBackend:
    """Compiled CPU kernels for one scheme specialisation.

    Attributes are ``run(n, args)`` loop kernels: ``pr2``, ``rates``,
    ``shepard``, ``mls``, ``verlet``, ``save_state``, ``half_step``,
    ``symplectic_correct``, ``pc_correct``.
    """

    name = "cpu"
    #: the particle arrays are NumPy arrays in host memory (code may edit them with NumPy)
    host_memory = True

    def __init__(self, spec):
        self.spec = spec
        attach_loops(self, cpu_jit, make_for_each, spec, "cpu")
        #: the rates particle by particle, as every backend has them; ``rates`` is `MutualRates` where the
        #: scheme allows (`shoal.physics.mutual`)
        self.rates_by_particle = self.rates
        if self.physics.mutual_tile is not None:
            self.rates = MutualRates(self.physics.mutual_tile, spec)
        self.compile_seconds = 0.0

    @staticmethod
    def threads():
        """Number of CPU threads Numba uses."""
        return numba.get_num_threads()

    def timed(self, kernel, n, args):
        """Run a kernel, adding its first-call (compile or cache load) time."""
        if kernel in _CALLED:  # a set lookup: `kernel.signatures` costs 20 us a call (a list of hashed types)
            kernel(n, args)
            return
        first = not kernel.signatures
        if first:
            reached("compile")  # a test hook (shoal.faults)
        t0 = time.perf_counter()
        kernel(n, args)
        if first:
            self.compile_seconds += time.perf_counter() - t0
        _CALLED.add(kernel)

    dt_terms = staticmethod(dt_terms)
    find_bad = staticmethod(find_bad)
    #: the rates read float32 split positions (`Model.split_positions`)
    split_positions = staticmethod(split_positions)
    body_sums = staticmethod(body_sums)

    # -- arrays: the CPU works on NumPy arrays in place
    @staticmethod
    def asarray(a):
        """The backend's copy of host array `a` (here: `a` itself)."""
        return a

    @staticmethod
    def zeros(shape, dtype):
        return np.zeros(shape, dtype=dtype)

    @staticmethod
    def copy(a):
        return a.copy()

    @staticmethod
    def to_host(a, start, stop):
        """Rows start..stop of `a` as a NumPy array (a view on the CPU)."""
        return a[start:stop]

    @staticmethod
    def copy_into(dst, src, n):
        """Rows 0..n of `dst` (a backend array) from `src` (a host or backend array)."""
        dst[:n] = src[:n]

    @staticmethod
    def copy_to_host(dst, src, n):
        """Rows 0..n of the host array `dst` from the backend array `src` (nothing when they are one array)."""
        if dst is not src and n > 0:
            dst[:n] = src[:n]

    # -- rows of particle arrays in a float64 buffer (the MPI halo, `shoal.parallel`)
    @staticmethod
    def pack_rows(arrays, rows, k, out):
        """Write rows ``rows[:k]`` of each of `arrays` side by side into ``out[:k]``.

        Parameters
        ----------
        arrays : sequence of backend arrays, (N,) or (N, w)
            Their columns follow each other in `out` (one column per 1D array).
        rows : backend int64 array, (>= k,)
            The rows to read.
        k : int
            Number of rows.
        out : backend float64 array, (>= k, columns)
            Receives the values (float32 and integer values are exact in float64).
        """
        if k == 0:
            return
        r = rows[:k]
        for a, c, w in row_columns(arrays):
            out[:k, c:c + w] = a[r].reshape(k, w)

    @staticmethod
    def unpack_rows(arrays, buf, rows, k):
        """The inverse of `pack_rows`: write ``buf[:k]`` into rows ``rows[:k]`` of each of `arrays`
        (converted to each array's dtype)."""
        if k == 0:
            return
        r = rows[:k]
        for a, c, w in row_columns(arrays):
            vals = buf[:k, c:c + w]
            a[r] = (vals[:, 0] if a.ndim == 1 else vals).astype(a.dtype)

    @staticmethod
    def zero_rows(arrays, rows, k):
        """Set rows ``rows[:k]`` of each of `arrays` to zero."""
        if k == 0:
            return
        r = rows[:k]
        for a in arrays:
            a[r] = 0

    @staticmethod
    def make_grid(lo, hi, support, cells_per_support, capacity, periodic=None):
        return CellGrid(lo, hi, support, cells_per_support, capacity, periodic=periodic)
