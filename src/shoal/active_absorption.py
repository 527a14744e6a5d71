"""Active wave absorption at a paddle (AWAS): the paddle moves so as to cancel the waves that come back to it.

A wave paddle (`shoal.motions.PistonWavemaker`, `FlapWavemaker`, `IrregularWaves`, `FocusedWaves`) with an
``absorption`` table is driven by its target signal X_T(t) (the excursion of its face at the still-water level)
plus a correction X_c(t) computed as the run goes, in the time domain, from the surface elevation measured in
front of it (Schaeffer & Klopman 2000, "Review of multidirectional active wave absorption methods", J.
Waterway, Port, Coastal, Ocean Eng. 126(2); the gauge-driven form DualSPHysics implements, Altomare et al.
2017, "Long-crested wave generation and absorption for SPH-based DualSPHysics model", Coastal Eng. 127).

Every time step, at the end of the step (time t):

1. the elevation eta_m is measured on a vertical line `gauge_offset` x_g in front of the paddle's face (the
   surface where the kernel sum of the fluid crosses 1/2, as a `shoal.probes.WaveGauge` reads it, over every
   process of the run), the line moving with the face;
2. the error e = eta_m - eta_T is what the paddle did not ask for: eta_T is the linear elevation its target
   motion makes at that distance x = x_g + X(t) from the face's rest position, the progressive wave and the
   evanescent near field (`shoal.waves.near_field`), times the target's ramp;
3. e is low-pass filtered, e_f <- e_f + (1 - exp(-dt / tau)) (e - e_f), with tau = x_g / c the time a wave
   takes from the gauge to the paddle (c the phase speed at the paddle's characteristic frequency): the gauge
   sees a returning wave tau before the paddle does, and a first-order filter delays a slow signal by tau, so
   the filtered error is the returning wave at the paddle (and the noise of the particle surface is smoothed
   over tau);
4. from `start` on, the correction velocity is

       U_c = -G e_f - X_c / T_d,

   G = omega_c / (H/S)(k_c d) (``gain = "linear"``: the paddle velocity that makes, by the paddle's transfer
   function, a wave of the measured amplitude at the characteristic frequency omega_c -- the wave's, or the
   spectrum's peak) or G = sqrt(g / d) (``gain = "shallow"``, the long-wave limit that DualSPHysics uses),
   either divided by the filter's amplitude response at omega_c, 1 / sqrt(1 + (omega_c tau)^2), and the drift
   control -X_c / T_d pulls the paddle back toward its target over T_d = `drift_periods` periods
   (a leak that keeps the correction's mean at zero; at omega_c it turns the correction's phase by
   atan(1 / (omega_c T_d)), 0.9 degrees for 10 periods).

Over the next step the face's excursion is X_T(t) + X_c(t_n) + U_c (t - t_n), its velocity X_T' + U_c, its
acceleration X_T'' + (U_c(t_n) - U_c(t_{n-1})) / dt (what the Adami wall pressure reads); a flap turns by
atan(X / (d - l)) about its hinge.

With G equal to the paddle's ideal gain G_0 at a frequency, a wave coming back at that frequency is absorbed
completely: the reflection off a paddle with the correction is |G_0 - G| / (G_0 + G) (a gain 12 % high at
kd = 1, the shallow-water gain's error there, reflects 6 %).

The controller's state (X_c, U_c, the last acceleration, e_f, the time of the last update) is saved in a
checkpoint and put back on a resume, so that a resumed run continues bitwise; under MPI every process measures
the same reduced elevation and keeps the same state.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from .analysis.kernel_sum import surface_level
from .geometry.shapes import PositiveReal, Spec
from .waves.dispersion import GRAVITY, wavenumber
from .waves.near_field import near_field

NonNegativeReal = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]


class ActiveAbsorption(Spec):
    """A wave paddle's ``[motions.absorption]`` table: active absorption of the waves that come back to it
    (module docstring).

    Attributes
    ----------
    start : float, optional
        Time [s] from which the correction acts (default: the end of the paddle's start-up ramp).
    gauge_offset : float, optional
        Distance [m] in front of the paddle's face at which the elevation is measured (default: the kernel's
        support radius 2h, the nearest line whose kernel sum the wall does not cut).
    gain : {"linear", "shallow"}
        G = omega_c / (H/S)(k_c d), the paddle's own transfer function at its characteristic frequency
        (default), or sqrt(g / d), the long-wave limit.
    drift_periods : float
        T_d / T_c, the drift control's time over the characteristic period (default 10).
    """

    start: NonNegativeReal | None = None
    gauge_offset: PositiveReal | None = None
    gain: Literal["linear", "shallow"] = "linear"
    drift_periods: PositiveReal = 10.0


class AbsorbingPaddle:
    """A wave paddle with active absorption, as the model moves it and as a callback of the run updates it
    (module docstring).

    It stands in the model's list of motions for the paddle's motion (`rigid_kinematics`, `rotation_axis`,
    `rotation_pivot`, `name`), and is called after every step (``paddle(sim)``) to measure and correct.

    Parameters
    ----------
    motion : shoal.motions.PistonWavemaker, FlapWavemaker, IrregularWaves or FocusedWaves
        The paddle's target motion, with its `absorption`.
    face : float
        The position [m] along the paddle's direction e of its wall surface at rest (its outermost
        particles' centres plus dp / 2).
    lateral : (3,) array_like
        A point [m] of the vertical line the gauge moves along, less its component along e (the paddle's
        middle across the flume; y = 0 in 2D).
    still_water : float
        The still-water level z [m].
    dp, h : float
        Particle spacing and smoothing length [m].
    dim : {2, 3}
    """

    def __init__(self, motion, *, face, lateral, still_water, dp, h, dim):
        spec = motion.absorption
        self.motion = motion
        self.spec = spec
        p = motion.wave_paddle()
        self.wave_paddle = p
        self.name = motion.name
        self.direction = np.asarray(p.direction, float)
        self.face = float(face)
        self.lateral = np.asarray(lateral, float)
        self.dim = int(dim)
        self.still_water = float(still_water)
        d = float(p.depth)
        self.offset = float(spec.gauge_offset) if spec.gauge_offset is not None else 2.0 * float(h)
        omega_c = 2.0 * math.pi / p.period
        k_c = wavenumber(p.period, d)
        transfer, _ = near_field(omega_c, d, 0.0, p.hinge)
        self.travel_time = self.offset / (omega_c / k_c)
        # the filter passes a wave of omega_c at 1 / sqrt(1 + (omega_c tau)^2) of its amplitude: made up here
        boost = math.hypot(1.0, omega_c * self.travel_time)
        self.gain = boost * (omega_c / transfer if spec.gain == "linear" else math.sqrt(GRAVITY / d))
        self.drift_time = spec.drift_periods * p.period
        self.start = float(spec.start) if spec.start is not None else float(p.ramp_end)
        # the gauge's line: dp/2 apart from half a depth below the still-water level to half a depth above it
        lo = max(still_water - 0.5 * d, still_water - d + 0.5 * dp)
        self.z = np.arange(lo, still_water + 0.5 * d + 0.25 * dp, 0.5 * dp)
        self._points = np.zeros((len(self.z), 3))
        self._points[:, 2] = self.z
        # the target's components and their near-field coefficients at the gauge (x = offset + X(t) moves
        # by a few % of a wavelength: E(x) is tabulated over the paddle's reach and interpolated)
        w = p.components
        self._omega = w.omegas
        self._k = w.wavenumbers
        self._a = w.amplitudes
        self._b = p.paddle_amplitudes
        self._phi = w.phases
        reach = max(float(np.sum(np.abs(self._b))), 0.0)
        self._xs = np.linspace(max(self.offset - 2.0 * reach, 0.0), self.offset + 2.0 * reach + 1e-9, 33)
        self._near = np.array([near_field(om, d, self._xs, p.hinge)[1] for om in self._omega])
        self.reset()

    def reset(self):
        """The controller at rest: no correction, nothing measured."""
        self.t_last = 0.0
        self.x_c = 0.0
        self.u_c = 0.0
        self.a_c = 0.0
        self.e_f = 0.0
        self.measured = float("nan")
        self.target = float("nan")

    # ------------------------------------------------------------------ what the model reads
    @property
    def rotation_axis(self):
        return self.motion.rotation_axis

    @property
    def rotation_pivot(self):
        return self.motion.rotation_pivot

    def correction(self, t):
        """(X_c, U_c, A_c) at time t [s]: the correction's excursion [m], velocity [m/s] and acceleration
        [m/s^2] at the still-water level, held from the last update."""
        return self.x_c + self.u_c * (t - self.t_last), self.u_c, self.a_c

    def rigid_kinematics(self, t, acceleration=True):
        """The paddle's rigid motion at time t [s]: its target's with the face's excursion shifted by the
        correction (`shoal.motions` ``offset_kinematics``)."""
        x, u, a = self.correction(t)
        return self.motion.offset_kinematics(t, x, u, a if acceleration else 0.0, acceleration)

    # ------------------------------------------------------------------ measuring and correcting
    def target_elevation(self, t, x):
        """eta_T [m] at the distance `x` [m] from the face's rest position at time t [s]: the target's
        progressive components and their near field, times the ramp (module docstring)."""
        arg = self._omega * t + self._phi
        # linear interpolation in the uniform table of E(x), every component at once (clamped at its ends)
        xs = self._xs
        u = min(max((x - xs[0]) / (xs[1] - xs[0]), 0.0), len(xs) - 1.0)
        k = min(int(u), len(xs) - 2)
        f = u - k
        near = self._near[:, k] * (1.0 - f) + self._near[:, k + 1] * f
        eta = np.dot(self._a, np.cos(arg - self._k * x)) - np.dot(near * self._b, np.sin(arg))
        return float(self.motion.envelope(t) * eta)

    def gauge_points(self, excursion):
        """(M, 3) world points [m] of the gauge's line when the face's excursion is `excursion` [m]."""
        pts = self._points
        s = self.face + excursion + self.offset
        pts[:, 0] = self.lateral[0] + s * self.direction[0]
        pts[:, 1] = 0.0 if self.dim == 2 else self.lateral[1] + s * self.direction[1]
        return pts

    def __call__(self, sim):
        t = float(sim.time)
        dt = t - self.t_last
        if dt < 0.0 or (dt == 0.0 and sim.step_count > 0):
            return
        self.x_c += self.u_c * dt
        self.t_last = t
        excursion = self.motion.excursion(t)[0] + self.x_c
        s = sim.model.sample(self.gauge_points(excursion), shepard=False)["kernel_sum"]
        self.measured = surface_level(self.z, s)
        self.target = self.target_elevation(t, self.offset + excursion)
        e = self.measured - self.still_water - self.target if math.isfinite(self.measured) else 0.0
        self.e_f += -math.expm1(-dt / self.travel_time) * (e - self.e_f)
        u = -self.gain * self.e_f - self.x_c / self.drift_time if t >= self.start else 0.0
        self.a_c = (u - self.u_c) / dt if dt > 0.0 else 0.0
        self.u_c = u

    # ------------------------------------------------------------------ checkpoints
    def checkpoint_state(self):
        """The controller's state, exact as floats (JSON keeps every bit of a double)."""
        return {"t_last": self.t_last, "x_c": self.x_c, "u_c": self.u_c, "a_c": self.a_c, "e_f": self.e_f}

    def restore_checkpoint_state(self, scalars, arrays, backup=None):
        """Put `checkpoint_state`'s values back; returns None (no warning)."""
        for key in ("t_last", "x_c", "u_c", "a_c", "e_f"):
            setattr(self, key, float(scalars[key]))
        return None


def absorbing_paddles(motions, positions, motion_of, *, still_water, dp, h, dim):
    """The model's motions with each paddle that has ``absorption`` replaced by its `AbsorbingPaddle`.

    Parameters
    ----------
    motions : list of motions
        The case's motions.
    positions : (N, 3) array
        Particle positions [m] at t = 0 (world coordinates).
    motion_of : (N,) int array
        The motion of each particle (-1: none).
    still_water : float
        The still-water level z [m].
    dp, h : float
        Particle spacing and smoothing length [m].
    dim : {2, 3}
    """
    out = []
    for k, m in enumerate(motions):
        if getattr(m, "absorption", None) is None:
            out.append(m)
            continue
        e = np.asarray(m.wave_paddle().direction, float)
        mine = np.asarray(positions, float)[np.asarray(motion_of) == k]
        if not len(mine):
            out.append(m)  # no solid moves with it: nothing to absorb with
            continue
        along = mine @ e
        face = float(along.max()) + 0.5 * dp
        middle = mine.mean(axis=0)
        lateral = middle - (middle @ e) * e
        out.append(AbsorbingPaddle(m, face=face, lateral=lateral, still_water=still_water, dp=dp, h=h, dim=dim))
    return out
