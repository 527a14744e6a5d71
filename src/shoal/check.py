"""``shoal check``: what a case will cost before it runs.

Generates the particles (so every geometry error shows up now), then
reports the counts by kind and by solid, the memory the solver will hold,
the first time step, the number of steps and the output size -- without
compiling or running anything.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import InputError
from .motions import check_motion_speeds
from .memory import case_cell_count, physical_memory, probe_bytes, probe_record_values, probe_samples, solver_bytes
from .physics.constants import speed_of_sound
from .physics.spec import MOVING
from .probes.placement import check_buried_probes, check_probes

VTU_BYTES_PER_PARTICLE = 84
"""Bytes per particle of one VTU snapshot (binary appended data: positions
and velocity 3 x float64, density and pressure float64, id and kind int32,
connectivity, offsets and cell types; measured on written files: 80-84)."""


def check_relaxation_zones(case, lo, hi):
    """Refuse a relaxation zone (`shoal.relaxation.RelaxationZone`) that lies outside the domain's x range
    [`lo`, `hi`] (`InputError`): it would relax nothing."""
    for i, zone in enumerate(case.relaxation):
        if zone.hi <= lo[0] or zone.lo >= hi[0]:
            raise InputError(f"relaxation[{i}]: the zone x = {zone.start:g} .. {zone.end:g} m lies outside the "
                             f"domain's x = [{lo[0]:.4g}, {hi[0]:.4g}] m and would relax nothing; put it inside")


def floating_lines(case):
    """Lines giving each floating body's mass, volume, centre of gravity, inertia, constraints, friction
    coefficient, release time (2D: per metre of width), from its lattice nodes and the values the case gives (`shoal.floating.FloatingBody`)."""
    from .geometry.generate import solid_nodes

    lines = []
    inputs = case.solid_inputs()
    unit = "/m" if case.dim == 2 else ""
    for k, s in enumerate(case.solids):
        f = s.floating
        if f is None:
            continue
        nodes = solid_nodes(case.dim, case.dp, inputs, k, case.lattice_origin)
        if len(nodes) == 0:
            raise InputError(f"solids[{k}] ({s.name or s.shape.type}) floats but holds no lattice node at dp = "
                             f"{case.dp:g} m: make it larger or dp smaller")
        mp = f.mass_properties(nodes, case.dp, case.dim)
        volume = len(nodes) * case.dp ** case.dim
        inertia = (f"inertia about y {mp.inertia[1, 1]:.4g}" if case.dim == 2 else "principal inertia " +
                   ", ".join(f"{v:.4g}" for v in np.linalg.eigvalsh(0.5 * (mp.inertia + mp.inertia.T))))
        c = ", ".join(f"{v:.4g}" for v in mp.centre)
        held = f.fixed or []
        how = (f"hinged about {list(f.hinge.axis)} through {list(f.hinge.point)}" if f.hinge is not None else
               f"fixed {', '.join(held)}" if held else "free")
        size = f"area {volume:.4g} m^2" if case.dim == 2 else f"volume {volume:.4g} m^3"
        lines.append(f"  floating {s.name or f'solids[{k}]'}: mass {mp.mass:.4g} kg{unit}, {size} "
                     f"(density {mp.mass / volume:.4g} kg/m^3), centre of gravity "
                     f"({c}) m, {inertia} kg m^2{unit}; {how}" + (f"; friction {f.friction:g}" if f.friction else "") +
                     (f"; held until t = {f.release_time:g} s" if f.release_time else ""))
    return lines


def open_boundary_lines(case):
    """Lines giving each open boundary's plane, buffer and flow (`shoal.open_boundary.OpenBoundary`): the
    discharge an imposed velocity brings in, as particles a second, and what that adds to the particle count
    and the solver's memory over the run were none to leave (the count's ceiling while a channel fills)."""
    from .memory import case_solver_bytes

    lines = []
    support = 2.0 * case.smoothing_length
    p = case.particles()
    per = case_solver_bytes(case) / len(p)
    for k, ob in enumerate(case.open_boundaries):
        n_buf = int((p.zone == k).sum())
        where = f"{'xy'[ob.axis]} = {ob.point[ob.axis]:g} m, normal {list(ob.normal)}"
        head = f"  open boundary {ob.name}: {where}, buffer {n_buf} particles in {ob.buffer_layers(support, case.dp)} rows"
        z = p.positions[p.zone == k, 2]
        u = ob.speed(z, case.dim)
        level = ob.level_bounds(0.0, case.end_time)
        if level is not None and level[0] != level[1]:
            head += f"; level from {level[0]:g} to {level[1]:g} m over the run (a time series)"
        if ob.follows_water:
            head += f"; level {ob.level:g} m at the start, then the water's next to the plane"
        if ob.holds_level:
            held = f"the level {level[0]:g} m" if level[0] == level[1] else "it"
            lines.append(head + f"; holds {held} (velocity from the Riemann invariant, mean over "
                                f"{ob.relaxation_time:g} s): its inflow is what the flow draws, not known before the run")
            continue
        if u is None:
            lines.append(head + "; velocity from the water inside (an outlet)")
            continue
        # the largest inflow of the run: a series' largest speed or discharge over the widest wet section
        top = level[1] if level is not None else None
        wet = ob.model_copy(update={"level": top}).wet_area(case.dim) if top is not None else ob.wet_area(case.dim)
        inflow = ob.inflow_bounds(0.0, case.end_time)
        if inflow is None:
            q = float(np.mean(u)) * ob.wet_area(case.dim)
        else:
            q = inflow[1] * (wet if ob.velocity is not None else 1.0)
        rate = q / case.dp ** case.dim  # particles a second through the plane
        unit = "m^2/s" if case.dim == 2 else "m^3/s"
        more = rate * case.end_time
        what = "inflow" if inflow is None or inflow[0] == inflow[1] else "largest inflow"
        lines.append(head + f"; {what} {q:.4g} {unit} ({rate:.4g} particles/s): at most {more:,.0f} more particles "
                            f"by t = {case.end_time:g} s, {more * per / 2**20:.3g} MiB more memory if none leaves")
    return lines


def check_case(case):
    """Lines describing `case`: particles, memory, time step, output size,
    checkpoint size. Raises `InputError` for what would stop the run: a
    geometry error, a probe outside the domain, a missing motion file, more
    memory than this machine has."""
    from .simulation.checkpoint import CHECKPOINT_OVERHEAD, checkpoint_bytes
    from .memory import check_memory

    case.revalidate()
    p = case.particles()
    check_probes(case, len(p))
    check_buried_probes(case)
    for m in case.motions:
        m.kinematics(0.0)  # reads a time-series file now: a missing or bad one is an error here, not in the run
    check_motion_speeds(case.motions, case.sound_speed, case.end_time, case.motion_reach())
    lo, hi = case.resolved_domain()
    check_relaxation_zones(case, lo, hi)
    o = case.options
    dim = case.dim
    h = case.smoothing_length
    g = float(np.linalg.norm(case.fluid.gravity))
    c0 = speed_of_sound(o.coef_sound, case.fluid.gravity, case.fluid.depth, case.fluid.u_max)
    axes = [0, 2] if dim == 2 else [0, 1, 2]
    n_cells = case_cell_count(case)
    n = len(p)
    mem = solver_bytes(n, dim, o, n_cells, moving=bool(np.any(p.kinds == MOVING)),
                       floating=any(s.floating is not None for s in case.solids))
    dt_c = o.cfl * h / c0
    dt_g = o.cfl * math.sqrt(h / g) if g > 0 else math.inf
    dt = o.fixed_dt if o.fixed_dt is not None else min(dt_c, dt_g)
    steps = case.end_time / dt if dt > 0 else math.inf
    # a snapshot every interval, at most one a step (inf and huge counts are printed, not turned into ints)
    snaps = min(case.end_time / case.output.interval + 1e-9, steps) + 1
    snaps = math.floor(snaps) if snaps < 1e15 else snaps
    steps = math.ceil(steps) if steps < 1e15 else steps
    counts = p.counts()
    shown = "".join(ch if ch.isprintable() else "?" for ch in case.description)  # no terminal escapes
    lines = [f"case {case.name}: {shown}" if case.description else f"case {case.name}",
             f"  {dim}D, dp = {case.dp:g} m, h = {h:.4g} m ({o.kernel}), c0 = {c0:.4g} m/s, "
             f"{o.integrator}, {o.precision}",
             f"  particles: {n:,} = {counts['fluid']:,} fluid + {counts['fixed']:,} fixed boundary + "
             f"{counts['moving']:,} moving boundary"]
    for k, s in enumerate(case.solids):
        nk = int(np.count_nonzero(p.body == k))
        desc = f"{s.boundary}" + (f", {s.layers} layers" if s.layers else "") + \
            (f", moved by {s.motion!r}" if s.motion else "") + (", floating" if s.floating else "")
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
    moving = bool(np.any(p.kinds == MOVING))
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
    lines += floating_lines(case)
    lines += open_boundary_lines(case)
    for i, zone in enumerate(case.relaxation):
        lines.append(f"  relaxation[{i}]: {zone.describe()}")
    from .advice import case_warnings

    lines += [f"  warning: {w}" for w in case_warnings(case)]
    return lines
