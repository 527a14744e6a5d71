"""``shoal check``: what a case will cost before it runs.

Generates the particles (so every geometry error shows up now), then
reports the counts by kind and by solid, the memory the solver will hold,
the first time step, the number of steps and the output size -- without
compiling or running anything.
"""

from __future__ import annotations

import math

import numpy as np

from .cases._checks import physical_memory

VTU_BYTES_PER_PARTICLE = 84
"""Bytes per particle of one VTU snapshot (binary appended data: positions
and velocity 3 x float64, density and pressure float64, id and kind int32,
connectivity, offsets and cell types; measured on written files: 80-84)."""


def solver_bytes(n, dim, options, n_cells, moving=False):
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
    positions float64 [dim] and motion index (int32). Plus 4 bytes per grid
    cell.
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
    per += 8 * dim + f * dim + f + 4 + 1
    per += 12
    if options.integrator == "verlet":
        per += f * dim + f
    else:
        per += 8 * dim + f * dim + f
    return per * n + 4 * (n_cells + 2) + fixed


def probe_samples(case, spec):
    """Samples a probe takes during the run (one at t = 0, then every interval)."""
    return int(math.floor(case.end_time / spec.interval + 1e-9)) + 1


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
        return 2, max(2, math.ceil((spec.z1 - spec.z0) / (0.5 * case.dp)) + 1)
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


def check_probes(case, n_particles):
    """`InputError` for a probe that would measure nothing: a point, gauge,
    grid node or tracker start outside the computational domain, a run-up
    range that misses it, a tracked id that is no particle."""
    from .errors import InputError

    lo, hi = case.resolved_domain()
    axes = (0, 2) if case.dim == 2 else (0, 1, 2)
    flat = (0,) if case.dim == 2 else (0, 1)
    dom = " x ".join(f"[{lo[a]:.4g}, {hi[a]:.4g}]" for a in axes) + (" m (x, z)" if case.dim == 2 else " m (x, y, z)")
    tol = 1e-9 * max(1.0, float(np.max(np.abs(np.concatenate([lo, hi])))))

    def outside(pt, which=axes):
        return any(not (lo[a] - tol <= pt[a] <= hi[a] + tol) for a in which)

    for i, pr in enumerate(case.probes):
        where = f"probes[{i}] ({pr.type} {pr.name!r})"
        if pr.type in ("points", "tracker", "pressure"):
            pts = pr.start if pr.type == "tracker" else pr.points
            for k, pt in enumerate(pts):
                if outside(pt):
                    key = "start" if pr.type == "tracker" else "points"
                    raise InputError(f"{where}: {key}[{k}] = {list(pt)} lies outside the domain {dom}; a probe must "
                                     "lie inside it")
            bad = [j for j in getattr(pr, "ids", []) if j >= n_particles]
            if bad:
                raise InputError(f"{where}: ids {bad[:5]} are no particles; the case has {n_particles:,} "
                                 f"(ids 0 to {n_particles - 1:,})")
        elif pr.type in ("gauge", "maxz"):
            if outside((pr.x, pr.y, 0.0), flat):
                xy = f"x = {pr.x:g}" + (f", y = {pr.y:g}" if case.dim == 3 else "")
                raise InputError(f"{where}: {xy} lies outside the domain {dom}; a gauge must stand inside it")
            if pr.type == "gauge" and (pr.z1 < lo[2] or pr.z0 > hi[2]):
                raise InputError(f"{where}: z0 .. z1 = {pr.z0:g} .. {pr.z1:g} m misses the domain's z range "
                                 f"[{lo[2]:.4g}, {hi[2]:.4g}] m")
        elif pr.type == "grid":
            for a, (node_axis, name) in enumerate(zip(pr.axes(), "xyz")):
                if a in axes and (node_axis.min() < lo[a] - tol or node_axis.max() > hi[a] + tol):
                    raise InputError(f"{where}: its nodes reach {name} = [{node_axis.min():.4g}, "
                                     f"{node_axis.max():.4g}] m, outside the domain {dom}; a grid must lie inside it")
        elif pr.type == "flow":
            a = "xyz".index(pr.axis)
            if case.dim == 2 and pr.axis == "y":
                raise InputError(f"{where}: axis = 'y' in a 2D run (the x-z plane); allowed 'x' or 'z'")
            if not lo[a] - tol <= pr.at <= hi[a] + tol:
                raise InputError(f"{where}: the section {pr.axis} = {pr.at:g} m lies outside the domain {dom}")
            if pr.lo is not None and pr.hi is not None:
                for k in axes:
                    if k != a and pr.hi[k] == pr.lo[k]:
                        raise InputError(f"{where}: lo[{k}] = hi[{k}] = {pr.lo[k]:g} m: the section has no extent in "
                                         f"{'xyz'[k]}; give hi[{k}] > lo[{k}], or leave lo and hi out")
        elif pr.type == "force":
            names = [s.name for s in case.solids]
            if pr.solid not in names:
                raise InputError(f"{where}: solid = {pr.solid!r} is none of the case's solids; allowed: "
                                 + ", ".join(repr(n) for n in names))
            if case.solids[names.index(pr.solid)].boundary != "dynamic":
                raise InputError(f"{where}: solid {pr.solid!r} has repulsive (Monaghan-Kajtar) boundary particles; "
                                 "force gauges measure solids of dynamic boundary particles (boundary = 'dynamic')")
        elif pr.type == "runup":
            if pr.x1 < lo[0] or pr.x0 > hi[0] or (case.dim == 3 and outside((0.0, pr.y, 0.0), (1,))):
                raise InputError(f"{where}: x0 .. x1 = {pr.x0:g} .. {pr.x1:g} m"
                                 + (f" at y = {pr.y:g} m" if case.dim == 3 else "")
                                 + f" misses the domain {dom}")


def check_case(case):
    """Lines describing `case`: particles, memory, time step, output size,
    checkpoint size. Raises `InputError` for what would stop the run: a
    geometry error, a probe outside the domain, a missing motion file, more
    memory than this machine has."""
    from .simulation.checkpoint import CHECKPOINT_OVERHEAD, checkpoint_bytes
    from .simulation.resources import check_memory

    p = case.particles()
    check_probes(case, len(p))
    for m in case.motions:
        m.kinematics(0.0)  # reads a time-series file now: a missing or bad one is an error here, not in the run
    lo, hi = case.resolved_domain()
    o = case.options
    dim = case.dim
    h = case.smoothing_length
    g = float(np.linalg.norm(case.fluid.gravity))
    u = case.fluid.u_max if case.fluid.u_max is not None else math.sqrt(g * case.fluid.depth)
    c0 = o.coef_sound * u
    cell = 2 * h / o.cells_per_support
    axes = [0, 2] if dim == 2 else [0, 1, 2]
    n_cells = int(np.prod([max(1, math.ceil((hi[a] - lo[a]) / cell)) for a in axes]))
    n = len(p)
    mem = solver_bytes(n, dim, o, n_cells, moving=bool(np.any(p.kinds == 2)))
    dt_c = o.cfl * h / c0
    dt_g = o.cfl * math.sqrt(h / g) if g > 0 else math.inf
    dt = o.fixed_dt if o.fixed_dt is not None else min(dt_c, dt_g)
    steps = case.end_time / dt if dt > 0 else math.inf
    # a snapshot every interval, at most one a step (inf and huge counts are printed, not turned into ints)
    snaps = min(case.end_time / case.output.interval + 1e-9, steps) + 1
    snaps = math.floor(snaps) if snaps < 1e15 else snaps
    steps = math.ceil(steps) if steps < 1e15 else steps
    counts = p.counts()
    lines = [f"case {case.name}: {case.description}" if case.description else f"case {case.name}",
             f"  {dim}D, dp = {case.dp:g} m, h = {h:.4g} m ({o.kernel}), c0 = {c0:.4g} m/s, "
             f"{o.integrator}, {o.precision}",
             f"  particles: {n:,} = {counts['fluid']:,} fluid + {counts['fixed']:,} fixed boundary + "
             f"{counts['moving']:,} moving boundary"]
    for k, s in enumerate(case.solids):
        nk = int(np.count_nonzero(p.body == k))
        desc = f"{s.boundary}" + (f", {s.layers} layers" if s.layers else "") + \
            (f", moved by {s.motion!r}" if s.motion else "")
        lines.append(f"    solids[{k}] {s.name or s.shape.type}: {nk:,} particles ({s.shape.type}, {desc})")
    lines.append("  domain: " + " x ".join(f"[{lo[a]:.4g}, {hi[a]:.4g}]" for a in axes) + " m"
                 + ("  (x, z)" if dim == 2 else "  (x, y, z)"))
    mem_host = physical_memory()
    if mem_host:
        check_memory(case, available=mem_host)  # the run could not fit on this machine at all
    pmem = probe_bytes(case)
    lines.append(f"  memory: {mem / 2**20:,.1f} MiB for the solver ({mem / n:.0f} B/particle)"
                 + (f" + {pmem / 2**20:,.3g} MiB for the probes' samples" if pmem >= 2**20 else "")
                 + (f"; this machine has {mem_host / 2**30:.1f} GiB" if mem_host else ""))
    lines.append(f"  time step: {dt:.3g} s ({'fixed' if o.fixed_dt else f'CFL {o.cfl}, acoustic limit at rest'})"
                 f"; about {steps:,} steps to t = {case.end_time:g} s")
    lines.append(f"  output: {snaps:,} snapshots every {case.output.interval:g} s, about "
                 f"{snaps * n * VTU_BYTES_PER_PARTICLE / 2**20:.3g} MiB")
    moving = bool(np.any(p.kinds == 2))
    records = sum(probe_record_values(case, s)[0] * probe_samples(case, s) for s in case.probes if s.type != "tracker")
    from .casefile import dumps_case

    toml = len(dumps_case(case, file_name="case.toml").encode("utf-8"))  # each checkpoint holds the case file
    ck = checkpoint_bytes(n, dim, o, moving, case_bytes=toml)
    ck_end = checkpoint_bytes(n, dim, o, moving, records, case_bytes=toml)
    cfg = case.checkpoint
    when = ([f"every {cfg.interval:g} s"] if cfg.interval > 0 else []) + \
        ([f"every {cfg.wall_interval:g} s of wall-clock time"] if cfg.wall_interval > 0 else []) + ["at the end"]
    lines.append(f"  checkpoints: {ck / 2**20:.3g} MiB each ({(ck - CHECKPOINT_OVERHEAD - toml) / n:.0f} B/particle"
                 + (f"; {ck_end / 2**20:.3g} MiB by the end with the probes' records" if ck_end > 1.01 * ck else "")
                 + f"), {', '.join(when)}; the newest {cfg.keep} kept: up to {cfg.keep * ck_end / 2**20:.3g} MiB")
    if case.motions:
        lines.append("  motions: " + ", ".join(f"{m.name} ({m.type})" for m in case.motions))
    from .advice import wave_scheme_warnings

    lines += [f"  warning: {w}" for w in wave_scheme_warnings(case)]
    return lines
