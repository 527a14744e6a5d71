"""Nonlinear regular waves: Fenton's stream-function wave and Stokes' fifth-order wave, computed by raschii
(Landet, https://pypi.org/project/raschii/), as Fourier series in the phase in the frame of a closed flume.

Both theories describe a steady wave of height H and length L = 2 pi / k in water of depth d, travelling at
the celerity c, by series in the phase theta = omega t - k x (omega = k c). Measuring z_b up from the bed,

    u = u_E + sum_{j=1}^{N} U_j cosh(j k z_b) / cosh(j k d) cos(j theta),
    w = -sum_{j=1}^{N} U_j sinh(j k z_b) / cosh(j k d) sin(j theta),
    eta = sum_{j=1}^{N} a_j cos(j theta)   (from the still-water level, whose height above the bed is d),

where U_j is the amplitude of the j-th harmonic of u at the still-water level and u_E the uniform (Eulerian)
current. Fenton's stream-function wave (Rienecker & Fenton 1981; Fenton 1988, "The numerical solution of
steady water wave problems", Computers & Geosciences 14; Fenton 1999, "Numerical methods for nonlinear
waves", Advances in Coastal and Ocean Engineering 5) solves the full nonlinear free-surface conditions at
N + 1 points of the surface for the coefficients B_j of the stream function psi = B_0 z_b + sum B_j
sinh(j k z_b) / cosh(j k d) cos(j k X), so U_j = j k B_j exactly. Stokes' fifth-order theory (Fenton 1985,
"A fifth-order Stokes theory for steady waves", J. Waterway, Port, Coastal and Ocean Eng. 111) expands in
the steepness eps = k H / 2, and its velocity is the same kind of series with N = 5. raschii 2.0 (the
classes ``FentonWave`` and ``StokesWave``) computes both; here their series are read off raschii's own
velocity and elevation at N + 1 phases or more, by a discrete Fourier transform, which is exact (to
round-off) for a trigonometric polynomial of degree N sampled at more than 2N points.

**The frame.** A steady wave is steady in a frame moving with it; its speed in the laboratory depends on the
current. raschii gives the wave without an Eulerian current (the time-mean velocity at every point below the
trough is zero, c = B_0) and with it a mean mass flux, the Stokes transport d c_S with c_S = c - Q / d (Q the
volume flux under the wave in the wave's frame). A wave flume with walls at both ends carries no mean mass
flux: its wave is the one whose mean mass transport is zero (Fenton 1990, "Nonlinear wave theories", The
Sea 9, sect. 2: c_S = 0), which travels at c = Q / d and carries the uniform return current u_E = Q / d - B_0
(< 0, against the wave). That is the frame used here: the velocity is raschii's plus u_E, Galilean-shifted
(raschii's field at x - u_E t), and a given period T means the laboratory period, L / (Q / d) = T. Imposed in
a relaxation zone, a wave with the Stokes transport would push mass into a closed flume and raise its far end
until a return current balanced it; the zero-mass-flux wave is the one a closed flume can carry.

`nonlinear_wave` returns a `NonlinearWave` (cached: a case validated twice solves once); it refuses, in one
line, a height past the breaking limit (Miche 1944, and raschii's criteria), a solution that does not
converge, and a Stokes wave whose profile has a second crest in its trough (shallow water, where Stokes
theory fails and Fenton's wave is the one to use).
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass

import numpy as np

from .dispersion import GRAVITY, regular_wavenumber

THEORIES = {"fenton": "Fenton stream-function", "stokes": "Stokes"}
"""The theories `nonlinear_wave` knows, with their names in messages."""

MAX_ORDER = {"fenton": 40, "stokes": 5}
"""The highest order N of each theory (raschii's Stokes theory stops at 5)."""


@dataclass(frozen=True, eq=False)
class NonlinearWave:
    """A nonlinear regular wave in the closed-flume frame (zero mean mass flux), as Fourier series in the
    phase theta = omega t - k x (the module docstring gives the series and the frame).

    Attributes
    ----------
    theory : str
        ``"fenton"`` or ``"stokes"``.
    height, depth : float
        H and d [m].
    order : int
        N, the number of harmonics.
    wavelength, wavenumber : float
        L [m] and k = 2 pi / L [1/m].
    period, omega, celerity : float
        T [s], omega = 2 pi / T [rad/s] and c = L / T = Q / d [m/s] in the laboratory (closed-flume) frame.
    current : float
        u_E = Q / d - B_0 [m/s], the uniform current of that frame (negative: the return flow under the wave).
    stokes_drift : float
        c_S = B_0 - Q / d [m/s], the depth-mean mass-transport velocity of raschii's wave (zero Eulerian
        current), which the frame removes.
    velocities : numpy.ndarray
        U_j [m/s], j = 1..N: the harmonics of u at the still-water level.
    amplitudes : numpy.ndarray
        a_j [m], j = 1..N: the harmonics of the elevation.
    crest, trough : float
        eta at theta = 0 and theta = pi [m] (above and below the still-water level: crest - trough = H).
    model : raschii.FentonWave or raschii.StokesWave
        raschii's wave (zero Eulerian current), the source of the series.
    """

    theory: str
    height: float
    depth: float
    order: int
    wavelength: float
    wavenumber: float
    period: float
    omega: float
    celerity: float
    current: float
    stokes_drift: float
    velocities: np.ndarray
    amplitudes: np.ndarray
    crest: float
    trough: float
    model: object

    def elevation(self, x, t):
        """eta [m] above the still-water level at `x` [m] and time `t` [s] (arrays broadcast), the wave
        travelling along +x with its crest at x = 0 at t = 0."""
        theta = self.omega * np.asarray(t, float) - self.wavenumber * np.asarray(x, float)
        j = np.arange(1, self.order + 1)
        return np.sum(self.amplitudes * np.cos(j * theta[..., None]), axis=-1)

    def velocity(self, x, z, t):
        """(u, w) [m/s] at `x` [m], `z` [m] above the still-water level and time `t` [s] (arrays broadcast;
        the series evaluated as they stand, above the surface too), from the series of the module docstring."""
        x, z, t = np.broadcast_arrays(np.asarray(x, float), np.asarray(z, float), np.asarray(t, float))
        j = np.arange(1, self.order + 1)
        kj = j * self.wavenumber
        theta = (self.omega * t - self.wavenumber * x)[..., None]
        zb = (z + self.depth)[..., None]
        # cosh(j k z_b) / cosh(j k d) and sinh(...) / cosh(j k d) without overflow in deep water
        e = np.exp(kj * (zb - self.depth)) / (1.0 + np.exp(-2.0 * kj * self.depth))
        f = np.exp(-kj * (zb + self.depth)) / (1.0 + np.exp(-2.0 * kj * self.depth))
        u = self.current + np.sum(self.velocities * (e + f) * np.cos(j * theta), axis=-1)
        w = -np.sum(self.velocities * (e - f) * np.sin(j * theta), axis=-1)
        return u, w


def _solver(theory):
    import raschii

    return {"fenton": raschii.FentonWave, "stokes": raschii.StokesWave}[theory]


def _label(theory, order):
    return f"{THEORIES[theory]} wave (N = {order})"


def _miche(height, length, depth):
    """H / H_max and H_max = 0.142 L tanh(k d) (Miche 1944)."""
    h_max = 0.142 * length * math.tanh(2.0 * math.pi * depth / length)
    return height / h_max, h_max


def _solve(theory, height, depth, length, order, g):
    """raschii's wave of `length`, its errors turned into one-line ValueErrors naming the breaking limit."""
    import raschii

    ratio, h_max = _miche(height, length, depth)
    try:
        with np.errstate(all="ignore"):
            model = _solver(theory)(height=height, depth=depth, length=length, N=order, g=g)
            ok = all(math.isfinite(float(v)) for v in (model.c, model.Q, model.k))
    except (raschii.RaschiiError, np.linalg.LinAlgError, ArithmeticError, ValueError) as err:
        reason = re.sub(r"np\.float64\(([^)]*)\)", r"\1", " ".join(str(err).split()))
        if ratio > 0.75:
            hint = "too close to breaking for the solver; give a lower height" + (
                " or a higher order" if theory == "fenton" else "")
        else:
            hint = "give the wavelength, or another theory" if theory == "stokes" else "give a lower height"
        raise ValueError(f"raschii's {_label(theory, order)} of H = {height:g} m, L = {length:.4g} m in "
                         f"d = {depth:g} m did not converge ({reason}) at H / H_max = {ratio:.2f} of the breaking "
                         f"limit H_max = 0.142 L tanh(kd) = {h_max:.3g} m (Miche 1944): {hint}") from None
    if not ok:
        raise ValueError(f"raschii's {_label(theory, order)} of H = {height:g} m, L = {length:.4g} m in d = "
                         f"{depth:g} m has no finite celerity (kd = {2 * math.pi * depth / length:.3g}: too deep); "
                         "use the linear target")
    return model


def _check_breaking(theory, height, depth, length, period=None):
    """Refuse a height past Miche's limit or raschii's breaking criteria for the wavelength `length`."""
    import raschii

    ratio, h_max = _miche(height, length, depth)
    err, _ = raschii.check_breaking_criteria(height, depth, length)
    what, longer = (f"a {period:g} s wave", "period") if period is not None else ("a wave", "wavelength")
    if err or ratio > 1.0:
        crit = "; ".join(s.strip() for s in err.strip().splitlines()) if err else ""
        raise ValueError(f"height = {height:g} m is past the breaking limit of {what} in {depth:g} m of water "
                         f"(L = {length:.4g} m): H_max = 0.142 L tanh(kd) = {h_max:.3g} m (Miche 1944), 0.78 d = "
                         f"{0.78 * depth:.3g} m, 0.14 L = {0.14 * length:.3g} m"
                         + (f" (raschii: {crit})" if crit else "")
                         + f"; no regular wave that high exists; give a lower height or a longer {longer}")


def _period(model, depth):
    """The laboratory period L / (Q / d) of raschii's `model` in the closed-flume frame."""
    return model.length * depth / model.Q


def _length_for_period(theory, height, depth, period, order, g):
    """The wavelength whose closed-flume period L d / Q(L) is `period` (the secant method from linear theory's
    wavelength and 1.05 times it; T(L) increases with L, and stays within a factor 2 of linear theory's)."""
    k = regular_wavenumber(height, period, depth, g)  # a finite wavelength, below Miche's limit in linear theory
    l0 = 2.0 * math.pi / k
    _check_breaking(theory, height, depth, l0, period)
    a, b = l0, 1.05 * l0
    first = _solve(theory, height, depth, a, order, g)
    if theory == "stokes":
        _stokes_single_crest(first, height, depth, a)
    fa = _period(first, depth) - period
    for _ in range(40):
        _check_breaking(theory, height, depth, b, period)
        model = _solve(theory, height, depth, b, order, g)
        fb = _period(model, depth) - period
        if abs(fb) <= 1e-10 * period:
            return model
        if fb == fa:
            break
        a, b, fa = b, b - fb * (b - a) / (fb - fa), fb
        if not (math.isfinite(b) and 0.5 * l0 < b < 2.0 * l0):  # nonlinear theories stay near linear theory's L
            break
    raise ValueError(f"no {_label(theory, order)} of period T = {period:g} s found in {depth:g} m of water "
                     f"(H = {height:g} m): the wavelength did not converge; give the wavelength instead")


def _series(model, order, depth):
    """U_j and a_j, j = 1..N, of raschii's `model` by a discrete Fourier transform of its velocity at the
    still-water level and its elevation at M = 4 (N + 1) phases over a wavelength (exact to round-off for
    series of degree N)."""
    m = 4 * (order + 1)
    x = model.length * np.arange(m) / m
    with np.errstate(all="ignore"):
        u = np.asarray(model.velocity(x, np.full(m, depth), 0.0, all_points_wet=True), float)[:, 0]
        eta = np.asarray(model.surface_elevation(x, 0.0, include_depth=False), float)
    fu, fe = np.fft.rfft(u) / m, np.fft.rfft(eta) / m
    return 2.0 * fu[1:order + 1].real, 2.0 * fe[1:order + 1].real


def _stokes_single_crest(model, height, depth, length):
    """Refuse a Stokes profile with a second crest in its trough (where Stokes theory fails: shallow water)."""
    theta = np.linspace(0.0, math.pi, 1001)
    eta = np.asarray(model.surface_elevation(theta / model.k, 0.0, include_depth=False), float)
    if np.any(np.diff(eta) > 1e-9 * height):
        ursell = height * length**2 / depth**3
        raise ValueError(f"Stokes theory (order {model.order}) fails for H = {height:g} m, L = {length:.4g} m in "
                         f"d = {depth:g} m (Ursell number H L^2 / d^3 = {ursell:.3g}): its profile has a second "
                         'crest in the trough; use type = "fenton"')


@functools.lru_cache(maxsize=64)
def _cached(theory, height, depth, period, wavelength, order, g):
    if wavelength is not None:
        _check_breaking(theory, height, depth, wavelength)
        model = _solve(theory, height, depth, wavelength, order, g)
    else:
        model = _length_for_period(theory, height, depth, period, order, g)
    length = float(model.length)
    _check_breaking(theory, height, depth, length, period)
    if theory == "stokes":
        _stokes_single_crest(model, height, depth, length)
    velocities, amplitudes = _series(model, order, depth)
    velocities.setflags(write=False)  # shared by every caller through the cache
    amplitudes.setflags(write=False)
    if not (np.all(np.isfinite(velocities)) and np.all(np.isfinite(amplitudes))):
        raise ValueError(f"raschii's {_label(theory, order)} of H = {height:g} m, L = {length:.4g} m in "
                         f"d = {depth:g} m has no finite velocity (kd = {2 * math.pi * depth / length:.3g}: too "
                         "deep); use the linear target")
    k = 2.0 * math.pi / length
    celerity = float(model.Q) / depth
    b0 = float(model.c)
    j = np.arange(1, order + 1)
    crest = float(np.sum(amplitudes))
    trough = float(np.sum(amplitudes * np.cos(j * math.pi)))
    return NonlinearWave(theory=theory, height=height, depth=depth, order=order, wavelength=length, wavenumber=k,
                         period=length / celerity, omega=k * celerity, celerity=celerity, current=celerity - b0,
                         stokes_drift=b0 - celerity, velocities=velocities, amplitudes=amplitudes, crest=crest,
                         trough=trough, model=model)


def nonlinear_wave(theory, height, depth, *, period=None, wavelength=None, order=None, g=GRAVITY):
    """The nonlinear regular wave of `height` H [m] and `period` T [s] (or `wavelength` L [m]) in `depth` d [m],
    in the closed-flume frame (zero mean mass flux; see the module docstring).

    Parameters
    ----------
    theory : {"fenton", "stokes"}
        Fenton's stream-function wave (Rienecker & Fenton 1981; Fenton 1988, 1999) or Stokes' fifth-order
        wave (Fenton 1985), both by raschii.
    height, depth : float
        H and d [m].
    period, wavelength : float
        T [s] in the laboratory frame, or L [m]: exactly one.
    order : int, optional
        N: the number of Fourier harmonics (Fenton; default 10) or the order of the expansion (Stokes, 1 to 5;
        default 5).
    g : float
        Gravity [m/s^2].

    Returns
    -------
    NonlinearWave

    Raises
    ------
    ValueError
        One line: a height past the breaking limit (Miche 1944: H_max = 0.142 L tanh(kd); raschii's
        0.78 d and 0.14 L), a period without a finite wavelength, a solution that does not converge, a Stokes
        profile with a second crest (shallow water), neither or both of `period` and `wavelength`.
    """
    if theory not in THEORIES:
        raise ValueError(f"theory = {theory!r}: not one of {', '.join(THEORIES)}")
    if (period is None) == (wavelength is None):
        raise ValueError("give the wave's period or its wavelength (one of the two)")
    order = (10 if theory == "fenton" else 5) if order is None else int(order)
    if not 1 <= order <= MAX_ORDER[theory]:
        raise ValueError(f"order = {order}: the {THEORIES[theory]} wave takes 1 to {MAX_ORDER[theory]}")
    args = [float(v) if v is not None else None for v in (height, depth, period, wavelength)]
    return _cached(theory, *args, order, float(g))
