"""Neighbour search: the cell grid and the gather find exactly the pairs
within the support 2h that a brute-force O(N^2) search finds.

The gather is driven by a tiny pair function that records each neighbour
index, so the whole pair set (not just counts) is compared. Binning and
`reorder` permute particles, so the comparison uses the permuted positions.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from shoal.backends.cpu import split_positions
from shoal.errors import InputError
from shoal.neighbours import CellGrid, brute_force_pairs
from shoal.neighbours.gather import make_gather
from shoal.options import SPHOptions
from shoal.physics.spec import SchemeSpec, make_params

MAX_NB = 1024
_DRIVERS = {}


def _driver(dim, cps, compact=False, precision="float64"):
    """(spec, run) where run(n, pos, spos, cell, cell_start, gdims, P, nb, count)
    writes every particle's neighbours into nb[i, :count[i]] (`compact`: the CPU's
    branch-free row compaction and its term buffer, which reads the split float32
    coordinates `spos`; the others ignore them)."""
    key = (dim, cps, compact, precision)
    if key not in _DRIVERS:
        spec = SchemeSpec.from_options(SPHOptions(precision=precision, cells_per_support=cps), dim)

        @numba.njit
        def record(acc, own, j, dx, dy, dz, r2, sy, data, P):
            nb = data[0]
            if acc < nb.shape[1]:
                nb[own, acc] = j
            return acc + 1

        if compact:
            # the compacted gather evaluates the pairs into a term buffer, then folds the terms in
            # order: a pair's terms are (1, its neighbour's index), and the fold records the index;
            # a candidate beyond 2h stores the terms of `init`, (0, -1), which it passes over
            @numba.njit
            def index_term(acc, own, j, dx, dy, dz, r2, sy, data, P):
                return (1.0, np.float64(j))

            @numba.njit
            def put(T, m, t):
                T[0, m] = t[0]
                T[1, m] = t[1]

            @numba.njit
            def fold(acc, T, m):
                count, nb, own = acc
                if T[0, m] == 0.0:
                    return acc
                if count < nb.shape[1]:
                    nb[own, count] = np.int64(T[1, m])
                return count + 1, nb, own

            gather = make_gather(numba.njit, spec, index_term, compact=True, terms=((0.0, -1.0), put, fold))

            @numba.njit
            def run(n, pos, spos, cell, cell_start, gdims, P, nb, count):
                for i in range(n):
                    count[i] = gather(i, i, (0, nb, i), pos, spos, cell, cell_start, gdims, (nb,), P)[0]
        else:
            gather = make_gather(numba.njit, spec, record)

            @numba.njit
            def run(n, pos, spos, cell, cell_start, gdims, P, nb, count):
                for i in range(n):
                    count[i] = gather(i, i, 0, pos, cell, cell_start, gdims, (nb,), P)

        _DRIVERS[key] = (spec, run)
    return _DRIVERS[key]


def _split(pos, grid):
    """The compact gather's split float32 coordinates of `pos` (`Model.split_positions`)."""
    n, dim = pos.shape
    out = np.zeros((2 * dim, max(n, 1)), np.float32)
    split_positions(n, pos, np.asarray(grid.lo, np.float64), out)
    return out


def _params(spec, h, grid):
    opts = SPHOptions(precision="float64")
    lo = [float(v) for v in grid.lo]
    grid_lo = (lo[0], lo[1], lo[2]) if grid.dim == 3 else (lo[0], 0.0, lo[1])
    return make_params(spec, dp=h, h=h, rho0=1000.0, c0=10.0, gamma=7.0, gravity=(0.0, 0.0, 0.0),
                       options=opts, mass_f=1.0, mass_b=1.0, grid_lo=grid_lo, inv_cs=1.0 / grid.cell_size)


def _bin(pos, lo, hi, h, cps):
    """Bin and reorder a copy of `pos` (plus an id column); returns grid, pos, ids."""
    pos = np.ascontiguousarray(pos, dtype=np.float64).copy()
    n, dim = pos.shape
    ids = np.arange(n, dtype=np.int32)
    grid = CellGrid(lo, hi, 2.0 * h, cps, n)
    scratch = {(pos.dtype.str, dim): np.empty((n, dim)), (ids.dtype.str, 0): np.empty(n, np.int32)}
    n_active = grid.bin(pos, n)
    grid.reorder([pos, ids], n, scratch)
    return grid, pos, ids, n_active


def _gather_pairs(pos, lo, hi, h, cps, precision="float64"):
    dim = pos.shape[1]
    spec, run = _driver(dim, cps, precision=precision)
    grid, spos, ids, n_active = _bin(pos, lo, hi, h, cps)
    split = _split(spos, grid)
    nb = np.full((max(n_active, 1), MAX_NB), -1, dtype=np.int64)
    count = np.zeros(max(n_active, 1), dtype=np.int64)
    run(n_active, spos, split, grid.cell, grid.cell_start, grid.gdims, _params(spec, h, grid), nb, count)
    assert count.max(initial=0) <= MAX_NB
    # the CPU's compacted rows visit the same neighbours in the same order
    _, run_c = _driver(dim, cps, compact=True, precision=precision)
    nb_c, count_c = np.full_like(nb, -1), np.zeros_like(count)
    run_c(n_active, spos, split, grid.cell, grid.cell_start, grid.gdims, _params(spec, h, grid), nb_c, count_c)
    np.testing.assert_array_equal(count_c, count)
    np.testing.assert_array_equal(nb_c, nb)
    pairs = {(i, int(nb[i, k])) for i in range(n_active) for k in range(count[i])}
    assert len(pairs) == int(count[:n_active].sum()), "a neighbour was visited twice"
    return grid, spos, ids, n_active, pairs


def _check_against_brute_force(pos, lo, hi, h, cps, strict=False):
    """Compare the gather's pairs with brute force on the binned positions.

    Cell indices are computed as floor((x - lo) / cell) in floating point, so
    a pair closer than 2h by an ulp or so can land n + 1 cells apart and be
    skipped; W and grad W vanish to far below double precision there
    (W ~ (2 - q)^3 at best), so outside `strict` mode a missing pair is
    accepted only within 1e-12 relative of the support radius.
    """
    grid, spos, ids, n_active, pairs = _gather_pairs(pos, lo, hi, h, cps)
    expected = brute_force_pairs(spos, 2.0 * h, n=n_active)
    missing = expected - pairs
    extra = pairs - expected
    if not strict:
        missing = {(i, j) for i, j in missing if np.linalg.norm(spos[i] - spos[j]) < 2.0 * h * (1.0 - 1e-12)}
    assert not missing and not extra, (f"{len(missing)} missing, {len(extra)} extra pairs, e.g. "
                                       f"{sorted(missing)[:3]} / {sorted(extra)[:3]}")
    return grid, spos, ids, n_active, pairs


def _inside(pos, grid):
    """Particles the grid keeps: finite and inside the domain [lo, hi)."""
    with np.errstate(invalid="ignore"):
        return np.all((pos >= grid.lo) & (pos < grid.hi), axis=1)


@pytest.mark.parametrize("cps", [1, 2, 3])
@pytest.mark.parametrize("dim", [2, 3])
def test_gather_equals_brute_force_random(dim, cps):
    rng = np.random.default_rng(100 * dim + cps)
    h = 0.0371  # no simple ratio with the box: cells straddle it
    lo = np.array([-0.13, 0.02, 0.5])[:dim]
    hi = lo + np.array([0.41, 0.23, 0.3])[:dim]
    n = 600 if dim == 2 else 900
    pos = lo + rng.random((n, dim)) * (hi - lo)
    pos[:5] = pos[5:10]  # coincident particles are neighbours (r = 0 < 2h)
    pos[10] = lo  # on the lower domain corner
    _, _, _, n_active, pairs = _check_against_brute_force(pos, lo, hi, h, cps, strict=True)
    assert n_active == n
    assert len(pairs) > 20 * n  # a meaningful number of neighbours


@pytest.mark.parametrize("cps", [1, 2, 3])
@pytest.mark.parametrize("dim", [2, 3])
def test_float32_compaction_finds_the_plain_gathers_pairs(dim, cps):
    """In float32 the compacted gather tests its candidates on the high float32 parts of the split
    coordinates, widened by their rounding, and takes a pair's r_i - r_j as the sum of the high and low
    parts' differences: the same pairs, in the same order, as the plain gather's float32 test on the
    float64 differences (`_gather_pairs` asserts it), on random points and on a lattice with pairs at
    exactly 2h."""
    rng = np.random.default_rng(7 * dim + cps)
    h = 0.0371
    lo = np.array([-0.13, 0.02, 0.5])[:dim]
    hi = lo + np.array([0.41, 0.23, 0.3])[:dim]
    n = 600 if dim == 2 else 900
    _gather_pairs(lo + rng.random((n, dim)) * (hi - lo), lo, hi, h, cps, precision="float32")
    cs = 0.125
    step = cs / 2
    k = np.arange(12 if dim == 2 else 8)
    lattice = np.stack([g.ravel() for g in np.meshgrid(*([k] * dim), indexing="ij")], axis=1)
    lo = np.array([-0.5, -0.25, -0.375])[:dim]
    _, _, _, _, pairs = _gather_pairs(lo + step * lattice, lo, lo + len(k) * step, 0.5 * cps * cs, cps,
                                      precision="float32")
    assert len(pairs) > 0


@pytest.mark.parametrize("cps", [1, 2, 3])
@pytest.mark.parametrize("dim", [2, 3])
def test_gather_on_cell_edges(dim, cps):
    """Lattice points on cell faces and at lo; pairs at exactly 2h excluded.

    Every number here is a binary fraction, so distances of exactly 2h
    (and exactly a cell size) occur and are computed exactly.
    """
    cs = 0.125
    h = 0.5 * cps * cs  # cell = 2h / cps = 0.125 for every cps
    lo = np.array([-0.5, -0.25, -0.375])[:dim]
    step = cs / 2  # cell faces and cell centres
    ncell = 6 if dim == 2 else 4
    k = np.arange(2 * ncell)
    grids = np.meshgrid(*([k] * dim), indexing="ij")
    pos = lo + step * np.stack([g.ravel() for g in grids], axis=1)
    hi = lo + ncell * cs
    grid, spos, ids, n_active, pairs = _check_against_brute_force(pos, lo, hi, h, cps, strict=True)
    assert grid.cell_size == cs
    assert n_active == len(pos)
    # exact-support pairs exist in the lattice and were excluded by both searches
    d = np.sqrt(((spos[:, None, :] - spos[None, :, :]) ** 2).sum(-1))
    assert np.any(d == 2 * h)
    assert not any(d[i, j] >= 2 * h for i, j in pairs)


@pytest.mark.parametrize("cps", [1, 2, 3])
@pytest.mark.parametrize("dim", [2, 3])
def test_trimmed_gather_after_particles_moved_since_binning(dim, cps):
    """A rate evaluation between two sorts (the symplectic scheme's second) gathers with positions
    moved since the binning. The rows are trimmed to the support sphere around the current r_i with
    a margin of `TRIM_MARGIN` cells, so with moves below half of it every pair the untrimmed stencil
    visits (binned cells at most n apart) and that is now within 2h is still found."""
    from shoal.neighbours.gather import TRIM_MARGIN

    rng = np.random.default_rng(31 * dim + cps)
    h = 0.0371
    lo = np.array([-0.13, 0.02, 0.5])[:dim]
    hi = lo + np.array([0.41, 0.23, 0.3])[:dim]
    n = 600 if dim == 2 else 900
    pos = lo + 0.02 + rng.random((n, dim)) * (hi - lo - 0.04)
    grid, spos, ids, n_active = _bin(pos, lo, hi, h, cps)
    assert n_active == n
    step = rng.normal(size=spos.shape)
    step *= (0.49 * TRIM_MARGIN * grid.cell_size) / np.linalg.norm(step, axis=1)[:, None]
    moved = spos + step
    found = {}
    for compact in (False, True):
        spec, run = _driver(dim, cps, compact)
        nb = np.full((n, MAX_NB), -1, dtype=np.int64)
        count = np.zeros(n, dtype=np.int64)
        run(n, moved, _split(moved, grid), grid.cell, grid.cell_start, grid.gdims, _params(spec, h, grid), nb,
            count)
        found[compact] = {(i, int(nb[i, k])) for i in range(n) for k in range(count[i])}
    assert found[True] == found[False]
    found = found[True]
    cells = np.floor((spos - grid.lo) / grid.cell_size).astype(np.int64)
    close = brute_force_pairs(moved, 2.0 * h, n=n)
    stencil = {(i, j) for i, j in close if np.abs(cells[i] - cells[j]).max() <= cps}
    assert stencil <= found, f"{len(stencil - found)} pairs missed, e.g. {sorted(stencil - found)[:3]}"
    assert found <= close
    assert len(close - stencil) < 0.01 * len(close)  # what even the untrimmed stencil misses


@pytest.mark.parametrize("dim", [2, 3])
def test_a_particle_far_from_its_binned_cell_meets_no_neighbours(dim):
    """Between two sorts a particle can move arbitrarily far from the cell it was binned in (a wall
    driven at an absurd speed, a blown-up position). Its trimmed rows are then empty: it meets no
    neighbour and no cell outside the grid is read (this read crashed the process with SIGSEGV);
    the other particles no longer meet it and keep every other pair."""
    rng = np.random.default_rng(7 * dim)
    h, cps = 0.0371, 2
    lo = np.array([-0.13, 0.02, 0.5])[:dim]
    hi = lo + np.array([0.41, 0.23, 0.3])[:dim]
    n = 600 if dim == 2 else 900
    pos = lo + rng.random((n, dim)) * (hi - lo)
    grid, spos, ids, n_active = _bin(pos, lo, hi, h, cps)
    far = {3: 1e7, 50: -1e7, 100: 1e300, 150: -1e300, 200: np.inf, 250: np.nan}
    moved = spos.copy()
    for i, x in far.items():
        moved[i, 0] = x
    for compact in (False, True):
        spec, run = _driver(dim, cps, compact)
        nb = np.full((n, MAX_NB), -1, dtype=np.int64)
        count = np.zeros(n, dtype=np.int64)
        run(n, moved, _split(moved, grid), grid.cell, grid.cell_start, grid.gdims, _params(spec, h, grid), nb,
            count)
        assert all(count[i] == 0 for i in far)
        found = {(i, int(nb[i, k])) for i in range(n) for k in range(count[i])}
        near = {(i, j) for i, j in brute_force_pairs(spos, 2.0 * h, n=n) if i not in far and j not in far}
        assert found == near


@pytest.mark.parametrize("dim", [2, 3])
def test_compacted_rows_longer_than_the_buffer_are_chunked(dim):
    """A stencil row with more candidates than `stack.ROW_CAP` (a dense cluster) is compacted in
    chunks of the buffer: the pairs still equal brute force, for the compacted gather too."""
    from shoal.neighbours.stack import ROW_CAP

    rng = np.random.default_rng(5 + dim)
    h = 0.05
    lo = np.zeros(dim)
    hi = np.full(dim, 0.6)
    n = 3 * ROW_CAP
    pos = 0.3 + 0.02 * rng.random((n, dim))  # all within a cell or two
    grid, spos, ids, n_active, pairs = _check_against_brute_force(pos, lo, hi, h, 2, strict=True)
    occ = np.diff(grid.cell_start[:grid.ncell + 1])
    assert occ.max() > ROW_CAP  # a row holds more than the buffer
    assert len(pairs) == n * (n - 1)


@pytest.mark.parametrize("dim", [2, 3])
def test_binning_sorts_by_cell_stably(dim):
    rng = np.random.default_rng(7 + dim)
    h = 0.05
    lo = np.zeros(dim)
    hi = np.full(dim, 0.8 if dim == 2 else 0.4)
    pos = lo + rng.random((500, dim)) * (hi - lo)
    grid, spos, ids, n_active = _bin(pos, lo, hi, h, 2)
    assert sorted(ids.tolist()) == list(range(len(pos)))  # a permutation
    np.testing.assert_array_equal(spos, pos[ids])  # every array follows the same permutation
    idx = np.floor((pos - grid.lo) / grid.cell_size).astype(np.int64)
    strides = np.cumprod(np.r_[1, grid.dims[:-1]])
    cell = (idx * strides).sum(1)
    np.testing.assert_array_equal(grid.cell[:n_active], cell[ids])
    assert np.all(np.diff(grid.cell[:n_active]) >= 0)
    # stable: ties (same cell) keep their original order
    same = np.diff(grid.cell[:n_active]) == 0
    assert np.all(np.diff(ids)[same] > 0)
    # cell_start brackets each cell's particles
    cs = grid.cell_start
    assert cs[0] == 0 and cs[grid.ncell] == n_active and cs[grid.ncell + 1] == len(pos)
    for c in np.unique(cell):
        assert np.all(grid.cell[cs[c]:cs[c + 1]] == c)
        assert cs[c + 1] - cs[c] == np.count_nonzero(cell == c)


@pytest.mark.parametrize("threads", [1, 2, 7])
def test_the_threads_counting_sort_is_a_stable_argsort_whatever_its_blocks(threads):
    """The grid's counting sort (`_counting_sort`) splits the cells into `threads` blocks from the previous
    sort's ranges: with no previous sort, a stale one, nearly sorted or shuffled cells, a cell holding every
    particle, particles outside the grid (cell ncell), its permutation is NumPy's stable argsort and its
    ranges are the cells' counts summed up. 7 blocks on this machine's threads: a thread sorts several."""
    from shoal.neighbours.grid import _counting_sort

    rng = np.random.default_rng(threads)
    blocks = np.zeros(2 * (threads + 1), np.int64)
    for trial in range(24):
        ncell = int(rng.integers(1, 3000))
        n = int(rng.integers(0, 5000))
        cell = rng.integers(0, ncell + 1, n).astype(np.int32)
        if trial % 3 == 1:
            cell.sort()  # in cell order since the last sort, a few particles moved
            cell[rng.integers(0, max(n, 1), min(n, 15))] = rng.integers(0, ncell + 1)
        elif trial % 3 == 2:
            cell[:] = rng.integers(0, ncell + 1)  # every particle in one cell
        cell_start = np.zeros(ncell + 2, np.int32)
        if trial % 2:
            cell_start[:] = np.sort(rng.integers(0, 2 * n + 1, ncell + 2))  # another sort's ranges
        perm = np.full(n, -1, np.int32)
        _counting_sort(cell, n, ncell, cell_start, perm, threads, blocks)
        np.testing.assert_array_equal(perm, np.argsort(cell, kind="stable"))
        np.testing.assert_array_equal(cell_start, np.r_[0, np.cumsum(np.bincount(cell, minlength=ncell + 1))])


def test_binning_is_the_same_on_one_thread_and_two():
    """`CellGrid.bin` on 1 and 2 threads of Numba's pool gives the same permutation and ranges, sort after
    sort of moving particles (each sort's blocks come from the previous one)."""
    rng = np.random.default_rng(3)
    lo, hi = np.zeros(3), np.array([0.6, 0.3, 0.4])
    pos = lo + rng.random((20000, 3)) * (hi - lo)
    grids = [CellGrid(lo, hi, 0.04, 2, len(pos)) for _ in range(2)]
    before = numba.get_num_threads()
    try:
        for step in range(3):
            pos += 0.01 * rng.standard_normal(pos.shape)  # some leave the box
            out = []
            for threads, grid in zip((1, min(2, numba.config.NUMBA_NUM_THREADS)), grids):
                numba.set_num_threads(threads)
                grid.bin(pos, len(pos))
                out.append((grid.perm.copy(), grid.cell_start.copy()))
            np.testing.assert_array_equal(out[0][0], out[1][0])
            np.testing.assert_array_equal(out[0][1], out[1][1])
            pos = pos[out[0][0]]
    finally:
        numba.set_num_threads(before)


@pytest.mark.parametrize("cps", [1, 2])
@pytest.mark.parametrize("dim", [2, 3])
def test_outside_and_nan_particles_go_last(dim, cps):
    rng = np.random.default_rng(11 * dim + cps)
    h = 0.04
    lo = np.array([0.0, -0.1, 0.2])[:dim]
    hi = lo + 0.32  # a whole number of cells: the grid box is exactly [lo, hi)
    n = 400
    pos = lo + rng.random((n, dim)) * (hi - lo)
    bad = {
        0: lo - 1e-9,                      # just below lo
        1: hi,                             # exactly at hi: outside (half-open box)
        2: np.full(dim, np.nan),
        3: np.r_[np.nan, lo[1:] + 0.01],   # only one NaN component
        4: np.r_[lo[:-1] + 0.01, np.inf],
        5: np.r_[lo[:-1] + 0.1, -np.inf],
        6: lo + 5.0,
    }
    for i, p in bad.items():
        pos[i] = p
    pos[7] = lo  # on the lower corner: inside
    pos[8] = np.r_[lo[:-1], hi[-1] - 1e-12]  # just inside the top
    grid, spos, ids, n_active, pairs = _check_against_brute_force(pos, lo, hi, h, cps)
    np.testing.assert_allclose(grid.hi, hi, rtol=0, atol=1e-15)
    assert n_active == n - len(bad) == np.count_nonzero(_inside(pos, grid))
    assert set(ids[n_active:].tolist()) == set(bad)
    assert {7, 8} <= set(ids[:n_active].tolist())
    assert all(i < n_active and j < n_active for i, j in pairs)
    assert np.all(np.isfinite(spos[:n_active]))


def test_grid_rejects_bad_bounds():
    with pytest.raises(InputError, match="must exceed"):
        CellGrid([0.0, 0.0], [1.0, 0.0], 0.1, 2, 10)
    with pytest.raises(InputError, match="2 or 3 numbers"):
        CellGrid([0.0], [1.0], 0.1, 2, 10)


def test_grid_cell_count():
    g = CellGrid([0.0, 0.0, 0.0], [1.0, 0.5, 0.25], 0.1, 2, 1)
    assert g.cell_size == pytest.approx(0.05)
    assert tuple(g.dims) == (20, 10, 5) and g.ncell == 1000 == CellGrid.cells_for(
        [0.0, 0.0, 0.0], [1.0, 0.5, 0.25], 0.1, 2)
    g2 = CellGrid([0.0, 0.0], [1.0, 0.5], 0.3, 1, 1)
    assert g2.gdims == (4, 1, 2)  # 2D grids are (nx, 1, nz); the box rounds up to whole cells


@st.composite
def _point_sets(draw):
    dim = draw(st.sampled_from([2, 3]))
    cps = draw(st.sampled_from([1, 2, 3]))
    n = draw(st.integers(1, 60))
    # a mix of lattice points (k/8 of a cell: faces, coincident points) and arbitrary ones
    ints = draw(st.lists(st.lists(st.integers(0, 8 * 5), min_size=dim, max_size=dim), min_size=n, max_size=n))
    floats = draw(st.lists(st.lists(st.floats(0.0, 5.0, allow_nan=False), min_size=dim, max_size=dim),
                           min_size=n, max_size=n))
    use_float = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    cell = 0.1
    units = np.where(np.array(use_float)[:, None], np.array(floats), np.array(ints) / 8.0)
    return dim, cps, units * cell, cell


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_point_sets())
def test_gather_property(case):
    dim, cps, pos, cell = case
    h = 0.5 * cps * cell
    lo = np.zeros(dim)
    hi = np.full(dim, 4.5 * cell)  # some points (up to 5 cells) fall outside
    grid, spos, ids, n_active, pairs = _check_against_brute_force(pos, lo, hi, h, cps)
    assert n_active == np.count_nonzero(_inside(pos, grid))
    assert sorted(ids.tolist()) == list(range(len(pos)))


@pytest.mark.parametrize("dim", [2, 3])
def test_split_positions_hold_the_float64_coordinates(dim):
    """`split_positions`: the high part is the coordinate (less the corner) rounded to float32, and high
    plus low gives it back to within 2^-47 of its size; the rows past n are left alone."""
    rng = np.random.default_rng(dim)
    n = 1000
    lo = np.array([-3.0, 0.25, -0.5])[:dim]
    pos = lo + rng.random((n, dim)) * np.array([120.0, 7.0, 2.0])[:dim]
    out = np.full((2 * dim, n + 3), 7.0, np.float32)
    split_positions(n, pos, lo, out)
    v = pos - lo
    np.testing.assert_array_equal(out[:dim, :n].T, v.astype(np.float32))
    back = out[:dim, :n].astype(np.float64) + out[dim:, :n].astype(np.float64)
    assert np.all(np.abs(back.T - v) <= 2.0 ** -47 * np.abs(v))
    assert np.all(out[:, n:] == 7.0)
