"""``shoal validate``: the two cheapest cases end to end, so the command cannot rot.

Runs ``shoal validate hydrostatic poiseuille --quick`` (about a minute on 2 cores) and checks the
report: REPORT.md, REPORT.html, results.json and one comparison PNG per case exist; each case has an
error figure with its tolerance and a PASS/FAIL line. Through the Python API, an impossible tolerance
gives FAIL with the reason, and a case whose run raises is a FAIL in the report, not a crash. Bad
input (an unknown case, --quick with --full) is one line and exit status 2.
"""

import json
import re

import numpy as np
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


class _Long(ValidationCase):
    name, title, cost = "long", "a case whose quick run takes an hour", 3600.0

    def run(self, quick, backend, out):
        raise AssertionError("the default quick set must not run a long case")


def test_default_quick_set_leaves_long_cases_out_but_a_named_one_runs(tmp_path, monkeypatch):
    """`shoal validate` (no names) must fit in about 15 minutes: a case whose quick run is longer
    than QUICK_SET_LIMIT is reported "not run" with the command that runs it; named, it runs."""
    import shoal.validation as v
    from shoal.validation import registry

    monkeypatch.setattr(registry, "VALIDATION_CASES", {"poiseuille": Poiseuille(), "long": _Long()})
    poi, long = run_validation(None, quick=True, out=tmp_path, log=None)
    assert poi.verdict == "PASS"
    assert long.status == "not run" and "`shoal validate long` runs it" in long.reason
    assert "not in the default quick set" in (tmp_path / "REPORT.md").read_text()
    (named,) = run_validation([_Long()], quick=True, out=tmp_path / "named", log=None)
    assert named.verdict == "FAIL" and "the default quick set must not run a long case" in named.reason
    chosen = v.default_quick_set(registry.all_cases())
    assert sum(c.cost for c in registry.all_cases() if c.name in chosen and not c.full_only) <= 15 * 60
    assert {"hydrostatic", "poiseuille", "dam-break-2d"} <= chosen


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
    from shoal.validation import PendingCase

    monkeypatch.setenv("SHOAL_VALIDATION_DIR", str(tmp_path / "empty"))
    pending = PendingCase("future-case", "A case of a later slice", "not yet in this slice of issue 8")
    results = run_validation([pending, "rip-current", "spheric-test2"], quick=True, out=tmp_path, log=None)
    assert [r.verdict for r in results] == ["not yet", "not run", "not run"]
    assert "full only" in results[2].reason
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


# ------------------------------------------------------------------ the comparisons on synthetic data
def _bore_record(t, x, peak, d0=0.1, d1=0.132):
    """A smooth undular-bore-like level at a gauge x: a front at x / 0.93 s, a first crest `peak`."""
    ta = x / 0.93
    front = 0.5 * (1 + np.tanh((t - ta) / 0.03))
    crest = (peak - d1) * np.exp(-(((t - ta - 0.15) / 0.08) ** 2))
    return d0 + (d1 - d0) * front + crest


def _bridge_result(tmp_path, increase):
    from shoal.validation.bridge_piers import GAUGES, BridgePiers

    case = BridgePiers()
    res = case.new_result(True, "cpu", tmp_path)
    t = np.arange(0, 2.1, 0.01)
    xs = dict(zip(GAUGES, (1.0, 1.4, 1.6)))
    runs = {}
    for label, f in (("no piers", 1.0), ("piers", 1.0 + increase)):
        runs[label] = dict(gauges={g: (x, t, _bore_record(t, x, 0.142 * f)) for g, x in xs.items()},
                           particles=1, fluid=1, steps=10, seconds=1.0, escaped=0)
    res.data = dict(runs=runs, dp=0.02, t_end=2.1)
    return case, res


@pytest.mark.parametrize("increase, passed", [(0.07, True), (0.0, False), (0.30, False), (-0.05, False)])
def test_bridge_piers_comparison_on_synthetic_records(tmp_path, increase, passed):
    case, res = _bridge_result(tmp_path, increase)
    figs, ok = case.compare(res)
    assert ok is passed
    judged = [m for m in res.metrics if m.tolerance is not None]
    assert len(judged) == 3 and all(m.tolerance_text == "in [2.00 %, 15.00 %]" for m in judged)
    for m in judged:  # the peak of the smoothed record, so a little under the synthetic crest ratio
        assert m.value == pytest.approx(increase, abs=0.01)
    assert figs[0].is_file() and figs[0].stat().st_size < 100_000


def test_bridge_piers_full_band_is_narrower():
    from shoal.validation.bridge_piers import BridgePiers

    assert BridgePiers().band(True) == (0.02, 0.15) and BridgePiers().band(False) == (0.03, 0.12)


def test_spheric_height_labels_are_mapped_by_arrival_time():
    from shoal.validation.spheric_test2 import height_label_mapping, load_reference

    t = np.linspace(0, 2, 201)
    step = lambda ta: np.where(t >= ta, 0.1, 0.0)  # noqa: E731
    mapping, _ = height_label_mapping(t, {"A": step(0.9), "B": step(0.35), "C": step(0.2), "D": 0.55 + 0 * t})
    assert mapping == {"D": 2.638, "C": 1.488, "B": 0.992, "A": 0.496}
    ref = load_reference()  # the official file: H1 is the gauge at 1.488 m, H3 the one behind the box
    assert ref["mapping"] == {"H1": 1.488, "H2": 0.992, "H3": 0.496, "H4": 2.638}
    assert ref["arrivals"]["H1"] == pytest.approx(0.194, abs=0.002)


def test_spheric_comparison_on_the_reference_itself_and_a_bad_record(tmp_path):
    from shoal.validation.spheric_test2 import GAUGE_X, SphericTest2, load_reference

    ref = load_reference()
    t = np.arange(0, 4.0 + 1e-9, 0.005)
    case = SphericTest2()

    def result(shift=0.0, scale=1.0):
        res = case.new_result(False, "cpu", tmp_path)
        res.data = dict(gauges={x: (t, scale * np.interp(t - shift, ref["t"], ref["heights"][x]))
                                for x in GAUGE_X.values()},
                        tp=t, pressure={k: scale * np.interp(t - shift, ref["t"], ref["pressure"][k])
                                        for k in ("P1", "P3")}, dp=0.05, end_time=4.0)
        return res

    good = result()
    figs, ok = case.compare(good)
    assert ok, [(m.name, m.value) for m in good.metrics]
    heights = [m for m in good.metrics if m.name.startswith("water height")]
    assert len(heights) == 4 and all(m.value < 0.01 for m in heights)
    time_err, peak_err = (m for m in good.metrics if m.name.startswith("P1"))
    assert abs(time_err.value) <= 0.005 and abs(peak_err.value) < 0.05, (time_err.note, peak_err.note)
    assert figs[0].is_file() and figs[0].stat().st_size < 100_000
    bad = result(shift=0.3, scale=0.4)
    _, ok = case.compare(bad)
    assert not ok
    assert next(m for m in bad.metrics if m.name.startswith("P1: time")).passed is False


def test_report_only_merges_saved_results_without_running(tmp_path, capsys, monkeypatch):
    import shoal.validation
    from shoal.validation import CaseResult, Metric, PendingCase

    monkeypatch.setitem(shoal.validation.VALIDATION_CASES, "future-case",
                        PendingCase("future-case", "A case of a later slice", "not yet"))

    def entry(case, quick, value, folder):
        r = CaseResult(case=case, title=case, quick=quick, out=folder / "figures", setup="s", reference="r",
                       tolerance="t", resolution="dp = 1", run_seconds=10.0)
        r.metrics = [Metric("band", value, 0.15, lower=0.02)]
        r.passed = r.metrics[0].passed
        (folder / "figures").mkdir(parents=True, exist_ok=True)
        png = folder / "figures" / f"{case}.png"
        png.write_bytes(b"png")
        (folder / "figures" / f"{case}_notes.txt").write_text("kept with the figures\n")
        r.figures = [png]
        return r

    base, a, b = tmp_path / "base", tmp_path / "a", tmp_path / "b"
    stale = CaseResult(case="future-case", status="not yet", reason="not yet")  # still pending: kept
    built = CaseResult(case="tidal-bores", status="not yet", reason="not yet")  # built since: not run
    write_report([entry("hydrostatic", True, 0.05, base), entry("bridge-piers", True, 0.0, base), stale, built],
                 base, True, "cpu", 20)
    bp = entry("bridge-piers", True, 0.0, a)  # the saved verdict is stale: the saved records say +7 %
    case, synthetic = _bridge_result(a / "figures", 0.07)
    case._save(synthetic)
    write_report([bp], a, True, "cpu", 10)
    write_report([entry("spheric-test2", False, 0.05, b)], b, False, "cpu", 10)
    assert main(["validate", "--report-only", "--from", str(a), "--from", str(b), "--out", str(base)]) == 0
    merged = {r["case"]: r for r in json.loads((base / "results.json").read_text())}
    assert list(merged) == ["hydrostatic", "tidal-bores", "spheric-test2", "bridge-piers", "future-case"]
    assert merged["future-case"]["verdict"] == "not yet" and merged["tidal-bores"]["verdict"] == "not run"
    assert "no saved result yet" in merged["tidal-bores"]["reason"]
    bpm = merged["bridge-piers"]["metrics"]  # compared again from the saved gauge records
    assert merged["bridge-piers"]["verdict"] == "PASS" and len(bpm) == 4 and bpm[0]["lower"] == 0.02
    assert bpm[0]["value"] == pytest.approx(0.07, abs=0.01)
    assert merged["spheric-test2"]["mode"] == "full" and merged["hydrostatic"]["setup"] == "s"
    assert (base / "figures" / "spheric-test2.png").is_file() and (base / "figures" / "bridge-piers_gauges.csv").is_file()
    assert (base / "figures" / "spheric-test2_notes.txt").is_file()
    md = (base / "REPORT.md").read_text()
    assert "quick and full resolutions" in md and "| full: dp = 1 |" in md and "--report-only" in md
    assert "in [2.00 %, 15.00 %]" in md
    assert main(["validate", "--from", str(a), "--out", str(base)]) == 2
    assert main(["validate", "--report-only", "--from", str(tmp_path / "none"), "--out", str(base)]) == 2
    assert capsys.readouterr().err.count("shoal: error:") == 2


@pytest.mark.parametrize("scale,passed", [(1.0, True), (0.9, False)])
def test_wave_flume_comparison_on_synthetic_records(tmp_path, scale, passed):
    import math

    from shoal.motions import wavenumber
    from shoal.validation.wave_flume import WaveFlume

    case = WaveFlume()
    p = case.params(True)
    T, d, H = p["period"], p["depth"], p["wave_height"]
    k = wavenumber(T, d)
    w, c = 2 * math.pi / T, 2 * math.pi / T / k
    t = np.arange(0.0, 12.0, T / 40)
    records = {x: (t, d + scale * 0.5 * H * np.sin(w * (t - x / c))) for x in (1.0, 2.0, 3.0)}
    res = case.new_result(True, "cpu", tmp_path)
    res.data = dict(records=records, windows={x: (2.0 + x, 2.0 + x + 4 * T) for x in records}, k=k, cg=1.1,
                    steps=1, stroke=0.05, **p)
    figs, ok = case.compare(res)
    assert ok is passed, [(m.name, m.value) for m in res.metrics]
    heights = [m for m in res.metrics if m.name.startswith("wave height")]
    assert len(heights) == 3 and all(abs(m.value - (scale - 1)) < 4e-3 for m in heights)
    assert all(m.passed for m in res.metrics if not m.name.startswith("wave height"))  # period, speed exact
    why = [n for n in res.notes if n.startswith("What the height FAIL says")]
    assert len(why) == (0 if passed else 1) and (passed or "-10.0% at 3 m" in why[0])
    assert figs[0].is_file() and figs[0].stat().st_size < 100_000


@pytest.mark.parametrize("kr,passed", [(0.03, True), (0.08, False)])
def test_wave_flume_reflection_check_on_synthetic_records(tmp_path, kr, passed):
    """The damping zone's reflection coefficient, from the 11-gauge array: K_r = 0.03 passes (tolerance
    0.05), 0.08 fails, each recovered to 1e-4; the incident height is Biesel's to 1e-4."""
    import math

    from shoal.motions import wavenumber
    from shoal.validation.wave_flume import WaveFlume

    case = WaveFlume()
    p = case.params(True)
    T, d, H = p["period"], p["depth"], p["wave_height"]
    k = wavenumber(T, d)
    w = 2 * math.pi / T
    t = np.arange(0.0, 14.0, T / 40)
    xs = [round(1.0 + 0.25 * i, 2) for i in range(11)]
    records = {x: (t, d + 0.5 * H * (np.sin(w * t - k * x) + kr * np.sin(w * t + k * x + 1.0))) for x in xs}
    res = case.new_result(True, "cpu", tmp_path)
    res.data = dict(records=records, windows={x: (2.0 + x, 2.0 + x + 4 * T) for x in (1.0, 2.0, 3.0)}, k=k,
                    cg=1.1, steps=1, stroke=0.05, sep_window=(10.0, 10.0 + 2 * T), **p)
    _, ok = case.compare(res)
    (refl,) = [m for m in res.metrics if m.name.startswith("reflection coefficient")]
    assert refl.value == pytest.approx(kr, abs=1e-4) and refl.passed is passed
    hi = re.search(r"H_I at x = 0 \(extrapolated\) ([+-]\d+\.\d)% of Biesel's", " ".join(res.notes))
    assert hi and abs(float(hi.group(1))) < 0.05  # +0.0 % or -0.0 %: the sign of a round-off


def test_report_only_twice_writes_each_comparison_note_once(tmp_path):
    """Each `--report-only` compares a saved case again, and the comparison writes its notes again: the
    report keeps the run's notes and one copy of the comparison's (a file from before the run's notes
    were counted loses its repeated copies too)."""
    from shoal.validation.report import merge_reports
    from shoal.validation.spheric_test2 import GAUGE_X, SphericTest2, load_reference

    ref = load_reference()
    t = np.arange(0, 4.0 + 1e-9, 0.005)
    case = SphericTest2()
    res = case.new_result(False, "cpu", tmp_path / "figures")
    late = lambda f: 0.5 * np.interp(t - 0.3, ref["t"], f)  # noqa: E731 - a late, low flow: FAIL notes
    res.data = dict(gauges={x: (t, late(ref["heights"][x])) for x in GAUGE_X.values()}, tp=t,
                    pressure={k: late(ref["pressure"][k]) for k in ("P1", "P3")}, dp=0.05, end_time=4.0)
    case._save(res)
    res.notes.append("a note of the run")
    res.run_notes = 1
    figs, res.passed = case.compare(res)
    res.figures = figs
    write_report([res], tmp_path, False, "cpu", 10)
    compare_notes = res.notes[1:]
    assert res.passed is False and len(compare_notes) == 2  # what the height and the P1 FAILs say
    for _ in range(2):
        assert merge_reports([], tmp_path)[0].notes == ["a note of the run"] + compare_notes
    saved = json.loads((tmp_path / "results.json").read_text())
    saved[0].pop("run_notes")  # an older results.json: the copies are told apart by their text
    saved[0]["notes"] = saved[0]["notes"] + compare_notes
    (tmp_path / "results.json").write_text(json.dumps(saved))
    assert merge_reports([], tmp_path)[0].notes == ["a note of the run"] + compare_notes
    assert (tmp_path / "REPORT.md").read_text().count(compare_notes[0]) == 1
