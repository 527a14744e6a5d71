"""Tait equation of state (Monaghan 1994; Batchelor 1967).

p = B [ (rho / rho0)^gamma - 1 ],  B = c0^2 rho0 / gamma,  gamma = 7,

with the speed of sound c0 = coef_sound * U_max (c0 >= 10 U_max keeps
density variations below about 1 %).
"""

import numpy as np

GAMMA = 7.0


def make_eos(jit, spec):
    """Return ``pressure(rho, P)`` compiled with `jit` (gamma = 7 unrolled)."""
    F = spec.float_type
    one = F(1.0)

    @jit
    def pressure(rho, P):
        x = rho * P.inv_rho0
        x2 = x * x
        x4 = x2 * x2
        return P.B * (x4 * x2 * x - one)

    return pressure


def sound_speed(c0, rho, rho0, gamma=GAMMA):
    """Local sound speed c = c0 (rho / rho0)^((gamma - 1) / 2) (NumPy)."""
    return c0 * (rho / rho0) ** ((gamma - 1.0) / 2.0)


def tait_coefficient(c0, rho0, gamma=GAMMA):
    """B = c0^2 rho0 / gamma [Pa]."""
    return float(c0) ** 2 * float(rho0) / gamma


def pressure_of(rho, rho0, B, gamma=GAMMA):
    """p = B [(rho / rho0)^gamma - 1] [Pa] (NumPy, float64)."""
    return B * ((np.asarray(rho, np.float64) / rho0) ** gamma - 1.0)


def density_of(p, rho0, B, gamma=GAMMA):
    """The inverse of `pressure_of`: rho = rho0 (1 + p / B)^(1 / gamma) [kg/m^3] (NumPy, float64); with
    the hydrostatic p = rho0 |g| depth, the density of water at rest at that depth."""
    return rho0 * (1.0 + np.asarray(p, np.float64) / B) ** (1.0 / gamma)
