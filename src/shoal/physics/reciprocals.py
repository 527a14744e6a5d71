"""The three reciprocals of a fluid pair, from one division.

The pair terms divide by a = r_ij^2 + eta^2 (artificial and laminar viscosity, the
Monaghan & Kos 1999 time-step term), s = rho_i + rho_j (viscosity, XSPH) and rho_j
(density diffusion, `density_diffusion`). One division of their product gives all three:

    d = 1 / (a rho_j s),   1/a = d rho_j s,   1/s = d a rho_j,   1/rho_j = d a s

(each within a few float roundings of the direct quotient). A division is the slowest
arithmetic of the pair loop: on the project's CPU the three separate divisions took a
fifth of the 3D dam break's pair loop (`benchmarks/profile_phases.py`), and on a GPU a
division is a multi-instruction sequence too.
"""


def make_reciprocals(jit, spec):
    """Return ``reciprocals(r2, eta2, rhoi, rhoj) -> (1 / (r2 + eta2), 1 / (rhoi + rhoj), 1 / rhoj)``.

    (It takes eta2, not the `Params` record: passing the record to it left a reference-count
    increment and decrement per pair in the compiled CPU loop, 20 % of the pair loop's time.)"""
    F = spec.float_type
    one = F(1.0)

    @jit
    def reciprocals(r2, eta2, rhoi, rhoj):
        a = r2 + eta2
        s = rhoi + rhoj
        ar = a * rhoj
        d = one / (ar * s)
        return d * rhoj * s, d * ar, d * a * s

    return reciprocals
