"""The open boundaries' buffer particles keep their imposed state: their rates are held at zero.

A particle of a buffer (zone tag > 0, `shoal.particle_buffers`) is fluid to every pair term, so that the
water beside the plane sees complete kernel sums, but its velocity and density are imposed each step by the
buffer, not integrated: after each rate evaluation its acceleration, density rate (and XSPH velocity) are
set to zero, so the integrator moves it at its imposed velocity and keeps its imposed density. Where the
scheme shifts particles (`shoal.physics.shifting`), a buffer particle's shift is set to zero as well: the
buffer's rows stay on the lattice the buffer places and extends them on.
"""


def make_buffer_hold(jit, spec):
    """Return ``hold(i, zone, ace, drho, xsph)`` compiled with `jit`: zero the rates of row i if it is a
    buffer's (zone[i] > 0); `xsph` is touched only where the scheme keeps the XSPH velocity."""
    dim = spec.dim
    has_xsph = bool(spec.xsph)

    @jit
    def hold(i, zone, ace, drho, xsph):
        """Zero the rates (and XSPH velocity) of a buffer particle."""
        if zone[i] > 0:
            for d in range(dim):
                ace[i, d] = 0.0
                if has_xsph:
                    xsph[i, d] = 0.0
            drho[i] = 0.0

    return hold


def make_shift_hold(jit, spec):
    """Return ``hold_shift(i, zone, out)`` compiled with `jit`: zero the shift ``out[i]`` of row i if it is a
    buffer's (zone[i] > 0), between `shoal.physics.shifting`'s ``shift`` and ``shift_apply``."""
    dim = spec.dim

    @jit
    def hold_shift(i, zone, out):
        """Zero the shift of a buffer particle."""
        if zone[i] > 0:
            for d in range(dim):
                out[i, d] = 0.0

    return hold_shift
