"""A run killed anywhere can always be re-run or resumed, to the bitwise result of a run never killed
(issue 30, must-show 4).

A tiny 2D dam break (312 particles, about 210 steps to 0.03 s, a snapshot and a checkpoint every 0.01 s,
a wave gauge) runs as ``python -m shoal run case.toml --out DIR`` in a subprocess and is killed with
SIGKILL -- nothing of shoal's runs after it: no signal handler, ``finally`` block or buffered write --

* at chosen points, through the test hook ``SHOAL_FAULT`` (`shoal.faults`: the process kills itself on
  reaching the point, so a window of a few milliseconds such as a checkpoint write is hit every time):
  while the kernels compile (on an empty Numba cache); while the particles are generated; in the middle
  of writing ``resolved.json`` and ``case.toml``; in the middle of the first time step; in the middle of
  writing the first snapshot and the first checkpoint; in a later snapshot's write; and, in the runs
  resumed after those kills, while the records are restored (the ``.pvd`` write), while the particles are
  generated, in the middle of a checkpoint's write and of a step; and while ``--overwrite`` clears an
  earlier run. The kills before the first checkpoint and those after it are each one chain in one run
  directory (a kill, the way on, the next kill in that run...), which costs one run to the end a chain
  instead of one a kill;
* and at random moments, again and again in one run directory (a fixed seed).

After each kill the rules of a run directory must hold: the user's case file is unchanged; every
``ckpt_*.h5`` in the directory reads back and verifies (a half-written checkpoint is never under that
name, so never picked up); when a checkpoint exists, ``shoal run --resume DIR`` continues from it; when
none does, ``--resume`` answers one ``shoal: error:`` line with exit 2, and the run starts again -- a
plain re-run when the directory holds no ``resolved.json``, else with ``--overwrite``, which the plain
re-run's one-line refusal names. Whichever way, the run then ends exactly as the uninterrupted reference
run does: the same final checkpoint (every array, particle by particle, bitwise), the same snapshots,
``.pvd``, gauge and escaped-particle records, and no temporary or set-aside file left behind. No command
ever prints a traceback.

The uninterrupted reference runs in a subprocess too, with the same Numba cache (one for this module, so
every subprocess after the compilation-phase kill's re-run loads the kernels instead of compiling them).
"""

from __future__ import annotations

import hashlib
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

import shoal
from shoal import write_case
from shoal.case import Checkpointing
from shoal.cli import main
from shoal.errors import InputError
from shoal.output import read_vtu
from shoal.probes import WaveGauge
from shoal.simulation.checkpoint import list_checkpoints, read_checkpoint
from shoal.simulation.resume import latest_checkpoint
from shoal.simulation.run_files import run_files

SRC = Path(shoal.__file__).resolve().parents[1]
NAME = "dam-break-2d"
END = 0.03
RUN_FLAGS = ["--no-progress", "--no-plot"]


# ------------------------------------------------------------------ the case and the reference run
@pytest.fixture(scope="module")
def numba_cache(tmp_path_factory):
    """An empty Numba cache for this module's subprocesses: the first run compiles (the compilation-phase
    kill, the first test, needs that), the others load what it saved."""
    return tmp_path_factory.mktemp("numba-cache")


@pytest.fixture(scope="module")
def case_file(tmp_path_factory):
    """(path, SHA-256) of the user's case file, in a folder of its own that no run writes to."""
    case = shoal.cases.dam_break_2d(dp=0.146 / 8, a=0.146, layers=2, end_time=END, output_interval=0.01)
    case = case.model_copy(update={
        "probes": [WaveGauge(name="g1", x=0.2, z0=0.0, z1=0.3, interval=0.002)],
        "checkpoint": Checkpointing(interval=0.01, wall_interval=0.0, keep=2)})
    path = tmp_path_factory.mktemp("user") / "case.toml"
    write_case(case, path)
    return path, hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def reference(tmp_path_factory, case_file, numba_cache):
    """(the run directory of the uninterrupted run, its wall time from start to exit [s])."""
    out = tmp_path_factory.mktemp("ref") / "run"
    t0 = time.monotonic()
    r = _shoal(["run", str(case_file[0]), "--out", str(out)], numba_cache)
    assert r.returncode == 0, r.stderr
    return out, time.monotonic() - t0


# ------------------------------------------------------------------ helpers
def _env(cache, fault=None):
    env = dict(os.environ, PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               NUMBA_CACHE_DIR=str(cache))
    env.pop("SHOAL_FAULT", None)
    if fault is not None:
        env["SHOAL_FAULT"] = fault
    return env


def _shoal(argv, cache, fault=None, timeout=300):
    """``python -m shoal ARGV`` in a subprocess (with `fault` as ``SHOAL_FAULT``); never a traceback."""
    r = subprocess.run([sys.executable, "-m", "shoal", *argv, *RUN_FLAGS], env=_env(cache, fault),
                       capture_output=True, text=True, timeout=timeout)
    assert "Traceback" not in r.stderr, r.stderr
    return r


def _killed(argv, cache, fault, timeout=300):
    """Run ``shoal ARGV`` with ``SHOAL_FAULT=fault``; it must die of its own SIGKILL there."""
    r = _shoal(argv, cache, fault, timeout)
    assert r.returncode == -signal.SIGKILL, f"not killed at {fault!r}: exit {r.returncode}, {r.stderr}"


def _cli(argv, capsys):
    """(exit status, standard error) of ``shoal ARGV`` in this process (only for refusals: nothing runs)."""
    capsys.readouterr()
    try:
        rc = main([*argv, *RUN_FLAGS])
    except SystemExit as exc:
        rc = exc.code
    return rc, capsys.readouterr().err


def _one_error_line(rc, err):
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("shoal: error: "), (rc, err)
    return lines[0]


def _check_after_kill(case_file, out):
    """What must hold after a kill (and after a run to the end): the user's case file unchanged, every
    checkpoint under its own name complete and verified (none is half-written), so that finding the newest
    one to resume from skips none with a warning."""
    path, digest = case_file
    assert hashlib.sha256(path.read_bytes()).hexdigest() == digest, "the user's case file changed"
    for p in list_checkpoints(out):
        read_checkpoint(p)  # raises CheckpointError on a truncated or corrupt file
    if list_checkpoints(out):
        warnings = []
        latest_checkpoint(out, warn=warnings.append)
        assert not warnings, warnings


def _next_command(case_file, out, capsys):
    """How a killed run goes on, by the rules, and the refusals met on the way, checked.

    Returns
    -------
    (str, list of str or None)
        ``("resume", argv)`` when a checkpoint short of the end time exists; ``("rerun", argv)`` when none
        exists and the directory holds no ``resolved.json`` (a plain re-run); ``("overwrite", argv)`` when
        none exists but ``resolved.json`` does (the plain re-run is refused in one line naming
        ``--overwrite``); ``("complete", None)`` when the kill came after the final checkpoint.
    """
    plain = ["run", str(case_file[0]), "--out", str(out)]
    try:
        ck = latest_checkpoint(out)
    except InputError:
        ck = None
    if ck is not None:
        if ck.time >= END * (1 - 1e-12):
            line = _one_error_line(*_cli(["run", "--resume", str(out)], capsys))
            assert "complete" in line
            return "complete", None
        return "resume", ["run", "--resume", str(out)]
    line = _one_error_line(*_cli(["run", "--resume", str(out)], capsys))
    if not (out / "resolved.json").exists():
        assert "no such run directory" in line or "no run to resume" in line, line
        return "rerun", plain
    # killed before case.toml was written: "no run to resume"; after: "no checkpoint ..., with --overwrite"
    assert "no run to resume" in line or "holds no checkpoint" in line and "--overwrite" in line, line
    line = _one_error_line(*_cli(plain, capsys))
    assert "--overwrite" in line, line
    return "overwrite", [*plain, "--overwrite"]


def _particles(path):
    """The particle and integrator arrays of a checkpoint, in particle-id order."""
    with h5py.File(path, "r") as f:
        order = np.argsort(f["particles/idp"][()], kind="stable")
        names = [f"particles/{k}" for k in f["particles"]] + [f"integrator/{k}" for k in f["integrator"]]
        return {k: f[k][()][order] for k in names}


def _assert_same_as_reference(ref, out):
    """`out` ended exactly as the uninterrupted run `ref`: final checkpoint (bitwise, every array), every
    snapshot, the collection, the gauge and escaped-particle records; no temporary or set-aside file."""
    a, b = read_checkpoint(list_checkpoints(ref)[0]), read_checkpoint(list_checkpoints(out)[0])
    assert (b.step, b.time) == (a.step, a.time)
    pa, pb = _particles(a.path), _particles(b.path)
    assert sorted(pa) == sorted(pb)
    for k in pa:
        assert pa[k].dtype == pb[k].dtype and np.array_equal(pa[k], pb[k]), k  # bitwise
    snaps = sorted(p.name for p in ref.glob(f"{NAME}_*.vtu"))
    assert sorted(p.name for p in out.glob(f"{NAME}_*.vtu")) == snaps and len(snaps) == 4
    for s in snaps:
        (xa, da), (xb, db) = read_vtu(ref / s), read_vtu(out / s)
        assert np.array_equal(xa, xb) and sorted(da) == sorted(db), s
        assert all(np.array_equal(da[k], db[k]) for k in da), s
    for f in (f"{NAME}.pvd", "gauge_g1.csv", "escaped.csv"):
        assert (out / f).read_bytes() == (ref / f).read_bytes(), f
    left = [p.name for p in out.iterdir() if p.name.endswith((".tmp", ".tmp.t", ".resume"))]
    assert not left, f"left behind: {left}"


# ------------------------------------------------------------------ the kills
def _check_mid_write(out, fault):
    """After a kill inside an atomic write: its temporary file is there, not renamed over the file (for a
    checkpoint or a snapshot, which are written once, the file is not there at all)."""
    if not fault.startswith("write:"):
        return
    tmp = list(out.glob(fault[len("write:"):].split("@")[0] + ".tmp"))
    assert len(tmp) == 1, (fault, tmp)
    if tmp[0].name.startswith(("ckpt_", f"{NAME}_")):
        assert not tmp[0].with_suffix("").exists(), fault


def _kill_chain(links, case_file, ref, cache, out, capsys, argv=None):
    """Start the run (or `argv`), kill it at each link's point in turn, going on by the rules after each
    kill; then let it run to its end, which must be that of the uninterrupted run `ref`.

    Parameters
    ----------
    links : list of tuple
        ``(SHOAL_FAULT, expected way on, *files the kill must leave)``: the way on is what
        `_next_command` must answer after that kill.
    """
    argv = argv or ["run", str(case_file[0]), "--out", str(out)]
    for fault, expect, *left in links:
        _killed(argv, cache, fault)
        _check_after_kill(case_file, out)
        _check_mid_write(out, fault)
        assert all((out / name).exists() for name in left), f"the kill at {fault!r} left no {left}"
        kind, argv = _next_command(case_file, out, capsys)
        assert kind == expect, f"after the kill at {fault!r}: {kind}, not {expect}"
    r = _shoal(argv, cache)
    assert r.returncode == 0, r.stderr
    _check_after_kill(case_file, out)
    _assert_same_as_reference(ref, out)


def test_killed_while_the_kernels_compile(case_file, numba_cache, tmp_path, capsys, request):
    """On an empty Numba cache, killed before the fourth kernel's first call: three are compiled (and saved
    in the cache), the rest not. The run starts again (nothing to resume) on that half-filled cache."""
    # (the reference run is asked for only at the end: made before, it would fill the cache)
    cache = numba_cache if not any(numba_cache.rglob("*.nbi")) else tmp_path / "numba-cache"  # (run alone)
    out = tmp_path / "run"
    _killed(["run", str(case_file[0]), "--out", str(out)], cache, "compile@4")
    assert any(cache.rglob("*.nbi")), "nothing was compiled before the kill"
    _check_after_kill(case_file, out)
    assert not list_checkpoints(out)
    kind, argv = _next_command(case_file, out, capsys)
    assert kind == "overwrite"
    r = _shoal(argv, cache)
    assert r.returncode == 0, r.stderr
    _check_after_kill(case_file, out)
    _assert_same_as_reference(request.getfixturevalue("reference")[0], out)


BEFORE_THE_FIRST_CHECKPOINT = [  # (SHOAL_FAULT, how the run goes on after that kill)
    ("generate", "rerun"),  # nothing written yet: not even the run directory
    ("write:resolved.json", "rerun"),  # the run's first file: the directory holds no file of shoal's yet
    ("write:case.toml", "overwrite"),
    ("step@1", "overwrite"),
    (f"write:{NAME}_0000.vtu", "overwrite"),
    ("write:ckpt_*.h5@1", "overwrite"),  # the first checkpoint, at t = 0.01 s
]


def test_killed_before_the_first_checkpoint(case_file, reference, numba_cache, tmp_path, capsys):
    """Killed in the set-up, in the first step, in the first snapshot's write and the first checkpoint's:
    nothing to resume, each time the run starts again."""
    _kill_chain(BEFORE_THE_FIRST_CHECKPOINT, case_file, reference[0], numba_cache, tmp_path / "run", capsys)


AFTER_A_CHECKPOINT = [
    (f"write:{NAME}_0002.vtu", "resume"),  # the snapshot at t = 0.02 s; the checkpoint at 0.01 s is there
    # the resumed run cutting its collection back to the checkpoint, after its gauge record got back the
    # bytes it held then and before the record's copy set aside (gauge_g1.csv.resume) is removed
    (f"write:{NAME}.pvd@1", "resume", "gauge_g1.csv.resume"),
    ("generate", "resume"),  # the resumed run generating its particles: its directory untouched
    ("write:ckpt_*.h5@1", "resume"),  # the resumed run's first checkpoint, at t = 0.02 s
    ("write:ckpt_*.h5@2", "resume"),  # its last, at the end time 0.03 s
    ("step@20", "resume"),  # 20 steps after the checkpoint at 0.02 s
]


def test_killed_after_a_checkpoint_and_again_while_resuming(case_file, reference, numba_cache, tmp_path,
                                                           capsys):
    """Killed in a snapshot's write after the first checkpoint, then each resumed run killed in its turn:
    while it restores its records, while it generates its particles, in a checkpoint's write, in a step;
    it resumes each time."""
    _kill_chain(AFTER_A_CHECKPOINT, case_file, reference[0], numba_cache, tmp_path / "run", capsys)


def test_killed_while_overwrite_clears_the_earlier_run(case_file, reference, numba_cache, tmp_path, capsys):
    """``--overwrite`` killed just before it removes the last of the earlier run's files: the directory
    must still be known as a shoal run, so that ``--overwrite`` clears it again (a directory holding a
    ``run.log`` or a ``case.toml`` but no ``resolved.json`` is refused as someone else's, even with it)."""
    out = tmp_path / "run"
    shutil.copytree(reference[0], out)
    last = f"remove:*@{len(run_files(out, [NAME]))}"
    _kill_chain([(last, "overwrite")], case_file, reference[0], numba_cache, out, capsys,
                argv=["run", str(case_file[0]), "--out", str(out), "--overwrite"])


def test_killed_at_random_moments_again_and_again(case_file, reference, numba_cache, tmp_path, capsys):
    """SIGKILL from outside after a random delay (a fixed seed), then the run goes on by the rules in the
    same directory and is killed again, three times; then it runs to its end."""
    rng = random.Random(304)
    out = tmp_path / "run"
    argv = ["run", str(case_file[0]), "--out", str(out)]
    seen = []
    for _ in range(3):
        delay = rng.uniform(0.05, 0.95) * reference[1]  # a moment of a whole run, start to exit
        proc = subprocess.Popen([sys.executable, "-m", "shoal", *argv, *RUN_FLAGS], env=_env(numba_cache),
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(delay)
        proc.send_signal(signal.SIGKILL)
        _, err = proc.communicate(timeout=60)
        assert "Traceback" not in err, err
        assert proc.returncode in (0, -signal.SIGKILL), err
        _check_after_kill(case_file, out)
        kind, argv = _next_command(case_file, out, capsys)
        seen.append((round(delay, 2), proc.returncode, kind))  # (shown when an assertion fails)
        if kind == "complete":  # the kill came after the final checkpoint (or the run had ended)
            break
    if argv is not None:
        r = _shoal(argv, numba_cache)
        assert r.returncode == 0, (seen, r.stderr)
    _check_after_kill(case_file, out)
    _assert_same_as_reference(reference[0], out)
