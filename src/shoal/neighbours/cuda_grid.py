"""Uniform cell grid with a stable sort of particles by cell (CUDA).

The GPU counterpart of `shoal.neighbours.grid.CellGrid`: the same
constructor arguments, the same geometry (taken from a `CellGrid` built
with capacity 0, so the two can never drift apart), the same cell numbering
c = ix + nx (iy + ny iz) (x fastest; 2D grids are (nx, 1, nz)), and the
same result: particles outside the box [lo, hi) or with a non-finite
coordinate get the extra cell ``ncell`` and sort to the end. The
permutation, the sorted cells and ``cell_start`` are *equal* to the CPU
grid's, element for element, because both sorts are stable (ties keep the
particle order), so a CPU and a CUDA run visit particles in the same order.

Method: a device LSD radix sort
-------------------------------
A counting sort whose scatter uses atomics to claim slots is not stable
(the order in which threads win the atomic is arbitrary), and ranking each
particle within its cell by counting the earlier particles of that cell
costs O(N * particles per cell) with a worst case of O(N^2). Instead
`bin` sorts the keys ``cell`` (values: the particle index) with a
least-significant-digit radix sort, which is stable by construction and
has no data-dependent worst case:

1. ``cell`` kernel: one thread per particle computes its cell (exactly the
   CPU arithmetic: ``min(int((x - lo) * (1 / cell_size)), dims - 1)`` in float64).
2. For each 4-bit digit of the key (``ceil(bit_length(ncell) / 4)``
   passes: 3 for 4095 cells, 6 for 10^7 cells), with blocks of ``T``
   threads (``block_size``, one key per thread):

   a. ``count``: each block histograms its keys' digit in shared memory
      (shared atomics; a sum, so the result does not depend on their
      order) into ``hist[digit * nblocks + block]`` (digit-major).
   b. an exclusive prefix sum of ``hist`` on the device (multi-block scan:
      per-tile scan of ``4 T`` counters, a recursive scan of the tile sums,
      then adding them back) gives, for every (digit, block), the first
      output slot of that block's keys with that digit. Digit-major, then
      block order, is exactly stable order.
   c. ``scatter``: each block ranks its keys stably within their digit
      (a block-wide exclusive scan of a 16 x T table of one-hot flags in
      shared memory, digit-major, so rank = number of keys of the block
      with a smaller digit, or the same digit and a smaller thread) and
      writes key and value to ``hist[digit, block] + rank``.

   The buffers ping-pong; the first buffer is chosen so that the last
   pass lands in ``cell_d`` / ``perm_d``.
3. ``cell_start`` kernel: one thread per cell c in [0, ncell + 2) sets
   ``cell_start[c]`` to the number of sorted keys smaller than c, by a
   binary search in the sorted keys (no atomics, no second scan; empty
   cells need no special case; ``cell_start[ncell]`` is the number of
   active particles, ``cell_start[ncell + 1] = n``).

Work: O(N * passes) for the sort, each pass reading the keys twice and
values once and writing keys and values (about 20 bytes per particle and
pass: 1.2 GB of traffic for 10^7 particles over 10^7 cells, 6 passes),
plus O(N / 16) for the scans of the histograms and O(ncell log2 N) for
``cell_start``; there is no data-dependent worst case (all particles in
one cell costs the same). Kernel launches per `bin`: 2 + passes * (3 + 2
per extra scan level); one scan level covers 4 T^2 / 16 = 16384
particles at T = 256, two cover 1.7e7. A tuned library sort (CUB's
onesweep: 8-bit digits, several keys per thread, decoupled look-back) is
faster; this one is self-contained, deterministic and runs under the CUDA
simulator, which has no warp intrinsics (shuffles, ballots): every
intra-block exchange here goes through shared memory and ``syncthreads``.

Memory on the device: 16 bytes per particle (two key and two value
buffers) + 64 / T bytes per particle (radix histograms) + 4 bytes per cell
(``cell_start``), all allocated once in ``__init__``.

Nothing is copied back to the host by `bin` unless asked: ``n_active``
(a property) copies the one integer ``cell_start[ncell]`` when it is read,
and ``n_active_d`` is that integer as a 1-element device view for kernels.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import cuda, int32

from ..backends.simulator import barrier_free, prepare
from .grid import CellGrid

prepare()  # under the CUDA simulator only: shared arrays one per block, barrier-free kernels in one thread

RADIX_BITS = 4
RADIX = 1 << RADIX_BITS
RADIX_MASK = RADIX - 1
SCAN_ITEMS = 4  # counters per thread in the prefix-sum tiles
DEFAULT_BLOCK = 256


def _pad(f):
    """Shared-memory index of flat element f with one padding word per 32
    (so that threads reading consecutive runs hit distinct banks)."""
    return f + (f >> 5)


@functools.lru_cache(maxsize=None)
def _kernels(block):
    """The CUDA kernels for blocks of `block` threads (a power of two).

    Shared-array sizes must be compile-time constants, so the kernels are
    built once per block size (and compiled lazily per argument types).
    """
    T = block
    TILE = T * SCAN_ITEMS
    FLAGS = RADIX * T
    FLAGS_PAD = _pad(FLAGS)
    TILE_PAD = _pad(TILE)
    T_PAD = _pad(T)
    R = T // 32

    @cuda.jit(device=True)
    def pad(f):
        return f + (f >> 5)

    @cuda.jit(device=True)
    def block_exclusive_scan(val, tmp, tmp2, t):
        """Exclusive prefix of `val` over the block's threads, and the
        block total. A raking scan with 4 barriers: 32 threads each sum
        R = T / 32 consecutive values, thread 0 scans those 32 sums, the 32
        threads write the prefixes back. `tmp` (pad(T) int32) and `tmp2`
        (33 int32) are shared; they must not be reused before a barrier.
        """
        tmp[pad(t)] = val
        cuda.syncthreads()
        if t < 32:
            acc = 0
            for j in range(R):
                acc += tmp[pad(t * R + j)]
            tmp2[t] = acc
        cuda.syncthreads()
        if t == 0:
            run = 0
            for j in range(32):
                v = tmp2[j]
                tmp2[j] = run
                run += v
            tmp2[32] = run
        cuda.syncthreads()
        if t < 32:
            run = tmp2[t]
            for j in range(R):
                f = pad(t * R + j)
                v = tmp[f]
                tmp[f] = run
                run += v
        cuda.syncthreads()
        return tmp[pad(t)], tmp2[32]

    @barrier_free
    @cuda.jit
    def cell_index(pos, n, lo, hi, inv_cs, dims, ncell, out):
        i = cuda.grid(1)
        if i < n:
            dim = pos.shape[1]
            c = 0
            stride = 1
            inside = True
            for d in range(dim):
                x = pos[i, d]
                if not (x >= lo[d] and x < hi[d]):  # also catches NaN
                    inside = False
                    break
                v = (x - lo[d]) * inv_cs
                c += min(int(v), dims[d] - 1) * stride
                stride *= dims[d]
            out[i] = c if inside else ncell

    @cuda.jit
    def radix_count(keys, n, shift, hist, nblocks):
        s = cuda.shared.array(RADIX, int32)
        t = cuda.threadIdx.x
        b = cuda.blockIdx.x
        if t < RADIX:
            s[t] = 0
        cuda.syncthreads()
        i = b * T + t
        if i < n:
            cuda.atomic.add(s, (keys[i] >> shift) & RADIX_MASK, 1)
        cuda.syncthreads()
        if t < RADIX:
            hist[t * nblocks + b] = s[t]

    @cuda.jit
    def radix_scatter(keys_in, vals_in, keys_out, vals_out, n, shift, hist, nblocks, first):
        flags = cuda.shared.array(FLAGS_PAD, int32)
        tmp = cuda.shared.array(T_PAD, int32)
        tmp2 = cuda.shared.array(33, int32)
        t = cuda.threadIdx.x
        b = cuda.blockIdx.x
        i = b * T + t
        for d in range(RADIX):  # flat index d * T + t: digit-major
            flags[pad(d * T + t)] = 0  # (own column: no barrier needed)
        valid = i < n
        k = 0
        dig = 0
        if valid:
            k = keys_in[i]
            dig = (k >> shift) & RADIX_MASK
            flags[pad(dig * T + t)] = 1
        cuda.syncthreads()
        # each thread scans RADIX consecutive flat entries, then the block
        acc = 0
        for j in range(RADIX):
            acc += flags[pad(t * RADIX + j)]
        excl, total = block_exclusive_scan(acc, tmp, tmp2, t)
        run = excl
        for j in range(RADIX):
            f = pad(t * RADIX + j)
            v = flags[f]
            flags[f] = run
            run += v
        cuda.syncthreads()
        if valid:
            # flags[d, t]: keys of the block before (d, t) in digit-major order
            rank = flags[pad(dig * T + t)] - flags[pad(dig * T)]
            dst = hist[dig * nblocks + b] + rank
            keys_out[dst] = k
            vals_out[dst] = i if first else vals_in[i]

    @cuda.jit
    def scan_tiles(a, m, sums):
        tile = cuda.shared.array(TILE_PAD, int32)
        tmp = cuda.shared.array(T_PAD, int32)
        tmp2 = cuda.shared.array(33, int32)
        t = cuda.threadIdx.x
        b = cuda.blockIdx.x
        base = b * TILE
        for j in range(SCAN_ITEMS):  # coalesced load
            f = j * T + t
            g = base + f
            tile[pad(f)] = a[g] if g < m else 0
        cuda.syncthreads()
        acc = 0
        for j in range(SCAN_ITEMS):
            acc += tile[pad(t * SCAN_ITEMS + j)]
        excl, total = block_exclusive_scan(acc, tmp, tmp2, t)
        run = excl
        for j in range(SCAN_ITEMS):
            f = pad(t * SCAN_ITEMS + j)
            v = tile[f]
            tile[f] = run
            run += v
        cuda.syncthreads()
        for j in range(SCAN_ITEMS):
            f = j * T + t
            g = base + f
            if g < m:
                a[g] = tile[pad(f)]
        if t == 0:
            sums[b] = total

    @barrier_free
    @cuda.jit
    def add_offsets(a, m, sums):
        t = cuda.threadIdx.x
        b = cuda.blockIdx.x
        off = sums[b]
        base = b * TILE
        for j in range(SCAN_ITEMS):
            g = base + j * T + t
            if g < m:
                a[g] += off

    @barrier_free
    @cuda.jit
    def cell_starts(cell, n, ncell2, out):
        c = cuda.grid(1)
        if c < ncell2:
            lo = 0
            hi = n
            while lo < hi:  # lower bound of c in the sorted keys
                mid = (lo + hi) // 2
                if cell[mid] < c:
                    lo = mid + 1
                else:
                    hi = mid
            out[c] = lo

    @barrier_free
    @cuda.jit
    def gather_1d(a, perm, n, out):
        k = cuda.grid(1)
        if k < n:
            out[k] = a[perm[k]]

    @barrier_free
    @cuda.jit
    def copy_1d(src, n, dst):
        k = cuda.grid(1)
        if k < n:
            dst[k] = src[k]

    @barrier_free
    @cuda.jit
    def gather_2d(a, perm, n, out):
        e = cuda.grid(1)  # one thread per element: coalesced writes
        m = a.shape[1]
        if e < n * m:
            k = e // m
            d = e - k * m
            out[k, d] = a[perm[k], d]

    @barrier_free
    @cuda.jit
    def copy_2d(src, n, dst):
        e = cuda.grid(1)
        m = src.shape[1]
        if e < n * m:
            k = e // m
            d = e - k * m
            dst[k, d] = src[k, d]

    return dict(cell_index=cell_index, radix_count=radix_count, radix_scatter=radix_scatter,
                scan_tiles=scan_tiles, add_offsets=add_offsets, cell_starts=cell_starts,
                gather_1d=gather_1d, copy_1d=copy_1d, gather_2d=gather_2d, copy_2d=copy_2d)


def _blocks(count, block):
    return (count + block - 1) // block


class CudaCellGrid:
    """A uniform grid of cells over [lo, hi) and its particle sort, on a GPU.

    Parameters
    ----------
    lo, hi : sequence of float, length dim
        Lower and upper corners of the domain [m]; particles outside are
        taken out of the computation (sorted to the end).
    support : float
        Kernel support radius 2h [m].
    cells_per_support : int
        Cells per support radius (cell size = support / cells_per_support).
    capacity : int
        Number of particles the device work arrays are sized for.
    block_size : int, optional
        Threads per block of the sort kernels, a power of two in [32, 512]
        (default 256; the radix scatter holds 68 * block_size bytes of
        shared memory).
    stream : numba.cuda.cudadrv.driver.Stream or 0, optional
        Stream every kernel is launched on (default: the default stream).

    Attributes
    ----------
    perm_d : device array of int32, (capacity,)
        After `bin`, ``perm_d[k]`` is the particle that goes to slot k.
    cell_d : device array of int32, (capacity,)
        After `bin`, the cells in sorted order (the cell of the particle in
        slot k once `reorder` has run); ``ncell`` for removed particles.
    cell_start_d : device array of int32, (ncell + 2,)
        First slot of each cell; ``cell_start_d[ncell]`` is the number of
        active particles and ``cell_start_d[ncell + 1]`` is n.
    n_active_d : device array of int32, (1,)
        A view of ``cell_start_d[ncell]``, for kernels.
    gdims : tuple of int
        (nx, ny, nz) as the gather expects; 2D grids are (nx, 1, nz).
    gdims_arr : device array of int64, (3,)
        `gdims` on the device.
    ncell : int
        Number of cells; the extra cell ``ncell`` holds removed particles.
    cell, cell_start, perm
        The same device arrays under `CellGrid`'s names (a drop-in for code
        that takes either grid).
    dim, n, cell_size, lo, hi, grid_hi, dims
        The geometry, as in `CellGrid`.

    Notes
    -----
    The geometry and its validation (`InputError` for bad bounds or too
    many cells) come from a `CellGrid` of capacity 0, which briefly holds
    a host array of ncell + 2 int32.
    """

    def __init__(self, lo, hi, support, cells_per_support, capacity, block_size=DEFAULT_BLOCK, stream=0,
                 periodic=None):
        block_size = int(block_size)
        if block_size < 32 or block_size > 512 or block_size & (block_size - 1):
            raise ValueError(f"block_size must be a power of two in [32, 512], got {block_size}")
        ref = CellGrid(lo, hi, support, cells_per_support, 0, periodic=periodic)
        self.dim = ref.dim
        self.n = ref.n
        self.cell_size = ref.cell_size
        self.lo = ref.lo
        self.hi = ref.hi
        self.grid_hi = ref.grid_hi
        self.dims = ref.dims
        self.ncell = ref.ncell
        self.gdims = ref.gdims
        del ref
        self.capacity = int(capacity)
        self.block_size = block_size
        self.stream = stream
        self._k = _kernels(block_size)
        self._inv_cs = 1.0 / self.cell_size
        self._passes = max(1, math.ceil(self.ncell.bit_length() / RADIX_BITS))

        self.gdims_arr = cuda.to_device(np.array(self.gdims, dtype=np.int64))
        self._lo_d = cuda.to_device(self.lo)
        self._hi_d = cuda.to_device(self.hi)
        self._dims_d = cuda.to_device(np.asarray(self.dims, dtype=np.int64))
        self.cell_start_d = cuda.device_array(self.ncell + 2, dtype=np.int32)
        self._allocate(self.capacity)
        self.n_active_d = self.cell_start_d[self.ncell:self.ncell + 1]
        self._host1 = np.zeros(1, dtype=np.int32)
        self._n = 0
        # an empty grid: every cell starts at 0
        self._k["cell_starts"][_blocks(self.ncell + 2, block_size), block_size, stream](
            self.cell_d, 0, self.ncell + 2, self.cell_start_d)

    def _allocate(self, capacity):
        """The per-particle work arrays (sorted cells, permutation, the radix sort's buffers)."""
        cap = max(int(capacity), 1)
        self.cell_d = cuda.device_array(cap, dtype=np.int32)
        self.perm_d = cuda.device_array(cap, dtype=np.int32)
        self._keys_alt = cuda.device_array(cap, dtype=np.int32)
        self._vals_alt = cuda.device_array(cap, dtype=np.int32)
        self._hist = cuda.device_array(RADIX * _blocks(cap, self.block_size), dtype=np.int32)
        # tile sums of each level of the multi-block scan of _hist
        tile = self.block_size * SCAN_ITEMS
        self._scan_aux = []
        m = self._hist.size
        while True:
            nb = _blocks(m, tile)
            self._scan_aux.append(cuda.device_array(nb, dtype=np.int32))
            if nb <= 1:
                break
            m = nb

    def resize(self, capacity):
        """Hold up to `capacity` particles from now on (new work arrays; the last `bin` is
        forgotten: call `bin` before reading `perm_d` / `cell_d` again). The cell table keeps
        its size."""
        self.capacity = int(capacity)
        self._allocate(self.capacity)
        self._n = 0

    # the CellGrid names, so that code written for either grid takes both
    @property
    def cell(self):
        """`cell_d` (the name `CellGrid` uses)."""
        return self.cell_d

    @property
    def cell_start(self):
        """`cell_start_d` (the name `CellGrid` uses)."""
        return self.cell_start_d

    @property
    def perm(self):
        """`perm_d` (the name `CellGrid` uses)."""
        return self.perm_d

    @property
    def nbytes(self):
        """Bytes of device memory held by the grid's arrays."""
        arrays = [self.cell_start_d, self.cell_d, self.perm_d, self._keys_alt, self._vals_alt, self._hist,
                  self.gdims_arr, self._lo_d, self._hi_d, self._dims_d, *self._scan_aux]
        return int(sum(a.nbytes for a in arrays))

    @property
    def n_active(self):
        """Number of particles inside the domain at the last `bin` (copies
        one int32 from the device, which waits for the stream)."""
        self.n_active_d.copy_to_host(self._host1, stream=self.stream)
        if not isinstance(self.stream, int):
            self.stream.synchronize()
        return int(self._host1[0])

    def bin(self, pos_d, n, read_back=True):
        """Compute the cells of the first `n` particles and the stable sort.

        Parameters
        ----------
        pos_d : device array, (>= n, dim), float32 or float64
            Particle positions (x, y, z in 3D; x, z in 2D).
        n : int
            Number of particles to bin (at most `capacity`).
        read_back : bool, optional
            Return the number of active particles (one 4-byte copy to the
            host, which synchronises). With False nothing is copied and
            None is returned; read `n_active` or use `n_active_d` later.

        Returns
        -------
        int or None
            The number of particles inside the domain (``cell_start[ncell]``).

        Notes
        -----
        Afterwards ``perm_d[k]`` is the particle for slot k, ``cell_d`` holds
        the sorted cells and ``cell_start_d`` the first slot of each cell;
        call `reorder` on every particle array.
        """
        n = int(n)
        if n < 0 or n > self.capacity:
            raise ValueError(f"cannot bin {n} particles in a grid of capacity {self.capacity}")
        if n and pos_d.shape[1] != self.dim:
            raise ValueError(f"positions have {pos_d.shape[1]} columns, the grid is {self.dim}D")
        k = self._k
        T = self.block_size
        s = self.stream
        self._n = n
        if n:
            nblocks = _blocks(n, T)
            passes = self._passes
            final = (self.cell_d, self.perm_d)
            alt = (self._keys_alt, self._vals_alt)
            # the buffer of pass p's input: the last pass must write `final`
            src = final if passes % 2 == 0 else alt
            dst = alt if src is final else final
            k["cell_index"][nblocks, T, s](pos_d, n, self._lo_d, self._hi_d, self._inv_cs, self._dims_d,
                                           self.ncell, src[0])
            for p in range(passes):
                shift = p * RADIX_BITS
                k["radix_count"][nblocks, T, s](src[0], n, shift, self._hist, nblocks)
                self._exclusive_scan(self._hist, RADIX * nblocks)
                k["radix_scatter"][nblocks, T, s](src[0], src[1], dst[0], dst[1], n, shift, self._hist,
                                                  nblocks, p == 0)
                src, dst = dst, src
        k["cell_starts"][_blocks(self.ncell + 2, T), T, s](self.cell_d, n, self.ncell + 2, self.cell_start_d)
        return self.n_active if read_back else None

    def _exclusive_scan(self, a, m, level=0):
        """In-place exclusive prefix sum of the first `m` int32 of device
        array `a` (m at most the radix histogram size)."""
        k = self._k
        T = self.block_size
        nb = _blocks(m, T * SCAN_ITEMS)
        sums = self._scan_aux[level]
        k["scan_tiles"][nb, T, self.stream](a, m, sums)
        if nb > 1:
            self._exclusive_scan(sums, nb, level + 1)
            k["add_offsets"][nb, T, self.stream](a, m, sums)

    def reorder(self, arrays, n, scratch):
        """Permute the first `n` rows of each device array into cell order.

        Parameters
        ----------
        arrays : sequence of device arrays, (>= n,) or (>= n, k)
            Arrays permuted in place by ``a[:n] = a[perm_d[:n]]``.
        n : int
            The `n` of the last `bin`.
        scratch : dict
            Maps ``(a.dtype.str, k)`` (k = 0 for 1D arrays) to a device work
            array of that dtype at least n long (and k wide), as made once
            by `make_scratch`; nothing is allocated here.
        """
        k = self._k
        T = self.block_size
        s = self.stream
        n = int(n)
        if n == 0:
            return
        perm = self.perm_d
        for a in arrays:
            if a.ndim == 1:
                w = scratch[(a.dtype.str, 0)]
                nb = _blocks(n, T)
                k["gather_1d"][nb, T, s](a, perm, n, w)
                k["copy_1d"][nb, T, s](w, n, a)
            else:
                w = scratch[(a.dtype.str, a.shape[1])]
                nb = _blocks(n * a.shape[1], T)
                k["gather_2d"][nb, T, s](a, perm, n, w)
                k["copy_2d"][nb, T, s](w, n, a)

    def make_scratch(self, arrays):
        """Device work arrays for `reorder` of arrays shaped like `arrays`.

        Returns a dict mapping ``(dtype.str, k)`` to a device array of
        `capacity` rows (one per distinct dtype and width). Call once.
        """
        scratch = {}
        cap = max(self.capacity, 1)
        for a in arrays:
            key = (a.dtype.str, 0 if a.ndim == 1 else a.shape[1])
            if key not in scratch:
                shape = cap if a.ndim == 1 else (cap, a.shape[1])
                scratch[key] = cuda.device_array(shape, dtype=a.dtype)
        return scratch
