"""Rigid-body dynamics of a floating body: its state, its constraints and a symplectic integrator.

This is the body half of issue 32's fluid-body coupling: given the force F and the torque T (about the
centre of gravity, world frame) on a body, held over a step, advance the body. The SPH coupling sums F and
T over the body's particles once per integrator stage and places the particles with `RigidBody.kinematics`.

State (`BodyState`)
    c, the centre of gravity [m]; R, the rotation from the body at t = 0 (a rotation matrix, kept
    orthonormal); v [m/s]; omega [rad/s], world frame. A body point at x0 at t = 0 is at
    x = c + R (x0 - c0) and moves at u = v + omega x (x - c).

    Why a matrix, not a quaternion: every update below is a product with an exact rotation (Rodrigues'
    formula, `shoal.motions.rotation_matrix`), what the particle placement (`shoal.motions.RigidKinematics`)
    reads is R, and 2D needs no more than one angle. Round-off alone moves R off the rotations by about
    1e-16 per product; one Newton-Schulz step R <- R (3 E - R^T R) / 2 per step (Higham 1986, the polar
    factor) takes it back, so |R^T R - E| stays at round-off however long the run.

Equations of motion (Goldstein, Poole & Safko 2002, ch. 5)
    M dv/dt = F,   dc/dt = v,   dL/dt = T,   L = I_w omega,   I_w = R I_0 R^T,   dR/dt = [omega]_x R,

    with I_0 the inertia about c at t = 0 (`shoal.mass_properties`). Written in the principal frame
    A = R Q (I_0 = Q diag(I_1, I_2, I_3) Q^T), these are Euler's equations for the full tensor.

Integrator: a splitting into free flight and kicks (Strang 1968)
    drift(h): the body moves freely for h, its momenta held: c += h v, and the free rigid rotor by the
    splitting of Dullweber, Leimkuhler & McLachlan (1997, "Symplectic splitting methods for rigid body
    molecular dynamics", J. Chem. Phys. 107, 5840): with Pi = A^T L the body-frame angular momentum and
    H = sum Pi_k^2 / (2 I_k), each term's flow is an exact rotation about one principal axis,

        X_k(s): A <- A R_k(s Pi_k / I_k),   Pi <- R_k(s Pi_k / I_k)^T Pi,

    composed symmetrically, X_1(h/2) X_2(h/2) X_3(h) X_2(h/2) X_1(h/2). Each X_k keeps L = A Pi
    exactly (to round-off), so a torque-free body conserves its angular momentum to round-off; the
    scheme is symplectic and time-reversible, of second order, its energy error bounded, O(h^2).
    kick(h): v += h F / M, L += h T (the loads held, the body still).

    `advance` (the full step, shoal's symplectic corrector) = drift(dt/2) kick(dt) drift(dt/2), with the
    loads measured at the half step; `predict` (the half step, shoal's predictor) = drift(dt/2) then
    kick(dt/2), the loads measured at the start. For the translation, these are exactly the fluid's
    predictor r = r^n + dt/2 v^n, v = v^n + dt/2 a^n and corrector v^{n+1} = v^n + dt a^{n+1/2},
    r^{n+1} = r^n + dt (v^n + v^{n+1}) / 2 (`shoal.timestepping.updates`), and the orientation at the
    half step is the same in both: the composite `symplectic_step` is the position Verlet scheme
    (Leimkuhler et al. 1996) with the rotor drift of DLM 1997, second order.

Constraints (ideal: their reactions do no work)
    * fixed degrees of freedom, by name: "x", "y", "z" (translations along world axes), "rx", "ry", "rz"
      (rotations about world axes through c). A fixed translation's velocity and force component are held
      at zero, so its coordinate does not change, bitwise. Rotations are free about all three axes, about
      one world axis a through c (the other two fixed), or none; with one free axis Euler's equations
      reduce exactly to I_a d(omega_a)/dt = a . T, I_a = a^T I_w a (constant: a rotation about a leaves
      a^T I_w a unchanged), and the drift is the exact rotation by h omega_a about a. Two free rotations
      with the third held (e.g. roll and pitch without yaw) are refused: holding omega . e_z = 0 about a
      fixed world axis is a non-holonomic constraint this mask cannot represent.
    * 2D (dim = 2, the x-z plane): y, rx and rz are fixed: x, z and the rotation about y move.
    * a hinge to the ground: rotation about a fixed axis a through a fixed point p only. Then
      I_p d(omega_a)/dt = a . (T + (c - p) x F), I_p = a^T I_w a + M |a x (c - p)|^2 (parallel axes),
      c = p + R (c0 - p), v = omega x (c - p).

Loads (gravity, a spring-damper, a user force) are in `shoal.body_loads`; the case-file spec that builds a
`RigidBody` is `shoal.floating.FloatingBody`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .mass_properties import MassProperties, principal_axes
from .motions import RigidKinematics, rotation_matrix

DOFS = ("x", "y", "z", "rx", "ry", "rz")
"""The names of a body's six degrees of freedom: translations along, and rotations about, the world axes."""

_AXES = np.eye(3)


class BodyState(NamedTuple):
    """A rigid body's state at one time (world frame).

    Attributes
    ----------
    position : numpy.ndarray
        c [m], the centre of gravity.
    rotation : numpy.ndarray
        R, (3, 3), the rotation from the body at t = 0: a body point at x0 then is at c + R (x0 - c0).
    velocity : numpy.ndarray
        v [m/s], of the centre of gravity.
    angular_velocity : numpy.ndarray
        omega = I_w^-1 L [rad/s].
    angular_momentum : numpy.ndarray
        L = I_w omega [kg m^2/s] about the centre of gravity: what a free body's kicks change and its drifts
        leave alone, so that without torque it stays what it was, bitwise (the orientation and omega follow
        from it).
    acceleration : numpy.ndarray
        dv/dt [m/s^2] under the last loads applied (zero at the start).
    angular_acceleration : numpy.ndarray
        d omega/dt [rad/s^2] under the last loads applied, by Euler's equations
        I_w alpha = T - omega x I_w omega (zero at the start).
    """

    position: np.ndarray
    rotation: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    angular_momentum: np.ndarray
    acceleration: np.ndarray
    angular_acceleration: np.ndarray


def cross3(a, b):
    """a x b of two 3-vectors (NumPy's cross costs tens of microseconds on 3-vectors)."""
    a0, a1, a2 = float(a[0]), float(a[1]), float(a[2])
    b0, b1, b2 = float(b[0]), float(b[1]), float(b[2])
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _orthonormalised(r):
    """One Newton-Schulz step towards the polar factor of r, R <- R (3 E - R^T R) / 2 (Higham 1986): the
    nearest rotation, to second order in |R^T R - E|, which round-off keeps near 1e-16."""
    return r @ (1.5 * np.eye(3) - 0.5 * (r.T @ r))


class RigidBody:
    """A rigid body: its mass properties, its constraints, and its integrator (module docstring).

    Parameters
    ----------
    mass_properties : shoal.mass_properties.MassProperties
        Mass M, centre of gravity c0 and inertia I_0 about c0 at t = 0 (world axes).
    dim : {2, 3}
        2: the x-z plane; y, rx and rz are fixed.
    fixed : iterable of str
        Fixed degrees of freedom, names from `DOFS`.
    hinge_point, hinge_axis : array_like, optional
        A hinge to the ground: the body only rotates about `hinge_axis` (not normalised: non-zero) through
        `hinge_point`. Not with `fixed`.
    """

    def __init__(self, mass_properties, dim=3, fixed=(), hinge_point=None, hinge_axis=None):
        mp = MassProperties(float(mass_properties.mass), np.array(mass_properties.centre, float),
                            np.array(mass_properties.inertia, float))
        if not mp.mass > 0:
            raise ValueError(f"mass = {mp.mass:g}: a body's mass must be above 0")
        if dim not in (2, 3):
            raise ValueError(f"dim = {dim}: must be 2 or 3")
        fixed = set(fixed)
        unknown = fixed - set(DOFS)
        if unknown:
            raise ValueError(f"fixed: unknown degrees of freedom {sorted(unknown)}; allowed: {', '.join(DOFS)}")
        if dim == 2:
            fixed |= {"y", "rx", "rz"}
        self.mass_properties = mp
        self.dim = dim
        self.mass = mp.mass
        self.centre0 = mp.centre
        self.inertia0 = 0.5 * (mp.inertia + mp.inertia.T)
        self.moments, self.principal = principal_axes(self.inertia0)
        if not self.moments[0] > 0:
            raise ValueError("the inertia tensor is not positive definite")
        self.fixed = frozenset(fixed)
        self.hinge_point = None
        if hinge_point is not None or hinge_axis is not None:
            if hinge_point is None or hinge_axis is None:
                raise ValueError("a hinge needs both its point and its axis")
            if set(fixed) - ({"y", "rx", "rz"} if dim == 2 else set()):
                raise ValueError("a hinge already fixes every degree of freedom but its rotation; leave out fixed")
            a = np.asarray(hinge_axis, float)
            if not np.linalg.norm(a) > 0:
                raise ValueError("hinge axis = [0, 0, 0] is no axis; give its direction, e.g. [0, 1, 0]")
            a = a / np.linalg.norm(a)
            if dim == 2 and not (a[0] == 0.0 and a[2] == 0.0):
                raise ValueError("a 2D body's hinge axis is y, [0, 1, 0]")
            self.hinge_point = np.asarray(hinge_point, float)
            if dim == 2:
                self.hinge_point = self.hinge_point * np.array([1.0, 0.0, 1.0])
            self.free_translation = np.zeros(3)
            self.rotation_mode, self.axis = "axis", a
            arm = cross3(a, self.centre0 - self.hinge_point)
            self.axis_inertia = float(a @ self.inertia0 @ a) + self.mass * float(arm @ arm)
            return
        self.free_translation = np.array([0.0 if k in fixed else 1.0 for k in ("x", "y", "z")])
        free_rot = [k for k, name in enumerate(("rx", "ry", "rz")) if name not in fixed]
        if len(free_rot) == 3:
            self.rotation_mode, self.axis = "free", None
        elif len(free_rot) == 1:
            self.rotation_mode, self.axis = "axis", _AXES[free_rot[0]].copy()
            self.axis_inertia = float(self.axis @ self.inertia0 @ self.axis)
        elif len(free_rot) == 0:
            self.rotation_mode, self.axis = "fixed", None
        else:
            held = ("rx", "ry", "rz")[({0, 1, 2} - set(free_rot)).pop()]
            raise ValueError(f"fixed = [{held}] leaves two rotations free: a body rotates about all three axes, "
                             "about one (fix the two others) or none")

    # ------------------------------------------------------------------ state
    def initial_state(self, velocity=(0.0, 0.0, 0.0), angular_velocity=(0.0, 0.0, 0.0)):
        """The state at t = 0: c = c0, R = E, and the given velocities projected onto the degrees of freedom
        the constraints leave free (a hinged body's v = omega x (c0 - p))."""
        v = np.asarray(velocity, float) * self.free_translation
        w = self._projected_omega(np.asarray(angular_velocity, float))
        c = self.centre0.copy()
        if self.hinge_point is not None:
            v = cross3(w, c - self.hinge_point)
        z = np.zeros(3)
        return BodyState(c, np.eye(3), v, w, self.inertia0 @ w, z, z.copy())

    def _projected_omega(self, w):
        if self.rotation_mode == "free":
            return w.copy()
        if self.rotation_mode == "axis":
            return float(w @ self.axis) * self.axis
        return np.zeros(3)

    def world_inertia(self, state):
        """I_w = R I_0 R^T [kg m^2], the inertia about c in world axes."""
        r = state.rotation
        return r @ self.inertia0 @ r.T

    def angular_momentum(self, state):
        """L = I_w omega [kg m^2/s] about the centre of gravity, world frame, from omega (the state's own
        L is the integrator's variable; the two agree to round-off)."""
        return self.world_inertia(state) @ state.angular_velocity

    def kinetic_energy(self, state):
        """E = M |v|^2 / 2 + omega . I_w omega / 2 [J]."""
        w = state.angular_velocity
        return 0.5 * self.mass * float(state.velocity @ state.velocity) + 0.5 * float(w @ self.world_inertia(state) @ w)

    def kinematics(self, state):
        """The rigid motion that places the body's particles (`shoal.motions.RigidKinematics`), its pivot the
        centre of gravity at t = 0: x = c0 + (c - c0) + R (x0 - c0), u = v + omega x R (x0 - c0), and
        a = dv/dt + alpha x r + omega x (omega x r) (the last loads' accelerations)."""
        return RigidKinematics(state.position - self.centre0, state.velocity.copy(), state.acceleration.copy(),
                               state.rotation.copy(), state.angular_velocity.copy(),
                               state.angular_acceleration.copy(), self.centre0.copy(),
                               self.rotation_mode != "fixed")

    # ------------------------------------------------------------------ integrator
    def predict(self, state, force, torque, dt):
        """The half step of shoal's symplectic scheme (call it with dt/2): drift(dt) with the state's
        velocities, then kick(dt) with the loads measured at `state` (module docstring).

        Parameters
        ----------
        state : BodyState
        force : array_like
            F [N], world frame, the total on the body (fluid, gravity, springs, user), measured at `state`.
        torque : array_like
            T [N m] about the centre of gravity `state.position`, world frame.
        dt : float
            [s].

        Returns
        -------
        BodyState
        """
        force, torque = np.asarray(force, float), np.asarray(torque, float)
        lever = state.position  # a hinge's torque about p takes F at the point where it was measured
        return self._kick(self._drift(state, dt), force, torque, dt, lever)

    def advance(self, state, force, torque, dt):
        """The full step of shoal's symplectic scheme: drift(dt/2), kick(dt) with the loads, drift(dt/2),
        from `state` (the start of the step), the loads measured at the half step that `predict` gave
        (whose orientation and centre the first drift reproduces exactly).

        Parameters
        ----------
        state : BodyState
            At the start of the step.
        force, torque : array_like
            F [N] and T [N m] about the centre of gravity, world frame, measured at the half step.
        dt : float
            [s].

        Returns
        -------
        BodyState
        """
        force, torque = np.asarray(force, float), np.asarray(torque, float)
        half = self._drift(state, 0.5 * dt)
        return self._drift(self._kick(half, force, torque, dt, half.position), 0.5 * dt)

    def _kick(self, state, force, torque, h, lever):
        """v += h F / M, L += h T with the body held still (a hinge: omega_a += h a.(T + (c - p) x F) / I_p)."""
        if self.hinge_point is not None:
            a = self.axis
            tau = float(a @ (torque + cross3(lever - self.hinge_point, force)))
            alpha = tau / self.axis_inertia
            w = state.angular_velocity + (h * alpha) * a
            arm = state.position - self.hinge_point
            v = cross3(w, arm)
            acc = cross3(alpha * a, arm) + cross3(w, v)
            return state._replace(velocity=v, angular_velocity=w, angular_momentum=self._momentum(state, w),
                                  acceleration=acc, angular_acceleration=alpha * a)
        acc = force * self.free_translation / self.mass
        v = state.velocity + h * acc
        if self.rotation_mode == "free":
            big_l = state.angular_momentum + h * torque
            w = self._omega(state.rotation, big_l)
            wm = 0.5 * (w + state.angular_velocity)
            # Euler's equations, I_w alpha = T - omega x I_w omega (the acceleration the walls report)
            alpha = self._omega(state.rotation, torque - cross3(wm, self._momentum(state, wm)))
            return state._replace(velocity=v, angular_velocity=w, angular_momentum=big_l, acceleration=acc,
                                  angular_acceleration=alpha)
        if self.rotation_mode == "axis":
            a = self.axis
            alpha = (float(a @ torque) / self.axis_inertia) * a
            w = state.angular_velocity + h * alpha
        else:
            w, alpha = state.angular_velocity, np.zeros(3)
        return state._replace(velocity=v, angular_velocity=w, angular_momentum=self._momentum(state, w),
                              acceleration=acc, angular_acceleration=alpha)

    def _omega(self, rotation, big_l):
        """omega = I_w^-1 L = A diag(1 / I_k) A^T L, A = R Q."""
        a = rotation @ self.principal
        return a @ ((a.T @ big_l) / self.moments)

    def _momentum(self, state, w):
        return state.rotation @ (self.inertia0 @ (state.rotation.T @ w))

    def _drift(self, state, h):
        """Free flight for h, the momenta held: c += h v and the free rotor (DLM 1997), or the exact rotation
        about a fixed axis."""
        if self.rotation_mode == "fixed":
            return state._replace(position=state.position + h * state.velocity)
        if self.rotation_mode == "axis":
            wa = float(self.axis @ state.angular_velocity)
            g = rotation_matrix(self.axis, h * wa)
            rot = _orthonormalised(g @ state.rotation)
            if self.hinge_point is None:
                return state._replace(position=state.position + h * state.velocity, rotation=rot)
            p = self.hinge_point
            c = p + g @ (state.position - p)
            w = state.angular_velocity
            return state._replace(position=c, rotation=rot, velocity=cross3(w, c - p))
        big_l = state.angular_momentum
        rows = (state.rotation @ self.principal).T  # rows: the principal axes A_k, world components
        a = [[float(x) for x in row] for row in rows]
        pi = [float(x) for x in rows @ big_l]  # Pi = A^T L
        i = [float(x) for x in self.moments]
        for k, s in ((0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)):
            # X_k(s h): A <- A R_k(phi), Pi <- R_k(phi)^T Pi, phi = s h Pi_k / I_k; R_k the rotation about
            # principal axis k, turning the two others (p, q) = (k + 1, k + 2) mod 3 (plain floats: a
            # 3 x 3 update is faster in Python than through NumPy's calls)
            phi = s * h * pi[k] / i[k]
            c, sn = math.cos(phi), math.sin(phi)
            p, q = (k + 1) % 3, (k + 2) % 3
            ap, aq = a[p], a[q]
            a[p] = [c * x + sn * y for x, y in zip(ap, aq)]
            a[q] = [c * y - sn * x for x, y in zip(ap, aq)]
            pi[p], pi[q] = c * pi[p] + sn * pi[q], c * pi[q] - sn * pi[p]
        rot = _orthonormalised(np.array(a).T @ self.principal.T)
        return state._replace(position=state.position + h * state.velocity, rotation=rot,
                              angular_velocity=self._omega(rot, big_l))


def symplectic_step(body, state, loads, t, dt):
    """One step of shoal's symplectic scheme for a body alone, as the SPH coupling will call it:

        F^n, T^n = loads(state^n, t);          s^{n+1/2} = body.predict(state^n, F^n, T^n, dt / 2);
        F', T' = loads(s^{n+1/2}, t + dt / 2);  state^{n+1} = body.advance(state^n, F', T', dt).

    Parameters
    ----------
    body : RigidBody
    state : BodyState
    loads : callable
        loads(state, t) -> (F [N], T [N m] about the state's centre of gravity), world frame
        (`shoal.body_loads.total_loads`).
    t, dt : float
        [s].

    Returns
    -------
    (BodyState, BodyState)
        The state at t + dt, and the half-step state at which the loads were measured.
    """
    f, tq = loads(state, t)
    half = body.predict(state, f, tq, 0.5 * dt)
    f, tq = loads(half, t + 0.5 * dt)
    return body.advance(state, f, tq, dt), half

