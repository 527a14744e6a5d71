"""Wall planes: the continuum force table against a direct sum over a Monaghan-Kajtar particle wall."""

import numpy as np
import pytest

from shoal.physics.planes import _w, plane_force_table


@pytest.mark.parametrize("dim", [2, 3])
def test_plane_force_is_the_limit_of_a_particle_wall(dim):
    """f(d) equals the normal force of a fine wall of MK particles at spacing dp/2 lying on the plane
    (a direct sum over the wall's particles; the continuum limit is reached to 1 % for d >= dp/2)."""
    dp = 0.01
    h = np.sqrt(dim) * dp
    k = 9.81 * 0.5 / 2
    table = plane_force_table(dim, dp, h, k)
    ds = np.linspace(0, 2 * h, len(table))
    s = (np.arange(-400, 401) + 0.5) * dp / 2  # wall particles, offset from the foot point
    for d in (0.5 * dp, dp, 1.5 * dp, 2.0 * dp):
        if dim == 2:
            r2 = d * d + s * s
        else:
            sx, sy = np.meshgrid(s, s, indexing="ij")
            r2 = d * d + sx.ravel() ** 2 + sy.ravel() ** 2
        r = np.sqrt(r2)
        direct = k * np.sum(np.where(r < 2 * h, _w(r / h), 0.0) * d / r2)
        f = np.interp(d, ds, table)
        assert f == pytest.approx(direct, rel=0.01), d
    assert table[-1] == 0 and np.all(np.diff(table) <= 0)  # repulsive, never weaker closer to the plane


@pytest.mark.parametrize("dim", [2, 3])
def test_plane_viscous_table_is_the_limit_of_a_particle_wall(dim):
    """The normal viscous coefficient G(d) of a plane equals the direct sum over a fine wall of
    particles at spacing dp/2 of d^2 (-fr) / (r^2 + eta^2) (artificial viscosity, Wendland kernel),
    to 1 % for d >= dp/2; it is positive (it resists approach) and zero at the support's edge."""
    from shoal.physics.kernels import grad_factor_array
    from shoal.physics.planes import plane_viscous_table
    from shoal.physics.spec import KERNEL_IDS, VISC_IDS

    dp = 0.01
    h = np.sqrt(dim) * dp
    kern = KERNEL_IDS["wendland"]
    table = plane_viscous_table(dim, dp, h, kern, VISC_IDS["artificial"])
    ds = np.linspace(0, 2 * h, len(table))
    s = (np.arange(-400, 401) + 0.5) * dp / 2
    for d in (0.5 * dp, dp, 1.5 * dp, 2.0 * dp):
        if dim == 2:
            r2 = d * d + s * s
        else:
            sx, sy = np.meshgrid(s, s, indexing="ij")
            r2 = d * d + sx.ravel() ** 2 + sy.ravel() ** 2
        fr = -grad_factor_array(kern, dim, h, np.sqrt(r2) / h)
        direct = np.sum(d * d * fr / (r2 + 0.01 * h * h))
        assert np.interp(d, ds, table) == pytest.approx(direct, rel=0.01), d
    assert table[-1] == 0 and np.all(table[:-1] > 0)
