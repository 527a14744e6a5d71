"""The user guide in `docs/` builds without a warning (Sphinx, MyST Markdown pages, autodoc of the public API),
and every link of the README and the guide that points into the repository reaches a file that is there."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def pages():
    """README.md, the guide's Markdown pages (not a build's output) and the measurement notes they point to."""
    guide = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.relative_to(DOCS).parts)
    return [ROOT / "README.md"] + guide + [ROOT / "benchmarks" / "results" / "notes" / "README.md"]


def test_docs_build_without_warnings(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    out = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-q",
                          "-d", str(tmp_path / "doctrees"), str(DOCS), str(tmp_path / "html")],
                         capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
    assert (tmp_path / "html" / "index.html").is_file()
    assert (tmp_path / "html" / "api.html").is_file()


LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^(```|~~~).*?^\1", re.M | re.S)


def slug(heading):
    """The anchor GitHub (and MyST's `myst_heading_anchors`) give a heading."""
    text = re.sub(r"[`*_]", "", heading.strip()).lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    text = FENCE.sub("", path.read_text())
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6}\s+(.+?)\s*#*$", text, re.M)} | set(
        re.findall(r'<a id="([^"]+)"', text))


def repo_links(text):
    """(file, anchor) of every Markdown link in `text` that points into the repository."""
    text = FENCE.sub("", text)
    text = re.sub(r"`[^`\n]*`", "", text)  # code spans are not links
    for m in LINK.finditer(text):
        target = m.group(1)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # https:, mailto:, ...
            continue
        file, _, anchor = target.partition("#")
        yield file, anchor


@pytest.mark.parametrize("page", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_links_into_the_repository_resolve(page):
    bad = []
    for file, anchor in repo_links(page.read_text()):
        dest = (page.parent / file).resolve() if file else page
        if not dest.exists():
            bad.append(f"{file}: no such file")
        elif not dest.is_relative_to(ROOT):
            bad.append(f"{file}: outside the repository")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            bad.append(f"{file}#{anchor}: no such heading")
    assert not bad, f"{page.relative_to(ROOT)}: " + "; ".join(bad)


def test_link_check_sees_links():
    """The check reads the links it must (a mutation check of the pattern)."""
    sample = "a [b](docs/x.md#y) `[c](d)` ![e](f.png \"t\") [g](https://h)\n```\n[i](j)\n```\n"
    assert list(repo_links(sample)) == [("docs/x.md", "y"), ("f.png", "")]
    assert slug("Which wall for which flow") == "which-wall-for-which-flow"
    assert slug("`shoal validate`: the report") == "shoal-validate-the-report"


PUBLIC = ("shoal", "shoal.geometry", "shoal.motions", "shoal.cases", "shoal.probes", "shoal.analysis",
          "shoal.validation", "shoal.output")
"""The packages whose ``__all__`` is the public API: each name a docstring, each documented."""


def _public_names():
    import importlib
    import inspect

    out = []
    for mod in PUBLIC:
        m = importlib.import_module(mod)
        for name in getattr(m, "__all__", []):
            obj = getattr(m, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                out.append((mod, name, obj))
    return out


def test_every_public_name_has_a_docstring_and_a_place_in_the_api_reference():
    """A public class or function (in a public package's ``__all__``) without a docstring, or missing from
    ``docs/api.md`` (an autodoc directive naming it where it is defined or where it is exported), fails."""
    api = (ROOT / "docs" / "api.md").read_text()
    undocumented, missing = [], []
    for mod, name, obj in _public_names():
        if not (obj.__doc__ or "").strip():
            undocumented.append(f"{mod}.{name}")
        where = {f"{mod}.{name}", f"{obj.__module__}.{obj.__qualname__}"}
        if not any(re.search(rf"::\s+{re.escape(w)}\s*$", api, re.M) for w in where):
            missing.append(f"{mod}.{name}")
    assert not undocumented, "no docstring: " + ", ".join(undocumented)
    assert not missing, "not in docs/api.md: " + ", ".join(missing)
