"""`Ranks`: what `shoal run` / `shoal.run_case` does on several MPI ranks (`shoal.runner` runs it).

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

import sys
import tempfile
import time
import traceback
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..errors import InputError, InstabilityError, OutputError, RunInterrupted
from ..simulation.run_log import print_warning
from ..simulation.run_files import dangling_link, refuse_foreign_files
from .collective import CollectiveError, agree, collective_check, write_error
from .decomposition import imbalance, weighted_counts

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
        # MPI_Abort has mpiexec kill every rank at once, and its output forwarding may not have read the message
        # from this rank's pipe yet (seen on a loaded 2-core machine: the run ended with an empty stderr)
        time.sleep(0.5)
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

    def finalize(self, sim):
        """At the end of a run (collective): the last state, unless the schedule has just written it."""
        if self.last_time is None or self.last_time < sim.time - 1e-12:
            self(sim)

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


class Ranks:
    """The hooks of a run on the ranks of `comm` (`shoal.runner` runs it; see
    `shoal.simulation.one_process` for what each hook answers).

    Bad input is found on every rank alike, or decided on rank 0 and broadcast, and raised
    everywhere; after the model is built, an error that is not collective (not raised on every
    rank together) ends every rank through `abort` (`guard`), so no rank is left waiting.
    """

    def __init__(self, comm):
        self.comm = comm
        self.rank, self.size = comm.Get_rank(), comm.Get_size()
        self.started = False
        self.model = None
        self.logged = 0
        self.backend = "cpu"

    def guard(self, start):
        try:
            return start()
        except BaseException as err:  # noqa: BLE001 -- anything not raised on every rank alike ends every rank
            if getattr(err, "collective", False) or (not self.started and isinstance(err, InputError)):
                raise
            if isinstance(err, (KeyboardInterrupt, RunInterrupted)):
                raise
            abort(self.comm, err)
            raise

    def prepare(self, case, out_dir, overwrite, resume):
        from ..memory import check_memory
        from ..simulation.one_process import StartPoint

        msg = None
        if self.rank == 0:
            try:
                snapshot_mode()
                if resume:
                    if not out_dir.is_dir() or not (out_dir / "resolved.json").exists() and not any(
                            out_dir.glob("ckpt_*")):
                        raise InputError(f"{out_dir} holds no run to resume (no resolved.json or checkpoint)")
                elif not overwrite and (out_dir / "resolved.json").exists():
                    raise InputError(f"{out_dir} already holds a run (resolved.json); choose another --out directory "
                                     "or pass --overwrite")
                else:
                    refuse_foreign_files(out_dir, case)
                check_memory(case)
                out_dir.mkdir(parents=True, exist_ok=True)
            except InputError as err:
                msg = str(err)
            except OSError as err:
                msg = dangling_link(out_dir) or f"cannot write to the output directory {out_dir}: {err.strerror or err}"
        agree(self.comm, msg)
        if not resume:
            return StartPoint(case)
        return self._resume_point(case, out_dir)  # InputError on every rank alike

    def _resume_point(self, case, out_dir):
        """The manifest (or the single-process checkpoint re-distributed) and this rank's checkpoint
        (or the union to re-distribute) (collective; InputError on every rank alike: no usable
        checkpoint, another case, a finished run)."""
        from ..simulation.one_process import StartPoint
        from ..simulation.resume import check_same_case, check_same_data
        from .checkpoint import find_resume

        warnings = []

        def warn(msg):
            print_warning(msg)
            warnings.append(msg)

        man, obj, ck = find_resume(out_dir, self.comm, warn=warn)
        check_same_case(case, ck)
        check_same_data(case, out_dir)  # every rank reads the same files: the same answer on each
        if ck.time >= case.end_time * (1 - 1e-12):
            raise InputError(f"the run in {out_dir} is complete (checkpoint {man.name} at t = {ck.time:.6g} s, "
                             f"end_time = {case.end_time:g} s); give a later --end-time to extend it")
        return StartPoint(case, ck, man, warnings)

    def warn(self, message):
        if self.rank == 0:
            print_warning(message)

    def hold(self, out_dir):
        """The run directory (made by rank 0 in `prepare`) is not locked under MPI."""
        return None

    # ------------------------------------------------------------ set-up
    def resolved(self, model):
        mpi = {"ranks": self.size, "slab_cuts_x": model.cuts[1:-1].tolist(), "halo_width": model.halo_width,
               "rebalance_interval": model.rebalance_interval, "rebalance_threshold": model.rebalance_threshold}
        if model.gpus is not None:
            mpi["gpus"] = model.gpus
        return {"mpi": mpi}

    def log_start(self, log, case, model, backend, resumed):
        self.backend = backend
        if not resumed:
            log.info("particles %d (fluid %d), dp %g m, h %g m, c0 %g m/s, backend %s, %d MPI ranks x %d threads, "
                     "%s; slab cuts x = %s m, halo %.4g m", model.n_global, case.n_fluid, case.dp, model.h, model.c0,
                     backend, self.size, model.backend.threads(), case.options.precision,
                     ", ".join(f"{c:.5g}" for c in model.cuts[1:-1]), model.halo_width)
            log.info("load balancing: %s", f"every {model.rebalance_interval} steps when the ranks' max / mean "
                     f"weighted count exceeds {model.rebalance_threshold:g}" if model.rebalance_interval else "off")
        if model.gpus is not None:  # a new run or a resume: the devices of this start
            from .gpu import describe

            for line in describe(model.gpus):
                log.info("GPU: %s", line)

    csv_kept_aside = ("escaped",)
    """Each rank cuts its own ``escaped*.csv`` back (`escaped`)."""

    def escaped(self, out_dir, model, case, ck):
        """This rank's ``escaped.csv`` (rank 0) or ``escaped.rank<r>.csv``, and the collective check
        that stops every rank when more than ``max_escaped_fraction`` of the fluid has left."""
        from ..simulation.escaped import EscapedRecorder

        self.model = model
        self.logged = len(model.rebalances)
        rec = EscapedRecorder(out_dir, model, 1.0, name="escaped.csv" if self.rank == 0 else
                              f"escaped.rank{self.rank}.csv",
                              resume_bytes=ck.meta["mpi"].get("escaped_bytes") if ck is not None else None)
        if case.max_escaped_fraction >= 1.0:
            return rec, None
        n_fluid0 = case.n_fluid

        def escaped_check(s):
            b = model.buffers  # what open boundaries created and removed (counted over the ranks) did not escape
            gone = n_fluid0 + ((b.created - b.removed) if b is not None else 0) - model.reduce(model.n_fluid, "sum")
            if gone > case.max_escaped_fraction * n_fluid0:
                raise CollectiveError(
                    f"{gone} of {n_fluid0} fluid particles ({100.0 * gone / n_fluid0:.1f} %) have left the domain by "
                    f"step {s.step_count}, t = {s.time:.6g} s, more than max_escaped_fraction = "
                    f"{case.max_escaped_fraction:g} (list in escaped*.csv): enlarge the domain, or check the inflow, "
                    "the walls and the time step")

        return rec, escaped_check

    def probe_dir(self, out_dir):
        """Rank 0 writes the probes' files; the others sample into a folder of their own."""
        return out_dir if self.rank == 0 else Path(tempfile.mkdtemp(prefix=f"shoal-rank{self.rank}-"))

    def snapshot_writer(self, out_dir, name, resume):
        return _Snapshots(out_dir, name, self.comm, snapshot_mode(), resume=resume)

    def stop_target(self, sim):
        """A stop signal marks this rank only; after each step the ranks agree (a MAX reduction) and all
        stop after the same step, so the final checkpoint is collective."""
        mark = SimpleNamespace(stop_requested=False)

        def agree_stop(s):
            if s.model.reduce(int(mark.stop_requested), "max"):
                s.stop_requested = True

        sim.after_step.append(agree_stop)  # not a callback: a checkpoint's callbacks stay those of one process
        return mark

    def checkpoint_files(self, escaped):
        """A file per rank and a manifest (`RankFiles`), with this rank's escaped-particle file length."""
        from .checkpoint import RankFiles

        return RankFiles(self.comm, escaped)

    def checkpoint_schedule(self, cfg):
        """The single-process checkpoint schedule, its wall-clock part decided by rank 0."""
        from ..simulation.schedules import WallTimeInterval, checkpoint_schedule
        from .checkpoint import CollectiveSchedule

        sched = checkpoint_schedule(cfg)
        sched.schedules = [CollectiveSchedule(s, self.comm) if isinstance(s, WallTimeInterval) else s
                           for s in sched.schedules]
        return sched

    def restore(self, sim, point, out_dir, backups, log):
        from ..simulation.checkpoint import restore_recorders
        from .checkpoint import cut_escaped_files, restore_rank

        ck = point.ck
        restore_rank(sim, ck)
        restore_recorders(sim, ck, out_dir, backups, None if log is None else lambda w: log.warning("%s", w))
        if self.rank == 0 and ck.meta["mpi"].get("redistribute"):  # a run on more ranks: the others' escapes
            cut_escaped_files(out_dir, ck.meta["mpi"]["escaped_bytes_ranks"], self.size)
        self.logged = len(sim.model.rebalances)

    def log_resumed(self, log, point, sim, case):
        ck, m = point.ck, sim.model
        source = ck.meta["mpi"].get("source")
        how = f"written by {source}, re-distributed over {self.size} ranks" if source else f"{self.size} ranks"
        log.info("resumed from %s (%s): step %d, t = %.9g s, dt %.6g s, slab cuts x = %s m; run to "
                 "t = %g s", point.path.name, how, ck.step, ck.time, sim.dt or 0.0,
                 ", ".join(f"{c:.5g}" for c in m.cuts[1:-1]), case.end_time)

    def log_rebalances(self, log):
        """The load balancing's re-cuts since the last call, in ``run.log``."""
        model = self.model
        for rec in model.rebalances[self.logged:]:
            if log is not None:
                log.info("re-balanced at t %.6g s (sort %d): max/mean weighted count %.3f -> %.3f, particles "
                         "per rank %s -> %s, slab cuts x = %s m", rec["time"], rec["sort"], rec["imbalance_before"],
                         rec["imbalance_after"], rec["counts_before"], rec["counts_after"],
                         ", ".join(f"{c:.5g}" for c in rec["cuts"]))
        self.logged = len(model.rebalances)

    # ------------------------------------------------------------ the run and its end
    def collective(self, err):
        return bool(getattr(err, "collective", False))

    def instability(self, message):
        return CollectiveError(message)

    def stop_signal(self, stopper, sim):
        if not sim.stop_requested:
            return 0
        return sim.model.reduce(int(getattr(stopper, "signum", None) or 0), "max")

    def resume_command(self, out_dir):
        return f"mpiexec -n {self.size} shoal run --resume {out_dir}"

    def count(self, model):
        return model.n_global, model.global_count(), model.reduce(model.n_escaped, "sum")

    def plot_data(self, model):
        pos, f = model.gather_particles()  # collective
        if self.rank != 0:
            return None
        return pos, np.linalg.norm(f["velocity"], axis=1), f["kind"]

    def finish(self, probe_dir):
        if self.rank != 0:
            import shutil

            shutil.rmtree(probe_dir, ignore_errors=True)

    def end_stats(self, model, wall):
        """(communication seconds min / max over the ranks, the wall time, the weighted counts, each rank's
        owned count, each rank's (rows, bytes, re-sizes)) (collective)."""
        return dict(comm_min=model.reduce(model.comm_seconds, "min"),
                    comm_max=model.reduce(model.comm_seconds, "max"), wall=wall,
                    balance=weighted_counts(self.comm, model.weighted_count()),
                    owned=self.comm.allgather(int(model.n_owned)),
                    memory=self.comm.allgather((int(model.capacity), int(model.nbytes()), int(model.store.resizes))))

    def log_end(self, log, result, stats, counts):
        self.log_rebalances(log)
        log.info("done: %d steps to t = %.6g s in %.2f s wall (%.2f s compile), %.3g particle-steps/s, %d particles "
                 "(%d at the start), %d escaped; communication (exchanges, reductions, gathers, and waiting for "
                 "the slowest rank) %.2f-%.2f s per rank, %.1f %% of the wall time at most",
                 result.steps, result.time, result.wall_seconds, result.compile_seconds,
                 result.particle_steps_per_second, counts[1], counts[0], counts[2], stats["comm_min"],
                 stats["comm_max"], 100.0 * stats["comm_max"] / max(stats["wall"], 1e-9))
        log.info("load balance at the end: %d re-cuts, max/mean weighted count %.3f, particles per rank %s",
                 len(self.model.rebalances), imbalance(stats["balance"]), stats["owned"])
        log.info("memory per rank, %s arrays (particle, work, grid): %s", "device" if self.backend == "cuda" else "host",
                 "; ".join(f"rank {r}: {rows} rows, {nb / 2**20:.1f} MiB ({nb / max(own, 1):.0f} B per owned particle), "
                           f"{k} re-size(s)" for r, ((rows, nb, k), own) in enumerate(zip(stats["memory"],
                                                                                           stats["owned"]))))
