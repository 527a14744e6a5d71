"""Low-dissipation Riemann fluxes between particle pairs (Zhang, Hu & Adams 2017).

Each interacting pair a-b is a one-dimensional Riemann problem along the line joining them,
e_ab = r_ab / |r_ab| (r_ab = r_a - r_b), with a as the left state and b as the right one. Its
linearised (acoustic) solution, with the low-dissipation limiter of Zhang, Hu & Adams (2017,
J. Comput. Phys. 335, 605-620, Eqs. 13-18),

    U_ab = (v_b - v_a) . e_ab                     (> 0: the pair closes in)
    beta = min(eta max(U_ab, 0), c0),  eta = 3
    p*   = (p_a + p_b) / 2 + beta rho_ab U_ab / 2
    v*   = (v_a + v_b) / 2 + (p_b - p_a - p^H_ab) / (2 rho_ab c0) e_ab,   rho_ab = (rho_a + rho_b) / 2,

takes the place of the particles' own pressures and velocities in the pair terms:

    d rho_a / dt = 2 rho_a sum_b V_b (v_a - v*) . grad_a W_ab
    d v_a / dt   = -2 sum_b m_b p* / (rho_a rho_b) grad_a W_ab + ...

With p* = (p_a + p_b) / 2 and v* = (v_a + v_b) / 2 they are the plain SPH equations; the
dissipation is what the Riemann solution adds: in the momentum equation a pressure that grows
only where the pair closes in, quadratically in its closing speed (the limiter: no dissipation
in expansion, none of Monaghan's linear artificial viscosity that damps waves), and in the
continuity equation a diffusion of the pressure jump across the pair, the acoustic wave's own
damping. With grad_a W_ab = fr r_ab (fr < 0) the continuity term is

    2 rho_a V_b (v_a - v*) . grad_a W_ab = rho_a V_b fr (v_ab . r_ab - dp_ab |r_ab| / (rho_ab c0)),
    dp_ab = p_b - p_a - p^H_ab.

p^H_ab = rho0 g . (r_b - r_a) is the hydrostatic part of the jump, which shoal removes as
Fourtakas et al. (2019) remove it from density diffusion: Zhang et al.'s term diffuses the
whole jump, and in still water the one-sided support at the free surface then raises the
surface particles' density step after step. Without gravity the term is theirs.

The pair form is applied between fluid particles only. Along the line of a fluid-wall pair the
limiter sees a stream sliding over the wall's particle lattice close in on the particles ahead and
open from those behind, and its one-sided dissipation then acts as a bed friction: measured
(`benchmarks/bed_drag.py`, 0.7 m/s over an Adami bed at dp = d0/10), applied to wall pairs it took
32.7 % of the stream's speed in 2 s, between fluid particles only 0.8 % (Adami walls without it:
0.7 %). Against a wall the problem is instead the fluid particle's and its mirror image's along the
wall's unit normal n (into the fluid; the ghost vectors of `shoal.geometry.normals`, which the
generator computes for ``riemann``, normalised by the model: `Model.wall_normal_of`), as in Zhang
et al.'s wall condition: the closing speed is U = -2 (v_a - u_w) . n, and the dissipative pressure
dp = beta rho_ab U / 2 (`wall_jump`), zero for a stream sliding along the wall, pushes along n, with
the weight of the pair's kernel gradient:

    d v_a / dt += 2 m_b dp / (rho_a rho_b) |grad_a W_ab| n,

as SPHinXsys applies the wall's Riemann dissipation (its fluid integration's wall contact). Along
the pair's line e_ab instead the push does work against the relative motion only where the pair
closes in along e_ab too, which a wall particle at a convex edge (a diagonal normal) does not
ensure: fluid falling down a face below the edge closes in along the edge's normal while it moves
away from the edge particle, and the push along e_ab then sped it up (measured: SPHERIC Test 2 at
dp = 0.05 m went unstable at t = 0.756 s by the box's upstream face). Along n the power is
-dp U / 2 times a positive weight: never positive. The force on the walls
(`shoal.physics.forces`) adds the same, so it stays the reaction of the fluid's momentum change. A model built without wall normals keeps the
plain terms at the walls. Zhang et al. run the scheme without artificial viscosity or density diffusion
(``alpha = 0`` or laminar viscosity, ``density_diffusion = "none"``).
"""

ETA = 3.0
"""The limiter's coefficient eta (Zhang, Hu & Adams 2017)."""


def make_riemann(jit, spec):
    """Return ``(riemann_pair, wall_jump)``:
    ``riemann_pair(pa, pb, rhoa, inv_rhob, vdotr, r, gdotr, inv_s, P) -> (prs, cont)`` of a fluid pair and
    ``wall_jump(ux, uy, uz, normals, row, sy, rhoa, rhob, P) -> (dp, nx, ny, nz)``, the dissipative
    pressure of a fluid-wall pair and the wall's unit normal it pushes along (u = v_a - u_w;
    normals[row] the wall's unit normal, `Model.wall_normal_of`; ny = 0 in 2D; a zero row, a wall
    particle without a normal, gives dp = 0).

    For ``riemann_pair``:

    Inputs: the pair's pressures, rho_a and 1 / rho_b (which the pair loop already has), vdotr =
    (v_a - v_b) . (r_a - r_b), r = |r_ab|,
    gdotr = g . (r_a - r_b), inv_s = 1 / (rho_a + rho_b). Outputs: ``prs`` = 2 p* / (rho_a rho_b),
    the pressure factor of the momentum term (in place of p_a/rho_a^2 + p_b/rho_b^2), and ``cont``
    = (rho_a / rho_b) (v_ab . r_ab - dp_ab r / (rho_ab c0)), the continuity term's factor (times
    m_b fr: ``m_b cont fr`` in place of m_b v_ab . r_ab fr).
    """
    F = spec.float_type
    zero, two = F(0.0), F(2.0)
    eta = F(ETA)

    @jit
    def riemann_pair(pa, pb, rhoa, inv_rhob, vdotr, r, gdotr, inv_s, P):
        closing = -vdotr / r if r > zero else zero  # U_ab = (v_b - v_a) . e_ab
        beta = min(eta * max(closing, zero), P.c0)
        # rho_ab = (rho_a + rho_b) / 2 = 1 / (2 inv_s)
        pstar = F(0.5) * (pa + pb + beta * closing / (two * inv_s))
        prs = two * pstar * inv_rhob / rhoa
        # p^H_b - p^H_a = rho0 g . (r_b - r_a) = -rho0 gdotr
        dp = pb - pa + P.rho0 * gdotr
        cont = rhoa * inv_rhob * (vdotr - dp * r * two * inv_s / P.c0)
        return prs, cont

    dim = spec.dim

    @jit
    def wall_jump(ux, uy, uz, normals, row, sy, rhoa, rhob, P):
        """The dissipative pressure of a fluid particle's Riemann problem with a wall particle along
        the wall's unit normal n (into the fluid), and n: the closing speed is that of the fluid
        and its mirror image, U = -2 (v_a - u_w) . n, and the pressure beta rho_ab U / 2 with
        beta = min(eta max(U, 0), c0), which pushes along n."""
        nx = normals[row, 0]
        nz = normals[row, dim - 1]
        ny = sy * normals[row, 1] if dim == 3 else zero
        closing = -two * (ux * nx + uy * ny + uz * nz)
        beta = min(eta * max(closing, zero), P.c0)
        return F(0.25) * beta * closing * (rhoa + rhob), nx, ny, nz

    return riemann_pair, wall_jump
