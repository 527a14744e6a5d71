"""The committed validation report is a pure function of ``validation/results.json``.

``validation/REPORT.md`` rebuilds byte for byte from ``validation/results.json`` (nothing of the machine
or the moment of rendering goes into it), and every entry records the commit and the UTC date it was
measured at; a fresh ``shoal validate`` stamps its entries with the checkout's commit (and whether the
source had changes not committed), a merge keeps them.
"""

import datetime
import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from shoal.validation import CaseResult, Metric, ValidationCase, run_validation
from shoal.validation.core import source_state
from shoal.validation.report import merge_reports, rebuild_report, write_report

ROOT = Path(__file__).resolve().parents[1]
VALIDATION = ROOT / "validation"
HEX40 = re.compile(r"^[0-9a-f]{40}$")


@pytest.fixture
def committed_case_folders(monkeypatch):
    """The report mentions which `validation/<case>/README.md` exist: read the repository's."""
    monkeypatch.setenv("SHOAL_VALIDATION_DIR", str(VALIDATION))


def test_committed_report_rebuilds_byte_identical(tmp_path, committed_case_folders):
    md = rebuild_report(VALIDATION / "results.json", tmp_path)
    assert md == tmp_path / "REPORT.md"
    assert md.read_bytes() == (VALIDATION / "REPORT.md").read_bytes(), (
        "validation/REPORT.md is not what validation/results.json renders to: rebuild it with "
        "python -c 'from shoal.validation.report import rebuild_report; rebuild_report(\"validation\")'")
    # rendering again (another folder, another moment) gives the same bytes
    again = rebuild_report(VALIDATION / "results.json", tmp_path / "again")
    assert again.read_bytes() == md.read_bytes()


def test_committed_html_copy_is_of_the_same_entries(committed_case_folders):
    """REPORT.html is rendered from the same Markdown (its exact bytes depend on markdown-it's version,
    so this checks that it is not stale: each entry's commit and verdict are in it)."""
    html = (VALIDATION / "REPORT.html").read_text()
    for e in json.loads((VALIDATION / "results.json").read_text()):
        assert f"<code>{e['commit']}</code>" in html, e["case"]
        assert f'id="{e["case"]}"' in html


def _git_date(commit):
    """The UTC committer date of `commit` in this repository, or None (no git, not a checkout, shallow)."""
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "show", "-s", "--format=%cI", commit],
                             capture_output=True, text=True, timeout=30)
    except OSError:
        return None
    if out.returncode != 0 or not out.stdout.strip():
        return None
    return datetime.datetime.fromisoformat(out.stdout.strip()).astimezone(datetime.timezone.utc).date()


def test_every_committed_entry_records_its_commit_and_date():
    entries = json.loads((VALIDATION / "results.json").read_text())
    assert entries
    for e in entries:
        assert isinstance(e.get("commit"), str) and HEX40.match(e["commit"]), e["case"]
        measured = datetime.date.fromisoformat(e["measured"])
        assert e.get("dirty") in (True, False, None), e["case"]
        committed = _git_date(e["commit"])
        if committed is not None:  # a run at a commit ends after the commit was made
            assert measured >= committed, (e["case"], e["commit"], e["measured"])


def _stamped(folder, case="hydrostatic", commit="a" * 40, measured="2026-01-02", value=0.01):
    r = CaseResult(case=case, title=case, quick=True, out=folder / "figures", setup="s", reference="r",
                   tolerance="t", resolution="dp = 1", particles="10", run_seconds=12.5, commit=commit,
                   measured=measured, dirty=False, machine="2 CPU cores, Python 3.11.7")
    r.metrics = [Metric("max error", value, 0.02)]
    r.passed = r.metrics[0].passed
    r.figures = [folder / "figures" / f"{case}.png"]
    return r


def test_write_report_renders_only_what_results_json_holds(tmp_path, committed_case_folders):
    write_report([_stamped(tmp_path / "a")], tmp_path / "a", quick=False, backend="cuda", seconds=999.0,
                 command="shoal validate --anything")
    md = (tmp_path / "a" / "REPORT.md").read_text()
    assert "shoal validate --anything" not in md and "cuda" not in md  # from the entries, not the call
    assert "Backend cpu, quick resolutions; 12 s of runs in all" in md
    assert "| 2026-01-02, `aaaaaaa` |" in md
    assert f"**Measured:** 2026-01-02 at commit `{'a' * 40}` (2 CPU cores, Python 3.11.7)." in md
    assert "![hydrostatic](figures/hydrostatic.png)" in md
    shutil.copy(tmp_path / "a" / "results.json", tmp_path / "copy.json")
    rebuilt = rebuild_report(tmp_path / "copy.json", tmp_path / "b")
    assert rebuilt.read_bytes() == (tmp_path / "a" / "REPORT.md").read_bytes()
    assert (tmp_path / "b" / "REPORT.html").read_bytes() == (tmp_path / "a" / "REPORT.html").read_bytes()


def test_an_entry_without_a_stamp_says_so(tmp_path, committed_case_folders):
    r = _stamped(tmp_path, commit=None, measured=None)
    r.dirty, r.machine, r.commit_note = None, "", "shoal 0.1 is not imported from a git checkout"
    write_report([r], tmp_path)
    assert json.loads((tmp_path / "results.json").read_text())[0]["commit"] is None
    md = (tmp_path / "REPORT.md").read_text()
    assert "| not recorded |" in md
    assert ("**Measured:** date not recorded, commit not recorded; shoal 0.1 is not imported from a git "
            "checkout.") in md


def test_a_merge_keeps_each_entry_its_own_stamp(tmp_path, committed_case_folders):
    write_report([_stamped(tmp_path / "base"), _stamped(tmp_path / "base", "poiseuille", "b" * 40)],
                 tmp_path / "base")
    write_report([_stamped(tmp_path / "new", "poiseuille", "c" * 40, "2026-02-03", value=0.015)], tmp_path / "new")
    merge_reports([tmp_path / "new"], tmp_path / "base")
    entries = {e["case"]: e for e in json.loads((tmp_path / "base" / "results.json").read_text())}
    assert (entries["hydrostatic"]["commit"], entries["hydrostatic"]["measured"]) == ("a" * 40, "2026-01-02")
    assert (entries["poiseuille"]["commit"], entries["poiseuille"]["measured"]) == ("c" * 40, "2026-02-03")


def test_a_merge_brings_the_figures_each_entry_names(tmp_path, committed_case_folders):
    """A merged entry's figures come with it, also one whose name is not the case's (sluice-gate draws
    sluice_gate.png), and the files named after the case; nothing else of the source folder."""
    new = _stamped(tmp_path / "new", "poiseuille", "c" * 40)
    new.figures = [tmp_path / "new" / "figures" / "poiseuille_profile.png", tmp_path / "new" / "figures" / "p.png"]
    write_report([new], tmp_path / "new")
    (tmp_path / "new" / "figures").mkdir(parents=True, exist_ok=True)
    for name in ("poiseuille_profile.png", "p.png", "poiseuille_data.csv", "other.png"):
        (tmp_path / "new" / "figures" / name).write_bytes(b"x")
    write_report([_stamped(tmp_path / "base")], tmp_path / "base")
    merge_reports([tmp_path / "new"], tmp_path / "base")
    got = sorted(f.name for f in (tmp_path / "base" / "figures").iterdir())
    assert {"poiseuille_profile.png", "p.png", "poiseuille_data.csv"} <= set(got) and "other.png" not in got


class _Instant(ValidationCase):
    name, title, cost = "instant", "a case that measures nothing", 0.0

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        res.metrics = [Metric("nothing", 0.0, 0.1)]
        return res

    def compare(self, result):
        return [], True


class _OwnStamp(_Instant):
    name = "own-stamp"

    def run(self, quick, backend, out):
        res = super().run(quick, backend, out)
        res.commit, res.measured, res.commit_note = "d" * 40, "2025-05-05", "the long run's own"
        return res


def test_run_validation_stamps_every_entry(tmp_path, monkeypatch):
    import shoal.validation as v

    monkeypatch.setattr(v, "source_state", lambda: ("e" * 40, True, ""))
    before = datetime.datetime.now(datetime.timezone.utc).date()
    run_validation([_Instant(), _OwnStamp()], out=tmp_path, log=None)
    after = datetime.datetime.now(datetime.timezone.utc).date()
    fresh, own = json.loads((tmp_path / "results.json").read_text())
    assert fresh["commit"] == "e" * 40 and fresh["dirty"] is True and "CPU cores" in fresh["machine"]
    assert before <= datetime.date.fromisoformat(fresh["measured"]) <= after
    assert (own["commit"], own["measured"], own["commit_note"]) == ("d" * 40, "2025-05-05", "the long run's own")
    assert "(uncommitted changes)" in (tmp_path / "REPORT.md").read_text()


def _git(root, *args):
    subprocess.run(["git", "-C", str(root), "-c", "user.name=t", "-c", "user.email=t@example.invalid",
                    "-c", "commit.gpgsign=false", *args], check=True, capture_output=True, timeout=30)


def test_source_state_reads_the_checkout(tmp_path):
    if shutil.which("git") is None:
        pytest.skip("git is not installed")
    root = tmp_path / "repo"
    (root / "src").mkdir(parents=True)
    (root / "validation").mkdir()
    (root / "src" / "m.py").write_text("x = 1\n")
    (root / "validation" / "REPORT.md").write_text("old\n")
    _git(root, "init", "-q")
    _git(root, "add", ".")
    _git(root, "commit", "-q", "-m", "first")
    commit, dirty, note = source_state(root)
    assert HEX40.match(commit) and dirty is False and note == ""
    (root / "validation" / "REPORT.md").write_text("rewritten by the run\n")  # the report's own output
    (root / "notes.txt").write_text("an untracked file outside src/\n")
    assert source_state(root) == (commit, False, "")
    (root / "src" / "new.py").write_text("y = 2\n")  # untracked source
    assert source_state(root) == (commit, True, "")
    (root / "src" / "new.py").unlink()
    (root / "src" / "m.py").write_text("x = 2\n")  # a tracked source changed
    assert source_state(root) == (commit, True, "")
    (tmp_path / "not-a-repo").mkdir()
    none_commit, none_dirty, why = source_state(tmp_path / "not-a-repo")
    assert none_commit is None and none_dirty is None and "git" in why
