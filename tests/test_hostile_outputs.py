"""Output that never destroys what the user owns, and a full disk answered in one line (issue 30, classes 1
and 3, and ``shoal --version`` of class 8).

Targets: ``shoal new -o`` and ``shoal plot-case -o`` refuse a symbolic link (the file it points to stays as
it was), a FIFO (no reader needed: nothing opens it), a directory, a device node and a path under a file,
each with one line and exit 2, and leave no temporary file.

Full disk: on a real tmpfs of a few hundred kB (mounted for the test where the machine allows it: root and
a kernel that lets this process mount; elsewhere those tests skip and the injected-ENOSPC ones stand), the
disk is filled just before a chosen write -- a checkpoint, a snapshot, a probe CSV sample, ``shoal new``,
``plot-case`` -- so the write meets the file system's own ENOSPC. Each must end with exit 4 and one line,
no temporary file, every checkpoint written before readable, and the run resumable to its end once the
filler is removed. HDF5 alone crashed the process here (a segfault after pages of tracebacks).
"""

from __future__ import annotations

import errno
import hashlib
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from shoal.cli import main
from shoal.simulation.checkpoint import list_checkpoints, read_checkpoint
from shoal.simulation.resume import latest_checkpoint

SRC = Path(__file__).resolve().parents[1] / "src"
RUN = ["still-water-2d", "--dp", "0.05", "--end-time", "0.1", "--output-interval", "0.02",
       "--checkpoint-interval", "0.01", "--no-progress", "--no-plot"]


def _cli(argv):
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


def _one_line(err, start="shoal: error: "):
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(start), err
    return lines[0]


def _state(path):
    """What a path is now: its lstat mode and, for a regular file, its bytes' hash."""
    st = os.lstat(path)
    digest = hashlib.sha256(Path(path).read_bytes()).hexdigest() if stat.S_ISREG(st.st_mode) else None
    return st.st_mode, digest


# ------------------------------------------------------------------ targets
def _targets(tmp_path):
    """(id, target path, the thing it is) for each output target shoal must refuse."""
    mine = tmp_path / "mine.toml"
    mine.write_text("# the user's own file\n")
    link = tmp_path / "link.toml"
    link.symlink_to(mine)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    folder = tmp_path / "folder"
    folder.mkdir()
    return [("symlink", link, "symbolic link"), ("fifo", fifo, "FIFO"), ("directory", folder, "directory"),
            ("device", Path(os.devnull), "character device"), ("under-a-file", mine / "x.out", "is a file")]


@pytest.mark.parametrize("command", ["new", "plot-case"])
def test_special_targets_are_refused_and_left_as_they_were(command, tmp_path, capsys):
    targets = _targets(tmp_path)
    before = {p: _state(p) for _, p, _ in targets if os.path.lexists(p)}
    mine = _state(tmp_path / "mine.toml")
    for name, target, what in targets:
        argv = [command, "still-water-2d", "-o", str(target)] + (["--force"] if command == "new" else [])
        assert _cli(argv) == 2, name
        line = _one_line(capsys.readouterr().err)
        assert what in line and str(target) in line, (name, line)
    assert {p: _state(p) for p in before} == before
    assert _state(tmp_path / "mine.toml") == mine  # not written through the link
    assert not list(tmp_path.rglob("*.tmp"))


def test_version():
    out = subprocess.run([sys.executable, "-m", "shoal", "--version"], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=str(SRC)))
    from shoal.version import __version__

    assert out.returncode == 0 and out.stdout.strip() == f"shoal {__version__}" and not out.stderr


# ------------------------------------------------------------------ full disk
@pytest.fixture
def small_disk(tmp_path):
    """A tmpfs of 400 kB mounted at tmp_path/disk (unmounted after); skips where mounting is not allowed."""
    disk = tmp_path / "disk"
    disk.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root; the injected-ENOSPC tests cover the full disk here")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=400k", "tmpfs", str(disk)], capture_output=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({r.stderr.decode().strip()}); the injected-ENOSPC tests stand")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


def _fill(disk):
    """Fill `disk` to the last byte with a filler file; returns its path (remove it to free the space)."""
    filler = disk / "filler"
    with open(filler, "ab", buffering=0) as f:
        for block in (1 << 16, 1 << 12, 1 << 8, 1):
            try:
                while True:
                    f.write(b"\0" * block)
            except OSError as err:
                assert err.errno == errno.ENOSPC
    return filler


def _fill_before(monkeypatch, module, name, disk, call):
    """Make call number `call` of `module.name` fill the disk first, then run the real function."""
    real = getattr(module, name)
    calls = {"n": 0}

    def filling(*a, **k):
        calls["n"] += 1
        if calls["n"] == call:
            _fill(disk)
        return real(*a, **k)

    monkeypatch.setattr(module, name, filling)


def _full_disk_then_resume(disk, capsys, min_checkpoints):
    out = disk / "run"
    rc = _cli(["run", *RUN, "--out", str(out)])
    line = _one_line(capsys.readouterr().err)
    assert rc == 4 and "no space left on device" in line and "--resume" in line, line
    assert not list(out.glob("*.tmp"))
    cks = list_checkpoints(out)
    assert len(cks) >= min_checkpoints
    for ck in cks:
        read_checkpoint(ck)  # every checkpoint written before is whole
    (disk / "filler").unlink()
    assert _cli(["run", "--resume", str(out), "--no-progress", "--no-plot"]) == 0
    capsys.readouterr()
    assert latest_checkpoint(out).time == pytest.approx(0.1)


def test_full_disk_during_a_checkpoint(small_disk, monkeypatch, capsys):
    import shoal.simulation.checkpoint as checkpoint

    _fill_before(monkeypatch, checkpoint, "write_checkpoint", small_disk, 3)
    _full_disk_then_resume(small_disk, capsys, 2)


def test_full_disk_during_a_snapshot(small_disk, monkeypatch, capsys):
    import shoal.simulation.writers as writers

    _fill_before(monkeypatch, writers, "write_vtu", small_disk, 3)
    _full_disk_then_resume(small_disk, capsys, 1)


def test_full_disk_during_a_probe_sample(small_disk, monkeypatch, capsys, tmp_path):
    """A wave gauge's CSV, flushed at every sample, meets the full disk at its fourth sample."""
    import shoal
    from shoal.probes import WaveGauge

    case = shoal.cases.still_water_2d(dp=0.05, end_time=0.1, output_interval=0.02)
    case = case.model_copy(update={"probes": [WaveGauge(name="g", x=0.3, z0=0.0, z1=0.4, interval=0.01)],
                                   "checkpoint": case.checkpoint.model_copy(update={"interval": 0.01})})
    path = tmp_path / "case.toml"
    shoal.write_case(case, path)
    from shoal.probes import ProbeRecorder

    _fill_before(monkeypatch, ProbeRecorder, "__call__", small_disk, 4)
    out = small_disk / "run"
    rc = _cli(["run", str(path), "--out", str(out), "--no-progress", "--no-plot"])
    line = _one_line(capsys.readouterr().err)
    assert rc == 4 and "no space left on device" in line, line
    for ck in list_checkpoints(out):
        read_checkpoint(ck)
    (small_disk / "filler").unlink()
    assert _cli(["run", "--resume", str(out), "--no-progress", "--no-plot"]) == 0
    capsys.readouterr()
    rows = (out / "gauge_g.csv").read_text().splitlines()[1:]
    times = [float(r.split(",")[0]) for r in rows]
    assert times == sorted(set(times)) and times[-1] == pytest.approx(0.1)  # none lost, none twice


@pytest.mark.parametrize("argv,name", [(["new", "still-water-2d", "--force", "-o"], "case.toml"),
                                       (["plot-case", "still-water-2d", "-o"], "case.png")])
def test_full_disk_for_new_and_plot_case_replaces_nothing(argv, name, small_disk, capsys):
    target = small_disk / name
    target.write_bytes(b"the user's earlier file\n")
    _fill(small_disk)
    assert _cli(argv + [str(target)]) == 4
    line = _one_line(capsys.readouterr().err)
    assert "no space left on device" in line and str(target) in line
    assert target.read_bytes() == b"the user's earlier file\n"
    assert sorted(p.name for p in small_disk.iterdir()) == sorted([name, "filler"])


def test_injected_enospc_during_a_checkpoint_is_one_line(tmp_path, monkeypatch, capsys):
    """Where no tmpfs can be mounted: the checkpoint's bytes meet ENOSPC from os.write at the third
    checkpoint; exit 4, one line, the earlier checkpoints whole, no temporary file, and the run resumes."""
    import shoal.simulation.checkpoint as checkpoint

    real = checkpoint.write_bytes_atomic
    calls = {"n": 0}

    def failing(path, data, chunk=1 << 24):
        calls["n"] += 1
        if calls["n"] != 3:
            return real(path, data, chunk)

        def no_space(fd, b):
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(checkpoint.os, "write", no_space)
        try:
            return real(path, data, chunk)
        finally:
            monkeypatch.undo()

    monkeypatch.setattr(checkpoint, "write_bytes_atomic", failing)
    out = tmp_path / "run"
    rc = _cli(["run", *RUN, "--out", str(out)])
    line = _one_line(capsys.readouterr().err)
    assert rc == 4 and "no space left on device" in line
    assert not list(out.glob("*.tmp")) and len(list_checkpoints(out)) == 2
    for ck in list_checkpoints(out):
        read_checkpoint(ck)
    assert _cli(["run", "--resume", str(out), "--no-progress", "--no-plot"]) == 0
    capsys.readouterr()
    assert latest_checkpoint(out).time == pytest.approx(0.1)


# ------------------------------------------------------------------ run directories
@pytest.mark.parametrize("name,content", [("case.toml", "# my own commented case\n"), ("run.log", "my notes\n"),
                                          ("gauge_g.csv", "time,level\n"), ("still-water-2d.pvd", "<mine/>\n"),
                                          ("still-water-2d_0000.vtu", "mine\n")])
def test_a_run_never_replaces_a_file_no_shoal_run_wrote(name, content, tmp_path, monkeypatch, capsys):
    """`--out .` beside one's own case.toml (or any file a run would write there): refused with one line
    naming the file, with or without --overwrite (which is for shoal's own runs), the file unchanged."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / name).write_text(content)
    for extra in ([], ["--overwrite"]):
        assert _cli(["run", *RUN, "--out", ".", *extra]) == 2
        line = _one_line(capsys.readouterr().err)
        assert f"holds {name}, which no shoal run wrote" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == [name] and (tmp_path / name).read_text() == content


def test_overwrite_leaves_nothing_of_the_earlier_run(tmp_path, capsys):
    """--overwrite removes the earlier run's snapshots and probe records before the new run: a shorter run
    with other probes leaves no snapshot numbered past its own and no CSV of a probe it does not have; a
    file of the user's in the run directory stays."""
    import shoal
    from shoal.probes import WaveGauge

    out = tmp_path / "run"
    case = shoal.cases.still_water_2d(dp=0.05, end_time=0.1, output_interval=0.02)
    first = case.model_copy(update={"probes": [WaveGauge(name="old", x=0.3, z0=0.0, z1=0.4, interval=0.01)]})
    shoal.run_case(first, out, plot=False)
    (out / "notes.txt").write_text("mine\n")
    assert (out / "gauge_old.csv").exists() and (out / "still-water-2d_0005.vtu").exists()
    second = case.model_copy(update={"end_time": 0.04,
                                     "probes": [WaveGauge(name="new", x=0.3, z0=0.0, z1=0.4, interval=0.01)]})
    shoal.run_case(second, out, plot=False, overwrite=True)
    names = sorted(p.name for p in out.iterdir())
    assert "gauge_old.csv" not in names and "gauge_new.csv" in names and "notes.txt" in names
    assert sorted(n for n in names if n.endswith(".vtu")) == [f"still-water-2d_000{k}.vtu" for k in range(3)]
    assert latest_checkpoint(out).time == pytest.approx(0.04)


# ------------------------------------------------------------------ Ctrl-C
def test_ctrl_c_before_the_time_loop_leaves_nothing_that_blocks_a_rerun(tmp_path, monkeypatch, capsys):
    """Ctrl-C while the kernels compile (here: at the first sort, after the run directory's set-up files are
    written): no advice to resume what cannot be resumed, and no directory that needs --overwrite; the same
    command then runs. During particle generation (before any file): the same answer, nothing written."""
    import shoal.model
    import shoal.runner

    out = tmp_path / "run"
    real_sort = shoal.model.Model.sort

    def interrupted(self):
        raise KeyboardInterrupt

    for where, target, name in (("compile", shoal.model.Model, "sort"), ("generation", shoal.runner, "build_model")):
        monkeypatch.setattr(target, name, interrupted if where == "compile" else lambda *a, **k: interrupted(None))
        assert _cli(["run", *RUN, "--out", str(out)]) == 130
        line = _one_line(capsys.readouterr().err, start="shoal: aborted")
        assert "nothing to resume" in line and "--resume" not in line and "--overwrite" not in line, line
        assert not out.exists(), sorted(p.name for p in out.iterdir())
        monkeypatch.undo()
    assert shoal.model.Model.sort is real_sort
    assert _cli(["run", *RUN, "--out", str(out)]) == 0
    capsys.readouterr()
    assert latest_checkpoint(out).time == pytest.approx(0.1)


def test_an_output_directory_that_is_a_loop_of_links_is_named(tmp_path, capsys):
    """`--out` at a symbolic link that leads nowhere (a loop): one line saying so, not "File exists"."""
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    assert _cli(["run", *RUN, "--out", str(tmp_path / "a")]) == 2
    line = _one_line(capsys.readouterr().err)
    assert "symbolic link that leads to no folder" in line and "File exists" not in line, line


def test_a_case_far_too_large_is_refused_with_readable_figures(capsys):
    """A spacing a million times finer than the tank: the memory refusal quotes its figures in 3 digits."""
    assert _cli(["check", "still-water-2d", "--dp", "1e-6"]) == 2
    line = _one_line(capsys.readouterr().err)
    assert "particles would be generated" in line and len(line) < 300, line
