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


NONLINEAR = BeachStandingWave.for_flume(depth=0.1, slope=0.1, sigma_paddle=3.0, breaking=0.5)


@pytest.mark.parametrize("t", [0.0, 0.9, 2.3, 3.7])
def test_nonlinear_fields_solve_the_nonlinear_shallow_water_equations(t):
    """With h = s X + eta and u towards the shore (X offshore): eta_t - (h u)_X = 0 and
    u_t - u u_X = g eta_X, by centred differences (second order: residuals below 1e-6 of the terms)."""
    w, s, g = NONLINEAR, NONLINEAR.slope, NONLINEAR.g
    X = np.linspace(0.3, 1.2, 60)  # wet at every phase (the shoreline runs between X = -A/s and +A/s)
    e, dt = 1e-5, 1e-5

    def h_u(Xs, ts):
        eta, u = w.nonlinear(Xs, ts)
        return (s * Xs + eta) * u

    eta, u = w.nonlinear(X, t)
    eta_t = (w.nonlinear(X, t + dt)[0] - w.nonlinear(X, t - dt)[0]) / (2 * dt)
    hu_X = (h_u(X + e, t) - h_u(X - e, t)) / (2 * e)
    assert np.all(np.isfinite(eta_t))
    assert np.abs(eta_t - hu_X).max() < 1e-6 * np.abs(hu_X).max()
    u_t = (w.nonlinear(X, t + dt)[1] - w.nonlinear(X, t - dt)[1]) / (2 * dt)
    u_X = (w.nonlinear(X + e, t)[1] - w.nonlinear(X - e, t)[1]) / (2 * e)
    eta_X = (w.nonlinear(X + e, t)[0] - w.nonlinear(X - e, t)[0]) / (2 * e)
    assert np.abs(u_t - u * u_X - g * eta_X).max() < 1e-6 * np.abs(g * eta_X).max()


def test_nonlinear_wave_tends_to_the_linear_one():
    """At epsilon = 1e-4 the nonlinear wave is the linear one within 1e-3 of its amplitudes."""
    w = BeachStandingWave.for_flume(depth=0.1, slope=0.1, sigma_paddle=3.0, breaking=1e-4)
    X = np.linspace(0.05, 1.0, 40)
    for t in (0.0, 0.4 * w.period, 0.8 * w.period):
        eta, u = w.nonlinear(X, t)
        assert np.abs(eta - w.elevation(X, t)).max() < 1e-3 * w.amplitude
        assert np.abs(u - w.velocity(X, t)).max() < 1e-3 * w.amplitude * w.omega / w.slope


def test_nonlinear_shoreline_reaches_plus_and_minus_A():
    """Carrier & Greenspan's run-up invariance: the shoreline's extremes are +A and -A (at t = T/4 and
    -T/4), and it is the surface at the shoreline's position, X = -eta / s."""
    w = NONLINEAR
    t = np.linspace(-0.5 * w.period, 0.5 * w.period, 4001)
    z = w.nonlinear_shoreline(t)
    assert z.max() == pytest.approx(w.amplitude, rel=1e-6)
    assert z.min() == pytest.approx(-w.amplitude, rel=1e-6)
    assert t[np.argmax(z)] == pytest.approx(0.25 * w.period, abs=w.period / 2000)
    assert t[np.argmin(z)] == pytest.approx(w.rundown_time, abs=w.period / 2000)
    # just offshore of the shoreline the water is continuous with it
    for tk in (0.1, 1.3, 2.9):
        zs = float(w.nonlinear_shoreline(tk))
        eta, _ = w.nonlinear(-zs / w.slope + 1e-7, tk)
        assert float(eta) == pytest.approx(zs, abs=1e-5 * w.amplitude)


def test_rundown_is_at_rest_with_its_surface():
    """At t = -T/4 the water is still (u = 0) and its surface is `rundown_surface`: -A at the
    shoreline, X = A / s, and the linear wave's -A J0(sigma) far offshore to within epsilon's order."""
    w = NONLINEAR
    X = np.linspace(0.23, 1.0, 30)
    eta, u = w.nonlinear(X, w.rundown_time)
    assert np.abs(u).max() < 1e-12 * w.amplitude * w.omega / w.slope
    assert np.allclose(eta, w.rundown_surface(X), rtol=0, atol=1e-6 * w.amplitude)
    assert float(w.rundown_surface(w.amplitude / w.slope)) == pytest.approx(-w.amplitude, rel=1e-6)
    assert np.isnan(w.rundown_surface(0.9 * w.amplitude / w.slope))  # dry
    assert np.isnan(w.nonlinear(0.0, w.rundown_time)[0])


def test_column_path_keeps_the_water_behind_it():
    """The paddle's path: the volume of water between the shoreline and the column moving with the flow
    stays what it was (to 1e-6), over a period, and the path is periodic."""
    w = NONLINEAR
    t0 = w.rundown_time
    t = t0 + np.linspace(0.0, w.period, 9)
    Xp = w.column_path(1.0, t0, t)
    assert Xp[-1] == pytest.approx(1.0, abs=1e-7)

    def volume(Xc, tk):
        Xs = -float(w.nonlinear_shoreline(tk)) / w.slope
        q = np.linspace(Xs, Xc, 4001)[1:]
        depth = w.slope * q + w.nonlinear(q, tk)[0]
        return float(np.trapezoid(np.concatenate([[0.0], depth]), np.linspace(Xs, Xc, 4001)))

    v0 = volume(1.0, t0)
    for Xk, tk in zip(Xp, t):
        assert volume(Xk, tk) == pytest.approx(v0, rel=1e-6)
