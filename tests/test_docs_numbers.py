"""Numbers shown in the README and the user guide (`docs/`) come from the data files that hold them
(`benchmarks/results/tables/`), through `benchmarks/readme_tables.py`: each table must be shown on a page, each
page's copy must be the one its data file gives, and each row must name where its values were read: raw
outputs that are in the repository, or the record of a measurement whose raw output was not kept (its
command, and the notes file that holds the figures as they were written down)."""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _tables():
    spec = importlib.util.spec_from_file_location("readme_tables", ROOT / "benchmarks" / "readme_tables.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


MOD = _tables()


def _pages_showing(name):
    return [p for p in MOD.pages() if name in MOD.shown(p.read_text())]


@pytest.mark.parametrize("name", MOD.names())
def test_table_is_its_data_file(name):
    pages = _pages_showing(name)
    assert pages, f"no page (README.md, docs/**/*.md) shows table {name}"
    data = MOD.load(name)
    for page in pages:
        shown = MOD.block(page.read_text(), name)
        assert shown is not None, f"{page.relative_to(ROOT)} lost the end marker of table {name}"
        assert shown == MOD.table(data), f"{page.relative_to(ROOT)}: run python benchmarks/readme_tables.py --write"
    for row in data["rows"]:
        assert len(row["values"]) == len(data["columns"]), row["measure"]
        for f in row["from"]:
            if isinstance(f, str):  # a raw output kept in the repository
                assert (MOD.RESULTS / f).is_file(), f
                continue
            if "validation" in f:  # a validation case's entry in the committed report
                assert (MOD.ROOT / f["validation"]).is_file(), f
                assert f["case"] in data["validation_cases"], f
                continue
            # a measurement whose raw output was not kept: its command, and the figures where first written down
            assert f.get("command"), (row["measure"], f)
            record = MOD.RESULTS / f["recorded_in"]
            assert record.is_file(), f["recorded_in"]
            text = record.read_text().replace("**", "")
            for value in row["values"]:
                assert value.replace("**", "") in text, (row["measure"], value, f["recorded_in"])


def test_every_shown_table_has_data():
    for page in MOD.pages():
        for name in MOD.shown(page.read_text()):
            assert name in MOD.names(), f"{page.relative_to(ROOT)} shows table {name} with no data file"


def test_validation_table_rows_are_the_committed_report(tmp_path, monkeypatch):
    """A table naming validation cases shows each judged figure of their entries in the report's results.json
    (value, tolerance, verdict as the report prints them, and the run), and says so when a case is not there."""
    import json

    entry = dict(case="heave-decay", status="run", mode="full", resolution="dp = 0.01 m", measured="2026-12-07",
                 commit="0123456789abcdef0123456789abcdef01234567", dirty=False,
                 metrics=[dict(name="period | error", value=-0.0123, tolerance=0.1, unit="%"),
                          dict(name="for information", value=0.5, tolerance=None, unit="%"),
                          dict(name="drift", value=0.2, tolerance=0.1, unit="dp")])
    results = tmp_path / "results.json"
    results.write_text(json.dumps([entry]))
    monkeypatch.setattr(MOD, "VALIDATION", results)
    rows = MOD.validation_rows(["heave-decay", "roll-decay"])
    assert [r["values"][:3] for r in rows] == [["-1.23 %", "10.00 %", "PASS"], ["0.2 dp", "0.1 dp", "FAIL"],
                                               ["not in the committed report", "-", "-"]]
    assert rows[0]["measure"] == "`heave-decay`: period \\| error"
    assert rows[0]["values"][3] == "full, dp = 0.01 m; 2026-12-07, `0123456`"
    assert rows[2]["values"][3] == "`shoal validate roll-decay`"


def test_there_are_tables():
    assert {"wall_choice", "riemann"} <= set(MOD.names())


def test_pages_include_the_guide():
    pages = {p.relative_to(ROOT).as_posix() for p in MOD.pages()}
    assert "README.md" in pages and "docs/index.md" in pages
    assert not any("_build" in p for p in pages)


def test_check_catches_a_changed_figure(tmp_path, monkeypatch):
    """--check fails on a page whose table differs from its data, and --write puts the data back."""
    page = tmp_path / "page.md"
    t = MOD.table(MOD.load("wall_choice"))
    begin, end = MOD.markers("wall_choice")
    page.write_text(f"x\n{begin}\n{t.replace('0.50', '0.51', 1)}{end}\ny\n")
    monkeypatch.setattr(MOD, "pages", lambda: [page])
    assert MOD.main(["--check"]) == 1  # riemann is shown nowhere, and wall_choice differs
    page.write_text(page.read_text() + f"{MOD.markers('riemann')[0]}\n{MOD.markers('riemann')[1]}\n")
    for name in MOD.names():
        if name not in ("wall_choice", "riemann"):
            page.write_text(page.read_text() + f"{MOD.markers(name)[0]}\n{MOD.markers(name)[1]}\n")
    assert MOD.main(["--write"]) == 0
    assert MOD.block(page.read_text(), "wall_choice") == t
    assert MOD.main(["--check"]) == 0
