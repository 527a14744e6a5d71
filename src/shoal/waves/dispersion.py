"""The linear dispersion relation of water waves, omega^2 = g k tanh(k d) (Airy 1845; Dean & Dalrymple 1991,
ch. 4), and the group velocity that follows from it."""

from __future__ import annotations

import math

import numpy as np

GRAVITY = 9.81
"""g [m/s^2] of the wave theory of the wave makers (whatever a case's own `gravity`)."""


def wavenumber(period, depth, g=GRAVITY):
    """Wavenumber k [1/m] of linear waves of `period` T [s] in water of `depth` d [m].

    Solves omega^2 = g k tanh(k d), omega = 2 pi / T (Airy 1845; Dean & Dalrymple 1991, ch. 4) by Newton's method
    from the larger of the deep-water guess omega^2 / g and the shallow-water guess omega / sqrt(g d), both below
    the root.

    Parameters
    ----------
    period, depth : float
        T [s] and d [m], positive.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    float
    """
    omega = 2.0 * math.pi / period
    k = max(omega**2 / g, omega / math.sqrt(g * depth))
    for _ in range(100):
        t = math.tanh(k * depth)
        f = g * k * t - omega**2
        df = g * t + g * k * depth * (1.0 - t * t)
        dk = f / df
        k -= dk
        if abs(dk) < 1e-14 * k:
            break
    return k


def wavenumbers(omega, depth, g=GRAVITY):
    """Wavenumbers k [1/m] of linear waves of angular frequencies `omega` [rad/s] in water of `depth` d [m].

    The vectorised `wavenumber`: omega^2 = g k tanh(k d) solved by Newton's method for every element at once,
    from the same guess; omega = 0 gives k = 0.

    Parameters
    ----------
    omega : array_like
        Angular frequencies [rad/s], non-negative.
    depth : float
        d [m], positive.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    numpy.ndarray
        k, of the shape of `omega`.
    """
    omega = np.asarray(omega, float)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        k = np.maximum(omega**2 / g, omega / math.sqrt(g * depth))
        for _ in range(100):
            t = np.tanh(k * depth)
            f = g * k * t - omega**2
            df = g * t + g * k * depth * (1.0 - t * t)
            dk = np.where(df > 0, f / np.where(df > 0, df, 1.0), 0.0)
            k = k - dk
            if not np.any(np.abs(dk) >= 1e-14 * k):
                break
    return k


def group_velocity(k, depth, g=GRAVITY):
    """Group velocity c_g [m/s] of linear waves of wavenumber `k` [1/m] in water of `depth` d [m]:
    c_g = (omega / 2k) (1 + 2kd / sinh 2kd), omega = sqrt(g k tanh kd) (Dean & Dalrymple 1991, ch. 4);
    sqrt(g d) at k = 0, and omega / 2k in deep water (no overflow of sinh).

    Parameters
    ----------
    k : array_like
        Wavenumbers [1/m], non-negative.
    depth : float
        d [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    numpy.ndarray or float
        c_g, of the shape of `k`.
    """
    k = np.asarray(k, float)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        x = 2.0 * k * depth
        ratio = np.where(x < 700.0, x / np.sinh(np.minimum(x, 700.0)), 0.0)  # 2kd / sinh 2kd, 0 past overflow
        ratio = np.where(x > 0, ratio, 1.0)
        phase = np.where(k > 0, np.sqrt(g * np.tanh(k * depth) / np.where(k > 0, k, 1.0)), math.sqrt(g * depth))
        out = 0.5 * phase * (1.0 + ratio)
    return float(out) if out.ndim == 0 else out


def regular_wavenumber(height, period, depth, g=GRAVITY):
    """Wavenumber k [1/m] of a regular wave of `height` H [m] and `period` T [s] in `depth` d [m] that exists.

    Raises ValueError (one line) for a period without a finite wavelength, and for a height above the
    breaking limit of Miche (1944), H_max = 0.142 L tanh(k d): no regular wave that high exists in that depth.
    Used by every kind of regular wave a case can ask for (the piston and flap paddles, a relaxation zone's
    linear target), so that all refuse alike."""
    try:
        k = wavenumber(period, depth, g)
    except (OverflowError, ZeroDivisionError):
        k = math.nan
    if not (math.isfinite(k) and k > 0 and math.isfinite(2.0 * math.pi / k)):
        raise ValueError(f"period = {period:g} s in {depth:g} m of water gives no finite wavelength; "
                         "give the period of a water wave in seconds")
    length = 2.0 * math.pi / k
    h_max = 0.142 * length * math.tanh(k * depth)
    if height > h_max:
        raise ValueError(f"height = {height:g} m is above the breaking limit H_max = 0.142 L tanh(kd) = "
                         f"{h_max:.3g} m (Miche 1944) of a {period:g} s wave in {depth:g} m of water "
                         f"(L = {length:.3g} m): no regular wave that high exists; give a lower height or a "
                         "longer period")
    return k
