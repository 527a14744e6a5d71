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
"""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field

from .geometry.shapes import PositiveReal, Spec, Vec3

_G = 9.81


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
    return 2.0 * (math.cosh(kd2) - 1.0) / (math.sinh(kd2) + kd2)


class Motion(Spec):
    """Base of motions: `name` is what solids refer to."""

    name: Annotated[str, Field(min_length=1)]

    def kinematics(self, t):
        """(displacement [m], velocity [m/s]) at time t [s], 3-vectors."""
        raise NotImplementedError


class ConstantVelocity(Motion):
    """Rigid motion at constant `velocity` [m/s] from time `start` [s]:
    displacement = velocity max(t - start, 0)."""

    type: Literal["constant_velocity"] = "constant_velocity"
    velocity: Vec3
    start: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0

    def kinematics(self, t):
        v = np.asarray(self.velocity, float)
        return v * max(t - self.start, 0.0), (v if t >= self.start else np.zeros(3))


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

    def kinematics(self, t):
        w = 2 * math.pi / self.period
        r, dr = self._ramp(t)
        t = max(t, 0.0)
        a = 0.5 * self.stroke
        e = self._unit()
        return e * (r * a * math.sin(w * t)), e * (a * (dr * math.sin(w * t) + r * w * math.cos(w * t)))


AnyMotion = Annotated[Union[ConstantVelocity, PistonWavemaker], Field(discriminator="type")]
