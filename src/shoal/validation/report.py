"""The validation report: ``REPORT.md``, its HTML copy and ``results.json``.

The report is a function of the entries of ``results.json`` alone (and of which case folders
``validation/<case>/`` hold a README): `write_report` writes ``results.json`` first and renders the
report from that file (`rebuild_report`), so the committed ``validation/REPORT.md`` rebuilds byte
for byte from ``validation/results.json`` (``tests/test_report_rebuild.py`` checks it). Nothing of the
machine or the moment of rendering goes into it: where and when each case was measured (its commit,
date and machine) is part of its entry (`shoal.validation.core.CaseResult`).

Markdown is turned into HTML with markdown-it-py (already installed with shoal: rich depends on it).
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path

from ..errors import InputError
from .core import find_validation_dir

CSS = ("body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;line-height:1.4}"
       "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .5em;"
       "text-align:left;vertical-align:top}img{max-width:100%}code{background:#f3f3f3}")


def _seconds(s):
    if s is None or not math.isfinite(s):
        return "-"
    return f"{s:.0f} s" if s < 120 else f"{s / 60:.1f} min"


def _run_time(r):
    if r.status not in ("run", "failed"):
        return "-"
    return _seconds(r.run_seconds) + (" (runs shared)" if r.shared else "")


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def _error_summary(res):
    """The case's judged errors in percent (the other judged figures when there are none)."""
    judged = [m for m in res.metrics if m.passed is not None and m.tolerance is not None and m.unit == "%"] or \
        [m for m in res.metrics if m.passed is not None and m.tolerance is not None]
    if not judged:
        return "; ".join(f"{m.name}: {'yes' if m.passed else 'no'}" for m in res.metrics if m.passed is not None) \
            or (res.reason if res.status != "run" else "-")
    return "; ".join(f"{m.value_text} (tol. {m.tolerance_text.replace('<= ', '')})" for m in judged[:3]) + \
        (" ..." if len(judged) > 3 else "")


def _measured_cell(r):
    """Where and when an entry was measured, short: "2026-12-05, `16512ce`"."""
    if not r.commit:
        return f"{r.measured}, commit not recorded" if r.measured else "not recorded"
    return f"{r.measured or 'date not recorded'}, `{r.commit[:7]}`" + (" (uncommitted changes)" if r.dirty else "")


def _measured_line(r):
    """The entry's "Measured" line: date, full commit, machine and the note on the commit."""
    text = f"**Measured:** {r.measured or 'date not recorded'}"
    if r.commit:
        text += f" at commit `{r.commit}`" + (", with changes not committed" if r.dirty else "")
    else:
        text += ", commit not recorded"
    if r.machine:
        text += f" ({r.machine})"
    return text + (f"; {r.commit_note}" if r.commit_note else "") + "."


def render_markdown(results):
    """The report of the entries `results` as Markdown text.

    A function of the entries alone (their fields as ``results.json`` holds them) and of which
    ``validation/<case>/README.md`` exist: the header's mode, backends and total run time are taken
    from the entries; figures are linked as ``figures/<name>`` (the report lives beside its
    ``figures/`` folder).
    """
    ran = [r for r in results if r.status in ("run", "failed")]
    modes = {bool(r.quick) for r in ran} or {bool(r.quick) for r in results}
    mode = "quick and full" if len(modes) > 1 else {True: "quick", False: "full"}[modes.pop()] if modes else "no"
    backends = ", ".join(sorted({r.backend for r in ran})) or "-"
    seconds = sum(r.run_seconds for r in ran if not r.shared and math.isfinite(r.run_seconds))
    counts = {}
    for r in results:
        counts[r.verdict] = counts.get(r.verdict, 0) + 1
    vdir = find_validation_dir()
    lines = [
        "# shoal validation report",
        "",
        "Rendered by `shoal validate` from the entries of the `results.json` beside it and nothing else "
        "(`shoal validate --report-only --out DIR` merges saved entries into it; "
        "`shoal.validation.report.rebuild_report(DIR)` renders it again from them, byte for byte). "
        f"Backend {backends}, {mode} resolutions; {_seconds(seconds)} of runs in all. Each case gives the "
        "commit and the date it was measured at.",
        "",
        "Summary: " + ", ".join(f"{v}: {n}" for v, n in counts.items()) + ". Each case's set-up, reference "
        f"data (with its source) and tolerance (with its justification) are also in `validation/<case>/README.md`.",
        "",
        "| case | resolution | particles | run time | error (tolerance) | result | measured |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in results:
        res_text = r.resolution or "-"
        if len(modes) > 1 and r.status in ("run", "failed"):  # quick and full entries: each case's own mode
            res_text = f"{'quick' if r.quick else 'full'}: {res_text}"
        lines.append(f"| [{r.case}](#{r.case}) | {_cell(res_text)} | {_cell(r.particles or '-')} | "
                     f"{_run_time(r)} | "
                     f"{_cell(_error_summary(r))} | **{r.verdict}** | {_cell(_measured_cell(r))} |")
    lines.append("")
    for r in results:
        lines += [f'<a id="{r.case}"></a>', "", f"## {r.case}: {r.title}", ""]
        if r.status == "not yet":
            lines += [f"**{r.verdict}**: {r.reason}.", ""]
            continue
        lines += [f"**Set-up.** {r.setup}", "", f"**Reference.** {r.reference}", "",
                  f"**Tolerance.** {r.tolerance}", ""]
        if (vdir / r.case / "README.md").is_file():
            lines += [f"Case folder: `validation/{r.case}/`.", ""]
        if r.status == "not run":
            lines += [f"**Result: not run** — {r.reason}.", ""]
            continue
        lines += [f"**Resolution:** {r.resolution or '-'}; **particles:** {r.particles or '-'}; "
                  f"**run time:** {_run_time(r)} ({r.backend}).", "", _measured_line(r), ""]
        if r.metrics:
            lines += ["| compared | error | tolerance | result | note |", "|---|---|---|---|---|"]
            for m in r.metrics:
                lines.append(f"| {_cell(m.name)} | {m.value_text} | {m.tolerance_text} | {m.verdict} | "
                             f"{_cell(m.note)} |")
            lines.append("")
        for f in r.figures:
            lines += [f"![{r.case}](figures/{Path(f).name})", ""]
        verdict = f"**Result: {r.verdict}**"
        if r.verdict == "FAIL":
            verdict += f" — {r.reason}" if r.reason else ""
        lines += [verdict, ""]
        for n in r.notes:
            if n:
                lines += [f"- {n}"]
        if r.notes:
            lines.append("")
    lines += ["## Closing note: each case's error", ""]
    for r in results:
        lines.append(f"- `{r.case}`: {r.verdict}" + (f" — {_error_summary(r)}" if r.status == "run" else
                                                      f" — {r.reason}" if r.reason else ""))
    lines.append("")
    return "\n".join(lines)


def markdown_to_html(text, title="shoal validation report"):
    """A standalone HTML page of the Markdown `text` (tables enabled)."""
    from markdown_it import MarkdownIt

    body = MarkdownIt("commonmark", {"html": True}).enable("table").render(text)
    return (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{CSS}</style></head><body>\n{body}</body></html>\n")


def _num(v):
    return None if isinstance(v, float) and not math.isfinite(v) else v


def _jsonable(results):
    out = []
    for r in results:
        out.append({
            "case": r.case, "title": r.title, "mode": "quick" if r.quick else "full", "backend": r.backend,
            "commit": r.commit, "measured": r.measured, "dirty": r.dirty, "commit_note": r.commit_note,
            "machine": r.machine,
            "status": r.status, "verdict": r.verdict, "reason": r.reason, "resolution": r.resolution,
            "particles": r.particles, "run_seconds": _num(r.run_seconds), "shared": r.shared,
            "setup": r.setup, "reference": r.reference, "tolerance": r.tolerance,
            "metrics": [{"name": m.name, "value": _num(m.value), "tolerance": m.tolerance, "unit": m.unit,
                         "passed": m.passed, "note": m.note, "lower": m.lower} for m in r.metrics],
            "figures": [Path(f).name for f in r.figures], "notes": r.notes, "run_notes": r.run_notes,
        })
    return out


def write_report(results, out, quick=None, backend=None, seconds=None, command=None):
    """Write ``results.json``, then ``REPORT.md`` and ``REPORT.html`` rendered from it, to `out`.

    The report is rendered from the file just written (`rebuild_report`), so it holds nothing the
    file does not. `quick`, `backend`, `seconds` and `command` are accepted from older callers and
    not used: the header's mode, backends and run time come from the entries. Returns the Markdown
    path.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(_jsonable(results), indent=2, default=float) + "\n")
    return rebuild_report(out / "results.json", out)


def rebuild_report(source, out=None):
    """Render ``REPORT.md`` and ``REPORT.html`` from a saved ``results.json`` alone; return the Markdown path.

    `source` is the ``results.json`` (or its folder); `out` the folder to write to (default: the
    source's). Nothing is run or compared again (unlike `merge_reports`) and no figure is touched:
    the same file gives the same report, byte for byte, on any machine and at any time (given the
    same ``validation/<case>/README.md`` files, whose presence the report mentions).
    """
    source = Path(source)
    if source.is_dir():
        source = source / "results.json"
    out = Path(out) if out is not None else source.parent
    out.mkdir(parents=True, exist_ok=True)
    text = render_markdown(results_from_json(source))
    md = out / "REPORT.md"
    md.write_text(text)
    (out / "REPORT.html").write_text(markdown_to_html(text))
    return md


# ------------------------------------------------------------------ a report from saved results
def results_from_json(path):
    """The `CaseResult` entries of a ``results.json`` written by `write_report`.

    Figures are resolved in the ``figures/`` folder beside the file. Older files lack the set-up,
    reference and tolerance texts and the "shared" flag: the texts are then taken from the case of
    that name (`shoal.validation.VALIDATION_CASES`), and "shared" from the notes (a run reused from
    another case says so). An entry without ``commit`` / ``measured`` (written before they were
    recorded) keeps None: the report says "not recorded".
    """
    from .core import CaseResult, Metric
    from .registry import VALIDATION_CASES

    path = Path(path)
    try:
        entries = json.loads(path.read_text())
    except (OSError, ValueError) as err:
        raise InputError(f"{path}: cannot read the saved results ({err})") from None
    if not isinstance(entries, list):
        raise InputError(f"{path}: not a shoal validate results.json (expected a list of cases)")
    out = []
    for e in entries:
        if not isinstance(e, dict) or "case" not in e:
            raise InputError(f"{path}: an entry without a case name")
        case = VALIDATION_CASES.get(e["case"])
        metrics = [Metric(m["name"], math.nan if m.get("value") is None else m["value"], m.get("tolerance"),
                          unit=m.get("unit", "%"), passed=m.get("passed"), note=m.get("note", ""),
                          lower=m.get("lower")) for m in e.get("metrics", [])]
        notes = list(e.get("notes", []))
        shared = e.get("shared")
        if shared is None:
            shared = any("shared" in n or "reused" in n for n in notes)
        r = CaseResult(case=e["case"], title=e.get("title", ""), quick=e.get("mode", "quick") == "quick",
                       backend=e.get("backend", "cpu"), out=path.parent / "figures",
                       setup=e.get("setup") or getattr(case, "setup", ""),
                       reference=e.get("reference") or getattr(case, "reference", ""),
                       tolerance=e.get("tolerance") or getattr(case, "tolerance_text", ""),
                       resolution=e.get("resolution", ""), particles=e.get("particles", ""),
                       run_seconds=math.nan if e.get("run_seconds") is None else e["run_seconds"],
                       shared=bool(shared), metrics=metrics,
                       figures=[path.parent / "figures" / f for f in e.get("figures", [])],
                       passed={"PASS": True, "FAIL": False}.get(e.get("verdict")), status=e.get("status", "run"),
                       reason=e.get("reason", ""), notes=notes, run_notes=e.get("run_notes"),
                       commit=e.get("commit"), measured=e.get("measured"), dirty=e.get("dirty"),
                       commit_note=e.get("commit_note") or "", machine=e.get("machine") or "")
        out.append(r)
    return out


def _compare_again(r):
    """Re-run the comparison of a saved entry from its saved records, where its case can load them."""
    from .registry import VALIDATION_CASES

    case = VALIDATION_CASES.get(r.case)
    if r.status != "run" or case is None or not hasattr(case, "load_saved"):
        return
    try:
        data = case.load_saved(r.out)
    except (OSError, ValueError, KeyError) as err:  # a damaged record: keep the saved comparison
        r.notes.append(f"the saved records could not be read again ({type(err).__name__}: {err}); the saved "
                       "comparison is shown")
        return
    if data is None:
        return
    saved = {k: v for k, v in (r.data or {}).items()}
    r.data = {**saved, **data}
    r.metrics, r.reason = [], ""
    # the comparison writes its notes again: keep the run's only (older files do not say which they are:
    # their repeated notes are dropped after the comparison)
    if r.run_notes is not None:
        r.notes = r.notes[:r.run_notes]
    before = len(r.notes)
    figs, passed = case.compare(r)
    fresh = r.notes[before:]
    kept = [n for n in dict.fromkeys(r.notes[:before]) if n not in fresh]
    r.notes, r.run_notes = kept + fresh, len(kept)
    r.figures, r.passed = list(figs), bool(passed) if passed is not None else None
    if r.passed is False:
        r.reason = "outside the tolerance: " + "; ".join(m.name for m in r.metrics if m.passed is False)


def merge_reports(sources, out, cases=None, command=None):
    """Rebuild the report in `out` from saved results, without running anything.

    The entries of ``out/results.json`` (if any) are taken first, then those of each folder in
    `sources` (each holding a ``results.json`` and its ``figures/``), an entry replacing the one of
    the same case; `cases` (names) restricts what is taken from `sources`. Figures and the saved
    records of a case (the files in ``figures/`` whose names start with the case name) are copied
    into ``out/figures/``. A case that saves its simulated records (a ``load_saved(folder)`` method,
    e.g. `bridge-piers`, `spheric-test2`) is compared again from them with the current comparison
    and tolerance. The cases are written in the order of `VALIDATION_CASES`. Each entry keeps the
    commit and date of its run (``commit``, ``measured``; a comparison made again does not change
    them); an entry saved as "not yet" whose case is built since becomes "not run", stamped with
    this checkout's commit and today's date. `command` is accepted from the CLI and not used (the
    report is rendered from ``results.json`` alone: `write_report`).

    Returns
    -------
    list of CaseResult
        The merged entries, in report order.
    """
    import shutil

    from .registry import VALIDATION_CASES

    out = Path(out)
    merged = {}
    if (out / "results.json").is_file():
        for r in results_from_json(out / "results.json"):
            _compare_again(r)
            merged[r.case] = r
    for src in sources or []:
        src = Path(src)
        if not (src / "results.json").is_file():
            raise InputError(f"--from {src}: no results.json there (a folder written by shoal validate --out)")
        for r in results_from_json(src / "results.json"):
            if cases and r.case not in cases:
                continue
            if src.resolve() != out.resolve():
                (out / "figures").mkdir(parents=True, exist_ok=True)
                # its figures by name (a case's may not start with its name: sluice-gate's sluice_gate.png) and
                # the files named after the case (the data behind a figure)
                named = {Path(f).name for f in r.figures}
                for f in sorted((src / "figures").iterdir()) if (src / "figures").is_dir() else []:
                    if f.name in named or f.name.startswith(r.case):
                        shutil.copy2(f, out / "figures" / f.name)
                r.figures = [out / "figures" / Path(f).name for f in r.figures]
                r.out = out / "figures"
            _compare_again(r)
            merged[r.case] = r
    from .core import PendingCase, machine_text, source_state, utc_date

    for r in merged.values():  # saved before its case was built: now a case without a saved result
        case = VALIDATION_CASES.get(r.case)
        if r.status == "not yet" and case is not None and not isinstance(case, PendingCase):
            r.status = "not run"
            r.title = case.title
            r.setup, r.reference, r.tolerance = case.setup, case.reference, case.tolerance_text
            r.reason = (f"no saved result yet (run `shoal validate {r.case}`, then merge it with "
                        "`shoal validate --report-only --from DIR`)")
            r.commit, r.dirty, r.commit_note = source_state()
            r.measured, r.machine = utc_date(), machine_text()
    if not merged:
        where = ", ".join(str(s) for s in sources or []) or f"{out} (no results.json)"
        raise InputError(f"nothing to merge: no saved result{' of ' + ', '.join(cases) if cases else ''} in {where}; "
                         "run `shoal validate --out DIR` first, then merge with `--from DIR`")
    order = list(VALIDATION_CASES)
    results = sorted(merged.values(), key=lambda r: (order.index(r.case) if r.case in order else len(order)))
    write_report(results, out)
    return results
