"""Time the phases of one step of the DualSPHysics 3D dam break (sort, rates, dt, update).

    python benchmarks/profile_phases.py --dp 0.0085 --steps 20
"""

import argparse
import time

import numpy as np


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--dp", type=float, default=0.0085)
    p.add_argument("--steps", type=int, default=20)
    p.add_argument("--precision", default="float32")
    a = p.parse_args()
    from shoal.cases import dam_break_dualsphysics
    from shoal.runner import build_model
    from shoal.timestepping import make_integrator

    case = dam_break_dualsphysics(dp=a.dp, precision=a.precision)
    m = build_model(case)
    integ = make_integrator(m)
    b = m.backend
    t = {"sort": 0.0, "rates": 0.0, "dt": 0.0, "update": 0.0}
    for step in range(a.steps + 2):
        t0 = time.perf_counter()
        m.sort()
        t1 = time.perf_counter()
        m.compute_rates()
        t2 = time.perf_counter()
        dt = m.time_step_limit()
        t3 = time.perf_counter()
        b.verlet(m.n, (m.pos, m.vel, m.rho, integ.vel_m1, integ.rho_m1, m.ace, m.drho, m.xsph, m.kind,
                       m.dtype.type(dt), False, m.P))
        t4 = time.perf_counter()
        if step >= 2:
            for k, v in zip(t, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
                t[k] += v
    total = sum(t.values())
    print(f"{m.n_total} particles, {a.precision}, per step: " + ", ".join(
        f"{k} {1e3 * v / a.steps:.1f} ms ({100 * v / total:.0f} %)" for k, v in t.items()))


if __name__ == "__main__":
    main()
