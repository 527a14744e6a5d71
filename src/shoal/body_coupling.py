"""Floating bodies moved by the fluid: the two-way coupling of rigid bodies and SPH particles (issue 32).

A floating body is a solid whose boundary particles are placed rigidly by the body's state
(`shoal.rigid_body`), the state advanced under the fluid's force and torque and the body's other loads
(`shoal.body_loads`: gravity, springs, a user force). Its particles are moving boundary particles like a
wave paddle's: its motion is one row of the model's motion table (`FloatingMotion`), so the wall
treatments (Adami, mDBC, dynamic), the particle placement x = c + R (x0 - c0), u = v + omega x r and every
backend are those of the prescribed motions.

Fluid loads
    The walls and the other bodies push a body's particles by a contact force when they come within dp of
    theirs (`shoal.physics.contact`), summed the same way.

    At every rate evaluation the force on each boundary particle b (`shoal.physics.forces`, the negative of
    what b does to the fluid, term by term) is summed over the body's particles:

        F = sum_b F_b,     T = sum_b (x_b - c) x F_b,

    c the body's centre of gravity at that stage (on the active backend: `Model.floating_loads`; over MPI
    ranks, each rank its own particles, then a sum). By construction the fluid receives -F: fluid and
    body together conserve momentum to the round-off of the pair forces.

A body with a ``release_time`` keeps its state over every step that starts before that time, its particles at
rest (its loads are still measured and written, its moorings stepped; its initial velocities apply from the
release): the water settles around it first, as DualSPHysics's ``FtPause``.

Time stepping (with shoal's integrators, stage by stage)
    symplectic and predictor-corrector:  state^{n+1/2} = predict(state^n, loads^n, dt/2), the particles
    placed there, rates at n+1/2, state^{n+1} = advance(state^n, loads^{n+1/2}, dt) (`RigidBody.predict`,
    `RigidBody.advance`: the same position-Verlet scheme as the fluid's symplectic corrector);
    Verlet: state^{n+1} = advance(state^n, loads^n, dt), whose position c^n + dt v^n + dt^2 a^n / 2 is the
    fluid's Verlet position update. As in DualSPHysics (Canelas et al. 2015), the body's loads are those
    of the stage's particle positions, its own update explicit.

The state of every body is the same on every MPI rank (each applies the same summed loads) and goes into
checkpoints (`checkpoint_state`), so a resumed run continues bitwise.
"""

from __future__ import annotations

import base64

import numpy as np

from .body_loads import Gravity, total_loads
from .rigid_body import BodyState

_STATE_FIELDS = BodyState._fields


class FloatingMotion:
    """The motion of a floating body in the model's motion table: the kinematics of its current state.

    Parameters
    ----------
    name : str
        The body's name (its solid's).
    body : shoal.rigid_body.RigidBody
    state : shoal.rigid_body.BodyState
        The state at t = 0.
    loads : list of callables
        The loads besides the fluid's, each ``load(body, state, t) -> (F, T)`` (`shoal.body_loads`).
    friction : float
        Coulomb's friction coefficient of the body's contacts with the walls and other bodies.
    release_time : float
        [s] The body keeps its initial state over every step that starts before this time.
    """

    floating = True

    def __init__(self, name, body, state, loads=(), friction=0.0, release_time=0.0):
        self.name = name
        self.body = body
        self.state = state
        self.friction = float(friction)
        """Coulomb's coefficient mu of the body's contacts (`shoal.physics.contact`)."""
        self.release_time = float(release_time)
        """[s] Held (its state unchanged) over each step that starts before it."""
        self.held = self.release_time > 0.0
        """Whether the current step started before `release_time`: the particles then stand still."""
        self.loads = list(loads)
        self._other = total_loads(body, self.loads)

    @property
    def rotation_axis(self):
        """None for a body that cannot rotate; else its rotation axis (y in 2D: what the model checks), or
        the z axis for a body free to turn about any (the model only asks whether it rotates)."""
        b = self.body
        if b.rotation_mode == "fixed":
            return None
        if b.dim == 2:
            return (0.0, 1.0, 0.0)
        return tuple(float(a) for a in b.axis) if b.axis is not None else (0.0, 0.0, 1.0)

    def rigid_kinematics(self, t, acceleration=True):
        """The kinematics of the current state (`shoal.rigid_body.RigidBody.kinematics`); `t` is the time
        the integrator places the particles at, which the coupling has already stepped the state to. While
        `held`, the state's position and orientation at rest (its initial velocities apply from the release)."""
        s = self.state
        if self.held:
            zero = np.zeros(3)
            s = s._replace(velocity=zero, angular_velocity=zero, acceleration=zero, angular_acceleration=zero)
        return self.body.kinematics(s)

    def add_load(self, load):
        """Add ``load(body, state, t) -> (F, T)`` to the loads besides the fluid's."""
        self.loads.append(load)
        self._other = total_loads(self.body, self.loads)

    def other_loads(self, state, t):
        """(F, T) of the loads besides the fluid's at `state` and time `t`."""
        return self._other(state, t)


class BodyCoupling:
    """The floating bodies of a model and their coupling to the fluid (module docstring).

    An instance without bodies does nothing (the model always has one), so the integrators call it
    unconditionally.

    Parameters
    ----------
    motions : list
        The model's motions; those with ``floating`` true are the bodies, in their order.
    dim : {2, 3}
    """

    def __init__(self, motions=(), dim=3):
        self.dim = dim
        self.moorings = []
        """`shoal.mooring.Mooring` objects holding the bodies (their fairleads' body indices are positions in
        `bodies`); each is stepped once a step, from the bodies' states at its start, and its forces, held
        over the step, are among the bodies' other loads (`floating_bodies`)."""
        self.index = [k for k, m in enumerate(motions) if getattr(m, "floating", False)]
        self.bodies = [motions[k] for k in self.index]
        self.row = np.full(max(len(motions), 1), -1, np.int32)
        for j, k in enumerate(self.index):
            self.row[k] = j
        nb = max(len(self.bodies), 1)
        self.centres = np.zeros((nb, 3))
        self.fluid = np.zeros((nb, 6))
        """F (columns 0-2) and T (3-5) of the fluid on each body at the last rate evaluation [N, N m]: each
        stage reads those of the rates it follows (no rates are computed between them)."""
        self.contact = np.zeros((nb, 6))
        """F and T of the contact forces of the walls and the other bodies (`shoal.physics.contact`), the
        same way."""
        self.joints = []
        """`shoal.joints.JointLoads` between pairs of the bodies, evaluated at every stage."""
        self._joint = np.zeros((nb, 6))
        self._start = [b.state for b in self.bodies]

    def __bool__(self):
        return bool(self.bodies)

    def measure(self, model):
        """The fluid's force and torque on each body now, from the rates just computed
        (`Model.floating_loads`)."""
        if not self.bodies:
            return
        for j, b in enumerate(self.bodies):
            self.centres[j] = b.state.position
        self.fluid[:] = model.floating_loads(self.row, self.centres)
        self.contact[:] = model.floating_loads(self.row, self.centres, contact=True)

    def _total(self, j, state, t):
        f, tq = self.bodies[j].other_loads(state, t)
        loads = self.fluid[j] + self.contact[j] + self._joint[j]
        return f + loads[:3], tq + loads[3:]

    def _joints_now(self):
        """The joints' loads at the bodies' current states, into `_joint`."""
        if self.joints:
            self._joint[:] = 0.0
            bodies, states = [b.body for b in self.bodies], [b.state for b in self.bodies]
            for jl in self.joints:
                jl.add_loads(bodies, states, self._joint)

    def _step_moorings(self, t, dt):
        """MoorDyn from t to t + dt, the fairleads moving from the bodies' states at t (an explicit coupling,
        as MoorDyn's own drivers: the lines' forces at t + dt, held over the step)."""
        if self.moorings:
            bodies, states = [b.body for b in self.bodies], [b.state for b in self.bodies]
            for m in self.moorings:
                m.loads(bodies, states, t, dt)

    def predict(self, t, dt):
        """The half step: each body from its state at `t` to t + dt/2 under the loads measured at `t`."""
        self._step_moorings(t, dt)
        self._joints_now()
        for j, b in enumerate(self.bodies):
            s = b.state
            self._start[j] = s
            b.held = t < b.release_time
            if b.held:
                continue
            f, tq = self._total(j, s, t)
            b.state = b.body.predict(s, f, tq, 0.5 * dt)

    def correct(self, t, dt):
        """The full step of the symplectic and predictor-corrector schemes: from the state at `t` under
        the loads measured at the half step."""
        self._joints_now()
        for j, b in enumerate(self.bodies):
            if b.held:
                continue
            f, tq = self._total(j, b.state, t + 0.5 * dt)
            b.state = b.body.advance(self._start[j], f, tq, dt)

    def advance(self, t, dt):
        """Verlet's step: from the state at `t` under the loads measured at `t`."""
        self._step_moorings(t, dt)
        self._joints_now()
        for j, b in enumerate(self.bodies):
            b.held = t < b.release_time
            if b.held:
                continue
            s = b.state
            f, tq = self._total(j, s, t)
            b.state = b.body.advance(s, f, tq, dt)

    # ------------------------------------------------------------------ checkpoints
    def checkpoint_state(self):
        """{"bodies": each body's state as plain lists of floats (exact in JSON), by name, and whether it is
        held; "moorings": each mooring's state (`shoal.mooring.Mooring.checkpoint_state`), base64 text}."""
        return {"bodies": [{"name": b.name, "held": b.held, **{k: np.asarray(v, float).ravel().tolist()
                                                             for k, v in zip(_STATE_FIELDS, b.state)}}
                           for b in self.bodies],
                "moorings": [base64.b64encode(m.checkpoint_state()).decode("ascii") for m in self.moorings]}

    def restore_state(self, saved):
        """Put back the states of `checkpoint_state`; raises ValueError when the bodies or moorings differ."""
        saved = saved or {}
        if isinstance(saved, list):  # written before moorings: the bodies alone
            saved = {"bodies": saved}
        moorings = saved.get("moorings", [])
        if len(moorings) != len(self.moorings):
            raise ValueError(f"the checkpoint has {len(moorings)} moorings, this case {len(self.moorings)}")
        for m, text in zip(self.moorings, moorings):
            m.restore_state(base64.b64decode(text))
        saved = list(saved.get("bodies", []))
        names = [b.name for b in self.bodies]
        if [s["name"] for s in saved] != names:
            raise ValueError(f"the checkpoint's floating bodies are {[s['name'] for s in saved]}, this case's "
                             f"{names}")
        for b, s in zip(self.bodies, saved):
            fields = {k: np.array(s[k], float) for k in _STATE_FIELDS}
            fields["rotation"] = fields["rotation"].reshape(3, 3)
            b.state = BodyState(**fields)
            b.held = bool(s.get("held", False))
        self._start = [b.state for b in self.bodies]


def _per_width(load, width):
    """`load` divided by `width` [m]: MoorDyn's whole-width forces on a 2D body, which is per metre."""
    def scaled(body, state, t):
        f, tq = load(body, state, t)
        return f / width, tq / width
    return scaled


def floating_bodies(case, gravity):
    """The floating solids of `case` and their moorings: ([`FloatingMotion` of each floating solid, in the
    order of its solids, with gravity `gravity` [m/s^2], its springs and its mooring lines as loads],
    [`shoal.mooring.Mooring` of each of ``case.moorings``, initialised at the bodies' t = 0 states])."""
    from .geometry.generate import solid_nodes
    from .mooring import Mooring

    out = []
    inputs = case.solid_inputs()
    for k, s in enumerate(case.solids):
        if s.floating is None:
            continue
        nodes = solid_nodes(case.dim, case.dp, inputs, k, case.lattice_origin)
        body, state = s.floating.rigid_body(nodes, case.dp, case.dim)
        loads = [Gravity(gravity), *s.floating.springs]
        out.append(FloatingMotion(s.name or f"solid{k}", body, state, loads, friction=s.floating.friction,
                                  release_time=s.floating.release_time))
    names = [b.name for b in out]
    moorings = []
    for spec in case.moorings:
        m = Mooring(spec.file, [(names.index(f.body), f.point) for f in spec.fairleads], origin=spec.origin)
        m.name = spec.name
        m.initialise([b.body for b in out], [b.state for b in out])
        for j in sorted({names.index(f.body) for f in spec.fairleads}):
            load = m.body_load(j)
            out[j].add_load(load if spec.width is None else _per_width(load, spec.width))
        moorings.append(m)
    return out, moorings
