"""Prescribed rigid motion of moving boundary particles (wavemakers, gates, moving walls).

r = r(0) + X_m(t), v = U_m(t) for the motion m of the particle's body: positions are set from the
initial ones, so no drift accumulates (`shoal.motions` gives X_m and U_m; `Model.move_bodies`
evaluates them at the times the integrator asks for).
"""

from .spec import MOVING, REPULSIVE_MOVING


def make_body_motion(jit, spec):
    """Return ``move_bodies(i, pos, vel, kind, idp, pos_init, motion_of, disp, mvel)`` compiled with `jit`."""
    dim = spec.dim

    @jit
    def move_bodies(i, pos, vel, kind, idp, pos_init, motion_of, disp, mvel):
        """Prescribed rigid motion of moving boundary particles:
        r = r(0) + X_m(t), v = U_m(t) for the motion m of the particle's body
        (positions from the initial ones, so no drift accumulates)."""
        if kind[i] == MOVING or kind[i] == REPULSIVE_MOVING:
            p = idp[i]
            m = motion_of[p]
            for d in range(dim):
                pos[i, d] = pos_init[p, d] + disp[m, d]
                vel[i, d] = mvel[m, d]

    return move_bodies
