"""A spectrum cut into sinusoidal components, and the linear surface elevation they make.

The elevation of a sea of N components travelling along +x is, in linear theory,

    eta(x, t) = sum_n a_n cos(omega_n t - k_n x + phi_n),   omega_n = 2 pi f_n,   omega_n^2 = g k_n tanh(k_n d).

`frequency_grid` places the f_n at multiples of one step df, so that eta repeats itself after the repeat period
1 / df; `random_phase_components` gives a random sea of a spectrum (deterministic amplitudes a_n =
sqrt(2 S(f_n) df) and uniformly random phases, or Rayleigh-distributed amplitudes); `focused_components` a
focused wave group (NewWave) that crests at one place and time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .dispersion import GRAVITY, wavenumbers

_CHUNK = 1 << 20
"""Elements (components x times) summed at once by `WaveComponents.elevation`."""


@dataclass(frozen=True)
class WaveComponents:
    """Sinusoidal components of a sea travelling along +x in water of depth `depth` [m].

    Attributes
    ----------
    frequencies : numpy.ndarray
        f_n [Hz], multiples of `df`.
    amplitudes : numpy.ndarray
        a_n [m], non-negative.
    phases : numpy.ndarray
        phi_n [rad].
    wavenumbers : numpy.ndarray
        k_n [1/m], from the linear dispersion relation (`shoal.waves.wavenumbers`).
    depth : float
        d [m].
    df : float
        The frequency step [Hz]; the elevation repeats after 1 / df.
    """

    frequencies: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    wavenumbers: np.ndarray
    depth: float
    df: float

    @property
    def omegas(self):
        """omega_n = 2 pi f_n [rad/s]."""
        return 2.0 * math.pi * self.frequencies

    @property
    def repeat_period(self):
        """1 / df [s]: eta(x, t + 1/df) = eta(x, t), the f_n being multiples of df."""
        return 1.0 / self.df

    @property
    def variance(self):
        """sum a_n^2 / 2 [m^2]: the variance of eta over a repeat period (Parseval)."""
        return float(0.5 * np.sum(self.amplitudes**2))

    @property
    def hm0(self):
        """4 sqrt(`variance`) [m]: the spectral significant height of the record of a repeat period."""
        return 4.0 * math.sqrt(self.variance)

    def elevation(self, x, t):
        """The linear elevation eta(x, t) = sum_n a_n cos(omega_n t - k_n x + phi_n) [m] at the distance `x`
        [m] along the direction of travel, at the times `t` [s] (array_like; the result has its shape)."""
        t = np.asarray(t, float)
        flat = t.ravel()
        a, w = self.amplitudes[:, None], self.omegas[:, None]
        shift = (self.phases - self.wavenumbers * float(x))[:, None]
        out = np.empty(flat.shape)
        step = max(1, _CHUNK // max(len(self.amplitudes), 1))
        for i in range(0, len(flat), step):
            out[i:i + step] = np.sum(a * np.cos(w * flat[None, i:i + step] + shift), axis=0)
        return out.reshape(t.shape)


def frequency_grid(f_min, f_max, components):
    """Frequencies f_n [Hz] of `components` N components over the band [`f_min`, `f_max`] [Hz], and their step.

    df = (f_max - f_min) / N and f_n = n df for the N consecutive integers n from n_0 = max(1, floor(f_min / df
    + 1)) (the integer nearest f_min / df + 1/2): each f_n stands for the bin [f_n - df/2, f_n + df/2], the
    bins cover the band to within df/2 at either end, and, the f_n being multiples of df, a sum of
    sinusoids at these frequencies repeats itself after exactly 1 / df (the repeat period). Bin centres
    f_min + (n + 1/2) df would not be multiples of df unless f_min / df were a half-integer.

    Parameters
    ----------
    f_min, f_max : float
        The band [Hz], 0 <= f_min < f_max.
    components : int
        N >= 1.

    Returns
    -------
    (numpy.ndarray, float)
        f_n [Hz] and df [Hz].
    """
    if not (0.0 <= f_min < f_max and components >= 1):
        raise ValueError(f"the band [{f_min:g}, {f_max:g}] Hz and {components} components: give "
                         "0 <= f_min < f_max and at least one component")
    df = (f_max - f_min) / components
    n0 = max(1, math.floor(f_min / df + 1.0))
    return (n0 + np.arange(components)) * df, df


def _band(spectrum, f_min, f_max, components, depth, g):
    fp = spectrum.peak_frequency
    f, df = frequency_grid(f_min * fp, f_max * fp, components)
    return f, df, spectrum.density(f), wavenumbers(2.0 * math.pi * f, depth, g)


def random_phase_components(spectrum, depth, components=256, f_min=0.5, f_max=3.0, seed=0,
                            random_amplitudes=False, rescale=True, g=GRAVITY):
    """A random sea of `spectrum`: deterministic amplitudes, random phases (or random amplitudes too).

    The band [f_min fp, f_max fp] (fp the spectrum's peak frequency) is cut into `components` N components
    (`frequency_grid`). Their amplitudes are a_n = sqrt(2 S(f_n) df), the variance of the spectrum in each
    bin; with `rescale` they are all multiplied by sqrt(m0 / sum(S(f_n) df)), m0 the spectrum's variance
    over all frequencies, so that sum a_n^2 / 2 = m0 and the sea has Hm0 = 4 sqrt(m0) = Hs: the variance
    outside the band is given back to it in proportion. The phases phi_n are drawn uniformly in [0, 2 pi)
    by ``numpy.random.default_rng(seed)`` ("deterministic amplitude, random phase"). With
    `random_amplitudes`, each a_n is then multiplied by sqrt(-ln U_n), U_n uniform in (0, 1] from the same
    generator after the phases: a_n is Rayleigh-distributed with mean square 2 S(f_n) df, as the real and
    imaginary parts of each Fourier coefficient of a Gaussian sea are independent normal variables (Tucker,
    Challenor & Carter 1984); the phases are the same as without.

    Parameters
    ----------
    spectrum : shoal.waves.Spectrum
    depth : float
        Water depth d [m] (for the wavenumbers).
    components : int
    f_min, f_max : float
        The band, as multiples of the peak frequency.
    seed : int
        Seed of the random generator (non-negative).
    random_amplitudes, rescale : bool
    g : float
        Gravity [m/s^2].

    Returns
    -------
    WaveComponents
    """
    f, df, s, k = _band(spectrum, f_min, f_max, components, depth, g)
    variance = s * df
    if rescale and np.sum(variance) > 0:
        variance = variance * (spectrum.m0 / np.sum(variance))
    amplitudes = np.sqrt(2.0 * variance)
    rng = np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2.0 * math.pi, components)
    if random_amplitudes:
        amplitudes = amplitudes * np.sqrt(-np.log(1.0 - rng.random(components)))
    return WaveComponents(f, amplitudes, phases, k, float(depth), float(df))


def focused_components(spectrum, depth, amplitude, x_focus, t_focus, components=256, f_min=0.5, f_max=3.0,
                       g=GRAVITY):
    """A focused wave group: every component crests at `x_focus` at `t_focus` (NewWave, Tromans, Anaturk &
    Hagemeijer 1991).

    The band is cut as by `random_phase_components`; the amplitudes follow the spectrum's shape and add up to
    the focus amplitude A, a_n = A S(f_n) df / sum_m S(f_m) df (the spectrum's scale, its Hs, does not
    matter), and the phases phi_n = k_n x_focus - omega_n t_focus put every crest at x_focus at t_focus:
    eta(x_focus, t_focus) = sum a_n = A, the largest elevation anywhere at any time (each term is at most
    a_n).

    Parameters
    ----------
    spectrum : shoal.waves.Spectrum
    depth : float
        d [m].
    amplitude : float
        A [m], the crest elevation at the focus.
    x_focus : float
        Distance [m] along the direction of travel.
    t_focus : float
        Time [s].
    components : int
    f_min, f_max : float
        The band, as multiples of the peak frequency.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    WaveComponents
    """
    f, df, s, k = _band(spectrum, f_min, f_max, components, depth, g)
    total = np.sum(s)
    if not total > 0:
        raise ValueError("the spectrum holds no energy in the band of the components; widen f_min .. f_max")
    amplitudes = amplitude * s / total
    phases = k * x_focus - 2.0 * math.pi * f * t_focus
    return WaveComponents(f, amplitudes, phases, k, float(depth), float(df))
