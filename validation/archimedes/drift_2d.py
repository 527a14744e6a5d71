"""The full 2D Archimedes box's sideways drift, run by run: how it grows, and what changes it.

Runs the `--full` 2D box of `shoal validate archimedes` (dp = 0.02 m, H = 10 dp, 10 s) with the changes asked
for, and prints `settled_metrics` and the largest drift of the centre [dp] up to t = 2, 4, ..., 10 s.

    python validation/archimedes/drift_2d.py --out runs/drift                      # as the validation runs it
    python validation/archimedes/drift_2d.py --out runs/drift64 --precision float64
    python validation/archimedes/drift_2d.py --out runs/driftz --zones 0.3         # damping zones at both ends
    python validation/archimedes/drift_2d.py --out runs/drift0 --offset 0          # released at its draft
"""

from __future__ import annotations

import argparse

import numpy as np

import shoal
from shoal.case import DampingZone
from shoal.options import SPHOptions
from shoal.validation.archimedes import archimedes_case, equilibrium_level, read_body_csv, settled_metrics

DP, LENGTH, BEAM, HEIGHT = 0.02, 1.2, 0.4, 0.2


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--precision", choices=("float32", "float64"), default="float32")
    ap.add_argument("--zones", type=float, default=0.0, help="damping zones this long [m] at both ends")
    ap.add_argument("--offset", type=float, default=DP, help="released this far above its draft [m]")
    a = ap.parse_args(argv)
    case = archimedes_case(dim=2, dp=DP, end_time=10.0, offset=a.offset, options=SPHOptions(precision=a.precision))
    if a.zones > 0:
        case = case.model_copy(update=dict(damping=[DampingZone(start=(a.zones, 0, 0), end=(0, 0, 0)),
                                                    DampingZone(start=(LENGTH - a.zones, 0, 0), end=(LENGTH, 0, 0))]))
    shoal.run_case(case, a.out, plot=False, progress=False, handle_signals=False, overwrite=True)
    r = read_body_csv(f"{a.out}/body_box.csv")
    level = equilibrium_level(case.n_fluid, DP, 2, 500.0 * BEAM * HEIGHT, LENGTH)
    print(settled_metrics(r["time"], r["x"], r["y"], r["z"], r["roll"], r["pitch"], level, HEIGHT, DP, 4.0))
    t, x = r["time"], r["x"]
    for tt in (2, 4, 6, 8, 10):
        print(f"t <= {tt:2d} s: largest drift {np.abs(x[t <= tt + 1e-9] - x[0]).max() / DP:.3g} dp")


if __name__ == "__main__":
    main()
