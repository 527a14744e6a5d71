"""Active absorption at a piston paddle against a vertical wall (issue 31, must-show 4).

A 2D flume of depth d ends in a vertical wall at x = length. The piston makes `--periods` regular waves
(a cosine ramp up and down of one period each), which reflect off the wall and come back; with
``--awas`` the paddle absorbs them (`shoal.active_absorption`), without it re-reflects them. The fluid's
kinetic energy is sampled every T/20; the energy left in the flume once the reflected train has reached the
paddle (and had time to be re-reflected to the middle of the flume) is compared with the incident train's
(`shoal.validation.active_absorption`).

    python benchmarks/awas_flume.py --awas --dp 0.0125 --out /tmp/awas_on
    python benchmarks/awas_flume.py --dp 0.0125 --out /tmp/awas_off
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))


def main(argv=None):
    from shoal.validation.active_absorption import absorption_flume, energy_left, run_flume, standing_envelope

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dp", type=float, default=0.0125)
    ap.add_argument("--depth", type=float, default=0.25)
    ap.add_argument("--height", type=float, default=0.04)
    ap.add_argument("--period", type=float, default=1.2)
    ap.add_argument("--periods", type=float, default=3.0, help="full periods between the ramps")
    ap.add_argument("--lengths", type=float, default=2.5, help="flume length in wavelengths")
    ap.add_argument("--awas", action="store_true")
    ap.add_argument("--gain", default="linear")
    ap.add_argument("--regular", type=float, default=0.0,
                    help="instead: run regular waves without stopping for this many periods")
    ap.add_argument("--out", type=Path, required=True)
    a = ap.parse_args(argv)
    case, info = absorption_flume(dp=a.dp, depth=a.depth, height=a.height, period=a.period, periods=a.periods,
                                  lengths=a.lengths, awas=a.awas, gain=a.gain, regular=a.regular)
    t0 = time.perf_counter()
    rec = run_flume(case, a.out)
    info.update(wall_s=time.perf_counter() - t0, awas=a.awas, particles=rec["particles"])
    info.update(standing_envelope(rec, info) if a.regular else energy_left(rec, info))
    (a.out / "awas_summary.json").write_text(json.dumps(info, indent=2, default=float) + "\n")
    print(json.dumps(info, indent=2, default=float))


if __name__ == "__main__":
    main()
