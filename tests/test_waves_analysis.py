"""Zero up-crossing wave statistics and phase speed (`shoal.analysis.waves`) on synthetic gauge records
whose heights, periods and speeds are known exactly."""

import math

import numpy as np
import pytest

from shoal.analysis.waves import phase_speed, wave_statistics
from shoal.errors import InputError

H, T, C = 0.05, 1.2, 1.6
W = 2 * math.pi / T


def _record(x, dt=T / 40, t_end=12.0, level=0.4, harmonic=0.0, phase=0.3):
    t = np.arange(0.0, t_end, dt)
    th = W * (t - x / C) + phase
    return t, level + 0.5 * H * np.sin(th) + harmonic * H * np.cos(2 * th)


def test_sine_sampled_forty_times_a_period():
    t, eta = _record(0.0)
    s = wave_statistics(t, eta, 2.0, 10.0)
    # the sampled extremes miss the true ones by at most (H/2)(1 - cos(pi/40)) each: 0.3 % of H
    assert s.height == pytest.approx(H, rel=3.1e-3) and s.height <= H
    assert s.period == pytest.approx(T, rel=1e-3)  # crossings interpolated linearly: 1e-3 T or better
    assert s.waves == 6 and s.mean_level == pytest.approx(0.4, abs=H / 20)


def test_second_harmonic_changes_the_height_as_crest_minus_trough():
    t, eta = _record(0.0, dt=T / 400, harmonic=0.1)
    s = wave_statistics(t, eta, 2.0, 10.0)
    th = np.linspace(0, 2 * np.pi, 100001)
    f = 0.5 * np.sin(th) + 0.1 * np.cos(2 * th)
    assert s.height == pytest.approx(H * (f.max() - f.min()), rel=1e-4)
    assert s.period == pytest.approx(T, rel=1e-4)


def test_phase_speed_from_the_lag_between_two_gauges():
    t, a = _record(1.0)
    _, b = _record(2.0)
    assert phase_speed(t, a, b, 1.0, 3.0, 9.0) == pytest.approx(C, rel=2e-3)


def test_a_window_without_a_whole_wave_is_refused():
    t, eta = _record(0.0)
    with pytest.raises(InputError, match="no whole wave"):
        wave_statistics(t, eta, 2.0, 2.0 + 0.9 * T)
    with pytest.raises(InputError, match="fewer than 8 samples"):
        wave_statistics(t, eta, 20.0, 30.0)


def _flume_records(HI, HR, delta, xs, T=1.2, d=0.4, second=0.0, noise=0.0, seed=0):
    """Linear incident (+x) and reflected (-x) waves decaying as exp(-delta * travel), plus a bound second
    harmonic and white noise: the synthetic record of a flume's gauges."""
    from shoal.motions import wavenumber

    k = wavenumber(T, d)
    w = 2 * np.pi / T
    t = np.arange(0.0, 12 * T, T / 40)
    rng = np.random.default_rng(seed)
    rec = {}
    for x in xs:
        th_i = w * t - k * x
        eta = (0.5 * HI * np.exp(-delta * x) * np.cos(th_i) + 0.5 * HR * np.exp(delta * x) * np.cos(w * t + k * x + 0.7)
               + second * np.cos(2 * th_i) + noise * rng.standard_normal(t.size))
        rec[float(x)] = eta
    return t, rec


def test_reflection_analysis_recovers_incident_reflected_and_decay():
    """Mansard & Funke separation on a synthetic record with known answers: H_I = 0.05 m, K_r = 0.1,
    decay 0.01 1/m, a 7 % second harmonic (Stokes, kd = 1.3) and white noise of 2 % of H. Over 60 noise
    seeds the estimates scatter (one standard deviation) by 0.14 % for H_I mid-array (x = 2 m), 0.34 %
    for H_I extrapolated to x = 0, 1.3e-3 for K_r and 1.4e-3 1/m for the decay: the tolerances are
    about 3.5 of those (without noise all four are exact to 1.5e-5, relative)."""
    from shoal.analysis import reflection_analysis

    xs = [1.0, 1.3, 1.75, 2.0, 2.6, 3.1]
    t, rec = _flume_records(0.05, 0.005, 0.01, xs, second=0.0035, noise=0.001)
    r = reflection_analysis(t, rec, 1.2, 0.4, 1.2, 13.2, fit_decay=True, x_ref=0.0)
    assert r.incident_height == pytest.approx(0.05, rel=1.2e-2)
    assert r.incident_height_at(2.0) == pytest.approx(0.05 * np.exp(-0.02), rel=5e-3)
    assert r.reflection_coefficient == pytest.approx(0.1, abs=5e-3)
    assert r.decay == pytest.approx(0.01, abs=5e-3)
    # without the decay the fit is the mean incident height over the array, and it leaves a misfit
    r0 = reflection_analysis(t, rec, 1.2, 0.4, 1.2, 13.2, x_ref=0.0)
    assert r0.decay == 0.0 and r0.residual > r.residual


def test_reflection_analysis_two_gauges_and_bad_spacing():
    """Goda & Suzuki's two-gauge case is exact without noise; gauges spaced by L/2 cannot separate."""
    from shoal.analysis import reflection_analysis
    from shoal.errors import InputError
    from shoal.motions import wavenumber

    t, rec = _flume_records(0.04, 0.012, 0.0, [2.0, 2.4])
    r = reflection_analysis(t, rec, 1.2, 0.4, 0.0, 12 * 1.2 - 1e-9)
    assert r.incident_height == pytest.approx(0.04, rel=1e-6)
    assert r.reflection_coefficient == pytest.approx(0.3, rel=1e-5)
    half = np.pi / wavenumber(1.2, 0.4)
    t, rec = _flume_records(0.04, 0.012, 0.0, [2.0, 2.0 + half])
    with pytest.raises(InputError, match="half a wavelength"):
        reflection_analysis(t, rec, 1.2, 0.4, 0.0, 14.0)
    with pytest.raises(InputError, match="at least 3 gauges"):
        reflection_analysis(t, rec, 1.2, 0.4, 0.0, 14.0, fit_decay=True)
