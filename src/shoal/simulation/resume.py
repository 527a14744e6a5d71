"""Reading a run's newest checkpoint back, of either kind.

A single-process run writes ``ckpt_NNNNNN.h5`` (`shoal.simulation.checkpoint`);
a run on several MPI ranks writes one such file per rank,
``ckpt_NNNNNN.rank<RRRR>.h5``, and then the manifest ``ckpt_NNNNNN.mpi.json``
that names them with their SHA-256 (`shoal.parallel.checkpoint` writes them).
`latest_checkpoint` picks the newest usable checkpoint of either kind (a
damaged one is skipped with a warning); a run on several ranks comes back
as the union of its ranks' owned particles (`read_union`), which a
single-process run continues from (`shoal.parallel.checkpoint.for_one_process`)
and a run on another number of ranks re-distributes.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import InputError
from .checkpoint import (CHECKPOINT_NAME, MPI_MANIFEST, Checkpoint, CheckpointError, list_checkpoints,
                         read_checkpoint)

MANIFEST_FORMAT = "shoal-mpi-checkpoint"
MANIFEST_VERSION = 1


def rank_path(out_dir, step, rank):
    """``out_dir/ckpt_NNNNNN.rank<RRRR>.h5``."""
    return Path(out_dir) / f"ckpt_{int(step):06d}.rank{int(rank):04d}.h5"


def manifest_path(out_dir, step):
    """``out_dir/ckpt_NNNNNN.mpi.json``."""
    return Path(out_dir) / f"ckpt_{int(step):06d}.mpi.json"


def list_manifests(out_dir):
    """Checkpoint manifests in `out_dir`, newest (highest step) first."""
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        return []
    found = [(int(m.group(1)), p) for p in out_dir.iterdir() if (m := MPI_MANIFEST.match(p.name))]
    return [p for _, p in sorted(found, reverse=True)]


def stored_digest(path):
    import h5py

    with h5py.File(path, "r") as f:
        d = f.attrs.get("sha256")
    return d.decode() if isinstance(d, bytes) else str(d)


def read_manifests(out_dir, warn=None):
    """The checkpoint manifests in `out_dir` that read back, newest first.

    Parameters
    ----------
    out_dir : path
        The run directory.
    warn : callable, optional
        ``warn(message)`` for each manifest skipped (unreadable, not JSON,
        another format or version, fields missing).

    Returns
    -------
    list of (Path, dict)
        Each manifest and its contents.
    """
    found = []
    for p in list_manifests(out_dir):
        try:
            obj = json.loads(p.read_text())
            if obj.get("format") != MANIFEST_FORMAT or obj.get("version") != MANIFEST_VERSION:
                raise ValueError(f"not a {MANIFEST_FORMAT} version {MANIFEST_VERSION} manifest")
            int(obj["ranks"]), list(obj["files"]), list(obj["sha256"])
        except (OSError, ValueError, KeyError, TypeError) as err:
            if warn is not None:
                warn(f"checkpoint {p} skipped: its manifest cannot be read ({err}); falling back to the "
                     "previous one")
            continue
        found.append((p, obj))
    return found


def read_union(out_dir, manifest, obj, rank=0):
    """The union of the owned particles of every rank file a manifest names.

    Parameters
    ----------
    out_dir : path
        The run directory.
    manifest : Path
        The manifest (``ckpt_NNNNNN.mpi.json``).
    obj : dict
        Its contents (`read_manifests`).
    rank : int, default 0
        The reading rank: the length of its ``escaped*.csv`` at the
        checkpoint is kept as ``meta["mpi"]["escaped_bytes"]``.

    Returns
    -------
    Checkpoint
        The owned particles of every rank (never the ghosts) with their
        integrator state, rank by rank in each rank's order; the probes' and
        snapshots' state of rank 0's file; ``meta["mpi"]`` marks it for
        re-distribution (`restore_rank`) or for a single process
        (`for_one_process`).

    Raises
    ------
    CheckpointError
        A rank file is missing, unreadable, damaged or not the file the
        manifest names (another SHA-256).
    """
    out_dir = Path(out_dir)
    try:
        cks = [read_rank_file(out_dir / f, d, manifest) for f, d in zip(obj["files"], obj["sha256"])]
    except OSError as err:
        raise CheckpointError(f"{manifest.name}: a rank file cannot be read ({err.strerror or err})") from None
    return union_of_ranks(cks, manifest, rank)


def checkpoint_step(path):
    return int(Path(path).name.split("_")[1].split(".")[0])


def read_rank_file(path, digest, manifest):
    ck = read_checkpoint(path)
    if stored_digest(path) != digest:
        raise CheckpointError(f"{path.name} is not the file {manifest.name} names (another checksum)")
    return ck


# the per-particle arrays a DistributedModel saves (`checkpoint_arrays`; xsph, tau, vwall when in use)
PARTICLE_NAMES = ("pos", "vel", "rho", "kind", "idp", "ace", "drho", "mu_max", "pr2", "xsph", "tau", "vwall")


def union_of(path, first, parts, rank, escaped_bytes, n_escaped, sort_count, rebalances, source):
    """A Checkpoint holding the active particles of every part (``(ck, rows, n_integrator)``),
    marked for re-distribution over the ranks (`restore_rank` keeps this rank's slab).
    `escaped_bytes`: the length at the checkpoint of each writer's ``escaped*.csv``
    (one per rank of the run written, in rank order); this rank's is kept as
    ``escaped_bytes``."""
    names = [k for k in PARTICLE_NAMES if k in first.particles]
    particles = {k: np.concatenate([c.particles[k][rows] for c, rows, _ in parts]) for k in names}
    n_int = parts[0][2]
    extra = [np.concatenate([c.extra[i][rows] for c, rows, _ in parts]) for i in range(n_int)]
    meta = json.loads(json.dumps(first.meta))
    meta["model"]["n"] = int(len(particles["pos"]))
    mine = int(escaped_bytes[rank]) if rank < len(escaped_bytes) else 0
    meta["mpi"] = {"redistribute": True, "source": source, "n_escaped": int(n_escaped), "sort_count": int(sort_count),
                   "rebalances": rebalances, "escaped_bytes": mine,
                   "escaped_bytes_ranks": [int(b) for b in escaped_bytes]}
    return Checkpoint(Path(path), meta, first.case_toml, particles, extra, first.callbacks, {})


def union_of_ranks(cks, path, rank):
    """The union of the owned particles of the rank files `cks` (another rank count)."""
    parts = [(c, np.flatnonzero(c.extra[-1] == 0), len(c.extra) - 1) for c in cks]  # ghost flags: the last array
    mpis = [c.meta["mpi"] for c in cks]
    escaped = [m["escaped_bytes"] for m in mpis]
    return union_of(path, cks[0], parts, rank, escaped, sum(c.meta["model"]["n_escaped"] for c in cks),
                  mpis[0]["sort_count"], mpis[0].get("rebalances", []), f"{len(cks)} MPI ranks")


def union_of_single(ck, rank):
    """The active particles of a single-process checkpoint `ck`, to re-distribute."""
    n = int(ck.meta["model"]["n"])
    escaped = 0
    for cb in ck.meta["callbacks"]:
        if cb["name"] == "escaped":
            escaped = int(cb.get("state", {}).get("file_bytes", 0))
    return union_of(ck.path, ck, [(ck, np.arange(n), len(ck.extra))], rank, [escaped], ck.meta["model"]["n_escaped"],
                  int(ck.meta["step_count"]) + 1, [], "1 process")


def latest_checkpoint(out_dir, warn=None, mpi=True):
    """The newest usable checkpoint in `out_dir`.

    Parameters
    ----------
    out_dir : path
        The run directory.
    warn : callable, optional
        ``warn(message)``: one line for each checkpoint skipped (it does not
        read back or verify) before the previous one is tried.
    mpi : bool, default True
        Also consider the checkpoints of a run on several MPI ranks (the
        manifests ``ckpt_NNNNNN.mpi.json``, `shoal.parallel.checkpoint`);
        whichever kind is newest (the highest step; a single-process one on
        a tie) is read.

    Returns
    -------
    Checkpoint
        A single-process checkpoint, or the union of the owned particles of
        a run on several ranks (every rank file verified against the
        manifest's SHA-256; ``meta["mpi"]["redistribute"]`` is true, see
        `read_union`).

    Raises
    ------
    InputError
        No checkpoint, or none that reads back and verifies.
    """
    candidates = [(int(CHECKPOINT_NAME.match(p.name).group(1)), 1, p, None) for p in list_checkpoints(out_dir)]
    if mpi:
        candidates += [(int(MPI_MANIFEST.match(p.name).group(1)), 0, p, obj)
                       for p, obj in read_manifests(out_dir, warn)]
    if not candidates:
        kinds = "ckpt_NNNNNN.h5 or ckpt_NNNNNN.mpi.json" if mpi else "ckpt_NNNNNN.h5"
        raise InputError(f"{out_dir} holds no checkpoint ({kinds}) to resume from: the run stopped before its "
                         "first one; start it again with --overwrite")
    candidates.sort(key=lambda c: c[:2], reverse=True)
    for _, _, p, obj in candidates:
        try:
            if obj is None:
                return read_checkpoint(p)
            return read_union(out_dir, p, obj)
        except CheckpointError as err:
            if warn is not None:
                warn(f"checkpoint {p} skipped: {err}; falling back to the previous one")
    raise InputError(f"none of the {len(candidates)} checkpoints in {out_dir} is readable "
                     f"({', '.join(c[2].name for c in candidates)}); the run cannot be resumed")


def check_same_case(case, ck):
    """InputError unless `case` is the case checkpoint `ck` was written with
    (end_time, [checkpoint] and max_escaped_fraction may differ)."""
    import tomllib

    from ..casefile import dumps_case

    a = tomllib.loads(ck.case_toml)
    b = tomllib.loads(dumps_case(case, commented=False))
    # parameters: how a built-in case was made, a record that is not the case (a commented case file keeps them
    # as a comment only, so the case.toml a run writes loads without them)
    free = ("end_time", "checkpoint", "max_escaped_fraction", "parameters")
    diff = sorted(k for k in set(a) | set(b) if k not in free and a.get(k) != b.get(k))
    if diff:
        raise InputError(f"the case differs from the one {ck.path.name} was written with (in: {', '.join(diff)}); "
                         "a resumed run continues the same case: only end_time, [checkpoint] and "
                         "max_escaped_fraction may change")


def check_same_data(case, out_dir):
    """InputError if a data file of `case` (`shoal.Case.data_files`) is missing or differs from the
    one the run in `out_dir` started with (its SHA-256 in ``resolved.json``): the case file names a
    data file only by its path, and a resumed run must continue the same case. A run directory
    whose ``resolved.json`` records no data files (written before they were recorded) is not checked."""
    try:
        recorded = json.loads((Path(out_dir) / "resolved.json").read_text(encoding="utf-8")).get("data_files")
    except (OSError, ValueError, AttributeError):
        return
    if not isinstance(recorded, dict):
        return
    now = case.data_files()
    for path, digest in recorded.items():
        if path in now and now[path] == digest:
            continue
        if now.get(path, digest) is None or not Path(path).is_file():
            raise InputError(f"{path} is missing: the run in {out_dir} read it when it started; put it back to "
                             "resume the run, or start it again with --overwrite")
        raise InputError(f"{path} has changed since the run in {out_dir} started (its SHA-256 differs from the one "
                         "in resolved.json): a resumed run continues the same case; restore the file, or start the "
                         "run again with --overwrite")
