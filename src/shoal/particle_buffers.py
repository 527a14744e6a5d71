"""`BufferZones`: the particles of a model's open boundaries, created, converted and removed each step.

Each particle carries a zone tag (``zone``, int8, a per-particle array that follows the sort): 0 for every
particle of the domain, k + 1 for a particle of the buffer of open boundary k (`shoal.open_boundary`). Buffer
particles are fluid particles to every kernel; what makes them a buffer:

* their rates are held at zero (`hold`, after each rate evaluation): the integrator moves them at their
  velocity and keeps their density, which `exchange` imposes;
* `exchange` (a stage of every step, after the integrator; `shoal.simulation.stages.OpenBoundaryExchange`):

  1. imposes the buffers' state: the velocity along the normal where the boundary imposes one (its
     tangential part zero), else the water's at the particle's mirror image across the plane (`_extrapolate`);
     at a boundary that holds its level, the speed of the shallow-water Riemann invariant
     (`shoal.open_boundary.riemann_speed`) from the depth and the mean speed of the water in a band next to
     the plane (`_band_state`);
     the density of the hydrostatic pressure rho0 g (level - z), of a fixed pressure, or the water's at the
     mirror image;
  2. a buffer particle now on the domain's side of its plane becomes fluid of the domain, and a copy of it
     is created `layers` dp further back, in the buffer (the buffer refills from its back end), unless a
     particle of the buffer is already within dp/2 of that place (`_clear_spawns`: after the flow has turned,
     the buffer's back holds water that came out of the domain); a particle of
     the domain now behind an open boundary's plane (within its section) joins that buffer; a buffer particle
     past the buffer's far end is removed;
  3. a boundary whose level is a time series fills its buffer to the level of the moment
     (`BufferZones._follow_levels`);
  4. the new particles are appended (the arrays grow when needed, `ParticleStore.ensure`), each with a new
     id (ids are never reused: `next_id`), and the removed rows are filled from the end (`_move_rows`).

The rows change order; the next sort puts them back in cell order. A one-process CPU run does this in place
on its arrays, a CUDA run on host mirrors of its device arrays (`ParticleStore.mirror`: the state goes to
the host and back each step, every array when rows were created or removed). On MPI ranks each rank does it
for the particles it owns (never its ghosts), the band sums and the buffers' column tops are combined over
the ranks and the new particles numbered rank after rank. The particles removed are counted (`removed`), not
recorded as escaped. The zone tags are among the model's arrays and `next_id`, `created`, `removed` in its
checkpoints (`checkpoint_state`): a one-process run resumes bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .physics.spec import FLUID
from .time_series import TimeSeries

GAMMA = 7.0
SPAWN_GAP = 0.5
"""A copy is not created within this many dp of a particle already in its buffer (`_clear_spawns`)."""


@njit(cache=True)
def _impose(n, pos, vel, rho, zone, axis, sign, imposed, pz, pu, pm, hydro, level, fixed, p_fixed, rho0, g, B):
    """Velocity and density of the buffer rows (module docstring, 1)."""
    dim = pos.shape[1]
    for i in range(n):
        t = zone[i]
        if t <= 0:
            continue
        k = t - 1
        z = pos[i, dim - 1]
        if imposed[k]:
            m = pm[k]
            if z <= pz[k, 0]:
                u = pu[k, 0]
            elif z >= pz[k, m - 1]:
                u = pu[k, m - 1]
            else:
                j = 1
                while pz[k, j] < z:
                    j += 1
                f = (z - pz[k, j - 1]) / (pz[k, j] - pz[k, j - 1])
                u = pu[k, j - 1] + f * (pu[k, j] - pu[k, j - 1])
            for d in range(dim):
                vel[i, d] = 0.0
            vel[i, axis[k]] = sign[k] * u
        if hydro[k]:
            p = rho0 * g * max(level[k] - z, 0.0)
            rho[i] = rho0 * (1.0 + p / B) ** (1.0 / 7.0)
        elif fixed[k]:
            rho[i] = rho0 * (1.0 + p_fixed[k] / B) ** (1.0 / 7.0)


DETERMINANT_LIMIT = 1e-3
"""Below this determinant of the normalised first-order system a mirror image takes the Shepard average
(`_extrapolate`), as DualSPHysics's ``determlimit`` does for its first-order extrapolation."""


@njit(cache=True)
def _extrapolate(n, pos, vel, rho, kind, zone, axis, x0, imposed, rho_extra, first, mass, cell_start, gdims, glo,
                 inv_cs, ncs, h, work):
    """The velocity of the buffer rows of the boundaries that impose none, and the density of those whose
    density is extrapolated, from the domain's fluid (zone 0) around each particle's mirror image across the
    plane, x_g = x_b + 2 |d| n (at the particle's height: the planes are vertical).

    First order (``first[k]``; Tafuni, Dominguez, Vacondio & Crespo 2018, as DualSPHysics): the value f_g and
    gradient grad f_g at x_g solve the corrected-kernel system (r_j = x_j - x_g, V_j = m / rho_j)

        sum_j V_j W_gj [1, r_j] . [f_g, grad f_g] = sum_j V_j W_gj f_j,
        sum_j V_j dW_gj/dx_g,d [1, r_j] . [f_g, grad f_g] = sum_j V_j dW_gj/dx_g,d f_j   (each axis d),

    which a linear field satisfies exactly, and the particle takes f_b = f_g + (x_b - x_g) . grad f_g. Where
    the support is too empty for it (a mirror image beside the free surface or a corner: the determinant of
    the system, normalised so that a full support gives 1, below `DETERMINANT_LIMIT`), and for the boundaries
    that ask for it (``extrapolation = "shepard"``), the Shepard average sum_j W_gj f_j / sum_j W_gj. The
    kernel is the Wendland shape (1 - q/2)^4 (2 q + 1), q = |r_j| / h, whose gradient with respect to x_g is
    5 (1 - q/2)^3 r_j / h^2; its normalisation cancels. `work` is a (4, 8) float64 scratch array."""
    dim = pos.shape[1]
    nx, ny, nz = gdims[0], gdims[1], gdims[2]
    supp2 = 4.0 * h * h
    inv_h2 = 1.0 / (h * h)
    # the integral of the kernel's shape over its support: a full support's sum_j V_j W_gj
    full = 4.0 * math.pi * h * h / 7.0 if dim == 2 else 16.0 * math.pi * h * h * h / 21.0
    m1 = dim + 1  # unknowns: f and its gradient
    for i in range(n):
        t = zone[i]
        if t <= 0 or (imposed[t - 1] and not rho_extra[t - 1]):
            continue
        k = t - 1
        gx = pos[i, 0]
        gy = pos[i, 1] if dim == 3 else 0.0
        gz = pos[i, dim - 1]
        if axis[k] == 0:
            gx = 2.0 * x0[k] - gx
        else:
            gy = 2.0 * x0[k] - gy
        ix = int((gx - glo[0]) * inv_cs)
        if dim == 3:
            iy = int((gy - glo[1]) * inv_cs)
            iz = int((gz - glo[2]) * inv_cs)
        else:
            iy = 0
            iz = int((gz - glo[1]) * inv_cs)
        # work[a, :m1]: the system's row a; work[a, 4 + c]: its right-hand side for field c (u_x, u_y, u_z, rho)
        for a in range(4):
            for c in range(8):
                work[a, c] = 0.0
        s = 0.0
        ux = 0.0
        uy = 0.0
        uz = 0.0
        sr = 0.0
        for zz in range(max(iz - ncs, 0), min(iz + ncs, nz - 1) + 1):
            for yy in range(max(iy - ncs, 0), min(iy + ncs, ny - 1) + 1):
                row = nx * (yy + ny * zz)
                x_lo = max(ix - ncs, 0)
                x_hi = min(ix + ncs, nx - 1)
                if x_lo > x_hi:
                    continue
                for j in range(cell_start[row + x_lo], cell_start[row + x_hi + 1]):
                    if kind[j] != FLUID or zone[j] != 0:
                        continue
                    rx = pos[j, 0] - gx
                    rz = pos[j, dim - 1] - gz
                    ry = pos[j, 1] - gy if dim == 3 else 0.0
                    r2 = rx * rx + ry * ry + rz * rz
                    if r2 >= supp2:
                        continue
                    q = math.sqrt(r2) / h
                    a3 = (1.0 - 0.5 * q) ** 3
                    w = a3 * (1.0 - 0.5 * q) * (2.0 * q + 1.0)
                    s += w
                    sr += w * rho[j]
                    ux += w * vel[j, 0]
                    uz += w * vel[j, dim - 1]
                    if dim == 3:
                        uy += w * vel[j, 1]
                    if not first[k]:
                        continue
                    v = mass / rho[j]
                    g = 5.0 * a3 * inv_h2 * v
                    for a in range(m1):
                        # row 0: V W; row 1 + d: V dW/dx_g,d (axes x, (y), z)
                        if a == 0:
                            wa = v * w
                        elif a == 1:
                            wa = g * rx
                        elif a == m1 - 1:
                            wa = g * rz
                        else:
                            wa = g * ry
                        work[a, 0] += wa
                        work[a, 1] += wa * rx
                        if dim == 3:
                            work[a, 2] += wa * ry
                        work[a, m1 - 1] += wa * rz
                        work[a, 4] += wa * vel[j, 0]
                        if dim == 3:
                            work[a, 5] += wa * vel[j, 1]
                        work[a, 6] += wa * vel[j, dim - 1]
                        work[a, 7] += wa * rho[j]
        if s <= 0.0:
            continue
        fx = ux / s
        fy = uy / s
        fz = uz / s
        fr = sr / s
        if first[k]:
            # Gaussian elimination with partial pivoting on the normalised system; det = the pivots' product
            det = 1.0
            for a in range(m1):
                for c in range(8):
                    work[a, c] /= full
            for c in range(m1):
                p = c
                for a in range(c + 1, m1):
                    if abs(work[a, c]) > abs(work[p, c]):
                        p = a
                if p != c:
                    det = -det
                    for b in range(8):
                        tmp = work[c, b]
                        work[c, b] = work[p, b]
                        work[p, b] = tmp
                piv = work[c, c]
                det *= piv
                if piv == 0.0:
                    break
                for a in range(c + 1, m1):
                    f = work[a, c] / piv
                    if f != 0.0:
                        for b in range(c, 8):
                            work[a, b] -= f * work[c, b]
            if abs(det) >= DETERMINANT_LIMIT:
                for b in range(4, 8):  # back substitution, field by field, into work[:, b]
                    for a in range(m1 - 1, -1, -1):
                        acc = work[a, b]
                        for c in range(a + 1, m1):
                            acc -= work[a, c] * work[c, b]
                        work[a, b] = acc / work[a, a]
                # f_b = f_g + (x_b - x_g) . grad f_g: x_b - x_g lies along the normal's axis
                step = pos[i, 0] - gx if axis[k] == 0 else pos[i, 1] - gy
                col = 1 + axis[k] if dim == 3 else 1
                fx = work[0, 4] + step * work[col, 4]
                fy = work[0, 5] + step * work[col, 5]
                fz = work[0, 6] + step * work[col, 6]
                fr = work[0, 7] + step * work[col, 7]
        if not imposed[k]:
            vel[i, 0] = fx
            vel[i, dim - 1] = fz
            if dim == 3:
                vel[i, 1] = fy
        if rho_extra[k]:
            rho[i] = fr


@njit(cache=True)
def _in_section(pos, i, k, axis, tlo, thi):
    """Whether row i lies within boundary k's section, its coordinates other than the normal's in [tlo, thi)."""
    for c in range(pos.shape[1]):
        if c != axis[k] and (pos[i, c] < tlo[k, c] or pos[i, c] >= thi[k, c]):
            return False
    return True


@njit(cache=True)
def _band_state(n, pos, vel, rho, kind, zone, ghost, axis, sign, x0, band, tlo, thi, mass, which, out):
    """For each boundary k with `which[k]`: out[k, 0] = sum of w V_j and out[k, 1] = sum of w V_j u_j over
    the domain's fluid inside the section at 0 <= d < band[k] from the plane (d along the normal, u_j the
    speed along it, V_j = mass / rho_j), with the tent weight w(d) = 4 min(d, band - d) / band^2 (unit integral
    over the band, zero at both ends: a particle enters and leaves the sums gradually). out[k, 0] / width is
    the water's depth next to the plane, out[k, 1] / out[k, 0] its mean speed."""
    nz = axis.shape[0]
    for k in range(nz):
        for c in range(out.shape[1]):
            out[k, c] = 0.0
    has_g = ghost.shape[0] >= n
    for i in range(n):
        if zone[i] != 0 or kind[i] != FLUID or (has_g and ghost[i] != 0):
            continue
        for k in range(nz):
            if not which[k]:
                continue
            d = sign[k] * (pos[i, axis[k]] - x0[k])
            L = band[k]
            if d < 0.0 or d >= L:
                continue
            if not _in_section(pos, i, k, axis, tlo, thi):
                continue
            w = 4.0 * min(d, L - d) / (L * L) * mass / rho[i]
            out[k, 0] += w
            out[k, 1] += w * sign[k] * vel[i, axis[k]]


@njit(cache=True)
def _classify(n, pos, kind, zone, ghost, axis, sign, x0, depth, tlo, thi, flags, spawn_src, spawn_zone):
    """Tag changes and the rows to remove or copy (module docstring, 2). Returns (spawns, removals), or
    (-1, 0) when `spawn_src` is too short (call again with a longer one)."""
    nz = axis.shape[0]
    s = 0
    r = 0
    has_g = ghost.shape[0] >= n
    for i in range(n):
        flags[i] = 0
        if has_g and ghost[i] != 0:
            continue  # another rank's particle: its owner converts it
        t = zone[i]
        if t > 0:
            k = t - 1
            d = sign[k] * (pos[i, axis[k]] - x0[k])
            if d >= 0.0:
                zone[i] = 0
                if s >= spawn_src.shape[0]:
                    return -1, 0
                spawn_src[s] = i
                spawn_zone[s] = k
                s += 1
            elif d < -depth[k]:
                flags[i] = 1
                r += 1
        elif kind[i] == FLUID:
            for k in range(nz):
                d = sign[k] * (pos[i, axis[k]] - x0[k])
                if d >= 0.0:
                    continue
                if not _in_section(pos, i, k, axis, tlo, thi):
                    continue
                if d >= -depth[k]:
                    zone[i] = k + 1
                else:
                    flags[i] = 1
                    r += 1
                break
    return s, r


@njit(cache=True)
def _trim(n, pos, zone, ghost, flags, k, limit):
    """Flag for removal the rows of boundary k's buffer above height `limit` (not another rank's); returns their
    count."""
    dim = pos.shape[1]
    has_g = ghost.shape[0] >= n
    r = 0
    for i in range(n):
        if has_g and ghost[i] != 0:
            continue
        if zone[i] == k + 1 and flags[i] == 0 and pos[i, dim - 1] > limit:
            flags[i] = 1
            r += 1
    return r


@njit(cache=True)
def _column(pos, i, tcol, t0, dp, ncol):
    """The lattice column (along the section's horizontal tangent, 3D) of row i; 0 in 2D."""
    if tcol < 0:
        return 0
    c = int(math.floor((pos[i, tcol] - t0) / dp))
    return min(max(c, 0), ncol - 1)


@njit(cache=True)
def _column_tops(n, pos, zone, ghost, flags, k, dp, tcol, t0, ztop):
    """ztop[c]: the height of the top particle of boundary k's buffer in each lattice column (this rank's; -inf
    in a column with none)."""
    dim = pos.shape[1]
    ncol = ztop.shape[0]
    has_g = ghost.shape[0] >= n
    for c in range(ncol):
        ztop[c] = -math.inf
    for i in range(n):
        if zone[i] == k + 1 and flags[i] == 0 and not (has_g and ghost[i] != 0):
            c = _column(pos, i, tcol, t0, dp, ncol)
            ztop[c] = max(ztop[c], pos[i, dim - 1])


@njit(cache=True)
def _top_rows(n, pos, zone, ghost, flags, k, level, dp, tcol, t0, ztop, src, kz, s0):
    """Append to `src` (from s0 on) the rows of boundary k's buffer in the top row of each lattice column
    (`ztop`, over every rank) whose top row stands at least dp below `level` (their copies a dp higher fill
    the buffer up to the level). Returns the new length of `src`, or -1 when it is too short."""
    dim = pos.shape[1]
    ncol = ztop.shape[0]
    has_g = ghost.shape[0] >= n
    s = s0
    for i in range(n):
        if zone[i] != k + 1 or flags[i] != 0 or (has_g and ghost[i] != 0):
            continue
        c = _column(pos, i, tcol, t0, dp, ncol)
        if ztop[c] + dp <= level and pos[i, dim - 1] >= ztop[c] - 0.5 * dp:
            if s >= src.shape[0]:
                return -1
            src[s] = i
            kz[s] = k
            s += 1
    return s


@njit(cache=True)
def _place_lifted(pos, zone, flags, idp, kz, dst0, count, dp, first_id):
    """The copies of top rows, `count` rows from `dst0` on: a dp higher, tagged, kept, numbered."""
    dim = pos.shape[1]
    for j in range(count):
        i = dst0 + j
        pos[i, dim - 1] += dp
        zone[i] = kz[j] + 1
        flags[i] = 0
        idp[i] = first_id + j


@njit(cache=True)
def _clear_spawns(count, pos, zone, src, kz, axis, sign, depth, gap, cell_start, gdims, glo, inv_cs):
    """Drop the copies (module docstring, 2) that would land within `gap` of a particle already in their
    buffer: after the flow through a plane has turned, the buffer's back holds water that came out of the domain,
    not the lattice the copies continue, and a copy on top of one of those particles would be thrown out by the
    pressure between them. Keeps the others in order in src / kz; returns their count. The rows searched are
    those of the last sort (`cell_start`), each within a cell of where it was then."""
    dim = pos.shape[1]
    nx, ny, nz = gdims[0], gdims[1], gdims[2]
    gap2 = gap * gap
    kept = 0
    for j in range(count):
        i = src[j]
        k = kz[j]
        tx = pos[i, 0]
        ty = pos[i, 1] if dim == 3 else 0.0
        tz = pos[i, dim - 1]
        if axis[k] == 0:
            tx -= sign[k] * depth[k]
        else:
            ty -= sign[k] * depth[k]
        ix = min(max(int((tx - glo[0]) * inv_cs), 0), nx - 1)
        if dim == 3:
            iy = min(max(int((ty - glo[1]) * inv_cs), 0), ny - 1)
            iz = min(max(int((tz - glo[2]) * inv_cs), 0), nz - 1)
        else:
            iy = 0
            iz = min(max(int((tz - glo[1]) * inv_cs), 0), nz - 1)
        clash = False
        for zz in range(max(iz - 1, 0), min(iz + 1, nz - 1) + 1):
            for yy in range(max(iy - 1, 0), min(iy + 1, ny - 1) + 1):
                row = nx * (yy + ny * zz)
                for q in range(cell_start[row + max(ix - 1, 0)], cell_start[row + min(ix + 1, nx - 1) + 1]):
                    if zone[q] != k + 1:
                        continue
                    dx = tx - pos[q, 0]
                    dz = tz - pos[q, dim - 1]
                    dy = ty - pos[q, 1] if dim == 3 else 0.0
                    if dx * dx + dy * dy + dz * dz < gap2:
                        clash = True
                        break
                if clash:
                    break
            if clash:
                break
        if not clash:
            src[kept] = i
            kz[kept] = k
            kept += 1
    return kept


@njit(cache=True)
def _copy_rows_2d(a, src, dst0, count):
    for j in range(count):
        for c in range(a.shape[1]):
            a[dst0 + j, c] = a[src[j], c]


@njit(cache=True)
def _copy_rows_1d(a, src, dst0, count):
    for j in range(count):
        a[dst0 + j] = a[src[j]]


@njit(cache=True)
def _place_spawns(pos, zone, idp, src, kz, dst0, count, axis, sign, depth, first_id):
    """The copies `count` rows from `dst0` on: moved `depth` back along their zone's normal, tagged and
    numbered."""
    for j in range(count):
        i = dst0 + j
        k = kz[j]
        pos[i, axis[k]] -= sign[k] * depth[k]
        zone[i] = k + 1
        idp[i] = first_id + j


@njit(cache=True)
def _holes(n, flags, holes, fillers):
    """Rows to fill (flagged, below n - removed) and the kept rows above that fill them, in order.
    Returns their count."""
    r = 0
    for i in range(n):
        if flags[i] != 0:
            r += 1
    keep_n = n - r
    h = 0
    for i in range(keep_n):
        if flags[i] != 0:
            holes[h] = i
            h += 1
    f = 0
    for i in range(keep_n, n):
        if flags[i] == 0:
            fillers[f] = i
            f += 1
    return h


@njit(cache=True)
def _move_rows_2d(a, holes, fillers, count):
    for j in range(count):
        for c in range(a.shape[1]):
            a[holes[j], c] = a[fillers[j], c]


@njit(cache=True)
def _move_rows_1d(a, holes, fillers, count):
    for j in range(count):
        a[holes[j]] = a[fillers[j]]


class BufferZones:
    """The open boundaries of a model at run time (module docstring).

    Parameters
    ----------
    model : Model
        A one-process model (CPU or CUDA backend); its rows `buffer_rows` (its initial order: row = id) are
        the buffers' particles at the start.
    zones : list of shoal.open_boundary.OpenBoundary
    buffer_zone : (N,) int array
        For each of the model's particles at the start, the index of its open boundary, -1 for the others.
    origin : 3 floats
        The particle lattice's origin [m] (`Case.lattice_origin`).
    surface_gravity : float
        |g| [m/s^2] for the hydrostatic density.
    """

    def __init__(self, model, zones, buffer_zone, origin, surface_gravity):
        from .errors import InputError
        from .open_boundary import plane_coordinate

        self.ranks = model.ghost_flags() is not None
        """The model is one MPI rank's slab (`shoal.parallel.model.DistributedModel`): each exchange works on its
        own particles, the counts, ids and band sums agreed over the ranks."""
        if not self.ranks and model.n != model.n_total:
            raise InputError("open boundaries need a model with all its particles active")
        self.model = model
        self.zones = list(zones)
        dim = model.dim
        cols = [0, 1, 2] if dim == 3 else [0, 2]
        internal = {c: k for k, c in enumerate(cols)}
        Z = len(self.zones)
        support = 2.0 * model.h
        self.axis = np.array([internal[z.axis] for z in self.zones], np.int64)
        self.sign = np.array([z.sign for z in self.zones], np.float64)
        self.x0 = np.array([plane_coordinate(z, model.dp, origin) for z in self.zones], np.float64)
        self.layers = np.array([z.buffer_layers(support, model.dp) for z in self.zones], np.int64)
        self.depth = self.layers * model.dp
        self.tlo = np.full((Z, dim), -math.inf)
        self.thi = np.full((Z, dim), math.inf)
        for k, z in enumerate(self.zones):
            lo, hi = z.section_box(dim)
            self.tlo[k] = lo[cols]
            self.thi[k] = hi[cols]
        M = max([2] + [len(z.profile.z) for z in self.zones if z.profile is not None])
        self.pz = np.zeros((Z, M))
        self.pu = np.zeros((Z, M))
        self.pm = np.ones(Z, np.int64)
        self.imposed = np.zeros(Z, np.bool_)
        for k, z in enumerate(self.zones):
            if z.profile is not None:
                m = len(z.profile.z)
                self.pz[k, :m], self.pu[k, :m], self.pm[k] = z.profile.z, z.profile.u, m
                self.imposed[k] = True
            else:
                u = z.speed(np.zeros(1), dim)
                if u is not None:
                    self.pu[k, 0] = u[0]
                    self.imposed[k] = True
        self.varies = [k for k, z in enumerate(self.zones) if z.varies]
        """The boundaries whose velocity, discharge or level is a `shoal.time_series.TimeSeries`."""
        self.water = np.array([z.follows_water for z in self.zones], np.bool_)
        """The boundaries whose level follows the water inside (`_follow_water`)."""
        self.follows = [k for k, z in enumerate(self.zones) if isinstance(z.level, TimeSeries) or self.water[k]]
        """The boundaries whose buffer is filled to a level that changes in time (`_follow_levels`)."""
        self._columns = {}
        for k in self.follows:
            z = self.zones[k]
            if dim == 2:
                self._columns[k] = (-1, 0.0, np.zeros(1))
            else:
                t = 1 - z.axis  # the section's horizontal tangent (x or y, also the internal column)
                lo, hi = sorted((z.lo[t], z.hi[t]))
                t0 = origin[t] + math.floor((lo - origin[t]) / model.dp) * model.dp
                self._columns[k] = (t, t0, np.zeros(int(math.ceil((hi - t0) / model.dp)) + 1))
        self.hydro = np.array([z.density_mode == "hydrostatic" for z in self.zones], np.bool_)
        self.fixed = np.array([z.density_mode == "fixed" for z in self.zones], np.bool_)
        self.p_fixed = np.array([z.pressure or 0.0 for z in self.zones], np.float64)
        self.rho_extra = np.array([z.density_mode == "extrapolated" for z in self.zones], np.bool_)
        self.first = np.array([z.extrapolation == "first_order" for z in self.zones], np.bool_)
        """The boundaries that extrapolate to first order (Tafuni et al. 2018), the others Shepard averages."""
        self._work = np.zeros((4, 8), np.float64)
        self.level = np.array([z.level_at(0.0) if z.level is not None else math.inf for z in self.zones], np.float64)
        self.riemann = np.array([z.holds_level for z in self.zones], np.bool_)
        self.imposed |= self.riemann
        self.band = np.full(Z, 3.0 * support)
        """Length of the band next to the plane [m] whose water gives the depth and speed of the Riemann
        invariant (three kernel supports)."""
        self.width = np.array([z.section_width(dim) for z in self.zones], np.float64)
        self.level_depth = np.array([z.level_at(0.0) - z.bed if z.holds_level else 0.0 for z in self.zones],
                                    np.float64)
        self._band = np.zeros((Z, 2))
        self._banded = self.riemann | self.water
        """The boundaries that read the water in the band next to their plane (`_band_sums`, one pass for all)."""
        self._riemann_ids = np.flatnonzero(self.riemann)
        self._water_ids = np.flatnonzero(self.water)
        self.top = np.array([max(z.lo[2], z.hi[2]) for z in self.zones], np.float64)
        """The top of each section [m]: a level that follows the water stops there."""
        self.mean_speed = np.full(Z, math.nan)
        """The running mean of the water's speed next to each level-holding plane [m/s] (`_hold_levels`; nan
        until the first exchange, which starts it at the water's speed then)."""
        self.tau = np.array([z.relaxation_time for z in self.zones], np.float64)
        self.g = float(surface_gravity)
        self.zone = model.new_array(model.scratch[(np.dtype(np.int8).str, 0)], owner=self)
        self.flags = model.new_array(model.scratch[(np.dtype(np.int8).str, 0)], owner=self)
        tags = (np.asarray(buffer_zone)[model.host(model.idp)] + 1).astype(np.int8)  # each row's, by its id
        local = int(np.count_nonzero(tags))
        model.backend.copy_into(self.zone, tags, model.n)
        # room for a buffer's worth of copies: a step creates its copies before it removes what left, so a
        # steady flow needs a few rows beyond its count, never the store's 25 % growth
        if model.store.capacity < model.n + local:
            model.store.resize(model.n + local)
        self.device = not model.backend.host_memory
        """The arrays live on a device: each exchange works on their host mirrors (`ParticleStore.mirror`)."""
        if self.device:
            model.store.mirror(self._arrays())
        self.next_id = int(model.n_total)
        """The id the next particle created gets."""
        self.created = 0
        """Particles created so far."""
        self.removed = 0
        """Particles removed so far (past a buffer's far end)."""
        self._spawn_src = np.zeros(max(64, local), np.int64)
        self._no_ghosts = np.zeros(0, np.int8)
        self._spawn_zone = np.zeros(len(self._spawn_src), np.int64)
        self._holes = np.zeros(len(self._spawn_src), np.int64)
        self._fillers = np.zeros(len(self._spawn_src), np.int64)

    def __len__(self):
        return len(self.zones)

    # ----------------------------------------------------------------- rates
    def hold(self, model):
        """Zero the buffer rows' rates (after each rate evaluation; the backends' ``hold_buffers`` kernel,
        `shoal.physics.buffer_hold`)."""
        b = model.backend
        b.timed(b.hold_buffers, model.n, (self.zone, model.ace, model.drho, model.xsph))

    def hold_shift(self, model, out):
        """Zero the buffer rows' particle shifts in `out` (between the shift and its application,
        `shoal.model.Model.apply_shifting`; the backends' ``hold_shift`` kernel): a buffer keeps its lattice."""
        b = model.backend
        b.timed(b.hold_shift, model.n, (self.zone, out))

    # --------------------------------------------------------------- the step
    def exchange(self, dt=0.0, t=0.0):
        """Impose the buffers' state, convert, create and remove particles (module docstring); `dt` [s] is the
        step just taken (for the running means of `_hold_levels`), `t` [s] the time now (for the quantities
        that change in time, `_follow_series`). On a device the work is done on host mirrors of the arrays:
        the state goes to the host, and back the imposed velocity, density and zone tags, or every array when
        rows were created or removed."""
        m = self.model
        st = m.store
        n = m.n
        if self.device:
            st.mirror(self._arrays())  # arrays made since (an integrator's) get theirs
            st.to_host(self._state(), n)
        H = st.host_of
        grid = self._host_grid()
        if self.varies:
            self._follow_series(t)
        if self._banded.any():
            self._band_sums()
            self._hold_levels(dt)
            self._follow_water()
        gh = self._ghosts()
        pos, vel, rho, kind, zone = (H(a) for a in self._state())
        _extrapolate(n, pos, vel, rho, kind, zone, self.axis, self.x0, self.imposed, self.rho_extra, self.first,
                     m.mass, *grid, int(m.options.cells_per_support), m.h, self._work)
        _impose(n, pos, vel, rho, zone, self.axis, self.sign, self.imposed, self.pz, self.pu, self.pm,
                self.hydro, self.level, self.fixed, self.p_fixed, m.rho0, self.g, m.B)
        while True:
            s, r = _classify(n, pos, kind, zone, gh, self.axis, self.sign, self.x0, self.depth, self.tlo,
                             self.thi, H(self.flags), self._spawn_src, self._spawn_zone)
            if s >= 0:
                break
            self._spawn_src = np.zeros(2 * len(self._spawn_src), np.int64)  # rare: more crossings than room
            self._spawn_zone = np.zeros(len(self._spawn_src), np.int64)
        if s:
            s = _clear_spawns(s, pos, zone, self._spawn_src, self._spawn_zone, self.axis, self.sign, self.depth,
                              SPAWN_GAP * m.dp, *grid)
        rows_change = bool(s or r or self.follows)
        if self.device and rows_change:  # the rest (the flags were written here)
            st.to_host([a for a in self._arrays() if all(a is not b for b in [*self._state(), self.flags])], n)
        del pos, vel, rho, kind, zone, gh  # growing the arrays (or their mirrors) may move them
        first, made = self._number(s)
        if s:
            st.ensure(n + s)
            for a in self._arrays():
                (_copy_rows_2d if a.ndim == 2 else _copy_rows_1d)(H(a), self._spawn_src, n, s)
            _place_spawns(H(m.pos), H(self.zone), H(m.idp), self._spawn_src, self._spawn_zone, n, s, self.axis,
                          self.sign, self.depth, first)
            # a copy's flag is its source's: 0 (a source became fluid this step, it is not removed)
            n += s
        if self.follows:
            r, lifted, lifted_all = self._follow_levels(n, r)
            n += lifted
            made += lifted_all
        gone = m.reduce(int(r), "sum") if self.ranks else r
        if r:
            if len(self._holes) < r:
                self._holes = np.zeros(2 * r, np.int64)
                self._fillers = np.zeros(2 * r, np.int64)
            h = _holes(n, H(self.flags), self._holes, self._fillers)
            for a in self._arrays():
                (_move_rows_2d if a.ndim == 2 else _move_rows_1d)(H(a), self._holes, self._fillers, h)
            n -= r
        self.removed += gone
        if self.device:
            st.to_device(self._arrays() if rows_change else [m.vel, m.rho, self.zone], n)
        m.n = n
        if self.ranks:
            m.n_total = m.n_global = m.n_global + made - gone
            # the halo's count of this rank's particles, for the counts read before the next sort
            m.halo.n_owned = int(np.count_nonzero(self._ghosts()[:n] == 0))
        else:
            m.n_total = n
        return s, r

    def _ghosts(self):
        """The ghost flags of the rows (host), or an empty array in one process (`_classify` etc.: no ghosts)."""
        return self.model.store.host_of(self.model.ghost_flags()) if self.ranks else self._no_ghosts

    def _number(self, count):
        """(the id of this process's first new particle, the particles new over all ranks) for `count` new
        particles here; advances `next_id` and `created`. With ranks, rank k's come after those of ranks below
        it (collective)."""
        m = self.model
        if self.ranks:
            counts = m.gather(int(count))
            first, made = self.next_id + sum(counts[:m.mpi_rank]), sum(counts)
        else:
            first, made = self.next_id, int(count)
        self.next_id += made
        self.created += made
        return first, made

    def _state(self):
        """The arrays the state imposed and the classification read and write."""
        m = self.model
        return [m.pos, m.vel, m.rho, m.kind, self.zone]

    def _host_grid(self):
        """(cell_start, cell counts per axis, grid corner, 1 / cell size) of the neighbour grid as host arrays:
        the cells of the last sort (the device's copied)."""
        gr = self.model.grid
        if not self.device:
            return gr.cell_start, gr.gdims_arr, gr.lo, 1.0 / gr.cell_size
        starts = gr.cell_start
        return (starts.copy_to_host(), np.asarray(gr.gdims, np.int64), np.asarray(gr.lo, np.float64),
                1.0 / gr.cell_size)

    def _follow_series(self, t):
        """The imposed speed, level and level-held depth of the boundaries given as time series, at time t."""
        dim = self.model.dim
        for k in self.varies:
            z = self.zones[k]
            if z.level is not None:
                self.level[k] = z.level_at(t)
                if z.holds_level:
                    self.level_depth[k] = self.level[k] - z.bed
            if z.profile is None and not z.holds_level:
                u = z.speed(np.zeros(1), dim, t)
                if u is not None:
                    self.pu[k, 0] = u[0]

    def _follow_levels(self, n, r):
        """Fill the buffers of the boundaries with a level that changes in time up to the level: the rows more
        than dp/2 above it are flagged for removal, and where the level stands a dp or more above a column's top
        row (over every rank) a copy of that row is appended a dp higher (new ids). Takes and returns the count
        of flagged rows, and returns the rows appended here (at n, with their imposed state) and over every
        rank."""
        m = self.model
        H = m.store.host_of
        dp = m.dp
        for k in self.follows:
            r += _trim(n, H(m.pos), H(self.zone), self._ghosts(), H(self.flags), k, self.level[k] + 0.5 * dp)
        # room for every buffer particle as a source: no rank retries alone between the collectives
        need = int(np.count_nonzero(H(self.zone)[:n]))
        if len(self._spawn_src) < need:
            self._spawn_src = np.zeros(2 * need, np.int64)
            self._spawn_zone = np.zeros(len(self._spawn_src), np.int64)
        total = made = 0
        while True:
            s = 0
            for k in self.follows:
                tcol, t0, ztop = self._columns[k]
                _column_tops(n + total, H(m.pos), H(self.zone), self._ghosts(), H(self.flags), k, dp, tcol, t0, ztop)
                if self.ranks:
                    ztop[:] = m.reduce_array(ztop, "max")
                s = _top_rows(n + total, H(m.pos), H(self.zone), self._ghosts(), H(self.flags), k, self.level[k], dp,
                              tcol, t0, ztop, self._spawn_src, self._spawn_zone, s)
            first, now = self._number(s)
            if not now:
                break
            if s:
                m.store.ensure(n + total + s)
                for a in self._arrays():
                    (_copy_rows_2d if a.ndim == 2 else _copy_rows_1d)(H(a), self._spawn_src, n + total, s)
                _place_lifted(H(m.pos), H(self.zone), H(self.flags), H(m.idp), self._spawn_zone, n + total, s, dp,
                              first)
            total += s
            made += now
        if total:
            _impose(n + total, H(m.pos), H(m.vel), H(m.rho), H(self.zone), self.axis, self.sign, self.imposed,
                    self.pz, self.pu, self.pm, self.hydro, self.level, self.fixed, self.p_fixed, m.rho0, self.g, m.B)
        return r, total, made

    def _band_sums(self):
        """`_band_state`'s sums into `_band` for every boundary that holds its level or follows the water, in
        one pass over the particles, over every rank."""
        m = self.model
        H = m.store.host_of
        _band_state(m.n, H(m.pos), H(m.vel), H(m.rho), H(m.kind), H(self.zone), self._ghosts(), self.axis,
                    self.sign, self.x0, self.band, self.tlo, self.thi, m.mass, self._banded, self._band)
        if self.ranks:
            self._band[:] = m.reduce_array(self._band, "sum")

    def _follow_water(self):
        """The level of each boundary that follows the water: the section's bottom plus the depth of the water
        in the band next to its plane (`_band_state`), at most the section's top."""
        for k in self._water_ids:
            depth = self._band[k, 0] / self.width[k]
            self.level[k] = min(self.zones[k].bed + depth, self.top[k])

    def _hold_levels(self, dt):
        """The speed of each boundary that holds its level, from the water next to its plane."""
        from .open_boundary import riemann_speed

        for k in self._riemann_ids:
            vol, flux = self._band[k]
            depth = vol / self.width[k]
            speed = flux / vol if vol > 0.0 else 0.0
            if math.isnan(self.mean_speed[k]):
                self.mean_speed[k] = speed
            self.mean_speed[k] += min(dt / self.tau[k], 1.0) * (speed - self.mean_speed[k])
            self.pu[k, 0] = riemann_speed(self.level_depth[k], depth, speed, self.mean_speed[k], self.g)

    def boundary_state(self, k):
        """(depth [m], mean speed [m/s]) of the water next to boundary k's plane at the last exchange (nan for
        a boundary that does not hold its level)."""
        if not self.riemann[k]:
            return math.nan, math.nan
        vol, flux = self._band[k]
        return vol / self.width[k], (flux / vol if vol > 0.0 else 0.0)

    def _arrays(self):
        """Every per-particle array once (the zone tags and flags among them)."""
        seen, out = set(), []
        for a in self.model.per_particle_arrays():
            if id(a) not in seen:
                seen.add(id(a))
                out.append(a)
        return out

    # ------------------------------------------------------------ checkpoints
    def checkpoint_state(self):
        """What a checkpoint keeps besides the zone tags (an array of the model's): the next id and the
        counts."""
        return {"next_id": int(self.next_id), "created": int(self.created), "removed": int(self.removed),
                "mean_speed": [None if math.isnan(v) else float(v) for v in self.mean_speed]}

    def restore_state(self, state):
        """Take `checkpoint_state`'s values back."""
        self.next_id = int(state["next_id"])
        self.created = int(state["created"])
        self.removed = int(state["removed"])
        if "mean_speed" in state:
            self.mean_speed[:] = [math.nan if v is None else v for v in state["mean_speed"]]

    # ---------------------------------------------------------------- counts
    def counts(self):
        """(fluid particles of the domain, buffer particles) now."""
        m = self.model
        z = m.host(self.zone)
        fluid = m.host(m.kind) == FLUID
        return int(np.count_nonzero(fluid & (z == 0))), int(np.count_nonzero(z > 0))
