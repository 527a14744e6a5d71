"""The breaking tidal bore in a longer 2D flume: is its settled front within 3 % of Belanger?

Runs the x-z section of `tidal-bore` (d0 = 0.1 m, U = 0.7 m/s: Belanger c = 0.873 m/s, d1 = 0.180 m,
Fr = 1.59) with the paper's scheme and alpha = 0.02 (the scheme under which the 2D front breaks;
`tests/test_tidal_bore.py::LOW_ALPHA`) in a flume `--length` metres long, with wave gauges every 0.5 m
(`--gauge-every`), and prints

- the front's arrival at each gauge (the level half-way between d0 and d1) and its speed over each span;
- the least-squares celerity over all gauges and over the gauges from `--settled` metres on (the front
  forms over the first half metre: at d0/20 it runs 24 % fast there while it breaks);
- the level behind the front at each gauge (`shoal.analysis.level_behind`, to the end of the record);
- the clear-water depth behind the front at each gauge: the water's volume within +-`--window` m of it
  per metre (`shoal.analysis.volume_depth`), averaged over the snapshots from 0.15 s after the arrival
  (a gauge in the broken water behind a breaking front reads 1-4 mm below it at d0/20);
- the kinematic breaking index B = max u_crest / c every `--snap` s (`shoal.analysis.crest_speed_ratio`;
  B >= 1: the crest's water overtakes the front, it breaks);
- the front's position in every snapshot: where the clear-water depth profile (bins of `--bin` m) falls
  through the half-way level (`shoal.analysis.front_position`), and the celerity fitted to that track
  from `--settled` m to the last gauge (and from the first gauge): many more points than the gauges'
  arrivals, which a breaking front, pulsating with its roller, passes at different phases;
- the inflow's speed in the lowest 2 cm between the front and the inflow wall every `--snap` s (a bed
  that drags the stream slows it below U; with DBC walls at d0/20 it fell to 0.28 m/s by t = 2.5 s).

The moving inflow wall meets the bore at t = L / (U + c) (3.18 s in a 5 m flume, at x = 2.78 m), so the
run ends at `--t-end` (default 0.95 L / (U + c)) and gauges beyond the meeting point are dropped.

    python benchmarks/breaking_bore.py --dp 0.01 --length 5      # d0/10, about 5 min on 2 threads
    python benchmarks/breaking_bore.py --dp 0.005 --length 5     # d0/20, 51 min on 2 threads
    python benchmarks/breaking_bore.py --dp 0.02 --length 1 --t-end 0.35 --gauge-every 0.1 --settled 0.1
                                                                  # a smoke test: seconds

Writes the measures as JSON to stdout (and to `--json FILE`).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def near_bed_inflow(pos, vel, t, c, U, length, depth=0.02, gap=0.3):
    """Mean speed towards the gate [m/s] of the fluid within `depth` of the bed, between `gap` m ahead of
    the bore's nominal front (x = c t) and `gap` m behind the inflow wall (x = L - U t); nan when that
    stretch is empty. Frictionless water keeps U there: a lower speed is the bed dragging the inflow."""
    sel = (pos[:, -1] < depth) & (pos[:, 0] > c * t + gap) & (pos[:, 0] < length - U * t - gap)
    return float(-np.mean(vel[sel, 0])) if sel.any() else float("nan")


def main(argv=None):
    import shoal
    from shoal.analysis import (arrival_time, bore_from_inflow, celerity, crest_speed_ratio, front_position,
                                level_behind, volume_depth)
    from shoal.cases import tidal_bore
    from shoal.cases.tidal_bore import PAPER_OPTIONS
    from shoal.errors import InputError
    from shoal.options import SPHOptions
    from shoal.output.pvd import read_pvd
    from shoal.output.vtu import read_vtu
    from shoal.physics.spec import FLUID

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dp", type=float, default=0.01, help="particle spacing [m] (d0/10 = 0.01, d0/20 = 0.005)")
    p.add_argument("--U", type=float, default=0.7, help="inflow speed [m/s]")
    p.add_argument("--length", type=float, default=5.0, help="flume length [m]")
    p.add_argument("--alpha", type=float, default=0.02, help="artificial viscosity coefficient")
    p.add_argument("--options", type=json.loads, default={},
                   help='other SPHOptions as JSON over the paper scheme, e.g. \'{"mls_every": 0}\'')
    p.add_argument("--settled", type=float, default=1.0, help="celerity from gauges at x >= this [m]")
    p.add_argument("--gauge-every", type=float, default=0.5,
                   help="wave gauges every this many metres from the gate [m] (0.5; a smoke test's short run "
                        "takes 0.1 with --length 1 --t-end 0.35)")
    p.add_argument("--t-end", type=float, default=None, help="end time [s] (default 0.95 L / (U + c))")
    p.add_argument("--snap", type=float, default=0.1, help="snapshot interval for the breaking index and the "
                   "volume depth [s]")
    p.add_argument("--window", type=float, default=0.05, help="half-length of the volume-depth window [m]")
    p.add_argument("--bin", type=float, default=0.05, help="bin length of the depth profile that tracks the "
                   "front [m]")
    p.add_argument("--json", type=Path, default=None, help="also write the measures here")
    p.add_argument("--keep", type=Path, default=None, help="run directory to keep (default: a temporary one)")
    p.add_argument("--reuse", action="store_true", help="measure the finished run in --keep again, without running")
    a = p.parse_args(argv)
    d0 = 0.1
    if not a.gauge_every > 0:
        raise InputError(f"--gauge-every {a.gauge_every:g}: must be a positive distance [m]")
    c_ref, d1, fr = bore_from_inflow(a.U, d0)
    t_meet = a.length / (a.U + c_ref)
    t_end = a.t_end if a.t_end is not None else 0.95 * t_meet
    x_meet = c_ref * t_end
    gauges = [float(x) for x in np.round(np.arange(a.gauge_every, a.length, a.gauge_every), 6) if x < x_meet - 0.1]
    if len(gauges) < 2:
        raise InputError(f"a {a.length:g} m flume to t = {t_end:g} s leaves fewer than two gauges; lengthen it")
    opts = SPHOptions(**dict(PAPER_OPTIONS, alpha=a.alpha, **a.options))
    case = tidal_bore(dp=a.dp, inflow_speed=a.U, dim=2, end_time=t_end, output_interval=a.snap, options=opts,
                      length=a.length, gauges_x=gauges)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        run_dir = a.keep or Path(tmp) / "run"
        if a.reuse:
            if a.keep is None or not (a.keep / "run.log").is_file():
                raise InputError("--reuse needs --keep DIR holding a finished run")
            res = None
        else:
            res = shoal.run_case(case, run_dir, plot=False, handle_signals=False)
        thr = d0 + 0.5 * (d1 - d0)
        arrivals, levels = [], []
        for x in gauges:
            data = np.loadtxt(run_dir / f"gauge_x{x:g}.csv", delimiter=",", skiprows=1, ndmin=2)
            t, z = data[:, 0], data[:, 1]
            ta = arrival_time(t, z, thr)
            arrivals.append(ta)
            try:
                levels.append(level_behind(t, z, ta) if np.isfinite(ta) else float("nan"))
            except InputError:
                levels.append(float("nan"))
        index, inflow, fronts, snap_t, x_ends = [], [], [], [], []
        vols = [[] for _ in gauges]
        mass = case.fluid.rho0 * a.dp**2
        for ts_k, name in read_pvd(run_dir / "tidal-bore.pvd"):  # (time, file) of each snapshot
            pts, data = read_vtu(run_dir / name)
            snap_t.append(ts_k)
            x_ends.append(a.length - a.U * ts_k - 0.3)  # the depth profile stops 0.3 m before the inflow wall
            fluid = data["kind"] == FLUID
            index.append(crest_speed_ratio(pts[fluid], data["velocity"][fluid], d0, d1, c_ref))
            inflow.append(near_bed_inflow(pts[fluid], data["velocity"][fluid], ts_k, c_ref, a.U, a.length))
            fronts.append(front_position(pts[fluid], data["density"][fluid], mass, thr, x_ends[-1], a.bin))
            for g, (x, ta) in enumerate(zip(gauges, arrivals)):
                if np.isfinite(ta) and ts_k >= ta + 0.15 - 1e-9:
                    vols[g].append(volume_depth(pts[fluid], data["density"][fluid], mass, x, a.window))
    wall = time.perf_counter() - t0
    xs, ts = np.array(gauges), np.array(arrivals)
    spans = [dict(x0=float(xs[i]), x1=float(xs[i + 1]), speed=float((xs[i + 1] - xs[i]) / (ts[i + 1] - ts[i])),
                  error=float((xs[i + 1] - xs[i]) / (ts[i + 1] - ts[i]) / c_ref - 1)) for i in range(len(xs) - 1)]
    settled = xs >= a.settled - 1e-9
    c_all = celerity(xs, ts)
    c_set = celerity(xs[settled], ts[settled]) if settled.sum() >= 2 else float("nan")
    tf, xf = np.array(snap_t), np.array(fronts)
    # up to a quarter metre past the last gauge; a front within two bins of the profile's end is the end
    found = np.isfinite(xf) & (xf <= xs[-1] + 0.25) & (xf < np.array(x_ends) - 2 * a.bin)
    track = found & (xf >= a.settled - 1e-9)
    c_track = celerity(xf[track], tf[track]) if track.sum() >= 2 else float("nan")
    track_all = found & (xf >= xs[0] - 1e-9)
    c_track_all = celerity(xf[track_all], tf[track_all]) if track_all.sum() >= 2 else float("nan")
    lev = {f"{x:g}": (float(v), float(v / d1 - 1)) for x, v in zip(xs, levels)}
    # at least three snapshots (0.2 s of the water behind the front), as level_behind wants 0.05 s of record
    vdep = {f"{x:g}": (float(np.mean(v)), float(np.mean(v) / d1 - 1), len(v)) if len(v) >= 3
            else (float("nan"), float("nan"), len(v)) for x, v in zip(xs, vols)}
    snap_t = [round(t, 4) for t in snap_t]
    first_break = next((t for t, b in zip(snap_t, index) if b >= 1.0), None)
    out = dict(dp=a.dp, U=a.U, length=a.length, alpha=a.alpha, options=a.options, t_end=t_end, particles=int(res.particles) if res else None,
               escaped=int(res.escaped) if res else None, steps=int(res.steps) if res else None,
               wall_s=round(wall) if res else None,
               belanger=dict(c=c_ref, d1=d1, froude=fr), gauges=list(map(float, xs)),
               arrivals=list(map(float, ts)), spans=spans, celerity_all=c_all, celerity_all_error=c_all / c_ref - 1,
               celerity_settled=c_set, celerity_settled_error=c_set / c_ref - 1, settled_from=a.settled,
               level_behind=lev, depth_behind=vdep, depth_window=a.window, breaking_index=dict(times=snap_t, B=[float(b) for b in index],
                                                     max=float(max(index)) if index else None,
                                                     first_above_1=first_break),
               front_track=dict(times=snap_t, x=[round(float(v), 4) for v in xf], bin=a.bin,
                                celerity_settled=c_track, celerity_settled_error=c_track / c_ref - 1,
                                snapshots_settled=int(track.sum()), celerity_all=c_track_all,
                                celerity_all_error=c_track_all / c_ref - 1),
               inflow_near_bed=dict(times=snap_t, speed=[round(float(u), 4) for u in inflow]))
    text = json.dumps(out, indent=1)
    print(text)
    if a.json:
        a.json.write_text(text + "\n")
    return out


if __name__ == "__main__":
    from shoal.errors import InputError

    try:
        main()
    except InputError as err:
        print(f"breaking_bore.py: {err}", file=sys.stderr)
        sys.exit(2)
