"""Prescribed motions of solid bodies, as plain functions of time.

A motion is data (a TOML ``[[motions]]`` table) with one method,
``kinematics(t)`` -> (displacement [m], velocity [m/s]), two 3-vectors; the
particles of every solid whose ``motion`` names it move rigidly with it:
x(t) = x(0) + displacement(t), and they carry velocity(t) into the
viscous and boundary terms.

* `ConstantVelocity`: a wall pushed at constant speed (the moving-wall
  inflow of the tidal-bore paper).
* `PistonWavemaker`: a piston paddle for regular waves of height H and
  period T in depth d, its stroke from Biesel's transfer function.
* `SolitaryPiston`: a piston paddle generating a solitary wave by Goring's
  (1978) method.
* `TimeSeriesMotion`: displacements read from a file (t, x[, y, z]),
  interpolated with a cubic spline (velocity its derivative).
* `IrregularWaves`: a piston paddle for a random sea of a spectrum
  (JONSWAP, Pierson-Moskowitz or tabulated), component by component with
  Biesel's transfer function.
* `FocusedWaves`: a piston paddle for a focused wave group (NewWave) that
  crests at a chosen place and time.

The wave theory (dispersion, transfer functions, spectra, components) is in
`shoal.waves`; `wavenumber` and `piston_height_to_stroke` are importable from
here too.

`check_motion_speeds` refuses a motion faster than the speed of sound c0
of the weakly compressible model and warns about one above `MACH_LIMIT` c0.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, PrivateAttr, field_validator, model_validator

from .geometry.shapes import CasePath, PositiveReal, Spec, Vec3
from .waves.components import focused_components, random_phase_components
from .waves.dispersion import group_velocity, wavenumber
from .waves.spectra import AnySpectrum
from .waves.transfer import piston_height_to_stroke

_G = 9.81

MACH_LIMIT = 0.1
"""Largest wall speed, as a fraction of c0, that weakly compressible SPH follows without warning: the
density varies as the square of the Mach number, by about 1 % at M = 0.1 (Monaghan 1994, the reason
c0 is ten times the largest flow speed)."""

_SAMPLES = 1001
"""Times at which a motion's speed is sampled to find its peak (besides the exact points of each kind)."""


class Motion(Spec):
    """Base of motions: `name` is what solids refer to."""

    name: Annotated[str, Field(min_length=1)]

    def kinematics(self, t):
        """(displacement [m], velocity [m/s]) at time t [s], 3-vectors."""
        raise NotImplementedError

    def peak_speed(self, t_end):
        """The largest speed |velocity(t)| [m/s] over 0 <= t <= `t_end` [s], from the times
        `_speed_times` gives (each kind lists where its peaks can be)."""
        times = self._speed_times(float(t_end))
        return max((math.hypot(*self.kinematics(float(t))[1]) for t in times), default=0.0)

    def _speed_times(self, t_end):
        return np.linspace(0.0, t_end, _SAMPLES)

    def acceleration(self, t, eps=1e-5):
        """Acceleration [m/s^2] at time t [s], a 3-vector: the central difference
        (v(t + eps) - v(t - eps)) / (2 eps) of the velocity (the Adami wall
        pressure of a moving wall needs it, `shoal.physics.wall_pressure`)."""
        return (np.asarray(self.kinematics(t + eps)[1], float)
                - np.asarray(self.kinematics(max(t - eps, 0.0))[1], float)) / (t + eps - max(t - eps, 0.0))


class ConstantVelocity(Motion):
    """Rigid motion at constant `velocity` [m/s] from time `start` [s]:
    displacement = velocity max(t - start, 0)."""

    type: Literal["constant_velocity"] = "constant_velocity"
    velocity: Vec3
    start: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0

    def kinematics(self, t):
        v = np.asarray(self.velocity, float)
        return v * max(t - self.start, 0.0), (v if t >= self.start else np.zeros(3))

    def acceleration(self, t, eps=1e-5):
        """Zero: the start is an impulsive step (no finite acceleration to extrapolate a pressure with)."""
        return np.zeros(3)

    def peak_speed(self, t_end):
        """|velocity| once the motion has started before `t_end`, else 0."""
        return math.hypot(*self.velocity) if self.start <= t_end else 0.0


class PistonWavemaker(Motion):
    """A piston paddle making regular waves of `height` H [m] and `period` T
    [s] in water of `depth` d [m].

    Stroke S = H / (H/S) with Biesel's transfer function
    (`piston_height_to_stroke`), and paddle displacement along `direction`
    X(t) = r(t) (S/2) sin(omega t), with the start-up ramp
    r(t) = (1 - cos(pi t / t_r)) / 2 for t < t_r = `ramp_periods` T.
    """

    type: Literal["piston"] = "piston"
    height: PositiveReal
    period: PositiveReal
    depth: PositiveReal
    direction: Vec3 = (1.0, 0.0, 0.0)
    ramp_periods: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 2.0

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse a period without a finite wavelength, and a height above the breaking limit of Miche (1944),
        H_max = 0.142 L tanh(k d): no regular wave that high exists in that depth."""
        try:
            k = wavenumber(self.period, self.depth)
        except (OverflowError, ZeroDivisionError):
            k = math.nan
        if not (math.isfinite(k) and k > 0 and math.isfinite(2.0 * math.pi / k)):
            raise ValueError(f"period = {self.period:g} s in {self.depth:g} m of water gives no finite wavelength; "
                             "give the period of a water wave in seconds")
        length = 2.0 * math.pi / k
        h_max = 0.142 * length * math.tanh(k * self.depth)
        if self.height > h_max:
            raise ValueError(f"height = {self.height:g} m is above the breaking limit H_max = 0.142 L tanh(kd) = "
                             f"{h_max:.3g} m (Miche 1944) of a {self.period:g} s wave in {self.depth:g} m of water "
                             f"(L = {length:.3g} m): no regular wave that high exists; give a lower height or a "
                             "longer period")
        ratio = piston_height_to_stroke(k, self.depth)
        stroke = self.height / ratio if ratio > 0 else math.inf
        if not stroke <= 1000.0 * self.depth:
            raise ValueError(f"period = {self.period:g} s needs a paddle stroke of {stroke:.3g} m, more than 1000 times "
                             f"the depth {self.depth:g} m (Biesel's H/S = {ratio:.3g}); give a shorter period")
        return self

    @property
    def wavenumber(self):
        return wavenumber(self.period, self.depth)

    @property
    def stroke(self):
        """Full stroke S [m] of the paddle."""
        return self.height / piston_height_to_stroke(self.wavenumber, self.depth)

    def _ramp(self, t):
        tr = self.ramp_periods * self.period
        if tr <= 0 or t >= tr:
            return 1.0, 0.0
        if t <= 0:
            return 0.0, 0.0
        return 0.5 * (1 - math.cos(math.pi * t / tr)), 0.5 * math.pi / tr * math.sin(math.pi * t / tr)

    def _unit(self):
        d = np.asarray(self.direction, float)
        return d / np.linalg.norm(d)

    def _speed_times(self, t_end):
        """The ramp and two periods after it: the motion is periodic from then on."""
        return np.linspace(0.0, min(t_end, (self.ramp_periods + 2.0) * self.period), _SAMPLES)

    def kinematics(self, t):
        w = 2 * math.pi / self.period
        r, dr = self._ramp(t)
        t = max(t, 0.0)
        a = 0.5 * self.stroke
        e = self._unit()
        return e * (r * a * math.sin(w * t)), e * (a * (dr * math.sin(w * t) + r * w * math.cos(w * t)))


class SolitaryPiston(Motion):
    """A piston paddle pushing out one solitary wave of `height` H [m] in
    water of `depth` d [m] (Goring 1978, as in DualSPHysics and GPUSPH).

    The paddle follows the water under the wave:
    dX/dt = c eta(X, t) / (d + eta(X, t)),
    eta(x, t) = H sech^2(k (c (t - t0) - x)), k = sqrt(3 H / (4 d^3)),
    c = sqrt(g (d + H)), integrated with RK4 from t = 0, where eta at the
    paddle is 0.2 % of H (t0 = 3.8 / (k c)), until it is 0.2 % again. With
    theta = k (c (t - t0) - X), dX/dtheta = eta / (k d), so the stroke is
    S tanh(3.8) with S = 2 H / (k d) = sqrt(16 H d / 3) (0.1 % in the tails).
    """

    type: Literal["solitary"] = "solitary"
    height: PositiveReal
    depth: PositiveReal
    direction: Vec3 = (1.0, 0.0, 0.0)
    start: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0
    _table: tuple | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse H / d above 0.78, the highest solitary wave (McCowan 1894)."""
        if self.height > 0.78 * self.depth:
            raise ValueError(f"height = {self.height:g} m is {self.height / self.depth:.3g} times the depth "
                             f"{self.depth:g} m: a solitary wave breaks above H / d = 0.78 (McCowan 1894); give a "
                             f"height of at most {0.78 * self.depth:.3g} m")
        try:  # k = sqrt(3 H / 4 d^3): d^3 overflows past d = 5.6e102 m, underflows below 1e-108 m
            finite = all(math.isfinite(v) and v > 0 for v in (self.k, self.stroke, self.duration))
        except (OverflowError, ZeroDivisionError):
            finite = False
        if not finite:
            raise ValueError(f"height = {self.height:g} m in {self.depth:g} m of water gives no finite paddle stroke "
                             "and duration; give the height and depth of a water wave in metres")
        return self

    @property
    def stroke(self):
        """Total paddle travel S = 2 H / (k d) [m]."""
        return 2.0 * self.height / (self.k * self.depth)

    @property
    def k(self):
        return math.sqrt(3.0 * self.height / (4.0 * self.depth**3))

    @property
    def celerity(self):
        return math.sqrt(_G * (self.depth + self.height))

    @property
    def duration(self):
        """Time the paddle moves [s]: until eta at the paddle is back to 0.2 % of H,
        (2 x 3.8 + k S) / (k c) (the paddle has moved S meanwhile)."""
        return (2.0 * 3.8 + self.k * self.stroke) / (self.k * self.celerity)

    def _speed_times(self, t_end):
        """The stroke, from `start` for `duration`: the paddle rests before and after."""
        return np.linspace(self.start, max(self.start, min(t_end, self.start + self.duration)), _SAMPLES)

    def _eta(self, x, t):
        t0 = 3.8 / (self.k * self.celerity)
        return self.height / math.cosh(self.k * (self.celerity * (t - t0) - x)) ** 2

    def _rate(self, x, t):
        e = self._eta(x, t)
        return self.celerity * e / (self.depth + e)

    def _build(self):
        n = 4000
        T = self.duration
        dt = T / n
        ts = np.linspace(0.0, T, n + 1)
        xs = np.zeros(n + 1)
        x = 0.0
        for i in range(n):
            t = ts[i]
            k1 = self._rate(x, t)
            k2 = self._rate(x + 0.5 * dt * k1, t + 0.5 * dt)
            k3 = self._rate(x + 0.5 * dt * k2, t + 0.5 * dt)
            k4 = self._rate(x + dt * k3, t + dt)
            x += dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            xs[i + 1] = x
        self._table = (ts, xs)
        return self._table

    def kinematics(self, t):
        ts, xs = self._table or self._build()
        e = np.asarray(self.direction, float)
        e = e / np.linalg.norm(e)
        tl = t - self.start
        if tl <= 0:
            return np.zeros(3), np.zeros(3)
        if tl >= ts[-1]:
            return e * xs[-1], np.zeros(3)
        x = float(np.interp(tl, ts, xs))
        return e * x, e * self._rate(x, tl)


class TimeSeriesMotion(Motion):
    """Rigid displacement read from `file`: columns t [s], x [m] (and
    optionally y, z), '#' comments and a header row allowed. A cubic spline
    (scipy) interpolates the displacement; the velocity is its derivative.
    Before the first time the body rests at the first displacement, after
    the last at the last. Relative paths are relative to the case file.
    """

    type: Literal["time_series"] = "time_series"
    file: CasePath
    scale: Annotated[float, Field(allow_inf_nan=False, strict=True)] = 1.0
    _spline: object = PrivateAttr(default=None)

    def _load(self):
        from scipy.interpolate import CubicSpline

        from .errors import InputError

        p = Path(self.file)
        if not p.is_file():
            raise InputError(f"motion {self.name!r}: time-series file {self.file!r} not found")
        try:
            a = np.genfromtxt(p, delimiter="," if p.suffix == ".csv" else None, comments="#")
        except ValueError as exc:
            raise InputError(f"motion {self.name!r}: {self.file!r} could not be read: {' '.join(str(exc).split())}") \
                from None
        a = np.atleast_2d(a)
        a = a[np.all(np.isfinite(a), axis=1)]
        if a.ndim != 2 or a.shape[1] < 2 or a.shape[1] > 4 or len(a) < 2:
            raise InputError(f"motion {self.name!r}: {self.file!r} must hold columns t, x[, y, z] with at least "
                             "two rows")
        t = a[:, 0]
        if np.any(np.diff(t) <= 0):
            raise InputError(f"motion {self.name!r}: the times in {self.file!r} must increase strictly")
        d = np.zeros((len(a), 3))
        d[:, : a.shape[1] - 1] = a[:, 1:] * self.scale
        self._spline = (CubicSpline(t, d, axis=0, bc_type="clamped"), t[0], t[-1], d[0], d[-1])
        return self._spline

    def kinematics(self, t):
        sp, t0, t1, d0, d1 = self._spline or self._load()
        if t <= t0:
            return d0.copy(), np.zeros(3)
        if t >= t1:
            return d1.copy(), np.zeros(3)
        return np.asarray(sp(t), float), np.asarray(sp(t, 1), float)

    def _speed_times(self, t_end):
        """The spline's knots, the times where a velocity component peaks (roots of the second
        derivative) and a uniform sampling, within the file's times and [0, t_end]."""
        sp, t0, t1, _, _ = self._spline or self._load()
        lo, hi = max(t0, 0.0), min(t1, t_end)
        if lo >= hi:
            return np.empty(0)  # the body rests at one end of the series the whole run
        # each velocity component is a quadratic on each piece: it peaks at a knot or where the acceleration is 0
        roots = sp.derivative(2).roots(extrapolate=False)
        roots = [np.atleast_1d(np.asarray(r, float)) for r in np.ravel(roots)] if roots.dtype == object else [roots]
        t = np.concatenate([sp.x, *roots, np.linspace(lo, hi, _SAMPLES)])
        return t[(t >= lo) & (t <= hi)]

    def acceleration(self, t, eps=1e-5):
        """The spline's second derivative (zero before the first and after the last time)."""
        sp, t0, t1, _, _ = self._spline or self._load()
        if t <= t0 or t >= t1:
            return np.zeros(3)
        return np.asarray(sp(t, 2), float)


MAX_COMPONENTS = 32768
"""Most wave components a spectral paddle may have (its kinematics sum them at every call)."""

MAX_HARMONIC = 1 << 16
"""Largest f_n / df of a spectral paddle's components: its signal is sampled 20 times per period of that
harmonic over a repeat period (`SpectralPaddle.peak_speed`)."""

_SAMPLES_PER_PERIOD = 20
"""Samples per period of a spectral paddle's fastest component where its peak speed is sought."""


class SpectralPaddle(Motion):
    """Base of the piston paddles driven by a sum of wave components (`IrregularWaves`, `FocusedWaves`).

    For components of amplitudes a_n, angular frequencies omega_n, wavenumbers k_n and phases phi_n (made by
    each kind from its `spectrum`, `shoal.waves.components`), the paddle moves along `direction` as

        X(t) = r(t) sum_n (a_n / T_n) sin(omega_n t + phi_n),   T_n = H/S of a piston at k_n d

    (Biesel's transfer function, `shoal.waves.piston_height_to_stroke`), with the start-up ramp
    r(t) = (1 - cos(pi t / t_r)) / 2 for t < t_r (`ramp`), 1 after; its velocity is the derivative of X.
    Each component is `PistonWavemaker`'s motion for a wave of height 2 a_n, shifted in phase: in linear
    theory the paddle makes, away from its evanescent near field, the elevation
    eta(x, t) = sum_n a_n cos(omega_n t - k_n x + phi_n) at the distance x in front of its rest position
    (`elevation`; the ramp's start reaches x about t_r + x / c_g later). The signal repeats itself after the
    repeat period 1 / df of the components (`shoal.waves.frequency_grid`).
    """

    spectrum: AnySpectrum
    depth: PositiveReal
    components: Annotated[int, Field(ge=1, le=MAX_COMPONENTS, strict=True)] = 256
    f_min: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.5
    f_max: Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)] = 3.0
    ramp_time: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] | None = None
    direction: Vec3 = (1.0, 0.0, 0.0)
    paddle: str = "piston"
    _waves: object = PrivateAttr(default=None)
    _grid: tuple | None = PrivateAttr(default=None)
    _terms: tuple | None = PrivateAttr(default=None)

    @field_validator("paddle")
    @classmethod
    def _a_piston(cls, v):
        if v == "flap":
            raise ValueError("paddle = 'flap' is not available yet: a flap rotates about its hinge, and shoal's "
                             "motions only translate a solid (shoal.waves.flap_height_to_stroke gives a flap's "
                             "transfer function); use paddle = 'piston'")
        if v != "piston":
            raise ValueError(f"paddle = {v!r} is not a paddle type; allowed: 'piston'")
        return v

    def _make_components(self):
        raise NotImplementedError

    def _check_components(self):
        """Refuse what gives no finite paddle signal (an empty band, a zero axis, infinite wavenumbers or phases,
        a travel over 1000 depths), a band too narrow for its components, a ramp of zero. Returns the
        components."""
        if not self.f_min < self.f_max:
            raise ValueError(f"f_min = {self.f_min:g} is not below f_max = {self.f_max:g} (both multiples of the "
                             "peak frequency); give the band of the components, e.g. f_min = 0.5, f_max = 3")
        if not np.linalg.norm(np.asarray(self.direction, float)) > 0:
            raise ValueError("direction = [0, 0, 0] is no axis; give the way the paddle pushes, e.g. [1, 0, 0]")
        fp = self.spectrum.peak_frequency
        if not (0.0 < fp < math.inf):
            raise ValueError(f"the spectrum peaks at f = {fp:g} Hz: the band of the components is set in multiples "
                             "of the peak frequency, which must be positive")
        try:
            with np.errstate(all="ignore"):
                waves = self._make_components()
                finite = bool(np.all(np.isfinite(waves.wavenumbers)) and np.all(np.isfinite(waves.amplitudes))
                              and np.all(waves.wavenumbers > 0) and math.isfinite(waves.repeat_period))
        except (OverflowError, ZeroDivisionError, FloatingPointError):
            finite = False
        if not finite:
            raise ValueError(f"a peak frequency of {fp:g} Hz in {self.depth:g} m of water gives no finite "
                             "wavelengths and amplitudes; give the spectrum of water waves in metres and seconds")
        if not np.any(waves.amplitudes > 0):
            raise ValueError(f"the spectrum holds no energy between f_min = {self.f_min:g} fp and f_max = "
                             f"{self.f_max:g} fp (fp = {fp:.4g} Hz): the paddle would not move; widen the band")
        if not np.all(np.abs(waves.phases) < 1e10):  # (beyond, a phase has lost its sixth decimal)
            raise ValueError("the components' phases k x - omega t at the focus are beyond 1e10 rad, where they "
                             "lose their precision; give a nearer x_focus or an earlier t_focus")
        harmonic = float(waves.frequencies.max() / waves.df)
        if harmonic > MAX_HARMONIC:
            raise ValueError(f"{self.components} components over f_min .. f_max = {self.f_min:g} .. {self.f_max:g} fp "
                             f"repeat only after {harmonic:.3g} periods of the fastest one (more than "
                             f"{MAX_HARMONIC}); widen the band or give fewer components")
        with np.errstate(all="ignore"):
            bound = float(np.sum(self._coefficients(waves)))
        if not bound <= 1000.0 * self.depth:
            travel = f"up to {bound:.3g} m" if math.isfinite(bound) else "without bound"
            raise ValueError(f"the components need a paddle travel {travel}, more than 1000 times the "
                             f"depth {self.depth:g} m (Biesel's H/S is small for long waves); raise f_min above "
                             f"{self.f_min:g} fp or give a shorter peak period")
        if self.ramp_time is not None and self.ramp_time <= 0:
            raise ValueError("ramp_time = 0 s would start the paddle away from where the case puts it (the sum of "
                             "the components is not 0 at t = 0); give a ramp of a peak period or more (the default "
                             "is two)")
        if self.ramp_time is not None and self.ramp_time > waves.repeat_period * (1 + 1e-9):
            raise ValueError(f"ramp_time = {self.ramp_time:g} s is longer than the repeat period 1/df = "
                             f"{waves.repeat_period:.4g} s of the components, after which the signal repeats itself; "
                             "give a shorter ramp (a few peak periods) or more components")
        return waves

    def _miche_height(self, fp):
        """Miche's (1944) highest wave H_max = 0.142 L tanh(kd) [m] at the frequency fp [Hz], and L [m]."""
        k = wavenumber(1.0 / fp, self.depth)
        length = 2.0 * math.pi / k
        return 0.142 * length * math.tanh(k * self.depth), length

    @property
    def wave_components(self):
        """The components (`shoal.waves.WaveComponents`): frequencies, amplitudes, phases, wavenumbers."""
        if self._waves is None:
            self._waves = self._make_components()
        return self._waves

    @property
    def repeat_period(self):
        """1 / df [s]: the paddle's signal repeats itself after this time (past the ramp)."""
        return self.wave_components.repeat_period

    @property
    def ramp(self):
        """t_r [s]: `ramp_time`, or else two peak periods (at most the repeat period)."""
        if self.ramp_time is not None:
            return float(self.ramp_time)
        return min(2.0 / self.spectrum.peak_frequency, self.repeat_period)

    @staticmethod
    def _coefficients(waves):
        """b_n = a_n / T_n [m]: the paddle amplitude of each component."""
        return waves.amplitudes / piston_height_to_stroke(waves.wavenumbers, waves.depth)

    def _ramp_factor(self, t):
        tr = self.ramp
        if tr <= 0 or t >= tr:
            return 1.0, 0.0
        if t <= 0:
            return 0.0, 0.0
        return 0.5 * (1 - math.cos(math.pi * t / tr)), 0.5 * math.pi / tr * math.sin(math.pi * t / tr)

    def _unit(self):
        d = np.asarray(self.direction, float)
        return d / np.linalg.norm(d)

    def _signal(self):
        """(b_n, omega_n, phi_n, b_n omega_n, the unit axis), computed once."""
        if self._terms is None:
            w = self.wave_components
            b = self._coefficients(w)
            self._terms = (b, w.omegas, w.phases, b * w.omegas, self._unit())
        return self._terms

    def kinematics(self, t):
        """(displacement [m], velocity [m/s]) at time t [s], 3-vectors along `direction`."""
        b, omega, phi, bw, e = self._signal()
        r, dr = self._ramp_factor(t)
        t = max(t, 0.0)
        arg = omega * t + phi
        s = float(np.dot(b, np.sin(arg)))
        c = float(np.dot(bw, np.cos(arg)))
        return e * (r * s), e * (dr * s + r * c)

    def elevation(self, x, t):
        """The linear target elevation eta(x, t) = sum_n a_n cos(omega_n t - k_n x + phi_n) [m] at the distance
        `x` [m] in front of the paddle's rest position, at the times `t` [s] (array_like), without the ramp:
        the far field of the paddle once the ramp has passed x, the theoretical record of a gauge there."""
        return self.wave_components.elevation(x, t)

    def _sampled(self):
        """(dt, s, c): the unramped displacement s_j = sum_n b_n sin(omega_n t_j + phi_n) and velocity c_j =
        sum_n b_n omega_n cos(omega_n t_j + phi_n) at t_j = j dt over one repeat period T = M dt,
        M = 2 ceil(10 n_max) (20 samples or more a period of the fastest component, n_max df its frequency),
        each by an inverse FFT (f_n = n df: a sum of cos(2 pi n j / M + psi_n))."""
        if self._grid is None:
            w = self.wave_components
            b = self._signal()[0]
            n = np.rint(w.frequencies / w.df).astype(np.int64)
            m = 2 * int(math.ceil(_SAMPLES_PER_PERIOD / 2 * max(int(n.max()), 1)))
            out = []
            for coef, shift in ((b, -0.5 * math.pi), (b * w.omegas, 0.0)):  # sin(u) = cos(u - pi/2)
                spectrum = np.zeros(m // 2 + 1, complex)
                np.add.at(spectrum, n, 0.5 * m * coef * np.exp(1j * (w.phases + shift)))
                out.append(np.fft.irfft(spectrum, m))
            self._grid = (w.repeat_period / m, out[0], out[1])
        return self._grid

    def _speed_times(self, t_end):
        """Times t_j = j dt (`_sampled`: 20 or more a period of the fastest component) from 0 to the end of the
        ramp and one repeat period after it (the signal is periodic past the ramp), up to `t_end`."""
        dt, s, _ = self._sampled()
        last = min(float(t_end), self.ramp + self.repeat_period)
        if last < 0:
            return np.empty(0)
        return np.arange(int(math.floor(last / dt)) + 1) * dt

    def peak_speed(self, t_end):
        """The largest speed [m/s] over 0 <= t <= `t_end` [s] at the times `_speed_times` gives and at the
        middle of the ramp: the ramp r(t) and its derivative times the sampled periodic signal, within about
        1 % (the sampling's)."""
        dt, s, c = self._sampled()
        t = self._speed_times(t_end)
        if not len(t):
            return 0.0
        j = np.arange(len(t)) % len(s)
        tr = self.ramp
        x = np.clip(t, 0.0, tr) / tr if tr > 0 else np.ones_like(t)
        r = 0.5 * (1.0 - np.cos(math.pi * x))
        dr = np.zeros_like(t)
        inside = (x > 0.0) & (x < 1.0)
        dr[inside] = 0.5 * math.pi / tr * np.sin(math.pi * x[inside])
        peak = float(np.max(np.abs(dr * s[j] + r * c[j])))
        if 0.0 < 0.5 * tr <= t_end:  # the middle of the ramp, where r' peaks (a ramp shorter than dt included)
            peak = max(peak, float(np.linalg.norm(self.kinematics(0.5 * tr)[1])))
        return peak

    @property
    def max_displacement(self):
        """The largest |X(t)| [m] of the paddle over all times (the ramp only lessens it), sampled as
        `peak_speed` samples the velocity: leave this much room behind the paddle's rest position."""
        return float(np.max(np.abs(self._sampled()[1])))


class IrregularWaves(SpectralPaddle):
    """A piston paddle making a random sea of `spectrum` in water of `depth` d [m] (`SpectralPaddle`).

    The components: `components` N over the band [`f_min` fp, `f_max` fp], fp the spectrum's peak frequency,
    amplitudes a_n = sqrt(2 S(f_n) df) (rescaled so that sum a_n^2 / 2 = m0 with `rescale`), phases uniformly
    random from ``numpy.random.default_rng(seed)``, and Rayleigh amplitudes with `random_amplitudes`
    (`shoal.waves.random_phase_components`). A significant height above the breaking limit of Miche (1944) at
    the peak period, Hs > 0.142 Lp tanh(kp d), is refused.
    """

    type: Literal["irregular"] = "irregular"
    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    random_amplitudes: Annotated[bool, Field(strict=True)] = False
    rescale: Annotated[bool, Field(strict=True)] = True

    def _make_components(self):
        return random_phase_components(self.spectrum, self.depth, self.components, self.f_min, self.f_max,
                                       self.seed, self.random_amplitudes, self.rescale)

    @model_validator(mode="after")
    def _a_sea_that_exists(self):
        """Refuse a band, a spectrum or a depth that gives no finite signal, and Hs above Miche's limit."""
        fp = self.spectrum.peak_frequency
        self._check_components()
        hs = self.spectrum.hm0
        h_max, length = self._miche_height(fp)
        if hs > h_max:
            raise ValueError(f"the spectrum's Hs = {hs:.3g} m is above the breaking limit H_max = 0.142 L tanh(kd) = "
                             f"{h_max:.3g} m (Miche 1944) of the peak period {1.0 / fp:.3g} s in {self.depth:g} m of "
                             f"water (L = {length:.3g} m): most of its waves would break at the paddle; give a "
                             "lower Hs or a longer peak period")
        return self


class FocusedWaves(SpectralPaddle):
    """A piston paddle making a focused wave group (NewWave, Tromans et al. 1991): every component crests at
    `x_focus` [m] in front of the paddle at `t_focus` [s], where the linear elevation is `amplitude` A [m]
    (`SpectralPaddle`).

    The components: `components` N over the band [`f_min` fp, `f_max` fp], amplitudes a_n = A S(f_n) df /
    sum S df (the spectrum gives the shape; its Hs does not matter) and phases phi_n = k_n x_focus - omega_n
    t_focus (`shoal.waves.focused_components`). Refused: t_focus before the slowest component, started at the
    end of the ramp, can reach x_focus (t_focus < t_r + x_focus / min c_g), and 2 A above the breaking limit
    of Miche (1944) at the peak period. The group focuses again every repeat period.
    """

    type: Literal["focused"] = "focused"
    amplitude: PositiveReal
    x_focus: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]
    t_focus: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]

    def _make_components(self):
        return focused_components(self.spectrum, self.depth, self.amplitude, self.x_focus, self.t_focus,
                                  self.components, self.f_min, self.f_max)

    @model_validator(mode="after")
    def _a_group_that_exists(self):
        """Refuse a band, a spectrum or a depth that gives no finite signal, a focus too high or too early."""
        fp = self.spectrum.peak_frequency
        waves = self._check_components()
        h_max, length = self._miche_height(fp)
        if 2.0 * self.amplitude > h_max:
            raise ValueError(f"amplitude = {self.amplitude:g} m makes a wave of height about {2 * self.amplitude:.3g} "
                             f"m at the focus, above the breaking limit H_max = 0.142 L tanh(kd) = {h_max:.3g} m "
                             f"(Miche 1944) of the peak period {1.0 / fp:.3g} s in {self.depth:g} m of water "
                             f"(L = {length:.3g} m); give an amplitude of at most {0.5 * h_max:.3g} m")
        cg = group_velocity(waves.wavenumbers, self.depth)
        slow = int(np.argmin(cg))
        ramp = self.ramp_time if self.ramp_time is not None else min(2.0 / fp, waves.repeat_period)
        earliest = ramp + self.x_focus / float(cg[slow])
        if self.t_focus < earliest:
            raise ValueError(f"t_focus = {self.t_focus:g} s is too early: the slowest component "
                             f"({waves.frequencies[slow]:.3g} Hz, group velocity {cg[slow]:.3g} m/s) leaves the "
                             f"paddle at the end of the ramp, {ramp:.3g} s, and reaches x_focus = {self.x_focus:g} m "
                             f"at {earliest:.3g} s; give t_focus >= {earliest:.3g} s")
        return self


AnyMotion = Annotated[Union[ConstantVelocity, PistonWavemaker, SolitaryPiston, TimeSeriesMotion, IrregularWaves,
                            FocusedWaves], Field(discriminator="type")]


def check_motion_speeds(motions, c0, t_end):
    """Refuse a motion faster than sound; warn about one faster than `MACH_LIMIT` c0.

    Weakly compressible SPH lets the density vary by (u / c0)^2 to carry a flow of speed u (Monaghan
    1994): a wall at u >= c0 outruns every pressure wave the fluid can send, and in one time step
    (CFL h / c0) it crosses more than the kernel support, through the fluid it should push. Such a
    motion is certainly a mistake of units or values (a time series in millimetres read as metres, a
    velocity of 1e12 m/s).

    Parameters
    ----------
    motions : list of Motion
    c0 : float
        The case's speed of sound [m/s] (`shoal.physics.constants.speed_of_sound`).
    t_end : float
        The case's end time [s]: only the motion up to then counts.

    Returns
    -------
    list of str
        One warning per motion whose peak speed is above `MACH_LIMIT` c0.

    Raises
    ------
    shoal.errors.InputError
        For a motion whose peak speed is not below c0 (or not finite).
    """
    from .errors import InputError

    warnings = []
    for m in motions:
        u = m.peak_speed(t_end)
        if not u < c0:
            raise InputError(f"motion {m.name!r} reaches {u:.3g} m/s, not below the speed of sound c0 = {c0:.3g} m/s "
                             f"of the weakly compressible fluid: no wall can be faster than sound here; keep its "
                             f"speed below {MACH_LIMIT:g} c0 = {MACH_LIMIT * c0:.3g} m/s (check the motion's units), or "
                             "raise c0 with options.coef_sound or fluid.u_max")
        if u > MACH_LIMIT * c0:
            warnings.append(fast_warning(f"motion {m.name!r} reaches", u, c0))
    return warnings


def fast_warning(what, u, c0):
    """The warning for a speed `u` [m/s] above `MACH_LIMIT` c0 (a wall's, or a fluid region's at the start):
    `what` names it ("motion 'gate' reaches")."""
    return (f"{what} {u:.3g} m/s, above {MACH_LIMIT:g} c0 = {MACH_LIMIT * c0:.3g} m/s: the fluid compresses by "
            f"more than 1 % (Mach {u / c0:.2g}); raise options.coef_sound or give fluid.u_max")
