"""The wall pressure of Adami, Hu & Adams (2012) (`wall_pressure = "adami"`).

Each dynamic boundary particle b takes the fluid's pressure extrapolated to
it, p_b = (sum_f p_f W_bf + (g - a_b) . sum_f rho_f r_bf W_bf) / sum_f W_bf.
Checked here against what the formula must give:

* in still water, whose pressure is linear in z, the extrapolation is exact
  for a linear field: p_b = rho0 g (H - z_b) at every wall particle below the
  surface (to the density's 0.1 % variation over the kernel), zero above it;
* a wall accelerating at a adds rho_f a . (r_f - r_b) averaged with the kernel;
* a uniform stream over a flat free-slip bed keeps its speed (Galilean
  invariance; a laminar boundary layer would be sqrt(nu t) = 1.4 mm thick
  after 2 s), where the dynamic boundary condition (DBC, each wall particle
  integrating its own continuity equation) drags it: measured with
  `benchmarks/bed_drag.py`, 0.7 m/s over a bed at dp = d0/10 loses 5.5 % of
  its depth-mean speed in 2 s on DBC walls, 0.7 % on Adami walls and none
  over a wall plane (see benchmarks/results/notes/README.md for d0/20).
"""

import numpy as np
import pytest

import shoal
from shoal.case import Domain
from shoal.cases import still_water_2d
from shoal.cases.tidal_bore import PAPER_OPTIONS
from shoal.geometry import Box, Tank
from shoal.motions import ConstantVelocity, PistonWavemaker, TimeSeriesMotion
from shoal.options import SPHOptions
from shoal.physics.spec import FLUID
from shoal.runner import build_model
from shoal.simulation import Simulation, TimeInterval

G = 9.81


def _wall_pressures(model):
    """Pressure of every particle and its kind and position, by row."""
    model.sort()
    model.compute_rates()
    return model.pressure(), model.host(model.kind), model.world_positions()


def test_still_water_wall_pressure_is_hydrostatic():
    depth, dp = 0.2, 0.01
    case = still_water_2d(dp=dp, depth=depth, length=0.3, options=SPHOptions(wall_pressure="adami",
                                                                             precision="float64"))
    model = build_model(case)
    p, kind, pos = _wall_pressures(model)
    z = pos[:, 2]
    wall = kind != FLUID
    # wall particles that see fluid: within the kernel support of some fluid particle
    from scipy.spatial import cKDTree

    tree = cKDTree(pos[kind == FLUID][:, [0, 2]])
    seen = wall & np.isfinite(tree.query(pos[:, [0, 2]], distance_upper_bound=2 * case.smoothing_length)[0])
    assert seen.sum() > 50
    ref = np.maximum(1000.0 * G * (depth - z), 0.0)
    err = np.abs(p[seen] - ref[seen]) / (1000.0 * G * depth)
    print(f"{seen.sum()} wall particles: max |p_b - rho0 g (H - z_b)| / (rho0 g H) = {err.max():.2e}")
    assert err.max() < 2e-3
    # the unseen deeper layer gets p = 0, rho = rho0
    unseen = wall & ~seen
    assert np.all(p[unseen] == 0.0)


def test_accelerating_wall_adds_rho_a_dx():
    """A paddle wall accelerating towards the fluid at a carries extra pressure
    a sum_f rho_f (x_f - x_b) W_bf / sum_f W_bf (Adami et al. 2012, Eq. 27): checked against that sum
    computed here from the positions, at the vertex t = 0.5 s of a displacement x(t) = a (t - 0.5)^2 / 2
    read from a time series (there the paddle is at its start, at rest, accelerating at a)."""
    import tempfile
    from pathlib import Path

    depth, dp, a = 0.1, 0.01, 2.0
    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "x.csv"
        t = np.linspace(0.0, 1.0, 101)
        np.savetxt(f, np.c_[t, 0.5 * a * (t - 0.5) ** 2], delimiter=",")
        motions = {"still": ConstantVelocity(name="paddle", velocity=(0, 0, 0)),
                   "accel": TimeSeriesMotion(name="paddle", file=str(f))}
        p = {}
        for key, motion in motions.items():
            case = shoal.Case(name="paddle", dim=2, dp=dp, end_time=0.1,
                              fluid=shoal.Fluid(depth=depth, surface_level=depth),
                              options=SPHOptions(wall_pressure="adami", precision="float64"),
                              solids=[shoal.Solid(name="paddle", shape=Box(lo=(-0.03, 0, 0), hi=(0.0, 0, 0.15)),
                                                  motion="paddle", layers=3),
                                      shoal.Solid(name="tank", shape=Tank(lo=(-0.03, 0, 0), hi=(0.3, 0, 0.15)),
                                                  layers=3)],
                              fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.3, 0, depth)))],
                              motions=[motion])
            model = build_model(case)
            model.move_bodies(0.5)
            if key == "accel":
                np.testing.assert_allclose(motion.acceleration(0.5), [a, 0, 0], rtol=1e-9)
            pr, kind, pos = _wall_pressures(model)
            ids = model.host(model.idp)
            p[key] = (pr[np.argsort(ids)], kind[np.argsort(ids)], pos[np.argsort(ids)],
                      model.host(model.rho)[np.argsort(ids)])
    (p0, kind, pos, rho), (p1, _, pos1, _) = p["still"], p["accel"]
    moving = kind == 2
    np.testing.assert_allclose(pos1, pos, atol=1e-9)  # the paddle is at its start in both
    h = model.h
    fl = kind == FLUID
    xf, zf, rf = pos[fl, 0], pos[fl, 2], rho[fl]
    checked = 0
    for b in np.flatnonzero(moving & (pos[:, 2] < depth - 2 * dp)):
        r = np.hypot(xf - pos[b, 0], zf - pos[b, 2])
        q = r / h
        wq = np.clip(1 - q / 2, 0, None) ** 4 * (2 * q + 1)  # Wendland: the normalisation cancels
        if wq.sum() == 0:
            continue
        expect = a * np.sum(rf * (xf - pos[b, 0]) * wq) / wq.sum()
        assert expect > 0
        assert p1[b] - p0[b] == pytest.approx(expect, rel=1e-6)
        checked += 1
    assert checked >= 10


def _stream(dp, wall_pressure, t_end, U=0.7, d0=0.1, L=0.4):
    """Uniform flow U over a flat bed (3 layers of dynamic particles), periodic in x, with the tidal-bore
    paper's scheme (alpha = 0.02, free-slip walls for the viscous term): depth-mean and near-bed (lowest
    2 cm) speeds over time."""
    case = shoal.Case(
        name="stream", dim=2, dp=dp, end_time=t_end,
        fluid=shoal.Fluid(depth=d0, u_max=U + (G * d0) ** 0.5, surface_level=d0),
        options=dict(PAPER_OPTIONS, alpha=0.02, wall_pressure=wall_pressure),
        solids=[shoal.Solid(name="bed", shape=Box(lo=(0, 0, -3 * dp), hi=(L, 0, 0)), layers=3)],
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L, 0, d0)), velocity=(-U, 0, 0))],
        domain=Domain(lo=(0, 0, -3 * dp), hi=(L, 0, 0.4), periodic=["x"]))
    model = build_model(case)
    sim = Simulation(model, t_end)
    out = []

    def record(s):
        m = s.model
        fl = m.host(m.kind) == FLUID
        pos, vel = m.world_positions()[fl], m.world_velocities()[fl]
        u, z = -vel[:, 0], pos[:, 2]
        out.append((s.time, float(u.mean()), float(u[z < 0.02].mean()), float(z.min())))

    sim.add_callback(record, TimeInterval(0.5))
    sim.run()
    return np.array(out), model


def test_uniform_stream_over_adami_bed_keeps_its_speed():
    """0.7 m/s over a free-slip bed for 2 s at dp = d0/10 (the DBC bed loses 5.5 % of it, see the module
    docstring): within 2 % of U, depth-mean and near the bed, no particle below the bed surface."""
    rec, model = _stream(0.01, "adami", 2.0)
    for t, mean, bed, zmin in rec:
        print(f"t = {t:.1f} s: depth-mean {mean:.4f} m/s, lowest 2 cm {bed:.4f} m/s, lowest particle {zmin:.4f} m")
    assert rec[-1, 0] == pytest.approx(2.0)
    assert np.all(np.abs(rec[:, 1] / 0.7 - 1) < 0.02)
    assert np.all(np.abs(rec[:, 2] / 0.7 - 1) < 0.02)
    assert np.all(rec[:, 3] > 0.0)
    assert model.n_escaped == 0


def test_motion_accelerations():
    """`Motion.acceleration`: the piston's central difference against its second derivative, and the
    impulsive constant-velocity start as zero."""
    m = PistonWavemaker(name="p", height=0.05, period=1.2, depth=0.4, ramp_periods=0.0)
    w = 2 * np.pi / 1.2
    for t in (0.1, 0.37, 0.9):
        np.testing.assert_allclose(m.acceleration(t)[0], -0.5 * m.stroke * w**2 * np.sin(w * t), rtol=1e-6)
    assert np.all(ConstantVelocity(name="c", velocity=(0.7, 0, 0)).acceleration(0.0) == 0)
