"""Numbers shown in the README come from the data files that hold them (`benchmarks/results/tables/`),
through `benchmarks/readme_tables.py`: each table must be the one the README shows, and each row must
name raw outputs that are in the repository."""

import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _tables():
    spec = importlib.util.spec_from_file_location("readme_tables", ROOT / "benchmarks" / "readme_tables.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


MOD = _tables()


@pytest.mark.parametrize("name", MOD.names())
def test_readme_table_is_its_data_file(name):
    shown = MOD.readme_block((ROOT / "README.md").read_text(), name)
    assert shown is not None, f"README.md lost the markers of table {name}"
    data = MOD.load(name)
    assert shown == MOD.table(data), "run python benchmarks/readme_tables.py --write"
    for row in data["rows"]:
        assert len(row["values"]) == len(data["columns"]), row["measure"]
        for f in row["from"]:
            assert (MOD.RESULTS / f).is_file(), f


def test_there_are_tables():
    assert "wall_choice" in MOD.names()
