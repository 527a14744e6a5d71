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
