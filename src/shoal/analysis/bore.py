"""Bores: the Rankine-Hugoniot (Belanger) state of a bore made by stopping a
flow, and the bore's celerity measured by wave gauges.

Water of depth d0 flows at speed U towards a wall (a closed gate); the
bore that forms travels upstream at celerity c (ground frame), leaving
water at rest of depth d1 behind it. In the bore's frame the water arrives
at U + c with depth d0 and leaves at c with depth d1; mass and momentum
across the front (per unit width, hydrostatic pressure) give

    (U + c) d0 = c d1,
    (U + c)^2 d0 + g d0^2 / 2 = c^2 d1 + g d1^2 / 2,

whose solution is Belanger's d1 / d0 = (sqrt(1 + 8 Fr^2) - 1) / 2 with
Fr = (U + c) / sqrt(g d0) the bore's Froude number.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError


def bore_from_inflow(inflow_speed, depth, g=9.81):
    """(celerity c [m/s] ground frame, conjugate depth d1 [m], Froude number Fr)
    of the bore made when a flow of depth `depth` at `inflow_speed` is stopped."""
    U, d0 = float(inflow_speed), float(depth)
    if not (U > 0 and d0 > 0):
        raise InputError("inflow_speed and depth must be positive")
    lo, hi = 1.0, 50.0
    for _ in range(200):
        fr = 0.5 * (lo + hi)
        d1 = d0 * 0.5 * (math.sqrt(1 + 8 * fr * fr) - 1)
        c = fr * math.sqrt(g * d0) - U
        if (U + c) * d0 - c * d1 > 0:  # continuity not yet met: a stronger bore
            lo = fr
        else:
            hi = fr
    fr = 0.5 * (lo + hi)
    return fr * math.sqrt(g * d0) - U, d0 * 0.5 * (math.sqrt(1 + 8 * fr * fr) - 1), fr


def arrival_time(times, levels, threshold):
    """First time the level reaches `threshold` [m], linearly interpolated (NaN if never)."""
    t = np.asarray(times, float)
    z = np.asarray(levels, float)
    above = np.flatnonzero(z >= threshold)
    if len(above) == 0:
        return float("nan")
    k = int(above[0])
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (threshold - z[k - 1]) / (z[k] - z[k - 1]) * (t[k] - t[k - 1]))


def celerity(xs, arrivals):
    """Bore celerity [m/s]: the least-squares slope of gauge position against arrival time."""
    xs = np.asarray(xs, float)
    ts = np.asarray(arrivals, float)
    ok = np.isfinite(ts)
    if ok.sum() < 2:
        raise InputError("the bore reached fewer than two gauges")
    return float(np.polyfit(ts[ok], xs[ok], 1)[0])
