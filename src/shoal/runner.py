"""Run a Case end to end: model, simulation, snapshots, log, progress, plot.

One orchestration for every run, over the processes it spans: one process
(`shoal.simulation.one_process.OneProcess`) or several MPI ranks under
``mpiexec`` (`shoal.parallel.run.Ranks`), which answer the few questions on
which the two differ (where a resume starts, which snapshot, escaped-particle
and checkpoint writers, the counts of the whole run).

`run_case` is what ``shoal run`` calls; it is also the one-call Python API:

>>> import shoal
>>> result = shoal.run_case(shoal.cases.dam_break_2d(dp=0.004), "out/dam")   # doctest: +SKIP
"""

from __future__ import annotations

import json
import platform
from pathlib import Path


from .build import build_model
from .errors import InputError, InstabilityError, OutputError, RunInterrupted
from .simulation import Simulation, TimeInterval
from .simulation.one_process import OneProcess
from .simulation.run_log import ProgressBar, close_run_log, open_run_log
from .simulation.run_result import RunResult, run_summary
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

    comm = world()
    if comm is None:
        procs = OneProcess()
    else:  # under mpiexec with several ranks (shoal.parallel.run)
        from .parallel.run import Ranks

        procs = Ranks(comm)
    out_dir = Path(out_dir)
    return procs.guard(lambda: _start(case, out_dir, procs, backend, progress, plot, max_steps, overwrite, resume,
                                      handle_signals))


def _start(case, out_dir, procs, backend, progress, plot, max_steps, overwrite, resume, handle_signals):
    if case is not None:
        case = case.sampled()  # a series given as a function runs as the table its case.toml will hold
    point = procs.prepare(case, out_dir, overwrite, resume)  # InputError on every process alike
    case = point.case
    model = build_model(case, backend)  # bad input fails here, before anything is written
    procs.started = True
    if not resume:
        from .advice import case_warnings

        for w in case_warnings(case):
            procs.warn(w)
            point.warnings.append(w)
    lock = procs.hold(out_dir)
    try:
        return _run(case, out_dir, procs, model, point, backend, progress, plot, max_steps, handle_signals)
    finally:
        if lock is not None:
            lock.close()


def _run(case, out_dir, procs, model, point, backend, progress, plot, max_steps, handle_signals):
    """The run: set-up files and log (rank 0), callbacks, restore, the time loop, the end; a failed
    resume is an InputError, a full disk an OutputError naming the last checkpoint."""
    from .simulation.checkpoint import CheckpointError, clear_checkpoints, set_aside_newer
    from .simulation.resources import DISK_FULL, disk_full_message
    from .simulation.run_files import clear_run

    log = None
    state = {"checkpoint": point.path}
    try:
        if procs.rank == 0:
            try:
                if point.ck is None:
                    clear_run(out_dir, case)  # the earlier run's files: none is read as this run's
                    clear_checkpoints(out_dir)  # a new run never resumes from an older run's state
                    # resolved.json first: a run killed before it wrote it would leave a run.log or case.toml
                    # that marks the directory as someone else's (`foreign_clash`), refused even --overwrite
                    _write_resolved(case, out_dir, procs, model, backend)
                else:
                    set_aside_newer(out_dir, point.ck.step)
                log = open_run_log(out_dir, append=point.ck is not None)
            except OSError as err:
                if err.errno in DISK_FULL:
                    raise OutputError(disk_full_message(err, out_dir)) from None
                raise InputError(f"cannot write to the output directory {out_dir}: {err.strerror or err}") from None
            for w in point.warnings:
                log.warning("%s", w)
        return _steps(case, out_dir, procs, model, point, backend, progress, plot, max_steps, handle_signals, log,
                      state)
    except CheckpointError as err:
        if log is not None:
            close_run_log(log)
        raise InputError(f"cannot resume {out_dir}: {err}") from None
    except OSError as err:
        if err.errno not in DISK_FULL or isinstance(err, OutputError):
            raise
        ckw = state.get("writer")
        msg = disk_full_message(err, out_dir, ckw.last_path if ckw is not None else state.get("checkpoint"))
        if log is not None:
            try:
                log.error("%s", msg)
            except OSError:
                pass
            close_run_log(log)
        raise OutputError(msg) from None


def _write_resolved(case, out_dir, procs, model, backend):
    """Write ``resolved.json`` (atomically): the set-up of a new run, and the mark of a shoal run directory."""
    from .output.atomic import write_text_atomic

    resolved = run_summary(case, model)
    resolved.update(shoal_version=__version__, backend=backend, python=platform.python_version(),
                    threads=model.backend.threads(), options=case.options.to_dict(), smoothing_length=model.h,
                    speed_of_sound=model.c0, eos_B=model.B, particle_mass=model.mass, **procs.resolved(model))
    write_text_atomic(out_dir / "resolved.json", json.dumps(resolved, indent=2, default=float) + "\n")


def _steps(case, out_dir, procs, model, point, backend, progress, plot, max_steps, handle_signals, log, state):
    import time as _time
    from contextlib import nullcontext

    from .active_absorption import AbsorbingPaddle
    from .casefile import dumps_case, write_case
    from .probes import make_recorder
    from .probes.body_recorder import BodyRecorder
    from .probes.mooring_recorder import mooring_recorders
    from .simulation import IterationInterval
    from .simulation.checkpoint import CheckpointWriter, set_aside_csvs
    from .simulation.signals import StopOnSignals

    ck = point.ck
    sim = Simulation(model, case.end_time)
    sim.damping = list(case.damping)
    sim.relaxation = case.relaxation_terms()
    if procs.rank == 0:
        write_case(case, out_dir / "case.toml")
        if ck is None:
            log.info("case %s: %s", case.name, case.description)
        log.info("shoal %s, Python %s", __version__, platform.python_version())
        procs.log_start(log, case, model, backend, resumed=ck is not None)
    # on a resume, the probe CSVs are set aside before the recorders re-create them, then get back exactly
    # the bytes they held at the checkpoint (a crash in between leaves the data in *.csv.resume)
    backups = set_aside_csvs(out_dir, skip=procs.csv_kept_aside) if procs.rank == 0 and ck is not None else {}
    escaped, escaped_check = procs.escaped(out_dir, model, case, ck)
    model.sort()  # particles in cell order for the first samples
    probe_dir = procs.probe_dir(out_dir)
    for paddle in model.motions:  # active absorption: every step, before the probes read the step
        if isinstance(paddle, AbsorbingPaddle):
            sim.add_callback(paddle, IterationInterval(1), name=f"absorption {paddle.name}")
    recorders = [make_recorder(p, probe_dir, case.dp, model) for p in case.probes]
    for rec in recorders:
        sim.add_callback(rec, TimeInterval(rec.spec.interval), name=f"probe {rec.spec.name}")
    floating = [s.floating for s in case.solids if s.floating is not None]
    for j, spec in enumerate(floating):  # each floating body's CSV (shoal.probes.body_recorder)
        rec = BodyRecorder(model, j, probe_dir)
        sim.add_callback(rec, TimeInterval(spec.interval or case.output.interval), name=f"body {rec.name}")
        recorders.append(rec)
    for spec, mooring in zip(case.moorings, model.floating.moorings):  # the lines' tensions and shapes
        for rec in mooring_recorders(mooring, spec.name, probe_dir):
            sim.add_callback(rec, TimeInterval(spec.interval or case.output.interval), name=f"mooring {rec.path.name}")
            recorders.append(rec)
    writer = procs.snapshot_writer(out_dir, case.name, resume=ck is not None)
    sim.add_callback(writer, TimeInterval(case.output.interval), name="snapshots")
    bar = ProgressBar(case.end_time, progress and procs.rank == 0)
    sim.add_callback(bar, TimeInterval(max(case.end_time / 200, 1e-12), exact=False), name="progress")

    def log_step(s):
        counts = procs.count(model)
        procs.log_rebalances(log)
        if log is not None:
            opened = ""
            if model.buffers is not None:
                opened = f" created {model.buffers.created} removed {model.buffers.removed}"
            log.info("step %d t %.6g s dt %.4g s particles %d escaped %d%s", s.step_count, s.time, s.dt or 0.0,
                     counts[1], counts[2], opened)

    sim.add_callback(log_step, TimeInterval(case.output.interval, exact=False), name="log")
    if escaped_check is not None:
        sim.add_callback(escaped_check, IterationInterval(1), name="escaped")
    stop_target = procs.stop_target(sim)
    ckw = CheckpointWriter(out_dir, dumps_case(case, file_name="case.toml"), case.checkpoint.keep, log,
                           files=procs.checkpoint_files(escaped))
    ck_cb = sim.add_callback(ckw, procs.checkpoint_schedule(case.checkpoint), name="checkpoint")  # last: sees the rest
    ck_cb.fresh_on_resume = True
    state["writer"] = ckw
    closers = [escaped, *recorders]
    if ck is not None:
        procs.restore(sim, point, out_dir, backups, log)
        for s in ck_cb.schedule.schedules:
            if isinstance(s, TimeInterval):
                s.skip_to(sim.time)
        ckw.last_step, ckw.last_path = ck.step, point.path
        if log is not None:
            procs.log_resumed(log, point, sim, case)
    t0 = _time.perf_counter()
    stopper = StopOnSignals(stop_target) if handle_signals else nullcontext()
    try:
        with stopper:
            sim.run(max_steps=max_steps)
    except InstabilityError as err:
        bar.stop()
        for rec in closers:
            rec.close()
        if not procs.collective(err):
            raise
        path = writer.write(model, sim.time, suffix="unstable")
        if log is not None:
            kept = f"; last checkpoint kept: {ckw.last_path.name}" if ckw.last_path is not None else ""
            log.error("%s; bad state written to %s%s", err, path.name, kept)
            close_run_log(log)
        raise procs.instability(f"{err} (state written to {path})") from None
    finally:
        bar.stop()
    if ckw.last_path is not None:
        state["checkpoint"] = ckw.last_path
    signum = procs.stop_signal(stopper, sim)
    if signum:  # the state at the stop goes to a checkpoint, not to an off-schedule snapshot
        import signal as _signal

        path = ckw.write(sim)
        for rec in closers:
            rec.close()
        procs.finish(probe_dir)
        msg = (f"stopped by {_signal.Signals(signum).name} at step {sim.step_count}, t = {sim.time:.6g} s; "
               f"checkpoint {path.name} written; continue with: {procs.resume_command(out_dir)}")
        if log is not None:
            log.warning("%s", msg)
            close_run_log(log)
        raise RunInterrupted(msg, signum, path)
    wall = _time.perf_counter() - t0
    sim.finalize()  # the last snapshot and checkpoint (done already if the end time was reached)
    state["checkpoint"] = final = ckw.last_path  # written before the recorders close: it records their files' lengths
    for rec in closers:
        rec.close()
    if plot:
        from .output import plot_particles

        data = procs.plot_data(model)
        if data is not None:
            plot_particles(out_dir / f"{case.name}_final.png", data[0], data[1], kind=data[2],
                           title=f"{case.name}  t = {sim.time:.3f} s", value_label="|v| [m/s]", dim=case.dim)
    procs.finish(probe_dir)
    counts = procs.count(model)
    stats = procs.end_stats(model, wall)
    result = RunResult(out_dir, sim.step_count, sim.time, sim.wall_seconds, model.backend.compile_seconds,
                       counts[0], counts[2], writer.count, model, sim, checkpoint=final,
                       resumed_from=point.path if ck is not None else None)
    if log is not None:
        procs.log_end(log, result, stats, counts)
        close_run_log(log)
    return result


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
