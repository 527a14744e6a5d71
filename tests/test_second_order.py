"""Second-order wave generation (`shoal.waves.second_order`, issue 31): the paddle's second-order correction
(Schäffer 1996; Madsen 1971) and the bound waves (Sharma & Dean 1981), against closed forms and limits.

The reference formulas are written out here, independently of the module:

* Madsen (1971), "On the generation of long waves", J. Geophys. Res. 76(36): the second-order stroke of a
  piston making regular waves, X = (S/2) sin(wt) + (H^2 / 32 d) (3 cosh kd / sinh^3 kd - 2 / m1) sin(2 wt),
  m1 = H/S (the form used by, e.g., DualSPHysics users' generation scripts);
* Stokes' second harmonic, a2 = k a^2 cosh kd (2 + cosh 2kd) / (4 sinh^3 kd) (Dean & Dalrymple 1991, ch. 11);
* Longuet-Higgins & Stewart (1962): the set-down under a group, -g (2 c_g / c - 1/2) / (g d - c_g^2) per unit
  a_n a_m;
* Longuet-Higgins (1963): deep-water sum and difference terms (k_n + k_m) / 2 and -|k_n - k_m| / 2 per unit
  a_n a_m;
* Schäffer (1996), "Second-order wavemaker theory for irregular waves", Ocean Eng. 23(1): his transfer
  function F+- (Eq. 41a, with E of 41b, M1 of 41c, M2 of 36b, c_j of 20, D_j of 21, H of 25d, K of 33), in
  the equation numbering of a public transcription of the paper's equations (a Python package
  `wavegenerator`, module `wavegenerator.functions`); written here from those equations. For the differences
  the second component's first-order quantities are those of -omega_m (its modes' complex conjugates), which
  is how the +- notation reads (the transcription keeps (omega_n + omega_m)^2 and unconjugated modes there;
  read that way literally, its differences do not agree with this module's).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shoal.waves import (GRAVITY, WaveComponents, bound_wave_transfer, bound_waves, default_modes, frequency_grid,
                         group_velocity, madsen_piston_second_harmonic, paddle_transfer, regular_second_order,
                         second_order_paddle, wavenumbers)

g = GRAVITY


def k_of(omega, depth):
    return float(wavenumbers(np.array([omega]), depth)[0])


def madsen(height, period, depth):
    """Madsen's (1971) second-harmonic stroke amplitude M [m] (X2 = M sin 2wt), written out here."""
    k = k_of(2 * math.pi / period, depth)
    kd = k * depth
    m1 = 4 * math.sinh(kd) ** 2 / (math.sinh(2 * kd) + 2 * kd)
    return height**2 / (32 * depth) * (3 * math.cosh(kd) / math.sinh(kd) ** 3 - 2 / m1)


def swept(depth, paddle, hinge):
    """int f dz: the volume the paddle sweeps per unit excursion at the still-water level."""
    if paddle == "piston":
        return depth
    lo = max(hinge, 0.0)
    return ((depth - hinge) ** 2 - (lo - hinge) ** 2) / (2 * (depth - hinge))


# --- (a) the regular wave: Madsen (1971) -----------------------------------------------------------------------

@pytest.mark.parametrize("period", [0.8, 1.2, 1.5, 2.0, 3.0, 6.0, 12.0])
def test_the_mass_flux_closure_is_madsens_closed_form(period):
    """One component, a piston, theory = "madsen": X2 = Re c exp(2 i w t) is Madsen's M sin(2 w t), c = -i M,
    amplitude and phase to round-off (kd from 0.12 to 3.2 in 0.5 m)."""
    depth, height = 0.5, 0.02
    x2 = regular_second_order(height, period, depth, theory="madsen")
    assert np.allclose(x2.omegas, [4 * math.pi / period], rtol=1e-14)
    m = madsen(height, period, depth)
    assert abs(x2.coefficients[0] - (-1j * m)) <= 1e-12 * abs(m)
    t = np.linspace(0.0, period, 7)
    assert np.allclose(madsen_piston_second_harmonic(height, period, depth) * np.sin(4 * math.pi * t / period),
                       x2.displacement(t), rtol=0, atol=1e-13 * abs(m))


def test_schaffers_correction_tends_to_madsens_in_shallow_water():
    """Schäffer's projection on cosh K(z + d) becomes the depth integral as Kd -> 0, and a piston makes no
    evanescent modes there: the ratio of the second harmonics tends to 1 as (kd)^4 (halving kd divides the
    difference by about 16, at least by 4), amplitude and phase."""
    depth, height = 1.0, 0.002
    err = []
    for period in (10.0, 20.0, 40.0):                       # kd = 0.20, 0.10, 0.050
        s = regular_second_order(height, period, depth).coefficients[0]
        m = madsen(height, period, depth)
        err.append(abs(s / (-1j * m) - 1))
    assert err[1] < 0.25 * err[0] and err[2] < 0.25 * err[1]
    assert err[2] < 1e-5


def test_schaffers_correction_differs_from_madsens_at_intermediate_depth():
    """At kd = 1.1 Madsen's second harmonic nearly vanishes (3 cosh kd / sinh^3 kd ~ 2 / m1) and Schäffer's does
    not: the two closures are different theories away from shallow water (the reason theory = "madsen" is
    offered only as the closed form's generalisation, not as the default)."""
    s = regular_second_order(0.02, 1.5, 0.5).coefficients[0]
    m = madsen(0.02, 1.5, 0.5)
    assert abs(s) > 10 * abs(m)


# --- (b) the bound waves: Stokes, Longuet-Higgins & Stewart --------------------------------------------------

@pytest.mark.parametrize("kd", [0.3, 0.7, 1.0, 2.0, 4.0, 10.0])
def test_identical_components_give_stokes_second_harmonic(kd):
    depth = 1.0
    k = kd / depth
    w = math.sqrt(g * k * math.tanh(kd))
    a = 0.01
    plus, _ = bound_wave_transfer(w, k, w, k, depth)
    a2 = k * a * a * math.cosh(kd) * (2 + math.cosh(2 * kd)) / (4 * math.sinh(kd) ** 3)
    assert float(plus) * a * a == pytest.approx(a2, rel=1e-12)
    # the same through bound_waves: eta2 = a2 cos 2 theta
    waves = WaveComponents(np.array([w / (2 * math.pi)]), np.array([a]), np.array([0.3]), np.array([k]), depth,
                           w / (2 * math.pi))
    t = np.linspace(0, 2 * math.pi / w, 9)
    x = 0.37
    expect = a2 * np.cos(2 * (w * t - k * x + 0.3))
    assert np.allclose(bound_waves(waves).elevation(x, t), expect, rtol=0, atol=1e-13 * a2)


@pytest.mark.parametrize("kd", [0.5, 1.0, 2.0, 3.0])
def test_narrow_group_gives_the_set_down_of_longuet_higgins_and_stewart(kd):
    """2 K-_nm (the pair counts twice) -> -g (2 c_g / c - 1/2) / (g d - c_g^2) as omega_m -> omega_n. With the two
    frequencies w0 (1 +- eps / 2), swapping them changes eps into -eps and leaves K- as it is: the difference is
    even in eps, of order eps^2 (halving eps divides it by 4), and below 1e-5 at eps = 1e-3."""
    depth = 1.0
    k0 = kd / depth
    w0 = math.sqrt(g * k0 * math.tanh(kd))
    c = w0 / k0
    cg = group_velocity(k0, depth)
    lhs = -g * (2 * cg / c - 0.5) / (g * depth - cg**2)

    def deviation(eps):
        wn, wm = w0 * (1 + eps / 2), w0 * (1 - eps / 2)
        _, minus = bound_wave_transfer(wn, k_of(wn, depth), wm, k_of(wm, depth), depth)
        return abs(2 * float(minus) / lhs - 1)

    d1, d2 = deviation(2e-3), deviation(1e-3)
    assert d2 < 1e-5
    assert d1 / d2 == pytest.approx(4.0, rel=0.05)


def test_deep_water_limits_of_the_bound_waves():
    """Longuet-Higgins (1963): in deep water K+ = (k_n + k_m) / 4, K- = -|k_n - k_m| / 4 (per ordered pair)."""
    depth = 200.0
    for tn, tm in ((1.0, 1.3), (0.8, 2.5), (1.0, 1.05)):
        wn, wm = 2 * math.pi / tn, 2 * math.pi / tm
        kn, km = k_of(wn, depth), k_of(wm, depth)
        plus, minus = bound_wave_transfer(wn, kn, wm, km, depth)
        assert float(plus) == pytest.approx((kn + km) / 4, rel=1e-12)
        assert float(minus) == pytest.approx(-abs(kn - km) / 4, rel=1e-10)


# --- (c) symmetry, the narrow-band, shallow-water and deep-water limits --------------------------------------

@pytest.mark.parametrize("paddle,hinge", [("piston", 0.0), ("flap", 0.0), ("flap", 0.2), ("flap", -0.3)])
def test_swapping_the_components(paddle, hinge):
    """G+_mn = G+_nm and G-_mn = conj(G-_nm) (the pair's term is real), K+- symmetric; G-_nn = 0."""
    depth = 0.5
    wn, wm = np.array([5.0, 6.3, 2.0]), np.array([7.0, 4.1, 2.0])
    pn, mn = paddle_transfer(wn, wm, depth, paddle, hinge, evanescent_modes=64)
    pm, mm = paddle_transfer(wm, wn, depth, paddle, hinge, evanescent_modes=64)
    assert np.allclose(pn, pm, rtol=1e-12, atol=0)
    assert np.allclose(mn, np.conj(mm), rtol=1e-12, atol=0)
    assert mn[2] == 0
    kn, km = wavenumbers(wn, depth), wavenumbers(wm, depth)
    a = bound_wave_transfer(wn[:2], kn[:2], wm[:2], km[:2], depth)
    b = bound_wave_transfer(wm[:2], km[:2], wn[:2], kn[:2], depth)
    assert np.allclose(a, b, rtol=1e-13, atol=0)


@pytest.mark.parametrize("paddle,hinge,period", [("piston", 0.0, 2.0), ("piston", 0.0, 0.6), ("flap", 0.0, 1.0),
                                                  ("flap", 0.2, 0.6), ("flap", -0.3, 1.0)])
def test_a_narrow_group_s_subharmonic_supplies_the_flux_of_its_bound_long_wave(paddle, hinge, period):
    """Near the paddle (a region much shorter than the group) the water's volume is conserved: the paddle's
    second-order flux int f dz dX2/dt (the first-order part, d(X1 eta1)/dt, is slow and vanishes with the
    bandwidth) is the flux c_g eta_b of the bound long wave, eta_b Longuet-Higgins & Stewart's set-down. So,
    as dw -> 0, 2 G-_nm -> c_g lhs / (i dw int f dz). The evanescent modes are needed for this (without them
    the ratio is 1.07 at kd = 0.77 and 11.7 at kd = 5.6, the piston cases here). The deviation is first order
    in dw / w; extrapolated to dw = 0 from dw / w = 2e-3 and 1e-3 it is the truncation of the evanescent series
    at J = 256 (measured: 2.7e-4 at kd = 5.6, halving when J doubles)."""
    depth = 0.5
    w0 = 2 * math.pi / period
    k0 = k_of(w0, depth)
    c, cg = w0 / k0, group_velocity(k0, depth)
    lhs = -g * (2 * cg / c - 0.5) / (g * depth - cg**2)

    def ratio(eps):
        wn, wm = w0 * (1 + eps / 2), w0 * (1 - eps / 2)
        _, minus = paddle_transfer(wn, wm, depth, paddle, hinge, evanescent_modes=256)
        return 2 * complex(minus) / (cg * lhs / (1j * (wn - wm) * swept(depth, paddle, hinge)))

    r1, r2 = ratio(2e-3), ratio(1e-3)
    assert abs(r2 - 1) < 2e-2
    assert abs(2 * r2 - r1 - 1) < 5e-4


@pytest.mark.parametrize("hinge", [0.0, 0.3])
def test_shallow_water_limits_of_the_flap(hinge):
    """As kd -> 0 the free waves are long and the paddle's flux int f dz dX2/dt must carry the bound waves'
    flux: Schäffer's correction tends to the mass-flux closure's, and a flap's to d / int f dz times the
    piston's (2 for a flap on the bed), sums and differences alike, the differences as (kd)^2 (halving kd
    divides them by about 4)."""
    depth = 1.0
    factor = depth / swept(depth, "flap", hinge)
    errs = []
    for period in (40.0, 80.0):                                # kd = 0.050, 0.025
        w = 2 * math.pi / period
        wn, wm = 1.1 * w, 0.9 * w
        fp, fm = paddle_transfer(wn, wm, depth, "flap", hinge)
        pp, pm = paddle_transfer(wn, wm, depth, "piston")
        mp, mm = paddle_transfer(wn, wm, depth, "flap", hinge, theory="madsen")
        errs.append([abs(fp / (factor * pp) - 1), abs(fm / (factor * pm) - 1), abs(fp / mp - 1), abs(fm / mm - 1)])
    errs = np.array(errs)
    assert np.all(errs[1] < 0.3 * errs[0])
    assert np.all(errs[1] < 3e-3)


def test_a_flap_of_fixed_draft_has_a_deep_water_limit():
    """A flap whose hinge stays 0.5 m below the surface: as the depth grows (4, 8, 16 m) its transfer
    functions converge, the step from 8 to 16 m 8 to 10 times smaller than that from 4 to 8 m (periods 1 s and
    2 s, whose difference wave is 6 m long; the default modes, 64 per draft in the depth). A piston reaching
    the bed has no such limit: its correction grows with the depth."""
    wn, wm = 2 * math.pi / 1.0, 2 * math.pi / 2.0
    values = [np.array(paddle_transfer(wn, wm, d, "flap", d - 0.5)) for d in (4.0, 8.0, 16.0)]
    step1, step2 = np.abs(values[1] - values[0]), np.abs(values[2] - values[1])
    assert np.all(step2 < 0.25 * step1)
    assert np.all(step2 < 5e-3 * np.abs(values[2]))


# --- (d) Schäffer's (1996) transfer functions -------------------------------------------------------------------

def _schaffer_wavenumbers(w, depth, modes):
    """k_0 and k_j = -i kappa_j (Schäffer's Eq. 15), kappa_j by bisection on omega^2 + g kappa tan(kappa d) = 0
    in ((j - 1/2) pi / d, j pi / d)."""
    k0 = k_of(w, depth)
    j = np.arange(1, modes + 1)
    lo, hi = (j - 0.5) * math.pi / depth + 1e-12, j * math.pi / depth - 1e-15
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        f = w * w + g * mid * np.tan(mid * depth)
        lo, hi = np.where(f > 0, lo, mid), np.where(f > 0, mid, hi)
    return np.concatenate([[k0 + 0j], -1j * 0.5 * (lo + hi)])


def schaffer_f(wn, wm, depth, l_below, modes, sign):
    """Schäffer's F+- (Eq. 41a) for a paddle hinged l_below under the bed (numpy.inf: a piston; negative: above
    the bed), the series cut after `modes` evanescent modes."""
    h = depth
    d = max(-l_below, 0.0)
    piston = math.isinf(l_below)

    def c_j(w, k):                                                   # Eq. (20), D_j of Eq. (21)
        dj = (k * h / 2) * (k * h / (np.sinh(k * h) * np.cosh(k * h)) + 1)
        if piston:
            return (w * w * h / g) / dj
        return (w * w * h / g - h / (h + l_below)) / dj + (h / (h + l_below)) / dj * np.cosh(k * d) / np.cosh(k * h)

    wb = sign * wm                                                   # a difference: the modes of -omega_m
    om = wn + wb
    big_k = k_of(abs(om), h)                                         # Eq. (33)
    kn = _schaffer_wavenumbers(wn, h, modes)
    kb = _schaffer_wavenumbers(wm, h, modes)
    kb = kb if sign > 0 else -np.conj(kb)
    cn, cb = c_j(wn, kn), c_j(wb, kb)
    m1 = 0.0 if piston else (1 / (h + l_below)) * (g / om**2) * (np.cosh(big_k * d) / np.cosh(big_k * h) - 1)

    def m2(w, k):                                                    # Eq. (36b)
        if piston:
            return 0.0
        ch = np.cosh(k * d) * np.cosh(big_k * d) / (np.cosh(k * h) * np.cosh(big_k * h))
        sh = np.sinh(k * d) * np.sinh(big_k * d) / (np.cosh(k * h) * np.cosh(big_k * h))
        bracket = 2 * k * big_k * (1 - ch) - (k * k + big_k**2) * (w * w * om * om / (g * g * k * big_k) - sh)
        return -(g / (h + l_below)) * (big_k / k) / (k * k - big_k**2) * bracket

    delta = 0.5 if (sign > 0 and wn == wm) else 1.0                  # Eq. (25b)
    e = delta * big_k**2 * h / (cn[0] * cb[0] * om**3 * (1 + m1))    # Eq. (41b)
    s1 = np.sum(cn * kn**2 / (kn**2 - big_k**2) * (wn**2 - om**2 + m2(wn, kn)))
    s2 = np.sum(cb * kb**2 / (kb**2 - big_k**2) * (wb**2 - om**2 + m2(wb, kb)))
    p = kn[:, None] + kb[None, :]
    hh = (om * (wn * wb - g * g * kn[:, None] * kb[None, :] / (wn * wb)) + (wn**3 + wb**3) / 2
          - (g * g / 2) * (kn[:, None] ** 2 / wn + kb[None, :] ** 2 / wb))  # Eq. (25d)
    s3 = np.sum(cn[:, None] * cb[None, :] * p / (p * p - big_k**2) * hh)
    return e * (-g / (2 * wn) * s1 - g / (2 * wb) * s2 + s3) / delta


@pytest.mark.parametrize("paddle,hinge", [("piston", 0.0), ("flap", 0.0), ("flap", 0.2), ("flap", -0.3)])
def test_the_transfer_functions_are_schaffers(paddle, hinge):
    """G+-_nm = -i F+-_nm / (2 d), F+- Schäffer's (1996) Eq. (41a), for a piston and flaps hinged at, above and
    below the bed, sums and differences, pairs from 0.7 s to 2 s in 0.5 m. Both series are cut at J = 800
    evanescent modes and extrapolated once (Schäffer's here as 2 F(J) - F(J/2)): they agree within 1e-7
    (measured: from 2e-10 to 4e-8 at J = 800, at most 3e-8 at J = 1600)."""
    depth = 0.5
    l_below = math.inf if paddle == "piston" else -hinge
    for tn, tm in ((1.0, 1.0), (1.0, 1.3), (0.7, 2.0)):
        wn, wm = 2 * math.pi / tn, 2 * math.pi / tm
        plus, minus = paddle_transfer(wn, wm, depth, paddle, hinge, evanescent_modes=800)
        f = 2 * schaffer_f(wn, wm, depth, l_below, 800, 1) - schaffer_f(wn, wm, depth, l_below, 400, 1)
        assert abs(complex(plus) / (-1j * f / (2 * depth)) - 1) < 1e-7
        if tn != tm:
            f = 2 * schaffer_f(wn, wm, depth, l_below, 800, -1) - schaffer_f(wn, wm, depth, l_below, 400, -1)
            assert abs(complex(minus) / (-1j * f / (2 * depth)) - 1) < 1e-7


# --- the signals --------------------------------------------------------------------------------------------

def grid_components(depth=0.5, count=5, phases=(0.3, -1.2, 2.0, 0.7, -0.4)):
    f, df = frequency_grid(0.6, 1.4, count)
    w = 2 * math.pi * f
    return WaveComponents(f, np.linspace(0.01, 0.02, count), np.array(phases[:count]), wavenumbers(w, depth), depth, df)


@pytest.mark.parametrize("paddle,hinge", [("piston", 0.0), ("flap", 0.15)])
def test_the_signal_is_the_double_sum_of_the_transfer_functions(paddle, hinge):
    """X2(t) of `second_order_paddle` (pairs grouped by frequency) and eta2 of `bound_waves` are the double sums
    of the module docstring over the transfer functions, to round-off."""
    waves = grid_components()
    x2 = second_order_paddle(waves, paddle, hinge, evanescent_modes=32)
    t = np.linspace(0.0, 7.0, 23)
    w, amp = waves.omegas, waves.amplitudes * np.exp(1j * waves.phases)
    gp, gm = paddle_transfer(w[:, None], w[None, :], waves.depth, paddle, hinge, evanescent_modes=32)
    expect = np.zeros_like(t)
    for n in range(len(w)):
        for m in range(len(w)):
            expect += np.real(gp[n, m] * amp[n] * amp[m] * np.exp(1j * (w[n] + w[m]) * t)
                              + gm[n, m] * amp[n] * np.conj(amp[m]) * np.exp(1j * (w[n] - w[m]) * t))
    scale = np.max(np.abs(expect))
    assert np.allclose(x2.displacement(t), expect, rtol=0, atol=1e-12 * scale)
    # grouped: each sum and difference frequency once, a multiple of 2 pi df
    assert len(np.unique(np.round(x2.omegas / (2 * math.pi * waves.df)))) == len(x2.omegas)
    assert x2.max_displacement >= np.max(np.abs(x2.displacement(np.linspace(0, 1 / waves.df, 500))))
    # bound waves
    k = waves.wavenumbers
    kp, km = bound_wave_transfer(w[:, None], k[:, None], w[None, :], k[None, :], waves.depth)
    km = np.where(np.eye(len(w), dtype=bool), 0.0, km)
    x = 1.3
    theta = w[:, None] * t[None, :] - k[:, None] * x + waves.phases[:, None]
    a = waves.amplitudes
    eta = sum(a[n] * a[m] * (kp[n, m] * np.cos(theta[n] + theta[m]) + km[n, m] * np.cos(theta[n] - theta[m]))
              for n in range(len(w)) for m in range(len(w)))
    assert np.allclose(bound_waves(waves).elevation(x, t), eta, rtol=0, atol=1e-13 * np.max(np.abs(eta)))


def test_velocity_and_acceleration_are_the_derivatives():
    x2 = second_order_paddle(grid_components(), evanescent_modes=16)
    t = np.linspace(0.5, 9.5, 31)
    h = 1e-4
    vel = (x2.displacement(t + h) - x2.displacement(t - h)) / (2 * h)
    acc = (x2.displacement(t + h) - 2 * x2.displacement(t) + x2.displacement(t - h)) / h**2
    wmax = np.max(x2.omegas)
    v, a = x2.velocity(t), x2.acceleration(t)
    assert np.allclose(vel, v, rtol=0, atol=(wmax * h) ** 2 * np.max(np.abs(v)))
    assert np.allclose(acc, a, rtol=0, atol=1e-4 * np.max(np.abs(a)))


def test_many_times_are_evaluated_in_chunks_alike():
    """2 million times (summed a chunk of 2^20 frequency-time elements at a time) give the direct sum."""
    x2 = second_order_paddle(grid_components(), evanescent_modes=8)
    assert len(x2.omegas) == 13              # 5 components on a grid: 9 sums, 4 differences
    t = np.linspace(0.0, 100.0, 2_001_000).reshape(1000, 2001)
    out = x2.velocity(t)
    assert out.shape == t.shape
    rows = [0, 517, 999]
    direct = np.real(np.sum((1j * x2.omegas * x2.coefficients)[:, None, None]
                            * np.exp(1j * x2.omegas[:, None, None] * t[None, rows]), axis=0))
    assert np.allclose(out[rows], direct, rtol=0, atol=1e-13 * np.max(np.abs(direct)))


def test_sub_and_superharmonic_parts():
    waves = grid_components(count=3)
    both = second_order_paddle(waves, evanescent_modes=8)
    sub = second_order_paddle(waves, superharmonic=False, evanescent_modes=8)
    sup = second_order_paddle(waves, subharmonic=False, evanescent_modes=8)
    none = second_order_paddle(waves, subharmonic=False, superharmonic=False, evanescent_modes=8)
    w = waves.omegas
    assert np.all(sub.omegas < w.max() - w.min() + 1e-9) and len(sub.omegas) == 2
    assert np.all(sup.omegas >= 2 * w.min() - 1e-9) and len(sup.omegas) == 5
    t = np.linspace(0, 5, 11)
    assert np.allclose(both.displacement(t), sub.displacement(t) + sup.displacement(t), rtol=0, atol=1e-15)
    assert len(none.omegas) == 0 and np.all(none.displacement(t) == 0)


def test_default_modes():
    assert default_modes(0.5) == 64
    assert default_modes(0.5, "flap", 0.0) == 64
    assert default_modes(0.5, "flap", -0.2) == 64
    assert default_modes(1.0, "flap", 0.5) == 128
    assert default_modes(1.0, "flap", 0.6) == 192
    assert second_order_paddle(grid_components(count=2), "flap", 0.25).evanescent_modes == 128
    assert second_order_paddle(grid_components(count=2), theory="madsen").evanescent_modes == 0


@pytest.mark.parametrize("kwargs,match", [
    (dict(paddle="wedge"), "paddle"),
    (dict(paddle="flap", hinge=0.5), "hinge"),
    (dict(paddle="piston", hinge=0.1), "hinge"),
    (dict(theory="stokes"), "theory"),
    (dict(evanescent_modes=-1), "evanescent_modes"),
    (dict(evanescent_modes=2.5), "evanescent_modes"),
    (dict(g=9.7), "wavenumbers"),
])
def test_refusals(kwargs, match):
    with pytest.raises(ValueError, match=match):
        second_order_paddle(grid_components(count=2), **kwargs)
