"""Floating bodies moved by the water (issue 32; `shoal.body_coupling`, `shoal.probes.body_recorder`).

The rigid-body dynamics alone are checked in tests/test_rigid_body.py; here the coupling: Archimedes, the
balance of the pair forces between fluid and body, output, checkpoints, case data and its errors.
"""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

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
D, L = 0.4, 1.2  # still-water depth, tank length [m]
B, H = 0.4, 0.2  # the box's width and height [m]: B/H = 2, so that at half the water's density it floats upright
# (a box of density s rho0 is stable upright when B/H > sqrt(6 s (1 - s)), 1.22 at s = 1/2: a square is not)


def _box_case(dp=0.02, draft=0.08, end_time=3.0, density=500.0, interval=0.01, options=None, x0=0.4,
              **floating):
    """2D: a box B = 0.4 m wide, H = 0.2 m high, of density `density`, in a tank L = 1.2 m long, D = 0.4 m deep,
    its bottom `draft` below the still-water level D at the start (the water fills the tank to D around it)."""
    zb = D - draft
    body = Solid(name="box", shape=Box(lo=(x0, 0, zb), hi=(x0 + B, 0, zb + H)),
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
    dp = 0.02 m (H = 10 dp): the run's result, its case and the body's CSV."""
    out = tmp_path_factory.mktemp("floating") / "run"
    case = _box_case()
    res = shoal.run_case(case, out, plot=False, progress=False, handle_signals=False)
    return res, case, _rows(out / "body_box.csv")


def test_archimedes_2d(released):
    """A box of density rho0/2 settles where it displaces its weight: its centre of gravity at the still-water
    level. The level is that of the fluid's own volume (n_fluid dp^2 over the tank's length, the box's
    displaced area M / rho0 added), 0.4067 m here. Over the last second the mean centre lies within 2 % of the
    box's height of it (issue 32, must-show 1; measured +1.1 %), the heave oscillation has decayed (radiation
    damping) to under a fifth of its start (the range of z over the last second below 4 % of H, from 20 %;
    measured 2.1 %), the box has not rolled by 1 degree (measured 1e-4 degree), and its centre has drifted
    sideways by less than dp/10 (measured 3e-4 dp)."""
    res, case, (head, rows) = released
    col = {c: k for k, c in enumerate(head)}
    t, z, x = rows[:, col["time"]], rows[:, col["z"]], rows[:, col["x"]]
    mass = 500.0 * B * H
    level = (case.n_fluid * case.dp**2 + mass / RHO) / L
    late = t >= 2.0
    assert abs(z[late].mean() - level) < 0.02 * H, (z[late].mean(), level)
    assert np.ptp(z[late]) < 0.04 * H
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
                    "wx", "wy", "wz", "fx", "fy", "fz", "tx", "ty", "tz", "cfx", "cfy", "cfz", "ctx", "cty", "ctz"]
    col = {c: k for k, c in enumerate(head)}
    assert np.allclose(np.diff(rows[:, 0]), 0.01) and rows[0, 0] == 0.0 and rows[-1, 0] == pytest.approx(3.0)
    for c in ("y", "vy", "roll", "yaw", "qx", "qz", "wx", "wz", "fy", "tx", "tz", "cfx", "cfy", "cfz", "ctx", "cty",
              "ctz"):  # 2D, and it touches nothing
        assert np.all(rows[:, col[c]] == 0.0), c
    q = rows[:, [col[c] for c in ("qw", "qx", "qy", "qz")]]
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-9)
    late = rows[:, 0] >= 2.0
    assert rows[late, col["fz"]].mean() == pytest.approx(500.0 * B * H * G, rel=0.02)


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
    assert coupled[2] == pytest.approx(500 * B * H * G, rel=0.2)  # the weight, give or take the heave


def _cut_and_resume(case, tmp_path, files):
    """Run `case` whole (into tmp_path/ref) and cut at about 60 % then resumed (tmp_path/cut); assert the two
    end bitwise equal (particles by id, and the bytes of `files`); returns the resumed run's result."""
    from tests.test_checkpoint import _state, penultimate

    case = case.model_copy(update={"checkpoint": Checkpointing(wall_interval=0.0)})
    ref = shoal.run_case(case, tmp_path / "ref", plot=False, handle_signals=False, progress=False)
    part = shoal.run_case(case, tmp_path / "cut", plot=False, max_steps=penultimate(ref.steps), handle_signals=False,
                          progress=False)
    res = shoal.resume_run(tmp_path / "cut", plot=False, handle_signals=False, progress=False)
    assert res.steps == ref.steps and part.steps < ref.steps
    a, b = _state(ref.checkpoint), _state(res.checkpoint)
    for k in ("pos", "vel", "rho", "idp"):
        assert np.array_equal(a[k], b[k]), k
    for name in files:
        assert (tmp_path / "ref" / name).read_bytes() == (tmp_path / "cut" / name).read_bytes(), name
    return res


def test_resume_with_a_floating_body_is_bitwise(tmp_path):
    """A run cut at 60 % and resumed from its checkpoint ends bitwise equal to the uninterrupted one: the
    particles, and the body's CSV row by row (its state is in the checkpoint)."""
    case = _box_case(dp=0.02, end_time=0.05, interval=0.005)
    res = _cut_and_resume(case.model_copy(update={"output": Output(interval=0.05)}), tmp_path, ["body_box.csv"])
    with h5py.File(res.checkpoint) as f:
        assert b'"floating"' in f["meta"][()].tobytes()


def test_a_body_is_held_until_its_release_time(tmp_path):
    """With release_time = 0.1 s the box released 1 dp above its draft (and thrown down at 0.1 m/s) stands
    still until then, its particles at rest, while the water's force on it is measured: over the second half
    of the hold (the start's acoustic ringing, +-5 % at first, averaged out) it carries the weight of the water
    it displaces, rho0 g B d at the held draft d = 0.08 m (80 % of its own weight), within 2 % (measured
    +0.5 %: the free surface's lift at this resolution, validation/archimedes/README.md). Released, it starts
    with its initial velocity and falls. A run cut while the box is held and resumed past the release ends
    bitwise, and so does one cut after the release (whether it is held is in the checkpoint)."""
    case = _box_case(dp=0.02, end_time=0.2, interval=0.01, velocity=(0.0, 0.0, -0.1), release_time=0.1)
    sim = Simulation(case)
    m, body = sim.model, sim.model.floating.bodies[0]
    z0 = body.state.position[2]
    box = m.body_of[m.host(m.idp)[:m.n]] == 1
    lift = []
    while sim.time < 0.1 - 1e-12:
        sim.step()
        assert body.held and body.state.position[2] == z0 and body.state.velocity[2] == -0.1
        assert not np.any(m.host(m.vel)[:m.n][box])
        if sim.time >= 0.05:
            lift.append(m.floating.fluid[0, 2])
    displaced = RHO * G * B * 0.08
    assert len(lift) > 50 and np.mean(lift) == pytest.approx(displaced, rel=0.02), np.mean(lift) / displaced
    for _ in range(3):
        sim.step()
    assert not body.held and body.state.position[2] < z0 and body.state.velocity[2] < -0.09
    assert np.abs(m.host(m.vel)[:m.n][box]).max() > 0.09
    for release in (0.04, 0.01):  # cut (at 0.03 s) while held, and after the release
        short = _box_case(dp=0.02, end_time=0.05, interval=0.005, velocity=(0.0, 0.0, -0.1), release_time=release)
        _cut_and_resume(short.model_copy(update={"output": Output(interval=0.05)}), tmp_path / f"r{release}",
                        ["body_box.csv"])


def test_case_file_round_trip_and_errors():
    case = _box_case(fixed=["x"], velocity=(0.0, 0.0, -0.1), friction=0.4, release_time=0.25)
    again = case_from_dict(tomllib.loads(dumps_case(case)))
    assert again.solids[1].floating == case.solids[1].floating
    model = build_model(case)
    body = model.floating.bodies[0]
    assert body.body.mass == pytest.approx(500 * B * H) and body.body.centre0 == pytest.approx([0.6, 0.0, 0.42])
    assert body.state.velocity.tolist() == [0.0, 0.0, -0.1] and body.friction == 0.4 and body.release_time == 0.25
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
    assert "friction = 0.0" in text
    path.write_text(text.replace("density = -5.0", "density = 500.0").replace("friction = 0.0", "friction = -0.2"))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "friction" in err and "greater than or equal to 0" in err
    assert "release_time = 0.0" in text
    path.write_text(text.replace("density = -5.0", "density = 500.0").replace("release_time = 0.0", "release_time = -1.0"))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "release_time" in err and "greater than or equal to 0" in err


def test_check_reports_each_floating_body():
    """`shoal check` gives the body's mass, area (2D) and density, centre of gravity and inertia: for the
    0.4 m x 0.2 m box of density 500, M = 40 kg/m and I_y = M (B^2 + H^2) / 12 = 0.6667 kg m^2/m exactly (the
    union of the lattice cells is the square)."""
    from shoal.check import check_case

    line = [x for x in check_case(_box_case(fixed=["x"])) if x.startswith("  floating")]
    assert line == ["  floating box: mass 40 kg/m, area 0.08 m^2 (density 500 kg/m^3), centre of gravity "
                    "(0.6, 0, 0.42) m, inertia about y 0.6667 kg m^2/m; fixed x"]
    line = [x for x in check_case(_box_case(friction=0.3, release_time=0.5)) if x.startswith("  floating")]
    assert line[0].endswith("; free; friction 0.3; held until t = 0.5 s")


MOORING_FILE = Path(__file__).parent / "data" / "floating" / "moored_box_2d.txt"
CORD_EA, CORD_L0 = 500.0, 0.47  # the cords of MOORING_FILE: axial stiffness [N], unstretched length [m]


def _moored_case(end_time, offset=0.04, interval=0.02):
    """The box (B x H = 0.4 x 0.2 m, density 500) in a 2D flume 2.4 m long and 0.4 m deep, damping zones over
    its last 0.5 m at each end, held by two taut elastic cords (MOORING_FILE: EA = 500 N, 0.47 m long) from
    anchors on the bed at x = 0.6 and 1.8 m to its bottom corners; symmetric about x = 1.2 m, where the box
    is released `offset` to the right of (on the lattice: the body's cells are its shape)."""
    from shoal.case import DampingZone
    from shoal.floating import Fairlead, MooringLines

    x0 = 1.0 + offset
    return Case(name="moored-box", dim=2, dp=0.02, end_time=end_time, fluid=Fluid(depth=D, surface_level=D),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(2.4, 0, 2 * D))),
                        Solid(name="box", shape=Box(lo=(x0, 0, 0.3), hi=(x0 + B, 0, 0.3 + H)),
                              floating=FloatingBody(density=500.0, interval=interval))],
                moorings=[MooringLines(file=str(MOORING_FILE), origin=(0, 0, D), width=1.0, interval=interval,
                                       fairleads=[Fairlead(body="box", point=(x0, 0, 0.3)),
                                                  Fairlead(body="box", point=(x0 + B, 0, 0.3))])],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.4, 0, D)))], output=Output(interval=end_time),
                damping=[DampingZone(start=(0.5, 0, 0), end=(0.0, 0, 0)),
                         DampingZone(start=(1.9, 0, 0), end=(2.4, 0, 0))])


def _cord_tension(rows, col, corner, anchor):
    """EA (l - L0) / L0 of a straight cord from `anchor` (x, z) to the body point at `corner` (x0 - c0) at each
    row of the body's CSV (the cords' weight in water, 0.3 N/m, sags them by far less than they stretch)."""
    a = np.radians(rows[:, col["pitch"]])  # about y: x' = cos a rx + sin a rz, z' = -sin a rx + cos a rz
    x = rows[:, col["x"]] + np.cos(a) * corner[0] + np.sin(a) * corner[1]
    z = rows[:, col["z"]] - np.sin(a) * corner[0] + np.cos(a) * corner[1]
    length = np.hypot(x - anchor[0], z - anchor[1])
    return CORD_EA * (length - CORD_L0) / CORD_L0


def test_moored_box_is_pulled_back_by_its_cords(tmp_path):
    """Issue 32, must-show 5 (second half), quick: the moored box released 4 cm (2 dp) right of its equilibrium
    is pulled back by its cords within a second (it passes within 1 cm of x = 1.2 m); each cord's fairlead
    tension that MoorDyn reports (``mooring_line<k>.csv``) is that of a straight elastic cord between its
    anchor and the body point where the body's CSV puts its fairlead, within 1 % at every row where the cord
    is taut (above 10 N; measured 0.24 % over a 4 s run): the fairleads follow the body, and the forces applied
    are MoorDyn's. The run to equilibrium is
    `test_moored_box_settles_at_its_equilibrium` (-m validation)."""
    shoal.run_case(_moored_case(1.0), tmp_path / "run", plot=False, progress=False, handle_signals=False)
    head, rows = _rows(tmp_path / "run" / "body_box.csv")
    col = {c: k for k, c in enumerate(head)}
    t, x = rows[:, 0], rows[:, col["x"]]
    assert x[0] == pytest.approx(1.24) and np.abs(x[(t >= 0.4) & (t <= 1.0)] - 1.2).min() < 0.01
    for k, (corner, anchor) in enumerate((((-0.2, -0.1), (0.6, 0.0)), ((0.2, -0.1), (1.8, 0.0))), start=1):
        tension = np.loadtxt(tmp_path / "run" / f"mooring_line{k}.csv", delimiter=",", skiprows=1)
        assert np.array_equal(tension[:, 0], t)
        taut = _cord_tension(rows, col, corner, anchor)
        # the right cord starts slack (shorter than L0: only its weight, 0.1 N, hangs on it); while it tightens,
        # its internal damping (MoorDyn's BA, 0.8 of critical) adds to the stretch's tension
        held = taut > 10.0
        assert held.sum() > 0.7 * len(t)
        np.testing.assert_allclose(tension[held, 1], taut[held], rtol=0.01)
    nodes = np.loadtxt(tmp_path / "run" / "mooring_line1_nodes.csv", delimiter=",", skiprows=1)
    assert nodes.shape == (len(t), 1 + 3 * 11) and np.allclose(nodes[:, 1:4], [0.6, 0.0, 0.0], atol=1e-9)


@pytest.mark.validation
def test_moored_box_settles_at_its_equilibrium(tmp_path):
    """Issue 32, must-show 5 (second half): the moored box released 4 cm right of its equilibrium comes back to
    it and stays, 4 s: over the last 2 s its mean centre is within dp/10 of x = 1.2 m (the symmetry line;
    measured 0.095 dp) and its mean height within 2 % of H of the static equilibrium (measured +0.5 %): the
    box's buoyancy rho g B (h - z_f) carries its weight and the two cords' vertical pull 2 T z_f / l, T = EA
    (l - L0) / L0, l = sqrt(0.4^2 + z_f^2), with the water level h of the fluid's volume and the box's
    displacement (z_f the height of the fairleads, the box's bottom; 2.3 minutes here)."""
    from scipy.optimize import brentq

    case = _moored_case(4.0)
    shoal.run_case(case, tmp_path / "run", plot=False, progress=False, handle_signals=False)
    head, rows = _rows(tmp_path / "run" / "body_box.csv")
    col = {c: k for k, c in enumerate(head)}
    late = rows[:, 0] >= 2.0
    area, length = case.n_fluid * case.dp**2, 2.4

    def balance(zf):
        h = (area - B * zf) / (length - B)
        cord = np.hypot(0.4, zf)
        return RHO * G * B * (h - zf) - 500.0 * B * H * G - 2 * CORD_EA * (cord - CORD_L0) / CORD_L0 * zf / cord

    zf = brentq(balance, 0.2, 0.4)
    assert abs(rows[late, col["x"]].mean() - 1.2) < case.dp / 10
    assert abs(rows[late, col["z"]].mean() - (zf + H / 2)) < 0.02 * H


def test_resume_with_a_moored_body_is_bitwise(tmp_path):
    """The mooring's state (MoorDyn's lines) is in the checkpoint: a moored run cut at 60 % and resumed ends
    bitwise equal to the uninterrupted one, particles and the cords' CSVs."""
    _cut_and_resume(_moored_case(0.04, interval=0.004), tmp_path,
                    ["body_box.csv", "mooring_line1.csv", "mooring_line2_nodes.csv"])


def test_mooring_case_errors():
    from shoal.floating import Fairlead, MooringLines

    case = _moored_case(1.0)
    spec = case.moorings[0]
    with pytest.raises(ValueError, match=r"fairleads\[0\].body = 'raft' is no floating solid \(floating: 'box'\)"):
        case.model_copy(update={"moorings": [spec.model_copy(update={
            "fairleads": [Fairlead(body="raft", point=(0, 0, 0)), *spec.fairleads[1:]]})]}).revalidate()
    with pytest.raises(Exception, match="give width"):
        case.model_copy(update={"moorings": [spec.model_copy(update={"width": None})]}).revalidate()
    with pytest.raises(Exception, match="mooring input file .*nowhere.txt: not found"):
        build_model(case.model_copy(update={"moorings": [MooringLines(
            file="/nowhere.txt", width=1.0, fairleads=spec.fairleads)]}))


def test_a_dense_box_stands_on_the_bed(tmp_path):
    """Contact (`shoal.physics.contact`): a box of density 2000 standing on the bed under water (no water under
    it) stays there, 0.4 s: the bed's push carries its weight and the water's pressure on its top (the water's
    force points down: none of it is under the box), in balance within 1 % of the weight at the end; its
    lowest particles never sink more than 0.15 dp into the bed (the contact's stiffness is the water's,
    rho0 c0^2: the overlap under this load is 1e-4 dp), and it is at rest (|v| < 1 mm/s).
    (Released from above, a body comes to rest on the film of water it traps under it, one particle thick,
    which takes SPH a second or more to squeeze out.)"""
    case = _box_case(dp=0.02, draft=D, end_time=0.4, density=2000.0, interval=0.01)
    shoal.run_case(case, tmp_path / "run", plot=False, progress=False, handle_signals=False)
    head, rows = _rows(tmp_path / "run" / "body_box.csv")
    col = {c: k for k, c in enumerate(head)}
    end = rows[-1]
    weight = 2000.0 * B * H * G
    bottom = rows[:, col["z"]] - H / 2  # the bed's surface is z = 0
    assert end[col["cfz"]] > weight and end[col["fz"]] < 0
    assert abs(end[col["fz"]] + end[col["cfz"]] - weight) < 0.01 * weight
    assert bottom.min() > -0.15 * case.dp, bottom.min() / case.dp
    assert abs(end[col["vz"]]) < 1e-3 and abs(end[col["vx"]]) < 1e-3


def test_a_box_thrown_at_a_wall_stops_at_it(tmp_path):
    """A floating box touching the tank's end wall, sent into it at 0.5 m/s, is stopped by the contact: its
    particles never come more than 0.15 dp into the wall (the stiffness is the water's: at this speed the
    overlap is about v sqrt(m / k) = v dp / c0 per particle pair, 0.01 dp), the wall pushes it back, and it
    rebounds slower than half its impact speed (the dashpot damps a particle of the water's mass critically;
    this box has ten times that per contact, whose restitution is 0.35: measured 0.38 of the impact speed).
    (Sent from a spacing away, the box stops on the column of water between it and the wall, 0.7 dp from it:
    SPH water squeezed between two walls leaves slowly.)"""
    case = _box_case(dp=0.02, draft=0.1, end_time=0.1, x0=L - B, interval=0.002, velocity=(0.5, 0.0, 0.0))
    shoal.run_case(case, tmp_path / "run", plot=False, progress=False, handle_signals=False)
    head, rows = _rows(tmp_path / "run" / "body_box.csv")
    col = {c: k for k, c in enumerate(head)}
    right = rows[:, col["x"]] + B / 2  # the body's right face; the wall's surface is x = L
    assert rows[:, col["cfx"]].min() < 0  # pushed back
    assert right.max() < L + 0.15 * case.dp, (right.max() - L) / case.dp
    assert -0.5 * 0.5 < rows[:, col["vx"]].min() < 0.0


def test_moored_box_3d_chains_hang_as_catenaries():
    """The built-in `moored-box-3d`: its four chains, initialised by MoorDyn with the box at rest, pull each
    fairlead with the tension of the elastic catenary with a seabed between its anchor and the box's corner
    (`shoal.catenary`, Irvine 1981: 0.894 m across, 0.4 m up, 1.2 m of chain weighing 0.788 N/m in water,
    EA = 10 kN), within 2 % (issue 32, must-show 5; measured -0.8 %), all four alike (the layout is
    symmetric), and towards their anchors."""
    import math

    from shoal.cases import moored_box_3d
    from shoal.catenary import catenary_tension

    model = build_model(moored_box_3d(dp=0.05))
    forces = model.floating.moorings[0].forces
    w = (0.1 - RHO * math.pi * 0.005**2 / 4) * G
    cat = catenary_tension(math.hypot(0.8, 0.4), 0.4, 1.2, w, 1.0e4)
    tension = np.linalg.norm(forces, axis=1)
    assert np.allclose(tension, cat.fairlead_tension, rtol=0.02), (tension, cat)
    assert np.ptp(tension) < 1e-6 * tension.max()
    corners = np.array([(x, y) for x in (1.8, 2.2) for y in (0.8, 1.2)])
    anchors = np.array([(1.0, 0.4), (1.0, 1.6), (3.0, 0.4), (3.0, 1.6)])
    toward = anchors - corners
    assert np.all(np.einsum("ij,ij->i", forces[:, :2], toward) > 0) and np.all(forces[:, 2] < 0)


def _dry_box(mu, velocity=(0.0, 0.0, 0.0), end_time=0.6, dp=0.02, boundary="dynamic"):
    """2D: the box (B = 0.4 m, H = 0.2 m, density 2000: 160 kg/m) standing on the bed of a dry tank 1.6 m long
    (its walls of `boundary` particles), frictional with coefficient `mu` (`shoal.physics.contact`); a puddle
    0.2 m x 0.04 m at the far end is the case's fluid (1.1 m away: it does not reach the box in `end_time`).
    c0 is that of 0.4 m of water."""
    body = Solid(name="box", shape=Box(lo=(0.1, 0, 0), hi=(0.1 + B, 0, H)),
                 floating=FloatingBody(density=2000.0, friction=mu, velocity=velocity))
    return Case(name="dry-box", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=0.4, surface_level=0.04),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.6, 0, 0.4)), boundary=boundary), body],
                fluids=[FluidRegion(shape=Box(lo=(1.4, 0, 0), hi=(1.6, 0, 0.04)))], output=Output(interval=end_time))


def _track(case, pull=None):
    """Run `case`, the box pulled along x by `pull` [N/m] if given: (t, x, vx, z) of the box each step, and
    the contact's dashpot c (`shoal.physics.contact.contact_constants`)."""
    from shoal.physics.contact import contact_constants

    sim = Simulation(case)
    box = sim.model.floating.bodies[0]
    if pull is not None:
        box.add_load(lambda body, state, t: (np.array([pull, 0.0, 0.0]), np.zeros(3)))
    rows = []
    sim.after_step.append(lambda s: rows.append((s.time, *box.state.position[[0, 2]], box.state.velocity[0])))
    sim.run()
    t, x, z, vx = np.array(rows).T
    m = sim.model
    return t, x, vx, z, contact_constants(m.rho0, m.c0, m.dp, m.dim)[2]


def test_friction_stops_a_sliding_box():
    """Coulomb friction (`shoal.physics.contact`): the box sent along the dry particle bed at v0 = 1 m/s with
    mu = 0.3 slides with the deceleration mu g (least squares over 0.05-0.25 s, while it slides at 0.85 to
    0.26 m/s, far above the pairs' slip speed mu F_n / c, 3 cm/s: within 1 %; the contact's cells slide over
    the bed's as over a flat surface) and stops after v0^2 / (2 mu g) = 0.170 m (within 2 %: below the slip
    speed the regularised friction is weaker), then stays (|v| < 1 mm/s). Frictionless, the same box keeps
    99 % of its speed over the same time: the deceleration is the friction's (spheres of diameter dp instead
    of cells lost 70 % here, riding over the bed's particles)."""
    mu, v0 = 0.3, 1.0
    t, x, vx, _, _ = _track(_dry_box(mu, velocity=(v0, 0.0, 0.0)))
    sliding = (t > 0.05) & (t < 0.25)
    slope = np.polyfit(t[sliding], vx[sliding], 1)[0]
    assert abs(slope / (-mu * G) - 1) < 0.01, slope / (-mu * G)
    travel = x[-1] - x[0]
    assert abs(travel / (v0 ** 2 / (2 * mu * G)) - 1) < 0.02, travel / (v0 ** 2 / (2 * mu * G))
    assert np.abs(vx[t > 0.5]).max() < 1e-3
    t, x, vx, _, _ = _track(_dry_box(0.0, velocity=(v0, 0.0, 0.0), end_time=0.34))
    assert vx[-1] > 0.99 * v0, vx[-1]


def test_a_box_slides_on_a_repulsive_bed():
    """On a bed of repulsive (Monaghan-Kajtar) particles, one layer at dp/2 spacing whose cells' outer face is
    the bed's surface, the box stands with its bottom particles dp/2 above the surface (within 0.01 dp) and,
    sent at 1 m/s with mu = 0.3, decelerates at mu g within 1 % (least squares over 0.05-0.25 s)."""
    mu = 0.3
    t, x, vx, z, _ = _track(_dry_box(mu, velocity=(1.0, 0.0, 0.0), end_time=0.3, boundary="repulsive"))
    assert np.abs(z - H / 2).max() < 0.01 * 0.02, np.abs(z - H / 2).max() / 0.02
    sliding = (t > 0.05) & (t < 0.25)
    slope = np.polyfit(t[sliding], vx[sliding], 1)[0]
    assert abs(slope / (-mu * G) - 1) < 0.01, slope / (-mu * G)


def test_friction_holds_a_box_pulled_below_its_limit():
    """Pulled along the particle bed by 0.4 mu M g (mu = 0.5) through its centre of gravity, the box does not
    accelerate: it creeps at the steady speed at which the contacts' dashpots carry the pull, pull / (n c),
    n = 20 the particles of its bottom face, c the contact's dashpot (`shoal.physics.contact`; below mu F_n
    at every contact: the pull's moment leaves the rear contact 70 % of the mean load), within 2 % and
    varying by under 1 % over 0.3-0.6 s. Pulled by 1.2 mu M g it slides, accelerating at (pull - mu M g) / M
    within 2 %."""
    mu, mass = 0.5, 2000.0 * B * H
    case = _dry_box(mu)
    pull = 0.4 * mu * mass * G
    t, x, vx, _, c = _track(case, pull=pull)
    late = t > 0.3
    creep = vx[late].mean()
    assert abs(creep / (pull / (round(B / case.dp) * c)) - 1) < 0.02, creep / (pull / (20 * c))
    assert np.ptp(vx[late]) < 0.01 * creep
    t, x, vx, _, _ = _track(case, pull=1.2 * mu * mass * G)
    moving = t > 0.1
    slope = np.polyfit(t[moving], vx[moving], 1)[0]
    assert abs(slope / (0.2 * mu * G) - 1) < 0.02, slope / (0.2 * mu * G)


def _box_on_a_plane(mu, slope_deg, end_time=0.4, dp=0.02):
    """The dry box of `_dry_box` standing on a wall plane z = 0.1 m (`shoal.case.WallPlane`) in the same tank,
    gravity tilted by `slope_deg` towards +x: the box on a slope of that angle."""
    from shoal.case import WallPlane

    a = np.radians(slope_deg)
    body = Solid(name="box", shape=Box(lo=(0.1, 0, 0.1), hi=(0.1 + B, 0, 0.1 + H)),
                 floating=FloatingBody(density=2000.0, friction=mu))
    return Case(name="box-on-a-slope", dim=2, dp=dp, end_time=end_time,
                fluid=Fluid(depth=0.4, surface_level=0.14, gravity=(G * np.sin(a), 0.0, -G * np.cos(a))),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.6, 0, 0.4))), body],
                planes=[WallPlane(point=(0.0, 0.0, 0.1), normal=(0.0, 0.0, 1.0))],
                fluids=[FluidRegion(shape=Box(lo=(1.4, 0, 0.1), hi=(1.6, 0, 0.14)))], output=Output(interval=end_time))


def test_a_box_slides_down_a_plane_slope_with_coulomb_friction():
    """On a wall plane (no particles) sloping 20 degrees, the box of mu = 0.2 < tan 20 deg slides down with the
    acceleration g (sin a - mu cos a) = 1.511 m/s^2 (least squares over 0.1-0.4 s, within 1 %) and stays on the
    plane (its bottom particles dp/2 above it within 0.01 dp); on a 10 degree slope with mu = 0.5 > tan 10 deg
    it is held, creeping at the speed at which the 20 contacts' dashpots carry its weight's component along
    the slope, M g sin a / (20 c), within 2 % (steady within 1 %)."""
    dp = 0.02
    a = np.radians(20.0)
    t, x, vx, z, c = _track(_box_on_a_plane(0.2, 20.0))
    moving = t > 0.1
    slope = np.polyfit(t[moving], vx[moving], 1)[0]
    expected = G * (np.sin(a) - 0.2 * np.cos(a))
    assert abs(slope / expected - 1) < 0.01, slope / expected
    assert np.abs(z - H / 2 - 0.1).max() < 0.01 * dp, np.abs(z - H / 2 - 0.1).max() / dp
    a = np.radians(10.0)
    t, x, vx, z, c = _track(_box_on_a_plane(0.5, 10.0))
    late = t > 0.2
    creep = 2000.0 * B * H * G * np.sin(a) / (round(B / dp) * c)
    assert abs(vx[late].mean() / creep - 1) < 0.02, vx[late].mean() / creep
    assert np.ptp(vx[late]) < 0.01 * vx[late].mean()


def test_two_bodies_rub_with_their_mean_friction_and_keep_their_momentum():
    """Friction between two floating bodies (`shoal.physics.contact`): a box B (0.2 m x 0.1 m, mu = 0.6) sent at
    1 m/s along the top of the box A (0.4 m x 0.2 m, mu = 0, on a frictionless wall plane), both of density
    2000. They rub with the mean coefficient 0.3: their relative velocity falls at 0.3 g (1 + M_B / M_A)
    (least squares over 0.03-0.2 s, within 1 %), and with no horizontal force from outside their total
    momentum M_A v_A + M_B v_B stays M_B v0 to 1e-9 of it (the contact's pair forces are equal and opposite)."""
    from shoal.case import WallPlane

    a = Solid(name="a", shape=Box(lo=(0.1, 0, 0.1), hi=(0.5, 0, 0.3)), floating=FloatingBody(density=2000.0))
    b = Solid(name="b", shape=Box(lo=(0.2, 0, 0.3), hi=(0.4, 0, 0.4)),
              floating=FloatingBody(density=2000.0, friction=0.6, velocity=(1.0, 0.0, 0.0)))
    case = Case(name="two-boxes", dim=2, dp=0.02, end_time=0.2, fluid=Fluid(depth=0.4, surface_level=0.14),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.6, 0, 0.6))), a, b],
                planes=[WallPlane(point=(0.0, 0.0, 0.1), normal=(0.0, 0.0, 1.0))],
                fluids=[FluidRegion(shape=Box(lo=(1.4, 0, 0.1), hi=(1.6, 0, 0.14)))], output=Output(interval=0.2))
    sim = Simulation(case)
    bodies = sim.model.floating.bodies
    ma, mb = (x.body.mass for x in bodies)
    rows = []
    sim.after_step.append(lambda s: rows.append((s.time, bodies[0].state.velocity[0], bodies[1].state.velocity[0])))
    sim.run()
    t, va, vb = np.array(rows).T
    sliding = t > 0.03
    slope = np.polyfit(t[sliding], (vb - va)[sliding], 1)[0]
    assert abs(slope / (-0.3 * G * (1 + mb / ma)) - 1) < 0.01, slope / (-0.3 * G * (1 + mb / ma))
    assert va[-1] > 0.1  # A is carried along
    assert np.abs(ma * va + mb * vb - mb * 1.0).max() < 1e-9 * mb, np.abs(ma * va + mb * vb - mb).max() / mb
