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
    components in 2D, 6 in 3D); with moving bodies, their initial
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
    if moving:
        per += 8 * dim + 4
    per += 8 * dim + f * dim + f + 4 + 1
    per += 12
    if options.integrator == "verlet":
        per += f * dim + f
    else:
        per += 8 * dim + f * dim + f
    return per * n + 4 * (n_cells + 2) + fixed


def check_case(case):
    """Lines describing `case`: particles, memory, time step, output size."""
    p = case.particles()
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
    steps = math.ceil(case.end_time / dt)
    snaps = int(math.floor(case.end_time / case.output.interval + 1e-9)) + 1
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
    lines.append(f"  memory: {mem / 2**20:,.1f} MiB for the solver ({mem / n:.0f} B/particle)"
                 + (f"; this machine has {mem_host / 2**30:.1f} GiB" if mem_host else ""))
    lines.append(f"  time step: {dt:.3g} s ({'fixed' if o.fixed_dt else f'CFL {o.cfl}, acoustic limit at rest'})"
                 f"; about {steps:,} steps to t = {case.end_time:g} s")
    lines.append(f"  output: {snaps} snapshots every {case.output.interval:g} s, about "
                 f"{snaps * n * VTU_BYTES_PER_PARTICLE / 2**20:.3g} MiB")
    if case.motions:
        lines.append("  motions: " + ", ".join(f"{m.name} ({m.type})" for m in case.motions))
    return lines
