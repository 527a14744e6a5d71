"""Paddles with ``order = 2`` (issue 31): the second-order correction of `shoal.waves.second_order` added to
the first-order signal, ramped by r(t)^2, in the kinematics every backend reads; the case file's key."""

from __future__ import annotations

import numpy as np
import pytest

from shoal.motions import FlapWavemaker, FocusedWaves, IrregularWaves, PistonWavemaker
from shoal.waves import JonswapSpectrum, regular_second_order, second_order_paddle

SEA = JonswapSpectrum(hs=0.04, tp=1.2)


@pytest.mark.parametrize("first,second,x2", [
    (PistonWavemaker(name="p", height=0.04, period=1.2, depth=0.25),
     PistonWavemaker(name="p", height=0.04, period=1.2, depth=0.25, order=2),
     lambda: regular_second_order(0.04, 1.2, 0.25, "piston")),
    (FlapWavemaker(name="f", height=0.04, period=1.2, depth=0.25, hinge=0.05),
     FlapWavemaker(name="f", height=0.04, period=1.2, depth=0.25, hinge=0.05, order=2),
     lambda: regular_second_order(0.04, 1.2, 0.25, "flap", 0.05)),
    (IrregularWaves(name="i", depth=0.25, spectrum=SEA, components=24),
     IrregularWaves(name="i", depth=0.25, spectrum=SEA, components=24, order=2),
     lambda: second_order_paddle(IrregularWaves(name="i", depth=0.25, spectrum=SEA, components=24).wave_components)),
], ids=["piston", "flap", "irregular"])
def test_the_second_order_paddle_adds_r_squared_x2(first, second, x2):
    """After the ramp the excursion is X1 + X2 exactly; during it X1 + r^2 X2; velocity and acceleration are
    its derivatives (central differences)."""
    c = x2()
    tr = second.wave_paddle().ramp_end
    for t in (tr + 0.37, tr + 2.9):
        a, b = first.excursion(t), second.excursion(t)
        assert b[0] - a[0] == pytest.approx(float(c.displacement(t)), abs=1e-15)
        assert b[1] - a[1] == pytest.approx(float(c.velocity(t)), abs=1e-14)
    t = 0.5 * tr
    r = second.envelope(t)
    assert second.excursion(t)[0] - first.excursion(t)[0] == pytest.approx(r * r * float(c.displacement(t)),
                                                                           abs=1e-15)
    h = 1e-6
    for t in (0.3 * tr, 0.8 * tr, tr + 1.0):
        x = [second.excursion(t + s)[0] for s in (-h, h)]
        v = [second.excursion(t + s)[1] for s in (-h, h)]
        assert (x[1] - x[0]) / (2 * h) == pytest.approx(second.excursion(t)[1], rel=1e-5, abs=1e-9)
        assert (v[1] - v[0]) / (2 * h) == pytest.approx(second.excursion(t)[2], rel=1e-4, abs=1e-7)


def test_a_second_order_piston_moves_its_particles_by_the_corrected_excursion():
    p = PistonWavemaker(name="p", height=0.04, period=1.2, depth=0.25, order=2)
    x0 = np.array([[0.0, 0.0, 0.1]])
    for t in (0.5, 3.3):
        x, u, _ = p.point_kinematics(x0, t)
        assert x[0, 0] == pytest.approx(p.excursion(t)[0], abs=1e-15)
        assert u[0, 0] == pytest.approx(p.excursion(t)[1], abs=1e-15)


def test_order_round_trips_through_toml_and_a_bad_order_is_one_line(tmp_path, monkeypatch, capsys):
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.casefile import dumps_case, load_case, write_case
    from shoal.cli import main
    from shoal.geometry.shapes import Box, Tank

    sea = FocusedWaves(name="sea", depth=0.25, amplitude=0.02, x_focus=1.0, t_focus=10.0, components=16, order=2,
                       spectrum=SEA)
    case = Case(name="o2", dim=2, dp=0.05, end_time=0.01, fluid=Fluid(depth=0.25, surface_level=0.25),
                motions=[sea], solids=[Solid(name="paddle", shape=Box(lo=(-0.2, 0, 0), hi=(0, 0, 0.5)), motion="sea"),
                                       Solid(name="tank", shape=Tank(lo=(-0.3, 0, 0), hi=(2.0, 0, 0.5)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, 0.25)))])
    path = write_case(case, tmp_path / "c.toml")
    back = load_case(path)
    assert isinstance(back.motions[0], FocusedWaves) and back.motions[0].order == 2
    monkeypatch.chdir(tmp_path)
    text = dumps_case(back)
    assert "order = 2" in text
    (tmp_path / "bad.toml").write_text(text.replace("order = 2", "order = 3"))
    try:
        status = main(["check", str(tmp_path / "bad.toml")])
    except SystemExit as exc:
        status = exc.code
    err = capsys.readouterr().err
    assert status == 2 and len(err.splitlines()) == 1 and "motions[0].order = 3: must be 1 or 2" in err, err
