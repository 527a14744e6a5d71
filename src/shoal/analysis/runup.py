"""Wave run-up exceedance and overtopping discharge from run-up and flow-gauge records.

**Run-up.** A run-up record z(t) is the shoreline's elevation on a slope (a `runup` gauge's
``zmax``). Its events are cut at the zero up-crossings of z about its mean over the window; each
event's run-up R is its highest sample less the still-water level (so R includes the set-up, the
mean level less the still-water level). The run-up exceeded by a fraction p of the events is the
empirical quantile of the events' R at 1 - p (linear interpolation between order statistics,
Hyndman & Fan 1996 type 7): R2% at p = 0.02, the run-up level of the design formulae (EurOtop 2018,
ch. 5; Stockdon et al. 2006, Coastal Eng. 53, 573-588). Where the peaks follow the Rayleigh
distribution P(R > r) = exp(-r^2 / (2 sigma^2)), R2% = sigma sqrt(2 ln 50) = 2.797 sigma.

**Overtopping.** A `flow` gauge on the crest writes the net volume that has passed it since t = 0,
V(t) (particle by particle, exact). Over the window [t0, t1] the overtopping volume per metre of
crest is (V(t1) - V(t0)) / b and the mean overtopping discharge q = that volume / (t1 - t0)
[m^3/s per m] (EurOtop 2018, ch. 1), V interpolated linearly at t0 and t1 and b the section's width
across the flow (1 m for a 2D run, whose volumes are per metre already).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .records import checked_record
from .zero_crossing import up_crossing_indices


@dataclass(frozen=True)
class RunupStatistics:
    """The run-up events of a record and their exceedance levels (`runup_statistics`)."""

    peaks: np.ndarray  #: run-up of each event above the still-water level [m]
    times: np.ndarray  #: time of each event's peak [s]
    setup: float  #: mean level of the record over the window less the still-water level [m]
    still_water_level: float  #: the datum of `peaks` [m]

    @property
    def events(self):
        """Number of run-up events."""
        return len(self.peaks)

    def exceedance(self, p):
        """Run-up level exceeded by a fraction `p` of the events [m] (the empirical quantile at 1 - p).

        Raises
        ------
        InputError
            p outside (0, 1), or fewer than 1 / p events (the level would lie beyond the highest).
        """
        p = float(p)
        if not 0.0 < p < 1.0:
            raise InputError(f"an exceedance fraction must lie in (0, 1); got {p:g}")
        need = int(np.ceil(1.0 / p - 1e-9))
        if self.events < need:
            raise InputError(f"the run-up exceeded by {100 * p:g} % of the events needs at least {need} events; "
                             f"the window holds {self.events}")
        return float(np.quantile(self.peaks, 1.0 - p))

    @property
    def R2(self):
        """R2%: the run-up exceeded by 2 % of the events [m] (at least 50 events)."""
        return self.exceedance(0.02)

    @property
    def Rmax(self):
        """The highest run-up [m]."""
        return float(np.max(self.peaks))

    @property
    def Rmean(self):
        """Mean run-up of the events [m]."""
        return float(np.mean(self.peaks))


def runup_statistics(t, z, still_water_level=0.0, t0=None, t1=None):
    """Run-up events of a shoreline-elevation record in [t0, t1].

    Parameters
    ----------
    t, z : array_like
        Times [s], strictly increasing, and the shoreline's elevation [m] (a `runup` gauge's zmax).
    still_water_level : float
        The still-water level [m] the run-up is measured from.
    t0, t1 : float, optional
        Analysis window [s] (default: the whole record).

    Returns
    -------
    RunupStatistics

    Raises
    ------
    InputError
        A bad record (shapes, times, a non-finite value in the window: a run-up gauge writes NaN
        when its range holds no fluid), or no whole event.
    """
    tw, zw = checked_record(t, z, t0, t1, min_samples=8, what="run-up record")
    mean = float(np.mean(zw))
    k = up_crossing_indices(zw - mean)
    if len(k) < 2:
        raise InputError(f"the window [{tw[0]:g}, {tw[-1]:g}] s holds no whole run-up event (fewer than two "
                         f"up-crossings of the mean level)")
    body = zw[:k[-1] + 1]
    starts = k[:-1] + 1
    peaks = np.maximum.reduceat(body, starts)
    where = np.array([s + int(np.argmax(body[s:e])) for s, e in zip(starts, np.append(starts[1:], body.size))])
    swl = float(still_water_level)
    return RunupStatistics(peaks=peaks - swl, times=tw[where], setup=mean - swl, still_water_level=swl)


@dataclass(frozen=True)
class Overtopping:
    """Overtopping over a window (`overtopping`)."""

    volume: float  #: volume that passed per metre of crest [m^3/m] (net, in the gauge's +axis direction)
    discharge: float  #: mean overtopping discharge q [m^3/s per m]
    t0: float  #: start of the window [s]
    t1: float  #: end of the window [s]


def overtopping(t, volume, t0=None, t1=None, width=1.0):
    """Overtopping volume and mean discharge per metre from a cumulative-volume record.

    Parameters
    ----------
    t, volume : array_like
        Times [s], strictly increasing, and the net volume that has passed the section since t = 0
        (a `flow` gauge's ``volume`` column: m^3 in 3D, m^2 per metre in 2D).
    t0, t1 : float, optional
        Window [s], within the record (default: its first and last samples); V is interpolated
        linearly there.
    width : float
        Width b [m] of the section across the flow (1 for a 2D run).

    Returns
    -------
    Overtopping
        volume = (V(t1) - V(t0)) / b, discharge q = volume / (t1 - t0).

    Raises
    ------
    InputError
        A bad record, a window outside it or empty, or a width that is not positive.
    """
    tt, v = checked_record(t, volume, None, None, min_samples=2, what="flow record")
    a = float(tt[0] if t0 is None else t0)
    b = float(tt[-1] if t1 is None else t1)
    if not (tt[0] <= a < b <= tt[-1]):
        raise InputError(f"the window [{a:g}, {b:g}] s must be non-empty and within the record "
                         f"[{tt[0]:g}, {tt[-1]:g}] s")
    if not float(width) > 0:
        raise InputError(f"width = {width!r} must be positive")
    passed = float(np.interp(b, tt, v) - np.interp(a, tt, v)) / float(width)
    return Overtopping(volume=passed, discharge=passed / (b - a), t0=a, t1=b)
