"""Writers: particle snapshots (VTU + PVD collection) as scheduled callbacks."""

from __future__ import annotations

import math
from pathlib import Path

from ..output import PVDWriter, write_vtu


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
        interrupted run after the checkpoint) are removed."""
        self.count = int(scalars["count"])
        self.last_time = None if scalars.get("last_time") is None else float(scalars["last_time"])
        self.pvd.truncate(-math.inf if self.last_time is None else self.last_time)
        for p in self.directory.glob(f"{self.name}_[0-9][0-9][0-9][0-9]*.vtu"):
            stem = p.stem[len(self.name) + 1:]
            if stem.isdigit() and int(stem) >= self.count:
                p.unlink()

    def __call__(self, sim):
        self.write(sim.model, sim.time)

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
