"""The modified dynamic boundary condition (mDBC) of English et al. (2022), as DualSPHysics 5.4.

With the plain dynamic boundary condition (DBC, Crespo et al. 2007) each wall particle integrates
its own continuity equation, and the fluid settles where the walls' pressure balances it: about
1.5 dp above the outermost wall layer in a moving surge (a gap of a spacing and more between the
fluid and the wall surface). mDBC gives each dynamic wall particle b the density of the fluid at
its **ghost node** x_g = x_b + g_b, the mirror image of x_b across the wall surface (g_b from the
geometry: `shoal.geometry.normals`), extrapolated back to x_b to first order:

    rho_b = rho_g + (x_b - x_g) . grad rho_g,

where (rho_g, grad rho_g) solve the kernel-gradient-corrected interpolation at the ghost node
(Liu & Liu 2006) over its fluid neighbours f, with V_f = m_f / rho_f, e_f = x_f - x_g and
grad W = grad_g W(x_g - x_f):

    [ sum V W          sum V W e^T         ] [ rho_g      ]   [ sum m W      ]
    [ sum V grad W     sum V grad W e^T    ] [ grad rho_g ] = [ sum m grad W ]

(a 3x3 system in 2D, 4x4 in 3D). Where the fit cannot be trusted the Shepard average
sum m W / sum V W is used instead: a nearly singular system (|det| < 1e-3, DualSPHysics's
``JSphCpu::InteractionMdbcCorrectionT2``), and, as DualSPHysics 5.4's mDBC2 does, a ghost node
with a kernel sum sum V W below 0.1 or an ill-conditioned system (infinity-norm condition number
above 50): a ghost node at the edge of a thin layer of water, whose few neighbours leave the
gradient to the kernel's shape rather than the data. A wall particle whose ghost node has no
fluid neighbour takes rho0. The density is held at rho0 or above, so that a wall
never pulls fluid towards it (as DBC's integrator and the Adami wall pressure do). The wall's
continuity equation is not integrated: its density is this extrapolation, recomputed at every
rate evaluation.

With ``no_slip = true`` the ghost node also gives the velocity that the viscous term sees at the
wall particle, u_b = 2 u_w - u_g, with u_g = sum V u W / sum V W the Shepard velocity at the
ghost node: the fluid velocity mirrored antisymmetrically across the wall surface, so that it
vanishes relative to the wall on the surface itself (DualSPHysics 5.4's no-slip mDBC). Free slip
is ``visco_bound_factor = 0``.

The sums are in the working precision and hold V_f (rho_f - rho0) where the formula has m_f, so
the fit is solved for rho_g - rho0: a float32 sum of masses would round the density's departure
from rho0, a part in a thousand, to three digits. Offsets are scaled by 1/h and gradients by h, a
similarity transform of the system that leaves its determinant unchanged and its entries of order
one. In float32 the walls then take a linear density field to within four units in the last place
(2.4e-4 kg/m^3, `tests/test_mdbc.py`); float64 sums made the pass three times slower on the CPU.

References
----------
A. English, J. M. Dominguez, R. Vacondio, A. J. C. Crespo, P. K. Stansby, S. J. Lind,
L. Chiapponi, M. Gomez-Gesteira, "Modified dynamic boundary conditions (mDBC) for
general-purpose smoothed particle hydrodynamics (SPH): application to tank sloshing, dam break
and fish pass problems", Comput. Part. Mech. 9 (2022) 911-925, doi:10.1007/s40571-021-00403-3.
M. B. Liu, G. R. Liu, "Restoring particle consistency in smoothed particle hydrodynamics",
Appl. Numer. Math. 56 (2006) 19-36.
"""

from .spec import FLUID, REPULSIVE

DETERMINANT_LIMIT = 1e-3
"""|det| of the (scaled) correction matrix below which the Shepard average replaces the
first-order fit (DualSPHysics's ``determlimit``)."""
KERNEL_SUM_MIN = 0.1
"""Kernel sum sum V W at the ghost node below which the Shepard average (at least rho0) replaces
the fit (DualSPHysics 5.4's mDBC2): a ghost node at the edge of a thin layer."""
CONDITION_MAX = 50.0
"""Infinity-norm condition number of the (h-scaled) correction matrix above which the Shepard
average replaces the fit (DualSPHysics 5.4's mDBC2 threshold, here on the scaled matrix, which is
about 1 where the ghost node's support is full)."""


def make_determinants(jit):
    """Return ``(det3, det4)``: determinants of 3x3 and 4x4 matrices given row by row as scalars."""

    @jit
    def det3(a, b, c, d, e, f, g, h, k):
        return a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g)

    @jit
    def det4(a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44):
        # Laplace expansion along the first two rows (2x2 minors of rows 1-2 and 3-4)
        s0 = a11 * a22 - a12 * a21
        s1 = a11 * a23 - a13 * a21
        s2 = a11 * a24 - a14 * a21
        s3 = a12 * a23 - a13 * a22
        s4 = a12 * a24 - a14 * a22
        s5 = a13 * a24 - a14 * a23
        c5 = a33 * a44 - a34 * a43
        c4 = a32 * a44 - a34 * a42
        c3 = a32 * a43 - a33 * a42
        c2 = a31 * a44 - a34 * a41
        c1 = a31 * a43 - a33 * a41
        c0 = a31 * a42 - a32 * a41
        return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0

    return det3, det4


def make_conditions(jit, det3):
    """Return ``(cond3, cond4)``: the infinity-norm condition number ||A|| ||A^-1|| of a 3x3 or 4x4
    matrix given row by row with its determinant (A^-1 = adj(A) / det, the adjugate's entries the
    cofactors)."""

    @jit
    def cond3(a, b, c, d, e, f, g, h, k, det):
        n = max(abs(a) + abs(b) + abs(c), abs(d) + abs(e) + abs(f), abs(g) + abs(h) + abs(k))
        # rows of the adjugate (the cofactors of the columns)
        r1 = abs(e * k - f * h) + abs(c * h - b * k) + abs(b * f - c * e)
        r2 = abs(f * g - d * k) + abs(a * k - c * g) + abs(c * d - a * f)
        r3 = abs(d * h - e * g) + abs(b * g - a * h) + abs(a * e - b * d)
        return n * max(r1, r2, r3) / abs(det)

    @jit
    def cond4(a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44, det):
        n = max(abs(a11) + abs(a12) + abs(a13) + abs(a14), abs(a21) + abs(a22) + abs(a23) + abs(a24),
                abs(a31) + abs(a32) + abs(a33) + abs(a34), abs(a41) + abs(a42) + abs(a43) + abs(a44))
        # row i of the adjugate holds the cofactors C_ji, |C_ji| = |minor without row j, column i|
        r1 = (abs(det3(a22, a23, a24, a32, a33, a34, a42, a43, a44)) + abs(det3(a12, a13, a14, a32, a33, a34, a42, a43, a44))
              + abs(det3(a12, a13, a14, a22, a23, a24, a42, a43, a44)) + abs(det3(a12, a13, a14, a22, a23, a24, a32, a33, a34)))
        r2 = (abs(det3(a21, a23, a24, a31, a33, a34, a41, a43, a44)) + abs(det3(a11, a13, a14, a31, a33, a34, a41, a43, a44))
              + abs(det3(a11, a13, a14, a21, a23, a24, a41, a43, a44)) + abs(det3(a11, a13, a14, a21, a23, a24, a31, a33, a34)))
        r3 = (abs(det3(a21, a22, a24, a31, a32, a34, a41, a42, a44)) + abs(det3(a11, a12, a14, a31, a32, a34, a41, a42, a44))
              + abs(det3(a11, a12, a14, a21, a22, a24, a41, a42, a44)) + abs(det3(a11, a12, a14, a21, a22, a24, a31, a32, a34)))
        r4 = (abs(det3(a21, a22, a23, a31, a32, a33, a41, a42, a43)) + abs(det3(a11, a12, a13, a31, a32, a33, a41, a42, a43))
              + abs(det3(a11, a12, a13, a21, a22, a23, a41, a42, a43)) + abs(det3(a11, a12, a13, a21, a22, a23, a31, a32, a33)))
        return n * max(r1, r2, r3, r4) / abs(det)

    return cond3, cond4


def make_mdbc(jit, spec, kernels, make_point_gather, unpack):
    """Return ``particle_mdbc(i, pos, vel, rho, kind, idp, ghost_of, id0, cell_start, grid_dims, Parr,
    vwall)`` writing the mDBC density of dynamic boundary particle i into ``rho[i]`` (and, with
    ``no_slip``, its viscous velocity into ``vwall[i]``).

    `ghost_of` (n_ids - id0, dim) holds the ghost vector g = x_g - x_b of each particle id from
    `id0` on (internal components; a zero row extrapolates at the particle itself).
    """
    F = spec.float_type
    dim = spec.dim
    no_slip = spec.no_slip
    w, grad_factor = kernels
    det3, det4 = make_determinants(jit)
    cond3, cond4 = make_conditions(jit, det3)
    limit = F(DETERMINANT_LIMIT)
    sum_min = F(KERNEL_SUM_MIN)
    cond_max = F(CONDITION_MAX)
    two = F(2.0)

    if dim == 2:
        @jit
        def ghost_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
            (a11, a12, a13, a21, a22, a23, a31, a32, a33, b1, b2, b3, ux, uz) = acc
            vel, rho, kind = data
            if kind[j] != FLUID:
                return acc
            q = r2 ** F(0.5) * P.inv_h
            rj = rho[j]
            v = P.mass_f / rj
            dr = v * (rj - P.rho0)
            wq = w(q, P)
            fr = grad_factor(q, P) * P.h
            # e = x_j - x_g = -(dx, dz) scaled by 1/h; h grad_g W = h fr (dx, dz) = fr' (dx, dz)
            ex, ez = -dx * P.inv_h, -dz * P.inv_h
            gx, gz = fr * dx, fr * dz
            vw, vgx, vgz = v * wq, v * gx, v * gz
            return (a11 + vw, a12 + vw * ex, a13 + vw * ez,
                    a21 + vgx, a22 + vgx * ex, a23 + vgx * ez,
                    a31 + vgz, a32 + vgz * ex, a33 + vgz * ez,
                    b1 + dr * wq, b2 + dr * gx, b3 + dr * gz,
                    ux + vw * vel[j, 0], uz + vw * vel[j, 1])
    else:
        @jit
        def ghost_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
            (a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44,
             b1, b2, b3, b4, ux, uy, uz) = acc
            vel, rho, kind = data
            if kind[j] != FLUID:
                return acc
            q = r2 ** F(0.5) * P.inv_h
            rj = rho[j]
            v = P.mass_f / rj
            dr = v * (rj - P.rho0)
            wq = w(q, P)
            fr = grad_factor(q, P) * P.h
            ex, ey, ez = -dx * P.inv_h, -dy * P.inv_h, -dz * P.inv_h
            gx, gy, gz = fr * dx, fr * dy, fr * dz
            vw, vgx, vgy, vgz = v * wq, v * gx, v * gy, v * gz
            return (a11 + vw, a12 + vw * ex, a13 + vw * ey, a14 + vw * ez,
                    a21 + vgx, a22 + vgx * ex, a23 + vgx * ey, a24 + vgx * ez,
                    a31 + vgy, a32 + vgy * ex, a33 + vgy * ey, a34 + vgy * ez,
                    a41 + vgz, a42 + vgz * ex, a43 + vgz * ey, a44 + vgz * ez,
                    b1 + dr * wq, b2 + dr * gx, b3 + dr * gy, b4 + dr * gz,
                    ux + vw * vel[j, 0], uy + vw * vel[j, 1], uz + vw * vel[j, 2])

    gather_at = make_point_gather(jit, spec, ghost_pair, wrap=True)

    @jit
    def particle_mdbc(i, pos, vel, rho, kind, idp, ghost_of, id0, cell_start, grid_dims, Parr, vwall):
        k = kind[i]
        if k == FLUID or k >= REPULSIVE:
            if no_slip:
                for d in range(dim):
                    vwall[i, d] = vel[i, d]
            return
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        p = idp[i] - id0
        z0 = F(0.0)
        rho0 = P.rho0
        if dim == 2:
            gx, gz = ghost_of[p, 0], ghost_of[p, 1]
            glo = (P.grid_lo_x, P.grid_lo_z, 0.0)
            acc = (z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0)
            (a11, a12, a13, a21, a22, a23, a31, a32, a33, b1, b2, b3, ux, uz) = gather_at(
                pos[i, 0] + gx, z0, pos[i, 1] + gz, 0, acc, pos, cell_start, gdims, glo, P.inv_cs,
                (vel, rho, kind), P)
            r = rho0
            if a11 > z0:
                r = rho0 + b1 / a11
                det = det3(a11, a12, a13, a21, a22, a23, a31, a32, a33)
                if (a11 >= sum_min and abs(det) >= limit
                        and cond3(a11, a12, a13, a21, a22, a23, a31, a32, a33, det) <= cond_max):
                    # Cramer's rule: rho_g, and grad rho_g scaled by h
                    rg = det3(b1, a12, a13, b2, a22, a23, b3, a32, a33) / det
                    sx = det3(a11, b1, a13, a21, b2, a23, a31, b3, a33) / det
                    sz = det3(a11, a12, b1, a21, a22, b2, a31, a32, b3) / det
                    # x_b - x_g = -g, in units of h
                    r = rho0 + rg - (sx * gx + sz * gz) * P.inv_h
            rho[i] = max(r, rho0)
            if no_slip:
                if a11 > z0:
                    vwall[i, 0] = two * vel[i, 0] - ux / a11
                    vwall[i, 1] = two * vel[i, 1] - uz / a11
                else:
                    vwall[i, 0] = vel[i, 0]
                    vwall[i, 1] = vel[i, 1]
        else:
            gx, gy, gz = ghost_of[p, 0], ghost_of[p, 1], ghost_of[p, 2]
            glo = (P.grid_lo_x, P.grid_lo_y, P.grid_lo_z)
            acc = (z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0)
            (a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44,
             b1, b2, b3, b4, ux, uy, uz) = gather_at(
                pos[i, 0] + gx, pos[i, 1] + gy, pos[i, 2] + gz, 0, acc, pos, cell_start, gdims, glo, P.inv_cs,
                (vel, rho, kind), P)
            r = rho0
            if a11 > z0:
                r = rho0 + b1 / a11
                det = det4(a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44)
                if (a11 >= sum_min and abs(det) >= limit
                        and cond4(a11, a12, a13, a14, a21, a22, a23, a24, a31, a32, a33, a34, a41, a42, a43, a44,
                                  det) <= cond_max):
                    rg = det4(b1, a12, a13, a14, b2, a22, a23, a24, b3, a32, a33, a34, b4, a42, a43, a44) / det
                    sx = det4(a11, b1, a13, a14, a21, b2, a23, a24, a31, b3, a33, a34, a41, b4, a43, a44) / det
                    sy = det4(a11, a12, b1, a14, a21, a22, b2, a24, a31, a32, b3, a34, a41, a42, b4, a44) / det
                    sz = det4(a11, a12, a13, b1, a21, a22, a23, b2, a31, a32, a33, b3, a41, a42, a43, b4) / det
                    r = rho0 + rg - (sx * gx + sy * gy + sz * gz) * P.inv_h
            rho[i] = max(r, rho0)
            if no_slip:
                if a11 > z0:
                    vwall[i, 0] = two * vel[i, 0] - ux / a11
                    vwall[i, 1] = two * vel[i, 1] - uy / a11
                    vwall[i, 2] = two * vel[i, 2] - uz / a11
                else:
                    for d in range(3):
                        vwall[i, d] = vel[i, d]

    return particle_mdbc
