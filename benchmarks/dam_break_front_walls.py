"""The 2D dam-break surge front by wall treatment and resolution (issue 28, item 5).

The `dam-break-2d` case (a column a x 2a, a = 0.146 m, in a tank 5a long) at dp = a / n for each
`--n`, with each `--wall` (`wall_pressure`), run to T = t sqrt(2 g / a) = 3.0. Printed per run: the
mean relative error of the front Z = x / a against Martin & Moyce (1952) over 0.8 <= T <= 3, and the
largest distance of the front outside the band between Martin & Moyce and Koshizuka & Oka (1996),
relative to the band's lower edge, at T = 0.8, 1.0, ..., 3.0 (the `shoal validate dam-break-2d`
measures, which pass at 7 %), and the signed error at T = 1, 2, 3.

    python benchmarks/dam_break_front_walls.py --n 18 36 --wall dynamic adami mdbc
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from shoal.analysis import load_reference, mean_relative_error, outside_band, surge_front
from shoal.cases import dam_break_2d
from shoal.options import SPHOptions
from shoal.runner import build_model
from shoal.simulation import Simulation, TimeInterval

A, G = 0.146, 9.81
T_SCALE = np.sqrt(2 * G / A)


RIEMANN = dict(riemann=True, alpha=0.0, density_diffusion="none")
"""What ``WALL+riemann`` adds to a scheme: the Riemann pair terms in place of the artificial viscosity
and density diffusion (`shoal.physics.riemann`)."""


def scheme(wall):
    """SPHOptions of a ``--wall`` entry: a wall_pressure, optionally with ``+riemann``."""
    name, _, extra = wall.partition("+")
    return SPHOptions(wall_pressure=name, **(RIEMANN if extra == "riemann" else {}))


def front(n, wall, t_end_T=3.0):
    case = dam_break_2d(dp=A / n, a=A, options=scheme(wall))
    model = build_model(case)
    sim = Simulation(model, t_end_T / T_SCALE)
    rec = []
    sim.add_callback(lambda s: rec.append((s.time * T_SCALE, surge_front(s.model) / A)), TimeInterval(0.05 / T_SCALE))
    t0 = time.perf_counter()
    sim.run()
    T, Z = np.array(rec).T
    return T, Z, time.perf_counter() - t0, case.n_particles


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=float, nargs="+", default=[18.0, 36.0], help="particles across a")
    ap.add_argument("--wall", nargs="+", default=["dynamic", "adami", "mdbc"],
                    help="wall_pressure values, each optionally with +riemann (e.g. adami+riemann)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    a = ap.parse_args(argv)
    Tm, Zm = load_reference("martin_moyce_front")
    Tk, Zk = load_reference("koshizuka_oka_front")
    out = []
    print(f"{'a/dp':>5} {'wall':14} {'particles':>9} {'MM mean':>8} {'band':>6} {'T=1':>7} {'T=2':>7} {'T=3':>7} {'s':>6}")
    for n in a.n:
        for wall in a.wall:
            T, Z, sec, npart = front(n, wall)
            err = mean_relative_error(T, Z, Tm, Zm, 0.8, 3.0)
            band = outside_band(T, Z, (Tm, Zm), (Tk, Zk), np.arange(0.8, 3.001, 0.2))
            at = {t: float(np.interp(t, T, Z) / np.interp(t, Tm, Zm) - 1) for t in (1.0, 2.0, 3.0)}
            print(f"{n:5g} {wall:14} {npart:9,d} {100 * err:7.2f}% {100 * band:5.2f}% "
                  f"{100 * at[1.0]:+6.2f}% {100 * at[2.0]:+6.2f}% {100 * at[3.0]:+6.2f}% {sec:6.0f}", flush=True)
            out.append(dict(n_per_a=n, wall=wall, particles=npart, mean_rel_err_mm=err, band=band,
                            rel_err_at_T={str(k): v for k, v in at.items()}, seconds=sec, T=T.tolist(), Z=Z.tolist()))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
