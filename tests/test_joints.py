"""Joints between floating bodies (`shoal.joints`): pins and hinges held by a stiff spring-damper."""

from __future__ import annotations

import numpy as np
import pytest

import shoal
from shoal.body_coupling import BodyCoupling, FloatingMotion
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.floating import FloatingBody
from shoal.geometry import Box, Tank
from shoal.joints import Joint, JointLoads
from shoal.mass_properties import MassProperties
from shoal.rigid_body import RigidBody


def _pair(axis=None, dt=1e-3):
    """Two bodies in space (no gravity, no fluid) pinned or hinged at the origin: A (2 kg) at (-0.3, 0, 0), B
    (1 kg) at (0.25, 0.1, 0), with velocities and spins that load the joint; omega_j = 0.2 / dt."""
    a = RigidBody(MassProperties(2.0, np.array([-0.3, 0.0, 0.0]), np.diag([0.02, 0.05, 0.06])))
    b = RigidBody(MassProperties(1.0, np.array([0.25, 0.1, 0.0]), np.diag([0.01, 0.03, 0.035])))
    sa = a.initial_state((0.1, 0.2, -0.1), (0.5, -1.0, 2.0))
    sb = b.initial_state((-0.2, 0.0, 0.3), (-1.0, 0.5, 0.0))
    coupling = BodyCoupling([FloatingMotion("a", a, sa), FloatingMotion("b", b, sb)], dim=3)
    coupling.joints = [JointLoads(0, 1, (0.0, 0.0, 0.0), axis, a, b, 0.2 / dt)]
    return coupling


def _momenta(coupling):
    """(total linear momentum, total angular momentum about the origin) of the bodies."""
    p, big_l = np.zeros(3), np.zeros(3)
    for m in coupling.bodies:
        s, body = m.state, m.body
        p += body.mass * s.velocity
        big_l += np.cross(s.position, body.mass * s.velocity) + body.angular_momentum(s)
    return p, big_l


@pytest.mark.parametrize("axis", [None, (0.0, 0.0, 1.0)], ids=["pin", "hinge"])
def test_joint_loads_are_internal_and_hold_the_bodies_together(axis):
    """Two bodies thrown and spun apart, tied by a pin (or a hinge about z), 2000 steps of the symplectic
    stages with nothing but the joint: their total momentum is conserved to round-off (the joint's force
    and its reaction, equal and opposite at each stage; measured 3e-15), their angular momentum about the
    origin to 1e-3 (the pair of forces acts at the joint's two points, a gap apart, which the start's
    transient opens to 1.3 mm while the spring takes up the initial mismatch of velocities; measured
    7.7e-4), the gap stays under 1 mm for bodies half a metre apart after that transient (measured 0.02 mm),
    and a hinge keeps the two bodies' axes within 1e-2 rad of each other (measured 6e-5 rad)."""
    coupling = _pair(axis)
    p0, l0 = _momenta(coupling)
    dt, gaps, angles = 1e-3, [], []
    bodies = [m.body for m in coupling.bodies]
    for n in range(2000):
        coupling.predict(n * dt, dt)
        coupling.correct(n * dt, dt)
        states = [m.state for m in coupling.bodies]
        gaps.append(coupling.joints[0].gap(bodies, states))
        if axis is not None:
            za, zb = states[0].rotation[:, 2], states[1].rotation[:, 2]
            angles.append(np.arccos(np.clip(za @ zb, -1, 1)))
    p1, l1 = _momenta(coupling)
    assert np.allclose(p1, p0, rtol=0, atol=1e-12 * np.abs(p0).max())
    assert np.allclose(l1, l0, rtol=0, atol=1e-3 * np.abs(l0).max())
    assert max(gaps[200:]) < 1e-3
    if axis is not None:
        assert max(angles[200:]) < 1e-2


def test_hinged_pontoons_in_water(tmp_path):
    """Two pontoons (0.3 x 0.1 m, density 500) side by side in a 2D tank, pinned at their adjacent top corners,
    the left one released 1 dp high: they ride on the water together, the joint's gap under 1e-3 dp at every
    row of the bodies' CSVs, and the right one, pulled by the left, moves."""
    dp, d = 0.02, 0.3
    pontoon = dict(density=500.0, interval=0.01)
    case = Case(name="raft", dim=2, dp=dp, end_time=0.4, fluid=Fluid(depth=d, surface_level=d),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.4, 0, 0.6))),
                        Solid(name="left", shape=Box(lo=(0.4, 0, 0.27), hi=(0.7, 0, 0.37)),
                              floating=FloatingBody(**pontoon)),
                        Solid(name="right", shape=Box(lo=(0.7, 0, 0.25), hi=(1.0, 0, 0.35)),
                              floating=FloatingBody(**pontoon))],
                joints=[Joint(bodies=["left", "right"], point=(0.7, 0, 0.35))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.4, 0, d)))], output=Output(interval=0.4))
    shoal.run_case(case, tmp_path / "run", plot=False, progress=False, handle_signals=False)
    rows = {n: np.loadtxt(tmp_path / "run" / f"body_{n}.csv", delimiter=",", skiprows=1) for n in ("left", "right")}
    # the joint's point on each body: c + R (x0 - c0), R about y by the pitch column (deg)
    ends = {}
    for n, x0 in (("left", (0.55, 0.32)), ("right", (0.85, 0.30))):
        r = rows[n]
        a = np.radians(r[:, 9])
        rx, rz = 0.7 - x0[0], 0.35 - x0[1]
        ends[n] = np.c_[r[:, 1] + np.cos(a) * rx + np.sin(a) * rz, r[:, 3] - np.sin(a) * rx + np.cos(a) * rz]
    assert np.max(np.linalg.norm(ends["left"] - ends["right"], axis=1)) < 1e-3 * dp
    assert np.ptp(rows["right"][:, 3]) > 0.05 * dp


def test_joint_errors():
    with pytest.raises(ValueError, match="a joint ties two different bodies"):
        Joint(bodies=["a", "a"], point=(0, 0, 0))
    with pytest.raises(ValueError, match="no axis"):
        Joint(bodies=["a", "b"], point=(0, 0, 0), axis=(0, 0, 0))
    with pytest.raises(ValueError, match=r"joints\[0\].bodies\[1\] = 'ghost' is no floating solid"):
        Case(name="j", dim=2, dp=0.02, fluid=Fluid(depth=0.3), fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1, 0, 0.3)))],
             solids=[Solid(name="a", shape=Box(lo=(0.4, 0, 0.25), hi=(0.6, 0, 0.35)), floating=FloatingBody(density=500.0))],
             joints=[Joint(bodies=["a", "ghost"], point=(0.5, 0, 0.3))])
