"""SPH interpolation at fixed points (probes, test points, wave gauges).

At a point x_p, with V_j = m_j / rho_j over the fluid particles within 2h
(rip-current paper, Eq. 11; GPUSPH's test points):

    plain:     A(x_p) = sum_j V_j A_j W(x_p - x_j)
    Shepard:   A(x_p) = sum_j V_j A_j W_pj / sum_j V_j W_pj

The kernel sum S = sum_j V_j W_pj is 1 inside the fluid and falls to 1/2 at
a free surface (half the support is empty): the plain sum is biased low
there by the factor S, which the Shepard form divides out. Shepard is the
default; S itself is what the wave gauges threshold (S >= 1/2 is water).

`make_probe` writes, for probe k, out[k] = (S, sum V p W, sum V rho W,
sum V u W [, sum V v W], sum V w W) in the working precision; the host
divides (Shepard) or not (plain).
"""

from .spec import FLUID


def n_probe_columns(dim):
    """Columns of the probe output: S, p, rho, and dim velocity components."""
    return 3 + dim


def make_probe(jit, spec, kernels, pressure, make_point_gather, unpack):
    """Return ``probe(k, points, pos, vel, rho, kind, cell_start, grid_dims, glo, inv_cs, Parr, out)``."""
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)
    w, _ = kernels

    @jit
    def probe_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        s, sp, sr, su, sv, sw = acc
        vel, rho, kind = data
        if kind[j] != FLUID:
            return acc
        # j's arrays are read before the calls: read after them, Numba kept a reference-count
        # increment and decrement per pair (`benchmarks/refcounts.py`)
        rj = rho[j]
        uj = vel[j, 0]
        vj = vel[j, 1] if dim == 3 else zero
        wj = vel[j, dim - 1]
        vw = P.mass_f / rj * w(r2 ** F(0.5) * P.inv_h, P)
        return (s + vw, sp + vw * pressure(rj, P), sr + vw * rj, su + vw * uj, sv + vw * vj, sw + vw * wj)

    gather_at = make_point_gather(jit, spec, probe_pair)

    @jit
    def probe(k, points, pos, vel, rho, kind, cell_start, grid_dims, glo, inv_cs, Parr, out):
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        acc = (zero, zero, zero, zero, zero, zero)
        s, sp, sr, su, sv, sw = gather_at(points[k, 0], points[k, 1], points[k, 2], 0, acc, pos, cell_start, gdims,
                                          glo, inv_cs, (vel, rho, kind), P)
        out[k, 0] = s
        out[k, 1] = sp
        out[k, 2] = sr
        out[k, 3] = su
        if dim == 3:
            out[k, 4] = sv
            out[k, 5] = sw
        else:
            out[k, 4] = sw

    return probe


def n_moment_columns(dim):
    """Columns of `make_sensor_moments`'s output: 14 in 3D, 9 in 2D."""
    return 14 if dim == 3 else 9


def make_sensor_moments(jit, spec, kernels, pressure, make_point_gather, unpack):
    """Return ``moments(k, points, pos, rho, kind, cell_start, grid_dims, glo, inv_cs, Parr, out)``: the
    weighted moments of the fluid around point k from which `shoal.probes.pressure_sensors` fits the
    pressure by linear least squares.

    ``points[k, :3]`` is the point, ``points[k, 3:6]`` the unit normal n_k of the wall it sits on (out of
    the wall into the fluid; zero for none) and ``points[k, 6]`` a depth b_k >= 0. Only the fluid
    particles in front of the wall's plane through the point, or less than b_k behind it, count:
    (x_j - x_k) . n_k >= -b_k. A transducer's face sees nothing behind it (water that has run over the
    wall's edge, or lies on the other side of a thin wall); b_k (half a spacing) keeps the particles that
    an impact has pressed a fraction of a spacing past the wall's surface, which still touch it.

    With weights w_j = V_j W(x_k - x_j) over the fluid particles within 2h (V_j = m_j / rho_j) and the
    offsets e_j = (x_j - x_k) / h, out[k] holds, in 3D,

        S, sum w e (3), sum w e e^T (xx, xy, xz, yy, yz, zz), sum w p, sum w p e (3)

    and in 2D S, sum w e (x, z), sum w e e^T (xx, xz, zz), sum w p, sum w p e (x, z). The sums are
    additive over disjoint sets of particles (MPI ranks add theirs); the offsets are scaled by 1/h so
    that the moment matrix is of order one in float32.
    """
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)
    w, _ = kernels

    @jit
    def moment_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        s, ex, ey, ez, exx, exy, exz, eyy, eyz, ezz, sp, px, py, pz = acc
        rho, kind, points = data
        if kind[j] != FLUID:
            return acc
        # (dx, dy, dz) = point - x_j, so j is behind the wall's plane where it has a positive projection
        if dx * F(points[own, 3]) + dy * F(points[own, 4]) + dz * F(points[own, 5]) > F(points[own, 6]):
            return acc
        rj = rho[j]
        wj = P.mass_f / rj * w(r2 ** F(0.5) * P.inv_h, P)
        pw = pressure(rj, P) * wj
        # (dx, dy, dz) = point - x_j: the offset of j from the point is its negative
        x, y, z = -dx * P.inv_h, -dy * P.inv_h, -dz * P.inv_h
        return (s + wj, ex + wj * x, ey + wj * y, ez + wj * z, exx + wj * x * x, exy + wj * x * y,
                exz + wj * x * z, eyy + wj * y * y, eyz + wj * y * z, ezz + wj * z * z, sp + pw,
                px + pw * x, py + pw * y, pz + pw * z)

    gather_at = make_point_gather(jit, spec, moment_pair)

    @jit
    def moments(k, points, pos, rho, kind, cell_start, grid_dims, glo, inv_cs, Parr, out):
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        acc = (zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero)
        s, ex, ey, ez, exx, exy, exz, eyy, eyz, ezz, sp, px, py, pz = gather_at(
            points[k, 0], points[k, 1], points[k, 2], k, acc, pos, cell_start, gdims, glo, inv_cs,
            (rho, kind, points), P)
        out[k, 0] = s
        if dim == 3:
            out[k, 1] = ex
            out[k, 2] = ey
            out[k, 3] = ez
            out[k, 4] = exx
            out[k, 5] = exy
            out[k, 6] = exz
            out[k, 7] = eyy
            out[k, 8] = eyz
            out[k, 9] = ezz
            out[k, 10] = sp
            out[k, 11] = px
            out[k, 12] = py
            out[k, 13] = pz
        else:
            # 2D stores (x, z): the gather's dz is the z offset, dy is zero
            out[k, 1] = ex
            out[k, 2] = ez
            out[k, 3] = exx
            out[k, 4] = exz
            out[k, 5] = ezz
            out[k, 6] = sp
            out[k, 7] = px
            out[k, 8] = pz

    return moments
