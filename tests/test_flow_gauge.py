"""Flow gauges (`shoal.probes.FlowGauge`, `shoal.probes.flow`): the volume that has passed a section and
the flow rate through it."""

import csv

import numpy as np
import pytest

import shoal
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.check import check_case
from shoal.errors import InputError
from shoal.geometry import Box, Tank
from shoal.probes import FlowGauge
from shoal.probes.flow import crossings, flow_measure


def _rows(path):
    rows = list(csv.reader(open(path)))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def test_crossings_count_each_pass_once_with_its_sign():
    """Below -> at or above the plane is +1, back is -1, no change or an unknown start is 0; with a
    period the short way round is taken and a pass through the period's seam is no crossing."""
    prev = np.array([0.3, 0.7, 0.3, 0.7, np.nan, 0.5, 0.49])
    now = np.array([0.7, 0.3, 0.4, 0.9, 0.9, 0.6, 0.5])
    assert crossings(prev, now, 0.5).tolist() == [1, -1, 0, 0, 0, 0, 1]
    # period 1, plane at 0.5: 0.9 -> 0.1 went up through the seam (x = 1 = 0), 0.1 -> 0.9 down through
    # it: neither crossed 0.5; 0.4 -> 0.6 and 0.6 -> 0.4 did; 0.95 -> 0.55 (short way: down 0.4) did not
    prev = np.array([0.9, 0.1, 0.4, 0.6, 0.95, 0.45])
    now = np.array([0.1, 0.9, 0.6, 0.4, 0.55, 0.05])
    assert crossings(prev, now, 0.5, period=1.0).tolist() == [0, 0, 1, -1, 0, 0]
    # ... and 0.3 -> 0.7 the short way is up through 0.5, but 0.2 -> 0.8 is down through the seam
    assert crossings(np.array([0.3, 0.2]), np.array([0.7, 0.8]), 0.5, period=1.0).tolist() == [1, 0]


def _stream(dp, nx, ny, nz, offset):
    g = np.stack(np.meshgrid((np.arange(nx) + offset) * dp, (np.arange(ny) + 0.5) * dp, (np.arange(nz) + 0.5) * dp,
                             indexing="ij"), -1).reshape(-1, 3)
    return g


@pytest.mark.parametrize("offset", [0.5, 0.137, 0.9])
def test_uniform_stream_on_a_lattice_is_measured_exactly(offset):
    """A 3D lattice moving at U along x, at any offset of the lattice from the plane: the volume passed in
    a time dt with U dt = 3 dp is 3 layers of the section, U A dt; the slab rate is U A (two layers in a
    slab 2 dp wide, whatever the offset); the extent lo/hi keeps the columns within it only; walls and
    the particles of the other ids do not count."""
    dp, U, rho0 = 0.01, 0.8, 1000.0
    nx, ny, nz = 20, 6, 5
    pos = _stream(dp, nx, ny, nz, offset)
    n = len(pos)
    kinds = np.zeros(n, int)
    kinds[:ny * nz] = 1  # the first x layer are walls: never counted
    ids = np.arange(n)[::-1].copy()  # ids are not the rows
    vel = np.tile([U, 0.0, 0.0], (n, 1))
    rho = np.full(n, rho0)
    mass = rho0 * dp**3
    spec = FlowGauge(name="f", at=0.105, interval=1.0)
    prev, crossed, q, area = flow_measure(pos, vel, rho, kinds, ids, spec, 3, dp, mass, None, n + 5)
    assert crossed is None and np.isnan(prev[n:]).all() and np.isnan(prev[ids[kinds == 1]]).all()
    A = ny * dp * nz * dp
    assert q == pytest.approx(U * A, rel=1e-12)
    assert area == pytest.approx(A, rel=1e-12)  # the wetted area: the lattice's section
    dt = 3 * dp / U
    now, crossed, _, _ = flow_measure(pos + vel * dt, vel, rho, kinds, ids, spec, 3, dp, mass, prev, n + 5)
    assert crossed * dp**3 == pytest.approx(U * A * dt, rel=1e-12)
    # the section's extent: y in [0, 2 dp] holds 2 of the 6 rows of columns (y = 0.5, 1.5 dp)
    part = spec.model_copy(update={"lo": (0.0, 0.0, 0.0), "hi": (0.0, 2.0 * dp, 1.0)})
    _, c2, q2, a2 = flow_measure(pos + vel * dt, vel, rho, kinds, ids, part, 3, dp, mass, prev, n + 5)
    assert c2 == crossed * 2 // ny
    assert q2 == pytest.approx(U * A * 2 / ny, rel=1e-12) and a2 == pytest.approx(A * 2 / ny, rel=1e-12)
    # the stream reversed: the same volume back, negative
    _, back, qb, _ = flow_measure(pos + vel * dt, -vel, rho, kinds, ids, spec, 3, dp, mass, now, n + 5)
    assert back == 0  # nothing moved since `now`
    _, back, _, _ = flow_measure(pos, -vel, rho, kinds, ids, spec, 3, dp, mass, now, n + 5)
    assert back == -crossed and qb == pytest.approx(-U * A, rel=1e-12)


def test_flow_gauge_spec_is_checked():
    with pytest.raises(ValueError, match="hi"):
        FlowGauge(name="f", at=0.0, lo=(0, 1.0, 0), hi=(0, 0.5, 1), interval=0.1)
    flat = FlowGauge(name="f", at=0.4, lo=(0, 0, 0.05), hi=(0, 0, 0.05), interval=0.1)  # no height
    with pytest.raises(InputError, match=r"lo\[2\] = hi\[2\] = 0.05 m: the section has no extent in z"):
        check_case(_ritter(0.02).model_copy(update={"probes": [flat]}))
    with pytest.raises(ValueError):
        FlowGauge(name="f", axis="w", at=0.0, interval=0.1)
    case = _ritter(0.02).model_copy(update={"probes": [FlowGauge(name="f", axis="y", at=0.0, interval=0.1)]})
    with pytest.raises(InputError, match="axis = 'y' in a 2D run"):
        check_case(case)
    case = _ritter(0.02).model_copy(update={"probes": [FlowGauge(name="f", at=7.0, interval=0.1)]})
    with pytest.raises(InputError, match="x = 7 m lies outside the domain"):
        check_case(case)


def test_flow_gauge_round_trips_a_case_file(tmp_path):
    case = _ritter(0.02).model_copy(update={"probes": [FlowGauge(name="gate", at=0.4, lo=(0, 0, 0), hi=(0, 0, 0.05),
                                                                 interval=0.01)]})
    shoal.write_case(case, tmp_path / "c.toml")
    text = (tmp_path / "c.toml").read_text()
    assert 'type = "flow"' in text and "at = 0.4" in text
    assert shoal.load_case(tmp_path / "c.toml").probes == case.probes


H, X0, LENGTH = 0.1, 0.4, 1.3
RITTER_Q = 8.0 / 27.0 * np.sqrt(9.81) * H**1.5


def _ritter(dp, end_time=0.6, options=None, probes=()):
    """A 2D dam break over a dry, free-slip bed: water H = 0.1 m deep in x < X0 = 0.4 m (4 H), tank 1.3 m."""
    return Case(name="ritter", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=H, surface_level=H),
                options=options or shoal.SPHOptions(visco_bound_factor=0.0),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(LENGTH, 0, 2 * H)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(X0, 0, H)))], probes=list(probes),
                output=Output(interval=end_time))


@pytest.fixture(scope="module")
def ritter_run(tmp_path_factory):
    """The dam break at dp = H/20 (1,600 fluid particles) to t = 0.6 s, flow gauges at the gate and
    half-way along the reservoir every 0.01 s; the run directory and the Model at the end."""
    from shoal.runner import build_model
    from shoal.probes.flow import FlowRecorder
    from shoal.simulation import Simulation, TimeInterval

    out = tmp_path_factory.mktemp("ritter")
    specs = [FlowGauge(name="gate", at=X0, interval=0.01), FlowGauge(name="mid", at=0.2, interval=0.01)]
    case = _ritter(H / 20, probes=specs)
    model = build_model(case)
    sim = Simulation(model, end_time=case.end_time)
    recs = [FlowRecorder(s, out, model) for s in specs]
    for r in recs:
        sim.add_callback(r, TimeInterval(0.01), name=r.spec.name)
    sim.run()
    for r in recs:  # one more sample at the end state, to compare with the particles there
        r(sim)
        r.close()
    return out, model, case, recs


def test_volume_passed_is_the_water_beyond_the_section(ritter_run):
    """Mass conservation, exactly: the volume counted through the gate is the particles' volume beyond it
    at the end, and the volume between the two gauges changed by what passed the first minus what passed
    the second (the count is per particle, so to the last particle)."""
    out, model, case, (gate, mid) = ritter_run
    pos, kinds, _ = model.owned_particles()
    x = pos[kinds == 0, 0]
    V = model.particle_volume
    assert V == pytest.approx(case.dp**2)
    assert np.count_nonzero(x >= X0) * V == pytest.approx(gate.volume, abs=1e-9 * V)
    n0 = round(0.2 / case.dp) * round(H / case.dp)  # particles in 0.2 <= x < 0.4 at t = 0
    between = np.count_nonzero((x >= 0.2) & (x < X0))
    assert (between - n0) * V == pytest.approx(mid.volume - gate.volume, abs=1e-9 * V)
    assert gate.volume > 0.1 * X0 * H  # a tenth of the reservoir has gone


def test_discharge_at_the_gate_is_ritters(ritter_run):
    """Ritter's dam break (dry, frictionless bed; shallow water): at the gate the depth is 4H/9 and the
    velocity 2/3 sqrt(gH), so the discharge is q = 8/27 sqrt(g) H^(3/2), constant until the wave reflected
    from the reservoir's end returns (T = t sqrt(g/H) of about 6 here, 4 H of reservoir). Averaged over
    T = 2-5, after the column's first fall (vertical accelerations that shallow-water theory leaves out),
    both measures of the gauge give it within 8 %: measured -5.1 % (count) and -6.1 % (slab) at H/20, and
    -4.1 % / -2.8 % at H/40 (the error falls with dp; the wave gauge at the gate reads 0.50 H and 0.485 H,
    above Ritter's 4/9 H: the vertical accelerations that shallow-water theory leaves out). The slab's time
    integral is the counted volume within 3 % (two measures of one flux; measured 1.0 % at H/20)."""
    out, model, case, _ = ritter_run
    head, d = _rows(out / "flow_gate.csv")
    assert head == ["time", "volume", "rate", "rate_slab", "area_slab"]
    t, vol, rate, slab, _ = d[:-1].T  # the last row is the extra end sample
    assert np.isnan(rate[0]) and vol[0] == 0.0
    T = t * np.sqrt(9.81 / H)
    w = (T >= 2.0) & (T <= 5.0)
    q_count = (vol[w][-1] - vol[w][0]) / (t[w][-1] - t[w][0])
    q_slab = float(np.mean(slab[w]))
    assert abs(q_count / RITTER_Q - 1) < 0.08, q_count / RITTER_Q
    assert abs(q_slab / RITTER_Q - 1) < 0.08, q_slab / RITTER_Q
    integral = float(np.sum(0.5 * (slab[1:] + slab[:-1]) * np.diff(t)))
    assert integral == pytest.approx(vol[-1], rel=0.03)


def test_flow_gauge_and_tracker_offline_read_the_runs_particles(tmp_path):
    """Run offline over the snapshots (`run_probes_offline`), a flow gauge counts the volume the run's
    gauge counted at the snapshot times exactly (the net count depends only on where each particle was and
    is: snapshot rows are in cell order, so the particles must be matched by their ids), and a tracker by
    id follows the particle the run's tracker followed (to float32 snapshot precision)."""
    from shoal.probes import Tracker
    from shoal.probes.offline import run_probes_offline

    case = _ritter(H / 10, end_time=0.3)
    parts = case.particles()
    front = np.flatnonzero(parts.kinds == 0)[np.argsort(-parts.positions[parts.kinds == 0, 0])][:3]  # at the gate
    specs = [FlowGauge(name="gate", at=X0, interval=0.05), Tracker(name="t", ids=front.tolist(), interval=0.05)]
    case = _ritter(H / 10, end_time=0.3, probes=specs).model_copy(update={"output": Output(interval=0.05)})
    shoal.run_case(case, tmp_path / "run", plot=False, progress=False)
    flow, track = run_probes_offline(tmp_path / "run", specs)
    _, on = _rows(tmp_path / "run" / "flow_gate.csv")
    off = np.array(flow.rows)
    assert off.shape[0] == on.shape[0] == 7 and np.allclose(off[:, 0], on[:, 0])
    assert on[-1, 1] > 20 * case.dp**2  # water has passed the gate
    np.testing.assert_allclose(off[:, 1], on[:, 1], rtol=0, atol=1e-12)
    _, tr_on = _rows(tmp_path / "run" / "track_t.csv")
    _, tr_off = _rows(tmp_path / "run" / "offline" / "track_t.csv")
    assert tr_off.shape == tr_on.shape and tr_on[-1, 1] - tr_on[0, 1] > 5 * case.dp  # they ran
    np.testing.assert_allclose(tr_off[:, 1:], tr_on[:, 1:], atol=1e-6)
