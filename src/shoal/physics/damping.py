"""Damping zones (as DualSPHysics's): the fluid's velocity relaxed to rest in a strip, e.g. at the
end of a flume, so waves are absorbed instead of reflected.

A fluid particle a fraction f in [0, 1] of the way into the zone (from the start plane, along e) has
its velocity multiplied by max(1 - dt rate f^2, 0) each step.
"""

from .spec import FLUID


def make_damping(jit, spec):
    """Return ``damp(i, pos, vel, kind, sx, sy, sz, ex, ey, ez, inv_len, rate, dt)`` compiled with `jit`."""
    F = spec.float_type
    dim = spec.dim

    @jit
    def damp(i, pos, vel, kind, sx, sy, sz, ex, ey, ez, inv_len, rate, dt):
        """Damping zone (as DualSPHysics's): a fluid particle a fraction f in [0, 1]
        of the way into the zone (from the start plane, along e) has its velocity
        multiplied by max(1 - dt rate f^2, 0) each step."""
        if kind[i] == FLUID:
            if dim == 3:
                s_ = (pos[i, 0] - sx) * ex + (pos[i, 1] - sy) * ey + (pos[i, 2] - sz) * ez
            else:
                s_ = (pos[i, 0] - sx) * ex + (pos[i, 1] - sz) * ez
            f = s_ * inv_len
            if f > 0.0:
                if f > 1.0:
                    f = 1.0
                k = 1.0 - dt * rate * f * f
                if k < 0.0:
                    k = 0.0
                for d in range(dim):
                    vel[i, d] = F(vel[i, d] * k)

    return damp
