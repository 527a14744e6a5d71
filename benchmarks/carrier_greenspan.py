"""Periodic run-up on a plane beach: the Carrier & Greenspan (1958) standing wave (issue 28, item 3).

A 2D flume whose bed is a plane beach of slope 1:cot from a piston paddle at x = 0 (still-water depth
d there) to above the run-up; the still-water shoreline is at x = d cot. The paddle moves with the
standing wave's velocity at its face and the fluid starts from the wave's state at t = 0: a flat
surface, the hydrostatic density, the velocity field of the solution
(`shoal.analysis.beach_standing_wave`), so there is no start-up transient. Over `--periods` periods the
shoreline (the tip of the water that still interacts with the body: a `runup` gauge with
`min_depth = dp` and `max_gap` the kernel support 2h), read from its still-water reading at t = 0 as a
laboratory gauge is zeroed, is compared with the theory: it rises and falls between +A and -A about
the still level, which the nonlinear solution of Carrier & Greenspan keeps below breaking (breaking
parameter epsilon = A omega^2 / (g s^2) < 1). A wave gauge checks the wave the paddle
keeps up against A J0(sigma) sin(omega t) offshore.

    python benchmarks/carrier_greenspan.py --cot 10 --ddp 20 --breaking 0.5 --sigma 3
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

import numpy as np

from shoal.analysis.beach_standing_wave import BeachStandingWave
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.cases.wave_flume import WAVE_OPTIONS
from shoal.geometry.shapes import Box, Slope, Tank
from shoal.motions import TimeSeriesMotion
from shoal.options import SPHOptions
from shoal.probes import RunupGauge, WaveGauge, make_recorder
from shoal.runner import build_model
from shoal.simulation import Simulation, TimeInterval


def flume(d, cot, dp, wave, options, end_time, folder):
    """The case: the paddle's displacement is written to `folder` as a time series (from one period
    before t = 0, so that the spline's clamped start does not touch the run)."""
    s = 1.0 / cot
    shore = d * cot
    stroke = wave.paddle_stroke(shore)
    T = wave.period
    t = np.arange(-T, end_time + T, T / 400)
    path = Path(folder) / "paddle.txt"
    np.savetxt(path, np.column_stack([t, stroke * np.sin(wave.omega * t)]), header="t [s], x [m]")
    top = d + 3 * wave.amplitude + 4 * dp
    x_end = top * cot
    x_back = -6 * dp
    solids = [Solid(name="paddle", shape=Box(lo=(-4 * dp, 0.0, 0.0), hi=(0.0, 0.0, top)), motion="paddle"),
              Solid(name="beach", shape=Slope(x0=0.0, z0=0.0, gradient=s)),
              Solid(name="flume", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(x_end, 0.0, top)))]
    # offshore, where the surface moves: J0's first extremum sigma = 3.83 when the paddle is beyond it
    # (X = 0.5 L with sigma_L = 5.4), else halfway to the paddle in sigma (X = L / 4)
    sigma_L = float(wave.sigma(shore))
    sigma_g = 3.8317 if sigma_L > 4.3 else 0.5 * sigma_L
    gauges = {"offshore": (sigma_g / (2 * wave.omega)) ** 2 * wave.g * s}
    interval = T / 200
    probes = [WaveGauge(name=n, x=shore - X, z0=0.0, z1=top, interval=interval) for n, X in gauges.items()]
    lo = shore - 3 * wave.amplitude * cot
    # the tip of the water that still interacts with the body: any particle (min_depth = dp), dry
    # stretches up to the kernel support 2h bridged
    support = 2 * options.coef_h * math.sqrt(2) * dp
    probes += [RunupGauge(name="tip", x0=lo, x1=x_end, min_depth=dp, max_gap=support, interval=interval)]
    case = Case(name="carrier-greenspan", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=d, surface_level=d),
                options=options, solids=solids, fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(x_end, 0, d)))],
                motions=[TimeSeriesMotion(name="paddle", file=str(path))], probes=probes,
                output=Output(interval=end_time))
    return case, gauges


def start_from_solution(model, wave, shore):
    """Give the fluid particles the wave's velocity at t = 0 (u, and w that keeps the flow on the bed)."""
    fluid = model.kind[:model.n] == 0
    p = model.world_positions()[fluid]
    X = shore - p[:, 0]
    height = np.maximum(p[:, 2] - wave.slope * p[:, 0], 0.0)
    u = wave.velocity(X, 0.0)
    w = wave.vertical_velocity(X, height, 0.0)
    vel = model.vel[:model.n]
    vel[fluid, 0] = u
    vel[fluid, 1] = w


def periods_excursion(t, z, T, t0=0.0):
    """Per whole period from t0: (highest, lowest) of z."""
    out = []
    k = 0
    while t0 + (k + 1) * T <= t[-1] + 1e-9:
        m = (t >= t0 + k * T) & (t < t0 + (k + 1) * T) & np.isfinite(z)
        if m.sum() > 10:
            out.append((float(np.max(z[m])), float(np.min(z[m]))))
        k += 1
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d", type=float, default=0.1, help="still-water depth at the paddle [m]")
    ap.add_argument("--cot", type=float, default=10.0, help="beach slope 1:cot")
    ap.add_argument("--ddp", type=float, default=20.0, help="d / dp")
    ap.add_argument("--breaking", type=float, default=0.5, help="epsilon = A omega^2 / (g s^2), < 1")
    ap.add_argument("--sigma", type=float, default=3.0,
                    help="sigma_L at the paddle (k d = sigma_L / (2 cot); away from 3.83 and 7.02)")
    ap.add_argument("--periods", type=float, default=3.0)
    ap.add_argument("--options", default="{}", help="JSON of SPHOptions over the wave flumes' scheme")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args(argv)
    d, dp, s = a.d, a.d / a.ddp, 1.0 / a.cot
    wave = BeachStandingWave.for_flume(d, s, a.sigma, a.breaking)
    opts = SPHOptions(**{**WAVE_OPTIONS[2], **json.loads(a.options)})
    T = wave.period
    end = a.periods * T
    shore = d * a.cot
    with tempfile.TemporaryDirectory() as tmp:
        case, gauges = flume(d, a.cot, dp, wave, opts, end, tmp)
        print(f"Carrier-Greenspan standing wave on 1:{a.cot:g}: d = {d} m, d/dp = {a.ddp:g}, A = {wave.amplitude:.5f} m "
              f"= {wave.amplitude / dp:.2f} dp (A/d = {wave.amplitude / d:.4f}), T = {T:.4f} s, kd = {a.sigma * s / 2:.3f}, "
              f"epsilon = {wave.breaking:.3f}, paddle stroke {wave.paddle_stroke(shore) * 1e3:.2f} mm; "
              f"{case.n_particles:,} particles, {a.periods:g} periods; options {a.options}", flush=True)
        t0 = time.perf_counter()
        model = build_model(case)
        start_from_solution(model, wave, shore)
        sim = Simulation(model, end)
        recs = [make_recorder(p, tmp, dp, model) for p in case.probes]
        for r in recs:
            sim.add_callback(r, TimeInterval(r.spec.interval), name=r.spec.name)
        sim.run()
        for r in recs:
            r.close()
        wall = time.perf_counter() - t0
        shore_rec = np.array(recs[-1].rows, float)
        gauge_recs = {r.spec.name: np.array(r.rows, float) for r in recs[:-1]}
    t, zs = shore_rec[:, 0], shore_rec[:, 1] - d
    z0 = zs[0]
    zs = zs - z0  # from the gauge's still-water reading
    per = periods_excursion(t, zs, T)
    A = wave.amplitude
    ups = [hi / A for hi, _ in per]
    downs = [lo / A for _, lo in per]
    exc = [(hi - lo) / (2 * A) for hi, lo in per]
    theory = wave.shoreline(t)
    ok = np.isfinite(zs)
    rms = float(np.sqrt(np.mean((zs[ok] - theory[ok]) ** 2)) / A)
    res = dict(cot=a.cot, ddp=a.ddp, d=d, breaking=wave.breaking, sigma_L=a.sigma, amplitude=A, period=T,
               amplitude_dp=A / dp, options=json.loads(a.options), particles=case.n_particles, wall_seconds=wall,
               shoreline_at_rest=z0 / A, runup=ups, rundown=downs, excursion=exc,
               shoreline_rms=rms, steps=sim.step_count,
               series=dict(t=t.tolist(), shoreline=(zs / A).tolist(), theory=(theory / A).tolist()))
    print(f"  shoreline at t = 0: {z0 / A:+.3f} A below the still level (the gauge's zero); per period, highest / lowest "
          f"over A (theory +1 / -1), "
          f"half the excursion over A (theory 1):")
    for k, (u, dn, e) in enumerate(zip(ups, downs, exc)):
        print(f"    period {k + 1}: {u:+.3f} / {dn:+.3f}   excursion {e:.3f} ({e - 1:+.1%})")
    print(f"  shoreline rms against A sin(omega t): {rms:.3f} A")
    for name, X in gauges.items():
        g = gauge_recs[name]
        eta = g[:, 1] - d
        amp_theory = abs(float(wave.elevation(X, T / 4)))  # A |J0(sigma)|
        per_g = periods_excursion(g[:, 0], eta, T)
        amps = [(hi - lo) / 2 / amp_theory for hi, lo in per_g]
        res[f"gauge_{name}"] = amps
        res["series"][f"gauge_{name}"] = (eta / amp_theory).tolist()
        print(f"  wave gauge at X = {X:.3f} m: amplitude over theory's {amp_theory * 1e3:.2f} mm: "
              + ", ".join(f"{v:.3f}" for v in amps))
    print(f"  {sim.step_count} steps, {wall:.0f} s", flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
