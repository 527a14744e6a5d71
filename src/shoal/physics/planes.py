"""Geometric planes as walls, without particles (GPUSPH's "planes").

A plane acts on a fluid particle at distance d < 2h with the force of a
wall of Monaghan & Kajtar (2009) boundary particles at spacing dp/2 lying
on it, in the continuum limit (the sum over the wall's particles becomes
an integral), so a plane and a particle wall push alike but the plane has
no roughness and costs no particles:

    f(d) = (K / beta) (2 / dp)^(dim-1) int W(r / h) d / r^2 dA,  r^2 = d^2 + s^2,

over the plane (a line in 2D), normal to it, K = g D, beta = 2, W the
dimensionless Wendland shape (1 - q/2)^4 (1 + 2q). `plane_force_table`
tabulates f on [0, 2h] (in 3D, held at its peak below d = 0.42 dp, where
the continuum force would fall to zero); the kernels interpolate it.

The same wall's viscous term, -sum_b m_b Pi_ib grad_i W_ib with the wall at
rest, is kept for the velocity component towards the plane and dropped
along it (planes are free-slip, as GPUSPH's): for a particle approaching the
plane with normal velocity v_n < 0 every wall particle has v_ib . r_ib =
v_n d < 0, the tangential parts cancel by symmetry, and

    a_n = v_n (alpha c0 h m / rho_ij) G(d),  G(d) = (2 / dp)^(dim-1) int d^2 (-fr) / (r^2 + eta^2) dA

(artificial viscosity; rho_ij = (rho_i + rho0) / 2, fr = (dW/dr)/r of the
scheme's kernel, eta^2 = 0.01 h^2), or with laminar viscosity the normal
part of sum_b m_b 4 nu fr r^2 / ((rho_i + rho0)(r^2 + eta^2)) v_i, both
times `visco_bound_factor`. Without it a water column standing on a plane
bounces on the plane's repulsion like a mass on a spring, undamped (seen:
a 2D tank's column still oscillating +-5 mm, +-0.1 m/s, after 3 s); with it
the plane dissipates a normal impact as the particle wall does. The
planes' normals are what the free-surface detection of the probes needs
near them.
"""

from __future__ import annotations

import numpy as np

N_TABLE = 256


def _w(q):
    t = np.clip(1.0 - 0.5 * q, 0.0, None)
    return t**4 * (1.0 + 2.0 * q)


def plane_force_table(dim, dp, h, k_over_beta, n=N_TABLE):
    """f(d) [m/s^2] at d = 2h i / (n - 1), i = 0 .. n-1 (the first entry, d = 0,
    is the value at d = 2h / (n - 1) / 2 to stay finite)."""
    ds = np.linspace(0.0, 2.0 * h, n)
    ds[0] = 0.5 * ds[1]
    out = np.zeros(n)
    s = np.linspace(0.0, 2.0 * h, 4001)  # |s| up to the support
    for k, d in enumerate(ds):
        if dim == 2:
            r2 = d * d + s * s
            f = _w(np.sqrt(r2) / h) * d / r2
            integral = 2.0 * np.trapezoid(f, s)  # both sides of the foot point
            out[k] = k_over_beta * (2.0 / dp) * integral
        else:
            r2 = d * d + s * s
            f = _w(np.sqrt(r2) / h) * d / r2 * 2.0 * np.pi * s  # rings of radius s
            out[k] = k_over_beta * (2.0 / dp) ** 2 * np.trapezoid(f, s)
    out[-1] = 0.0
    # In 3D the continuum force vanishes as d -> 0 (like d log(2h/d)) and peaks at
    # d = 0.42 dp; below the peak the table holds the peak value, so a particle pushed
    # closer than that is never pushed less.
    return np.maximum.accumulate(out[::-1])[::-1]


def plane_viscous_table(dim, dp, h, kernel, viscosity, n=N_TABLE):
    """The normal viscous coefficient of a plane, per unit normal velocity, at
    d = 2h i / (n - 1): G(d) = (2/dp)^(dim-1) int d^2 (-fr) / (r^2 + eta^2) dA
    (artificial viscosity) or (2/dp)^(dim-1) int d^2 (-fr) / (r^2 + eta^2) dA
    with d^2 replaced by r^2 (laminar), [1/m^(dim+2)] x m^(dim-1)."""
    from .kernels import grad_factor_array
    from .spec import VISC_IDS

    ds = np.linspace(0.0, 2.0 * h, n)
    ds[0] = 0.5 * ds[1]
    eta2 = 0.01 * h * h
    s = np.linspace(0.0, 2.0 * h, 4001)
    out = np.zeros(n)
    for k, d in enumerate(ds):
        r2 = d * d + s * s
        fr = -grad_factor_array(kernel, dim, h, np.sqrt(r2) / h)
        top = d * d if viscosity == VISC_IDS["artificial"] else r2
        f = top * fr / (r2 + eta2)
        if dim == 2:
            out[k] = (2.0 / dp) * 2.0 * np.trapezoid(f, s)
        else:
            out[k] = (2.0 / dp) ** 2 * np.trapezoid(f * 2.0 * np.pi * s, s)
    out[-1] = 0.0
    return out


def plane_tables(spec, dp, h, k_over_beta):
    """(2, N_TABLE) array: the plane's force table and its viscous table."""
    return np.stack([plane_force_table(spec.dim, dp, h, k_over_beta),
                     plane_viscous_table(spec.dim, dp, h, spec.kernel, spec.viscosity)])


def make_plane_force(jit, spec):
    """Return ``plane_accel(xi, yi, zi, vxi, vyi, vzi, rhoi, planes, table, P) -> (ax, ay, az)``: the
    sum of the plane forces on a particle at (xi, yi, zi) moving at (vxi, vyi, vzi) with density
    rhoi (internal coordinates; in 2D y = 0).

    `planes` is (n_planes, 4) float64: unit normal (x, y, z) pointing into the
    fluid and offset c, the plane being n . r = c; `table` the (2, n) force and
    viscous tables (`plane_tables`).
    """
    from .spec import VISC_IDS

    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)
    two = F(2.0)
    artificial = spec.viscosity == VISC_IDS["artificial"]

    @jit
    def plane_accel(xi, yi, zi, vxi, vyi, vzi, rhoi, planes, table, P):
        ax = zero
        ay = zero
        az = zero
        nt = table.shape[1]
        two_h = 2.0 * P.h
        for k in range(planes.shape[0]):
            nx = planes[k, 0]
            ny = planes[k, 1]
            nz = planes[k, 2]
            d = nx * xi + ny * yi + nz * zi - planes[k, 3]
            if d < two_h:
                u = d / two_h * (nt - 1)
                if u < 0.0:
                    u = 0.0  # a particle through the plane gets the strongest push back
                j = int(u)
                if j >= nt - 1:
                    continue
                t = u - j
                f = F((1.0 - t) * table[0, j] + t * table[0, j + 1])
                vn = F(nx) * vxi + F(ny) * vyi + F(nz) * vzi
                if vn < zero:  # approaching: the normal part of the wall's viscous term
                    g = F((1.0 - t) * table[1, j] + t * table[1, j + 1])
                    if artificial:
                        c = P.alpha * P.c0 * P.h * P.mass_f * two / (rhoi + P.rho0)
                    else:
                        c = P.nu4 * P.mass_f / (rhoi + P.rho0)
                    f -= P.visc_bound * c * g * vn
                ax += f * F(nx)
                ay += f * F(ny)
                az += f * F(nz)
        return ax, ay, az

    return plane_accel
