"""Incident and reflected irregular waves separated from a line of gauges (`shoal.analysis.reflection`),
on synthetic records of exact linear theory: an incident Gaussian sea and a reflected one of known
reflection coefficient and arbitrary phase at every frequency."""

import numpy as np
import pytest

from shoal.analysis import irregular_reflection
from shoal.errors import InputError

D, G = 0.5, 9.81


def k_of(f):
    """Linear dispersion omega^2 = g k tanh(k d), solved independently of the module (bisection)."""
    from scipy.optimize import brentq

    return np.array([brentq(lambda k: G * k * np.tanh(k * D) - (2 * np.pi * x) ** 2, 1e-9, 1e4) for x in f])


def flume(xs, kr=0.3, n=2 ** 13, dt=0.05, noise=0.0, seed=0):
    """Records at xs [m] of an incident Gaussian sea (Gaussian spectrum, fp 1 Hz, sigma 0.15 Hz) and a
    reflected one kr times its amplitude at every frequency with a random phase, each component on a bin
    of the n-sample window; `noise`: white noise of that fraction of each record's standard deviation.
    Returns t, {x: eta}, f, A_I(f) at x = 0, A_R(f) at x = 0."""
    rng = np.random.default_rng(seed)
    f = np.fft.rfftfreq(n, dt)
    S = np.exp(-0.5 * ((f - 1.0) / 0.15) ** 2)
    AI = np.sqrt(S * f[1]) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) * 0.01
    AR = kr * np.abs(AI) * np.exp(2j * np.pi * rng.random(f.size))
    AI[[0, -1]] = AR[[0, -1]] = 0
    k = np.concatenate([[0.0], k_of(f[1:])])
    records = {}
    for x in xs:
        eta = np.fft.irfft((AI * np.exp(-1j * k * x) + AR * np.exp(1j * k * x)) * n / 2, n)
        records[x] = D + eta + noise * np.std(eta) * rng.standard_normal(n)
    return np.arange(n) * dt, records, f, AI, AR


def test_three_gauges_recover_the_exact_spectra():
    """Mansard & Funke on noise-free linear waves: every usable bin's incident and reflected amplitude,
    hence K_r = 0.3, exact to rounding (measured: 1e-14); the residual of the fit vanishes."""
    xs = (2.0, 2.15, 2.4)
    t, rec, f, AI, AR = flume(xs)
    r = irregular_reflection(t, rec, D, f_min=0.5, f_max=2.0, x_ref=0.0)
    band = (f >= 0.5) & (f <= 2.0)
    assert np.allclose(r.f, f[band], rtol=1e-12)
    u = r.usable
    assert u.sum() > 0.9 * u.size
    assert np.allclose(r.incident[u], AI[band][u], rtol=0, atol=1e-9 * np.abs(AI).max())
    assert np.allclose(r.reflected[u], AR[band][u], rtol=0, atol=1e-9 * np.abs(AI).max())
    assert r.reflection_coefficient == pytest.approx(0.3, abs=1e-6)
    assert r.residual < 1e-9
    assert r.m0_incident == pytest.approx(np.sum(np.abs(AI[band][u]) ** 2) / 2, rel=1e-9)
    assert r.Hm0_reflected == pytest.approx(0.3 * r.Hm0_incident, rel=1e-6)
    assert np.all(r.S_incident[~u] == 0) and np.all(np.isnan(r.incident[~u]))
    # at the first gauge (the default x_ref) the amplitudes carry the phase k x
    r1 = irregular_reflection(t, rec, D, f_min=0.5, f_max=2.0)
    k = k_of(r1.f[u])
    assert r1.x_ref == 2.0
    assert np.allclose(r1.incident[u], AI[band][u] * np.exp(-1j * k * 2.0), atol=1e-9 * np.abs(AI).max())
    assert r1.reflection_coefficient == pytest.approx(0.3, abs=1e-6)


def test_two_gauges_use_the_goda_suzuki_band():
    """Two gauges 0.3 m apart: a bin is used exactly where the spacing lies between 0.1 and 0.4
    wavelengths (or that range shifted by half wavelengths), and there the separation is exact."""
    xs = (1.0, 1.3)
    t, rec, f, AI, AR = flume(xs, kr=0.5)
    r = irregular_reflection(t, rec, D)
    ratio = (0.3 * k_of(r.f) / (2 * np.pi)) % 0.5
    assert np.array_equal(r.usable, (ratio >= 0.1 - 1e-12) & (ratio <= 0.4 + 1e-12))
    assert np.allclose(r.separability, np.sin(0.3 * k_of(r.f)) ** 2)
    assert r.reflection_coefficient == pytest.approx(0.5, abs=1e-6)
    lo, hi = r.band
    assert lo == pytest.approx(r.f[r.usable][0]) and 0.5 < lo < 0.7 and hi > 1.5


def test_white_noise_of_one_percent_moves_kr_by_little():
    """1 % white noise at each gauge (variance 1e-4 of the record's) spread to 10 Hz: 15 % of it falls
    in the band 0.5 to 2 Hz, and the least squares pass at most 1 / (n s) <= 1 / (3 x 0.345) of it into
    each wave, adding at most 1.5e-5 m0 to m0_R = 0.09 m0 (and as much to m0_I): K_r moves by less
    than 1e-4 relative (measured: 9e-5). The tolerance, 1e-3 of K_r, leaves a factor of 10."""
    t, rec, f, AI, AR = flume((2.0, 2.15, 2.4), noise=0.01, seed=3)
    r = irregular_reflection(t, rec, D, f_min=0.5, f_max=2.0)
    assert r.reflection_coefficient == pytest.approx(0.3, rel=1e-3)
    assert r.residual > 1e-4  # noise makes three gauges disagree


def test_bad_arrays_and_records_are_refused_in_one_line():
    t, rec, *_ = flume((2.0, 2.15, 2.4), n=1024)
    cases = [
        (lambda: irregular_reflection(t, {2.0: rec[2.0]}, D), "at least 2 gauges"),
        (lambda: irregular_reflection(t, {2.0: rec[2.0], "2": rec[2.15]}, D), "same x"),
        (lambda: irregular_reflection(t, {2.0: rec[2.0], 2.001: rec[2.15]}, D, f_max=2.0), "no frequency"),
        (lambda: irregular_reflection(t, {2.0: rec[2.0], 2.15: np.where(t > 5, np.nan, rec[2.15])}, D), "non-finite"),
        (lambda: irregular_reflection(t[::-1], rec, D), "increase strictly"),
        (lambda: irregular_reflection(t, {2.0: rec[2.0], 2.15: rec[2.15][:-1]}, D), "one length"),
        (lambda: irregular_reflection(t, rec, 0.0), "depth"),
        (lambda: irregular_reflection(t, rec, D, f_min=20.0), "no frequency bin"),
    ]
    for call, message in cases:
        with pytest.raises(InputError, match=message) as excinfo:
            call()
        assert "\n" not in str(excinfo.value), message
