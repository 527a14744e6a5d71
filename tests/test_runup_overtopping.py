"""Run-up exceedance and overtopping discharge (`shoal.analysis.runup`) on records whose answers are
known: run-up events of Rayleigh-distributed peaks, and cumulative volumes of known discharge."""

import numpy as np
import pytest

from shoal.analysis import overtopping, runup_statistics
from shoal.errors import InputError


def runup_record(peaks, setup=0.02, swl=0.5, per_event=40, period=8.0):
    """A shoreline record of one sine cycle per event, amplitude = that event's peak above the set-up,
    sampled per_event times a cycle (the crest on a sample), with a sample before the first cycle and
    one after the last so that every cycle starts at an up-crossing."""
    s = np.arange(-1, per_event * len(peaks) + 1)
    amp = np.asarray(peaks)[np.clip(s // per_event, 0, len(peaks) - 1)]
    return s * period / per_event, swl + setup + amp * np.sin(2 * np.pi * s / per_event)


def test_r2_of_rayleigh_peaks():
    """20,000 events whose peaks above the set-up are Rayleigh of scale sigma: P(R > r) =
    exp(-r^2 / (2 sigma^2)), R2% = sigma sqrt(2 ln 50) = 2.797 sigma. Each event's peak is found
    exactly; the empirical 98 % quantile of 20,000 scatters by sqrt(0.02 x 0.98 / 20000) / pdf(R2%) =
    0.63 % of R2% (pdf = 0.02 x 2.797 / sigma); the tolerance is four of those."""
    sigma, setup, swl = 0.05, 0.02, 0.5
    peaks = np.random.default_rng(1).rayleigh(sigma, 20000)
    t, z = runup_record(peaks, setup, swl)
    r = runup_statistics(t, z, still_water_level=swl)
    assert r.events == 20000
    assert np.allclose(r.peaks, peaks + setup, rtol=0, atol=1e-12)
    assert r.setup == pytest.approx(setup, abs=1e-7)  # the two samples outside the cycles shift the mean
    assert r.R2 == pytest.approx(np.quantile(peaks, 0.98) + setup, abs=1e-12)
    assert r.R2 - setup == pytest.approx(sigma * np.sqrt(2 * np.log(50)), rel=4 * 0.0063)
    assert r.exceedance(0.5) == pytest.approx(np.median(peaks) + setup, abs=1e-12)
    assert r.Rmax == pytest.approx(peaks.max() + setup, abs=1e-12)
    assert r.Rmean == pytest.approx(peaks.mean() + setup, abs=1e-12)
    assert np.allclose(r.times, (np.arange(20000) + 0.25) * 8.0)


def test_runup_refusals_in_one_line():
    t, z = runup_record(np.full(30, 0.05))
    cases = [
        (lambda: runup_statistics(t, z).R2, "at least 50 events"),
        (lambda: runup_statistics(t, z).exceedance(1.5), r"in \(0, 1\)"),
        (lambda: runup_statistics(t, np.where(t > 20, np.nan, z)), "non-finite"),
        (lambda: runup_statistics(t[::-1], z), "increase strictly"),
        (lambda: runup_statistics(t, z, t0=0.0, t1=6.0), "no whole run-up event"),
    ]
    for call, message in cases:
        with pytest.raises(InputError, match=message) as excinfo:
            call()
        assert "\n" not in str(excinfo.value), message
    assert runup_statistics(t, z).events == 30


def test_overtopping_discharge_and_volume_per_metre():
    """A steady discharge q passing in particle volumes dp^2 (2D, per metre): the counted volume is a
    staircase below q t by less than dp^2, so the mean discharge over [t0, t1] is q within
    dp^2 / (t1 - t0); a 3D section b wide gives the volume per metre."""
    q, dp = 0.004, 0.01
    t = np.arange(0.0, 100.0, 0.05)
    stair = dp ** 2 * np.floor(q * t / dp ** 2)
    o = overtopping(t, stair, t0=20.0, t1=80.0)
    assert o.discharge == pytest.approx(q, abs=dp ** 2 / 60.0)
    assert o.volume == pytest.approx(q * 60.0, abs=dp ** 2)
    o = overtopping(t, q * t * 0.5, width=0.5)  # 3D: m^3 through a section 0.5 m wide
    assert o.discharge == pytest.approx(q, rel=1e-12) and (o.t0, o.t1) == (0.0, t[-1])
    o = overtopping(t, q * t, t0=10.025, t1=10.075)  # between samples: V interpolated linearly
    assert o.volume == pytest.approx(q * 0.05, rel=1e-9)


def test_overtopping_refusals_in_one_line():
    t = np.arange(0.0, 10.0, 0.1)
    v = 0.01 * t
    cases = [
        (lambda: overtopping(t, v, t0=5.0, t1=5.0), "non-empty"),
        (lambda: overtopping(t, v, t0=-1.0), "within the record"),
        (lambda: overtopping(t, v, width=0.0), "width"),
        (lambda: overtopping(t[::-1], v), "increase strictly"),
        (lambda: overtopping(t, np.where(t > 5, np.nan, v)), "non-finite"),
    ]
    for call, message in cases:
        with pytest.raises(InputError, match=message) as excinfo:
            call()
        assert "\n" not in str(excinfo.value), message
