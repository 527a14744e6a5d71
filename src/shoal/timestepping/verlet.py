"""Verlet time stepping with an Euler step every N steps (DualSPHysics).

Per step: sort particles into cells; compute rates at t^n; choose dt;
then r^{n+1} = r^n + dt v^n + dt^2/2 a^n, v^{n+1} = v^{n-1} + 2 dt a^n,
rho^{n+1} = rho^{n-1} + 2 dt D^n; every N-th step the Euler form
v^{n+1} = v^n + dt a^n, rho^{n+1} = rho^n + dt D^n decouples the two
interleaved sequences (Verlet 1967; Crespo et al. 2015, DualSPHysics).
One rate evaluation per step.

Caution: the leapfrog update of the density integrates the density
diffusion term with a centred difference in time, which is unstable for a
diffusion term; only the Euler steps damp the spurious mode. Measured here:
a quiescent 3D tank (Wendland, delta = 0.1, Euler every 40 steps) grows a
density oscillation after ~3000 steps, while every-10 Euler steps, delta =
0.05 or the cubic kernel stay stable. The symplectic scheme has no such mode.
"""


class Verlet:
    """Verlet integrator; `euler_every` from ``options.verlet_euler_every``."""

    rate_evaluations_per_step = 1

    def __init__(self, model):
        self.model = model
        self.vel_m1 = model.new_array(model.vel, owner=self)
        self.rho_m1 = model.new_array(model.rho, owner=self)
        self.euler_every = model.options.verlet_euler_every
        self.count = 0

    def checkpoint_state(self):
        """What a checkpoint keeps: the steps since the last Euler step (and the Euler interval)."""
        return {"count": int(self.count), "euler_every": int(self.euler_every)}

    def restore_state(self, state):
        """Continue the Verlet / Euler sequence of a checkpoint (`checkpoint_state`)."""
        self.count = int(state["count"])
        self.euler_every = int(state.get("euler_every", self.euler_every))

    def reset_density_history(self):
        """After a density filter, restart the two-level density sequence."""
        m = self.model
        self.rho_m1[: m.n] = m.rho[: m.n]

    def step(self, choose_dt):
        """Advance one step; `choose_dt(dt_limit)` returns the dt to take."""
        m = self.model
        m.sort()
        m.move_bodies(m.time)
        m.compute_rates()
        dt = choose_dt(m.time_step_limit())
        self.count += 1
        euler = self.count >= self.euler_every
        if euler:
            self.count = 0
        b = m.backend
        b.timed(b.verlet, m.n, (m.pos, m.vel, m.rho, self.vel_m1, self.rho_m1, m.ace, m.drho, m.xsph,
                                m.kind, m.dtype.type(dt), euler, m.P))
        m.floating.advance(m.time, dt)  # floating bodies under the loads of the rates at n
        m.move_bodies(m.time + dt)
        return dt
