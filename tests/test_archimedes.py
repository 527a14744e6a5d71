"""The Archimedes validation case (issue 32, must-show 1; `shoal.validation.archimedes`,
``shoal validate archimedes``): its metrics on synthetic records, exactly, its case, and its quick run
(``-m validation``). The suite's quick 2D run of the same box is `tests/test_floating.py::test_archimedes_2d`."""

from __future__ import annotations

import numpy as np
import pytest

from shoal.validation.archimedes import (DRAFT_TOLERANCE, DRIFT_TOLERANCE, TILT_TOLERANCE, Archimedes,
                                         archimedes_case, equilibrium_level, gauge_level, settled_metrics)


def test_equilibrium_level_is_the_fluid_volume_plus_the_displacement():
    # 2D, the box of tests/test_floating.py: 1120 fluid particles at dp = 0.02 m, M = 40 kg/m, tank 1.2 m long
    assert equilibrium_level(1120, 0.02, 2, 40.0, 1.2) == pytest.approx((1120 * 4e-4 + 0.04) / 1.2, rel=1e-15)
    assert equilibrium_level(1120, 0.02, 2, 40.0, 1.2) == pytest.approx(0.4066666666666667, rel=1e-15)
    # 3D: 1000 particles of 1 cm^3, a body of 0.5 kg displacing 0.5 l, 0.1 m x 0.1 m tank
    assert equilibrium_level(1000, 0.01, 3, 0.5, 0.01, rho0=1000.0) == pytest.approx(0.15, rel=1e-14)


def _record(level=0.4, height=0.2, dp=0.02, bias=0.003, swing=0.01, tilt=0.3, drift=(0.0012, -0.0016)):
    """10 s at 0.01 s: a heave `swing` (whole periods, 1 Hz) that stops at t = 6 s, then the centre at
    level + bias; roll and pitch reaching -tilt and tilt / 2; the centre moved by `drift` (x, y) at t = 5 s
    and back."""
    t = np.round(np.arange(0, 1001) * 0.01, 10)
    z = level + bias + np.where(t < 6.0, swing * np.sin(2 * np.pi * t), 0.0)
    roll = -tilt * np.sin(np.pi * t / 10)
    pitch = 0.5 * tilt * np.sin(np.pi * t / 10) ** 2
    bump = np.exp(-((t - 5.0) / 0.5) ** 2)
    x, y = 0.6 + drift[0] * bump, 0.3 + drift[1] * bump
    return t, x, y, z, roll, pitch


def test_settled_metrics_on_a_synthetic_record():
    t, x, y, z, roll, pitch = _record()
    m = settled_metrics(t, x, y, z, roll, pitch, level=0.4, height=0.2, dp=0.02, window=4.0)
    assert m["mean_z"] == pytest.approx(0.403, abs=1e-15)
    assert m["draft_error"] == pytest.approx(0.003 / 0.2, rel=1e-12)  # the swing ended before the window
    assert m["roll"] == pytest.approx(0.3, rel=1e-12) and m["pitch"] == pytest.approx(0.15, rel=1e-12)
    assert m["tilt"] == m["roll"]
    assert m["drift"] == pytest.approx(np.hypot(0.0012, 0.0016) / 0.02, rel=1e-12)  # 0.1 dp, at t = 5 s
    assert m["heave_range"] == 0.0
    # a window reaching into the swing: its whole periods average out, its range shows
    m = settled_metrics(t, x, y, z, roll, pitch, level=0.4, height=0.2, dp=0.02, window=6.0)
    assert m["draft_error"] == pytest.approx(0.015, abs=1e-12)
    assert m["heave_range"] == pytest.approx(0.02 / 0.2, rel=1e-3)
    # the drift counts from the first row
    m = settled_metrics(t, x + 0.01, y, z, roll, pitch, level=0.4, height=0.2, dp=0.02, window=4.0)
    assert m["drift"] == pytest.approx(np.hypot(0.0012, 0.0016) / 0.02, rel=1e-9)


def test_gauge_level_adds_half_a_spacing():
    t = np.round(np.arange(0, 101) * 0.01, 10)
    zmax = np.where(t < 0.5, 0.5, 0.39 + 0.002 * np.cos(2 * np.pi * 10 * t))
    assert gauge_level(t, zmax, 0.02, 0.5) == pytest.approx(0.40 + 0.002 / 51, rel=1e-12)


def _result(tmp_path, bias_2d=0.003, tilt=0.3, drift=(0.0012, -0.0016)):
    case = Archimedes()
    res = case.new_result(True, "cpu", tmp_path)
    runs = []
    for label, dim, dp, height in (("2D", 2, 0.02, 0.2), ("3D", 3, 0.025, 0.1)):
        t, x, y, z, roll, pitch = _record(level=0.4, height=height, dp=dp,
                                          bias=bias_2d if dim == 2 else 0.0005, tilt=tilt, drift=drift)
        runs.append(dict(label=label, dim=dim, dp=dp, height=height, level=0.4, window=4.0, end_time=10.0,
                         t=t.tolist(), x=x.tolist(), y=y.tolist(), z=z.tolist(), roll=roll.tolist(),
                         pitch=pitch.tolist(), gauge_t=t.tolist(), gauge_z=np.full(t.size, 0.39).tolist(),
                         sph_volume=0.9986, steps=100, seconds=1.0, n_fluid=1))
    res.data = dict(runs=runs)
    return case, res


@pytest.mark.parametrize("bias_2d, tilt, drift, passed", [
    (0.003, 0.3, (0.0012, -0.0016), True),  # 1.5 % of H, 0.3 deg, 0.1 dp
    (0.0041, 0.3, (0.0, 0.0), False),  # 2.05 % of H
    (0.003, 1.01, (0.0, 0.0), False),  # 1.01 deg
    (0.003, 0.3, (0.0013, -0.0016), False),  # 0.103 dp in 2D
])
def test_comparison_on_synthetic_records(tmp_path, bias_2d, tilt, drift, passed):
    case, res = _result(tmp_path, bias_2d, tilt, drift)
    figs, ok = case.compare(res)
    assert ok is passed
    assert figs[0].exists()
    judged = [m for m in res.metrics if m.tolerance is not None]
    assert [m.tolerance for m in judged] == [DRAFT_TOLERANCE, TILT_TOLERANCE, DRIFT_TOLERANCE] * 2
    draft2, tilt2, drift2 = (m.value for m in judged[:3])
    assert draft2 == pytest.approx(bias_2d / 0.2, rel=1e-9)
    assert tilt2 == pytest.approx(tilt, rel=1e-12) and drift2 == pytest.approx(np.hypot(*drift) / 0.02, rel=1e-9)
    assert judged[3].value == pytest.approx(0.0005 / 0.1, rel=1e-9)
    info = [m for m in res.metrics if m.tolerance is None and "water level" in m.name]
    # the gauges' 0.39 m + dp/2 against 0.4 m: 0 in 2D; 3D 0.0025 m of H = 0.1 m
    assert [m.value for m in info] == pytest.approx([0.0, 0.025], abs=1e-12)


def test_the_cases_are_the_box_released_one_spacing_above_its_draft():
    """2D: the box of tests/test_floating.py (0.4 x 0.2 m, density 500, tank 1.2 m, water 0.4 m), its bottom
    at 0.32 m; 3D: B x B x H with B/H = 2 in the middle of a square tank; max-z gauges halfway to the walls."""
    c2 = archimedes_case(dim=2, dp=0.02)
    box = c2.solids[1].shape
    assert box.lo == pytest.approx((0.4, 0.0, 0.32)) and box.hi == pytest.approx((0.8, 0.0, 0.52))
    assert c2.solids[1].floating.density == 500.0 and not c2.solids[1].floating.fixed
    assert [c for g in c2.probes for c in (g.x, g.y)] == pytest.approx([0.2, 0.0, 1.0, 0.0])
    quick3d = Archimedes().params(True)[1]["case"]
    assert quick3d["dim"] == 3 and quick3d["beam"] == 2 * quick3d["height"] and quick3d["offset"] == 0.0
    full3d = Archimedes().params(False)[1]["case"]
    assert full3d["dim"] == 3 and full3d["beam"] == 2 * full3d["height"] and "offset" not in full3d
    for kw, offset in ((quick3d, 0.0), (full3d, full3d["dp"])):
        c3 = archimedes_case(**kw)
        box = c3.solids[1].shape
        half, L = kw["beam"] / 2, kw["length"]
        assert box.lo == pytest.approx((L / 2 - half, L / 2 - half, kw["depth"] - kw["height"] / 2 + offset))
        assert box.hi[2] - box.lo[2] == pytest.approx(kw["height"]) and len(c3.probes) == 4
    for quick in (True, False):
        assert [p["label"] for p in Archimedes().params(quick)] == ["2D", "3D"]
    assert [p["label"] for p in Archimedes(only=["2D"]).params(False)] == ["2D"]
    assert all(p["case"]["end_time"] == 10.0 for p in Archimedes().params(False))


@pytest.mark.validation
def test_quick_archimedes_run(tmp_path):
    """``shoal validate archimedes --quick`` (issue 32, must-show 1): the 2D box (H = 10 dp) released 1 dp above
    its draft, 3 s: its mean height over the last second within 2 % of H of Archimedes' level (measured +1.11 %),
    tilt below 1 degree (1.1e-4), drift below dp/10 (2.8e-4 dp); the 3D box (B x B x H = 0.2 x 0.2 x 0.1 m,
    H = 4 dp) released at its draft, 0.8 s: its height within 5 % of H (+3.61 %; the coarse box's waterline
    error), tilt 4.3e-5 degree, drift 3.7e-6 dp. 4.4 minutes on one core."""
    case = Archimedes()
    res = case.run(True, "cpu", tmp_path)
    figs, passed = case.compare(res)
    print([(m.name, m.value) for m in res.metrics], res.notes)
    assert figs and figs[0].exists()
    assert passed, [(m.name, m.value) for m in res.metrics if m.passed is False]
