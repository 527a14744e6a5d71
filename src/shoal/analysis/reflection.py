"""Incident and reflected irregular waves separated from synchronous records of a line of gauges.

Each gauge j at x_j records eta_j(t) over the same window of N samples; the discrete Fourier transform
gives its complex amplitude at each frequency f_n = n / (N dt),

    Z_j(f_n) = (2 / N) sum_m eta_j(t_m) exp(-2 pi i n m / N),

so that eta_j = sum_n Re(Z_j exp(2 pi i f_n t)). Linear waves travelling towards +x (incident) and -x
(reflected) with the wavenumber k of omega^2 = g k tanh(k d) give at every frequency

    Z_j = A_I exp(-i k (x_j - x_ref)) + A_R exp(i k (x_j - x_ref)),

two gauges determine A_I, A_R (Goda & Suzuki 1976) and more over-determine them: the least-squares
solution is Mansard & Funke's (1980). Its normal matrix has the determinant

    4 sum_{j<l} sin^2(k (x_l - x_j)) = n^2 s,   s = 1 - |(1/n) sum_j exp(2 i k x_j)|^2,

for n gauges; s in [0, 1] is the array's separability at that frequency. It vanishes where every
spacing is a multiple of half a wavelength (the waves cannot be told apart) and the noise in A_I, A_R
grows as 1 / (n s). A frequency is used where s >= sin^2(pi / 5) = 0.345: for two gauges that is
Goda & Suzuki's range 0.1 < dx / L < 0.4 (and its repeats, dx / L modulo 1/2); for three or more it is
the same bound on Mansard & Funke's singularity function.

The incident and reflected variance densities are S_I = |A_I|^2 / (2 df) and S_R = |A_R|^2 / (2 df)
(a raw periodogram: two degrees of freedom per bin), and the bulk reflection coefficient over the
usable band Kr = sqrt(m0_R / m0_I). The FFT treats the window as one period of the record: a
component that does not fit a whole number of times in it leaks into the neighbouring bins, whose
wavenumbers differ, so take a long window (many peak periods) of a steady sea state. For regular
waves, `shoal.analysis.reflection_analysis` fits the paddle's frequency alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .records import checked_record, uniform_samples

SEPARABILITY_MIN = float(np.sin(np.pi / 5) ** 2)
"""Least separability s of a usable frequency: sin^2(pi/5), the two-gauge bound 0.1 < dx/L < 0.4."""


def _wavenumbers(f, depth, g):
    """k [1/m] of omega^2 = g k tanh(k d) at each frequency f [Hz] > 0 (vectorised Newton iteration
    from the larger of the deep- and shallow-water values, which converges monotonically)."""
    omega = 2.0 * np.pi * np.asarray(f, float)
    k = np.maximum(omega ** 2 / g, omega / np.sqrt(g * depth))
    for _ in range(100):
        th = np.tanh(k * depth)
        dk = (g * k * th - omega ** 2) / (g * th + g * k * depth * (1.0 - th * th))
        k = k - dk
        if np.all(np.abs(dk) <= 1e-14 * k):
            break
    return k


@dataclass(frozen=True)
class IrregularReflection:
    """Incident and reflected spectra separated from a line of gauges (`irregular_reflection`).

    Amplitudes are complex, at ``x_ref``, per frequency bin; eta = sum Re(A exp(i (2 pi f t -/+ k x))).
    Only the usable bins (`usable`) enter the bulk values.
    """

    f: np.ndarray  #: bin frequencies [Hz] (f > 0 within the band asked for)
    incident: np.ndarray  #: complex incident amplitude A_I at x_ref [m] (NaN where not usable)
    reflected: np.ndarray  #: complex reflected amplitude A_R at x_ref [m] (NaN where not usable)
    separability: np.ndarray  #: s = 1 - |mean_j exp(2 i k x_j)|^2 at each bin, in [0, 1]
    usable: np.ndarray  #: bool: s >= the bound, so the bin was separated
    wavenumber: np.ndarray  #: k [1/m] at each bin
    df: float  #: frequency resolution [Hz]
    x_ref: float  #: reference position [m]
    residual: float  #: rms misfit of the gauges' amplitudes over their rms, usable bins (0 for 2 gauges)

    @property
    def S_incident(self):
        """Incident variance density |A_I|^2 / (2 df) [m^2/Hz] (0 where not usable)."""
        return np.where(self.usable, np.abs(np.nan_to_num(self.incident)) ** 2 / (2 * self.df), 0.0)

    @property
    def S_reflected(self):
        """Reflected variance density |A_R|^2 / (2 df) [m^2/Hz] (0 where not usable)."""
        return np.where(self.usable, np.abs(np.nan_to_num(self.reflected)) ** 2 / (2 * self.df), 0.0)

    @property
    def m0_incident(self):
        """Incident variance over the usable bins [m^2]."""
        return float(np.sum(self.S_incident) * self.df)

    @property
    def m0_reflected(self):
        """Reflected variance over the usable bins [m^2]."""
        return float(np.sum(self.S_reflected) * self.df)

    @property
    def Hm0_incident(self):
        """Incident Hm0 = 4 sqrt(m0_I) [m] over the usable bins."""
        return 4.0 * float(np.sqrt(self.m0_incident))

    @property
    def Hm0_reflected(self):
        """Reflected Hm0 = 4 sqrt(m0_R) [m] over the usable bins."""
        return 4.0 * float(np.sqrt(self.m0_reflected))

    @property
    def reflection_coefficient(self):
        """Bulk reflection coefficient Kr = sqrt(m0_R / m0_I) over the usable bins."""
        return float(np.sqrt(self.m0_reflected / self.m0_incident))

    @property
    def band(self):
        """(lowest, highest) usable frequency [Hz]."""
        fu = self.f[self.usable]
        return float(fu[0]), float(fu[-1])


def irregular_reflection(t, records, depth, t0=None, t1=None, f_min=None, f_max=None, x_ref=None,
                         min_separability=SEPARABILITY_MIN, g=9.81):
    """Separate incident and reflected irregular waves from two or more synchronous gauges.

    Goda & Suzuki (1976) for two gauges, the least squares of Mansard & Funke (1980) for three or more,
    frequency by frequency of the records' FFT over the window (the module's docstring gives the
    equations and the usable-band criterion).

    Parameters
    ----------
    t : array_like
        Sample times [s], common to the gauges, strictly increasing (a non-uniform record is
        interpolated linearly onto its median step).
    records : dict
        {x [m]: elevations [m]} of at least two gauges along the wave's direction.
    depth : float
        Still-water depth d [m] (uniform over the array).
    t0, t1 : float, optional
        Analysis window [s] (default: the whole record).
    f_min, f_max : float, optional
        Band to separate [Hz] (default: every bin above 0); within it, only the bins whose
        separability reaches `min_separability` are used.
    x_ref : float, optional
        Where the amplitudes are given (default: the first gauge).
    min_separability : float
        Least s of a usable bin, in (0, 1].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    IrregularReflection

    Raises
    ------
    InputError
        Fewer than two gauges, two at one place, a bad record, a depth that is not positive, or no
        usable bin in the band (the message gives the spacings).
    """
    items = sorted(((float(x), eta) for x, eta in records.items()), key=lambda item: item[0])
    xs = np.array([x for x, _ in items], float)
    if len(xs) < 2:
        raise InputError(f"irregular reflection analysis needs at least 2 gauges; got {len(xs)}")
    if np.any(np.diff(xs) <= 0):
        raise InputError("two gauges of the reflection array are at the same x")
    if not float(depth) > 0:
        raise InputError(f"depth = {depth!r} must be positive")
    if not 0 < float(min_separability) <= 1:
        raise InputError(f"min_separability = {min_separability!r} must lie in (0, 1]")
    try:
        stacked = np.vstack([np.asarray(eta, float) for _, eta in items])
    except ValueError:
        raise InputError("the gauge records must be 1-D arrays of one length, that of the times") from None
    tw, eta = checked_record(t, stacked, t0, t1, min_samples=16, what="gauge records")
    tw, eta, dt, _ = uniform_samples(tw, eta)
    n = eta.shape[1]
    Z = 2.0 * np.fft.rfft(eta - eta.mean(axis=1, keepdims=True), axis=1) / n
    f = np.fft.rfftfreq(n, dt)
    df = float(f[1])
    lo = 0.0 if f_min is None else float(f_min)
    hi = np.inf if f_max is None else float(f_max)
    sel = (f > 0) & (f >= lo) & (f <= hi)
    if n % 2 == 0:
        sel[-1] = False  # the Nyquist bin holds a real amplitude only: it cannot carry two waves
    if not sel.any():
        raise InputError(f"the band [{lo:g}, {hi:g}] Hz holds no frequency bin (df = {df:g} Hz)")
    f, Z = f[sel], Z[:, sel]
    k = _wavenumbers(f, float(depth), float(g))
    x0 = float(xs[0] if x_ref is None else x_ref)
    dx = xs - x0
    s = 1.0 - np.abs(np.mean(np.exp(2j * k[None, :] * xs[:, None]), axis=0)) ** 2
    usable = s >= float(min_separability)
    if not usable.any():
        L = 2 * np.pi / k
        raise InputError(f"no frequency in [{f[0]:.4g}, {f[-1]:.4g}] Hz is separable by gauges at "
                         f"{', '.join(f'{x:g}' for x in xs)} m: wavelengths there span {L.min():.3g} to "
                         f"{L.max():.3g} m, and a spacing between L/10 and 2L/5 is needed (Goda & Suzuki 1976)")
    # least squares per bin: M a = Z with M = [exp(-i k dx), exp(i k dx)], solved by the normal equations
    E = np.exp(-1j * k[None, :] * dx[:, None])  # (gauges, bins)
    m = len(xs)
    b1 = np.sum(np.conj(E) * Z, axis=0)  # E^H Z
    b2 = np.sum(E * Z, axis=0)  # (conj E)^H Z
    c = np.sum(E * E, axis=0)  # (conj E)^H E = sum exp(-2 i k dx)
    det = m * m - np.abs(c) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        AI = (m * b1 - np.conj(c) * b2) / det
        AR = (m * b2 - c * b1) / det
    AI = np.where(usable, AI, np.nan)
    AR = np.where(usable, AR, np.nan)
    fit = E[:, usable] * AI[usable] + np.conj(E[:, usable]) * AR[usable]
    scale = float(np.sqrt(np.sum(np.abs(Z[:, usable]) ** 2)))
    residual = float(np.sqrt(np.sum(np.abs(fit - Z[:, usable]) ** 2))) / scale if scale > 0 else 0.0
    return IrregularReflection(f=f, incident=AI, reflected=AR, separability=s, usable=usable, wavenumber=k,
                               df=df, x_ref=x0, residual=residual)

