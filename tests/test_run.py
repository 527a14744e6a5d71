"""End-to-end runs: files written, instability handling, escaped particles."""

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from shoal import InstabilityError, SPHOptions, run_case
from shoal.cases import still_water_2d
from shoal.cli import main
from shoal.model import Model
from shoal.output import read_vtu
from shoal.simulation import Simulation


def test_cli_run_writes_snapshots_log_png_and_resolved(tmp_path, capsys):
    out = tmp_path / "sw"
    rc = main(["run", "still-water-2d", "--dp", "0.05", "--end-time", "0.1", "--output-interval", "0.05",
               "--out", str(out), "--no-progress"])
    assert rc == 0
    printed = capsys.readouterr().out
    assert "particle-steps/s" in printed
    pvd = ET.parse(out / "still-water-2d.pvd").getroot()
    entries = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    # outputs land exactly on the requested times
    assert [t for t, _ in entries] == pytest.approx([0.0, 0.05, 0.1], abs=1e-12)
    pts, data = read_vtu(out / entries[-1][1])
    assert set(data) >= {"velocity", "density", "pressure", "id", "kind"}
    assert pts.shape[1] == 3 and np.all(pts[:, 1] == 0.0)  # 2D runs in the x-z plane
    assert data["velocity"].shape == (len(pts), 3)
    assert set(np.unique(data["kind"])) == {0, 1}
    assert sorted(data["id"].tolist()) == list(range(len(pts)))
    res = json.loads((out / "resolved.json").read_text())
    assert res["dp"] == 0.05 and res["options"]["kernel"] == "wendland"
    assert res["bytes_per_particle"] > 0 and res["speed_of_sound"] > 10 * (9.81 * 0.5) ** 0.5
    assert "done:" in (out / "run.log").read_text()
    assert (out / "still-water-2d_final.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # running again into the same directory must not overwrite it silently
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    rc = main(["run", "still-water-2d", "--dp", "0.05", "--end-time", "0.1", "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "--overwrite" in err
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before
    assert main(["run", "still-water-2d", "--dp", "0.05", "--end-time", "0.05", "--out", str(out),
                 "--no-progress", "--overwrite", "--no-plot"]) == 0


def test_unstable_run_stops_with_location_and_keeps_output(tmp_path):
    # a fixed time step ~30x the stable one: the run must blow up, and say where
    case = still_water_2d(dp=0.05, end_time=1.0, output_interval=0.01,
                          options=SPHOptions(fixed_dt=0.01))
    with pytest.raises(InstabilityError) as err:
        run_case(case, tmp_path, plot=False)
    msg = str(err.value)
    assert "unstable at step" in msg or "dt fell" in msg or "not a positive" in msg
    assert "particle id" in msg and "(x, y, z)" in msg
    assert (tmp_path / "still-water-2d_0000.vtu").exists()
    assert (tmp_path / "still-water-2d_unstable.vtu").exists()
    assert "ERROR" in (tmp_path / "run.log").read_text()


def test_particles_leaving_the_domain_are_removed_and_counted():
    # a free block of fluid moving at 1 m/s in +x, without gravity, towards the domain's end
    dp = 0.02
    g = np.arange(10) * dp + dp / 2
    X, Z = np.meshgrid(g, g, indexing="ij")
    pos = np.column_stack([X.ravel(), np.zeros(X.size), Z.ravel()])
    vel = np.zeros_like(pos)
    vel[:, 0] = 1.0
    m = Model(pos, np.zeros(len(pos), np.int8), dp=dp, dim=2, domain=((0, 0, 0), (0.3, 0, 0.2)),
              gravity=(0, 0, 0), u_max=1.0, velocities=vel)
    sim = Simulation(m, end_time=0.2)
    sim.run()
    # the block front started at x = 0.2 and the domain ends at 0.3: after 0.2 s at ~1 m/s,
    # the particles initially beyond x = 0.1 (about half) have left
    assert 0.3 * len(pos) < m.n_escaped < 0.8 * len(pos)
    assert m.n == len(pos) - m.n_escaped
    assert np.all(m.pos[: m.n, 0] < 0.3)
    assert np.all(np.isfinite(m.pos[: m.n]))


def test_particle_steps_per_second_counts_only_the_run_less_its_own_compiling(tmp_path):
    """The throughput is particles x steps over the run's wall time less the compiling done inside the
    run. Kernels first called while the model is built are compiled outside the run's wall time; with
    that time subtracted too, a short run reported nan (`shoal run tidal-bore --dp 0.02 --end-time 0.02`:
    0.2 s run, 0.3 s compiling) or a throughput too high."""
    case = still_water_2d(dp=0.05, end_time=0.02)
    res = run_case(case, tmp_path / "a", plot=False)
    sim = res.simulation
    assert 0.0 <= sim.compile_seconds <= res.compile_seconds
    assert res.particle_steps_per_second == pytest.approx(
        res.particles * res.steps / (sim.wall_seconds - sim.compile_seconds))
    assert np.isfinite(res.particle_steps_per_second) and res.particle_steps_per_second > 0
