"""The variance density spectrum of a gauge record and the sea-state parameters it gives.

A gauge's elevation record eta(t) over a window is cut into K segments of L samples that overlap by a
fraction (half, by default); each segment's mean is removed, it is tapered by a window w (Hann by
default) and its periodogram taken, and the K periodograms are averaged: Welch's (1967) method, the
estimate of the one-sided variance density S(f) [m^2/Hz] (`scipy.signal.welch`, density scaling:
the periodogram is divided by fs sum w_n^2, which corrects for the taper's loss of variance, so that
sum_j S_j df is the taper-weighted variance of the segments exactly).

Each bin's estimate is S(f) times a chi-square variable of nu degrees of freedom over nu,

    nu = 2 K / (1 + 2 sum_{j=1}^{K-1} (1 - j/K) rho_j),
    rho_j = (sum_n w_n w_{n+jD})^2 / (sum_n w_n^2)^2,

D the step between segments, L less the overlap (Welch 1967; Percival & Walden 1993, ch. 6; for the Hann
window at half overlap rho_1 = 1/36 and nu = 36 K^2 / (19 K - 1)), so its relative standard error is
sqrt(2 / nu). The sea-state parameters come from the spectral moments (IAHR 1989, "List of sea-state
parameters"; Goda 2010, ch. 2; Holthuijsen 2007, ch. 4):

    m_n = int f^n S(f) df,  Hm0 = 4 sqrt(m0),  Tm01 = m0 / m1,  Tm02 = sqrt(m0 / m2),
    Tm-10 = m_{-1} / m0,      Tp = 1 / fp.

`band_ratios` compares a measured spectrum with a target density band by band.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from .records import checked_record, uniform_samples


@dataclass(frozen=True)
class Spectrum:
    """A one-sided variance density spectrum, as `wave_spectrum` estimates it.

    The moments and the sea-state parameters integrate over the bins with f > 0 (rectangle rule,
    m_n = sum_j f_j^n S_j df, the sum for which Parseval's identity holds): the record's mean is
    removed, so the zero-frequency bin holds only what the lowest frequencies leak into it.
    """

    f: np.ndarray  #: bin frequencies [Hz], from 0 (or the band's first bin) in steps of df
    S: np.ndarray  #: variance density [m^2/Hz] (for a record in metres)
    df: float  #: frequency resolution [Hz]: 1 / (segment duration)
    segments: int  #: number K of segments averaged
    dof: float  #: degrees of freedom nu of each bin's estimate (Welch 1967)
    dt: float  #: sample step of the record analysed [s]
    resampled: bool = False  #: the record's steps were not uniform: it was interpolated onto dt

    def _positive(self, f_min=None, f_max=None):
        lo = 0.0 if f_min is None else float(f_min)
        hi = np.inf if f_max is None else float(f_max)
        sel = (self.f > 0) & (self.f >= lo) & (self.f <= hi)
        if not sel.any():
            raise InputError(f"the band [{lo:g}, {hi:g}] Hz holds no frequency bin of the spectrum "
                             f"(f = {self.f[0]:g} ... {self.f[-1]:g} Hz, df = {self.df:g} Hz)")
        return self.f[sel], self.S[sel]

    def moment(self, n, f_min=None, f_max=None):
        """Spectral moment m_n = int f^n S(f) df [m^2 Hz^n] over [f_min, f_max] (default: every bin).

        Parameters
        ----------
        n : float
            Order (m_{-1}, m0, m1, m2 give the periods; any real order is allowed).
        f_min, f_max : float, optional
            Band [Hz], ends included; the zero-frequency bin is always left out.
        """
        f, S = self._positive(f_min, f_max)
        return float(np.sum(f ** float(n) * S) * self.df)

    def band(self, f_min=None, f_max=None):
        """The spectrum restricted to the bins in [f_min, f_max] [Hz] (f > 0): its parameters
        (``spectrum.band(0.5 * fp, 3 * fp).Hm0``) are those of the band."""
        f, S = self._positive(f_min, f_max)
        return replace(self, f=f, S=S)

    @property
    def m0(self):
        """Zeroth moment m0 [m^2]: the record's variance."""
        return self.moment(0)

    @property
    def Hm0(self):
        """Spectral significant wave height Hm0 = 4 sqrt(m0) [m] (IAHR 1989)."""
        return 4.0 * float(np.sqrt(self.moment(0)))

    @property
    def Tm01(self):
        """Mean period Tm01 = m0 / m1 [s]."""
        return self.moment(0) / self.moment(1)

    @property
    def Tm02(self):
        """Mean zero-crossing period Tm02 = sqrt(m0 / m2) [s] (Rice 1944; equals the mean zero
        up-crossing period of a Gaussian record)."""
        return float(np.sqrt(self.moment(0) / self.moment(2)))

    @property
    def Tm_10(self):
        """Energy period Tm-1,0 = m_{-1} / m0 [s] (the period of wave run-up and overtopping formulae,
        EurOtop 2018)."""
        return self.moment(-1) / self.moment(0)

    def peak_frequency(self, method="parabola"):
        """Peak frequency fp [Hz].

        Parameters
        ----------
        method : {"parabola", "bin", "s4"}
            ``"bin"``: the frequency of the highest bin, a multiple of df. ``"parabola"`` (the default):
            the vertex of the parabola through ln S at the highest bin i and its two neighbours,
            fp = f_i + df (l_{i-1} - l_{i+1}) / (2 (l_{i-1} - 2 l_i + l_{i+1})), l = ln S, which is not
            tied to the bins: exact for a Gaussian peak, and within 0.02 df of a sinusoid's frequency
            under the Hann taper (the highest bin's frequency where the peak is the first or last bin).
            ``"s4"``: the centroid of S^4, fp = sum f S^4 / sum S^4 (Young 1995, Ocean Eng. 22,
            669-686), which weighs every bin near the peak and so scatters less from record to
            record than the highest bin does.
        """
        f, S = self._positive()
        i = int(np.argmax(S))
        if method == "bin":
            return float(f[i])
        if method == "s4":
            w = (S / S[i]) ** 4
            return float(np.sum(f * w) / np.sum(w))
        if method != "parabola":
            raise InputError(f"unknown peak method {method!r}: use 'parabola', 'bin' or 's4'")
        if i == 0 or i == len(S) - 1:
            return float(f[i])
        if not np.all(S[i - 1:i + 2] > 0):
            return float(f[i])
        a, b, c = np.log(S[i - 1:i + 2])
        curvature = a - 2.0 * b + c
        shift = 0.5 * (a - c) / curvature if curvature < 0 else 0.0
        return float(f[i] + shift * self.df)

    def peak_period(self, method="parabola"):
        """Peak period Tp = 1 / fp [s] (`peak_frequency` gives the methods)."""
        return 1.0 / self.peak_frequency(method)

    @property
    def Tp(self):
        """Peak period Tp = 1 / fp [s], fp from the parabola through ln S at the highest bin and its
        neighbours (`peak_frequency`)."""
        return self.peak_period("parabola")


def welch_dof(window, nperseg, noverlap, segments):
    """Degrees of freedom of a Welch estimate at a frequency between 0 and the Nyquist frequency.

    nu = 2 K / (1 + 2 sum_{j=1}^{K-1} (1 - j/K) rho_j), with rho_j = (sum_n w_n w_{n+jD})^2 /
    (sum_n w_n^2)^2 the overlap correlation of segments j steps D = L - noverlap apart (Welch 1967;
    Percival & Walden 1993, ch. 6). Without overlap nu = 2K.
    """
    from scipy.signal import get_window

    w = np.asarray(get_window(window, nperseg), float)
    step = nperseg - noverlap
    s2 = float(np.sum(w * w))
    total = 0.0
    for j in range(1, segments):
        if j * step >= nperseg:
            break
        rho = (float(np.dot(w[:nperseg - j * step], w[j * step:])) / s2) ** 2
        total += (1.0 - j / segments) * rho
    return 2.0 * segments / (1.0 + 2.0 * total)


def wave_spectrum(t, eta, t0=None, t1=None, segment=None, overlap=0.5, window="hann"):
    """Variance density spectrum of a gauge record by Welch's method.

    The window's samples are cut into segments of `segment` seconds overlapping by `overlap`; each is
    detrended by its mean, tapered by `window` and Fourier transformed, and the periodograms are
    averaged (Welch 1967; `scipy.signal.welch` with density scaling). A record whose time steps are not
    uniform (within 1e-3 of their median) is first interpolated linearly onto its median step, and the
    result says so (`Spectrum.resampled`).

    Parameters
    ----------
    t, eta : array_like
        Sample times [s] (strictly increasing) and elevations [m] (any datum).
    t0, t1 : float, optional
        Analysis window [s] (default: the whole record).
    segment : float, optional
        Segment duration [s]; the resolution is df = 1 / segment. Default: a quarter of the window,
        which with half overlap makes 7 segments (about 13 degrees of freedom with the Hann window).
        Longer segments resolve the spectrum finer and scatter more (nu falls as K does).
    overlap : float
        Fraction of a segment shared with the next, in [0, 1).
    window : str or tuple
        Taper, as `scipy.signal.get_window` names it.

    Returns
    -------
    Spectrum

    Raises
    ------
    InputError
        A bad record (`checked_record`: shapes, times that do not increase, a non-finite value), an
        overlap outside [0, 1), an unknown window, or a window that holds fewer than two segments.
    """
    from scipy.signal import get_window, welch

    tw, e = checked_record(t, eta, t0, t1, min_samples=16, what="gauge record")
    tw, e, dt, resampled = uniform_samples(tw, e)
    if not 0.0 <= float(overlap) < 1.0:
        raise InputError(f"overlap = {overlap!r} must lie in [0, 1)")
    n = e.size
    L = n // 4 if segment is None else int(round(float(segment) / dt))
    if L < 8:
        raise InputError(f"a segment of {segment if segment is not None else L * dt:g} s holds {L} samples "
                         f"(dt = {dt:g} s); at least 8 are needed")
    noverlap = min(int(round(float(overlap) * L)), L - 1)
    K = 1 + (n - L) // (L - noverlap) if L <= n else 0
    if K < 2:
        raise InputError(f"the window of {n * dt:g} s holds {K} segment(s) of {L * dt:g} s with overlap "
                         f"{overlap:g}; at least 2 are needed: shorten the segment or lengthen the window")
    try:
        get_window(window, L)
    except (ValueError, TypeError) as err:
        raise InputError(f"unknown spectral window {window!r} ({err})") from None
    f, S = welch(e - np.mean(e), fs=1.0 / dt, window=window, nperseg=L, noverlap=noverlap,
                 detrend="constant", scaling="density")
    return Spectrum(f=np.asarray(f, float), S=np.asarray(S, float), df=1.0 / (L * dt), segments=int(K),
                    dof=welch_dof(window, L, noverlap, int(K)), dt=dt, resampled=resampled)


def band_ratios(spectrum, target, fp, edges=None):
    """Measured over target energy in bands of frequency scaled by the peak frequency.

    Band i spans [edges[i] fp, edges[i+1] fp] (default edges 0.7, 0.8, ..., 1.5: eight bands of
    0.1 fp, the check of issue 31 that the measured spectrum lies within 15 % of the target in each).
    Its ratio is

        r_i = sum_j o_ij S_j / sum_j o_ij S_target(f_j),

    the sums over the spectrum's bins, each bin standing for [f_j - df/2, f_j + df/2] and o_ij the
    fraction of it inside band i (a bin that straddles an edge is shared between the two bands). The
    target is sampled at the same bins, so the ratio compares like with like; the estimate's own
    smoothing (the taper's spectral window, about 2 df wide for Hann) biases it where the target curves
    sharply on that scale.

    Parameters
    ----------
    spectrum : Spectrum
        The measured spectrum (`wave_spectrum`).
    target : callable or array_like
        The target variance density [m^2/Hz]: a function of frequency [Hz], or its values at
        ``spectrum.f``.
    fp : float
        Peak frequency [Hz] that scales the bands (usually the target's).
    edges : array_like, optional
        Band edges in units of fp, increasing.

    Returns
    -------
    ndarray
        One ratio per band.

    Raises
    ------
    InputError
        A band narrower than the resolution df or outside the spectrum, or one where the target
        holds no energy.

    Notes
    -----
    A record of a Gaussian sea (random amplitudes) scatters about the target: the band's energy is
    a weighted mean square of the band-passed record, whose relative standard error is about
    sqrt(c / (T B)) for a band of width B [Hz] over which S is nearly flat, in a record of T s
    (Bendat & Piersol 2010, ch. 8). Here c = N sum_n a_n^2 >= 1 counts the uneven weights a_n
    (sum 1) that the overlapping tapers give the N samples: 1.19 for the default 7 Hann segments at
    half overlap, 1.06 for many. A 200 s record and bands of 0.1 Hz give 24 %, so a 15 % check needs
    a long record; a record made with deterministic amplitudes (random phases only) scatters about
    2.5 times less.
    """
    e = np.arange(0.7, 1.5 + 1e-9, 0.1) if edges is None else np.asarray(edges, float)
    if e.ndim != 1 or e.size < 2 or not np.all(np.diff(e) > 0) or not fp > 0:
        raise InputError("band edges must be an increasing 1-D array of two or more values, and fp > 0")
    f, S, df = spectrum.f, spectrum.S, spectrum.df
    if callable(target):
        T = np.asarray(target(f), float)
    else:
        T = np.asarray(target, float)
    if T.shape != f.shape:
        raise InputError(f"the target holds {T.size} values for the spectrum's {f.size} bins")
    lo_bins, hi_bins = f - 0.5 * df, f + 0.5 * df
    ratios = []
    for a, b in zip(e[:-1] * fp, e[1:] * fp):
        if b - a < df * (1 - 1e-9):
            raise InputError(f"the band [{a:.4g}, {b:.4g}] Hz is narrower than the spectrum's resolution "
                             f"df = {df:.4g} Hz: use longer segments")
        if a < lo_bins[0] - 1e-9 * df or b > hi_bins[-1] + 1e-9 * df:
            raise InputError(f"the band [{a:.4g}, {b:.4g}] Hz lies outside the spectrum "
                             f"({f[0]:.4g} ... {f[-1]:.4g} Hz)")
        o = np.clip(np.minimum(hi_bins, b) - np.maximum(lo_bins, a), 0.0, None) / df
        expected = float(np.sum(o * T))
        if not expected > 0:
            raise InputError(f"the target holds no energy in the band [{a:.4g}, {b:.4g}] Hz")
        ratios.append(float(np.sum(o * S)) / expected)
    return np.array(ratios)
