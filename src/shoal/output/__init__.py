"""Simulation output: VTU snapshots, the PVD time index and quick-look plots."""

from shoal.output.plot import plot_particles
from shoal.output.pvd import PVDWriter
from shoal.output.vtu import read_vtu, write_vtu

__all__ = ["PVDWriter", "plot_particles", "read_vtu", "write_vtu"]
