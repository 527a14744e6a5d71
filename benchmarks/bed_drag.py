"""Does the bed drag a uniform stream? A free-slip flow over a flat bed, periodic in x.

Water d0 = 0.1 m deep flows at U = 0.7 m/s (the breaking bore's inflow) over a flat bed, in a
channel `--length` long and periodic in x, with the tidal-bore paper's scheme (cubic kernel,
predictor-corrector, XSPH 0.5, MLS filter every 30 steps, SPS, free-slip walls for the viscous term;
alpha = 0.02, the breaking bore's; `--options` to change). The theory is Galilean invariance: nothing should slow it
(a laminar boundary layer would be sqrt(nu t) = 1.4 mm thick after 2 s). Prints, every `--every`
seconds, the depth-mean speed, the speed of the lowest 2 cm, the spread of the near-bed velocities
and the lowest particle, for each bed:

- ``dynamic``: three layers of dynamic boundary particles (DBC, Crespo et al. 2007), each integrating
  its own continuity equation;
- ``adami``: the same particles with the pressure extrapolated from the fluid (Adami et al. 2012,
  `wall_pressure = "adami"`);
- ``mdbc``: the same particles with the density of the fluid at their ghost nodes (English et al.
  2022, `wall_pressure = "mdbc"`);
- ``plane``: a geometric wall plane (no particles; `shoal.physics.planes`).

    python benchmarks/bed_drag.py --dp 0.01                 # d0/10, about 30 s a bed on 2 threads
    python benchmarks/bed_drag.py --dp 0.005 --beds dynamic adami   # d0/20, about 2 min a bed

Writes the series as JSON to `--json FILE` too.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

G = 9.81


def stream_case(dp, bed, U=0.7, d0=0.1, length=0.4, t_end=2.0, options=None):
    """The periodic channel over a `bed` of "dynamic", "adami", "mdbc" or "plane"."""
    import shoal
    from shoal.case import Domain, WallPlane
    from shoal.cases.tidal_bore import PAPER_OPTIONS
    from shoal.geometry import Box

    opts = dict(PAPER_OPTIONS, alpha=0.02)
    opts.update(options or {})
    if bed in ("adami", "mdbc"):
        opts["wall_pressure"] = bed
    solids, planes = [], []
    if bed == "plane":
        planes = [WallPlane(point=(0, 0, 0), normal=(0, 0, 1))]
    else:
        solids = [shoal.Solid(name="bed", shape=Box(lo=(0, 0, -3 * dp), hi=(length, 0, 0)), layers=3)]
    return shoal.Case(
        name="stream", dim=2, dp=dp, end_time=t_end, description=f"uniform stream over a {bed} bed",
        fluid=shoal.Fluid(depth=d0, u_max=U + (G * d0) ** 0.5, surface_level=d0), options=opts,
        solids=solids, planes=planes,
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, d0)), velocity=(-U, 0, 0))],
        domain=Domain(lo=(0, 0, -3 * dp), hi=(length, 0, 0.4), periodic=["x"]))


def run(case, every, U):
    """Run `case`; the series (t, depth-mean u, near-bed u, near-bed sd of u and w, lowest z)."""
    import shoal
    from shoal.physics.spec import FLUID
    from shoal.runner import build_model

    model = build_model(case)
    sim = shoal.Simulation(model, end_time=case.end_time)
    rows = []

    def record(s):
        m = s.model
        fl = m.host(m.kind) == FLUID
        pos, vel = m.world_positions()[fl], m.world_velocities()[fl]
        u, w, z = -vel[:, 0], vel[:, -1], pos[:, -1]
        nb = z < 0.02
        rows.append(dict(t=round(s.time, 6), mean=float(u.mean()), near_bed=float(u[nb].mean()),
                         sd_u=float(u[nb].std()), sd_w=float(w[nb].std()), z_min=float(z.min())))

    sim.add_callback(record, shoal.TimeInterval(every))
    t0 = time.perf_counter()
    sim.run()
    return dict(series=rows, wall_s=round(time.perf_counter() - t0, 1), steps=sim.step_count,
                particles=int(model.n_total), escaped=int(model.n_escaped),
                loss_mean=1 - rows[-1]["mean"] / U, loss_near_bed=1 - rows[-1]["near_bed"] / U)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dp", type=float, default=0.01, help="particle spacing [m] (d0/10 = 0.01)")
    p.add_argument("--U", type=float, default=0.7, help="stream speed [m/s]")
    p.add_argument("--length", type=float, default=0.4, help="period along x [m]")
    p.add_argument("--t-end", type=float, default=2.0, help="end time [s]")
    p.add_argument("--every", type=float, default=0.25, help="sampling interval [s]")
    p.add_argument("--beds", nargs="+", default=["dynamic", "adami", "plane"], choices=["dynamic", "adami", "mdbc", "plane"])
    p.add_argument("--options", type=json.loads, default={}, help="SPHOptions over the scheme, as JSON")
    p.add_argument("--json", type=Path, default=None, help="also write the results here")
    a = p.parse_args(argv)
    out = dict(dp=a.dp, U=a.U, length=a.length, t_end=a.t_end, options=a.options, beds={})
    for bed in a.beds:
        r = run(stream_case(a.dp, bed, a.U, 0.1, a.length, a.t_end, a.options), a.every, a.U)
        out["beds"][bed] = r
        print(f"{bed} bed: {r['particles']} particles, {r['steps']} steps, {r['wall_s']} s")
        print("   t [s]  mean [m/s]  lowest 2 cm  sd u    sd w    lowest z [m]")
        for s in r["series"]:
            print(f"  {s['t']:5.2f}   {s['mean']:.4f}      {s['near_bed']:.4f}      {s['sd_u']:.4f}  "
                  f"{s['sd_w']:.4f}  {s['z_min']:.4f}")
        print(f"  speed lost by t = {a.t_end:g} s: depth-mean {100 * r['loss_mean']:.1f} %, "
              f"lowest 2 cm {100 * r['loss_near_bed']:.1f} %; escaped {r['escaped']}")
    if a.json:
        a.json.write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    try:
        main()
    except ValueError as err:
        print(f"bed_drag.py: {err}", file=sys.stderr)
        sys.exit(2)
