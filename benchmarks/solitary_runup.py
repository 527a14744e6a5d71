"""Run-up of a solitary wave on a plane beach against the shallow-water theory (issue 28, item 2).

A 2D flume of still-water depth d: a `solitary` piston (Goring 1978) at x = 0 pushes out one solitary
wave of height H; it runs over 20 d of flat bed, then up a plane beach of slope 1:cot from x = 20 d.
Wave gauges at x = 2 d and x = 17 d measure the wave's height (the largest elevation as it passes) and
so what the flume keeps of it over 15 depths; run-up gauges over the beach record the shoreline's
highest elevation: the highest fluid particle (`type = "runup"`), the wet shoreline where the water
layer is at least one spacing thick (`min_depth = dp`), and the tip of the tongue (`min_depth = dp`,
`max_gap = 2h`), read from its still-water value at t = 0 as a laboratory gauge is zeroed.

Reference: the run-up law of the non-breaking solitary wave from the linear shallow-water equations
(Synolakis 1987, J. Fluid Mech. 185, 523-545, Eq. 32; `validation-data` section 5),

    R / d = 2.831 sqrt(cot beta) (H / d)^(5/4),

valid for waves that do not break on the way up, H/d < 0.818 (tan beta)^(10/9) (Synolakis 1987): 0.029
on 1:20, 0.063 on 1:10.

    python benchmarks/solitary_runup.py --cot 10 --H 0.05 --ddp 20
    python benchmarks/solitary_runup.py --cot 10 --H 0.05 --ddp 20 --options '{"riemann": true}'
    python benchmarks/solitary_runup.py --ddp 5 --end 0.1     # a smoke test: seconds, no run-up yet
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

import numpy as np

import shoal
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.cases.wave_flume import WAVE_OPTIONS
from shoal.geometry.shapes import Box, Slope, Tank
from shoal.motions import SolitaryPiston
from shoal.options import SPHOptions
from shoal.probes import RunupGauge, WaveGauge


def runup_law(H, cot):
    """R / d of Synolakis (1987) for a solitary wave of H / d on a beach of slope 1:cot."""
    return 2.831 * math.sqrt(cot) * H**1.25


def breaks(H, cot):
    """True where Synolakis's non-breaking criterion H/d < 0.818 (tan beta)^(10/9) fails."""
    return H >= 0.818 * (1.0 / cot) ** (10.0 / 9.0)


def flume(d, H, cot, dp, options, end_time, fit_surface=False):
    paddle = SolitaryPiston(name="paddle", height=H * d, depth=d)
    x_toe = 20 * d
    R = runup_law(H, cot) * d
    top = d + max(3 * R, 0.3 * d)
    x_end = x_toe + top * cot
    x_back = -4 * dp - 2 * dp
    solids = [Solid(name="paddle", shape=Box(lo=(-4 * dp, 0.0, 0.0), hi=(0.0, 0.0, top)), motion="paddle"),
              Solid(name="beach", shape=Slope(x0=x_toe, z0=0.0, gradient=1.0 / cot), fit_surface=fit_surface),
              Solid(name="flume", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(x_end, 0.0, top)))]
    shore = x_toe + d * cot
    probes = [WaveGauge(name=f"x{k}d", x=k * d, z0=0.5 * d, z1=top, interval=0.005) for k in (2, 17)]
    support = 2 * options.coef_h * math.sqrt(2) * dp
    probes += [RunupGauge(name="top", x0=shore - 2 * d * cot * H, x1=x_end, interval=0.005),
               RunupGauge(name="wet", x0=x_toe, x1=x_end, min_depth=dp, interval=0.005),
               RunupGauge(name="tip", x0=x_toe, x1=x_end, min_depth=dp, max_gap=support, interval=0.005)]
    return Case(name="solitary-runup", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=d, surface_level=d),
                options=options, solids=solids, fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(x_end, 0, d)))],
                motions=[paddle], probes=probes, output=Output(interval=end_time / 8)), R


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d", type=float, default=0.1, help="still-water depth [m]")
    ap.add_argument("--H", type=float, default=0.05, help="wave height over depth H/d")
    ap.add_argument("--cot", type=float, default=10.0, help="beach slope 1:cot")
    ap.add_argument("--ddp", type=float, default=20.0, help="d / dp")
    ap.add_argument("--wall", default="dynamic", choices=["dynamic", "adami", "mdbc"])
    ap.add_argument("--scheme", default="wave", choices=["wave", "default"],
                    help="the wave flumes' options (laminar, free-slip viscous walls, wide kernel) or the defaults")
    ap.add_argument("--options", default="{}", help='more SPHOptions as a JSON object, e.g. \'{"riemann": true}\'')
    ap.add_argument("--fit-surface", action="store_true", help="the beach's wall particles on layers parallel to it")
    ap.add_argument("--out", help="keep the run here (else a temporary folder)")
    ap.add_argument("--json", help="write the figures to this JSON file")
    ap.add_argument("--end", type=float, default=None,
                    help="end time [s] (default: the crest's travel to the shoreline and its climb, plus 1 s); "
                         "a short one is a smoke test, before the wave reaches the beach")
    a = ap.parse_args(argv)
    d, dp = a.d, a.d / a.ddp
    extra = json.loads(a.options)
    opts = SPHOptions(**({**WAVE_OPTIONS[2], "wall_pressure": a.wall, **extra} if a.scheme == "wave" else
                         {"wall_pressure": a.wall, **extra}))
    # the crest leaves the paddle at t0 = 3.8 / (k c) (`SolitaryPiston`), reaches the still-water shoreline
    # (x = 20 d + d cot) a travel time later, and climbs for a time of order cot^(1/2) (d/g)^(1/2) more
    paddle = SolitaryPiston(name="paddle", height=a.H * d, depth=d)
    t0 = 3.8 / (paddle.k * paddle.celerity)
    end = t0 + (20 * d + d * a.cot) / paddle.celerity + 3.0 * math.sqrt(d / 9.81) * a.cot ** 0.5 + 1.0
    end = end if a.end is None else a.end
    case, R = flume(d, a.H, a.cot, dp, opts, end, fit_surface=a.fit_surface)
    print(f"solitary wave H/d = {a.H:g} on 1:{a.cot:g} (breaks: {breaks(a.H, a.cot)}), d = {d} m, d/dp = {a.ddp:g}, "
          f"{case.n_particles:,} particles, to t = {end:.2f} s; scheme {a.scheme}, walls {a.wall}, options {extra}, fit_surface {a.fit_surface}",
          flush=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(a.out) if a.out else Path(tmp)
        shoal.run_case(case, out, progress=False, plot=False, overwrite=True)
        g2 = np.loadtxt(out / "gauge_x2d.csv", delimiter=",", skiprows=1)
        g17 = np.loadtxt(out / "gauge_x17d.csv", delimiter=",", skiprows=1)
        top = np.loadtxt(out / "runup_top.csv", delimiter=",", skiprows=1)
        wet = np.loadtxt(out / "runup_wet.csv", delimiter=",", skiprows=1)
        tip = np.loadtxt(out / "runup_tip.csv", delimiter=",", skiprows=1)
    H2, H17 = (np.nanmax(g[:, 1]) - d for g in (g2, g17))
    r_top = np.nanmax(top[:, 1]) - d
    r_wet = np.nanmax(wet[:, 1]) - d
    r_tip = np.nanmax(tip[:, 1]) - tip[0, 1]  # from the gauge's still-water reading
    res = dict(H=a.H, cot=a.cot, ddp=a.ddp, wall=a.wall, scheme=a.scheme, options=extra, fit_surface=a.fit_surface, particles=case.n_particles,
               wall_seconds=time.perf_counter() - t0, H_2d=H2 / d, H_17d=H17 / d, height_kept=H17 / H2,
               runup_theory=R / d, runup_top=r_top / d, runup_wet=r_wet / d, runup_tip=r_tip / d,
               tip_zero=(tip[0, 1] - d) / d)
    print(f"  wave height at x = 2 d: {H2 / d:.4f} d (target {a.H:g} d); at 17 d: {H17 / d:.4f} d; kept "
          f"{100 * H17 / H2:.1f} % over 15 depths")
    print(f"  run-up: theory {R / d:.4f} d; highest particle centre {r_top / d:.4f} d ({r_top / R - 1:+.1%}); "
          f"wet shoreline (layer >= dp) {r_wet / d:.4f} d ({r_wet / R - 1:+.1%}); tongue's tip (max_gap 2h), from "
          f"its still-water reading {(tip[0, 1] - d) / d:+.4f} d: {r_tip / d:.4f} d ({r_tip / R - 1:+.1%}); "
          f"{res['wall_seconds']:.0f} s",
          flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
