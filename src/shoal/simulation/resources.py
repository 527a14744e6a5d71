"""Before a run: will it fit in memory? During it: a full disk.

`check_memory` refuses (`InputError`, exit status 2) a case whose solver
arrays (`shoal.check.solver_bytes`, what `Model.nbytes` then counts) exceed
the memory available now (``MemAvailable`` of /proc/meminfo; the physical
memory where that is unknown). `disk_full_message` words an ENOSPC/EDQUOT
error for the user; `lock_run_dir` keeps two processes out of one run
directory.
"""

from __future__ import annotations

import errno
import math
import os

import numpy as np

from ..errors import InputError

DISK_FULL = (errno.ENOSPC, errno.EDQUOT)


def available_memory():
    """Bytes of memory available to a new run now (0 if unknown):
    ``MemAvailable`` from /proc/meminfo, else the physical memory."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 0


def case_solver_bytes(case):
    """Bytes the solver will hold for `case` (generates its particles)."""
    from ..check import solver_bytes

    p = case.particles()
    lo, hi = case.resolved_domain()
    o = case.options
    cell = 2 * case.smoothing_length / o.cells_per_support
    axes = [0, 2] if case.dim == 2 else [0, 1, 2]
    n_cells = int(np.prod([max(1, math.ceil((hi[a] - lo[a]) / cell)) for a in axes]))
    return solver_bytes(len(p), case.dim, o, n_cells, moving=bool(np.any(p.kinds == 2)))


def check_memory(case, available=None):
    """Raise `InputError` if the solver arrays of `case` exceed the memory
    available (`available` bytes, default `available_memory()`)."""
    need = case_solver_bytes(case)
    have = available_memory() if available is None else available
    if have and need > have:
        n = case.n_particles
        raise InputError(f"the run needs {need / 2**30:.2f} GiB for {n:,} particles but only {have / 2**30:.2f} GiB "
                         f"of memory is available here: use a larger dp (memory grows as dp^-{case.dim}), "
                         "or free memory")
    return need


def lock_run_dir(out_dir):
    """Hold an exclusive lock on ``out_dir/.shoal.lock`` (flock) for the
    run: a second shoal process in the same directory (a job submitted
    twice, a ``--resume`` while the run is still going) is refused with
    `InputError`. Returns the open lock file; closing it releases the lock
    (the process ending does too, however it ends)."""
    import fcntl

    path = os.path.join(out_dir, ".shoal.lock")
    f = open(path, "a+")
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.seek(0)
        pid = f.read().strip()
        f.close()
        raise InputError(f"another shoal process{f' (pid {pid})' if pid else ''} is running in {out_dir}; "
                         "wait for it to end or stop it (SIGTERM writes a checkpoint) before running or "
                         "resuming there") from None
    except OSError:
        return f  # a file system without locks: run unlocked
    f.seek(0)
    f.truncate()
    f.write(f"{os.getpid()}\n")
    f.flush()
    return f


def disk_full_message(err, out_dir, checkpoint=None):
    """One line for a write that failed with ENOSPC/EDQUOT."""
    what = "no space left on device" if err.errno == errno.ENOSPC else "disk quota exceeded"
    where = f" writing {err.filename}" if getattr(err, "filename", None) else f" writing to {out_dir}"
    then = (f"; resume from {checkpoint.name} with `shoal run --resume {out_dir}` once space is freed"
            if checkpoint is not None else "; free space and run again")
    return f"{what}{where}: the run stopped, files already written are intact{then}"
