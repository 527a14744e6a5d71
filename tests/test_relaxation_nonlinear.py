"""Nonlinear regular-wave targets of relaxation zones (`shoal.relaxation.FentonTarget`, `StokesTarget`, solved by
raschii in `shoal.waves.nonlinear`): the target against raschii's own velocity on the compiled CPU function and
through the CUDA simulator, the closed flume's frame, the small-amplitude limit, a zone making a steep Fenton
wave in SPH, and one-line refusals of waves that do not exist."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from cuda_support import HAVE_CUDA, SIMULATOR

import shoal
from shoal.geometry import Box, Tank
from shoal.physics.relaxation import make_relaxation
from shoal.physics.spec import FLUID
from shoal.relaxation import FentonTarget, RelaxationZone, StokesTarget, resolve_zone
from shoal.waves import wavenumber

D, H, T = 0.2, 0.06, 0.7
"""A steep wave: H / L = 0.081, H = 0.62 of Miche's limit, kd = 1.69; crest 0.59 H above the still water."""
LEVEL = 0.5  # still-water level of the zones [m] (bed at 0.3 m)
ZONE = dict(start=3.0, end=2.0)  # w = 1 (the target imposed) for x <= 2 m
TARGETS = {
    "fenton": FentonTarget(height=H, period=T, depth=D, phase=0.4, origin=0.3),
    "fenton-wavelength-minus-x": FentonTarget(height=H, wavelength=0.8, depth=D, order=16, direction="-x",
                                              origin=-0.2, phase=2.0),
    "stokes": StokesTarget(height=H, period=T, depth=D, phase=-1.1),
}


def _raschii(target, x, zb, t, wet=False):
    """raschii's own (u, w) and eta of `target` at `x` [m], `zb` [m] above the bed and time `t` [s]: its wave
    (zero Eulerian current, travelling along +x at c = B_0) seen from the closed flume, that is shifted by
    the flume's current u_E (x -> x - u_E t, u -> u + u_E) and mirrored for a wave along -x, its crest put
    at the origin at t = -phase / omega."""
    wave = target.wave
    s = 1.0 if target.direction == "+x" else -1.0
    X = s * (np.asarray(x, float) - target.origin) - target.phase / wave.wavenumber - wave.current * t
    vel = np.atleast_2d(wave.model.velocity(X, zb, t, all_points_wet=wet))
    eta = wave.model.surface_elevation(X, t, include_depth=False)
    return s * (wave.current + vel[:, 0]), vel[:, 1], eta


def _relax(precision="float64"):
    """The compiled per-particle function of both backends (`shoal.physics.relaxation`) on the CPU, with the
    CPU backend's decorator, in 2D."""
    from shoal.backends.cpu import cpu_jit

    spec = types.SimpleNamespace(float_type=np.dtype(precision).type, dim=2)
    return make_relaxation(cpu_jit, spec)


def _points(target, t, n=24):
    """(x, z) [m] below the target's surface at time `t`: n columns over a wavelength inside the zone's w = 1
    part, each at 0, 30, 60, 90 and 99.9 % of the local water depth (bed to the target's surface)."""
    x = np.linspace(2.0 - target.wave.wavelength, 2.0, n)
    eta = _raschii(target, x, np.full(n, D), t)[2]
    frac = np.array([0.0, 0.3, 0.6, 0.9, 0.999])
    xs = np.repeat(x, len(frac))
    zb = (np.outer(D + eta, frac)).ravel()
    return xs, zb


def _run_relax(relax, terms, pos, t, dtype=np.float64):
    """One call of `relax` per point at weight 1 (c = 1): the velocity becomes the target's."""
    n = len(pos)
    buf = terms.buffer()
    terms.fill(t, buf)
    vel = np.zeros((n, 2), dtype)
    kind = np.full(n, FLUID, np.int8)
    p = np.asarray(pos, np.float64)
    for i in range(n):
        relax(i, p, vel, kind, terms.start, terms.inv_len, terms.sign, terms.origin, terms.level, terms.depth, 0.1,
              terms.count, buf)
    return vel


# ------------------------------------------------------------------ the target against raschii
@pytest.mark.parametrize("name", sorted(TARGETS))
def test_target_velocity_is_raschiis_on_the_cpu_function(name):
    """At points from the bed to the target's surface over a wavelength, where the zone imposes its target
    (w = 1), the compiled function's velocity is raschii's evaluation (the frame shift only added) to
    round-off: 1e-13 m/s against velocities up to 0.37 m/s (measured: 4.2e-15 at most). The host-side
    reference `RelaxationTerms.velocity` and the elevation agree alike; the float32 function within 2e-6 m/s
    (measured 1.7e-7: float32 rounding of some twenty operations)."""
    target = TARGETS[name]
    terms = resolve_zone(RelaxationZone(**ZONE, target=target), surface_level=LEVEL)
    assert terms.count == target.order + 1  # the harmonics and the current
    t = 5.3  # past the ramp of two periods
    x, zb = _points(target, t)
    vel = _run_relax(_relax(), terms, np.column_stack([x, LEVEL - D + zb]), t)
    u, w, _ = _raschii(target, x, zb, t)
    assert np.max(np.abs(u)) > 0.2 and np.max(np.abs(w)) > 0.15
    np.testing.assert_allclose(vel[:, 0], u, rtol=0, atol=1e-13)
    np.testing.assert_allclose(vel[:, 1], w, rtol=0, atol=1e-13)
    host = np.array([terms.velocity(xi, LEVEL - D + zi, t) for xi, zi in zip(x, zb)])
    np.testing.assert_allclose(host, vel, rtol=0, atol=1e-13)
    xe = x[::5]
    np.testing.assert_allclose([terms.elevation(xi, t) for xi in xe], _raschii(target, xe, np.full(len(xe), D), t)[2],
                               rtol=0, atol=1e-14)
    # float32: the same function in the working precision of float32 runs
    v32 = _run_relax(_relax("float32"), terms, np.column_stack([x, LEVEL - D + zb]), t, np.float32)
    np.testing.assert_allclose(v32, vel, rtol=0, atol=2e-6)


def test_clipping_and_ramp():
    """Above the target's crest a particle gets the velocity at the crest's height (the series hold to the
    wave's surface; a particle above it keeps the crest's), below the bed the bed's; during the ramp the
    whole target, current included, is scaled by r(t) = (1 - cos(pi t / t_r)) / 2."""
    target = TARGETS["fenton"]
    wave = target.wave
    terms = resolve_zone(RelaxationZone(**ZONE, target=target), surface_level=LEVEL)
    assert terms.level == pytest.approx(LEVEL + wave.crest, abs=1e-15) and terms.ramp_time == pytest.approx(2 * T)
    relax = _relax()
    t = 6.1
    for x in (0.4, 1.3):
        pts = [(x, LEVEL + wave.crest + 0.05), (x, LEVEL + wave.crest), (x, LEVEL - D - 0.05), (x, LEVEL - D)]
        v = _run_relax(relax, terms, pts, t)
        assert np.array_equal(v[0], v[1]) and np.array_equal(v[2], v[3])
        # raschii's series at the crest's height (above its local surface unless x is under a crest)
        u, w, _ = _raschii(target, np.array([x]), np.array([D + wave.crest]), t, wet=True)
        assert v[1, 0] == pytest.approx(u[0], abs=1e-13) and v[1, 1] == pytest.approx(w[0], abs=1e-13)
    x = np.array([0.9])
    half = _run_relax(relax, terms, [(0.9, LEVEL - 0.05)], T)[0]
    u, w, _ = _raschii(target, x, np.array([D - 0.05]), T)
    r = 0.5 * (1 - math.cos(math.pi * T / (2 * T)))
    assert half[0] == pytest.approx(r * u[0], abs=1e-13) and half[1] == pytest.approx(r * w[0], abs=1e-13)


def test_the_frame_of_a_closed_flume():
    """The target carries no mean mass flux (a flume with walls at both ends): the volume flux through a
    section, int_{-d}^{eta} u dz averaged over a period (Gauss-Legendre in z, the periodic trapezoid rule in
    t: exact to 1e-15 for these smooth periodic integrands) is zero against the Stokes transport c_S d =
    4.0e-3 m^2/s that raschii's own frame carries: below 1e-9 m^2/s for Fenton's wave (raschii's Newton
    tolerance; measured 1.6e-11), and within 2 % of the transport for Stokes' fifth-order wave, whose
    velocity and flux Q are series truncated at fifth order (measured 0.8 %; 4.7 % at third order). It
    travels at c = Q / d with the requested period (to 1e-10), its current u_E is minus the Stokes drift,
    and crest - trough is the height (to the 1e-8 d at which raschii's Newton iteration stops)."""
    for target in (TARGETS["fenton"], TARGETS["stokes"]):
        wave = target.wave
        assert wave.period == pytest.approx(T, rel=1e-10)
        assert wave.celerity == pytest.approx(float(wave.model.Q) / D, rel=1e-14)
        assert wave.current == pytest.approx(-wave.stokes_drift, rel=1e-14) and wave.current < -0.01
        # raschii's Newton iteration stops at residuals of 1e-8 (lengths in units of the depth)
        assert wave.crest - wave.trough == pytest.approx(H, abs=1e-8 * D)
        ts = np.arange(64) * wave.period / 64
        gz, gw = np.polynomial.legendre.leggauss(40)
        fluxes = []
        for t in ts:
            eta = float(wave.elevation(0.0, t))
            z = -D + (gz + 1) * (eta + D) / 2
            u, _ = wave.velocity(0.0, z, t)
            fluxes.append(np.sum(gw * u) * (eta + D) / 2)
        transport = wave.stokes_drift * D  # what raschii's frame, without the current, carries into the flume
        assert transport > 3.9e-3
        assert abs(np.mean(fluxes)) < (1e-9 if target.type == "fenton" else 2e-2 * transport)


def test_small_waves_are_stokes_second_order_theory():
    """As H -> 0 the nonlinear waves become Airy's, with Stokes' second-order harmonic and the return flow of
    Airy's Stokes transport: at H = 1 mm (eps = kH/2 = 4.4e-3) the wavelength, the first harmonic's velocity
    at the still-water level a omega coth(kd) and elevation a = H/2 (Airy), the second harmonic's elevation
    a_2 = (k H^2 / 16) cosh(kd) (2 + cosh 2kd) / sinh^3(kd) (Stokes' second order; Dean & Dalrymple 1991,
    ch. 11) and the current u_E = -g a^2 / (2 c d) = -a omega coth(kd) a / (2d) (the mass transport E / (rho c)
    of linear theory returned; Longuet-Higgins 1953, Fenton 1990), each to 5 eps^2 = 1e-4: the next
    corrections are O(eps^2), with coefficients below one here (measured: 1.8e-5 at most)."""
    h = 1e-3
    k = wavenumber(T, D)
    a = h / 2
    eps = k * a
    airy = a * (2 * math.pi / T) / math.tanh(k * D)
    a2 = h * h * k / 16 * math.cosh(k * D) * (2 + math.cosh(2 * k * D)) / math.sinh(k * D) ** 3
    for cls in (FentonTarget, StokesTarget):
        wave = cls(height=h, period=T, depth=D).wave
        tol = 5 * eps**2
        assert wave.wavenumber == pytest.approx(k, rel=tol)
        assert wave.velocities[0] == pytest.approx(airy, rel=tol)
        assert wave.amplitudes[0] == pytest.approx(a, rel=tol)
        assert wave.amplitudes[1] == pytest.approx(a2, rel=tol)
        assert wave.current == pytest.approx(-airy * a / (2 * D), rel=tol)


def test_stokes_and_fenton_agree_where_stokes_theory_holds():
    """The steep wave of these tests (kd = 1.69, eps = kH/2 = 0.25) by both theories: the fifth-order
    expansion's error is of order eps^6 = 2.7e-4 in the dispersion and eps^5 = 1e-3 in the profile (measured:
    wavelength 3.2e-4 and crest 2.0e-3 apart); bounds 1e-3 and 1e-2."""
    f, s = TARGETS["fenton"].wave, TARGETS["stokes"].wave
    assert s.wavelength == pytest.approx(f.wavelength, rel=1e-3)
    assert s.crest == pytest.approx(f.crest, rel=1e-2)
    assert f.crest / H == pytest.approx(0.59, abs=0.01)  # a steep wave: crest 0.59 H, not linear theory's 0.5 H


# ------------------------------------------------------------------ the CUDA function
def _cuda_and_cpu(precision):
    from numba import cuda

    from shoal.backends.cuda import cuda_device_jit, make_for_each

    spec = types.SimpleNamespace(float_type=np.dtype(precision).type, dim=2)
    run = make_for_each(make_relaxation(cuda_device_jit, spec))
    out = []
    for target in TARGETS.values():
        terms = resolve_zone(RelaxationZone(**ZONE, target=target), surface_level=LEVEL)
        t = 5.3
        x, zb = _points(target, t, n=8)
        pos = np.column_stack([x, LEVEL - D + zb])
        cpu = _run_relax(_relax(precision), terms, pos, t, np.dtype(precision))
        buf = terms.buffer()
        terms.fill(t, buf)
        vel = cuda.to_device(np.zeros((len(pos), 2), np.dtype(precision)))
        kind = cuda.to_device(np.full(len(pos), FLUID, np.int8))
        run(len(pos), (cuda.to_device(pos), vel, kind, terms.start, terms.inv_len, terms.sign, terms.origin,
                       terms.level, terms.depth, 0.1, terms.count, cuda.to_device(buf)))
        out.append((vel.copy_to_host(), cpu))
    return out


@pytest.mark.skipif(not HAVE_CUDA, reason="needs a GPU or NUMBA_ENABLE_CUDASIM=1 (test_cuda_under_the_simulator "
                    "runs it under the simulator in a child process)")
@pytest.mark.parametrize("precision,tol", [("float64", 1e-14), ("float32", 2e-6)])
def test_cuda_function_gives_the_cpu_velocities(precision, tol):
    """The same per-particle function compiled for CUDA (one thread per point, the CUDA backend's loop) gives
    the CPU function's velocities for the three targets: float64 to 1e-14 m/s (libm against CUDA's or
    Python's math, a few ulp; measured under the simulator 2.2e-16), float32 to 2e-6 m/s (the float32
    rounding of some twenty operations on velocities of 0.37 m/s; measured 3.0e-8)."""
    for vel, cpu in _cuda_and_cpu(precision):
        assert np.max(np.abs(cpu)) > 0.1
        np.testing.assert_allclose(vel, cpu, rtol=0, atol=tol)


def test_cuda_under_the_simulator():
    """`test_cuda_function_gives_the_cpu_velocities` under Numba's CUDA simulator in a child process (a few
    seconds: 40 points per target)."""
    if HAVE_CUDA:
        pytest.skip("CUDA (or the simulator) is available here: the test runs in this process")
    here = Path(__file__).resolve()
    src = str(Path(shoal.__file__).resolve().parents[1])
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    env["PYTHONPATH"] = os.pathsep.join([src] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    proc = subprocess.run([sys.executable, "-m", "pytest", str(here), "-q", "-p", "no:cacheprovider", "-k",
                           "cuda_function_gives"], cwd=here.parents[1], env=env, capture_output=True, text=True,
                          timeout=600)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0 and "2 passed" in out, out[-3000:]


# ------------------------------------------------------------------ bad inputs: one line each
@pytest.mark.parametrize("cls,kw,message", [
    (FentonTarget, dict(height=0.11, wavelength=0.8), r"^height = 0.11 m is past the breaking limit of a wave in 0.2 m "
     r"of water \(L = 0.8 m\): H_max = 0.142 L tanh\(kd\) = 0.104 m \(Miche 1944\)"),
    (FentonTarget, dict(height=0.1, wavelength=0.8), r"^raschii's Fenton stream-function wave \(N = 10\) of H = 0.1 m, "
     r"L = 0.8 m in d = 0.2 m did not converge \(.*\) at H / H_max = 0.96 of the breaking limit H_max = 0.142 L "
     r"tanh\(kd\) = 0.104 m \(Miche 1944\): too close to breaking"),
    (StokesTarget, dict(height=0.11, period=0.7), r"^height = 0.11 m is above the breaking limit H_max = 0.142 L "
     r"tanh\(kd\) = 0.0962 m \(Miche 1944\) of a 0.7 s wave"),
    (StokesTarget, dict(height=0.05, period=2.0, depth=0.1), r"^Stokes theory \(order 5\) fails .* second crest in "
     r"the trough; use type = \"fenton\""),
    (FentonTarget, dict(height=0.05), r"^give the wave's period or its wavelength \(one of the two\)"),
    (FentonTarget, dict(height=0.05, period=0.7, wavelength=0.8), r"^give the wave's period or its wavelength"),
])
def test_waves_that_do_not_exist_are_refused_in_one_line(cls, kw, message):
    from pydantic import ValidationError

    kw = dict(dict(depth=D), **kw)
    with pytest.raises(ValidationError) as info:
        cls(**kw)
    (err,) = info.value.errors()
    text = str(err["ctx"]["error"])
    assert "\n" not in text
    assert re.search(message, text), text


@pytest.mark.parametrize("target,message", [
    ('{ type = "fenton", height = 0.1, wavelength = 0.8, depth = 0.2 }', "too close to breaking"),
    ('{ type = "fenton", height = 0.11, wavelength = 0.8, depth = 0.2 }', "past the breaking limit"),
    ('{ type = "stokes", height = 0.05, period = 0.7, depth = 0.2, order = 6 }', "less than or equal to 5"),
    ('{ type = "fenton", height = 0.05, depth = 0.2 }', "period or its wavelength"),
])
def test_shoal_check_refuses_a_bad_nonlinear_target_in_one_line(tmp_path, capsys, target, message):
    from shoal.cli import main

    path = tmp_path / "bad.toml"
    shoal.write_case(_tank(), path)
    path.write_text(path.read_text().replace("relaxation = []\n", "") + f"\n[[relaxation]]\nstart = 0.8\nend = 0.0\n"
                    f"target = {target}\n")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err


def _tank(relaxation=()):
    return shoal.Case(name="rz", dim=2, dp=0.05, fluid=shoal.Fluid(depth=D, surface_level=D),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(2.0, 0, 0.4)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, D)))], relaxation=list(relaxation))


def test_nonlinear_zones_load_from_toml_and_check(tmp_path):
    from shoal.check import check_case

    case = _tank([RelaxationZone(start=0.8, end=0.0, target=TARGETS["fenton"]),
                  RelaxationZone(start=1.2, end=2.0, target=StokesTarget(height=0.03, wavelength=0.8, depth=D,
                                                                           direction="-x"))])
    path = tmp_path / "nl.toml"
    shoal.write_case(case, path)
    text = path.read_text()
    assert 'type = "fenton"' in text and 'type = "stokes"' in text
    back = shoal.load_case(path)
    assert back.relaxation == case.relaxation
    lines = check_case(back)
    assert any("relaxation[0]:" in ln and "Fenton stream-function wave of order 10, H = 0.06 m, T = 0.7 s" in ln
               for ln in lines), lines
    assert any("relaxation[1]:" in ln and "Stokes wave of order 5" in ln and "L = 0.8 m" in ln for ln in lines)


# ------------------------------------------------------------------ a zone making a steep Fenton wave in SPH
def _fenton_flume(dp, tmp_path, end_time, flume=1.0, absorber=1.0, gauges=(0.25, 0.5, 0.75)):
    """A 2D flume in d = 0.2 m: a zone making the steep Fenton wave of these tests (H = 0.06 m, T = 0.7 s,
    N = 10: L = 0.743 m) over its first wavelength (w = 1 at the left wall), `flume` wavelengths of flume, a
    still-water zone `absorber` wavelengths long (w = 1 at the right wall), and wave gauges `gauges`
    wavelengths from the generation zone. Returns {fraction: (t, eta)} and the wave."""
    from shoal.cases.wave_flume import WAVE_OPTIONS
    from shoal.probes import ProbeRecorder, WaveGauge

    target = FentonTarget(height=H, period=T, depth=D)
    L = target.wave.wavelength
    length = (1 + flume + absorber) * L
    case = shoal.Case(name="fenton-flume", dim=2, dp=dp, end_time=end_time,
                      fluid=shoal.Fluid(depth=D, surface_level=D), options=shoal.SPHOptions(**WAVE_OPTIONS[2]),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(length, 0, 0.4)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, D)))],
                      relaxation=[RelaxationZone(start=L, end=0.0, target=target),
                                  RelaxationZone(start=(1 + flume) * L, end=length)])
    sim = shoal.Simulation(case)
    recs = {}
    for f in gauges:
        rec = ProbeRecorder(WaveGauge(name=f"g{f}", x=(1 + f) * L, z0=D - 0.1, z1=D + 0.1, interval=0.01),
                            tmp_path, dp)
        sim.add_callback(rec, shoal.TimeInterval(0.01))
        recs[f] = rec
    sim.run()
    out = {}
    for f, rec in recs.items():
        rec.close()
        rows = np.array(rec.rows)
        out[f] = (rows[:, 0], rows[:, 1] - D)
    return out, target.wave


def _heights(records, periods):
    """Per gauge: the crest-to-trough height (the mean over the last `periods` periods of each period's
    maximum minus minimum) and the mean level over them [m]."""
    out = {}
    for f, (t, eta) in records.items():
        t1 = t[-1]
        per = [eta[(t > t1 - (m + 1) * T + 1e-9) & (t <= t1 - m * T + 1e-9)] for m in range(periods)]
        out[f] = (float(np.mean([p.max() - p.min() for p in per])), float(np.mean(np.concatenate(per))))
    return out


def _report(dp, heights):
    mean_h = np.mean([h for h, _ in heights.values()])
    print(f"dp = {dp} m (H/dp = {H / dp:.1f}): heights " + ", ".join(
        f"{h * 1000:.1f} mm ({h / H - 1:+.1%}) at {f} L" for f, (h, _) in heights.items())
        + f"; mean {mean_h / H - 1:+.1%}; mean levels " + ", ".join(f"{m * 1000:+.2f}" for _, m in heights.values())
        + " mm")
    return mean_h


def test_a_fenton_zone_makes_the_steep_wave_quick(tmp_path):
    """A zone makes the steep Fenton wave (H = 0.06 m, T = 0.7 s in 0.2 m: H / L = 0.081, 0.62 of Miche's
    limit) at a coarse resolution, dp = 0.025 m (H/dp = 2.4, 8 particles in the depth; 5 s of flow, about
    50 s on one core). Over the last two periods, at gauges 0.25, 0.5 and 0.75 wavelengths from the zone:

    * the crest-to-trough height, averaged over the three gauges (two of them a quarter wavelength apart,
      where the partial standing wave of the absorber's reflection, K_r of about 0.05 at this resolution,
      modulates the height in opposite senses), within 10 % of the target: measured -4.2 %, -0.8 %, -3.7 %
      (mean -2.9 %); a linear check at this H/dp allows 15 % further from its zone
      (`tests/test_relaxation.py`), the check at 5 % is the validation test below;
    * the mean level within 3 mm of the still-water level (measured +1.3 to +1.9 mm; +0.05 mm in still
      water): the target carries no mean mass flux. A target with the Stokes transport c_S d = 4.0e-3 m^2/s
      (a linear target of the same height, measured: +8.0 to +9.5 mm) piles up about c_S d t / (2 L) = 9 mm
      in this flume over the run."""
    records, wave = _fenton_flume(0.025, tmp_path, 5.0)
    heights = _heights(records, 2)
    mean_h = _report(0.025, heights)
    assert abs(mean_h / H - 1) < 0.10
    assert all(abs(m) < 3e-3 for _, m in heights.values())


@pytest.mark.validation
def test_a_fenton_zone_makes_the_steep_wave(tmp_path):
    """The quick check's flume at dp = 0.0125 m (H/dp = 4.8, 16 particles in the depth), two wavelengths of
    flume and an absorbing zone two wavelengths long, 6 s of flow: the crest-to-trough height at gauges 0.5
    to 1.25 wavelengths from the zone within 5 % of the target H (the issue's figure for the linear zone)
    at each gauge, and the mean level within 2 mm of the still water (about 9 min on one core). Measured:
    +1.6 %, -1.8 %, +1.1 %, -3.1 % (mean -0.6 %); mean levels +1.2 to +1.4 mm (as at the quick check's
    resolution: a small set-up not explained yet, a seventh of what the Stokes transport would pile up)."""
    records, wave = _fenton_flume(0.0125, tmp_path, 6.0, flume=2.0, absorber=2.0, gauges=(0.5, 0.75, 1.0, 1.25))
    heights = _heights(records, 2)
    _report(0.0125, heights)
    assert all(abs(h / H - 1) < 0.05 for h, _ in heights.values())
    assert all(abs(m) < 2e-3 for _, m in heights.values())
