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


def _files(d):
    return {p.relative_to(d): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def test_a_resume_refuses_a_data_file_changed_or_gone(flume, capsys):
    """The case file names a data file by its path only: a file edited or moved after the run started
    would make the resumed run another case. Each is one line, exit 2, the run directory untouched; the
    file put back, the run resumes."""
    common = ["--no-progress", "--no-plot"]
    assert _cli(["run", "cases/flume.toml", "--out", "runs/a", "--end-time", "0.04", *common]) == 0
    capsys.readouterr()
    run = flume / "runs/a"
    before = _files(run)
    paddle = flume / "cases/paddle.csv"
    original = paddle.read_text()
    paddle.write_text(original.replace("0.1,0.002", "0.1,0.003"))
    assert _cli(["run", "--resume", "runs/a", "--end-time", "0.06", *common]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("shoal: error: ") and "Traceback" not in err, err
    assert f"{paddle} has changed since the run in runs/a started" in err and "--overwrite" in err
    assert _files(run) == before
    paddle.write_text(original)
    (flume / "cases/bed.csv").rename(flume / "bed.csv")
    assert _cli(["run", "--resume", "runs/a", "--end-time", "0.06", *common]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bed.csv" in err and ("missing" in err or "not found" in err), err
    assert _files(run) == before
    (flume / "bed.csv").rename(flume / "cases/bed.csv")
    assert _cli(["run", "--resume", "runs/a", "--end-time", "0.06", *common]) == 0
    assert latest_checkpoint(run).time == pytest.approx(0.06)
    capsys.readouterr()


STL_CUBE = "solid c\n" + "".join(
    "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {x} {y} {z}\n" for x, y, z in f) + "endloop\nendfacet\n"
    for f in [((0, 0, 0), (0, .1, 0), (.1, .1, 0)), ((0, 0, 0), (.1, .1, 0), (.1, 0, 0)),
              ((0, 0, .1), (.1, 0, .1), (.1, .1, .1)), ((0, 0, .1), (.1, .1, .1), (0, .1, .1)),
              ((0, 0, 0), (.1, 0, 0), (.1, 0, .1)), ((0, 0, 0), (.1, 0, .1), (0, 0, .1)),
              ((.1, 0, 0), (.1, .1, 0), (.1, .1, .1)), ((.1, 0, 0), (.1, .1, .1), (.1, 0, .1)),
              ((.1, .1, 0), (0, .1, 0), (0, .1, .1)), ((.1, .1, 0), (0, .1, .1), (.1, .1, .1)),
              ((0, .1, 0), (0, 0, 0), (0, 0, .1)), ((0, .1, 0), (0, 0, .1), (0, .1, .1))]) + "endsolid c\n"


@pytest.mark.parametrize("kind,name,table", [
    ("bathymetry-csv", "data/bed.csv", '[[solids]]\nname = "bed"\nshape = {{ type = "bathymetry", file = "{f}", '
                                       'base = -0.3 }}\n'),
    ("bathymetry-npz", "data/bed.npz", '[[solids]]\nname = "bed"\nshape = {{ type = "bathymetry", file = "{f}", '
                                       'base = -0.3 }}\n'),
    ("stl-mesh", "data/rock.stl", '[[solids]]\nname = "rock"\nshape = {{ type = "mesh", file = "{f}" }}\n'),
    ("time-series", "data/paddle.csv", '[[motions]]\ntype = "time_series"\nname = "p"\nfile = "{f}"\n\n'
                                       '[[solids]]\nname = "paddle"\nmotion = "p"\n'
                                       'shape = {{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.3, 0.3] }}\n'),
    ("dot-dot-path", "../shared/bed.csv", '[[solids]]\nname = "bed"\nshape = {{ type = "bathymetry", '
                                          'file = "{f}", base = -0.3 }}\n'),
])
def test_data_paths_are_relative_to_the_case_file_and_stay_the_same_file(kind, name, table, tmp_path, monkeypatch):
    """Each kind of data file, named relative to its case file (a sibling folder, a parent's): loaded
    from another folder, the case reads that file; its resolved case (what a run writes), copied to a
    third folder and loaded from a fourth, still names the same file, with the same SHA-256."""
    import io

    from shoal.casefile import dumps_case, load_case

    case_dir = tmp_path / "project" / "cases"
    data = (case_dir / name).resolve()
    case_dir.mkdir(parents=True)
    data.parent.mkdir(parents=True, exist_ok=True)
    if name.endswith(".npz"):
        buf = io.BytesIO()
        np.savez(buf, x=np.array([0.0, 1.0]), y=np.array([0.0, 1.0]), z=np.array([[-0.1, -0.1], [0.0, 0.0]]))
        data.write_bytes(buf.getvalue())
    elif name.endswith(".stl"):
        data.write_text(STL_CUBE)
    elif "paddle" in name:
        data.write_text("t,x\n0,0\n0.1,0.001\n")
    else:
        data.write_text("x,y,z\n0,0,-0.1\n1,0,0\n0,1,-0.1\n1,1,0\n")
    text = ('name = "c"\ndim = 3\ndp = 0.05\nend_time = 0.1\n\n[fluid]\ndepth = 0.2\n\n'
            '[[fluids]]\nshape = { type = "box", lo = [0.0, 0.0, 0.0], hi = [1.0, 0.3, 0.2] }\n\n'
            + table.format(f=name))
    (case_dir / "c.toml").write_text(text)
    (tmp_path / "a").mkdir()
    monkeypatch.chdir(tmp_path / "a")
    case = load_case("../project/cases/c.toml")
    files = case.data_files()
    assert list(files) == [str(data)] and files[str(data)] is not None, (kind, files)
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "case.toml").write_text(dumps_case(case, commented=False))
    (tmp_path / "c").mkdir()
    monkeypatch.chdir(tmp_path / "c")
    assert load_case("../b/case.toml").data_files() == files
