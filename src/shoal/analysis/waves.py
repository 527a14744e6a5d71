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

A flume's gauges also see what the far end reflects. `reflection_analysis`
separates the incident and reflected first harmonics from three or more
gauges (Mansard & Funke 1980; two gauges: Goda & Suzuki 1976), optionally
with a spatial decay rate, which measures a scheme's numerical damping of a
progressive wave directly.
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


@dataclass
class ReflectionAnalysis:
    """Incident and reflected regular waves separated from an array of gauges.

    Heights are those of the first harmonic (at the paddle's frequency) at
    ``x_ref``; the incident wave travels towards +x.
    """

    incident_height: float  #: incident first-harmonic height at x_ref [m]
    reflected_height: float  #: reflected first-harmonic height at x_ref [m]
    decay: float  #: spatial amplitude decay rate delta [1/m] (0 unless fitted)
    wavenumber: float  #: k used [1/m]
    x_ref: float  #: reference position [m]
    residual: float  #: rms misfit of the gauges' complex amplitudes / incident amplitude
    gauge_heights: np.ndarray  #: first-harmonic height at each gauge [m]

    @property
    def reflection_coefficient(self):
        """K_r = H_R / H_I at x_ref."""
        return self.reflected_height / self.incident_height

    def incident_height_at(self, x):
        """Incident first-harmonic height at x [m] (with the fitted decay)."""
        return self.incident_height * float(np.exp(-self.decay * (x - self.x_ref)))


def harmonic_amplitude(t, eta, omega, t0, t1):
    """Complex amplitude Z of eta(t) ~ mean + Re(Z exp(i omega t)) over [t0, t1] (least squares)."""
    tw, ew = _window(t, eta, t0, t1)
    A = np.column_stack([np.cos(omega * tw), np.sin(omega * tw), np.ones_like(tw)])
    c, *_ = np.linalg.lstsq(A, ew, rcond=None)
    return complex(c[0], -c[1])


def reflection_analysis(t, records, period, depth, t0, t1, fit_decay=False, x_ref=None, g=9.81):
    """Separate incident and reflected regular waves from gauges along a flume.

    The least-squares method of Mansard & Funke (1980) (two gauges: Goda &
    Suzuki 1976): each gauge's record over [t0, t1] gives the complex
    amplitude Z_j of its first harmonic at omega = 2 pi / T; with k from the
    linear dispersion relation omega^2 = g k tanh(k d), the gauges at x_j
    must satisfy

        Z_j = A_I exp(-(i k + delta) (x_j - x_ref)) + A_R exp((i k + delta) (x_j - x_ref)),

    solved for the complex A_I, A_R by linear least squares. With
    `fit_decay`, the spatial decay rate delta of both waves (a dissipative
    scheme or bed) is also fitted, by minimising the misfit over delta.
    Incident height H_I = 2 |A_I|, reflected H_R = 2 |A_R|, K_r = H_R / H_I.

    Parameters
    ----------
    t : array_like
        Sample times [s], common to the gauges.
    records : dict
        {x [m]: elevations} of at least two gauges (three with `fit_decay`).
    period, depth : float
        Wave period T [s] and still-water depth d [m].
    t0, t1 : float
        Analysis window [s]: a whole number of periods is best.
    fit_decay : bool
        Fit delta too (otherwise delta = 0).
    x_ref : float, optional
        Where the heights are given (default: the first gauge).

    Returns
    -------
    ReflectionAnalysis

    Raises
    ------
    InputError
        Too few gauges, or gauges so placed that incident and reflected
        waves cannot be told apart (every spacing a multiple of L/2).
    """
    from ..motions import wavenumber

    xs = np.array(sorted(records), float)
    need = 3 if fit_decay else 2
    if len(xs) < need:
        raise InputError(f"reflection analysis needs at least {need} gauges; got {len(xs)}")
    omega = 2 * np.pi / period
    k = wavenumber(period, depth, g)
    x0 = float(xs[0] if x_ref is None else x_ref)
    Z = np.array([harmonic_amplitude(t, records[x], omega, t0, t1) for x in xs])
    dx = xs - x0
    # Goda & Suzuki: a pair spaced by a multiple of L/2 cannot separate the waves
    spacing = np.abs(xs[:, None] - xs[None, :])[np.triu_indices(len(xs), 1)]
    if np.all(np.abs(np.sin(k * spacing)) < 0.1):
        raise InputError(f"gauges at {', '.join(f'{x:g}' for x in xs)} m are spaced by multiples of half a "
                         f"wavelength (L/2 = {np.pi / k:.3g} m): move one so that a spacing lies between "
                         f"L/10 and 2L/5 (Goda & Suzuki 1976)")

    def solve(delta):
        M = np.column_stack([np.exp(-(1j * k + delta) * dx), np.exp((1j * k + delta) * dx)])
        a, *_ = np.linalg.lstsq(M, Z, rcond=None)
        return a, float(np.sqrt(np.mean(np.abs(M @ a - Z) ** 2)))

    delta = 0.0
    if fit_decay:
        from scipy.optimize import minimize_scalar

        span = max(float(xs[-1] - xs[0]), 1e-9)
        delta = float(minimize_scalar(lambda d_: solve(d_)[1], bounds=(-2.0 / span, 2.0 / span),
                                      method="bounded", options=dict(xatol=1e-6)).x)
    (AI, AR), res = solve(delta)
    return ReflectionAnalysis(incident_height=2 * abs(AI), reflected_height=2 * abs(AR), decay=delta,
                              wavenumber=float(k), x_ref=x0, residual=res / max(abs(AI), 1e-300),
                              gauge_heights=2 * np.abs(Z))
