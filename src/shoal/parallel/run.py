"""`run_case_mpi`: `shoal run` / `shoal.run_case` on several MPI ranks.

What it writes (from rank 0 unless said): ``case.toml``, ``resolved.json``
(with the ranks and slab cuts), ``run.log`` (with the re-cuts of the load
balancing and the communication share of the wall time), snapshots as
``<name>_NNNN.pvtu`` + ``<name>.pvd``, each rank writing its own piece
``<name>_NNNN/<name>_NNNN_<rank>.vtu`` (nothing gathered; ParaView opens the
``.pvd`` as one dataset, `shoal.output.read_vtu` reads a ``.pvtu`` whole, so
`shoal post` and the offline probes read them unchanged), or with
``SHOAL_MPI_SNAPSHOTS=gather`` gathered to rank 0 into the ``<name>_NNNN.vtu``
files of a single-process run; point probes, wave gauges and test-point
grids (each point sampled by the rank whose slab holds it, the values on
every rank, rank 0 writes), trackers (each tracked particle read on the rank
that owns it, gathered by id), max-z and run-up gauges (each rank's owned
particles, reduced over the ranks; rank 0 writes), ``escaped.csv`` (rank
0's escapes; rank r's in ``escaped.rank<r>.csv``) and the final PNG
(gathered).

Checkpoints (`shoal.parallel.checkpoint`): every rank writes its own
``ckpt_NNNNNN.rank<RRRR>.h5`` and rank 0 the ``ckpt_NNNNNN.mpi.json``
manifest, on the case's schedule (simulated time, and wall-clock time as
rank 0's clock says) and at the end; ``--resume`` continues the run on the
same number of ranks, bitwise; on another number of ranks, or from a
single-process run's checkpoint, the particles are re-distributed (equal to
round-off).

With ``--backend cuda`` each rank uses one GPU (its rank on the node modulo
the node's devices, `shoal.parallel.gpu`; ``run.log`` and ``resolved.json``
name each rank's device); halos and migrating particles go through host
memory, so no CUDA-aware MPI is needed.

Stop signals: SIGINT / SIGTERM reaching any rank (mpiexec forwards them to
every rank; a batch system signals every task) end the run after the same
step on every rank (the ranks agree after each step, one MAX reduction),
with a final checkpoint, and `RunInterrupted` on every rank (``shoal run``
exits with 128 + the signal number), as a single-process run; a second
signal aborts at once, the last checkpoint kept.

A periodic x axis closes the slabs into a ring: the last rank and rank 0
exchange halos and migrating particles like any two neighbours (a particle
leaving the domain's end is wrapped by the single-process sort and sent the
shorter way round; the ghosts keep their true positions, which the periodic
neighbour search wraps). With 2 ranks each slab is at least two halo widths
wide, since the neighbour on both sides is the same rank.

Errors: bad input is found on every rank alike (or decided on rank 0 and
broadcast) and raised everywhere; a collective check (instability, escaped
fluid, a failed write) raises the same error on every rank; any other error
on one rank prints ``shoal: MPI rank R: ...`` and calls ``MPI_Abort``, which
ends every rank: a failing rank never leaves the others hanging.
"""

from __future__ import annotations

import csv
import json
import platform
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

from ..version import __version__
from ..errors import InputError, InstabilityError, OutputError, RunInterrupted
from .decomposition import imbalance, weighted_counts
from .collective import CollectiveError, agree, collective_check, write_error

EXIT_STATUS = {InputError: 2, InstabilityError: 3, OutputError: 4}


def _status(err):
    for cls, code in EXIT_STATUS.items():
        if isinstance(err, cls):
            return code
    return 1


def abort(comm, err):
    """Print `err` with this rank's number on the process's real stderr and end every rank."""
    r = comm.Get_rank()
    if isinstance(err, (InputError, InstabilityError, OutputError)):
        text = f"shoal: MPI rank {r}: {err}\n"
    else:
        text = f"shoal: MPI rank {r}: unexpected error:\n" + "".join(traceback.format_exception(err))
    try:
        sys.__stderr__.write(text)
        sys.__stderr__.flush()
    finally:
        comm.Abort(_status(err))


SNAPSHOT_MODES = ("pieces", "gather")


def snapshot_mode(environ=None):
    """How snapshots are written under MPI: ``SHOAL_MPI_SNAPSHOTS`` = ``pieces``
    (default: a ``.vtu`` piece per rank and a ``.pvtu``) or ``gather`` (gathered
    to rank 0 into one ``.vtu``, as a single-process run writes).

    Raises
    ------
    InputError
        Another value.
    """
    import os

    env = os.environ if environ is None else environ
    mode = env.get("SHOAL_MPI_SNAPSHOTS", "").strip().lower() or "pieces"
    if mode not in SNAPSHOT_MODES:
        raise InputError(f"SHOAL_MPI_SNAPSHOTS = {mode!r}: give pieces (one .vtu per rank and a .pvtu, the default) "
                         "or gather (one .vtu written by rank 0)")
    return mode


class _Snapshots:
    """Snapshot callback under MPI (collective): ``<name>_NNNN.pvtu`` + ``<name>.pvd``.

    Mode ``pieces`` (default): every rank writes its own particles as
    ``<name>_NNNN/<name>_NNNN_<rank>.vtu`` (ParaView's layout for its own
    parallel writer) and rank 0 the ``<name>_NNNN.pvtu`` that names the
    pieces; the ``.pvd`` lists the ``.pvtu`` files, so ParaView opens the
    run as one dataset and `shoal.output.read_vtu` reads a snapshot whole.
    Nothing is gathered. Mode ``gather``: the particles are gathered to
    rank 0 and written as ``<name>_NNNN.vtu`` (in id order), the files of
    a single-process run. A write that fails on any rank raises
    `CollectiveOutputError` on every rank.
    """

    def __init__(self, out_dir, name, comm, mode="pieces", resume=False):
        from ..output import PVDWriter

        self.directory = Path(out_dir)
        self.name = name
        self.comm = comm
        self.rank, self.size = comm.Get_rank(), comm.Get_size()
        self.mode = mode
        self.pvd = PVDWriter(self.directory, name, resume=resume) if self.rank == 0 else None
        self.count = 0
        self.last_time = None

    def checkpoint_state(self):
        """What a checkpoint keeps: the number of snapshots written and the time of the last one."""
        return {"count": self.count, "last_time": self.last_time}

    def restore_checkpoint_state(self, scalars, arrays, backup=None):
        """Continue the series after a checkpoint: the next snapshot is number ``count``; rank 0
        drops the collection's entries after the checkpoint's last snapshot and removes the
        snapshots numbered from ``count`` on (``.pvtu`` and piece folders, or ``.vtu``), written
        by the interrupted run after the checkpoint."""
        import math

        from ..simulation.writers import remove_snapshots

        self.count = int(scalars["count"])
        self.last_time = None if scalars.get("last_time") is None else float(scalars["last_time"])
        if self.rank != 0:
            return
        self.pvd.truncate(-math.inf if self.last_time is None else self.last_time)
        remove_snapshots(self.directory, self.name, self.count)

    def __call__(self, sim):
        self.write(sim.model, sim.time)

    def write(self, model, time, suffix=None):
        """Write one snapshot of `model` at `time` [s] (collective); returns its path (the
        ``.pvtu`` or the ``.vtu``) on every rank."""
        base = f"{self.name}_{self.count:04d}" if suffix is None else f"{self.name}_{suffix}"
        path = self.directory / (f"{base}.pvtu" if self.mode == "pieces" else f"{base}.vtu")
        if self.mode == "pieces":
            self._write_pieces(model, time, base, path)
        else:
            self._write_gathered(model, time, path)
        if suffix is None:
            if self.rank == 0:
                msg = None
                try:
                    self.pvd.add(time, path.name)
                except OSError as err:
                    msg = write_error(err, self.pvd.path)
                collective_check(self.comm, msg)
            else:
                collective_check(self.comm, None)
            self.count += 1
            self.last_time = time
        return path

    def _write_pieces(self, model, time, base, path):
        from ..output import write_pvtu, write_vtu
        from ..output.vtu import pvtu_layout

        pos, fields = model.world_positions(), model.fields()
        piece = self.directory / base / f"{base}_{self.rank}.vtu"
        msg = None
        try:
            piece.parent.mkdir(exist_ok=True)
            write_vtu(piece, pos, fields, time=time)
        except OSError as err:
            msg = write_error(err, piece)
        collective_check(self.comm, msg)
        msg = None
        if self.rank == 0:
            try:
                write_pvtu(path, [f"{base}/{base}_{r}.vtu" for r in range(self.size)], pvtu_layout(pos, fields))
            except OSError as err:
                msg = write_error(err, path)
        collective_check(self.comm, msg)

    def _write_gathered(self, model, time, path):
        from ..output import write_vtu

        data = model.gather_particles()
        msg = None
        if self.rank == 0:
            try:
                write_vtu(path, data[0], data[1], time=time)
            except OSError as err:
                msg = write_error(err, path)
        collective_check(self.comm, msg)


def _escaped_recorder(out_dir, model, rank, resume_bytes=None):
    """This rank's escaped-particle recorder (``escaped.csv`` on rank 0, ``escaped.rank<r>.csv``
    elsewhere); on a resume (`resume_bytes`: its length at the checkpoint) the file is cut back
    to that length and appended to."""
    from ..simulation.escaped import HEADER, EscapedRecorder

    rec = EscapedRecorder.__new__(EscapedRecorder)
    rec.path = Path(out_dir) / ("escaped.csv" if rank == 0 else f"escaped.rank{rank}.csv")
    rec.max_fraction = 1.0
    rec.n_fluid0 = 0
    if resume_bytes and rec.path.exists():
        rec.file = open(rec.path, "r+", newline="")
        rec.file.truncate(int(resume_bytes))
        rec.file.seek(0, 2)
        rec.writer = csv.writer(rec.file)
    else:
        rec.file = open(rec.path, "w", newline="")
        rec.writer = csv.writer(rec.file)
        rec.writer.writerow(HEADER)
    rec.file.flush()
    rec.last = None
    model.on_escape = rec.on_escape
    return rec


def run_case_mpi(case, out_dir, comm, backend="cpu", progress=False, plot=True, max_steps=None, overwrite=False,
                 resume=False, handle_signals=True):
    """`shoal.run_case` on every rank of `comm` (see the module docstring). Returns a `RunResult`
    on every rank (``particles``, ``escaped``: whole-run figures)."""
    rank = comm.Get_rank()
    out_dir = Path(out_dir)
    started = False
    try:
        msg = None
        if rank == 0:
            from ..memory import check_memory

            try:
                snapshot_mode()
                if resume:
                    if not out_dir.is_dir() or not (out_dir / "resolved.json").exists() and not any(
                            out_dir.glob("ckpt_*")):
                        raise InputError(f"{out_dir} holds no run to resume (no resolved.json or checkpoint)")
                elif not overwrite and (out_dir / "resolved.json").exists():
                    raise InputError(f"{out_dir} already holds a run (resolved.json); choose another --out directory "
                                     "or pass --overwrite")
                check_memory(case)
                out_dir.mkdir(parents=True, exist_ok=True)
                if not resume:
                    from ..advice import wave_scheme_warnings
                    from ..simulation.run_log import print_warning

                    for w in wave_scheme_warnings(case):
                        print_warning(w)
            except InputError as err:
                msg = str(err)
            except OSError as err:
                msg = f"cannot write to the output directory {out_dir}: {err.strerror or err}"
        agree(comm, msg)
        resume_point = None
        if resume:
            resume_point = _resume_point(case, out_dir, comm)  # InputError on every rank alike
        from ..build import build_model

        model = build_model(case, backend)  # a DistributedModel: deterministic errors, raised on every rank
        started = True
        return _run(case, out_dir, comm, model, progress, plot, max_steps, backend, resume_point, handle_signals)
    except BaseException as err:  # noqa: BLE001 -- anything not raised on every rank alike ends every rank
        if getattr(err, "collective", False) or (not started and isinstance(err, InputError)):
            raise
        if isinstance(err, (KeyboardInterrupt, RunInterrupted)):
            raise
        abort(comm, err)
        raise


def _resume_point(case, out_dir, comm):
    """(path, this rank's Checkpoint, warnings) to resume the run in `out_dir` from: the path is
    the manifest (or the single-process checkpoint re-distributed), the checkpoint this rank's
    file (or the union to re-distribute) (collective; InputError on every rank alike: no usable
    checkpoint, another case, a finished run)."""
    from ..simulation.resume import check_same_case
    from ..simulation.run_log import print_warning
    from .checkpoint import find_resume

    warnings = []

    def warn(msg):
        print_warning(msg)
        warnings.append(msg)

    man, obj, ck = find_resume(out_dir, comm, warn=warn)
    check_same_case(case, ck)
    if ck.time >= case.end_time * (1 - 1e-12):
        raise InputError(f"the run in {out_dir} is complete (checkpoint {man.name} at t = {ck.time:.6g} s, "
                         f"end_time = {case.end_time:g} s); give a later --end-time to extend it")
    return man, ck, warnings


def _checkpoint_schedule(cfg, comm):
    """The single-process checkpoint schedule, its wall-clock part decided by rank 0."""
    from ..simulation.schedules import checkpoint_schedule as single
    from ..simulation.schedules import WallTimeInterval
    from .checkpoint import CollectiveSchedule

    sched = single(cfg)
    sched.schedules = [CollectiveSchedule(s, comm) if isinstance(s, WallTimeInterval) else s
                       for s in sched.schedules]
    return sched


def _run(case, out_dir, comm, model, progress, plot, max_steps, backend, resume_point=None, handle_signals=True):
    import time as _time
    from contextlib import nullcontext
    from types import SimpleNamespace

    from ..simulation.signals import StopOnSignals

    from ..casefile import dumps_case, write_case
    from ..probes import make_recorder
    from ..simulation.run_log import ProgressBar, close_run_log, open_run_log
    from ..simulation.run_result import RunResult, run_summary
    from ..simulation import IterationInterval, Simulation, TimeInterval
    from ..simulation.checkpoint import clear_checkpoints, restore_recorders, set_aside_csvs, set_aside_newer
    from .checkpoint import MPICheckpointWriter, cut_escaped_files, restore_rank

    rank, size = comm.Get_rank(), comm.Get_size()
    sim = Simulation(model, case.end_time)
    sim.damping = list(case.damping)
    man, ck, warnings = resume_point if resume_point is not None else (None, None, [])
    log = None
    if rank == 0:
        if ck is None:
            clear_checkpoints(out_dir)  # a new run never resumes from an older run's state
        else:
            set_aside_newer(out_dir, ck.step)
        write_case(case, out_dir / "case.toml")
    if rank == 0 and ck is not None:
        log = open_run_log(out_dir, append=True)
        for w in warnings:
            log.warning("%s", w)
    elif rank == 0:
        resolved = run_summary(case, model)
        resolved.update(shoal_version=__version__, backend=backend, python=platform.python_version(),
                        threads=model.backend.threads(), options=case.options.to_dict(), smoothing_length=model.h,
                        speed_of_sound=model.c0, eos_B=model.B, particle_mass=model.mass,
                        mpi={"ranks": size, "slab_cuts_x": model.cuts[1:-1].tolist(),
                             "halo_width": model.halo_width, "rebalance_interval": model.rebalance_interval,
                             "rebalance_threshold": model.rebalance_threshold})
        if model.gpus is not None:
            resolved["mpi"]["gpus"] = model.gpus
        (out_dir / "resolved.json").write_text(json.dumps(resolved, indent=2, default=float) + "\n")
        log = open_run_log(out_dir)
        log.info("case %s: %s", case.name, case.description)
        log.info("particles %d (fluid %d), dp %g m, h %g m, c0 %g m/s, backend %s, %d MPI ranks x %d threads, %s; "
                 "slab cuts x = %s m, halo %.4g m", model.n_global, case.n_fluid, case.dp, model.h, model.c0,
                 backend, size, model.backend.threads(), case.options.precision,
                 ", ".join(f"{c:.5g}" for c in model.cuts[1:-1]), model.halo_width)
        log.info("load balancing: %s", f"every {model.rebalance_interval} steps when the ranks' max / mean weighted "
                 f"count exceeds {model.rebalance_threshold:g}" if model.rebalance_interval else "off")
    if log is not None and model.gpus is not None:  # a new run or a resume: the devices of this start
        from .gpu import describe

        for line in describe(model.gpus):
            log.info("GPU: %s", line)
    # on a resume, rank 0's probe CSVs are set aside before the recorders re-create them, then get back
    # exactly the bytes they held at the checkpoint (as a single-process resume does)
    backups = set_aside_csvs(out_dir, skip=("escaped",)) if rank == 0 and ck is not None else {}
    escaped = _escaped_recorder(out_dir, model, rank,
                                resume_bytes=ck.meta["mpi"].get("escaped_bytes") if ck is not None else None)
    model.sort()
    probe_dir = out_dir if rank == 0 else Path(tempfile.mkdtemp(prefix=f"shoal-rank{rank}-"))
    recorders = [make_recorder(p, probe_dir, case.dp, model) for p in case.probes]
    for rec in recorders:
        sim.add_callback(rec, TimeInterval(rec.spec.interval), name=f"probe {rec.spec.name}")
    writer = _Snapshots(out_dir, case.name, comm, snapshot_mode(), resume=ck is not None)
    sim.add_callback(writer, TimeInterval(case.output.interval), name="snapshots")
    bar = ProgressBar(case.end_time, progress and rank == 0)
    sim.add_callback(bar, TimeInterval(max(case.end_time / 200, 1e-12), exact=False), name="progress")
    n_fluid0 = case.n_fluid

    logged = [len(model.rebalances)]

    def log_rebalances():
        for rec in model.rebalances[logged[0]:]:
            if log is not None:
                log.info("re-balanced at t %.6g s (sort %d): max/mean weighted count %.3f -> %.3f, particles "
                         "per rank %s -> %s, slab cuts x = %s m", rec["time"], rec["sort"], rec["imbalance_before"],
                         rec["imbalance_after"], rec["counts_before"], rec["counts_after"],
                         ", ".join(f"{c:.5g}" for c in rec["cuts"]))
        logged[0] = len(model.rebalances)

    def log_step(s):
        n = model.global_count()
        esc = model.allreduce(model.n_escaped, "sum")
        log_rebalances()
        if log is not None:
            log.info("step %d t %.6g s dt %.4g s particles %d escaped %d", s.step_count, s.time, s.dt or 0.0, n, esc)

    sim.add_callback(log_step, TimeInterval(case.output.interval, exact=False), name="log")
    if case.max_escaped_fraction < 1.0:
        def escaped_check(s):
            gone = n_fluid0 - model.allreduce(model.n_fluid, "sum")
            if gone > case.max_escaped_fraction * n_fluid0:
                raise CollectiveError(
                    f"{gone} of {n_fluid0} fluid particles ({100.0 * gone / n_fluid0:.1f} %) have left the domain by "
                    f"step {s.step_count}, t = {s.time:.6g} s, more than max_escaped_fraction = "
                    f"{case.max_escaped_fraction:g} (list in escaped*.csv): enlarge the domain, or check the inflow, "
                    "the walls and the time step")
        sim.add_callback(escaped_check, IterationInterval(1), name="escaped")
    # stop signals: the handler marks this rank only (`mark`); every step the ranks agree (a MAX
    # reduction) and all stop after the same step, so the final checkpoint is collective
    mark = SimpleNamespace(stop_requested=False)

    def agree_stop(s):
        if model.allreduce(int(mark.stop_requested), "max"):
            s.stop_requested = True

    sim.after_step.append(agree_stop)  # not a callback: a checkpoint's callbacks stay those of one process
    ckw = MPICheckpointWriter(out_dir, dumps_case(case, file_name="case.toml"), case.checkpoint.keep, comm, log,
                              escaped)
    ck_cb = sim.add_callback(ckw, _checkpoint_schedule(case.checkpoint, comm), name="checkpoint")  # last
    ck_cb.fresh_on_resume = True
    closers = [escaped, *recorders]
    if ck is not None:
        restore_rank(sim, ck)
        restore_recorders(sim, ck, out_dir, backups, None if log is None else lambda w: log.warning("%s", w))
        if rank == 0 and ck.meta["mpi"].get("redistribute"):  # a run on more ranks: the others' escapes
            cut_escaped_files(out_dir, ck.meta["mpi"]["escaped_bytes_ranks"], size)
        for sch in ck_cb.schedule.schedules:
            if isinstance(sch, TimeInterval):
                sch.skip_to(sim.time)
        ckw.last_step, ckw.last_path = ck.step, man
        logged[0] = len(model.rebalances)
        if log is not None:
            source = ck.meta["mpi"].get("source")
            how = f"written by {source}, re-distributed over {size} ranks" if source else f"{size} ranks"
            log.info("resumed from %s (%s): step %d, t = %.9g s, dt %.6g s, slab cuts x = %s m; run to "
                     "t = %g s", man.name, how, ck.step, ck.time, sim.dt or 0.0,
                     ", ".join(f"{c:.5g}" for c in model.cuts[1:-1]), case.end_time)
    t0 = _time.perf_counter()
    stopper = StopOnSignals(mark) if handle_signals else nullcontext()
    try:
        with stopper:
            sim.run(max_steps=max_steps)
    except InstabilityError as err:
        bar.stop()
        for rec in closers:
            rec.close()
        if not getattr(err, "collective", False):
            raise
        path = writer.write(model, sim.time, suffix="unstable")
        if log is not None:
            kept = f"; last checkpoint kept: {ckw.last_path.name}" if ckw.last_path is not None else ""
            log.error("%s; bad state written to %s%s", err, path.name, kept)
            close_run_log(log)
        raise CollectiveError(f"{err} (state written to {path or out_dir})") from None
    finally:
        bar.stop()
    signum = model.allreduce(int(getattr(stopper, "signum", None) or 0), "max") if sim.stop_requested else 0
    if writer.last_time is None or writer.last_time < sim.time - 1e-12:
        writer(sim)
    final = ckw.write(sim)  # before closing the recorders: it records their files' lengths
    for rec in closers:
        rec.close()
    if signum:
        import signal as _signal

        msg = (f"stopped by {_signal.Signals(signum).name} at step {sim.step_count}, t = {sim.time:.6g} s; "
               f"checkpoint {final.name} written on {size} ranks; continue with: mpiexec -n {size} shoal run "
               f"--resume {out_dir}")
        if log is not None:
            log.warning("%s", msg)
            close_run_log(log)
        raise RunInterrupted(msg, signum, final)
    wall = _time.perf_counter() - t0
    comm_max = model.allreduce(model.comm_seconds, "max")
    comm_min = model.allreduce(model.comm_seconds, "min")
    n_escaped = model.allreduce(model.n_escaped, "sum")
    n_now = model.global_count()
    log_rebalances()
    balance = weighted_counts(comm, model.weighted_count())
    owned_counts = comm.allgather(int(model.n_owned))
    memory = comm.allgather((int(model.capacity), int(model.nbytes()), int(model.resizes)))
    data = model.gather_particles() if plot else None
    if plot and rank == 0:
        from ..output import plot_particles

        pos, f = data
        plot_particles(out_dir / f"{case.name}_final.png", pos, np.linalg.norm(f["velocity"], axis=1), kind=f["kind"],
                       title=f"{case.name}  t = {sim.time:.3f} s", value_label="|v| [m/s]", dim=case.dim)
    if rank != 0:
        import shutil

        shutil.rmtree(probe_dir, ignore_errors=True)
    result = RunResult(out_dir, sim.step_count, sim.time, sim.wall_seconds, model.backend.compile_seconds,
                       model.n_global, n_escaped, writer.count, model, sim, checkpoint=final, resumed_from=man)
    if log is not None:
        log.info("done: %d steps to t = %.6g s in %.2f s wall (%.2f s compile), %.3g particle-steps/s, %d particles "
                 "(%d at the start), %d escaped; communication (exchanges, reductions, gathers, and waiting for "
                 "the slowest rank) %.2f-%.2f s per rank, %.1f %% of the wall time at most",
                 result.steps, result.time, result.wall_seconds, result.compile_seconds,
                 result.particle_steps_per_second, n_now, model.n_global, n_escaped, comm_min, comm_max,
                 100.0 * comm_max / max(wall, 1e-9))
        log.info("load balance at the end: %d re-cuts, max/mean weighted count %.3f, particles per rank %s",
                 len(model.rebalances), imbalance(balance), owned_counts)
        log.info("memory per rank, %s arrays (particle, work, grid): %s", "device" if backend == "cuda" else "host",
                 "; ".join(f"rank {r}: {rows} rows, {nb / 2**20:.1f} MiB ({nb / max(own, 1):.0f} B per owned particle), "
                           f"{k} re-size(s)" for r, ((rows, nb, k), own) in enumerate(zip(memory, owned_counts))))
        close_run_log(log)
    return result
