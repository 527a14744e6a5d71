"""Sphinx configuration of shoal's user guide (MyST Markdown pages; `tests/test_docs_build.py` builds it)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))  # autodoc imports the checkout's shoal, installed or not

project = "shoal"
author = "the shoal developers"
copyright = "the shoal developers"

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown"}
exclude_patterns = ["_build"]
root_doc = "index"

myst_heading_anchors = 3

autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_numpy_docstring = True
napoleon_google_docstring = False

html_theme = "alabaster"
html_title = "shoal"


def _anchors(app):
    """`validation/REPORT.md` (included by validation.md) marks each case with an HTML anchor,
    ``<a id="case"></a>``, and links to it as ``[case](#case)``: make each such anchor a docutils
    target, so that the links resolve (and Sphinx writes the id) instead of warning."""
    import re

    from docutils import nodes
    from docutils.transforms import Transform

    anchor = re.compile(r'^<a id="([A-Za-z0-9_.-]+)">$')

    class RawAnchors(Transform):
        default_priority = 250  # before docutils' PropagateTargets and MyST's anchor resolution

        def apply(self):
            for raw in list(self.document.findall(nodes.raw)):
                m = anchor.match(raw.astext().strip()) if raw.get("format") == "html" else None
                if not m or m.group(1) in self.document.ids:
                    continue
                close = raw.next_node(descend=False, siblings=True)
                if isinstance(close, nodes.raw) and close.astext().strip() == "</a>":
                    close.parent.remove(close)
                target = nodes.target("", "", ids=[m.group(1)])
                self.document.ids[m.group(1)] = target
                para = raw.parent
                if isinstance(para, nodes.paragraph) and len(para.children) == 1:
                    para.replace_self(target)  # the anchor was a paragraph of its own
                else:
                    raw.replace_self(target)

    app.add_transform(RawAnchors)


def _repository_files(app):
    """A link from a page to a Markdown file of the repository outside `docs/` (a validation case's README,
    `validation/REPORT.md`, a results folder's README) is a link to that file, as it is on GitHub: MyST takes
    any ``.md`` link for a page of the guide, so turn those that name no page into a download of the file."""
    import os
    from pathlib import Path

    from sphinx import addnodes
    from sphinx.transforms import SphinxTransform

    class RepositoryFiles(SphinxTransform):
        default_priority = 500

        def apply(self):
            here = Path(self.env.doc2path(self.env.docname)).parent
            for ref in list(self.document.findall(addnodes.pending_xref)):
                if ref.get("reftype") != "myst" or ref.get("refdomain") != "doc":
                    continue
                if ref["reftarget"] in self.env.found_docs:
                    continue
                target = Path(self.env.srcdir, ref["reftarget"] + ".md").resolve()
                if not target.is_file():
                    continue  # MyST's own warning stands
                link = addnodes.download_reference(
                    "", "", refdoc=ref["refdoc"], reftype="myst", refdomain=None,
                    refexplicit=ref.get("refexplicit", False), reftarget=os.path.relpath(target, here))
                link.extend(ref.children)
                link.source, link.line = ref.source, ref.line
                ref.replace_self(link)

    app.add_transform(RepositoryFiles)


def _short_signatures(app, what, name, obj, options, signature, return_annotation):
    """A case's pydantic models take every field as a keyword: show the names, not the defaults' reprs."""
    try:
        from pydantic import BaseModel
    except ImportError:
        return None
    if what == "class" and isinstance(obj, type) and issubclass(obj, BaseModel):
        return "(*, " + ", ".join(obj.model_fields) + ")", None
    return None


def _plain_bars(app, what, name, obj, options, lines):
    """Docstrings write |x| for an absolute value or a norm, which reStructuredText reads as a
    substitution: escape the bars, except on a table's rows (a line that starts and ends with one)."""
    import re

    for k, line in enumerate(lines):
        text = line.strip()
        if not (text.startswith("|") and text.endswith("|") and len(text) > 1):
            lines[k] = re.sub(r"(?<!\\)\|", r"\\|", line)


def setup(app):
    app.connect("autodoc-process-docstring", _plain_bars)
    _anchors(app)
    _repository_files(app)
    app.connect("autodoc-process-signature", _short_signatures)
