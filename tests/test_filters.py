"""Density filters: Shepard (zeroth order) and MLS (first order).

* MLS (Colagrossi & Landrini 2003) reproduces a linear density field
  exactly, whatever the particle arrangement, as long as the moment matrix
  is well conditioned: in the interior and along the free edges.
* Shepard reproduces a constant field exactly everywhere; in the interior
  of a regular lattice it keeps a gentle linear field too, but at a free
  edge its one-sided average is biased (a known property, which the MLS
  correction removes).
* Both match a NumPy transcription of their formulas on a noisy,
  jittered block (including MLS's Shepard fallback).
* Boundary particles keep their density.
"""

from __future__ import annotations

import numpy as np
import pytest

from shoal.options import SPHOptions
from shoal.physics.spec import FIXED, FLUID

OPTIONS = SPHOptions(precision="float64")
SLOPE = 1e-3  # rho = rho0 (1 + SLOPE x / L)


def _block(fluid_block, dim, jitter=0.0, kinds=None, seed=0):
    n_side = (24, 20) if dim == 2 else (11, 10, 10)
    return fluid_block(dim, n_side, OPTIONS, dp=0.01, jitter=jitter, seed=seed, kinds=kinds)


def _linear_field(model, direction=None):
    n = model.n
    pos = model.pos[:n]
    L = np.ptp(pos[:, 0])
    if direction is None:
        direction = np.zeros(model.dim)
        direction[0] = 1.0
    return model.rho0 * (1.0 + SLOPE * (pos @ direction) / L)


def _interior(model, margin_h=2.0):
    n = model.n
    pos = model.pos[:n]
    lo, hi = pos.min(0), pos.max(0)
    m = margin_h * model.h
    return np.all((pos > lo + m) & (pos < hi - m), axis=1)


@pytest.mark.parametrize("jitter", [0.0, 0.2], ids=["lattice", "jittered"])
@pytest.mark.parametrize("dim", [2, 3])
def test_mls_reproduces_linear_field(fluid_block, dim, jitter):
    model = _block(fluid_block, dim, jitter=jitter, seed=dim)
    n = model.n
    direction = np.array([1.0, -0.6, 0.3])[:dim]
    exact = _linear_field(model, direction)
    model.rho[:n] = exact
    model.apply_filter("mls")
    err = np.abs(model.rho[:n] / exact - 1.0)
    assert np.count_nonzero(_interior(model)) >= 8
    # first-order consistency holds in the interior and along the free
    # edges and corners alike (the moment matrix stays well conditioned)
    assert err.max() < 1e-12


@pytest.mark.parametrize("kind", ["shepard", "mls"])
def test_filters_smooth_noise(fluid_block, kind):
    """The filters do filter: small-scale density noise on a linear field is
    damped (so the exactness tests above cannot pass with a no-op filter)."""
    model = _block(fluid_block, 2, jitter=0.1, seed=4)
    n = model.n
    exact = _linear_field(model)
    noise = 1e-4 * np.random.default_rng(9).standard_normal(n)
    model.rho[:n] = exact * (1.0 + noise)
    model.apply_filter(kind)
    inner = _interior(model)
    before = np.sqrt(np.mean(noise[inner] ** 2))
    after = np.sqrt(np.mean((model.rho[:n][inner] / exact[inner] - 1.0) ** 2))
    assert after < before / 2  # about 2.7x for both with h = 1.41 dp


@pytest.mark.parametrize("dim", [2, 3])
def test_shepard_reproduces_constant_field(fluid_block, dim):
    model = _block(fluid_block, dim, jitter=0.2, seed=10 + dim)
    n = model.n
    rho_c = 1013.25
    model.rho[:n] = rho_c
    model.apply_filter("shepard")
    np.testing.assert_allclose(model.rho[:n], rho_c, rtol=1e-13)
    model.apply_filter("mls")
    np.testing.assert_allclose(model.rho[:n], rho_c, rtol=1e-12)


def test_shepard_linear_field_interior_and_edge_bias(fluid_block):
    model = _block(fluid_block, 2)
    n = model.n
    exact = _linear_field(model)
    model.rho[:n] = exact
    model.apply_filter("shepard")
    err = model.rho[:n] / exact - 1.0
    inner = _interior(model)
    # lattice symmetry cancels the first moment in the interior; what is left
    # is the harmonic-mean curvature, O((SLOPE h / L)^2) ~ 4e-9
    assert np.abs(err[inner]).max() < 1e-7
    # at the left and right free edges the average is one-sided: biased
    # towards the interior by a fraction of SLOPE h / L
    pos = model.pos[:n]
    L = np.ptp(pos[:, 0])
    left = pos[:, 0] < pos[:, 0].min() + 0.5 * model.dp
    right = pos[:, 0] > pos[:, 0].max() - 0.5 * model.dp
    bias = SLOPE * model.h / L
    assert np.all(err[left] > 0.1 * bias) and np.all(err[right] < -0.1 * bias)
    assert np.abs(err).max() < 2 * bias


def _wendland(r, h, dim):
    aw = 7.0 / (4.0 * np.pi * h**2) if dim == 2 else 21.0 / (16.0 * np.pi * h**3)
    q = r / h
    return aw * np.clip(1.0 - 0.5 * q, 0.0, None) ** 4 * (2.0 * q + 1.0)


def _reference_filters(pos, rho, mass, h, dim):
    """Shepard and MLS written out with NumPy from the formulas in
    shoal.physics.filters (all neighbours within 2h, i included)."""
    rij = pos[:, None, :] - pos[None, :, :]
    r = np.sqrt((rij**2).sum(-1))
    W = np.where(r < 2 * h, _wendland(r, h, dim), 0.0)
    shepard = (mass * W).sum(1) / (mass * W / rho[None, :]).sum(1)
    mls = np.empty(len(pos))
    for i in range(len(pos)):
        j = W[i] > 0
        basis = np.column_stack([np.ones(j.sum()), rij[i, j]])  # (1, r_i - r_j)
        v = mass * W[i, j] / rho[j]
        A = (basis * v[:, None]).T @ basis
        hadamard = np.linalg.det(A) / np.prod(np.diag(A))
        if hadamard > 1e-3:
            beta = np.linalg.solve(A, np.eye(dim + 1)[0])
        else:
            beta = np.eye(dim + 1)[0] / A[0, 0]
        mls[i] = (mass * W[i, j] * (basis @ beta)).sum()
    return shepard, mls


@pytest.mark.parametrize("dim", [2, 3])
def test_filters_match_reference_formulas(fluid_block, dim):
    n_side = (12, 10) if dim == 2 else (7, 6, 6)
    model = fluid_block(dim, n_side, OPTIONS, dp=0.01, jitter=0.2, seed=21)
    n = model.n
    rng = np.random.default_rng(5)
    rho = model.rho0 * (1.0 + 0.01 * rng.standard_normal(n))
    pos = model.pos[:n].copy()
    ref_shepard, ref_mls = _reference_filters(pos, rho, model.mass, model.h, dim)
    for kind, ref in (("shepard", ref_shepard), ("mls", ref_mls)):
        model.rho[:n] = rho
        model.apply_filter(kind)
        np.testing.assert_allclose(model.rho[:n], ref, rtol=1e-12, err_msg=kind)
    # the filters changed the noisy field noticeably
    assert np.abs(ref_mls / rho - 1).max() > 1e-3


def test_filters_keep_boundary_density_and_use_it(fluid_block):
    """Boundary particles are not filtered but take part as neighbours with
    their own density: a linear field across fluid and walls stays exact."""
    dim = 2

    def kinds(pos):
        return np.where(pos[:, 2] < 0.03, FIXED, FLUID)

    model = _block(fluid_block, dim, kinds=kinds)
    n = model.n
    exact = _linear_field(model, np.array([0.4, 1.0]))
    wall = model.kind[:n] != FLUID
    assert 0 < np.count_nonzero(wall) < n
    rho = exact.copy()
    rho[wall] *= 1.0 + 1e-4 * np.arange(np.count_nonzero(wall))  # distinctive wall values
    model.rho[:n] = rho
    model.apply_filter("mls")
    np.testing.assert_array_equal(model.rho[:n][wall], rho[wall])
    # fluid particles whose neighbourhood has no perturbed wall particle
    pos = model.pos[:n]
    far = pos[:, 1] > 0.03 + 2 * model.h
    inner = _interior(model) & far & ~wall
    assert np.count_nonzero(inner) >= 8
    np.testing.assert_allclose(model.rho[:n][inner], exact[inner], rtol=1e-12)
    model.rho[:n] = exact
    model.apply_filter("shepard")
    np.testing.assert_array_equal(model.rho[:n][wall], exact[wall])
    # fluid next to the wall sees the wall's (linear) density: MLS exact there
    model.rho[:n] = exact
    model.apply_filter("mls")
    np.testing.assert_allclose(model.rho[:n][_interior(model) & ~wall], exact[_interior(model) & ~wall],
                               rtol=1e-12)


def test_filters_with_adami_walls_use_the_fluid_only(fluid_block):
    """With the Adami wall pressure the walls' densities are the fluid's extrapolated: the filters leave
    them out, so whatever the walls hold, MLS keeps a linear fluid field exact next to the wall too (its
    one-sided fit stays first order) and Shepard returns the fluid's constant."""
    dim = 2

    def kinds(pos):
        return np.where(pos[:, 2] < 0.03, FIXED, FLUID)

    model = fluid_block(dim, (24, 20), SPHOptions(precision="float64", wall_pressure="adami"), dp=0.01,
                        kinds=kinds)
    n = model.n
    exact = _linear_field(model, np.array([0.4, 1.0]))
    wall = model.kind[:n] != FLUID
    rho = exact.copy()
    rho[wall] = 1100.0  # nothing like the fluid's: would show in any sum that used them
    model.rho[:n] = rho
    model.apply_filter("mls")
    np.testing.assert_array_equal(model.rho[:n][wall], rho[wall])
    pos = model.pos[:n]
    near = ~wall & (pos[:, 1] < 0.03 + 2 * model.h) & (pos[:, 0] > 2 * model.h) & (pos[:, 0] < 0.24 - 2 * model.h)
    assert np.count_nonzero(near) >= 8
    np.testing.assert_allclose(model.rho[:n][near], exact[near], rtol=1e-12)
    model.rho[:n] = np.where(wall, 1100.0, 1000.0)
    model.apply_filter("shepard")
    np.testing.assert_allclose(model.rho[:n][~wall], 1000.0, rtol=1e-12)


def test_mls_via_simulation_schedule_resets_density_history(fluid_block):
    """`mls_every` applies the filter after the scheduled steps (smoke check
    of the wiring: densities stay finite and the Verlet history is reset)."""
    from shoal.simulation import Simulation

    model = fluid_block(2, (24, 20), SPHOptions(precision="float64", mls_every=2, integrator="verlet"), dp=0.01)
    sim = Simulation(model, end_time=10.0)
    sim.run(max_steps=2)
    n = model.n
    assert np.all(np.isfinite(model.rho[:n]))
    np.testing.assert_array_equal(sim.integrator.rho_m1[:n], model.rho[:n])
