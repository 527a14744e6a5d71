"""Mooring lines (issue 32): the analytic elastic catenary (`shoal.catenary`) in its known limits, MoorDyn's
static line against it, and the coupling of MoorDyn's fairlead forces to shoal's rigid bodies
(`shoal.mooring`): force and torque sums, kinematics handed to MoorDyn, errors, CSV output, checkpoints."""

from __future__ import annotations

import csv
import re
import math
from pathlib import Path

import numpy as np
import pytest

from shoal.catenary import catenary_tension
from shoal.errors import InputError
from shoal.mass_properties import MassProperties
from shoal.motions import rotation_matrix
from shoal.rigid_body import RigidBody

DATA = Path(__file__).resolve().parent / "data" / "mooring"
CATENARY_FILE = DATA / "catenary_line.txt"
TWO_LINES_FILE = DATA / "two_lines.txt"

# the chain of both input files: (mass per length - rho_w * pi d^2 / 4) * g, EA, L
CHAIN_W = (80.0 - 1025.0 * math.pi / 4.0 * 0.1**2) * 9.81
CHAIN_EA = 5.0e8
CHAIN_L = 150.0
TOLERANCE = 0.02  # issue 32: MoorDyn's static fairlead tension within 2 % of the analytic catenary


# ---------------------------------------------------------------- the analytic catenary
def test_vertical_taut_line():
    """x_F = 0, fully suspended and stretched: top tension = mean tension EA (z/L - 1) + half the weight,
    the bottom's w L less."""
    w, el, ea, z = 100.0, 50.0, 1.0e6, 60.0
    c = catenary_tension(0.0, z, el, w, ea, seabed=False)
    v = ea * (z - el) / el + w * el / 2.0
    assert c.horizontal == 0.0
    assert c.vertical == pytest.approx(v, rel=1e-14)
    assert c.anchor_tension == pytest.approx(v - w * el, rel=1e-14)
    # and the general solve tends to it as the line leans off the vertical
    near = catenary_tension(1e-6, z, el, w, ea, seabed=False)
    assert near.vertical == pytest.approx(v, rel=1e-9)
    assert near.horizontal == pytest.approx(v * 1e-6 / z, rel=2e-2)  # H / V ~ x_F / z_F


def test_slack_line_hangs_vertically():
    """A line longer than it needs: H = 0, it hangs over s with z = s + w s^2 / (2 EA), V = w s, the rest on
    the seabed; continuous with the catenary (H -> 0) where the grounded part just reaches the anchor."""
    w, el, ea, z = 100.0, 50.0, 1.0e6, 30.0
    c = catenary_tension(5.0, z, el, w, ea)
    s = c.vertical / w
    assert c.horizontal == 0.0 and c.anchor_tension == 0.0
    assert s + w * s * s / (2.0 * ea) == pytest.approx(z, rel=1e-14)
    assert c.grounded_length == pytest.approx(el - s, rel=1e-14)
    just = catenary_tension(el - z + 1e-6, z, el, w, math.inf)
    assert just.horizontal < 1e-3 and just.vertical == pytest.approx(w * z, rel=1e-8)


def test_inextensible_limit_is_the_textbook_catenary():
    """EA = inf with touchdown: with a = H / w the suspended length is s = sqrt(z (z + 2 a)), its horizontal
    reach a asinh(s / a), and V = w s (e.g. Irvine 1981, section 2.2)."""
    w, el, z, a = 705.0, 150.0, 45.0, 50.0
    s = math.sqrt(z * (z + 2.0 * a))
    x = el - s + a * math.asinh(s / a)
    c = catenary_tension(x, z, el, w, math.inf)
    assert c.horizontal == pytest.approx(w * a, rel=1e-10)
    assert c.vertical == pytest.approx(w * s, rel=1e-10)
    assert c.grounded_length == pytest.approx(el - s, rel=1e-10)
    assert c.anchor_tension == c.horizontal  # frictionless seabed
    # a stiff elastic line approaches it at the rate of its strain, T / EA ~ 1e-4 here
    stiff = catenary_tension(x, z, el, w, 1e9)
    assert stiff.horizontal == pytest.approx(w * a, rel=5e-3)
    assert stiff.horizontal < c.horizontal  # stretching slackens it


def test_hand_checkable_suspended_line():
    """Ends at one height, inextensible: symmetry gives V = w L / 2; with H = 1000 N, w = 100 N/m (a = 10 m)
    and a span of 20 m, L = 2 a sinh(x / (2 a)) = 20 sinh(1) m."""
    c = catenary_tension(20.0, 0.0, 20.0 * math.sinh(1.0), 100.0, math.inf, seabed=False)
    assert c.horizontal == pytest.approx(1000.0, rel=1e-12)
    assert c.vertical == pytest.approx(1000.0 * math.sinh(1.0), rel=1e-12)
    assert c.anchor_tension == pytest.approx(c.fairlead_tension, rel=1e-12)


def test_weightless_taut_line_is_a_spring():
    """w -> 0: a straight elastic bar, H = EA (x / L - 1)."""
    c = catenary_tension(101.0, 0.0, 100.0, 1e-6, 1e6, seabed=False)
    assert c.horizontal == pytest.approx(1e4, rel=1e-9)
    assert c.vertical == pytest.approx(1e-6 * 100.0 / 2.0, rel=1e-6)


def test_touchdown_is_continuous():
    """The seabed and the fully suspended equations meet where the grounded length reaches 0."""
    w, el, ea, z = CHAIN_W, CHAIN_L, CHAIN_EA, 45.0
    lo, hi = 140.0, 142.0
    assert catenary_tension(lo, z, el, w, ea).grounded_length > 0
    assert catenary_tension(hi, z, el, w, ea).grounded_length == 0
    for _ in range(60):  # bisect for the touchdown span
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if catenary_tension(mid, z, el, w, ea).grounded_length > 0 else (lo, mid)
    a, b = catenary_tension(lo, z, el, w, ea), catenary_tension(hi, z, el, w, ea, seabed=False)
    assert a.vertical == pytest.approx(w * el, rel=1e-9) and b.vertical == pytest.approx(w * el, rel=1e-9)
    assert a.horizontal == pytest.approx(b.horizontal, rel=1e-9)


@pytest.mark.parametrize("args, match", [
    ((10.0, 5.0, 0.0, 1.0, 1.0), "length"),
    ((10.0, 5.0, 20.0, -1.0, 1.0), "weight"),
    ((10.0, 5.0, 20.0, 1.0, 0.0), "stiffness"),
    ((-1.0, 5.0, 20.0, 1.0, 1.0), "horizontal span"),
    ((10.0, -5.0, 20.0, 1.0, 1.0), "above"),
    ((30.0, 5.0, 20.0, 1.0, math.inf), "inextensible"),
])
def test_catenary_refuses_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        catenary_tension(*args)


# ---------------------------------------------------------------- MoorDyn through shoal.mooring
moordyn = pytest.importorskip("moordyn")
from shoal.mooring import Mooring, MooringRecorder  # noqa: E402


def _body(centre=(0.0, 0.0, -3.0)):
    return RigidBody(MassProperties(1.0e5, np.array(centre, float), np.diag([1e6, 2e6, 3e6])))


def _moving(body, t):
    """A body state at time t: displaced, rotated and moving (a surge-heave-pitch-yaw motion)."""
    s = body.initial_state()
    r = rotation_matrix(np.array([0.2, 1.0, 0.3]) / np.linalg.norm([0.2, 1.0, 0.3]), 0.05 * math.sin(t))
    return s._replace(position=body.centre0 + np.array([2.0 * math.sin(t), 0.5 * math.sin(0.5 * t), 0.3 * math.cos(t)]),
                      rotation=r, velocity=np.array([2.0 * math.cos(t), 0.25 * math.cos(0.5 * t), -0.3 * math.sin(t)]),
                      angular_velocity=np.array([0.01, 0.05 * math.cos(t), 0.02]))


def _states(bodies, t):
    return [bodies[0].initial_state(), _moving(bodies[1], t)]


@pytest.mark.parametrize("offset", [0.0, 12.0], ids=["touching_seabed", "fully_suspended"])
def test_moordyn_static_line_matches_the_catenary(offset):
    """The fairlead held still: after MoorDyn's initial static solve and 2 s of steps, the line's pull on the
    fairlead (what the body receives) and on the anchor are the analytic elastic catenary's, within 2 %."""
    body = _body()
    fair = np.array([offset, 0.0, -5.0])
    with Mooring(CATENARY_FILE, [(0, fair)]) as m:
        state = body.initial_state()
        m.initialise([body], [state])
        for k in range(20):
            m.loads([body], [state], 0.1 * k, 0.1)
        f = m.forces[0]
        anchor, _ = m.line_end_forces(0)
    c = catenary_tension(fair[0] + 130.0, fair[2] + 50.0, CHAIN_L, CHAIN_W, CHAIN_EA)
    assert (c.grounded_length > 0) == (offset == 0.0)
    errors = {"fairlead tension": np.linalg.norm(f) / c.fairlead_tension - 1.0,
              "H": -f[0] / c.horizontal - 1.0, "V": -f[2] / c.vertical - 1.0,
              "anchor tension": np.linalg.norm(anchor) / c.anchor_tension - 1.0}
    print(f"MoorDyn vs catenary ({'seabed' if offset == 0 else 'suspended'}): "
          + ", ".join(f"{k} {100 * v:+.3f} %" for k, v in errors.items()))
    assert abs(f[1]) < 1e-9 * np.linalg.norm(f)
    for name, err in errors.items():
        assert abs(err) < TOLERANCE, (name, err)


@pytest.fixture
def two_lines():
    """Two bodies; both fairleads of two_lines.txt on body 1 (body 0 unmoored), initialised where
    `_moving` puts body 1 at t = 0."""
    bodies = [_body((3.0, 3.0, 0.0)), _body()]
    fairleads = [(1, [-5.0, 0.0, -5.0]), (1, [0.0, 5.0, -5.0])]
    m = Mooring(TWO_LINES_FILE, fairleads)
    m.initialise(bodies, _states(bodies, 0.0))
    yield m, bodies
    m.close()


def test_loads_are_the_fairlead_forces_at_the_fairleads(two_lines):
    """F = F_1 + F_2 and T = (x_1 - c) x F_1 + (x_2 - c) x F_2 about the centre of gravity, with
    x_k = c + R (x0_k - c0) where the body's state puts its fairleads; MoorDyn gets those points and their
    velocities v + omega x (x - c), and moves them along the velocities over the step."""
    m, bodies = two_lines
    dt = 0.05
    for k in range(14):  # the body moving from t = 0 to 0.7 s
        m.loads(bodies, _states(bodies, k * dt), k * dt, dt)
    t = 14 * dt
    states = _states(bodies, t)
    out = m.loads(bodies, states, t, dt)
    s = states[1]
    x0 = np.array([[-5.0, 0.0, -5.0], [0.0, 5.0, -5.0]])
    x = s.position + (x0 - bodies[1].centre0) @ s.rotation.T
    u = s.velocity + np.cross(s.angular_velocity, x - s.position)
    for k, point in enumerate(m._coupled):  # MoorDyn's coupled points at the step's end
        np.testing.assert_allclose(moordyn.GetPointPos(point), x[k] + dt * u[k], rtol=0, atol=1e-12)
        np.testing.assert_allclose(moordyn.GetPointVel(point), u[k], rtol=0, atol=1e-12)
    f1, f2 = m.forces
    assert np.all(out[0][0] == 0.0) and np.all(out[0][1] == 0.0)
    np.testing.assert_allclose(out[1][0], f1 + f2, rtol=1e-15, atol=0)
    torque = np.cross(x[0] - s.position, f1) + np.cross(x[1] - s.position, f2)
    np.testing.assert_allclose(out[1][1], torque, rtol=1e-12, atol=1e-9 * np.linalg.norm(torque))
    # each fairlead force is its line's pull on end B, down and towards its anchor
    for k in range(2):
        np.testing.assert_array_equal(m.line_end_forces(k)[1], m.forces[k])
    assert f1[0] < 0 and f2[1] > 0 and f1[2] < 0 and f2[2] < 0
    # the held load for the integrator's stages: the same at the same state
    f_held, t_held = m.body_load(1)(bodies[1], s, t)
    np.testing.assert_allclose(f_held, out[1][0], rtol=1e-15)
    np.testing.assert_allclose(t_held, out[1][1], rtol=1e-12, atol=1e-9 * np.linalg.norm(torque))


def test_origin_shifts_the_frame():
    """A case with its bed at z = 0 and MoorDyn's origin at the still water level 50 m above: the same forces,
    bitwise, as the same mooring in MoorDyn's frame, and the nodes 50 m higher."""
    shift = np.array([0.0, 0.0, 50.0])
    results = []
    for origin in (np.zeros(3), shift):
        body = _body(np.array([0.0, 0.0, -3.0]) + origin)
        fairleads = [(0, np.array(x0) + origin) for x0 in ([-5.0, 0.0, -5.0], [0.0, 5.0, -5.0])]
        with Mooring(TWO_LINES_FILE, fairleads, origin=origin) as m:
            m.initialise([body], [body.initial_state()])
            m.loads([body], [body.initial_state()], 0.0, 0.1)
            results.append((m.forces.copy(), m.line_nodes(0)))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_allclose(results[1][1], results[0][1] + shift, rtol=0, atol=1e-12)
    with pytest.raises(InputError, match="origin"):
        Mooring(TWO_LINES_FILE, TWO_FAIRLEADS, origin=[0.0, 1.0])


def test_recorder_writes_a_row_per_call(two_lines, tmp_path):
    m, bodies = two_lines
    n_nodes = 13  # 12 segments
    times = []
    with MooringRecorder(m, tmp_path) as rec:
        rec.record(0.0)
        times.append(0.0)
        for k in range(3):
            m.loads(bodies, _states(bodies, 0.1 * k), 0.1 * k, 0.1)
            rec.record(0.1 * (k + 1))
            times.append(0.1 * (k + 1))
        last = [m.line_end_forces(i) for i in range(2)], [m.line_nodes(i) for i in range(2)]
    for i in range(2):
        rows = list(csv.reader(open(tmp_path / f"mooring_line{i + 1}.csv")))
        assert rows[0] == ["time [s]", "fairlead_tension [N]", "anchor_tension [N]"]
        assert [float(r[0]) for r in rows[1:]] == pytest.approx(times)
        fa, fb = last[0][i]
        assert float(rows[-1][1]) == pytest.approx(np.linalg.norm(fb), rel=1e-8)
        assert float(rows[-1][2]) == pytest.approx(np.linalg.norm(fa), rel=1e-8)
        nodes = list(csv.reader(open(tmp_path / f"mooring_line{i + 1}_nodes.csv")))
        assert nodes[0][:4] == ["time [s]", "x0 [m]", "y0 [m]", "z0 [m]"] and len(nodes[0]) == 1 + 3 * n_nodes
        assert len(nodes) == 1 + len(times)
        np.testing.assert_allclose(np.array(nodes[-1][1:], float).reshape(-1, 3), last[1][i], rtol=1e-8, atol=1e-7)
    # resuming from a checkpoint at t = 0.1 drops the later rows and appends
    with MooringRecorder(m, tmp_path, resume_time=0.1) as rec:
        rec.record(0.2)
    rows = list(csv.reader(open(tmp_path / "mooring_line1.csv")))
    assert [float(r[0]) for r in rows[1:]] == pytest.approx([0.0, 0.1, 0.2])
    assert len(list(csv.reader(open(tmp_path / "mooring_line2_nodes.csv")))) == 4


def test_checkpoint_restore_continues_bitwise(two_lines):
    """A run checkpointed after 5 steps and restored into a new Mooring gives the same forces, bitwise, as
    the run that went on."""
    m, bodies = two_lines
    dt = 0.05

    def step(mooring, k):
        return mooring.loads(bodies, _states(bodies, k * dt), k * dt, dt)

    for k in range(5):
        step(m, k)
    saved = m.checkpoint_state()
    assert isinstance(saved, bytes)
    ref = [step(m, k) for k in range(5, 10)]
    with Mooring(TWO_LINES_FILE, m.fairleads) as again:
        again.restore_state(saved)
        out = [step(again, k) for k in range(5, 10)]
    for (fa, ta), (fb, tb) in zip(ref, out):
        for a, b in zip(fa + ta, fb + tb):
            np.testing.assert_array_equal(a, b)
    with Mooring(CATENARY_FILE, [(0, [0.0, 0.0, -5.0])]) as other:
        with pytest.raises(InputError, match="fairleads"):
            other.restore_state(saved)
        with pytest.raises(InputError, match="not one of shoal's"):
            other.restore_state(b"not a checkpoint")


def test_moordyn_files_stay_out_of_the_input_directory(tmp_path, capfd):
    """MoorDyn's own files go to moordyn_dir (or nowhere), not beside the input file; the console stays quiet."""
    before = sorted(p.name for p in DATA.iterdir())
    body = _body()
    with Mooring(TWO_LINES_FILE, [(0, [-5.0, 0.0, -5.0]), (0, [0.0, 5.0, -5.0])], moordyn_dir=tmp_path / "md") as m:
        m.initialise([body], [body.initial_state()])
        m.loads([body], [body.initial_state()], 0.0, 0.1)
        private = m._workdir
    assert (tmp_path / "md" / "two_lines.out").is_file()
    assert not private.exists()
    with Mooring(TWO_LINES_FILE, [(0, [-5.0, 0.0, -5.0]), (0, [0.0, 5.0, -5.0])]) as m:
        m.initialise([body], [body.initial_state()])
        private = m._workdir
    assert not private.exists()
    assert sorted(p.name for p in DATA.iterdir()) == before
    out, err = capfd.readouterr()
    assert "MoorDyn" not in out + err and "t = " not in out


def test_earlier_moordyn_output_beside_the_input_is_left_alone(tmp_path):
    """The private directory links the input's neighbours (files it may name), but not the files MoorDyn
    writes, which it would overwrite through the links."""
    (tmp_path / "two_lines.txt").write_text(TWO_LINES_FILE.read_text())
    (tmp_path / "two_lines.out").write_text("an earlier run's output\n")
    (tmp_path / "waves.dat").write_text("a file the input could name\n")
    body = _body()
    with Mooring(tmp_path / "two_lines.txt", [(0, [-5.0, 0.0, -5.0]), (0, [0.0, 5.0, -5.0])]) as m:
        assert (m._workdir / "waves.dat").read_text() == "a file the input could name\n"
        m.initialise([body], [body.initial_state()])
        m.loads([body], [body.initial_state()], 0.0, 0.1)
    assert (tmp_path / "two_lines.out").read_text() == "an earlier run's output\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["two_lines.out", "two_lines.txt", "waves.dat"]


def _variant(tmp_path, old, new, name="variant.txt"):
    text = TWO_LINES_FILE.read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


TWO_FAIRLEADS = [(0, [-5.0, 0.0, -5.0]), (0, [0.0, 5.0, -5.0])]


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match=r"mooring input file .*nope\.txt: not found"):
        Mooring(tmp_path / "nope.txt", [])


def test_not_a_moordyn_file(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_text("a shopping list\n")
    with pytest.raises(InputError, match=r"notes\.txt: no lines"):
        Mooring(path, [])


def test_moordyn_refusal_is_one_line(tmp_path):
    path = _variant(tmp_path, "1    chain      1        2", "1    rope       1        2")
    with pytest.raises(InputError) as e:
        Mooring(path, TWO_FAIRLEADS)
    msg = str(e.value)
    assert "\n" not in msg and str(path) in msg and "Unrecognized line type rope" in msg
    assert "shoal-moordyn" not in msg  # names the user's file, not the private copy


def test_fairlead_count_must_match(tmp_path):
    with pytest.raises(InputError, match="2 coupled points, 1 fairleads given"):
        Mooring(TWO_LINES_FILE, TWO_FAIRLEADS[:1])


def test_coupled_bodies_are_refused(tmp_path):
    path = _variant(tmp_path, "---------------------- POINTS", (
        "---------------------- BODIES ---------------------------------------\n"
        "ID   Attachment  X0  Y0  Z0  r0  p0  y0  Mass  CG*  I*  Volume  CdA*  Ca*\n"
        "(#)  (word)      (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)\n"
        "1    coupled     0   0   0   0   0   0   0     0    0   0       0     0\n"
        "---------------------- POINTS"))
    path.write_text(path.read_text().replace("2     Coupled      -5.0", "2     Body1        -5.0"))
    with pytest.raises(InputError, match="couples bodies or rods"):
        Mooring(path, TWO_FAIRLEADS[1:])


@pytest.mark.parametrize("fairleads, match", [
    ([(0, [0.0, 0.0]), (0, [0.0, 5.0, -5.0])], "fairlead 0"),
    ([(-1, [0.0, 0.0, -5.0]), (0, [0.0, 5.0, -5.0])], "body index -1"),
    ([(0, [0.0, math.nan, -5.0]), (0, [0.0, 5.0, -5.0])], "not finite"),
])
def test_bad_fairleads(fairleads, match):
    with pytest.raises(InputError, match=match):
        Mooring(TWO_LINES_FILE, fairleads)


def test_fairlead_on_a_missing_body():
    m = Mooring(TWO_LINES_FILE, [(0, [-5.0, 0.0, -5.0]), (3, [0.0, 5.0, -5.0])])
    body = _body()
    with pytest.raises(InputError, match="body index 3, but there are 1 bodies"):
        m.initialise([body], [body.initial_state()])
    m.close()


def test_the_user_guide_example_runs(tmp_path, monkeypatch):
    """docs/mooring.md: its MoorDyn input file (the ``text`` block) and its Python block run as shown, with
    the body settling on its lines."""
    page = (Path(__file__).resolve().parents[1] / "docs" / "mooring.md").read_text()
    blocks = {}
    for lang, code in re.findall(r"^```(\w+)\n(.*?)^```$", page, re.M | re.S):
        blocks.setdefault(lang, code)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mooring.txt").write_text(blocks["text"])
    namespace = {}
    exec(compile(blocks["python"], "docs/mooring.md", "exec"), namespace)
    forces = namespace["mooring"].forces
    assert forces[0][0] < 0 < forces[1][0] and forces[0][2] < 0  # each line pulls towards its anchor, down
    assert abs(namespace["state"].position[0]) < 1e-6  # the symmetric lines keep the body centred
    assert len((tmp_path / "mooring-output" / "mooring_line2.csv").read_text().splitlines()) == 102
    assert (tmp_path / "moordyn-files" / "mooring.out").is_file()
