"""The code of the README and the user guide runs (issue 29): every fenced block marked runnable.

A block is marked by the line ``<!-- runnable -->`` right above its fence (an HTML comment: nothing
shows in the rendered page). The Python blocks of one page run in order, in one namespace, in a
temporary directory that holds what the pages refer to: ``my-flume.toml`` (written by ``shoal new``'s
wave flume) and ``runs/flume`` (a run of it stopped after two steps, so it can be resumed). Every
time loop is cut to two steps (`Simulation.run`), so a block's calls, names and arguments are checked,
not its physics (the tests of the physics do that). A TOML block marked runnable is a whole case file:
it loads, validates and generates its particles (`shoal check`).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
MARK = "<!-- runnable -->"
FENCE = re.compile(r"^```(\w+)\s*$")


def runnable_blocks(path):
    """[(language, first line number, code)] of the blocks marked runnable in `path`."""
    lines = path.read_text().splitlines()
    out = []
    for k, line in enumerate(lines):
        m = FENCE.match(line)
        if not m or k == 0 or lines[k - 1].strip() != MARK:
            continue
        end = next(j for j in range(k + 1, len(lines)) if lines[j].startswith("```"))
        out.append((m.group(1), k + 2, "\n".join(lines[k + 1:end]) + "\n"))
    return out


def test_marked_blocks_are_found():
    """The pages that teach the Python API and the case files mark their examples."""
    found = {p.relative_to(ROOT).as_posix(): runnable_blocks(p) for p in PAGES}
    assert [lang for lang, _, _ in found["README.md"]] == ["python"]
    assert len([b for b in found["docs/python.md"] if b[0] == "python"]) >= 5
    assert [lang for lang, _, _ in found["docs/cases.md"]][:1] == ["toml"]


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A folder with ``my-flume.toml`` and a resumable ``runs/flume`` in it; the time loops cut to two
    steps while the blocks run."""
    import shoal
    from shoal.simulation import Simulation

    d = tmp_path_factory.mktemp("docs")
    run = Simulation.run

    def two_steps(self, max_steps=None):
        return run(self, max_steps=2 if max_steps is None else min(max_steps, 2))

    Simulation.run = two_steps
    old = os.getcwd()
    os.chdir(d)
    try:
        case = shoal.cases.wave_flume_2d(dp=0.05, end_time=1.0)
        shoal.write_case(case, "my-flume.toml")
        shoal.run_case(case, "runs/flume", plot=False)
        yield d
    finally:
        os.chdir(old)
        Simulation.run = run


@pytest.mark.parametrize("page", [p for p in PAGES if any(lang == "python" for lang, _, _ in runnable_blocks(p))],
                         ids=lambda p: p.relative_to(ROOT).as_posix())
def test_python_blocks_run(page, workdir, tmp_path, monkeypatch):
    import shutil

    shutil.copytree(workdir, tmp_path / "page")
    monkeypatch.chdir(tmp_path / "page")
    namespace = {"__name__": "__docs__"}
    for lang, line, code in runnable_blocks(page):
        if lang != "python":
            continue
        try:
            exec(compile(code, f"{page.name}:{line}", "exec"), namespace)
        except Exception as err:  # noqa: BLE001 -- the message names the page and line
            pytest.fail(f"{page.relative_to(ROOT)}, the block at line {line}: {type(err).__name__}: {err}")


@pytest.mark.parametrize("page", [p for p in PAGES if any(lang == "toml" for lang, _, _ in runnable_blocks(p))],
                         ids=lambda p: p.relative_to(ROOT).as_posix())
def test_toml_blocks_are_valid_cases(page, tmp_path):
    from shoal.check import check_case
    from shoal.casefile import load_case

    for lang, line, code in runnable_blocks(page):
        if lang != "toml":
            continue
        path = tmp_path / f"{page.stem}_{line}.toml"
        path.write_text(code)
        lines = check_case(load_case(path))
        assert any("particles:" in x for x in lines), (page.name, line)
