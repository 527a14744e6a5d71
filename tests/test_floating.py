"""Floating bodies moved by the water (issue 32; `shoal.body_coupling`, `shoal.probes.body_recorder`).

The rigid-body dynamics alone are checked in tests/test_rigid_body.py; here the coupling: Archimedes, the
balance of the pair forces between fluid and body, output, checkpoints, case data and its errors.
"""

from __future__ import annotations

import csv
import tomllib

import h5py
import numpy as np
import pytest

import shoal
from shoal.case import Case, Checkpointing, Fluid, FluidRegion, Output, Solid
from shoal.casefile import case_from_dict, dumps_case
from shoal.floating import FloatingBody
from shoal.geometry import Box, Tank
from shoal.options import SPHOptions
from shoal.physics.spec import FLUID
from shoal.runner import build_model
from shoal.simulation import Simulation

RHO, G = 1000.0, 9.81
D, L, B = 0.4, 1.0, 0.2  # still-water depth, tank length, box side [m]


def _box_case(dp=0.02, draft=0.08, end_time=3.0, density=500.0, interval=0.01, options=None, x0=0.4,
              **floating):
    """2D: a square box of side B = 0.2 m and density `density` in a tank L = 1 m long, D = 0.4 m deep, its
    bottom `draft` below the still-water level D at the start (the water fills the tank to D around it)."""
    zb = D - draft
    body = Solid(name="box", shape=Box(lo=(x0, 0, zb), hi=(x0 + B, 0, zb + B)),
                 floating=FloatingBody(density=density, interval=interval, **floating))
    return Case(name="floating-box", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=D, surface_level=D),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, 0, 2 * D))), body],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L, 0, D)))], output=Output(interval=end_time),
                options=options or SPHOptions())


def _rows(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


@pytest.fixture(scope="module")
def released(tmp_path_factory):
    """The box of density 500 released at rest 2 cm (1 dp) above the draft that floats it, run for 3 s at
    dp = 0.02 m (B = 10 dp): the run's result, its case and the body's CSV."""
    out = tmp_path_factory.mktemp("floating") / "run"
    case = _box_case()
    res = shoal.run_case(case, out, plot=False, progress=False, handle_signals=False)
    return res, case, _rows(out / "body_box.csv")


def test_archimedes_2d(released):
    """A box of density rho0/2 settles where it displaces its weight: its centre of gravity at the still-water
    level. The level is that of the fluid's own volume (n_fluid dp^2 over the tank's length, the box's
    displaced area M / rho0 added), 0.404 m here. Over the last second the mean centre lies within 2 % of the
    box's height of it (issue 32, must-show 1), the heave oscillation has decayed (radiation damping) to
    within 1 % of B, the box has not rolled by 1 degree, and its centre has drifted sideways by less than
    dp/10."""
    res, case, (head, rows) = released
    col = {c: k for k, c in enumerate(head)}
    t, z, x = rows[:, col["time"]], rows[:, col["z"]], rows[:, col["x"]]
    mass = 500.0 * B * B
    level = (case.n_fluid * case.dp**2 + mass / RHO) / L
    late = t >= 2.0
    assert abs(z[late].mean() - level) < 0.02 * B, (z[late].mean(), level)
    assert np.ptp(z[late]) < 0.01 * B
    assert np.abs(rows[:, col["pitch"]]).max() < 1.0
    assert np.abs(x - x[0]).max() < case.dp / 10
    # released above its equilibrium, it first falls: the heave starts downwards
    assert z[t <= 0.1][-1] < z[0]


def test_body_csv_columns_and_loads(released):
    """The CSV has a row every 0.01 s with the documented columns; 2D: no y motion, no roll or yaw, a unit
    quaternion about y; at rest at the end, the fluid carries the box's weight within 2 % (its force is that
    of the rows' own particle positions)."""
    res, case, (head, rows) = released
    assert head == ["time", "x", "y", "z", "qw", "qx", "qy", "qz", "roll", "pitch", "yaw", "vx", "vy", "vz",
                    "wx", "wy", "wz", "fx", "fy", "fz", "tx", "ty", "tz"]
    col = {c: k for k, c in enumerate(head)}
    assert np.allclose(np.diff(rows[:, 0]), 0.01) and rows[0, 0] == 0.0 and rows[-1, 0] == pytest.approx(3.0)
    for c in ("y", "vy", "roll", "yaw", "qx", "qz", "wx", "wz", "fy", "tx", "tz"):
        assert np.all(rows[:, col[c]] == 0.0), c
    q = rows[:, [col[c] for c in ("qw", "qx", "qy", "qz")]]
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-9)
    late = rows[:, 0] >= 2.0
    assert rows[late, col["fz"]].mean() == pytest.approx(500.0 * B * B * G, rel=0.02)


def _momentum_balance(model):
    """(sum over the fluid of m (a - g), the force on every boundary particle summed, the force on the
    floating body by `floating_loads`, and the same from `wall_forces` over the body's particles)."""
    model.compute_rates()
    kinds = model.host(model.kind)
    ace = model.host(model.ace).astype(np.float64)
    g = model.gravity[[0, 2]]
    fluid = model.mass * (ace[kinds == FLUID] - g).sum(axis=0)
    forces, ids = model.wall_forces()
    walls = forces.sum(axis=0)[[0, 2]]
    body = forces[model.body_of[ids] == 1].sum(axis=0)
    coupling = model.floating
    centres = np.array([b.state.position for b in coupling.bodies])
    return fluid, walls, model.floating_loads(coupling.row, centres)[0], body


def test_fluid_and_body_forces_balance():
    """Issue 32, must-show 6: the force of the fluid on the body is the opposite of the body's on the fluid.
    With the box moving (released 1 dp off its equilibrium, 400 steps in), sum_fluid m (a - g) plus the
    forces of the fluid on all boundary particles (tank and body) is zero to 1e-6 of the water's weight (pair
    by pair antisymmetric; float64 here, so round-off), and the body's load that the coupling applies is the
    sum of its particles' wall forces (the force gauge's), bitwise."""
    case = _box_case(dp=0.02, end_time=1.0, options=SPHOptions(precision="float64"))
    sim = Simulation(case)
    for _ in range(400):
        sim.step()
    m = sim.model
    assert abs(m.floating.bodies[0].state.velocity[2]) > 1e-3  # it moves
    fluid, walls, coupled, body = _momentum_balance(m)
    weight = case.n_fluid * RHO * case.dp**2 * G
    assert np.abs(fluid + walls).max() < 1e-6 * weight
    assert np.array_equal(coupled[:3], body)
    assert coupled[2] == pytest.approx(500 * B * B * G, rel=0.2)  # the weight, give or take the heave


def test_resume_with_a_floating_body_is_bitwise(tmp_path):
    """A run cut at 60 % and resumed from its checkpoint ends bitwise equal to the uninterrupted one: the
    particles, and the body's CSV row by row (its state is in the checkpoint)."""
    from tests.test_checkpoint import _state, penultimate

    case = _box_case(dp=0.02, end_time=0.05, interval=0.005)
    case = case.model_copy(update={"checkpoint": Checkpointing(wall_interval=0.0), "output": Output(interval=0.05)})
    ref = shoal.run_case(case, tmp_path / "ref", plot=False, handle_signals=False, progress=False)
    part = shoal.run_case(case, tmp_path / "cut", plot=False, max_steps=penultimate(ref.steps), handle_signals=False,
                          progress=False)
    res = shoal.resume_run(tmp_path / "cut", plot=False, handle_signals=False, progress=False)
    assert res.steps == ref.steps and part.steps < ref.steps
    a, b = _state(ref.checkpoint), _state(res.checkpoint)
    for k in ("pos", "vel", "rho", "idp"):
        assert np.array_equal(a[k], b[k]), k
    assert (tmp_path / "ref" / "body_box.csv").read_bytes() == (tmp_path / "cut" / "body_box.csv").read_bytes()
    with h5py.File(res.checkpoint) as f:
        assert b'"floating"' in f["meta"][()].tobytes()


def test_case_file_round_trip_and_errors():
    case = _box_case(fixed=["x"], velocity=(0.0, 0.0, -0.1))
    again = case_from_dict(tomllib.loads(dumps_case(case)))
    assert again.solids[1].floating == case.solids[1].floating
    model = build_model(case)
    body = model.floating.bodies[0]
    assert body.body.mass == pytest.approx(500 * B * B) and body.body.centre0 == pytest.approx([0.5, 0.0, 0.42])
    assert body.state.velocity.tolist() == [0.0, 0.0, -0.1]
    box = case.solids[1]
    with pytest.raises(ValueError, match="motion = 'paddle' and floating both given"):
        Solid(name="b", shape=box.shape, motion="paddle", floating=FloatingBody(density=500.0))
    with pytest.raises(ValueError, match="a tank cannot float"):
        Solid(name="b", shape=Tank(lo=(0, 0, 0), hi=(1, 0, 1)), floating=FloatingBody(density=500.0))
    with pytest.raises(ValueError, match="dynamic boundary particles"):
        Solid(name="b", shape=box.shape, boundary="repulsive", floating=FloatingBody(density=500.0))
    with pytest.raises(ValueError, match="floating bodies named box more than once"):
        Case(name="two", dim=2, dp=0.02, fluids=case.fluids, fluid=case.fluid, solids=[*case.solids, box])


def test_bad_floating_table_in_a_case_file_is_one_line(tmp_path, capsys):
    from shoal.cli import main

    text = dumps_case(_box_case()).replace("density = 500.0", "density = -5.0")
    assert "density = -5.0" in text
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "density" in err and "greater than 0" in err


def test_check_reports_each_floating_body():
    """`shoal check` gives the body's mass, area (2D) and density, centre of gravity and inertia: for the
    0.2 m square of density 500, M = 20 kg/m and I_y = M (a^2 + b^2) / 12 = 0.1333 kg m^2/m exactly (the
    union of the lattice cells is the square)."""
    from shoal.check import check_case

    line = [x for x in check_case(_box_case(fixed=["x"])) if x.startswith("  floating")]
    assert line == ["  floating box: mass 20 kg/m, area 0.04 m^2 (density 500 kg/m^3), centre of gravity "
                    "(0.5, 0, 0.42) m, inertia about y 0.1333 kg m^2/m; fixed x"]
