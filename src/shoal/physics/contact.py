"""Contact of floating bodies with the walls and with each other: a normal spring-dashpot between particles.

Boundary particles do not interact with each other in SPH (a wall's pressure acts on the fluid only), so
without this a floating body would pass through the bed, a wall or another body. Each particle b of a
floating body is pushed away from every dynamic boundary particle w of another solid (a fixed wall, a
paddle, another body) closer than the contact distance d_c = dp, the spacing at which two lattice cells
touch (each particle stands for a cell of side dp):

    F_b += max(k (d_c - r) - c v_n, 0) e,    e = (x_b - x_w) / r,   v_n = (u_b - u_w) . e,   r = |x_b - x_w|,

a linear normal spring-dashpot (the discrete-element contact of Cundall & Strack 1979) that never
attracts. The stiffness is that of the water itself: a layer of fluid of thickness dp compressed by
delta = d_c - r pushes with the pressure rho0 c0^2 delta / dp on a face dp^(dim-1), so

    k = rho0 c0^2 dp^(dim-2),   c = 2 sqrt(k m),   m = rho0 dp^dim

(critically damped for a particle of the water's mass; a body with more mass per contact rebounds a little,
with the restitution exp(-pi zeta / sqrt(1 - zeta^2)), zeta = sqrt(m / m_contact): a box of 40 kg/m meeting
a wall with 10 particles, 0.35), and a contact resolves in the time step the fluid already takes (its period
2 pi sqrt(m / k) = 2 pi dp / c0, some 40 of the acoustic time steps CFL h / c0).
Why this and not the walls' own pressure (DualSPHysics's floating particles meet the walls through the
dynamic boundary condition, as fluid does): a body's particles are walls here, whose pressure comes from
the fluid, so a body with no water between it and the bed would feel nothing; a contact force acts
whatever the water does, and its stiffness keeps the overlap of a resting body to k / (its weight per
contact), far below dp. Tangential friction is not modelled: a body slides freely along a wall.

The force goes into the body's loads (`shoal.body_coupling`) and, summed like the fluid's, over MPI ranks;
a wall's reaction is not applied (walls do not move), another body's is its own particles' sum.
"""

from .rates import make_store
from .spec import FIXED, MOVING


def contact_constants(rho0, c0, dp, dim):
    """(d_c [m], k, c) of the contact force (module docstring): d_c = dp, k = rho0 c0^2 dp^(dim-2) [N/m; 2D:
    N/m per metre], c = 2 sqrt(k rho0 dp^dim) [N s/m; 2D: per metre]."""
    k = rho0 * c0 * c0 * dp ** (dim - 2)
    return dp, k, 2.0 * (k * rho0 * dp ** dim) ** 0.5


def make_contact(jit, spec, make_gather, unpack):
    """Return ``particle_contact(i, pos, vel, kind, idp, motion_of, row, cell, cell_start, grid_dims, Parr,
    dc, k, c, force)`` writing into ``force[i]`` (internal components) the contact force on particle i of a
    floating body (``row[motion_of[idp[i]]] >= 0``), zero for every other particle."""
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)

    @jit
    def contact_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        fx, fy, fz = acc
        m, ux, uy, uz, dc, k, c = own
        vel, kind, idp, motion_of = data
        kj = kind[j]
        if kj != FIXED and kj != MOVING:
            return acc
        if kj == MOVING and motion_of[idp[j]] == m:
            return acc  # the body's own particle
        if r2 >= dc * dc or r2 <= 0.0:
            return acc
        r = r2 ** 0.5
        vjx = vel[j, 0]
        vjz = vel[j, dim - 1]
        vjy = sy * vel[j, 1] if dim == 3 else zero
        vn = ((ux - vjx) * dx + (uy - vjy) * dy + (uz - vjz) * dz) / r
        f = k * (dc - r) - c * vn
        if f <= 0.0:
            return acc
        f = f / r
        return fx + f * dx, fy + f * dy, fz + f * dz

    gather = make_gather(jit, spec, contact_pair)
    store = make_store(jit, spec)

    @jit
    def particle_contact(i, pos, vel, kind, idp, motion_of, row, cell, cell_start, grid_dims, Parr, dc, k, c, force):
        for d in range(dim):
            force[i, d] = zero
        if kind[i] != MOVING:
            return
        m = motion_of[idp[i]]
        if row[m] < 0:
            return
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        ux = float(vel[i, 0])
        uz = float(vel[i, dim - 1])
        uy = float(vel[i, 1]) if dim == 3 else 0.0
        fx, fy, fz = gather(i, (m, ux, uy, uz, dc, k, c), (0.0, 0.0, 0.0), pos, cell, cell_start, gdims,
                            (vel, kind, idp, motion_of), P)
        store(force, i, 1.0, fx, fy, fz)

    return particle_contact
