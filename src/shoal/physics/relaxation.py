"""Relaxation zones (Jacobsen, Fuhrman & Fredsoe 2012; in SPH, Altomare et al. 2018): a fluid particle's
velocity relaxed toward target wave kinematics, with a weight that grows across the zone.

The zone, its targets and the choice of the per-step coefficient are described in `shoal.relaxation`; this
module holds the per-particle function both backends compile. Per particle: xi = (x - start) / (end -
start); nothing before the zone (xi <= 0); the weight w = (exp(xi^3.5) - 1) / (e - 1) (1 for xi >= 1); the
coefficient c = 1 - (1 - w)^(dt / tau); the target (u, w) summed over the components from the terms the host
wrote for the time (`shoal.relaxation.RelaxationTerms.fill`); then v <- v + c (v_target - v), the lateral
velocity (3D) relaxed toward 0.

One formula serves every target: with z' = z - z_c measured from the zone's clipping ceiling z_c and clipped
to [-D, 0] (D the ceiling's height above the bed), u = sum C_n (e^{k_n z'} + e^{-k_n (z' + 2D)}) cos(theta_n)
and w = sum D_n (e^{k_n z'} - e^{-k_n (z' + 2D)}) sin(theta_n), which are 2 e^{-k_n D} cosh(k_n z_b) and
2 e^{-k_n D} sinh(k_n z_b) at the height z_b = z' + D above the bed. A linear target (Airy) has its ceiling
at the still-water level (D = d, C_n = s r a_n omega_n / (1 - e^{-2 k_n d})); a nonlinear one (Fenton's
stream-function wave, Fenton 1988; Stokes' fifth order, Fenton 1985; by raschii) has it at its crest, each
harmonic a component, C_n = s r U_n e^{k_n (D - d)} / (1 + e^{-2 k_n d}), and its uniform current a component
of k_n = 0 (e^0 + e^0 = 2, e^0 - e^0 = 0).
"""

import math

from .spec import FLUID


def make_relaxation(jit, spec):
    """Return ``relax(i, pos, vel, kind, start, inv_len, sign, origin, level, depth, steps, count, terms)``
    compiled with `jit`.

    Arguments after the particle arrays: the zone's inner end `start` [m] and 1 / (end - start) [1/m], the
    direction `sign` (+1 or -1) and `origin` x_0 [m] of the target, the clipping ceiling `level` z_c [m] (the
    still-water level of a linear target, the crest of a nonlinear one) and its height `depth` D [m] above
    the bed, `steps` = dt / tau, the number of components `count` and the (count, 4) float64 `terms` of the
    time (k_n, omega_n t + phi_n, C_n, D_n of the module docstring).
    """
    F = spec.float_type
    dim = spec.dim
    zero, one, two = F(0.0), F(1.0), F(2.0)
    exponent = F(3.5)
    e_minus_1 = F(math.e - 1.0)

    @jit
    def relax(i, pos, vel, kind, start, inv_len, sign, origin, level, depth, steps, count, terms):
        """Relaxation zone (Jacobsen et al. 2012): w = (exp(xi^3.5) - 1) / (e - 1) at xi = (x - start) /
        (end - start), c = 1 - (1 - w)^(dt / tau), v <- v + c (v_target - v) with the target
        u = sum C_n (e^{kz} + e^{-k(z+2D)}) cos(theta_n), w = sum D_n (e^{kz} - e^{-k(z+2D)}) sin(theta_n),
        theta_n = (omega_n t + phi_n) - s k_n (x - x_0), z from the ceiling `level` clipped to [-D, 0]."""
        if kind[i] == FLUID:
            xi = (pos[i, 0] - start) * inv_len
            if xi > 0.0:
                if xi >= 1.0:
                    w = one
                else:
                    w = (math.exp(F(xi) ** exponent) - one) / e_minus_1
                c = one - (one - w) ** F(steps)
                d = F(depth)  # D
                z = F(pos[i, dim - 1] - level)
                if z > zero:
                    z = zero
                if z < -d:
                    z = -d
                dx = pos[i, 0] - origin
                u = zero
                v = zero
                for n in range(count):
                    k = terms[n, 0]
                    theta = F(terms[n, 1] - sign * k * dx)
                    kf = F(k)
                    e1 = math.exp(kf * z)
                    e2 = math.exp(-kf * (z + two * d))
                    u += F(terms[n, 2]) * (e1 + e2) * math.cos(theta)
                    v += F(terms[n, 3]) * (e1 - e2) * math.sin(theta)
                vel[i, 0] = F(vel[i, 0] + c * (u - vel[i, 0]))
                if dim == 3:
                    vel[i, 1] = F(vel[i, 1] - c * vel[i, 1])
                vel[i, dim - 1] = F(vel[i, dim - 1] + c * (v - vel[i, dim - 1]))

    return relax
