"""Prescribed motions of solid bodies, as plain functions of time.

A motion is data (a TOML ``[[motions]]`` table) whose ``rigid_kinematics(t)`` gives a rigid motion
(`RigidKinematics`): a rotation R(t) about a pivot c (a point of the body at t = 0), angular velocity
omega(t), and a translation d(t) of velocity v(t). The particles of every solid whose ``motion`` names
it move rigidly with it,

    x(t) = c + d(t) + R(t) (x(0) - c),    u(t) = v(t) + omega(t) x (x(t) - c - d(t)),

and carry u(t) into the viscous and boundary terms (`shoal.physics.body_motion`). ``kinematics(t)`` ->
(d(t), v(t)), two 3-vectors, is the translation alone: the whole motion of the kinds that do not rotate
(R = I, omega = 0).

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
* `FlapWavemaker`: a flap paddle hinged at a height above the bed, rotating
  about its hinge, for regular waves; its stroke from the flap's transfer
  function. `IrregularWaves` and `FocusedWaves` drive a flap too
  (``paddle = "flap"``).
* `RotationMotion`: a sinusoidal rotation about a fixed axis through a pivot
  (DualSPHysics's ``mvrotsinu``).

The wave theory (dispersion, transfer functions, spectra, components) is in
`shoal.waves`; `wavenumber` and `piston_height_to_stroke` are importable from
here too.

`check_motion_speeds` refuses a motion faster than the speed of sound c0
of the weakly compressible model and warns about one above `MACH_LIMIT` c0.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal, NamedTuple, Union

import numpy as np
from pydantic import Field, PrivateAttr, field_validator, model_validator

from .active_absorption import ActiveAbsorption
from .geometry.shapes import CasePath, PositiveReal, Spec, Vec3
from .waves.components import WaveComponents, focused_components, random_phase_components
from .waves.dispersion import group_velocity, regular_wavenumber, wavenumber
from .waves.second_order import regular_second_order, second_order_paddle
from .waves.spectra import AnySpectrum
from .waves.transfer import flap_height_to_stroke, piston_height_to_stroke

_G = 9.81

MACH_LIMIT = 0.1
"""Largest wall speed, as a fraction of c0, that weakly compressible SPH follows without warning: the
density varies as the square of the Mach number, by about 1 % at M = 0.1 (Monaghan 1994, the reason
c0 is ten times the largest flow speed)."""

_SAMPLES = 1001
"""Times at which a motion's speed is sampled to find its peak (besides the exact points of each kind)."""


MAX_FLAP_ANGLE = math.pi / 4
"""Largest angle [rad] a flap paddle may swing either side of vertical (45 degrees): its transfer function is
linear theory, where the face's excursion (d - l) tan(theta) is the stroke; at 45 degrees tan(theta) is already
27 % above theta, and the flap lies over the water it should push."""


def rotation_matrix(axis, angle):
    """The rotation by `angle` [rad] about the unit vector `axis` (right-handed), by Rodrigues' formula:

        R = cos(theta) I + sin(theta) [a]_x + (1 - cos(theta)) a a^T,

    [a]_x the cross-product matrix of a (Rodrigues 1840; Goldstein, Poole & Safko 2002, ch. 4); 1 - cos(theta) is
    taken as 2 sin^2(theta / 2), without cancellation at small angles. About y (a = (0, 1, 0)) a positive angle turns
    +z towards +x: R = [[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]].

    Parameters
    ----------
    axis : sequence of 3 floats
        Unit vector (not normalised here).
    angle : float
        [rad].

    Returns
    -------
    numpy.ndarray
        (3, 3).
    """
    x, y, z = (float(a) for a in axis)
    c, s = math.cos(angle), math.sin(angle)
    v = 2.0 * math.sin(0.5 * angle) ** 2
    return np.array([[c + v * x * x, v * x * y - s * z, v * x * z + s * y],
                     [v * y * x + s * z, c + v * y * y, v * y * z - s * x],
                     [v * z * x - s * y, v * z * y + s * x, c + v * z * z]])


class RigidKinematics(NamedTuple):
    """A rigid motion at one time, world 3-vectors (`Motion.rigid_kinematics`).

    A point of the body at x0 at t = 0 is at x = c + d + R (x0 - c), moves at u = v + omega x r and
    accelerates at a = a_d + alpha x r + omega x (omega x r), with r = R (x0 - c) (Goldstein, Poole & Safko
    2002, ch. 4). `rotates` is false for a motion that never rotates (R = I, omega = alpha = 0): its points
    are at x0 + d exactly.

    Attributes
    ----------
    displacement : numpy.ndarray
        d [m], the pivot's displacement.
    velocity : numpy.ndarray
        v = dd/dt [m/s].
    acceleration : numpy.ndarray
        a_d = dv/dt [m/s^2] (zero where not asked for).
    rotation : numpy.ndarray
        R, (3, 3).
    angular_velocity : numpy.ndarray
        omega [rad/s].
    angular_acceleration : numpy.ndarray
        alpha = d omega / dt [rad/s^2].
    pivot : numpy.ndarray
        c [m], the point of the body at t = 0 that the rotation leaves in place.
    rotates : bool
    """

    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    rotation: np.ndarray
    angular_velocity: np.ndarray
    angular_acceleration: np.ndarray
    pivot: np.ndarray
    rotates: bool

    def points(self, x0):
        """(x [m], u [m/s], a [m/s^2]), each (N, 3), of the body points that were at `x0` ((N, 3) or (3,)) at
        t = 0, computed as the kernels compute them (`shoal.physics.body_motion`): x = (c + d) + R (x0 - c)."""
        x0 = np.atleast_2d(np.asarray(x0, float))
        if not self.rotates:
            n = len(x0)
            return (x0 + self.displacement, np.tile(self.velocity, (n, 1)), np.tile(self.acceleration, (n, 1)))
        r0 = x0 - self.pivot
        rot = self.rotation
        r = r0[:, 0:1] * rot[:, 0] + r0[:, 1:2] * rot[:, 1] + r0[:, 2:3] * rot[:, 2]
        w, al = self.angular_velocity, self.angular_acceleration
        x = (self.pivot + self.displacement) + r
        u = self.velocity + np.cross(w, r)
        a = self.acceleration + np.cross(al, r) + np.cross(w, np.cross(w, r))
        return x, u, a


def _translation(d, v, a):
    return RigidKinematics(np.asarray(d, float), np.asarray(v, float), np.asarray(a, float), np.eye(3),
                           np.zeros(3), np.zeros(3), np.zeros(3), False)


def _cosine_ramp(t, tr):
    """(r, dr/dt, d2r/dt2) of the start-up ramp r(t) = (1 - cos(pi t / t_r)) / 2 for 0 < t < t_r, 0 before,
    1 after (and 1 for t_r = 0)."""
    if tr <= 0 or t >= tr:
        return 1.0, 0.0, 0.0
    if t <= 0:
        return 0.0, 0.0, 0.0
    q = math.pi / tr
    return 0.5 * (1 - math.cos(q * t)), 0.5 * q * math.sin(q * t), 0.5 * q * q * math.cos(q * t)


def _flap_angle(x, xd, xdd, arm):
    """(theta, dtheta/dt, d2theta/dt2) of a flap whose face crosses the still-water level, `arm` [m] above its
    hinge, at the horizontal excursion x(t) [m] (with its derivatives xd, xdd): theta = atan(q), q = x / arm,
    theta' = q' / (1 + q^2), theta'' = (q'' (1 + q^2) - 2 q q'^2) / (1 + q^2)^2."""
    q, qd, qdd = x / arm, xd / arm, xdd / arm
    s = 1.0 + q * q
    return math.atan(q), qd / s, (qdd * s - 2.0 * q * qd * qd) / (s * s)


def _envelope(t, tr, stop=None):
    """(r, dr/dt, d2r/dt2) of a paddle's envelope: the start-up ramp `_cosine_ramp` over `tr`, times, from the
    time `stop` on (None: never), the same ramp run backwards, 1 - r(t - stop), which brings it to rest."""
    r, dr, ddr = _cosine_ramp(t, tr)
    if stop is None:
        return r, dr, ddr
    q, dq, ddq = _cosine_ramp(t - stop, tr)
    s, ds, dds = 1.0 - q, -dq, -ddq
    return r * s, dr * s + r * ds, ddr * s + 2.0 * dr * ds + r * dds


class WavePaddle(NamedTuple):
    """What an active absorber (`shoal.active_absorption`) needs to know of a wave paddle (``wave_paddle()``).

    Attributes
    ----------
    kind : {"piston", "flap"}
    depth : float
        d [m] at the paddle.
    hinge : float or None
        A flap's hinge height l [m] above the bed; None for a piston.
    components : shoal.waves.WaveComponents
        The target's components: eta = sum a_n cos(omega_n t - k_n x + phi_n).
    paddle_amplitudes : numpy.ndarray
        b_n = a_n / (H/S)_n [m]: X(t) = sum b_n sin(omega_n t + phi_n) at the still-water level.
    period : float
        The characteristic period T_c [s]: the wave's, or the spectrum's peak period.
    ramp_end : float
        The end of the start-up ramp [s].
    direction : numpy.ndarray
        The unit horizontal vector e the paddle pushes along.
    """

    kind: str
    depth: float
    hinge: float | None
    components: WaveComponents
    paddle_amplitudes: np.ndarray
    period: float
    ramp_end: float
    direction: np.ndarray


def _with_second_order(x, r, dr, ddr, second, t):
    """(X, X', X'') of a first-order excursion `x` = (X1, X1', X1'') plus a second-order correction `second`
    (`shoal.waves.SecondOrderPaddle`, None: none) ramped by r(t)^2: the correction scales with the square of the
    amplitude, so the ramp that brings the first order up brings it up squared, r^2 X2, with the derivatives
    2 r r' X2 + r^2 X2' and (2 r'^2 + 2 r r'') X2 + 4 r r' X2' + r^2 X2''."""
    if second is None or r == 0.0:
        return x
    t = max(t, 0.0)
    x2 = float(second.displacement(t))
    v2 = float(second.velocity(t))
    a2 = float(second.acceleration(t))
    return (x[0] + r * r * x2, x[1] + 2.0 * r * dr * x2 + r * r * v2,
            x[2] + (2.0 * dr * dr + 2.0 * r * ddr) * x2 + 4.0 * r * dr * v2 + r * r * a2)


def _regular_components(height, period, depth, k):
    """One component: eta = (H / 2) cos(omega t - k x), the elevation of X(t) = (S / 2) sin(omega t)."""
    one = np.ones(1)
    return WaveComponents(one / period, one * (0.5 * height), np.zeros(1), one * k, float(depth), 1.0 / period)


class WavePaddleMixin:
    """The surface excursion and the rigid motion with a shifted excursion, shared by the wave paddles
    (`PistonWavemaker`, `FlapWavemaker`, `SpectralPaddle`): each defines ``excursion(t)``, ``envelope(t)``,
    ``wave_paddle()``, ``is_flap``, a piston ``_unit()`` (its axis) and a flap ``arm``, ``rotation_axis`` and
    ``rotation_pivot``."""

    def offset_kinematics(self, t, dx, du, da, acceleration=True):
        """The rigid motion at time t [s] with the face's excursion at the still-water level shifted by dx
        [m], moving at du [m/s] and accelerating at da [m/s^2] more than the target (an active absorber's
        correction): a piston translates by (X + dx) e; a flap turns by atan((X + dx) / L) about its hinge."""
        if not self.is_flap:
            base = self.rigid_kinematics(t, acceleration)
            e = self._unit()
            return _translation(base.displacement + dx * e, base.velocity + du * e,
                                base.acceleration + (da * e if acceleration else 0.0))
        x, xd, xdd = self.excursion(t)
        theta, w, al = _flap_angle(x + dx, xd + du, xdd + da, self.arm)
        a = self.rotation_axis
        return RigidKinematics(np.zeros(3), np.zeros(3), np.zeros(3), rotation_matrix(a, theta), w * a,
                               (al if acceleration else 0.0) * a, self.rotation_pivot, True)


class RegularPaddleMixin(WavePaddleMixin):
    """The regular paddles' (`PistonWavemaker`, `FlapWavemaker`) envelope, second-order correction and
    excursion X(t) = r(t) (S/2) sin(omega t) (+ r(t)^2 X2(t)), from their `height`, `period`, `depth`,
    `ramp_periods`, `duration`, `order` and `stroke` (a flap's also `hinge`)."""

    def envelope(self, t):
        """r(t): the start-up ramp, and the stop after `duration`."""
        return _envelope(t, self.ramp_periods * self.period, self.duration)[0]

    def second_order(self):
        """The second-order correction X2 of the face's excursion at the still-water level
        (`shoal.waves.regular_second_order`, Schäffer 1996: the displacement at twice the frequency that
        cancels the free second harmonic; a flap's for its `hinge`), or None for ``order = 1``; computed once
        for the wave it belongs to."""
        if self.order == 1:
            return None
        hinge = self.hinge if self.is_flap else 0.0
        key = (self.height, self.period, self.depth, hinge)
        if self._second is None or self._second[0] != key:
            kind = "flap" if self.is_flap else "piston"
            self._second = (key, regular_second_order(self.height, self.period, self.depth, kind, hinge))
        return self._second[1]

    def excursion(self, t):
        """(X, X', X'') at time t [s]: the face's excursion along `direction` at the still-water level [m] (a
        piston's displacement) and its derivatives (with ``order = 2``, the second-order correction
        r(t)^2 X2(t) added)."""
        w = 2.0 * math.pi / self.period
        r, dr, ddr = _envelope(t, self.ramp_periods * self.period, self.duration)
        ts = max(t, 0.0)
        a = 0.5 * self.stroke
        s, c = math.sin(w * ts), math.cos(w * ts)
        x = (r * a * s, a * (dr * s + r * w * c), a * (ddr * s + 2.0 * dr * w * c - r * w * w * s))
        return _with_second_order(x, r, dr, ddr, self.second_order(), t)


def _hinge_axis(direction):
    """The unit axis z x e of a flap pushing along the horizontal `direction` e: a positive angle about it swings
    the flap's top along +e. Raises ValueError for a direction that is not horizontal."""
    e = np.asarray(direction, float)
    if not (e[2] == 0.0 and math.hypot(e[0], e[1]) > 0):
        raise ValueError(f"direction = {[float(v) for v in direction]}: a flap pushes along a horizontal direction "
                         "(its hinge is horizontal, normal to it); give a direction with z = 0, e.g. [1, 0, 0]")
    a = np.array([-e[1], e[0], 0.0])
    return a / np.linalg.norm(a)


class Motion(Spec):
    """Base of motions: `name` is what solids refer to."""

    name: Annotated[str, Field(min_length=1)]

    def kinematics(self, t):
        """(displacement [m], velocity [m/s]) at time t [s], 3-vectors: the translation (of the pivot, for a
        motion that rotates too, `rigid_kinematics`)."""
        raise NotImplementedError

    @property
    def rotation_axis(self):
        """The unit axis (3-vector) of a motion that rotates about a fixed axis; None for one that only
        translates."""
        return None

    def rigid_kinematics(self, t, acceleration=True):
        """The rigid motion at time t [s] (`RigidKinematics`); for a motion that only translates,
        `kinematics` with R = I, and `acceleration` (else zero) when `acceleration` is true."""
        d, v = self.kinematics(t)
        return _translation(d, v, self.acceleration(t) if acceleration else np.zeros(3))

    def point_kinematics(self, points, t):
        """(x [m], u [m/s], a [m/s^2]), each (N, 3), at time t [s] of the body points that were at `points`
        ((N, 3) world coordinates [m]) at t = 0 (`RigidKinematics.points`)."""
        return self.rigid_kinematics(t).points(points)

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


class PistonWavemaker(RegularPaddleMixin, Motion):
    """A piston paddle making regular waves of `height` H [m] and `period` T
    [s] in water of `depth` d [m].

    Stroke S = H / (H/S) with Biesel's transfer function
    (`piston_height_to_stroke`), and paddle displacement along `direction`
    X(t) = r(t) (S/2) sin(omega t), with the start-up ramp
    r(t) = (1 - cos(pi t / t_r)) / 2 for t < t_r = `ramp_periods` T. With a
    `duration` t_s [s] the paddle stops: from t_s the envelope r(t) is
    multiplied by the same ramp run backwards, 1 - r(t - t_s), so that it
    is at rest from t_s + t_r on. `absorption` adds active absorption
    (`shoal.active_absorption`): the paddle then also cancels the waves
    that come back to it, and goes on doing so once it has stopped making
    its own.
    """

    type: Literal["piston"] = "piston"
    height: PositiveReal
    period: PositiveReal
    depth: PositiveReal
    direction: Vec3 = (1.0, 0.0, 0.0)
    ramp_periods: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 2.0
    duration: Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)] | None = None
    absorption: ActiveAbsorption | None = None
    order: Literal[1, 2] = 1
    _second: tuple | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse a period without a finite wavelength, and a height above the breaking limit of Miche (1944),
        H_max = 0.142 L tanh(k d): no regular wave that high exists in that depth."""
        k = regular_wavenumber(self.height, self.period, self.depth)
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
        if self.duration is None:
            if tr <= 0 or t >= tr:
                return 1.0, 0.0
            if t <= 0:
                return 0.0, 0.0
            return 0.5 * (1 - math.cos(math.pi * t / tr)), 0.5 * math.pi / tr * math.sin(math.pi * t / tr)
        return _envelope(t, tr, self.duration)[:2]

    def _unit(self):
        d = np.asarray(self.direction, float)
        return d / np.linalg.norm(d)

    @property
    def is_flap(self):
        return False

    def wave_paddle(self):
        """The paddle as an active absorber sees it (`WavePaddle`)."""
        k = self.wavenumber
        return WavePaddle("piston", float(self.depth), None, _regular_components(self.height, self.period,
                                                                                 self.depth, k),
                          np.array([0.5 * self.stroke]), float(self.period), self.ramp_periods * self.period,
                          self._unit())

    def _speed_times(self, t_end):
        """The ramp and two periods after it: the motion is periodic from then on."""
        return np.linspace(0.0, min(t_end, (self.ramp_periods + 2.0) * self.period), _SAMPLES)

    def kinematics(self, t):
        if self.order == 2:
            x, u, _ = self.excursion(t)
            e = self._unit()
            return e * x, e * u
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


class RotatingMotion(Motion):
    """Base of the motions that rotate a body about a fixed axis through a fixed pivot: R(t) the rotation by
    the angle theta(t) about `rotation_axis` (`rotation_matrix`), omega = theta' a, alpha = theta'' a; the
    pivot does not move (d = v = a_d = 0). Each kind gives `angle`, the axis and the pivot."""

    @property
    def rotation_pivot(self):
        """c [m], the point on the axis the rotation leaves in place (world coordinates)."""
        raise NotImplementedError

    def angle(self, t):
        """(theta [rad], dtheta/dt [rad/s], d2theta/dt2 [rad/s^2]) at time t [s]."""
        raise NotImplementedError

    @property
    def default_reach(self):
        """The distance from the axis [m] at which `peak_speed` measures the wall speed when not told."""
        return 0.0

    def kinematics(self, t):
        """(0, 0): the pivot does not move (the rotation: `rigid_kinematics`)."""
        return np.zeros(3), np.zeros(3)

    def acceleration(self, t, eps=1e-5):
        """Zero: the pivot does not move (the rotation's: `rigid_kinematics`)."""
        return np.zeros(3)

    def rigid_kinematics(self, t, acceleration=True):
        """The rotation by `angle` about the axis through the pivot (`RigidKinematics`); its angular
        acceleration is exact, whatever `acceleration` says (it costs nothing)."""
        theta, w, al = self.angle(t)
        a = np.asarray(self.rotation_axis, float)
        return RigidKinematics(np.zeros(3), np.zeros(3), np.zeros(3), rotation_matrix(a, theta), w * a, al * a,
                               np.array(self.rotation_pivot, float), True)

    def peak_speed(self, t_end, reach=None):
        """The largest wall speed |theta'| reach [m/s] over 0 <= t <= `t_end` [s] of a point `reach` [m] from
        the axis (default: `default_reach`), at the times `_speed_times` gives."""
        reach = self.default_reach if reach is None else float(reach)
        times = self._speed_times(float(t_end))
        return max((abs(self.angle(float(t))[1]) for t in times), default=0.0) * reach


class RotationMotion(RotatingMotion):
    """A sinusoidal rotation about the fixed `axis` through `pivot` (DualSPHysics's ``mvrotsinu``):

        theta(t) = r(t) A [sin(omega t + phi) - sin(phi)],   omega = 2 pi / T,

    A = `amplitude` [rad], T = `period` [s], phi = `phase` [rad], positive about `axis` by the right-hand rule,
    r(t) = (1 - cos(pi t / t_r)) / 2 the start-up ramp for t < t_r = `ramp_periods` T (1 after; none by
    default). The case's geometry is the body at t = 0, at the phase phi of its swing (theta(0) = 0).
    """

    type: Literal["rotation"] = "rotation"
    amplitude: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]
    period: PositiveReal
    axis: Vec3 = (0.0, 1.0, 0.0)
    pivot: Vec3 = (0.0, 0.0, 0.0)
    phase: Annotated[float, Field(allow_inf_nan=False, strict=True)] = 0.0
    ramp_periods: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0

    @model_validator(mode="after")
    def _a_rotation(self):
        """Refuse a zero axis, and a swing whose angular speed A omega is not finite."""
        if not np.linalg.norm(np.asarray(self.axis, float)) > 0:
            raise ValueError("axis = [0, 0, 0] is no axis; give the direction of the rotation axis, e.g. [0, 1, 0]")
        if not math.isfinite(self.amplitude * 2.0 * math.pi / self.period):
            raise ValueError(f"amplitude = {self.amplitude:g} rad over period = {self.period:g} s gives no finite "
                             "angular speed; give the amplitude in radians and the period in seconds")
        return self

    @property
    def rotation_axis(self):
        a = np.asarray(self.axis, float)
        return a / np.linalg.norm(a)

    @property
    def rotation_pivot(self):
        return np.asarray(self.pivot, float)

    def angle(self, t):
        """(theta, theta', theta'') at time t [s] (class docstring)."""
        w = 2.0 * math.pi / self.period
        r, dr, ddr = _cosine_ramp(t, self.ramp_periods * self.period)
        t = max(t, 0.0)
        amp = self.amplitude
        s, c = math.sin(w * t + self.phase), math.cos(w * t + self.phase)
        f = amp * (s - math.sin(self.phase))
        fd, fdd = amp * w * c, -amp * w * w * s
        return r * f, dr * f + r * fd, ddr * f + 2.0 * dr * fd + r * fdd

    def _speed_times(self, t_end):
        """The ramp and two periods after it: the motion is periodic from then on."""
        return np.linspace(0.0, min(t_end, (self.ramp_periods + 2.0) * self.period), _SAMPLES)


class FlapWavemaker(RegularPaddleMixin, RotatingMotion):
    """A flap paddle making regular waves of `height` H [m] and `period` T [s] in water of `depth` d [m],
    hinged `hinge` l [m] above the bed (0: on the bed; negative: below it, through a slot), rotating about the
    horizontal hinge line through `pivot` (default (0, 0, l): the bed at z = 0), normal to `direction` e.

    Stroke S = H / (H/S) with the flap's transfer function (`shoal.waves.flap_height_to_stroke`, Biesel &
    Suquet 1951), S the horizontal excursion of the flap's face at the still-water level, peak to peak. The
    face crosses that level, the arm L = d - l above the hinge, at

        X(t) = r(t) (S/2) sin(omega t),   theta(t) = atan(X(t) / L),

    r(t) = (1 - cos(pi t / t_r)) / 2 for t < t_r = `ramp_periods` T the start-up ramp, so the flap swings
    theta_0 = atan(S / (2 L)) either side of vertical (S = 2 L tan theta_0) and its top first moves along e.
    The excursion at the surface is sinusoidal, as the piston's (and for small theta_0, theta(t) ~ r(t)
    theta_0 sin(omega t)); the same sum of components drives an irregular flap (`IrregularWaves`).
    `duration` and `absorption` as `PistonWavemaker`'s.
    """

    type: Literal["flap"] = "flap"
    height: PositiveReal
    period: PositiveReal
    depth: PositiveReal
    hinge: Annotated[float, Field(allow_inf_nan=False, strict=True)] = 0.0
    pivot: Vec3 | None = None
    direction: Vec3 = (1.0, 0.0, 0.0)
    ramp_periods: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 2.0
    duration: Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)] | None = None
    absorption: ActiveAbsorption | None = None
    order: Literal[1, 2] = 1
    _second: tuple | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse a hinge at or above the still-water level, a direction that is not horizontal, a period without
        a finite wavelength, a height above the breaking limit of Miche (1944), H_max = 0.142 L tanh(k d), and
        a swing beyond `MAX_FLAP_ANGLE`."""
        if not self.hinge < self.depth:
            raise ValueError(f"hinge = {self.hinge:g} m is not below the still-water level d = {self.depth:g} m: a "
                             "flap hinged there moves no water; give hinge < depth (0: hinged at the bed)")
        _hinge_axis(self.direction)
        k = regular_wavenumber(self.height, self.period, self.depth)
        ratio = flap_height_to_stroke(k, self.depth, self.hinge)
        stroke = self.height / ratio if ratio > 0 else math.inf
        arm = self.depth - self.hinge
        theta = math.atan(0.5 * stroke / arm) if math.isfinite(stroke) else 0.5 * math.pi
        if not theta <= MAX_FLAP_ANGLE:
            raise ValueError(f"height = {self.height:g} m at period = {self.period:g} s needs a flap stroke of "
                             f"{stroke:.3g} m at the surface, a swing of {math.degrees(theta):.3g} degrees either "
                             f"side of vertical (H/S = {ratio:.3g}, hinge {arm:.3g} m below the surface), more than "
                             f"{math.degrees(MAX_FLAP_ANGLE):g}: give a lower height or a shorter period (a piston "
                             "needs half the stroke for long waves)")
        return self

    @property
    def wavenumber(self):
        return wavenumber(self.period, self.depth)

    @property
    def stroke(self):
        """Full stroke S [m] of the flap's face at the still-water level."""
        return self.height / flap_height_to_stroke(self.wavenumber, self.depth, self.hinge)

    @property
    def arm(self):
        """L = d - l [m]: from the hinge up to the still-water level."""
        return self.depth - self.hinge

    @property
    def angle_amplitude(self):
        """theta_0 = atan(S / (2 L)) [rad], the flap's largest angle from vertical."""
        return math.atan(0.5 * self.stroke / self.arm)

    @property
    def rotation_axis(self):
        return _hinge_axis(self.direction)

    @property
    def rotation_pivot(self):
        return np.array(self.pivot if self.pivot is not None else (0.0, 0.0, self.hinge), float)

    @property
    def default_reach(self):
        """L: the wall speed `peak_speed` gives is the face's at the still-water level."""
        return self.arm

    @property
    def is_flap(self):
        return True

    def angle(self, t):
        """(theta, theta', theta'') at time t [s] from the face's excursion X(t) at the surface (class
        docstring)."""
        return _flap_angle(*self.excursion(t), self.arm)

    def wave_paddle(self):
        """The paddle as an active absorber sees it (`WavePaddle`)."""
        e = np.asarray(self.direction, float)
        return WavePaddle("flap", float(self.depth), float(self.hinge),
                          _regular_components(self.height, self.period, self.depth, self.wavenumber),
                          np.array([0.5 * self.stroke]), float(self.period), self.ramp_periods * self.period,
                          e / np.linalg.norm(e))

    def _speed_times(self, t_end):
        """The ramp and two periods after it: the motion is periodic from then on."""
        return np.linspace(0.0, min(t_end, (self.ramp_periods + 2.0) * self.period), _SAMPLES)


MAX_COMPONENTS = 32768
"""Most wave components a spectral paddle may have (its kinematics sum them at every call)."""

MAX_HARMONIC = 1 << 16
"""Largest f_n / df of a spectral paddle's components: its signal is sampled 20 times per period of that
harmonic over a repeat period (`SpectralPaddle.peak_speed`)."""

_SAMPLES_PER_PERIOD = 20
"""Samples per period of a spectral paddle's fastest component where its peak speed is sought."""


class SpectralPaddle(WavePaddleMixin, Motion):
    """Base of the paddles driven by a sum of wave components (`IrregularWaves`, `FocusedWaves`): a piston, or
    a flap (``paddle = "flap"``).

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

    A flap (``paddle = "flap"``) hinged `hinge` l [m] above the bed, about the horizontal line through `pivot`
    (default (0, 0, l)) normal to `direction`, takes T_n = H/S of a flap at k_n d hinged at l
    (`shoal.waves.flap_height_to_stroke`, the stroke measured at the still-water level): X(t) above, the sum
    of the components' excursions (linear superposition, small angles), is the horizontal excursion of the
    flap's face at the still-water level, the arm L = d - l above the hinge, and the flap's angle is
    theta(t) = atan(X(t) / L) (`FlapWavemaker` for one component). `max_displacement` is then the largest
    excursion at the surface.
    """

    spectrum: AnySpectrum
    depth: PositiveReal
    components: Annotated[int, Field(ge=1, le=MAX_COMPONENTS, strict=True)] = 256
    f_min: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.5
    f_max: Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)] = 3.0
    ramp_time: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] | None = None
    direction: Vec3 = (1.0, 0.0, 0.0)
    paddle: str = "piston"
    hinge: Annotated[float, Field(allow_inf_nan=False, strict=True)] = 0.0
    pivot: Vec3 | None = None
    absorption: ActiveAbsorption | None = None
    order: Literal[1, 2] = 1
    _waves: object = PrivateAttr(default=None)
    _second: tuple | None = PrivateAttr(default=None)
    _grid: tuple | None = PrivateAttr(default=None)
    _terms: tuple | None = PrivateAttr(default=None)

    @field_validator("paddle")
    @classmethod
    def _a_paddle(cls, v):
        if v not in ("piston", "flap"):
            raise ValueError(f"paddle = {v!r} is not a paddle type; allowed: 'piston', 'flap'")
        return v

    def _check_paddle(self):
        """Refuse a flap's keys on a piston, a flap hinged at or above the still-water level, and a flap pushing
        along a direction that is not horizontal."""
        if self.paddle == "piston":
            if self.hinge != 0.0 or self.pivot is not None:
                raise ValueError("hinge and pivot place a flap's hinge; paddle = 'piston' has none: give "
                                 "paddle = 'flap' or leave them out")
            return
        if not self.hinge < self.depth:
            raise ValueError(f"hinge = {self.hinge:g} m is not below the still-water level d = {self.depth:g} m: a "
                             "flap hinged there moves no water; give hinge < depth (0: hinged at the bed)")
        _hinge_axis(self.direction)

    def _make_components(self):
        raise NotImplementedError

    def _check_components(self):
        """Refuse what gives no finite paddle signal (an empty band, a zero axis, infinite wavenumbers or phases,
        a travel over 1000 depths), a band too narrow for its components, a ramp of zero. Returns the
        components."""
        self._check_paddle()
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
        if self.paddle == "flap":  # (sampled as `max_displacement` is; not kept: a case's motions compare equal)
            with np.errstate(all="ignore"):
                reach = float(np.max(np.abs(self._sample(waves, self._coefficients(waves))[1])))
            theta = math.atan(reach / self.arm)
            if not theta <= MAX_FLAP_ANGLE:
                raise ValueError(f"the components swing the flap up to {math.degrees(theta):.3g} degrees from "
                                 f"vertical (an excursion of {reach:.3g} m at the surface, the hinge {self.arm:.3g} "
                                 f"m below it), more than {math.degrees(MAX_FLAP_ANGLE):g}: give a lower Hs or "
                                 "amplitude, or raise f_min (long waves need the largest strokes)")
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

    def _coefficients(self, waves):
        """b_n = a_n / T_n [m]: the paddle amplitude of each component (a flap's: at the still-water level)."""
        if self.paddle == "flap":
            return waves.amplitudes / flap_height_to_stroke(waves.wavenumbers, waves.depth, self.hinge)
        return waves.amplitudes / piston_height_to_stroke(waves.wavenumbers, waves.depth)

    @property
    def arm(self):
        """A flap's L = d - l [m], from the hinge up to the still-water level."""
        return self.depth - self.hinge

    @property
    def rotation_axis(self):
        """A flap's hinge axis z x e (e: `direction`); None for a piston."""
        return _hinge_axis(self.direction) if self.paddle == "flap" else None

    @property
    def rotation_pivot(self):
        """A flap's hinge point [m]: `pivot`, default (0, 0, `hinge`)."""
        return np.array(self.pivot if self.pivot is not None else (0.0, 0.0, self.hinge), float)

    @property
    def default_reach(self):
        """A flap's L: `peak_speed` gives the face's speed at the still-water level."""
        return self.arm

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
        """(b_n, omega_n, phi_n, b_n omega_n, the unit axis, b_n omega_n^2), computed once."""
        if self._terms is None:
            w = self.wave_components
            b = self._coefficients(w)
            self._terms = (b, w.omegas, w.phases, b * w.omegas, self._unit(), b * w.omegas**2)
        return self._terms

    def kinematics(self, t):
        """(displacement [m], velocity [m/s]) at time t [s], 3-vectors along `direction`; a flap's hinge does
        not move: (0, 0) (its rotation: `rigid_kinematics`)."""
        if self.paddle == "flap":
            return np.zeros(3), np.zeros(3)
        if self.order == 2:
            x, u, _ = self.excursion(t)
            e = self._unit()
            return e * x, e * u
        b, omega, phi, bw, e, _ = self._signal()
        r, dr = self._ramp_factor(t)
        t = max(t, 0.0)
        arg = omega * t + phi
        s = float(np.dot(b, np.sin(arg)))
        c = float(np.dot(bw, np.cos(arg)))
        return e * (r * s), e * (dr * s + r * c)

    def acceleration(self, t, eps=1e-5):
        """A piston's acceleration (`Motion.acceleration`); a flap's hinge does not move: zero."""
        if self.paddle == "flap":
            return np.zeros(3)
        return super().acceleration(t, eps)

    @property
    def is_flap(self):
        return self.paddle == "flap"

    def envelope(self, t):
        """r(t): the start-up ramp."""
        return _cosine_ramp(t, self.ramp)[0]

    def second_order(self):
        """The second-order correction X2 of the components (`shoal.waves.second_order_paddle`, Schäffer 1996:
        the sub- and superharmonic paddle motion that cancels the spurious free waves), or None for
        ``order = 1``; computed once for the components it belongs to (its cost grows as N^2)."""
        if self.order == 1:
            return None
        w = self.wave_components
        if self._second is None or self._second[0] is not w:
            self._second = (w, second_order_paddle(w, self.paddle, self.hinge))
        return self._second[1]

    def excursion(self, t):
        """(X, X', X'') at time t [s]: the excursion along `direction` [m] (a flap's face at the still-water
        level) and its derivatives, X'' = r'' s + 2 r' s' + r s'' (with ``order = 2``, the second-order
        correction r(t)^2 X2(t) added)."""
        b, omega, phi, bw, _, bw2 = self._signal()
        r, dr, ddr = _cosine_ramp(t, self.ramp)
        ts = max(t, 0.0)
        arg = omega * ts + phi
        sin, cos = np.sin(arg), np.cos(arg)
        s = float(np.dot(b, sin))
        c = float(np.dot(bw, cos))
        a = -float(np.dot(bw2, sin))
        return _with_second_order((r * s, dr * s + r * c, ddr * s + 2.0 * dr * c + r * a), r, dr, ddr,
                                  self.second_order(), t)

    def angle(self, t):
        """A flap's (theta [rad], dtheta/dt [rad/s], d2theta/dt2 [rad/s^2]) at time t [s]: theta = atan(X / L)
        of the excursion X(t) at the surface (`excursion`)."""
        return _flap_angle(*self.excursion(t), self.arm)

    def wave_paddle(self):
        """The paddle as an active absorber sees it (`WavePaddle`)."""
        flap = self.paddle == "flap"
        return WavePaddle(self.paddle, float(self.depth), float(self.hinge) if flap else None,
                          self.wave_components, self._signal()[0], 1.0 / self.spectrum.peak_frequency, self.ramp,
                          self._unit())

    def rigid_kinematics(self, t, acceleration=True):
        """A piston's translation (`Motion.rigid_kinematics`); a flap's rotation by `angle` about its hinge."""
        if self.paddle != "flap":
            return super().rigid_kinematics(t, acceleration)
        theta, w, al = self.angle(t)
        a = self.rotation_axis
        return RigidKinematics(np.zeros(3), np.zeros(3), np.zeros(3), rotation_matrix(a, theta), w * a, al * a,
                               self.rotation_pivot, True)

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
            self._grid = self._sample(self.wave_components, self._signal()[0])
        return self._grid

    @staticmethod
    def _sample(w, b):
        """`_sampled` of the components `w` with the paddle amplitudes `b`."""
        n = np.rint(w.frequencies / w.df).astype(np.int64)
        m = 2 * int(math.ceil(_SAMPLES_PER_PERIOD / 2 * max(int(n.max()), 1)))
        out = []
        for coef, shift in ((b, -0.5 * math.pi), (b * w.omegas, 0.0)):  # sin(u) = cos(u - pi/2)
            spectrum = np.zeros(m // 2 + 1, complex)
            np.add.at(spectrum, n, 0.5 * m * coef * np.exp(1j * (w.phases + shift)))
            out.append(np.fft.irfft(spectrum, m))
        return w.repeat_period / m, out[0], out[1]

    def _speed_times(self, t_end):
        """Times t_j = j dt (`_sampled`: 20 or more a period of the fastest component) from 0 to the end of the
        ramp and one repeat period after it (the signal is periodic past the ramp), up to `t_end`."""
        dt, s, _ = self._sampled()
        last = min(float(t_end), self.ramp + self.repeat_period)
        if last < 0:
            return np.empty(0)
        return np.arange(int(math.floor(last / dt)) + 1) * dt

    def peak_speed(self, t_end, reach=None):
        """The largest speed [m/s] over 0 <= t <= `t_end` [s] at the times `_speed_times` gives and at the
        middle of the ramp: the ramp r(t) and its derivative times the sampled periodic signal, within about
        1 % (the sampling's). A flap's: |theta'| times `reach` [m] from the hinge (default `default_reach`,
        the still-water level), theta' = (X' / L) / (1 + (X / L)^2)."""
        if self.paddle == "flap":
            return self._flap_peak_speed(t_end, self.default_reach if reach is None else float(reach))
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

    def _flap_peak_speed(self, t_end, reach):
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
        q, qd = r * s[j] / self.arm, (dr * s[j] + r * c[j]) / self.arm
        peak = float(np.max(np.abs(qd / (1.0 + q * q))))
        if 0.0 < 0.5 * tr <= t_end:
            peak = max(peak, abs(self.angle(0.5 * tr)[1]))
        return peak * reach

    @property
    def max_displacement(self):
        """The largest |X(t)| [m] of the paddle over all times (the ramp only lessens it), sampled as
        `peak_speed` samples the velocity, plus the bound sum |c_p| of a second-order correction: leave this
        much room behind the paddle's rest position."""
        second = self.second_order()
        return float(np.max(np.abs(self._sampled()[1]))) + (second.max_displacement if second is not None else 0.0)


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
                            FocusedWaves, FlapWavemaker, RotationMotion], Field(discriminator="type")]


def check_motion_speeds(motions, c0, t_end, reach=None):
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
    reach : dict of str to float, optional
        For a motion that rotates, by its name: the largest distance [m] of its body from the axis
        (`shoal.Case.motion_reach`), where its wall is fastest; without it, the motion's `default_reach`
        (a flap's face at the still-water level).

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
        if m.rotation_axis is not None:
            u = m.peak_speed(t_end, (reach or {}).get(m.name))
        else:
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
