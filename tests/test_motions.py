"""Prescribed motions: wavemaker theory and rigid motion of moving walls in a run."""

import math

import numpy as np
import pytest

from shoal.case import Case, Fluid, FluidRegion, Solid
from shoal.geometry.shapes import Box, Tank
from shoal.motions import ConstantVelocity, PistonWavemaker, piston_height_to_stroke, wavenumber
from shoal.runner import build_model
from shoal.simulation import Simulation


@pytest.mark.parametrize("period,depth", [(1.0, 0.5), (1.5, 0.517), (3.0, 0.2), (0.6, 2.0)])
def test_wavenumber_solves_the_dispersion_relation(period, depth):
    k = wavenumber(period, depth)
    omega = 2 * math.pi / period
    assert omega**2 == pytest.approx(9.81 * k * math.tanh(k * depth), rel=1e-12)


def test_biesel_limits():
    """Shallow water: H/S -> kd (Galvin's 'volume displaced' result);
    deep water: H/S -> 2 (Dean & Dalrymple 1991, Fig. 6.4)."""
    for kd in (1e-3, 1e-2):
        assert piston_height_to_stroke(kd, 1.0) == pytest.approx(kd, rel=1e-4)
    assert piston_height_to_stroke(20.0, 1.0) == pytest.approx(2.0, rel=1e-9)
    # the same function written as 4 sinh^2(kd) / (sinh 2kd + 2kd)
    for kd in (0.3, 1.0, 2.5):
        assert piston_height_to_stroke(kd, 1.0) == pytest.approx(
            4 * math.sinh(kd) ** 2 / (math.sinh(2 * kd) + 2 * kd), rel=1e-12)


def test_piston_kinematics():
    p = PistonWavemaker(name="p", height=0.1, period=1.2, depth=0.4, ramp_periods=2.0)
    k = wavenumber(1.2, 0.4)
    assert p.stroke == pytest.approx(0.1 / piston_height_to_stroke(k, 0.4))
    # velocity is the time derivative of displacement (ramp included)
    for t in (0.1, 0.9, 2.3, 2.4, 5.0):
        e = 1e-6
        d = (p.kinematics(t + e)[0] - p.kinematics(t - e)[0]) / (2 * e)
        np.testing.assert_allclose(p.kinematics(t)[1], d, atol=1e-6)
    # after the ramp the amplitude is S/2
    ts = np.linspace(3 * 1.2, 5 * 1.2, 2001)
    x = np.array([p.kinematics(t)[0][0] for t in ts])
    assert x.max() == pytest.approx(p.stroke / 2, rel=1e-4)
    assert p.kinematics(0.0)[0][0] == 0.0 and p.kinematics(0.0)[1][0] == 0.0


@pytest.mark.parametrize("integrator", ["symplectic", "verlet", "predictor_corrector"])
def test_moving_wall_moves_rigidly_with_its_motion(integrator):
    u = -0.3
    case = Case(name="wall", dim=2, dp=0.02, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"integrator": integrator},
                solids=[Solid(name="wall", shape=Box(lo=(0.6, 0, 0), hi=(0.66, 0, 0.2)), motion="push"),
                        Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(0.66, 0, 0.2), open=["top", "xmax"]))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.6, 0, 0.1)), velocity=(u, 0, 0))],
                motions=[ConstantVelocity(name="push", velocity=(u, 0, 0))])
    model = build_model(case)
    p0 = case.particles()
    sim = Simulation(model, end_time=0.05).run()
    assert sim.time == pytest.approx(0.05)
    ids = model.host(model.idp)
    pos = model.world_positions()
    vel = model.world_velocities()
    moving = p0.kinds[ids] == 2
    assert moving.sum() == np.count_nonzero(p0.kinds == 2) > 0
    expect = p0.positions[ids[moving]] + [u * sim.time, 0, 0]
    np.testing.assert_allclose(pos[moving], expect, atol=1e-12)
    np.testing.assert_allclose(vel[moving], [[u, 0, 0]] * int(moving.sum()), rtol=1e-6)
    fixed = p0.kinds[ids] == 1
    np.testing.assert_array_equal(pos[fixed], p0.positions[ids[fixed]])
    assert model.n_escaped == 0


@pytest.mark.parametrize("H,d", [(0.05, 0.4), (0.1, 0.25)])
def test_solitary_piston_stroke_is_gorings(H, d):
    """Goring (1978): the paddle travels S = 2 H / (k d) = sqrt(16 H d / 3) in total, and its
    speed peaks at c H / (d + H) as the crest passes."""
    from shoal.motions import SolitaryPiston

    m = SolitaryPiston(name="s", height=H, depth=d)
    end, v_end = m.kinematics(10 * m.duration)
    # the motion starts and stops where eta = 0.2 % H: the tails miss 1 - tanh(3.8) = 0.1 % of the stroke
    assert end[0] == pytest.approx(math.sqrt(16 * H * d / 3), rel=2e-3)
    assert np.all(v_end == 0)
    ts = np.linspace(0, m.duration, 4001)
    v = np.array([m.kinematics(t)[1][0] for t in ts])
    c = math.sqrt(9.81 * (d + H))
    assert v.max() == pytest.approx(c * H / (d + H), rel=1e-3)
    x = np.array([m.kinematics(t)[0][0] for t in ts])
    np.testing.assert_allclose(np.gradient(x, ts)[1:-1], v[1:-1], atol=2e-3 * v.max())


def test_time_series_motion(tmp_path):
    from shoal.errors import InputError
    from shoal.motions import TimeSeriesMotion

    t = np.linspace(0, 2, 81)
    x = 0.1 * np.sin(np.pi * t)
    np.savetxt(tmp_path / "paddle.csv", np.column_stack([t, x]), delimiter=",", header="t,x")
    m = TimeSeriesMotion(name="p", file=str(tmp_path / "paddle.csv"))
    for tt in (0.3, 0.77, 1.5):
        d, v = m.kinematics(tt)
        assert d[0] == pytest.approx(0.1 * math.sin(math.pi * tt), abs=1e-6)
        assert v[0] == pytest.approx(0.1 * math.pi * math.cos(math.pi * tt), abs=2e-4)
        assert d[1] == d[2] == 0
    assert m.kinematics(-1)[0][0] == 0 and m.kinematics(5)[0][0] == pytest.approx(x[-1])
    (tmp_path / "bad.csv").write_text("0,1\n0,2\n")
    with pytest.raises(InputError, match="increase"):
        TimeSeriesMotion(name="b", file=str(tmp_path / "bad.csv")).kinematics(0.5)
    with pytest.raises(InputError, match="not found"):
        TimeSeriesMotion(name="b", file=str(tmp_path / "none.csv")).kinematics(0.5)


def test_peak_speeds_are_each_motions_largest_speed(tmp_path):
    """The peak speed `check_motion_speeds` compares with c0: the velocity amplitude pi S / T of a
    piston (reached once the ramp is over), |v| of a constant velocity once started, c H / (d + H) of a solitary
    paddle under the crest, and the spline's largest |dX/dt| of a time series (found from its knots
    and the zeros of its acceleration: no denser sampling finds more)."""
    from shoal.motions import SolitaryPiston, TimeSeriesMotion

    p = PistonWavemaker(name="p", height=0.05, period=1.2, depth=0.4)
    assert p.peak_speed(100.0) == pytest.approx(math.pi * p.stroke / p.period, rel=1e-4)
    assert p.peak_speed(0.5) < 0.5 * math.pi * p.stroke / p.period  # still in the ramp at t = 0.5 s
    c = ConstantVelocity(name="c", velocity=(3.0, 0.0, 4.0), start=1.0)
    assert c.peak_speed(2.0) == 5.0 and c.peak_speed(0.5) == 0.0
    s = SolitaryPiston(name="s", height=0.1, depth=0.4)
    # the paddle follows the water under the crest: dX/dt = c H / (d + H) at the crest
    assert s.peak_speed(10.0) == pytest.approx(s.celerity * 0.1 / 0.5, rel=1e-3)
    t = np.linspace(0, 2, 9)
    np.savetxt(tmp_path / "paddle.csv", np.column_stack([t, 0.1 * np.sin(np.pi * t)]), delimiter=",")
    ts = TimeSeriesMotion(name="t", file=str(tmp_path / "paddle.csv"))
    dense = max(abs(ts.kinematics(u)[1][0]) for u in np.linspace(0, 2, 20001))
    assert dense > 0.3  # the series moves (its clamped ends make the spline overshoot pi / 10 = 0.314)
    assert dense <= ts.peak_speed(5.0) <= dense * (1 + 1e-6)
    assert ts.peak_speed(-1.0) == 0.0  # before the run starts nothing moves


def test_a_wall_faster_than_sound_is_refused_and_a_fast_one_warned():
    """c0 = 20 sqrt(g 0.4) = 39.6 m/s: a wall at c0 or faster is refused, one above 0.1 c0 warned."""
    from shoal.errors import InputError
    from shoal.motions import check_motion_speeds

    c0 = 20.0 * math.sqrt(9.81 * 0.4)
    assert check_motion_speeds([ConstantVelocity(name="w", velocity=(0.3, 0.0, 0.0))], c0, 10.0) == []
    (w,) = check_motion_speeds([ConstantVelocity(name="w", velocity=(5.0, 0.0, 0.0))], c0, 10.0)
    assert "'w' reaches 5 m/s" in w and "0.1 c0 = 3.96 m/s" in w
    for v in (c0, 1e12, -1e12, 1e308):
        with pytest.raises(InputError, match="not below the speed of sound c0 = 39.6 m/s"):
            check_motion_speeds([ConstantVelocity(name="w", velocity=(0.0, 0.0, v))], c0, 10.0)
    # a wall that would start after the run ends never moves
    assert check_motion_speeds([ConstantVelocity(name="w", velocity=(1e12, 0.0, 0.0), start=20.0)], c0, 10.0) == []
