"""Each pair of neighbours once, in parallel without conflicting writes (CPU).

A pair {i, j} belongs to the particle that comes first in cell order: particle i visits the
candidates j > i of its stencil (its *half stencil*), and a pair's terms for j are added to j's sums
where i finds it. Of the per-particle gather's stencil rows (`gather`), i keeps those after its own
row in cell order whole and its own row from i + 1, and skips the others: one contiguous range of
particles a row, as before, with half the candidates.

i then writes to particles within n cells of its own in x and y and in the n planes of cells above
(n = `cells_per_support`). The grid is cut into *tiles*, n cells along x by n along z (all of y), so
that the writes of tile (bx, bz) stay within tiles bx - 1 .. bx + 1 and bz .. bz + 1: tiles whose bx
differ by a multiple of 3 and whose bz differ by a multiple of 2 never write to the same particle.
Tiles as small as that keep the threads' loads even: at rest, the DualSPHysics dam break's tiles of a
colour, dealt by their weights to 16 threads, load the busiest thread at most 1 / 0.971 of the mean at
920,136 particles (1 / 0.888 with tiles 2n cells along x), 1 / 0.836 at 173,531 (1 / 0.743).
The tiles of each of the six colours (bx mod 3, bz mod 2) are swept at once, one tile by one thread in
cell order, the colours one after the other. Each particle's sums are thus added up in an order set by
the grid alone, not by the threads nor by how the tiles are dealt to them: the results are the same
bits with any thread count. The tiles of a colour are dealt to the threads costliest first, each to the
least loaded thread (`deal_tiles`), a tile weighed by its fluid particles (a wall particle's pairs are
with fluid only, and most of its candidates are walls). A wall particle whose half stencil reaches no
tile with fluid (`make_tiles`' ``reaches``) has no pair, and is not visited.

Used by the CPU's rates where the scheme's pair terms allow (`shoal.physics.mutual`); without
periodic axes or a symmetry plane.
"""

import numba
import numpy as np

from .gather import TRIM_MARGIN, make_compaction, make_row_trim
from .stack import ROW_CAP, both_buffer_f32, both_buffer_f64, row_buffer

WALL_WEIGHT = 0.2
"""Cost of a wall particle against a fluid one when tiles are dealt to threads (`deal_tiles`)."""

COLOURS = 6
"""Tile colours: (bx mod 3) + 3 (bz mod 2) (see the module docstring)."""


def make_half_gather(jit, spec, pair, terms, only):
    """Return ``gather(i, own, acc, everyone, pos, spos, cell, cell_start, gdims, data, out, P)``: particle
    i's half stencil (see the module docstring), as `make_gather`'s compact gather.

    The trimmed rows' ranges are found first and their candidates compacted into a buffer
    (`gather.make_compaction`), keeping those within the support for which ``everyone`` is true or
    ``only(j, data)`` holds; ``pair(own, j, dx, dy, dz, r2, data, P)`` then runs over the buffer as a loop
    without carried dependence (which LLVM vectorises), storing its terms with ``put(T, m, terms)`` (the
    zero terms ``init`` for a candidate beyond 2h in the working precision), and ``fold(acc, own, T, m, j,
    data, out, P)`` adds them up in the candidates' order, i's into the returned accumulator and j's into
    the arrays of `out`.

    terms : ``(init, put, fold)``, at most `stack.TERMS_BOTH` values a pair.
    """
    dim = spec.dim
    init, put, fold = terms
    f32 = spec.float_type == np.float32
    trimmed_row, n_rows, _ = make_row_trim(jit, spec, (spec.cells_per_support + TRIM_MARGIN) ** 2)
    split_own, fill, difference = make_compaction(jit, spec, only)

    @jit
    def half_rows(i, c, ux, uy, uz, cell_start, gdims, rows):
        nx, ny, nz = gdims
        ix = c % nx
        t = c // nx
        if dim == 3:
            iy = t % ny
            iz = t // ny
        else:
            iy = 0
            iz = t
        own_row = iy + ny * iz if dim == 3 else iz
        for r in range(n_rows):
            row, x0, x1 = trimmed_row(r, ix, iy, iz, ux, uy, uz, nx, ny, nz)
            a = b = 0
            if row >= own_row and x0 <= x1:
                a = cell_start[nx * row + x0]
                if row == own_row:
                    a = max(a, np.int64(i) + 1)
                b = max(a, cell_start[nx * row + x1 + 1])
            rows[r] = a
            rows[ROW_CAP // 2 + r] = b

    @jit
    def gather(i, own, acc, everyone, pos, spos, cell, cell_start, gdims, data, out, P):
        ui = np.uint64(i)
        buf = row_buffer()
        if f32:
            T = both_buffer_f32()
        else:
            T = both_buffer_f64()
        xi = pos[i, 0]
        zi = pos[i, dim - 1]
        yi = pos[i, 1] if dim == 3 else 0.0
        coarse2, split = split_own(i, spos, gdims, P)
        rows = row_buffer()
        half_rows(ui, cell[i], (xi - P.grid_lo_x) * P.inv_cs, (yi - P.grid_lo_y) * P.inv_cs,
                  (zi - P.grid_lo_z) * P.inv_cs, cell_start, gdims, rows)
        r = 0
        s0, stop = rows[0], rows[ROW_CAP // 2]
        while r < n_rows:
            k, r, s0, stop = fill(buf, rows, n_rows, r, s0, stop, ui, split, coarse2, spos, everyone, data)
            for m in range(np.uint64(k)):
                j = np.uint64(buf[m])
                dx, dy, dz, r2, keep = difference(j, split, xi, yi, zi, pos, spos, P)
                t = pair(own, j, dx, dy, dz, r2, data, P)
                put(T, m, t if keep else init)
            for m in range(np.uint64(k)):
                acc = fold(acc, own, T, m, np.uint64(buf[m]), data, out, P)
        return acc

    return gather


def make_tiles(jit, spec):
    """Return ``(tile_cells, reaches)``.

    ``tile_cells(t, gdims)`` -> (x0, x1, z0, z1, colour): tile t holds the cells x0 <= cx < x1,
    z0 <= cz < z1 (all of y; in 2D z is the second axis), tiles numbered bx + ntx bz (`tile_counter`).
    ``reaches(t, gdims, flags)``: whether ``flags`` (one a tile) is set for a tile that the half stencils
    of tile t's particles reach, bx - 1 .. bx + 1 and bz .. bz + 1 (see the module docstring)."""
    n = spec.cells_per_support

    @jit
    def place(t, gdims):
        # tile t's (bx, bz) and the tiles along x and z
        nx, ny, nz = gdims
        ntx = (nx + n - 1) // n
        return t % ntx, t // ntx, ntx, (nz + n - 1) // n

    @jit
    def tile_cells(t, gdims):
        bx, bz, _, _ = place(t, gdims)
        x0 = bx * n
        z0 = bz * n
        return x0, min(x0 + n, gdims[0]), z0, min(z0 + n, gdims[2]), bx % 3 + 3 * (bz % 2)

    @jit
    def reaches(t, gdims, flags):
        bx, bz, ntx, ntz = place(t, gdims)
        for b in range(max(bx - 1, 0), min(bx + 2, ntx)):
            for d in range(bz, min(bz + 2, ntz)):
                if flags[b + ntx * d]:
                    return True
        return False

    return tile_cells, reaches


def tile_counter(spec):
    """``count(gdims)`` -> the number of tiles of a grid of (nx, ny, nz) cells: ceil(nx / n) ceil(nz / n)."""
    n = spec.cells_per_support

    def count(gdims):
        nx, ny, nz = gdims
        return -(-nx // n) * -(-nz // n)

    return count


@numba.njit(cache=True)
def deal_tiles(colour_of, threads, cost, order, starts):
    """Deal the tiles of each colour to `threads` threads, costliest first, each to the least loaded.

    Parameters
    ----------
    colour_of : int64 array (n_tiles,)
        Each tile's colour, 0 .. `COLOURS` - 1.
    threads : int
    cost : float64 array (n_tiles + threads,)
        The tiles' costs in ``cost[:n_tiles]``; the rest is work space.
    order : int64 array (3 n_tiles + threads,)
        Receives in ``order[starts[c (threads + 1) + t] : starts[c (threads + 1) + t + 1]]`` the tiles of
        colour c that thread t sweeps; the rest is work space.
    starts : int64 array (COLOURS (threads + 1),)
    """
    n_tiles = colour_of.shape[0]
    load = cost[n_tiles:n_tiles + threads]
    ranked = order[n_tiles:2 * n_tiles]  # a colour's tiles, costliest first
    dealt = order[2 * n_tiles:3 * n_tiles]  # the thread each of them goes to
    fill = order[3 * n_tiles:3 * n_tiles + threads]  # running offsets while grouping by thread
    first = 0  # where the colour's tiles go in order[:n_tiles]
    for colour in range(COLOURS):
        m = 0
        for t in range(n_tiles):
            if colour_of[t] == colour and cost[t] > 0.0:
                ranked[m] = t
                m += 1
        # Shell sort, costliest first (the tiles of a colour: a few thousand at most)
        gap = 1
        while gap < m // 3:
            gap = 3 * gap + 1
        while gap > 0:
            for k in range(gap, m):
                v = ranked[k]
                c = cost[v]
                q = k
                while q >= gap and cost[ranked[q - gap]] < c:
                    ranked[q] = ranked[q - gap]
                    q -= gap
                ranked[q] = v
            gap //= 3
        base = colour * (threads + 1)
        for t in range(threads):
            load[t] = 0.0
            starts[base + t + 1] = 0
        for k in range(m):
            best = 0
            for t in range(1, threads):
                if load[t] < load[best]:
                    best = t
            load[best] += cost[ranked[k]]
            dealt[k] = best
            starts[base + best + 1] += 1
        starts[base] = first
        for t in range(threads):
            starts[base + t + 1] += starts[base + t]
            fill[t] = starts[base + t]
        for k in range(m):
            t = dealt[k]
            order[fill[t]] = ranked[k]
            fill[t] += 1
        first += m
