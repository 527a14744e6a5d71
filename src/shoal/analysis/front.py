"""Surge-front position of a dam break."""

import numpy as np

from ..physics.spec import FLUID


def surge_front(model, x0=0.0):
    """Distance of the leading fluid particle from the back wall at `x0` [m].

    The front is the largest x of the active fluid particles (as in the
    PySPH and DualSPHysics dam-break comparisons); Martin & Moyce (1952)
    recorded the leading edge of the surge along the bed.
    """
    fluid = model.host(model.kind) == FLUID
    return float(np.max(model.host(model.pos)[:, 0][fluid])) - x0


def outside_band(T, Z, band_a, band_b, times):
    """Largest distance of a front Z(T) outside the band between two experiments, relative to the
    band's lower edge, over `times`: max_t max(lo - Z, Z - hi, 0) / lo, with (lo, hi) the two
    experiments' fronts at t (each a (T, Z) pair of arrays, interpolated linearly)."""
    worst = 0.0
    for t in times:
        lo, hi = sorted((np.interp(t, *band_a), np.interp(t, *band_b)))
        z = np.interp(t, T, Z)
        worst = max(worst, max(lo - z, z - hi, 0.0) / lo)
    return float(worst)
