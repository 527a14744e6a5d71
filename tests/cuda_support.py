"""Shared helpers for the CUDA tests: run on a GPU, or under Numba's CUDA simulator.

The simulator must be chosen before `numba.cuda` is first imported, which in a
normal `pytest` run has already happened (or may happen) in another test module.
So when this process has neither a GPU nor the simulator, each CUDA test module
has one test, `run_module_under_simulator`, that runs the module again in a
child `pytest` with ``NUMBA_ENABLE_CUDASIM=1`` (the child sees the variable and
never starts another child).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

SIMULATOR = os.environ.get("NUMBA_ENABLE_CUDASIM") == "1"


def _have_gpu():
    if SIMULATOR:
        return False
    try:
        from numba import cuda

        return bool(cuda.is_available())
    except Exception:  # no driver, no toolkit
        return False


HAVE_CUDA = SIMULATOR or _have_gpu()

needs_cuda = pytest.mark.skipif(not HAVE_CUDA, reason="needs a GPU or NUMBA_ENABLE_CUDASIM=1 (the module's "
                                "simulator-run test runs it under the simulator in a child process)")


def run_module_under_simulator(test_file, runner_name, timeout=1800, kernel_log=None):
    """Run `test_file` (minus `runner_name`) under the simulator in a child pytest.

    The parity module takes about 30 s under the simulator on a 2-core machine (its barrier-free
    kernels run in one thread and the radix sort's on a pool of threads, `shoal.backends.simulator`;
    about 100 s with the simulator's thread per GPU thread, 5 minutes without a short GIL switch
    interval either); the child gets 30 minutes before it counts as failed. With `kernel_log` (a path) the child logs
    every kernel launch there (`cuda_kernels.record`)."""
    if HAVE_CUDA:
        pytest.skip("CUDA (or the simulator) is available here: the tests run in this process")
    import shoal

    src = str(Path(shoal.__file__).resolve().parents[1])
    import numba

    # the child shares the cores as this process does (one thread per xdist worker: conftest.py)
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", NUMBA_NUM_THREADS=str(numba.get_num_threads()))
    if kernel_log:
        env["SHOAL_CUDA_KERNEL_LOG"] = str(kernel_log)
    env["PYTHONPATH"] = os.pathsep.join([src] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    here = Path(test_file).resolve()
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", str(here), "-q", "-s", "-p", "no:cacheprovider", "-k", f"not {runner_name}"],
        cwd=here.parents[1], env=env, capture_output=True, text=True, timeout=timeout)
    out = proc.stdout + proc.stderr
    print(out[-3000:])
    assert proc.returncode == 0, f"simulator run failed:\n{out}"
    assert " passed" in out and "skipped" not in out and "failed" not in out, out
