"""The rates of one pair for both of its particles at once (Newton's third law), for the CPU's pair sweep.

The pair terms of `shoal.physics.rates` are symmetric or antisymmetric in the pair. With
r_ij = r_i - r_j, v_ij = v_i - v_j, grad_i W_ij = F(r) r_ij (F = `grad_factor`, so
grad_j W_ji = -grad_i W_ij) and the masses m_i, m_j of the two particles' kinds, one evaluation of
the pair gives both particles' terms:

    a_i += -m_j V,    a_j += +m_i V,    V = (p_i/rho_i^2 + p_j/rho_j^2 + R_ij + b Pi_ij) F r_ij - b l_ij v_ij
    drho_i += m_j v_ij . r_ij F + D_ij,    drho_j += m_i v_ij . r_ij F + D_ji
    xsph_i -= eps m_j W_ij v_ij / rho_ij,  xsph_j += eps m_i W_ij v_ij / rho_ij  (fluid pairs)

where R_ij is the tensile correction, Pi_ij the artificial viscosity (symmetric: v_ij . r_ij and
rho_i + rho_j are), l_ij = lam_ij / m_j the laminar coefficient per unit mass, b = 1 between fluid
particles and `visc_bound` against a wall, and D the density diffusion between fluid particles,
which is not symmetric (D_ji is `density_diffusion` with the roles swapped: its density difference
and 1/rho change sides). The time-step term |h v_ij . r_ij / (r_ij^2 + eta^2)| is the same for
both. A wall particle receives no acceleration; with DBC it integrates continuity with its fluid
neighbours (`rates`' ``bound_pair``: the same m_fluid v_ij . r_ij F), otherwise nothing; wall-wall
pairs are not evaluated. These are the terms `rates` sums particle by particle (the CUDA backend
and the CPU's other schemes), summed here in another order: the results agree to round-off
(`tests/test_mutual_rates.py`).

Each pair is then evaluated once instead of twice (measured in `benchmarks/results/issue34/mutual_pairs/`).
The schemes this covers are those whose pair terms have the form above
(`mutual_supported`), with SPS's stress term (antisymmetric as the pressure's, between fluid particles)
and no-slip walls (a wall particle's no-slip velocity in place of its own in the viscous term, on
either side of the pair); Riemann pairs, repulsive particles, periodic axes and symmetry planes keep the
per-particle gather.
"""

import numpy as np

from ..neighbours.half_sweep import WALL_WEIGHT, make_tiles
from .rates import make_store, make_tensile
from .reciprocals import make_reciprocals
from .spec import FLUID


def mutual_supported(spec):
    """Whether the CPU may evaluate `spec`'s rates a pair at a time (see the module docstring)."""
    return not (spec.riemann or spec.repulsive or spec.periodic or spec.symmetry)


def make_mutual(jit, spec, kernels, viscous, diffusion, reciprocals, tensile):
    """Return ``(mutual_pair, init)``.

    ``mutual_pair(own, j, dx, dy, dz, r2, data, P)`` -> the pair's terms (Vx, Vy, Vz, dri, drj, mu, Xx,
    Xy, Xz): V as in the module docstring (a_i += -m_j fl_i V, a_j += m_i fl_j V), the two density
    rates (zero for a wall particle that does not integrate continuity), the time-step term, and the
    XSPH vector 2 W_ij v_ij / (rho_i + rho_j) between fluid particles (xsph_i -= eps m_j X,
    xsph_j += eps m_i X). ``own`` = (v_ix, v_iy, v_iz, rho_i, 1/rho_i, p_i/rho_i^2, tensile coefficient
    of i, 1 if i is fluid else 0, m_i, i's velocity in the viscous term (3), tau_i / rho_i^2 (6, or 3 in
    2D, then zeros)); ``data`` = (vel, rho, pr2, kind, tau, vwall).
    ``init``: the terms of no pair (zeros).
    """
    F = spec.float_type
    dim = spec.dim
    zero, one, two = F(0.0), F(1.0), F(2.0)
    w, grad_factor = kernels
    tensile_coef, tensile_pair = tensile
    use_tensile = spec.tensile
    use_xsph = spec.xsph
    use_sps = spec.sps
    no_slip = spec.no_slip
    dbc = spec.wall_pressure == 0

    @jit
    def mutual_pair(own, j, dx, dy, dz, r2, data, P):
        vix, viy, viz, rhoi, inv_rhoi, pr2i, ti, fli, mi, wix, wiy, wiz, t0, t1, t2, t3, t4, t5 = own
        vel, rho, pr2, kind, tau, vwall = data
        # j's values are all read first (see `rates`: a read after a call left reference counting)
        vjx = vel[j, 0]
        vjz = vel[j, dim - 1]
        vjy = vel[j, 1] if dim == 3 else zero
        rhoj = rho[j]
        pr2j = pr2[j]
        is_fluid = kind[j] == FLUID
        flj = one if is_fluid else zero
        if use_sps:
            # tau_i/rho_i^2 + tau_j/rho_j^2 (a wall particle's is zero; the term is between fluid particles)
            if dim == 3:
                sxx, sxy, sxz = t0 + tau[j, 0], t1 + tau[j, 1], t2 + tau[j, 2]
                syy, syz, szz = t3 + tau[j, 3], t4 + tau[j, 4], t5 + tau[j, 5]
            else:
                sxx, sxz, szz = t0 + tau[j, 0], t1 + tau[j, 1], t2 + tau[j, 2]
        ux, uy, uz = vix - vjx, viy - vjy, viz - vjz
        vdotr = ux * dx + uy * dy + uz * dz
        # the viscous term's velocity difference: a wall particle's no-slip velocity in place of its own
        wx, wy, wz, vdotr_v = ux, uy, uz, vdotr
        if no_slip:
            wjx = vjx if is_fluid else vwall[j, 0]
            wjz = vjz if is_fluid else vwall[j, dim - 1]
            wjy = (vjy if is_fluid else vwall[j, 1]) if dim == 3 else zero
            wx, wy, wz = wix - wjx, wiy - wjy, wiz - wjz
            vdotr_v = wx * dx + wy * dy + wz * dz
        r = r2 ** F(0.5)
        q = r * P.inv_h
        fr = grad_factor(q, P)
        both = fli * flj
        mj = P.mass_b + flj * (P.mass_f - P.mass_b)
        vb = P.visc_bound + both * (one - P.visc_bound)
        inv_a, inv_s, inv_rhoj = reciprocals(r2, P.eta2, rhoi, rhoj)
        prs = pr2i + pr2j
        if use_tensile:
            prs += tensile_pair(q, ti, tensile_coef(pr2j), P)
        pi_ij, lam = viscous(vdotr_v, r2, fr, one, inv_a, inv_s, P)
        g = (prs + vb * pi_ij) * fr
        lam *= vb
        vx, vy, vz = g * dx - lam * wx, g * dy - lam * wy, g * dz - lam * wz
        if use_sps:
            # the stress term m_j (..) . grad_i W_ij between fluid particles, antisymmetric as the pressure's
            c = both * fr
            if dim == 3:
                vx -= c * (sxx * dx + sxy * dy + sxz * dz)
                vy -= c * (sxy * dx + syy * dy + syz * dz)
                vz -= c * (sxz * dx + syz * dy + szz * dz)
            else:
                vx -= c * (sxx * dx + sxz * dz)
                vz -= c * (sxz * dx + szz * dz)
        cont = vdotr * fr
        # density: continuity for both, diffusion between fluid particles; a wall particle integrates
        # continuity only under DBC
        dri = mj * cont + both * diffusion(rhoi, rhoj, inv_rhoj, dx, dy, dz, fr, mj, P)
        drj = mi * cont + both * diffusion(rhoj, rhoi, inv_rhoi, -dx, -dy, -dz, fr, mi, P)
        if not dbc:
            dri *= fli
            drj *= flj
        mu = abs(P.h * vdotr * inv_a)
        if use_xsph:
            c = two * both * w(q, P) * inv_s
            return vx, vy, vz, dri, drj, mu, fli * mj, flj * mi, c * ux, c * uy, c * uz
        return vx, vy, vz, dri, drj, mu, fli * mj, flj * mi, zero, zero, zero

    init = (zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero)
    return mutual_pair, init


def make_particle_mutual(jit, spec, kernels, viscous, diffusion, make_half_gather, unpack, plane_accel=None):
    """Return ``(mutual_tile, particle_mutual)``, the CPU's rates a pair at a time (`mutual_supported`).

    ``mutual_tile(mode, t, pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph,
    mu_max, planes, ptable, tau, vwall, cost, colour_of, wet)`` is what the CPU's sweep calls (`shoal.backends.cpu`),
    t a particle or a tile of `shoal.neighbours.half_sweep`: mode 0 starts particle t's sums
    (``mutual_init``); mode 1 weighs tile t into ``cost[t]`` (`half_sweep.WALL_WEIGHT`), writes its
    colour into ``colour_of[t]`` and into ``wet[t]`` whether it holds fluid; mode 2, once modes 0 and 1 have
    run for every particle and tile, sweeps tile t (``particle_mutual`` for each of its particles, in cell
    order), but for its wall particles only where a tile their half stencils reach (the tile's neighbours
    in x and the tiles above them) holds fluid: a wall particle pairs with fluid only, and most of a tank's
    wall particles are away from the water.

    ``mutual_init(i, kind, ace, drho, xsph, mu_max, Parr)`` starts particle i's sums: gravity for a
    fluid particle's acceleration, zero otherwise. ``particle_mutual(i, pos, spos, vel, rho, pr2, kind,
    cell, cell_start, gdims, Parr, ace, drho, xsph, mu_max, planes, ptable, tau, vwall)`` then evaluates the pairs
    of i's half stencil (`shoal.neighbours.half_sweep`), adds their terms to i's sums and to its
    neighbours', and, for a fluid particle, the wall planes' force; the arguments are those of
    `rates`' ``particle_rates`` (`gdims` a tuple). After every particle has been swept (never two
    that write to the same particles at once: `half_sweep`), ace, drho, xsph and mu_max hold what
    ``particle_rates`` writes.
    """
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    use_xsph = spec.xsph
    use_planes = spec.planes
    use_sps = spec.sps
    no_slip = spec.no_slip
    w, grad_factor = kernels
    reciprocals = make_reciprocals(jit, spec)
    tensile = make_tensile(jit, spec, w)
    tensile_coef = tensile[0]
    mutual_pair, init = make_mutual(jit, spec, kernels, viscous, diffusion, reciprocals, tensile)
    store = make_store(jit, spec)

    @jit
    def add_to(out, i, c, x, y, z):
        # out[i] += c (x, y, z) in the stored components ((x, z) in 2D)
        out[i, 0] += c * x
        if dim == 3:
            out[i, 1] += c * y
            out[i, 2] += c * z
        else:
            out[i, 1] += c * z

    @jit
    def put(T, m, t):
        T[0, m] = t[0]
        T[1, m] = t[1]
        T[2, m] = t[2]
        T[3, m] = t[3]
        T[4, m] = t[4]
        T[5, m] = t[5]
        T[6, m] = t[6]
        T[7, m] = t[7]
        if use_xsph:
            T[8, m] = t[8]
            T[9, m] = t[9]
            T[10, m] = t[10]

    @jit
    def fold(acc, own, T, m, j, data, out, P):
        ax, ay, az, dr, vm, xx, xy, xz = acc
        ace, drho, xsph, mu_max = out
        ci, cj = T[6, m], T[7, m]
        vx, vy, vz, mu = T[0, m], T[1, m], T[2, m], T[5, m]
        add_to(ace, j, cj, vx, vy, vz)
        drho[j] += T[4, m]
        mu_max[j] = max(mu_max[j], mu if cj != zero else zero)
        if use_xsph:
            add_to(xsph, j, P.xsph_eps * cj, T[8, m], T[9, m], T[10, m])
            xx -= ci * T[8, m]
            xy -= ci * T[9, m]
            xz -= ci * T[10, m]
        return ax - ci * vx, ay - ci * vy, az - ci * vz, dr + T[3, m], max(vm, mu), xx, xy, xz

    @jit
    def fluid_only(j, data):
        return data[3][j] == FLUID

    # a wall particle's pairs are with fluid particles only (most of its candidates are walls)
    gather = make_half_gather(jit, spec, mutual_pair, (init, put, fold), fluid_only)

    @jit
    def mutual_init(i, kind, ace, drho, xsph, mu_max, Parr):
        P = unpack(Parr)
        store(ace, i, one if kind[i] == FLUID else zero, P.gx, P.gy, P.gz)
        drho[i] = zero
        mu_max[i] = zero
        if use_xsph:
            store(xsph, i, zero, zero, zero, zero)

    @jit
    def particle_mutual(i, pos, spos, vel, rho, pr2, kind, cell, cell_start, gdims, Parr, ace, drho, xsph, mu_max,
                        planes, ptable, tau, vwall):
        P = unpack(Parr)
        vix = vel[i, 0]
        viz = vel[i, dim - 1]
        viy = vel[i, 1] if dim == 3 else zero
        rhoi = rho[i]
        pr2i = pr2[i]
        is_fluid = kind[i] == FLUID
        fli = one if is_fluid else zero
        mi = P.mass_f if is_fluid else P.mass_b
        # i's velocity in the viscous term: a wall particle's no-slip velocity
        wix, wiy, wiz = vix, viy, viz
        if no_slip and not is_fluid:
            wix = vwall[i, 0]
            wiz = vwall[i, dim - 1]
            wiy = vwall[i, 1] if dim == 3 else zero
        t0 = t1 = t2 = t3 = t4 = t5 = zero
        if use_sps:
            t0, t1, t2 = tau[i, 0], tau[i, 1], tau[i, 2]
            if dim == 3:
                t3, t4, t5 = tau[i, 3], tau[i, 4], tau[i, 5]
        own = (vix, viy, viz, rhoi, one / rhoi, pr2i, tensile_coef(pr2i), fli, mi, wix, wiy, wiz, t0, t1, t2, t3, t4, t5)
        data = (vel, rho, pr2, kind, tau, vwall)
        out = (ace, drho, xsph, mu_max)
        acc = (zero, zero, zero, zero, zero, zero, zero, zero)
        ax, ay, az, dr, vm, xx, xy, xz = gather(i, own, acc, is_fluid, pos, spos, cell, cell_start, gdims, data,
                                                out, P)
        if is_fluid and use_planes:
            qx, qy, qz = plane_accel(pos[i, 0], pos[i, 1] if dim == 3 else 0.0, pos[i, dim - 1], vix, viy, viz,
                                     rhoi, planes, ptable, P)
            ax += qx
            ay += qy
            az += qz
        add_to(ace, i, fli, ax, ay, az)
        drho[i] += dr
        mu_max[i] = max(mu_max[i], fli * vm)
        if use_xsph:
            add_to(xsph, i, P.xsph_eps * fli, xx, xy, xz)

    tile_cells, reaches = make_tiles(jit, spec)
    wall_weight = WALL_WEIGHT

    @jit
    def mutual_tile(mode, t, pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph,
                    mu_max, planes, ptable, tau, vwall, cost, colour_of, wet):
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        if mode == 0:
            mutual_init(t, kind, ace, drho, xsph, mu_max, Parr)
            return
        nx, ny = gdims[0], gdims[1]
        x0, x1, z0, z1, colour = tile_cells(t, gdims)
        wet_near = mode == 2 and reaches(t, gdims, wet)
        c = 0.0
        f = 0
        for z in range(z0, z1):
            for y in range(ny if dim == 3 else 1):
                row = nx * (y + ny * z) if dim == 3 else nx * z
                for i in range(cell_start[row + x0], cell_start[row + x1]):
                    if mode == 1:
                        is_fluid = kind[i] == FLUID
                        c += 1.0 if is_fluid else wall_weight
                        f += is_fluid
                    elif wet_near or kind[i] == FLUID:
                        particle_mutual(np.uint64(i), pos, spos, vel, rho, pr2, kind, cell, cell_start, gdims, Parr,
                                        ace, drho, xsph, mu_max, planes, ptable, tau, vwall)
        if mode == 1:
            cost[t] = c
            colour_of[t] = colour
            wet[t] = f > 0

    return mutual_tile, particle_mutual
