"""A Case: everything needed to set up a simulation, as plain data.

Built-in cases (`shoal.cases`) are functions returning a `Case`. A Case
holds the generated particles, the domain, the fluid constants, the scheme
options and the run controls (end time, output interval).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .options import SPHOptions


@dataclass
class Case:
    """A simulation set-up.

    Parameters
    ----------
    name : str
        Case name (used for output file names).
    dim : {2, 3}
    dp : float
        Particle spacing [m].
    positions : (N, 3) array
        Particle positions [m] (world coordinates).
    kinds : (N,) int array
        0 fluid, 1 fixed boundary, 2 moving boundary.
    domain : tuple of two 3-sequences
        Computational box (lo, hi) [m]; particles leaving it are removed.
    options : SPHOptions
    rho0 : float
        Reference density [kg/m^3].
    gravity : 3-sequence
        Gravity [m/s^2].
    fluid_height : float
        Reference depth H [m] for c0 = coef_sound sqrt(g H).
    surface_z : float or None
        Initial free-surface level for the hydrostatic initial density.
    end_time : float
        Simulated time to run [s].
    output_interval : float
        Time between particle snapshots [s].
    description : str
        What the case is and what it is compared with.
    parameters : dict
        The parameters the case function was called with (for the record).
    """

    name: str
    dim: int
    dp: float
    positions: np.ndarray
    kinds: np.ndarray
    domain: tuple
    options: SPHOptions = field(default_factory=SPHOptions)
    rho0: float = 1000.0
    gravity: tuple = (0.0, 0.0, -9.81)
    fluid_height: float | None = None
    surface_z: float | None = None
    end_time: float = 1.0
    output_interval: float = 0.1
    description: str = ""
    parameters: dict = field(default_factory=dict)

    @property
    def n_particles(self):
        return len(self.positions)

    @property
    def n_fluid(self):
        return int(np.count_nonzero(np.asarray(self.kinds) == 0))

    def summary(self):
        """A dict describing the case (for the resolved-parameters file)."""
        return {
            "name": self.name, "dim": self.dim, "dp": self.dp,
            "particles": self.n_particles, "fluid_particles": self.n_fluid,
            "domain": [list(map(float, self.domain[0])), list(map(float, self.domain[1]))],
            "rho0": self.rho0, "gravity": list(map(float, self.gravity)),
            "fluid_height": self.fluid_height, "surface_z": self.surface_z,
            "end_time": self.end_time, "output_interval": self.output_interval,
            "parameters": self.parameters, "options": self.options.to_dict(),
        }
