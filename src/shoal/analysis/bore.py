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


def level_behind(times, levels, t_arrival, delay=0.15):
    """Mean level [m] behind the front: the gauge record from `delay` s after the
    bore's arrival to its end (over the undulations of an undular bore)."""
    t = np.asarray(times, float)
    z = np.asarray(levels, float)
    w = t >= t_arrival + delay
    if w.sum() < 5:
        raise InputError(f"the record ends less than {delay:g} s after the bore arrived: run longer")
    return float(np.mean(z[w]))


def volume_depth(positions, densities, mass, x, half_width, width=None):
    """Clear-water depth [m] at `x`: the volume of the fluid particles within
    `half_width` of x, sum m / rho, per unit plan area.

    d = sum_{|x_i - x| < w} (m / rho_i) / (2 w B), B the flume's width (1 in
    2D, where `mass` is per unit width, rho0 dp^2). This is the depth that the
    bore relations' mass balance (U + c) d0 = c d1 speaks of, and it needs
    no free surface: behind a breaking front, whose broken surface is rough
    and disordered, a wave gauge (kernel-sum threshold S = 1/2) reads below
    it (the breaking bore at dp = 5 mm: 1 to 4 mm, 0.3 to 0.8 dp, below,
    while both read d0 to 0.1 mm in the smooth inflow).

    Parameters
    ----------
    positions : (N, 3) array
        Fluid particle positions [m] (x along the flume).
    densities : (N,) array
        Their densities [kg/m^3].
    mass : float
        Particle mass [kg] (2D: per unit width, kg/m).
    x, half_width : float
        Window centre and half-length along x [m].
    width : float, optional
        Flume width [m] in 3D (the extent in y the particles fill).
    """
    p = np.asarray(positions, float)
    r = np.asarray(densities, float)
    w = float(half_width)
    if not w > 0:
        raise InputError(f"half_width = {half_width!r} must be > 0")
    sel = np.abs(p[:, 0] - float(x)) < w
    return float(np.sum(mass / r[sel]) / (2.0 * w * (1.0 if width is None else float(width))))


def front_position(positions, densities, mass, level, x_max, bin_width, width=None):
    """Position [m] of a bore's front travelling towards +x: where the
    clear-water depth (`volume_depth` over bins of `bin_width` along x, from
    x = 0 to `x_max`) last falls through `level`, linearly interpolated
    between bin centres.

    The depth profile d(x_k) = sum_{i in bin k} (m / rho_i) / (b B) needs no
    free surface, so the front of a breaking bore, whose roller is a
    disordered spray of particles that a wave gauge reads low, is found from
    its water's volume. With `level` = (d0 + d1) / 2 the front's positions
    over time give its celerity (`celerity(fronts, times)`), from every
    snapshot rather than from a few gauges, which a pulsating breaking front
    passes at different phases of its roller. For a sharp step inside one
    bin the interpolation is within 0.09 `bin_width` of the step.

    Parameters
    ----------
    positions : (N, 3) array
        Fluid particle positions [m] (x along the flume, z up).
    densities : (N,) array
        Their densities [kg/m^3].
    mass : float
        Particle mass [kg] (2D: per unit width).
    level : float
        Depth [m] that marks the front, between d0 and d1.
    x_max : float
        End of the profile [m] (keep out an inflow wall's neighbourhood).
    bin_width : float
        Bin length along x [m] (several dp: a bin holds whole columns).
    width : float, optional
        Flume width [m] in 3D.

    Returns
    -------
    float
        The front's x [m]; NaN when no bin reaches `level`.
    """
    p = np.asarray(positions, float)
    r = np.asarray(densities, float)
    b = float(bin_width)
    if not b > 0 or not float(x_max) > b:
        raise InputError(f"bin_width = {bin_width!r} must be > 0 and below x_max = {x_max!r}")
    nb = int(float(x_max) // b)
    k = np.floor(p[:, 0] / b).astype(np.int64)
    ok = (k >= 0) & (k < nb)
    depth = np.bincount(k[ok], weights=mass / r[ok], minlength=nb) / (b * (1.0 if width is None else float(width)))
    wet = np.flatnonzero(depth >= float(level))
    if len(wet) == 0:
        return float("nan")
    j = int(wet[-1])
    xc = (j + 0.5) * b
    if j == nb - 1:
        return float(xc)
    return float(xc + b * (depth[j] - level) / (depth[j] - depth[j + 1]))


def undulations(times, levels, t_arrival, d1, window=1.0):
    """Secondary waves behind a bore front, from a gauge record.

    Returns ``(n_crests, first_crest)``: the number of wave crests (local
    maxima of the record smoothed over 5 samples, standing more than 2 % of
    d1 above the neighbouring troughs)
    within `window` s after `t_arrival`, and the first crest's height over
    the conjugate depth d1, (z_max - d1) / d1. An undular bore (Froude
    number below about 1.3; Favre 1935, Chanson 2009) shows crests with the
    first one well above d1; a breaking bore a single rise to d1 with no
    secondary waves.
    """
    t = np.asarray(times, float)
    z = np.asarray(levels, float)
    w = (t >= t_arrival) & (t <= t_arrival + window)
    if w.sum() < 10:
        raise InputError("too few samples after the bore's arrival")
    zw = np.convolve(z[w], np.ones(5) / 5, mode="valid")
    tol = 0.02 * d1
    crests, low, high, rising = 0, zw[0], zw[0], True
    for v in zw[1:]:  # a hysteresis peak counter (tolerance tol): noise is not a crest
        if rising:
            if v > high:
                high = v
            elif v < high - tol:
                crests += 1
                rising, low = False, v
        else:
            if v < low:
                low = v
            elif v > low + tol:
                rising, high = True, v
    return crests, float((zw.max() - d1) / d1)


def crest_speed_ratio(positions, velocities, depth, d1, celerity, direction=1.0, dim_z=2):
    """The kinematic breaking index of a bore: the largest horizontal particle
    speed in the bore's direction in the raised water, over the bore's celerity.

    A wave front breaks when its crest's water overtakes the front, i.e. when
    the horizontal velocity of crest particles reaches the crest's speed
    (the kinematic breaking criterion: Perlin, Choi & Tian 2013, Ann. Rev.
    Fluid Mech. 45; for bores, the roller's surface flow outruns the toe:
    Chanson 2009). Water in the raised layer, z > d0 + (d1 - d0) / 2, is
    searched, in the ground frame, where the bore travels at `celerity`
    along `direction` (+1 or -1 along x). B = max(u_x direction) / c: an
    undular bore has B well below 1 (its orbital velocities are a fraction
    of c), a breaking bore's plunging crest B >= 1.

    Parameters
    ----------
    positions, velocities : (n, 3) arrays
        Fluid particles' positions [m] and velocities [m/s].
    depth, d1 : float
        Depth ahead of the bore d0 and conjugate depth d1 [m] (Belanger,
        `bore_from_inflow`).
    celerity : float
        The bore's celerity c [m/s], ground frame.

    Returns
    -------
    float
        B (0 when no water is above the mid level).
    """
    p = np.asarray(positions, float)
    v = np.asarray(velocities, float)
    if not celerity > 0:
        raise InputError(f"celerity = {celerity!r}; it must be positive")
    up = p[:, dim_z] > depth + 0.5 * (d1 - depth)
    if not up.any():
        return 0.0
    return float(np.max(direction * v[up, 0]) / celerity)
