"""Symplectic position-Verlet scheme (Leimkuhler et al. 1996), as in DualSPHysics.

Per step: save state n; rates at n; choose dt; predictor over dt/2
(r, v, rho at n+1/2); rates at n+1/2; corrector
v^{n+1} = v^n + dt a^{n+1/2}, r^{n+1} = r^n + dt (v^{n+1} + v^n)/2,
rho^{n+1} = rho^n (2 - e)/(2 + e), e = -(D^{n+1/2}/rho^{n+1/2}) dt.
Two rate evaluations per step; second-order and time-reversible. Floating
bodies take the same two stages (`shoal.body_coupling`).
"""


class Symplectic:
    """Symplectic integrator."""

    rate_evaluations_per_step = 2

    def __init__(self, model):
        self.model = model
        self.pos_n = model.new_array(model.pos, owner=self)
        self.vel_n = model.new_array(model.vel, owner=self)
        self.rho_n = model.new_array(model.rho, owner=self)

    def checkpoint_state(self):
        """What a checkpoint keeps of the integrator besides its arrays: nothing (each step starts
        from the saved state n)."""
        return {}

    def restore_state(self, state):
        """(Nothing to restore: `checkpoint_state`.)"""

    def reset_density_history(self):
        pass

    def _saved(self):
        return (self.pos_n, self.vel_n, self.rho_n)

    def step(self, choose_dt):
        m = self.model
        b = m.backend
        m.sort()
        m.move_bodies(m.time)
        b.timed(b.save_state, m.n, (m.pos, m.vel, m.rho, *self._saved()))
        m.compute_rates()
        dt = choose_dt(m.time_step_limit())
        F = m.dtype.type
        b.timed(b.half_step, m.n, (m.pos, m.vel, m.rho, *self._saved(), m.ace, m.drho, m.xsph, m.kind,
                                   F(dt), m.P))
        m.floating.predict(m.time, dt)  # floating bodies to n+1/2 under the loads of the rates at n
        m.move_bodies(m.time + 0.5 * dt)
        m.compute_rates()
        self.correct(F(dt))
        m.floating.correct(m.time, dt)  # and to n+1 under those at n+1/2
        m.move_bodies(m.time + dt)
        return dt

    def correct(self, dt):
        m = self.model
        b = m.backend
        b.timed(b.symplectic_correct, m.n, (m.pos, m.vel, m.rho, *self._saved(), m.ace, m.drho, m.xsph,
                                            m.kind, dt, m.P))
