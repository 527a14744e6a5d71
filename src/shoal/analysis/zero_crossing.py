"""Zero up-crossing statistics of an irregular-wave record.

The record's window is cut into individual waves at its zero up-crossings about the window's mean
level, as `shoal.analysis.wave_statistics` does for regular waves: each wave's height H is its highest
sample less its lowest between two successive up-crossings, its period T the time between them (the
crossings interpolated linearly between samples). From the N waves (IAHR 1989, "List of sea-state
parameters"; Goda 2010, ch. 2):

    Hmean = (1/N) sum H,   Hrms = sqrt((1/N) sum H^2),   Hmax = max H,   Tz = (1/N) sum T,
    H1/p  = the mean height of the N // p highest waves (H1/3, H1/10),
    T1/3  = the mean period of the waves that make H1/3,  THmax = the period of the highest wave.

For a narrow-band Gaussian sea the heights follow the Rayleigh distribution, P(H > h) =
exp(-h^2 / (8 m0)), with m0 the record's variance (Longuet-Higgins 1952): Hrms = sqrt(8 m0),
Hmean = sqrt(2 pi m0), H1/3 = 4.004 sqrt(m0), H1/10 = 5.090 sqrt(m0). A broader spectrum makes the
heights smaller (H1/3 near 3.8 sqrt(m0) for sea states; Longuet-Higgins 1980; Goda 2010, ch. 2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .records import checked_record
from .waves import WaveStatistics


@dataclass
class ZeroCrossingStatistics(WaveStatistics):
    """Zero up-crossing statistics of an irregular record: a `WaveStatistics` (heights, periods,
    crossings, mean_level, the means height and period) with the sea-state parameters of the
    individual waves."""

    def highest(self, p):
        """Mean height of the highest N // p of the N waves, H1/p [m] (the highest first, ties in
        the order they came).

        Raises
        ------
        InputError
            Fewer than p waves.
        """
        return float(np.mean(self.heights[self._highest_order(p)]))

    def _highest_order(self, p):
        n = int(len(self.heights) // p)
        if n < 1:
            raise InputError(f"H1/{p:g} needs at least {p:g} waves; the window holds {len(self.heights)}")
        return np.argsort(-self.heights, kind="stable")[:n]

    @property
    def H1_3(self):
        """Significant wave height H1/3 [m]: the mean height of the highest third of the waves."""
        return self.highest(3)

    @property
    def H1_10(self):
        """H1/10 [m]: the mean height of the highest tenth of the waves."""
        return self.highest(10)

    @property
    def Hmax(self):
        """Height of the highest wave [m]."""
        return float(np.max(self.heights))

    @property
    def Hmean(self):
        """Mean wave height [m]."""
        return float(np.mean(self.heights))

    @property
    def Hrms(self):
        """Root-mean-square wave height sqrt(mean H^2) [m]."""
        return float(np.sqrt(np.mean(self.heights ** 2)))

    @property
    def Tz(self):
        """Mean zero up-crossing period [s]: (last crossing - first) / N."""
        return self.period

    @property
    def T1_3(self):
        """Significant wave period T1/3 [s]: the mean period of the waves that make H1/3."""
        return float(np.mean(self.periods[self._highest_order(3)]))

    @property
    def THmax(self):
        """Period of the highest wave [s] (the first of equal highest)."""
        return float(self.periods[int(np.argmax(self.heights))])


def up_crossing_indices(eta):
    """Indices k where eta crosses zero upwards between samples k and k + 1 (eta[k] < 0 <= eta[k+1])."""
    eta = np.asarray(eta, float)
    return np.nonzero((eta[:-1] < 0) & (eta[1:] >= 0))[0]


def zero_crossing_statistics(t, eta, t0=None, t1=None):
    """Zero up-crossing statistics of the whole waves of a record in [t0, t1].

    Parameters
    ----------
    t, eta : array_like
        Gauge record: times [s], strictly increasing, and elevations [m] (any datum).
    t0, t1 : float, optional
        Analysis window [s] (default: the whole record).

    Returns
    -------
    ZeroCrossingStatistics
        For a regular record, the same heights, periods and crossings as `wave_statistics`.

    Raises
    ------
    InputError
        A bad record (shapes, times that do not increase, a non-finite value in the window: see
        `shoal.analysis.records.checked_record`), or a window without a whole wave.
    """
    tw, e = checked_record(t, eta, t0, t1, min_samples=8, what="gauge record")
    mean = float(np.mean(e))
    e = e - mean
    k = up_crossing_indices(e)
    if len(k) < 2:
        raise InputError(f"the window [{tw[0]:g}, {tw[-1]:g}] s holds no whole wave (fewer than two zero "
                         f"up-crossings)")
    tc = tw[k] - e[k] * (tw[k + 1] - tw[k]) / (e[k + 1] - e[k])
    body = e[:k[-1] + 1]
    starts = k[:-1] + 1
    heights = np.maximum.reduceat(body, starts) - np.minimum.reduceat(body, starts)
    return ZeroCrossingStatistics(heights=heights, periods=np.diff(tc), crossings=tc, mean_level=mean)
