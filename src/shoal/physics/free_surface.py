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

Dry wall particles -- those of a wall rising above the water, with no fluid
particle within 2h at their own height or above (higher than 0.35 h below
them, "height" against gravity) -- take part in neither sum. Marrone et al.'s
walls are mirror images of the fluid, so above the water they have none; a
particle wall does, and at the contact line those particles tilt the normal
towards the air by 45 degrees and stand at the edge of the wider cone, so the
top particle next to a side wall went either way (64 of the 100 top particles
of a 3D tank were flagged before this).
"""

from .spec import FLUID


def make_free_surface(jit, spec, kernels, make_gather, unpack):
    """Return ``(wet_walls, free_surface, surface_normal)``:
    ``wet_walls(i, pos, kind, cell, cell_start, grid_dims, Parr, wet)`` sets wet[i] = 1 for a fluid
    particle and for a boundary particle with a fluid neighbour within 2h not lower than 0.35 h below
    it, else 0; ``free_surface(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, wet, out)``:
    out[i] = 1 for a free-surface fluid particle, else 0 (dry boundary particles ignored);
    ``surface_normal(i, pos, rho, kind, cell, cell_start, gdims, P, planes, wet)``: the unit normal of step 1
    (a device function for other per-particle functions, `shoal.physics.shifting`)."""
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    cos_fluid = F(0.8660254037844387)   # cos(pi/6)
    cos_wall = F(0.7071067811865476)    # cos(pi/4)
    _, grad_factor = kernels

    @jit
    def wet_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        ux, uy, uz, lim = own
        kind = data
        # (dx, dy, dz) = r_i - r_j: j is not lower than lim below i when (r_j - r_i) . up >= -lim
        # (no short-circuit: a conditional read of `kind` kept a reference count per pair)
        fluid = kind[j] == FLUID
        return acc | (fluid & (ux * dx + uy * dy + uz * dz <= lim))

    gather_wet = make_gather(jit, spec, wet_pair)

    @jit
    def wet_walls(i, pos, kind, cell, cell_start, grid_dims, Parr, wet):
        P = unpack(Parr)
        if kind[i] == FLUID:
            wet[i] = 1
            return
        g2 = P.gx * P.gx + P.gy * P.gy + P.gz * P.gz
        if g2 == zero:
            wet[i] = 1  # no "up" without gravity: every wall counts
            return
        inv = one / g2 ** F(0.5)
        up = (-P.gx * inv, -P.gy * inv, -P.gz * inv)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        w = gather_wet(i, (up[0], up[1], up[2], F(0.35) * P.h), False, pos, cell, cell_start, gdims, kind, P)
        wet[i] = 1 if w else 0

    @jit
    def grad_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        gx, gy, gz, nb, nbound = acc
        rho, kind, wet = data
        if wet[j] == 0:
            return acc
        fr = grad_factor(r2 ** F(0.5) * P.inv_h, P)
        mj = P.mass_f if kind[j] == FLUID else P.mass_b
        v = mj / rho[j] * fr
        return gx + v * dx, gy + v * dy, gz + v * dz, nb + 1, nbound + (0 if kind[j] == FLUID else 1)

    @jit
    def cone_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        nx, ny, nz, cmin = own
        rho, kind, wet = data
        if wet[j] == 0:
            return acc
        # r_j - r_i = -(dx, dy, dz)
        c = -(nx * dx + ny * dy + nz * dz) / r2 ** F(0.5)
        return acc or c > cmin

    gather_grad = make_gather(jit, spec, grad_pair)
    gather_cone = make_gather(jit, spec, cone_pair)

    @jit
    def surface_normal(i, pos, rho, kind, cell, cell_start, gdims, P, planes, wet):
        """(nx, ny, nz, nb, nbound): particle i's unit normal n_i = -sum_j V_j grad_i W_ij / |...| (step 1
        of the module docstring, the plane-normal correction included; (0, 0, 0) when the sum vanishes,
        a fully surrounded particle), and its numbers of wet neighbours and of boundary ones among
        them. In 2D the normal's components are (x, 0, z)."""
        data = (rho, kind, wet)
        gx, gy, gz, nb, nbound = gather_grad(i, 0, (zero, zero, zero, 0, 0), pos, cell, cell_start, gdims,
                                             data, P)
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
            return zero, zero, zero, nb, nbound
        return nx / norm, ny / norm, nz / norm, nb, nbound

    @jit
    def free_surface(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, wet, out):
        P = unpack(Parr)
        out[i] = 0
        if kind[i] != FLUID:
            return
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        nx, ny, nz, nb, nbound = surface_normal(i, pos, rho, kind, cell, cell_start, gdims, P, planes, wet)
        if nb == 0:
            out[i] = 1
            return
        if nx == zero and ny == zero and nz == zero:
            return  # a fully surrounded particle
        cmin = cos_wall if nbound > 0 else cos_fluid
        covered = gather_cone(i, (nx, ny, nz, cmin), False, pos, cell, cell_start, gdims, (rho, kind, wet), P)
        if not covered:
            out[i] = 1

    return wet_walls, free_surface, surface_normal
