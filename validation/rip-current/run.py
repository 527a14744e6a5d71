"""The rip-current validation run of issue 6, item 5 (a documented run, not a CI test).

Reproduces the run analysed in ``README.md``: the built-in ``rip-current`` case (the
Drønen et al. 2002 bar / rip-channel basin of the GPUSPH rip-current paper, H = 0.19 m, T = 1.5 s,
0.15 m of water over the bar crest) at a CPU resolution (dp = 0.05 m, three particles over the crest;
about 2.5 h on two cores), to t = 16.5 s (11 periods: the paper averages one period after at least 10),
with the changes listed below, a test-point grid over the bar, the channel and the trough, and wave gauges.

    PYTHONPATH=src nohup python validation/rip-current/run.py --out runs/rip-0.05 > runs/rip-0.05.out 2>&1 &
    PYTHONPATH=src python validation/rip-current/analyse.py runs/rip-0.05

A run stopped by SIGTERM/SIGINT (or a crash) continues with
``PYTHONPATH=src python -m shoal run --resume runs/rip-0.05`` (the test points held in memory
are in the checkpoints); ``--end-time`` extends a finished run. The coarse run of 2026-12-02 is
``--dp 0.075 --end-time 22.5`` (analysed with ``--periods 5``).

Changes from the built-in case, each for the cost of a CPU run (see README.md):

* dp = 0.05 m (three particles over the bar crest; 0.075 m, two, is the coarsest the case accepts,
  and there the set-up over the bar is not resolved: README.md);
* the paddle stands at x = 4.5 m instead of 0 (1.5 m = 2.9 depths = 0.53 wavelength of flat bed
  before the 1/27 slope instead of 6 m): the bar, channel and beach are unchanged, in the case's
  coordinates (crest at x = 12.4 m, so 7.9 m from the paddle instead of 12.4 m);
* the basin's end wall at x = 21.0 m instead of 23.1 m (the beach then ends 0.18 m above still
  water instead of 0.3 m; the shoreline is at 17.9 m);
* options: the case's (the paper's scheme: Wendland, Shepard every 20 steps, SPS, no density
  diffusion, symplectic, float32) with the changes of `OPTION_CHANGES` (c0, alpha, free-slip
  walls, Verlet, no SPS).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import shoal
from shoal.case import Case, FluidRegion, Solid
from shoal.cases.rip_current import PAPER_OPTIONS, rip_current
from shoal.geometry.shapes import Box, Tank
from shoal.probes import TestPoints, WaveGauge

DP = 0.05             # particle spacing [m]
PADDLE_X = 4.5        # paddle rest position [m] (case default 0: 6 m of flat bed)
BASIN_END = 21.0      # end wall of the basin [m] (case default 23.1: where the beach reaches the wall top)
PERIOD = 1.5          # wave period [s]
END_TIME = 16.5       # 11 periods (averaging over the last one, after 10 periods, as the paper)
OUTPUT_INTERVAL = 1.5  # one snapshot a period
GRID_INTERVAL = PERIOD / 10
GAUGE_INTERVAL = PERIOD / 30
CREST_X = 12.4

OPTION_CHANGES = dict(
    # c0 = 10 sqrt(g H) = 22.5 m/s instead of 20 sqrt(g H): still more than 10 times the largest
    # velocity (breaking crests about 2 m/s; the paper's criterion, its Eq. 7-8 text), and it halves
    # the number of steps (the time step is acoustic).
    coef_sound=10.0,
    # The paper has no artificial viscosity (its Pi_ij is the SPS term); the case's alpha = 0.1 is a
    # stand-in whose viscosity alpha h c0 / 10 grows with dp: at dp = 0.075 m it would be
    # 0.029 m^2/s and damp the waves long before the bar. alpha = 0.01 as in the wave-flume validation.
    alpha=0.01,
    # Free-slip walls for the viscous term: the kernel support 2h = 0.26 m is deeper than the water
    # over the crest (0.15 m), so a no-slip artificial viscosity would act as a bed friction on the
    # whole water column; and the side walls stand for lines of symmetry of a periodic bar/rip system.
    visco_bound_factor=0.0,
    # one force evaluation per step (DualSPHysics's default for wave cases; Euler step every 40)
    # instead of the symplectic scheme's two; no density diffusion, so Verlet's caveat does not apply
    integrator="verlet",
    # the SPS eddy viscosity (Cs dp)^2 |S| is about 4e-4 m^2/s here, an order of magnitude below the
    # artificial viscosity kept (alpha h c0 / 10 = 2.9e-3 m^2/s): it costs a pass and changes nothing
    turbulence="none",
)
OPTIONS = dict(PAPER_OPTIONS, **OPTION_CHANGES)

# where the set-up is compared: along the crest line, over the middle of the bar and of the channel
GAUGES = {  # name: (x, y)
    "offshore": (5.5, 2.0),          # 1 m from the paddle, on the flat bed: the incident wave
    "toe_bar": (9.0, 2.5), "toe_channel": (9.0, 0.5),        # bar's offshore toe (x_off = 8.89 m)
    "crest_bar": (CREST_X, 2.5), "crest_channel": (CREST_X, 0.5),
    "trough_bar": (14.0, 2.5), "trough_channel": (14.0, 0.5),  # shoreward of the bar
    "inshore_bar": (16.0, 2.5), "inshore_channel": (16.0, 0.5),
}


def bed_level(x, y):
    """Bed elevation [m] of the basin at (x, y): bilinear in the case's `rip_current_bed` grid."""
    from shoal.cases.rip_current import rip_current_bed

    grid = rip_current_bed()[0]
    xs, ys, z = np.asarray(grid.x), np.asarray(grid.y), np.asarray(grid.z)
    col = np.array([np.interp(x, xs, z[:, j]) for j in range(len(ys))])
    return float(np.interp(y, ys, col))


def probes(dp=DP, swl=None):
    """The test-point grid and the wave gauges."""
    swl = 0.5170 if swl is None else swl
    # plan view x = 8.0 .. 18.0 m (bar toe to beyond the shoreline at x = 17.9 m), y one node spacing
    # from each side wall, z from just above the channel bed at the bar toe to above the wave crests;
    # about 2 dp apart in plan, dp in the vertical (uniform: the depth average needs it)
    dxy = 2 * dp
    x0, x1 = 8.0, 18.0
    nx = int(round((x1 - x0) / dxy)) + 1
    y0, y1 = dxy, 4.0 - dxy
    ny = int(round((y1 - y0) / dxy)) + 1
    z0, z1 = 0.08, swl + 0.24
    nz = int(round((z1 - z0) / dp)) + 1
    grid = TestPoints(name="bar", lo=(x0, y0, z0), hi=(x1, y1, z1), counts=(nx, ny, nz),
                      interval=GRID_INTERVAL)
    gauges = []
    for name, (x, y) in GAUGES.items():
        zb = bed_level(x, y)
        gauges.append(WaveGauge(name=name, x=x, y=y, z0=round(zb + dp, 4), z1=round(swl + 0.3, 4),
                                interval=GAUGE_INTERVAL))
    return [grid, *gauges]


def make_case(dp=DP, paddle_x=PADDLE_X, end_time=END_TIME, output_interval=OUTPUT_INTERVAL, basin_end=BASIN_END):
    """The run's Case: the built-in case with the paddle moved to `paddle_x`, the basin's end wall
    at `basin_end`, the options of `OPTIONS`, and the probes."""
    base = rip_current(dp=dp, end_time=end_time, output_interval=output_interval,
                       options=shoal.SPHOptions(**OPTIONS))
    solids = []
    for s in base.solids:
        sh = s.shape
        if s.name == "paddle":
            sh = Box(lo=(sh.lo[0] + paddle_x, sh.lo[1], sh.lo[2]), hi=(sh.hi[0] + paddle_x, sh.hi[1], sh.hi[2]))
        elif s.name == "basin":
            sh = Tank(lo=(sh.lo[0] + paddle_x, sh.lo[1], sh.lo[2]), hi=(min(sh.hi[0], basin_end), sh.hi[1], sh.hi[2]),
                      open=list(sh.open))
        solids.append(Solid(name=s.name, shape=sh, boundary=s.boundary, layers=s.layers, motion=s.motion))
    (fl,) = base.fluids
    hi = (min(fl.shape.hi[0], basin_end), fl.shape.hi[1], fl.shape.hi[2])
    fluids = [FluidRegion(shape=Box(lo=(paddle_x, fl.shape.lo[1], fl.shape.lo[2]), hi=hi),
                          velocity=fl.velocity)]
    swl = base.parameters["still_water_level"]
    params = dict(base.parameters, paddle_x=paddle_x, basin_end=basin_end, option_changes=str(OPTION_CHANGES))
    fields = {k: getattr(base, k) for k in Case.model_fields}
    fields.update(solids=solids, fluids=fluids, probes=probes(dp, swl), parameters=params,
                  description=base.description + f"; paddle at x = {paddle_x:g} m (validation run)")
    return Case(**fields)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True, help="run directory (outside the repository)")
    ap.add_argument("--dp", type=float, default=DP)
    ap.add_argument("--paddle-x", type=float, default=PADDLE_X)
    ap.add_argument("--end-time", type=float, default=END_TIME)
    ap.add_argument("--basin-end", type=float, default=BASIN_END)
    ap.add_argument("--max-steps", type=int, default=None, help="stop after N steps (timing)")
    ap.add_argument("--check", action="store_true", help="print the counts and time step, do not run")
    ap.add_argument("--overwrite", action="store_true")
    ap.add_argument("--backend", default="cpu", help="cpu (default) or cuda (dp = 0.03-0.04 m: a GPU run, "
                                                     "`benchmarks/device/check.sh rip`)")
    a = ap.parse_args(argv)
    case = make_case(a.dp, a.paddle_x, a.end_time, basin_end=a.basin_end)
    if a.check:
        from shoal.check import check_case

        print("\n".join(check_case(case)))
        return 0
    res = shoal.run_case(case, a.out, backend=a.backend, progress=False, plot=True, max_steps=a.max_steps,
                         overwrite=a.overwrite)
    print(f"done: {res.steps} steps to t = {res.time:.4g} s, {res.particles} particles, "
          f"{res.wall_seconds:.0f} s wall ({res.compile_seconds:.0f} s compile), "
          f"{res.particle_steps_per_second:.3g} particle-steps/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
