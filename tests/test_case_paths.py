"""Data files named in a case file are relative to the case file, and stay the same files for a resumed run
and for the resolved case a run writes (issue 30, class 2).

A case file ``cases/flume.toml`` names ``bed.csv`` (a bathymetry) and ``paddle.csv`` (a time-series motion)
beside it and is run from the folder above as ``shoal run cases/flume.toml``. The resolved case used to keep
``cases/bed.csv``, a path relative to the current folder, which the resolved ``case.toml`` then read relative
to the run directory: the run could not be resumed ("the case differs") and the resolved case could not be
run again ("not found"). Paths are now stored absolute.
"""

from __future__ import annotations

import os
import tomllib

import numpy as np
import pytest

from shoal.cli import main
from shoal.simulation.resume import latest_checkpoint

FLUME = """\
name = "flume"
dim = 2
dp = 0.04
end_time = 0.06

[fluid]
depth = 0.2
surface_level = 0.2

[output]
interval = 0.02

[checkpoint]
interval = 0.02

[[motions]]
type = "time_series"
name = "paddle"
file = "paddle.csv"

[[solids]]
name = "bed"
shape = { type = "bathymetry", file = "bed.csv", base = -0.3 }

[[solids]]
name = "paddle"
motion = "paddle"
shape = { type = "box", lo = [-0.12, 0.0, -0.3], hi = [-0.04, 0.0, 0.5] }

[[fluids]]
shape = { type = "box", lo = [0.0, 0.0, -0.3], hi = [1.0, 0.0, 0.2] }
"""


def _cli(argv):
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


@pytest.fixture
def flume(tmp_path, monkeypatch):
    cases = tmp_path / "cases"
    cases.mkdir()
    rows = ["x,y,z"] + [f"{x},{y},{z}" for x, z in ((0.0, -0.1), (0.5, -0.1), (1.0, 0.05)) for y in (0.0, 1.0)]
    (cases / "bed.csv").write_text("\n".join(rows) + "\n")
    (cases / "paddle.csv").write_text("t,x\n0,0\n0.05,0.001\n0.1,0.002\n0.2,0.002\n")
    (cases / "flume.toml").write_text(FLUME)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_a_run_with_data_files_beside_its_case_file_resumes_and_runs_again(flume, capsys):
    common = ["--no-progress", "--no-plot"]
    assert _cli(["run", "cases/flume.toml", "--out", "runs/a", "--end-time", "0.04", *common]) == 0
    resolved = tomllib.loads((flume / "runs/a/case.toml").read_text())
    files = [resolved["motions"][0]["file"], resolved["solids"][0]["shape"]["file"]]
    assert files == [str(flume / "cases/paddle.csv"), str(flume / "cases/bed.csv")]
    assert _cli(["run", "--resume", "runs/a", "--end-time", "0.06", *common]) == 0
    assert latest_checkpoint(flume / "runs/a").time == pytest.approx(0.06)
    # the resolved case runs again, from another folder too, as the same case
    (flume / "elsewhere").mkdir()
    os.chdir(flume / "elsewhere")
    assert _cli(["run", "../runs/a/case.toml", "--out", "../runs/b", *common]) == 0
    # the resumed run and the run of its resolved case end alike, particle by particle (0.04 s is an output
    # time of both, so their steps are the same)
    a, b = (latest_checkpoint(flume / f"runs/{r}").particles for r in "ab")
    pa, pb = np.empty_like(a["pos"]), np.empty_like(b["pos"])
    pa[a["idp"]], pb[b["idp"]] = a["pos"], b["pos"]
    assert np.array_equal(pa, pb)
    capsys.readouterr()
