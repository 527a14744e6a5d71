"""The modified dynamic boundary condition (mDBC, English et al. 2022; `shoal.physics.mdbc`).

Each dynamic wall particle takes the density of the fluid at its ghost node, its mirror image
across the wall surface, extrapolated back to the particle to first order. What the formula must
give, checked here on tanks built from bare arrays (ghost vectors written by hand: the mirror
across the nearest point of the tank's inner box, so a corner particle mirrors through the corner):

* a fluid whose density is linear in space gives every wall particle the value of that linear
  field at the particle's own position, to round-off (the kernel-gradient-corrected fit is exact
  for linear fields wherever the correction matrix is regular), also across a periodic face;
* a uniform stream gives the walls the no-slip velocity 2 u_wall - U = -U;
* still water keeps its lowest fluid layer half a spacing above the bed.
"""

import numpy as np
import pytest

from shoal.errors import InputError
from shoal.geometry.lattice import box_fill, tank_walls
from shoal.model import Model
from shoal.options import SPHOptions
from shoal.physics.spec import FLUID

RHO0 = 1000.0


def _tank(dim, dp, lo, hi, fill_hi, layers=3, **options):
    """A tank [lo, hi] of `layers` wall layers filled up to `fill_hi`; ghost vectors mirror each wall
    particle across the nearest point of the box [lo, hi]."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    fl = box_fill(lo, fill_hi, dp, dim)
    wl = tank_walls(lo, hi, dp, dim, layers=layers)
    pos = np.vstack([fl, wl])
    kinds = np.r_[np.zeros(len(fl), np.int8), np.ones(len(wl), np.int8)]
    near = np.clip(pos, lo, hi)
    if dim == 2:
        near[:, 1] = 0.0
    ghost = 2.0 * (near - pos)
    ghost[kinds == FLUID] = 0.0
    opts = SPHOptions(**{"wall_pressure": "mdbc", "precision": "float64", **options})
    pad = (layers + 1) * dp
    m = Model(pos, kinds, dp=dp, dim=dim, domain=(lo - pad, hi + pad), options=opts,
              fluid_height=float(fill_hi[2] - lo[2]), surface_z=float(fill_hi[2]), wall_normals=ghost)
    return m, ghost


def _set_by_id(model, name, values):
    """Write `values` (rows in particle-id order) into the model's array `name` (rows in cell order)."""
    ids = model.host(model.idp)
    a = getattr(model, name)
    a[: model.n] = values[ids]


def _by_id(model, array):
    ids = model.host(model.idp)
    out = np.empty_like(model.host(array))
    out[ids] = model.host(array)
    return out


@pytest.mark.parametrize("precision", ["float64", "float32"])
@pytest.mark.parametrize("dim", [2, 3])
def test_linear_density_is_extrapolated_exactly_to_the_walls(dim, precision):
    """Exact to round-off in float64; in float32, to a few units in the last place of the density (its
    ulp is 6.1e-5 kg/m^3 at rho0): the sums hold rho - rho0, not rho, so they keep its digits."""
    dp = 0.02
    hi = [0.3, 0.2, 0.3]
    m, ghost = _tank(dim, dp, [0, 0, 0], hi, hi, layers=3, precision=precision)  # open top
    pos = m.world_positions()
    ids = m.host(m.idp)
    pos_id = np.empty_like(pos)
    pos_id[ids] = pos
    grad = np.array([40.0, -25.0, -90.0]) if dim == 3 else np.array([40.0, 0.0, -90.0])
    field = RHO0 + 40.0 + (pos_id - [0.15, 0.1, 0.3]) @ grad  # > rho0 everywhere: the floor never bites
    field = field.astype(m.dtype).astype(np.float64)  # what the particles hold
    assert field.min() > RHO0
    kinds = np.r_[m.host(m.kind)][np.argsort(ids)]
    m.sort()
    _set_by_id(m, "rho", field)
    m.compute_rates()
    rho = _by_id(m, m.rho)
    wall = kinds != FLUID
    # wall particles whose ghost node lies well inside the fluid (2h from the open top): full fit
    g_pos = pos_id + ghost
    inside = wall & (g_pos[:, 2] < hi[2] - 2 * m.h)
    assert inside.sum() > (100 if dim == 2 else 1000)
    err = np.abs(rho[inside] - field[inside])
    print(f"{dim}D {precision}: {inside.sum()} wall particles, max |rho_b - linear field| = {err.max():.2e} kg/m^3")
    assert err.max() < (1e-8 * RHO0 if precision == "float64" else 10 * 6.1e-5)
    # the walls' continuity is not integrated
    assert np.all(_by_id(m, m.drho)[wall] == 0.0)


def test_ghost_nodes_see_across_a_periodic_face():
    """A bed periodic in x under fluid whose density varies with depth only (quadratically, so that
    the first-order fit has an error that depends on which neighbours it sees): every bed particle
    at a given depth must get the same density, whatever its x. The ghost nodes next to the faces
    see the fluid across them as the others see their neighbours (without the wrap they would fit
    one-sided supports and differ)."""
    dp, L, H = 0.02, 0.3, 0.2
    fl = box_fill([0, 0, 0], [L, 0, H], dp, 2)
    bed = box_fill([0, 0, -3 * dp], [L, 0, 0], dp, 2)
    pos = np.vstack([fl, bed])
    kinds = np.r_[np.zeros(len(fl), np.int8), np.ones(len(bed), np.int8)]
    ghost = np.zeros_like(pos)
    ghost[kinds == 1, 2] = -2.0 * pos[kinds == 1, 2]
    m = Model(pos, kinds, dp=dp, dim=2, domain=([0, 0, -3 * dp], [L, 0, 0.5]), periodic=["x"],
              options=SPHOptions(wall_pressure="mdbc", precision="float64"), fluid_height=H, wall_normals=ghost)
    field = RHO0 + 20.0 - 60.0 * pos[:, 2] + 3000.0 * pos[:, 2] ** 2
    m.sort()
    _set_by_id(m, "rho", field)
    m.compute_rates()
    rho = _by_id(m, m.rho)
    edge = (pos[:, 0] < 2 * m.h) | (pos[:, 0] > L - 2 * m.h)
    checked = 0
    for z in np.unique(np.round(pos[kinds == 1, 2], 9)):
        row = (kinds == 1) & (np.abs(pos[:, 2] - z) < 1e-9)
        middle = rho[row & ~edge]
        assert np.ptp(middle) < 1e-9 * RHO0
        err = np.abs(rho[row & edge] - middle[0])
        assert err.max() < 1e-9 * RHO0, (z, err.max())
        assert abs(middle[0] - field[row][0]) > 1e-6  # the quadratic is not fitted exactly: the test can bite
        checked += int((row & edge).sum())
    assert checked >= 12


def test_no_slip_velocity_mirrors_the_ghost_velocity():
    dp = 0.02
    m, ghost = _tank(2, dp, [0, 0, 0], [0.4, 0, 0.3], [0.4, 0, 0.2], no_slip=True)
    kinds = _by_id(m, m.kind)
    U = np.array([0.3, -0.1])
    m.sort()
    vel = np.zeros((m.n_total, 2))
    vel[kinds == FLUID] = U
    _set_by_id(m, "vel", vel)
    m.compute_rates()
    vwall = _by_id(m, m.vwall)
    pos = np.empty((m.n_total, 3))
    pos[m.host(m.idp)] = m.world_positions()
    submerged = (kinds != FLUID) & (pos[:, 2] + ghost[:, 2] < 0.2 - 2 * m.h)
    assert submerged.sum() > 50
    np.testing.assert_allclose(vwall[submerged], np.broadcast_to(-U, (submerged.sum(), 2)), atol=1e-12)
    np.testing.assert_array_equal(vwall[kinds == FLUID], vel[kinds == FLUID])


def test_still_water_sits_half_a_spacing_above_the_bed():
    """Still water (H/dp = 20) for 0.5 s: the lowest fluid layer stays at dp/2 above the bed surface
    (within 0.1 dp), the floor's density is the fluid's hydrostatic one extrapolated (within 2 % of
    rho0 g H: the SPH free surface adds about 1 % to the head at this resolution, as on any wall)."""
    from shoal.simulation import Simulation

    dp, H = 0.01, 0.2
    m, _ = _tank(2, dp, [0, 0, 0], [0.4, 0, 0.3], [0.4, 0, H], precision="float32")
    Simulation(m, 0.5).run()
    pos = m.world_positions()
    kinds = m.host(m.kind)
    z = pos[kinds == FLUID, 2]
    print(f"lowest fluid particle z = {z.min() / dp:.3f} dp")
    assert abs(z.min() / dp - 0.5) < 0.1
    p = m.pressure()
    floor = (kinds != FLUID) & (np.abs(pos[:, 2] + dp / 2) < 1e-6) & (pos[:, 0] > 0.1) & (pos[:, 0] < 0.3)
    ref = RHO0 * 9.81 * (H + dp / 2)
    ratio = p[floor] / ref
    print(f"first floor layer: p / rho0 g (H + dp/2) = {ratio.min():.4f} - {ratio.max():.4f}")
    assert np.all(np.abs(ratio - 1) < 0.02)


def test_mdbc_without_ghost_vectors_is_refused():
    fl = box_fill([0, 0, 0], [0.2, 0, 0.1], 0.02, 2)
    wl = tank_walls([0, 0, 0], [0.2, 0, 0.2], 0.02, 2)
    pos = np.vstack([fl, wl])
    kinds = np.r_[np.zeros(len(fl)), np.ones(len(wl))]
    with pytest.raises(InputError, match="ghost vectors"):
        Model(pos, kinds, dp=0.02, dim=2, domain=([-0.1, 0, -0.1], [0.3, 0, 0.3]),
              options=SPHOptions(wall_pressure="mdbc"), fluid_height=0.1)
