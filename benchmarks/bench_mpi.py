"""Benchmark: strong scaling of the MPI slab decomposition (shoal.parallel) on a 3D dam break.

Runs the DualSPHysics 5.4 3D dam break (`dam_break_dualsphysics`, as
`bench_dambreak.py`) for `--steps` steps in each configuration

    1 rank x T threads, 1 rank x 1 thread, R ranks x 1 thread (R = 2 by default)

(``mpiexec -n R`` with ``NUMBA_NUM_THREADS``) and prints one JSON object per
configuration and a table: particles, particle-steps per second (wall time of
the timed steps, after `--warmup` steps of compilation and first sorts), and
for the MPI runs each rank's particles, ghosts, and communication time
(halo exchanges, migration, the dt reduction, the collective checks, and
the waiting for the slowest rank at each of them) as a share of the step
time. The slowest rank waits least, so its share is about the cost of the
communication itself; the fastest rank's share adds the load imbalance.

    python benchmarks/bench_mpi.py --dp 0.0085 --steps 40          # ~173k particles
    python benchmarks/bench_mpi.py --dp 0.0058 --steps 20          # ~500k (the issue's size)
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path


def worker(args):
    from shoal.cases import dam_break_dualsphysics
    from shoal.parallel import world
    from shoal.runner import build_model
    from shoal.simulation import Simulation

    case = dam_break_dualsphysics(dp=args.dp, precision=args.precision).with_options(integrator=args.integrator)
    model = build_model(case)
    comm = world()
    sim = Simulation(model, end_time=1e9)
    sim.run(max_steps=args.warmup)
    c0 = getattr(model, "comm_seconds", 0.0)
    if comm is not None:
        comm.Barrier()
    t0 = time.perf_counter()
    sim.run(max_steps=args.steps)
    if comm is not None:
        comm.Barrier()
    wall = time.perf_counter() - t0
    n = case.n_particles
    out = {"particles": n, "steps": args.steps, "wall_s": wall, "s_per_step": wall / args.steps,
           "particle_steps_per_s": n * args.steps / wall, "threads": int(os.environ.get("NUMBA_NUM_THREADS", 0)),
           "ranks": 1 if comm is None else comm.Get_size(), "integrator": args.integrator}
    if comm is not None:
        mine = {"owned": int(model.n_owned), "ghosts": int(model.n_ghost), "comm_s": model.comm_seconds - c0}
        every = comm.gather(mine, root=0)
        if comm.Get_rank() != 0:
            return
        out["per_rank"] = every
        out["comm_share_per_rank"] = [e["comm_s"] / wall for e in every]
        out["slab_cuts_x"] = model.cuts[1:-1].tolist()
    print("RESULT " + json.dumps(out), flush=True)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dp", type=float, default=0.0085, help="particle spacing [m] (0.0085: ~173k, 0.0058: ~500k)")
    p.add_argument("--steps", type=int, default=40)
    p.add_argument("--warmup", type=int, default=3)
    p.add_argument("--precision", choices=["float32", "float64"], default="float32")
    p.add_argument("--integrator", default="verlet", choices=["verlet", "symplectic", "predictor_corrector"])
    p.add_argument("--ranks", type=int, default=2, help="ranks of the MPI run")
    p.add_argument("--threads", type=int, default=os.cpu_count(), help="threads of the 1-rank run")
    p.add_argument("--only", choices=["1xT", "1x1", "Rx1"], action="append", help="run only these configurations")
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        return worker(args)
    mpiexec = shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or shutil.which("mpiexec")
    if mpiexec is None:
        sys.exit("bench_mpi: no mpiexec: pip install 'shoal[mpi]'")
    version = subprocess.run([mpiexec, "--version"], capture_output=True, text=True).stdout
    over = ["--oversubscribe"] if "Open MPI" in version else []
    src = str(Path(__file__).resolve().parents[1] / "src")
    base = [sys.executable, __file__, "--worker", "--dp", str(args.dp), "--steps", str(args.steps), "--warmup",
            str(args.warmup), "--precision", args.precision, "--integrator", args.integrator]
    configs = [("1xT", 1, args.threads), ("1x1", 1, 1), ("Rx1", args.ranks, 1)]
    rows = []
    for name, ranks, threads in configs:
        if args.only and name not in args.only:
            continue
        env = dict(os.environ, NUMBA_NUM_THREADS=str(threads),
                   PYTHONPATH=src + os.pathsep + os.environ.get("PYTHONPATH", ""))
        cmd = ([mpiexec, *over, "-n", str(ranks)] if ranks > 1 else []) + base
        r = subprocess.run(cmd, capture_output=True, text=True, env=env)
        line = [s for s in r.stdout.splitlines() if s.startswith("RESULT ")]
        if r.returncode != 0 or not line:
            sys.exit(f"bench_mpi: {name} failed:\n{r.stdout[-2000:]}\n{r.stderr[-3000:]}")
        res = json.loads(line[0][len("RESULT "):])
        print(json.dumps(res), flush=True)
        rows.append((f"{ranks} rank{'s' if ranks > 1 else ''} x {threads} thread{'s' if threads > 1 else ''}", res))
    print(f"\n| configuration | particles | particle-steps/s | s/step | communication share per rank |")
    print("|---|---|---|---|---|")
    for label, res in rows:
        share = ", ".join(f"{100 * s:.1f} %" for s in res.get("comm_share_per_rank", [])) or "-"
        print(f"| {label} | {res['particles']:,} | {res['particle_steps_per_s']:.3g} | {res['s_per_step']:.3f} | {share} |")


if __name__ == "__main__":
    main()
