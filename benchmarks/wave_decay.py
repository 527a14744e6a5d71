"""Numerical damping of a linear standing wave in a periodic 2D channel.

A wave flume's height falls along the flume when the scheme dissipates; this
script measures that dissipation in isolation, without a paddle, gauges or a
beach. A periodic channel one wavelength long (L from the linear dispersion
relation for period T and depth d) over a bed of boundary particles starts
flat, hydrostatic, with the velocity field of a linear standing wave of
amplitude a at the instant of zero elevation (Dean & Dalrymple 1991, ch. 4):

    u = a w cosh(k z) / sinh(k d) sin(k x),   w = -a w sinh(k z) / sinh(k d) cos(k x)

(z up from the bed, w = 2 pi / T). Linear theory keeps the wave energy
E = (1/4) rho g a^2 L per unit width constant (water's viscosity damps it by
exp(-4 nu k^2 t): 0.01 % per period here). The kinetic energy peaks every
T/2, when the surface is flat and all of E is kinetic; the script fits the
decay of those peaks, E ~ exp(-2 gamma t), so a progressive wave would lose
height as exp(-gamma x / c_g) over a distance x (c_g the group velocity). It
prints gamma, the height lost per period and per wavelength of travel, and the
standing-wave period (twice the spacing of the peaks) against T.

The kinetic energy also holds motion that is not the wave (particle-scale
noise, other modes), so the script projects the velocity on the wave's own
shape (mass-weighted, at the particles' current positions) and fits the peaks
of that mode's kinetic energy too ("mode_..."): what the wave keeps. The rest
is printed as the noise's kinetic energy at the mode's peaks, and the total
energy including the compression energy of the Tait equation of state
(m B [rho^6 / (6 rho0^7) + 1 / rho - 7 / (6 rho0)] per particle) at the end.

    python benchmarks/wave_decay.py --dp 0.02 --periods 3 --viscosity laminar
    python benchmarks/wave_decay.py --dp 0.02 --viscosity laminar --coef-h 1.5
    python benchmarks/wave_decay.py --dp 0.02 --bed plane --settle 0.5
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np


def build(dp0, depth, period, amplitude, options, bed="dynamic"):
    import shoal
    from shoal.case import Domain
    from shoal.geometry import Box
    from shoal.motions import wavenumber

    k = wavenumber(period, depth)
    L0 = 2 * math.pi / k
    n = max(8, round(L0 / dp0))
    dp = L0 / n  # the period holds a whole number of lattice spacings
    layers = 3
    if bed == "plane":  # a wall without particles: free-slip, no lattice for the fluid to rub on
        from shoal.case import WallPlane
        walls = dict(planes=[WallPlane(point=(0, 0, 0), normal=(0, 0, 1))])
    else:
        walls = dict(solids=[shoal.Solid(name="bed", shape=Box(lo=(0, 0, -layers * dp), hi=(L0, 0, 0)),
                                         boundary=bed, layers=layers if bed == "dynamic" else None)])
    case = shoal.Case(
        name="wave-decay", dim=2, dp=dp, end_time=1.0,
        fluid=shoal.Fluid(depth=depth, surface_level=depth),
        options=options, **walls,
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L0, 0, depth)))],
        domain=Domain(lo=(0, 0, -layers * dp), hi=(L0, 0, depth + 0.5 * depth), periodic=["x"]))
    return case, k, L0, dp


def energy(model, g):
    from shoal.physics.spec import FLUID

    kind = model.host(model.kind)
    f = kind == FLUID
    pos = model.host(model.pos)[f]
    vel = model.host(model.vel)[f].astype(np.float64)
    m = model.mass if np.ndim(model.mass) == 0 else model.host(model.mass)[f]
    ke = 0.5 * np.sum(m * np.sum(vel**2, axis=1))
    pe = np.sum(m * g * pos[:, -1])
    return ke, pe


def elastic_energy(model):
    """Internal (compression) energy of every particle, fluid and wall, for the Tait equation of state:
    m int_rho0^rho p / rho'^2 d rho' = m B [rho^6 / (6 rho0^7) + 1 / rho - 7 / (6 rho0)]."""
    rho = model.host(model.rho).astype(np.float64)
    r0 = model.rho0
    u = model.B * (rho**6 / (6 * r0**7) + 1 / rho - 7 / (6 * r0))
    m = model.mass if np.ndim(model.mass) == 0 else model.host(model.mass)
    return float(np.sum(m * u))


def mode_projection(model, k, depth):
    """Project the fluid velocity on the standing wave's velocity shape at the particles' positions:
    u = cosh(kz) sin(kx), w = -sinh(kz) cos(kx) (over sinh(kd)). Returns the mode's coefficient
    (m/s, the antinode surface speed a w) and its kinetic energy; the rest of the kinetic energy is in
    other motions (particle noise, other modes): the projection is orthogonal in the mass-weighted sum."""
    from shoal.physics.spec import FLUID

    f = model.host(model.kind) == FLUID
    pos = model.host(model.pos)[f]
    vel = model.host(model.vel)[f].astype(np.float64)
    x, z = pos[:, 0], pos[:, -1]
    sh = math.sinh(k * depth)
    pu, pw = np.cosh(k * z) / sh * np.sin(k * x), -np.sinh(k * z) / sh * np.cos(k * x)
    m = model.mass if np.ndim(model.mass) == 0 else model.host(model.mass)[f]
    norm = np.sum(m * (pu * pu + pw * pw))
    c = np.sum(m * (vel[:, 0] * pu + vel[:, -1] * pw)) / norm
    return float(c), float(0.5 * c * c * norm)


def _peaks(t, y):
    """t = 0 and the maxima of y(t), each refined by a parabola through its three samples."""
    from scipy.signal import find_peaks

    dt_s = t[1] - t[0]
    tp, vp = [0.0], [y[0]]
    for i in find_peaks(y)[0]:
        if 0 < i < len(t) - 1:
            y0, y1, y2 = y[i - 1:i + 2]
            shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
            tp.append(t[i] + shift * dt_s)
            vp.append(y1 - 0.25 * (y0 - y2) * shift)
    return np.array(tp), np.array(vp)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dp", type=float, default=0.02)
    p.add_argument("--depth", type=float, default=0.4)
    p.add_argument("--period", type=float, default=1.2)
    p.add_argument("--height", type=float, default=0.05, help="standing-wave height 2a at the antinodes [m]")
    p.add_argument("--periods", type=float, default=3.0)
    p.add_argument("--kernel", default="wendland")
    p.add_argument("--viscosity", default="artificial")
    p.add_argument("--alpha", type=float, default=0.01)
    p.add_argument("--nu", type=float, default=1e-6)
    p.add_argument("--density-diffusion", default="fourtakas")
    p.add_argument("--delta", type=float, default=0.1)
    p.add_argument("--coef-h", type=float, default=1.0)
    p.add_argument("--coef-sound", type=float, default=20.0)
    p.add_argument("--visco-bound-factor", type=float, default=0.0)
    p.add_argument("--integrator", default="symplectic")
    p.add_argument("--cfl", type=float, default=0.2)
    p.add_argument("--precision", default="float32")
    p.add_argument("--bed", default="dynamic", choices=("dynamic", "repulsive", "plane"),
                   help="the bed: dynamic boundary particles, Monaghan-Kajtar particles or a wall plane")
    p.add_argument("--settle", type=float, default=0.0,
                   help="let the still column settle this long [s] (velocities relaxed) before the wave starts")
    p.add_argument("--riemann", action="store_true", help="the Riemann pair terms (Zhang, Hu & Adams 2017)")
    p.add_argument("--wall-pressure", default="adami", choices=("dynamic", "adami", "mdbc"))
    p.add_argument("--shifting", default="none", choices=("none", "delta_plus"),
                   help="particle shifting (delta-plus-SPH, Sun et al. 2017)")
    p.add_argument("--csv", help="write the energy series (t, E, KE) here")
    a = p.parse_args(argv)

    from shoal import SPHOptions
    from shoal.physics.spec import FLUID
    from shoal.simulation import Simulation

    opts = SPHOptions(kernel=a.kernel, viscosity=a.viscosity, alpha=a.alpha, nu=a.nu,
                      density_diffusion=a.density_diffusion, delta=a.delta, coef_h=a.coef_h,
                      coef_sound=a.coef_sound, visco_bound_factor=a.visco_bound_factor, integrator=a.integrator,
                      cfl=a.cfl, precision=a.precision, riemann=a.riemann, wall_pressure=a.wall_pressure,
                      shifting=a.shifting)
    amp = 0.5 * a.height
    case, k, L, dp = build(a.dp, a.depth, a.period, amp, opts, bed=a.bed)
    w = 2 * math.pi / a.period
    end = a.periods * a.period
    sim = Simulation(case, end_time=end)
    m = sim.model
    g = 9.81
    kind = m.host(m.kind)
    f = kind == FLUID
    t_settle = 0.0
    if a.settle > 0:
        # let the still column settle first (its lattice start is not the discrete equilibrium, most of all
        # on a wall plane, where it bounces on the plane's repulsion): velocities relaxed by 1 % a step
        from shoal.simulation import IterationInterval

        def relax(s):
            v = s.model.host(s.model.vel)
            v[s.model.host(s.model.kind) == FLUID] *= 0.99
            s.model.vel[:] = v

        sim.end_time = a.settle
        cb = sim.add_callback(relax, IterationInterval(1))
        sim.run()
        sim.callbacks.remove(cb)
        t_settle = sim.time
        sim.end_time = t_settle + end
        kind = m.host(m.kind)
        f = kind == FLUID
    pos = m.host(m.pos)
    vel = m.host(m.vel)
    x, z = pos[f, 0], pos[f, -1]
    sh = math.sinh(k * a.depth)
    vel[f, 0] = amp * w * np.cosh(k * z) / sh * np.sin(k * x)
    vel[f, -1] = -amp * w * np.sinh(k * z) / sh * np.cos(k * x)
    m.vel[:] = vel
    ke0, pe0 = energy(m, g)
    # rest energy: the same particles settled flat (the start is flat: its potential energy is the rest one)
    e_lin = 0.25 * 1000.0 * g * amp**2 * L  # energy of a linear standing wave of amplitude a, per unit width
    u0 = elastic_energy(m)
    c0_, kem0 = mode_projection(m, k, a.depth)
    times, es, kes, cs, kems, eus = [t_settle], [ke0], [ke0], [c0_], [kem0], [ke0]
    sample = a.period / 40

    def record(s):
        ke, pe = energy(s.model, g)
        c, kem = mode_projection(s.model, k, a.depth)
        times.append(s.time)
        es.append(ke + pe - pe0)
        kes.append(ke)
        cs.append(c)
        kems.append(kem)
        eus.append(ke + pe - pe0 + elastic_energy(s.model) - u0)

    from shoal.simulation import TimeInterval

    t0 = time.perf_counter()
    sim.add_callback(record, TimeInterval(sample, start=t_settle + sample))
    sim.run()
    wall = time.perf_counter() - t0
    t, e, ke = np.array(times) - t_settle, np.array(es), np.array(kes)
    cm, kem, etot = np.array(cs), np.array(kems), np.array(eus)
    if a.csv:
        np.savetxt(a.csv, np.c_[t, e, ke, cm, kem, etot], delimiter=",",
                   header="time,E_above_rest,KE,mode_coefficient,KE_mode,E_with_elastic", comments="")
    # The kinetic energy peaks when the surface is flat (all the wave's energy is kinetic there), every
    # T/2: its maxima (refined by a parabola through the three samples around each) decay as
    # exp(-2 gamma t). The total E above the flat start is printed for information only: its potential
    # part also sees the whole column settle (1e-5 m of settling is 3 % of E at dp = 0.01 m).
    tp, vp = _peaks(t, ke)
    # the same for the standing-wave mode's own kinetic energy (the projection): what the wave keeps
    tm, vm = _peaks(t, kem)
    gamma_m = -0.5 * np.polyfit(tm, np.log(vm), 1)[0] if len(tm) >= 3 else float("nan")
    gamma = -0.5 * np.polyfit(tp, np.log(vp), 1)[0] if len(tp) >= 3 else float("nan")
    T_meas = 2 * float(np.mean(np.diff(tp))) if len(tp) >= 3 else float("nan")
    cg = 0.5 * w / k * (1 + 2 * k * a.depth / math.sinh(2 * k * a.depth))
    out = {
        "dp": dp, "bed": a.bed, "H_over_dp": a.height / dp, "particles": int(m.n), "steps": sim.step_count, "wall_s": round(wall, 1),
        "options": {k_: getattr(opts, k_) for k_ in ("shifting", "kernel", "viscosity", "alpha", "nu",
                                                     "density_diffusion", "delta", "coef_h", "coef_sound",
                                                     "visco_bound_factor", "integrator", "cfl", "precision")},
        "E0_over_linear": float(e[0] / e_lin),  # initial energy (all kinetic) vs linear theory
        "gamma_per_s": float(gamma),
        "height_loss_per_period_percent": 100 * (1 - math.exp(-gamma * a.period)),
        "height_loss_per_wavelength_travelled_percent": 100 * (1 - math.exp(-gamma * L / cg)),
        "kinetic_energy_peaks_over_first": [round(float(v / vp[0]), 4) for v in vp],
        "mode_gamma_per_s": float(gamma_m),
        "mode_height_loss_per_wavelength_travelled_percent": 100 * (1 - math.exp(-gamma_m * L / cg)),
        "mode_kinetic_energy_peaks_over_first": [round(float(v / vm[0]), 4) for v in vm],
        "noise_kinetic_energy_at_mode_peaks_over_first": [round(float(np.interp(x_, t, ke - kem) / vm[0]), 4)
                                                          for x_ in tm],
        "energy_with_elastic_at_end_over_start": float(etot[-1] / etot[0]),
        "total_energy_above_rest_at_end_over_start": float(e[-1] / e[0]),
        "period_measured_s": T_meas, "period_error_percent": 100 * (T_meas / a.period - 1),
    }
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
