"""Uniform cell grid with a counting sort of particles by cell (CPU).

The domain box [lo, hi) is cut into cells of size 2h / n (n =
`cells_per_support`); the linear cell index is c = ix + nx (iy + ny iz)
(x fastest). Each binning computes every particle's cell, sorts the
particles by cell with a stable counting sort, and reorders the particle
arrays so that neighbours are close in memory. Particles outside the box
(or with a non-finite position) get the extra cell ``ncell`` and so sort
to the end: the active particles are the first ``cell_start[ncell]``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..errors import InputError

MAX_CELLS = 2**31 - 16


@numba.njit(parallel=True, cache=True)
def _cell_index(pos, n, lo, hi, inv_cs, dims, ncell, out):
    dim = pos.shape[1]
    for i in numba.prange(n):
        c = 0
        stride = 1
        inside = True
        for d in range(dim):
            x = pos[i, d]
            v = (x - lo[d]) * inv_cs
            if not (x >= lo[d] and x < hi[d]):  # also catches NaN
                inside = False
                break
            c += min(int(v), dims[d] - 1) * stride
            stride *= dims[d]
        out[i] = c if inside else ncell


@numba.njit(parallel=True, cache=True)
def _counting_sort(cell, n, ncell, cell_start, perm, threads, blocks):
    """Stable counting sort of the first n particles by ``cell`` (0 .. ncell), on `threads` threads.

    Each thread owns a block of cells [b_t, b_t+1) (``blocks[:threads + 1]``) and sorts the
    particles of its cells: it scans every particle and counts its own cells' (into ``cell_start``'s
    slots of those cells, which no other thread touches), then, once the blocks' totals give its
    offset, sums the counts up into the ends of its cells' ranges and scatters its particles from
    the last to the first, each to the end of its cell's range, which leaves the ranges' starts in
    ``cell_start``. The blocks split the work
    (two passes over a block's cells, two over its particles, as the previous sort's ``cell_start``
    counts them) evenly; any split gives the same result.
    ``blocks[threads + 1:]`` holds the blocks' totals (work space, 2 (threads + 1) values in all).
    """
    m = ncell + 1  # the cells 0 .. ncell (ncell: outside the grid)
    # a thread's work: two passes over its cells, two over its particles (the previous sort's)
    work = 2 * m + 2 * np.int64(cell_start[m])
    blocks[0] = 0
    for t in range(1, threads):
        target = (work * t) // threads
        a, b = blocks[t - 1], m  # the first cell c with 2 c + 2 cell_start[c] >= target
        while a < b:
            c = (a + b) // 2
            if 2 * c + 2 * np.int64(cell_start[c]) < target:
                a = c + 1
            else:
                b = c
        blocks[t] = a
    blocks[threads] = m
    total = blocks[threads + 1:]
    for t in numba.prange(threads):
        lo, hi = blocks[t], blocks[t + 1]
        for c in range(lo, hi):
            cell_start[c] = 0
        s = 0
        for i in range(n):
            c = cell[i]
            if c >= lo and c < hi:
                cell_start[c] += 1
                s += 1
        total[t] = s
    offset = 0
    for t in range(threads):
        s = total[t]
        total[t] = offset
        offset += s
    for t in numba.prange(threads):
        lo, hi = blocks[t], blocks[t + 1]
        end = total[t]
        for c in range(lo, hi):
            end += cell_start[c]
            cell_start[c] = end  # the end of cell c's range
        for i in range(n - 1, -1, -1):
            c = cell[i]
            if c >= lo and c < hi:
                cell_start[c] -= 1
                perm[cell_start[c]] = i
    cell_start[m] = n


@numba.njit(parallel=True, cache=True)
def _gather_rows(a, perm, n, scratch):
    m = a.shape[1]
    for k in numba.prange(n):
        p = perm[k]
        for d in range(m):
            scratch[k, d] = a[p, d]
    for k in numba.prange(n):
        for d in range(m):
            a[k, d] = scratch[k, d]


@numba.njit(parallel=True, cache=True)
def _gather_1d(a, perm, n, scratch):
    for k in numba.prange(n):
        scratch[k] = a[perm[k]]
    for k in numba.prange(n):
        a[k] = scratch[k]


@numba.njit(parallel=True, cache=True)
def _sorted_cells(cell, perm, n, out):
    for k in numba.prange(n):
        out[k] = cell[perm[k]]


def grid_dims(lo, hi, cell_size, periodic=None):
    """Cells along each axis of the grid over the box [lo, hi): ceil(L / cell_size), at least 1; a
    periodic axis is tiled by whole cells (floor: the last one up to 2x wider), so the stencil
    that wraps round still covers the support.

    Parameters
    ----------
    lo, hi : array_like, shape (2,) or (3,)
        The box [m] (2D: x, z).
    cell_size : float
        Cell edge [m]: the support 2h over the cells per support.
    periodic : sequence of bool, optional
        The periodic axes.

    Returns
    -------
    numpy.ndarray of int64
    """
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    dims = np.maximum(np.ceil((hi - lo) / cell_size).astype(np.int64), 1)
    for d in np.flatnonzero(np.zeros(lo.size, bool) if periodic is None else np.asarray(periodic, bool)):
        dims[d] = int(np.floor((hi[d] - lo[d]) / cell_size + 1e-9))
    return dims


class CellGrid:
    """A uniform grid of cells over the box [lo, hi) and its particle sort.

    Parameters
    ----------
    lo, hi : sequence of float, length dim
        Lower and upper corners of the domain [m]; particles outside are
        taken out of the computation.
    support : float
        Kernel support radius 2h [m].
    cells_per_support : int
        Cells per support radius (cell size = support / cells_per_support).
    capacity : int
        Number of particles the work arrays are sized for.
    periodic : sequence of bool, optional
        Periodic axes: their length is cut into whole cells (at least
        2n + 1), and the gather wraps round (see `neighbours.gather`).
    """

    def __init__(self, lo, hi, support, cells_per_support, capacity, periodic=None):
        lo = np.asarray(lo, dtype=np.float64)
        hi = np.asarray(hi, dtype=np.float64)
        if lo.shape != hi.shape or lo.ndim != 1 or lo.size not in (2, 3):
            raise InputError(f"domain bounds must be 2 or 3 numbers each, got lo={lo.tolist()} hi={hi.tolist()}")
        if not np.all(hi > lo):
            raise InputError(f"domain upper corner {hi.tolist()} must exceed the lower corner {lo.tolist()} in every direction")
        self.dim = lo.size
        self.n = int(cells_per_support)
        self.cell_size = float(support) / self.n
        self.periodic = np.zeros(self.dim, bool) if periodic is None else np.asarray(periodic, bool)
        dims = grid_dims(lo, hi, self.cell_size, self.periodic)
        for d in np.flatnonzero(self.periodic):
            # the stencil that wraps round a periodic axis needs 2n + 1 distinct cells
            if dims[d] < 2 * self.n + 1:
                raise InputError(
                    f"the periodic length {hi[d] - lo[d]:.4g} m along {'xyz'[d] if self.dim == 3 else 'xz'[d]} is "
                    f"too short for the kernel support: it must be at least {(2 * self.n + 1) * self.cell_size:.4g} m "
                    f"({2 * self.n + 1} cells of {self.cell_size:.4g} m)")
        ncell = int(np.prod(dims))
        if ncell > MAX_CELLS:
            raise InputError(
                f"the neighbour grid would need {ncell:.3g} cells (domain {(hi - lo).tolist()} m, cell "
                f"{self.cell_size:.3g} m); enlarge dp or shrink the domain (at most {MAX_CELLS:.3g} cells)")
        self.lo = lo
        self.hi = hi  # the domain; the grid itself may reach up to one cell further
        self.grid_hi = lo + dims * self.cell_size
        self.dims = dims
        self.ncell = ncell
        # (nx, ny, nz) as the gather expects; 2D grids are (nx, 1, nz)
        if self.dim == 3:
            self.gdims = (int(dims[0]), int(dims[1]), int(dims[2]))
        else:
            self.gdims = (int(dims[0]), 1, int(dims[1]))
        self.gdims_arr = np.array(self.gdims, dtype=np.int64)
        self.cell_start = np.zeros(ncell + 2, dtype=np.int32)
        self.cell = np.zeros(capacity, dtype=np.int32)
        self.perm = np.zeros(capacity, dtype=np.int32)
        self._unsorted = np.zeros(capacity, dtype=np.int32)
        self._blocks = np.zeros(2 * (numba.config.NUMBA_NUM_THREADS + 1), dtype=np.int64)
        self._dims = dims.astype(np.int64)
        self._inv_cs = 1.0 / self.cell_size
        self.n_active = 0

    @property
    def nbytes(self):
        """Bytes held by the grid's arrays."""
        return self.cell_start.nbytes + self.cell.nbytes + self.perm.nbytes + self._unsorted.nbytes

    def resize(self, capacity):
        """Hold up to `capacity` particles from now on: the per-particle work arrays are resized in place
        (the cell table keeps its size)."""
        for a in (self.cell, self.perm, self._unsorted):
            a.resize(int(capacity), refcheck=False)

    def bin(self, pos, n):
        """Compute cells of the first `n` particles and the sort permutation.

        After `bin`, ``perm[k]`` is the particle that goes to slot k; call
        `reorder` on every particle array, which then leaves ``cell`` in
        sorted order. Returns the number of particles inside the domain.
        """
        _cell_index(pos, n, self.lo, self.hi, self._inv_cs, self._dims, self.ncell, self._unsorted)
        threads = numba.get_num_threads()
        _counting_sort(self._unsorted, n, self.ncell, self.cell_start, self.perm, threads, self._blocks)
        _sorted_cells(self._unsorted, self.perm, n, self.cell)
        self.n_active = int(self.cell_start[self.ncell])
        return self.n_active

    def reorder(self, arrays, n, scratch):
        """Permute each array's first `n` rows into cell order, in place.

        `scratch` maps (dtype, ncols) to a work array at least n long;
        no allocation happens here.
        """
        perm = self.perm
        for a in arrays:
            if a.ndim == 1:
                _gather_1d(a, perm, n, scratch[(a.dtype.str, 0)])
            else:
                _gather_rows(a, perm, n, scratch[(a.dtype.str, a.shape[1])])

    @staticmethod
    def cells_for(lo, hi, support, cells_per_support):
        """Number of cells a grid over [lo, hi) would have (for estimates)."""
        cs = support / cells_per_support
        return math.prod(max(math.ceil((b - a) / cs), 1) for a, b in zip(lo, hi))
