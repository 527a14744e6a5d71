"""A floating box in waves (issue 32, must-show 4): the built-in `floating-box-2d` and the validation case
`floating-box-waves` (`shoal.validation.floating_waves`).

The analysis on exact synthetic records (incident and reflected waves at the gauges, a box that heaves, surges,
pitches and drifts); the linear theory's limits; a short run of the built-in case; the quick validation run
(``-m validation``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shoal.cases import CASES, get_case
from shoal.errors import InputError
from shoal.validation.floating_waves import (FloatingBoxWaves, body_in_waves, linear_heave_rao, long_wave_surge_rao,
                                             response_amplitudes)


def test_response_amplitudes_are_exact_on_a_drifting_sinusoid():
    """y = c + v t + a cos(omega t + phi) over whole periods: |Z| = a, arg Z = phi, v, to round-off."""
    t = np.arange(0.0, 10.0, 0.01)
    w = 2 * math.pi / 1.7
    y = 0.3 + 0.004 * t + 0.02 * np.cos(w * t + 0.7)
    a, phi, v = response_amplitudes(t, y, w, 2.0, 2.0 + 3 * 1.7)
    assert a == pytest.approx(0.02, rel=1e-10) and phi == pytest.approx(0.7, abs=1e-9)
    assert v == pytest.approx(0.004, rel=1e-9)
    with pytest.raises(ValueError, match="at least 5"):
        response_amplitudes(t, y, w, 3.0, 3.02)


def test_body_in_waves_recovers_the_rao_from_incident_and_reflected_waves():
    """Gauges in front of the box see an incident wave of amplitude A and a reflected one of 0.2 A (a partial
    standing wave: their heights vary by +-20 %); the box heaves 1.1 A, surges 2.2 A with a drift of 3 mm/s and
    pitches 0.9 kA. The separation gives A and K_r = 0.2, and the RAOs, exactly."""
    from shoal.waves import wavenumber

    T, d, A, box_x = 1.866, 0.2, 0.015, 2.0
    w = 2 * math.pi / T
    k = wavenumber(T, d)
    t = np.arange(0.0, 12.0, T / 40)
    gauges = {x: A * np.cos(w * t - k * (x - box_x)) + 0.2 * A * np.cos(w * t + k * (x - box_x) + 0.4)
              for x in (0.6, 1.0, 1.4)}
    tb = np.arange(0.0, 12.0, T / 80)
    body = dict(z=0.15 + 1.1 * A * np.cos(w * tb - 0.3), x=box_x + 0.003 * tb + 2.2 * A * np.cos(w * tb + 1.2),
                pitch=np.degrees(0.9 * k * A * np.sin(w * tb)))
    m = body_in_waves(tb, body, t, gauges, T, d, box_x, 4.0, 4.0 + 2 * T)
    assert m["amplitude"] == pytest.approx(A, rel=1e-9)
    assert m["reflection"] == pytest.approx(0.2, rel=1e-9)
    assert m["heave_rao"] == pytest.approx(1.1, rel=1e-9)
    assert m["surge_rao"] == pytest.approx(2.2, rel=1e-9)
    assert m["pitch_ratio"] == pytest.approx(0.9, rel=1e-9)
    assert m["drift_velocity"] == pytest.approx(0.003, rel=1e-9)
    assert max(np.ptp(g) for g in gauges.values()) / min(np.ptp(g) for g in gauges.values()) > 1.2


def test_linear_heave_rao_tends_to_one_in_long_waves():
    """The potential-flow RAO of the validation's box: 1 within 0.5 % at kd = 0.05; in shallow water the Haskind
    exciting force is the hydrostatic rho g B A (b33 -> rho g B^2 / (2 sqrt(g d))) within 1 %; 1.023 at the
    validation's kd = 0.5."""
    from shoal.waves import GRAVITY

    d, B, T = 0.2, 0.2, 0.05
    for kd, tol in ((0.05, 0.005), (0.1, 0.01)):
        k = kd / d
        w = math.sqrt(GRAVITY * k * math.tanh(kd))
        r = linear_heave_rao(w, B, T, d)
        assert r["rao"] == pytest.approx(1.0, abs=tol)
        assert r["exciting"] == pytest.approx(1.0, abs=0.01)
        assert r["b33"] == pytest.approx(1000 * 9.81 * B * B / (2 * math.sqrt(9.81 * d)), rel=0.01)
    k = 0.5 / d
    r = linear_heave_rao(math.sqrt(GRAVITY * k * math.tanh(0.5)), B, T, d)
    assert r["rao"] == pytest.approx(1.023, abs=1e-3) and r["kd"] == pytest.approx(0.5, rel=1e-9)


def test_long_wave_surge_is_the_water_excursion():
    """The surge limit is coth kd for a vanishing draft and the draft-average of the excursion otherwise."""
    assert long_wave_surge_rao(2.5, 0.2, 0.0) == pytest.approx(1 / math.tanh(0.5))
    zs = np.linspace(-0.05, 0.0, 20001)
    avg = np.mean(np.cosh(2.5 * (zs + 0.2)) / math.sinh(0.5))
    assert long_wave_surge_rao(2.5, 0.2, 0.05) == pytest.approx(avg, rel=1e-6)


def test_floating_box_case_is_built_in_and_refuses_bad_boxes():
    """`floating-box-2d` is listed; a box that capsizes (a square of density 500), sinks, sits on a gauge or
    behind the damping zone is refused in one line."""
    assert "floating-box-2d" in CASES
    case = get_case("floating-box-2d", dp=0.02)
    box = case.solids[-1]
    assert box.name == "box" and box.floating.density == 500.0 and case.damping
    assert box.shape.lo[2] == pytest.approx(0.4 - 0.05)  # at its floating draft
    for kw, msg in ((dict(box_beam=0.1), "capsizes"), (dict(box_density=1200.0), "does not float"),
                    (dict(gauges_x=[3.0]), "lies on the box"), (dict(zone_start=2.5), "beyond the box"),
                    (dict(box_x=7.0), "outside the flume")):
        with pytest.raises(InputError, match=msg) as err:
            get_case("floating-box-2d", dp=0.02, **kw)
        assert "\n" not in str(err.value)


def test_floating_box_case_runs_and_the_box_moves(tmp_path):
    """A few hundred steps of a short flume at a coarse dp: ``body_box.csv`` is written, the box moves (it
    settles on its draft), and stays near where it was put."""
    from shoal import run_case

    case = get_case("floating-box-2d", dp=0.025, length=2.5, box_x=1.5, zone_start=1.8, gauges_x=[0.5, 1.0],
                    end_time=1.0, body_interval=0.005)
    run_case(case, tmp_path / "run", plot=False, max_steps=250, handle_signals=False)
    lines = (tmp_path / "run" / "body_box.csv").read_text().splitlines()
    head = lines[0].split(",")
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    assert len(rows) > 5 and np.all(np.isfinite(rows))
    z, x = rows[:, head.index("z")], rows[:, head.index("x")]
    assert np.ptp(z) > 1e-5 and abs(z[-1] - z[0]) < 0.01 and abs(x[-1] - 1.5) < 0.01
    assert (tmp_path / "run" / "gauge_x0.5.csv").exists()


@pytest.mark.validation
def test_quick_validation_run(tmp_path):
    """The quick run (dp = 0.02 m): heave RAO within 10 % of linear theory, surge within 15 % of the water's
    excursion, drift down-wave."""
    case = FloatingBoxWaves()
    res = case.run(True, "cpu", tmp_path)
    figs, passed = case.compare(res)
    for m in res.metrics:
        print(m.name, m.value, m.note)
    assert passed, [m.name for m in res.metrics if m.passed is False]
