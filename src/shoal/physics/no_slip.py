"""No-slip walls for the viscous term: the boundary velocity of Adami, Hu &
Adams (2012), as PySPH's ``SolidWallNoSlipBC``.

A dynamic boundary particle carries the wall's velocity u_w (zero, or the
motion's). Used as it is in the viscous term, the fluid sticks to the
boundary particles, so the no-slip plane sits at the first boundary layer,
about half a spacing behind the wall surface. With ``no_slip = true`` the
viscous term sees each boundary particle b with the velocity

    u_b = 2 u_w - u~_b,   u~_b = sum_f u_f W_bf / sum_f W_bf

(Adami et al. 2012, Eq. 22-23): u~_b is the Shepard-interpolated fluid
velocity at the boundary particle, so the fluid velocity is extrapolated
antisymmetrically through the wall and the interpolated velocity vanishes
(relative to the wall) at the wall surface instead of at the particles.
Continuity, pressure and the time-step limit still use u_w. A boundary
particle with no fluid neighbour keeps u_b = u_w.

Reference: S. Adami, X. Y. Hu, N. A. Adams, "A generalized wall boundary
condition for smoothed particle hydrodynamics", J. Comput. Phys. 231
(2012) 7057-7075.
"""

from .spec import FLUID, REPULSIVE


def make_wall_velocity(jit, spec, kernels, make_gather, unpack):
    """Return ``particle_wall_velocity(i, pos, vel, kind, cell, cell_start, grid_dims, Parr, vwall)``
    writing u_b = 2 u_w - u~_b of boundary particle i into ``vwall[i]`` (fluid
    particles: their own velocity)."""
    F = spec.float_type
    dim = spec.dim
    zero, two = F(0.0), F(2.0)
    w, _ = kernels

    @jit
    def sum_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        s, ux, uy, uz = acc
        vel, kind = data
        if kind[j] != FLUID:
            return acc
        wq = w(r2 ** F(0.5) * P.inv_h, P)
        vy = sy * vel[j, 1] if dim == 3 else zero
        return s + wq, ux + wq * vel[j, 0], uy + wq * vy, uz + wq * vel[j, dim - 1]

    gather = make_gather(jit, spec, sum_pair)

    @jit
    def particle_wall_velocity(i, pos, vel, kind, cell, cell_start, grid_dims, Parr, vwall):
        if kind[i] == FLUID or kind[i] >= REPULSIVE:
            for d in range(dim):
                vwall[i, d] = vel[i, d]
            return
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        s, ux, uy, uz = gather(i, (zero,), (zero, zero, zero, zero), pos, cell, cell_start, gdims, (vel, kind), P)
        if s > zero:
            inv = F(1.0) / s
            vwall[i, 0] = two * vel[i, 0] - ux * inv
            vwall[i, dim - 1] = two * vel[i, dim - 1] - uz * inv
            if dim == 3:
                vwall[i, 1] = two * vel[i, 1] - uy * inv
        else:
            for d in range(dim):
                vwall[i, d] = vel[i, d]

    return particle_wall_velocity
