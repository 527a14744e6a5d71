"""Writers: particle snapshots (VTU + PVD collection) as scheduled callbacks."""

from __future__ import annotations

import math
from pathlib import Path

from ..output import PVDWriter, write_vtu


def remove_snapshots(directory, name, first):
    """Remove the snapshots numbered `first` and later (written after the
    checkpoint a run resumes from): ``<name>_NNNN.vtu``, and a run on
    several MPI ranks' ``<name>_NNNN.pvtu`` and piece folders ``<name>_NNNN/``.

    Parameters
    ----------
    directory : Path
        The run directory.
    name : str
        The case name (the snapshots' prefix).
    first : int
        The first snapshot number removed.
    """
    import shutil

    for p in Path(directory).glob(f"{name}_[0-9][0-9][0-9][0-9]*"):
        stem = p.name[len(name) + 1:].split(".")[0]
        if not (stem.isdigit() and int(stem) >= first):
            continue
        if p.is_dir():
            shutil.rmtree(p, ignore_errors=True)
        elif p.suffix in (".pvtu", ".vtu"):
            p.unlink()


class SnapshotWriter:
    """Write the active particles as ``<dir>/<name>_NNNN.vtu`` plus ``<name>.pvd``.

    Point data: velocity (3 components), density, pressure, id and kind
    (0 fluid, 1 fixed boundary, 2 moving boundary).
    """

    def __init__(self, directory, name, resume=False):
        self.directory = Path(directory)
        self.name = name
        self.pvd = PVDWriter(self.directory, name, resume=resume)
        self.count = 0
        self.last_time = None

    def checkpoint_state(self):
        """What a checkpoint keeps: the number of snapshots written (`count`,
        the next file number) and the time of the last one."""
        return {"count": self.count, "last_time": self.last_time}

    def restore_checkpoint_state(self, scalars, arrays, backup=None):
        """Continue the series after a checkpoint: the next snapshot is number
        ``count``; the collection drops entries after the checkpoint's last
        snapshot, and snapshot files numbered from ``count`` on (written by the
        interrupted run after the checkpoint, `remove_snapshots`) are removed.
        The collection may list a run on several MPI ranks' ``.pvtu`` files
        (a single-process resume of such a run): it goes on with ``.vtu``
        files, one time series still."""
        self.count = int(scalars["count"])
        self.last_time = None if scalars.get("last_time") is None else float(scalars["last_time"])
        self.pvd.truncate(-math.inf if self.last_time is None else self.last_time)
        remove_snapshots(self.directory, self.name, self.count)

    def __call__(self, sim):
        self.write(sim.model, sim.time)

    def finalize(self, sim):
        """At the end of a run: the last state, unless the schedule has just written it."""
        if self.last_time is None or self.last_time < sim.time - 1e-12:
            self(sim)

    def write(self, model, time, suffix=None):
        """Write one snapshot of `model` at `time` [s]; returns the path."""
        fname = f"{self.name}_{self.count:04d}.vtu" if suffix is None else f"{self.name}_{suffix}.vtu"
        path = self.directory / fname
        write_vtu(path, model.world_positions(), model.fields(), time=time)
        if suffix is None:
            self.pvd.add(time, fname)
            self.count += 1
            self.last_time = time
        return path
