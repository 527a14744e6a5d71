"""A kernel compiled in this process and the same kernel loaded from Numba's
on-disk cache give bitwise the same run.

Bitwise restart (issue 7) needs more than a deterministic loop: a run is
often started on a cold cache (its kernels compiled in that process) and
resumed in a new process that loads them from the cache. With LLVM's
``reassoc`` fast-math flag the two gave different rounding (a 2D dam break
differed by 2e-7 m after 2,461 steps), so ``shoal.backends.cpu.FASTMATH``
leaves it out. This test runs the same steps twice in fresh processes that
share an empty cache directory: the first compiles and writes the cache, the
second loads it; the final states must be equal bit for bit.
"""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import shoal

SRC = Path(shoal.__file__).resolve().parents[1]

SCRIPT = """
import sys, numpy as np, numba, shoal
from shoal.simulation import Simulation
case = shoal.cases.dam_break_2d(dp=0.02, end_time=1.0)
sim = Simulation(case)
sim.run(max_steps=300)
m = sim.model
order = np.argsort(m.host(m.idp))
np.savez(sys.argv[1], pos=m.host(m.pos)[order], vel=m.host(m.vel)[order], rho=m.host(m.rho)[order])
"""


def _run(cache_dir, out):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir),
               PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(out)], env=env, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return np.load(out)


def test_cold_compile_and_cache_load_give_the_same_run(tmp_path):
    cache = tmp_path / "numba-cache"
    cold = _run(cache, tmp_path / "cold.npz")
    assert any(cache.rglob("*.nbi"))  # the first process wrote the cache
    warm = _run(cache, tmp_path / "warm.npz")
    for k in ("pos", "vel", "rho"):
        assert np.array_equal(cold[k], warm[k]), k
