"""How fast still water in the Archimedes tank breaks its mirror symmetry, with or without the box.

The 2D tank of `shoal validate archimedes --full` (1.2 m long, water 0.4 m deep, dp = 0.02 m) starts on a
lattice symmetric about x = L/2. Each fluid particle is paired with its mirror image at t = 0; every 0.5 s the
script prints how far the pairs are from mirror images of each other (rms and max, in dp). Exact arithmetic
would keep them at 0; what grows is the round-off, amplified by the particles' own dynamics.

    python validation/archimedes/still_water_symmetry.py                       # the water alone, float32
    python validation/archimedes/still_water_symmetry.py --precision float64
    python validation/archimedes/still_water_symmetry.py --box                 # with the floating box
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.spatial import cKDTree

from shoal.options import SPHOptions
from shoal.physics.spec import FLUID
from shoal.simulation import Simulation
from shoal.validation.archimedes import archimedes_case

DP, LENGTH = 0.02, 1.2


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--precision", choices=("float32", "float64"), default="float32")
    ap.add_argument("--box", action="store_true", help="with the floating box (as the validation runs it)")
    ap.add_argument("--end", type=float, default=10.0, help="[s]")
    a = ap.parse_args(argv)
    case = archimedes_case(dim=2, dp=DP, end_time=a.end, options=SPHOptions(precision=a.precision))
    if not a.box:
        case = case.model_copy(update=dict(solids=[case.solids[0]]))
    sim = Simulation(case)
    m = sim.model

    def fluid():
        rows = m.owned_rows()
        pos, ids, kind = m.host(m.pos)[rows].astype(float), m.host(m.idp)[rows], m.host(m.kind)[rows]
        keep = kind == FLUID
        order = np.argsort(ids[keep])
        return pos[keep][order], ids[keep][order]

    pos, ids = fluid()
    mirror = pos.copy()
    mirror[:, 0] = LENGTH - mirror[:, 0]
    dist, partner = cKDTree(pos).query(mirror)
    if dist.max() > 1e-6 * DP:
        raise SystemExit("the fluid's lattice is not symmetric about the tank's middle")
    for target in np.arange(0.5, a.end + 1e-9, 0.5):
        while sim.time < target - 1e-12:
            sim.step()
        now, now_ids = fluid()
        if not np.array_equal(now_ids, ids):
            raise SystemExit("fluid particles were lost")
        gap = np.stack([now[:, 0] + now[partner, 0] - LENGTH, now[:, -1] - now[partner, -1]], axis=1)
        size = np.sqrt((gap ** 2).sum(axis=1)) / DP
        print(f"t = {sim.time:5.2f} s: mirror asymmetry rms {np.sqrt((size ** 2).mean()):.3e} dp, max {size.max():.3e} dp",
              flush=True)


if __name__ == "__main__":
    main()
