"""Contact of floating bodies with the walls and with each other: cells that push apart, with Coulomb friction.

Boundary particles do not interact with each other in SPH (a wall's pressure acts on the fluid only), so
without this a floating body would pass through the bed, a wall or another body. Each boundary particle
stands for its lattice cell, a square (3D: a cube) of side d_c = dp, or d_c / 2 for a repulsive
(Monaghan-Kajtar) particle, a node of the fine lattice whose outermost cells' faces are the wall's surface
(`shoal.geometry.generate`); here the cells are taken aligned with the world axes. The cell of a floating
body's particle b and the cell (half-side s_w) of a boundary particle w of another solid (a fixed wall, a
paddle, another body) overlap when |x_b - x_w| < d_c / 2 + s_w along every axis, by
o_a = d_c / 2 + s_w - |x_b - x_w|_a on axis a. They push apart along the axis n of their least overlap (the
separating axis of two boxes; +-x, +-y or +-z, towards b) with a linear spring-dashpot scaled by the
overlap's area across n, A = prod_{a != n} o_a / d_c^(dim-1):

    delta = o_n,   v = u_b - u_w,   v_n = v . n,   v_t = v - v_n n,
    F_n = A max(k delta - c v_n, 0),
    F_b += F_n n - min(mu F_n, A c |v_t|) v_t / |v_t|,

a normal spring-dashpot that never attracts (the discrete-element contact of Cundall & Strack 1979) and a
tangential force that is Coulomb's friction mu F_n while the surfaces slide and a dashpot below that (the
history-free regularised friction of Haff & Werner 1986, LAMMPS's ``gran/hooke``; DualSPHysics's DEM,
Canelas et al. 2016, caps its Coulomb force the same way). Why cells and not spheres: the areas A of one
cell over a flat wall of cells sum to one whatever its offset along the wall (the overlaps' lengths along
the wall add up to the cell's side), so a body slides over a flat wall of particles as over a flat surface; spheres of diameter dp
(the contact of DualSPHysics's DEM) let each particle dip 0.13 dp between two of the wall's and the body
ride over them as over cobbles (measured here: a frictionless box sliding at 1 m/s on a particle bed lost
70 % of its speed in 0.35 s). The force is equal and opposite between two bodies' particles. A body that
has turned meets the walls with world-aligned cells, a staircase along its tilted faces: the exact
geometry of tilted contacts is not modelled.

The stiffness is that of the water itself: a layer of fluid of thickness dp compressed by delta pushes
with the pressure rho0 c0^2 delta / dp on a face dp^(dim-1), so

    k = rho0 c0^2 dp^(dim-2),   c = 2 sqrt(k m),   m = rho0 dp^dim

(critically damped for a particle of the water's mass; a body with more mass per contact rebounds a little,
with the restitution exp(-pi zeta / sqrt(1 - zeta^2)), zeta = sqrt(m / m_contact): a box of 40 kg/m meeting
a wall with 10 particles, 0.35), and a contact resolves in the time step the fluid already takes (its period
2 pi sqrt(m / k) = 2 pi dp / c0, some 40 of the acoustic time steps CFL h / c0).

A wall plane (`shoal.case.WallPlane`, `shoal.physics.planes`) pushes a body's particle whose cell reaches
it, at the height d < d_c / 2 above it, the same way along its unit normal n: F_n = max(k (d_c / 2 - d) -
c u_b . n, 0) (A = 1), the friction as above with v = u_b (planes are at rest); a tilted plane is a slope
without the lattice's steps.

Friction: mu is the floating body's (`shoal.floating.FloatingBody.friction`, 0 by default: frictionless);
two floating bodies in contact take the mean of their two, as DualSPHysics's DEM does. The dashpot c
bounds the tangential force at low sliding speed, so a body held by friction creeps: a tangential load T
(below mu times its normal load) carried by n cell contacts moves it at T / (n c), e.g. 5.7 mm/s for a 2D
box of 40 kg/m on a 10 degree slope on 20 contacts at dp = 0.01 m, c0 = 30 m/s; stiffer, c would no longer
be stable for a body of one water particle's mass per contact. Without a history of each pair's
tangential displacement (Cundall & Strack's spring) there is no exact sticking.

Why this and not the walls' own pressure (DualSPHysics's floating particles meet the walls through the
dynamic boundary condition, as fluid does): a body's particles are walls here, whose pressure comes from
the fluid, so a body with no water between it and the bed would feel nothing; a contact force acts
whatever the water does, and its stiffness keeps the overlap of a resting body to k / (its weight per
contact), far below dp.

The force goes into the body's loads (`shoal.body_coupling`) and, summed like the fluid's, over MPI ranks;
a wall's reaction is not applied (walls do not move), another body's is its own particles' sum.
"""

from .rates import make_store
from .spec import FLUID, MOVING, REPULSIVE, REPULSIVE_MOVING


def contact_constants(rho0, c0, dp, dim):
    """(d_c [m], k, c) of the contact force (module docstring): d_c = dp, k = rho0 c0^2 dp^(dim-2) [N/m; 2D:
    N/m per metre], c = 2 sqrt(k rho0 dp^dim) [N s/m; 2D: per metre]."""
    k = rho0 * c0 * c0 * dp ** (dim - 2)
    return dp, k, 2.0 * (k * rho0 * dp ** dim) ** 0.5


def make_contact(jit, spec, make_gather, unpack):
    """Return ``particle_contact(i, pos, vel, kind, idp, motion_of, row, friction, planes, cell, cell_start,
    grid_dims, Parr, dc, k, c, force)`` writing into ``force[i]`` (internal components) the contact force on
    particle i of a floating body (``row[motion_of[idp[i]]] >= 0``), zero for every other particle;
    ``friction[m]`` is the Coulomb coefficient of the floating body of motion m, `planes` (n, 4) the wall
    planes (unit normal, offset; read only when the scheme has planes) (module docstring)."""
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)

    @jit
    def contact_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        fx, fy, fz = acc
        m, ux, uy, uz, dc, k, c, mu = own
        vel, kind, idp, motion_of, row, friction = data
        kj = kind[j]
        if kj == FLUID or kj > REPULSIVE_MOVING:
            return acc
        if kj == MOVING:
            mj = motion_of[idp[j]]
            if mj == m:
                return acc  # the body's own particle
            if row[mj] >= 0:
                mu = 0.5 * (mu + friction[mj])  # another floating body: the mean of the two
        # j's cell: side dc, or dc/2 for a repulsive particle (a node of the fine lattice, whose outer face is
        # the wall's surface)
        hw = 0.5 * dc if kj < REPULSIVE else 0.25 * dc
        reach = 0.5 * dc + hw
        ox = reach - abs(dx)
        oz = reach - abs(dz)
        oy = reach - abs(dy) if dim == 3 else dc
        if ox <= 0.0 or oy <= 0.0 or oz <= 0.0:
            return acc
        # the separating axis: the least overlap; A, the overlap's area across it, over dc^(dim-1)
        nx, ny, nz = 0.0, 0.0, 0.0
        if ox <= oz and ox <= oy:
            delta = ox
            area = oz * oy / (dc * dc) if dim == 3 else oz / dc
            nx = 1.0 if dx >= 0.0 else -1.0
        elif oz <= oy:
            delta = oz
            area = ox * oy / (dc * dc) if dim == 3 else ox / dc
            nz = 1.0 if dz >= 0.0 else -1.0
        else:
            delta = oy
            area = ox * oz / (dc * dc)
            ny = 1.0 if dy >= 0.0 else -1.0
        vjx = vel[j, 0]
        vjz = vel[j, dim - 1]
        vjy = sy * vel[j, 1] if dim == 3 else zero
        wx, wy, wz = ux - vjx, uy - vjy, uz - vjz
        vn = wx * nx + wy * ny + wz * nz
        f = k * delta - c * vn
        if f <= 0.0:
            return acc
        f = area * f
        fx, fy, fz = fx + f * nx, fy + f * ny, fz + f * nz
        if mu > 0.0:
            tx, ty, tz = wx - vn * nx, wy - vn * ny, wz - vn * nz
            vt = (tx * tx + ty * ty + tz * tz) ** 0.5
            if vt > 0.0:
                ft = min(mu * f, area * c * vt) / vt
                fx, fy, fz = fx - ft * tx, fy - ft * ty, fz - ft * tz
        return fx, fy, fz

    gather = make_gather(jit, spec, contact_pair)
    store = make_store(jit, spec)

    use_planes = spec.planes

    @jit
    def particle_contact(i, pos, vel, kind, idp, motion_of, row, friction, planes, cell, cell_start, grid_dims, Parr,
                         dc, k, c, force):
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
        mu = float(friction[m])
        fx, fy, fz = gather(i, (m, ux, uy, uz, dc, k, c, mu), (0.0, 0.0, 0.0), pos, cell, cell_start,
                            gdims, (vel, kind, idp, motion_of, row, friction), P)
        if use_planes:
            x = float(pos[i, 0])
            y = float(pos[i, 1]) if dim == 3 else 0.0
            z = float(pos[i, dim - 1])
            for p in range(planes.shape[0]):
                ex, ey, ez = planes[p, 0], planes[p, 1], planes[p, 2]
                gap = ex * x + ey * y + ez * z - planes[p, 3]  # the particle's height above the plane
                if gap >= 0.5 * dc or gap <= -0.5 * dc:
                    continue  # not touching (or behind the plane: another side of the domain)
                vn = ux * ex + uy * ey + uz * ez
                f = k * (0.5 * dc - gap) - c * vn
                if f <= 0.0:
                    continue
                fx, fy, fz = fx + f * ex, fy + f * ey, fz + f * ez
                if mu > 0.0:
                    tx, ty, tz = ux - vn * ex, uy - vn * ey, uz - vn * ez
                    vt = (tx * tx + ty * ty + tz * tz) ** 0.5
                    if vt > 0.0:
                        ft = min(mu * f, c * vt) / vt
                        fx, fy, fz = fx - ft * tx, fy - ft * ty, fz - ft * tz
        store(force, i, 1.0, fx, fy, fz)

    return particle_contact
