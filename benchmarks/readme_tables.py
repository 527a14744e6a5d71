"""The README's tables of measured figures, generated from the data files in `results/tables/`.

Each `results/tables/NAME.json` holds a table: its ``columns`` (with optional ``column_names`` to show),
its ``rows`` (a ``measure``, one value per column, and ``from``: the raw benchmark outputs, relative
to `results/`, that the values were read from), and an ``about`` line. The README shows each between
the markers ``<!-- table NAME -->`` and ``<!-- end table NAME -->``.

    python benchmarks/readme_tables.py            # print every table (markdown)
    python benchmarks/readme_tables.py --write    # put them into README.md between their markers
    python benchmarks/readme_tables.py --check    # exit 1 if a README table differs from its data

(`tests/test_docs_numbers.py` runs the check.)
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
TABLES = RESULTS / "tables"
README = HERE.parent / "README.md"


def markers(name):
    return f"<!-- table {name} -->", f"<!-- end table {name} -->"


def load(name):
    return json.loads((TABLES / f"{name}.json").read_text())


def names():
    return sorted(p.stem for p in TABLES.glob("*.json"))


def table(d):
    """The markdown table of one data file's content `d`."""
    shown = d.get("column_names", d["columns"])
    lines = [f"| {d.get('measure_name', 'measured')} | " + " | ".join(shown) + " |", "|---|" + "---|" * len(shown)]
    for row in d["rows"]:
        lines.append(f"| {row['measure']} | " + " | ".join(row["values"]) + " |")
    return "\n".join(lines) + "\n"


def readme_block(text, name):
    """The text between the README's markers of table `name`, or None."""
    begin, end = markers(name)
    if begin not in text or end not in text:
        return None
    return text.split(begin, 1)[1].split(end, 1)[0].strip("\n") + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true", help="write the tables into README.md")
    g.add_argument("--check", action="store_true", help="exit 1 if a README table is not its data's")
    a = ap.parse_args(argv)
    text = README.read_text()
    bad = []
    for name in names():
        t = table(load(name))
        if a.write:
            begin, end = markers(name)
            if begin not in text:
                print(f"README.md has no {begin} marker", file=sys.stderr)
                return 1
            head, rest = text.split(begin, 1)
            text = f"{head}{begin}\n{t}{end}{rest.split(end, 1)[1]}"
        elif a.check:
            if readme_block(text, name) != t:
                bad.append(name)
        else:
            print(f"{name}:\n{t}")
    if a.write:
        README.write_text(text)
    if bad:
        print(f"README.md's tables {', '.join(bad)} differ from benchmarks/results/tables/; "
              "run python benchmarks/readme_tables.py --write", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
