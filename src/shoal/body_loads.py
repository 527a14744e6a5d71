"""Loads on a rigid body besides the fluid's: gravity, a linear spring-damper to a fixed point, a user force.

Each load is a callable ``load(body, state, t) -> (F, T)``: the force F [N] and the torque T [N m] about the
body's centre of gravity, world frame, at the state `state` (`shoal.rigid_body.BodyState`) and time t [s].
`total_loads` sums them (with the fluid's, once the SPH coupling gives it) into the ``loads(state, t)`` that
`shoal.rigid_body.symplectic_step` reads. A force F at a body point x gives the torque (x - c) x F.

2D bodies (the x-z plane) are per unit width: forces in N/m, stiffnesses in N/m^2.
"""

from __future__ import annotations

from typing import Annotated, Callable

import numpy as np
from pydantic import Field

from .geometry.shapes import Spec, Vec3
from .rigid_body import cross3

NonNegativeReal = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]


def body_point(body, state, x0):
    """(x [m], u [m/s]) now of the body point that was at `x0` [m] at t = 0: x = c + R (x0 - c0),
    u = v + omega x (x - c)."""
    r = state.rotation @ (np.asarray(x0, float) - body.centre0)
    return state.position + r, state.velocity + cross3(state.angular_velocity, r)


class Gravity:
    """The body's weight, F = M g at the centre of gravity (no torque about it).

    Parameters
    ----------
    g : sequence of 3 floats
        [m/s^2], default (0, 0, -9.81).
    """

    def __init__(self, g=(0.0, 0.0, -9.81)):
        self.g = np.asarray(g, float)

    def __call__(self, body, state, t):
        return body.mass * self.g, np.zeros(3)


class SpringDamper(Spec):
    """A linear spring-damper from a point of the body to a fixed `anchor` (e.g. a taut mooring line's
    linear model, a heave spring of a wave-energy converter).

    With d = x_b - anchor, x_b the body point that was at `attachment` at t = 0 (default: the centre of
    gravity) and u_b its velocity,

        rest_length = 0:  F = -k d - c u_b,
        rest_length > 0:  F = -[k (|d| - L_0) + c (u_b . n)] n,   n = d / |d|  (axial only),

    k = `stiffness` [N/m], c = `damping` [N s/m], L_0 = `rest_length` [m]; applied at x_b, so about the
    centre of gravity T = (x_b - c) x F.
    """

    anchor: Vec3
    stiffness: NonNegativeReal
    damping: NonNegativeReal = 0.0
    rest_length: NonNegativeReal = 0.0
    attachment: Vec3 | None = None

    def __call__(self, body, state, t):
        x0 = body.centre0 if self.attachment is None else self.attachment
        x, u = body_point(body, state, x0)
        d = x - np.asarray(self.anchor, float)
        k, c = self.stiffness, self.damping
        if self.rest_length == 0.0:
            f = -k * d - c * u
        else:
            length = float(np.linalg.norm(d))
            if length == 0.0:  # no direction: a spring of rest length L0 at zero length has none to push along
                f = np.zeros(3)
            else:
                n = d / length
                f = -(k * (length - self.rest_length) + c * float(u @ n)) * n
        return f, cross3(x - state.position, f)


class UserForce:
    """A force given as a function of time, applied at a body point (a tow line, a test load).

    Parameters
    ----------
    force : callable
        force(t) -> F [N], a 3-vector, world frame.
    attachment : sequence of 3 floats, optional
        Where it acts: the body point that was there at t = 0 [m] (default: the centre of gravity, no
        torque).
    torque : callable, optional
        torque(t) -> a further torque [N m], world frame.
    """

    def __init__(self, force: Callable, attachment=None, torque: Callable | None = None):
        self.force, self.attachment, self.torque = force, attachment, torque

    def __call__(self, body, state, t):
        f = np.asarray(self.force(t), float)
        tq = np.zeros(3) if self.torque is None else np.asarray(self.torque(t), float).copy()
        if self.attachment is not None:
            x, _ = body_point(body, state, self.attachment)
            tq = tq + cross3(x - state.position, f)
        return f, tq


def total_loads(body, loads, fluid=None):
    """``loads(state, t) -> (F, T)``: the sum of `loads` (each ``load(body, state, t)``), plus
    ``fluid(state, t) -> (F, T)`` (the SPH coupling's sums over the body's particles) when given."""

    def total(state, t):
        f, tq = np.zeros(3), np.zeros(3)
        for load in loads:
            df, dt = load(body, state, t)
            f, tq = f + df, tq + dt
        if fluid is not None:
            df, dt = fluid(state, t)
            f, tq = f + np.asarray(df, float), tq + np.asarray(dt, float)
        return f, tq

    return total
