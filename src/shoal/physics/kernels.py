"""Smoothing kernels W(r, h) with support 2h, and their gradients.

Both are written with `max(.., 0)` forms so that they have no branches
(faster in the pair loop, and equal to zero beyond the support).

* Wendland (1995) C2, the "quintic" kernel of DualSPHysics and GPUSPH:
  W = alpha_D (1 - q/2)^4 (2q + 1), 0 <= q = r/h <= 2,
  alpha_D = 7 / (4 pi h^2) in 2D, 21 / (16 pi h^3) in 3D.
  dW/dq = -5 alpha_D q (1 - q/2)^3.
* Cubic spline (Monaghan & Lattanzio 1985):
  W = alpha_D [ (2 - q)^3 / 4 - (1 - q)^3_+ ],
  alpha_D = 10 / (7 pi h^2) in 2D, 1 / (pi h^3) in 3D.

The gradient is returned as a factor ``fr`` with grad_i W_ij = fr * r_ij,
r_ij = r_i - r_j, i.e. fr = (dW/dr) / r <= 0.
"""

from .spec import KERNEL_IDS

WENDLAND = KERNEL_IDS["wendland"]
CUBIC = KERNEL_IDS["cubic"]


def make_kernels(jit, spec):
    """Return ``(w, grad_factor)`` compiled with `jit` for `spec`.

    ``w(q, P)`` gives W for q = r/h; ``grad_factor(q, P)`` gives fr with
    grad_i W_ij = fr * r_ij. `P` is the run's `Params`.
    """
    F = spec.float_type
    zero, one, two = F(0.0), F(1.0), F(2.0)
    half, quarter, m5, m075, three = F(0.5), F(0.25), F(-5.0), F(-0.75), F(3.0)
    tiny = F(1e-6)

    if spec.kernel == WENDLAND:
        @jit
        def w(q, P):
            t = max(one - half * q, zero)
            t2 = t * t
            return P.aw * t2 * t2 * (two * q + one)

        @jit
        def grad_factor(q, P):
            # (dW/dq)/q = -5 aw (1 - q/2)^3, and dW/dr / r = that / h^2
            t = max(one - half * q, zero)
            return m5 * P.agrad * t * t * t
    else:
        @jit
        def w(q, P):
            a = max(two - q, zero)
            b = max(one - q, zero)
            return P.aw * (quarter * a * a * a - b * b * b)

        @jit
        def grad_factor(q, P):
            a = max(two - q, zero)
            b = max(one - q, zero)
            # dW/dq = -0.75 (2-q)^2 + 3 (1-q)_+^2, which is O(q) near 0
            return P.agrad * (m075 * a * a + three * b * b) / max(q, tiny)

    return w, grad_factor


def grad_factor_array(kernel, dim, h, q):
    """NumPy form of ``grad_factor`` (fr = (dW/dr) / r [1/m^(dim+2)]) for arrays of q, in float64:
    for tables built once per run (e.g. the wall planes' viscous term)."""
    import numpy as np

    from .spec import kernel_normalisation

    q = np.asarray(q, dtype=np.float64)
    aw = kernel_normalisation(kernel, dim, h)
    if kernel == WENDLAND:
        t = np.clip(1.0 - 0.5 * q, 0.0, None)
        return -5.0 * aw / (h * h) * t**3
    a = np.clip(2.0 - q, 0.0, None)
    b = np.clip(1.0 - q, 0.0, None)
    return aw / (h * h) * (-0.75 * a * a + 3.0 * b * b) / np.maximum(q, 1e-6)
