"""Thread scaling of the CPU backend in one process (issue 34, must-show 4).

Steps the DualSPHysics 3D dam break with each thread count in turn, a few steps at a time, for several rounds,
in one process: the counts alternate within seconds of each other, so a drift of the machine (the 2-core
machines here vary from minute to minute as well as from day to day) falls on every count alike, which
separate runs one after the other do not give. Prints the mean time a step of each count per round and the
speed-up of each count over the first (the ratio of the means over all rounds).

    python benchmarks/thread_scaling.py --dp 0.0085 --threads 1 2 --rounds 4 --steps 5
    python benchmarks/thread_scaling.py --dp 0.0065 --threads 1 2 4 8 16 --json scaling.json   # a many-core node
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path


def fail(message):
    print(f"thread_scaling.py: error: {message}", file=sys.stderr)
    raise SystemExit(2)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dp", type=float, default=0.0085, help="particle spacing [m] (0.0085: 173,531 particles)")
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts, the first the reference")
    p.add_argument("--rounds", type=int, default=4, help="rounds over the thread counts")
    p.add_argument("--steps", type=int, default=5, help="steps of each count in a round")
    p.add_argument("--precision", choices=["float32", "float64"], default="float32")
    p.add_argument("--json", type=Path, help="write every figure to this file")
    a = p.parse_args(argv)
    import numba

    most = numba.config.NUMBA_NUM_THREADS
    if min(a.threads) < 1 or max(a.threads) > most:
        fail(f"--threads must be between 1 and {most} (Numba's thread pool; NUMBA_NUM_THREADS sets it)")
    if a.rounds < 1 or a.steps < 1:
        fail("--rounds and --steps must be at least 1")
    from shoal.cases import dam_break_dualsphysics
    from shoal.errors import InputError
    from shoal.runner import build_model
    from shoal.simulation import Simulation

    try:
        model = build_model(dam_break_dualsphysics(dp=a.dp, precision=a.precision))
    except InputError as err:
        fail(str(err))
    sim = Simulation(model, end_time=1e9)
    for t in a.threads:  # compile, and the first sorts, outside the timed steps
        numba.set_num_threads(t)
        sim.run(max_steps=2)
    times = {t: [] for t in a.threads}
    for r in range(a.rounds):
        for t in a.threads:
            numba.set_num_threads(t)
            t0 = time.perf_counter()
            sim.run(max_steps=a.steps)
            times[t].append((time.perf_counter() - t0) / a.steps)
        print(f"round {r + 1}: " + ", ".join(f"{t} threads {1e3 * times[t][-1]:.1f} ms" for t in a.threads),
              flush=True)
    mean = {t: sum(v) / len(v) for t, v in times.items()}
    ref = a.threads[0]
    speedup = {t: mean[ref] / mean[t] for t in a.threads}
    print(f"{model.n_total:,} particles, {a.precision}, a step: " + ", ".join(
        f"{t} threads {1e3 * mean[t]:.1f} ms ({speedup[t]:.2f}x, efficiency {speedup[t] * ref / t:.2f})"
        for t in a.threads))
    if a.json:
        a.json.write_text(json.dumps({"dp": a.dp, "precision": a.precision, "particles": model.n_total,
                                      "steps": a.steps, "rounds": a.rounds,
                                      "seconds_per_step": {str(t): v for t, v in times.items()},
                                      "speedup": {str(t): s for t, s in speedup.items()}}, indent=2) + "\n")


if __name__ == "__main__":
    main()
