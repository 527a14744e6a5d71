"""Checking and windowing a time series before it is analysed.

The irregular-wave analyses (`shoal.analysis.spectral`, `shoal.analysis.zero_crossing`,
`shoal.analysis.reflection`, `shoal.analysis.runup`) take a record as its sample times and values.
They share one set of checks, each a one-line `InputError`: the times and values are 1-D arrays of one
length, the times increase strictly, every value in the window is finite (a gap is not silently
bridged), and the window holds enough samples. `uniform_samples` puts a record on a uniform time step,
which an FFT needs.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def checked_record(t, values, t0=None, t1=None, min_samples=8, what="record"):
    """The samples of a record in the window [t0, t1], checked.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times [s], strictly increasing.
    values : array_like, shape (N,) or (M, N)
        The record (or M records sampled at the same times).
    t0, t1 : float, optional
        Window [s] (default: the whole record); both ends included.
    min_samples : int
        Fewest samples the window may hold.
    what : str
        How the messages name the record.

    Returns
    -------
    (t, values) : ndarray
        The window's times and values (float64 copies).

    Raises
    ------
    InputError
        Shapes that differ, times that do not increase, a non-finite value in the window, or fewer
        than `min_samples` samples in it.
    """
    t = np.array(t, float)
    v = np.array(values, float)
    if t.ndim != 1 or v.ndim not in (1, 2) or v.shape[-1] != t.size:
        raise InputError(f"the {what}'s times and values must be 1-D arrays of the same length "
                         f"(got shapes {t.shape} and {v.shape})")
    if not np.all(np.isfinite(t)):
        raise InputError(f"the {what}'s times hold a NaN or an infinity")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        k = int(np.argmax(np.diff(t) <= 0))
        raise InputError(f"the {what}'s times must increase strictly; sample {k + 1} "
                         f"(t = {t[k + 1]:g} s) does not come after t = {t[k]:g} s")
    lo = -np.inf if t0 is None else float(t0)
    hi = np.inf if t1 is None else float(t1)
    sel = (t >= lo) & (t <= hi)
    t, v = t[sel], v[..., sel]
    if t.size < min_samples:
        raise InputError(f"the window [{lo:g}, {hi:g}] s holds {t.size} samples of the {what}; "
                         f"at least {min_samples} are needed")
    bad = ~np.isfinite(v)
    if bad.any():
        k = int(np.argmax(bad.reshape(-1, t.size).any(axis=0)))
        raise InputError(f"the {what} holds a non-finite value (NaN or infinity) at t = {t[k]:g} s "
                         f"in the window: cut the window or fill the gap")
    return t, v


def uniform_samples(t, values, rtol=1e-3):
    """The record on a uniform time step.

    A record whose steps all lie within `rtol` of their median is uniform already: it is returned as it
    is, with the median step. Otherwise it is resampled by linear interpolation onto t[0] + k * dt, dt
    the median step, over [t[0], t[-1]] (a variable-step record, or one with a missing sample); linear
    interpolation damps what varies within a step, so sample the gauges uniformly where it matters.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Strictly increasing times [s] (`checked_record`).
    values : ndarray, shape (N,) or (M, N)
        The record(s).
    rtol : float
        Relative tolerance on the steps (a CSV file's rounding of its times is well within 1e-3).

    Returns
    -------
    (t, values, dt, resampled) : (ndarray, ndarray, float, bool)
    """
    steps = np.diff(t)
    dt = float(np.median(steps))
    if np.all(np.abs(steps - dt) <= rtol * dt):
        return t, values, dt, False
    n = int(np.floor((t[-1] - t[0]) / dt + 1e-9)) + 1
    tu = t[0] + dt * np.arange(n)
    v = np.atleast_2d(values)
    vu = np.vstack([np.interp(tu, t, row) for row in v])
    return tu, (vu if np.ndim(values) == 2 else vu[0]), dt, True
