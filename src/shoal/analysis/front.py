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
