"""``shoal validate``: the two cheapest cases end to end, so the command cannot rot.

Runs ``shoal validate hydrostatic poiseuille --quick`` (about a minute on 2 cores) and checks the
report: REPORT.md, REPORT.html, results.json and one comparison PNG per case exist; each case has an
error figure with its tolerance and a PASS/FAIL line. Through the Python API, an impossible tolerance
gives FAIL with the reason, and a case whose run raises is a FAIL in the report, not a crash. Bad
input (an unknown case, --quick with --full) is one line and exit status 2.
"""

import json
import re

import pytest

from shoal.cli import main
from shoal.validation import Hydrostatic, Poiseuille, ValidationCase, get_cases, run_validation
from shoal.validation.report import write_report


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("validate")
    rc = main(["validate", "hydrostatic", "poiseuille", "--quick", "--out", str(out)])
    return rc, out


def test_validate_quick_writes_the_report(quick_report):
    rc, out = quick_report
    assert rc == 0
    md = (out / "REPORT.md").read_text()
    html = (out / "REPORT.html").read_text()
    assert "<table>" in html and "<img" in html
    results = {r["case"]: r for r in json.loads((out / "results.json").read_text())}
    assert set(results) == {"hydrostatic", "poiseuille"}
    for name in ("hydrostatic", "poiseuille"):
        r = results[name]
        assert r["verdict"] == "PASS", r
        judged = [m for m in r["metrics"] if m["tolerance"] is not None]
        assert judged and all(m["value"] is not None and m["passed"] for m in judged)
        png = out / "figures" / f"{name}.png"
        assert png.is_file() and 0 < png.stat().st_size < 100_000
        assert f"![{name}](figures/{name}.png)" in md
        section = md.split(f"## {name}:")[1].split("\n## ")[0]
        assert re.search(r"\| max .* \| \d+\.\d+ % \| <= \d+\.\d+ % \| PASS \|", section), section
        assert "**Result: PASS**" in section
        assert "**Resolution:**" in section and "**particles:**" in section and "**run time:**" in section
    # the stated errors are the measured ones
    assert results["poiseuille"]["metrics"][0]["value"] < 0.03
    assert results["hydrostatic"]["metrics"][0]["value"] < 0.02


class _Crashes(ValidationCase):
    name, title, cost = "crashes", "a case whose run raises", 0.0

    def run(self, quick, backend, out):
        raise RuntimeError("deliberate failure")


def test_impossible_tolerance_is_a_fail_not_a_crash(tmp_path):
    results = run_validation([Poiseuille(tolerance=1e-9), _Crashes()], quick=True, out=tmp_path, log=None)
    poi, crash = results
    assert poi.verdict == "FAIL" and poi.passed is False and poi.status == "run"
    assert "outside the tolerance" in poi.reason and poi.metrics[0].passed is False
    assert poi.figures and poi.figures[0].is_file()
    assert crash.verdict == "FAIL" and "RuntimeError: deliberate failure" in crash.reason
    md = (tmp_path / "REPORT.md").read_text()
    assert "**Result: FAIL** — outside the tolerance" in md
    assert "**Result: FAIL** — the run raised RuntimeError: deliberate failure" in md


def test_a_case_not_built_yet_and_a_missing_long_run_are_reported(tmp_path, monkeypatch):
    monkeypatch.setenv("SHOAL_VALIDATION_DIR", str(tmp_path / "empty"))
    results = run_validation(["spheric-test2", "rip-current"], quick=True, out=tmp_path, log=None)
    assert [r.verdict for r in results] == ["not yet", "not run"]
    md = (tmp_path / "REPORT.md").read_text()
    assert "**Result: not run**" in md and "not yet in this slice" in md


def test_rip_current_entry_reads_results_json(tmp_path, monkeypatch):
    folder = tmp_path / "v" / "rip-current"
    folder.mkdir(parents=True)
    (folder / "results.json").write_text(json.dumps({
        "run": {"dp": 0.075}, "setup_grid_mm": {"crest_bar_minus_channel": 1.5},
        "channel_current": {"U_mean_m_s": -0.02},
        "checks": {"setup_bar_above_channel_at_crest_grid": True, "channel_current_offshore": True,
                   "two_counter_rotating_cells": False}}))
    monkeypatch.setenv("SHOAL_VALIDATION_DIR", str(tmp_path / "v"))
    (res,) = run_validation(["rip-current"], quick=True, out=tmp_path / "out", log=None)
    assert res.status == "run" and res.verdict == "FAIL"
    assert "two counter-rotating circulation cells" in res.reason


def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path):
    assert main(["validate", "no-such-case", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("shoal: error: unknown validation case 'no-such-case'") and err.count("\n") == 1
    assert main(["validate", "--quick", "--full"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("shoal: error:") and "--full" in err and err.count("\n") == 1
    assert not (tmp_path / "REPORT.md").exists()


def test_every_case_is_listed_and_cheapest_two_are_the_ci_ones():
    names = [c.name for c in get_cases()]
    assert names[:2] == ["hydrostatic", "poiseuille"]
    for n in ("dam-break-2d", "tidal-bores", "undular-bore-amplitude", "resolution-study", "rip-current"):
        assert n in names
    ran = sorted((c for c in get_cases() if c.cost > 0), key=lambda c: c.cost)
    assert {c.name for c in ran[:2]} == {"hydrostatic", "poiseuille"}
    assert isinstance(get_cases(["hydrostatic"])[0], Hydrostatic)


def test_report_of_no_cases_is_still_written(tmp_path):
    write_report([], tmp_path, quick=True, backend="cpu", seconds=0.0)
    assert (tmp_path / "REPORT.md").is_file() and (tmp_path / "REPORT.html").is_file()
