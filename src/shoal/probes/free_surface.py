"""Free-surface detection after Marrone et al. (2010), as the rip-current
paper applies it in GPUSPH.

1. A normal from the kernel-gradient sum over all neighbours (fluid and
   boundary particles, V_j = m_j / rho_j):
       n_i = - sum_j V_j grad_i W_ij / |sum_j V_j grad_i W_ij|,
   pointing out of the fluid (grad_i W_ij points from i towards j).
   Near a wall plane the sum misses the plane's side, so the component of
   n_i pointing into a plane within 2h is removed (the plane-normal
   correction).
2. The cone test: particle i is on the free surface when no neighbour j
   within 2h lies inside the cone of half-angle pi/6 around n_i,
   angle(r_j - r_i, n_i) < pi/6; near boundary particles (some within 2h)
   the cone opens to pi/4, as wall particles sit on a coarser, offset
   pattern.
A particle without any neighbour is a surface particle (a spray drop).
"""

from ..physics.spec import FLUID


def make_free_surface(jit, spec, kernels, make_gather, unpack):
    """Return ``free_surface(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, out)``:
    out[i] = 1 for a free-surface fluid particle, else 0."""
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    cos_fluid = F(0.8660254037844387)   # cos(pi/6)
    cos_wall = F(0.7071067811865476)    # cos(pi/4)
    _, grad_factor = kernels

    @jit
    def grad_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        gx, gy, gz, nb, nbound = acc
        rho, kind = data
        fr = grad_factor(r2 ** F(0.5) * P.inv_h, P)
        mj = P.mass_f if kind[j] == FLUID else P.mass_b
        v = mj / rho[j] * fr
        return gx + v * dx, gy + v * dy, gz + v * dz, nb + 1, nbound + (0 if kind[j] == FLUID else 1)

    @jit
    def cone_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        nx, ny, nz, cmin = own
        # r_j - r_i = -(dx, dy, dz)
        c = -(nx * dx + ny * dy + nz * dz) / r2 ** F(0.5)
        return acc or c > cmin

    gather_grad = make_gather(jit, spec, grad_pair)
    gather_cone = make_gather(jit, spec, cone_pair)

    @jit
    def free_surface(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, out):
        P = unpack(Parr)
        out[i] = 0
        if kind[i] != FLUID:
            return
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        data = (rho, kind)
        gx, gy, gz, nb, nbound = gather_grad(i, 0, (zero, zero, zero, 0, 0), pos, cell, cell_start, gdims,
                                             data, P)
        if nb == 0:
            out[i] = 1
            return
        # n = -sum V grad W; grad_i W_ij = fr r_ij, summed above as (gx, gy, gz)
        nx, ny, nz = -gx, -gy, -gz
        # plane-normal correction: drop the part of n pointing into a plane within 2h
        for k in range(planes.shape[0]):
            px, py, pz = F(planes[k, 0]), F(planes[k, 1]), F(planes[k, 2])
            if dim == 2:
                d = planes[k, 0] * pos[i, 0] + planes[k, 2] * pos[i, 1] - planes[k, 3]
                pnx, pny, pnz = px, zero, pz
            else:
                d = planes[k, 0] * pos[i, 0] + planes[k, 1] * pos[i, 1] + planes[k, 2] * pos[i, 2] - planes[k, 3]
                pnx, pny, pnz = px, py, pz
            if d < 2.0 * P.h:
                dot = nx * pnx + ny * pny + nz * pnz
                if dot < zero:
                    nx -= dot * pnx
                    ny -= dot * pny
                    nz -= dot * pnz
        norm = (nx * nx + ny * ny + nz * nz) ** F(0.5)
        if norm == zero:
            return  # a fully surrounded particle
        nx, ny, nz = nx / norm, ny / norm, nz / norm
        cmin = cos_wall if nbound > 0 else cos_fluid
        covered = gather_cone(i, (nx, ny, nz, cmin), False, pos, cell, cell_start, gdims, data, P)
        if not covered:
            out[i] = 1

    return free_surface
