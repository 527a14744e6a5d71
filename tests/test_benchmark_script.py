"""The engine benchmark script (`benchmarks/bench_dambreak.py`), which the GPU session of issue 3 runs
unattended: one JSON object whose counts are the case's, and bad input as a one-line error, exit 2."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_dambreak.py"


def run(*args):
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, env=env,
                          timeout=600)


def test_bench_reports_the_case_it_ran():
    from shoal.cases import dam_break_dualsphysics

    out = run("--dp", "0.03", "--steps", "3", "--warmup", "1")
    assert out.returncode == 0, out.stderr[-2000:]
    r = json.loads(out.stdout)
    case = dam_break_dualsphysics(dp=0.03, precision="float32")
    assert r["particles"] == case.n_particles and r["fluid_particles"] == case.n_fluid
    assert r["steps"] == 3 and r["force_evaluations"] == 3  # Verlet: one force evaluation a step
    assert abs(r["particle_steps_per_second"] * r["wall_seconds"] - 3 * r["particles"]) < 1e-3 * 3 * r["particles"]
    # float32 state: at least position, velocity (3 x 4 B each), density, rates (3 + 1 floats) per particle
    assert 44 <= r["bytes_per_particle"] < 400
    assert "device_bytes" not in r  # only measured on a GPU


def test_bench_bad_input_is_one_line_exit_2():
    out = run("--dp", "0.05", "--steps", "1")
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("bench_dambreak: error: dp = 0.05 m is too coarse")
    assert out.stdout == ""


def test_bench_from_a_checkpoint_times_the_run_where_it_stopped(tmp_path):
    """``--from-checkpoint`` (issue 34, developed flow): the timed steps continue a run of the same case from its
    checkpoint, so the simulated time starts at the checkpoint's; a checkpoint of another case (another dp) is
    refused in one line, exit 2."""
    from shoal.simulation.checkpoint import list_checkpoints

    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    made = subprocess.run([sys.executable, "-m", "shoal", "run", "dam-break-dualsphysics", "--dp", "0.03",
                           "--end-time", "0.01", "--checkpoint-interval", "0.01", "--output-interval", "0.01",
                           "--out", str(tmp_path / "db"), "--no-progress", "--no-plot"],
                          capture_output=True, text=True, env=env, timeout=600)
    assert made.returncode == 0, made.stderr[-2000:]
    ck = list_checkpoints(tmp_path / "db")[0]  # the newest
    out = run("--dp", "0.03", "--steps", "2", "--warmup", "1", "--from-checkpoint", str(ck))
    assert out.returncode == 0, out.stderr[-2000:]
    r = json.loads(out.stdout)
    assert r["start_time"] >= 0.01 and r["simulated_time"] > r["start_time"]
    out = run("--dp", "0.025", "--steps", "1", "--from-checkpoint", str(ck))
    assert out.returncode == 2 and out.stderr.count("\n") == 1, out.stderr
    assert out.stderr.startswith("bench_dambreak: error: ") and "particles" in out.stderr


REGRESSION = SCRIPT.parent / "regression.py"


def test_regression_script_runs_base_and_tree_abba(tmp_path):
    """`benchmarks/regression.py` (issue 34 item 5): the base commit (here HEAD) and the working tree,
    compiled by a first run each, then timed base, tree, tree, base; the ratio printed is the sum of the
    tree's particle-steps/s over the base's."""
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=SCRIPT.parents[1], capture_output=True, text=True)
    if head.returncode != 0:
        pytest.skip("not a git checkout: the script compares with a commit")
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    out = subprocess.run([sys.executable, str(REGRESSION), "--dp", "0.03", "--steps", "2", "--warmup", "1",
                          "--json", str(tmp_path / "r.json")], capture_output=True, text=True, env=env, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    r = json.loads((tmp_path / "r.json").read_text())
    assert r["base_commit"] == head.stdout.strip()
    assert [x["tree"] for x in r["runs"]] == ["base", "tree", "tree", "base"]
    speeds = {k: sum(x["particle_steps_per_second"] for x in r["runs"] if x["tree"] == k) for k in ("base", "tree")}
    assert r["ratio"] == speeds["tree"] / speeds["base"]
    assert f"tree / base (HEAD = {r['base_commit'][:10]}): {r['ratio']:.3f}" in out.stdout
    assert len({x["particles"] for x in r["runs"]}) == 1


def test_regression_script_bad_base_is_one_line_exit_2():
    out = subprocess.run([sys.executable, str(REGRESSION), "--base", "no-such-rev-x", "--dp", "0.03"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert out.stderr.startswith("regression.py: error: --base 'no-such-rev-x' is not a commit")


def test_the_spheric_benchmark_times_developed_flow_after_a_run_from_rest():
    """``--case spheric-benchmark --developed-from T`` (issue 34): SPHERIC Test 2 with the cross-code benchmark's
    settings, run from rest to T in the same process before the timed steps, which then start at the first step
    past T; the run from rest is reported apart. A negative T is refused in one line, exit 2."""
    from shoal.cases import spheric_benchmark

    out = run("--case", "spheric-benchmark", "--dp", "0.04", "--steps", "2", "--warmup", "1",
              "--developed-from", "0.01")
    assert out.returncode == 0, out.stderr[-2000:]
    r = json.loads(out.stdout)
    case = spheric_benchmark(dp=0.04)
    assert r["case"] == "spheric-benchmark" and r["particles"] == case.n_particles
    assert r["advance_steps"] >= 1 and 0.01 <= r["start_time"] < r["simulated_time"]
    assert abs(r["ms_per_step"] - 1e3 * r["wall_seconds"] / 2) < 1e-9 * r["ms_per_step"]
    bad = run("--case", "spheric-benchmark", "--dp", "0.04", "--developed-from", "-0.5")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--developed-from" in bad.stderr
