"""What a run needs in memory, and refusing a case that cannot fit.

The solver's arrays (`solver_bytes`, what `Model.nbytes` then counts) and
the probes' records (`probe_bytes`) are counted before a run
(`check_memory`: the memory available now, ``MemAvailable`` of
/proc/meminfo, the physical memory where that is unknown); a case whose
particles could not even be generated in this machine's memory, or whose
generation would scan too many lattice nodes, is refused before any
particle is made (`check_generation_size`, `check_count`). Each refusal is
one `InputError` line (exit status 2) saying what to change.
"""

from __future__ import annotations

import math
import os

import numpy as np

from .errors import InputError
from .physics.constants import cell_count
from .physics.spec import MOVING

BYTES_PER_PARTICLE = 600
"""Peak bytes per particle while a case is generated and run (float64 generation
arrays plus solver arrays of either precision), a deliberate over-estimate."""


def physical_memory():
    """Bytes of physical memory of this machine (0 if unknown)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 0


def check_count(n_estimate, dim):
    """Refuse (`InputError`) a particle count whose arrays cannot fit in this machine's memory."""
    mem = physical_memory()
    if mem and n_estimate * BYTES_PER_PARTICLE > 0.8 * mem:
        fit = int(0.8 * mem / BYTES_PER_PARTICLE)
        raise InputError(f"about {n_estimate:.3g} particles would be generated, needing about "
                         f"{n_estimate * BYTES_PER_PARTICLE / 2**30:.3g} GiB; this machine has "
                         f"{mem / 2**30:.1f} GiB, enough for about {fit:.2g} particles: use a larger dp")


def solver_bytes(n, dim, options, n_cells, moving=False, floating=False, open_boundaries=False):
    """Bytes the solver holds for `n` particles (what `Model.nbytes` counts
    once the integrator has allocated its state), in the options' precision.

    Per particle: positions float64 [dim]; velocity, acceleration [dim] and
    density, drho/dt, max viscous term, p/rho^2 in the working precision; kind
    (int8) and id (int32); XSPH [dim] if on; reorder scratch (float64 [dim],
    float [dim], float, int32, int8); the grid's cell, permutation and key
    (3 int32); the integrator's saved state (symplectic and
    predictor-corrector: positions float64 [dim], velocity [dim], density;
    Verlet: velocity [dim], density); with SPS turbulence, the stress (3
    components in 2D, 6 in 3D); with no-slip walls, the wall velocity
    [dim]; with moving bodies, their initial
    positions float64 [dim] and motion index (int32); with floating bodies,
    the per-particle fluid force [dim] and contact force (float64 [dim]) their
    loads are summed from; with open boundaries, each particle's zone tag and
    flag (2 int8, `shoal.particle_buffers`). Plus 4 bytes per grid cell.
    """
    f = np.dtype(options.precision).itemsize
    per = 8 * dim + f * dim * 2 + f * 4 + 1 + 4
    fixed = 0
    if options.xsph > 0:
        per += f * dim
    else:
        fixed += f * dim  # a one-row placeholder
    ntau = 3 if dim == 2 else 6
    if options.turbulence == "sps":
        per += f * ntau  # tau / rho^2
    else:
        fixed += f * ntau
    if options.no_slip:
        per += f * dim  # the no-slip wall velocity
    else:
        fixed += f * dim
    if moving:
        per += 8 * dim + 4
    if floating:
        per += f * dim + 8 * dim
    if open_boundaries:
        per += 2
    per += 8 * dim + f * dim + f + 4 + 1
    per += 12
    if options.integrator == "verlet":
        per += f * dim + f
    else:
        per += 8 * dim + f * dim + f
    return per * n + 4 * (n_cells + 2) + fixed


def probe_samples(case, spec):
    """Samples a probe takes during the run (one at t = 0, then every interval); inf past the floats."""
    n = case.end_time / spec.interval + 1e-9
    return int(math.floor(n)) + 1 if math.isfinite(n) else math.inf


def probe_record_values(case, spec):
    """(values held per sample, sample points) of a probe: what its recorder
    keeps in memory and in every checkpoint by the end of the run is
    values x samples (test-point grids: u, v, w, p, rho and the kernel sum per
    node; point probes: u, v, w, p, rho per point; gauges: the level; max-z
    and run-up gauges: z (and x, y))."""
    if spec.type == "grid":
        nodes = math.prod(spec.counts)
        return 6 * nodes, nodes
    if spec.type == "points":
        return 1 + 5 * len(spec.points), len(spec.points)
    if spec.type == "pressure":
        return 1 + len(spec.points), len(spec.points)
    if spec.type == "gauge":
        n = (spec.z1 - spec.z0) / (0.5 * case.dp)  # inf for z0 .. z1 beyond the floats (-1e308 .. 1e308)
        return 2, max(2, math.ceil(n) + 1) if math.isfinite(n) else math.inf
    if spec.type == "maxz":
        return 2, 0
    if spec.type == "runup":
        return 4, 0
    if spec.type in ("flow", "force"):
        return 4, 0
    return 0, 0  # trackers write their rows to the CSV only


def probe_bytes(case, specs=None):
    """Bytes the probes (`specs`, default all the case's) hold in memory by
    the end of the run: their sample points and sampling buffers, and the
    records they keep (a test-point grid keeps every sample, float64, for
    its NetCDF file; the CSV probes keep their rows as Python floats, about
    32 bytes a value)."""
    f = np.dtype(case.options.precision).itemsize
    total = 0
    for spec in case.probes if specs is None else specs:
        values, points = probe_record_values(case, spec)
        n = probe_samples(case, spec)
        per_value = 8 if spec.type == "grid" else 32  # float64 samples; Python floats in lists of rows
        total += values * n * per_value + points * (24 + (3 + case.dim) * f)
    return total


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


def case_cell_count(case):
    """Cells of the neighbour grid of `case` (`shoal.physics.constants.cell_count` over its domain)."""
    lo, hi = case.resolved_domain()
    axes = [0, 2] if case.dim == 2 else [0, 1, 2]
    periodic = [a in (case.domain.periodic if case.domain else ()) for a in ("x", "y", "z")]
    return cell_count(np.asarray(lo)[axes], np.asarray(hi)[axes], case.smoothing_length, case.options.cells_per_support,
                      [periodic[a] for a in axes])


def case_solver_bytes(case):
    """Bytes the solver will hold for `case` (generates its particles): rows for its particles, and with open
    boundaries room for a buffer's worth of copies (`shoal.particle_buffers.BufferZones`)."""
    p = case.particles()
    rows = len(p) + (int((p.zone >= 0).sum()) if p.zone is not None else 0)
    return solver_bytes(rows, case.dim, case.options, case_cell_count(case), moving=bool(np.any(p.kinds == MOVING)),
                        floating=any(s.floating is not None for s in case.solids),
                        open_boundaries=bool(case.open_boundaries))


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
    (`check_count`: about 600 bytes per particle,
    within 80 % of the physical memory).
    """
    from .geometry.generate import support_layers

    dim, dp = case.dim, float(case.dp)
    axes = (0, 2) if dim == 2 else (0, 1, 2)
    ext = [max(float(hi[a] - lo[a]), 0.0) for a in axes]
    nodes = math.prod(e / dp + 1.0 for e in ext)
    if any(s.boundary == "repulsive" for s in case.solids):
        nodes *= 1 + 2**dim  # a second pass at dp/2
    mem = physical_memory()
    if nodes <= NODE_LIMIT and (not mem or nodes * BYTES_PER_PARTICLE <= 0.8 * mem):
        return
    if all(math.isfinite(e) for e in ext) and math.isfinite(nodes):  # (a dp such as 5e-324: nodes overflow)
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
    samples (`probe_bytes`) exceed the memory available
    (`available` bytes, default `available_memory()`)."""
    solver = case_solver_bytes(case)
    probes = probe_bytes(case)
    need = solver + probes
    have = available_memory() if available is None else available
    if have and need > have:
        n = case.n_particles
        if probes > 0.01 * need or math.isinf(probes):
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
