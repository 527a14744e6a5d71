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

`check_motion_speeds` refuses a motion faster than the speed of sound c0
of the weakly compressible model and warns about one above `MACH_LIMIT` c0.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, PrivateAttr, model_validator

from .geometry.shapes import CasePath, PositiveReal, Spec, Vec3

_G = 9.81

MACH_LIMIT = 0.1
"""Largest wall speed, as a fraction of c0, that weakly compressible SPH follows without warning: the
density varies as the square of the Mach number, by about 1 % at M = 0.1 (Monaghan 1994, the reason
c0 is ten times the largest flow speed)."""

_SAMPLES = 1001
"""Times at which a motion's speed is sampled to find its peak (besides the exact points of each kind)."""


def wavenumber(period, depth, g=_G):
    """Wavenumber k [1/m] of linear waves: omega^2 = g k tanh(k d)
    (Airy), solved by Newton's method from the deep-water guess."""
    omega = 2.0 * math.pi / period
    k = max(omega**2 / g, omega / math.sqrt(g * depth))
    for _ in range(100):
        t = math.tanh(k * depth)
        f = g * k * t - omega**2
        df = g * t + g * k * depth * (1.0 - t * t)
        dk = f / df
        k -= dk
        if abs(dk) < 1e-14 * k:
            break
    return k


def piston_height_to_stroke(k, depth):
    """Biesel transfer function of a piston wavemaker,
    H / S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd) (Biesel & Suquet 1951;
    Dean & Dalrymple 1991, Eq. 6.21)."""
    kd2 = 2.0 * k * depth
    if kd2 > 50.0:  # deep water: the ratio is 2 to double precision (and cosh, sinh overflow past 710)
        return 2.0
    return 2.0 * (math.cosh(kd2) - 1.0) / (math.sinh(kd2) + kd2)


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


AnyMotion = Annotated[Union[ConstantVelocity, PistonWavemaker, SolitaryPiston, TimeSeriesMotion],
                      Field(discriminator="type")]


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
