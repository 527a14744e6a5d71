"""Irregular and focused waves from a piston paddle (issue 31): components, their linear elevation, the paddle's
kinematics, the case file.

The physics is checked against independent computations: Parseval's theorem on a synthesised record, the
focus condition, `PistonWavemaker` for a single component (the transfer function and the phase convention),
numerical derivatives, dense sampling of the periodic signal; the case-file side against the TOML round trip
and the command line's one-line errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydantic import ValidationError

import shoal
from shoal.casefile import dumps_case, load_case, write_case
from shoal.cli import main
from shoal.errors import InputError
from shoal.geometry.shapes import Box, Tank
from shoal.motions import FocusedWaves, IrregularWaves, PistonWavemaker, check_motion_speeds
from shoal.waves import (JonswapSpectrum, PiersonMoskowitzSpectrum, focused_components, frequency_grid,
                         piston_height_to_stroke, random_phase_components, wavenumbers)

JONSWAP = JonswapSpectrum(hs=0.05, tp=1.5)
PM = PiersonMoskowitzSpectrum(hs=0.05, tp=1.5)


# ------------------------------------------------------------------ components
@pytest.mark.parametrize("f_min,f_max,n", [(1 / 3, 2.0, 256), (0.0, 1.0, 10), (0.7, 0.9, 1), (0.5, 4.5, 1000)])
def test_frequency_grid_is_multiples_of_df_covering_the_band(f_min, f_max, n):
    f, df = frequency_grid(f_min, f_max, n)
    assert len(f) == n and df == pytest.approx((f_max - f_min) / n, rel=1e-15)
    np.testing.assert_allclose(f / df, np.round(f / df), atol=1e-9)          # multiples of df
    np.testing.assert_allclose(np.diff(f), df, rtol=1e-12)
    # bins [f_n - df/2, f_n + df/2] cover the band to within df/2 at either end
    assert abs((f[0] - df / 2) - f_min) <= df / 2 * (1 + 1e-12)
    assert abs((f[-1] + df / 2) - f_max) <= df / 2 * (1 + 1e-12)
    with pytest.raises(ValueError):
        frequency_grid(f_max, f_min, n)


def test_amplitudes_carry_the_spectrum_variance():
    """sum a_n^2 / 2 = sum S(f_n) df (the variance of the discretised band) without rescaling, and m0 =
    Hs^2/16 with it, to rounding (1e-13)."""
    raw = random_phase_components(JONSWAP, 0.5, rescale=False)
    f, df = frequency_grid(0.5 / 1.5, 3.0 / 1.5, 256)
    np.testing.assert_array_equal(raw.frequencies, f)
    assert raw.df == df and raw.repeat_period == pytest.approx(153.6, rel=1e-12)
    assert raw.variance == pytest.approx(float(np.sum(JONSWAP.density(f) * df)), rel=1e-13)
    np.testing.assert_allclose(raw.amplitudes, np.sqrt(2 * JONSWAP.density(f) * df), rtol=1e-15)
    # the band keeps 99.0 % of the variance of a JONSWAP of gamma = 3.3 (the rest is above 3 fp)
    assert raw.variance / JONSWAP.m0 == pytest.approx(0.990, abs=1e-3)
    full = random_phase_components(JONSWAP, 0.5)
    assert full.variance == pytest.approx(0.05**2 / 16, rel=1e-13) and full.hm0 == pytest.approx(0.05, rel=1e-13)
    np.testing.assert_allclose(full.amplitudes / raw.amplitudes, math.sqrt(JONSWAP.m0 / raw.variance), rtol=1e-13)
    np.testing.assert_allclose(full.wavenumbers, wavenumbers(2 * np.pi * f, 0.5), rtol=0)


def test_phases_come_from_the_seed():
    a = random_phase_components(JONSWAP, 0.5, seed=7)
    b = random_phase_components(JONSWAP, 0.5, seed=7)
    c = random_phase_components(JONSWAP, 0.5, seed=8)
    np.testing.assert_array_equal(a.phases, b.phases)
    assert not np.allclose(a.phases, c.phases)
    np.testing.assert_array_equal(a.phases, np.random.default_rng(7).uniform(0.0, 2 * math.pi, 256))
    assert np.all((a.phases >= 0) & (a.phases < 2 * math.pi))


def test_random_amplitudes_are_rayleigh_with_the_same_phases():
    """a_n = sqrt(2 S df) sqrt(-ln U_n), U_n the generator's next N uniforms in (0, 1] after the phases
    (Tucker et al. 1984); E[-ln U] = 1, so the record's variance is that of the spectrum on average: with
    4096 components the ratio is within 5 standard deviations, sqrt(sum a^4) / sum a^2 each, of 1."""
    det = random_phase_components(JONSWAP, 0.5, components=4096, seed=3)
    ran = random_phase_components(JONSWAP, 0.5, components=4096, seed=3, random_amplitudes=True)
    np.testing.assert_array_equal(det.phases, ran.phases)
    rng = np.random.default_rng(3)
    rng.uniform(0.0, 2 * math.pi, 4096)
    np.testing.assert_allclose(ran.amplitudes, det.amplitudes * np.sqrt(-np.log(1.0 - rng.random(4096))), rtol=1e-15)
    a2 = det.amplitudes**2
    sigma = math.sqrt(np.sum(a2**2)) / np.sum(a2)
    assert abs(ran.variance / det.variance - 1) < 5 * sigma


@pytest.mark.parametrize("random_amplitudes", [False, True])
def test_the_synthesised_record_has_hm0_of_its_amplitudes_parseval(random_amplitudes):
    """Over one repeat period, sampled at M > 2 n_max equal steps, the record's variance is sum a_n^2 / 2
    exactly (Parseval: the components fall on the DFT's bins), so Hm0 = 4 std(eta) = 4 sqrt(sum a^2 / 2) to
    rounding, and the DFT gives back each a_n."""
    w = random_phase_components(JONSWAP, 0.5, components=128, seed=11, random_amplitudes=random_amplitudes)
    n = np.rint(w.frequencies / w.df).astype(int)
    m = 4 * int(n.max())
    t = np.arange(m) * (w.repeat_period / m)
    eta = w.elevation(2.0, t)
    assert abs(eta.mean()) < 1e-14
    assert 4 * eta.std() == pytest.approx(w.hm0, rel=1e-12)
    spectrum = np.fft.rfft(eta) * 2 / m
    np.testing.assert_allclose(np.abs(spectrum[n]), w.amplitudes, atol=1e-13 * w.amplitudes.max())
    assert np.max(np.abs(np.delete(spectrum, n))) < 1e-13 * w.amplitudes.max()


def test_focused_components_crest_together_at_the_focus():
    """eta(x_f, t_f) = sum a_n = A (to 1e-12 A), and it is the largest elevation of the record there over a
    whole repeat period (and at other places): each term is at most a_n."""
    A, xf, tf = 0.04, 4.0, 30.0
    w = focused_components(JONSWAP, 0.5, A, xf, tf, components=128)
    assert float(np.sum(w.amplitudes)) == pytest.approx(A, rel=1e-14)
    s = JONSWAP.density(w.frequencies)
    np.testing.assert_allclose(w.amplitudes / A, s / np.sum(s), rtol=1e-13)
    assert abs(w.elevation(xf, [tf])[0] - A) <= 1e-12 * A
    t = tf + np.linspace(-0.5, 0.5, 20001) * w.repeat_period
    eta = w.elevation(xf, t)
    assert eta.max() <= A * (1 + 1e-12)
    assert t[np.argmax(eta)] == pytest.approx(tf, abs=w.repeat_period / 20000)
    assert w.elevation(2.0, t).max() < 0.9 * A  # away from the focus the group is spread out


# ------------------------------------------------------------------ the paddle
def test_one_focused_component_is_the_regular_piston_ramp_included():
    """A single component at fp (band 0.5 .. 1.5 fp) focused at x = 0, t = T has phase -2 pi: its paddle is
    PistonWavemaker's for H = 2A, T = Tp, with the same ramp (ramp_time = 1 period = ramp_periods 1):
    X = r(t) (S/2) sin(omega t) -- the same transfer function and phase convention, to rounding."""
    T, d, A = 1.5, 0.5, 0.02
    f = FocusedWaves(name="f", spectrum=PM, depth=d, amplitude=A, x_focus=0.0, t_focus=T, components=1, f_min=0.5,
                     f_max=1.5, ramp_time=T)
    p = PistonWavemaker(name="p", height=2 * A, period=T, depth=d, ramp_periods=1.0)
    assert f.wave_components.frequencies[0] == pytest.approx(1 / T, rel=1e-15)
    for t in np.linspace(0.0, 6 * T, 97):
        (x1, v1), (x2, v2) = f.kinematics(float(t)), p.kinematics(float(t))
        np.testing.assert_allclose(x1, x2, rtol=0, atol=1e-13 * p.stroke)
        np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-12 * p.stroke / T)
    assert f.max_displacement == pytest.approx(p.stroke / 2, rel=1e-12)


def test_one_random_phase_component_is_the_regular_piston_shifted_by_its_phase():
    """With one component a = sqrt(2 m0) = Hs / (2 sqrt 2) (rescaled), X(t) = (a / T) sin(omega t + phi): past
    both ramps, PistonWavemaker's displacement for H = 2a at t + phi / omega; and the linear elevation is
    a cos(omega t - k x + phi)."""
    T, d = 1.5, 0.5
    m = IrregularWaves(name="i", spectrum=PM, depth=d, components=1, f_min=0.5, f_max=1.5, seed=5, ramp_time=T)
    w = m.wave_components
    a, phi, k = w.amplitudes[0], w.phases[0], w.wavenumbers[0]
    assert a == pytest.approx(0.05 / (2 * math.sqrt(2)), rel=1e-14)
    p = PistonWavemaker(name="p", height=2 * a, period=T, depth=d, ramp_periods=0.0)
    omega = 2 * math.pi / T
    for t in np.linspace(T, 8 * T, 57):
        (x1, v1), (x2, v2) = m.kinematics(float(t)), p.kinematics(float(t) + phi / omega)
        np.testing.assert_allclose(x1, x2, rtol=0, atol=1e-12 * p.stroke)
        np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-11 * p.stroke / T)
    t = np.linspace(0, 10, 101)
    np.testing.assert_allclose(m.elevation(3.0, t), a * np.cos(omega * t - k * 3.0 + phi), rtol=0, atol=1e-15)


@pytest.mark.parametrize("motion", [
    IrregularWaves(name="i", spectrum=JONSWAP, depth=0.5, components=64, seed=2, direction=(0.0, 0.0, 2.0)),
    IrregularWaves(name="r", spectrum=PM, depth=0.3, components=64, random_amplitudes=True, ramp_time=4.0),
    FocusedWaves(name="f", spectrum=JONSWAP, depth=0.5, amplitude=0.03, x_focus=3.0, t_focus=25.0, components=64),
], ids=["irregular", "random-amplitudes", "focused"])
def test_kinematics_velocity_is_the_derivative_and_the_paddle_starts_at_rest(motion):
    """Velocity = central difference of the displacement (step 1e-6 s: truncation ~1e-12 and rounding ~1e-11
    of the peak speed), in the ramp and after; X(0) = 0, U(0) = 0; motion along `direction`, normalised."""
    e = np.asarray(motion.direction) / np.linalg.norm(motion.direction)
    peak = motion.peak_speed(100.0)
    for t in (0.3, 1.1, motion.ramp - 0.01, motion.ramp + 0.01, 7.7, 33.3):
        h = 1e-6
        d = (motion.kinematics(t + h)[0] - motion.kinematics(t - h)[0]) / (2 * h)
        x, v = motion.kinematics(t)
        np.testing.assert_allclose(v, d, atol=1e-8 * peak)
        np.testing.assert_allclose(x, e * np.dot(x, e), atol=1e-15)
    x0, v0 = motion.kinematics(0.0)
    assert np.all(x0 == 0) and np.all(v0 == 0)


def _dense_velocity(motion, t):
    """U(t) along the axis from the components directly (ramp included), vectorised."""
    w = motion.wave_components
    b = w.amplitudes / piston_height_to_stroke(w.wavenumbers, w.depth)
    s = np.sum(b[:, None] * np.sin(w.omegas[:, None] * t + w.phases[:, None]), axis=0)
    c = np.sum((b * w.omegas)[:, None] * np.cos(w.omegas[:, None] * t + w.phases[:, None]), axis=0)
    x = np.clip(t / motion.ramp, 0, 1)
    r, dr = 0.5 * (1 - np.cos(np.pi * x)), np.where(x < 1, 0.5 * np.pi / motion.ramp * np.sin(np.pi * x), 0.0)
    return dr * s + r * c, s


@pytest.mark.parametrize("motion", [
    IrregularWaves(name="i", spectrum=JONSWAP, depth=0.5, components=64, seed=4),
    FocusedWaves(name="f", spectrum=PM, depth=0.5, amplitude=0.03, x_focus=3.0, t_focus=25.0, components=64),
], ids=["irregular", "focused"])
def test_peak_speed_and_largest_excursion_over_the_periodic_signal(motion):
    """The signal repeats after 1/df past the ramp: `peak_speed` samples the ramp and one repeat period at
    20 points per period of the fastest component, so it is below the true peak by at most
    1 - cos(pi / 20) ~ 1.2 %; a dense sampling (400 a period: within 3e-5) bounds it from both sides. Same
    for `max_displacement`. Up to a t_end inside the ramp only that part counts."""
    w = motion.wave_components
    t = np.linspace(0.0, motion.ramp + motion.repeat_period, int(400 * (motion.ramp + motion.repeat_period)
                                                                 * w.frequencies.max()))
    v, s = _dense_velocity(motion, t)
    dense, excursion = np.abs(v).max(), np.abs(s).max()
    assert dense * (1 - 0.0125) <= motion.peak_speed(1e6) <= dense * (1 + 1e-4)
    assert excursion * (1 - 0.0125) <= motion.max_displacement <= excursion * (1 + 1e-4)
    early = t <= 0.5 * motion.ramp
    assert motion.peak_speed(0.5 * motion.ramp) <= np.abs(v[early]).max() * (1 + 1e-4)
    assert motion.peak_speed(0.5 * motion.ramp) >= np.abs(v[early]).max() * (1 - 0.0125)
    assert motion.peak_speed(-1.0) == 0.0
    times = motion._speed_times(1e6)
    assert np.max(np.diff(times)) <= 1 / (20 * w.frequencies.max()) * (1 + 1e-12)
    assert times[-1] >= motion.ramp + motion.repeat_period * (1 - 1 / 1000)


def test_defaults_ramp_and_repeat_period():
    m = IrregularWaves(name="i", spectrum=JONSWAP, depth=0.5)
    assert m.components == 256 and (m.f_min, m.f_max) == (0.5, 3.0) and m.seed == 0 and m.paddle == "piston"
    assert m.ramp == pytest.approx(3.0) and m.repeat_period == pytest.approx(153.6, rel=1e-12)
    # one component in a band of 1 fp repeats after Tp: the default ramp is then Tp, not 2 Tp
    one = IrregularWaves(name="i", spectrum=JONSWAP, depth=0.5, components=1, f_min=0.5, f_max=1.5)
    assert one.ramp == pytest.approx(1.5, rel=1e-12)


def test_a_fast_paddle_is_warned_about_like_any_wall():
    m = IrregularWaves(name="i", spectrum=JonswapSpectrum(hs=0.2, tp=2.0), depth=0.5)
    u = m.peak_speed(100.0)
    assert check_motion_speeds([m], c0=100 * u, t_end=100.0) == []
    (w,) = check_motion_speeds([m], c0=5 * u, t_end=100.0)
    assert "motion 'i' reaches" in w
    with pytest.raises(InputError, match="not below the speed of sound"):
        check_motion_speeds([m], c0=0.5 * u, t_end=100.0)


def test_python_construction_refuses_with_the_reason():
    ok = dict(name="i", spectrum=JONSWAP, depth=0.5)
    for bad, fragment in [
        (dict(paddle="flap", hinge=0.5), "hinge = 0.5 m is not below the still-water level"),
        (dict(paddle="wedge"), "not a paddle type; allowed: 'piston', 'flap'"),
        (dict(f_min=2.0, f_max=1.0), "f_min = 2 is not below f_max = 1"),
        (dict(components=0), "greater than or equal to 1"),
        (dict(components=40000), "less than or equal to 32768"),
        (dict(spectrum=JonswapSpectrum(hs=0.5, tp=1.5)), "above the breaking limit"),
        (dict(ramp_time=0.0), "ramp_time = 0 s would start the paddle away"),
        (dict(ramp_time=500.0), "longer than the repeat period 1/df = 153.6 s"),
        (dict(direction=(0.0, 0.0, 0.0)), "direction = [0, 0, 0] is no axis"),
        (dict(seed=-1), "greater than or equal to 0"),
        (dict(f_min=2.99999, f_max=3.0), "repeat only after"),
    ]:
        with pytest.raises(ValidationError, match=None) as err:
            IrregularWaves(**(ok | bad))
        assert fragment in str(err.value), (bad, str(err.value))


# ------------------------------------------------------------------ case files
def _case(tmp_path):
    spectrum_file = tmp_path / "measured.txt"
    f = np.linspace(0.2, 2.0, 37)
    np.savetxt(spectrum_file, np.column_stack([f, PM.density(f)]), header="f [Hz]  S [m^2/Hz]")
    return shoal.Case(
        name="basin", dim=2, dp=0.05, end_time=1.0, fluid=shoal.Fluid(depth=0.5, surface_level=0.5),
        motions=[IrregularWaves(name="sea", spectrum=JONSWAP, depth=0.5, components=128, seed=9,
                                random_amplitudes=True),
                 FocusedWaves(name="group", spectrum={"type": "file", "file": str(spectrum_file)}, depth=0.5,
                              amplitude=0.03, x_focus=2.0, t_focus=20.0, ramp_time=2.5)],
        solids=[shoal.Solid(name="paddle", shape=Box(lo=(-0.1, 0, 0), hi=(0, 0, 0.8)), motion="sea"),
                shoal.Solid(name="flume", shape=Tank(lo=(-0.3, 0, 0), hi=(4.0, 0, 0.8)))],
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(4.0, 0, 0.5)))])


def test_irregular_and_focused_motions_round_trip_through_toml(tmp_path):
    case = _case(tmp_path)
    path = write_case(case, tmp_path / "basin.toml")
    text = path.read_text()
    assert 'type = "irregular"' in text and 'type = "focused"' in text and "[motions.spectrum]" in text
    case2 = load_case(path)
    assert case2.resolved() == case.resolved()
    for m, m2 in zip(case.motions, case2.motions):
        assert type(m2) is type(m) and m2.model_dump() == m.model_dump()
        for t in (0.0, 1.3, 17.0):
            np.testing.assert_array_equal(m.kinematics(t)[0], m2.kinematics(t)[0])
    assert dumps_case(case2) == dumps_case(case)


def test_python_and_toml_build_the_same_motion(tmp_path):
    (tmp_path / "c.toml").write_text(BASE + IRREGULAR)
    m = load_case(tmp_path / "c.toml").motions[0]
    assert m == IrregularWaves(name="p", depth=0.3, spectrum=JonswapSpectrum(hs=0.03, tp=1.2, gamma=3.3), seed=1)


BASE = """\
name = "tank"
dim = 2
dp = 0.05
end_time = 0.01

[fluid]
depth = 0.3
surface_level = 0.3

[[solids]]
name = "tank"
shape = { type = "tank", lo = [0.0, 0.0, 0.0], hi = [0.6, 0.0, 0.5] }

[[fluids]]
shape = { type = "box", lo = [0.0, 0.0, 0.0], hi = [0.6, 0.0, 0.3] }
"""
IRREGULAR = ('\n[[motions]]\ntype = "irregular"\nname = "p"\ndepth = 0.3\nseed = 1\n'
             'spectrum = { type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3 }\n')
FOCUSED = ('\n[[motions]]\ntype = "focused"\nname = "f"\ndepth = 0.3\namplitude = 0.02\nx_focus = 3.0\n'
           't_focus = 40.0\nspectrum = { type = "pierson_moskowitz", hs = 0.03, tp = 1.2 }\n')

CORPUS = [
    ("paddle-unknown", IRREGULAR + 'paddle = "wedge"\n', ["motions[0].paddle = 'wedge' is not a paddle type",
                                                           "allowed: 'piston', 'flap'"]),
    ("hs-above-miche", IRREGULAR.replace("hs = 0.03", "hs = 0.3"),
     ["motions[0]: the spectrum's Hs = 0.3 m is above the breaking limit", "Miche 1944", "0.198 m"]),
    ("band-empty", IRREGULAR + "f_min = 3.0\nf_max = 3.0\n", ["f_min = 3 is not below f_max = 3"]),
    ("components-0", IRREGULAR + "components = 0\n", ["motions[0].components = 0", "greater than or equal to 1"]),
    ("components-float", IRREGULAR + "components = 2.5\n", ["motions[0].components = 2.5"]),
    ("spectrum-unknown", IRREGULAR.replace('"jonswap"', '"bretschneider"'),
     ["motions[0].spectrum.type = 'bretschneider' is not a known type", "'jonswap', 'pierson_moskowitz', 'file'"]),
    ("spectrum-unknown-key", IRREGULAR.replace("gamma = 3.3", "gama = 3.3"),
     ["unknown key 'gama' in motions[0].spectrum", "allowed keys: gamma, hs, sigma_a, sigma_b, tp, type"]),
    ("spectrum-no-type", IRREGULAR.replace('type = "jonswap", ', ""),
     ["motions[0].spectrum: missing key 'type' (one of 'jonswap', 'pierson_moskowitz', 'file')"]),
    ("spectrum-gamma-nan", IRREGULAR.replace("gamma = 3.3", "gamma = nan"),
     ["motions[0].spectrum.gamma = nan", "finite"]),
    ("spectrum-not-a-table", IRREGULAR.replace('{ type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3 }', "3"),
     ["motions[0].spectrum = 3 must be a table"]),
    ("spectrum-file-missing", IRREGULAR.replace('type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3',
                                                'type = "file", file = "none.txt"'),
     ["motions[0]: spectrum file", "none.txt': not found", "give two columns, f [Hz] and S [m^2/Hz]"]),
    ("spectrum-file-three-columns", IRREGULAR.replace('type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3',
                                                      'type = "file", file = "s.txt"'),
     ["s.txt': line 1 ('0.5 0.1 3') is not two numbers"]),
    ("ramp-zero", IRREGULAR + "ramp_time = 0.0\n", ["ramp_time = 0 s would start the paddle away"]),
    ("period-1e-300", IRREGULAR.replace("tp = 1.2", "tp = 1e-300"), ["gives no finite wavelengths"]),
    ("period-1e300", IRREGULAR.replace("tp = 1.2", "tp = 1e300"), ["more than 1000 times the depth"]),
    ("focus-too-early", FOCUSED.replace("t_focus = 40.0", "t_focus = 2.0"),
     ["motions[0]: t_focus = 2 s is too early", "give t_focus >= 12 s"]),
    ("focus-too-high", FOCUSED.replace("amplitude = 0.02", "amplitude = 0.2"),
     ["amplitude = 0.2 m makes a wave of height about 0.4 m", "give an amplitude of at most 0.099 m"]),
    ("focus-too-far", FOCUSED.replace("x_focus = 3.0", "x_focus = 1e300").replace("t_focus = 40.0", "t_focus = 1e305"),
     ["phases", "beyond 1e10 rad"]),
    ("spectrum-file-peak-at-0", IRREGULAR.replace('type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3',
                                                  'type = "file", file = "zero.txt"'),
     ["the spectrum peaks at f = 0 Hz"]),
    ("spectrum-file-nothing-in-band", IRREGULAR.replace('type = "jonswap", hs = 0.03, tp = 1.2, gamma = 3.3',
                                                        'type = "file", file = "narrow.txt"') + "f_min = 2.0\n",
     ["the spectrum holds no energy between f_min = 2 fp and f_max = 3 fp", "widen the band"]),
    ("focus-missing-amplitude", FOCUSED.replace("amplitude = 0.02\n", ""),
     ["missing required key motions[0].amplitude"]),
]


@pytest.mark.parametrize("toml,fragments", [pytest.param(c[1], c[2], id=c[0]) for c in CORPUS])
def test_bad_wave_input_is_one_line_and_exit_2(toml, fragments, tmp_path, monkeypatch, capsys):
    """`shoal check` on each: exit status 2 and one line ``shoal: error: FILE: ...`` naming the key."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.txt").write_text("0.5 0.1 3\n0.6 0.2 4\n")
    (tmp_path / "zero.txt").write_text("0.0 1.0\n0.6 0.2\n")
    (tmp_path / "narrow.txt").write_text("0.5 0.0\n0.6 0.2\n0.7 0.0\n")
    (tmp_path / "case.toml").write_text(BASE + toml)
    try:
        status = main(["check", str(tmp_path / "case.toml")])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    assert status == 2, (status, out, err)
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("shoal: error: "), err
    for part in fragments:
        assert part in lines[0], (part, lines[0])


def test_a_wave_basin_passes_shoal_check(tmp_path, capsys):
    (tmp_path / "case.toml").write_text(BASE.replace("0.6, 0.0, 0.5", "6.0, 0.0, 0.5").replace("0.6, 0.0, 0.3",
                                                                                              "6.0, 0.0, 0.3")
                                        + IRREGULAR + FOCUSED.replace('name = "f"', 'name = "g"'))
    assert main(["check", str(tmp_path / "case.toml")]) == 0
    out, err = capsys.readouterr()
    assert "motions: p (irregular), g (focused)" in out
    assert "warning: the case makes waves (motion 'p')" in out  # the wave scheme's advice covers the new paddles


LIMITS = ["nan", "inf", "-inf", "1.7976931348623157e308", "5e-324", "-0.0", "0", "-1", "1e300", "9223372036854775807",
          "-9223372036854775808", "true", '"1"']


@pytest.mark.parametrize("key", ["depth", "hs", "tp", "gamma", "sigma_a", "sigma_b", "components", "f_min", "f_max",
                                 "seed", "ramp_time", "amplitude", "x_focus", "t_focus"])
def test_numbers_at_the_limits_give_a_case_or_one_line(key, tmp_path):
    """Every number of both tables replaced by the float and int64 limits: `load_case` gives a Case whose paddle
    has finite kinematics and peak speed, or a one-line InputError, never another exception."""
    spectrum_keys = ("hs", "tp", "gamma", "sigma_a", "sigma_b")
    for value in LIMITS:
        for table in (IRREGULAR, FOCUSED):
            text = table
            if key in spectrum_keys:
                inner = text.split("spectrum = { ")[1].split(" }")[0]
                items = dict(item.split(" = ") for item in inner.split(", "))
                items[key] = value
                text = text.replace(inner, ", ".join(f"{k} = {v}" for k, v in items.items()))
            elif f"\n{key} = " in text:
                text = "\n".join(f"{key} = {value}" if line.startswith(f"{key} = ") else line
                                 for line in text.split("\n"))
            else:
                text = text + f"{key} = {value}\n"
            (tmp_path / "c.toml").write_text(BASE + text)
            try:
                case = load_case(tmp_path / "c.toml")
            except InputError as err:
                assert "\n" not in str(err), str(err)
                continue
            m = case.motions[0]
            x, v = m.kinematics(12.345)
            assert np.all(np.isfinite(x)) and np.all(np.isfinite(v)), (key, value)
            assert math.isfinite(m.peak_speed(60.0)), (key, value)


def test_a_paddle_moves_the_wall_particles_in_a_run():
    """A 2D tank whose paddle follows an irregular sea: after a few steps its particles sit at x(0) + X(t)."""
    from shoal.runner import build_model
    from shoal.simulation import Simulation

    paddle = IrregularWaves(name="sea", spectrum=JonswapSpectrum(hs=0.02, tp=1.0), depth=0.2, components=32,
                            ramp_time=0.05)
    case = shoal.Case(name="sea", dim=2, dp=0.02, fluid=shoal.Fluid(depth=0.2, surface_level=0.2),
                      solids=[shoal.Solid(name="paddle", shape=Box(lo=(-0.06, 0, 0), hi=(0.0, 0, 0.3)), motion="sea"),
                              shoal.Solid(name="tank", shape=Tank(lo=(-0.2, 0, 0), hi=(0.8, 0, 0.3)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.8, 0, 0.2)))], motions=[paddle])
    model = build_model(case)
    p0 = case.particles()
    sim = Simulation(model, end_time=0.06).run()
    ids = model.host(model.idp)
    moving = p0.kinds[ids] == 2
    assert moving.sum() > 0
    x, v = paddle.kinematics(sim.time)
    assert abs(x[0]) > 0
    np.testing.assert_allclose(model.world_positions()[moving], p0.positions[ids[moving]] + x, atol=1e-12)
    np.testing.assert_allclose(model.world_velocities()[moving], [v] * int(moving.sum()), rtol=1e-6, atol=1e-12)
