"""Predictor-corrector scheme of Monaghan (1994), as in SPHysics.

Per step: save state n; rates at n; choose dt; predictor
phi^{n+1/2} = phi^n + dt/2 F^n; rates at n+1/2; corrector
phi^{n+1/2} = phi^n + dt/2 F^{n+1/2}; then phi^{n+1} = 2 phi^{n+1/2} - phi^n
(phi = r, v, rho). Two rate evaluations per step.
"""

from .symplectic import Symplectic


class PredictorCorrector(Symplectic):
    """Monaghan (1994) predictor-corrector integrator."""

    def correct(self, dt):
        m = self.model
        b = m.backend
        b.timed(b.pc_correct, m.n, (m.pos, m.vel, m.rho, *self._saved(), m.ace, m.drho, m.xsph,
                                    m.kind, dt, m.P))
