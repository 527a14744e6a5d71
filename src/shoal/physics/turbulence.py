"""Sub-particle-scale (SPS) turbulence: a Smagorinsky eddy viscosity.

Dalrymple & Rogers (2006), after Gotoh, Shibahara & Sakai (2001) and as in
DualSPHysics. With the strain rate S_ab = (d_b v_a + d_a v_b) / 2 and
|S| = sqrt(2 S_ab S_ab), the SPS stress per unit density is

    tau_ab / rho = 2 nu_t S_ab - (2/3) k delta_ab - (2/3) C_I dp^2 |S|^2 delta_ab,
    nu_t = (Cs dp)^2 |S|,   k = nu_t div(v)   (DualSPHysics' closure),

and it enters the momentum equation as

    dv_i/dt += sum_j m_j (tau_i / rho_i^2 + tau_j / rho_j^2) . grad_i W_ij,

between fluid particles. The velocity gradient is the SPH gradient
d_b v_a (r_i) = sum_j V_j (v_ja - v_ia) d_b W_ij, V_j = m_j / rho_j, over
all neighbours (walls carry their velocity: zero, or the motion's). Each
particle stores tau / rho^2 -- the 6 (3D: xx, xy, xz, yy, yz, zz) or 3 (2D:
xx, xz, zz) components -- once per rate evaluation, before the forces.
"""

from .spec import FLUID

N_TAU = {2: 3, 3: 6}


def make_sps(jit, spec, kernels, make_gather, unpack):
    """Return ``particle_sps(i, pos, vel, rho, kind, cell, cell_start, grid_dims, Parr, tau)``
    writing tau_i / rho_i^2 (zero for boundary particles)."""
    F = spec.float_type
    dim = spec.dim
    zero, half, two, third2 = F(0.0), F(0.5), F(2.0), F(2.0 / 3.0)
    _, grad_factor = kernels

    @jit
    def grad_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        gxx, gxy, gxz, gyx, gyy, gyz, gzx, gzy, gzz = acc
        vix, viy, viz = own
        vel, rho, kind = data
        fr = grad_factor(r2 ** F(0.5) * P.inv_h, P)
        mj = P.mass_f if kind[j] == FLUID else P.mass_b
        vj = mj / rho[j] * fr
        ux = vel[j, 0] - vix
        uz = vel[j, dim - 1] - viz
        uy = (sy * vel[j, 1] - viy) if dim == 3 else zero
        # d_b v_a = sum V_j (v_j - v_i)_a fr (r_i - r_j)_b
        return (gxx + vj * ux * dx, gxy + vj * ux * dy, gxz + vj * ux * dz,
                gyx + vj * uy * dx, gyy + vj * uy * dy, gyz + vj * uy * dz,
                gzx + vj * uz * dx, gzy + vj * uz * dy, gzz + vj * uz * dz)

    gather = make_gather(jit, spec, grad_pair)

    @jit
    def particle_sps(i, pos, vel, rho, kind, cell, cell_start, grid_dims, Parr, tau):
        P = unpack(Parr)
        if kind[i] != FLUID:
            for c in range(tau.shape[1]):
                tau[i, c] = zero
            return
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        vix = vel[i, 0]
        viz = vel[i, dim - 1]
        viy = vel[i, 1] if dim == 3 else zero
        acc = (zero, zero, zero, zero, zero, zero, zero, zero, zero)
        gxx, gxy, gxz, gyx, gyy, gyz, gzx, gzy, gzz = gather(i, (vix, viy, viz), acc, pos, cell, cell_start,
                                                              gdims, (vel, rho, kind), P)
        sxx, syy, szz = gxx, gyy, gzz
        sxy = half * (gxy + gyx)
        sxz = half * (gxz + gzx)
        syz = half * (gyz + gzy)
        s2 = two * (sxx * sxx + syy * syy + szz * szz) + F(4.0) * (sxy * sxy + sxz * sxz + syz * syz)
        nut = P.sps_smag * s2 ** F(0.5)
        iso = third2 * nut * (sxx + syy + szz) + P.sps_blin * s2
        r = rho[i]
        k = F(1.0) / r  # tau / rho^2 = (tau / rho) / rho
        if dim == 3:
            tau[i, 0] = k * (two * nut * sxx - iso)
            tau[i, 1] = k * (two * nut * sxy)
            tau[i, 2] = k * (two * nut * sxz)
            tau[i, 3] = k * (two * nut * syy - iso)
            tau[i, 4] = k * (two * nut * syz)
            tau[i, 5] = k * (two * nut * szz - iso)
        else:
            tau[i, 0] = k * (two * nut * sxx - iso)
            tau[i, 1] = k * (two * nut * sxz)
            tau[i, 2] = k * (two * nut * szz - iso)

    return particle_sps
