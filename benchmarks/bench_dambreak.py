"""Benchmark: the DualSPHysics 5.4 3D dam break (01_DamBreak), or SPHERIC Test 2 as the cross-code GPU
benchmark runs it, for N steps.

Prints one JSON object: particles, steps, force evaluations, wall time
excluding compilation, particle-steps per second, compile time, peak memory
(resident set) and solver bytes per particle; with ``--backend cuda`` also
the device memory the run holds (free memory before the model is built minus
free memory after the timed steps).

    python benchmarks/bench_dambreak.py --dp 0.0085 --steps 100 --precision float32
    python benchmarks/bench_dambreak.py --dp 0.0085 --steps 100 --floating 800   # the column floats
    python benchmarks/bench_dambreak.py --dp 0.012 --steps 40 --from-checkpoint runs/db/ckpt_004100.h5
    python benchmarks/bench_dambreak.py --case spheric-benchmark --dp 0.006 --backend cuda --steps 2000 --developed-from 0.5

``--from-checkpoint`` times developed flow: the steps start from a checkpoint of a run of the same case (the same
dp, precision and integrator), e.g. ``shoal run dam-break-dualsphysics --dp 0.012 --end-time 0.5
--checkpoint-interval 0.5 --out runs/db`` (after the impact on the far wall, 0.5 s), instead of from rest, where
the particles still sit on their lattice. ``--developed-from T`` does the same in one process: it runs the case
from rest to the simulated time T (timed apart, ``advance_seconds``) and then times the steps.

``--case spheric-benchmark`` is `shoal.cases.spheric_benchmark`: SPHERIC Test 2 with the settings of the public
cross-code benchmark (``tomashalada/sph-benchmarks``, damBreak3D: DualSPHysics 5.4 14.52 ms a step and TNL-SPH
12.51 ms on an H100 SXM at dp = 6 mm, 4,989,696 particles; Wendland, h = 2 dp, alpha = 0.02, Molteni delta = 0.1,
three layers of dynamic boundary particles, Verlet). At dp = 6 mm shoal generates 4,993,539 particles.

The default case is `shoal.cases.dam_break_dualsphysics` (tank 1.6 x 0.67 x 0.4 m,
water 0.4 x 0.67 x 0.3 m, hollow column; cubic spline with tensile
correction, h = sqrt(3) dp, c0 = 20 sqrt(g H), alpha = 0.1, Fourtakas
delta = 0.1, one layer of dynamic boundary particles, Verlet + Euler every
40 steps, CFL 0.2). The first `--warmup` steps (compilation or cache load,
and the first sorts) are timed separately as compile time.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time


def device_memory(backend):
    """(free, total) memory of the current CUDA device [bytes] (None on the CPU, or under the simulator)."""
    if backend != "cuda":
        return None
    from numba import cuda

    cuda.synchronize()
    info = cuda.current_context().get_memory_info()
    return None if info.free == float("inf") else (int(info.free), int(info.total))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--case", default="dam-break-dualsphysics", choices=["dam-break-dualsphysics", "spheric-benchmark"],
                   help="the DualSPHysics example (default) or SPHERIC Test 2 as the cross-code GPU benchmark runs it")
    p.add_argument("--dp", type=float, default=0.0085,
                   help="particle spacing [m] (0.0085: 173,531 particles of the DualSPHysics dam break; 0.006: "
                        "4,993,539 of the SPHERIC benchmark)")
    p.add_argument("--steps", type=int, default=100, help="timed steps")
    p.add_argument("--warmup", type=int, default=2, help="untimed first steps (compilation)")
    p.add_argument("--precision", choices=["float32", "float64"], default="float32")
    p.add_argument("--integrator", default="verlet", choices=["verlet", "symplectic", "predictor_corrector"])
    p.add_argument("--cells-per-support", type=int, default=2)
    p.add_argument("--threads", type=int, default=None, help="Numba threads (default: all)")
    p.add_argument("--backend", default="cpu", choices=["cpu", "cuda"])
    p.add_argument("--from-checkpoint", default=None, metavar="FILE",
                   help="start the timed steps from this checkpoint of a run of the same case (developed flow)")
    p.add_argument("--developed-from", type=float, default=None, metavar="T",
                   help="run from rest (or the checkpoint) to the simulated time T [s] before the timed steps "
                        "(developed flow in one process)")
    p.add_argument("--floating", type=float, default=None, metavar="DENSITY",
                   help="make the column a floating body of this density [kg/m^3] (issue 32: a floating body's cost)")
    args = p.parse_args(argv)
    if args.developed_from is not None and not (args.developed_from >= 0 and args.developed_from < float("inf")):
        from shoal.errors import InputError

        raise InputError(f"--developed-from {args.developed_from}: give a simulated time [s] of 0 or more")


    import numba

    if args.threads:
        numba.set_num_threads(args.threads)
    t_import = time.perf_counter()
    if args.case == "spheric-benchmark":  # imported only when asked: regression.py runs this on older trees too
        from shoal.cases import spheric_benchmark as make
    else:
        from shoal.cases import dam_break_dualsphysics as make
    from shoal.runner import build_model
    from shoal.simulation import Simulation

    case = make(dp=args.dp, precision=args.precision)
    case = case.with_options(integrator=args.integrator, cells_per_support=args.cells_per_support)
    if args.floating is not None:
        from shoal.floating import FloatingBody

        solids = [s if s.name != "column" else s.model_copy(update={"floating": FloatingBody(density=args.floating)})
                  for s in case.solids]
        case = case.model_copy(update={"solids": solids}).revalidate()
    mem_before = device_memory(args.backend)
    model = build_model(case, backend=args.backend)
    sim = Simulation(model, end_time=1e9)
    if args.from_checkpoint:
        from pathlib import Path

        from shoal.simulation.checkpoint import read_checkpoint, restore
        restore(sim, read_checkpoint(Path(args.from_checkpoint)))
    t0 = time.perf_counter()
    sim.run(max_steps=args.warmup)
    t1 = time.perf_counter()
    warm = t1 - t0
    advance_steps = 0
    if args.developed_from is not None:
        while sim.time < args.developed_from:  # one step a call: stops at the first step past T
            sim.run(max_steps=1)
            advance_steps += 1
        if args.backend == "cuda":
            from numba import cuda

            cuda.synchronize()
    t2 = time.perf_counter()
    advance = t2 - t1
    t1 = t2
    start_time = sim.time
    sim.run(max_steps=args.steps)
    if args.backend == "cuda":
        from numba import cuda

        cuda.synchronize()
    wall = time.perf_counter() - t1
    mem_after = device_memory(args.backend)
    n = model.n_total
    evals = args.steps * sim.integrator.rate_evaluations_per_step
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    out = {
        "case": case.name, "floating": args.floating, "backend": args.backend, "dp": args.dp, "precision": args.precision, "integrator": args.integrator,
        "cells_per_support": args.cells_per_support, "threads": numba.get_num_threads(),
        "particles": n, "fluid_particles": case.n_fluid, "steps": args.steps,
        "force_evaluations": evals, "wall_seconds": wall,
        "particle_steps_per_second": n * args.steps / wall,
        "force_evaluations_per_second": n * evals / wall,
        "seconds_per_step": wall / args.steps,
        "ms_per_step": 1e3 * wall / args.steps,
        "compile_seconds": round(model.backend.compile_seconds, 3),
        "warmup_seconds": round(warm, 3),
        "advance_steps": advance_steps,
        "advance_seconds": round(advance, 3),
        "setup_seconds": round(t0 - t_import, 3),
        "start_time": start_time,
        "simulated_time": sim.time,
        "peak_rss_bytes": peak,
        "solver_bytes": model.nbytes(),
        "bytes_per_particle": model.nbytes() / n,
        "peak_rss_bytes_per_particle": peak / n,
    }
    if args.backend == "cuda":
        from shoal.backends import cuda as backend

        cap = getattr(backend, "max_registers", None)  # older trees (regression.py) have no cap
        out["cuda_max_registers"] = cap() if cap else None  # SHOAL_CUDA_MAX_REGISTERS; None: the compiler's choice
    if mem_before is not None and mem_after is not None:
        # what the run holds on the GPU: its arrays, the sort's buffers, the kernels' code and Numba's pools
        out["device_bytes"] = mem_before[0] - mem_after[0]
        out["device_bytes_per_particle"] = out["device_bytes"] / n
        out["device_total_bytes"] = mem_after[1]
    json.dump(out, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    from shoal.errors import InputError
    from shoal.simulation.checkpoint import CheckpointError

    try:
        main()
    except (InputError, CheckpointError) as err:
        sys.stderr.write(f"bench_dambreak: error: {err}\n")
        sys.exit(2)
