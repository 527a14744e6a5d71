"""Prescribed rigid motion of moving boundary particles (wavemakers, flaps, gates, moving walls).

Each motion m is, at time t, a rigid motion of its body: a rotation R_m(t) about the pivot c_m (a
point of the body at t = 0) followed by the translation d_m(t), with the velocity v_m(t) and the
angular velocity omega_m(t) (Goldstein, Poole & Safko 2002, ch. 4):

    x(t) = c + d(t) + R(t) (x(0) - c),
    u(t) = v(t) + omega(t) x r,                     r = R(t) (x(0) - c) = x(t) - c - d(t),
    a(t) = a_d(t) + alpha(t) x r + omega(t) x (omega(t) x r).

Positions are set from the initial ones, so no drift accumulates. A motion that only translates
(R = I, omega = 0) takes x(t) = x(0) + d(t), u = v(t) exactly, as before rotation existed.
`shoal.motions` gives the kinematics, `Model.move_bodies` evaluates them at the times the integrator
asks for and writes them into the motion table, one row per motion, in the model's internal
coordinates (`motion_layout`, `fill_motion_row`); 2D runs are in the x-z plane, where a rotation is
about the y axis and omega is the one number omega_y.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .spec import MOVING, REPULSIVE_MOVING


class MotionLayout(NamedTuple):
    """Column offsets of a motion's row in the motion table (float64, one row per motion).

    `rot`: R row by row (dim x dim: in 2D the (x, z) block of the 3D matrix), `pivot`: c, `disp`: d,
    `vel`: v, `acc`: a_d (dim each), `omega`, `alpha`: omega and d omega / dt (3 in 3D; omega_y and
    alpha_y in 2D), `rotates`: 1.0 for a motion that may rotate, 0.0 for one that only translates;
    `width`: the row's length."""

    rot: int
    pivot: int
    disp: int
    vel: int
    omega: int
    acc: int
    alpha: int
    rotates: int
    width: int


def motion_layout(dim):
    """The `MotionLayout` of a `dim`-dimensional model (15 columns in 2D, 28 in 3D)."""
    spin = 3 if dim == 3 else 1
    pivot = dim * dim
    disp = pivot + dim
    vel = disp + dim
    omega = vel + dim
    acc = omega + spin
    alpha = acc + dim
    rotates = alpha + spin
    return MotionLayout(0, pivot, disp, vel, omega, acc, alpha, rotates, rotates + 1)


def fill_motion_row(row, dim, state):
    """Write one motion's kinematics into its table row, in the model's internal coordinates.

    Parameters
    ----------
    row : (width,) float64 array
        The motion's row of the table (`motion_layout`).
    dim : {2, 3}
    state : shoal.motions.RigidKinematics
        World 3-vectors ``displacement``, ``velocity``, ``acceleration``, ``angular_velocity``,
        ``angular_acceleration``, ``pivot``, the 3 x 3 ``rotation`` and the flag ``rotates``.
    """
    lay = motion_layout(dim)
    cols = [0, 1, 2] if dim == 3 else [0, 2]
    spin = [0, 1, 2] if dim == 3 else [1]
    row[lay.disp:lay.disp + dim] = np.asarray(state.displacement, float)[cols]
    row[lay.vel:lay.vel + dim] = np.asarray(state.velocity, float)[cols]
    row[lay.acc:lay.acc + dim] = np.asarray(state.acceleration, float)[cols]
    if state.rotates:
        row[lay.rot:lay.rot + dim * dim] = np.asarray(state.rotation, float)[np.ix_(cols, cols)].ravel()
        row[lay.pivot:lay.pivot + dim] = np.asarray(state.pivot, float)[cols]
        row[lay.omega:lay.omega + len(spin)] = np.asarray(state.angular_velocity, float)[spin]
        row[lay.alpha:lay.alpha + len(spin)] = np.asarray(state.angular_acceleration, float)[spin]
        row[lay.rotates] = 1.0
    else:
        row[lay.rot:lay.rot + dim * dim] = np.eye(dim).ravel()
        row[lay.pivot:lay.pivot + dim] = 0.0
        row[lay.omega:lay.omega + len(spin)] = 0.0
        row[lay.alpha:lay.alpha + len(spin)] = 0.0
        row[lay.rotates] = 0.0


def make_body_motion(jit, spec):
    """Return ``move_bodies(i, pos, vel, kind, idp, pos_init, motion_of, table)`` compiled with `jit`.

    `table` is the motion table (`motion_layout`); `motion_of` maps a particle id (`idp`) to its motion;
    `pos_init` holds the positions at t = 0 by id (float64, as `pos`)."""
    dim = spec.dim
    lay = motion_layout(dim)
    ROT, PIV, DISP, VEL, OMG, ROTATES = lay.rot, lay.pivot, lay.disp, lay.vel, lay.omega, lay.rotates

    @jit
    def move_bodies(i, pos, vel, kind, idp, pos_init, motion_of, table):
        """Rigid motion of the moving boundary particles: x = c + d + R (x0 - c), u = v + omega x r,
        r = R (x0 - c) (module docstring); x = x0 + d, u = v for a motion that only translates."""
        if kind[i] == MOVING or kind[i] == REPULSIVE_MOVING:
            p = idp[i]
            m = motion_of[p]
            if table[m, ROTATES] == 0.0:
                for d in range(dim):
                    pos[i, d] = pos_init[p, d] + table[m, DISP + d]
                    vel[i, d] = table[m, VEL + d]
            elif dim == 2:
                # (x, z) plane, rotation about y: omega x r = (omega_y r_z, -omega_y r_x)
                rx = pos_init[p, 0] - table[m, PIV]
                rz = pos_init[p, 1] - table[m, PIV + 1]
                qx = table[m, ROT] * rx + table[m, ROT + 1] * rz
                qz = table[m, ROT + 2] * rx + table[m, ROT + 3] * rz
                pos[i, 0] = table[m, PIV] + table[m, DISP] + qx
                pos[i, 1] = table[m, PIV + 1] + table[m, DISP + 1] + qz
                w = table[m, OMG]
                vel[i, 0] = table[m, VEL] + w * qz
                vel[i, 1] = table[m, VEL + 1] - w * qx
            else:
                rx = pos_init[p, 0] - table[m, PIV]
                ry = pos_init[p, 1] - table[m, PIV + 1]
                rz = pos_init[p, 2] - table[m, PIV + 2]
                qx = table[m, ROT] * rx + table[m, ROT + 1] * ry + table[m, ROT + 2] * rz
                qy = table[m, ROT + 3] * rx + table[m, ROT + 4] * ry + table[m, ROT + 5] * rz
                qz = table[m, ROT + 6] * rx + table[m, ROT + 7] * ry + table[m, ROT + 8] * rz
                pos[i, 0] = table[m, PIV] + table[m, DISP] + qx
                pos[i, 1] = table[m, PIV + 1] + table[m, DISP + 1] + qy
                pos[i, 2] = table[m, PIV + 2] + table[m, DISP + 2] + qz
                wx, wy, wz = table[m, OMG], table[m, OMG + 1], table[m, OMG + 2]
                vel[i, 0] = table[m, VEL] + (wy * qz - wz * qy)
                vel[i, 1] = table[m, VEL + 1] + (wz * qx - wx * qz)
                vel[i, 2] = table[m, VEL + 2] + (wx * qy - wy * qx)

    return move_bodies


def make_wall_vector_rotation(jit, spec):
    """Return ``rotate_wall_vectors(i, kind, idp, motion_of, table, id0, initial, current)`` compiled with
    `jit`: current[p - id0] = R_m initial[p - id0] for a moving dynamic boundary particle i (id p) of a
    motion m that rotates.

    The tables indexed by particle id less `id0` that hold a direction fixed to the wall -- the mDBC
    ghost vectors (`shoal.physics.mdbc`) and the Riemann wall normals (`shoal.physics.riemann`) -- turn
    with the wall; `initial` holds them at t = 0. A translating wall leaves them as they are."""
    dim = spec.dim
    lay = motion_layout(dim)
    ROT, ROTATES = lay.rot, lay.rotates

    @jit
    def rotate_wall_vectors(i, kind, idp, motion_of, table, id0, initial, current):
        """g(t) = R(t) g(0) for the wall vector g of a moving dynamic boundary particle."""
        if kind[i] == MOVING:
            p = idp[i]
            m = motion_of[p]
            if table[m, ROTATES] != 0.0:
                row = p - id0
                if dim == 2:
                    gx, gz = initial[row, 0], initial[row, 1]
                    current[row, 0] = table[m, ROT] * gx + table[m, ROT + 1] * gz
                    current[row, 1] = table[m, ROT + 2] * gx + table[m, ROT + 3] * gz
                else:
                    gx, gy, gz = initial[row, 0], initial[row, 1], initial[row, 2]
                    for d in range(3):
                        current[row, d] = (table[m, ROT + 3 * d] * gx + table[m, ROT + 3 * d + 1] * gy
                                           + table[m, ROT + 3 * d + 2] * gz)

    return rotate_wall_vectors
