"""The tables of measured figures in README.md and the user guide (`docs/`), generated from the data files in
`results/tables/`.

Each `results/tables/NAME.json` holds a table: its ``columns`` (with optional ``column_names`` to show,
and ``measure_name``, the first column's heading), its ``rows`` and an ``about`` line. A row has a
``measure``, one value per column, and ``from``: where its values were read. An entry of ``from`` is either
a raw benchmark output kept in the repository (a path relative to `results/`), or, for figures whose raw
output was not kept, the record of the measurement: an object with the ``command`` that made it (and the
``commit`` and ``date`` when they are known) and ``recorded_in``, the file under `results/` that holds the
figures as they were first written down (`results/notes/README.md`).

A data file may instead name validation cases (``validation_cases``, a list of case names): its rows are then
the judged figures of those cases in the committed validation report's `validation/results.json` (what
`shoal validate --out validation` writes), each with its tolerance, verdict, mode and the commit it was measured
on, so that a page's validation figures are the report's.

A page shows table NAME between the markers ``<!-- table NAME -->`` and ``<!-- end table NAME -->``, each on a
line of its own (a marker quoted inside a line is text); the pages are README.md and every Markdown file under
`docs/` (not a build's output).

    python benchmarks/readme_tables.py            # print every table (markdown)
    python benchmarks/readme_tables.py --write    # put them into the pages, between their markers
    python benchmarks/readme_tables.py --check    # exit 1 if a page's table differs from its data

(`tests/test_docs_numbers.py` runs the check.)
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"
TABLES = RESULTS / "tables"
README = ROOT / "README.md"
DOCS = ROOT / "docs"
VALIDATION = ROOT / "validation" / "results.json"

BEGIN = re.compile(r"^<!-- table (\S+) -->$", re.M)


def markers(name):
    return f"<!-- table {name} -->", f"<!-- end table {name} -->"


def load(name):
    d = json.loads((TABLES / f"{name}.json").read_text())
    if "validation_cases" in d:
        d = dict(d, rows=validation_rows(d["validation_cases"]))
    return d


def validation_rows(cases):
    """The rows of the judged figures (a tolerance given) of validation `cases`, in that order, from the
    committed report's entries (`VALIDATION`): measured, tolerance, verdict, and the run (mode, resolution,
    date and commit). A case not in the report has one row saying so and how to run it."""
    from shoal.validation.core import Metric

    entries = {e["case"]: e for e in json.loads(VALIDATION.read_text())}
    rows = []
    for case in cases:
        source = [dict(validation=rel(VALIDATION), case=case)]
        e = entries.get(case)
        if e is None or e.get("status") != "run":
            rows.append(dict(measure=f"`{case}`", values=["not in the committed report", "-", "-",
                                                          f"`shoal validate {case}`"], **{"from": source}))
            continue
        run = f"{e['mode']}, {e['resolution']}; {e.get('measured') or 'date not recorded'}" + \
            (f", `{e['commit'][:7]}`" if e.get("commit") else "") + (" (uncommitted changes)" if e.get("dirty") else "")
        for m in e["metrics"]:
            metric = Metric(**m)
            if metric.tolerance is None:
                continue
            rows.append(dict(measure=f"`{case}`: {_cell(metric.name)}",
                             values=[metric.value_text, metric.tolerance_text.replace("<= ", ""), metric.verdict,
                                     _cell(run)], **{"from": source}))
    return rows


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def names():
    return sorted(p.stem for p in TABLES.glob("*.json"))


def pages():
    """The files that may show tables: README.md and the guide's Markdown pages."""
    docs = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.relative_to(DOCS).parts)
    return [README] + docs


def shown(text):
    """The names of the tables whose begin marker `text` holds."""
    return BEGIN.findall(text)


def table(d):
    """The markdown table of one data file's content `d`."""
    shown = d.get("column_names", d["columns"])
    lines = [f"| {d.get('measure_name', 'measured')} | " + " | ".join(shown) + " |", "|---|" + "---|" * len(shown)]
    for row in d["rows"]:
        lines.append(f"| {row['measure']} | " + " | ".join(row["values"]) + " |")
    return "\n".join(lines) + "\n"


def _split(text, marker):
    """(before, after) the first line of `text` that is `marker`, or None."""
    m = re.search(rf"^{re.escape(marker)}$", text, re.M)
    return None if m is None else (text[:m.start()], text[m.end():])


def block(text, name):
    """The text between the markers of table `name` in `text`, or None."""
    begin, end = markers(name)
    head = _split(text, begin)
    tail = None if head is None else _split(head[1], end)
    if tail is None:
        return None
    return tail[0].strip("\n") + "\n"


readme_block = block  # the name it had when only README.md held tables


def replace(text, name, t):
    """`text` with table `name`'s block replaced by `t` (every occurrence)."""
    begin, end = markers(name)
    out = []
    while (cut := _split(text, begin)) is not None:
        head, rest = cut
        tail = _split(rest, end)
        if tail is None:
            raise ValueError(f"{begin} has no {end}")
        out.append(f"{head}{begin}\n{t}{end}")
        text = tail[1]
    return "".join(out) + text


def rel(path):
    try:
        return path.relative_to(ROOT).as_posix()
    except ValueError:
        return str(path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true", help="write the tables into their pages")
    g.add_argument("--check", action="store_true", help="exit 1 if a page's table is not its data's")
    a = ap.parse_args(argv)
    known = names()
    if not (a.write or a.check):
        for name in known:
            print(f"{name}:\n{table(load(name))}")
        return 0
    tables = {name: table(load(name)) for name in known}
    where = {name: [] for name in known}
    problems = []
    for page in pages():
        text = page.read_text()
        new = text
        for name in dict.fromkeys(shown(text)):
            if name not in tables:
                problems.append(f"{rel(page)} shows table {name}, which has no data file {rel(TABLES)}/{name}.json")
                continue
            where[name].append(page)
            if a.write:
                try:
                    new = replace(new, name, tables[name])
                except ValueError as e:
                    problems.append(f"{rel(page)}: {e}")
            elif block(text, name) != tables[name]:
                problems.append(f"{rel(page)}: table {name} differs from {rel(TABLES)}/{name}.json")
        if a.write and new != text:
            page.write_text(new)
    for name, found in where.items():
        if not found:
            problems.append(f"table {name} is shown on no page (README.md, docs/**/*.md): add its markers "
                            f"{markers(name)[0]} {markers(name)[1]}")
    if problems:
        print("\n".join(problems), file=sys.stderr)
        if a.check:
            print("run python benchmarks/readme_tables.py --write", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
