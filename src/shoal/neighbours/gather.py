"""The per-particle neighbour gather over a sorted uniform cell grid.

Cells have size 2h / n (n = `cells_per_support`) and particles are stored
in cell order with x the fastest cell index, so the cells (ix-n .. ix+n, iy,
iz) form one contiguous range of particles: a particle visits (2n+1)^(dim-1)
such x-ranges. Positions are float64 in every run (as DualSPHysics keeps
them in double): the difference r_i - r_j is taken in float64 and only then
rounded to the working precision, so slow flows in float32 runs still move
by their true displacement (a float32 coordinate of 0.5 m has a 6e-8 m ulp,
a few steps' displacement of still water; the CPU's compact gather gets the
same rounded difference from split float32 coordinates, see `make_gather`). Every pair within the support
2h is passed to ``pair``,
which folds it into an accumulator tuple (written once, used by the rates,
the filters and the probes, on every backend).

Each row is trimmed to the cells the support sphere of particle i can reach
(without periodic axes or a symmetry plane): a row whose y-z rectangle lies
farther than 2h from r_i is skipped, and the x-range of the others is cut to
x_i -+ sqrt((2h)^2 - d^2), d the distance from r_i to the rectangle; a row
whose cut range is empty is skipped before any cell is read, so a particle
that has moved far from the cell it was binned in (a wall driven at an absurd
speed, a blown-up position) meets no neighbours instead of reading outside
the grid. With
n = 2 this visits 84 h^3 of cells on average instead of 125 h^3 (the
support sphere is 33.5 h^3): a third fewer candidates, 471 -> 328 a
particle in the 3D benchmark. The radius has a margin of `TRIM_MARGIN` of a
cell, because a rate evaluation between two sorts (the symplectic scheme's
second) sees particles up to 0.1 h v / c0 from where they were binned.

Periodic axes (x, and y in 3D): the cell grid tiles the period exactly
(see `CellGrid`), and a stencil that runs off one side continues on the
other with the neighbour's image shifted by the period L:
r_i - (r_j -+ L). With periodic x, each row is scanned as up to three
contiguous segments (the main one and the wrapped ones).
"""

import numpy as np

from .stack import ROW_CAP, row_buffer, term_buffer_f32, term_buffer_f64

TRIM_MARGIN = 0.05
"""Margin [cells] on the support radius of the row trimming (see the module docstring)."""


def make_gather(jit, spec, pair, compact=False, terms=None, only=None, rows_first=False):
    """Return ``gather(i, own, acc, pos, cell, cell_start, gdims, data, P)``.

    Parameters of the returned function
    -----------------------------------
    i : particle index; own : tuple of particle i's values passed to `pair`;
    acc : accumulator tuple; pos : (N, dim) positions; cell : (N,) cell of
    each particle at the last binning; cell_start : (ncell + 2,) first particle
    of each cell; gdims : (nx, ny, nz); data : tuple of arrays passed to
    `pair`; P : `Params`.

    ``pair(acc, own, j, dx, dy, dz, r2, sy, data, P)`` returns the new
    accumulator; (dx, dy, dz) = r_i - r_j (dy = 0 in 2D, where the second
    stored component is z); sy = 1, or -1 when j stands for its mirror
    image across a symmetry plane y = const (its y velocity is reversed).

    compact : CPU only, without periodic axes or a symmetry plane; needs
    `terms`; the returned function then takes the split coordinates after
    `pos`: ``gather(i, own, acc, pos, spos, cell, ...)``, `spos` (2 dim, N)
    float32 with the high parts float32(x - lo) in rows 0 .. dim - 1 and
    the low parts float32(x - lo - high) in rows dim .. 2 dim - 1
    (`shoal.backends.cpu.split_positions`). The ranges of all the trimmed
    rows are found first; the rows are then walked without a branch, each
    candidate's index written to a stack buffer (`stack.row_buffer`) and
    the count advanced only for those within the support, until the buffer
    is full or the rows are done. That test reads the high parts (half the
    bytes of the float64 positions, one coordinate a row) and widens the
    support by their rounding (2^-24 of the grid's extent a coordinate), so
    that it keeps every neighbour; the pair loop drops the few beyond 2h
    (they store the terms of `init`, which add nothing). There a pair's
    r_i - r_j is, in float32, the sum of the high and the low parts'
    differences (the float64 difference rounded to float32: two nearby
    coordinates of like magnitude have an exact high difference), without
    reading the float64 positions again; in float64 it is taken from `pos`.
    `pair` then runs over the buffered neighbours as a loop with no
    carried dependence, which LLVM vectorises: each call starts from the
    accumulator `init` and its result is stored with `put` into a term buffer
    (`stack.term_buffer_f32` / `_f64`); a last loop adds the terms up with
    `fold`, in the order of the neighbours. The same pairs are summed in the
    same order as without `compact`, and the results agree to round-off (a
    pair's terms are added as one value). In developed flow the support
    test's branch is mispredicted about a third of the time, which the
    compaction avoids; the vectorised pair loop and the longer lists it runs
    over (a buffer holds several rows) are measured in
    `benchmarks/results/issue34/vector_pairs/`.
    terms : ``(init, put, fold)`` for `compact`: the accumulator a pair's
    terms are computed from (zeros for sums), ``put(T, m, acc)`` storing an
    accumulator in column m of the (`stack.TERMS`, `stack.ROW_CAP`) buffer T,
    and ``fold(acc, T, m)`` adding column m to an accumulator.
    only : optional ``only(j, data)`` -> bool, a screen: candidates for which it is False are passed
        over before their distance is computed (a wall particle's gather takes only fluid neighbours,
        and most of its candidates are wall particles). The plain and `rows_first` gathers apply it;
        the others take every candidate, so `pair` must still refuse what it does not take.
    rows_first : CPU only, without periodic axes or a symmetry plane: the ranges of all the trimmed
        rows are found before the rows are walked, as with `compact`.
    """
    n = spec.cells_per_support
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    one = F(1.0)
    if spec.periodic or spec.symmetry:
        return _make_periodic_gather(jit, spec, pair)
    reach2 = (n + TRIM_MARGIN) ** 2  # the support radius in cells, squared, with the margin
    screen = only is not None
    if not screen:
        only = _everyone(jit)
    if compact:
        if terms is None:
            raise TypeError("make_gather(compact=True) needs terms=(init, put, fold)")
        return _make_compact_gather(jit, spec, pair, reach2, terms)
    if rows_first:
        return _make_rows_first_gather(jit, spec, pair, reach2, only, screen)

    if dim == 3:
        @jit
        def gather(i, own, acc, pos, cell, cell_start, gdims, data, P):
            ii = np.int64(i)  # i is unsigned: compared with a signed j, both would be converted to float64
            nx, ny, nz = gdims
            c = cell[i]
            ix = c % nx
            t = c // nx
            iy = t % ny
            iz = t // ny
            xi, yi, zi = pos[i, 0], pos[i, 1], pos[i, 2]
            # r_i in cell units, for the trimming
            ux = (xi - P.grid_lo_x) * P.inv_cs
            uy = (yi - P.grid_lo_y) * P.inv_cs
            uz = (zi - P.grid_lo_z) * P.inv_cs
            supp2 = P.supp2
            for z in range(max(iz - n, 0), min(iz + n, nz - 1) + 1):
                ez = max(0.0, max(z - uz, uz - (z + 1)))
                for y in range(max(iy - n, 0), min(iy + n, ny - 1) + 1):
                    ey = max(0.0, max(y - uy, uy - (y + 1)))
                    e2 = reach2 - ey * ey - ez * ez
                    if e2 <= 0.0:
                        continue
                    e = e2 ** 0.5
                    x0 = max(int(ux - e), ix - n, 0)
                    x1 = min(int(ux + e), ix + n, nx - 1)
                    if x0 > x1:
                        continue
                    row = nx * (y + ny * z)
                    for j in range(cell_start[row + x0], cell_start[row + x1 + 1]):
                        if screen and not only(j, data):
                            continue
                        dx = F(xi - pos[j, 0])
                        dy = F(yi - pos[j, 1])
                        dz = F(zi - pos[j, 2])
                        r2 = dx * dx + dy * dy + dz * dz
                        if r2 < supp2 and j != ii:
                            acc = pair(acc, own, j, dx, dy, dz, r2, one, data, P)
            return acc
    else:
        @jit
        def gather(i, own, acc, pos, cell, cell_start, gdims, data, P):
            ii = np.int64(i)  # i is unsigned: compared with a signed j, both would be converted to float64
            nx, ny, nz = gdims
            c = cell[i]
            ix = c % nx
            iz = c // nx
            xi, zi = pos[i, 0], pos[i, 1]
            ux = (xi - P.grid_lo_x) * P.inv_cs
            uz = (zi - P.grid_lo_z) * P.inv_cs
            supp2 = P.supp2
            for z in range(max(iz - n, 0), min(iz + n, nz - 1) + 1):
                ez = max(0.0, max(z - uz, uz - (z + 1)))
                e2 = reach2 - ez * ez
                if e2 <= 0.0:
                    continue
                e = e2 ** 0.5
                x0 = max(int(ux - e), ix - n, 0)
                x1 = min(int(ux + e), ix + n, nx - 1)
                if x0 > x1:
                    continue
                row = nx * z
                for j in range(cell_start[row + x0], cell_start[row + x1 + 1]):
                    if screen and not only(j, data):
                        continue
                    dx = F(xi - pos[j, 0])
                    dz = F(zi - pos[j, 1])
                    r2 = dx * dx + dz * dz
                    if r2 < supp2 and j != ii:
                        acc = pair(acc, own, j, dx, zero, dz, r2, one, data, P)
            return acc

    return gather


def _everyone(jit):
    """The `only` of a gather that screens no candidate."""
    @jit
    def everyone(j, data):
        return True

    return everyone


def make_row_trim(jit, spec, reach2):
    """Return ``(trimmed_row, n_rows, side)`` (CPU): ``trimmed_row(r, ix, iy, iz, ux, uy, uz, nx, ny, nz)`` ->
    (row, x0, x1), the row of cells (y + ny z in 3D, z in 2D) of stencil row r around cell (ix, iy, iz) and
    its cells x0 .. x1 within the support of a point at (ux, uy, uz) in cell units (with `TRIM_MARGIN`;
    x0 > x1 where the trimmed row is empty or off the grid); the stencil has n_rows rows, `side` a side."""
    n = spec.cells_per_support
    dim = spec.dim
    side = 2 * n + 1
    n_rows = side * side if dim == 3 else side
    if n_rows > ROW_CAP // 2:
        raise ValueError(f"cells_per_support = {n} gives {n_rows} stencil rows; a row buffer holds "
                         f"at most {ROW_CAP // 2}")

    @jit
    def trimmed_row(r, ix, iy, iz, ux, uy, uz, nx, ny, nz):
        if dim == 3:
            z = iz - n + r // side
            y = iy - n + r % side
        else:
            z = iz - n + r
            y = 0
        row = y + ny * z if dim == 3 else z
        if z < 0 or z >= nz or y < 0 or y >= ny:
            return row, 1, 0
        ez = max(0.0, max(z - uz, uz - (z + 1)))
        ey = max(0.0, max(y - uy, uy - (y + 1))) if dim == 3 else 0.0
        e2 = reach2 - ey * ey - ez * ez
        if e2 <= 0.0:
            return row, 1, 0
        e = e2 ** 0.5
        return row, max(int(ux - e), ix - n, 0), min(int(ux + e), ix + n, nx - 1)

    return trimmed_row, n_rows, side


def _make_row_ranges(jit, spec, reach2):
    """Return ``(row_ranges, n_rows)`` (CPU): ``row_ranges(c, ux, uy, uz, cell_start, gdims, rows)`` writes
    the particles [start, stop) of each of the n_rows trimmed stencil rows around cell c, for a point at
    (ux, uy, uz) in cell units, into ``rows[r]`` and ``rows[ROW_CAP // 2 + r]`` of a `stack.row_buffer`
    (an empty range where the trimmed row is empty). Found before the rows are walked: computed between
    two rows' walks, each row's range waited for its square root and its reads of cell_start."""
    dim = spec.dim
    trimmed_row, n_rows, _ = make_row_trim(jit, spec, reach2)

    @jit
    def row_range(r, ix, iy, iz, ux, uy, uz, cell_start, nx, ny, nz):
        """Particles [start, stop) of stencil row r (empty where the trimmed row is)."""
        row, x0, x1 = trimmed_row(r, ix, iy, iz, ux, uy, uz, nx, ny, nz)
        if x0 > x1:
            return 0, 0
        return cell_start[nx * row + x0], cell_start[nx * row + x1 + 1]

    @jit
    def row_ranges(c, ux, uy, uz, cell_start, gdims, rows):
        nx, ny, nz = gdims
        ix = c % nx
        t = c // nx
        if dim == 3:
            iy = t % ny
            iz = t // ny
        else:
            iy = 0
            iz = t
        for r in range(n_rows):
            a, b = row_range(r, ix, iy, iz, ux, uy, uz, cell_start, nx, ny, nz)
            rows[r] = a
            rows[ROW_CAP // 2 + r] = b

    return row_ranges, n_rows


def _make_rows_first_gather(jit, spec, pair, reach2, only, screen):
    """`make_gather` with rows_first=True (CPU): the trimmed rows' ranges found first, then walked."""
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    one = F(1.0)
    row_ranges, n_rows = _make_row_ranges(jit, spec, reach2)

    @jit
    def gather(i, own, acc, pos, cell, cell_start, gdims, data, P):
        ii = np.int64(i)  # i is unsigned: compared with a signed j, both would be converted to float64
        xi = pos[i, 0]
        zi = pos[i, dim - 1]
        yi = pos[i, 1] if dim == 3 else 0.0
        rows = row_buffer()
        row_ranges(cell[i], (xi - P.grid_lo_x) * P.inv_cs, (yi - P.grid_lo_y) * P.inv_cs,
                   (zi - P.grid_lo_z) * P.inv_cs, cell_start, gdims, rows)
        supp2 = P.supp2
        for r in range(n_rows):
            for j in range(rows[r], rows[ROW_CAP // 2 + r]):
                if screen and not only(j, data):
                    continue
                dx = F(xi - pos[j, 0])
                dz = F(zi - pos[j, dim - 1])
                dy = F(yi - pos[j, 1]) if dim == 3 else zero
                r2 = dx * dx + dy * dy + dz * dz
                if r2 < supp2 and j != ii:
                    acc = pair(acc, own, j, dx, dy, dz, r2, one, data, P)
        return acc

    return gather


def make_compaction(jit, spec, only):
    """Return ``(split_own, fill, difference)``, the pieces of a compacted gather (CPU) on the split
    float32 coordinates (see `make_gather`, ``compact``), shared by the compact gather and the half
    stencil of `shoal.neighbours.half_sweep`.

    ``split_own(i, spos, gdims, P)`` -> (coarse2, own): the compaction's support squared, widened by the
    high parts' rounding (at most 2^-24 L a coordinate, L the grid's extent, so that it keeps every
    neighbour within 2h), and i's high and low parts (xs, ys, zs, xl, yl, zl).
    ``fill(buf, rows, n_rows, r, s0, stop, ui, own, coarse2, spos, everyone, data)`` -> (k, r, s0, stop):
    walks the candidates of the rows' ranges (``rows[r]`` .. ``rows[ROW_CAP // 2 + r]``, from candidate s0
    of row r, which ends at stop) without a branch, writing each index to ``buf[k]`` and advancing k for
    those within coarse2, other than i (``ui``), for which `everyone` or ``only(j, data)`` holds, until the
    buffer is full or the rows are done; returns where it stopped.
    ``difference(j, own, xi, yi, zi, pos, spos, P)`` -> (dx, dy, dz, r2, keep): r_i - r_j in the working
    precision and whether it lies within 2h: in float32 the sum of the high and the low parts'
    differences (the float64 difference rounded to float32: two nearby coordinates of like magnitude have
    an exact high difference), in float64 from the positions.
    """
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    f32 = F == np.float32

    @jit
    def split_own(i, spos, gdims, P):
        nx, ny, nz = gdims
        extent = max(nx, ny, nz) / P.inv_cs
        reach = 2.0 * P.h + extent * 2.0 ** -21
        coarse2 = np.float32(reach * reach * (1.0 + 2.0 ** -20))
        xs = spos[0, i]
        zs = spos[dim - 1, i]
        ys = spos[1, i] if dim == 3 else np.float32(0.0)
        xl = spos[dim, i]
        zl = spos[2 * dim - 1, i]
        yl = spos[dim + 1, i] if dim == 3 else np.float32(0.0)
        return coarse2, (xs, ys, zs, xl, yl, zl)

    @jit
    def fill(buf, rows, n_rows, r, s0, stop, ui, own, coarse2, spos, everyone, data):
        xs, ys, zs = own[0], own[1], own[2]
        k = 0
        while r < n_rows:
            room = ROW_CAP - k
            if stop - s0 > room and k > 0:
                break
            s1 = min(s0 + room, stop)
            # unsigned indices: Numba adds no negative-index wraparound to their loads and stores
            for j in range(np.uint64(s0), np.uint64(s1)):
                ex = xs - spos[0, j]
                ez = zs - spos[dim - 1, j]
                ey = ys - spos[1, j] if dim == 3 else np.float32(0.0)
                buf[np.uint64(k)] = j
                k += (ex * ex + ey * ey + ez * ez < coarse2) & (j != ui) & (everyone | only(j, data))
            s0 = s1
            if s0 >= stop:
                r += 1
                if r < n_rows:
                    s0, stop = rows[r], rows[ROW_CAP // 2 + r]
        return k, r, s0, stop

    @jit
    def difference(j, own, xi, yi, zi, pos, spos, P):
        if f32:
            xs, ys, zs, xl, yl, zl = own
            dx = (xs - spos[0, j]) + (xl - spos[dim, j])
            dz = (zs - spos[dim - 1, j]) + (zl - spos[2 * dim - 1, j])
            dy = (ys - spos[1, j]) + (yl - spos[dim + 1, j]) if dim == 3 else zero
            r2 = dx * dx + dy * dy + dz * dz
            return dx, dy, dz, r2, r2 < P.supp2
        ex = xi - pos[j, 0]
        ez = zi - pos[j, dim - 1]
        ey = yi - pos[j, 1] if dim == 3 else 0.0
        keep = ex * ex + ey * ey + ez * ez < np.float64(P.supp2)
        dx = F(ex)
        dy = F(ey)
        dz = F(ez)
        return dx, dy, dz, dx * dx + dy * dy + dz * dz, keep

    return split_own, fill, difference


def _make_compact_gather(jit, spec, pair, reach2, terms):
    """`make_gather` with compact=True (CPU): the rows' candidates compacted into a buffer, their
    pairs evaluated by a vectorised loop into a term buffer, the terms then summed in order."""
    dim = spec.dim
    one = spec.float_type(1.0)
    init, put, fold = terms
    f32 = spec.float_type == np.float32
    row_ranges, n_rows = _make_row_ranges(jit, spec, reach2)
    split_own, fill, difference = make_compaction(jit, spec, _everyone(jit))

    @jit
    def gather(i, own, acc, pos, spos, cell, cell_start, gdims, data, P):
        ui = np.uint64(i)  # j is unsigned too: with one signed, both would be converted to float64
        buf = row_buffer()
        if f32:
            T = term_buffer_f32()
        else:
            T = term_buffer_f64()
        xi = pos[i, 0]
        zi = pos[i, dim - 1]
        yi = pos[i, 1] if dim == 3 else 0.0
        coarse2, split = split_own(i, spos, gdims, P)
        rows = row_buffer()
        row_ranges(cell[i], (xi - P.grid_lo_x) * P.inv_cs, (yi - P.grid_lo_y) * P.inv_cs,
                   (zi - P.grid_lo_z) * P.inv_cs, cell_start, gdims, rows)
        r = 0
        s0, stop = rows[0], rows[ROW_CAP // 2]
        while r < n_rows:
            # fill the buffer with the candidates of as many rows as it holds, keeping those within
            # the support (a branch-free compaction), ...
            k, r, s0, stop = fill(buf, rows, n_rows, r, s0, stop, ui, split, coarse2, spos, True, data)
            # ... then evaluate its pairs, which are independent (LLVM vectorises this loop), ...
            for m in range(np.uint64(k)):
                j = np.uint64(buf[m])
                dx, dy, dz, r2, keep = difference(j, split, xi, yi, zi, pos, spos, P)
                # the support test in the working precision: a candidate the widened test kept beyond
                # it stores the zero terms of `init`, which add nothing
                t = pair(init, own, j, dx, dy, dz, r2, one, data, P)
                put(T, m, t if keep else init)
            # ... and add them up in the neighbours' order
            for m in range(np.uint64(k)):
                acc = fold(acc, T, m)
        return acc

    return gather


def make_periodic_wraps(jit, spec):
    """Return ``(wrap_row, x_segment)``, the stencil's continuation across periodic faces.

    ``wrap_row(y, ny, ly)`` -> (row index, y shift, use): a stencil row y off either end of a
    periodic y axis continues at the other end, its neighbours' images shifted by the period.
    ``x_segment(seg, ix, nx, lx)`` -> (first cell, last cell, x shift) of the segment `seg` of an
    x-row around cell ix: 0 the cells within the grid, 1 those off the low end (cells at the high
    end, images at x - L), 2 those off the high end; first > last when the segment is empty."""
    n = spec.cells_per_support
    px = bool(spec.periodic & 1)
    py = bool(spec.periodic & 2) and spec.dim == 3

    @jit
    def wrap_row(y, ny, ly):
        if y < 0:
            return y + ny, ly, py
        if y >= ny:
            return y - ny, -ly, py
        return y, 0.0, True

    @jit
    def x_segment(seg, ix, nx, lx):
        if seg == 0:
            return max(ix - n, 0), min(ix + n, nx - 1), 0.0
        if seg == 1:
            if px and ix - n < 0:
                return nx + ix - n, nx - 1, lx
            return 1, 0, 0.0
        if px and ix + n > nx - 1:
            return 0, ix + n - nx, -lx
        return 1, 0, 0.0

    return wrap_row, x_segment


def _make_periodic_gather(jit, spec, pair):
    """The gather with periodic axes and/or a symmetry plane y = ys (3D).

    Symmetry plane (the "domain separation" of the tidal-bore paper): for a
    particle i within 2h of the plane, a second scan visits the neighbours j
    of i's mirror image r_i' = (x_i, 2 ys - y_i, z_i); each stands for the
    mirror image of j, at r_j' = (x_j, 2 ys - y_j, z_j) with velocity
    (u, -v, w), so r_i - r_j' = (x_i - x_j, y_i + y_j - 2 ys, z_i - z_j) and
    the pair gets sy = -1. A particle within h of the plane meets its own
    image too (j = i is kept in that scan).
    """
    n = spec.cells_per_support
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    one, mone = F(1.0), F(-1.0)
    sym = bool(spec.symmetry) and dim == 3
    wrap_row, x_segment = make_periodic_wraps(jit, spec)

    @jit
    def gather(i, own, acc, pos, cell, cell_start, gdims, data, P):
        nx, ny, nz = gdims
        ii = np.int64(i)  # i is unsigned: compared with a signed j, both would be converted to float64
        c = cell[i]
        ix = c % nx
        t = c // nx
        iy0 = t % ny
        iz = t // ny
        xi = pos[i, 0]
        zi = pos[i, dim - 1]
        yi = pos[i, 1] if dim == 3 else 0.0
        supp2 = P.supp2
        lx = P.per_len_x
        ly = P.per_len_y
        n_scans = 1
        if sym:
            if abs(yi - P.sym_y) < 2.0 * P.h:
                n_scans = 2
        for scan in range(n_scans):
            iy = iy0
            sy = one
            if scan == 1:
                iy = int((2.0 * P.sym_y - yi - P.grid_lo_y) * P.inv_cs)
                sy = mone
            for z in range(max(iz - n, 0), min(iz + n, nz - 1) + 1):
                for oy in range(-n, n + 1) if dim == 3 else range(0, 1):
                    y, yshift, use = wrap_row(iy + oy, ny, ly)
                    if not use:
                        continue
                    row = nx * (y + ny * z)
                    for seg in range(3):
                        a, b, xshift = x_segment(seg, ix, nx, lx)
                        if a > b:
                            continue
                        for j in range(cell_start[row + a], cell_start[row + b + 1]):
                            dx = F(xi - pos[j, 0] + xshift)
                            dz = F(zi - pos[j, dim - 1])
                            if dim == 3:
                                if scan == 1:
                                    dy = F(yi + pos[j, 1] - 2.0 * P.sym_y + yshift)
                                else:
                                    dy = F(yi - pos[j, 1] + yshift)
                            else:
                                dy = zero
                            r2 = dx * dx + dy * dy + dz * dz
                            if r2 < supp2 and (j != ii or scan == 1):
                                acc = pair(acc, own, j, dx, dy, dz, r2, sy, data, P)
        return acc

    return gather


def make_point_gather(jit, spec, pair, wrap=False):
    """Return ``gather_at(x, y, z, own, acc, pos, cell_start, gdims, glo, inv_cs, data, P)``: the
    neighbours of an arbitrary point (a probe), found from its coordinates (internal order: (x, z)
    in 2D, y ignored) with the grid's lower corner `glo` and 1 / cell size `inv_cs`.
    ``pair(acc, own, j, dx, dy, dz, r2, sy, data, P)`` as for particles, with r = point - r_j.

    Without `wrap`, periodic images and symmetry planes are not applied (a probe closer than 2h to
    a periodic face or a symmetry plane sees only the particles on this side). With `wrap` (the
    ghost nodes of `shoal.physics.mdbc`) the point is first brought into the period and the
    stencil continues across periodic faces as in the particle gather; symmetry planes are still
    not applied."""
    n = spec.cells_per_support
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    one = F(1.0)
    if wrap and spec.periodic:
        return _make_periodic_point_gather(jit, spec, pair)

    @jit
    def gather_at(x, y, z, own, acc, pos, cell_start, gdims, glo, inv_cs, data, P):
        nx, ny, nz = gdims
        ix = int((x - glo[0]) * inv_cs)
        if dim == 3:
            iy = int((y - glo[1]) * inv_cs)
            iz = int((z - glo[2]) * inv_cs)
        else:
            iy = 0
            iz = int((z - glo[1]) * inv_cs)
        x0 = max(ix - n, 0)
        x1 = min(ix + n, nx - 1)
        if x0 > x1:
            return acc
        supp2 = P.supp2
        for zz in range(max(iz - n, 0), min(iz + n, nz - 1) + 1):
            for yy in range(max(iy - n, 0), min(iy + n, ny - 1) + 1):
                row = nx * (yy + ny * zz)
                for j in range(cell_start[row + x0], cell_start[row + x1 + 1]):
                    dx = F(x - pos[j, 0])
                    dz = F(z - pos[j, dim - 1])
                    dy = F(y - pos[j, 1]) if dim == 3 else zero
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 < supp2:
                        acc = pair(acc, own, j, dx, dy, dz, r2, one, data, P)
        return acc

    return gather_at


def _make_periodic_point_gather(jit, spec, pair):
    """`make_point_gather` with ``wrap``: the point is brought into the period, and each row is
    scanned as up to three segments with the neighbours' images shifted by the period, as in
    `_make_periodic_gather`."""
    n = spec.cells_per_support
    dim = spec.dim
    F = spec.float_type
    zero = F(0.0)
    one = F(1.0)
    px = bool(spec.periodic & 1)
    py = bool(spec.periodic & 2) and dim == 3
    wrap_row, x_segment = make_periodic_wraps(jit, spec)

    @jit
    def gather_at(x, y, z, own, acc, pos, cell_start, gdims, glo, inv_cs, data, P):
        nx, ny, nz = gdims
        lx = P.per_len_x
        ly = P.per_len_y
        if px:
            x = glo[0] + (x - glo[0]) % lx
        if py:
            y = glo[1] + (y - glo[1]) % ly
        ix = min(max(int((x - glo[0]) * inv_cs), 0), nx - 1)
        if dim == 3:
            iy = min(max(int((y - glo[1]) * inv_cs), 0), ny - 1)
            iz = int((z - glo[2]) * inv_cs)
        else:
            iy = 0
            iz = int((z - glo[1]) * inv_cs)
        supp2 = P.supp2
        for zz in range(max(iz - n, 0), min(iz + n, nz - 1) + 1):
            for oy in range(-n, n + 1) if dim == 3 else range(0, 1):
                yy, yshift, use = wrap_row(iy + oy, ny, ly)
                if not use:
                    continue
                row = nx * (yy + ny * zz)
                for seg in range(3):
                    a, b, xshift = x_segment(seg, ix, nx, lx)
                    if a > b:
                        continue
                    for j in range(cell_start[row + a], cell_start[row + b + 1]):
                        dx = F(x - pos[j, 0] + xshift)
                        dz = F(z - pos[j, dim - 1])
                        dy = F(y - pos[j, 1] + yshift) if dim == 3 else zero
                        r2 = dx * dx + dy * dy + dz * dz
                        if r2 < supp2:
                            acc = pair(acc, own, j, dx, dy, dz, r2, one, data, P)
        return acc

    return gather_at
