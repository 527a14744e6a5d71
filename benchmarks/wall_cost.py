"""The cost of one rate evaluation by wall treatment (and with the Riemann pair terms).

A 3D tank with a water block (`dam_break_3d`: a column a x 2a over a width, 3 wall layers: most of its
particles are walls, the case where the wall treatment costs most), built once per scheme; each scheme
is timed over `--evals` evaluations of the rates (sort, wall pass, pair loop) after two warm-up ones, in
the order given and then again in reverse (the 2-core machines drift: a ratio counts only measured back
to back, both ways). Prints ms per evaluation and the ratio to the first scheme.

    python benchmarks/wall_cost.py --schemes dynamic adami mdbc adami+riemann
"""

from __future__ import annotations

import argparse
import json
import time

SCHEMES = {
    "dynamic": dict(wall_pressure="dynamic"),
    "adami": dict(wall_pressure="adami"),
    "mdbc": dict(wall_pressure="mdbc"),
    "adami+riemann": dict(wall_pressure="adami", riemann=True, alpha=0.0, density_diffusion="none"),
}


def build(scheme, dp):
    from shoal.cases import dam_break_3d
    from shoal.options import SPHOptions
    from shoal.runner import build_model

    case = dam_break_3d(dp=dp, options=SPHOptions(**SCHEMES[scheme]))
    return build_model(case)


def time_evals(model, n):
    model.sort()
    model.compute_rates()
    model.compute_rates()
    t0 = time.perf_counter()
    for _ in range(n):
        model.sort()
        model.compute_rates()
    return (time.perf_counter() - t0) / n


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dp", type=float, default=0.008)
    ap.add_argument("--evals", type=int, default=30)
    ap.add_argument("--schemes", nargs="+", default=list(SCHEMES), choices=list(SCHEMES))
    a = ap.parse_args(argv)
    models = {s: build(s, a.dp) for s in a.schemes}
    m0 = models[a.schemes[0]]
    walls = int((m0.kind[:m0.n] != 0).sum())
    print(f"dam_break_3d, dp = {a.dp} m: {m0.n:,} particles, {walls / m0.n:.0%} walls; {a.evals} evaluations each")
    times = {s: [] for s in a.schemes}
    for order in (a.schemes, a.schemes[::-1]):
        for s in order:
            times[s].append(time_evals(models[s], a.evals))
    base = sum(times[a.schemes[0]]) / 2
    out = {}
    for s in a.schemes:
        t = times[s]
        out[s] = dict(ms=[1e3 * x for x in t], ratio=sum(t) / 2 / base)
        print(f"  {s:15} {1e3 * t[0]:8.2f} ms, reverse {1e3 * t[1]:8.2f} ms; ratio {out[s]['ratio']:.3f}")
    print(json.dumps(dict(dp=a.dp, particles=int(m0.n), wall_fraction=walls / m0.n, evals=a.evals, schemes=out)))


if __name__ == "__main__":
    main()
