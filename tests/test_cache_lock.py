"""Processes sharing one Numba cache directory keep every entry, each pointing at its own code.

`shoal.cache_lock` makes each read-modify-write of a cache index atomic. Here
six processes each compile the six specialisations of one ``cache=True``
function, in six rotated orders, starting together on one cache directory, on a
file system made slow (0.5 s to write an index), so different signatures are
saved at the same moment. Afterwards the index must
hold all six signatures, and a fresh process must load each of them without
compiling and compute the right result with it (an entry naming another
signature's data file would run code compiled for other types: a wrong value, or a crash). Unlocked,
Numba's index keeps only the last writer's view: entries go missing.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(not hasattr(os, "fork") or sys.platform == "win32",
                                reason="flock is POSIX only")

MODULE = '''
import numba

@numba.njit(cache=True)
def twice_plus(x, y):
    s = x
    for _ in range(3):
        s = s + y
    return s + x - y - y - y
'''

# six argument pairs: six specialisations of twice_plus, each with its own exact result 2x
ARGS = ["(3, 4)", "(3.5, 4.0)", "(numba.float32(1.5), numba.float32(2.0))", "(2 + 1j, 1j)",
        "(np.int32(7), np.int32(1))", "(np.arange(3.0), np.ones(3))"]

WORKER = '''
import os, sys, time
import numpy as np
import numba
import shoal  # installs the lock
import shared_mod
from numba.core.caching import IndexDataCacheFile

# a slow file system: 0.5 s between reading an index and writing it back, so that unlocked
# processes would overwrite each other's entries
_save_index = IndexDataCacheFile._save_index
def slow_save_index(self, overloads):
    time.sleep(0.5)
    _save_index(self, overloads)
IndexDataCacheFile._save_index = slow_save_index

args = [{args}]
start = float(sys.argv[2])
while time.time() < start:
    time.sleep(0.001)
k = int(sys.argv[1])
for a in args[k:] + args[:k]:
    shared_mod.twice_plus(*a)
'''

CHECK = '''
import numpy as np
import numba
import shoal
import shared_mod
args = [{args}]
for a in args:
    r = shared_mod.twice_plus(*a)
    assert np.shape(r) == np.shape(a[0]) and np.all(r == 2 * a[0]), (a, r)
print("loaded", len(shared_mod.twice_plus.stats.cache_hits), "compiled", len(shared_mod.twice_plus.stats.cache_misses))
'''


def test_concurrent_processes_keep_every_entry(tmp_path):
    import time

    (tmp_path / "shared_mod.py").write_text(MODULE)
    args = ", ".join(ARGS)
    (tmp_path / "worker.py").write_text(textwrap.dedent(WORKER.format(args=args)))
    (tmp_path / "check.py").write_text(textwrap.dedent(CHECK.format(args=args)))
    cache = tmp_path / "cache"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), PYTHONPATH=os.pathsep.join(
        [str(tmp_path)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    env.pop("NUMBA_DISABLE_JIT", None)
    start = time.time() + 8.0  # every worker has imported numba and shoal by then
    procs = [subprocess.Popen([sys.executable, str(tmp_path / "worker.py"), str(k), str(start)], env=env,
                              stderr=subprocess.PIPE) for k in range(len(ARGS))]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err.decode()[-2000:]

    (index,) = cache.rglob("*twice_plus*.nbi")
    with open(index, "rb") as f:
        pickle.load(f)  # Numba's version
        _stamp, overloads = pickle.loads(f.read())
    assert len(overloads) == len(ARGS), f"{len(overloads)} of {len(ARGS)} entries in the index"
    assert len(set(overloads.values())) == len(ARGS)  # each entry its own data file

    out = subprocess.run([sys.executable, str(tmp_path / "check.py")], env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["loaded", str(len(ARGS)), "compiled", "0"], out.stdout
