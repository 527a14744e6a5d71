"""Periodic axes and the symmetry plane: a particle that left the domain through one comes back.

A particle that crossed a periodic face comes back by one period (x -> x - L at x >= lo + L,
x -> x + L at x < lo; y likewise); one that crossed the symmetry plane y = y_s comes back as its
mirror image, with its y velocity reversed.
"""


def make_periodic_wrap(jit, spec, unpack):
    """Return ``wrap_periodic(i, pos, vel, lo_x, lo_y, Parr)`` compiled with `jit`."""
    dim = spec.dim
    px = bool(spec.periodic & 1)
    py = bool(spec.periodic & 2) and dim == 3
    sym = spec.symmetry if dim == 3 else 0

    @jit
    def wrap_periodic(i, pos, vel, lo_x, lo_y, Parr):
        """Bring a particle that crossed a periodic face back by one period:
        x -> x - L if x >= lo + L, x -> x + L if x < lo."""
        P = unpack(Parr)
        if px:
            x = pos[i, 0]
            if x >= lo_x + P.per_len_x:
                pos[i, 0] = x - P.per_len_x
            elif x < lo_x:
                pos[i, 0] = x + P.per_len_x
        if py:
            y = pos[i, 1]
            if y >= lo_y + P.per_len_y:
                pos[i, 1] = y - P.per_len_y
            elif y < lo_y:
                pos[i, 1] = y + P.per_len_y
        if sym != 0:
            # a particle that crossed the symmetry plane comes back as its mirror image
            y = pos[i, 1]
            if (sym == 1 and y > P.sym_y) or (sym == 2 and y < P.sym_y):
                pos[i, 1] = 2.0 * P.sym_y - y
                vel[i, 1] = -vel[i, 1]

    return wrap_periodic
