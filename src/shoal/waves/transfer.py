"""Wavemaker transfer functions: the height H of the progressive wave a paddle of stroke S makes, in linear
theory (Biesel & Suquet 1951; Dean & Dalrymple 1991, section 6.3).

The paddle's horizontal displacement X(z, t) = (S(z) / 2) sin(omega t) is projected onto the progressive mode
cosh k(d + z) of the water's motion (the rest goes into evanescent modes that die out within a few depths of
the paddle):

    H / S = 4 sinh(kd) I / (sinh 2kd + 2kd),   I = k int_{-d}^{0} (S(z) / S) cosh k(d + z) dz,

with S the stroke at the still-water level. A piston (S(z) = S) has I = sinh kd; a flap hinged at the height
l above the bed (S(z) = S (d + z - l) / (d - l) above the hinge, 0 below) has
I = sinh kd - (cosh kd - cosh kl) / (k (d - l)).

Both ratios tend to kd (piston) and kd / 2 (flap on the bed) in shallow water, where the wave's volume is the
volume the paddle sweeps, and to 2 in deep water, where only the motion near the surface counts.
"""

from __future__ import annotations

import math

import numpy as np

_DEEP = 20.0
"""kd above which the ratios are computed from the scaled exponentials (exp(-2kd) < 5e-18, no overflow)."""


def _piston(k, depth):
    kd2 = 2.0 * k * depth
    if kd2 > 50.0:  # deep water: the ratio is 2 to double precision (and cosh, sinh overflow past 710)
        return 2.0
    return 2.0 * (math.cosh(kd2) - 1.0) / (math.sinh(kd2) + kd2)


def piston_height_to_stroke(k, depth):
    """Biesel transfer function of a piston wavemaker,
    H / S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd) (Biesel & Suquet 1951; Dean & Dalrymple 1991, Eq. 6.21).

    Tends to kd in shallow water and to 2 in deep water (2 exactly for 2kd > 50, where the difference is below
    double precision and cosh, sinh would overflow past 2kd = 710).

    Parameters
    ----------
    k : float or array_like
        Wavenumber [1/m] (`shoal.waves.wavenumber`).
    depth : float
        Still-water depth d [m] at the paddle.

    Returns
    -------
    float or numpy.ndarray
        H / S; an array (each element computed as the float would be) for an array `k`.
    """
    if np.ndim(k) == 0 and np.ndim(depth) == 0:
        return _piston(float(k), float(depth))
    k, depth = np.broadcast_arrays(np.asarray(k, float), np.asarray(depth, float))
    return np.array([_piston(float(a), float(b)) for a, b in zip(k.ravel(), depth.ravel())]).reshape(k.shape)


def _flap(k, depth, hinge):
    kd = k * depth
    arm = depth - hinge          # from the hinge to the still-water level [m]
    lo = max(hinge, 0.0)         # the paddle moves water from the bed or the hinge, whichever is higher
    if kd == 0.0:
        return 0.0
    if kd > _DEEP:
        q = math.exp(-2.0 * kd)
        below = math.exp(-k * (depth - lo)) * (1.0 + math.exp(-2.0 * k * lo))   # cosh(k lo) / (e^kd / 2)
        inner = (1.0 - q) - ((1.0 + q) - below) / (k * arm)
        return 2.0 * (1.0 - q) * inner / ((1.0 - q * q) + 4.0 * kd * q)
    s = math.sinh(kd)
    # cosh kd - cosh k lo = 2 sinh(k (d + lo) / 2) sinh(k (d - lo) / 2), without the cancellation near kd = 0
    delta = 2.0 * math.sinh(0.5 * k * (depth + lo)) * math.sinh(0.5 * k * (depth - lo))
    return 4.0 * s * (s - delta / (k * arm)) / (math.sinh(2.0 * kd) + 2.0 * kd)


def flap_height_to_stroke(k, depth, hinge=0.0):
    """Transfer function of a flap wavemaker hinged at the height `hinge` l above the bed, the stroke S measured
    at the still-water level:

        H / S = 4 sinh(kd) [sinh kd - (cosh kd - cosh kl) / (k (d - l))] / (sinh 2kd + 2kd).

    For a flap hinged at the bed (l = 0) this is
    H / S = 4 (sinh kd / kd) (kd sinh kd - cosh kd + 1) / (sinh 2kd + 2kd) (Biesel & Suquet 1951; Dean &
    Dalrymple 1991, Eq. 6.23); for l > 0 it is the same projection of the paddle's displacement onto the
    progressive mode (module docstring; Biesel & Suquet 1951; hinged paddles of any draft: Hudspeth & Guenther
    2009), the water below the hinge held by a fixed wall. A hinge below the bed (l < 0) is allowed: the paddle
    then also moves at the bed, by -l / (d - l) of its stroke, and the ratio tends to the piston's as
    l -> -inf.

    Tends to kd / 2 (l = 0) in shallow water and to 2 in deep water; computed from exp(-2kd) for kd > 20
    (no overflow).

    Parameters
    ----------
    k : float or array_like
        Wavenumber [1/m] (`shoal.waves.wavenumber`).
    depth : float
        Still-water depth d [m] at the paddle.
    hinge : float
        Height l [m] of the hinge above the bed, below the still-water level (l < d).

    Returns
    -------
    float or numpy.ndarray
        H / S, of the shape of `k`.

    Raises
    ------
    ValueError
        For a hinge at or above the still-water level.
    """
    if not hinge < depth:
        raise ValueError(f"hinge = {hinge:g} m is not below the still-water level d = {depth:g} m: a flap hinged "
                         "there moves no water; give hinge < depth (0: hinged at the bed, negative: below it)")
    if np.ndim(k) == 0:
        return _flap(float(k), float(depth), float(hinge))
    k = np.asarray(k, float)
    return np.array([_flap(a, float(depth), float(hinge)) for a in k.ravel()]).reshape(k.shape)
