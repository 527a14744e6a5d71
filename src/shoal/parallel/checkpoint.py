"""Checkpoints of a run on several MPI ranks: one HDF5 file per rank and a manifest.

A checkpoint at step NNNNNN is

``ckpt_NNNNNN.rank<RRRR>.h5``
    one per rank, in the single-process format (`shoal.simulation.checkpoint`:
    ``particles/*``, ``integrator/extra_*``, ``callbacks/*``, ``meta``,
    ``case_toml``, the SHA-256 of the datasets as an attribute), holding the
    rank's active rows (owned particles and ghosts, in their current order,
    the ghost flags as the last integrator array), plus ``mpi/cuts``,
    ``mpi/send_left``, ``mpi/send_right``, ``mpi/ghost_rows`` (the rows the
    halo refresh sends and fills) and, in ``meta["mpi"]``, the rank's counts,
    the load balancing's sort count and records, and the byte length of its
    ``escaped*.csv``;
``ckpt_NNNNNN.mpi.json``
    the manifest, written by rank 0 once every rank's file is on disk: the
    rank count, step, time, the cuts, and each rank's file name and SHA-256.

A checkpoint exists once its manifest does (written atomically, after the
rank files): a crash mid-write leaves the previous ones usable. On resume
every rank reads and verifies its own file against the manifest; if any
rank's file is missing or damaged, the previous manifest is tried (with a
one-line warning). The state is put back row for row, so a resumed run
on the same number of ranks continues **bitwise** as if it had never
stopped (the ranks compute in the same order on the same data).

Another number of ranks, or a single-process run's checkpoint
(``ckpt_NNNNNN.h5``): every rank reads every file, takes the union of the
owned particles (with their integrator state), cuts the slabs afresh at the
weighted quantiles and keeps its own; the probes' and snapshots' state comes
from rank 0's file (the same on every rank). The run then continues as a
run on the new rank count would, equal to the uninterrupted run to
round-off (not bitwise: the pair sums are summed in another order).
Whichever of the two kinds of checkpoint is newest is resumed.

On one process (``shoal run --resume`` without mpiexec),
`shoal.simulation.resume.latest_checkpoint` reads the newest complete
checkpoint of either kind: an MPI one as the same union (`read_union`,
every rank file verified against the manifest's SHA-256; a damaged or
missing one: the previous checkpoint, with a warning), which
`for_one_process` lays out as a single-process Model's arrays; the
run continues there, equal to the uninterrupted runs to round-off.
"""

from __future__ import annotations

import json
import os
import time as _time
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..output.atomic import write_text_atomic
from ..simulation.checkpoint import (MPI_MANIFEST, MPI_RANK_FILE, CheckpointError, capture, fsync_dir, list_checkpoints,
                                     restore_scalars, utf8_array, write_checkpoint)
from ..simulation.resume import (MANIFEST_FORMAT, MANIFEST_VERSION, checkpoint_step, latest_checkpoint,
                                 list_manifests, manifest_path, rank_path, read_manifests, read_rank_file,
                                 read_union, stored_digest, union_of_single)
from .collective import CollectiveInputError, collective_check, write_error


def capture_rank(sim, case_toml, escaped_bytes=0):
    """The datasets of this rank's checkpoint file (name -> ndarray)."""
    m = sim.model
    ds = capture(sim, case_toml, particles=m.checkpoint_arrays(), rows=m.n)
    scalars, arrays = m.checkpoint_state()
    for k, a in arrays.items():
        ds[f"mpi/{k}"] = a
    meta = json.loads(bytes(ds["meta"]).decode("utf-8"))
    meta["mpi"] = dict(scalars, escaped_bytes=int(escaped_bytes))
    ds["meta"] = utf8_array(json.dumps(meta))
    return ds


def _write_json(path, obj):
    write_text_atomic(path, json.dumps(obj, indent=1) + "\n")
    fsync_dir(path.parent)


class RankFiles:
    """Where a checkpoint of a run on several MPI ranks goes (`shoal.simulation.checkpoint.CheckpointWriter`
    writes it): a file per rank, then rank 0's manifest once every file is on disk (collective: a write
    that fails on any rank ends every rank with one error).

    Parameters
    ----------
    comm : mpi4py communicator
    escaped : EscapedRecorder, optional
        This rank's escaped-particle recorder (its CSV length is saved).
    """

    def __init__(self, comm, escaped=None):
        self.comm = comm
        self.escaped = escaped
        self.leader = comm.Get_rank() == 0

    def write(self, sim, out_dir, case_toml):
        """Write this rank's file and (rank 0) the manifest; returns (the manifest's path, the number of
        rank files, their bytes (rank 0; 0 elsewhere))."""
        rank, size = self.comm.Get_rank(), self.comm.Get_size()
        nbytes = 0
        if self.escaped is not None:
            self.escaped.file.flush()
            nbytes = os.fstat(self.escaped.file.fileno()).st_size
        path = rank_path(out_dir, sim.step_count, rank)
        msg, digest = None, None
        try:
            write_checkpoint(path, capture_rank(sim, case_toml, nbytes))
            digest = stored_digest(path)
        except OSError as err:
            msg = write_error(err, path)
        collective_check(self.comm, msg)
        digests = self.comm.gather((path.name, digest, path.stat().st_size), root=0)
        man = manifest_path(out_dir, sim.step_count)
        msg = None
        if rank == 0:
            obj = {"format": MANIFEST_FORMAT, "version": MANIFEST_VERSION, "ranks": size, "step": int(sim.step_count),
                   "time": float(sim.time), "cuts": [float(c) for c in sim.model.cuts[1:-1]],
                   "files": [d[0] for d in digests], "sha256": [d[1] for d in digests],
                   "written": _time.strftime("%Y-%m-%dT%H:%M:%S")}
            try:
                _write_json(man, obj)
            except OSError as err:
                msg = write_error(err, man)
        collective_check(self.comm, msg)
        return man, size, sum(d[2] for d in digests) if rank == 0 else 0

    def still_there(self, path):
        """Always: whether to write again must not depend on what one rank sees on disk."""
        return True

    def prune(self, out_dir, keep):
        """Remove the manifests older than the newest `keep` and their rank files, then any rank
        file older than the oldest kept manifest (left by a crash mid-write)."""
        mans = list_manifests(out_dir)
        kept = mans[:keep]
        for old in mans[keep:]:
            files = []
            try:
                files = json.loads(old.read_text()).get("files", [])
            except (OSError, ValueError):
                pass
            try:
                old.unlink()
            except OSError:
                pass
            for name in files:
                try:
                    (out_dir / name).unlink()
                except OSError:
                    pass
        if kept:
            oldest = int(MPI_MANIFEST.match(kept[-1].name).group(1))
            for p in out_dir.iterdir():
                m = MPI_RANK_FILE.match(p.name)
                if m and int(m.group(1)) < oldest:
                    try:
                        p.unlink()
                    except OSError:
                        pass


def find_resume(out_dir, comm, warn=None):
    """The newest checkpoint every rank can read (collective).

    Parameters
    ----------
    out_dir : path
        The run directory.
    comm : mpi4py communicator
    warn : callable, optional
        ``warn(message)`` on rank 0 for each checkpoint skipped.

    Returns
    -------
    (Path, dict, Checkpoint)
        The manifest, its contents, and this rank's checkpoint.

    Raises
    ------
    InputError
        (On every rank alike.) No checkpoint, or none readable on every rank.

    Notes
    -----
    A checkpoint of another rank count, or of a single-process run, comes
    back as the union of its active particles (``meta["mpi"]["redistribute"]``;
    the manifest contents are None for a single-process one), which
    `restore_rank` re-distributes over the ranks.
    """
    out_dir = Path(out_dir)
    rank, size = comm.Get_rank(), comm.Get_size()
    found, message = [], None
    if rank == 0:
        found = [(str(p), obj) for p, obj in read_manifests(out_dir, warn)]
        single = list_checkpoints(out_dir)
        if not found and not single:
            message = (f"{out_dir} holds no checkpoint (ckpt_NNNNNN.mpi.json) to resume from: the run stopped before "
                       "its first one; start it again with --overwrite")
        elif single and found and checkpoint_step(single[0]) > checkpoint_step(Path(found[0][0])):
            found = []  # a single-process checkpoint is the newest state
    found, message = comm.bcast((found, message), root=0)
    if message:
        raise InputError(message)
    if not found:  # a single-process run's checkpoint: re-distributed over the ranks
        single = latest_checkpoint(out_dir, warn=warn if rank == 0 else None, mpi=False)  # the same on every rank
        return single.path, None, union_of_single(single, rank)
    for p, obj in found:
        p = Path(p)
        msg, ck = None, None
        try:
            if int(obj["ranks"]) == size:
                f = out_dir / obj["files"][rank]
                ck = read_rank_file(f, obj["sha256"][rank], p)
                mpi = ck.meta.get("mpi", {})
                if mpi.get("rank") != rank or mpi.get("size") != size:
                    raise CheckpointError(f"{f.name} is rank {mpi.get('rank')} of {mpi.get('size')}, not {rank} "
                                          f"of {size}")
            else:  # written by another number of ranks: every rank reads every file, then keeps its new slab
                ck = read_union(out_dir, p, obj, rank)
        except CheckpointError as err:
            msg = str(err)
        except OSError as err:
            msg = f"{p.name}: a rank file cannot be read ({err.strerror or err})"
        msgs = comm.allgather(msg)
        bad = [(r, m) for r, m in enumerate(msgs) if m]
        if not bad:
            return p, obj, ck
        if warn is not None and rank == 0:
            warn(f"checkpoint {p.name} skipped: rank {bad[0][0]}: {bad[0][1]}; falling back to the previous one")
    names = ", ".join(Path(p).name for p, _ in found)
    raise InputError(f"none of the checkpoints in {out_dir} ({names}) is readable on every rank; the run cannot be "
                     "resumed")


def _restore_redistributed(sim, ck):
    """Keep this rank's slab of the union `ck` (`union_of`) at cuts computed afresh."""
    from ..simulation.checkpoint import Checkpoint
    from .decomposition import particle_weights, slab_cuts

    m = sim.model
    x = ck.particles["pos"][:, 0].astype(np.float64)
    w = particle_weights(ck.particles["kind"])
    try:
        cuts = slab_cuts(x, w, m.mpi_size, m.min_slab_width)
    except InputError as err:
        raise CollectiveInputError(f"cannot resume on {m.mpi_size} ranks: {err}") from None
    r = m.mpi_rank
    sel = np.flatnonzero((x >= cuts[r]) & (x < cuts[r + 1]))
    names = set(m.checkpoint_arrays())
    missing = sorted(names - set(ck.particles))
    if missing:
        raise CheckpointError(f"{ck.path.name} lacks the particle arrays {', '.join(missing)}")
    particles = {k: ck.particles[k][sel] for k in names}
    extra = [e[sel] for e in ck.extra] + [np.zeros(len(sel), np.int8)]  # the ghost flags: none yet
    mpi = ck.meta["mpi"]
    scalars = {"n_owned": len(sel), "n_ghost": 0, "ghost_counts": [0, 0], "sort_count": mpi["sort_count"],
               "halo_fresh": False, "rebalances": mpi["rebalances"]}
    empty = np.zeros(0, np.int64)
    try:
        m.restore_checkpoint(len(sel), particles, extra, scalars,
                             {"cuts": cuts, "send_left": empty, "send_right": empty, "ghost_rows": empty})
    except (ValueError, KeyError) as err:
        raise CheckpointError(f"{ck.path.name}: {err}") from None
    meta = json.loads(json.dumps(ck.meta))
    meta["model"]["n"] = len(sel)
    meta["model"]["n_escaped"] = mpi["n_escaped"] if r == 0 else 0
    restore_scalars(sim, Checkpoint(ck.path, meta, ck.case_toml, {}, extra, ck.callbacks, {}))


def _no_open_boundaries(model):
    """Refuse to resume a case with open boundaries on another number of ranks than wrote the checkpoint (its
    particle count and ids changed during the run: the re-cut and the union are not put back yet)."""
    if model.buffers is not None:
        raise CheckpointError("a run with open boundaries resumes on the number of MPI ranks that wrote its "
                              "checkpoint (one process from a one-process checkpoint), for now")


def restore_rank(sim, ck):
    """Put this rank's checkpoint `ck` into `sim` (a Simulation of a `DistributedModel` built
    from the same case, with the same callbacks in the same order).

    Raises
    ------
    CheckpointError
        The checkpoint does not match the model or the Simulation.
    """
    m = sim.model
    mm = ck.meta["model"]
    # with open boundaries the particle count changes (`shoal.particle_buffers`): the checkpoint's holds
    same_count = m.buffers is not None or mm["n_total"] == m.n_global
    if not same_count or mm["dim"] != m.dim or mm["dtype"] != np.dtype(m.dtype).str:
        raise CheckpointError(f"{ck.path.name} holds {mm['n_total']} particles ({mm['dim']}D, {mm['dtype']}); "
                              f"this case has {m.n_global} ({m.dim}D, {np.dtype(m.dtype).str})")
    if ck.meta["mpi"].get("redistribute"):
        _no_open_boundaries(m)
        return _restore_redistributed(sim, ck)
    arrays = {k[len("mpi/"):]: v for k, v in ck.other.items() if k.startswith("mpi/")}
    try:
        m.restore_checkpoint(int(mm["n"]), ck.particles, ck.extra, ck.meta["mpi"], arrays)
    except (ValueError, KeyError) as err:
        raise CheckpointError(f"{ck.path.name}: {err}") from None
    restore_scalars(sim, ck)
    if m.buffers is not None:
        m.n_global = m.n_total  # the count over every rank, as the checkpoint's (restore_scalars)


# the Model arrays indexed by particle id, not by row (they do not follow the sort; a DistributedModel
# keeps them whole, so its checkpoints do not hold them): the single-process Model's own are kept
_BY_ID = ("pos_init", "motion_of")


def for_one_process(ck, sim):
    """The union `ck` of a run on several MPI ranks (`read_union`) as a checkpoint of the
    single-process Simulation `sim` (built from the same case), which
    `shoal.simulation.checkpoint.restore` then puts back.

    Parameters
    ----------
    ck : Checkpoint
        The union of the ranks' owned particles (``meta["mpi"]["redistribute"]``).
    sim : Simulation
        A Simulation of a single-process `Model`, with its callbacks.

    Returns
    -------
    Checkpoint
        In the single-process layout: every per-particle array with the
        model's ``n_total`` rows, the active particles first (the union, in
        the ranks' order; the next sort puts them in cell order), then the
        particles that left the domain during the run (in id order, with the
        state they had in `sim`'s model: their last one is in the
        ``escaped*.csv`` files), the integrator's arrays in the same rows;
        the arrays indexed by id (moving bodies' initial positions and
        motions) are the model's; the escaped count summed over the ranks; the
        callbacks' state matched to `sim`'s callbacks by name (the
        single-process ``escaped`` recorder gets rank 0's ``escaped.csv``
        length). ``meta["mpi"]`` keeps ``source`` and ``escaped_bytes_ranks``
        (`cut_escaped_files`).

    Raises
    ------
    CheckpointError
        The checkpoint does not match the model or the Simulation, or its
        ranks do not hold every active particle exactly once.
    """
    _no_open_boundaries(sim.model)
    from ..simulation.checkpoint import Checkpoint

    m = sim.model
    mm, mpi = ck.meta["model"], ck.meta["mpi"]
    if mm["n_total"] != m.n_total or mm["dim"] != m.dim or mm["dtype"] != np.dtype(m.dtype).str:
        raise CheckpointError(f"{ck.path.name} holds {mm['n_total']} particles ({mm['dim']}D, {mm['dtype']}); "
                              f"this case has {m.n_total} ({m.dim}D, {np.dtype(m.dtype).str})")
    ids = np.asarray(ck.particles["idp"], np.int64)
    n_escaped = int(mpi["n_escaped"])
    if len(ids) and (ids.min() < 0 or ids.max() >= m.n_total):
        raise CheckpointError(f"{ck.path.name}: particle ids outside 0..{m.n_total - 1}")
    held = np.bincount(ids, minlength=m.n_total)
    if held.max(initial=0) > 1 or len(ids) + n_escaped != m.n_total:
        raise CheckpointError(f"{ck.path.name}: the ranks hold {len(ids)} particles ({int(np.sum(held > 1))} ids "
                              f"more than once) and {n_escaped} have left the domain, of {m.n_total}")
    row = np.empty(m.n_total, np.int64)
    row[m.host(m.idp, 0, m.n_total)] = np.arange(m.n_total)
    gone = row[np.flatnonzero(held == 0)]  # this model's rows of the particles that left the domain

    def whole(name, src, dst):
        if src.dtype != dst.dtype or src.shape[1:] != dst.shape[1:]:
            raise CheckpointError(f"{ck.path.name}: array {name} is {src.dtype}{tuple(src.shape)}, the model's "
                                  f"{dst.dtype}{tuple(dst.shape)}")
        return np.concatenate([src, m.backend.to_host(dst, 0, m.n_total)[gone]])

    particles = {}
    for name, dst in m.checkpoint_arrays().items():
        if name in ck.particles:
            particles[name] = whole(name, ck.particles[name], dst)
        elif name in _BY_ID:
            particles[name] = np.array(m.backend.to_host(dst, 0, m.n_total))
        else:
            raise CheckpointError(f"{ck.path.name} lacks the particle array {name}")
    if len(ck.extra) != len(m.extra_arrays):
        raise CheckpointError(f"{ck.path.name} was written with the {ck.meta['integrator']['type']} integrator; this "
                              f"run uses {type(sim.integrator).__name__}")
    extra = [whole(f"integrator {k}", e, dst) for k, (e, dst) in enumerate(zip(ck.extra, m.extra_arrays))]
    saved = {c["name"]: k for k, c in enumerate(ck.meta["callbacks"])}
    callbacks, states = [], {}
    for k, cb in enumerate(sim.callbacks):
        j = saved.get(cb.name)
        if cb.name == "escaped":  # rank 0's escaped.csv (a run on several ranks has no such recorder)
            entry = {"name": cb.name, "schedule": {} if j is None else ck.meta["callbacks"][j]["schedule"],
                     "state": {"file_bytes": int(mpi["escaped_bytes_ranks"][0]), "file_name": "escaped.csv"}}
        elif j is not None:
            entry = ck.meta["callbacks"][j]
            if j in ck.callbacks:
                states[k] = ck.callbacks[j]
        elif getattr(cb, "fresh_on_resume", False):
            entry = {"name": cb.name, "schedule": {}}
        else:
            raise CheckpointError(f"{ck.path.name} has no state for the callback {cb.name!r} (its callbacks are: "
                                  f"{', '.join(saved)})")
        callbacks.append(entry)
    meta = json.loads(json.dumps(ck.meta))
    meta["model"].update(n=len(ids), n_escaped=n_escaped)
    meta["integrator"]["n_extra"] = len(extra)
    meta["callbacks"] = callbacks
    meta["mpi"] = {"source": mpi["source"], "escaped_bytes_ranks": mpi["escaped_bytes_ranks"]}
    return Checkpoint(ck.path, meta, ck.case_toml, particles, extra, states, {})


def cut_escaped_files(out_dir, lengths, first):
    """Cut the files ``escaped.rank<R>.csv`` of the ranks R >= `first` back to their
    lengths at a checkpoint (`lengths`: bytes per rank of the run that wrote it):
    on a resume with fewer ranks nobody writes them any more, and the particles
    they list after the checkpoint escape again in the resumed run (into another
    rank's file).

    Parameters
    ----------
    out_dir : path
        The run directory.
    lengths : sequence of int
        ``meta["mpi"]["escaped_bytes_ranks"]`` of the checkpoint resumed from.
    first : int
        The first rank that is not in the resumed run.
    """
    for r in range(max(int(first), 1), len(lengths)):
        path = Path(out_dir) / f"escaped.rank{r}.csv"
        if path.exists() and path.stat().st_size > int(lengths[r]):
            os.truncate(path, int(lengths[r]))


class CollectiveSchedule:
    """A schedule whose decision is rank 0's (broadcast): for the wall-clock part of the
    checkpoint schedule, which the ranks' clocks would otherwise decide apart. Every
    rank still asks its own schedule, so their counters advance alike."""

    def __init__(self, inner, comm):
        self.inner = inner
        self.comm = comm

    def next_time(self):
        return self.inner.next_time()

    def due(self, sim):
        return bool(self.comm.bcast(bool(self.inner.due(sim)), root=0))

    def get_state(self):
        return self.inner.get_state()

    def set_state(self, state):
        self.inner.set_state(state)
