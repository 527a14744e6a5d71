"""The free surface on a vertical line of SPH samples: where the fluid's kernel sum crosses 1/2.

The kernel sum S(x) = sum_j V_j W(x - x_j) of the fluid particles is 1 inside the water, 0 in the air and
about 1/2 on a free surface, where half of the kernel's support is wet. A wave gauge (`shoal.probes.WaveGauge`)
and an active absorber (`shoal.active_absorption`) sample S upwards along a vertical line and read the level
as its highest crossing of 1/2 -- the kernel-sum threshold of DualSPHysics's MeasureTool.
"""

from __future__ import annotations

import numpy as np


def surface_level(z, s, threshold=0.5):
    """Highest z where the kernel sum s (sampled upwards at z) is >= threshold,
    linearly interpolated to the crossing; NaN if the line is all dry, z[-1]
    if it is all wet."""
    wet = s >= threshold
    if not wet.any():
        return float("nan")
    k = int(np.flatnonzero(wet)[-1])
    if k == len(z) - 1:
        return float(z[-1])
    s0, s1 = s[k], s[k + 1]
    return float(z[k] + (s0 - threshold) / (s0 - s1) * (z[k + 1] - z[k]))
