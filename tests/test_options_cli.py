"""Input validation: SPHOptions and the command line.

Bad input must give one clear line naming what is wrong and what is
allowed: `InputError` from the Python API, ``shoal: error: ...`` on stderr
and exit status 2 from the command line, never a traceback.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from shoal.cli import main
from shoal.errors import InputError, ShoalError
from shoal.options import SPHOptions
from shoal.physics.spec import SchemeSpec

SRC = Path(__file__).resolve().parents[1] / "src"


@pytest.mark.parametrize("key,value,expected", [
    ("kernel", "gaussian", ["kernel", "'gaussian'", "'wendland'", "'cubic'"]),
    ("viscosity", "sps", ["viscosity", "'sps'", "'artificial'", "'laminar'"]),
    ("density_diffusion", "antuono", ["density_diffusion", "'none'", "'molteni'", "'fourtakas'"]),
    ("integrator", "rk4", ["integrator", "'rk4'", "'verlet'", "'symplectic'", "'predictor_corrector'"]),
    ("precision", "float16", ["precision", "'float16'", "'float32'", "'float64'"]),
    ("cfl", 2, ["cfl", "2", "0 < cfl <= 1"]),
    ("cfl", 0.0, ["cfl", "> 0"]),
    ("delta", -1, ["delta", "-1", ">= 0"]),
    ("alpha", float("nan"), ["alpha", "finite"]),
    ("alpha", "lots", ["alpha", "'lots'", "number"]),
    ("nu", -1e-6, ["nu", ">= 0"]),
    ("coef_h", 0, ["coef_h", "> 0"]),
    ("coef_sound", float("inf"), ["coef_sound", "finite"]),
    ("xsph", 1.5, ["xsph", "0 <= xsph <= 1"]),
    ("fixed_dt", 0.0, ["fixed_dt", "> 0"]),
    ("cells_per_support", 4, ["cells_per_support", "1, 2 or 3"]),
    ("shepard_every", 2.5, ["shepard_every", "integer >= 0"]),
    ("mls_every", -1, ["mls_every", "integer >= 0"]),
    ("verlet_euler_every", True, ["verlet_euler_every", "integer"]),
])
def test_options_reject_bad_values(key, value, expected):
    with pytest.raises(InputError) as info:
        SPHOptions(**{key: value})
    msg = str(info.value)
    assert "\n" not in msg
    for part in expected:
        assert part in msg, (part, msg)
    assert isinstance(info.value, (ShoalError, ValueError))


def test_options_reject_inconsistent_combinations():
    with pytest.raises(InputError, match="shepard_every and mls_every"):
        SPHOptions(shepard_every=20, mls_every=30)
    with pytest.raises(InputError, match="verlet_euler_every = 0"):
        SPHOptions(verlet_euler_every=0, integrator="verlet")
    # ... which the other integrators do not use
    assert SPHOptions(verlet_euler_every=0, integrator="symplectic").verlet_euler_every == 0


def test_options_defaults_and_boundaries_accepted():
    o = SPHOptions()
    assert (o.kernel, o.viscosity, o.density_diffusion, o.precision) == (
        "wendland", "artificial", "fourtakas", "float32")
    assert o.integrator in ("verlet", "symplectic", "predictor_corrector")
    assert o.cfl == 0.2 and o.cells_per_support == 2 and o.fixed_dt is None
    for ok in (dict(cfl=1.0), dict(alpha=0.0), dict(delta=0.0), dict(xsph=1.0), dict(nu=0.0),
               dict(cells_per_support=1), dict(cells_per_support=3), dict(fixed_dt=1e-5), dict(mls_every=30)):
        SPHOptions(**ok)


def test_options_are_frozen():
    o = SPHOptions()
    with pytest.raises(AttributeError):
        o.kernel = "cubic"


def test_from_dict_rejects_unknown_keys_and_round_trips():
    with pytest.raises(InputError) as info:
        SPHOptions.from_dict({"kernel": "cubic", "bogus": 1, "cfll": 0.1})
    msg = str(info.value)
    assert "bogus" in msg and "cfll" in msg and "allowed" in msg and "kernel" in msg and "cfl" in msg
    o = SPHOptions(kernel="cubic", viscosity="laminar", nu=1e-3, xsph=0.5, mls_every=30, precision="float64")
    assert SPHOptions.from_dict(o.to_dict()) == o
    with pytest.raises(InputError, match="kernel"):
        SPHOptions.from_dict({"kernel": "gaussian"})


def test_scheme_spec_key_distinguishes_compiled_choices():
    base = SPHOptions()
    keys = {SchemeSpec.from_options(o, d).key for o, d in [
        (base, 2), (base, 3), (SPHOptions(precision="float64"), 2), (SPHOptions(kernel="cubic"), 2),
        (SPHOptions(viscosity="laminar"), 2), (SPHOptions(density_diffusion="none"), 2),
        (SPHOptions(tensile_correction=True), 2), (SPHOptions(xsph=0.5), 2), (SPHOptions(cells_per_support=1), 2)]}
    assert len(keys) == 9
    # run-time constants do not change the specialisation
    assert SchemeSpec.from_options(SPHOptions(alpha=0.5, cfl=0.3, delta=0.0), 2) == SchemeSpec.from_options(base, 2)


# ----------------------------------------------------------------------------- CLI

def _cli(argv):
    """Run the CLI in-process; returns the exit status (returned or raised)."""
    try:
        return main(argv)
    except SystemExit as exc:  # argparse errors exit through SystemExit(2)
        return exc.code


@pytest.mark.parametrize("argv,words", [
    (["run", "nope"], ["'nope'", "dam-break-2d", "still-water-3d"]),
    (["run", "--dp", "-1"], ["--dp", "positive", "-1"]),
    (["run", "--dp", "0"], ["--dp", "positive"]),
    (["run", "--dp", "nan"], ["--dp", "positive"]),
    (["run", "--dp", "abc"], ["--dp", "number", "abc"]),
    (["run", "--dp", "1"], ["dp", "too coarse"]),
    (["run", "still-water-2d", "--dp", "0.4"], ["dp", "too coarse"]),
    (["run", "--end-time", "-2"], ["--end-time", "positive"]),
    (["run", "--precision", "float16"], ["float16", "float32", "float64"]),
    (["run", "--integrator", "rk4"], ["rk4", "verlet"]),
    (["run", "--kernel", "gaussian"], ["gaussian", "wendland"]),
    (["run", "--bogus"], ["--bogus"]),
    (["run", "--option", "alpha"], ["--option", "'alpha'", "KEY=VALUE"]),
    (["run", "--option", "bogus=1"], ["--option", "'bogus'", "allowed keys", "wall_pressure"]),
    (["run", "--option", "alpha=lots"], ["--option", "alpha", "'lots'", "number"]),
    (["run", "--option", "xsph=true"], ["xsph", "true", "number"]),
    (["run", "--option", "wall_pressure=dbc"], ["wall_pressure", "'dbc'", "'dynamic'", "'adami'"]),
    (["run", "tidal-bore", "--option", "shepard_every=20"], ["shepard_every and mls_every"]),
    (["run", "--resume", "runs/x", "--option", "alpha=0.02"], ["--option", "cannot be given"]),
    (["--bogus"], ["--bogus"]),
    (["frobnicate"], ["frobnicate"]),
])
def test_cli_bad_input_is_one_line_exit_2(capsys, argv, words):
    status = _cli(argv)
    out, err = capsys.readouterr()
    assert status == 2
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("shoal: error: ")
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert out == ""  # nothing ran, nothing was announced


def test_cli_cases_lists_builtin_cases(capsys):
    assert _cli(["cases"]) == 0
    out, err = capsys.readouterr()
    names = [line.split()[0] for line in out.splitlines() if line.strip()]
    assert {"dam-break-2d", "dam-break-3d", "still-water-2d", "still-water-3d"} <= set(names)
    assert err == ""
    # each case has a one-line description
    assert all(len(line.split(None, 1)) == 2 for line in out.splitlines())


def test_cli_info_and_help(capsys):
    assert _cli(["info"]) == 0
    out, _ = capsys.readouterr()
    assert "cpu" in out and "shoal" in out
    assert _cli([]) == 0
    out, _ = capsys.readouterr()
    assert "run" in out and "cases" in out


def test_module_entry_point_reports_bad_case_without_traceback(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, "-m", "shoal", "run", "nope", "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("shoal: error: ") and "'nope'" in lines[0]
    assert "Traceback" not in proc.stderr
    assert proc.stdout == ""
    assert not (tmp_path / "o").exists()  # nothing was written


def test_cli_option_sets_any_sph_option(tmp_path, capsys):
    """--option KEY=VALUE (repeatable) changes an SPH option of a built-in case or a case file, as the case
    file's [options] table does: the run's resolved case holds the new values, the rest unchanged."""
    import json

    out = tmp_path / "run"
    argv = ["run", "tidal-bore", "--param", "dim=2", "--dp", "0.02", "--end-time", "0.002", "--no-progress",
            "--no-plot", "--out", str(out), "--option", "alpha=0.02", "--option", "wall_pressure=adami"]
    assert _cli(argv) == 0
    opts = json.loads((out / "resolved.json").read_text())["options"]
    assert opts["alpha"] == 0.02 and opts["wall_pressure"] == "adami"
    assert opts["mls_every"] == 30 and opts["kernel"] == "cubic"  # the case's own scheme otherwise
    assert _cli(["run", str(out / "case.toml"), "--end-time", "0.002", "--no-progress", "--no-plot",
                 "--out", str(tmp_path / "again"), "--option", "alpha=0.05"]) == 0
    assert json.loads((tmp_path / "again" / "resolved.json").read_text())["options"]["alpha"] == 0.05
