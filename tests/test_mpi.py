"""MPI domain decomposition (shoal.parallel, issue 9): halo, migration, and a
small 3D dam break on 2 ranks against the single-process run.

The tests that start ranks are skipped when mpi4py is not installed or
``mpiexec`` does not start 2 ranks here (``pip install '.[mpi]'`` brings both
from wheels); the slab cuts, the row packing and the single-process path are
tested without MPI. Each rank runs with one Numba thread.

Under CI (the environment variable ``CI`` set to anything but "", "0" or
"false", as ``.ci/run`` does) those conditions fail the tests, with the same
message, instead of skipping them: the test extra installs mpi4py and the
MPICH wheel, so a CI run where the ranks cannot start is broken, not exempt.
``mpiexec`` is looked for beside ``sys.executable`` first (the venv's, which
``.ci/run`` does not put on the PATH), then on the PATH;
``SHOAL_TEST_MPIEXEC`` names another launcher (a path or a command name).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
HERE = Path(__file__).resolve().parent


def strict():
    """True under CI: the environment variable ``CI`` set to anything but "", "0" or "false"."""
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false")


def unavailable(reason):
    """Skip the test for `reason` (no MPI here), or fail it with the same message under CI (`strict`)."""
    if strict():
        pytest.fail(reason, pytrace=False)
    pytest.skip(reason)


def _mpiexec():
    named = os.environ.get("SHOAL_TEST_MPIEXEC")
    if named:
        exe = shutil.which(named)
    else:
        exe = shutil.which("mpiexec", path=str(Path(sys.executable).parent)) or shutil.which("mpiexec")
    if exe is None:
        unavailable(f"no mpiexec{f' {named!r} (SHOAL_TEST_MPIEXEC)' if named else ''} "
                    "(pip install mpich, or a system MPI)")
    try:
        version = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired):
        unavailable("mpiexec --version failed")
    extra = ["--oversubscribe"] if "Open MPI" in version or "OpenRTE" in version else []
    return [exe, *extra]


def _env():
    env = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("SHOAL_MPI", None)
    return env


@pytest.fixture(scope="module")
def mpiexec():
    """The command that starts ranks (``[mpiexec, options...]``), after a probe that 2 ranks start
    and see each other; skips, or fails under CI (`strict`), when they cannot."""
    try:
        import mpi4py  # noqa: F401
    except ImportError as exc:
        unavailable(f"could not import 'mpi4py': {exc}")
    cmd = _mpiexec()
    probe = "from mpi4py import MPI; import sys; sys.exit(0 if MPI.COMM_WORLD.Get_size() == 2 else 1)"
    try:
        r = subprocess.run([*cmd, "-n", "2", sys.executable, "-c", probe], capture_output=True, text=True,
                           timeout=60, env=_env())
    except subprocess.TimeoutExpired:
        unavailable("mpiexec -n 2 did not finish in 60 s")
    except OSError as exc:
        unavailable(f"mpiexec -n 2 does not run 2 ranks here: {exc}")
    if r.returncode != 0:
        unavailable(f"mpiexec -n 2 does not run 2 ranks here: {r.stderr.strip()[-300:]}")
    return cmd


@pytest.mark.parametrize("ci", ["", "0", "false", "1", "true"])
def test_no_mpi_skips_or_fails_under_ci(ci, monkeypatch):
    """Without a launcher the tests that start ranks skip, and fail with the same message when CI is
    set (`unavailable`): SHOAL_TEST_MPIEXEC names one that does not exist."""
    monkeypatch.setenv("CI", ci)
    monkeypatch.setenv("SHOAL_TEST_MPIEXEC", "/nonexistent/mpiexec")
    expected = pytest.fail.Exception if ci in ("1", "true") else pytest.skip.Exception
    with pytest.raises(expected, match=r"no mpiexec '/nonexistent/mpiexec' \(SHOAL_TEST_MPIEXEC\)"):
        _mpiexec()


def test_world_is_none_outside_mpi():
    """The single-process path never imports mpi4py nor changes the Model."""
    code = ("import sys, shoal.parallel as p, shoal.runner; "
            "assert p.world() is None and 'mpi4py' not in sys.modules; print('ok')")
    env = _env()
    for v in ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MV2_COMM_WORLD_SIZE", "PMIX_SIZE"):
        env.pop(v, None)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0 and "ok" in r.stdout, r.stderr


def test_slab_cuts():
    from shoal.errors import InputError
    from shoal.parallel.decomposition import slab_cuts

    x = np.linspace(0.0, 1.0, 1001)
    cuts = slab_cuts(x, np.ones_like(x), 4, 0.1)
    assert cuts[0] == -np.inf and cuts[-1] == np.inf
    assert np.allclose(cuts[1:-1], [0.25, 0.5, 0.75], atol=2e-3)
    # weights: the heavy half gets the cut
    w = np.where(x < 0.5, 3.0, 1.0)
    assert slab_cuts(x, w, 2, 0.1)[1] < 0.5
    # a narrow slab is widened to the halo width
    xs = np.concatenate([np.zeros(900), np.linspace(0, 1, 100)])
    c = slab_cuts(xs, np.ones_like(xs), 2, 0.3)
    assert c[1] >= 0.3 - 1e-12
    with pytest.raises(InputError, match="at most 3 ranks"):
        slab_cuts(x, np.ones_like(x), 5, 0.3)


def test_pack_unpack_round_trip():
    """Rows of float64, float32, int8 and int32 arrays travel exactly through the float64 buffer."""
    from shoal.parallel.halo import columns, pack, unpack

    rng = np.random.default_rng(0)
    arrays = [rng.normal(size=(50, 3)), rng.normal(size=(50, 2)).astype(np.float32),
              rng.integers(0, 5, 50).astype(np.int8), rng.integers(0, 2**31 - 1, 50).astype(np.int32),
              rng.normal(size=50).astype(np.float32)]
    rows = np.array([3, 7, 7, 49, 0])
    buf = pack(arrays, rows)
    assert buf.shape == (5, columns(arrays)) == (5, 8)
    out = [np.zeros_like(a) for a in arrays]
    unpack(out, buf, slice(10, 15))
    unpack(out, buf, np.array([20, 21, 22, 23, 24]))
    for a, o in zip(arrays, out):
        assert np.array_equal(o[10:15], a[rows]) and np.array_equal(o[20:25], a[rows])


def test_halo_migration_and_rates(mpiexec):
    """Rates near the slab cut equal the single-process rates to round-off (float32, after random
    displacements, velocities and densities; default scheme, SPS + XSPH + diffusion, and mDBC walls,
    whose densities too are compared); the time step
    is the same; particles pushed across the cut each way end up on exactly one rank. The particle probes
    (tracked positions, the nearest fluid particles to start points, max-z and run-up gauges with
    regions across the cut) equal the single-process Model's on the same particles exactly (a max and a
    selection have no round-off), on every rank, and ignore the ghosts (moved 1 m up: nothing changes;
    with the ghosts counted the check fails)."""
    r = subprocess.run([*mpiexec, "-n", "2", sys.executable, str(HERE / "mpi" / "check_halo.py")],
                       capture_output=True, text=True, timeout=300, env=_env())
    line = [s for s in r.stdout.splitlines() if s.startswith("RESULTS ")]
    assert line, r.stdout[-2000:] + r.stderr[-3000:]
    res = json.loads(line[0][len("RESULTS "):])
    assert res["default_fluid_near_cut"] > 100
    assert res["default_rates_rel_err"] < 1e-5, res
    assert res["sps_xsph_symplectic_rates_rel_err"] < 1e-5, res
    assert res["mdbc_rates_rel_err"] < 1e-5, res  # mDBC walls: halo as deep as their ghost nodes
    assert res["riemann_rates_rel_err"] < 1e-5, res  # the Riemann wall term: the walls' normals by id
    assert res["default_dt_rel_err"] < 1e-6 and res["sps_xsph_symplectic_dt_rel_err"] < 1e-6, res
    assert res["migration_unique"] and res["migration_moved_on_one_rank"] and res["migration_owned_inside_slab"], res
    # trackers, max-z and run-up gauges over the cut: exactly the single-process values, on every rank, from
    # the owned particles only (ghosts moved 1 m up change nothing); the tracked ids lie on both ranks, and
    # a run-up's highest particle and its landward end lie on different sides of the cut
    assert res["particle_probes_equal"] and res["particle_probes_same_on_every_rank"], res
    assert res["particle_probes_ghosts_ignored"] and res["particle_probes_dry_is_nan"], res
    assert min(res["particle_probes_ids_per_rank"]) > 0 and res["particle_probes_runup_split_across_cut"] > 0, res
    assert r.returncode == 0, r.stderr[-2000:]


def _front(vtu):
    from shoal.output.vtu import read_vtu

    pts, data = read_vtu(vtu)[:2]
    fluid = np.asarray(data["kind"]) == 0
    return float(pts[fluid, 0].max()), np.asarray(data["id"]), pts


def _particle_probes(interval):
    """A tracker, a max-z and a run-up gauge for the small 3D dam break (dp = 0.02 m, water in
    x < 0.146 m, 0.16 m wide; 2 ranks: the slab cut starts at x = 0.17 m): the tracker follows the
    fluid particles nearest to the front's foot (it runs across the cut), to the back of the column
    (stays on rank 0) and to the front's top corner, and id 100 (fluid, at the back); the max-z gauge sits
    on the cut (dry at first: NaN), the run-up range spans it, its y band holds one column of particles;
    pressure sensors on the bed under the column (rank 0), on the cut, and beyond it (rank 1)."""
    from shoal.probes import FlowGauge, ForceGauge, MaxZGauge, PressureSensors, RunupGauge, Tracker

    return [Tracker(name="t", start=[(0.128, 0.072, 0.012), (0.012, 0.07, 0.15), (0.13, 0.09, 0.288)], ids=[100],
                    interval=interval),
            MaxZGauge(name="cut", x=0.17, y=0.08, radius=0.03, interval=interval),
            RunupGauge(name="r", x0=0.1, x1=0.5, y=0.07, band=0.02, interval=interval),
            RunupGauge(name="wet", x0=0.0, x1=0.5, y=0.07, band=0.06, min_depth=0.02, interval=interval),
            FlowGauge(name="cut", at=0.17, interval=interval),
            ForceGauge(name="tank", solid="tank", interval=interval),
            PressureSensors(name="bed", points=[(0.07, 0.08, 0.0), (0.17, 0.08, 0.0), (0.25, 0.08, 0.0)],
                            normal=(0.0, 0.0, 1.0), interval=interval)]


@pytest.fixture(scope="module")
def dam_break_runs(mpiexec, tmp_path_factory):
    """A small 3D dam break (9,204 particles, symplectic, float32, to t = 0.15 s, a gauge in the column,
    the particle probes of `PARTICLE_PROBES`) run once on 1 process and once on 2 ranks (`shoal run`):
    (case, run dir of 1, run dir of 2, stdouts)."""
    import shoal
    from shoal.cases.dam_break import dam_break_3d
    from shoal.probes import WaveGauge

    tmp_path = tmp_path_factory.mktemp("dam_break")
    case = dam_break_3d(dp=0.02, end_time=0.15, output_interval=0.05,
                        options=shoal.SPHOptions(integrator="symplectic"))
    case = case.model_copy(update={"probes": [WaveGauge(name="column", x=0.07, y=0.08, z0=0.0, z1=0.35,
                                                        interval=0.025), *_particle_probes(0.025)]})
    one, two = _run_one_and_two(mpiexec, case, tmp_path)
    return case, tmp_path / "one", tmp_path / "two", (one.stdout, two.stdout)


def _run_one_and_two(mpiexec, case, tmp_path):
    """`shoal run` the case on 1 process (into tmp_path/one) and on 2 ranks (tmp_path/two):
    the two CompletedProcesses, both checked to have succeeded."""
    import shoal

    toml = tmp_path / "case.toml"
    shoal.write_case(case, toml)
    base = [sys.executable, "-m", "shoal", "run", str(toml), "--no-plot", "--no-progress"]
    one = subprocess.run([*base, "--out", str(tmp_path / "one")], capture_output=True, text=True, timeout=300,
                         env=_env())
    assert one.returncode == 0, one.stderr[-2000:]
    two = subprocess.run([*mpiexec, "-n", "2", *base, "--out", str(tmp_path / "two")], capture_output=True,
                         text=True, timeout=300, env=_env())
    assert two.returncode == 0, two.stdout[-1000:] + two.stderr[-2000:]
    return one, two


def test_dam_break_two_ranks_matches_one(dam_break_runs):
    """A small 3D dam break (9,204 particles, symplectic, float32, to t = 0.15 s) on 2 ranks against 1:
    the same particles (ids), so the mass (count x particle mass) is exactly conserved; the front and a
    gauge in the column within 0.01 dp. The runs differ by round-off only (the order of the pair sums
    within a cell differs, so they are not bitwise equal): measured 4e-8 m at the front and 1e-8 m at the
    gauge at t = 0.2 s (dp = 0.02 m); a halo or migration fault gives differences of the order of dp."""
    case, one, two, (out1, out2) = dam_break_runs
    dp = case.dp
    assert out2.count("shoal: ") == out1.count("shoal: ")  # rank 0 speaks alone
    resolved = json.loads((two / "resolved.json").read_text())
    assert resolved["mpi"]["ranks"] == 2
    f1, ids1, p1 = _front(one / "dam-break-3d_0003.vtu")
    f2, ids2, p2 = _front(two / "dam-break-3d_0003.pvtu")
    # every particle exactly once, none lost: mass = count x particle mass, exactly conserved
    assert len(ids2) == len(ids1) == case.n_particles
    assert np.array_equal(np.sort(ids2), np.arange(case.n_particles))
    assert f1 - case.parameters["a"] > 2 * dp  # the surge has moved
    assert abs(f2 - f1) <= 0.01 * dp, (f1, f2)
    g1 = np.loadtxt(one / "gauge_column.csv", delimiter=",", skiprows=1)
    g2 = np.loadtxt(two / "gauge_column.csv", delimiter=",", skiprows=1)
    assert g1.shape == g2.shape and np.allclose(g1[:, 0], g2[:, 0])
    assert g1[0, 1] - g1[-1, 1] > 2 * dp  # the level in the column falls
    assert np.max(np.abs(g1[:, 1] - g2[:, 1])) <= 0.01 * dp, np.column_stack([g1, g2[:, 1]])
    log = (two / "run.log").read_text()
    assert "2 MPI ranks" in log and "communication" in log and "load balance at the end" in log
    mem = [line for line in log.splitlines() if "memory per rank, host arrays" in line]
    assert len(mem) == 1 and "rank 0: " in mem[0] and "rank 1: " in mem[0], log
    rows = [int(r.split(" rows")[0].split(": ")[-1]) for r in mem[0].split(": ", 1)[1].split("; ")]
    # each rank holds its slab, not the case; its arrays grow 25 % beyond what it holds, capped at the
    # case's size, and with the Adami walls' 4h halo rank 1 starts holding 7,860 of this small tank's 9,204
    # particles, so its rows may reach the cap: the two together must stay below two copies of the case
    assert min(rows) < case.n_particles and sum(rows) < 2 * case.n_particles, mem


def _csv_rows(path):
    import csv

    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [r[0] for r in rows[1:]], np.array([[float(v) for v in r[1:]] for r in rows[1:]])


def test_particle_probes_two_ranks_match_one(dam_break_runs):
    """Trackers, max-z, run-up and flow gauges under MPI (`_particle_probes` in the small 3D dam break, 7
    samples to t = 0.15 s): the 2-rank run writes the files of the single-process run: the same header
    (the same particles chosen from the start points), the same sample times (as text), NaN in the same
    places (the max-z gauge on the cut is dry at first), and values within 1e-6 m (5e-5 dp). The tracked
    particle at the front's foot runs across the slab cut (x = 0.17 m; no re-cut in this run) and is
    owned by rank 0 at t = 0 and by rank 1 at the end (the snapshots' pieces), so its rows came from
    both ranks; the max-z gauge's circle and the run-up's range span the cut. Not bitwise: the runs
    differ by round-off (the order of the pair sums within a cell differs), measured at most 3.3e-8 m
    here at t = 0.15 s (the other comparisons: 4e-8 m at the front at 0.2 s, 1.4e-7 m for every
    particle at 0.08 s); 1e-6 m leaves room for that round-off to grow differently elsewhere while a
    particle from the wrong rank or a wrong reduction gives differences of the order of dp (or NaNs
    where the run has values). A ghost copy would differ from its owner by far less (a step's drift):
    `test_halo_migration_and_rates` checks that the ghosts are never read."""
    from shoal.output import read_vtu

    case, one, two, _ = dam_break_runs
    dp = case.dp
    errs = {}
    for name in ("track_t.csv", "maxz_cut.csv", "runup_r.csv", "runup_wet.csv", "flow_cut.csv"):
        h1, t1, v1 = _csv_rows(one / name)
        h2, t2, v2 = _csv_rows(two / name)
        assert h1 == h2 and t1 == t2 and len(t1) == 7, (name, h1, h2, t1, t2)
        assert v1.shape == v2.shape and np.array_equal(np.isnan(v1), np.isnan(v2)), (name, v1, v2)
        errs[name] = float(np.nanmax(np.abs(v1 - v2)))
        assert errs[name] <= 1e-6, (name, errs)
    # the max-z gauge on the cut: dry at t = 0, then the surge reaches it; the run-up always reads
    _, _, mz = _csv_rows(two / "maxz_cut.csv")
    assert np.isnan(mz[0, 0]) and np.all(np.isfinite(mz[-3:, 0])), mz
    _, _, ru = _csv_rows(two / "runup_r.csv")
    assert np.all(np.isfinite(ru)) and ru[0, 0] > ru[-1, 0] + 2 * dp, ru  # the column falls
    # the wet shoreline (min_depth = dp, columns over both ranks' slabs): on the bed at t = 0 (the column's
    # foot, x = a - dp/2), then the surge's tongue carries it across the cut
    _, _, sh = _csv_rows(two / "runup_wet.csv")
    assert abs(sh[0, 0]) < 1e-6 and abs(sh[0, 1] - 0.13) < 1e-6 and sh[-1, 1] > 0.17, sh
    # the force on the tank (its particles on both ranks): the sum over the ranks, the single-process force
    # within 1e-4 of its size (the ghosts a rank reads at a sample are those of the step's last exchange)
    h1, t1, f1 = _csv_rows(one / "force_tank.csv")
    h2, t2, f2 = _csv_rows(two / "force_tank.csv")
    assert h1 == h2 and t1 == t2 and np.max(np.abs(f1 - f2)) <= 1e-4 * np.max(np.abs(f1)), (f1, f2)
    weight = case.n_fluid * 1000 * dp**3 * 9.81  # the column's, 62 N: the tank carries it at t = 0
    assert f1[0, 2] == pytest.approx(-weight, rel=0.05), f1[0]
    # the flow gauge on the cut: particles pass it from rank 0's slab into rank 1's; the volume counted is
    # whole particles (dp^3 each), the same on both runs (checked above), and grows
    _, _, fl = _csv_rows(two / "flow_cut.csv")
    assert fl[0, 0] == 0.0 and fl[-1, 0] > 10 * dp**3 and np.all(np.diff(fl[:, 0]) >= 0), fl
    assert np.allclose(fl[:, 0] / dp**3, np.round(fl[:, 0] / dp**3), atol=1e-6)
    # the pressure sensors on the bed (one on each rank's side and one on the cut): the same readings within
    # 0.5 % of rho0 g h (h = 2a, the column's height): each point's sums come from one rank; a point left
    # out or counted twice reads 0 or twice the pressure; the sensor under the column reads it at t = 0
    h1, t1, p1 = _csv_rows(one / "pressure_bed.csv")
    h2, t2, p2 = _csv_rows(two / "pressure_bed.csv")
    scale = 1000 * 9.81 * 2 * case.parameters["a"]
    assert h1 == h2 and t1 == t2 and np.max(np.abs(p1 - p2)) <= 5e-3 * scale, (p1, p2)
    assert p1[0, 0] == pytest.approx(scale, rel=0.05) and p1[0, 1] == p1[0, 2] == 0.0, p1[0]
    assert np.all(p1[-2:, 1] != 0.0), p1  # the surge has reached the sensor on the cut
    # the tracker: id 100, then the fluid particles nearest to the start points (on the lattice at t = 0)
    head, _, tr = _csv_rows(two / "track_t.csv")
    ids = [int(c[2:]) for c in head[1::3]]
    assert ids[0] == 100 and len(set(ids)) == 4
    xyz = tr.reshape(len(tr), 4, 3)
    assert np.allclose(xyz[0, 1:], [[0.13, 0.07, 0.01], [0.01, 0.07, 0.15], [0.13, 0.09, 0.29]], atol=1e-6)
    assert xyz[0, 1, 0] < 0.17 < xyz[-1, 1, 0]  # the foot of the front ran across the cut (x = 0.17 m)
    owners = []
    for snap in ("dam-break-3d_0000", "dam-break-3d_0003"):
        owners.append([r for r in range(2) if ids[1] in read_vtu(two / snap / f"{snap}_{r}.vtu")[1]["id"]])
    assert owners == [[0], [1]], owners


def test_pvtu_pieces_are_the_single_process_snapshots(dam_break_runs):
    """Per-rank VTU pieces: the 2-rank run's .pvd lists one .pvtu per snapshot (the same times as the
    single-process .pvd), each .pvtu (parsed as XML) names two existing pieces whose arrays have the
    types and components it declares; the union of the pieces holds every particle exactly once (no
    piece empty, none shared) with the single-process snapshot's fields, and positions within 0.01 dp
    of it (round-off, as above)."""
    import xml.etree.ElementTree as ET

    from shoal.output import read_vtu
    from shoal.output.pvd import PVDWriter

    case, one, two, _ = dam_break_runs
    e1, e2 = PVDWriter._load(one / "dam-break-3d.pvd"), PVDWriter._load(two / "dam-break-3d.pvd")
    assert [t for t, _ in e1] == [t for t, _ in e2] and len(e2) == 4
    assert not list(two.glob("*.vtu"))  # nothing gathered
    for (t, f1), (_, f2) in zip(e1, e2):
        assert f2.endswith(".pvtu") and (two / f2).is_file(), f2
        root = ET.parse(two / f2).getroot()
        assert root.get("type") == "PUnstructuredGrid"
        grid = root.find("PUnstructuredGrid")
        declared = {da.get("Name"): (da.get("type"), da.get("NumberOfComponents"))
                    for da in grid.iterfind("PPointData/PDataArray")}
        assert set(declared) == {"velocity", "density", "pressure", "id", "kind", "free_surface"}
        assert grid.find("PPoints/PDataArray").get("type") == "Float64"
        sources = [p.get("Source") for p in grid.iterfind("Piece")]
        assert len(sources) == 2
        ids_per_piece = []
        for src in sources:
            piece = two / Path(f2).parent / src
            assert piece.is_file(), piece
            proot = ET.parse(piece).getroot()
            arrays = {da.get("Name"): (da.get("type"), da.get("NumberOfComponents"))
                      for da in proot.iterfind("UnstructuredGrid/Piece/PointData/DataArray")}
            assert arrays == declared, (arrays, declared)
            ids_per_piece.append(read_vtu(piece)[1]["id"])
        assert all(len(i) for i in ids_per_piece)
        assert not set(ids_per_piece[0].tolist()) & set(ids_per_piece[1].tolist())
        p1, d1 = read_vtu(one / f1)
        p2, d2 = read_vtu(two / f2)  # the union of the pieces
        assert set(d1) == set(d2) and len(p2) == len(p1) == case.n_particles
        o1, o2 = np.argsort(d1["id"]), np.argsort(d2["id"])
        assert np.array_equal(d1["id"][o1], d2["id"][o2]) and np.array_equal(d1["kind"][o1], d2["kind"][o2])
        for k in d1:
            assert d1[k].dtype == d2[k].dtype, k
        assert np.max(np.abs(p1[o1] - p2[o2])) <= 0.01 * case.dp, t


def test_pvtu_round_trip_with_an_empty_piece(tmp_path):
    """write_pvtu + read_vtu on the .pvtu: the pieces concatenated in order, an empty piece included."""
    from shoal.output import read_vtu, write_pvtu, write_vtu
    from shoal.output.vtu import pvtu_layout, pvtu_pieces

    rng = np.random.default_rng(3)
    parts = []
    for k, n in enumerate((5, 0, 7)):
        pts = rng.normal(size=(n, 3))
        data = {"velocity": rng.normal(size=(n, 3)).astype(np.float32), "id": np.arange(n, dtype=np.int32) + 10 * k,
                "kind": np.zeros(n, np.int8)}
        (tmp_path / "s").mkdir(exist_ok=True)
        write_vtu(tmp_path / "s" / f"s_{k}.vtu", pts, data, time=0.5)
        parts.append((pts, data))
    layout = pvtu_layout(parts[0][0], parts[0][1])
    assert layout["point_data"] == [("velocity", "Float32", 3), ("id", "Int32", None), ("kind", "Int32", None)]
    write_pvtu(tmp_path / "s.pvtu", [f"s/s_{k}.vtu" for k in range(3)], layout)
    assert [p.name for p in pvtu_pieces(tmp_path / "s.pvtu")] == ["s_0.vtu", "s_1.vtu", "s_2.vtu"]
    pts, data = read_vtu(tmp_path / "s.pvtu")
    assert np.array_equal(pts, np.concatenate([p for p, _ in parts]))
    assert np.array_equal(data["id"], np.concatenate([d["id"] for _, d in parts]))
    assert data["velocity"].shape == (12, 3) and data["velocity"].dtype == np.float32


def test_too_many_ranks_is_one_line(mpiexec, tmp_path):
    """More ranks than slabs at least one halo wide: exit status 2, one line naming the limit."""
    r = subprocess.run([*mpiexec, "-n", "3", sys.executable, "-m", "shoal", "run", "dam-break-3d", "--dp", "0.01",
                        "--param", "tank_length=0.05", "--param", "a=0.05", "--end-time", "0.01", "--out",
                        str(tmp_path / "x"), "--no-plot", "--no-progress"],
                       capture_output=True, text=True, timeout=120, env=_env())
    assert r.returncode == 2, r.stdout + r.stderr
    lines = [s for s in r.stderr.splitlines() if s.strip()]
    assert len(lines) == 1 and "too many" in lines[0] and "at most" in lines[0], r.stderr


def test_failing_rank_ends_every_rank(mpiexec, tmp_path):
    """An error on one rank alone (injected in its 5th rate evaluation) ends every rank with that rank's
    message (MPI_Abort) instead of leaving the other waiting in the next exchange."""
    r = subprocess.run([*mpiexec, "-n", "2", sys.executable, str(HERE / "mpi" / "fail_one_rank.py"),
                        str(tmp_path / "run")], capture_output=True, text=True, timeout=180, env=_env())
    assert r.returncode != 0
    assert "shoal: MPI rank 1: unexpected error" in r.stderr and "injected failure on rank 1" in r.stderr, r.stderr


def test_instability_is_collective(mpiexec, tmp_path):
    """A blow-up found on any rank stops every rank together: exit status 3, one message naming the
    particle and the rank, and the bad state in <case>_unstable.pvtu and its per-rank pieces."""
    import shoal
    from shoal.cases.dam_break import dam_break_3d

    case = dam_break_3d(dp=0.02, end_time=0.1, options=shoal.SPHOptions(fixed_dt=1.5e-3, integrator="symplectic"))
    shoal.write_case(case, tmp_path / "blow.toml")
    r = subprocess.run([*mpiexec, "-n", "2", sys.executable, "-m", "shoal", "run", str(tmp_path / "blow.toml"),
                        "--out", str(tmp_path / "run"), "--no-plot", "--no-progress"],
                       capture_output=True, text=True, timeout=180, env=_env())
    assert r.returncode == 3, r.stdout + r.stderr
    lines = [s for s in r.stderr.splitlines() if s.strip()]
    assert len(lines) == 1 and "run stopped: unstable at step" in lines[0] and "(MPI rank " in lines[0], r.stderr
    assert (tmp_path / "run" / "dam-break-3d_unstable.pvtu").exists()
    assert len(list((tmp_path / "run" / "dam-break-3d_unstable").glob("dam-break-3d_unstable_*.vtu"))) == 2


def test_rebalance_settings():
    """Load-balancing settings: arguments, then the environment, then the defaults; bad values are one line."""
    from shoal.errors import InputError
    from shoal.parallel.rebalancer import rebalance_settings

    assert rebalance_settings(environ={}) == (20, 1.1)
    assert rebalance_settings(environ={"SHOAL_MPI_REBALANCE_INTERVAL": "7",
                                       "SHOAL_MPI_REBALANCE_THRESHOLD": "1.3"}) == (7, 1.3)
    assert rebalance_settings(0, 1.0, environ={"SHOAL_MPI_REBALANCE_INTERVAL": "x"}) == (0, 1.0)
    for env, match in (({"SHOAL_MPI_REBALANCE_INTERVAL": "ten"}, "whole number"),
                       ({"SHOAL_MPI_REBALANCE_INTERVAL": "-1"}, "whole number"),
                       ({"SHOAL_MPI_REBALANCE_THRESHOLD": "0.9"}, ">= 1"),
                       ({"SHOAL_MPI_REBALANCE_THRESHOLD": "nan"}, ">= 1")):
        with pytest.raises(InputError, match=match) as err:
            rebalance_settings(environ=env)
        assert "\n" not in str(err.value)


def test_rebalance_from_unbalanced_cut_matches_one_rank(mpiexec, tmp_path):
    """A 3D dam break (9,204 particles, symplectic, float32, to t = 0.08 s, ~400 steps) started on 2 ranks
    from a cut that gives rank 0 a quarter of the weighted count (fluid 1, wall 0.25; imbalance max/mean
    1.60) and re-balanced every 5 steps above max/mean 1.05: the first check re-cuts (measured: weighted
    counts 589.5 / 2341.5 -> 1450.5 / 1480.5, imbalance 1.010; a cut cannot split the 174 wall particles
    (43.5) that share one x plane); at the end the imbalance is still below 1.06 (measured 1.020); every
    particle is owned exactly once, inside its rank's slab (mass = count x particle mass, exact); the
    run-time cut code on the ranks' slabs gives the start's cut code on the gathered particles; every
    particle's position equals the single-process run's within 0.01 dp (measured 1.4e-7 m = 7e-6 dp)."""
    script = str(HERE / "mpi" / "check_rebalance.py")
    one = subprocess.run([sys.executable, script, str(tmp_path / "one.npz")], capture_output=True, text=True,
                         timeout=300, env=_env())
    assert one.returncode == 0, one.stderr[-2000:]
    two = subprocess.run([*mpiexec, "-n", "2", sys.executable, script, str(tmp_path / "two.npz")],
                         capture_output=True, text=True, timeout=300, env=_env())
    assert two.returncode == 0, two.stdout[-1000:] + two.stderr[-3000:]
    a, b = np.load(tmp_path / "one.npz"), np.load(tmp_path / "two.npz")
    info = json.loads(str(b["info"]))
    n = info["n_global"]
    assert np.array_equal(b["ids"], np.arange(n)) and np.array_equal(a["ids"], b["ids"])  # each id once
    assert sum(info["owned_end"]) == n and info["owned_inside_slab"]
    first = info["rebalances"][0]
    assert first["sort"] == 6 and first["imbalance_before"] > 1.5  # the first check (after 5 sorts)
    w0, w1 = first["weighted_after"]
    assert abs(w0 - w1) <= 0.02 * (w0 + w1) and first["imbalance_after"] < 1.05, first
    assert sum(first["counts_after"]) == n
    w0, w1 = info["weighted_end"]
    assert max(w0, w1) / (0.5 * (w0 + w1)) < 1.06, info
    assert np.allclose(info["distributed_cuts"], info["serial_cuts"], rtol=0, atol=1e-12), info
    err = float(np.abs(a["pos"] - b["pos"]).max())
    assert err <= 0.01 * 0.02, err


def _mpi_final_state(run):
    """Owned particles of the newest MPI checkpoint of `run` (every rank's file, by id), its manifest."""
    import h5py

    from shoal.parallel.checkpoint import list_manifests

    man = json.loads(list_manifests(run)[0].read_text())
    parts = []
    for f in man["files"]:
        with h5py.File(run / f, "r") as h:
            extra = [h[f"integrator/extra_{k}"][()] for k in range(len(h["integrator"]))]
            own = extra[-1] == 0  # the ghost flags are the last integrator array
            part = {k: h[f"particles/{k}"][()][own] for k in ("pos", "vel", "rho", "kind", "idp")}
            part["extra"] = [e[own] for e in extra[:-1]]
            parts.append(part)
    ids = np.concatenate([p["idp"] for p in parts])
    order = np.argsort(ids)
    out = {k: np.concatenate([p[k] for p in parts])[order] for k in ("pos", "vel", "rho", "kind", "idp")}
    out["extra"] = [np.concatenate([p["extra"][i] for p in parts])[order] for i in range(len(parts[0]["extra"]))]
    return man, out


def test_resume_on_two_ranks_is_bitwise_and_on_three_redistributed(mpiexec, tmp_path):
    """Per-rank checkpoints and --resume: a 3D dam break (9,204 particles, symplectic, float32) on 2 ranks,
    re-balanced every 5 steps whenever the ranks differ at all (threshold 1.0: the cut moves with the water
    from t = 0.095 s on), run uninterrupted to t = 0.11 s and, in a second directory, stopped at t = 0.1 s
    (its final checkpoint) then resumed with `shoal run --resume --end-time 0.11`: the final checkpoints
    hold bitwise the same owned particles (position, velocity, density, kind, id, the integrator's
    arrays) and cuts, re-cuts happened on both sides of the stop, the last snapshots are bitwise equal
    piece by piece (the same rows on the same ranks in the same order), the gauge, tracker, max-z and
    run-up CSVs and the .pvd are byte for byte equal. Bitwise because every rank restores its rows
    (ghosts included) in their order, the cuts, the halo's send lists and the load balancing's sort
    count, so each rank repeats the same operations on the same data. Only the newest 2 checkpoints are kept. A
    resume on 1 process reads the 2-rank checkpoint and finds the run complete (one line, exit 2); on 3
    ranks the particles are re-distributed
    (every rank reads both files, new cuts) and the result is within 0.01 dp of the uninterrupted run
    (round-off: measured 5e-9 m, 3e-7 dp), and so are its tracker, max-z and run-up records (the rows
    written before the stop kept, the same times, values within 1e-6 m)."""
    import shoal
    from shoal.case import Checkpointing
    from shoal.cases.dam_break import dam_break_3d
    from shoal.output import read_vtu
    from shoal.probes import WaveGauge

    def case_file(name, end):
        case = dam_break_3d(dp=0.02, end_time=end, output_interval=0.025,
                            options=shoal.SPHOptions(integrator="symplectic"))
        case = case.model_copy(update={
            "probes": [WaveGauge(name="column", x=0.07, y=0.08, z0=0.0, z1=0.35, interval=0.01),
                       *_particle_probes(0.01)],
            "checkpoint": Checkpointing(interval=0.04, wall_interval=0.0, keep=2)})
        path = tmp_path / name
        shoal.write_case(case, path)
        return path

    env = dict(_env(), SHOAL_MPI_REBALANCE_INTERVAL="5", SHOAL_MPI_REBALANCE_THRESHOLD="1.0")
    run = [sys.executable, "-m", "shoal", "run", "--no-plot", "--no-progress"]
    a, b = tmp_path / "a", tmp_path / "b"
    for toml, out in ((case_file("a.toml", 0.11), a), (case_file("b.toml", 0.1), b)):
        r = subprocess.run([*mpiexec, "-n", "2", *run, str(toml), "--out", str(out)], capture_output=True,
                           text=True, timeout=300, env=env)
        assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-2000:]
    stopped, _ = _mpi_final_state(b)
    assert stopped["ranks"] == 2 and stopped["time"] == 0.1
    # on one process without a later end time: the 2-rank checkpoint is read (its rank files verified) and
    # found complete; one line, exit 2 (test_two_rank_checkpoint_resumed_on_one_process continues one)
    r1 = subprocess.run([*run, "--resume", str(b)], capture_output=True, text=True, timeout=120, env=env)
    lines = [s for s in r1.stderr.splitlines() if s.strip()]
    assert r1.returncode == 2 and len(lines) == 1, r1.stderr
    assert f"is complete (checkpoint ckpt_{stopped['step']:06d}.mpi.json at t = 0.1 s" in lines[0], r1.stderr
    # on 3 ranks: re-distributed
    c = tmp_path / "c"
    shutil.copytree(b, c)
    r3 = subprocess.run([*mpiexec, "-n", "3", *run, "--resume", str(c), "--end-time", "0.11"],
                        capture_output=True, text=True, timeout=300, env=env)
    assert r3.returncode == 0, r3.stdout[-1000:] + r3.stderr[-2000:]
    r = subprocess.run([*mpiexec, "-n", "2", *run, "--resume", str(b), "--end-time", "0.11"], capture_output=True,
                       text=True, timeout=300, env=env)
    assert r.returncode == 0 and "resumed from ckpt_" in r.stdout, r.stdout[-1000:] + r.stderr[-2000:]
    man_a, sa = _mpi_final_state(a)
    man_b, sb = _mpi_final_state(b)
    assert man_a["step"] == man_b["step"] and man_a["time"] == man_b["time"] == 0.11
    assert man_a["cuts"] == man_b["cuts"]
    for k in ("pos", "vel", "rho", "kind", "idp"):
        assert sa[k].dtype == sb[k].dtype and np.array_equal(sa[k], sb[k]), k  # bitwise
    assert len(sa["extra"]) == 3 and all(np.array_equal(x, y) for x, y in zip(sa["extra"], sb["extra"]))
    assert np.array_equal(sa["idp"], np.arange(9204))
    log_a, log_b = (a / "run.log").read_text(), (b / "run.log").read_text()
    recuts = [float(line.split("re-balanced at t ")[1].split()[0]) for line in log_a.splitlines()
              if "re-balanced at t " in line]
    assert min(recuts) < 0.1 < max(recuts), recuts
    assert "resumed from ckpt_" in log_b and log_b.count("case dam-break-3d") == 1
    assert log_b.count("re-balanced at t ") == len(recuts)  # the same re-cuts, none twice
    last = "dam-break-3d_0005"
    for piece in range(2):
        pa, da = read_vtu(a / last / f"{last}_{piece}.vtu")
        pb, db = read_vtu(b / last / f"{last}_{piece}.vtu")
        assert np.array_equal(pa, pb) and all(np.array_equal(da[k], db[k]) for k in da)
    for name in ("gauge_column.csv", "track_t.csv", "maxz_cut.csv", "runup_r.csv", "flow_cut.csv", "force_tank.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    assert (a / "dam-break-3d.pvd").read_text() == (b / "dam-break-3d.pvd").read_text()
    assert len(list(b.glob("ckpt_*.mpi.json"))) == 2 and len(list(b.glob("ckpt_*.rank*.h5"))) == 4
    # the 3-rank continuation: every particle once, within 0.01 dp of the uninterrupted run (round-off)
    man_c, sc = _mpi_final_state(c)
    assert man_c["ranks"] == 3 and man_c["time"] == 0.11 and len(man_c["cuts"]) == 2
    assert np.array_equal(sc["idp"], np.arange(9204))
    assert np.max(np.abs(sc["pos"] - sa["pos"])) <= 0.01 * 0.02
    assert "written by 2 MPI ranks, re-distributed over 3 ranks" in (c / "run.log").read_text()
    for name in ("track_t.csv", "maxz_cut.csv", "runup_r.csv", "runup_wet.csv", "flow_cut.csv"):  # rows before the stop kept, then on
        ha, ta, va = _csv_rows(a / name)
        hc, tc, vc = _csv_rows(c / name)
        assert ha == hc and ta == tc and len(ta) == 12 and np.array_equal(np.isnan(va), np.isnan(vc)), name
        assert np.nanmax(np.abs(va - vc)) <= 1e-6, name


def _dam_break_2d_file(path, end, checkpoint, integrator="symplectic"):
    """Write the 2D dam break of the cross-process resume tests to `path`: dp = 0.01 m, a snapshot every
    0.01 s, a wave gauge, a tracker, a max-z and a run-up gauge every 0.005 s, the [checkpoint] settings
    `checkpoint`."""
    import shoal
    from shoal.probes import MaxZGauge, RunupGauge, Tracker, WaveGauge

    case = shoal.cases.dam_break_2d(dp=0.01, end_time=end, output_interval=0.01,
                                    options=shoal.SPHOptions(integrator=integrator))
    probes = [WaveGauge(name="g", x=0.07, z0=0.0, z1=0.3, interval=0.005),
              Tracker(name="t", start=[(0.1, 0.0, 0.01), (0.01, 0.0, 0.1)], interval=0.005),
              MaxZGauge(name="m", x=0.15, radius=0.02, interval=0.005),
              RunupGauge(name="r", x0=0.0, x1=0.5, interval=0.005)]
    shoal.write_case(case.model_copy(update={"probes": probes, "checkpoint": checkpoint}), path)
    return path


RUN = [sys.executable, "-m", "shoal", "run", "--no-plot", "--no-progress"]


def test_single_process_checkpoint_resumed_on_two_ranks(mpiexec, tmp_path):
    """A single-process run's checkpoint resumed under mpiexec -n 2 (the particles re-distributed over
    the ranks): a 2D dam break (dp = 0.01 m, symplectic) stopped at t = 0.05 s on one process and continued
    on 2 ranks to 0.07 s keeps every particle once and ends within 0.01 dp of the uninterrupted
    single-process run (measured 7e-9 m); the gauge's record continues with the same times and values
    within 0.01 dp (measured 1e-9 m), and so do a tracker's (the ids it chose on one process), a max-z
    and a run-up gauge's (values within 1e-6 m)."""
    from shoal.case import Checkpointing
    from shoal.output import read_vtu

    for end, out in ((0.07, "ref"), (0.05, "cut")):
        toml = _dam_break_2d_file(tmp_path / f"{out}.toml", end, Checkpointing(wall_interval=0.0))
        r = subprocess.run([*RUN, str(toml), "--out", str(tmp_path / out)], capture_output=True, text=True,
                           timeout=300, env=_env())
        assert r.returncode == 0, r.stderr[-2000:]
    r = subprocess.run([*mpiexec, "-n", "2", *RUN, "--resume", str(tmp_path / "cut"), "--end-time", "0.07"],
                       capture_output=True, text=True, timeout=300, env=_env())
    assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-2000:]
    assert "written by 1 process, re-distributed over 2 ranks" in (tmp_path / "cut" / "run.log").read_text()
    p1, d1 = read_vtu(tmp_path / "ref" / "dam-break-2d_0007.vtu")
    p2, d2 = read_vtu(tmp_path / "cut" / "dam-break-2d_0007.pvtu")
    o1, o2 = np.argsort(d1["id"]), np.argsort(d2["id"])
    assert np.array_equal(d1["id"][o1], d2["id"][o2]) and len(p2) == len(p1)
    assert np.max(np.abs(p1[o1] - p2[o2])) <= 0.01 * 0.01
    g1 = np.loadtxt(tmp_path / "ref" / "gauge_g.csv", delimiter=",", skiprows=1)
    g2 = np.loadtxt(tmp_path / "cut" / "gauge_g.csv", delimiter=",", skiprows=1)
    assert g1.shape == g2.shape and np.array_equal(g1[:, 0], g2[:, 0]) and np.all(np.isfinite(g2[:, 1]))
    assert np.max(np.abs(g1[:, 1] - g2[:, 1])) <= 0.01 * 0.01
    for name in ("track_t.csv", "maxz_m.csv", "runup_r.csv"):  # continued on 2 ranks from the checkpoint's rows
        h1, t1, v1 = _csv_rows(tmp_path / "ref" / name)
        h2, t2, v2 = _csv_rows(tmp_path / "cut" / name)
        assert h1 == h2 and t1 == t2 and len(t1) == 15 and np.array_equal(np.isnan(v1), np.isnan(v2)), name
        assert np.nanmax(np.abs(v1 - v2)) <= 1e-6, name


def _single_final_state(run):
    """Particles of the newest single-process checkpoint of `run` (the active rows), in id order."""
    import h5py

    from shoal.simulation.checkpoint import list_checkpoints

    with h5py.File(list_checkpoints(run)[0], "r") as h:
        meta = json.loads(bytes(h["meta"][()]).decode())
        n = meta["model"]["n"]
        order = np.argsort(h["particles/idp"][()][:n])
        return dict({k: h[f"particles/{k}"][()][:n][order] for k in ("pos", "vel", "rho", "kind", "idp")}, meta=meta)


def _h5(path, name):
    """Dataset `name` of the HDF5 file `path`."""
    import h5py

    with h5py.File(path, "r") as h:
        return h[name][()]


def test_two_rank_checkpoint_resumed_on_one_process(mpiexec, tmp_path):
    """A run on 2 MPI ranks continued by `shoal run --resume` on one process (no mpiexec): the 2D dam
    break of `_dam_break_2d_file` with Verlet (its previous step and Euler counter are state) on 2 ranks to
    t = 0.07 s, a checkpoint at 0.05 s; in a copy of its directory the final checkpoint is damaged (a rank
    file cut short), so the resume warns once (one line), falls back to the 0.05 s one (the newest complete
    one), reads the union of the two ranks' owned particles and continues to 0.07 s on one process (with a
    rank file of each checkpoint missing, the resume warns for each and fails with one error line, exit 2).
    Then: every particle once (ids 0..N-1, the kinds, the count of the uninterrupted runs); positions
    within 1e-6 m (1e-4 dp) of the uninterrupted single-process run and of the uninterrupted 2-rank run.
    Round-off, not bitwise (the pair sums run in another order): measured 2.0e-7 m to the single-process
    run and 7e-8 m to the 2-rank run, which differ by 1.6e-7 m from each other; the cross-rank-count
    resumes with the symplectic scheme measured 5e-9 and 7e-9 m, Verlet's leapfrog carries the round-off
    further. A fault is far larger: measured by hand, Verlet's previous step taken as the current one
    (its state lost) gives 2.4e-5 m. The Euler counter, whose loss moves the positions by less than the
    round-off here, is checked exactly: the final step count and counter equal both uninterrupted runs'.
    The gauge, tracker, max-z and run-up CSVs hold the reference's sample times (the same text: no gap,
    none twice; the rows after 0.05 s the 2-rank run wrote are cut) with values within 1e-6 m (measured
    9e-8 m); the .pvd lists each of the 8 snapshot times once, the 2-rank run's .pvtu up to the
    checkpoint, then the resumed run's .vtu, each file there, no .pvtu or piece folder of the
    abandoned part left; the last .vtu holds the final checkpoint's particles."""
    from shoal.case import Checkpointing
    from shoal.output import read_vtu
    from shoal.output.pvd import PVDWriter

    ref, two, one = tmp_path / "ref", tmp_path / "two", tmp_path / "one"
    toml = _dam_break_2d_file(tmp_path / "db.toml", 0.07, Checkpointing(interval=0.05, wall_interval=0.0),
                              integrator="verlet")
    r = subprocess.run([*RUN, str(toml), "--out", str(ref)], capture_output=True, text=True, timeout=300, env=_env())
    assert r.returncode == 0, r.stderr[-2000:]
    r = subprocess.run([*mpiexec, "-n", "2", *RUN, str(toml), "--out", str(two)], capture_output=True, text=True,
                       timeout=300, env=_env())
    assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-2000:]
    shutil.copytree(two, one)
    man = sorted(one.glob("ckpt_*.mpi.json"))
    assert len(man) == 2 and [json.loads(m.read_text())["time"] for m in man] == [0.05, 0.07], man
    # no complete checkpoint (a rank file of each missing): a warning for each, then one error line, exit 2
    none = tmp_path / "none"
    shutil.copytree(two, none)
    for m in man:
        (none / json.loads(m.read_text())["files"][0]).unlink()
    r = subprocess.run([*RUN, "--resume", str(none)], capture_output=True, text=True, timeout=300, env=_env())
    lines = [s for s in r.stderr.splitlines() if s.strip()]
    assert r.returncode == 2 and len(lines) == 3 and all(s.startswith("shoal: warning: ") for s in lines[:2]), r.stderr
    assert lines[2].startswith(f"shoal: error: none of the 2 checkpoints in {none} is readable"), r.stderr
    bad = one / json.loads(man[1].read_text())["files"][1]
    bad.write_bytes(bad.read_bytes()[: bad.stat().st_size // 2])  # the newest checkpoint: incomplete
    r = subprocess.run([*RUN, "--resume", str(one)], capture_output=True, text=True, timeout=300, env=_env())
    assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-2000:]
    lines = [s for s in r.stderr.splitlines() if s.strip()]
    assert len(lines) == 1 and f"checkpoint {man[1]} skipped" in lines[0], r.stderr
    log = (one / "run.log").read_text()
    assert f"resumed from {man[0].name} (written by 2 MPI ranks, continued on 1 process)" in log, log[-2000:]
    assert not man[1].exists() and (one / (man[1].name + ".bad")).exists() and not bad.exists()  # set aside
    (man2, s2), s1, sr = _mpi_final_state(two), _single_final_state(ref), _single_final_state(one)
    n = len(s1["idp"])
    assert np.array_equal(s1["idp"], np.arange(n)) and np.array_equal(s2["idp"], s1["idp"])
    assert np.array_equal(sr["idp"], s1["idp"]) and np.array_equal(sr["kind"], s1["kind"])
    errs = [float(np.max(np.abs(sr["pos"] - s["pos"]))) for s in (s1, s2)]
    assert max(errs) <= 1e-6, errs
    # the Verlet state: the same step count and Euler counter at the end as both uninterrupted runs
    ends = [s1["meta"], json.loads(bytes(_h5(two / man2["files"][0], "meta")).decode()), sr["meta"]]
    assert len({(m["step_count"], m["integrator"]["scalars"]["count"]) for m in ends}) == 1, ends
    for name in ("gauge_g.csv", "track_t.csv", "maxz_m.csv", "runup_r.csv"):  # the records continue
        h1, t1, v1 = _csv_rows(ref / name)
        h2, t2, v2 = _csv_rows(one / name)
        assert h1 == h2 and t1 == t2 and len(t1) == 15 and np.array_equal(np.isnan(v1), np.isnan(v2)), name
        assert np.nanmax(np.abs(v1 - v2)) <= 1e-6, (name, np.nanmax(np.abs(v1 - v2)))
    e1, e2 = PVDWriter._load(ref / "dam-break-2d.pvd"), PVDWriter._load(one / "dam-break-2d.pvd")
    assert [t for t, _ in e2] == [t for t, _ in e1] and len(e2) == 8, e2
    assert [f for _, f in e2] == [f"dam-break-2d_{k:04d}.{'pvtu' if k < 6 else 'vtu'}" for k in range(8)], e2
    assert all((one / f).is_file() for _, f in e2)
    assert sorted(p.name for p in one.glob("dam-break-2d_000[67]*")) == ["dam-break-2d_0006.vtu",
                                                                       "dam-break-2d_0007.vtu"]
    p, d = read_vtu(one / "dam-break-2d_0007.vtu")
    o = np.argsort(d["id"])
    assert np.array_equal(d["id"][o], sr["idp"]) and np.array_equal(p[o][:, [0, 2]], sr["pos"])


def test_moving_wall_two_ranks_matches_one(mpiexec, tmp_path):
    """A moving boundary under MPI: the 2D tidal-bore flume (1 m long, dp = 0.02 m, 566 particles, the
    paper's scheme with SPS: a halo of 4h) pushed by its inflow wall at U = 0.7 m/s to t = 0.1 s, on
    2 ranks against 1. Each rank builds only its slab, so the wall (at x = 1 m) is on rank 1 alone
    and rank 1's rows are not the case's ids: the wall must still follow its motion from its initial
    position looked up by the global id (``pos_init`` / ``motion_of`` kept for the whole case, and
    set up on rank 0 too, which has no moving particle at the start). Checked: every id once, the
    moving particles where the motion puts them (x0 - U t, to 1e-9 m: the motion is exact) in both
    runs, the fluid within 0.01 dp of the single-process run (round-off of the pair-sum order; a
    wall in the wrong place moves the water by the order of dp), the gauge the same within 0.01 dp."""
    from shoal.cases import tidal_bore
    from shoal.output.vtu import read_vtu

    U, t_end, dp = 0.7, 0.1, 0.02
    case = tidal_bore(dp=dp, inflow_speed=U, dim=2, length=1.0, gauges_x=[0.3], end_time=t_end,
                      output_interval=t_end)
    _run_one_and_two(mpiexec, case, tmp_path)
    p0, d0 = read_vtu(tmp_path / "one" / "tidal-bore_0000.vtu")[:2]
    p1, d1 = read_vtu(tmp_path / "one" / "tidal-bore_0001.vtu")[:2]
    p2, d2 = read_vtu(tmp_path / "two" / "tidal-bore_0001.pvtu")[:2]
    n = case.n_particles
    by_id = []
    for pts, data in ((p0, d0), (p1, d1), (p2, d2)):
        ids = np.asarray(data["id"])
        assert np.array_equal(np.sort(ids), np.arange(n))
        out = np.empty_like(pts)
        out[ids] = pts
        kinds = np.empty(n, int)
        kinds[ids] = data["kind"]
        by_id.append((out, kinds))
    (x0, k0), (x1, _), (x2, _) = by_id
    moving = k0 == 2
    assert moving.sum() > 10 and x0[moving, 0].min() >= 1.0 - 1e-9  # the inflow wall, at x >= 1 m
    for x in (x1, x2):
        assert np.max(np.abs(x[moving, 0] - (x0[moving, 0] - U * t_end))) <= 1e-9
        assert np.max(np.abs(x[moving, 2] - x0[moving, 2])) <= 1e-9
    fluid = k0 == 0
    assert np.max(np.abs(x1[fluid] - x0[fluid])) > 0.5 * U * t_end  # the water moved
    assert np.max(np.abs(x2[fluid] - x1[fluid])) <= 0.01 * dp
    g1 = np.loadtxt(tmp_path / "one" / "gauge_x0.3.csv", delimiter=",", skiprows=1)
    g2 = np.loadtxt(tmp_path / "two" / "gauge_x0.3.csv", delimiter=",", skiprows=1)
    assert g1.shape == g2.shape and np.max(np.abs(g1[:, 1] - g2[:, 1])) <= 0.01 * dp


def _by_id_one_and_two(tmp_path, name, n):
    """(start positions, [final positions of the 1-process run, of the 2-rank run]), each (n, 3) by particle id,
    from the first and second snapshots of `_run_one_and_two`'s runs; every id is checked to appear once."""
    from shoal.output.vtu import read_vtu

    p0, d0 = read_vtu(tmp_path / "one" / f"{name}_0000.vtu")[:2]
    by_id = []
    for path in (tmp_path / "one" / f"{name}_0001.vtu", tmp_path / "two" / f"{name}_0001.pvtu"):
        pts, data = read_vtu(path)[:2]
        ids = np.asarray(data["id"])
        assert np.array_equal(np.sort(ids), np.arange(n))
        out = np.empty_like(pts)
        out[ids] = pts
        by_id.append(out)
    x0 = np.empty_like(p0)
    x0[np.asarray(d0["id"])] = p0
    return x0, by_id


def test_rotating_flap_two_ranks_matches_one(mpiexec, tmp_path):
    """A rotating wall under MPI: a 2D flume (1 m, dp = 0.02 m) whose left wall is a flap hinged at the bed
    (`FlapWavemaker`, no ramp), to t = 0.1 s on 2 ranks against 1. The flap is on rank 0 alone; rank 1 sets
    up the motion table too. Checked: every id once, the flap's particles where the rotation puts them from
    their start positions (`RigidKinematics.points`, 1e-9 m) in both runs, and the fluid within 0.01 dp of
    the single-process run (round-off of the pair-sum order; a wall in the wrong place moves the water by
    the order of dp)."""
    from shoal.case import Case, Fluid, FluidRegion, Output, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import FlapWavemaker

    t_end, dp = 0.1, 0.02
    flap = FlapWavemaker(name="flap", height=0.04, period=0.8, depth=0.2, ramp_periods=0.0)
    case = Case(name="flap", dim=2, dp=dp, end_time=t_end, fluid=Fluid(depth=0.2, surface_level=0.2),
                options=dict(viscosity="laminar", nu=1e-6, visco_bound_factor=0.0, coef_h=1.5),
                motions=[flap], output=Output(interval=t_end),
                solids=[Solid(name="flap", shape=Box(lo=(-0.06, 0, 0), hi=(0, 0, 0.3)), motion="flap"),
                        Solid(name="flume", shape=Tank(lo=(-0.16, 0, 0), hi=(1.0, 0, 0.3)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0, 0.2)))])
    _run_one_and_two(mpiexec, case, tmp_path)
    x0, by_id = _by_id_one_and_two(tmp_path, "flap", case.n_particles)
    kinds = case.particles().kinds
    moving = kinds == 2
    want = flap.point_kinematics(x0[moving], t_end)[0]
    assert np.abs(want - x0[moving]).max() > 0.1 * dp  # the flap turned
    for x in by_id:
        assert np.max(np.abs(x[moving] - want)) <= 1e-9
    fluid = kinds == 0
    assert np.max(np.abs(by_id[1][fluid] - by_id[0][fluid])) <= 0.01 * dp


def test_active_absorption_two_ranks_matches_one(mpiexec, tmp_path):
    """Active absorption under MPI: a 2D flume (1.2 m, dp = 0.025 m) whose piston corrects its motion from the
    elevation it measures 2h in front of it from the start (`shoal.active_absorption`), to t = 0.3 s on 2 ranks
    against 1. The gauge's kernel sums are reduced over the ranks, so both ranks keep the controller of the
    single process: the paddle's particles, which the controller has moved off the target motion, within a
    thousandth of that correction of the single-process run's (the measured elevation differs by the fluid's
    round-off only), and the fluid within 0.01 dp (round-off of the pair sums' order)."""
    from shoal.active_absorption import ActiveAbsorption
    from shoal.case import Case, Fluid, FluidRegion, Output, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import PistonWavemaker

    t_end, dp, d = 0.3, 0.025, 0.25
    piston = PistonWavemaker(name="piston", height=0.03, period=0.8, depth=d, ramp_periods=0.5,
                             absorption=ActiveAbsorption(start=0.0))
    case = Case(name="awas", dim=2, dp=dp, end_time=t_end, fluid=Fluid(depth=d, surface_level=d),
                options=dict(viscosity="laminar", nu=1e-6, visco_bound_factor=0.0, coef_h=1.5),
                motions=[piston], output=Output(interval=t_end),
                solids=[Solid(name="paddle", shape=Box(lo=(-0.1, 0, 0), hi=(0, 0, 0.4)), motion="piston"),
                        Solid(name="flume", shape=Tank(lo=(-0.2, 0, 0), hi=(1.2, 0, 0.4)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.2, 0, d)))])
    _run_one_and_two(mpiexec, case, tmp_path)
    x0, by_id = _by_id_one_and_two(tmp_path, "awas", case.n_particles)
    kinds = case.particles().kinds
    moving = kinds == 2
    target = piston.point_kinematics(x0[moving], t_end)[0]
    correction = np.max(np.abs(by_id[0][moving] - target))
    assert correction > 1e-5  # the controller moved the paddle off its target
    # the same controller on both ranks: the paddles differ only by what the fluid's round-off does to the
    # measured elevation, a thousandth of the correction
    assert np.max(np.abs(by_id[1][moving] - by_id[0][moving])) <= 1e-3 * correction
    fluid = kinds == 0
    assert np.max(np.abs(by_id[1][fluid] - by_id[0][fluid])) <= 0.01 * dp


def test_relaxation_zones_two_ranks_match_one(mpiexec, tmp_path):
    """Relaxation zones under MPI: a 2D tank 2 m long (dp = 0.05 m) with a linear-wave zone at its left end
    and a still-water zone at its right, each on one rank's slab, to t = 0.2 s on 2 ranks against 1. The
    relaxation is elementwise (each rank relaxes the particles it owns), so the fluid stays within 0.01 dp
    of the single-process run (round-off of the pair sums' order)."""
    import shoal
    from shoal.geometry import Box, Tank
    from shoal.output.vtu import read_vtu
    from shoal.relaxation import LinearTarget, RelaxationZone

    d = 0.4
    case = shoal.Case(name="rz", dim=2, dp=0.05, end_time=0.2, fluid=shoal.Fluid(depth=d, surface_level=d),
                      solids=[shoal.Solid(shape=Tank(lo=(0, 0, 0), hi=(2.0, 0, 0.6)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, d)))],
                      output=shoal.Output(interval=0.2),
                      relaxation=[RelaxationZone(start=0.6, end=0.0, ramp_time=0.05,
                                                 target=LinearTarget(height=0.05, period=1.0, depth=d)),
                                  RelaxationZone(start=1.4, end=2.0)])
    _run_one_and_two(mpiexec, case, tmp_path)
    p1, d1 = read_vtu(tmp_path / "one" / "rz_0001.vtu")[:2]
    p2, d2 = read_vtu(tmp_path / "two" / "rz_0001.pvtu")[:2]
    x1, x2 = np.empty_like(p1), np.empty_like(p2)
    x1[np.asarray(d1["id"])] = p1
    x2[np.asarray(d2["id"])] = p2
    kinds = np.empty(len(p1), int)
    kinds[np.asarray(d1["id"])] = d1["kind"]
    p0 = read_vtu(tmp_path / "one" / "rz_0000.vtu")[0]
    x0 = np.empty_like(p0)
    x0[np.asarray(read_vtu(tmp_path / "one" / "rz_0000.vtu")[1]["id"])] = p0
    fluid = kinds == 0
    assert np.max(np.abs(x1[fluid] - x0[fluid])) > 0.002  # the zone moved the water
    assert np.max(np.abs(x2[fluid] - x1[fluid])) <= 0.01 * case.dp


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_stop_signal_on_two_ranks_checkpoints_and_resumes(mpiexec, tmp_path, sig):
    """A stop signal to ``mpiexec -n 2 shoal run`` (which forwards it to every rank; a batch system
    signals every task itself) ends the run after the same step on both ranks (they agree after each
    step) with a final checkpoint on 2 ranks and exit status 128 + the signal (130, 143), as on one
    process; ``--resume`` then continues it on 2 ranks to the end."""
    import signal
    import time

    import shoal
    from shoal.cases import dam_break_2d

    case = dam_break_2d(dp=0.02, end_time=60.0, output_interval=10.0)  # far longer than the test waits
    toml = tmp_path / "case.toml"
    shoal.write_case(case, toml)
    out = tmp_path / "run"
    run = [sys.executable, "-m", "shoal", "run", "--no-plot", "--no-progress"]
    proc = subprocess.Popen([*mpiexec, "-n", "2", *run, str(toml), "--out", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=_env())
    log = out / "run.log"
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:  # stepping (the handlers are installed)
        if log.exists() and " INFO step " in log.read_text():
            break
        time.sleep(0.5)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(getattr(signal, sig))
    stdout, stderr = proc.communicate(timeout=120)
    status = 128 + getattr(signal, sig)
    assert proc.returncode == status, (proc.returncode, stdout[-1000:], stderr[-2000:])
    assert f"stopped by {sig} at step" in stderr and "--resume" in stderr, stderr
    (man,) = sorted(out.glob("ckpt_*.mpi.json"))
    meta = json.loads(man.read_text())
    step = int(man.name.split("_")[1].split(".")[0])
    assert len(list(out.glob(f"ckpt_{step:06d}.rank*.h5"))) == 2, meta
    assert f"WARNING stopped by {sig} at step {step}," in log.read_text()
    t_stop = float(stderr.split(f"at step {step}, t = ")[1].split(" s")[0])
    r = subprocess.run([*mpiexec, "-n", "2", *run, "--resume", str(out), "--end-time", f"{t_stop + 0.02:.6g}"],
                       capture_output=True, text=True, timeout=300, env=_env())
    assert r.returncode == 0 and f"resumed from {man.name}" in r.stdout, r.stdout[-1000:] + r.stderr[-2000:]


def test_one_rank_on_the_mpi_path_writes_what_one_process_writes(mpiexec, tmp_path):
    """One run path (issue 29): ``SHOAL_MPI=1 mpiexec -n 1 shoal run`` goes through the MPI side of the
    run (a `DistributedModel` over `shoal.parallel.run.Ranks`, snapshots gathered) and writes the
    single-process run's probe and escaped-particle files byte for byte, and snapshots holding the same
    particles bitwise (in id order, where one process writes them in cell order)."""
    import shoal
    from shoal.cases import dam_break_2d
    from shoal.output import read_vtu
    from shoal.probes import WaveGauge

    case = dam_break_2d(dp=0.02, end_time=0.1, output_interval=0.05)
    case = case.model_copy(update={"probes": [WaveGauge(name="g", x=0.3, z0=0.0, z1=0.5, interval=0.01)]})
    toml = tmp_path / "case.toml"
    shoal.write_case(case, toml)
    run = [sys.executable, "-m", "shoal", "run", str(toml), "--no-plot", "--no-progress", "--out"]
    one = subprocess.run([*run, str(tmp_path / "one")], capture_output=True, text=True, timeout=300, env=_env())
    assert one.returncode == 0, one.stderr[-2000:]
    env = dict(_env(), SHOAL_MPI="1", SHOAL_MPI_SNAPSHOTS="gather")
    ranks = subprocess.run([*mpiexec, "-n", "1", *run, str(tmp_path / "ranks")], capture_output=True, text=True,
                           timeout=300, env=env)
    assert ranks.returncode == 0, ranks.stderr[-2000:]
    a, b = tmp_path / "one", tmp_path / "ranks"
    assert "1 MPI ranks" in (b / "run.log").read_text() and "MPI" not in (a / "run.log").read_text()
    assert list(b.glob("ckpt_*.mpi.json")) and not [p for p in b.glob("ckpt_*.h5") if ".rank" not in p.name]
    for name in ("gauge_g.csv", "escaped.csv", "case.toml"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    snaps = sorted(p.name for p in a.glob("dam-break-2d_*.vtu"))
    assert len(snaps) == 3 and snaps == sorted(p.name for p in b.glob("dam-break-2d_*.vtu"))
    for name in snaps:
        pa, da = read_vtu(a / name)
        pb, db = read_vtu(b / name)
        ia, ib = np.argsort(da["id"]), np.argsort(db["id"])
        assert sorted(da) == sorted(db) and np.array_equal(pa[ia], pb[ib]), name
        for field in da:
            assert np.array_equal(da[field][ia], db[field][ib]), (name, field)


def _periodic_channel(dp=0.01, length=0.8, end_time=0.1):
    """A 2D channel periodic in x (0.1 m between plates of 3 layers of particles, `length` long),
    water started at 0.5 m/s along x and driven by a body force of 2 m/s^2, float64: it moves 5 dp in
    0.1 s, across the slab cuts and round the period (the wall friction shears it)."""
    import shoal
    from shoal.case import Domain
    from shoal.geometry import Box

    D, layers = 0.1, 3
    return shoal.Case(
        name="channel", dim=2, dp=dp, end_time=end_time, description="periodic channel",
        fluid=shoal.Fluid(u_max=1.0, gravity=(2.0, 0, 0)),
        options={"precision": "float64", "integrator": "symplectic"},
        solids=[shoal.Solid(name="bottom", shape=Box(lo=(0, 0, -layers * dp), hi=(length, 0, 0)), layers=layers),
                shoal.Solid(name="top", shape=Box(lo=(0, 0, D), hi=(length, 0, D + layers * dp)), layers=layers)],
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, D)), velocity=(0.5, 0, 0))],
        output=shoal.Output(interval=end_time),
        domain=Domain(lo=(0, 0, -layers * dp), hi=(length, 0, D + layers * dp), periodic=["x"]))


def test_periodic_x_on_two_and_three_ranks_matches_one(mpiexec, tmp_path):
    """A periodic x axis under MPI (the slabs close into a ring): the periodic channel of
    `_periodic_channel` (1,280 particles) to t = 0.1 s on 1, 2 and 3 ranks. The water moves 5 dp
    along x, so particles cross the cuts and leave the domain's end to re-enter at the other (sent
    from the last rank to rank 0 round the ring), and every rank's halo spans the period's ends.
    Checked: every id once on each run; the fluid positions (the difference taken round the period)
    and velocities within 1e-6 dp and 1e-6 m/s of the single-process run (float64: round-off of the
    pair-sum order, measured 4.7e-16 m and 2.4e-14 m/s; with rank 0 not sending its halo round the
    ring to the last rank, the 2-rank run differs by 0.0145 m = 1.5 dp and 0.24 m/s); more than five
    particles wrapped."""
    from shoal.output.vtu import read_vtu

    case = _periodic_channel()
    _run_one_and_two(mpiexec, case, tmp_path)
    three = subprocess.run([*mpiexec, "-n", "3", sys.executable, "-m", "shoal", "run", str(tmp_path / "case.toml"),
                            "--no-plot", "--no-progress", "--out", str(tmp_path / "three")], capture_output=True,
                           text=True, timeout=300, env=_env())
    assert three.returncode == 0, three.stdout[-1000:] + three.stderr[-2000:]
    n, L, dp = case.n_particles, 0.8, case.dp
    runs = {}
    for name, f in (("start", "one/channel_0000.vtu"), ("one", "one/channel_0001.vtu"),
                    ("two", "two/channel_0001.pvtu"), ("three", "three/channel_0001.pvtu")):
        pts, data = read_vtu(tmp_path / f)[:2]
        ids = np.asarray(data["id"])
        assert np.array_equal(np.sort(ids), np.arange(n)), name
        pos, vel, kind = np.empty((n, 3)), np.empty((n, 3)), np.empty(n, int)
        pos[ids], vel[ids], kind[ids] = pts, data["velocity"], data["kind"]
        runs[name] = (pos, vel, kind)
    fluid = runs["start"][2] == 0
    x0, x1 = runs["start"][0][fluid, 0], runs["one"][0][fluid, 0]
    assert np.count_nonzero(x1 < x0 - L / 2) > 5  # particles went round the period
    for name in ("two", "three"):
        dx = runs[name][0][fluid] - runs["one"][0][fluid]
        dx[:, 0] = (dx[:, 0] + L / 2) % L - L / 2
        dv = runs[name][1][fluid] - runs["one"][1][fluid]
        print(f"{name} ranks: max |dx| {np.abs(dx).max():.3g} m, max |dv| {np.abs(dv).max():.3g} m/s")
        assert np.abs(dx).max() <= 1e-6 * dp and np.abs(dv).max() <= 1e-6, name
    log = (tmp_path / "three" / "run.log").read_text()
    assert "3 MPI ranks" in log


def test_the_distributed_model_overrides_no_physics_method():
    """Issue 29: `DistributedModel` takes part in the physics through the Model's hooks (ghost refresh,
    reductions, raising together), not by overriding the physics methods."""
    from shoal.model import Model
    from shoal.parallel.model import DistributedModel

    physics = ("compute_rates", "time_step_limit", "apply_filter", "check", "free_surface", "body_force",
               "apply_damping", "apply_relaxation", "move_bodies", "wall_forces")
    assert all(hasattr(Model, m) for m in physics)
    assert not [m for m in physics if m in vars(DistributedModel)]
    hooks = ("refresh_ghosts", "ghosts_spent", "clear_ghost_rates", "reduce", "raise_together", "reduce_array",
             "gather", "answers", "owned_rows")
    assert all(h in vars(Model) and h in vars(DistributedModel) for h in hooks)
    # the probe and output queries are the Model's, written once over the hooks; what else the distributed
    # model overrides is its storage: the sort (migration, halo, load balancing), the arrays it keeps
    # mirrored, the fluid it owns, its ghost rows and the per-rank checkpoint
    queries = ("sample", "sensor_moments", "world_positions", "world_velocities", "pressure", "fields",
               "owned_particles", "particle_positions", "nearest_fluid", "flow_sample", "shoreline", "highest_fluid")
    assert all(q in vars(Model) for q in queries)
    storage = ("__init__", "sort", "new_array", "n_fluid", "checkpoint_arrays", "require_fluid", "ghost_flags")
    overrides = {k for k in vars(DistributedModel) if k in vars(Model) and k not in ("__module__", "__doc__")}
    assert overrides == set(hooks) | set(storage), sorted(overrides)


def test_floating_body_two_ranks_matches_one(mpiexec, tmp_path):
    """A floating box across the slab cut (`shoal.body_coupling`): a 2D tank 1 m long, the box (0.2 m, density
    500) in its middle released 1 dp above its draft, to t = 0.3 s on 2 ranks against 1. Each rank sums the
    fluid's force on the body particles it owns and the sums are added over the ranks, so both ranks move the
    body as the single process does: its centre within 1e-4 dp at every row of body_box.csv (the loads differ
    by the round-off of the pair sums' order), and the fluid within 0.01 dp."""
    from shoal.case import Case, Fluid, FluidRegion, Output, Solid
    from shoal.floating import FloatingBody
    from shoal.geometry.shapes import Box, Tank

    t_end, dp, d = 0.3, 0.02, 0.4
    case = Case(name="float", dim=2, dp=dp, end_time=t_end, fluid=Fluid(depth=d, surface_level=d),
                output=Output(interval=t_end),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.0, 0, 0.8))),
                        Solid(name="box", shape=Box(lo=(0.4, 0, 0.32), hi=(0.6, 0, 0.52)),
                              floating=FloatingBody(density=500.0, interval=0.01))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0, d)))])
    _run_one_and_two(mpiexec, case, tmp_path)
    one, two = (np.loadtxt(tmp_path / r / "body_box.csv", delimiter=",", skiprows=1) for r in ("one", "two"))
    assert one.shape == two.shape and len(one) == 31
    assert np.ptp(one[:, 3]) > 0.1 * dp  # the body moved
    assert np.max(np.abs(one[:, 1:4] - two[:, 1:4])) <= 1e-4 * dp
    x0, by_id = _by_id_one_and_two(tmp_path, "float", case.n_particles)
    fluid = case.particles().kinds == 0
    assert np.max(np.abs(by_id[1][fluid] - by_id[0][fluid])) <= 0.01 * dp


def test_moored_body_two_ranks_matches_one(mpiexec, tmp_path):
    """A moored floating box under MPI: the 2D box on two taut cords (MoorDyn, tests/test_floating.py's
    `_moored_case`) released 2 dp off its equilibrium, to t = 0.1 s on 2 ranks against 1. Every rank steps its
    own copy of MoorDyn from the same body states, so the cords' tensions and the box's path are the single
    process's: the centre within 1e-4 dp and the tensions within 1e-4 relative at every row."""
    from tests.test_floating import _moored_case

    case = _moored_case(0.1, interval=0.01)
    _run_one_and_two(mpiexec, case, tmp_path)
    for name in ("body_box.csv", "mooring_line1.csv", "mooring_line2.csv"):
        one, two = (np.loadtxt(tmp_path / r / name, delimiter=",", skiprows=1) for r in ("one", "two"))
        assert one.shape == two.shape and len(one) == 11, name
        if name == "body_box.csv":
            assert np.ptp(one[:, 1]) > 0.1 * case.dp  # the cords pull it back
            assert np.max(np.abs(one[:, 1:4] - two[:, 1:4])) <= 1e-4 * case.dp
        else:
            np.testing.assert_allclose(two[:, 1:], one[:, 1:], rtol=1e-4)


@pytest.mark.parametrize("inlet", ["velocity", "rising-level"])
def test_open_boundaries_two_ranks_match_one(mpiexec, tmp_path, inlet):
    """Open boundaries on 2 ranks against 1 (`shoal.particle_buffers`): a channel 0.3-0.4 m long (dp = 0.02 m),
    the water let in at x = 0 and out at its end, to t = 0.2 s. Each rank
    converts, creates and removes its own particles, numbers its new ones after the lower ranks' and combines
    the inlet's band sums over the ranks: the same particles (ids) at the end, as many created and removed,
    the water within 0.01 dp of the single-process run, the same volume through a flow gauge. With an inlet of imposed velocity and an outlet that
    takes twice as much (the fluid drains: max_escaped_fraction = 0.005 must not count what the outlet removed as
    escaped); and with an inlet holding a level that rises 0.05 m (rows lifted into its buffer) against an
    outlet that takes 0.2 m/s with its level following the water (``level_mode = "water"``), the slab cut
    inside both boundaries' bands (their depths and the inlet's speed summed over both ranks). Stopped halfway and resumed on 2 ranks, that run ends bitwise as the run in one go; the first one's
    checkpoint resumed in one process is refused in one line (the union of the ranks' particles is not put
    back yet with open boundaries)."""
    import re

    import shoal
    from shoal.case import Case, Fluid, FluidRegion, Output, Solid
    from shoal.geometry.shapes import Box
    from shoal.open_boundary import OpenBoundary
    from shoal.output.vtu import read_vtu
    from shoal.probes import FlowGauge
    from shoal.time_series import TimeSeries

    dp, d, t_end = 0.02, 0.2, 0.2
    length = 0.4 if inlet == "velocity" else 0.3  # the cut inside the inlet's band (0.17 m wide)
    if inlet == "velocity":
        ins, outs = dict(velocity=0.2, level=d), dict(level=d, velocity=-0.4)  # draining: more out than in
    else:
        ins = dict(velocity_mode="riemann", relaxation_time=0.02,
                   level=TimeSeries(t=[0.0, t_end], value=[d, d + 0.05]))
        outs = dict(level=d, velocity=-0.2, level_mode="water")
    case = Case(name="channel", dim=2, dp=dp, end_time=t_end, fluid=Fluid(depth=d, surface_level=d),
                max_escaped_fraction=0.005,  # what an outlet removes has not escaped
                options={"wall_pressure": "adami", "visco_bound_factor": 0.0}, output=Output(interval=t_end),
                solids=[Solid(name="bed", shape=Box(lo=(-0.2, 0, -4 * dp), hi=(length + 0.2, 0, 0)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, d)), velocity=(0.2, 0, 0))],
                probes=[FlowGauge(name="q", at=0.05, interval=0.01)],
                open_boundaries=[
                    OpenBoundary(name="in", point=(0, 0, 0), normal=(1, 0, 0), lo=(0, 0, 0), hi=(0, 0, 2 * d), **ins),
                    OpenBoundary(name="out", point=(length, 0, 0), normal=(-1, 0, 0), lo=(length, 0, 0),
                                 hi=(length, 0, 2 * d), **outs)])
    _run_one_and_two(mpiexec, case, tmp_path)
    counts = []
    for run in ("one", "two"):
        last = [ln for ln in (tmp_path / run / "run.log").read_text().splitlines() if " created " in ln][-1]
        counts.append(tuple(int(v) for v in re.search(r"created (\d+) removed (\d+)", last).groups()))
    assert counts[0] == counts[1] and min(counts[0]) >= 20, counts  # two rows of the section or more each way
    cut = json.loads((tmp_path / "two" / "resolved.json").read_text())["mpi"]
    print(counts, cut)
    if inlet != "velocity":
        assert cut["slab_cuts_x"][0] < 6 * case.smoothing_length  # the band: 3 kernel supports
    snaps = []
    for path in (tmp_path / "one" / "channel_0001.vtu", tmp_path / "two" / "channel_0001.pvtu"):
        pts, data = read_vtu(path)[:2]
        ids = np.asarray(data["id"])
        order = np.argsort(ids)
        snaps.append((ids[order], pts[order]))
    (i1, p1), (i2, p2) = snaps
    assert np.array_equal(i1, i2) and len(np.unique(i1)) == len(i1)
    assert i1.max() >= case.n_particles  # particles made during the run are among them
    assert np.max(np.abs(p1 - p2)) <= 0.01 * dp
    # a flow gauge counts the particles the inlet made as they pass (ids beyond the case's, on either rank)
    q1, q2 = (np.loadtxt(tmp_path / r / "flow_q.csv", delimiter=",", skiprows=1) for r in ("one", "two"))
    assert q1.shape == q2.shape and q1[-1, 1] > 10 * dp ** 2 and np.array_equal(q1[:, 1], q2[:, 1])
    run = [sys.executable, "-m", "shoal", "run", "--no-plot", "--no-progress"]
    if inlet == "velocity":  # the 2 ranks' checkpoint in one process: not put back yet, one line, exit 2
        r = subprocess.run([*run, "--resume", str(tmp_path / "two"), "--end-time", str(2 * t_end)],
                           capture_output=True, text=True, timeout=120, env=_env())
        lines = [s for s in r.stderr.splitlines() if s.strip()]
        assert r.returncode == 2 and len(lines) == 1 and "resumes on the number of MPI ranks" in lines[0], r.stderr
    else:  # stopped at t_end / 2 and resumed on 2 ranks: bitwise the run in one go
        half = tmp_path / "half.toml"
        shoal.write_case(case.model_copy(update={"end_time": 0.5 * t_end}), half)
        for extra in ([str(half), "--out", str(tmp_path / "half")], ["--resume", str(tmp_path / "half"),
                                                                       "--end-time", str(t_end)]):
            r = subprocess.run([*mpiexec, "-n", "2", *run, *extra], capture_output=True, text=True, timeout=120,
                               env=_env())
            assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-2000:]
        (man_a, sa), (man_b, sb) = _mpi_final_state(tmp_path / "two"), _mpi_final_state(tmp_path / "half")
        assert man_a["step"] == man_b["step"] and man_a["time"] == man_b["time"]
        for k in ("pos", "vel", "rho", "kind", "idp"):
            assert np.array_equal(sa[k], sb[k]), k
        assert all(np.array_equal(x, y) for x, y in zip(sa["extra"], sb["extra"]))
