"""Regular waves at gauges: zero-crossing heights and periods, phase speed.

A gauge records the free-surface elevation eta(t) at a fixed x. Over a
window [t0, t1] (after the paddle's ramp has passed the gauge and before the
beach's reflection returns), the record is cut into individual waves at its
zero up-crossings about the window's mean level, each wave's height is its
crest minus its trough and its period the time between its two up-crossings
(the zero up-crossing method of wave analysis: IAHR 1989, "List of sea-state
parameters"; Goda 2010, ch. 2). Crossing times are linearly interpolated
between samples, so the period of a wave sampled N times per period is known
to a small fraction of T/N.

The phase speed between two gauges a distance dx apart is dx / lag, the lag
being the mean shift of the up-crossings from the first gauge to the second
(the waves of a regular train are identical, so the nearest later crossing
of the downstream gauge is the same wave when dx < L). Linear theory:
omega^2 = g k tanh(k d), c = omega / k (`shoal.motions.wavenumber`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError


@dataclass
class WaveStatistics:
    """Zero up-crossing statistics of one gauge over one window."""

    heights: np.ndarray  #: height of each whole wave [m]
    periods: np.ndarray  #: period of each whole wave [s]
    crossings: np.ndarray  #: zero up-crossing times [s] (one more than waves)
    mean_level: float  #: mean elevation over the window [m]

    @property
    def height(self):
        """Mean wave height [m]."""
        return float(np.mean(self.heights))

    @property
    def period(self):
        """Mean wave period [s]: (last crossing - first) / number of waves."""
        return float((self.crossings[-1] - self.crossings[0]) / len(self.periods))

    @property
    def waves(self):
        return len(self.heights)


def _window(t, eta, t0, t1):
    t = np.asarray(t, float)
    eta = np.asarray(eta, float)
    if t.ndim != 1 or t.shape != eta.shape:
        raise InputError("times and elevations must be 1-D arrays of the same length")
    sel = (t >= t0) & (t <= t1) & np.isfinite(eta)
    if np.count_nonzero(sel) < 8:
        raise InputError(f"the window [{t0:g}, {t1:g}] s holds fewer than 8 samples of the record")
    return t[sel], eta[sel]


def up_crossings(t, eta):
    """Times where eta crosses zero upwards (linear interpolation)."""
    t = np.asarray(t, float)
    eta = np.asarray(eta, float)
    k = np.nonzero((eta[:-1] < 0) & (eta[1:] >= 0))[0]
    return t[k] - eta[k] * (t[k + 1] - t[k]) / (eta[k + 1] - eta[k])


def wave_statistics(t, eta, t0, t1):
    """Zero up-crossing heights and periods of the whole waves in [t0, t1].

    Parameters
    ----------
    t, eta : array_like
        Gauge record: times [s] and elevations [m] (any datum).
    t0, t1 : float
        Analysis window [s].

    Returns
    -------
    WaveStatistics

    Raises
    ------
    InputError
        If the window holds fewer than one whole wave.
    """
    tw, ew = _window(t, eta, t0, t1)
    mean = float(np.mean(ew))
    e = ew - mean
    tc = up_crossings(tw, e)
    if len(tc) < 2:
        raise InputError(f"the window [{t0:g}, {t1:g}] s holds no whole wave (fewer than two zero up-crossings)")
    heights, periods = [], []
    for a, b in zip(tc[:-1], tc[1:]):
        seg = e[(tw >= a) & (tw <= b)]
        heights.append(float(seg.max() - seg.min()) if len(seg) else 0.0)
        periods.append(float(b - a))
    return WaveStatistics(np.array(heights), np.array(periods), tc, mean)


def phase_speed(t, eta_a, eta_b, dx, t0, t1):
    """Phase speed [m/s] between gauge a and gauge b, `dx` [m] downstream of a.

    The lag is the mean delay from each up-crossing of a in [t0, t1] to the
    first up-crossing of b after it (b's window extends by one period).
    """
    sa = wave_statistics(t, eta_a, t0, t1)
    tb, eb = _window(t, eta_b, t0, t1 + 2 * sa.period)
    cb = up_crossings(tb, eb - np.mean(eb))
    lags = []
    for c in sa.crossings:
        later = cb[cb > c]
        if len(later):
            lags.append(later[0] - c)
    if not lags:
        raise InputError("gauge b has no up-crossing after gauge a's in the window")
    return float(dx / np.mean(lags))
