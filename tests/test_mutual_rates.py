"""The CPU's rates a pair at a time (`shoal.physics.mutual`, `shoal.neighbours.half_sweep`).

Each pair is evaluated once and its terms added to both particles (Newton's third law), the grid's
tiles swept colour by colour. The sums are those of the per-particle rates (`shoal.physics.rates`, what
the CUDA backend runs) in another order: they must agree to round-off in every scheme the sweep takes,
give the same bits with any number of threads, and never let two threads write to one particle.
"""

import json
import os
from dataclasses import replace
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from shoal.backends.cpu import MutualRates
from shoal.cases import dam_break_2d, dam_break_3d, dam_break_dualsphysics, floating_box_2d
from shoal.neighbours.half_sweep import COLOURS, deal_tiles, make_tiles, tile_counter
from shoal.physics.mutual import mutual_supported
from shoal.physics.spec import FLUID
from shoal.runner import build_model
from shoal.timestepping import make_integrator

ROOT = Path(__file__).resolve().parents[1]


def _advance(m, steps):
    """`steps` steps of the case's integrator (the particles off their lattice and moving), then a sort."""
    integ = make_integrator(m)
    for _ in range(steps):
        m.time += integ.step(lambda limit: limit)
    m.sort()


def _both(m):
    """(per-particle, pair-at-a-time) rates of the model's current state: ace, drho, xsph, mu_max."""
    b = m.backend
    out = []
    mutual = b.rates
    for kernel in (b.rates_by_particle, mutual):
        b.rates = kernel
        m._rates()
        out.append([a[:m.n].copy() for a in (m.ace, m.drho, m.xsph, m.mu_max)])
    b.rates = mutual
    return out


# each scheme once, in one precision (the physics is the same code in both; two compiled kernels a
# scheme, per particle and a pair at a time, are what this file's time goes to)
CASES = {
    # the DualSPHysics benchmark: cubic spline, tensile correction, Fourtakas diffusion, DBC walls
    "dualsphysics-3d": (lambda p: dam_break_dualsphysics(dp=0.03, precision=p), "float32"),
    # the defaults (Wendland, Adami walls) with SPS turbulence (the rip-current paper's) and no-slip walls, 3D
    "sps-no-slip-3d": (lambda p: dam_break_3d(dp=0.03).with_options(precision=p, turbulence="sps", no_slip=True),
                       "float64"),
    # XSPH, laminar viscosity (a thousand times water's, so that it counts), Molteni diffusion, wall friction, mDBC
    "xsph-laminar-mdbc": (lambda p: dam_break_2d(dp=0.01).with_options(
        precision=p, xsph=0.5, viscosity="laminar", nu=1e-3, density_diffusion="molteni", visco_bound_factor=0.3,
        wall_pressure="mdbc"), "float64"),
    # a floating body (moving wall particles with their own velocities), DBC walls, SPS, no-slip
    "floating-sps-no-slip-dbc": (lambda p: floating_box_2d(dp=0.02).with_options(
        precision=p, wall_pressure="dynamic", turbulence="sps", no_slip=True), "float32"),
}

TOLERANCE = {"float32": 1e-4, "float64": 1e-11}
"""Largest difference from the per-particle rates, relative to the largest rate over the fluid: a few hundred
roundings of a sum of ~100-200 terms (measured 7e-7 and 1e-15); a missing or doubled pair's term is of the
order of the rate itself, a term of the wrong sign showed at 1e-5 and more in float64."""


@pytest.mark.parametrize("name", sorted(CASES))
def test_pair_at_a_time_rates_equal_the_per_particle_rates(name):
    """Every rate (acceleration, density rate, XSPH, the time-step term) within `TOLERANCE` of the per-particle
    rates' in the state after a few steps; wall particles get no acceleration, and a density rate only
    under DBC."""
    make, precision = CASES[name]
    tol = TOLERANCE[precision]
    m = build_model(make(precision))
    assert isinstance(m.backend.rates, MutualRates), name
    _advance(m, 5)
    ref, got = _both(m)
    fluid = m.kind[:m.n] == FLUID
    labels = ("ace", "drho", "xsph", "mu_max")
    for label, a, b in zip(labels, ref, got):
        if label == "xsph" and not m.spec.xsph:
            continue
        scale = np.abs(a[fluid]).max()
        assert scale > 0, label
        assert np.abs(a - b).max() <= tol * scale, (label, np.abs(a - b).max() / scale)
    walls = ~fluid
    assert not got[0][walls].any()
    if m.spec.wall_pressure != 0:
        assert not got[1][walls].any()
    else:
        assert np.abs(got[1][walls]).max() > 0


def test_the_schemes_the_sweep_takes():
    """Riemann pairs, repulsive particles, periodic axes and symmetry planes keep the per-particle rates."""
    m = build_model(dam_break_2d(dp=0.02))
    assert mutual_supported(m.spec)
    for change in (dict(riemann=True), dict(repulsive=True), dict(periodic=1), dict(symmetry=1)):
        assert not mutual_supported(replace(m.spec, **change)), change
    m = build_model(dam_break_2d(dp=0.02).with_options(riemann=True, alpha=0.0, density_diffusion="none"))
    assert not isinstance(m.backend.rates, MutualRates)


_THREADS_SCRIPT = """
import json, sys
import numba
import numpy as np
from shoal.cases import dam_break_dualsphysics
from shoal.runner import build_model
from shoal.timestepping import make_integrator
m = build_model(dam_break_dualsphysics(dp=0.03))
integ = make_integrator(m)
for _ in range(4):
    m.time += integ.step(lambda limit: limit)
m.sort()
res = {}
for t in (1, 2, 3):
    numba.set_num_threads(t)
    m._rates()
    res[t] = [a[:m.n].copy() for a in (m.ace, m.drho, m.mu_max)]
print(json.dumps({"same": all(all(np.array_equal(x, y) for x, y in zip(res[1], res[t])) for t in (2, 3))}))
"""


def test_the_same_bits_with_any_number_of_threads():
    """1, 2 and 3 threads deal the tiles differently; every particle's sum keeps its order."""
    env = dict(os.environ, NUMBA_NUM_THREADS="3")
    r = subprocess.run([sys.executable, "-c", _THREADS_SCRIPT], env=env, capture_output=True, text=True, timeout=600,
                       cwd=ROOT)
    assert r.returncode == 0, r.stderr[-2000:]
    assert json.loads(r.stdout.strip().splitlines()[-1]) == {"same": True}


def test_no_two_tiles_of_a_colour_write_to_one_particle():
    """Each neighbour pair within 2h belongs to the particle first in cell order, and its tile and the
    other particle's lie within one tile in x and the tile above in z (the premise of the colouring),
    here for a 3D dam break after a few steps, the pairs found by a k-d tree."""
    m = build_model(dam_break_3d(dp=0.03))
    _advance(m, 5)
    n = m.n
    nx, ny, nz = (int(d) for d in m.grid.gdims_arr[:3])
    cps = m.spec.cells_per_support
    cell = m.grid.cell[:n]
    cx = cell % nx
    cz = cell // (nx * ny)
    # each cell's tile (bx, bz) and colour, as the sweep's own tiling (`make_tiles`) cuts the grid
    tile_cells, _ = make_tiles(lambda f: f, m.spec)
    tile_of = np.full((nz, nx, 2), -1)
    colour_of = np.full((nz, nx), -1)
    ntx = -(-nx // cps)
    for t in range(tile_counter(m.spec)((nx, ny, nz))):
        x0, x1, z0, z1, c = tile_cells(t, (nx, ny, nz))
        tile_of[z0:z1, x0:x1] = (t % ntx, t // ntx)
        colour_of[z0:z1, x0:x1] = c
    assert np.all(tile_of >= 0)  # every cell in a tile
    bx, bz = tile_of[cz, cx, 0], tile_of[cz, cx, 1]
    support = 2 * float(m.h)
    pairs = cKDTree(m.pos[:n]).query_pairs(support * (1 + 1e-6), output_type="ndarray")
    assert len(pairs) > 1000
    i = pairs.min(axis=1)
    j = pairs.max(axis=1)
    # a pair belongs to i (the first in cell order): j's tile is bx - 1 .. bx + 1, bz .. bz + 1 of i's
    assert np.all(np.abs(bx[j] - bx[i]) <= 1)
    assert np.all((bz[j] - bz[i] >= 0) & (bz[j] - bz[i] <= 1))
    # so two tiles of one colour (bx 3 apart or more, or bz 2 apart or more) never write to one particle
    colour = bx % 3 + 3 * (bz % 2)
    np.testing.assert_array_equal(colour, colour_of[cz, cx])
    assert set(np.unique(colour)) <= set(range(COLOURS))


def test_tiles_are_dealt_once_each_costliest_first():
    """Every tile with particles goes to exactly one thread of its colour; each thread's load is within
    one tile's cost of the colour's mean load (the greedy bound of dealing costliest first)."""
    rng = np.random.default_rng(3)
    n_tiles, threads = 400, 5
    cost = np.zeros(n_tiles + threads)
    cost[:n_tiles] = rng.exponential(1.0, n_tiles) * (rng.random(n_tiles) > 0.2)
    colour = rng.integers(0, COLOURS, n_tiles).astype(np.int64)
    order = np.zeros(3 * n_tiles + threads, np.int64)
    starts = np.zeros(COLOURS * (threads + 1), np.int64)
    deal_tiles(colour, threads, cost, order, starts)
    seen = []
    for c in range(COLOURS):
        base = c * (threads + 1)
        loads = []
        for t in range(threads):
            tiles = order[starts[base + t]:starts[base + t + 1]]
            assert np.all(colour[tiles] == c)
            seen.extend(tiles.tolist())
            loads.append(cost[tiles].sum())
        mine = (colour == c) & (cost[:n_tiles] > 0)
        assert max(loads) <= cost[:n_tiles][mine].sum() / threads + cost[:n_tiles][mine].max() + 1e-12
    assert sorted(seen) == sorted(np.flatnonzero(cost[:n_tiles] > 0).tolist())
