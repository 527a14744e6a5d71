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


def test_case_file_round_trip_and_errors():
    case = _box_case(fixed=["x"], velocity=(0.0, 0.0, -0.1))
    again = case_from_dict(tomllib.loads(dumps_case(case)))
    assert again.solids[1].floating == case.solids[1].floating
    model = build_model(case)
    body = model.floating.bodies[0]
    assert body.body.mass == pytest.approx(500 * B * H) and body.body.centre0 == pytest.approx([0.6, 0.0, 0.42])
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
    0.4 m x 0.2 m box of density 500, M = 40 kg/m and I_y = M (B^2 + H^2) / 12 = 0.6667 kg m^2/m exactly (the
    union of the lattice cells is the square)."""
    from shoal.check import check_case

    line = [x for x in check_case(_box_case(fixed=["x"])) if x.startswith("  floating")]
    assert line == ["  floating box: mass 40 kg/m, area 0.08 m^2 (density 500 kg/m^3), centre of gravity "
                    "(0.6, 0, 0.42) m, inertia about y 0.6667 kg m^2/m; fixed x"]


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
    rho0 c0^2: the overlap under this load is 1e-4 dp; frictionless particles could slide half a spacing into
    the hollows between the bed's particles, 0.14 dp deep), and it is at rest (|v| < 1 mm/s).
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
    this box has ten times that per contact: measured 0.35 of the impact speed). (Sent from a spacing
    away, the box stops on the column of water between it and the wall, 0.7 dp from it: SPH water squeezed
    between two walls leaves slowly.)"""
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
