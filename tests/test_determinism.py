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
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), NUMBA_DEBUG_CACHE="1",
               PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(out)], env=env, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return np.load(out), proc.stdout


def test_cold_compile_and_cache_load_give_the_same_run(tmp_path):
    cache = tmp_path / "numba-cache"
    cold, _ = _run(cache, tmp_path / "cold.npz")
    assert any(cache.rglob("*.nbi"))  # the first process wrote the cache
    warm, log = _run(cache, tmp_path / "warm.npz")
    # the second process compiled nothing: every kernel's cache key (which pickles the functions
    # it calls) is the same in a new process
    saved = [line for line in log.splitlines() if "data saved" in line]
    assert not saved, saved[:3]
    assert "data loaded" in log
    for k in ("pos", "vel", "rho"):
        assert np.array_equal(cold[k], warm[k]), k


def test_each_kernel_has_its_own_cache_entry():
    """Every distinct loop kernel has its own name in Numba's on-disk cache, the same in every
    build: kernels that differ never share an index file, so processes compiling different schemes
    at once (the MPI ranks of a test, a parameter sweep) cannot hand each other's machine code to a
    later run. Schemes that build a kernel alike share it, and its name (`shoal.physics.identity`):
    the pr2 loop reads the precision only."""
    from shoal.backends.cpu import CPUBackend
    from shoal.options import SPHOptions
    from shoal.physics.spec import SchemeSpec

    names = {}
    for dim in (2, 3):
        for precision in ("float32", "float64"):
            spec = SchemeSpec.from_options(SPHOptions(precision=precision), dim)
            a, b = CPUBackend(spec), CPUBackend(spec)
            for k in ("rates", "pr2", "verlet"):
                qa, qb = getattr(a, k).py_func.__qualname__, getattr(b, k).py_func.__qualname__
                assert qa == qb  # stable: the cache is found again
                names[(dim, precision, k)] = qa
    distinct = {key: name for key, name in names.items() if key[2] != "pr2"}
    assert len(set(distinct.values())) == len(distinct)
    for precision in ("float32", "float64"):
        assert names[(2, precision, "pr2")] == names[(3, precision, "pr2")]
    assert names[(2, "float32", "pr2")] != names[(2, "float64", "pr2")]
    assert not set(distinct.values()) & {names[(2, p, "pr2")] for p in ("float32", "float64")}
