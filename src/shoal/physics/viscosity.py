"""Viscous pair terms.

* Artificial viscosity (Monaghan 1992), added to the pressure term:
  Pi_ij = -alpha c0 mu_ij / rho_ij  when v_ij . r_ij < 0 (else 0),
  mu_ij = h v_ij . r_ij / (r_ij^2 + eta^2),  rho_ij = (rho_i + rho_j)/2,
  eta^2 = 0.01 h^2; the acceleration gets -m_j Pi_ij grad_i W_ij.
* Laminar viscosity (Lo & Shao 2002, after Morris et al. 1997):
  a_i += sum_j m_j 4 nu (r_ij . grad_i W_ij) / ((rho_i + rho_j)(r_ij^2 + eta^2)) v_ij.

``viscous`` returns ``(Pi_ij, lam_ij)``: the artificial term (added to the
pressure factor) and the laminar coefficient multiplying v_ij. The term of
the model not selected is a compile-time zero. It takes the reciprocals
1/(r_ij^2 + eta^2) and 1/(rho_i + rho_j) instead of dividing (`reciprocals`
computes them, with the pair's other reciprocal, from one division).
"""

from .spec import VISC_IDS

ARTIFICIAL = VISC_IDS["artificial"]
LAMINAR = VISC_IDS["laminar"]


def make_viscosity(jit, spec):
    """Return ``viscous(vdotr, r2, fr, mj, inv_a, inv_s, P)`` compiled with `jit`;
    inv_a = 1 / (r2 + eta2), inv_s = 1 / (rho_i + rho_j)."""
    F = spec.float_type
    zero, two = F(0.0), F(2.0)

    if spec.viscosity == ARTIFICIAL:
        @jit
        def viscous(vdotr, r2, fr, mj, inv_a, inv_s, P):
            # -alpha c0 mu / rho_ij with mu = h min(v.r, 0) / (r2 + eta2) and rho_ij = (rho_i + rho_j) / 2
            return -two * P.alpha * P.c0 * P.h * min(vdotr, zero) * inv_a * inv_s, zero
    else:
        @jit
        def viscous(vdotr, r2, fr, mj, inv_a, inv_s, P):
            return zero, mj * P.nu4 * fr * r2 * inv_a * inv_s

    return viscous
