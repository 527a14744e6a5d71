"""The force the fluid exerts on each dynamic boundary particle (all backends).

A fluid particle a feels from a boundary particle b the pair acceleration of the momentum equation
(`shoal.physics.rates`),

    dv_a/dt |_b = -m_b (p_a/rho_a^2 + p_b/rho_b^2 + R_ab + Pi_ab) grad_a W_ab + lam_ab (v_a - u_b),

(Pi_ab the artificial and lam_ab the laminar viscous term times `visco_bound_factor`; u_b the
boundary particle's velocity, or its no-slip velocity with ``no_slip``). By Newton's third law the
fluid pushes b with the opposite force,

    F_b = -sum_a m_a dv_a/dt |_b
        = m_b sum_a [ -m_a (p_a/rho_a^2 + p_b/rho_b^2 + R_ab + Pi_ab) grad_b W_ab + lam_ba (u_b - v_a) ],

which this pass evaluates per boundary particle, from its fluid neighbours, with the same terms as the
rates: summed over a body's particles it is the hydrodynamic force on the body (DualSPHysics's
ComputeForces does the same sum over a body's boundary particles), and over every wall it balances the
fluid's momentum budget exactly. [N]; 2D: per metre of width [N/m]. Fluid and repulsive
(Monaghan-Kajtar) particles get 0.
"""

from .rates import make_store, make_tensile
from .reciprocals import make_reciprocals
from .riemann import make_riemann
from .spec import FIXED, FLUID, MOVING


def make_wall_force(jit, spec, kernels, viscous, make_gather, unpack):
    """Return ``particle_wall_force(i, pos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr,
    vwall, idp, ghosts, gid0, only_moving, force)`` writing F_b of boundary particle i into ``force[i]``
    (internal components); `ghosts`, `gid0` as for the rates (`shoal.physics.rates`); with `only_moving`,
    of the moving boundary particles only (the floating bodies' loads need no more), 0 on the others."""
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)
    w, grad_factor = kernels
    tensile = spec.tensile
    no_slip = spec.no_slip
    tensile_coef, tensile_pair = make_tensile(jit, spec, w)
    store = make_store(jit, spec)
    reciprocals = make_reciprocals(jit, spec)
    riemann = spec.riemann
    _, wall_jump = make_riemann(jit, spec)
    one = F(1.0)

    @jit
    def force_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        fx, fy, fz = acc
        ubx, uby, ubz, rhob, pr2b, tb, wbx, wby, wbz, row = own
        vel, rho, pr2, kind, ghosts = data
        if kind[j] != FLUID:
            return acc
        q = r2 ** F(0.5) * P.inv_h
        fr = grad_factor(q, P)
        vjx = vel[j, 0]
        vjz = vel[j, dim - 1]
        vjy = sy * vel[j, 1] if dim == 3 else zero
        ux, uy, uz = ubx - vjx, uby - vjy, ubz - vjz  # u_b - v_a
        vdotr = ux * dx + uy * dy + uz * dz            # (u_b - v_a) . (r_b - r_a) = v_ab . r_ab
        pr2a = pr2[j]
        prs = pr2a + pr2b
        if riemann and row >= 0:
            # the Riemann dissipation along the wall's normal, as the rates add it (`shoal.physics.riemann`)
            # (with the opposite sign: the force on the wall)
            rhoa = rho[j]
            dp, nx, ny, nz = wall_jump(vjx - wbx, vjy - wby, vjz - wbz, ghosts, row, one, rhoa, rhob, P)
            c = P.mass_f * F(2.0) * dp / (rhoa * rhob) * fr * r2 ** F(0.5)
            fx += c * nx
            fy += c * ny
            fz += c * nz
        if tensile:
            prs += tensile_pair(q, tensile_coef(pr2a), tb, P)
        inv_a, inv_s, _ = reciprocals(r2, P.eta2, rho[j], rhob)
        pi_ab, lam = viscous(vdotr, r2, fr, P.mass_f, inv_a, inv_s, P)
        pi_ab *= P.visc_bound
        lam *= P.visc_bound
        f = -P.mass_f * (prs + pi_ab) * fr
        return fx + f * dx + lam * ux, fy + f * dy + lam * uy, fz + f * dz + lam * uz

    gather = make_gather(jit, spec, force_pair)

    @jit
    def particle_wall_force(i, pos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, vwall, idp, ghosts, gid0,
                            only_moving, force):
        P = unpack(Parr)
        for d in range(dim):
            force[i, d] = zero
        k = kind[i]
        if k != MOVING and (only_moving or k != FIXED):
            return
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        u = vwall if no_slip else vel
        ubx = u[i, 0]
        ubz = u[i, dim - 1]
        uby = u[i, 1] if dim == 3 else zero
        pr2b = pr2[i]
        tb = tensile_coef(pr2b)
        row = idp[i] - gid0 if gid0 >= 0 else -1
        wbx = vel[i, 0]
        wbz = vel[i, dim - 1]
        wby = vel[i, 1] if dim == 3 else zero
        fx, fy, fz = gather(i, (ubx, uby, ubz, rho[i], pr2b, tb, wbx, wby, wbz, row), (zero, zero, zero), pos, cell,
                            cell_start, gdims, (vel, rho, pr2, kind, ghosts), P)
        store(force, i, P.mass_b, fx, fy, fz)

    return particle_wall_force
