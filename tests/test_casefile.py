"""TOML case files: round trip of the built-in cases, one-line errors for
malformed files, the command line's exit codes, and case files as data.

Every malformed file must give one `InputError` line that names the file,
the key path as the user wrote it (``solids[0].shape.lo``, ``options``
... ``cfl``) and something about what is allowed. Run with ``pytest -s`` to
see the messages.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from shoal.casefile import dumps_case, load_case, write_case
from shoal.cases import CASES, get_case
from shoal.cli import main
from shoal.errors import InputError

# ----------------------------------------------------------------------------- round trip

ROUND_TRIP = {
    "dam-break-2d": dict(dp=0.01),
    "dam-break-3d": dict(dp=0.02),
    "dam-break-dualsphysics": dict(dp=0.03),
    "spheric-benchmark": dict(dp=0.04),
    "still-water-2d": dict(dp=0.05),
    "still-water-3d": dict(dp=0.05),
    "wave-flume-2d": dict(dp=0.04),
    "wave-flume-3d": dict(dp=0.08),
    "wave-basin-2d": dict(dp=0.04, length=4.5),
    # 0.03 is refused by the case itself ("too coarse: ... use dp <= 0.025 m")
    "tidal-bore": dict(dp=0.025),
    "tidal-bore-piers": dict(dp=0.025),
    "rip-current": dict(dp=0.075),
    "floating-box-2d": dict(dp=0.025),
    "moored-box-3d": dict(dp=0.05),
    "open-channel-2d": dict(dp=0.04),
    "open-channel-3d": dict(dp=0.05, length=0.6, gauges_x=[0.3]),
    "sluice-gate-2d": dict(dp=0.015),
    "weir-2d": dict(dp=0.02),
}

PARTICLE_ARRAYS = ("positions", "kinds", "velocities", "body", "region", "spacing")



def _round_trip_param(name):
    return pytest.param(name, id=name)


def test_round_trip_table_covers_every_builtin_case():
    assert set(ROUND_TRIP) == set(CASES)


def _assert_same_case(case, case2):
    p, p2 = case.particles(), case2.particles()
    assert len(p) == len(p2) and p.n_fluid == p2.n_fluid > 0
    for name in PARTICLE_ARRAYS:
        np.testing.assert_array_equal(getattr(p2, name), getattr(p, name), err_msg=name)
    assert case2.resolved() == case.resolved()


@pytest.mark.parametrize("name", [_round_trip_param(n) for n in ROUND_TRIP])
def test_builtin_case_round_trips_through_toml(name, tmp_path):
    case = get_case(name, **ROUND_TRIP[name])
    path = write_case(case, tmp_path / "c.toml")
    assert path == tmp_path / "c.toml"
    assert not (tmp_path / "c.toml.tmp").exists()  # written atomically
    case2 = load_case(path)
    _assert_same_case(case.model_copy(update={"parameters": {}}), case2)  # parameters: a comment (issue 30)


@pytest.mark.parametrize("name,kwargs", [
    ("tidal-bore", dict(dp=0.025, half=True)),          # symmetry plane, open ymax face
    ("rip-current", dict(dp=0.075, boundary="repulsive")),  # dp/2 repulsive particles
])
def test_builtin_variants_round_trip_uncommented(name, kwargs, tmp_path):
    case = get_case(name, **kwargs)
    text = dumps_case(case, commented=False)
    assert "#" not in text
    path = tmp_path / "c.toml"
    path.write_text(text, encoding="utf-8")
    _assert_same_case(case, load_case(path))


def test_dumped_case_is_commented_and_ordered():
    text = dumps_case(get_case("dam-break-2d", dp=0.01), file_name="db.toml")
    assert text.startswith("# shoal case file (TOML)")
    assert "shoal run db.toml" in text
    assert "dp = 0.01  # particle spacing [m]" in text
    assert text.index("name = ") < text.index("[fluid]") < text.index("[[solids]]") < text.index("[[fluids]]")


# ----------------------------------------------------------------------------- a minimal valid case

BASE = """\
name = "mini"
dim = 2
dp = 0.02
end_time = 0.5

[fluid]
depth = 0.2

[options]
cfl = 0.2

[output]
interval = 0.1

[domain]
lo = [-0.2, 0.0, -0.2]
hi = [1.2, 0.0, 0.8]

[[motions]]
name = "paddle"
type = "piston"
height = 0.02
period = 1.0
depth = 0.2

[[solids]]
name = "tank"
shape = { type = "tank", lo = [0.0, 0.0, 0.0], hi = [1.0, 0.0, 0.6] }

[[solids]]
name = "paddle"
motion = "paddle"
shape = { type = "box", lo = [0.1, 0.0, 0.02], hi = [0.14, 0.0, 0.4] }

[[fluids]]
shape = { type = "box", lo = [0.2, 0.0, 0.0], hi = [0.8, 0.0, 0.2] }
velocity = [0.0, 0.0, 0.0]
"""

PADDLE_SHAPE = 'shape = { type = "box", lo = [0.1, 0.0, 0.02], hi = [0.14, 0.0, 0.4] }'


def edit(*pairs, prepend="", append=""):
    """BASE with each (old, new) replaced once (old must be there)."""
    text = BASE
    for old, new in pairs:
        assert text.count(old) >= 1, old
        text = text.replace(old, new, 1)
    return prepend + text + append


def solid1(shape):
    """BASE with the paddle's shape (solids[1].shape) replaced by `shape`."""
    return edit((PADDLE_SHAPE, f"shape = {shape}"))


def test_base_case_loads_and_generates(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(BASE)
    case = load_case(path)
    assert case.name == "mini" and case.dim == 2 and case.dp == 0.02
    assert [s.name for s in case.solids] == ["tank", "paddle"]
    assert case.motions[0].type == "piston"
    counts = case.particles().counts()
    assert counts["fluid"] == 300 and counts["fixed"] > 0 and counts["moving"] > 0


# (id, text, stage, fragments that must all be in the message)
# stage "load": load_case raises; "particles": the file loads, case.particles() raises.
MALFORMED = [
    # --- unknown keys
    ("unknown-top-level-key", edit(prepend='colour = "blue"\n'), "load",
     ["unknown key 'colour'", "top level", "allowed keys:", "dp"]),
    ("unknown-key-fluid", edit(("depth = 0.2\n\n[options]", "depth = 0.2\ndept = 0.3\n\n[options]")), "load",
     ["unknown key 'dept'", "in fluid", "allowed keys:", "depth, gravity"]),
    ("unknown-key-options", edit(("cfl = 0.2", "cfl = 0.2\ncfll = 0.1")), "load",
     ["options", "'cfll'", "allowed keys:", "cfl, coef_h"]),
    ("unknown-key-solid", edit(('name = "tank"', 'name = "tank"\nboundry = "dynamic"')), "load",
     ["unknown key 'boundry'", "solids[0]", "allowed keys:", "boundary, fit_surface, floating, layers"]),
    ("fit-surface-on-a-tank", edit(('name = "tank"', 'name = "tank"\nfit_surface = true')), "load",
     ["solids[0]", "fit_surface = true is for a bed", "slope or bathymetry", "tank"]),
    ("fit-surface-not-a-bool", edit(('name = "tank"', 'name = "tank"\nfit_surface = "yes"')), "load",
     ["solids[0].fit_surface"]),
    ("unknown-key-shape", edit(('type = "tank",', 'type = "tank", radius = 1.0,')), "load",
     ["unknown key 'radius'", "solids[0].shape", "allowed keys: hi, lo, open, type"]),
    ("unknown-key-motion", edit(("height = 0.02", "height = 0.02\namplitude = 0.1")), "load",
     ["unknown key 'amplitude'", "motions[0]", "allowed keys:", "period"]),
    ("unknown-key-output", edit(("interval = 0.1", "interval = 0.1\nevery = 2")), "load",
     ["unknown key 'every'", "in output", "allowed keys: interval"]),
    ("unknown-key-domain", edit(("[domain]\n", "[domain]\nmid = [0.5, 0.0, 0.3]\n")), "load",
     ["unknown key 'mid'", "in domain", "allowed keys: hi, lo"]),
    # --- missing required keys
    ("missing-dp", edit(("dp = 0.02\n", "")), "load", ["missing required key dp"]),
    ("missing-name", edit(('name = "mini"\n', "")), "load", ["missing required key name"]),
    ("missing-fluids", BASE[:BASE.index("[[fluids]]")], "load", ["missing required key fluids"]),
    ("missing-shape-lo", edit(('type = "tank", lo = [0.0, 0.0, 0.0], ', 'type = "tank", ')), "load",
     ["missing required key solids[0].shape.lo"]),
    ("empty-fluids", BASE[:BASE.index("[[fluids]]")].replace("end_time = 0.5", "end_time = 0.5\nfluids = []"),
     "load", ["fluids = []", "at least 1 value"]),
    ("missing-depth-and-u_max", edit(("depth = 0.2\n\n[options]", "rho0 = 1000.0\n\n[options]")), "load",
     ["fluid needs a depth", "u_max"]),
    # --- wrong types
    ("dp-string", edit(("dp = 0.02", 'dp = "fast"')), "load", ["dp = 'fast'", "must be a number"]),
    ("dim-4", edit(("dim = 2", "dim = 4")), "load", ["dim = 4", "2 or 3"]),
    ("dim-2.5", edit(("dim = 2", "dim = 2.5")), "load", ["dim = 2.5", "must be the integer 2 or 3"]),
    ("layers-2.5", edit(('name = "tank"', 'name = "tank"\nlayers = 2.5')), "load",
     ["solids[0].layers = 2.5", "must be an integer"]),
    ("layers-0", edit(('name = "tank"', 'name = "tank"\nlayers = 0')), "load",
     ["solids[0].layers = 0", "greater than or equal to 1"]),
    ("layers-bool", edit(('name = "tank"', 'name = "tank"\nlayers = true')), "load",
     ["solids[0].layers", "must be an integer"]),
    # NB: the message says a *key* velocity[2] is missing; it does not say "3 values"
    ("velocity-2-components", edit(("velocity = [0.0, 0.0, 0.0]", "velocity = [0.0, 0.0]")), "load",
     ["fluids[0].velocity", "too few values"]),
    ("velocity-4-components", edit(("velocity = [0.0, 0.0, 0.0]", "velocity = [0.0, 0.0, 0.0, 1.0]")), "load",
     ["fluids[0].velocity", "at most 3 values"]),
    ("lo-with-string", edit(('type = "tank", lo = [0.0, 0.0, 0.0]', 'type = "tank", lo = [0.0, "zero", 0.0]')),
     "load", ["solids[0].shape.lo[1] = 'zero'", "must be a number"]),
    ("gravity-as-table", edit(("depth = 0.2\n\n[options]", "depth = 0.2\ngravity = { z = -9.81 }\n\n[options]")),
     "load", ["fluid.gravity", "must be an array"]),
    ("shape-as-string", solid1('"box"'), "load", ["solids[1].shape = 'box'", "must be a table"]),
    ("options-not-table", edit(("[options]\ncfl = 0.2\n", ""), ('name = "mini"', 'name = "mini"\noptions = 3')),
     "load", ["options", "must be a table"]),
    ("description-int", edit(("end_time = 0.5", "end_time = 0.5\ndescription = 5")), "load",
     ["description = 5", "must be a valid string"]),
    # --- out-of-range values
    ("dp-negative", edit(("dp = 0.02", "dp = -1")), "load", ["dp = -1", "greater than 0"]),
    ("end_time-zero", edit(("end_time = 0.5", "end_time = 0")), "load", ["end_time = 0", "greater than 0"]),
    ("output-interval-negative", edit(("interval = 0.1", "interval = -0.1")), "load",
     ["output.interval = -0.1", "greater than 0"]),
    ("options-cfl-2", edit(("cfl = 0.2", "cfl = 2")), "load", ["options", "cfl = 2", "0 < cfl <= 1"]),
    ("options-kernel-gauss", edit(("cfl = 0.2", 'cfl = 0.2\nkernel = "gauss"')), "load",
     ["options", "kernel = 'gauss'", "choose one of 'wendland', 'cubic'"]),
    ("options-cfl-string", edit(("cfl = 0.2", 'cfl = "0.1"')), "load", ["options", "cfl = '0.1'", "must be a number"]),
    ("options-shepard-bool", edit(("cfl = 0.2", "cfl = 0.2\nshepard_every = true")), "load",
     ["options", "shepard_every", "must be an integer"]),
    ("options-precision", edit(("cfl = 0.2", 'cfl = 0.2\nprecision = "float16"')), "load",
     ["options", "precision = 'float16'", "'float32', 'float64'"]),
    ("options-two-filters", edit(("cfl = 0.2", "cfl = 0.2\nshepard_every = 10\nmls_every = 10")), "load",
     ["options", "shepard_every and mls_every", "choose one"]),
    ("boundary-sticky", edit(('name = "tank"', 'name = "tank"\nboundary = "sticky"')), "load",
     ["solids[0].boundary = 'sticky'", "must be 'dynamic' or 'repulsive'"]),
    ("tank-open-face", edit(('type = "tank",', 'type = "tank", open = ["roof"],')), "load",
     ["solids[0].shape.open[0] = 'roof'", "'xmin'", "'top' or 'bottom'"]),
    ("domain-hi-below-lo", edit(("hi = [1.2, 0.0, 0.8]", "hi = [1.2, 0.0, -0.5]")), "load",
     ["domain", "hi.z = -0.5", "must be above lo.z"]),
    ("cylinder-radius-zero", solid1('{ type = "cylinder", axis = "y", center = [0.5, 0.3], radius = 0 }'), "load",
     ["solids[1].shape.radius = 0", "greater than 0"]),
    # --- shapes
    ("shape-type-unknown", edit(('type = "tank"', 'type = "bowl"')), "load",
     ["solids[0].shape.type = 'bowl'", "not a known type", "allowed: 'box', 'tank'", "'mesh'"]),
    ("shape-without-type", edit(('type = "tank", ', "")), "load",
     ["solids[0].shape", "missing key 'type'", "'box', 'tank'"]),
    ("box-hi-below-lo", edit(("hi = [0.8, 0.0, 0.2]", "hi = [0.1, 0.0, 0.2]")), "load",
     ["fluids[0].shape", "hi.x = 0.1 is below lo.x = 0.2", "hi must be >= lo"]),
    ("tank-flat", edit(("hi = [1.0, 0.0, 0.6]", "hi = [1.0, 0.0, 0.0]")), "load",
     ["solids[0].shape", "hi.z = 0.0 must be above lo.z"]),
    ("prism-2-vertices", solid1('{ type = "prism", axis = "y", vertices = [[0.1, 0.0], [0.2, 0.1]] }'), "load",
     ["solids[1].shape.vertices", "at least 3 values"]),
    ("prism-collinear", solid1('{ type = "prism", axis = "y", vertices = [[0.0, 0.1], [0.5, 0.1], [1.0, 0.1]] }'),
     "load", ["solids[1].shape", "zero area", "3 corners not on one line"]),
    ("prism-repeated-vertex", solid1('{ type = "prism", axis = "y", vertices = [[0.1, 0.2], [0.1, 0.2], [0.1, 0.2]] }'),
     "load", ["solids[1].shape", "zero area"]),
    ("bathymetry-two-sources",
     solid1('{ type = "bathymetry", profile = { x = [0.0, 1.0], z = [0.0, 0.1] }, file = "bed.csv" }'), "load",
     ["solids[1].shape", "exactly one of profile, grid, file or function", "got profile, file"]),
    ("bathymetry-profile-x-decreasing",
     solid1('{ type = "bathymetry", profile = { x = [0.0, 0.5, 0.4], z = [0.0, 0.1, 0.2] } }'), "load",
     ["solids[1].shape.profile", "x must increase strictly"]),
    ("bathymetry-profile-lengths",
     solid1('{ type = "bathymetry", profile = { x = [0.0, 0.5, 1.0], z = [0.0, 0.1] } }'), "load",
     ["solids[1].shape.profile", "one z per x"]),
    # --- motions
    ("motion-undefined", edit(('motion = "paddle"', 'motion = "wiggle"')), "load",
     ["solids[1].motion = 'wiggle'", "names no motion", "motions: paddle"]),
    ("motion-duplicate-name",
     edit(append='\n[[motions]]\nname = "paddle"\ntype = "constant_velocity"\nvelocity = [0.1, 0.0, 0.0]\n'),
     "load", ["motion names must be unique", "repeated: paddle"]),
    ("piston-negative-period", edit(("period = 1.0", "period = -1.0")), "load",
     ["motions[0].period = -1.0", "greater than 0"]),
    ("motion-type-unknown", edit(('type = "piston"', 'type = "wobble"')), "load",
     ["motions[0].type = 'wobble'", "not a known type", "'constant_velocity', 'piston'"]),
    ("motion-without-type", edit(('type = "piston"\n', "")), "load",
     ["motions[0]", "missing key 'type'", "'constant_velocity', 'piston'"]),
    ("motion-start-negative",
     edit(append='\n[[motions]]\nname = "push"\ntype = "constant_velocity"\nvelocity = [0.1, 0.0, 0.0]\n'
                 'start = -1.0\n'), "load", ["motions[1].start = -1.0", "greater than or equal to 0"]),
    # --- nan / inf
    ("dp-nan", edit(("dp = 0.02", "dp = nan")), "load", ["dp = nan", "must be a finite number"]),
    ("lo-inf", edit(("lo = [0.2, 0.0, 0.0]", "lo = [0.2, 0.0, inf]")), "load",
     ["fluids[0].shape.lo[2] = inf", "must be a finite number"]),
    ("depth-inf", edit(("depth = 0.2\n\n[options]", "depth = inf\n\n[options]")), "load",
     ["fluid.depth = inf", "must be a finite number"]),
    ("gravity-nan", edit(("depth = 0.2\n\n[options]", "depth = 0.2\ngravity = [0.0, 0.0, nan]\n\n[options]")),
     "load", ["fluid.gravity[2] = nan", "must be a finite number"]),
    ("options-cfl-nan", edit(("cfl = 0.2", "cfl = nan")), "load", ["options", "cfl = nan", "finite number > 0"]),
    ("dp-overflow-to-inf", edit(("dp = 0.02", "dp = 1e400")), "load", ["dp = inf", "must be a finite number"]),
    # --- not TOML at all
    ("invalid-toml", edit(("dp = 0.02", "dp = ")), "load", ["not valid TOML", "line 3"]),
    ("table-redefined", edit(("[output]\ninterval = 0.1\n", "[output]\ninterval = 0.1\n[output]\n")), "load",
     ["not valid TOML"]),
    # --- valid file, impossible geometry (raised by case.particles())
    ("fluid-inside-solid", solid1('{ type = "box", lo = [0.15, 0.0, -0.1], hi = [0.9, 0.0, 0.5] }'), "particles",
     ["holds no particle", "inside solids"]),
    ("fluid-box-thinner-than-dp", edit(("hi = [0.8, 0.0, 0.2]", "hi = [0.2, 0.0, 0.2]")), "particles",
     ["holds no particle", "thinner than dp"]),
]


def test_enough_malformed_files():
    assert len(MALFORMED) >= 30
    assert len({m[0] for m in MALFORMED}) == len(MALFORMED)
    assert len({m[1] for m in MALFORMED}) == len(MALFORMED)  # every variant differs


def _error_of(path, stage):
    if stage == "load":
        with pytest.raises(InputError) as info:
            load_case(path)
    else:
        case = load_case(path)  # the file itself is valid
        with pytest.raises(InputError) as info:
            case.particles()
    return str(info.value)


@pytest.mark.parametrize("text,stage,fragments", [pytest.param(*m[1:], id=m[0]) for m in MALFORMED])
def test_malformed_case_file_gives_one_line_error(text, stage, fragments, tmp_path, request):
    path = tmp_path / "case.toml"
    path.write_text(text, encoding="utf-8")
    msg = _error_of(path, stage)
    print(f"\n[{request.node.callspec.id}] {msg}")
    assert "\n" not in msg and "\r" not in msg, msg
    if stage == "load":
        assert msg.startswith(f"{path}: "), msg  # names the file
    assert "Traceback" not in msg
    for part in fragments:
        assert part in msg, (part, msg)


def test_several_problems_are_counted(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(edit(("dp = 0.02", "dp = -1"), ("end_time = 0.5", "end_time = -1")))
    msg = _error_of(path, "load")
    print("\n" + msg)
    assert "\n" not in msg
    assert "dp = -1" in msg and "(and 1 more problem)" in msg


def test_empty_and_binary_files(tmp_path):
    empty = tmp_path / "empty.toml"
    empty.write_text("")
    msg = _error_of(empty, "load")
    assert "missing required key name" in msg and "more problems" in msg and "\n" not in msg
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00bad")
    msg = _error_of(binary, "load")
    assert "not a text file" in msg and "\n" not in msg


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found") as info:
        load_case(tmp_path / "nope.toml")
    assert "nope.toml" in str(info.value)


# Defects found by this file and fixed since: kept as regression tests.

def test_prism_collinear_inexact_vertices_rejected(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(solid1('{ type = "prism", axis = "y", vertices = [[0.1, 0.0], [0.2, 0.1], [0.3, 0.2]] }'))
    msg = _error_of(path, "load")
    assert "zero area" in msg


def test_boolean_is_not_a_number(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(edit(("end_time = 0.5", "end_time = true")))
    _error_of(path, "load")


def test_string_is_not_a_number(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(edit(("dp = 0.02", 'dp = "0.02"')))
    _error_of(path, "load")


# ----------------------------------------------------------------------------- command line

def _cli(argv):
    try:
        return main(argv)
    except SystemExit as exc:  # argparse
        return exc.code


def _one_error_line(err):
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("shoal: error: "), err
    assert "Traceback" not in err
    return lines[0]


@pytest.fixture
def bad_toml(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(edit(("cfl = 0.2", "cfl = 2")))
    return path


@pytest.fixture
def good_toml(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(BASE)
    return path


def test_cli_check_bad_file_exit_2(bad_toml, capsys):
    assert _cli(["check", str(bad_toml)]) == 2
    out, err = capsys.readouterr()
    line = _one_error_line(err)
    print("\n" + line)
    assert str(bad_toml) in line and "cfl = 2" in line
    assert out == ""


def test_cli_check_missing_file_exit_2(tmp_path, capsys):
    missing = tmp_path / "missing.toml"
    assert _cli(["check", str(missing)]) == 2
    out, err = capsys.readouterr()
    line = _one_error_line(err)
    print("\n" + line)
    assert "missing.toml" in line and "not found" in line


def test_cli_run_bad_file_exit_2_and_writes_nothing(bad_toml, tmp_path, capsys):
    out_dir = tmp_path / "o"
    assert _cli(["run", str(bad_toml), "--out", str(out_dir), "--no-progress", "--no-plot"]) == 2
    out, err = capsys.readouterr()
    _one_error_line(err)
    assert out == ""
    assert not out_dir.exists() or not any(out_dir.iterdir())


def test_cli_check_good_file(good_toml, capsys):
    assert _cli(["check", str(good_toml)]) == 0
    out, err = capsys.readouterr()
    assert "particles:" in out
    assert "case mini" in out
    assert err == ""


def test_cli_check_rejects_param_with_a_file(good_toml, capsys):
    assert _cli(["check", str(good_toml), "--param", "depth=0.3"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "--param" in line and "built-in" in line


def test_cli_new_writes_a_loadable_file_and_does_not_overwrite(tmp_path, capsys):
    path = tmp_path / "db.toml"
    assert _cli(["new", "dam-break-2d", "-o", str(path)]) == 0
    out, err = capsys.readouterr()
    assert str(path) in out and err == ""
    case = load_case(path)
    assert case.name == get_case("dam-break-2d").name
    assert case.resolved() == get_case("dam-break-2d").model_copy(update={"parameters": {}}).resolved()
    before = path.read_bytes()
    assert _cli(["new", "dam-break-2d", "-o", str(path), "--dp", "0.01"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "exists" in line and "--force" in line
    assert path.read_bytes() == before
    assert _cli(["new", "dam-break-2d", "-o", str(path), "--dp", "0.01", "--force"]) == 0
    capsys.readouterr()
    assert load_case(path).dp == 0.01


def test_cli_new_wave_flume_2d(tmp_path, capsys):
    path = tmp_path / "wf.toml"
    assert _cli(["new", "wave-flume-2d", "-o", str(path)]) == 0
    assert load_case(path).dim == 2


def test_none_in_parameters_is_writable(tmp_path):
    case = load_case(_write(tmp_path, BASE))
    case = case.model_copy(update={"parameters": {"dp": 0.02, "width": None}})
    write_case(case, tmp_path / "out.toml", commented=False)  # uncommented (a checkpoint's copy): the record kept
    assert load_case(tmp_path / "out.toml").resolved()["parameters"] == {"dp": 0.02}


def test_a_commented_case_file_records_the_parameters_only_as_a_comment(tmp_path):
    """`shoal new` writes the built-in case's parameters as comment lines, not as a table a user would
    edit to no effect (issue 30, class 7); the case it writes loads to the same case otherwise."""
    path = tmp_path / "wf.toml"
    assert _cli(["new", "wave-flume-2d", "-o", str(path)]) == 0
    text = path.read_text()
    assert "[parameters]" not in text and "parameters =" not in text
    record = [line for line in text.splitlines() if line.startswith("#   ")]
    assert "depth = 0.4" in " ".join(record) and "gauges_x = [1.0, 2.0, 3.0]" in " ".join(record)
    case = get_case("wave-flume-2d")
    loaded = load_case(path)
    assert loaded.parameters == {} and loaded.resolved() == case.model_copy(update={"parameters": {}}).resolved()
    # odd keys and strings stay inside their comment lines
    odd = case.model_copy(update={"parameters": {"a\nb": "x\ny", "n": float("nan"), "ok": True}})
    lines = dumps_case(odd).splitlines()
    assert any(line == '#   "a\\nb" = "x\\ny", n = nan, ok = true' for line in lines), lines
    assert tomllib.loads(dumps_case(odd)).get("parameters") is None


def test_cli_new_unknown_case(tmp_path, capsys):
    path = tmp_path / "x.toml"
    assert _cli(["new", "no-such-case", "-o", str(path)]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "'no-such-case'" in line and "dam-break-2d" in line
    assert not path.exists()


def test_cli_param_of_builtin_case(capsys):
    # the brief's --dp 0.03 is refused by tidal-bore ("too coarse ... use dp <= 0.025 m")
    assert _cli(["check", "tidal-bore", "--dp", "0.025", "--param", "inflow_speed=0.7"]) == 0
    out, err = capsys.readouterr()
    assert "breaking" in out and "U = 0.7 m/s" in out
    assert _cli(["check", "tidal-bore", "--dp", "0.025", "--param", "inflow_speed=0.3"]) == 0
    assert "undular" in capsys.readouterr().out


def test_cli_unknown_param_lists_the_parameters(capsys):
    assert _cli(["check", "tidal-bore", "--dp", "0.025", "--param", "foo=1"]) == 2
    out, err = capsys.readouterr()
    line = _one_error_line(err)
    print("\n" + line)
    assert "'foo'" in line
    for p in ("inflow_speed", "depth", "half"):
        assert p in line
    assert out == ""


def test_cli_malformed_param(capsys):
    assert _cli(["check", "tidal-bore", "--param", "inflow_speed"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "KEY=VALUE" in line


# ----------------------------------------------------------------------------- case files are data

def test_code_like_name_is_rejected_and_never_run(tmp_path, capfd):
    marker = tmp_path / "pwned"
    code = f"__import__('pathlib').Path('{marker}').touch()"
    path = tmp_path / "evil.toml"
    path.write_text(edit(('name = "mini"', f'name = "{code}"')))
    msg = _error_of(path, "load")
    print("\n" + msg)
    assert "\n" not in msg and "name = " in msg and "use letters" in msg
    assert _cli(["check", str(path)]) == 2
    _, err = capfd.readouterr()
    _one_error_line(err)
    assert not marker.exists()


def test_echo_name_rejected_by_cli(tmp_path, capfd):
    path = tmp_path / "evil.toml"
    path.write_text(edit(('name = "mini"', """name = "__import__('os').system('echo hi')\"""")))
    assert _cli(["check", str(path)]) == 2
    out, err = capfd.readouterr()
    assert "hi" not in out.split()
    line = _one_error_line(err)
    assert "name = " in line


@pytest.mark.parametrize("value", ['"lambda x, y: 0.0 * x"', '"os.system"', "3", "{ module = \"math\" }"])
def test_bathymetry_function_is_python_api_only(value, tmp_path, capfd):
    path = tmp_path / "fn.toml"
    path.write_text(solid1(f'{{ type = "bathymetry", function = {value} }}'))
    msg = _error_of(path, "load")
    print("\n" + msg)
    assert "\n" not in msg and "solids[1].shape.function" in msg
    assert _cli(["check", str(path)]) == 2
    out, err = capfd.readouterr()
    _one_error_line(err)
    # with a valid source beside it, the function key still fails
    path.write_text(solid1('{ type = "bathymetry", profile = { x = [0.0, 1.0], z = [0.0, 0.1] }, '
                           f"function = {value} }}"))
    assert _cli(["check", str(path)]) == 2
    _one_error_line(capfd.readouterr().err)


def test_function_bathymetry_cannot_be_written(tmp_path):
    from shoal.geometry.shapes import Bathymetry

    case = load_case(_write(tmp_path, solid1('{ type = "bathymetry", profile = { x = [0.0, 1.0], z = [0.0, 0.1] } }')))
    solids = list(case.solids)
    solids[1] = solids[1].model_copy(update={"shape": Bathymetry(function=lambda x, y: 0.0 * x)})
    case = case.model_copy(update={"solids": solids})
    with pytest.raises(InputError, match="Python function cannot be written") as info:
        write_case(case, tmp_path / "out.toml")
    assert "\n" not in str(info.value)
    assert not (tmp_path / "out.toml").exists()


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "case.toml"
    path.write_text(text, encoding="utf-8")
    return path
