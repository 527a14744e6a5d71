"""Incident and reflected waves along the 2D wave flume, in sliding windows.

Runs `wave-flume-2d` (piston waves H = 0.05 m, T = 1.2 s, d = 0.4 m, the flume's scheme
`shoal.cases.wave_flume.WAVE_OPTIONS`) with a damping zone and gauges every 0.25 m from 0.5 m to
just before the zone, then separates the first harmonic at every gauge into an incident and a
reflected wave with a common spatial decay (Mansard & Funke 1980, `shoal.analysis.reflection_analysis`)
over sliding two-period windows. It prints, per window, the incident first-harmonic height at 1, 2
and 3 m against Biesel's target, the decay per metre and the reflection coefficient at the zone's
start: what the validation case's zero up-crossing heights mix together (the paddle's output, the
scheme's damping, the reflection, and higher harmonics).

    python benchmarks/flume_reflection.py                       # the validation's flume (zone 4.5-6 m, 1:10 beach)
    python benchmarks/flume_reflection.py --length 8.5 --zone 4.5 8.5 --beach-slope 0.5   # a 4 m zone
    python benchmarks/flume_reflection.py --analyse-only runs/flume   # again, on a finished run

Measured (dp = 0.02 m, to t = 16 s, one thread, about 55 min each on a loaded 2-core machine): see
`benchmarks/results/notes/README.md` (Validation, on waves).
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

import numpy as np


def run(args):
    import shoal
    from shoal.case import DampingZone
    from shoal.cases import wave_flume_2d
    from shoal.cases.wave_flume import WAVE_OPTIONS
    from shoal.options import SPHOptions

    gauges = tuple(np.round(np.arange(0.5, args.zone[0] - 0.2 + 1e-9, 0.25), 3))
    case = wave_flume_2d(dp=args.dp, depth=args.depth, wave_height=args.height, period=args.period, ramp_periods=2.0,
                         length=args.length, beach_slope=args.beach_slope, end_time=args.end, output_interval=args.end,
                         gauges_x=gauges, options=SPHOptions(**WAVE_OPTIONS[2]))
    case = case.model_copy(update={"damping": [DampingZone(start=(args.zone[0], 0, 0), end=(args.zone[1], 0, 0),
                                                           rate=10.0)]})
    print(f"{case.n_particles:,} particles, gauges {gauges[0]:g}-{gauges[-1]:g} m", flush=True)
    shoal.run_case(case, Path(args.out), plot=False, handle_signals=False)


def analyse(out, period, depth, height, zone_start):
    from shoal.analysis import reflection_analysis

    recs = {}
    for f in Path(out).glob("gauge_x*.csv"):
        x = float(re.search(r"gauge_x([0-9.]+)\.csv", f.name).group(1))
        d = np.loadtxt(f, delimiter=",", skiprows=1, ndmin=2)
        recs[x] = d
    n = min(len(d) for d in recs.values())
    t = next(iter(recs.values()))[:n, 0]
    eta = {x: d[:n, 1] for x, d in recs.items()}
    print("window [s]    H_I/H - 1 at 1 / 2 / 3 m     decay [%/m]   K_r at the zone")
    for a in np.arange(3.0, t[-1] - 2 * period, period):
        r = reflection_analysis(t, eta, period, depth, a, a + 2 * period, fit_decay=True, x_ref=0.0)
        hs = " / ".join(f"{r.incident_height_at(x) / height - 1:+.1%}" for x in (1.0, 2.0, 3.0))
        kr = r.reflected_height * math.exp(r.decay * zone_start) / (r.incident_height * math.exp(-r.decay * zone_start))
        print(f"{a:5.1f}-{a + 2 * period:5.1f}   {hs}    {r.decay * 100:6.2f}      {kr:.3f}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dp", type=float, default=0.02)
    p.add_argument("--height", type=float, default=0.05)
    p.add_argument("--period", type=float, default=1.2)
    p.add_argument("--depth", type=float, default=0.4)
    p.add_argument("--length", type=float, default=6.0, help="paddle to the toe of the beach [m]")
    p.add_argument("--beach-slope", type=float, default=0.1)
    p.add_argument("--zone", type=float, nargs=2, default=(4.5, 6.0), help="damping zone start, end [m]")
    p.add_argument("--end", type=float, default=16.0, help="end time [s]")
    p.add_argument("--out", default="runs/flume-reflection")
    p.add_argument("--analyse-only", metavar="RUN_DIR", help="analyse a finished run instead of running")
    args = p.parse_args(argv)
    if args.analyse_only is None:
        run(args)
    analyse(args.analyse_only or args.out, args.period, args.depth, args.height, args.zone[0])


if __name__ == "__main__":
    main()
