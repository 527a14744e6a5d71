"""Checkpoints: the whole state of a run in one HDF5 file, for an exact restart.

A checkpoint ``<run>/ckpt_NNNNNN.h5`` (NNNNNN: the step count) holds what a
run needs to continue **bitwise** as if it had never stopped:

``particles/<name>``
    the per-particle arrays the `Model` names as its state
    (`Model.checkpoint_arrays`; all ``n_total`` rows, in their current
    order, including rows of particles that have left the domain):
    positions, velocities, densities, kinds, ids, the moving particles'
    initial positions and motion indices, the rate arrays;
``integrator/extra_<k>``
    the integrator's state arrays (`Model.extra_arrays`: Verlet's previous
    velocity and density, the symplectic scheme's saved step);
``callbacks/<k>/<key>``
    the array state of callback k, as its ``checkpoint_state()`` gives it
    (probe rows, test-point samples, tracked ids);
``meta``
    JSON (UTF-8 bytes): time, step count, dt, dt0, the model's active and
    escaped counts, the integrator's scalars (its ``checkpoint_state()``:
    Verlet's step counter), the
    schedule counters of every callback, each callback's scalar state (CSV
    byte lengths, snapshot count), the format version, shoal's version;
``case_toml``
    the resolved case file the run was started with (UTF-8 bytes).

The root attribute ``sha256`` is the SHA-256 of every dataset (name, dtype,
shape and bytes, in name order); `read_checkpoint` recomputes it, so a
truncated or corrupted file is detected and skipped. Files are written
atomically: ``ckpt_NNNNNN.h5.tmp``, flushed and fsync'ed, then renamed with
`os.replace` (and the directory fsync'ed), so a crash mid-write leaves the
previous checkpoints untouched. Only the newest `keep` are kept.

Motions are pure functions of time (their tables are rebuilt from the case),
so they carry no state of their own.

A run on several MPI ranks writes one such file per rank,
``ckpt_NNNNNN.rank<RRRR>.h5``, and a manifest ``ckpt_NNNNNN.mpi.json``
(`shoal.parallel.checkpoint`); `capture` saves a rank's active rows.
`shoal.simulation.resume.latest_checkpoint` picks the newest checkpoint of either kind; a run on
several ranks comes back as the union of the ranks' owned particles, which
a single-process run continues from
(`shoal.parallel.checkpoint.for_one_process`).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ShoalError
from ..output.atomic import write_bytes_atomic

FORMAT = "shoal-checkpoint"
VERSION = 1
CHECKPOINT_NAME = re.compile(r"^ckpt_(\d+)\.h5$")


RENAMED = {"vmax": "mu_max"}
"""Particle arrays saved under another name by earlier versions (read under the current one)."""


class CheckpointError(ShoalError):
    """A checkpoint file that cannot be used (unreadable, truncated, corrupt,
    or written by another case or scheme)."""


@dataclass
class Checkpoint:
    """A checkpoint read back from disk.

    Attributes
    ----------
    path : Path
        The file.
    meta : dict
        Scalar state (see the module docstring).
    case_toml : str
        The resolved case file text the run was started with.
    particles : dict of str -> ndarray
        Per-particle arrays of the Model, by attribute name.
    extra : list of ndarray
        The integrator's state arrays, in `Model.extra_arrays` order.
    callbacks : dict of int -> dict of str -> ndarray
        Array state of the callbacks, by callback index.
    other : dict of str -> ndarray
        Any other dataset, by its full name (e.g. ``mpi/cuts`` in the per-rank
        files of a run on several MPI ranks, `shoal.parallel.checkpoint`).
    """

    path: Path
    meta: dict
    case_toml: str
    particles: dict = field(default_factory=dict)
    extra: list = field(default_factory=list)
    callbacks: dict = field(default_factory=dict)
    other: dict = field(default_factory=dict)

    @property
    def time(self):
        """Simulated time of the state [s]."""
        return float(self.meta["time"])

    @property
    def step(self):
        """Step count of the state."""
        return int(self.meta["step_count"])


def checkpoint_path(out_dir, step):
    """``out_dir/ckpt_NNNNNN.h5`` for step `step`."""
    return Path(out_dir) / f"ckpt_{int(step):06d}.h5"


def list_checkpoints(out_dir):
    """Checkpoint files in `out_dir`, newest (highest step) first."""
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        return []
    found = []
    for p in out_dir.iterdir():
        m = CHECKPOINT_NAME.match(p.name)
        if m:
            found.append((int(m.group(1)), p))
    return [p for _, p in sorted(found, reverse=True)]


# ------------------------------------------------------------------ capture
CHECKPOINT_OVERHEAD = 13 * 1024
"""Bytes of a checkpoint besides its arrays and the case file: the HDF5
structure (12.4 to 14.4 KiB measured, with 13 to 19 datasets) and the
metadata JSON."""


def checkpoint_bytes(n, dim, options, moving=False, probe_values=0, case_bytes=4096):
    """Bytes of one checkpoint of `n` particles, as `capture` writes it: the
    Model's per-particle arrays (`Model.checkpoint_arrays`: positions float64 [dim];
    velocity, acceleration [dim], density, drho/dt, max viscous term, p/rho^2
    in the working precision; kind int8, id int32; XSPH [dim], SPS stress
    (3 or 6) and no-slip wall velocity [dim] when those are on; the moving
    particles' initial positions float64 [dim] and motion index int32 when
    the case has moving bodies), the integrator's arrays (symplectic and
    predictor-corrector: positions float64 [dim], velocity [dim], density;
    Verlet: velocity [dim], density), `probe_values` float64 values of
    probe records, the case file (`case_bytes`), plus `CHECKPOINT_OVERHEAD`.
    3D, Verlet, float32: 85 bytes a particle (86.8 measured on a
    9,204-particle file, overhead included).
    """
    f = np.dtype(options.precision).itemsize
    per = 8 * dim + f * dim * 2 + f * 4 + 1 + 4
    if options.xsph > 0:
        per += f * dim
    if options.turbulence == "sps":
        per += f * (3 if dim == 2 else 6)
    if options.no_slip:
        per += f * dim
    if moving:
        per += 8 * dim + 4
    if options.integrator == "verlet":
        per += f * dim + f
    else:
        per += 8 * dim + f * dim + f
    return per * n + 8 * probe_values + case_bytes + CHECKPOINT_OVERHEAD


def _is_array(a):
    return hasattr(a, "shape") and hasattr(a, "dtype") and len(getattr(a, "shape", ())) >= 1


def _f(v):
    """A float for JSON: repr round-trips exactly; non-finite as strings."""
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else repr(v)


def _unf(v):
    return None if v is None else float(v)


def callback_state(func):
    """(scalars, arrays) of a callback's recorder state, or None.

    A stateful callback says what it saves: ``checkpoint_state()`` returns
    a dict (ndarray values become datasets, the rest JSON) and
    ``restore_checkpoint_state(scalars, arrays, backup)`` puts it back (the
    probe recorders through `shoal.probes.recorder_state.Recorder`: their
    CSV's byte length, rows, samples or ids). A callback without it has no
    state.
    """
    state = func.checkpoint_state() if hasattr(func, "checkpoint_state") else None
    if not state:
        return None
    scalars = {k: v for k, v in state.items() if not isinstance(v, np.ndarray)}
    arrays = {k: v for k, v in state.items() if isinstance(v, np.ndarray)}
    return scalars, arrays


def _digest(datasets):
    h = hashlib.sha256()
    for name in sorted(datasets):
        a = np.ascontiguousarray(datasets[name])
        h.update(name.encode())
        h.update(a.dtype.str.encode())
        h.update(repr(tuple(a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()


def utf8_array(s):
    """`s` as a uint8 array of its UTF-8 bytes (how text is stored in a checkpoint)."""
    return np.frombuffer(s.encode("utf-8"), dtype=np.uint8)


def capture(sim, case_toml, particles=None, rows=None):
    """The datasets of a checkpoint of `sim` (name -> ndarray).

    Parameters
    ----------
    sim : Simulation
    case_toml : str
        The resolved case file text.
    particles : dict of str -> array, optional
        The per-particle arrays to save (default: the model's `checkpoint_arrays`).
    rows : int, optional
        Save only the first `rows` rows of those and of the integrator's
        arrays (default: every row). A rank of an MPI run saves its active
        rows (`shoal.parallel.checkpoint`).
    """
    from ..version import __version__

    m = sim.model
    ds = {}
    for name, a in (m.checkpoint_arrays() if particles is None else particles).items():
        ds[f"particles/{name}"] = np.array(m.backend.to_host(a, 0, a.shape[0] if rows is None else rows))
    for k, a in enumerate(m.extra_arrays):
        ds[f"integrator/extra_{k}"] = np.array(m.backend.to_host(a, 0, a.shape[0] if rows is None else rows))
    cbs = []
    for k, cb in enumerate(sim.callbacks):
        entry = {"name": cb.name, "schedule": cb.schedule.get_state() if hasattr(cb.schedule, "get_state") else {}}
        st = callback_state(cb.func)
        if st is not None:
            scalars, arrays = st
            entry["state"] = scalars
            entry["arrays"] = sorted(arrays)
            for key, a in arrays.items():
                ds[f"callbacks/{k}/{key}"] = np.ascontiguousarray(a)
        cbs.append(entry)
    meta = {
        "format": FORMAT, "version": VERSION, "shoal_version": __version__,
        "time": _f(sim.time), "step_count": int(sim.step_count), "dt": _f(sim.dt), "dt0": _f(sim.dt0),
        "end_time": _f(sim.end_time), "wall_seconds": _f(sim.elapsed_wall_seconds()),
        "model": {"n": int(m.n), "n_total": int(m.n_total), "n_escaped": int(m.n_escaped), "time": _f(m.time),
                  "dim": int(m.dim), "dtype": np.dtype(m.dtype).str, "backend": m.backend.name},
        "integrator": {"type": type(sim.integrator).__name__, "scalars": sim.integrator.checkpoint_state(),
                       "n_extra": len(m.extra_arrays)},
        "callbacks": cbs,
        "floating": m.floating.checkpoint_state(),
        "buffers": m.buffers.checkpoint_state() if m.buffers is not None else {},
        "written": _time.strftime("%Y-%m-%dT%H:%M:%S"),
    }
    ds["meta"] = utf8_array(json.dumps(meta))
    ds["case_toml"] = utf8_array(case_toml)
    return ds


# ------------------------------------------------------------------ writing
def fsync_dir(path):
    """fsync the directory `path` (so a rename in it is on disk); a file system that refuses is left be."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def hdf5_image(datasets, attrs):
    """The bytes of an HDF5 file holding `datasets` (name -> array) and the root attributes `attrs`,
    built in memory.

    HDF5 reports a failed write (a full disk) as an error from deep inside the library, and closing the
    half-written file then crashes the process; a file built in memory and written with plain
    ``os.write`` fails as an `OSError` instead, which the caller reports in one line."""
    import io

    import h5py

    buf = io.BytesIO()
    with h5py.File(buf, "w") as f:
        for name, a in datasets.items():
            f.create_dataset(name, data=a)
        for key, value in attrs.items():
            f.attrs[key] = value
    return buf.getbuffer()


def write_checkpoint(path, datasets):
    """Write `datasets` to `path` atomically (``.tmp``, fsync, `os.replace`)
    with their SHA-256 as the root attribute ``sha256``. The file is built in
    memory first (`hdf5_image`: about the checkpoint's size more memory while
    it is written), so a full disk is an `OSError` (ENOSPC); on any error the
    temporary file is removed and the error re-raised; `path` and every other
    file are untouched."""
    image = hdf5_image(datasets, {"format": FORMAT, "version": VERSION, "sha256": _digest(datasets)})
    path = write_bytes_atomic(path, image)
    fsync_dir(Path(path).parent)
    return path


def read_checkpoint(path):
    """Read and verify a checkpoint; raises `CheckpointError` naming why a
    file cannot be used (unreadable or truncated HDF5, wrong format,
    checksum mismatch)."""
    import h5py

    path = Path(path)
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != FORMAT:
                raise CheckpointError(f"{path.name} is not a shoal checkpoint")
            stored = f.attrs.get("sha256")
            ds = {}

            def visit(name, obj):
                if isinstance(obj, h5py.Dataset):
                    ds[name] = obj[()]

            f.visititems(visit)
    except CheckpointError:
        raise
    except Exception as err:  # h5py raises OSError, KeyError, ValueError... on damaged files
        raise CheckpointError(f"{path.name} cannot be read ({type(err).__name__}: "
                              f"{str(err).splitlines()[0] if str(err) else 'damaged'})") from None
    if isinstance(stored, bytes):
        stored = stored.decode()
    if stored != _digest(ds):
        raise CheckpointError(f"{path.name} fails its checksum (truncated or corrupted)")
    try:
        meta = json.loads(bytes(ds.pop("meta")).decode("utf-8"))
        case_toml = bytes(ds.pop("case_toml")).decode("utf-8")
    except (KeyError, ValueError) as err:
        raise CheckpointError(f"{path.name} has no readable meta data ({err})") from None
    if meta.get("version") != VERSION:
        raise CheckpointError(f"{path.name} has format version {meta.get('version')}; this shoal reads {VERSION}")
    ck = Checkpoint(path, meta, case_toml)
    for name, a in ds.items():
        parts = name.split("/")
        if parts[0] == "particles":
            ck.particles[RENAMED.get(parts[1], parts[1])] = a
        elif parts[0] == "integrator":
            ck.extra.append((int(parts[1].split("_")[1]), a))
        elif parts[0] == "callbacks":
            ck.callbacks.setdefault(int(parts[1]), {})["/".join(parts[2:])] = a
        else:
            ck.other[name] = a
    ck.extra = [a for _, a in sorted(ck.extra, key=lambda t: t[0])]
    return ck


MPI_MANIFEST = re.compile(r"^ckpt_(\d+)\.mpi\.json$")
MPI_RANK_FILE = re.compile(r"^ckpt_(\d+)\.rank(\d+)\.h5$")


# ------------------------------------------------------------------ restore
def restore(sim, ck):
    """Put the state of checkpoint `ck` into `sim` (built from the same case,
    with the same callbacks in the same order); raises `CheckpointError` if
    the checkpoint does not match the Simulation."""
    m = sim.model
    meta = ck.meta
    mm = meta["model"]
    # with open boundaries the particle count changes (`shoal.particle_buffers`): the checkpoint's holds
    same_count = m.buffers is not None or mm["n_total"] == m.n_total
    if not same_count or mm["dim"] != m.dim or mm["dtype"] != np.dtype(m.dtype).str:
        raise CheckpointError(f"{ck.path.name} holds {mm['n_total']} particles ({mm['dim']}D, {mm['dtype']}); "
                              f"this case has {m.n_total} ({m.dim}D, {np.dtype(m.dtype).str})")
    rows = ck.particles["pos"].shape[0] if "pos" in ck.particles else 0
    if rows > m.capacity:  # the run had grown its arrays (`shoal.particle_store`)
        m.store.resize(rows)
    arrays = m.checkpoint_arrays()
    missing = sorted(set(arrays) - set(ck.particles))
    if missing:
        raise CheckpointError(f"{ck.path.name} lacks the particle arrays {', '.join(missing)} (written by another "
                              "version or scheme)")
    for name, dst in arrays.items():
        src = ck.particles[name]
        if tuple(src.shape) != tuple(dst.shape) or src.dtype != dst.dtype:
            raise CheckpointError(f"{ck.path.name}: particle array {name} is {src.dtype}{tuple(src.shape)}, "
                                  f"the model's {dst.dtype}{tuple(dst.shape)}")
        m.backend.copy_into(dst, src, src.shape[0])
    it = meta["integrator"]
    if it["type"] != type(sim.integrator).__name__ or len(ck.extra) != len(m.extra_arrays):
        raise CheckpointError(f"{ck.path.name} was written with the {it['type']} integrator; this run uses "
                              f"{type(sim.integrator).__name__}")
    for dst, src in zip(m.extra_arrays, ck.extra):
        if tuple(src.shape) != tuple(dst.shape) or src.dtype != dst.dtype:
            raise CheckpointError(f"{ck.path.name}: an integrator array does not match the model")
        m.backend.copy_into(dst, src, src.shape[0])
    restore_scalars(sim, ck)


def restore_scalars(sim, ck):
    """The scalar part of `restore`: the integrator's scalars, the model's active
    and escaped counts and time, the Simulation's time, step count and time
    steps, and the schedules of the callbacks (checked against the checkpoint's
    by name); raises `CheckpointError` on a mismatch."""
    m = sim.model
    meta = ck.meta
    mm = meta["model"]
    it = meta["integrator"]
    if it["type"] != type(sim.integrator).__name__ or len(ck.extra) != len(m.extra_arrays):
        raise CheckpointError(f"{ck.path.name} was written with the {it['type']} integrator; this run uses "
                              f"{type(sim.integrator).__name__}")
    sim.integrator.restore_state(it["scalars"])
    try:
        m.floating.restore_state(meta.get("floating", []))
    except ValueError as err:
        raise CheckpointError(f"{ck.path.name}: {err}") from None
    if m.buffers is not None:
        m.buffers.restore_state(meta.get("buffers", {}))
        m.n_total = int(mm["n_total"])
    m.n = int(mm["n"])
    m.n_escaped = int(mm["n_escaped"])
    m.time = _unf(mm["time"])
    sim.time = _unf(meta["time"])
    sim.step_count = int(meta["step_count"])
    sim.dt = _unf(meta["dt"])
    sim.dt0 = _unf(meta["dt0"])
    sim.wall_seconds = _unf(meta.get("wall_seconds")) or 0.0
    sim.started = True
    saved = meta["callbacks"]
    for k, cb in enumerate(sim.callbacks):
        if getattr(cb, "fresh_on_resume", False):
            continue
        if k >= len(saved) or saved[k]["name"] != cb.name:
            have = ", ".join(c["name"] for c in saved)
            raise CheckpointError(f"{ck.path.name}: callback {k} is {cb.name!r} here but the checkpoint's "
                                  f"callbacks are: {have}")
        if hasattr(cb.schedule, "set_state"):
            cb.schedule.set_state(saved[k]["schedule"])


def callback_saved_state(ck, index, name):
    """(scalars, arrays) saved for callback `index` (named `name`), or ({}, {})."""
    saved = ck.meta["callbacks"]
    if index >= len(saved) or saved[index]["name"] != name:
        return {}, {}
    return saved[index].get("state", {}), ck.callbacks.get(index, {})


def set_aside(path):
    """Rename `path` to ``path.resume`` before a recorder re-creates it (a
    crash mid-restart keeps the data there; a later restart reads it back).
    Returns the backup path, or None if neither exists."""
    path = Path(path)
    bak = path.with_name(path.name + ".resume")
    if bak.exists():
        return bak  # left by an interrupted restart: it holds the data
    if path.exists():
        os.replace(path, bak)
        return bak
    return None


def restore_recorder(rec, scalars, arrays, backup=None):
    """Restore a probe recorder (built afresh for the resumed run) from its
    checkpoint state: its CSV gets back exactly the bytes it held at the
    checkpoint (rows written after it, by the interrupted run, are dropped),
    and its in-memory rows, samples or ids are restored.

    Returns
    -------
    str or None
        A warning if the file held less than at the checkpoint (rows lost
        by the system, e.g. a power cut before they reached the disk).
    """
    return rec.restore_checkpoint_state(scalars, arrays, backup)


def set_aside_csvs(out_dir, skip=()):
    """Rename the CSV files of a run being resumed aside (`set_aside`), before
    its recorders re-create them; `restore_recorders` puts their data back.

    Parameters
    ----------
    out_dir : Path
        The run directory.
    skip : tuple of str, optional
        Leave the files whose names start with one of these where they are.

    Returns
    -------
    dict of str -> Path
        The backup (``*.csv.resume``) of each file, by the file's name; one
        left by an interrupted resume holds the data and is kept as it is.
    """
    backups = {}
    for p in sorted(out_dir.glob("*.csv")) + sorted(out_dir.glob("*.csv.resume")):
        name = p.name[: -len(".resume")] if p.name.endswith(".resume") else p.name
        if name not in backups and not name.startswith(tuple(skip)):
            bak = set_aside(out_dir / name)
            if bak is not None:
                backups[name] = bak
    return backups


def restore_recorders(sim, ck, out_dir, backups, warn=None):
    """Restore every callback of a resumed Simulation that has state in its
    checkpoint: each probe CSV gets back exactly the bytes it held at the
    checkpoint (rows the interrupted run wrote after it are dropped, so no
    time is recorded twice or missing), in-memory rows, samples and ids, the
    snapshot numbering.

    Parameters
    ----------
    sim : Simulation
        The resumed Simulation (its state already put back, `restore`); its
        callbacks flagged ``fresh_on_resume`` are left as they are.
    ck : Checkpoint
        The checkpoint, in the layout of `sim`'s callbacks.
    out_dir : Path
        The run directory.
    backups : dict of str -> Path
        The CSV files set aside before the recorders re-created them
        (`set_aside_csvs`). A backup whose data is back in its recorder's
        file is removed; one of a file no recorder re-created is put back
        as it was; one of a file re-created without state in the checkpoint
        is kept, with a warning.
    warn : callable, optional
        ``warn(message)``: one line for each problem (a file shorter than at
        the checkpoint, a file re-created without state).
    """
    restored = set()
    for k, cb in enumerate(sim.callbacks):
        if getattr(cb, "fresh_on_resume", False):
            continue
        scalars, arrays = callback_saved_state(ck, k, cb.name)
        if scalars or arrays:
            bak = backups.get(scalars.get("file_name"))
            w = restore_recorder(cb.func, scalars, arrays, bak)
            if bak is not None:
                restored.add(scalars.get("file_name"))
            if w and warn is not None:
                warn(w)
    for name, bak in backups.items():
        if name in restored:
            bak.unlink()  # its data is back in the re-created file
        elif not (out_dir / name).exists():
            bak.replace(out_dir / name)  # not a recorder's file: put it back as it was
        elif warn is not None:
            warn(f"{name} was re-created but the checkpoint has no state for it; its old data is in {bak.name}")


# ------------------------------------------------------------------ callback
class OneFile:
    """Where a checkpoint of one process goes: ``ckpt_NNNNNN.h5``, the whole state in one file.

    A run on several MPI ranks writes a file per rank and a manifest instead
    (`shoal.parallel.checkpoint.RankFiles`); `CheckpointWriter` writes either.
    """

    leader = True
    """Whether this process prunes old checkpoints and logs the writes."""

    def write(self, sim, out_dir, case_toml):
        """Write the checkpoint of `sim` now; returns (the path it is known by, the number of files,
        their bytes)."""
        path = checkpoint_path(out_dir, sim.step_count)
        write_checkpoint(path, capture(sim, case_toml))
        return path, 1, path.stat().st_size

    def still_there(self, path):
        """Whether the checkpoint written last at `path` is still on disk (written again if not)."""
        return path.exists()

    def prune(self, out_dir, keep):
        """Remove all but the newest `keep` checkpoints."""
        for old in list_checkpoints(out_dir)[keep:]:
            try:
                old.unlink()
            except OSError:
                pass


class CheckpointWriter:
    """A Simulation callback writing a checkpoint and keeping the newest `keep`, for one process or
    many: `files` says where a checkpoint goes (`OneFile`: ``ckpt_NNNNNN.h5``; a run on several MPI
    ranks: `shoal.parallel.checkpoint.RankFiles`, a file per rank and a manifest, written
    collectively).

    Add it last, so every other callback's state at the step is included.

    Parameters
    ----------
    out_dir : path
        Run directory.
    case_toml : str
        The resolved case file text (stored in each checkpoint).
    keep : int
        Checkpoints kept.
    log : logging.Logger, optional
        Where each write is logged.
    files : OneFile or RankFiles, optional
        Default `OneFile`.
    """

    def __init__(self, out_dir, case_toml, keep=2, log=None, files=None):
        self.out_dir = Path(out_dir)
        self.case_toml = case_toml
        self.keep = max(1, int(keep))
        self.log = log
        self.files = files if files is not None else OneFile()
        self.last_step = None
        self.last_path = None
        self.written = 0

    def __call__(self, sim):
        self.write(sim)

    def finalize(self, sim):
        """At the end of a run: the last checkpoint (`write`)."""
        self.write(sim)

    def write(self, sim):
        """Write a checkpoint of `sim` now (once per step); returns its path (a run on several ranks:
        its manifest's)."""
        if self.last_step == sim.step_count and self.last_path is not None and self.files.still_there(self.last_path):
            return self.last_path
        t0 = _time.perf_counter()
        path, nfiles, nbytes = self.files.write(sim, self.out_dir, self.case_toml)
        self.last_step, self.last_path = sim.step_count, path
        self.written += 1
        if self.files.leader:
            self.files.prune(self.out_dir, self.keep)
            if self.log is not None:
                what = f"{nfiles} rank files, " if nfiles > 1 else ""
                self.log.info("checkpoint %s: step %d, t = %.9g s, %s%.1f MiB in %.2f s", path.name, sim.step_count,
                              sim.time, what, nbytes / 2**20, _time.perf_counter() - t0)
        return path


def clear_checkpoints(out_dir):
    """Remove every checkpoint (and temporary and set-aside file) in `out_dir`:
    a new run there must never resume from an older run's state."""
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        return
    for p in out_dir.iterdir():
        if CHECKPOINT_NAME.match(p.name) or re.match(r"^ckpt_\d+\.h5\.(tmp|bad)$", p.name) or p.name.endswith(".csv.resume"):
            p.unlink()
        elif re.match(r"^ckpt_\d+\.(mpi\.json|rank\d+\.h5)(\.tmp|\.bad)?$", p.name):
            p.unlink()  # a run on several MPI ranks (shoal.parallel.checkpoint)


def set_aside_newer(out_dir, step):
    """Rename the checkpoints newer than the one resumed from (damaged ones,
    skipped on resume), of either kind (``ckpt_NNNNNN.h5``, and a run on
    several MPI ranks' manifests and rank files), to ``*.bad`` and remove
    stale ``*.tmp`` files, so the resumed run never mistakes them for its
    own.

    Parameters
    ----------
    out_dir : path
        The run directory.
    step : int or Checkpoint
        The step of the checkpoint resumed from (or that checkpoint).
    """
    step = step.step if isinstance(step, Checkpoint) else int(step)
    for p in Path(out_dir).iterdir():
        m = CHECKPOINT_NAME.match(p.name) or MPI_MANIFEST.match(p.name) or MPI_RANK_FILE.match(p.name)
        if m and int(m.group(1)) > step:
            os.replace(p, p.with_name(p.name + ".bad"))
        elif re.match(r"^ckpt_\d+\.(h5|mpi\.json|rank\d+\.h5)\.tmp$", p.name):
            p.unlink()
