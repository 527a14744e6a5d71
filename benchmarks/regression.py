"""Performance regression check: the working tree against a commit, back to back on this machine.

Runs ``benchmarks/bench_dambreak.py`` (the DualSPHysics 3D dam break) on the source of a base commit
(default ``HEAD``: the working tree's uncommitted changes against the last commit; ``HEAD~1`` for the
last commit against its parent) and on the working tree, in the order base, tree, tree, base (ABBA,
repeated ``--rounds`` times), each tree's kernels compiled by a short run first, and prints the
particle-steps per second of every run and the ratio tree / base (the sum of the tree's runs over the
base's). A ratio counts only within one sitting: the 2-core machines differ by up to 2.5x from one day
to the next, and ABBA cancels a drift within the sitting to first order.

    python benchmarks/regression.py                     # uncommitted changes against HEAD
    python benchmarks/regression.py --base HEAD~1       # the last commit against its parent
    python benchmarks/regression.py --dp 0.0085 --steps 100 --precision float64
    python benchmarks/regression.py --dp 0.012 --from-checkpoint runs/db/ckpt_004100.h5   # developed flow

The base's source is exported with ``git archive`` into a temporary folder (nothing in the repository
changes); both trees are measured with the working tree's copy of ``bench_dambreak.py``, so that the
measurement itself is the same. ``--json FILE`` writes every figure.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks" / "bench_dambreak.py"


def fail(message, status=2):
    """One line on stderr, then exit (2: bad input)."""
    print(f"regression.py: error: {message}", file=sys.stderr)
    raise SystemExit(status)


def export(rev, dest):
    """Write the files of commit `rev` under `dest` (``git archive``); return the commit's hash."""
    sha = subprocess.run(["git", "rev-parse", "--verify", f"{rev}^{{commit}}"], cwd=ROOT, capture_output=True,
                         text=True)
    if sha.returncode != 0:
        fail(f"--base {rev!r} is not a commit of {ROOT} ({' '.join(sha.stderr.split()) or 'git failed'})")
    archive = Path(dest) / "base.tar"
    subprocess.run(["git", "archive", "--format=tar", "-o", str(archive), sha.stdout.strip(), "src"], cwd=ROOT,
                   check=True)
    with tarfile.open(archive) as tar:
        if hasattr(tarfile, "data_filter"):  # Python 3.11.4 and later
            tar.extractall(dest, filter="data")
        else:
            tar.extractall(dest)
    archive.unlink()
    return sha.stdout.strip()


def bench(src, args, steps, warmup):
    """One run of bench_dambreak.py with `src` first on the import path: its JSON object."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(src)] + [p for p in os.environ.get("PYTHONPATH", "")
                                                                    .split(os.pathsep) if p]))
    cmd = [sys.executable, str(BENCH), "--dp", str(args.dp), "--steps", str(steps), "--warmup", str(warmup),
           "--precision", args.precision]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    if args.from_checkpoint:
        cmd += ["--from-checkpoint", str(args.from_checkpoint)]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        tail = r.stderr.strip().splitlines()[-1:] or ["no message"]
        fail(f"bench_dambreak.py failed on {src}: {tail[0]}", status=2 if r.returncode == 2 else 1)
    return json.loads(r.stdout[r.stdout.index("{"):])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", default="HEAD", help="commit to compare the working tree with (default HEAD)")
    p.add_argument("--dp", type=float, default=0.012, help="particle spacing [m] (0.012: 68,032 particles)")
    p.add_argument("--steps", type=int, default=60, help="timed steps per run")
    p.add_argument("--warmup", type=int, default=5, help="untimed first steps of each run")
    p.add_argument("--precision", choices=["float32", "float64"], default="float32")
    p.add_argument("--threads", type=int, default=None, help="Numba threads (default: all)")
    p.add_argument("--rounds", type=int, default=1, help="ABBA rounds (default 1: four timed runs)")
    p.add_argument("--from-checkpoint", default=None, metavar="FILE",
                   help="time developed flow: every run starts from this checkpoint (bench_dambreak.py)")
    p.add_argument("--json", default=None, help="write the figures to this file")
    args = p.parse_args(argv)
    if args.rounds < 1 or args.steps < 1 or args.warmup < 1:
        fail("--rounds, --steps and --warmup must be at least 1")
    with tempfile.TemporaryDirectory(prefix="shoal-regression-") as tmp:
        sha = export(args.base, tmp)
        trees = {"base": Path(tmp) / "src", "tree": ROOT / "src"}
        for name, src in trees.items():  # compile (or load) each tree's kernels outside the timed runs
            bench(src, args, 1, 1)
        runs = []
        for _ in range(args.rounds):
            for name in ("base", "tree", "tree", "base"):
                res = bench(trees[name], args, args.steps, args.warmup)
                runs.append({"tree": name, "particle_steps_per_second": res["particle_steps_per_second"],
                             "bytes_per_particle": res["bytes_per_particle"], "particles": res["particles"]})
                print(f"{len(runs):3d}  {name:5s} {res['particle_steps_per_second']:14,.0f} particle-steps/s  "
                      f"{res['bytes_per_particle']:6.1f} B/particle", flush=True)
    total = {k: sum(r["particle_steps_per_second"] for r in runs if r["tree"] == k) for k in ("base", "tree")}
    ratio = total["tree"] / total["base"]
    print(f"tree / base ({args.base} = {sha[:10]}): {ratio:.3f}  ({runs[0]['particles']:,} particles, "
          f"{args.precision}, {args.steps} steps a run, {args.rounds} ABBA round(s))")
    if args.json:
        Path(args.json).write_text(json.dumps({"base": args.base, "base_commit": sha, "ratio": ratio,
                                               "dp": args.dp, "steps": args.steps, "precision": args.precision,
                                               "from_checkpoint": args.from_checkpoint,
                                               "runs": runs}, indent=2) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
