"""Still water in a tank: hydrostatic pressure p = rho0 g (H - z).

After the start-up transient the pressure of fluid particles away from the
walls must follow rho0 g (H - z) within 2 % of the bottom pressure
rho0 g H, the free surface stay within one dp of its initial level, and
mass be conserved exactly (constant particle masses, no particle lost).

"Away from the walls": more than a fifth of the tank from each side wall
and more than one kernel support 2h above the bed, where the dynamic
boundary particles' pressure noise reaches the first fluid layers (the
error there is printed too). The fine 2D run (dp = H/100, 62,680 steps)
is what showed float32 positions to be too coarse for still water (3.1 %
after 2 s); with float64 positions it gives 1.4 % in float32 runs.
"""

import numpy as np
import pytest

from shoal.cases import still_water_2d, still_water_3d
from shoal.options import SPHOptions
from shoal.physics.spec import FLUID
from shoal.runner import build_model
from shoal.simulation import Simulation, TimeInterval

G = 9.81


def settle(case, t_end, t_avg):
    """Run to t_end; average particle pressure over the last t_avg seconds."""
    model = build_model(case)
    n_fluid0 = model.n_fluid
    top0 = model.world_positions()[model.kind[: model.n] == FLUID, 2].max()
    sim = Simulation(model, t_end)
    acc = {}

    def sample(s):
        if s.time >= t_end - t_avg - 1e-9:
            ids = s.model.idp[: s.model.n]
            for k, v in (("p", s.model.pressure()), ("z", s.model.world_positions()[:, 2]),
                         ("x", s.model.world_positions()[:, 0]), ("y", s.model.world_positions()[:, 1])):
                arr = np.zeros(s.model.n_total)
                arr[ids] = v
                acc.setdefault(k, []).append(arr)

    sim.add_callback(sample, TimeInterval(t_avg / 10))
    sim.run()
    kind = np.zeros(model.n_total, dtype=int)
    kind[model.idp[: model.n]] = model.kind[: model.n]
    mean = {k: np.mean(v, axis=0) for k, v in acc.items()}
    return model, sim, mean, kind, n_fluid0, top0


def check_hydrostatic(case, depth, lengths, t_end, t_avg, below_surface=0.0):
    model, sim, m, kind, n_fluid0, top0 = settle(case, t_end, t_avg)
    fluid = kind == FLUID
    interior = fluid.copy()
    # away from the side walls: more than a fifth of the tank from each wall
    interior &= (m["x"] > 0.2 * lengths[0]) & (m["x"] < 0.8 * lengths[0])
    if case.dim == 3:
        interior &= (m["y"] > 0.2 * lengths[1]) & (m["y"] < 0.8 * lengths[1])
    interior &= m["z"] < depth - below_surface
    h = case.options.coef_h * np.sqrt(case.dim) * case.dp
    near_bed = interior & (m["z"] < 2 * h)
    interior &= m["z"] >= 2 * h
    p_ref = 1000.0 * G * (depth - m["z"][interior])
    err = np.max(np.abs(m["p"][interior] - p_ref)) / (1000.0 * G * depth)
    err_bed = np.max(np.abs(m["p"][near_bed] - 1000.0 * G * (depth - m["z"][near_bed]))) / (1000.0 * G * depth)
    print(f"{case.name}: within 2h of the bed: max error {err_bed:.4f}")
    top = model.world_positions()[model.host(model.kind) == FLUID, 2].max()
    print(f"{case.name}: max |p - rho0 g (H - z)| / (rho0 g H) = {err:.4f}; surface moved {abs(top - top0):.2e} m "
          f"(dp = {case.dp} m); {sim.step_count} steps")
    assert err < 0.02
    assert abs(top - top0) < case.dp
    assert model.n_fluid == n_fluid0 and model.n_escaped == 0
    return err


def test_still_water_2d():
    depth, length = 0.4, 0.8
    check_hydrostatic(still_water_2d(dp=0.02, depth=depth, length=length), depth, (length,),
                      t_end=1.5, t_avg=0.5)


def test_still_water_2d_dbc_walls():
    """The same tank with DBC walls (each wall particle integrating its own continuity equation) instead
    of the default Adami walls: hydrostatic within 2 % and nothing lost (measured: 1.0 % in the interior,
    1.2 % within 2h of the bed; Adami 1.0 % and 1.3 %)."""
    depth, length = 0.4, 0.8
    check_hydrostatic(still_water_2d(dp=0.02, depth=depth, length=length,
                                     options=SPHOptions(wall_pressure="dynamic")), depth, (length,),
                      t_end=1.5, t_avg=0.5)


def test_still_water_2d_riemann():
    """The same tank with the Riemann pair terms (`riemann = true`, no artificial viscosity, no density
    diffusion): the acoustic diffusion, its hydrostatic jump left out, keeps the tank hydrostatic within
    2 % with the surface in place (measured: 0.9 % in the interior, 1.0 % within 2h of the bed)."""
    depth, length = 0.4, 0.8
    opts = SPHOptions(riemann=True, alpha=0.0, density_diffusion="none")
    check_hydrostatic(still_water_2d(dp=0.02, depth=depth, length=length, options=opts), depth, (length,),
                      t_end=1.5, t_avg=0.5)


def test_still_water_3d():
    """Coarse (10 particles deep): compared below the surface layer of one
    kernel support 2h, where the kernel is truncated (the top particle
    layer sits ~3 % of rho0 g H high at this resolution; 2D at 20 particles
    deep passes with the surface layer included)."""
    depth, length, width = 0.3, 0.3, 0.3
    case = still_water_3d(dp=0.03, depth=depth, length=length, width=width, layers=3)
    h = case.options.coef_h * 3**0.5 * case.dp
    check_hydrostatic(case, depth, (length, width), t_end=0.6, t_avg=0.2, below_surface=2 * h)


@pytest.mark.validation
def test_still_water_3d_fine():
    depth, length, width = 0.3, 0.3, 0.3
    check_hydrostatic(still_water_3d(dp=0.015, depth=depth, length=length, width=width, layers=3),
                      depth, (length, width), t_end=1.0, t_avg=0.3)


@pytest.mark.validation
def test_still_water_2d_fine():
    depth, length = 0.5, 1.0
    check_hydrostatic(still_water_2d(dp=0.005, depth=depth, length=length), depth, (length,),
                      t_end=2.0, t_avg=0.5)


def test_still_water_with_repulsive_walls():
    """Monaghan & Kajtar (2009) walls (one layer at dp/2, K = g D): over 10^4 steps no particle
    crosses a wall (every fluid particle stays inside the tank) and, once settled, the pressure
    away from the walls is hydrostatic within 3 % of rho0 g H below the settled free surface
    (the water column first rises: the fluid starts 0.75 dp from the wall particles, closer than
    where their force balances the pressure, and settles about half a spacing higher)."""
    import shoal
    from shoal.geometry import Box, Tank

    depth, length, dp = 0.4, 0.8, 0.02
    case = shoal.Case(name="still-water-mk", dim=2, dp=dp, end_time=1.5,
                      fluid=shoal.Fluid(depth=depth, surface_level=depth),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(length, 0, 0.6)), boundary="repulsive")],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)))])
    model, sim, m, kind, n_fluid0, top0 = settle(case, 1.5, 0.3)
    assert sim.step_count >= 10_000
    fluid = kind == FLUID
    pos = model.world_positions()
    fl_now = model.host(model.kind) == FLUID
    assert pos[fl_now, 0].min() > 0 and pos[fl_now, 0].max() < length and pos[fl_now, 2].min() > 0
    assert model.n_fluid == n_fluid0 and model.n_escaped == 0
    x, z, p = m["x"], m["z"], m["p"]
    interior = fluid & (x > 0.2 * length) & (x < 0.8 * length)
    # settled surface: the mean top particle of the interior columns, plus half a spacing
    cols = np.round(x[interior] / dp).astype(int)
    tops = [z[interior][cols == c].max() for c in np.unique(cols)]
    surf = float(np.mean(tops)) + 0.5 * dp
    h = case.smoothing_length
    inner = interior & (z > 2 * h) & (z < surf - 2 * h)
    err = np.max(np.abs(p[inner] - 1000.0 * G * (surf - z[inner]))) / (1000.0 * G * depth)
    print(f"repulsive walls: {sim.step_count} steps, settled surface {surf:.4f} m (filled to {depth} m), "
          f"max hydrostatic error {err:.4f}")
    assert abs(surf - depth) < 2 * dp
    assert err < 0.03


def test_still_water_between_wall_planes():
    """A tank whose bed and side walls are geometric planes (no particles): over 10^4 steps the
    water stays inside the planes and the pressure away from the walls is hydrostatic below the
    settled surface within 3 % of rho0 g H. Measured: 1.6 % at 1.5 s. (Before the planes had the
    normal part of the wall's viscous term the column bounced on the planes' repulsion, +-0.1 m/s
    still at 3 s, and the error was 3.8 %.)"""
    import shoal
    from shoal.case import Domain, WallPlane
    from shoal.geometry import Box

    depth, length, dp = 0.4, 0.8, 0.02
    case = shoal.Case(name="still-water-planes", dim=2, dp=dp, end_time=1.5,
                      fluid=shoal.Fluid(depth=depth, surface_level=depth),
                      planes=[WallPlane(point=(0, 0, 0), normal=(0, 0, 1)),
                              WallPlane(point=(0, 0, 0), normal=(1, 0, 0)),
                              WallPlane(point=(length, 0, 0), normal=(-1, 0, 0))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)))],
                      domain=Domain(lo=(-0.1, 0, -0.1), hi=(length + 0.1, 0, 0.8)))
    assert case.particles().counts() == {"fluid": 40 * 20, "fixed": 0, "moving": 0}
    model, sim, m, kind, n_fluid0, top0 = settle(case, 1.5, 0.3)
    assert sim.step_count >= 10_000
    pos = model.world_positions()
    assert pos[:, 0].min() > 0 and pos[:, 0].max() < length and pos[:, 2].min() > 0
    assert model.n_escaped == 0
    x, z, p = m["x"], m["z"], m["p"]
    interior = (x > 0.2 * length) & (x < 0.8 * length)
    cols = np.round(x[interior] / dp).astype(int)
    surf = float(np.mean([z[interior][cols == c].max() for c in np.unique(cols)])) + 0.5 * dp
    h = case.smoothing_length
    inner = interior & (z > 2 * h) & (z < surf - 2 * h)
    err = np.max(np.abs(p[inner] - 1000.0 * G * (surf - z[inner]))) / (1000.0 * G * depth)
    print(f"wall planes: {sim.step_count} steps, settled surface {surf:.4f} m, max hydrostatic error {err:.4f}")
    assert abs(surf - depth) < 2 * dp
    assert err < 0.03
