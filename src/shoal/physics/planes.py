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
the continuum force would fall to zero); the kernels interpolate it. Planes are free-slip
(no viscous term), as GPUSPH's; their normals are what the free-surface
detection of the probes needs near them.
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


def make_plane_force(jit, spec):
    """Return ``plane_accel(xi, yi, zi, planes, table, P) -> (ax, ay, az)``: the sum of the
    plane forces on a particle at (xi, yi, zi) (internal coordinates; in 2D y = 0).

    `planes` is (n_planes, 4) float64: unit normal (x, y, z) pointing into the
    fluid and offset c, the plane being n . r = c; `table` the force table.
    """
    F = spec.float_type
    dim = spec.dim
    zero = F(0.0)

    @jit
    def plane_accel(xi, yi, zi, planes, table, P):
        ax = zero
        ay = zero
        az = zero
        nt = table.shape[0]
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
                f = F((1.0 - t) * table[j] + t * table[j + 1])
                ax += f * F(nx)
                ay += f * F(ny)
                az += f * F(nz)
        return ax, ay, az

    return plane_accel
