"""Particle shifting of the delta-plus-SPH model (Sun, Colagrossi, Marrone & Zhang 2017, "The
delta-plus-SPH model: simple procedures for a further improvement of the SPH scheme", CMAME 315, 25-49,
section on the particle shifting technique), applied once per step after the integrator.

Each fluid particle i is moved by

    delta r_i = -C Ma (2h)^2 sum_j [1 + R (W_ij / W(dp))^n] grad_i W_ij V_j,     R = 0.2, n = 4,

with V_j = m_j / rho_j over its fluid and wet boundary neighbours within 2h (not the repulsive-force
boundary particles, whose spacing is not the fluid's; nor the dry wall particles of a wall rising above
the water, as in the free-surface detection: beside the contact line they would push the top particle
off the wall, 0.0086 dp in one step on a still 2D lattice at dp = 20 mm before they were left out), Ma = U_max / c0 the run's Mach number and C the CFL-type
coefficient (`SPHOptions.shifting_coef`). The sum is the gradient of the kernel sum, so particles move
down the gradient of their concentration: toward gaps, away from clumps. The term R (W_ij / W(dp))^4
grows steeply as a pair comes closer than dp and pushes such a pair apart (it damps the pairing that
tensile instability starts; Sun et al. take it from Monaghan's 2000 tensile correction). On a regular
lattice of uniform density every term cancels with its mirror: nothing moves.

Free surface (Sun et al. 2017's treatment, with shoal's detection): the kernel sum of a particle at or
near the free surface is truncated on the air's side, and the shift would push it out through the
surface. So for a particle detected as free surface (Marrone et al. 2010, `shoal.physics.free_surface`)
or having a free-surface fluid neighbour within 2h (the surface's vicinity), only the tangential part is
kept,

    delta r_i <- (I - n_i n_i) delta r_i,

with n_i the unit normal of `shoal.physics.free_surface` (-sum_j V_j grad_i W_ij normalised, the wall-plane
correction included; Sun et al. use the renormalised gradient of the kernel sum, which points the same way
on a flat surface). A particle without any neighbour within 2h (a drop of spray) is not shifted.

Wall planes (`planes`, no particles): a particle within 2h of a plane has no neighbours beyond it and the
sum would push it toward the plane; the component of delta r pointing into such a plane is removed (the
same correction as the normal's).

The shift's length is capped at `max_shift` (0.1 dp, from `shoal.model.Model.apply_shifting`): Sun et
al. 2017 limit the shift so that no particle jumps; the bound used here is shoal's choice, a safeguard
that the tests' still and perturbed lattices never reach.

Positions only: Sun et al. 2017 move the positions and leave the velocity and density as they are (the
error is of the order of the shift times the field's gradient, second order in the ALE sense they
discuss); the consistent form that also corrects them is Sun et al. 2019, not this one.

The shift of every particle is computed from the positions before any is moved (a first pass writes
them into a buffer, a second adds them), so the result does not depend on the order of the particles.
"""

from .spec import FLUID, REPULSIVE

R_COEF = 0.2
"""R of the anti-clumping term (Sun et al. 2017)."""

N_EXP = 4
"""n of the anti-clumping term (Sun et al. 2017)."""


def make_shifting(jit, spec, kernels, surface_normal, make_gather, unpack):
    """Return ``(shift, shift_apply)`` compiled with `jit`.

    ``shift(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, wet, surface, coef, max_shift,
    out)`` writes particle i's shift delta r_i [m] (module docstring) into ``out[i]`` (float64, (N, dim);
    zero for a boundary particle or an isolated one); `wet` is the wet-wall flag of
    `shoal.physics.free_surface`, `surface` its free-surface flag, `coef` = C Ma (2h)^2 [m^2] and
    `max_shift` the cap [m]. ``shift_apply(i, pos, kind, out)`` adds ``out[i]`` to a fluid particle's
    position.
    """
    F = spec.float_type
    dim = spec.dim
    zero, one = F(0.0), F(1.0)
    r_coef = F(R_COEF)
    w, grad_factor = kernels

    @jit
    def shift_pair(acc, own, j, dx, dy, dz, r2, sy, data, P):
        ax, ay, az, nf, near = acc
        rho, kind, surface, wet = data
        if kind[j] >= REPULSIVE or wet[j] == 0:
            return acc
        fluid = kind[j] == FLUID
        mj = P.mass_f if fluid else P.mass_b
        q = r2 ** F(0.5) * P.inv_h
        ratio = w(q, P) * P.inv_wdp  # W_ij / W(dp)
        ratio2 = ratio * ratio
        # [1 + R (W_ij / W(dp))^4] grad_i W_ij V_j, grad_i W_ij = fr r_ij (r_ij = (dx, dy, dz) = r_i - r_j)
        v = mj / rho[j] * grad_factor(q, P) * (one + r_coef * ratio2 * ratio2)
        return (ax + v * dx, ay + v * dy, az + v * dz, nf + (1 if fluid else 0),
                near | (fluid & (surface[j] == 1)))

    gather_shift = make_gather(jit, spec, shift_pair)

    @jit
    def shift(i, pos, rho, kind, cell, cell_start, grid_dims, Parr, planes, wet, surface, coef, max_shift, out):
        """delta r_i = -C Ma (2h)^2 sum_j [1 + R (W_ij / W(dp))^n] grad_i W_ij V_j (Sun et al. 2017), its
        normal part removed at and near the free surface, into `out[i]`."""
        for d in range(dim):
            out[i, d] = 0.0
        if kind[i] != FLUID:
            return
        P = unpack(Parr)
        gdims = (grid_dims[0], grid_dims[1], grid_dims[2])
        ax, ay, az, nf, near = gather_shift(i, 0, (zero, zero, zero, 0, False), pos, cell, cell_start, gdims,
                                            (rho, kind, surface, wet), P)
        if nf == 0:
            return  # an isolated particle (spray): no concentration to even out
        c = -F(coef)
        sx, sy, sz = c * ax, c * ay, c * az
        if surface[i] == 1 or near:
            nx, ny, nz, nb, nbound = surface_normal(i, pos, rho, kind, cell, cell_start, gdims, P, planes, wet)
            dot = sx * nx + sy * ny + sz * nz  # (I - n n) delta r: the tangential part only
            sx -= dot * nx
            sy -= dot * ny
            sz -= dot * nz
        # a wall plane within 2h: no neighbours beyond it, so no shift into it
        for k in range(planes.shape[0]):
            px, py, pz = F(planes[k, 0]), F(planes[k, 1]), F(planes[k, 2])
            if dim == 2:
                d = planes[k, 0] * pos[i, 0] + planes[k, 2] * pos[i, 1] - planes[k, 3]
                py = zero
            else:
                d = planes[k, 0] * pos[i, 0] + planes[k, 1] * pos[i, 1] + planes[k, 2] * pos[i, 2] - planes[k, 3]
            if d < 2.0 * P.h:
                dot = sx * px + sy * py + sz * pz
                if dot < zero:
                    sx -= dot * px
                    sy -= dot * py
                    sz -= dot * pz
        length = (sx * sx + sy * sy + sz * sz) ** F(0.5)
        cap = F(max_shift)
        if length > cap:
            scale = cap / length
            sx, sy, sz = sx * scale, sy * scale, sz * scale
        out[i, 0] = sx
        if dim == 3:
            out[i, 1] = sy
        out[i, dim - 1] = sz

    @jit
    def shift_apply(i, pos, kind, out):
        """r_i <- r_i + delta r_i for a fluid particle."""
        if kind[i] == FLUID:
            for d in range(dim):
                pos[i, d] += out[i, d]

    return shift, shift_apply
