"""Wall pressure extrapolated from the fluid: the generalized wall boundary
condition of Adami, Hu & Adams (2012), as PySPH's ``SolidWallPressureBC``.

With the default dynamic boundary condition (DBC, Crespo et al. 2007) each
wall particle integrates its own continuity equation. Its density then
follows the lattice of fluid particles sliding over it: in a flow along a
wall it swings by +-0.2 % (+-300 Pa at c0 = 34 m/s, a third of the bed's
hydrostatic pressure in the 0.1 m deep tidal-bore flume), and that forcing
grows a layer of noisy particles that drags the flow (measured here: a
uniform 0.7 m/s stream over a flat bed at dp = 5 mm, periodic, free-slip,
loses half its near-bed speed between t = 1 and 2 s; with the wall
densities frozen it keeps 0.700 m/s). With ``wall_pressure = "adami"``
each dynamic boundary particle b takes, at every rate evaluation, the
pressure of the fluid around it, extrapolated to its position with the
hydrostatic and acceleration terms (Adami et al. 2012, Eq. 27):

    p_b = ( sum_f p_f W_bf + (g - a_b) . sum_f rho_f r_bf W_bf ) / sum_f W_bf,

r_bf = r_b - r_f, over the fluid neighbours f, with a_b the wall's
prescribed acceleration at b (zero for a fixed wall). For a moving wall that rotates it is that of
the rigid motion at the particle, a_b = a_d + alpha x r + omega x (omega x r), r = r_b - c - d(t) the
particle's position from the motion's pivot (`shoal.physics.body_motion`), so each particle of a
flap takes its own acceleration (Adami et al. 2012, Eq. 27, with a_b per particle). p_b is clamped at zero
from below (a wall never pulls fluid in: the DBC keeps rho_b >= rho0 for the
same reason), and the wall's density is the Tait equation of state solved
for it, rho_b = rho0 (1 + p_b / B)^(1/gamma), so that the pressure term, the
artificial viscosity and the filters see it as before. A wall particle with
no fluid neighbour takes p_b = 0. Continuity for the wall particles is not
integrated (their d rho / dt is zero).

Reference: S. Adami, X. Y. Hu, N. A. Adams, "A generalized wall boundary
condition for smoothed particle hydrodynamics", J. Comput. Phys. 231
(2012) 7057-7075.
"""

from .body_motion import motion_layout
from .eos import GAMMA
from .spec import FLUID, MOVING, REPULSIVE


def make_wall_pressure(jit, spec, kernels, pressure, make_gather, unpack):
    """Return ``particle_wall_pressure(i, pos, rho, kind, idp, motion_of, table, cell, cell_start, grid_dims,
    Parr)`` writing the extrapolated density of boundary particle i into ``rho[i]``.

    `table` is the motion table (`shoal.physics.body_motion.motion_layout`: each motion's acceleration,
    and its pivot, displacement, angular velocity and acceleration where it rotates); `motion_of` maps a
    particle id (`idp`) to its motion (read for moving boundary particles only).
    """
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    lay = motion_layout(dim)
    PIV, DISP, OMG, ACC, ALPHA, ROTATES = lay.pivot, lay.disp, lay.omega, lay.acc, lay.alpha, lay.rotates
    inv_gamma = F(1.0 / GAMMA)
    w, _ = kernels

    @jit
    def sum_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        s, sp, sx, sy_, sz = acc
        rho, kind = data
        if kind[j] != FLUID:
            return acc
        wq = w(r2 ** F(0.5) * P.inv_h, P)
        rj = rho[j]
        rw = rj * wq
        # r_bf = r_b - r_f = (dx, dy, dz)
        return s + wq, sp + pressure(rj, P) * wq, sx + rw * dx, sy_ + rw * dy, sz + rw * dz

    gather = make_gather(jit, spec, sum_pair)

    @jit
    def wall_acceleration(i, pos, m, table):
        """(a_x, a_y, a_z) of moving wall particle i of motion m: a_d + alpha x r + omega x (omega x r),
        r = x_i - c - d (2D: rotation about y, omega x (omega x r) = -omega_y^2 r)."""
        ax = F(table[m, ACC])
        if dim == 3:
            ay = F(table[m, ACC + 1])
            az = F(table[m, ACC + 2])
        else:
            ay = zero
            az = F(table[m, ACC + 1])
        if table[m, ROTATES] != 0.0:
            if dim == 2:
                rx = F(pos[i, 0] - (table[m, PIV] + table[m, DISP]))
                rz = F(pos[i, 1] - (table[m, PIV + 1] + table[m, DISP + 1]))
                om, al = F(table[m, OMG]), F(table[m, ALPHA])
                ax += al * rz - om * om * rx
                az += -al * rx - om * om * rz
            else:
                rx = F(pos[i, 0] - (table[m, PIV] + table[m, DISP]))
                ry = F(pos[i, 1] - (table[m, PIV + 1] + table[m, DISP + 1]))
                rz = F(pos[i, 2] - (table[m, PIV + 2] + table[m, DISP + 2]))
                wx, wy, wz = F(table[m, OMG]), F(table[m, OMG + 1]), F(table[m, OMG + 2])
                bx, by, bz = F(table[m, ALPHA]), F(table[m, ALPHA + 1]), F(table[m, ALPHA + 2])
                # omega x r, then omega x (omega x r)
                ux, uy, uz = wy * rz - wz * ry, wz * rx - wx * rz, wx * ry - wy * rx
                ax += (by * rz - bz * ry) + (wy * uz - wz * uy)
                ay += (bz * rx - bx * rz) + (wz * ux - wx * uz)
                az += (bx * ry - by * rx) + (wx * uy - wy * ux)
        return ax, ay, az

    @jit
    def particle_wall_pressure(i, pos, rho, kind, idp, motion_of, table, cell, cell_start, grid_dims, Parr):
        k = kind[i]
        if k == FLUID or k >= REPULSIVE:
            return
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        s, sp, sx, sy, sz = gather(i, (zero,), (zero, zero, zero, zero, zero), pos, cell, cell_start, gdims,
                                   (rho, kind), P)
        if s > zero:
            ax, ay, az = zero, zero, zero
            if k == MOVING:
                ax, ay, az = wall_acceleration(i, pos, motion_of[idp[i]], table)
            # 2D stores (x, z): the gather's dz is the z difference and dy is zero
            p = (sp + (P.gx - ax) * sx + (P.gy - ay) * sy + (P.gz - az) * sz) / s
            if p < zero:
                p = zero
            rho[i] = P.rho0 * (one + p / P.B) ** inv_gamma
        else:
            rho[i] = P.rho0

    return particle_wall_pressure
