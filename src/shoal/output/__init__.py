"""Simulation output: VTU snapshots (PVTU pieces under MPI), the PVD time index and quick-look plots."""

from shoal.output.plot import plot_particles
from shoal.output.pvd import PVDWriter, read_pvd
from shoal.output.vtu import read_pvtu, read_vtu, write_pvtu, write_vtu

__all__ = ["PVDWriter", "plot_particles", "read_pvtu", "read_vtu", "write_pvtu", "write_vtu"]
