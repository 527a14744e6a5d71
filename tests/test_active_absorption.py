"""Active wave absorption at a paddle (issue 31): the paddle's near field, the controller, the paddle's stop, the
case file, and the absorption of a wave train in SPH.

The near field is checked against an independent computation (SciPy's quadrature of the mode projections and
root finding), the transfer function against Biesel's; the controller against the linear theory of an
absorbing paddle it implements, driven by a synthetic surface; the SPH run against the energy left in a flume
closed by a vertical wall.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shoal.active_absorption import AbsorbingPaddle, ActiveAbsorption
from shoal.motions import FlapWavemaker, IrregularWaves, PistonWavemaker
from shoal.waves import JonswapSpectrum, flap_height_to_stroke, piston_height_to_stroke, wavenumber
from shoal.waves.near_field import evanescent_wavenumbers, near_field

G = 9.81


# ------------------------------------------------------------------ the paddle's near field
@pytest.mark.parametrize("kd", [0.3, 1.11, 2.0, 4.0])
@pytest.mark.parametrize("hinge", [None, 0.0, 0.1, -0.05])
def test_the_progressive_mode_is_biesels_transfer_function(kd, hinge):
    d = 0.5
    k = kd / d
    omega = math.sqrt(G * k * math.tanh(kd))
    t, _ = near_field(omega, d, 0.0, hinge)
    ref = piston_height_to_stroke(k, d) if hinge is None else flap_height_to_stroke(k, d, hinge)
    assert t == pytest.approx(ref, rel=1e-9)


def test_evanescent_wavenumbers_solve_the_dispersion_relation_in_their_brackets():
    d, omega = 0.4, 5.0
    kappa = evanescent_wavenumbers(omega, d, 50)
    n = np.arange(1, 51)
    assert np.all(kappa * d > (n - 0.5) * math.pi) and np.all(kappa * d < n * math.pi)
    np.testing.assert_allclose(omega**2 + G * kappa * np.tan(kappa * d), 0.0, atol=1e-9 * omega**2)


@pytest.mark.parametrize("hinge", [None, 0.1])
def test_the_near_field_matches_an_independent_quadrature(hinge):
    """E(x) against SciPy: the modes' projections integrated numerically, the roots by brentq."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    d, kd = 0.5, 1.11
    k = kd / d
    omega = math.sqrt(G * k * math.tanh(kd))
    arm = d - (hinge or 0.0)

    def f(z):  # the paddle's velocity profile, 1 at the still-water level
        return 1.0 if hinge is None else max(z + arm, 0.0) / arm

    xs = np.array([0.02, 0.05, 0.2])
    ref = np.zeros(len(xs))
    for n in range(1, 121):
        q = brentq(lambda q: q * math.tan(q) + omega**2 * d / G, (n - 0.5) * math.pi + 1e-12, n * math.pi - 1e-12)
        kap = q / d
        num = quad(lambda z: f(z) * math.cos(kap * (d + z)), -d, 0.0, limit=200, points=[-arm])[0]
        c = num / quad(lambda z: math.cos(kap * (d + z)) ** 2, -d, 0.0, limit=200)[0]
        ref += omega**2 / G * c / kap * math.cos(q) * np.exp(-kap * xs)
    _, e = near_field(omega, d, xs, hinge)
    np.testing.assert_allclose(e, ref, rtol=2e-3, atol=1e-6)


def test_the_near_field_is_small_in_shallow_water_and_dies_within_two_depths():
    """Every evanescent mode decays at least as exp(-kappa_1 x), kappa_1 d > pi / 2: below e^-pi = 4.3 % of
    its value at the face two depths away."""
    d = 0.5
    for kd, bound in ((0.1, 0.002), (2.0, 0.3)):
        k = kd / d
        omega = math.sqrt(G * k * math.tanh(kd))
        t, e = near_field(omega, d, np.array([0.0, 2 * d]))
        assert abs(e[0]) / t < bound
        assert abs(e[1]) < math.exp(-math.pi) * abs(e[0])


# ------------------------------------------------------------------ the paddle's stop and its kinematics
def test_a_paddle_with_a_duration_ramps_down_and_stays_at_rest():
    p = PistonWavemaker(name="p", height=0.04, period=1.2, depth=0.25, ramp_periods=1.0, duration=4.8)
    x, u, a = zip(*(p.excursion(t) for t in np.linspace(0, 10, 2001)))
    x, u = np.array(x), np.array(u)
    t = np.linspace(0, 10, 2001)
    assert np.all(x[t >= 6.0] == 0.0) and np.all(u[t >= 6.0] == 0.0)
    # before the stop it is the regular paddle
    q = PistonWavemaker(name="q", height=0.04, period=1.2, depth=0.25, ramp_periods=1.0)
    for s in (0.3, 2.0, 4.7):
        assert p.kinematics(s)[0][0] == pytest.approx(q.kinematics(s)[0][0], abs=1e-15)
    # the envelope's derivatives are continuous: X' by central differences
    h = 1e-6
    for s in (4.9, 5.4, 5.9):
        assert (p.excursion(s + h)[0] - p.excursion(s - h)[0]) / (2 * h) == pytest.approx(p.excursion(s)[1],
                                                                                          rel=1e-5, abs=1e-9)
        assert (p.excursion(s + h)[1] - p.excursion(s - h)[1]) / (2 * h) == pytest.approx(p.excursion(s)[2],
                                                                                          rel=1e-4, abs=1e-7)


@pytest.mark.parametrize("motion", [
    PistonWavemaker(name="p", height=0.04, period=1.2, depth=0.25),
    FlapWavemaker(name="f", height=0.04, period=1.2, depth=0.25),
    IrregularWaves(name="i", depth=0.25, spectrum=JonswapSpectrum(hs=0.03, tp=1.2), components=32),
    IrregularWaves(name="j", depth=0.25, spectrum=JonswapSpectrum(hs=0.03, tp=1.2), components=32, paddle="flap"),
], ids=["piston", "flap", "irregular-piston", "irregular-flap"])
def test_no_correction_is_the_target_motion_and_a_shift_moves_the_face(motion):
    for t in (0.0, 0.7, 3.1):
        a, b = motion.rigid_kinematics(t), motion.offset_kinematics(t, 0.0, 0.0, 0.0)
        for u, v in zip(a, b):
            np.testing.assert_array_equal(np.asarray(u), np.asarray(v))
        # a shift dx of the excursion moves where the face crosses the still-water level by dx along its axis
        p = motion.wave_paddle()
        face = np.array([[0.0, 0.0, 0.5 * p.depth], [0.0, 0.0, p.depth]])  # two points of the face at rest

        def crossing(dx):
            (a0, a1) = motion.offset_kinematics(t, dx, 0.0, 0.0).points(face)[0]
            s = (p.depth - a0[2]) / (a1[2] - a0[2])
            return a0 + s * (a1 - a0)

        assert (crossing(0.01) - crossing(0.0)) @ p.direction == pytest.approx(0.01, rel=1e-9)


# ------------------------------------------------------------------ the controller
class _Surface:
    """A stand-in model whose `sample` reads a prescribed surface eta(x, t): kernel sum 1 below, 0 above,
    linear over dp around it (what `surface_level` inverts exactly)."""

    def __init__(self, eta, dp):
        self.eta, self.dp, self.t = eta, dp, 0.0

    def sample(self, points, shepard=False):
        level = self.eta(points[0, 0], self.t)
        s = np.clip(0.5 - (points[:, 2] - level) / self.dp, 0.0, 1.0)
        return {"kernel_sum": s}


class _Sim:
    def __init__(self, model):
        self.model, self.time, self.step_count = model, 0.0, 0

    def advance(self, dt):
        self.time += dt
        self.model.t = self.time
        self.step_count += 1


def _controller(motion, d=0.25, dp=0.0125):
    return AbsorbingPaddle(motion, face=0.0, lateral=(0.0, 0.0, 0.0), still_water=d, dp=dp, h=2.1 * dp, dim=2)


def test_the_paddles_own_wave_asks_for_no_correction():
    """A surface that is exactly the target's (progressive wave and near field at the moving gauge) leaves the
    correction at zero to round-off: the paddle does not fight its own wave."""
    d = 0.25
    m = PistonWavemaker(name="p", height=0.04, period=1.2, depth=d, ramp_periods=1.0,
                        absorption=ActiveAbsorption(start=0.0))
    c = _controller(m)
    model = _Surface(lambda x, t: d + c.target_elevation(t, x - c.face), 2 * (c.z[1] - c.z[0]))
    sim = _Sim(model)
    for _ in range(3000):
        sim.advance(1e-3)
        c(sim)
    assert abs(c.u_c) < 1e-9 and abs(c.x_c) < 1e-9


@pytest.mark.parametrize("gain", ["linear", "shallow"])
def test_a_returning_wave_is_absorbed_as_the_linear_theory_says(gain):
    """A wave coming back to a paddle at rest in front of it: the gauge reads the incoming wave and its
    reflection, and the paddle's correction makes a wave of amplitude eta_A (linear transfer function). The
    closed loop in the frequency domain gives eta_A = -2 G eta_R / (G_0 + G) at the paddle, so the outgoing
    wave eta_R + eta_A has the reflection coefficient |G_0 - G| / (G_0 + G): 0 for the linear gain, 6 % for
    the shallow-water gain at kd = 0.95. The simulated loop (the correction's wave fed back to the gauge)
    reaches that to within the filter's and the drift control's phase errors (a few per cent)."""
    d, period, a_r = 0.25, 1.2, 0.01
    omega = 2 * math.pi / period
    k = wavenumber(period, d)
    m = PistonWavemaker(name="p", height=1e-4, period=period, depth=d, ramp_periods=1.0, duration=1e-3,
                        absorption=ActiveAbsorption(start=0.0, gain=gain, drift_periods=1e6))
    c = _controller(m)
    t0 = piston_height_to_stroke(k, d)
    g0 = omega / t0
    ramp = lambda t: min(t / (2 * period), 1.0)  # noqa: E731

    def eta(x, t):  # incoming + reflected off the paddle + the correction's wave (progressive, far-field)
        inc = a_r * ramp(t) * (math.cos(omega * t + k * x) + math.cos(omega * t - k * x))
        return d + inc + c_wave(x, t)

    dt = 2e-4
    steps = int(12 * period / dt)
    hist_t, hist_u = np.zeros(steps + 1), np.zeros(steps + 1)
    filled = [1]

    def c_wave(x, t):  # the progressive wave of the correction: eta_A(x, t) = (T0 / omega) U_c(t - x / c)
        tt = t - x / (omega / k)
        n = filled[0]
        return t0 / omega * float(np.interp(tt, hist_t[:n], hist_u[:n]))

    sim = _Sim(_Surface(eta, 0.0125))
    for i in range(steps):
        sim.advance(dt)
        c(sim)
        hist_t[i + 1], hist_u[i + 1] = sim.time, c.u_c
        filled[0] = i + 2
    # over the last two periods: the outgoing wave at the paddle, eta_R + eta_A, against the prediction
    t = hist_t
    sel = t > t[-1] - 2 * period
    eta_a = t0 / omega * hist_u[sel]
    out = a_r * np.cos(omega * t[sel]) + eta_a
    kr = (np.max(out) - np.min(out)) / (2 * a_r)
    nominal = g0 if gain == "linear" else math.sqrt(G / d)  # the filter takes out the boost it is given
    expected = abs(g0 - nominal) / (g0 + nominal)
    assert kr == pytest.approx(expected, abs=0.02)
    if gain == "linear":
        assert kr < 0.02


def test_drift_control_holds_the_paddle_against_a_constant_error():
    """A constant error e (a set-down the target does not know) drives the correction toward the steady state
    of U = -G e - X / T_d = 0, X = -G e T_d, not beyond: without the leak it would drift without bound."""
    d = 0.25
    m = PistonWavemaker(name="p", height=1e-4, period=1.2, depth=d, ramp_periods=1.0, duration=1e-3,
                        absorption=ActiveAbsorption(start=0.0, drift_periods=2.0))
    c = _controller(m)
    sim = _Sim(_Surface(lambda x, t: d - 0.002, 0.0125))
    for _ in range(40000):
        sim.advance(1e-3)
        c(sim)
    steady = c.gain * 0.002 * c.drift_time
    assert c.x_c == pytest.approx(steady, rel=0.01)


def test_the_controller_state_round_trips_bitwise():
    """A controller restored from another's `checkpoint_state` mid-run continues bitwise like it."""
    d = 0.25
    m = PistonWavemaker(name="p", height=0.04, period=1.2, depth=d, ramp_periods=1.0,
                        absorption=ActiveAbsorption(start=0.5))
    a, b = _controller(m), _controller(m)
    surf = lambda x, t: d + 0.01 * math.sin(3.3 * t) + 0.003 * math.cos(17 * t)  # noqa: E731
    sa, sb = _Sim(_Surface(surf, 0.0125)), _Sim(_Surface(surf, 0.0125))
    for _ in range(700):
        sa.advance(1.37e-3)
        a(sa)
    import json

    state = json.loads(json.dumps(a.checkpoint_state()))
    b.restore_checkpoint_state(state, {})
    sb.time, sb.step_count, sb.model.t = sa.time, sa.step_count, sa.time
    for _ in range(500):
        sa.advance(1.37e-3)
        sb.advance(1.37e-3)
        a(sa)
        b(sb)
        assert all(np.array_equal(np.asarray(u), np.asarray(v))
                   for u, v in zip(a.rigid_kinematics(sa.time + 5e-4), b.rigid_kinematics(sb.time + 5e-4)))
    assert a.checkpoint_state() == b.checkpoint_state()


# ------------------------------------------------------------------ the case file
ABSORBING = """\
name = "awas"
dim = 2
dp = 0.05
end_time = 0.01

[fluid]
depth = 0.25
surface_level = 0.25

[[solids]]
name = "tank"
shape = { type = "tank", lo = [-0.3, 0.0, 0.0], hi = [2.0, 0.0, 0.5] }

[[solids]]
name = "paddle"
shape = { type = "box", lo = [-0.2, 0.0, 0.0], hi = [0.0, 0.0, 0.5] }
motion = "piston"

[[fluids]]
shape = { type = "box", lo = [0.0, 0.0, 0.0], hi = [2.0, 0.0, 0.25] }

[[motions]]
type = "piston"
name = "piston"
height = 0.03
period = 1.0
depth = 0.25
duration = 3.0

[motions.absorption]
gain = "shallow"
drift_periods = 5.0
"""


def test_absorption_round_trips_through_toml_and_builds_an_absorbing_paddle(tmp_path):
    from shoal.build import build_model
    from shoal.casefile import dumps_case, load_case

    (tmp_path / "c.toml").write_text(ABSORBING)
    case = load_case(tmp_path / "c.toml")
    m = case.motions[0]
    assert m.absorption == ActiveAbsorption(gain="shallow", drift_periods=5.0) and m.duration == 3.0
    (tmp_path / "d.toml").write_text(dumps_case(case))
    assert load_case(tmp_path / "d.toml").motions == case.motions
    model = build_model(case)
    paddle = model.motions[0]
    assert isinstance(paddle, AbsorbingPaddle)
    assert paddle.face == pytest.approx(0.0, abs=1e-9)  # the paddle's wall surface at x = 0
    assert paddle.gain == pytest.approx(math.hypot(1.0, 2 * math.pi / 1.0 * paddle.travel_time)
                                        * math.sqrt(G / 0.25), rel=1e-12)
    assert paddle.start == pytest.approx(2.0)  # the end of the default two-period ramp


@pytest.mark.parametrize("fragment,expected", [
    ('gain = "shallow"', ["motions[0].absorption.gain", "'linear'", "'shallow'"]),
    ("drift_periods = 5.0", ["motions[0].absorption.drift_periods = -1", "greater than 0"]),
    ("[motions.absorption]", ["unknown key 'gauge' in motions[0].absorption"]),
    ("duration = 3.0", ["motions[0].duration = 0", "greater than 0"]),
])
def test_bad_absorption_input_is_one_line_and_exit_2(fragment, expected, tmp_path, monkeypatch, capsys):
    from shoal.cli import main

    bad = {'gain = "shallow"': 'gain = "deep"', "drift_periods = 5.0": "drift_periods = -1",
           "[motions.absorption]": "[motions.absorption]\ngauge = 3", "duration = 3.0": "duration = 0"}[fragment]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "case.toml").write_text(ABSORBING.replace(fragment, bad))
    try:
        status = main(["check", str(tmp_path / "case.toml")])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    assert status == 2, (status, out, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("shoal: error: ") and "Traceback" not in err, err
    for part in expected:
        assert part in lines[0], (part, lines[0])


# ------------------------------------------------------------------ SPH
def test_the_paddle_absorbs_the_train_the_wall_sends_back(tmp_path):
    """Issue 31, must-show 4 (quick version of `shoal validate active-absorption`): a train of one full period
    between ramps, against a wall two wavelengths away (kd = 1.68, d/dp = 8). With absorption, under 10 % of
    the incident train's energy is left in the flume once the train's tail has been to the wall and back to
    the paddle (the validation case runs the same flume without absorption: measured, 0.66 of it stays at
    d/dp = 10). The incident energy is that of the train linear theory gives the paddle's signal, less SPH's
    damping on the way: E = rho g a^2 c_g (N T + 3/4 t_r) / 2 for N full periods and two cosine ramps of
    t_r (int r^2 dt = 3/8 t_r each), of which the coarse flume keeps more than half."""
    from shoal.validation.active_absorption import ActiveAbsorptionCase

    case = ActiveAbsorptionCase()
    res = case.run(True, "cpu", tmp_path)
    _, passed = case.compare(res)
    out = res.data["train_on"]
    assert out["fraction_left"] < 0.10 and passed, out
    a, period = 0.5 * out["height"], out["period"]
    train = 1000.0 * G * a * a * out["group_velocity"] * (out["periods"] * period + 0.75 * period) / 2
    assert 0.5 * train < out["incident_energy"] < 1.05 * train, (out, train)


def _small_flume(t_end, dp=0.025, d=0.25):
    """A 2D flume 1.2 m long whose piston corrects its motion from the start (`ActiveAbsorption(start=0)`)."""
    from shoal.case import Case, Checkpointing, Fluid, FluidRegion, Output, Solid
    from shoal.geometry.shapes import Box, Tank

    piston = PistonWavemaker(name="piston", height=0.03, period=0.8, depth=d, ramp_periods=0.5,
                             absorption=ActiveAbsorption(start=0.0))
    return Case(name="awas", dim=2, dp=dp, end_time=t_end, fluid=Fluid(depth=d, surface_level=d),
                options=dict(viscosity="laminar", nu=1e-6, visco_bound_factor=0.0, coef_h=1.5),
                motions=[piston], output=Output(interval=t_end), checkpoint=Checkpointing(wall_interval=0.0),
                solids=[Solid(name="paddle", shape=Box(lo=(-0.1, 0, 0), hi=(0, 0, 0.4)), motion="piston"),
                        Solid(name="flume", shape=Tank(lo=(-0.2, 0, 0), hi=(1.2, 0, 0.4)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.2, 0, d)))])


def test_an_absorbing_run_resumes_bitwise(tmp_path):
    """Cut at about 60 % of its steps and resumed from the checkpoint, a run whose paddle corrects its motion
    every step ends bitwise where the uninterrupted run ends: the controller's state is in the checkpoint
    (without it the resumed paddle would start from no correction and move elsewhere)."""
    import h5py

    from shoal import resume_run, run_case

    case = _small_flume(0.15)
    ref = run_case(case, tmp_path / "ref", plot=False, handle_signals=False)
    part = run_case(case, tmp_path / "cut", plot=False, max_steps=int(0.6 * ref.steps), handle_signals=False)
    assert part.steps < ref.steps
    with h5py.File(part.checkpoint, "r") as f:
        import json

        meta = json.loads(bytes(f["meta"][()]).decode())
    saved = [c for c in meta["callbacks"] if c["name"] == "absorption piston"]
    assert saved and saved[0]["state"]["u_c"] != 0.0  # a correction under way at the cut
    res = resume_run(tmp_path / "cut", plot=False, handle_signals=False)
    assert res.steps == ref.steps

    def state(path):
        with h5py.File(path, "r") as f:
            order = np.argsort(f["particles/idp"][()])
            return {k: f[f"particles/{k}"][()][order] for k in ("pos", "vel", "rho")}

    a, b = state(ref.checkpoint), state(res.checkpoint)
    for k in a:
        assert np.array_equal(a[k], b[k]), k
