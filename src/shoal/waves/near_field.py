"""The elevation a paddle makes near itself: the progressive wave and the evanescent modes, in linear theory.

A paddle in water of depth d whose face moves horizontally by X(t) = b sin(omega t) at the still-water level,
with the velocity profile U(z) = f(z) X'(t) (f = 1 for a piston; f = (d + z - l) / (d - l) above a flap's hinge
at the height l above the bed, 0 below it), makes the velocity potential of Havelock (1929) (Dean & Dalrymple
1991, section 6.3): the profile f is expanded in the depth modes

    f(z) = c_0 cosh k (d + z) + sum_{n >= 1} c_n cos kappa_n (d + z),

    omega^2 = g k tanh kd,   omega^2 = -g kappa_n tan(kappa_n d),   (n - 1/2) pi < kappa_n d < n pi,

c_n = int f cos kappa_n (d + z) dz / int cos^2 kappa_n (d + z) dz over the depth (and the same with cosh for
c_0). The progressive mode carries the wave away, eta_0 = a cos(omega t - k x) with a = c_0 sinh(kd) b (the
transfer function H / S of `shoal.waves.transfer`); each evanescent mode stays at the paddle, decaying as
exp(-kappa_n x), in quadrature with the progressive wave:

    eta(x, t) = a cos(omega t - k x) - E(x) X(t),
    E(x) = (omega^2 / g) sum_{n >= 1} (c_n / kappa_n) cos(kappa_n d) exp(-kappa_n x).

A gauge a fraction of a depth in front of a paddle reads the near field too: at kd = 1.1 a piston's E b is
about 7 % of the wave amplitude at the face, 20 % at kd = 2. An active absorber (`shoal.active_absorption`)
compares what such a gauge reads with this elevation, so that the near field of the wave it makes is not taken
for a wave coming back.
"""

from __future__ import annotations

import math

import numpy as np

from .dispersion import GRAVITY

MODES = 400
"""Evanescent modes summed: their terms fall as 1 / n^2 at the face (the tail beyond n is about 1 / n of the
sum), and as exp(-n pi x / d) in front of it."""


def evanescent_wavenumbers(omega, depth, modes=MODES):
    """kappa_n [1/m], n = 1 .. `modes`, the roots of omega^2 = -g kappa tan(kappa d) in ((n - 1/2) pi / d,
    n pi / d), by Newton's method on q sin q + nu cos q = 0 (q = kappa d, nu = omega^2 d / g), started from the
    asymptote q = n pi - nu / (n pi) and kept inside its bracket."""
    nu = float(omega) ** 2 * float(depth) / GRAVITY
    n = np.arange(1, int(modes) + 1, dtype=float)
    lo, hi = (n - 0.5) * math.pi, n * math.pi
    q = np.clip(n * math.pi - nu / (n * math.pi), lo + 1e-12, hi - 1e-12)
    for _ in range(60):
        f = q * np.sin(q) + nu * np.cos(q)
        df = np.sin(q) + q * np.cos(q) - nu * np.sin(q)
        step = f / df
        q = np.clip(q - step, lo + 1e-15, hi - 1e-15)
        if np.all(np.abs(step) <= 1e-15 * q):
            break
    return q / float(depth)


def _profile_integrals(kappa, depth, hinge, hyperbolic):
    """int_{s0}^{d} f cos(kappa s) ds (or cosh) with s = d + z and f = 1 (hinge None) or (s - l) / (d - l), s0 =
    max(l, 0), and int_0^d cos^2 (cosh^2), closed forms."""
    d = float(depth)
    if hyperbolic:
        sn, cs, sq = np.sinh, np.cosh, 1.0
    else:
        sn, cs, sq = np.sin, np.cos, -1.0
    norm = 0.5 * d + sn(2.0 * kappa * d) / (4.0 * kappa)
    if hinge is None:
        return sn(kappa * d) / kappa, norm
    l = float(hinge)
    s0 = max(l, 0.0)

    def antiderivative(s):  # of (s - l) cos(kappa s): (s - l) sin / kappa + cos / kappa^2 (cosh: - cosh / k^2)
        return (s - l) * sn(kappa * s) / kappa - sq * cs(kappa * s) / kappa**2

    return (antiderivative(d) - antiderivative(s0)) / (d - l), norm


def near_field(omega, depth, x, hinge=None, modes=MODES):
    """(T, E): the paddle's transfer a / b = T and its near-field coefficient E(x) [1/m] (module docstring).

    Parameters
    ----------
    omega : float
        Angular frequency [rad/s].
    depth : float
        d [m].
    x : float or array_like
        Distance [m] in front of the paddle's face (x >= 0).
    hinge : float, optional
        A flap's hinge height l [m] above the bed (below the still-water level; negative: below the bed);
        None (default) for a piston.
    modes : int
        Evanescent modes summed (`MODES`).

    Returns
    -------
    (float, float or numpy.ndarray)
        T = c_0 sinh(kd), which equals H / S of `shoal.waves.piston_height_to_stroke` or
        `flap_height_to_stroke`, and E(x) (the shape of `x`), so that eta = T b cos(omega t - k x) - E(x) b
        sin(omega t) for X(t) = b sin(omega t).
    """
    from .dispersion import wavenumber

    d = float(depth)
    k = wavenumber(2.0 * math.pi / float(omega), d)
    kd = k * d
    if kd > 20.0:  # deep water (cosh, sinh overflow): the transfer functions' own deep-water forms
        from .transfer import flap_height_to_stroke, piston_height_to_stroke

        t = float(piston_height_to_stroke(k, d) if hinge is None else flap_height_to_stroke(k, d, hinge))
    else:
        num, norm = _profile_integrals(k, d, hinge, True)
        t = float(num / norm * math.sinh(kd))
    kappa = evanescent_wavenumbers(omega, d, modes)
    num, norm = _profile_integrals(kappa, d, hinge, False)
    c = num / norm
    x = np.asarray(x, float)
    terms = (c / kappa * np.cos(kappa * d))[:, None] * np.exp(-np.outer(kappa, np.atleast_1d(x).ravel()))
    e_x = float(omega) ** 2 / GRAVITY * terms.sum(axis=0)
    return t, (float(e_x[0]) if x.ndim == 0 else e_x.reshape(x.shape))
