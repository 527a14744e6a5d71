"""Warnings about numerics that damp waves (`shoal.advice`)."""

import shoal
from shoal.advice import wave_scheme_warnings
from shoal.cases import dam_break_2d, wave_flume_2d, wave_flume_3d
from shoal.cli import main
from shoal.options import SPHOptions


def test_a_wave_case_on_the_default_scheme_is_warned_about():
    """A flume with a piston paddle and the default scheme (alpha = 0.1, coef_h = 1, wall friction):
    one warning naming each damping setting and the wave flumes' options; the built-in flumes
    (their wave scheme) and a dam break (no paddle) get none."""
    w = wave_scheme_warnings(wave_flume_2d(options=SPHOptions()))
    assert len(w) == 1
    for part in ("motion 'piston'", "alpha = 0.1", "coef_h = 1", "visco_bound_factor = 1", "viscosity = 'laminar'",
                 "coef_h = 1.5"):
        assert part in w[0], (part, w[0])
    assert wave_scheme_warnings(wave_flume_2d()) == []
    assert wave_scheme_warnings(wave_flume_3d()) == []
    assert wave_scheme_warnings(dam_break_2d()) == []
    laminar = SPHOptions(viscosity="laminar", visco_bound_factor=1.0, coef_h=1.5)  # laminar: no wall friction
    assert wave_scheme_warnings(wave_flume_2d(options=laminar)) == []


def test_check_and_run_print_the_warning(tmp_path, capsys):
    """`shoal check` lists the warning with the case's figures; `shoal run` prints it on stderr and
    keeps it in run.log."""
    case = wave_flume_2d(dp=0.04, end_time=0.01, options=SPHOptions())
    path = tmp_path / "flume.toml"
    shoal.write_case(case, path)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "warning: the case makes waves" in out
    assert main(["run", str(path), "--out", str(tmp_path / "run"), "--no-plot", "--no-progress"]) == 0
    err = capsys.readouterr().err
    assert err.count("shoal: warning: the case makes waves") == 1
    assert "the case makes waves" in (tmp_path / "run" / "run.log").read_text()


def test_fast_fluid_and_walls_are_warned_about():
    """Above 0.1 c0 the fluid compresses by more than 1 % (Monaghan 1994): a fluid region starting
    that fast, or a wall moving that fast, gets one warning each; no built-in case gets one."""
    from shoal.advice import case_warnings
    from shoal.cases import CASES, get_case
    from shoal.motions import ConstantVelocity

    case = dam_break_2d()
    c0 = case.sound_speed
    fast = case.model_copy(update={"fluids": [f.model_copy(update={"velocity": (0.2 * c0, 0.0, 0.0)})
                                              for f in case.fluids]})
    (w,) = case_warnings(fast)
    assert w.startswith("fluids[0] starts at") and "above 0.1 c0" in w
    wall = case.model_copy(update={"motions": [ConstantVelocity(name="gate", velocity=(0.0, 0.0, 0.5 * c0))]})
    (w,) = case_warnings(wall)
    assert w.startswith("motion 'gate' reaches") and "Mach 0.5" in w
    for name in CASES:
        assert case_warnings(get_case(name)) == wave_scheme_warnings(get_case(name)), name
