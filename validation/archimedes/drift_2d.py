"""The full 2D Archimedes box's sideways drift, run by run: how it grows, and what changes it.

Runs the `--full` 2D box of `shoal validate archimedes` (dp = 0.02 m, H = 10 dp, 10 s) with the changes asked
for, and prints `settled_metrics` and the largest drift of the centre [dp] and tilt [deg] up to 2, 4, ... s after the
release (`--release`: the box held that long while the water settles; the drift is from where it is held).

    python validation/archimedes/drift_2d.py --out runs/drift                      # as the validation runs it
    python validation/archimedes/drift_2d.py --out runs/drift64 --precision float64
    python validation/archimedes/drift_2d.py --out runs/driftz --zones 0.3         # damping zones at both ends
    python validation/archimedes/drift_2d.py --out runs/drift0 --offset 0          # released at its draft
    python validation/archimedes/drift_2d.py --out runs/driftx --fixed x           # the sway held
    python validation/archimedes/drift_2d.py --out runs/drifta --no-wall-acceleration
    python validation/archimedes/drift_2d.py --out runs/driftv --option integrator=verlet
    python validation/archimedes/drift_2d.py --out runs/driftd --option wall_pressure=dynamic
    python validation/archimedes/drift_2d.py --out runs/drifts --release 10 --end 20  # into settled water

`--no-wall-acceleration` (a diagnosis, not a scheme) leaves the body's acceleration out of the Adami wall
pressure's extrapolation (`shoal.physics.wall_pressure`) by giving the wall kinematics without it.
"""

from __future__ import annotations

import argparse

import numpy as np

import shoal
from shoal.body_coupling import FloatingMotion
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
    ap.add_argument("--release", type=float, default=0.0, help="the box's release_time [s]")
    ap.add_argument("--end", type=float, default=10.0, help="[s]")
    ap.add_argument("--fixed", nargs="*", default=[], choices=("x", "z"), help="degrees of freedom held")
    ap.add_argument("--no-wall-acceleration", action="store_true")
    ap.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                    help="an SPHOptions field (numbers as numbers), e.g. integrator=verlet")
    a = ap.parse_args(argv)
    if a.no_wall_acceleration:
        def without_acceleration(self, t, acceleration=True):
            zero = np.zeros(3)
            return self.body.kinematics(self.state._replace(acceleration=zero, angular_acceleration=zero))
        FloatingMotion.rigid_kinematics = without_acceleration
    options = {"precision": a.precision}
    for item in a.option:
        key, _, value = item.partition("=")
        try:
            options[key] = float(value)
        except ValueError:
            options[key] = value
    case = archimedes_case(dim=2, dp=DP, end_time=a.end, offset=a.offset, options=SPHOptions(**options),
                           floating=dict(fixed=a.fixed, release_time=a.release))
    if a.zones > 0:
        case = case.model_copy(update=dict(damping=[DampingZone(start=(a.zones, 0, 0), end=(0, 0, 0)),
                                                    DampingZone(start=(LENGTH - a.zones, 0, 0), end=(LENGTH, 0, 0))]))
    shoal.run_case(case, a.out, plot=False, progress=False, handle_signals=False, overwrite=True)
    r = read_body_csv(f"{a.out}/body_box.csv")
    level = equilibrium_level(case.n_fluid, DP, 2, 500.0 * BEAM * HEIGHT, LENGTH)
    print(settled_metrics(r["time"], r["x"], r["y"], r["z"], r["roll"], r["pitch"], level, HEIGHT, DP, 4.0))
    t, x, pitch = r["time"], r["x"], r["pitch"]
    for tt in np.arange(a.release + 2.0, a.end + 1e-9, 2.0):
        upto = t <= tt + 1e-9
        print(f"t <= {tt:4.1f} s: largest drift {np.abs(x[upto] - x[0]).max() / DP:.3g} dp, "
              f"largest tilt {np.abs(pitch[upto]).max():.3g} deg")


if __name__ == "__main__":
    main()
