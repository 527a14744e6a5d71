"""Density diffusion ("delta-SPH") terms added to the continuity equation.

D_i = delta h c0 sum_j psi_ij . grad_i W_ij  V_j,  V_j = m_j / rho_j,

* Molteni & Colagrossi (2009): psi_ij = 2 (rho_j - rho_i) r_ji / |r_ij|^2.
* Fourtakas, Dominguez, Vacondio & Rogers (2019): the same with the
  hydrostatic part removed, psi_ij = 2 (rho^T_j - rho^T_i) r_ji / |r_ij|^2,
  rho^T = rho - rho^H. With the Tait EOS linearised about rho0 the
  hydrostatic difference is rho^H_j - rho^H_i = (rho0 / c0^2) g . (r_j - r_i)
  (the relative error of the linearisation is below 1e-8 for dz <= 2h).

Applied between fluid particles only, as DualSPHysics does, so the dynamic
boundary particles' density is not diffused into the fluid.
Since r_ji . grad_i W_ij = -fr r^2, psi . grad W = -2 (rho_j - rho_i) fr.
The term takes 1 / rho_j precomputed (`reciprocals`) instead of dividing.
"""

from .spec import DIFF_IDS

NONE = DIFF_IDS["none"]
MOLTENI = DIFF_IDS["molteni"]
FOURTAKAS = DIFF_IDS["fourtakas"]


def make_density_diffusion(jit, spec):
    """Return ``diffusion(rhoi, rhoj, inv_rhoj, dx, dy, dz, fr, mj, P)`` compiled with `jit`."""
    F = spec.float_type
    zero = F(0.0)
    mode = spec.diffusion

    @jit
    def diffusion(rhoi, rhoj, inv_rhoj, dx, dy, dz, fr, mj, P):
        if mode == NONE:
            return zero
        drho = rhoj - rhoi
        if mode == FOURTAKAS:
            # rho^H_j - rho^H_i = (rho0/c0^2) g.(r_j - r_i) = -(rho0/c0^2) g.r_ij
            drho += P.rho0_c02 * (P.gx * dx + P.gy * dy + P.gz * dz)
        return -P.ddt_coef * drho * fr * mj * inv_rhoj

    return diffusion
