"""Relaxation zones: the fluid's velocity relaxed toward target wave kinematics, to make waves or absorb them.

A `RelaxationZone` (a case's ``[[relaxation]]`` table) is a strip along x from `start` (its inner end, toward
the region of interest) to `end` (its outer end, toward the boundary of the domain). A fluid particle a
fraction xi = (x - start) / (end - start) of the way in has the weight

    w(xi) = (exp(xi^3.5) - 1) / (e - 1),   0 <= xi <= 1 (w = 1 beyond `end`, no relaxation before `start`),

that is 1 - alpha_R(xi) of Jacobsen, Fuhrman & Fredsoe (2012, waves2Foam): alpha_R(chi) = 1 - (exp(chi^3.5) -
1) / (e - 1) is the weight they keep the computed solution with, 1 at the zone's inner end (chi = 0) and 0 at
its outer end (chi = 1); w is the weight of the target. It rises from 0 at the inner end with zero slope (and
a small one over most of the zone) and reaches 1 at the outer end.

Jacobsen et al. blend once per time step of their solver, phi <- (1 - w) phi + w phi_target, which ties the
strength of the zone to the step. Here the blend is made per time `time_scale` tau: over a step dt,

    u <- u + c (u_target - u),   c = 1 - (1 - w)^(dt / tau),

so the deviation from the target shrinks by the factor (1 - w) every tau whatever the step (two half steps
give exactly one step's c), the target is imposed where w = 1 (c = 1) and nothing changes where w = 0. It is
the exact solution over dt of du/dt = -lambda (u - u_target) with the rate lambda = -ln(1 - w) / tau held
over the step. The SPH relaxation zones of DualSPHysics (Altomare et al. 2018, "Improved relaxation zone
method in SPH-based model for coastal engineering applications", Applied Ocean Research 81) correct the
velocity with a factor proportional to dt for the same reason; this form is that factor's exact composition.

Targets (`target`):

* `StillTarget` (``type = "still"``): u = 0, an absorber (a smooth sponge whose target is rest);
* `LinearTarget` (``type = "linear"``): a regular Airy wave of `height`, `period` in `depth`, along +x or -x;
* `FentonTarget` (``type = "fenton"``): Fenton's stream-function wave of order N (Rienecker & Fenton 1981;
  Fenton 1988, 1999), and `StokesTarget` (``type = "stokes"``): Stokes' fifth-order wave (Fenton 1985), of
  `height`, `period` or `wavelength` in `depth`, along +x or -x, computed by raschii
  (`shoal.waves.nonlinear`) in the frame of a closed flume (zero mean mass flux);
* `MotionTarget` (``type = "motion"``): the components of an ``irregular`` or ``focused`` motion of the case
  (`shoal.motions.IrregularWaves`, `FocusedWaves`), the sea its paddle would make, without the paddle.

The velocity of N components of amplitudes a_n, angular frequencies omega_n, wavenumbers k_n and phases phi_n
in water of depth d travelling along s x (s = +1 or -1), z measured up from the still-water level, is linear
theory's (Dean & Dalrymple 1991, ch. 4)

    u = s r(t) sum_n a_n omega_n cosh(k_n (z + d)) / sinh(k_n d) cos(theta_n),
    w = -r(t) sum_n a_n omega_n sinh(k_n (z + d)) / sinh(k_n d) sin(theta_n),
    theta_n = omega_n t - s k_n (x - x_0) + phi_n,

with the elevation eta = r(t) sum_n a_n cos(theta_n) (so w = d eta / dt at z = 0), the ramp r(t) = (1 -
cos(pi t / t_r)) / 2 for t < t_r and 1 after, and x_0 the `origin`. Above the still-water level the velocity
is that at z = 0 (linear theory ends there; the crest's fluid gets the surface's velocity), and z is clipped
to the bed below. The hyperbolic ratios are evaluated as (e^{k z} +- e^{-k (z + 2d)}) / (1 - e^{-2kd}), which
does not overflow in deep water.

The nonlinear targets are series of the same form (`shoal.waves.nonlinear`): harmonic j = 1..N of the wave of
wavenumber k and angular frequency omega is a component of wavenumber j k, angular frequency j omega and phase
j phi, whose velocity at the still-water level has the amplitude U_j (the j-th Fourier coefficient of u there),

    u = s r(t) [u_E + sum_j U_j cosh(j k (z + d)) / cosh(j k d) cos(theta_j)],
    w = -r(t) sum_j U_j sinh(j k (z + d)) / cosh(j k d) sin(theta_j),
    theta_j = j (omega t - s k (x - x_0) + phi),

with the uniform current u_E = Q / d - B_0 of the closed flume's frame (the return flow that cancels the
wave's Stokes transport; `shoal.waves.nonlinear` says why that frame) as one more component, of wavenumber
and frequency 0 (cosh(0) / cosh(0) = 1, sin(0) = 0), and the elevation eta = r(t) sum_j a_j cos(theta_j).
The series hold up to the wave's own surface, which at a crest lies above the still-water level, so z is
clipped to the bed below and to the target's crest level eta_c above (not to the still-water level): below
the target's surface the target is the theory's wave exactly, a crest's fluid included; a particle that the
SPH surface holds above the target's gets the series continued as they stand up to the crest level, and
their value there above it. Linear theory is the case U_n = a_n omega_n coth(k_n d), u_E = 0, clipped at
the still-water level.

Only the velocity is relaxed, not the density (the "level"): in weakly compressible SPH the free surface is
where the particles are, and a density set to the hydrostatic pressure of a target elevation would push the
particles to it through a pressure jump rather than place them there; relaxing the velocity, w included,
moves the fluid to the target elevation by continuity, as the zone's volume flux follows the target's.

`RelaxationTerms` is a zone resolved against its case (the components, the still-water level): its `fill`
writes the per-component terms of a time into a preallocated array, which the compiled per-particle function
(`shoal.physics.relaxation`) reads on either backend. The function measures z from the zone's clipping
ceiling (`RelaxationTerms.level`: the still-water level, or the crest of a nonlinear target) and clips it to
[-D, 0], D (`RelaxationTerms.depth`) the ceiling's height above the bed; the hyperbolic ratios of either
kind of target are its (e^{k z} +- e^{-k (z + 2D)}) times a per-component scale (`RelaxationTerms` gives
it), so the one function serves every target.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, model_validator

from .geometry.shapes import PositiveReal, Real, Spec
from .waves.dispersion import regular_wavenumber, wavenumber
from .waves.nonlinear import MAX_ORDER, nonlinear_wave

TERM_COLUMNS = 4
"""Columns of the per-component terms `RelaxationTerms.fill` writes: k_n, omega_n t + phi_n (mod 2 pi),
s r S_n, -r S_n, with the scale S_n = a_n omega_n / (1 - exp(-2 k_n d)) of a linear component and
U_n exp(k_n (D - d)) / (1 + exp(-2 k_n d)) of a nonlinear target's (`RelaxationTerms`)."""

SPECTRAL_MOTIONS = ("irregular", "focused")
"""The motion types whose components a `MotionTarget` can take."""


def relaxation_weight(xi):
    """The target's weight w(xi) = (exp(xi^3.5) - 1) / (e - 1) at the fractions `xi` of the way into a zone.

    1 - alpha_R of Jacobsen, Fuhrman & Fredsoe (2012); xi is clipped to [0, 1] (w = 0 before the zone's inner
    end, 1 beyond its outer end).

    Parameters
    ----------
    xi : array_like
        (x - start) / (end - start).

    Returns
    -------
    numpy.ndarray or float
    """
    xi = np.clip(np.asarray(xi, float), 0.0, 1.0)
    w = np.where(xi >= 1.0, 1.0, np.expm1(xi**3.5) / (math.e - 1.0))
    return float(w) if w.ndim == 0 else w


def step_coefficient(w, dt, time_scale):
    """The fraction c = 1 - (1 - w)^(dt / tau) of the deviation from the target removed over a step `dt` [s]
    at the weight `w`, tau = `time_scale` [s] (see the module docstring)."""
    return 1.0 - np.power(1.0 - np.asarray(w, float), dt / time_scale)


def ramp_factor(t, ramp_time):
    """r(t) = (1 - cos(pi t / t_r)) / 2 for 0 < t < t_r, 0 before, 1 after (the paddles' start-up ramp)."""
    if ramp_time <= 0 or t >= ramp_time:
        return 1.0
    if t <= 0:
        return 0.0
    return 0.5 * (1.0 - math.cos(math.pi * t / ramp_time))


class StillTarget(Spec):
    """Rest: u = 0 (a smooth absorber)."""

    type: Literal["still"] = "still"


class LinearTarget(Spec):
    """A regular linear (Airy) wave of `height` H [m] and `period` T [s] in `depth` d [m], travelling along
    `direction` ("+x" or "-x"), with elevation eta = (H/2) cos(omega t - s k (x - origin) + phase)."""

    type: Literal["linear"] = "linear"
    height: PositiveReal
    period: PositiveReal
    depth: PositiveReal
    direction: Literal["+x", "-x"] = "+x"
    phase: Real = 0.0
    origin: Real = 0.0

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse a period without a finite wavelength, and a height above Miche's (1944) breaking limit."""
        regular_wavenumber(self.height, self.period, self.depth)
        return self


class NonlinearTarget(Spec):
    """Base of the nonlinear regular-wave targets (`FentonTarget`, `StokesTarget`): a wave of `height` H [m]
    and `period` T [s] (in the laboratory) or `wavelength` L [m] (one of the two) in `depth` d [m], travelling
    along `direction` ("+x" or "-x"), its crest at x = `origin` [m] at t = -`phase` / omega, in the closed
    flume's frame (zero mean mass flux; `shoal.waves.nonlinear`)."""

    height: PositiveReal
    period: PositiveReal | None = None
    wavelength: PositiveReal | None = None
    depth: PositiveReal
    direction: Literal["+x", "-x"] = "+x"
    phase: Real = 0.0
    origin: Real = 0.0

    @model_validator(mode="after")
    def _a_wave_that_exists(self):
        """Refuse neither or both of period and wavelength, a height past the breaking limit, a solution that
        does not converge (`shoal.waves.nonlinear.nonlinear_wave`)."""
        self.wave  # noqa: B018  (solved once and cached)
        return self

    @property
    def wave(self):
        """The solved wave (`shoal.waves.nonlinear.NonlinearWave`, cached)."""
        return nonlinear_wave(getattr(self, "type", None), self.height, self.depth, period=self.period,
                              wavelength=self.wavelength, order=getattr(self, "order", None))


class FentonTarget(NonlinearTarget):
    """Fenton's stream-function wave of `order` N (Rienecker & Fenton 1981; Fenton 1988, 1999), by raschii:
    N Fourier harmonics solving the full nonlinear free-surface conditions, valid from deep to shallow water
    and up to near breaking (N = 10 suffices for most waves; steeper ones want 20 or more). The other keys
    are `NonlinearTarget`'s."""

    type: Literal["fenton"] = "fenton"
    order: Annotated[int, Field(ge=1, le=MAX_ORDER["fenton"], strict=True)] = 10


class StokesTarget(NonlinearTarget):
    """Stokes' fifth-order wave (Fenton 1985), by raschii: an expansion in the steepness k H / 2, good in deep
    and intermediate water (shallow water, where its profile gets a second crest in the trough, is refused:
    use `FentonTarget`). `order` 1 to 5 (default 5) truncates the expansion. The other keys are
    `NonlinearTarget`'s."""

    type: Literal["stokes"] = "stokes"
    order: Annotated[int, Field(ge=1, le=MAX_ORDER["stokes"], strict=True)] = 5


class MotionTarget(Spec):
    """The sea of the ``irregular`` or ``focused`` motion named `motion`: its components'
    eta(x, t) = sum_n a_n cos(omega_n t - k_n (x - origin) + phi_n) along the motion's direction (the sign of
    its x component), `origin` [m] standing for the paddle's rest position."""

    type: Literal["motion"] = "motion"
    motion: Annotated[str, Field(min_length=1)]
    origin: Real = 0.0


AnyTarget = Annotated[Union[StillTarget, LinearTarget, FentonTarget, StokesTarget, MotionTarget],
                      Field(discriminator="type")]


class RelaxationZone(Spec):
    """A relaxation zone along x (see the module docstring): the target's weight is 0 at x = `start` (the
    inner end) and 1 at x = `end` (the outer end, at the domain's boundary) and beyond.

    Parameters
    ----------
    start, end : float
        x [m] of the inner and outer ends; `end` may lie on either side of `start`.
    target : StillTarget, LinearTarget, FentonTarget, StokesTarget or MotionTarget
        What the velocity is relaxed toward (default: still water).
    time_scale : float
        tau [s]: the deviation from the target shrinks by (1 - w) every tau (default 1 ms).
    ramp_time : float, optional
        t_r [s] of the target's start-up ramp; default: two periods (linear, fenton, stokes), the motion's
        ramp (motion).
    level : float, optional
        Still-water level [m] that z is measured from; default: the case's ``fluid.surface_level``.
    """

    start: Real
    end: Real
    target: AnyTarget = StillTarget()
    time_scale: PositiveReal = 1e-3
    ramp_time: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] | None = None
    level: Real | None = None

    @model_validator(mode="after")
    def _length(self):
        if not abs(self.end - self.start) > 0:
            raise ValueError(f"start = end = {self.start:g} m: the zone has zero length (give its inner end as "
                             "start and its outer end, at the boundary, as end)")
        return self

    @property
    def lo(self):
        return min(self.start, self.end)

    @property
    def hi(self):
        return max(self.start, self.end)

    def describe(self):
        """A one-line description (``shoal check``)."""
        t = self.target
        if isinstance(t, LinearTarget):
            what = (f"linear wave H = {t.height:g} m, T = {t.period:g} s, d = {t.depth:g} m, along {t.direction}")
        elif isinstance(t, NonlinearTarget):
            wave = t.wave
            what = (f"{'Fenton stream-function' if t.type == 'fenton' else 'Stokes'} wave of order {t.order}, "
                    f"H = {t.height:g} m, T = {wave.period:.4g} s, L = {wave.wavelength:.4g} m, d = {t.depth:g} m, "
                    f"along {t.direction} (crest {wave.crest:.3g} m, return current {wave.current:.3g} m/s)")
        elif isinstance(t, MotionTarget):
            what = f"the sea of motion {t.motion!r}"
        else:
            what = "still water (absorber)"
        return (f"x = {self.start:g} .. {self.end:g} m (w = 1 at {self.end:g} m), {what}, "
                f"time scale {self.time_scale:g} s")


class RelaxationTerms:
    """A relaxation zone resolved against its case: its geometry and the target's components.

    Parameters
    ----------
    zone : RelaxationZone
    amplitudes, omegas, wavenumbers, phases : array_like
        a_n [m], omega_n [rad/s], k_n [1/m], phi_n [rad] of the target's elevation (empty for still water).
    depth : float
        d [m] (any positive number for still water).
    level : float
        The still-water level [m].
    sign : float
        +1 (travelling along +x) or -1.
    origin : float
        x_0 [m].
    ramp_time : float
        t_r [s] (0: none).
    velocities : array_like, optional
        U_n [m/s], the amplitudes of the components' u at the still-water level: u = s r sum U_n
        cosh(k_n (z + d)) / cosh(k_n d) cos(theta_n), w = -r sum U_n sinh(k_n (z + d)) / cosh(k_n d)
        sin(theta_n) (a component of k_n = 0 is a uniform current). Default: linear theory's a_n omega_n
        coth(k_n d).
    ceiling : float
        eta_c [m]: z is clipped to eta_c above the still-water level (0: linear theory's still-water level;
        a nonlinear target's crest).

    Attributes
    ----------
    level, depth : float
        What the compiled function reads: the clipping ceiling [m] (still-water level + eta_c) and its height
        D = d + eta_c [m] above the bed.
    still_level, water_depth : float
        The still-water level and d [m].
    """

    def __init__(self, zone, amplitudes=(), omegas=(), wavenumbers=(), phases=(), depth=1.0, level=0.0, sign=1.0,
                 origin=0.0, ramp_time=0.0, velocities=None, ceiling=0.0):
        self.zone = zone
        self.start = float(zone.start)
        self.inv_len = 1.0 / (float(zone.end) - float(zone.start))
        self.time_scale = float(zone.time_scale)
        self.a = np.asarray(amplitudes, float).ravel()
        self.omega = np.asarray(omegas, float).ravel()
        self.k = np.asarray(wavenumbers, float).ravel()
        self.phi = np.asarray(phases, float).ravel()
        self.water_depth = float(depth)
        self.still_level = float(level)
        self.ceiling = float(ceiling)
        self.depth = self.water_depth + self.ceiling
        self.level = self.still_level + self.ceiling
        self.sign = 1.0 if sign >= 0 else -1.0
        self.origin = float(origin)
        self.ramp_time = float(ramp_time)
        if velocities is None:
            # a_n omega_n / (1 - exp(-2 k_n d)): cosh(k (z + d)) / sinh(k d) = (e^{kz} + e^{-k(z+2d)}) / (1 - e^{-2kd})
            self._scale = self.a * self.omega / -np.expm1(-2.0 * self.k * self.water_depth)
        else:
            # U_n cosh(k z_b) / cosh(k d) = U_n exp(k (D - d)) / (1 + exp(-2 k d)) (e^{kz'} + e^{-k(z'+2D)}), with
            # z_b = z' + D the height above the bed and z' measured from the ceiling (1/2 (1 + 1) = 1 at k = 0)
            u = np.asarray(velocities, float).ravel()
            self._scale = u * np.exp(self.k * self.ceiling) / (1.0 + np.exp(-2.0 * self.k * self.water_depth))
        self.count = len(self.a)

    def buffer(self):
        """A zeroed (max(N, 1), `TERM_COLUMNS`) float64 array for `fill` (one row for still water, unread)."""
        return np.zeros((max(self.count, 1), TERM_COLUMNS))

    def fill(self, t, out):
        """Write the terms of time `t` [s] into `out` (from `buffer`) in place: k_n, omega_n t + phi_n reduced
        to [0, 2 pi), s r S_n and -r S_n (the scales S_n of `TERM_COLUMNS`)."""
        n = self.count
        if n == 0:
            return out
        r = ramp_factor(t, self.ramp_time)
        out[:n, 0] = self.k
        col = out[:n, 1]
        np.multiply(self.omega, t, out=col)
        np.add(col, self.phi, out=col)
        np.remainder(col, 2.0 * math.pi, out=col)
        np.multiply(self._scale, self.sign * r, out=out[:n, 2])
        np.multiply(self._scale, -r, out=out[:n, 3])
        return out

    def _theta(self, x, t):
        return self.omega * t - self.sign * self.k * (x - self.origin) + self.phi

    def elevation(self, x, t):
        """The target elevation eta [m] at `x` [m] (scalar) and time `t` [s] (scalar), ramp included."""
        if self.count == 0:
            return 0.0
        return ramp_factor(t, self.ramp_time) * float(np.sum(self.a * np.cos(self._theta(float(x), float(t)))))

    def velocity(self, x, z, t):
        """The target velocity (u, w) [m/s] at `x`, `z` [m] (scalars: z absolute, clipped to the ceiling -- the
        still-water level, or a nonlinear target's crest -- and the bed) and time `t` [s], ramp included (the
        host-side reference of the compiled per-particle function)."""
        if self.count == 0:
            return 0.0, 0.0
        zr = min(max(float(z) - self.level, -self.depth), 0.0)
        e1 = np.exp(self.k * zr)
        e2 = np.exp(-self.k * (zr + 2.0 * self.depth))
        th = self._theta(float(x), float(t))
        r = ramp_factor(t, self.ramp_time)
        u = self.sign * r * float(np.sum(self._scale * (e1 + e2) * np.cos(th)))
        w = -r * float(np.sum(self._scale * (e1 - e2) * np.sin(th)))
        return u, w


def nonlinear_terms(zone, target, level):
    """The `RelaxationTerms` of `zone` with the nonlinear `target` (`FentonTarget`, `StokesTarget`) about the
    still-water level `level` [m]: harmonic j = 1..N of the wave (`shoal.waves.nonlinear.NonlinearWave`) as the
    component of wavenumber j k, angular frequency j omega, phase j phi, elevation amplitude a_j and velocity
    amplitude U_j, the closed flume's current u_E as a component of wavenumber and frequency 0, and z clipped
    to the crest (see the module docstring). Default ramp: two periods."""
    wave = target.wave
    j = np.arange(1, wave.order + 1, dtype=float)
    ramp = zone.ramp_time if zone.ramp_time is not None else 2.0 * wave.period
    return RelaxationTerms(zone, np.append(wave.amplitudes, 0.0), np.append(j * wave.omega, 0.0),
                           np.append(j * wave.wavenumber, 0.0), np.append(j * target.phase, 0.0), wave.depth, level,
                           1.0 if target.direction == "+x" else -1.0, target.origin, ramp,
                           velocities=np.append(wave.velocities, wave.current), ceiling=max(wave.crest, 0.0))


def resolve_zone(zone, motions=(), surface_level=None):
    """The `RelaxationTerms` of `zone` in a case with `motions` and the still-water level `surface_level`.

    Raises ValueError for a motion target naming no irregular or focused motion, and for a wave target
    without a still-water level (neither the zone's `level` nor the case's ``fluid.surface_level``)."""
    t = zone.target
    level = zone.level if zone.level is not None else surface_level
    if t.type == "still":
        return RelaxationTerms(zone, level=level or 0.0)
    if level is None:
        raise ValueError("a wave target needs the still-water level z is measured from: give the zone a level or "
                         "the case a fluid.surface_level")
    if t.type == "linear":
        k = wavenumber(t.period, t.depth)
        ramp = zone.ramp_time if zone.ramp_time is not None else 2.0 * t.period
        return RelaxationTerms(zone, [0.5 * t.height], [2.0 * math.pi / t.period], [k], [t.phase], t.depth, level,
                               1.0 if t.direction == "+x" else -1.0, t.origin, ramp)
    if isinstance(t, NonlinearTarget):
        return nonlinear_terms(zone, t, level)
    found = [m for m in motions if m.name == t.motion and getattr(m, "type", None) in SPECTRAL_MOTIONS]
    if not found:
        names = [m.name for m in motions if getattr(m, "type", None) in SPECTRAL_MOTIONS]
        raise ValueError(f"target.motion = {t.motion!r} names no irregular or focused motion (those of the case: "
                         f"{', '.join(names) if names else 'none'})")
    m = found[0]
    w = m.wave_components
    ramp = zone.ramp_time if zone.ramp_time is not None else m.ramp
    sign = 1.0 if float(m.direction[0]) >= 0 else -1.0
    return RelaxationTerms(zone, w.amplitudes, w.omegas, w.wavenumbers, w.phases, w.depth, level, sign, t.origin,
                           ramp)
