"""The standing long wave on a plane beach (`shoal.analysis.beach_standing_wave`), the reference of
the periodic run-up benchmark (Carrier & Greenspan 1958): its fields must solve the linear
shallow-water equations over h = s X, and its paddle and initial state must be the solution's own."""

from __future__ import annotations

import numpy as np
import pytest

from shoal.analysis.beach_standing_wave import BeachStandingWave

WAVE = BeachStandingWave.for_flume(depth=0.1, slope=0.1, sigma_paddle=5.4, breaking=0.5)


def test_for_flume_sets_the_breaking_parameter_and_kd():
    assert WAVE.breaking == pytest.approx(0.5, rel=1e-12)
    # k d = omega sqrt(d / g) = sigma_L s / 2
    assert WAVE.omega * np.sqrt(0.1 / 9.81) == pytest.approx(5.4 * 0.1 / 2, rel=1e-12)
    assert WAVE.sigma(1.0) == pytest.approx(5.4, rel=1e-12)  # the paddle, L = d / s = 1 m offshore


@pytest.mark.parametrize("t", [0.3, 1.1, 2.0])
def test_fields_solve_the_linear_shallow_water_equations(t):
    """d eta/dt - d(h u)/dX = 0 and du/dt = g d eta/dX (u landward, X offshore: -d/dx = d/dX), by
    centred differences: residuals below 1e-6 of the terms."""
    s, g = WAVE.slope, WAVE.g
    X = np.linspace(0.01, 1.2, 200)
    e, dt = 1e-6, 1e-6
    deta_dt = (WAVE.elevation(X, t + dt) - WAVE.elevation(X, t - dt)) / (2 * dt)
    dhu_dX = (s * (X + e) * WAVE.velocity(X + e, t) - s * (X - e) * WAVE.velocity(X - e, t)) / (2 * e)
    scale = np.abs(dhu_dX).max()
    assert np.abs(deta_dt - dhu_dX).max() < 1e-6 * scale
    du_dt = (WAVE.velocity(X, t + dt) - WAVE.velocity(X, t - dt)) / (2 * dt)
    deta_dX = (WAVE.elevation(X + e, t) - WAVE.elevation(X - e, t)) / (2 * e)
    assert np.abs(du_dt - g * deta_dX).max() < 1e-6 * g * np.abs(deta_dX).max() + 1e-12


def test_shoreline_and_its_speed():
    """At X = 0 the surface is A sin(omega t) and the flow A omega / s cos(omega t), the speed of a
    shoreline running up and down a slope s."""
    t = np.linspace(0, WAVE.period, 50)
    assert np.allclose(WAVE.elevation(0.0, t), WAVE.shoreline(t), rtol=0, atol=1e-15)
    assert np.allclose(WAVE.velocity(0.0, t), WAVE.amplitude * WAVE.omega / WAVE.slope * np.cos(WAVE.omega * t))


def test_du_dx_and_the_vertical_velocity():
    """du/dx is the derivative of u along x = -X; w follows the bed (w = s u on it) and makes the
    flow divergence-free (dw/dz = -du/dx)."""
    X = np.linspace(0.0, 1.0, 101)
    e = 1e-6
    num = -(WAVE.velocity(X + e, 0.0) - WAVE.velocity(np.maximum(X - e, 0.0), 0.0)) / (X + e - np.maximum(X - e, 0.0))
    assert np.allclose(WAVE.du_dx(X, 0.0), num, rtol=1e-5, atol=1e-9)
    assert np.allclose(WAVE.vertical_velocity(X, 0.0, 0.0), WAVE.slope * WAVE.velocity(X, 0.0))
    dw_dz = (WAVE.vertical_velocity(X, 0.02, 0.0) - WAVE.vertical_velocity(X, 0.01, 0.0)) / 0.01
    assert np.allclose(dw_dz, -WAVE.du_dx(X, 0.0))


def test_paddle_moves_with_the_flow_at_its_face():
    """d xi / dt = u(L, t): the stroke's rate at t = 0 is the solution's velocity at the paddle."""
    L = 1.0
    assert WAVE.paddle_stroke(L) * WAVE.omega == pytest.approx(float(WAVE.velocity(L, 0.0)), rel=1e-12)
