"""`shoal validate wall-impact` (issue 28, item 4): the ringing and first-peak measures on records whose answers
are known, and the quick run (the 2D dam break on a wall at H/dp = 60: ringing after 5 ms within 20 % of the
peak at z = 0.05, 0.25 and 0.5 a)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from shoal.validation.spheric_test2 import H0, RHO0
from shoal.validation.wall_impact import WallImpact, first_peak, ringing


def impact_record(amplitude, peak=5000.0, level=1000.0, t_hit=0.1, dt=2e-4, end=0.3, f=1000.0):
    """Dry, then a one-sample spike of `peak` at `t_hit`, then `level` with a cosine of `amplitude` at `f`
    Hz (5 samples a period at 0.2 ms: a 5 ms window holds whole periods, so the running mean is `level`)."""
    t = np.round(np.arange(0.0, end, dt), 10)
    p = np.where(t > t_hit, level + amplitude * np.cos(2 * math.pi * f * (t - t_hit)), 0.0)
    p[np.flatnonzero(np.isclose(t, t_hit))] = peak
    return t, p


@pytest.mark.parametrize("amplitude", [0.0, 400.0, 1500.0])
def test_ringing_is_the_oscillation_about_the_running_mean_over_the_peak(amplitude):
    t, p = impact_record(amplitude)
    r = ringing(t, p)
    assert r["t_contact"] == pytest.approx(0.1) and r["t_peak"] == pytest.approx(0.1) and r["peak"] == 5000.0
    assert r["ringing"] == pytest.approx(amplitude / 5000.0, abs=1e-9)
    assert r["min"] == pytest.approx(1000.0 + amplitude * math.cos(0.8 * math.pi))  # the lowest of 5 samples


def test_ringing_leaves_out_the_first_five_milliseconds():
    t, p = impact_record(100.0)
    p[(t > 0.1) & (t <= 0.102)] = -3000.0  # the hammer's rebound, out of the 5 ms means from 5 ms on
    r = ringing(t, p)
    assert r["ringing"] == pytest.approx(100.0 / 5000.0, abs=1e-9) and r["min"] == -3000.0


def test_a_dry_sensor_has_no_impact():
    t = np.arange(0.0, 0.1, 1e-3)
    assert all(math.isnan(v) for v in ringing(t, np.zeros_like(t)).values())


def bump(t, t0, p0, width=0.01):
    return p0 * np.exp(-0.5 * ((t - t0) / width) ** 2)


def test_first_peak_against_the_experiment():
    """A record 10 ms late and 20 % high against a smooth reference: both differences come back, averaged or
    not; a dip inside the quarter second after the measured impact is the lowest pressure, one after it is not."""
    t_ref = np.arange(0.0, 1.0, 1e-3)
    p_ref = bump(t_ref, 0.42, 10_000.0)
    t = np.arange(0.0, 0.9, 1e-3)
    p = bump(t, 0.43, 12_000.0)
    scale = RHO0 * 9.81 * H0
    p[np.argmin(abs(t - 0.6))] = -0.6 * scale
    p[np.argmin(abs(t - 0.8))] = -5.0 * scale
    m = first_peak(t, p, t_ref, p_ref)
    for label in ("smoothed", "raw"):
        assert m[label]["dt"] == pytest.approx(0.01, abs=1e-9)
        assert m[label]["rel"] == pytest.approx(0.2, rel=1e-3)
    assert m["min_after"] == pytest.approx(-0.6)
    p[np.argmin(abs(t - 0.6))] = np.nan  # a dry sample reads 0
    assert first_peak(t, p, t_ref, p_ref)["min_after"] == pytest.approx(0.0, abs=1e-9)


def test_quick_wall_impact(tmp_path):
    """`shoal validate wall-impact --quick` passes: the 2D surge's pressure at the bottom of the far wall rings by at
    most 20 % of its peak after 5 ms, unfiltered (issue 28, item 4; measured 16.3 % on two machines whose
    round-off differs); the two sensors higher up are reported, not judged (one core: about 50 s)."""
    case = WallImpact()
    res = case.run(quick=True, backend="cpu", out=tmp_path)
    figures, passed = case.compare(res)
    assert passed, [(m.name, m.value, m.note) for m in res.metrics]
    assert [m.name.split(":")[0] for m in res.metrics] == [f"2D wall, z = {f:g} a" for f in (0.05, 0.25, 0.5)]
    assert [m.passed for m in res.metrics] == [True, None, None]
    assert figures and figures[0].exists()
    two = res.data["two"]
    assert np.median(np.diff(two["t"])) == pytest.approx(2e-4)
    # the surge reached every sensor, and the lowest one first
    contact = [ringing(two["t"], two["p"][f])["t_contact"] for f in (0.05, 0.25, 0.5)]
    assert all(math.isfinite(c) for c in contact) and contact == sorted(contact)
