"""The cost of open boundaries (issue 33): particle-steps per second of the open channel against the same flow
with periodic ends.

``--mode open``: the built-in `open-channel-2d` (`shoal.cases.open_channel_2d`: an inlet of imposed discharge,
an outlet, particles created and removed every step); ``--mode periodic``: the same water, bed and scheme in a
flume whose ends are joined (``domain.periodic = ["x"]``), no open boundary. Both start from the stream at its
speed; `--warmup` untimed steps (compilation), then `--steps` timed ones. Prints one JSON record (and writes it
to `--out` when given). Speed claims need the two modes run back to back, and again in reverse order:

    for mode in open periodic periodic open; do
        python benchmarks/bench_open_channel.py --mode $mode --dp 0.005 --threads 1
    done
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path


def periodic_channel(dp, depth=0.2, length=2.0, discharge=0.04):
    """`open_channel_2d`'s water and bed in a flume with periodic ends."""
    from shoal.case import Case, Domain, Fluid, FluidRegion, Output, Solid
    from shoal.cases.open_channel import CHANNEL_OPTIONS
    from shoal.geometry.shapes import Box
    from shoal.options import SPHOptions

    layers = 4
    return Case(name="periodic-channel-2d", dim=2, dp=dp, end_time=100.0, fluid=Fluid(depth=depth, surface_level=depth),
                options=SPHOptions(**CHANNEL_OPTIONS),
                solids=[Solid(name="bed", shape=Box(lo=(0, 0, -layers * dp), hi=(length, 0, 0)), layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)), velocity=(discharge / depth, 0, 0))],
                domain=Domain(lo=(0, 0, -(layers + 2) * dp), hi=(length, 0, 3 * depth), periodic=["x"]),
                output=Output(interval=100.0))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mode", choices=["open", "periodic"], required=True)
    p.add_argument("--dp", type=float, default=0.005, help="particle spacing [m] (0.005: about 16,000 fluid)")
    p.add_argument("--steps", type=int, default=2000, help="timed steps")
    p.add_argument("--warmup", type=int, default=20, help="untimed first steps")
    p.add_argument("--threads", type=int, default=None, help="Numba threads (default: all)")
    p.add_argument("--out", type=Path, default=None, help="write the JSON record here too")
    a = p.parse_args(argv)
    import numba

    if a.threads:
        numba.set_num_threads(a.threads)
    from shoal.cases import open_channel_2d
    from shoal.runner import build_model
    from shoal.simulation import Simulation

    case = open_channel_2d(dp=a.dp, end_time=100.0, output_interval=100.0, gauges_x=()) if a.mode == "open" \
        else periodic_channel(a.dp)
    t0 = time.perf_counter()
    model = build_model(case)
    sim = Simulation(model, case.end_time)
    setup = time.perf_counter() - t0
    sim.run(max_steps=a.warmup)
    n_steps, n_sum = 0, 0
    t0 = time.perf_counter()
    for _ in range(a.steps):
        sim.run(max_steps=1)
        n_steps += 1
        n_sum += model.n
    wall = time.perf_counter() - t0
    rec = {"mode": a.mode, "dp": a.dp, "threads": numba.get_num_threads(), "steps": n_steps,
           "mean_particles": n_sum / n_steps, "wall_seconds": wall, "setup_seconds": setup,
           "particle_steps_per_second": n_sum / wall, "simulated_time": sim.time,
           "solver_bytes": model.nbytes(), "bytes_per_particle": model.nbytes() / model.n,
           "created": model.buffers.created if model.buffers is not None else 0,
           "removed": model.buffers.removed if model.buffers is not None else 0}
    text = json.dumps(rec, indent=2)
    print(text)
    if a.out is not None:
        a.out.parent.mkdir(parents=True, exist_ok=True)
        a.out.write_text(text + "\n")


if __name__ == "__main__":
    main()
