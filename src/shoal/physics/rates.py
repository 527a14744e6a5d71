"""Rates of change of the WCSPH equations for one particle (all backends).

Continuity (Monaghan 1992) with density diffusion D_i:
    d rho_i/dt = sum_j m_j v_ij . grad_i W_ij + D_i
Momentum with the symmetric pressure term, viscosity and gravity:
    d v_i/dt = -sum_j m_j (p_i/rho_i^2 + p_j/rho_j^2 + R_ij + Pi_ij) grad_i W_ij
               + sum_j lam_ij v_ij + g
(R_ij the Monaghan (2000) tensile correction when enabled, Pi_ij the
artificial and lam_ij the laminar viscous term, see `viscosity`; both
multiplied by `visco_bound_factor` when j is a boundary particle.)
With ``riemann = true`` the pressures and velocities of each pair of fluid particles are replaced by
the pair's Riemann solution (p*, v*) of Zhang, Hu & Adams (2017), and a fluid-wall pair gets the
dissipation of the Riemann problem along the wall's normal (`shoal.physics.riemann`).
XSPH (Monaghan 1989): dx_i/dt = v_i + eps sum_j (m_j / rho_ij) v_ji W_ij.
SPS turbulence (when on): + sum_j m_j (tau_i/rho_i^2 + tau_j/rho_j^2) . grad_i W_ij
between fluid particles, tau from `turbulence` (Dalrymple & Rogers 2006).

Dynamic boundary particles (Crespo, Gomez-Gesteira & Dalrymple 2007) obey
the continuity equation with their fluid neighbours and the equation of
state, and do not move by the forces; their density never drops below rho0
(set in the integrator) so that they keep pushing fluid away.

Repulsive boundary particles (Monaghan & Kajtar 2009; rip-current paper,
Eqs. 9-10) take no part in continuity, pressure or diffusion; a fluid
particle i feels from each one, b,
    f_ib = (K / beta) r_ib / r_ib^2 W(q) 2 m_b / (m_i + m_b) - m_b Pi_ib grad_i W_ib,
with K = g D, beta = dp / dp_b = 2, equal masses (as the paper) and the
dimensionless Wendland shape W(q) = (1 - q/2)^4 (1 + 2q), W(0) = 1.

The time-step limit needs max_j |h v_ij . r_ij / (r_ij^2 + eta^2)|
(Monaghan & Kos 1999), accumulated here per particle.
"""

from .reciprocals import make_reciprocals
from .riemann import make_riemann
from .spec import FLUID, REPULSIVE


def make_tensile(jit, spec, w):
    """Return ``(tensile_coef, tensile_pair)`` of the Monaghan (2000) tensile correction:
    ``tensile_coef(pr2)`` = eps p/rho^2 (eps = 0.01 under compression, -0.2 under tension) of one
    particle, and ``tensile_pair(q, ta, tb, P)`` = R_ab = (W(q) / W(dp))^4 (eps_a p_a/rho_a^2 +
    eps_b p_b/rho_b^2), added to the pressure factor of a pair."""
    F = spec.float_type
    zero = F(0.0)
    t_pos, t_neg = F(0.01), F(-0.2)

    @jit
    def tensile_coef(pr2):
        return pr2 * (t_pos if pr2 > zero else t_neg)

    @jit
    def tensile_pair(q, ta, tb, P):
        wq = w(q, P) * P.inv_wdp
        wq2 = wq * wq
        return wq2 * wq2 * (ta + tb)

    return tensile_coef, tensile_pair


def make_store(jit, spec):
    """Return ``store(out, i, c, x, y, z)``: out[i] = c (x, y, z) in the stored components ((x, z) in 2D)."""
    dim = spec.dim

    @jit
    def store(out, i, c, x, y, z):
        out[i, 0] = c * x
        if dim == 3:
            out[i, 1] = c * y
            out[i, 2] = c * z
        else:
            out[i, 1] = c * z

    return store


def make_rates(jit, spec, kernels, pressure, viscous, diffusion, make_gather, unpack, plane_accel=None,
               compact=False):
    """Return ``particle_rates(i, pos, spos, vel, rho, pr2, kind, cell, cell_start,
    grid_dims, Parr, ace, drho, xsph, mu_max, tau, planes, ptable, vwall, idp, ghosts, gid0)``, which writes
    particle i's rates.

    `spos` (2 dim, N) float32 holds the split coordinates of the compact gather (`make_gather`, read only
    with `compact`; `Model.split_positions`).

    `ghosts` is the walls' unit-normal table by particle id less `gid0` (`Model.wall_normal_of`);
    with ``riemann`` and ``gid0 >= 0`` a fluid-wall pair adds the Riemann dissipation along the
    wall's normal (`shoal.physics.riemann`); read only then.

    `vwall` holds the boundary particles' no-slip velocities (`no_slip`; read
    only when the scheme has ``no_slip``).

    `planes` (n, 4) and `ptable` are the wall planes and their force table
    (`shoal.physics.planes`; read only when the scheme has planes).

    `tau` holds tau / rho^2 of the SPS stress (read only when the scheme has SPS).

    `Parr` is the `Params` record array, `grid_dims` the (nx, ny, nz) array.

    `pr2` holds p / rho^2 of every particle (computed once per evaluation).
    `xsph` is written only when the scheme has XSPH.

    `compact`: compact the fluid particles' stencil rows (`make_gather`; CPU only).
    """
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    w, grad_factor = kernels
    tensile = spec.tensile
    use_xsph = spec.xsph
    use_sps = spec.sps
    use_mk = spec.repulsive
    use_planes = spec.planes
    no_slip = spec.no_slip
    wall_pressure = spec.wall_pressure != 0
    riemann = spec.riemann
    riemann_pair, wall_jump = make_riemann(jit, spec)
    two, halfq = F(2.0), F(0.5)
    tensile_coef, tensile_pair = make_tensile(jit, spec, w)
    store = make_store(jit, spec)
    reciprocals = make_reciprocals(jit, spec)

    @jit
    def fluid_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        ax, ay, az, dr, xx, xy, xz, mu_max = acc
        vix, viy, viz, rhoi, pr2i, ti, t0, t1, t2, t3, t4, t5 = own
        vel, rho, pr2, kind, tau, vwall, idp, ghosts, gid0 = data
        r = r2 ** F(0.5)
        q = r * P.inv_h
        fr = grad_factor(q, P)
        if use_mk:
            if kind[j] >= REPULSIVE:
                t = one - halfq * q
                t2 = t * t
                c = P.mk_k * t2 * t2 * (one + two * q) / r2
                vjx = vel[j, 0]
                vjz = vel[j, dim - 1]
                vjy = sy * vel[j, 1] if dim == 3 else zero
                ux, uy, uz = vix - vjx, viy - vjy, viz - vjz
                vdotr = ux * dx + uy * dy + uz * dz
                inv_a, inv_s, _ = reciprocals(r2, P.eta2, rhoi, P.rho0)
                pi_ij, lam = viscous(vdotr, r2, fr, P.mass_f, inv_a, inv_s, P)
                pi_ij *= P.visc_bound
                lam *= P.visc_bound
                f = c - P.mass_f * pi_ij * fr
                mu_max = max(mu_max, abs(P.h * vdotr * inv_a))
                return (ax + f * dx + lam * ux, ay + f * dy + lam * uy, az + f * dz + lam * uz, dr, xx, xy, xz,
                        mu_max)
        vjx = vel[j, 0]
        vjz = vel[j, dim - 1]
        vjy = sy * vel[j, 1] if dim == 3 else zero
        ux, uy, uz = vix - vjx, viy - vjy, viz - vjz
        vdotr = ux * dx + uy * dy + uz * dz
        # the fluid / boundary distinctions below are selects and factors of one or zero, not
        # branches: neighbours of both kinds alternate in cell order, and the mispredicted branches
        # cost 8 % of the pair loop (3D dam break, this project's CPU)
        is_fluid = kind[j] == FLUID
        fl = one if is_fluid else zero
        mj = P.mass_f if is_fluid else P.mass_b
        vb = one if is_fluid else P.visc_bound
        rhoj = rho[j]
        pr2j = pr2[j]
        # j's arrays are all read before the calls below: Numba left an array read after them with
        # a reference-count increment and decrement per pair (20 % of the pair loop's time;
        # `benchmarks/refcounts.py` finds them)
        if use_sps:
            # (tau_i/rho_i^2 + tau_j/rho_j^2); a mirror image's stress has its xy and yz components
            # reversed; a boundary particle's tau is zero
            if dim == 3:
                sxx, sxy, sxz = t0 + tau[j, 0], t1 + sy * tau[j, 1], t2 + tau[j, 2]
                syy, syz, szz = t3 + tau[j, 3], t4 + sy * tau[j, 4], t5 + tau[j, 5]
            else:
                sxx, sxz, szz = t0 + tau[j, 0], t1 + tau[j, 1], t2 + tau[j, 2]
        # viscous term: against a boundary particle, its no-slip velocity when enabled (`no_slip`)
        wx, wy, wz, vdotr_v = ux, uy, uz, vdotr
        if no_slip:
            if not is_fluid:
                wx = vix - vwall[j, 0]
                wz = viz - vwall[j, dim - 1]
                wy = viy - sy * vwall[j, 1] if dim == 3 else zero
                vdotr_v = wx * dx + wy * dy + wz * dz
        inv_a, inv_s, inv_rhoj = reciprocals(r2, P.eta2, rhoi, rhoj)
        # continuity, with density diffusion between fluid particles only; momentum's pressure factor
        prs, cont = pr2i + pr2j, vdotr
        if riemann:
            # between fluid particles only (a select, not a branch, as above)
            prs_r, cont_r = riemann_pair(pr2i * rhoi * rhoi, pr2j * rhoj * rhoj, rhoi, inv_rhoj, vdotr, r,
                                         P.gx * dx + P.gy * dy + P.gz * dz, inv_s, P)
            prs += fl * (prs_r - prs)
            cont += fl * (cont_r - cont)
            if gid0 >= 0 and not is_fluid:
                # a wall: the closing speed along its normal (its ghost vector's direction), and the
                # dissipative pressure pushing along it with the weight |grad W| = -fr r
                wall_dp, nx, ny, nz = wall_jump(vix - vjx, viy - vjy, viz - vjz, ghosts, idp[j] - gid0, sy, rhoi,
                                                rhoj, P)
                c = -two * mj * wall_dp * inv_rhoj / rhoi * fr * r
                ax += c * nx
                ay += c * ny
                az += c * nz
        dr += mj * cont * fr + fl * diffusion(rhoi, rhoj, inv_rhoj, dx, dy, dz, fr, mj, P)
        if tensile:
            prs += tensile_pair(q, ti, tensile_coef(pr2j), P)
        pi_ij, lam = viscous(vdotr_v, r2, fr, mj, inv_a, inv_s, P)
        pi_ij *= vb
        lam *= vb
        f = -mj * (prs + pi_ij) * fr
        ax += f * dx + lam * wx
        ay += f * dy + lam * wy
        az += f * dz + lam * wz
        if use_sps:
            # the stress term sum_j m_j (..) . grad W, grad W = fr r_ij, between fluid particles
            c = fl * mj * fr
            if dim == 3:
                ax += c * (sxx * dx + sxy * dy + sxz * dz)
                ay += c * (sxy * dx + syy * dy + syz * dz)
                az += c * (sxz * dx + syz * dy + szz * dz)
            else:
                ax += c * (sxx * dx + sxz * dz)
                az += c * (sxz * dx + szz * dz)
        mu_max = max(mu_max, abs(P.h * vdotr * inv_a))
        if use_xsph:
            # m_j W_ij / rho_ij with rho_ij = (rho_i + rho_j) / 2, between fluid particles
            c = two * fl * mj * w(q, P) * inv_s
            xx -= c * ux
            xy -= c * uy
            xz -= c * uz
        return ax, ay, az, dr, xx, xy, xz, mu_max

    @jit
    def bound_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        vix, viy, viz = own
        vel, rho, pr2, kind, tau, vwall, idp, ghosts, gid0 = data
        # with fluid neighbours only (a branch, unlike `fluid_pair`: most of a wall particle's
        # neighbours are wall particles, so it is well predicted and skips their kernel gradients)
        if kind[j] != FLUID:
            return acc
        q = r2 ** F(0.5) * P.inv_h
        fr = grad_factor(q, P)
        vjz = vel[j, dim - 1]
        vjy = sy * vel[j, 1] if dim == 3 else zero
        vdotr = (vix - vel[j, 0]) * dx + (viy - vjy) * dy + (viz - vjz) * dz
        return acc + P.mass_f * vdotr * fr

    @jit
    def particle_pr2(i, rho, pr2, Parr):
        """p_i / rho_i^2 from the equation of state, once per evaluation."""
        P = unpack(Parr)
        r = rho[i]
        pr2[i] = pressure(r, P) / (r * r)

    # the fluid particles' gather is 96 % of a step: on the CPU its rows are compacted and its pairs
    # evaluated by a vectorised loop into a buffer of terms (`make_gather`'s `terms`)
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

    @jit
    def fold(acc, T, m):
        # the sums of `fluid_pair`, and the maximum of its time-step term
        return (acc[0] + T[0, m], acc[1] + T[1, m], acc[2] + T[2, m], acc[3] + T[3, m], acc[4] + T[4, m],
                acc[5] + T[5, m], acc[6] + T[6, m], max(acc[7], T[7, m]))

    init = (zero, zero, zero, zero, zero, zero, zero, zero)
    gather_fluid = make_gather(jit, spec, fluid_pair, compact=compact, terms=(init, put, fold))
    # with periodic axes or a symmetry plane `make_gather` gives the periodic gather, which takes no `spos`
    split = compact and not (spec.periodic or spec.symmetry)
    @jit
    def fluid_only(j, data):
        return data[3][j] == FLUID

    # a wall particle's candidates are screened by kind before their distance is taken: most are wall
    # particles (on the CPU its rows' ranges are found first, as the fluid gather's)
    gather_bound = make_gather(jit, spec, bound_pair, only=fluid_only, rows_first=compact)

    @jit
    def particle_rates(i, pos, spos, vel, rho, pr2, kind, cell, cell_start, grid_dims, Parr, ace, drho, xsph, mu_max,
                       tau, planes, ptable, vwall, idp, ghosts, gid0):
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        vix = vel[i, 0]
        viz = vel[i, dim - 1]
        viy = vel[i, 1] if dim == 3 else zero
        data = (vel, rho, pr2, kind, tau, vwall, idp, ghosts, gid0)
        if kind[i] == FLUID:
            pr2i = pr2[i]
            ti = tensile_coef(pr2i)
            if use_sps:
                if dim == 3:
                    own = (vix, viy, viz, rho[i], pr2i, ti, tau[i, 0], tau[i, 1], tau[i, 2], tau[i, 3], tau[i, 4],
                           tau[i, 5])
                else:
                    own = (vix, viy, viz, rho[i], pr2i, ti, tau[i, 0], tau[i, 1], tau[i, 2], zero, zero, zero)
            else:
                own = (vix, viy, viz, rho[i], pr2i, ti, zero, zero, zero, zero, zero, zero)
            acc = (zero, zero, zero, zero, zero, zero, zero, zero)
            if split:
                ax, ay, az, dr, xx, xy, xz, vm = gather_fluid(i, own, acc, pos, spos, cell, cell_start, gdims, data, P)
            else:
                ax, ay, az, dr, xx, xy, xz, vm = gather_fluid(i, own, acc, pos, cell, cell_start, gdims, data, P)
            if use_planes:
                qx, qy, qz = plane_accel(pos[i, 0], pos[i, 1] if dim == 3 else 0.0, pos[i, dim - 1], vix, viy, viz,
                                         rho[i], planes, ptable, P)
                ax += qx
                ay += qy
                az += qz
            ace[i, 0] = ax + P.gx
            if dim == 3:
                ace[i, 1] = ay + P.gy
                ace[i, 2] = az + P.gz
            else:
                ace[i, 1] = az + P.gz
            drho[i] = dr
            mu_max[i] = vm
            if use_xsph:
                store(xsph, i, P.xsph_eps, xx, xy, xz)
        elif use_mk and kind[i] >= REPULSIVE:
            for d in range(dim):
                ace[i, d] = zero
            drho[i] = zero
            mu_max[i] = zero
            if use_xsph:
                for d in range(dim):
                    xsph[i, d] = zero
        else:
            # with the Adami wall pressure or mDBC a wall's density is extrapolated, not integrated
            dr = zero if wall_pressure else gather_bound(i, (vix, viy, viz), zero, pos, cell, cell_start, gdims,
                                                         data, P)
            for d in range(dim):
                ace[i, d] = zero
            drho[i] = dr
            mu_max[i] = zero
            if use_xsph:
                for d in range(dim):
                    xsph[i, d] = zero

    return particle_pr2, particle_rates
