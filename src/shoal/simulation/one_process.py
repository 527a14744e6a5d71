"""What a run on one process does where a run on several MPI ranks does otherwise.

`shoal.runner` orchestrates every run once, over the processes it spans: `OneProcess` here, or
`shoal.parallel.run.Ranks` under ``mpiexec``. Each answers the same questions: where a resumed run
starts (`prepare`), how the run directory is held (`hold`), which snapshot, escaped-particle and
checkpoint writers it uses, how a checkpoint is put back, what the counts of the whole run are, and
what ``resolved.json`` and ``run.log`` say of the set-up and the end. On one process the
communication is trivial: rank 0 of 1, every reduction the value itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, InstabilityError, OutputError
from .run_log import print_warning
from .run_files import dangling_link, refuse_foreign_files


@dataclass
class StartPoint:
    """Where a run starts: its case, and for a resumed run the checkpoint (`ck`, this process's
    part), the file it came from (`path`: the ``ckpt_NNNNNN.h5`` or an MPI run's manifest) and
    the warnings met finding it."""

    case: object
    ck: object = None
    path: Path | None = None
    warnings: list = field(default_factory=list)


class OneProcess:
    """The hooks of a run on one process (see the module docstring)."""

    rank, size = 0, 1
    started = False

    def guard(self, start):
        """Run `start()`; on one process an error simply propagates."""
        return start()

    def prepare(self, case, out_dir, overwrite, resume):
        """The `StartPoint` of a run in `out_dir`; InputError for a directory already used (without
        `overwrite`), nothing to resume, another case, a finished run, or a run too large for the
        memory available."""
        from ..memory import check_memory

        point = StartPoint(case)
        if resume:
            point = resume_point(case, out_dir)
        elif not overwrite and (out_dir / "resolved.json").exists():
            raise InputError(f"{out_dir} already holds a run (resolved.json); choose another --out directory "
                             "or pass --overwrite (or --resume to continue it)")
        else:
            refuse_foreign_files(out_dir, case)
        check_memory(point.case)
        return point

    def warn(self, message):
        """Print a warning (every process prints on one process)."""
        print_warning(message)

    def hold(self, out_dir):
        """Create `out_dir` and lock it for this run (`lock_run_dir`); returns the lock."""
        from .resources import DISK_FULL, disk_full_message, lock_run_dir

        try:
            out_dir.mkdir(parents=True, exist_ok=True)
            return lock_run_dir(out_dir)
        except OSError as err:
            if err.errno in DISK_FULL:
                raise OutputError(disk_full_message(err, out_dir)) from None
            if dangling_link(out_dir):
                raise InputError(dangling_link(out_dir)) from None
            if out_dir.exists() and not out_dir.is_dir():
                raise InputError(f"the output directory {out_dir} is a file; choose another --out directory") from None
            raise InputError(f"cannot write to the output directory {out_dir}: {err.strerror or err}") from None

    # ------------------------------------------------------------ set-up
    def resolved(self, model):
        """What ``resolved.json`` adds for this layout: the solver's memory."""
        return {"solver_bytes": model.nbytes(), "bytes_per_particle": model.nbytes() / model.n_total}

    def log_start(self, log, case, model, backend, resumed):
        log.info("particles %d (fluid %d), dp %g m, h %g m, c0 %g m/s, backend %s, %d threads, %s",
                 model.n_total, case.n_fluid, case.dp, model.h, model.c0, backend, model.backend.threads(),
                 case.options.precision)

    csv_kept_aside = ()
    """Run files a resume leaves where they are when it sets the probe CSVs aside."""

    def escaped(self, out_dir, model, case, ck):
        """(recorder of ``escaped.csv``, its every-step callback): the run stops when more than
        ``max_escaped_fraction`` of the fluid has left."""
        from .escaped import EscapedRecorder

        rec = EscapedRecorder(out_dir, model, case.max_escaped_fraction)
        return rec, rec

    def probe_dir(self, out_dir):
        return out_dir

    def snapshot_writer(self, out_dir, name, resume):
        from .writers import SnapshotWriter

        return SnapshotWriter(out_dir, name, resume=resume)

    def stop_target(self, sim):
        """What a stop signal marks: the Simulation itself."""
        return sim

    def checkpoint_files(self, escaped):
        """One file per checkpoint (`OneFile`)."""
        from .checkpoint import OneFile

        return OneFile()

    def checkpoint_schedule(self, cfg):
        from .schedules import checkpoint_schedule

        return checkpoint_schedule(cfg)

    def restore(self, sim, point, out_dir, backups, log):
        """Put the checkpoint back into `sim` and its recorders; a run on several MPI ranks continues
        here from the union of its ranks' particles (`for_one_process`)."""
        from .checkpoint import restore, restore_recorders

        ck = point.ck
        mpi = ck.meta.get("mpi", {})
        if mpi.get("redistribute"):
            from ..parallel.checkpoint import for_one_process

            ck = for_one_process(ck, sim)
        restore(sim, ck)

        def warn(w):
            print_warning(w)
            log.warning("%s", w)

        restore_recorders(sim, ck, out_dir, backups, warn)
        if mpi.get("redistribute"):
            from ..parallel.checkpoint import cut_escaped_files

            cut_escaped_files(out_dir, mpi["escaped_bytes_ranks"], 1)  # escapes go to escaped.csv from now on

    def log_rebalances(self, log):
        """(A run on one process has no load balancing.)"""

    def log_resumed(self, log, point, sim, case):
        ck = point.ck
        mpi = ck.meta.get("mpi", {})
        log.info("resumed from %s%s: step %d, t = %.9g s, dt %.6g s; run to t = %g s", point.path.name,
                 f" (written by {mpi['source']}, continued on 1 process)" if mpi.get("redistribute") else "",
                 ck.step, ck.time, sim.dt or 0.0, case.end_time)

    # ------------------------------------------------------------ the run and its end
    def collective(self, err):
        """An error every process raised together (on one process, every one)."""
        return True

    def instability(self, message):
        return InstabilityError(message)

    def stop_signal(self, stopper, sim):
        """The stop signal that ended the run (0: none)."""
        return int(getattr(stopper, "signum", None) or 0)

    def resume_command(self, out_dir):
        return f"shoal run --resume {out_dir}"

    def count(self, model):
        """(particles at the start, particles now, escaped) of the whole run."""
        return model.n_total, model.n, model.n_escaped

    def plot_data(self, model):
        """(positions, |v|, kinds) to plot the final state, or None on a rank that does not plot."""
        return model.world_positions(), np.linalg.norm(model.world_velocities(), axis=1), model.host(model.kind)

    def finish(self, probe_dir):
        """Remove what this process kept only for the run."""

    def end_stats(self, model, wall):
        """Figures of the whole run for the last lines of ``run.log`` (collective under MPI)."""
        return None

    def log_end(self, log, result, stats, counts):
        log.info("done: %d steps to t = %.6g s in %.2f s wall (%.2f s compile), %.3g particle-steps/s, "
                 "%d particles escaped", result.steps, result.time, result.wall_seconds, result.compile_seconds,
                 result.particle_steps_per_second, result.escaped)


def resume_point(case, out_dir):
    """The `StartPoint` to resume the run in `out_dir` from on one process: its newest valid
    checkpoint of either kind (a damaged one is skipped with a warning)."""
    from ..casefile import load_case
    from .resume import check_same_case, check_same_data, latest_checkpoint

    if not (out_dir / "resolved.json").exists() and not any(out_dir.glob("ckpt_*")):
        raise InputError(f"{out_dir} holds no run to resume (no resolved.json or checkpoint)")
    warnings = []

    def warn(msg):
        print_warning(msg)
        warnings.append(msg)

    ck = latest_checkpoint(out_dir, warn=warn)
    if case is None:
        toml = out_dir / "case.toml"
        if not toml.exists():
            raise InputError(f"{toml} is missing: the run's case file is needed to resume it")
        case = load_case(toml)
    check_same_case(case, ck)
    check_same_data(case, out_dir)
    if ck.time >= case.end_time * (1 - 1e-12):
        raise InputError(f"the run in {out_dir} is complete (checkpoint {ck.path.name} at t = {ck.time:.6g} s, "
                         f"end_time = {case.end_time:g} s); give a later --end-time to extend it")
    return StartPoint(case, ck, ck.path, warnings)
