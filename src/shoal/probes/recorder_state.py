"""What a probe recorder saves in a checkpoint, and how a resumed run gets it back.

A recorder keeps its state in a few attributes: a CSV ``file`` (at
``path``), its in-memory ``rows``, a test-point grid's ``times`` and
``samples``, a tracker's ``ids``. `recorder_state` reads them into one
dict (the checkpoint stores arrays as datasets and the rest as JSON);
`restore_recorder_files` puts them back, the CSV cut to exactly the bytes it
held at the checkpoint. A recorder with more state (`FlowRecorder`) calls
both from its own ``checkpoint_state`` / ``restore_checkpoint_state``; the others inherit them from
`Recorder`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np


def recorder_state(func):
    """The state a probe recorder keeps in its attributes (see `shoal.simulation.checkpoint.callback_state`), as one dict;
    a recorder with more state calls it from its ``checkpoint_state``."""
    state = {}
    f = getattr(func, "file", None)
    path = getattr(func, "path", None)
    if f is not None and path is not None and not getattr(f, "closed", True):
        f.flush()
        state["file_bytes"] = int(os.fstat(f.fileno()).st_size)
        state["file_name"] = Path(path).name
    rows = getattr(func, "rows", None)
    if isinstance(rows, list):
        state["n_rows"] = len(rows)
        if rows:
            state["rows"] = np.asarray(rows, dtype=np.float64)
    times = getattr(func, "times", None)
    samples = getattr(func, "samples", None)
    if isinstance(times, list) and isinstance(samples, list):
        state["times"] = np.asarray(times, dtype=np.float64)
        for key in (samples[0] if samples else {}):
            state[f"samples/{key}"] = np.stack([np.asarray(s[key]) for s in samples])
        state["sample_keys"] = list(samples[0]) if samples else []
    ids = getattr(func, "ids", None)
    if isinstance(ids, np.ndarray):
        state["ids"] = ids
    return state


def file_head(path, n_bytes=None):
    """The first `n_bytes` bytes of file `path` (all of it if None)."""
    with open(path, "rb") as f:
        return f.read() if n_bytes is None else f.read(n_bytes)


def restore_recorder_files(rec, scalars, arrays, backup=None):
    """`restore_recorder` for the state of `recorder_state`: the CSV cut back to its length at
    the checkpoint, the rows, samples and ids; returns the warning (or None)."""
    warning = None
    f = getattr(rec, "file", None)
    if f is not None and backup is not None and Path(backup).exists():
        # the bytes the file held at the checkpoint (rows written after it are dropped)
        n = int(scalars["file_bytes"]) if "file_bytes" in scalars else None
        data = file_head(backup, n)
        if n is not None and len(data) < n:
            data = data[: data.rfind(b"\n") + 1]
            warning = (f"{Path(rec.path).name} held {len(data)} bytes, fewer than the {n} it held at the "
                       "checkpoint: rows recorded before the checkpoint were lost by the system")
        f.flush()
        f.seek(0)
        f.truncate()
        f.write(data.decode("utf-8"))
        f.flush()
        os.fsync(f.fileno())
    if isinstance(getattr(rec, "rows", None), list):
        rows = arrays.get("rows")
        rec.rows[:] = [] if rows is None else [list(map(float, r)) for r in rows]
    if "times" in arrays and isinstance(getattr(rec, "samples", None), list):
        keys = scalars.get("sample_keys", [])
        times = arrays["times"]
        rec.times[:] = [float(t) for t in times]
        rec.samples[:] = [{k: arrays[f"samples/{k}"][i] for k in keys} for i in range(len(times))]
    if "ids" in arrays and isinstance(getattr(rec, "ids", None), np.ndarray):
        rec.ids = arrays["ids"]
    return warning


class Recorder:
    """A recorder whose checkpoint state is what `recorder_state` reads of its attributes (its CSV's
    length, its rows, samples or ids): its ``checkpoint_state`` and ``restore_checkpoint_state``
    say so. Every stateful callback of a run defines the two methods; one that defines neither (a
    log line, the progress bar) has no state to save."""

    def checkpoint_state(self):
        """What a checkpoint keeps of this recorder (`recorder_state`)."""
        return recorder_state(self)

    def restore_checkpoint_state(self, scalars, arrays, backup=None):
        """Put the state of `checkpoint_state` back (`restore_recorder_files`); returns a warning or None."""
        return restore_recorder_files(self, scalars, arrays, backup)
