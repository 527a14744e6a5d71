"""Second-order wave generation: the paddle motion that suppresses spurious free waves (Schäffer 1996), and the
bound waves of second-order theory (Sharma & Dean 1981).

A paddle driven by the first-order signal X1(t) (`shoal.motions.SpectralPaddle`) makes, besides the target
components eta1 = sum_n a_n cos(omega_n t - k_n x + phi_n), waves at the sums and differences of their
frequencies. Part of them are the bound waves of second-order theory, which travel with the groups and belong
to the target sea (`bound_waves`); the rest are free waves, made because the paddle moves the water as a
first-order paddle does and not as the second-order sea needs: long waves at the difference frequencies, which
run ahead of the groups and reflect in the flume, and short ones at the sums. A second-order displacement
X2(t), added to X1, cancels them (`second_order_paddle`).

Conventions
-----------
A_n = a_n exp(i phi_n) are the components' complex amplitudes, eta1 = Re sum_n A_n exp(i (omega_n t - k_n x)).
The first-order displacement at the still-water level is X1 = Re sum_n Xh_n exp(i omega_n t), Xh_n = -i A_n / T_n,
T_n = H/S of the paddle (`shoal.waves.piston_height_to_stroke`, `flap_height_to_stroke`), that is
X1 = sum_n (a_n / T_n) sin(omega_n t + phi_n): the signal of `shoal.motions.SpectralPaddle`. Second-order
quantities are double sums over all ordered pairs,

    X2(t)     = sum_n sum_m Re[ G+_nm A_n A_m  exp(i (omega_n + omega_m) t)
                              + G-_nm A_n A_m* exp(i (omega_n - omega_m) t) ]            (`paddle_transfer`),
    eta2(x,t) = sum_n sum_m a_n a_m [ K+_nm cos(theta_n + theta_m) + K-_nm cos(theta_n - theta_m) ]
                                                                                    (`bound_wave_transfer`),

theta_n = omega_n t - k_n x + phi_n, G+_nm = G+_mn, G-_mn = conj(G-_nm), the difference terms n = m (a mean
displacement, the mean level) left out. The paddle's face is x = f(z) X(t), z up from the still-water level, d
the depth: f = 1 (piston), or f = (z + d - l) / (d - l) above a hinge at the height l above the bed and 0
below it (flap, the water below the hinge held by a wall; l < 0 puts the hinge below the bed); X is the
excursion at z = 0 (for a flap, shoal's angle is atan(X / (d - l))).

The theory (Schäffer 1996; the steps as derived here)
----------------------------------------------------
1. First order. Each component is a progressive mode and evanescent modes (Havelock 1929; Dean & Dalrymple
   1991, section 6.3): phi1 = Re sum_j C_j cosh(k_j (z + d)) exp(i (omega t - k_j x)), k_0 = k real and
   k_j = -i kappa_j with omega^2 = -g kappa_j tan(kappa_j d), so that every mode satisfies
   omega^2 = g k_j tanh(k_j d) (Schäffer's Eq. 15). The paddle condition phi_x = f dX/dt at x = 0, projected
   on the modes (orthogonal on -d < z < 0), gives C_j = -omega Xh int f cosh k_j(z+d) dz / (k_j N_j),
   N_j = int cosh^2 k_j(z+d) dz (his Eqs. 20-21), and C_0 = i g A / (omega cosh kd) gives Xh = -i A / T.
2. Second order, at Omega = omega_n +- omega_m, for the potential Phi (time factor exp(i Omega t)):
   - at the free surface, -Omega^2 Phi + g Phi_z = Q, Q = -d/dt |grad phi1|^2 + (1/g) phi1_t d/dz (phi1_tt
     + g phi1_z) at z = 0 (the Stokes expansion; Dean & Dalrymple 1991, ch. 11; Sharma & Dean 1981). Two
     first-order modes a, b (of omega_a, omega_b, the second taken as its conjugate, a mode of -omega_m, for
     a difference) force Q_ab exp(-i p x), p = k_a + k_b; with the modes' surface elevations eta_a,
     Q_ab + Q_ba = 2 i eta_a eta_b H_ab, H_ab = Omega (omega_a omega_b - g^2 k_a k_b / (omega_a omega_b))
     + (omega_a^3 + omega_b^3) / 2 - (g^2 / 2) (k_a^2 / omega_a + k_b^2 / omega_b), Schäffer's Eq. (25d).
     The bound potential B cosh(p (z + d)) exp(-i p x), B = Q_ab / (g p sinh pd - Omega^2 cosh pd), answers
     it: the progressive-progressive pairs (p = k_n +- k_m) make the bound waves of the target sea, the pairs
     with an evanescent mode die out within a few depths of the paddle;
   - at the paddle, the exact condition on x = X(z, t) expanded about x = 0:
     Phi_x = f dX2/dt + [X1_z phi1_z - X1 phi1_xx].
3. The rest of Phi satisfies the homogeneous free-surface condition and is a sum of modes at Omega: a free
   wave of wavenumber K (Omega^2 = g K tanh Kd, Schäffer's Eq. 33) and evanescent ones. The free wave's
   amplitude is the projection of the paddle condition on cosh K(z + d), and X2 is the displacement that makes
   it zero:

       i Omega Xh2 int f cosh K(z+d) dz = sum_ab -i p Q_ab cosh(Kd) / (g (p^2 - K^2))
                                         - int [X1_z phi1_z - X1 phi1_xx] cosh K(z+d) dz,

   the first sum being the projection of the bound potentials' flux through the paddle (the integral of
   cosh p(z+d) cosh K(z+d) and the bound denominator are the same combination of p and K), the double sum over
   the modes of Schäffer's Eq. (41a); the second, his single sums over k_j^2 / (k_j^2 - K^2) (with M_2 of his
   Eq. 36b for a flap). Every pair of modes of the two components takes part, the evanescent ones included:
   the terms that Schäffer found important where the paddle's motion fits the progressive mode poorly (a piston
   in deep water, the high frequencies of a spectrum). Without them the subharmonic of a narrow group misses
   the mass flux of its bound long wave (below) by 7 % at kd = 0.8 and by a factor of 11.7 at kd = 5.6.
   G+-_nm = -i F+-_nm / (2 d), F+- Schäffer's transfer functions (his Eq. 41a): within 1e-7 in the tests.

``theory = "madsen"`` replaces the projection on cosh K(z + d) by the depth integral, the mass flux through the
paddle (the free wave taken as long, its velocity uniform over the depth), and keeps the progressive modes only:
for one component and a piston this is Madsen's (1971) closed form (`madsen_piston_second_harmonic`),
X2 = (H^2 / 32 d) (3 cosh kd / sinh^3 kd - 2 / (H/S)) sin(2 omega t), to round-off. The two closures agree in
shallow water (relative difference O((kd)^2)) and part as kd grows: at kd = 1.1 Schäffer's second harmonic is
13 times Madsen's, which nearly vanishes there.

Checks (tests/test_second_order.py): eta2 is Stokes' second harmonic for one component, the set-down of
Longuet-Higgins & Stewart (1962) under a narrow group and Longuet-Higgins's (1963) deep-water limits;
G+- equals Schäffer's F+- as above;
in the narrow-band limit the subharmonic displacement supplies the mass flux of the bound long wave,
int f dz dX2/dt = c_g eta2, for a piston and flaps at any depth; in shallow water the closures agree and a flap
needs d / int f dz times the piston's correction; a flap of fixed draft has a deep-water limit (a piston that
reaches the bed has none: its correction grows with the depth, the near field of its deep part with it).

Series over evanescent modes
----------------------------
The sums over the evanescent modes converge like 1/J (their terms fall as 1/kappa_j^2, a trace of the singular
flow where the paddle meets the free surface). They run to J = `evanescent_modes` modes with one Richardson step
(the modes J/2 < j <= J count twice, which removes the 1/J term), and the products of two evanescent modes,
whose terms fall fast away from the first few modes of either component, over min(a, b) <= J/4. The default
(`default_modes`) is J = 64 per draft in the depth, 64 ceil(d / (d - max(l, 0))): the hinge of a flap above
the bed leaves in the series an oscillation of a period of about 2 d / (d - l) modes. The error grows with
omega^2 d / g of the components (their evanescent modes reach their asymptotic form only beyond
j ~ omega^2 d / (pi g)); measured against J = 2048 for a piston and flaps, the default is within 2e-4 at
omega^2 d / g = 1, 1e-3 at 2.5, 3e-3 at 5, 1.4e-2 at 10 and 8e-2 at 20 (the error falls about as 1 / J^2:
raise `evanescent_modes` for the high-frequency tail of a spectrum in deep water). The build time grows as
J^2 and as the square of the number of components (6 to 9 s for 256 components at J = 64 here).

References
----------
Dalzell, J. F. (1999). A note on finite depth second-order wave-wave interactions. Appl. Ocean Res. 21, 105-111.
Dean, R. G. & Dalrymple, R. A. (1991). Water wave mechanics for engineers and scientists. World Scientific.
Forristall, G. Z. (2000). Wave crest distributions: observations and second-order theory. J. Phys. Oceanogr.
30, 1931-1943.
Havelock, T. H. (1929). Forced surface-waves on water. Phil. Mag. 8, 569-576.
Longuet-Higgins, M. S. (1963). The effect of non-linearities on statistical distributions in the theory of
sea waves. J. Fluid Mech. 17, 459-480.
Longuet-Higgins, M. S. & Stewart, R. W. (1962). Radiation stress and mass transport in gravity waves, with
application to 'surf beats'. J. Fluid Mech. 13, 481-504.
Madsen, O. S. (1971). On the generation of long waves. J. Geophys. Res. 76(36), 8672-8683.
Schäffer, H. A. (1996). Second-order wavemaker theory for irregular waves. Ocean Eng. 23(1), 47-88 (equation
numbers as listed by a public transcription of its equations; see the tests).
Sharma, J. N. & Dean, R. G. (1981). Second-order directional seas and associated wave forces. Soc. Petrol.
Eng. J. 21(1), 129-140.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .components import WaveComponents
from .dispersion import GRAVITY, wavenumbers

__all__ = ["THEORIES", "BoundWaves", "SecondOrderPaddle", "bound_wave_transfer", "bound_waves", "default_modes",
           "madsen_piston_second_harmonic", "paddle_transfer", "regular_second_order", "second_order_paddle"]

THEORIES = ("schaffer", "madsen")
"""The closures of the free-wave condition: Schäffer (1996), Madsen (1971)."""

_LOG_HALF = math.log(0.5)
_CHUNK = 1 << 20
"""Elements (frequencies x times) summed at once when a signal is evaluated."""
_PAIR_ELEMENTS = 1 << 18
"""Elements (pairs x modes x modes) of one block of the pair computation."""


# ------------------------------------------------------------------------------------------------------------
# Integrals of exponentials on the paddle's face

def _phi(z):
    """(m1, m2, e) with phi1(z) = (e^z - 1) / z = m1 exp(e) and phi2(z) = (e^z - 1 - z) / z^2 = m2 exp(e).

    e = z where Re z > 0 and |z| >= 1/2 (m1, m2 then stay bounded however large z is), else 0; a Taylor series
    below |z| = 1/2, where the closed forms cancel."""
    z = np.asarray(z, complex)
    m1 = np.empty(z.shape, complex)
    m2 = np.empty(z.shape, complex)
    e = np.zeros(z.shape, complex)
    small = np.abs(z) < 0.5
    if np.any(small):
        zs = z[small]
        s1, s2 = np.zeros_like(zs), np.zeros_like(zs)
        t1, t2 = np.ones_like(zs), np.full_like(zs, 0.5)       # z^n / (n + 1)!, z^n / (n + 2)!
        for n in range(16):
            s1, s2 = s1 + t1, s2 + t2
            t1, t2 = t1 * zs / (n + 2), t2 * zs / (n + 3)
        m1[small], m2[small] = s1, s2
    big = ~small
    if np.any(big):
        zb = z[big]
        split = zb.real > 0
        w = np.where(split, -zb, zb)                             # Re w <= 0: e^w bounded
        ew = np.exp(w)
        p1 = (ew - 1.0) / w
        # phi1(z) = e^z phi1(-z); phi2(z) = e^z (e^w - phi1(w)) / w for w = -z
        m1[big] = p1
        m2[big] = np.where(split, (ew - p1) / w, (ew - 1.0 - w) / (w * w))
        e[big] = np.where(split, zb, 0.0)
    return m1, m2, e


def _integral(weight, logc, q):
    """sum_t exp(logc_t) int_lo^d (alpha + beta (s - lo)) exp(q_t (s - d)) ds over the last axis (the terms t),
    s = z + d the height above the bed, `weight` = (alpha, beta, lo, d - lo)."""
    alpha, beta, _, length = weight
    m1, m2, e = _phi(-q * length)
    return np.sum(np.exp(logc + e) * (alpha * length * m1 + beta * length * length * m2), axis=-1)


def _terms(k, lognu, depth, sinh=False):
    """cosh(k s) / nu (or sinh(k s) / nu) as two exponentials exp(logc) exp(q (s - d)): (logc, q), last axis 2."""
    kd = k * depth
    plus = _LOG_HALF + kd - lognu
    minus = _LOG_HALF - kd - lognu + (1j * math.pi if sinh else 0.0)
    return np.stack([plus, minus], axis=-1), np.stack([k, -k], axis=-1)


def _product(a, b):
    """The terms of the product of two sums of exponentials (last axes combined)."""
    lc = a[0][..., :, None] + b[0][..., None, :]
    qc = a[1][..., :, None] + b[1][..., None, :]
    return lc.reshape(lc.shape[:-2] + (-1,)), qc.reshape(qc.shape[:-2] + (-1,))


def _free_mode_terms(K, depth):
    """cosh(K s) / cosh(K d) for real K > 0 as exponentials (logc, q) (no overflow for any K d)."""
    K = np.asarray(K, float)
    lk = np.log1p(np.exp(-2.0 * K * depth))
    return (np.stack([-lk, -2.0 * K * depth - lk], axis=-1).astype(complex),
            np.stack([K, -K], axis=-1).astype(complex))


def _evanescent_wavenumbers(omega, depth, modes, g):
    """kappa_j [1/m], j = 1 .. `modes`: the roots of omega^2 = -g kappa tan(kappa d) in ((j - 1/2) pi, j pi) / d.

    With y = j pi - kappa d in (0, pi/2), (j pi - y) tan y = omega^2 d / g, solved by the iteration
    y <- atan(omega^2 d / (g (j pi - y))), a contraction (its derivative is below 1 / pi)."""
    sigma = np.asarray(omega, float)[..., None] ** 2 * depth / g
    j = np.arange(1, modes + 1) * math.pi
    y = np.zeros(sigma.shape[:-1] + (modes,))
    for _ in range(200):
        y_new = np.arctan(sigma / (j - y))
        done = y.size == 0 or np.max(np.abs(y_new - y)) <= 1e-15
        y = y_new
        if done:
            break
    return (j - y) / depth


# ------------------------------------------------------------------------------------------------------------
# The paddle, the first-order modes, the pairs

def _paddle_weight(paddle, depth, hinge):
    """(alpha, beta, lo, d - lo): the paddle's shape f = alpha + beta (s - lo) on lo <= s <= d, 0 below."""
    if paddle == "piston":
        return (1.0, 0.0, 0.0, float(depth))
    if paddle == "flap":
        arm = depth - hinge
        lo = max(hinge, 0.0)
        return ((lo - hinge) / arm, 1.0 / arm, lo, depth - lo)
    raise ValueError(f"paddle = {paddle!r} is not a paddle type; allowed: 'piston', 'flap'")


def _check(depth, paddle, hinge, theory, modes):
    if not (math.isfinite(depth) and depth > 0):
        raise ValueError(f"depth = {depth:g} m: give the still-water depth at the paddle, positive")
    if paddle == "flap" and not hinge < depth:
        raise ValueError(f"hinge = {hinge:g} m is not below the still-water level d = {depth:g} m: a flap hinged "
                         "there moves no water; give hinge < depth (0: hinged at the bed)")
    if paddle == "piston" and hinge != 0.0:
        raise ValueError("hinge places a flap's hinge; paddle = 'piston' has none: give paddle = 'flap' or leave "
                         "it out")
    if theory not in THEORIES:
        raise ValueError(f"theory = {theory!r} is not a theory; allowed: 'schaffer' (Schäffer 1996), 'madsen' "
                         "(Madsen 1971)")
    if modes is not None and (isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or modes < 0):
        raise ValueError(f"evanescent_modes = {modes!r}: give a whole number of modes, 0 or more, or None (64 per "
                         "draft in the depth: module docstring)")


def default_modes(depth, paddle="piston", hinge=0.0):
    """The default number J of evanescent modes: 64 ceil(d / (d - max(l, 0))) (64 for a piston and a flap hinged at
    or below the bed). A flap hinged above the bed bends its profile at the hinge, whose trace in the series
    needs modes in proportion to d over the flap's draft d - l. The accuracy also depends on omega^2 d / g
    of the components (module docstring: 1e-3 at 2.5, 1.4e-2 at 10).

    Parameters
    ----------
    depth : float
        d [m].
    paddle : str
        "piston" or "flap".
    hinge : float
        l [m].

    Returns
    -------
    int
    """
    if paddle != "flap" or hinge <= 0.0:
        return 64
    return 64 * math.ceil(depth / (depth - hinge) - 1e-9)


class _FirstOrder:
    """The first-order modes of the components (one row each): wavenumbers k_j (k_0 real, k_j = -i kappa_j),
    amplitudes C_j of cosh(k_j s) / nu_j (nu_0 = cosh k d, nu_j = 1), their surface values C cosh(k_j d) / nu_j
    and C sinh(k_j d) / nu_j, and the paddle amplitudes Xh."""

    def __init__(self, omega, amplitude, depth, weight, modes, g):
        h = depth
        self.omega = np.asarray(omega, float)
        k0 = wavenumbers(self.omega, h, g)
        kappa = _evanescent_wavenumbers(self.omega, h, modes, g)
        n = len(k0)
        self.k = np.concatenate([k0[:, None].astype(complex), -1j * kappa], axis=1)
        lognu = np.zeros(self.k.shape, complex)
        lognu[:, 0] = k0 * h + np.log1p(np.exp(-2.0 * k0 * h)) - math.log(2.0)
        self.cosh = _terms(self.k, lognu, h)
        self.sinh = _terms(self.k, lognu, h, sinh=True)
        fpsi = _integral(weight, *self.cosh)
        norm = _integral((1.0, 0.0, 0.0, h), *_product(self.cosh, self.cosh))
        self.xhat = -1j * g * np.asarray(amplitude, complex) * k0 * norm[:, 0] / (self.omega**2 * fpsi[:, 0])
        coef = -self.omega[:, None] * self.xhat[:, None] * fpsi / (self.k * norm)
        ch = np.concatenate([np.ones((n, 1)), np.cos(kappa * h)], axis=1)
        sh = np.concatenate([np.tanh(k0 * h)[:, None], -1j * np.sin(kappa * h)], axis=1)
        self.coef = coef
        self.c_surf = coef * ch
        self.s_surf = coef * sh


def _side(first, idx, conj, cut):
    """The modes of components `idx` (their first `cut`), as those of -omega, -k*, C* for `conj` (the complex
    conjugate of a mode is a mode of the negative frequency)."""
    w = first.omega[idx]
    k, c, s = first.k[idx, :cut], first.c_surf[idx, :cut], first.s_surf[idx, :cut]
    if conj:
        return -w, -np.conj(k), np.conj(c), -np.conj(s)
    return w, k, c, s


def _richardson(modes, cut):
    """Weights of the modes 0 .. cut - 1: 1 up to J/2, 2 above (one Richardson step on a 1/J tail)."""
    j = np.arange(cut)
    return np.where(j <= modes // 2, 1.0, 2.0) if modes >= 2 else np.ones(cut)


def _surface_sum(a, b, Om, K, g, theory, depth, weights):
    """sum over the modes a of one side and b of the other (both orders) of the projection of the bound
    potentials' flux, weighted by `weights` (a x b).

    The forcing of a pair of modes is a sum of four products, Q_ab = sum_t F_t(a) G_t(b):
    Q_ab = -2 i Omega [(k s)_a (k s)_b - (k c)_a (k c)_b] + i omega_a c_a [k_b^2 c_b - (omega_b^2 / g) k_b s_b]
    + i [k_a^2 c_a - (omega_a^2 / g) k_a s_a] omega_b c_b (c, s: the modes' surface values C cosh(k d),
    C sinh(k d)), so that the double sum is one matrix product with the kernel of the projection,
    -i p / (g (p^2 - K^2)) (Schäffer) or -i tanh(p d) / (g p tanh(p d) - Omega^2) (Madsen), p = k_a + k_b."""
    wa, ka, ca, sa = a
    wb, kb, cb, sb = b
    om = Om[:, None]
    f = np.stack([-2j * om * ka * sa, 2j * om * ka * ca, 1j * wa[:, None] * ca,
                  1j * (ka * ka * ca - (wa**2 / g)[:, None] * ka * sa)], axis=-1)
    gg = np.stack([kb * sb, kb * cb, kb * kb * cb - (wb**2 / g)[:, None] * kb * sb, wb[:, None] * cb], axis=-1)
    p = ka[:, :, None] + kb[:, None, :]
    if theory == "schaffer":
        KK = (K * K)[:, None, None]
        kernel = p / (p * p - KK) * (weights * (-1j / g))
    else:
        t = np.tanh(p * depth)
        kernel = t / (g * p * t - (Om * Om)[:, None, None]) * (weights * -1j)
    return np.sum(f * np.matmul(kernel, gg), axis=(1, 2))


def _paddle_side(first, idx, conj, cut, weight, wave, modes):
    """sum_j C_j [k_j int f' sinh(k_j s) w ds + k_j^2 int f cosh(k_j s) w ds] over the modes of components `idx`
    (w the projection's weight function), Richardson-weighted.

    cosh and sinh have the same exponents (their second term differs in sign only), so both integrals come
    from one evaluation of phi1, phi2."""
    logc, q = _product((first.cosh[0][idx, :cut], first.cosh[1][idx, :cut]), (wave[0][:, None, :], wave[1][:, None, :]))
    alpha, beta, _, length = weight
    m1, m2, e = _phi(-q * length)
    ex = np.exp(logc + e)
    sign = np.repeat([1.0, -1.0], wave[0].shape[-1])      # the sinh terms: the second exponential negated
    i_f = np.sum(ex * (alpha * length * m1 + beta * length * length * m2), axis=-1)
    i_fp = np.sum(ex * (sign * beta * length) * m1, axis=-1)
    k, c = first.k[idx, :cut], first.coef[idx, :cut]
    total = np.sum(_richardson(modes, cut) * c * (k * i_fp + k * k * i_f), axis=1)
    return np.conj(total) if conj else total


def _pair_displacement(first, weight, n, m, sign, depth, theory, modes, g):
    """Xh2 of the pairs (n, m) at omega_n + sign omega_m: the complex amplitude of the second-order displacement
    at that frequency (X2 = Re Xh2 exp(i Omega t)), for the pairs taken once (n < m, and n = m for sums)."""
    h = depth
    cut = modes + 1 if theory == "schaffer" else 1
    Om = first.omega[n] + sign * first.omega[m]
    K = wavenumbers(Om, h, g)
    a = _side(first, n, False, cut)
    b = _side(first, m, sign < 0, cut)
    w = _richardson(modes, cut)
    small = min(cut, max(1, modes // 4 + 1))             # the L-shaped block: min(a, b) < small
    rows = (a[0],) + tuple(x[:, :small] for x in a[1:])
    flux = _surface_sum(rows, b, Om, K, g, theory, h, np.maximum(w[:small, None], w[None, :]))
    if cut > small:
        cols = (a[0],) + tuple(x[:, small:] for x in a[1:])
        low = (b[0],) + tuple(x[:, :small] for x in b[1:])
        flux = flux + _surface_sum(cols, low, Om, K, g, theory, h, np.maximum(w[small:, None], w[None, :small]))
    if theory == "schaffer":
        wave = _free_mode_terms(K, h)
    else:
        wave = (np.zeros((len(n), 1), complex), np.zeros((len(n), 1), complex))
    xm = np.conj(first.xhat[m]) if sign < 0 else first.xhat[m]
    nonlinear = (first.xhat[n] * _paddle_side(first, m, sign < 0, cut, weight, wave, modes)
                 + xm * _paddle_side(first, n, False, cut, weight, wave, modes))
    swept = _integral(weight, *wave)
    once = np.where(n == m, 0.25, 0.5)
    return once * (flux - nonlinear) / (1j * Om * swept)


def _pairs(omega, subharmonic, superharmonic):
    """Index arrays (n, m) of the sum pairs (n <= m) and of the difference pairs, these ordered so that
    omega_n > omega_m (components of equal frequency make no difference term: that is the mean)."""
    i, j = np.triu_indices(len(omega))
    su = (i, j) if superharmonic else (i[:0], j[:0])
    if not subharmonic:
        return su, (i[:0], j[:0])
    off = omega[i] != omega[j]
    i, j = i[off], j[off]
    swap = omega[i] < omega[j]
    return su, (np.where(swap, j, i), np.where(swap, i, j))


def _chunks(size, per_pair):
    step = max(1, _PAIR_ELEMENTS // max(per_pair, 1))
    return [slice(s, min(size, s + step)) for s in range(0, size, step)]


# ------------------------------------------------------------------------------------------------------------
# Bound waves

def bound_wave_transfer(omega_n, k_n, omega_m, k_m, depth, g=GRAVITY):
    """Second-order bound-wave transfer functions K+_nm, K-_nm of waves travelling along +x (Sharma & Dean 1981,
    in the form of Dalzell 1999 and Forristall 2000)::

        eta2 = sum_n sum_m a_n a_m [K+_nm cos(theta_n + theta_m) + K-_nm cos(theta_n - theta_m)],
        K+-_nm = (1/4) [ (D+-_nm - (k_n k_m -+ R_n R_m)) / sqrt(R_n R_m) + R_n + R_m ],
        D+-_nm = { (sqrt R_n +- sqrt R_m) [ sqrt R_m (k_n^2 - R_n^2) +- sqrt R_n (k_m^2 - R_m^2) ]
                   + 2 (sqrt R_n +- sqrt R_m)^2 (k_n k_m -+ R_n R_m) }
                 / [ (sqrt R_n +- sqrt R_m)^2 - k+-_nm tanh(k+-_nm d) ],

    R = omega^2 / g, k+-_nm = k_n +- k_m, the sum over all ordered pairs (each pair n != m counts twice).
    K+_nn a_n^2 is Stokes' second harmonic, k a^2 cosh kd (2 + cosh 2kd) / (4 sinh^3 kd); 2 K-_nm tends, for
    omega_m -> omega_n, to the set-down of Longuet-Higgins & Stewart (1962) under a group,
    -g (2 c_g / c - 1/2) / (g d - c_g^2); in deep water K+ -> (k_n + k_m) / 4 and K- -> -|k_n - k_m| / 4
    (Longuet-Higgins 1963). K-_nn (the mean level) is not defined: NaN.

    Parameters
    ----------
    omega_n, k_n, omega_m, k_m : array_like
        Angular frequencies [rad/s] and wavenumbers [1/m] of the two components (broadcast together).
    depth : float
        d [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        K+ and K- [1/m].
    """
    wn, kn, wm, km = np.broadcast_arrays(*(np.asarray(v, float) for v in (omega_n, k_n, omega_m, k_m)))
    rn, rm = wn**2 / g, wm**2 / g
    sn, sm = np.sqrt(rn), np.sqrt(rm)
    out = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for s in (1.0, -1.0):
            kk = kn + s * km
            num = ((sn + s * sm) * (sm * (kn**2 - rn**2) + s * sn * (km**2 - rm**2))
                   + 2.0 * (sn + s * sm) ** 2 * (kn * km - s * rn * rm))
            d = num / ((sn + s * sm) ** 2 - kk * np.tanh(kk * depth))
            out.append(0.25 * ((d - (kn * km - s * rn * rm)) / np.sqrt(rn * rm) + rn + rm))
    plus, minus = out
    minus = np.where(wn == wm, np.nan, minus)
    return plus, minus


@dataclass(frozen=True)
class BoundWaves:
    """The second-order bound waves of a set of components: eta2(x, t) = Re sum_p c_p exp(i (Omega_p t - K_p x)),
    one term per pair of components (n <= m for the sums, n < m for the differences),
    c_p = 2 K+-_nm A_n A_m^(*) (K+_nn A_n^2 for n = m), K_p = k_n +- k_m (`bound_wave_transfer`).

    Attributes
    ----------
    omegas : numpy.ndarray
        Omega_p = omega_n +- omega_m [rad/s].
    wavenumbers : numpy.ndarray
        K_p [1/m] (negative for a difference whose higher frequency has the smaller wavenumber: none in
        water of one depth).
    coefficients : numpy.ndarray
        c_p [m], complex.
    """

    omegas: np.ndarray
    wavenumbers: np.ndarray
    coefficients: np.ndarray

    def elevation(self, x, t):
        """eta2(x, t) [m] at the distance `x` [m] in front of the paddle, at the times `t` [s] (array_like; the
        result has its shape). Add `shoal.waves.WaveComponents.elevation` for the target to second order."""
        c = self.coefficients * np.exp(-1j * self.wavenumbers * float(x))
        return _evaluate(self.omegas, c, t, 0)


def bound_waves(waves, *, subharmonic=True, superharmonic=True, g=GRAVITY):
    """The second-order bound waves of `waves` (Sharma & Dean 1981; `bound_wave_transfer`).

    Parameters
    ----------
    waves : shoal.waves.WaveComponents
    subharmonic, superharmonic : bool
        Keep the difference-frequency (set-down, bound long waves) and the sum-frequency terms.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    BoundWaves
    """
    w, k = waves.omegas, np.asarray(waves.wavenumbers, float)
    amp = waves.amplitudes * np.exp(1j * waves.phases)
    su, sb = _pairs(w, subharmonic, superharmonic)
    kp, _ = bound_wave_transfer(w[su[0]], k[su[0]], w[su[1]], k[su[1]], waves.depth, g)
    _, km = bound_wave_transfer(w[sb[0]], k[sb[0]], w[sb[1]], k[sb[1]], waves.depth, g)
    cp = np.where(su[0] == su[1], 1.0, 2.0) * kp * amp[su[0]] * amp[su[1]]
    cm = 2.0 * km * amp[sb[0]] * np.conj(amp[sb[1]])
    return BoundWaves(np.concatenate([w[su[0]] + w[su[1]], w[sb[0]] - w[sb[1]]]),
                      np.concatenate([k[su[0]] + k[su[1]], k[sb[0]] - k[sb[1]]]),
                      np.concatenate([cp, cm]))


# ------------------------------------------------------------------------------------------------------------
# The paddle

def _evaluate(omegas, coefficients, t, derivative):
    """Re sum_p (i Omega_p)^derivative c_p exp(i Omega_p t) at the times `t`, summed in chunks."""
    t = np.asarray(t, float)
    flat = t.ravel()
    c = (coefficients * (1j * omegas) ** derivative)[:, None]
    w = np.asarray(omegas, float)[:, None]
    out = np.zeros(flat.shape)
    step = max(1, _CHUNK // max(len(omegas), 1))
    for i in range(0, len(flat), step):
        out[i:i + step] = np.real(np.sum(c * np.exp(1j * w * flat[None, i:i + step]), axis=0))
    return out.reshape(t.shape)


@dataclass(frozen=True)
class SecondOrderPaddle:
    """The second-order paddle displacement X2(t) = Re sum_p c_p exp(i Omega_p t) [m], at the still-water level
    (`second_order_paddle`). X1 + X2 drives the paddle, X1 its first-order signal (for a flap, X is the excursion
    of the face at the still-water level, the angle atan(X / (d - l))).

    Attributes
    ----------
    omegas : numpy.ndarray
        Omega_p [rad/s], the sums and differences of the components' frequencies (each frequency once when the
        components lie on a grid of multiples of df, as `shoal.waves.frequency_grid` makes them).
    coefficients : numpy.ndarray
        c_p [m], complex.
    depth : float
    paddle : str
        "piston" or "flap".
    hinge : float
        l [m], the flap's hinge above the bed.
    theory : str
        "schaffer" or "madsen".
    evanescent_modes : int
    """

    omegas: np.ndarray
    coefficients: np.ndarray
    depth: float
    paddle: str
    hinge: float
    theory: str
    evanescent_modes: int

    def displacement(self, t):
        """X2(t) [m] at the times `t` [s] (array_like; the result has its shape)."""
        return _evaluate(self.omegas, self.coefficients, t, 0)

    def velocity(self, t):
        """dX2/dt [m/s] at the times `t` [s]."""
        return _evaluate(self.omegas, self.coefficients, t, 1)

    def acceleration(self, t):
        """d^2X2/dt^2 [m/s^2] at the times `t` [s]."""
        return _evaluate(self.omegas, self.coefficients, t, 2)

    @property
    def max_displacement(self):
        """sum_p |c_p| [m]: a bound on |X2(t)| at any time."""
        return float(np.sum(np.abs(self.coefficients)))


def _group(omegas, coefficients, step):
    """The terms of equal frequency added together when the frequencies are multiples of `step` [rad/s]."""
    if not (step > 0 and len(omegas)):
        return omegas, coefficients
    index = np.rint(omegas / step)
    if not np.allclose(index * step, omegas, rtol=1e-9, atol=0.0):
        return omegas, coefficients
    keys, inverse = np.unique(index.astype(np.int64), return_inverse=True)
    total = np.zeros(len(keys), complex)
    np.add.at(total, inverse, coefficients)
    return keys * step, total


def second_order_paddle(waves, paddle="piston", hinge=0.0, *, subharmonic=True, superharmonic=True,
                        theory="schaffer", evanescent_modes=None, g=GRAVITY):
    """The second-order paddle displacement X2(t) that suppresses the spurious free waves of `waves`.

    For every pair of components, X2 holds the term at the sum (superharmonic) and at the difference
    (subharmonic) of their frequencies that makes the free wave at that frequency zero, to second order in
    the wave steepness; the module's docstring gives the theory (Schäffer 1996), its equations and the
    conventions (X1 = sum_n (a_n / T_n) sin(omega_n t + phi_n), the signal of `shoal.motions.SpectralPaddle`).
    The first-order signal stays as it is: the paddle moves as X1 + X2.

    Parameters
    ----------
    waves : shoal.waves.WaveComponents
        The first-order components (their wavenumbers must be those of `g`).
    paddle : str
        "piston", or "flap" hinged `hinge` l [m] above the bed (l < d; l < 0: below it).
    hinge : float
        l [m], for a flap.
    subharmonic, superharmonic : bool
        Correct the difference-frequency waves (the spurious long waves), the sum-frequency ones, or both.
    theory : str
        "schaffer": the free wave's projection on its mode cosh K(z + d), the evanescent modes of the first
        order included (Schäffer 1996); "madsen": the depth-integrated mass flux, progressive modes only
        (Madsen 1971: exact for long free waves; the closed form for one component and a piston).
    evanescent_modes : int or None
        J, the evanescent modes of each component (0 leaves them out); None: `default_modes`.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    SecondOrderPaddle

    Raises
    ------
    ValueError
        For an unknown paddle or theory, a flap's hinge at or above the still-water level, a hinge given to a
        piston, a negative number of modes, or components whose wavenumbers are not those of `g`.
    """
    depth = float(waves.depth)
    _check(depth, paddle, float(hinge), theory, evanescent_modes)
    weight = _paddle_weight(paddle, depth, float(hinge))
    keep = np.flatnonzero(waves.amplitudes > 0)
    w = waves.omegas[keep]
    amp = (waves.amplitudes * np.exp(1j * waves.phases))[keep]
    k = wavenumbers(w, depth, g)
    if not np.allclose(k, np.asarray(waves.wavenumbers, float)[keep], rtol=1e-9, atol=0.0):
        raise ValueError(f"the components' wavenumbers are not those of omega^2 = g k tanh(k d) with g = {g:g} "
                         "m/s^2 and their depth: make them with the same g")
    modes = _modes(evanescent_modes, depth, paddle, float(hinge), theory)
    first = _FirstOrder(w, amp, depth, weight, modes, g)
    su, sb = _pairs(w, subharmonic, superharmonic)
    omegas, coefficients = [], []
    for (n, m), sign in ((su, 1.0), (sb, -1.0)):
        for part in _chunks(len(n), _per_pair(modes)):
            nn, mm = n[part], m[part]
            coefficients.append(_pair_displacement(first, weight, nn, mm, sign, depth, theory, modes, g))
            omegas.append(w[nn] + sign * w[mm])
    omegas = np.concatenate(omegas) if omegas else np.zeros(0)
    coefficients = np.concatenate(coefficients) if coefficients else np.zeros(0, complex)
    omegas, coefficients = _group(omegas, coefficients, 2.0 * math.pi * float(waves.df))
    return SecondOrderPaddle(omegas, coefficients, depth, paddle, float(hinge), theory, modes)


def _modes(modes, depth, paddle, hinge, theory):
    if theory != "schaffer":
        return 0
    return default_modes(depth, paddle, hinge) if modes is None else int(modes)


def _per_pair(modes):
    """Elements of the largest arrays of one pair: the two blocks of mode pairs and the paddle's integrals."""
    return 2 * (modes + 1) * (modes // 4 + 1) + 8 * (modes + 1)


def paddle_transfer(omega_n, omega_m, depth, paddle="piston", hinge=0.0, *, theory="schaffer", evanescent_modes=None,
                    g=GRAVITY):
    """Second-order paddle transfer functions G+_nm, G-_nm [1/m] of two components (module docstring):

        X2 = sum_n sum_m Re[ G+_nm A_n A_m exp(i (omega_n + omega_m) t) + G-_nm A_n A_m* exp(i (omega_n - omega_m) t) ],

    X2 the displacement at the still-water level, A_n the components' complex amplitudes (eta1 =
    Re sum A_n exp(i (omega_n t - k_n x))). G+ is symmetric, G-_mn = conj(G-_nm); G-_nn (a mean displacement)
    is 0. In Schäffer's (1996) notation, G+-_nm = -i F+-_nm / (2 d), F+- of his Eq. (41a).

    Parameters
    ----------
    omega_n, omega_m : array_like
        Angular frequencies [rad/s] (broadcast together), positive.
    depth : float
        d [m].
    paddle, hinge, theory, evanescent_modes, g
        As `second_order_paddle`.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        G+ and G-, complex, of the broadcast shape.
    """
    depth = float(depth)
    _check(depth, paddle, float(hinge), theory, evanescent_modes)
    wn, wm = np.broadcast_arrays(np.asarray(omega_n, float), np.asarray(omega_m, float))
    shape = wn.shape
    wn, wm = wn.ravel(), wm.ravel()
    if not (np.all(np.isfinite(wn)) and np.all(np.isfinite(wm)) and np.all(wn > 0) and np.all(wm > 0)):
        raise ValueError("give positive, finite angular frequencies")
    weight = _paddle_weight(paddle, depth, float(hinge))
    modes = _modes(evanescent_modes, depth, paddle, float(hinge), theory)
    first = _FirstOrder(np.concatenate([wn, wm]), np.ones(2 * len(wn)), depth, weight, modes, g)
    count = len(wn)
    n, m = np.arange(count), np.arange(count) + count
    plus = np.zeros(count, complex)
    minus = np.zeros(count, complex)
    for part in _chunks(count, _per_pair(modes)):
        plus[part] = 0.5 * _pair_displacement(first, weight, n[part], m[part], 1.0, depth, theory, modes, g)
    differ = np.flatnonzero(wn != wm)
    swap = wn[differ] < wm[differ]           # computed at omega_n - omega_m > 0; G-_mn = conj(G-_nm)
    hi = np.where(swap, m[differ], n[differ])
    lo = np.where(swap, n[differ], m[differ])
    for part in _chunks(len(differ), _per_pair(modes)):
        value = 0.5 * _pair_displacement(first, weight, hi[part], lo[part], -1.0, depth, theory, modes, g)
        minus[differ[part]] = np.where(swap[part], np.conj(value), value)
    return plus.reshape(shape), minus.reshape(shape)


def madsen_piston_second_harmonic(height, period, depth, g=GRAVITY):
    """The second-order stroke correction of a piston making regular waves, Madsen (1971):

        X(t) = (S/2) sin(omega t) + M sin(2 omega t),   M = (H^2 / (32 d)) (3 cosh kd / sinh^3 kd - 2 / m1),

    m1 = H/S of the piston (`shoal.waves.piston_height_to_stroke`), for the wave eta = (H/2) cos(omega t - k x)
    plus its Stokes second harmonic. It is the mass-flux closure (``theory = "madsen"`` of
    `second_order_paddle`); Schäffer's (1996) tends to it in shallow water. Madsen's limit of validity is
    H L^2 / d^3 < 8 pi^2 / 3 (the shallow-water second harmonic below a quarter of the first).

    Parameters
    ----------
    height, period, depth : float
        H [m], T [s], d [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    float
        M [m].
    """
    k = float(wavenumbers(np.array([2.0 * math.pi / period]), depth, g)[0])
    kd = k * depth
    m1 = 2.0 * (math.cosh(2.0 * kd) - 1.0) / (math.sinh(2.0 * kd) + 2.0 * kd)
    return height**2 / (32.0 * depth) * (3.0 * math.cosh(kd) / math.sinh(kd) ** 3 - 2.0 / m1)


def regular_second_order(height, period, depth, paddle="piston", hinge=0.0, *, theory="schaffer",
                         evanescent_modes=None, g=GRAVITY):
    """The second-order correction of a paddle making the regular wave eta1 = (H/2) cos(omega t - k x) with
    X1 = (S/2) sin(omega t) (`shoal.motions.PistonWavemaker`, `FlapWavemaker`): one component of
    `second_order_paddle`, X2(t) = Re c exp(2 i omega t) (a single frequency 2 omega).

    Parameters
    ----------
    height, period, depth : float
        H [m], T [s], d [m].
    paddle, hinge, theory, evanescent_modes, g
        As `second_order_paddle`.

    Returns
    -------
    SecondOrderPaddle
    """
    f = 1.0 / float(period)
    k = wavenumbers(np.array([2.0 * math.pi * f]), depth, g)
    waves = WaveComponents(np.array([f]), np.array([0.5 * float(height)]), np.zeros(1), k, float(depth), f)
    return second_order_paddle(waves, paddle, hinge, subharmonic=False, theory=theory,
                               evanescent_modes=evanescent_modes, g=g)
