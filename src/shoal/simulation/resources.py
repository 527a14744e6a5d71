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


NODE_LIMIT = 4e9
"""Most lattice nodes particle generation may scan (it visits every node of
the generation box: about 1-3 million a second, so this is most of an hour)."""

SAMPLE_NODES = 50_000
"""Nodes of the coarse lattice on which `check_generation_size` measures the
fluid volume."""


def check_generation_size(case, lo, hi):
    """Refuse (`InputError`), before any particle is generated, a case whose
    particles cannot fit in this machine's memory or whose generation box
    holds more than `NODE_LIMIT` lattice nodes: a tiny dp on a big case
    gives one line at once instead of hours of generation or an
    out-of-memory crash.

    Free when every node of the box [lo, hi] could be a particle and still
    fit. Otherwise the fluid particles are estimated from the volume of the
    fluid regions outside the solids, sampled on a coarse lattice of about
    `SAMPLE_NODES` nodes (a lower bound: walls come on top), and checked as
    the built-in cases check their counts
    (`shoal.cases._checks.check_count`: about 600 bytes per particle,
    within 80 % of the physical memory).
    """
    from ..cases._checks import BYTES_PER_PARTICLE, check_count, physical_memory
    from ..geometry.generate import support_layers

    dim, dp = case.dim, float(case.dp)
    axes = (0, 2) if dim == 2 else (0, 1, 2)
    ext = [max(float(hi[a] - lo[a]), 0.0) for a in axes]
    nodes = math.prod(e / dp + 1.0 for e in ext)
    if any(s.boundary == "repulsive" for s in case.solids):
        nodes *= 1 + 2**dim  # a second pass at dp/2
    mem = physical_memory()
    if nodes <= NODE_LIMIT and (not mem or nodes * BYTES_PER_PARTICLE <= 0.8 * mem):
        return
    if all(math.isfinite(e) for e in ext):
        # about SAMPLE_NODES sample nodes, as evenly spaced as the box allows (an axis shorter than the
        # spacing gets one node, and the others share the rest), never closer than dp
        counts = [1] * dim
        free = [k for k in range(dim) if ext[k] > 0]
        while free:
            log_step = (sum(math.log(ext[k]) for k in free) - math.log(SAMPLE_NODES)) / len(free)
            short = [k for k in free if math.log(ext[k]) < log_step]
            if not short:
                break
            for k in short:
                counts[k] = 1
                free.remove(k)
        for k in free:
            counts[k] = max(1, min(round(ext[k] / math.exp(log_step)), math.ceil(ext[k] / dp)))
        coords = [float(lo[a]) + (np.arange(c) + 0.5) * (e / c) for a, e, c in zip(axes, ext, counts)]
        grids = np.meshgrid(*coords, indexing="ij")
        pts = np.zeros((grids[0].size, 3))
        for a, g in zip(axes, grids):
            pts[:, a] = g.ravel()
        fluid = np.zeros(len(pts), bool)
        for f in case.fluids:
            fluid |= f.shape.contains(pts, dim, 0.0)
        layers = support_layers(2.0 * case.smoothing_length / dp)
        for s in case.solids:
            if s.shape.type != "mesh":  # (a winding number per sample point: too slow to be worth it here)
                fluid &= ~s.shape.contains(pts, dim, (s.layers or layers) * dp)
        check_count(int(np.count_nonzero(fluid)) * math.prod(max(1.0, e / dp) / c for e, c in zip(ext, counts)), dim)
    if nodes > NODE_LIMIT:
        size = " x ".join(f"{e:.4g}" for e in ext)
        raise InputError(f"generating the particles would scan {nodes:.3g} lattice nodes (a {size} m box at dp = "
                         f"{dp:g} m; at most {NODE_LIMIT:.0e}): use a larger dp, or a smaller domain or thinner walls")


def check_memory(case, available=None):
    """Raise `InputError` if the solver arrays of `case` and its probes'
    samples (`shoal.check.probe_bytes`) exceed the memory available
    (`available` bytes, default `available_memory()`)."""
    from ..check import probe_bytes

    solver = case_solver_bytes(case)
    probes = probe_bytes(case)
    need = solver + probes
    have = available_memory() if available is None else available
    if have and need > have:
        n = case.n_particles
        if probes > 0.01 * need:
            k, spec = max(enumerate(case.probes), key=lambda ks: probe_bytes(case, [ks[1]]))
            how = {"grid": "fewer grid nodes (counts) or a longer interval",
                   "gauge": "a shorter z0 .. z1 (sampled every dp/2)"}.get(spec.type, "fewer points or a longer interval")
            raise InputError(f"the run needs {need / 2**30:.3g} GiB ({solver / 2**30:.3g} GiB for {n:,} particles, "
                             f"{probes / 2**30:.3g} GiB for the probes' sample points and records, most of it for "
                             f"probes[{k}] ({spec.type} {spec.name!r})) but only {have / 2**30:.2f} GiB of memory is "
                             f"available here: give that probe {how}")
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
