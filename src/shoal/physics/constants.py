"""The constants a scheme derives from a case, each defined once.

The model (`shoal.model.Model`), ``shoal check`` (`shoal.check`), the memory
check before a run (`shoal.memory`) and the case's own validation
(`shoal.case.Case`) all take them from here:

* smoothing length ``h = coef_h sqrt(dim) dp`` (DualSPHysics's convention;
  the kernel support is 2h);
* speed of sound ``c0 = coef_sound U``, ``U = u_max`` when given, else
  ``sqrt(|g| H)`` of the reference depth H (Monaghan 1994: c0 >= 10 U keeps
  density variations below about 1 %); the equation of state's coefficient
  ``B = c0^2 rho0 / gamma`` is `shoal.physics.eos.tait_coefficient`;
* particle mass ``m = rho0 dp^dim`` (every particle, fluid and boundary);
* the neighbour grid's cell count (`shoal.neighbours.grid.grid_dims`, cells
  of edge 2h / cells_per_support).
"""

from __future__ import annotations

import math

import numpy as np

from ..neighbours.grid import grid_dims


def smoothing_length(coef_h, dim, dp):
    """h = coef_h sqrt(dim) dp [m]."""
    return float(coef_h) * math.sqrt(dim) * float(dp)


def reference_speed(gravity, depth=None, u_max=None):
    """U [m/s] that sets the speed of sound: `u_max` when given, else sqrt(|g| depth); None when
    neither can be formed (no u_max, and no depth)."""
    if u_max is not None:
        return float(u_max)
    if depth is None:
        return None
    return math.sqrt(float(np.linalg.norm(np.asarray(gravity, np.float64))) * float(depth))


def speed_of_sound(coef_sound, gravity, depth=None, u_max=None):
    """c0 = coef_sound U [m/s] (`reference_speed`); None when U cannot be formed."""
    u = reference_speed(gravity, depth, u_max)
    return None if u is None else float(coef_sound) * u


def particle_mass(rho0, dp, dim):
    """m = rho0 dp^dim [kg] (2D: per metre of width, kg/m)."""
    return float(rho0) * float(dp) ** dim


def cell_count(lo, hi, h, cells_per_support, periodic=None):
    """Cells of the neighbour grid over the box [lo, hi) (2D: x, z) for smoothing length `h`."""
    return int(np.prod(grid_dims(lo, hi, 2.0 * h / cells_per_support, periodic)))
