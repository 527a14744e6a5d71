"""Writers: particle snapshots (VTU + PVD collection) as scheduled callbacks."""

from __future__ import annotations

from pathlib import Path

from ..output import PVDWriter, write_vtu


class SnapshotWriter:
    """Write the active particles as ``<dir>/<name>_NNNN.vtu`` plus ``<name>.pvd``.

    Point data: velocity (3 components), density, pressure, id and kind
    (0 fluid, 1 fixed boundary, 2 moving boundary).
    """

    def __init__(self, directory, name):
        self.directory = Path(directory)
        self.name = name
        self.pvd = PVDWriter(self.directory, name)
        self.count = 0
        self.last_time = None

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
