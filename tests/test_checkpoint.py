"""Checkpoints and exact restart, stop signals, blow-ups and escaped particles (issue 7).

A 2D dam break at dp = 0.01 m (about 1,500 particles, ~2,400 steps to 0.2 s)
with a wave gauge and a test-point grid runs once uninterrupted (in this
process) and once in a subprocess that is killed (SIGKILL / stopped with
SIGTERM) after its first checkpoint and then resumed with ``--resume``: the
final particle states (from the final checkpoints, by particle id) must be
bitwise equal, and the gauge CSVs must hold the same times, none twice.
"""

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

import shoal
from shoal import SPHOptions, load_case, run_case, write_case
from shoal.case import Checkpointing
from shoal.cli import main
from shoal.output import read_vtu
from shoal.probes import FlowGauge, ForceGauge, TestPoints, WaveGauge
from shoal.simulation.checkpoint import list_checkpoints, read_checkpoint
from shoal.simulation.resume import latest_checkpoint

SRC = Path(shoal.__file__).resolve().parents[1]
END = 0.2


def _case_file(tmp_path):
    case = shoal.cases.dam_break_2d(dp=0.01, end_time=END, output_interval=0.05)
    case = case.model_copy(update={
        "probes": [WaveGauge(name="g1", x=0.25, z0=0.0, z1=0.3, interval=0.004),
                   TestPoints(name="grid", lo=(0.05, 0, 0.02), hi=(0.6, 0, 0.2), counts=(6, 1, 3), interval=0.01),
                   FlowGauge(name="surge", at=0.2, interval=0.004), ForceGauge(name="tank", solid="tank", interval=0.004)],
        "checkpoint": Checkpointing(interval=0.02, wall_interval=0.0, keep=2)})
    path = tmp_path / "case.toml"
    write_case(case, path)
    return path


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run (in this process) of the case file."""
    tmp = tmp_path_factory.mktemp("ref")
    toml = _case_file(tmp)
    res = run_case(load_case(toml), tmp / "run", plot=False)
    return toml, tmp / "run", res


def _start(toml, out):
    env = dict(os.environ, PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.Popen([sys.executable, "-m", "shoal", "run", str(toml), "--out", str(out), "--no-progress",
                             "--no-plot"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_checkpoint(proc, out, timeout=120):
    t0 = time.monotonic()
    while not list_checkpoints(out):
        assert proc.poll() is None, f"the run ended before its first checkpoint: {proc.communicate()}"
        assert time.monotonic() - t0 < timeout
        time.sleep(0.02)


def _resume(out, *extra):
    return main(["run", "--resume", str(out), "--no-progress", "--no-plot", *extra])


def _state(path):
    """Final particle state of a checkpoint, in id order."""
    with h5py.File(path, "r") as f:
        idp = f["particles/idp"][()]
        order = np.argsort(idp)
        out = {k: f[f"particles/{k}"][()][order] for k in ("pos", "vel", "rho", "kind", "idp")}
        out["extra"] = [f[f"integrator/extra_{k}"][()][order] for k in range(len(f["integrator"]))]
    return out


def _assert_same_final(ref_run, out):
    a = _state(list_checkpoints(ref_run)[0])
    b = _state(list_checkpoints(out)[0])
    for k in ("pos", "vel", "rho", "kind", "idp"):
        assert a[k].dtype == b[k].dtype
        assert np.array_equal(a[k], b[k]), k  # bitwise
    assert read_checkpoint(list_checkpoints(out)[0]).time == read_checkpoint(list_checkpoints(ref_run)[0]).time
    # the last snapshots are bitwise equal too
    pa, da = read_vtu(ref_run / "dam-break-2d_0004.vtu")
    pb, db = read_vtu(out / "dam-break-2d_0004.vtu")
    assert np.array_equal(pa, pb) and np.array_equal(da["velocity"], db["velocity"])


def _gauge_times(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["time", "level"]
    return [float(r[0]) for r in rows[1:]]


def _assert_same_records(ref_run, out):
    ta, tb = _gauge_times(ref_run / "gauge_g1.csv"), _gauge_times(out / "gauge_g1.csv")
    assert len(tb) == len(set(tb))  # no time twice
    assert tb == ta  # none missing
    assert (out / "gauge_g1.csv").read_bytes() == (ref_run / "gauge_g1.csv").read_bytes()
    # the flow gauge's count goes on across the restart (its per-particle state is in the checkpoint)
    assert (out / "flow_surge.csv").read_bytes() == (ref_run / "flow_surge.csv").read_bytes()
    assert (out / "force_tank.csv").read_bytes() == (ref_run / "force_tank.csv").read_bytes()
    import xarray as xr

    with xr.open_dataset(ref_run / "testpoints_grid.nc", engine="scipy") as a, \
            xr.open_dataset(out / "testpoints_grid.nc", engine="scipy") as b:
        assert np.array_equal(a["time"].values, b["time"].values)
        assert np.array_equal(a["p"].values, b["p"].values, equal_nan=True)
    pvd = (out / "dam-break-2d.pvd").read_text()
    assert pvd == (ref_run / "dam-break-2d.pvd").read_text()


def test_sigkill_then_resume_is_bitwise_identical(reference, tmp_path):
    toml, ref_run, res = reference
    out = tmp_path / "run"
    proc = _start(toml, out)
    _wait_for_checkpoint(proc, out)
    time.sleep(0.3)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    killed_at = read_checkpoint(list_checkpoints(out)[0]).time
    assert killed_at < END
    assert _resume(out) == 0
    _assert_same_final(ref_run, out)
    _assert_same_records(ref_run, out)
    log = (out / "run.log").read_text()
    assert log.count("case dam-break-2d") == 1 and "resumed from ckpt_" in log and "done:" in log


def test_sigterm_stops_with_checkpoint_and_message_then_resume_and_corrupt_fallback(reference, tmp_path, capsys):
    toml, ref_run, res = reference
    out = tmp_path / "run"
    proc = _start(toml, out)
    _wait_for_checkpoint(proc, out)
    time.sleep(0.3)  # a few steps past the checkpoint
    assert proc.poll() is None
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    last = err.strip().splitlines()[-1]
    assert last.startswith("shoal: stopped by SIGTERM at step ") and f"shoal run --resume {out}" in last
    ckpts = list_checkpoints(out)
    assert len(ckpts) == 2  # the scheduled one and the one written at the stop
    step_stop = read_checkpoint(ckpts[0]).step
    assert f"step {step_stop}," in last
    # damage the newest checkpoint: the resume must skip it (one warning line) and use the previous one
    # (inside the positions' data: the middle of the file can fall on HDF5 padding no read visits)
    with h5py.File(ckpts[0], "r") as f:
        mid = f["particles/pos"].id.get_offset() + f["particles/pos"].id.get_storage_size() // 2
    data = bytearray(ckpts[0].read_bytes())
    data[mid:mid + 64] = bytes(b ^ 0xFF for b in data[mid:mid + 64])
    ckpts[0].write_bytes(bytes(data))
    capsys.readouterr()
    assert _resume(out) == 0
    err = capsys.readouterr().err
    warn = [line for line in err.splitlines() if "warning" in line]
    assert len(warn) == 1 and ckpts[0].name in warn[0] and "falling back" in warn[0]
    assert (out / (ckpts[0].name + ".bad")).exists() or ckpts[0].exists()
    _assert_same_final(ref_run, out)
    _assert_same_records(ref_run, out)


def test_truncated_checkpoint_is_skipped(reference, tmp_path):
    toml, ref_run, res = reference
    # two valid checkpoints of the reference run; truncate the newest one
    import shutil

    out = tmp_path / "run"
    shutil.copytree(ref_run, out)
    newest = list_checkpoints(out)[0]
    newest.write_bytes(newest.read_bytes()[: newest.stat().st_size // 3])
    warnings = []
    ck = latest_checkpoint(out, warn=warnings.append)
    assert ck.path == list_checkpoints(out)[1] and len(warnings) == 1 and newest.name in warnings[0]


def test_resume_refuses_a_finished_run_or_a_changed_case(reference, tmp_path, capsys):
    toml, ref_run, res = reference
    capsys.readouterr()
    assert _resume(ref_run) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "complete" in err and "--end-time" in err
    assert _resume(tmp_path / "nowhere") == 2
    assert main(["run", "--resume", str(ref_run), "--dp", "0.02"]) == 2
    assert "cannot be given" in capsys.readouterr().err


def test_blow_up_names_step_time_particle_keeps_outputs_and_checkpoints(tmp_path, capsys):
    case = shoal.cases.still_water_2d(dp=0.05, end_time=1.0, output_interval=0.01, options=SPHOptions(fixed_dt=0.01))
    toml = tmp_path / "sw.toml"
    write_case(case.model_copy(update={"checkpoint": Checkpointing(interval=0.01, wall_interval=0.0)}), toml)
    out = tmp_path / "run"
    rc = main(["run", str(toml), "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 3
    assert err.count("\n") == 1 and err.startswith("shoal: run stopped: ")
    assert "step" in err and "t = " in err and "particle id" in err and "(x, y, z)" in err
    assert (out / "still-water-2d_unstable.vtu").exists()
    pts, data = read_vtu(out / "still-water-2d_0000.vtu")  # earlier output intact
    assert len(pts) > 0 and np.all(np.isfinite(data["density"]))
    assert "ERROR" in (out / "run.log").read_text() and "last checkpoint kept" in (out / "run.log").read_text()
    ck = latest_checkpoint(out)  # the checkpoints before the blow-up are kept and valid
    assert ck.step >= 1 and np.all(np.isfinite(ck.particles["pos"]))


def test_escaped_particles_are_recorded_and_can_stop_the_run(tmp_path):
    # a block of fluid shot at 2 m/s towards the open end of a short domain, no gravity
    from shoal.geometry import Box

    case = shoal.Case(name="jet", dim=2, dp=0.02, end_time=0.12,
                      fluid=shoal.Fluid(u_max=2.0, gravity=(0, 0, 0)),
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.2, 0, 0.2)), velocity=(2.0, 0, 0))],
                      domain=shoal.Domain(lo=(-0.05, 0, -0.05), hi=(0.35, 0, 0.25)),
                      output=shoal.Output(interval=0.06))
    res = run_case(case, tmp_path / "a", plot=False)
    with open(tmp_path / "a" / "escaped.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["id", "kind", "time", "x", "y", "z", "u", "v", "w"]
    assert len(rows) - 1 == res.escaped > 0
    ids = [int(r[0]) for r in rows[1:]]
    assert len(set(ids)) == len(ids)
    assert all(float(r[3]) > 0.35 for r in rows[1:]) and all(float(r[6]) > 1.0 for r in rows[1:])
    with pytest.raises(shoal.InstabilityError, match="max_escaped_fraction = 0.1"):
        run_case(case.model_copy(update={"max_escaped_fraction": 0.1}), tmp_path / "b", plot=False)


def test_memory_refusal(monkeypatch, tmp_path, capsys):
    import shoal.memory as mem

    monkeypatch.setattr(mem, "available_memory", lambda: 1000)
    rc = main(["run", "still-water-2d", "--dp", "0.05", "--out", str(tmp_path / "x"), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "memory" in err and "larger dp" in err
    assert not (tmp_path / "x").exists()


def test_disk_full_is_one_clear_error_and_keeps_what_was_written(monkeypatch, tmp_path, capsys):
    import errno

    import shoal.simulation.writers as writers

    calls = {"n": 0}
    real = writers.write_vtu

    def flaky(path, *a, **k):
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real(path, *a, **k)

    monkeypatch.setattr(writers, "write_vtu", flaky)
    out = tmp_path / "run"
    rc = main(["run", "still-water-2d", "--dp", "0.05", "--end-time", "0.1", "--output-interval", "0.02",
               "--checkpoint-interval", "0.01", "--out", str(out), "--no-progress", "--no-plot"])
    err = capsys.readouterr().err
    assert rc == 4 and err.count("\n") == 1 and "no space left on device" in err and "--resume" in err
    read_vtu(out / "still-water-2d_0001.vtu")
    assert 0.03 <= latest_checkpoint(out).time < 0.04  # the last one before the failed write


def test_stop_signal_handler_first_stops_second_aborts():
    from shoal.simulation.signals import Aborted, StopOnSignals

    class Sim:
        stop_requested = False

    sim = Sim()
    before = signal.getsignal(signal.SIGINT)
    with pytest.raises(Aborted):
        with StopOnSignals(sim) as s:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.01)
            assert sim.stop_requested and s.signum == signal.SIGTERM
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.01)
    assert signal.getsignal(signal.SIGINT) is before


def test_verlet_resume_in_process_is_bitwise(tmp_path):
    # Verlet keeps the previous step's velocity and density and an Euler-step counter; a run cut at a step
    # where that counter is mid-cycle must continue exactly
    case = shoal.cases.dam_break_2d(dp=0.01, end_time=0.05, output_interval=0.05,
                                    options=SPHOptions(integrator="verlet", verlet_euler_every=7))
    case = case.model_copy(update={"checkpoint": Checkpointing(wall_interval=0.0)})
    ref = run_case(case, tmp_path / "ref", plot=False, handle_signals=False)
    part = run_case(case, tmp_path / "cut", plot=False, max_steps=penultimate(ref.steps), handle_signals=False)
    assert part.simulation.integrator.count % 7 != 0 and part.steps < ref.steps
    res = shoal.resume_run(tmp_path / "cut", plot=False, handle_signals=False)
    assert res.resumed_from.name == f"ckpt_{part.steps:06d}.h5" and res.steps == ref.steps
    a, b = _state(ref.checkpoint), _state(res.checkpoint)
    for k in ("pos", "vel", "rho", "idp"):
        assert np.array_equal(a[k], b[k]), k
    assert all(np.array_equal(x, y) for x, y in zip(a["extra"], b["extra"]))


def test_resume_with_relaxation_zones_is_bitwise(tmp_path):
    # the zones' targets are functions of the time and the case alone (nothing of theirs is in a
    # checkpoint): a resumed run relaxes toward the same targets at the same times, bitwise
    from shoal.relaxation import LinearTarget, RelaxationZone

    case = shoal.cases.dam_break_2d(dp=0.01, end_time=0.05, output_interval=0.05)
    zones = [RelaxationZone(start=0.08, end=0.0, level=0.2, ramp_time=0.01,
                            target=LinearTarget(height=0.02, period=0.5, depth=0.2)),
             RelaxationZone(start=0.1, end=0.146)]
    case = case.model_copy(update={"checkpoint": Checkpointing(wall_interval=0.0), "relaxation": zones})
    ref = run_case(case, tmp_path / "ref", plot=False, handle_signals=False)
    part = run_case(case, tmp_path / "cut", plot=False, max_steps=penultimate(ref.steps), handle_signals=False)
    res = shoal.resume_run(tmp_path / "cut", plot=False, handle_signals=False)
    assert res.steps == ref.steps and part.steps < ref.steps
    a, b = _state(ref.checkpoint), _state(res.checkpoint)
    for k in ("pos", "vel", "rho", "idp"):
        assert np.array_equal(a[k], b[k]), k


def penultimate(steps):
    """A step count about 60 % through a run, not a multiple of 7."""
    n = int(0.6 * steps)
    return n if n % 7 else n + 3


def test_a_second_process_in_the_same_run_directory_is_refused(reference, tmp_path, capsys):
    import shutil

    from shoal.simulation.resources import lock_run_dir

    toml, ref_run, res = reference
    out = tmp_path / "run"
    shutil.copytree(ref_run, out)
    held = lock_run_dir(out)  # as if the run were still going
    try:
        capsys.readouterr()
        assert _resume(out, "--end-time", "0.3") == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "another shoal process" in err and str(os.getpid()) in err
    finally:
        held.close()


def test_extending_a_finished_run(reference, tmp_path):
    import shutil

    toml, ref_run, res = reference
    out = tmp_path / "run"
    shutil.copytree(ref_run, out)
    assert _resume(out, "--end-time", "0.25") == 0
    t = _gauge_times(out / "gauge_g1.csv")
    assert t[: len(_gauge_times(ref_run / "gauge_g1.csv"))] == _gauge_times(ref_run / "gauge_g1.csv")
    assert np.all(np.diff(t) > 0) and t[-1] == pytest.approx(0.248, abs=1e-9)
    assert read_checkpoint(list_checkpoints(out)[0]).time == pytest.approx(0.25, abs=1e-12)
    assert load_case(out / "case.toml").end_time == 0.25


def test_a_checkpoint_written_during_the_run_records_the_wall_time_so_far(tmp_path):
    # the wall time of a resumed run adds the checkpoint's: one written from a callback in the middle of
    # a `run` call must count that call's time so far (it recorded the time at the call's start, so a run
    # resumed from it reported only the segments before, and a particle-step rate far too high)
    case = shoal.cases.dam_break_2d(dp=0.02, end_time=0.02, output_interval=0.02)
    case = case.model_copy(update={"checkpoint": Checkpointing(interval=0.01, wall_interval=0.0, keep=3)})
    res = run_case(case, tmp_path / "run", plot=False, handle_signals=False)
    metas = sorted((read_checkpoint(p).meta for p in list_checkpoints(tmp_path / "run")),
                   key=lambda m: m["step_count"])
    walls = [m["wall_seconds"] for m in metas]
    assert len(walls) >= 2  # at t = 0.01 s, during the run, and the final one
    assert 0 < walls[0] < walls[-1] <= res.wall_seconds
    resumed = shoal.resume_run(tmp_path / "run", end_time=0.03, plot=False, handle_signals=False)
    assert resumed.wall_seconds > res.wall_seconds  # the resumed run counts the first run's time, then its own


def test_a_checkpoint_of_an_earlier_version_with_vmax_restores(tmp_path):
    """The viscous time-step term's array was saved as ``particles/vmax`` before it was named
    ``mu_max``: such a checkpoint still restores, into ``mu_max``."""
    from shoal.build import build_model
    from shoal.cases import dam_break_2d
    from shoal.simulation.checkpoint import capture, restore, write_checkpoint

    case = dam_break_2d(dp=0.02, end_time=0.05)
    sim = shoal.Simulation(build_model(case), case.end_time)
    sim.run(max_steps=3)
    ds = capture(sim, "")
    ds["particles/vmax"] = ds.pop("particles/mu_max")
    path = tmp_path / "ckpt_000003.h5"
    write_checkpoint(path, ds)
    again = shoal.Simulation(build_model(case), case.end_time)
    restore(again, read_checkpoint(path))
    m, a = sim.model, again.model
    assert np.array_equal(m.host(m.mu_max), a.host(a.mu_max)) and np.any(m.host(m.mu_max) > 0)
    assert again.step_count == 3


def test_simulation_run_ends_a_run_as_the_runner_does(tmp_path):
    """Issue 29: a Simulation driven from Python ends its run the same way `run_case` does: at the end time
    its snapshot writer writes the last state (the end time 0.013 s is off its 0.005 s schedule) and its
    checkpoint writer, added last, the last checkpoint; a run stopped by ``max_steps`` ends there when
    its caller calls `finalize`, once per step."""
    from shoal.simulation import Simulation, TimeInterval
    from shoal.simulation.checkpoint import CheckpointWriter
    from shoal.simulation.writers import SnapshotWriter

    case = shoal.cases.dam_break_2d(dp=0.146 / 6, a=0.146, layers=2, end_time=0.013)
    for label, max_steps in (("whole", None), ("part", 7)):
        out = tmp_path / label
        out.mkdir()
        sim = Simulation(case)
        snaps = SnapshotWriter(out, "s")
        ckw = CheckpointWriter(out, "# a test", keep=5)
        sim.add_callback(snaps, TimeInterval(0.005), name="snapshots")
        sim.add_callback(ckw, TimeInterval(1.0), name="checkpoint")
        sim.run(max_steps=max_steps)
        if max_steps is None:
            assert sim.time == pytest.approx(0.013, abs=1e-12)
            assert snaps.last_time == sim.time and snaps.count == 4  # t = 0, 0.005, 0.01 and the end
        else:
            assert sim.step_count == 7 and snaps.count == 1 and ckw.last_step == 0  # t = 0 only
            sim.finalize()
            sim.finalize()
            assert snaps.count == 2 and snaps.last_time == sim.time
        assert ckw.written == 2 and read_checkpoint(ckw.last_path).step == sim.step_count  # t = 0 and the end
