"""Smoothing kernels: normalisation, support, gradient and lattice consistency.

The compiled ``w(q, P)`` and ``grad_factor(q, P)`` of the CPU backend are
checked against the mathematics they implement:

* W integrates to one over its support (Gauss-Legendre on each polynomial
  piece, which is exact for piecewise polynomials);
* W >= 0, is non-increasing, and is exactly zero for q >= 2;
* fr = (dW/dr) / r <= 0 matches a central finite difference of W;
* on a regular lattice with h = sqrt(dim) dp the discrete partition of unity
  sum_j V_j W_ij is close to one, sum_j V_j grad W_ij vanishes and
  -sum_j V_j r_ij (x) grad_i W_ij is close to the identity (the gradient
  normalisation);
* the float32 specialisation computes in float32.
"""

import math

import numba
import numpy as np
import pytest
from numba import types

from shoal.options import SPHOptions
from shoal.physics.spec import KERNEL_IDS, SchemeSpec, kernel_normalisation, make_params

KERNELS = ["wendland", "cubic"]
DIMS = [2, 3]


def _setup(backend_for, kernel, dim, h, precision="float64", dp=None):
    opts = SPHOptions(kernel=kernel, precision=precision)
    backend = backend_for(opts, dim)
    spec = SchemeSpec.from_options(opts, dim)
    dp = h / math.sqrt(dim) if dp is None else dp
    # (no neighbour gather here: the grid's corner and cell size are placeholders)
    P = make_params(spec, dp=dp, h=h, rho0=1000.0, c0=10.0, gamma=7.0, gravity=(0.0, 0.0, 0.0),
                    options=opts, mass_f=1.0, mass_b=1.0, grid_lo=(0.0, 0.0, 0.0), inv_cs=1.0 / h)
    return backend.physics, P


_VEC = {}


def _vectorised(phys):
    """njit loops evaluating w and grad_factor on arrays of q (cached per physics)."""
    key = id(phys)
    if key not in _VEC:
        w, g = phys.w, phys.grad_factor

        @numba.njit
        def w_many(q, P):
            out = np.empty(q.size, dtype=q.dtype)
            for k in range(q.size):
                out[k] = w(q[k], P)
            return out

        @numba.njit
        def g_many(q, P):
            out = np.empty(q.size, dtype=q.dtype)
            for k in range(q.size):
                out[k] = g(q[k], P)
            return out

        _VEC[key] = (phys, w_many, g_many)  # keep phys alive so its id stays unique
    return _VEC[key][1:]


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_kernel_integrates_to_one(backend_for, kernel, dim):
    h = 0.037
    phys, P = _setup(backend_for, kernel, dim, h)
    w_many, _ = _vectorised(phys)
    x, wts = np.polynomial.legendre.leggauss(16)
    total = 0.0
    # both kernels are polynomials on [0, 1] and [1, 2] (the cubic has a kink at q = 1)
    for a, b in ((0.0, 1.0), (1.0, 2.0)):
        q = 0.5 * (b - a) * x + 0.5 * (a + b)
        r = q * h
        shell = 2.0 * np.pi * r if dim == 2 else 4.0 * np.pi * r * r
        total += 0.5 * (b - a) * h * np.sum(wts * w_many(q, P) * shell)
    assert total == pytest.approx(1.0, abs=1e-10)
    assert P.aw == pytest.approx(kernel_normalisation(KERNEL_IDS[kernel], dim, h), rel=1e-15)


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_kernel_support_and_sign(backend_for, kernel, dim):
    h = 0.02
    phys, P = _setup(backend_for, kernel, dim, h)
    w_many, g_many = _vectorised(phys)
    q = np.linspace(0.0, 2.0, 2001)
    wq = w_many(q, P)
    assert np.all(wq >= 0.0)
    assert np.all(np.diff(wq) <= 0.0), "W must not increase with distance"
    assert wq[0] > 0.0
    # W(0) from the closed forms: Wendland aw * 1, cubic aw * (2 - 1) = aw
    assert wq[0] == pytest.approx(P.aw, rel=1e-15)
    outside = np.array([2.0, 2.0 + 1e-12, 2.0001, 2.5, 3.0, 10.0, 1e6])
    assert np.all(w_many(outside, P) == 0.0)
    assert np.all(g_many(outside, P) == 0.0)
    fr = g_many(q[1:], P)
    assert np.all(fr <= 0.0)
    assert np.all(fr[:-1] < 0.0)  # strictly attractive-gradient inside the support


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_grad_factor_matches_finite_difference(backend_for, kernel, dim):
    h = 0.05
    phys, P = _setup(backend_for, kernel, dim, h)
    w_many, g_many = _vectorised(phys)
    r = np.linspace(0.05, 1.95, 39) * h
    eps = 1e-5 * h
    dwdr = (w_many((r + eps) / h, P) - w_many((r - eps) / h, P)) / (2.0 * eps)
    fr = g_many(r / h, P)
    scale = np.max(np.abs(dwdr))
    np.testing.assert_allclose(fr * r, dwdr, rtol=0.0, atol=1e-8 * scale)


@pytest.mark.parametrize("kernel,limit", [("wendland", -5.0), ("cubic", -3.0)])
def test_grad_factor_finite_at_origin(backend_for, kernel, limit):
    """fr -> (d2W/dq2)(0) aw / h^2 as q -> 0: finite, so grad W -> 0 smoothly."""
    h = 0.01
    phys, P = _setup(backend_for, kernel, 2, h)
    _, g_many = _vectorised(phys)
    fr = g_many(np.array([1e-4]), P)[0]
    assert fr / P.agrad == pytest.approx(limit, rel=1e-3)


def _lattice(dim, dp, reach):
    k = np.arange(-reach, reach + 1)
    grids = np.meshgrid(*([k] * dim), indexing="ij")
    return np.stack([g.ravel() for g in grids], axis=1) * dp


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_lattice_sums(backend_for, kernel, dim):
    dp = 0.01
    h = math.sqrt(dim) * dp  # coef_h = 1
    phys, P = _setup(backend_for, kernel, dim, h, dp=dp)
    w_many, g_many = _vectorised(phys)
    rij = -_lattice(dim, dp, 5)  # r_i - r_j with particle i at the origin, j included
    r = np.sqrt((rij**2).sum(1))
    assert r.max() > 2 * h + dp  # the lattice covers the whole support
    V = dp**dim
    q = r / h
    shepard = V * w_many(q, P).sum()
    assert shepard == pytest.approx(1.0, abs=0.01)  # 0.2-0.7 % for these kernels
    fr = g_many(q, P)
    grad = V * (fr[:, None] * rij)  # V_j grad_i W_ij
    gsum = grad.sum(0)
    assert np.all(np.abs(gsum) <= 1e-12 * np.abs(grad).sum(0))
    # first-order consistency: sum_j V_j (r_j - r_i) (x) grad_i W_ij = I
    moment = -(rij[:, :, None] * grad[:, None, :]).sum(0)
    np.testing.assert_allclose(moment, np.eye(dim), atol=0.02)


@pytest.mark.parametrize("kernel", KERNELS)
def test_float32_specialisation_stays_float32(backend_for, kernel):
    h = 0.02
    phys32, P32 = _setup(backend_for, kernel, 2, h, precision="float32")
    phys64, P64 = _setup(backend_for, kernel, 2, h, precision="float64")
    # all constants in float32, but the periods and the symmetry-plane geometry (float64 positions)
    assert all(isinstance(v, np.float32) for k, v in P32._asdict().items() if k not in ("dim", "per_len_x", "per_len_y", "sym_y", "grid_lo_x", "grid_lo_y", "grid_lo_z", "inv_cs"))
    for fn in (phys32.w, phys32.grad_factor):
        fn(np.float32(0.7), P32)
        sigs = [s for s in fn.nopython_signatures if s.args[0] == types.float32]
        assert sigs, fn.nopython_signatures
        assert all(s.return_type == types.float32 for s in sigs)
    for q in (0.1, 0.7, 1.0, 1.3, 1.9):
        assert phys32.w(np.float32(q), P32) == pytest.approx(phys64.w(q, P64), rel=2e-6)
        assert phys32.grad_factor(np.float32(q), P32) == pytest.approx(phys64.grad_factor(q, P64), rel=2e-6)
