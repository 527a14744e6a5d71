"""Run a Case end to end: model, simulation, snapshots, log, progress, plot.

`run_case` is what ``shoal run`` calls; it is also the one-call Python API:

>>> import shoal
>>> result = shoal.run_case(shoal.cases.dam_break_2d(dp=0.004), "out/dam")   # doctest: +SKIP
"""

from __future__ import annotations

import json
import platform
from pathlib import Path

import numpy as np

from .build import build_model
from .errors import InputError, InstabilityError, OutputError, RunInterrupted
from .simulation import Simulation, TimeInterval
from .simulation.resume import check_same_case
from .simulation.run_log import ProgressBar, close_run_log, open_run_log, print_warning
from .simulation.run_result import RunResult, run_summary
from .simulation.schedules import checkpoint_schedule
from .simulation.writers import SnapshotWriter
from .version import __version__


def run_case(case, out_dir, backend="cpu", progress=False, plot=True, max_steps=None, overwrite=False,
             resume=False, handle_signals=True):
    """Run `case`, writing everything under `out_dir`.

    Writes ``<name>.pvd`` and ``<name>_NNNN.vtu`` snapshots every
    ``case.output.interval`` s, ``run.log``, ``case.toml`` (the resolved
    case: every default filled in; ``shoal run case.toml`` runs it again),
    ``resolved.json`` (particle counts, derived constants, versions),
    ``escaped.csv`` (particles that left the domain), checkpoints
    ``ckpt_NNNNNN.h5`` (see `shoal.simulation.checkpoint`) and
    ``<name>_final.png``. A run that goes
    unstable writes ``<name>_unstable.vtu`` of the bad state, keeps what it
    wrote (checkpoints included), and raises `InstabilityError`. An `out_dir`
    that already holds a run (a ``resolved.json``) is refused unless
    `overwrite` is true, so no earlier result is lost by accident.

    Parameters
    ----------
    case : Case or None
        The case (None with `resume`: the run's own ``case.toml``).
    out_dir : path
        Run directory.
    backend : {"cpu", "cuda"}
    progress : bool
        Show a progress bar.
    plot : bool
        Write the PNG of the final state.
    max_steps : int, optional
        Stop after this many steps (tests).
    overwrite : bool
        Replace a run already in `out_dir` (its checkpoints are removed).
    resume : bool
        Continue the run in `out_dir` from its newest valid checkpoint (a
        damaged one is skipped with a warning): probe CSVs are cut back to
        the checkpoint and appended to, the snapshot series and ``run.log``
        continue. `case` must be that run's case; only ``end_time``,
        ``[checkpoint]`` and ``max_escaped_fraction`` may differ. On the CPU
        the result is bitwise that of an uninterrupted run. A run on several
        MPI ranks continues on this process from the union of its ranks'
        particles (`shoal.parallel.checkpoint.for_one_process`; equal to the
        uninterrupted run to round-off), the ``.pvd`` listing its ``.pvtu``
        snapshots and then this process's ``.vtu`` ones.
    handle_signals : bool
        On the main thread, the first SIGINT/SIGTERM ends the run after the
        current step with a final checkpoint (`RunInterrupted`); a second
        aborts at once.

    Returns
    -------
    RunResult

    Raises
    ------
    InputError
        Bad input, a run directory already used, a run too large for the
        memory available, nothing to resume.
    InstabilityError
        The run blew up, or too much fluid left the domain.
    RunInterrupted
        Stopped by a signal (after writing a checkpoint).
    OutputError
        The disk filled up (or another write failed).
    """
    from .parallel import world
    from .memory import check_memory
    from .simulation.resources import DISK_FULL, disk_full_message, lock_run_dir

    if world() is not None:  # several MPI ranks (shoal.parallel.run)
        from .parallel.run import run_case_mpi

        return run_case_mpi(case, out_dir, world(), backend=backend, progress=progress, plot=plot,
                            max_steps=max_steps, overwrite=overwrite, resume=resume, handle_signals=handle_signals)
    out_dir = Path(out_dir)
    warnings = []
    ck = None
    if resume:
        case, ck = _resume_point(case, out_dir, warnings.append)
    elif not overwrite and (out_dir / "resolved.json").exists():
        raise InputError(f"{out_dir} already holds a run (resolved.json); choose another --out directory "
                         "or pass --overwrite (or --resume to continue it)")
    check_memory(case)
    model = build_model(case, backend)  # bad input fails here, before anything is written
    if not resume:
        from .advice import wave_scheme_warnings

        for w in wave_scheme_warnings(case):
            print_warning(w)
            warnings.append(w)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        lock = lock_run_dir(out_dir)
    except OSError as err:
        if err.errno in DISK_FULL:
            raise OutputError(disk_full_message(err, out_dir)) from None
        if out_dir.exists() and not out_dir.is_dir():
            raise InputError(f"the output directory {out_dir} is a file; choose another --out directory") from None
        raise InputError(f"cannot write to the output directory {out_dir}: {err.strerror or err}") from None
    try:
        return _locked_run(case, out_dir, backend, progress, plot, max_steps, ck, model, handle_signals, warnings)
    finally:
        lock.close()


def _locked_run(case, out_dir, backend, progress, plot, max_steps, ck, model, handle_signals, warnings):
    from .simulation.checkpoint import CheckpointError, clear_checkpoints, set_aside_newer
    from .simulation.resources import DISK_FULL, disk_full_message

    try:
        if ck is None:
            clear_checkpoints(out_dir)
        else:
            set_aside_newer(out_dir, ck)
        log = open_run_log(out_dir, append=ck is not None)
    except OSError as err:
        if err.errno in DISK_FULL:
            raise OutputError(disk_full_message(err, out_dir)) from None
        raise InputError(f"cannot write to the output directory {out_dir}: {err.strerror or err}") from None
    for w in warnings:
        log.warning("%s", w)
    state = {"checkpoint": ck.path if ck is not None else None}
    try:
        return _run(case, out_dir, backend, progress, plot, max_steps, ck, log, model, handle_signals, state)
    except CheckpointError as err:
        close_run_log(log)
        raise InputError(f"cannot resume {out_dir}: {err}") from None
    except OSError as err:
        if err.errno not in DISK_FULL or isinstance(err, OutputError):
            raise
        ckw = state.get("writer")
        msg = disk_full_message(err, out_dir, ckw.last_path if ckw is not None else state.get("checkpoint"))
        try:
            log.error("%s", msg)
        except OSError:
            pass
        close_run_log(log)
        raise OutputError(msg) from None


def _run(case, out_dir, backend, progress, plot, max_steps, ck, log, model, handle_signals, state):
    from contextlib import nullcontext

    from .casefile import dumps_case, write_case
    from .probes import make_recorder
    from .simulation import IterationInterval
    from .simulation.checkpoint import CheckpointWriter, restore, restore_recorders, set_aside_csvs
    from .simulation.escaped import EscapedRecorder
    from .simulation.signals import StopOnSignals

    sim = Simulation(model, case.end_time)
    sim.damping = list(case.damping)
    write_case(case, out_dir / "case.toml")
    case_toml = dumps_case(case, file_name="case.toml")
    if ck is None:
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
    # on a restart, the CSVs are renamed aside before the recorders re-create them, then get back exactly
    # the bytes they held at the checkpoint (a crash in between leaves the data in *.csv.resume)
    backups = set_aside_csvs(out_dir) if ck is not None else {}
    escaped = EscapedRecorder(out_dir, model, case.max_escaped_fraction)
    model.sort()  # particles in cell order for the first samples
    recorders = [make_recorder(p, out_dir, case.dp, model) for p in case.probes]
    for rec in recorders:
        sim.add_callback(rec, TimeInterval(rec.spec.interval), name=f"probe {rec.spec.name}")
    writer = SnapshotWriter(out_dir, case.name, resume=ck is not None)
    sim.add_callback(writer, TimeInterval(case.output.interval), name="snapshots")
    bar = ProgressBar(case.end_time, progress)
    sim.add_callback(bar, TimeInterval(max(case.end_time / 200, 1e-12), exact=False),
                     name="progress")

    def log_step(s):
        log.info("step %d t %.6g s dt %.4g s particles %d escaped %d", s.step_count, s.time, s.dt or 0.0,
                 s.model.n, s.model.n_escaped)

    sim.add_callback(log_step, TimeInterval(case.output.interval, exact=False), name="log")
    sim.add_callback(escaped, IterationInterval(1), name="escaped")
    ckw = CheckpointWriter(out_dir, case_toml, case.checkpoint.keep, log)
    ck_cb = sim.add_callback(ckw, checkpoint_schedule(case.checkpoint), name="checkpoint")  # last: sees the rest
    ck_cb.fresh_on_resume = True
    state["writer"] = ckw
    closers = [escaped, *recorders]
    if ck is not None:
        mpi = ck.meta.get("mpi", {})
        if mpi.get("redistribute"):  # a run on several MPI ranks (the union of its ranks), continued here
            from .parallel.checkpoint import for_one_process

            ck = for_one_process(ck, sim)
        restore(sim, ck)

        def warn(w):
            print_warning(w)
            log.warning("%s", w)

        restore_recorders(sim, ck, out_dir, backups, warn)
        if mpi.get("redistribute"):
            from .parallel.checkpoint import cut_escaped_files

            cut_escaped_files(out_dir, mpi["escaped_bytes_ranks"], 1)  # escapes go to escaped.csv from now on
        for s in ck_cb.schedule.schedules:
            if isinstance(s, TimeInterval):
                s.skip_to(sim.time)
        ckw.last_step, ckw.last_path = ck.step, ck.path
        log.info("resumed from %s%s: step %d, t = %.9g s, dt %.6g s; run to t = %g s", ck.path.name,
                 f" (written by {mpi['source']}, continued on 1 process)" if mpi.get("redistribute") else "",
                 ck.step, ck.time, sim.dt or 0.0, case.end_time)
    stopper = StopOnSignals(sim) if handle_signals else nullcontext()
    try:
        with stopper:
            sim.run(max_steps=max_steps)
            if ckw.last_path is not None:
                state["checkpoint"] = ckw.last_path
            signum = getattr(stopper, "signum", None)
            if signum is not None:
                import signal as _signal

                path = ckw.write(sim)
                for rec in closers:
                    rec.close()
                name = _signal.Signals(signum).name
                msg = (f"stopped by {name} at step {sim.step_count}, t = {sim.time:.6g} s; checkpoint {path.name} "
                       f"written; continue with: shoal run --resume {out_dir}")
                log.warning("%s", msg)
                close_run_log(log)
                raise RunInterrupted(msg, signum, path)
    except InstabilityError as err:
        bar.stop()
        for rec in closers:
            rec.close()
        path = writer.write(model, sim.time, suffix="unstable")
        kept = f"; last checkpoint kept: {ckw.last_path.name}" if ckw.last_path is not None else ""
        log.error("%s; bad state written to %s%s", err, path.name, kept)
        close_run_log(log)
        raise InstabilityError(f"{err} (state written to {path})") from None
    except BaseException:
        bar.stop()
        raise
    bar.stop()
    if writer.last_time is None or writer.last_time < sim.time - 1e-12:
        writer(sim)
    state["checkpoint"] = ckw.write(sim)  # before closing the recorders: it records their files' lengths
    for rec in closers:
        rec.close()
    if plot:
        from .output import plot_particles

        v = np.linalg.norm(model.world_velocities(), axis=1)
        plot_particles(out_dir / f"{case.name}_final.png", model.world_positions(), v, kind=model.host(model.kind),
                       title=f"{case.name}  t = {sim.time:.3f} s", value_label="|v| [m/s]", dim=case.dim)
    result = RunResult(out_dir, sim.step_count, sim.time, sim.wall_seconds, model.backend.compile_seconds,
                       model.n_total, model.n_escaped, writer.count, model, sim, checkpoint=state["checkpoint"],
                       resumed_from=ck.path if ck is not None else None)
    log.info("done: %d steps to t = %.6g s in %.2f s wall (%.2f s compile), %.3g particle-steps/s, "
             "%d particles escaped", result.steps, result.time, result.wall_seconds, result.compile_seconds,
             result.particle_steps_per_second, result.escaped)
    close_run_log(log)
    return result


def _resume_point(case, out_dir, collect):
    """(case, checkpoint) to resume the run in `out_dir` from."""
    from .casefile import load_case
    from .simulation.resume import latest_checkpoint

    if not (out_dir / "resolved.json").exists() and not any(out_dir.glob("ckpt_*")):
        raise InputError(f"{out_dir} holds no run to resume (no resolved.json or checkpoint)")

    def warn(msg):
        print_warning(msg)
        collect(msg)

    ck = latest_checkpoint(out_dir, warn=warn)
    if case is None:
        toml = out_dir / "case.toml"
        if not toml.exists():
            raise InputError(f"{toml} is missing: the run's case file is needed to resume it")
        case = load_case(toml)
    check_same_case(case, ck)
    if ck.time >= case.end_time * (1 - 1e-12):
        raise InputError(f"the run in {out_dir} is complete (checkpoint {ck.path.name} at t = {ck.time:.6g} s, "
                         f"end_time = {case.end_time:g} s); give a later --end-time to extend it")
    return case, ck


def resume_run(out_dir, end_time=None, checkpoint_interval=None, backend="cpu", progress=False, plot=True,
               max_steps=None, handle_signals=True):
    """Continue the run in `out_dir` from its newest valid checkpoint.

    Parameters
    ----------
    out_dir : path
        A run directory (its ``case.toml`` and ``ckpt_NNNNNN.h5`` files, or
        the ``ckpt_NNNNNN.mpi.json`` manifests and rank files of a run on
        several MPI ranks).
    end_time : float, optional
        A new end time [s] (to extend a finished run); default: the case's.
    checkpoint_interval : float, optional
        A new simulated-time checkpoint interval [s].
    backend, progress, plot, max_steps, handle_signals
        As for `run_case`.

    Returns
    -------
    RunResult
    """
    from .casefile import load_case

    out_dir = Path(out_dir)
    toml = out_dir / "case.toml"
    if not toml.exists():
        raise InputError(f"{out_dir} holds no run to resume ({toml.name} is missing)")
    case = load_case(toml)
    update = {}
    if end_time is not None:
        update["end_time"] = float(end_time)
    if checkpoint_interval is not None:
        update["checkpoint"] = case.checkpoint.model_copy(update={"interval": float(checkpoint_interval)})
    if update:
        case = case.model_copy(update=update)
    return run_case(case, out_dir, backend=backend, progress=progress, plot=plot, max_steps=max_steps, resume=True,
                    handle_signals=handle_signals)
