"""How the undular bore's fitted celerity depends on the snapshots it is fitted to.

Runs the 2D bore of `tests/test_tidal_bore.py::test_undular_bore_one_scheme_quick` (U = 0.3 m/s,
d0 = 0.1 m, dp = 0.01 m, the paper's scheme with Adami walls and alpha = 0.02, 3 m flume, to
t = 0.95 L / (U + c)) with snapshots every 0.02 s, and prints the celerity fitted to the front's
position (`shoal.analysis.front_position`, 5 cm bins, level (d0 + d1) / 2) while it is within
1.0-2.25 m, from every snapshot and from those 0.1 s apart, against Belanger's. A small change of the
CFL number, or the CPU's rates particle by particle instead of a pair at a time (the same sums in
another order), perturbs the run at round-off:

    python benchmarks/bore_snapshots.py --cfl 0.1999
    python benchmarks/bore_snapshots.py --cfl 0.2001 --by-particle
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np


def main(argv=None):
    import shoal
    from shoal.analysis import bore_from_inflow, celerity, front_position
    from shoal.cases import tidal_bore
    from shoal.cases.tidal_bore import PAPER_OPTIONS
    from shoal.options import SPHOptions
    from shoal.output.pvd import read_pvd
    from shoal.output.vtu import read_vtu
    from shoal.physics.spec import FLUID

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cfl", type=float, default=0.2)
    ap.add_argument("--by-particle", action="store_true", help="the CPU's rates particle by particle")
    args = ap.parse_args(argv)
    if args.by_particle:
        import shoal.backends.cpu as cpu

        init = cpu.CPUBackend.__init__

        def by_particle(self, spec):
            init(self, spec)
            self.rates = self.rates_by_particle

        cpu.CPUBackend.__init__ = by_particle
    U, d0, dp, L = 0.3, 0.1, 0.01, 3.0
    c, d1, _ = bore_from_inflow(U, d0)
    t_end = 0.95 * L / (U + c)
    opts = SPHOptions(**dict(PAPER_OPTIONS, alpha=0.02, wall_pressure="adami", cfl=args.cfl))
    case = tidal_bore(dp=dp, inflow_speed=U, dim=2, end_time=t_end, output_interval=0.02, options=opts, length=L,
                      gauges_x=[0.5, 1.0, 1.5, 2.0])
    mid, mass = d0 + 0.5 * (d1 - d0), 1000.0 * dp**2
    with tempfile.TemporaryDirectory() as tmp:
        run = Path(tmp) / "run"
        shoal.run_case(case, run, plot=False, handle_signals=False)
        times, fronts = [], []
        for t, name in read_pvd(run / "tidal-bore.pvd"):
            pts, data = read_vtu(run / name)
            fl = data["kind"] == FLUID
            x_end = L - U * t - 0.3
            xf = front_position(pts[fl], data["density"][fl], mass, mid, x_end, 0.05)
            if 1.0 <= xf <= 2.25 and xf < x_end - 0.1:
                times.append(t)
                fronts.append(xf)
    t, x = np.array(times), np.array(fronts)
    tenth = np.abs(t * 10 - np.round(t * 10)) < 1e-6
    out = dict(cfl=args.cfl, by_particle=args.by_particle, celerity_belanger=c,
               every_0_02s=dict(snapshots=int(len(t)), error=celerity(x, t) / c - 1),
               every_0_1s=dict(snapshots=int(tenth.sum()), error=celerity(x[tenth], t[tenth]) / c - 1))
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
