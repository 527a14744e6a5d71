"""The sluice gate and the broad-crested weir (issue 33, must-shows 3 and 5; `shoal.validation.sluice_gate`,
`shoal.validation.weir`): their hydraulic references checked against the energy equation they come from, the
cases' geometry and `shoal check` line, and the SPH runs behind the validation marker."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from shoal.validation.sluice_gate import CC, free_flow_discharge_coefficient
from shoal.validation.weir import C_IDEAL, critical_discharge

G = 9.81


@pytest.mark.parametrize("a, y1", [(0.06, 0.3), (0.09, 0.29), (0.02, 0.5)])
def test_sluice_discharge_coefficient_is_the_energy_equation(a, y1):
    """Henderson's Cd = Cc / sqrt(1 + Cc a / y1) is the q that carries the energy y1 + q^2 / (2 g y1^2) upstream
    unchanged to the vena contracta's y2 = Cc a, solved here by root finding."""
    y2 = CC * a
    q = brentq(lambda q: (y1 + q * q / (2 * G * y1 * y1)) - (y2 + q * q / (2 * G * y2 * y2)), 1e-9, 10.0)
    assert q / (a * math.sqrt(2 * G * y1)) == pytest.approx(free_flow_discharge_coefficient(a, y1), rel=1e-9)


@pytest.mark.parametrize("head", [0.05, 0.1, 0.3])
def test_critical_discharge_is_the_most_a_head_can_pass(head):
    """q = (2/3)^(3/2) sqrt(g) H^(3/2) is the largest y sqrt(2 g (H - y)) over the depth y (critical flow:
    the least energy for the discharge), at y = 2H/3; and C = q / (sqrt(2g) H^(3/2)) = 0.3849."""
    res = minimize_scalar(lambda y: -y * math.sqrt(2 * G * (head - y)), bounds=(0, head), method="bounded",
                          options={"xatol": 1e-12})
    assert -res.fun == pytest.approx(critical_discharge(head), rel=1e-9)
    assert res.x == pytest.approx(2 * head / 3, rel=1e-5)
    assert C_IDEAL == pytest.approx(0.3849, abs=1e-4)


def test_steady_measures_reads_the_gauges_over_the_window(tmp_path):
    """`steady_measures` from records written as the probes write them: the discharge is the counted volume's
    change over the window over its length, y2 the mean of the jet's gauges at 3 a and 5 a, Cd and Cc from
    them, and the jet's profile keyed by the gauges' distance in openings, in the order of that distance; the
    samples outside the window are left out."""
    from shoal.cases.sluice_gate import JET_GAUGES
    from shoal.validation.sluice_gate import WINDOW, profile_note, steady_measures

    a, q, y1 = 0.06, 0.085, 0.3
    t = np.round(np.arange(0.0, 6.0 + 1e-9, 0.02), 2)
    inside = (t >= WINDOW[0]) & (t <= WINDOW[1])
    for name, rate in (("upstream", 1.01 * q), ("downstream", q)):
        rows = "".join(f"{ti:g},{rate * ti:.9g},0,0,{0.25 if w else 9.0}\n" for ti, w in zip(t, inside))
        (tmp_path / f"flow_{name}.csv").write_text("time,volume,rate,rate_slab,area_slab\n" + rows)

    def gauge(name, level):
        rows = "".join(f"{ti:g},{level if w else 1.0}\n" for ti, w in zip(t, inside))
        (tmp_path / f"gauge_{name}.csv").write_text("time,level\n" + rows)

    gauge("y1", y1)
    depth = {k: (0.70 - 0.01 * k) * a for k in JET_GAUGES}
    for k, d in depth.items():
        gauge(f"jet{k:g}a", d)
    m = steady_measures(tmp_path, a)
    assert m["q_downstream"] == pytest.approx(q, rel=1e-6)
    assert m["q_upstream"] == pytest.approx(1.01 * q, rel=1e-6)
    assert m["area_downstream"] == pytest.approx(0.25)
    assert m["y1"] == pytest.approx(y1)
    assert m["y2"] == pytest.approx(0.5 * (depth[3.0] + depth[5.0]))
    assert m["cd"] == pytest.approx(q / (a * math.sqrt(2 * G * y1)), rel=1e-6)
    assert m["cc"] == pytest.approx(m["y2"] / a)
    assert list(m["jet_profile"]) == ["1", "1.5", "2", "2.5", "3", "4", "5"]
    assert list(m["jet_profile"].values()) == pytest.approx([0.70 - 0.01 * k for k in JET_GAUGES])
    assert profile_note(m) == "; y / a at 1, 1.5, 2, 2.5, 3, 4, 5 a: 0.690, 0.685, 0.680, 0.675, 0.670, 0.660, 0.650"


def test_the_gate_opening_is_the_gap_between_the_walls_surfaces():
    """The gate's lowest row of particles sits half a spacing above the opening a, as the bed's top row sits
    half a spacing below z = 0: the gap between the walls' surfaces (half a spacing outside their particles) is
    a. Its lip is flat for more than a spacing, then bevelled."""
    from shoal.cases.sluice_gate import sluice_gate_2d

    dp, a = 0.01, 0.06
    p = sluice_gate_2d(dp=dp, opening=a).particles()
    gate = p.body == p.body_names.index("gate")
    bed = p.body == p.body_names.index("bed")
    z = p.positions[:, 2]
    assert z[gate].min() == pytest.approx(a + dp / 2)
    assert z[bed].max() == pytest.approx(-dp / 2)
    assert np.count_nonzero(gate & np.isclose(z, a + dp / 2)) == 2


def test_shoal_check_says_the_inlet_holds_its_level():
    from shoal.cases.sluice_gate import sluice_gate_2d
    from shoal.check import check_case

    text = "\n".join(check_case(sluice_gate_2d(dp=0.015)))
    assert "open boundary reservoir: x = 0 m" in text
    assert "holds the level 0.3 m (velocity from the Riemann invariant, mean over 3 s)" in text


@pytest.mark.validation
def test_sluice_gate_quick():
    """Issue 33, must-show 3 (`shoal validate sluice-gate --quick`, dp = 0.01 m, about 3 min on 2 cores): Cd
    and the contracted depth within 5 % of Henderson's for a = 0.06 and 0.09 m."""
    _passes("sluice-gate")


@pytest.mark.validation
def test_weir_quick():
    """Issue 33, must-show 5 (`shoal validate weir --quick`, dp = 0.01 m): C within 5 % of 0.3849."""
    _passes("weir")


def _passes(name):
    import tempfile

    from shoal.validation import VALIDATION_CASES

    case = VALIDATION_CASES[name]
    with tempfile.TemporaryDirectory() as tmp:
        res = case.run(True, "cpu", tmp)
        _, passed = case.compare(res)
    for m in res.metrics:
        print(m.name, m.value_text, m.verdict, m.note)
    assert passed
