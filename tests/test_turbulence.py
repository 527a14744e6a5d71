"""SPS turbulence (Dalrymple & Rogers 2006): the eddy viscosity vanishes in
uniform flow and equals the Smagorinsky value for a prescribed shear."""

import numpy as np
import pytest

from shoal.model import Model
from shoal.options import SPHOptions


def _lattice(dim, n=16, dp=0.01):
    axes = [(np.arange(n) + 0.5) * dp] * 3
    if dim == 2:
        axes[1] = [0.0]
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3), dp


def _model(pos, vel, dim, dp, precision="float64", cs=0.12, ci=0.0066):
    opts = SPHOptions(precision=precision, turbulence="sps", sps_cs=cs, sps_ci=ci, density_diffusion="none")
    lo = pos.min(0) - dp
    hi = pos.max(0) + dp
    m = Model(pos, np.zeros(len(pos), np.int8), dp=dp, dim=dim, domain=(lo, hi), options=opts, gravity=(0, 0, 0),
              u_max=1.0, velocities=vel)
    m.sort()
    m.compute_rates()
    ids = m.host(m.idp)
    tau = np.empty_like(m.host(m.tau))
    tau[ids] = m.host(m.tau)
    return m, tau


def _lattice_gradient_factor(dim, dp, coef_h=1.0):
    """G = -sum_j V_j fr_ij dz_ij^2 over a full regular lattice neighbourhood: the SPH
    gradient of a linear field z is G (not exactly 1 on a lattice). Wendland C2:
    grad W = fr r_ij with fr = -5 aw / h^2 (1 - q/2)^3 (Wendland 1995)."""
    h = coef_h * np.sqrt(dim) * dp
    aw = 7 / (4 * np.pi * h**2) if dim == 2 else 21 / (16 * np.pi * h**3)
    k = np.arange(-4, 5) * dp
    grids = np.meshgrid(*([k] * dim), indexing="ij")
    off = np.stack([g.ravel() for g in grids], -1)
    r = np.linalg.norm(off, axis=1)
    q = r / h
    fr = np.where(q < 2, -5 * aw / h**2 * np.clip(1 - q / 2, 0, None) ** 3, 0.0)
    return float(-np.sum(dp**dim * fr * off[:, -1] ** 2))


def _interior(pos, dp, n, margin):
    c = (pos[:, [0, 2]] > margin * dp) & (pos[:, [0, 2]] < (n - margin) * dp)
    return np.all(c, axis=1)


@pytest.mark.parametrize("dim", [2, 3])
def test_no_eddy_viscosity_in_uniform_flow(dim):
    pos, dp = _lattice(dim)
    vel = np.tile([0.3, 0.2 if dim == 3 else 0.0, -0.1], (len(pos), 1))
    m, tau = _model(pos, vel, dim, dp)
    assert np.max(np.abs(tau)) < 1e-12


@pytest.mark.parametrize("dim", [2, 3])
def test_smagorinsky_stress_for_a_simple_shear(dim):
    """u = gamma z: S_xz = gamma / 2, |S| = gamma, nu_t = (Cs dp)^2 gamma;
    tau_xz / rho = 2 nu_t S_xz = (Cs dp)^2 gamma^2 and the isotropic part
    -(2/3) C_I dp^2 gamma^2 (div v = 0) on the diagonal (interior particles,
    where the SPH gradient of a linear field is exact to the kernel's
    lattice sum)."""
    n = 16
    pos, dp = _lattice(dim, n)
    gamma = 5.0
    vel = np.zeros_like(pos)
    vel[:, 0] = gamma * pos[:, 2]
    cs, ci = 0.12, 0.0066
    m, tau = _model(pos, vel, dim, dp, cs=cs, ci=ci)
    inner = _interior(pos, dp, n, 4)
    if dim == 3:
        inner &= (pos[:, 1] > 4 * dp) & (pos[:, 1] < (n - 4) * dp)
    rho = 1000.0
    xz_col, zz_col = (2, 5) if dim == 3 else (1, 2)
    tau_xz = tau[inner, xz_col] * rho  # stored tau / rho^2 = (tau / rho) / rho
    # the SPH velocity gradient of u = gamma z on the lattice is G gamma, G within 1 % of 1
    G = _lattice_gradient_factor(dim, dp)
    assert abs(G - 1) < 0.01
    g = G * gamma
    expect_xz = (cs * dp) ** 2 * g**2
    iso = -(2.0 / 3.0) * ci * dp**2 * g**2
    np.testing.assert_allclose(tau_xz, expect_xz, rtol=1e-9)
    np.testing.assert_allclose(tau[inner, 0] * rho, iso, rtol=1e-9)
    np.testing.assert_allclose(tau[inner, zz_col] * rho, iso, rtol=1e-9)
    # and nu_t itself: tau_xz / (2 S_xz) = (Cs dp)^2 |S|
    np.testing.assert_allclose(tau_xz / g, (cs * dp) ** 2 * g, rtol=1e-9)


def test_sps_force_is_the_divergence_of_the_stress():
    """For u = a z^2 (z > 0): S_xz = a z, |S| = 2 a z, so tau_xz / rho = 2 nu_t S_xz =
    4 (Cs dp)^2 a^2 z^2 and the SPS acceleration is its divergence d(tau_xz/rho)/dz =
    8 (Cs dp)^2 a^2 z (C_I = 0). The acceleration with SPS minus without is that, within 5 %
    (interior particles; the SPH divergence of the SPH gradient carries lattice errors of a
    few per cent)."""
    n = 24
    pos, dp = _lattice(2, n)
    a = 20.0
    vel = np.zeros_like(pos)
    vel[:, 0] = a * pos[:, 2] ** 2
    cs = 0.5  # a large Cs so the SPS force dominates round-off of the other terms
    m_on, _ = _model(pos, vel, 2, dp, cs=cs, ci=0.0)
    opts = SPHOptions(precision="float64", density_diffusion="none")
    lo, hi = pos.min(0) - dp, pos.max(0) + dp
    m_off = Model(pos, np.zeros(len(pos), np.int8), dp=dp, dim=2, domain=(lo, hi), options=opts, gravity=(0, 0, 0),
                  u_max=1.0, velocities=vel)
    m_off.sort()
    m_off.compute_rates()
    ace = []
    for m in (m_on, m_off):
        out = np.empty_like(m.host(m.ace))
        out[m.host(m.idp)] = m.host(m.ace)
        ace.append(out)
    inner = _interior(pos, dp, n, 5)
    z = pos[inner, 2]
    # tau_xz/rho = (Cs dp)^2 |S| 2 S_xz with S_xz = a z, |S| = 2 a z  ->  4 (Cs dp)^2 a^2 z^2
    expect = 8 * (cs * dp) ** 2 * a * a * z
    got = (ace[0] - ace[1])[inner, 0]
    np.testing.assert_allclose(got, expect, rtol=0.05)
