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

from ..physics.spec import FLUID


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
