"""Relaxation zones (`shoal.relaxation`, `shoal.physics.relaxation`): the weight, the targets against linear
theory, one relaxation stage on the particles, the case's checks, and zones absorbing and making waves."""

from __future__ import annotations

import math

import numpy as np
import pytest

import shoal
from shoal.errors import InputError
from shoal.geometry import Box, Tank
from shoal.motions import FocusedWaves, IrregularWaves, PistonWavemaker
from shoal.relaxation import (LinearTarget, MotionTarget, RelaxationZone, StillTarget, relaxation_weight,
                              resolve_zone, step_coefficient)
from shoal.runner import build_model
from shoal.waves import JonswapSpectrum, wavenumber

D, H, T = 0.4, 0.05, 1.2  # depth, height, period of the linear target [m, m, s]


# ------------------------------------------------------------------ the weight and the per-step coefficient
def test_weight_is_jacobsens_exponential_with_its_limits():
    xi = np.linspace(0.0, 1.0, 101)
    w = relaxation_weight(xi)
    np.testing.assert_allclose(w, (np.exp(xi**3.5) - 1.0) / (math.e - 1.0), rtol=1e-14, atol=1e-16)
    assert relaxation_weight(0.0) == 0.0 and relaxation_weight(1.0) == 1.0
    assert relaxation_weight(-0.5) == 0.0 and relaxation_weight(3.0) == 1.0  # clipped: outside, beyond the end
    assert np.all(np.diff(w) > 0)  # rises monotonically
    assert relaxation_weight(0.5) == pytest.approx(0.05378, abs=1e-5)  # gentle over the inner half
    assert relaxation_weight(1e-3) < 1e-10  # starts with zero slope (no kink where the zone begins)


def test_step_coefficient_imposes_the_target_at_w1_and_does_not_depend_on_the_step():
    assert step_coefficient(1.0, 1e-4, 1e-3) == 1.0
    assert step_coefficient(0.0, 1e-4, 1e-3) == 0.0
    for w in (0.01, 0.3, 0.9):
        half = step_coefficient(w, 0.5e-4, 1e-3)
        full = step_coefficient(w, 1e-4, 1e-3)
        assert 1.0 - (1.0 - half) ** 2 == pytest.approx(full, rel=1e-13)
        assert step_coefficient(w, 1e-3, 1e-3) == pytest.approx(w, rel=1e-14)  # dt = tau: Jacobsen's blend


# ------------------------------------------------------------------ targets against linear theory
def _airy(x, z, t, direction=1.0, phase=0.0, x0=0.0):
    """Airy's u, w, eta for the linear target (z from the still-water level), in the textbook form."""
    k = wavenumber(T, D)
    om = 2 * math.pi / T
    th = om * t - direction * k * (x - x0) + phase
    a = H / 2
    u = direction * a * om * math.cosh(k * (z + D)) / math.sinh(k * D) * math.cos(th)
    w = -a * om * math.sinh(k * (z + D)) / math.sinh(k * D) * math.sin(th)
    return u, w, a * math.cos(th)


@pytest.mark.parametrize("direction", ["+x", "-x"])
def test_linear_target_is_airys_wave(direction):
    level = 0.4
    s = 1.0 if direction == "+x" else -1.0
    zone = RelaxationZone(start=1.0, end=0.0, target=LinearTarget(height=H, period=T, depth=D, direction=direction,
                                                                   phase=0.7, origin=0.3))
    terms = resolve_zone(zone, surface_level=level)
    t = 5.0  # past the default ramp of two periods
    for x in (0.0, 0.37, 1.9):
        for z in (-0.4, -0.25, -0.01, 0.0):
            u, w = terms.velocity(x, level + z, t)
            ua, wa, eta = _airy(x, z, t, s, 0.7, 0.3)
            assert u == pytest.approx(ua, abs=1e-12) and w == pytest.approx(wa, abs=1e-12)
        assert terms.elevation(x, t) == pytest.approx(_airy(x, 0.0, t, s, 0.7, 0.3)[2], abs=1e-14)
    # above the still-water level: the velocity at z = 0; below the bed: at the bed
    assert terms.velocity(0.37, level + 0.03, t) == terms.velocity(0.37, level, t)
    assert terms.velocity(0.37, level - D - 0.1, t) == terms.velocity(0.37, level - D, t)
    # the ramp: nothing at t = 0, half way through it a half
    assert terms.velocity(0.37, level - 0.1, 0.0) == (0.0, 0.0)
    u1 = terms.velocity(0.37, level - 0.1, T)[0]
    assert u1 == pytest.approx(0.5 * (1 - math.cos(math.pi * T / (2 * T))) * _airy(0.37, -0.1, T, s, 0.7, 0.3)[0],
                               abs=1e-12)


def _jonswap_motion(**kw):
    return IrregularWaves(name="sea", spectrum=JonswapSpectrum(hs=0.05, tp=1.2), depth=D, components=64, seed=3,
                          ramp_time=2.4, **kw)


def test_irregular_target_is_the_motions_sea():
    """A zone with the motion target carries the paddle's sea: its elevation is the motion's `elevation` at the
    distance from the origin (the paddle's rest position), its w at the still-water level d eta / dt, and its
    u there sum a_n omega_n coth(k_n d) cos(theta_n)."""
    sea = _jonswap_motion()
    x0, level = -0.5, 0.4
    terms = resolve_zone(RelaxationZone(start=2.0, end=0.0, target=MotionTarget(motion="sea", origin=x0)),
                         [sea], surface_level=level)
    assert terms.count == 64 and terms.ramp_time == 2.4
    wc = sea.wave_components
    for x in (0.0, 1.3):
        for t in (3.0, 7.7):
            assert terms.elevation(x, t) == pytest.approx(float(sea.elevation(x - x0, t)), abs=1e-13)
            eps = 1e-6
            deta = (sea.elevation(x - x0, t + eps) - sea.elevation(x - x0, t - eps)) / (2 * eps)
            u, w = terms.velocity(x, level, t)
            assert w == pytest.approx(float(deta), abs=1e-8)
            th = wc.omegas * t - wc.wavenumbers * (x - x0) + wc.phases
            ua = np.sum(wc.amplitudes * wc.omegas / np.tanh(wc.wavenumbers * D) * np.cos(th))
            assert u == pytest.approx(float(ua), abs=1e-12)
    # a focused group and a paddle pushing along -x: the target travels along -x
    group = FocusedWaves(name="g", spectrum=JonswapSpectrum(hs=0.05, tp=1.2), depth=D, amplitude=0.03,
                         x_focus=2.0, t_focus=10.0, components=32, direction=(-1.0, 0.0, 0.0))
    gterms = resolve_zone(RelaxationZone(start=0.0, end=1.0, target=MotionTarget(motion="g", origin=3.0)), [group],
                          surface_level=level)
    assert gterms.sign == -1.0
    assert gterms.elevation(1.0, 10.0) == pytest.approx(0.03, rel=1e-12)  # 2 m from the paddle along -x


# ------------------------------------------------------------------ one relaxation stage on the particles
def _tank(precision="float64", relaxation=(), motions=()):
    return shoal.Case(name="rz", dim=2, dp=0.05, fluid=shoal.Fluid(depth=D, surface_level=D),
                      options=shoal.SPHOptions(precision=precision),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(2.0, 0, 0.6)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, D)), velocity=(0.3, 0, -0.1))],
                      relaxation=list(relaxation), motions=list(motions))


def _fluid(m):
    return m.host(m.kind) == 0


def test_a_stage_with_w1_sets_the_target_and_w0_changes_nothing():
    zone = RelaxationZone(start=-2.0, end=-1.0, target=LinearTarget(height=H, period=T, depth=D, phase=0.4))
    case = _tank(relaxation=[zone])
    m = build_model(case)
    terms = case.relaxation_terms()
    t = 3.7
    m.apply_relaxation(terms, t, 1e-4)  # every fluid particle lies beyond the zone's outer end: w = 1, c = 1
    pos, vel = m.world_positions(), m.world_velocities()
    fl = _fluid(m)
    target = np.array([terms[0].velocity(x, z, t) for x, z in pos[fl][:, [0, 2]]])
    assert np.max(np.abs(target)) > 0.05
    np.testing.assert_allclose(vel[fl][:, [0, 2]], target, rtol=0, atol=1e-12)
    assert np.all(vel[~fl] == 0)  # walls untouched
    # a zone wholly beyond the fluid (w = 0 everywhere it could reach): nothing changes, bitwise
    before = m.world_velocities().copy()
    far = resolve_zone(RelaxationZone(start=5.0, end=6.0, target=LinearTarget(height=H, period=T, depth=D)),
                       surface_level=D)
    m.apply_relaxation([far], t, 1e-4)
    assert np.array_equal(m.world_velocities(), before)


@pytest.mark.parametrize("precision,tol", [("float64", 1e-13), ("float32", 2e-6)])
def test_two_half_steps_equal_one_step(precision, tol):
    """Toward still water over the zone x = 0.5 .. 1.5 m (w from 0 to 1): each particle's velocity is scaled
    by (1 - w)^(dt / tau), and two steps of dt / 2 give one step of dt (the strength does not depend on the
    time step)."""
    zone = RelaxationZone(start=0.5, end=1.5, target=StillTarget(), time_scale=2e-3)
    a, b = build_model(_tank(precision)), build_model(_tank(precision))
    terms = resolve_zone(zone)
    a.apply_relaxation([terms], 1.0, 1e-3)
    b.apply_relaxation([terms], 0.9995, 0.5e-3)
    b.apply_relaxation([terms], 1.0, 0.5e-3)
    pos, va, vb = a.world_positions(), a.world_velocities(), b.world_velocities()
    fl = _fluid(a)
    expect = (1.0 - relaxation_weight((pos[fl, 0] - 0.5) / 1.0))[:, None] ** 0.5 * np.array([0.3, 0.0, -0.1])
    np.testing.assert_allclose(va[fl], expect, rtol=tol, atol=tol)
    np.testing.assert_allclose(vb[fl], va[fl], rtol=tol, atol=tol)
    inside = fl & (pos[:, 0] > 0.6)
    assert np.all(np.abs(va[inside, 0]) < 0.3 - 1e-6)  # the zone did act


# ------------------------------------------------------------------ the case: TOML, checks
def test_zones_load_from_toml_check_and_refuse_bad_ones(tmp_path):
    from shoal.check import check_case

    sea = _jonswap_motion()
    case = _tank(relaxation=[RelaxationZone(start=0.6, end=0.0, target=MotionTarget(motion="sea")),
                             RelaxationZone(start=1.4, end=2.0)], motions=[sea])
    path = tmp_path / "rz.toml"
    shoal.write_case(case, path)
    text = path.read_text()
    assert "[[relaxation]]" in text and 'type = "motion"' in text
    back = shoal.load_case(path)
    assert back.relaxation == case.relaxation
    lines = check_case(back)
    assert any("relaxation[0]: x = 0.6 .. 0 m (w = 1 at 0 m), the sea of motion 'sea'" in ln for ln in lines)
    assert any("relaxation[1]:" in ln and "still water" in ln for ln in lines)

    with pytest.raises(ValueError, match="zero length"):
        RelaxationZone(start=1.0, end=1.0)
    with pytest.raises(ValueError, match=r"relaxation\[0\]: target.motion = 'paddle' names no irregular or focused"):
        _tank(relaxation=[RelaxationZone(start=0.6, end=0.0, target=MotionTarget(motion="paddle"))],
              motions=[PistonWavemaker(name="paddle", height=H, period=T, depth=D)])
    no_level = _tank().model_copy(update={"fluid": shoal.Fluid(depth=D)})
    with pytest.raises(InputError, match="still-water level"):
        no_level.model_copy(update={"relaxation": [RelaxationZone(
            start=0.6, end=0.0, target=LinearTarget(height=H, period=T, depth=D))]}).revalidate()
    outside = _tank(relaxation=[RelaxationZone(start=5.0, end=6.0)])
    with pytest.raises(InputError, match=r"relaxation\[0\]: the zone x = 5 .. 6 m lies outside the domain"):
        check_case(outside)


@pytest.mark.parametrize("zone,message", [
    ("start = 1.0\nend = 1.0\n", "zero length"),
    ("start = 5.0\nend = 6.0\n", "lies outside the domain"),
    ('start = 0.5\nend = 0.0\ntarget = { type = "motion", motion = "nothing" }\n', "names no irregular or focused"),
])
def test_shoal_check_refuses_a_bad_zone_in_one_line(tmp_path, capsys, zone, message):
    from shoal.cli import main

    path = tmp_path / "bad.toml"
    shoal.write_case(_tank(), path)
    path.write_text(path.read_text().replace("relaxation = []\n", "") + "\n[[relaxation]]\n" + zone)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err


# ------------------------------------------------------------------ zones on a flume: making and absorbing waves
def _flume_run(dp, tmp_path, end_time, absorber=1.0):
    """A 2D flume (T = 0.7 s, d = 0.2 m, H = 0.05 m: L = 0.71 m): a linear-wave zone over its first wavelength
    (w = 1 at the left wall), two wavelengths of flume, a still-water zone `absorber` wavelengths long (w = 1
    at the right wall), and three wave gauges 0.8, 1.0 and 1.3 wavelengths from the generation zone. Returns
    the gauges' times and records {x: eta} and (L, H, T, d)."""
    from shoal.cases.wave_flume import WAVE_OPTIONS
    from shoal.probes import ProbeRecorder, WaveGauge

    d, h, period = 0.2, 0.05, 0.7
    L = 2 * math.pi / wavenumber(period, d)
    length = (3 + absorber) * L
    case = shoal.Case(name="rz-flume", dim=2, dp=dp, end_time=end_time, fluid=shoal.Fluid(depth=d, surface_level=d),
                      options=shoal.SPHOptions(**WAVE_OPTIONS[2]),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(length, 0, 0.4)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, d)))],
                      relaxation=[RelaxationZone(start=L, end=0.0,
                                                 target=LinearTarget(height=h, period=period, depth=d)),
                                  RelaxationZone(start=3 * L, end=length)])
    sim = shoal.Simulation(case)
    gauges = {}
    for f in (0.8, 1.0, 1.3):
        x = L + f * L
        rec = ProbeRecorder(WaveGauge(name=f"g{f}", x=x, z0=d - 0.1, z1=d + 0.1, interval=0.02), tmp_path, dp)
        sim.add_callback(rec, shoal.TimeInterval(0.02))
        gauges[x] = rec
    sim.run()
    records = {}
    for x, rec in gauges.items():
        rec.close()
        rows = np.array(rec.rows)
        records[x] = rows[:, 1] - d
    return rows[:, 0], records, (L, h, period, d)


def _analyse(run, periods, dp):
    """Mansard & Funke's incident height and the far zone's reflection coefficient over the last `periods`."""
    from shoal.analysis.waves import reflection_analysis

    t, records, (L, h, period, d) = run
    t1 = float(t[-1])
    r = reflection_analysis(t, records, period, d, t1 - periods * period, t1)
    err = r.incident_height / h - 1.0
    x0 = min(records)
    print(f"dp = {dp} m (H/dp = {h / dp:.1f}): incident height {r.incident_height * 1000:.2f} mm at x = {x0:.3f} m, "
          f"{(x0 - L) / L:.2f} L from the generation zone (target {h * 1000:.0f} mm: {100 * err:+.1f} %); "
          f"reflection coefficient of the absorbing zone {r.reflection_coefficient:.3f}; first-harmonic heights "
          f"at the gauges {np.round(r.gauge_heights * 1000, 2)} mm; misfit {r.residual:.3f}")
    return err, r


@pytest.fixture(scope="module")
def coarse_flume(tmp_path_factory):
    dp = 0.025
    return _analyse(_flume_run(dp, tmp_path_factory.mktemp("flume"), 5.0), 2, dp)


def test_a_linear_zone_makes_the_target_wave_quick(coarse_flume):
    """The generation zone's wave 0.8 .. 1.3 wavelengths from it, at a coarse resolution (dp = 0.025 m,
    H/dp = 2): its incident first-harmonic height (Mansard & Funke's separation, three gauges, the last two
    periods of a 5 s run) against the target H. Within 15 % here (measured: 43.8 mm, -12.4 %), where two
    particles per wave height resolve the wave coarsely (its decay along the flume and the gauges' kernel-sum
    surface included); the check at the issue's 5 % is
    `test_a_linear_zone_makes_the_target_wave` (-m validation)."""
    err, _ = coarse_flume
    assert abs(err) < 0.15


def test_a_still_water_zone_absorbs_the_wave_quick(coarse_flume):
    """The still-water zone over the flume's last wavelength (w = 1 at its end wall) reflects the wave that the
    generation zone makes: Mansard & Funke's K_r from the same run, against K_r = 1 of the bare end wall it
    replaces (a standing wave). Below 10 % at this resolution (measured: 0.042); the issue's 5 % at H/dp = 5
    with a zone two wavelengths long: `test_a_still_water_zone_reflects_less_than_5_percent` (-m validation)."""
    _, r = coarse_flume
    assert r.reflection_coefficient < 0.10


@pytest.fixture(scope="module")
def fine_flume(tmp_path_factory):
    """The flume of the quick checks at H/dp = 5 (dp = 0.01 m) with an absorbing zone two wavelengths long,
    analysed over the last four periods of a 6 s run (about 20 minutes on 2 shared cores)."""
    dp = 0.01
    return _analyse(_flume_run(dp, tmp_path_factory.mktemp("fine"), 6.0, absorber=2.0), 4, dp)


@pytest.mark.validation
def test_a_linear_zone_makes_the_target_wave(fine_flume):
    """The generation zone's incident height within 5 % of the target (the issue's figure) at H/dp = 5
    (measured: 49.35 mm against 50 mm, -1.3 %; -0.6 % with an absorbing zone one wavelength long)."""
    err, _ = fine_flume
    assert abs(err) < 0.05


@pytest.mark.validation
def test_a_still_water_zone_reflects_less_than_5_percent(fine_flume):
    """The absorbing zone's reflection coefficient (Mansard & Funke) below 5 % (the issue's figure) at
    H/dp = 5, with a zone two wavelengths long and the default time scale: measured K_r = 0.012. One
    wavelength long, the same zone reflected 0.063 (0.042 at the quick check's resolution, whose own damping
    of the wave helps)."""
    _, r = fine_flume
    assert r.reflection_coefficient < 0.05
