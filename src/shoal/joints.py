"""Joints between two floating bodies: a pin (ball joint) or a hinge, held by a stiff spring-damper.

A joint ties the point of body A and the point of body B that were both at ``point`` at t = 0. With
x_A, x_B those body points now (`shoal.body_loads.body_point`), u_A, u_B their velocities,

    F = -k (x_A - x_B) - c (u_A - u_B)   on A at x_A,   -F on B at x_B,

and a hinge also keeps the axis a (fixed in both bodies, along `axis` at t = 0; a_A = R_A a0, a_B = R_B a0)
common to both, by the torque

    T = k_r (a_A x a_B) - c_r (w_rel - (w_rel . a) a),   w_rel = w_A - w_B,   on A, and -T on B,

which turns a_A toward a_B and damps every relative rotation but the one about the axis. The loads are
internal: they add nothing to the pair's momentum or angular momentum (F and -F act at points that the
spring keeps together, within its error). In 2D (the x-z plane, rotations about y) a pin is a hinge about y.

Why a spring and not an exact constraint (Lagrange multipliers, as Project Chrono, which DualSPHysics couples
for its joints): the bodies are advanced explicitly, stage by stage, with the fluid; a spring stiff enough
that its natural frequency omega_j = 0.2 / dt_c (dt_c = CFL h / c0, the acoustic time step) keeps the joint's
error at F / k (a body's weight over k: microns at flume scale) and is integrated stably by the same
stages (omega_j dt < 2 for the symplectic scheme; here 0.2). Its damping is critical. Stiffness and damping
follow from the pair's reduced mass and inertia, m = m_A m_B / (m_A + m_B):

    k = m omega_j^2,  c = 2 m omega_j;   k_r = I omega_j^2,  c_r = 2 I omega_j,   I = I_A I_B / (I_A + I_B),

I_A, I_B each body's smallest principal moment.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, field_validator

from .body_loads import body_point
from .geometry.shapes import Spec, Vec3
from .rigid_body import cross3


class Joint(Spec):
    """A joint between two floating solids (module docstring).

    Attributes
    ----------
    bodies : 2 str
        The names of the two floating solids.
    point : 3 floats
        Where the joint is at t = 0 [m] (a point of both bodies from then on).
    axis : 3 floats, optional
        A hinge: the bodies turn relative to each other about this axis only (fixed in both). Default: a pin
        (ball joint), free in every relative rotation; in 2D, a pin is a hinge about y.
    """

    bodies: Annotated[list[Annotated[str, Field(min_length=1)]], Field(min_length=2, max_length=2)]
    point: Vec3
    axis: Vec3 | None = None

    @field_validator("bodies")
    @classmethod
    def _two(cls, v):
        if v[0] == v[1]:
            raise ValueError(f"bodies = {v}: a joint ties two different bodies")
        return v

    @field_validator("axis")
    @classmethod
    def _an_axis(cls, v):
        if v is not None and not np.linalg.norm(np.asarray(v, float)) > 0:
            raise ValueError("axis = [0, 0, 0] is no axis; give the hinge's direction, or leave it out for a pin")
        return v


class JointLoads:
    """The loads of one joint on its two bodies (module docstring).

    Parameters
    ----------
    a, b : int
        The two bodies' positions in the list of bodies given to `loads`.
    point : array_like
        The joint at t = 0 [m].
    axis : array_like or None
        A hinge's axis at t = 0, or None (a pin).
    body_a, body_b : shoal.rigid_body.RigidBody
    omega : float
        The joint's natural frequency omega_j [rad/s].
    dim : {2, 3}
    """

    def __init__(self, a, b, point, axis, body_a, body_b, omega, dim=3):
        self.a, self.b = int(a), int(b)
        self.point = np.asarray(point, float).copy()
        self.axis = None if axis is None or dim == 2 else np.asarray(axis, float) / np.linalg.norm(axis)
        m = body_a.mass * body_b.mass / (body_a.mass + body_b.mass)
        ia, ib = float(body_a.moments[0]), float(body_b.moments[0])
        inertia = ia * ib / (ia + ib)
        self.k, self.c = m * omega * omega, 2.0 * m * omega
        self.k_r, self.c_r = inertia * omega * omega, 2.0 * inertia * omega

    def gap(self, bodies, states):
        """|x_A - x_B| [m]: how far apart the joint's two points are."""
        xa, _ = body_point(bodies[self.a], states[self.a], self.point)
        xb, _ = body_point(bodies[self.b], states[self.b], self.point)
        return float(np.linalg.norm(xa - xb))

    def add_loads(self, bodies, states, out):
        """Add the joint's force (columns 0-2) and torque about each centre of gravity (3-5) to `out`, (B, 6)."""
        sa, sb = states[self.a], states[self.b]
        xa, ua = body_point(bodies[self.a], sa, self.point)
        xb, ub = body_point(bodies[self.b], sb, self.point)
        f = -self.k * (xa - xb) - self.c * (ua - ub)
        ta = cross3(xa - sa.position, f)
        tb = cross3(xb - sb.position, -f)
        if self.axis is not None:
            aa = sa.rotation @ self.axis
            ab = sb.rotation @ self.axis
            w = sa.angular_velocity - sb.angular_velocity
            a = 0.5 * (aa + ab)
            a = a / np.linalg.norm(a)
            t = self.k_r * cross3(aa, ab) - self.c_r * (w - float(w @ a) * a)
            ta, tb = ta + t, tb - t
        out[self.a, :3] += f
        out[self.a, 3:] += ta
        out[self.b, :3] -= f
        out[self.b, 3:] += tb


def joint_loads(case, names, bodies):
    """The `JointLoads` of ``case.joints``: `names` and `bodies` are the floating bodies' names and
    `shoal.rigid_body.RigidBody` objects, in one order; omega_j = 0.2 / (CFL h / c0) (module docstring)."""
    dt = case.options.cfl * case.smoothing_length / case.sound_speed
    omega = 0.2 / dt
    out = []
    for j in case.joints:
        a, b = names.index(j.bodies[0]), names.index(j.bodies[1])
        out.append(JointLoads(a, b, j.point, j.axis, bodies[a], bodies[b], omega, case.dim))
    return out
