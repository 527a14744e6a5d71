"""Periodic run-up on a plane beach: the Carrier & Greenspan (1958) standing wave (issue 28, item 3).

The flume of `shoal validate periodic-runup` (`shoal.validation.periodic_runup`) at any slope,
resolution, breaking parameter and scheme: a 2D beach of slope 1:cot from a piston paddle at x = 0
(still-water depth d there). The flume starts at rest at the nonlinear solution's lowest rundown
(t = -T/4) and the paddle moves as the solution's water column at its face
(`shoal.analysis.beach_standing_wave`), so there is no start-up transient. Over `--periods` periods
from t = 0 the shoreline (the tip of the water that still interacts with the body: a `runup` gauge with
`min_depth = dp` and `max_gap` the kernel support 2h; its offset read at the start, where the shoreline
is at -A) is compared with the theory: it rises and falls between +A and -A about the still level, as
the nonlinear solution of Carrier & Greenspan keeps it below breaking (breaking parameter
epsilon = A omega^2 / (g s^2) < 1). A wave gauge checks the wave offshore against the nonlinear
solution's surface there.

    python benchmarks/carrier_greenspan.py --cot 10 --ddp 20 --breaking 0.5 --sigma 3
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from shoal.analysis.beach_standing_wave import BeachStandingWave
from shoal.cases.wave_flume import WAVE_OPTIONS
from shoal.options import SPHOptions
from shoal.validation.periodic_runup import excursions, run_periodic_runup


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d", type=float, default=0.1, help="still-water depth at the paddle [m]")
    ap.add_argument("--cot", type=float, default=10.0, help="beach slope 1:cot")
    ap.add_argument("--ddp", type=float, default=20.0, help="d / dp")
    ap.add_argument("--breaking", type=float, default=0.5, help="epsilon = A omega^2 / (g s^2), < 1")
    ap.add_argument("--sigma", type=float, default=3.0,
                    help="sigma_L at the paddle (k d = sigma_L / (2 cot); not 3.83, 7.02, ...: the closed basin's modes)")
    ap.add_argument("--periods", type=float, default=3.0)
    ap.add_argument("--options", default="{}", help="JSON of SPHOptions over the wave flumes' scheme")
    ap.add_argument("--lattice-beach", action="store_true",
                    help="the beach's wall particles on the lattice's staircase (default: fit_surface, layers parallel to it)")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args(argv)
    d, dp, s = a.d, a.d / a.ddp, 1.0 / a.cot
    wave = BeachStandingWave.for_flume(d, s, a.sigma, a.breaking)
    opts = SPHOptions(**{**WAVE_OPTIONS[2], **json.loads(a.options)})
    T, A = wave.period, wave.amplitude
    path = wave.column_path(d * a.cot, wave.rundown_time, wave.rundown_time + np.linspace(0.0, T, 401))
    stroke = 0.5 * (path.max() - path.min())
    print(f"Carrier-Greenspan standing wave on 1:{a.cot:g}: d = {d} m, d/dp = {a.ddp:g}, A = {A:.5f} m "
          f"= {A / dp:.2f} dp (A/d = {A / d:.4f}), T = {T:.4f} s, kd = {a.sigma * s / 2:.3f}, "
          f"epsilon = {wave.breaking:.3f}, paddle stroke {stroke * 1e3:.2f} mm (linear theory's "
          f"{wave.paddle_stroke(d * a.cot) * 1e3:.2f}); "
          f"{a.periods:g} periods; options {a.options}; fit_surface {not a.lattice_beach}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        r = run_periodic_runup(wave, d, a.cot, dp, opts, a.periods, Path(tmp), fit_surface=not a.lattice_beach)
    t, zs = r["t"], r["shoreline"]
    per = excursions(t, zs, T)
    ups, downs = [hi / A for hi, _ in per], [lo / A for _, lo in per]
    exc = [(hi - lo) / (2 * A) for hi, lo in per]
    theory = wave.nonlinear_shoreline(t)
    ok = np.isfinite(zs) & (t >= 0)
    rms = float(np.sqrt(np.mean((zs[ok] - theory[ok]) ** 2)) / A)
    tg, zg = r["offshore_t"], r["offshore"]
    eta_g = wave.nonlinear(r["X_offshore"], tg)[0]
    per_g, per_n = excursions(tg, zg, T), excursions(tg, eta_g, T)
    amps = [(hi - lo) / (hn - ln) for (hi, lo), (hn, ln) in zip(per_g, per_n)]
    on = tg >= 0
    rms_g = float(np.sqrt(np.nanmean((zg[on] - eta_g[on]) ** 2)) / (0.5 * (np.nanmax(eta_g) - np.nanmin(eta_g))))
    res = dict(cot=a.cot, ddp=a.ddp, d=d, fit_surface=not a.lattice_beach, breaking=wave.breaking, sigma_L=a.sigma,
               amplitude=A, period=T,
               amplitude_dp=A / dp, options=json.loads(a.options), particles=r["particles"],
               wall_seconds=r["seconds"], shoreline_zero=r["zero"] / A, runup=ups, rundown=downs, excursion=exc,
               shoreline_rms=rms, offshore_range=amps, offshore_rms=rms_g, steps=r["steps"],
               series=dict(t=t.tolist(), shoreline=(zs / A).tolist(), theory=(theory / A).tolist(),
                           offshore_t=tg.tolist(), offshore=(zg / A).tolist(), offshore_theory=(eta_g / A).tolist()))
    print(f"  {r['particles']:,} particles; started at rest at the rundown (t = -T/4); the gauge reads "
          f"{r['zero'] / A:+.3f} A from the true shoreline there; per period from t = 0, highest / lowest over A "
          "(theory +1 / -1), half the excursion over A (theory 1):")
    for k, (u, dn, e) in enumerate(zip(ups, downs, exc)):
        print(f"    period {k + 1}: {u:+.3f} / {dn:+.3f}   excursion {e:.3f} ({e - 1:+.1%})")
    print(f"  shoreline rms against the nonlinear solution's: {rms:.3f} A")
    print(f"  wave gauge at X = {r['X_offshore']:.3f} m: range per period over the nonlinear solution's: "
          + ", ".join(f"{v:.3f}" for v in amps) + f"; rms difference {rms_g:.3f} of its amplitude")
    print(f"  {r['steps']} steps, {r['seconds']:.0f} s", flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
