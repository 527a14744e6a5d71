"""Run a Case end to end: model, simulation, snapshots, log, progress, plot.

`run_case` is what ``shoal run`` calls; it is also the one-call Python API:

>>> import shoal
>>> result = shoal.run_case(shoal.cases.dam_break_2d(dp=0.004), "out/dam")   # doctest: +SKIP
"""

from __future__ import annotations

import json
import logging
import math
import platform
import time as _time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import __version__
from .errors import InputError, InstabilityError
from .model import Model
from .simulation import Simulation, TimeInterval
from .simulation.writers import SnapshotWriter


@dataclass
class RunResult:
    """What a finished run reports."""

    out_dir: Path
    steps: int
    time: float
    wall_seconds: float
    compile_seconds: float
    particles: int
    escaped: int
    snapshots: int
    model: Model
    simulation: Simulation

    @property
    def particle_steps_per_second(self):
        run = self.wall_seconds - self.compile_seconds
        return self.particles * self.steps / run if run > 0 else math.nan


def build_model(case, backend="cpu"):
    """The `Model` of a `Case`: generate its particles and compile the scheme."""
    p = case.particles()
    sym = None
    if case.symmetry_planes:
        if len(case.symmetry_planes) > 1:
            raise InputError("one symmetry plane per case is supported")
        sp = case.symmetry_planes[0]
        n = np.asarray(sp.normal, float)
        if case.dim != 3 or abs(abs(n[1]) - 1.0) > 1e-9:
            raise InputError(f"symmetry plane normal {list(sp.normal)}: only planes y = const (normal [0, 1, 0] or "
                             "[0, -1, 0]) in 3D cases are supported")
        sym = (float(sp.point[1]), float(np.sign(n[1])))
    index = {m.name: k for k, m in enumerate(case.motions)}
    body_motion = np.array([index.get(s.motion, -1) if s.motion else -1 for s in case.solids] + [-1], np.int32)
    motion_of = np.where(p.body >= 0, body_motion[p.body], -1)
    kinds = p.kinds.copy()
    rep = np.array([s.boundary == "repulsive" for s in case.solids] + [False])
    on_rep = (p.body >= 0) & rep[p.body]
    kinds[on_rep] += 2  # 1 -> 3 (repulsive), 2 -> 4 (moving repulsive)
    fl = case.fluid
    return Model(p.positions, kinds, dp=case.dp, dim=case.dim, domain=case.resolved_domain(),
                 options=case.options, rho0=fl.rho0, gravity=fl.gravity, fluid_height=fl.depth, u_max=fl.u_max,
                 surface_z=fl.surface_level, velocities=p.velocities, motions=case.motions, motion_of=motion_of,
                 periodic=tuple(case.domain.periodic) if case.domain else (),
                 planes=[(pl.point, pl.normal) for pl in case.planes], symmetry_y=sym, backend=backend)


def run_summary(case, model):
    """What a run records about its set-up (``resolved.json``)."""
    lo, hi = case.resolved_domain()
    counts = case.particles().counts()
    return {
        "name": case.name, "dim": case.dim, "dp": case.dp, "particles": counts, "total_particles": model.n_total,
        "domain": [lo.tolist(), hi.tolist()], "end_time": case.end_time, "output_interval": case.output.interval,
        "parameters": case.parameters,
    }


def _logger(out_dir):
    log = logging.getLogger(f"shoal.run.{out_dir}")
    log.setLevel(logging.INFO)
    log.propagate = False
    for h in list(log.handlers):
        log.removeHandler(h)
    fh = logging.FileHandler(out_dir / "run.log", mode="w")
    fh.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(fh)
    return log


class _Progress:
    """A rich progress bar: simulated time, dt, steps/s and ETA."""

    def __init__(self, end_time, enabled):
        self.enabled = enabled
        self.end_time = end_time
        self.t0 = _time.perf_counter()
        self.last_steps = 0
        if enabled:
            from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

            self.bar = Progress(TextColumn("[bold]t = {task.fields[t]:.4f} s"), BarColumn(),
                                TextColumn("dt = {task.fields[dt]:.2e} s  {task.fields[sps]:.0f} steps/s"),
                                TimeRemainingColumn(), transient=False)
            self.task = self.bar.add_task("run", total=end_time, t=0.0, dt=0.0, sps=0.0)
            self.bar.start()

    def __call__(self, sim):
        if not self.enabled:
            return
        now = _time.perf_counter()
        sps = (sim.step_count - self.last_steps) / max(now - self.t0, 1e-9)
        self.t0, self.last_steps = now, sim.step_count
        self.bar.update(self.task, completed=sim.time, t=sim.time, dt=sim.dt or 0.0, sps=sps)

    def stop(self):
        if self.enabled:
            self.bar.stop()


def run_case(case, out_dir, backend="cpu", progress=False, plot=True, max_steps=None, overwrite=False):
    """Run `case`, writing everything under `out_dir`.

    Writes ``<name>.pvd`` and ``<name>_NNNN.vtu`` snapshots every
    ``case.output.interval`` s, ``run.log``, ``case.toml`` (the resolved
    case: every default filled in; ``shoal run case.toml`` runs it again),
    ``resolved.json`` (particle counts, derived constants, versions) and
    ``<name>_final.png``. A run that goes
    unstable writes ``<name>_unstable.vtu`` of the bad state, keeps what it
    wrote, and raises `InstabilityError`. An `out_dir` that already holds a
    run (a ``resolved.json``) is refused unless `overwrite` is true, so no
    earlier result is lost by accident.

    Returns
    -------
    RunResult
    """
    out_dir = Path(out_dir)
    if not overwrite and (out_dir / "resolved.json").exists():
        raise InputError(f"{out_dir} already holds a run (resolved.json); choose another --out directory "
                         "or pass --overwrite")
    model = build_model(case, backend)  # bad input fails here, before anything is written
    out_dir.mkdir(parents=True, exist_ok=True)
    log = _logger(out_dir)
    sim = Simulation(model, case.end_time)
    sim.damping = list(case.damping)
    from .casefile import write_case

    write_case(case, out_dir / "case.toml")
    resolved = run_summary(case, model)
    resolved.update(
        shoal_version=__version__, backend=backend, python=platform.python_version(),
        threads=model.backend.threads(), options=case.options.to_dict(), smoothing_length=model.h,
        speed_of_sound=model.c0,
        eos_B=model.B, particle_mass=model.mass, solver_bytes=model.nbytes(),
        bytes_per_particle=model.nbytes() / model.n_total,
    )
    (out_dir / "resolved.json").write_text(json.dumps(resolved, indent=2, default=float) + "\n")
    log.info("case %s: %s", case.name, case.description)
    log.info("particles %d (fluid %d), dp %g m, h %g m, c0 %g m/s, backend %s, %d threads, %s",
             model.n_total, case.n_fluid, case.dp, model.h, model.c0, backend, model.backend.threads(),
             case.options.precision)
    from .probes import make_recorder

    model.sort()  # particles in cell order for the first samples
    recorders = [make_recorder(p, out_dir, case.dp, model) for p in case.probes]
    for rec in recorders:
        sim.add_callback(rec, TimeInterval(rec.spec.interval), name=f"probe {rec.spec.name}")
    writer = SnapshotWriter(out_dir, case.name)
    sim.add_callback(writer, TimeInterval(case.output.interval), name="snapshots")
    bar = _Progress(case.end_time, progress)
    sim.add_callback(bar, TimeInterval(max(case.end_time / 200, 1e-12), exact=False),
                     name="progress")

    def log_step(s):
        log.info("step %d t %.6g s dt %.4g s particles %d escaped %d", s.step_count, s.time, s.dt or 0.0,
                 s.model.n, s.model.n_escaped)

    sim.add_callback(log_step, TimeInterval(case.output.interval, exact=False), name="log")
    try:
        sim.run(max_steps=max_steps)
    except InstabilityError as err:
        bar.stop()
        for rec in recorders:
            rec.close()
        path = writer.write(model, sim.time, suffix="unstable")
        log.error("%s; bad state written to %s", err, path.name)
        raise InstabilityError(f"{err} (state written to {path})") from None
    bar.stop()
    for rec in recorders:
        rec.close()
    if writer.last_time is None or writer.last_time < sim.time - 1e-12:
        writer(sim)
    if plot:
        from .output import plot_particles

        v = np.linalg.norm(model.world_velocities(), axis=1)
        plot_particles(out_dir / f"{case.name}_final.png", model.world_positions(), v, kind=model.host(model.kind),
                       title=f"{case.name}  t = {sim.time:.3f} s", value_label="|v| [m/s]", dim=case.dim)
    result = RunResult(out_dir, sim.step_count, sim.time, sim.wall_seconds, model.backend.compile_seconds,
                       model.n_total, model.n_escaped, writer.count, model, sim)
    log.info("done: %d steps to t = %.6g s in %.2f s wall (%.2f s compile), %.3g particle-steps/s, "
             "%d particles escaped", result.steps, result.time, result.wall_seconds, result.compile_seconds,
             result.particle_steps_per_second, result.escaped)
    for h in list(log.handlers):
        h.close()
        log.removeHandler(h)
    return result
