"""``shoal validate``: run the validation cases, compare with reference data, write a report.

    from shoal.validation import run_validation, get_cases
    results = run_validation(get_cases(["hydrostatic", "poiseuille"]), quick=True, out="runs/validate")

Each case (`VALIDATION_CASES`) is a `ValidationCase` with ``run(quick, backend, out)`` and
``compare(result)``; a case can be given with its own tolerance, e.g. ``Hydrostatic(tolerance=0.01)``.
A case whose run or comparison raises is reported as FAIL with the error, not as a crash. The
report (``REPORT.md``, ``REPORT.html``, ``results.json`` and the PNGs in ``figures/``) is written to
`out`; ``shoal validate --quick --out validation`` regenerates the committed ``validation/REPORT.md``.
Reference data and each case's README (set-up, reference with its source, tolerance with its
justification) are in the repository's ``validation/<case>/`` folders.
"""

from __future__ import annotations

import time
import traceback
from pathlib import Path

from .active_absorption import ActiveAbsorptionCase
from .archimedes import Archimedes
from .bores import TidalBores, UndularAmplitude
from .bridge_piers import BridgePiers
from .core import (CaseResult, Metric, PendingCase, ValidationCase, find_validation_dir, machine_text, source_state,
                   utc_date)
from .dam_break import DamBreak2D
from .flap import FlapWaves
from .floating_waves import FloatingBoxWaves
from .focused_wave import FocusedWave
from .heave_decay import HeaveDecay
from .hydrostatic import Hydrostatic
from .periodic_runup import PeriodicRunup
from .poiseuille import Poiseuille
from .registry import VALIDATION_CASES, get_cases
from .resolution import ResolutionStudy
from .rip_current import RipCurrent
from .roll_decay import RollDecay
from .ship_section_decay import ShipSectionDecay
from .ship_section_waves import ShipSectionWaves
from .sluice_gate import SluiceGate
from .spheric_test2 import SphericTest2
from .wall_impact import WallImpact
from .wave_flume import WaveFlume
from .weir import BroadCrestedWeir

__all__ = ["VALIDATION_CASES", "get_cases", "run_validation", "ValidationCase", "CaseResult", "Metric",
           "Hydrostatic", "DamBreak2D", "Poiseuille", "TidalBores", "UndularAmplitude", "RipCurrent",
           "ResolutionStudy", "SphericTest2", "BridgePiers", "WaveFlume", "PeriodicRunup", "ActiveAbsorptionCase",
           "FlapWaves", "FocusedWave", "HeaveDecay", "RollDecay",
           "ShipSectionDecay", "FloatingBoxWaves", "ShipSectionWaves",
           "Archimedes", "SluiceGate", "BroadCrestedWeir", "WallImpact",
           "PendingCase", "find_validation_dir", "default_quick_set"]

QUICK_SET_LIMIT = 600.0
"""A case whose quick run takes longer than this [s] (its `cost`) is left out of the default quick set
(``shoal validate`` without case names), so that the set fits in about 15 minutes on 2 cores; naming
it runs it."""

QUICK_SET_BUDGET = 900.0
"""The default quick set's time [s] on 2 cores: it takes the cases in report order while their costs add up
to no more than this (`default_quick_set`); the others are named to run."""


def default_quick_set(cases):
    """The names of the `cases` that ``shoal validate`` runs in quick mode without case names: in report order,
    each whose `cost` is at most `QUICK_SET_LIMIT` while the sum stays within `QUICK_SET_BUDGET` (a case only
    run with ``--full`` counts nothing)."""
    chosen, total = set(), 0.0
    for case in cases:
        if case.full_only:
            chosen.add(case.name)
        elif case.cost <= QUICK_SET_LIMIT and total + case.cost <= QUICK_SET_BUDGET:
            chosen.add(case.name)
            total += case.cost
    return chosen


def run_validation(cases=None, quick=True, backend="cpu", out="runs/validate", log=print, command=None):
    """Run `cases`, compare each with its reference and write the report to `out`.

    Parameters
    ----------
    cases : list of ValidationCase or str, optional
        The cases (instances, or names of `VALIDATION_CASES`); default all, but in quick mode those
        outside `default_quick_set` (a quick run longer than `QUICK_SET_LIMIT`, or past the set's
        `QUICK_SET_BUDGET`) are reported "not run" (name them to run them).
    quick : bool
        The quick resolutions (the default set fits in about 15 minutes on 2 cores) or the full ones.
    backend : {"cpu", "cuda"}
    out : path
        Folder for ``REPORT.md``, ``REPORT.html``, ``results.json`` and ``figures/``.
    log : callable or None
        Called with one line per case as it starts and ends.
    command : str, optional
        The command line (accepted for the CLI; the report is rendered from ``results.json`` alone,
        which does not hold it).

    Returns
    -------
    list of CaseResult
        One per case, in order, each with its metrics, figures and verdict, and where and when it
        was measured: ``commit`` and ``dirty`` (`shoal.validation.core.source_state` of the source,
        taken once as the session starts), ``measured`` (the UTC date each case's entry was
        completed) and ``machine``. A case that sets ``commit`` or ``measured`` itself keeps its own.
    """
    from .report import write_report

    default_set = cases is None
    cases = get_cases(None) if cases is None else [get_cases([c])[0] if isinstance(c, str) else c for c in cases]
    in_set = default_quick_set(cases) if default_set else {c.name for c in cases}
    out = Path(out)
    fig_dir = out / "figures"
    log = log or (lambda *_: None)
    mode = "quick" if quick else "full"
    results = []
    commit, dirty, commit_note = source_state()
    machine = machine_text()

    def stamp(res):
        if res.commit is None and res.measured is None:
            res.commit, res.dirty, res.commit_note = commit, dirty, commit_note
            res.measured, res.machine = utc_date(), machine

    for case in cases:
        log(f"shoal validate: {case.name} ({mode}) ...")
        t0 = time.perf_counter()
        if quick and case.name not in in_set:
            res = CaseResult(case=case.name, title=case.title, quick=quick, backend=backend, out=fig_dir,
                             setup=case.setup, reference=case.reference, tolerance=case.tolerance_text)
            res.status = "not run"
            why = (f"its quick run takes about {case.cost / 60:.0f} min on 2 cores" if case.cost > QUICK_SET_LIMIT
                   else f"the cases before it take the set's {QUICK_SET_BUDGET / 60:.0f} min")
            res.reason = f"not in the default quick set ({why}): `shoal validate {case.name}` runs it"
            log(f"shoal validate: {case.name}: {res.verdict} ({res.reason})")
            stamp(res)
            results.append(res)
            continue
        try:
            res = case.run(quick, backend, fig_dir)
        except KeyboardInterrupt:
            raise
        except Exception as err:  # a crashed run is a FAIL in the report, with its reason
            res = CaseResult(case=case.name, title=case.title, quick=quick, backend=backend, out=fig_dir,
                             setup=case.setup, reference=case.reference, tolerance=case.tolerance_text)
            res.status, res.reason = "failed", f"the run raised {type(err).__name__}: {err}"
            res.notes.append(_last_frame(err))
            res.run_seconds = time.perf_counter() - t0
        if res.status == "run":
            res.run_notes = len(res.notes)  # the notes after these are the comparison's
            try:
                figs, passed = case.compare(res)
                res.figures, res.passed = list(figs), bool(passed) if passed is not None else None
            except KeyboardInterrupt:
                raise
            except Exception as err:
                res.status, res.reason = "failed", f"the comparison raised {type(err).__name__}: {err}"
                res.notes.append(_last_frame(err))
        if res.passed is False and not res.reason:
            bad = [m.name for m in res.metrics if m.passed is False]
            res.reason = "outside the tolerance: " + "; ".join(bad)
        log(f"shoal validate: {case.name}: {res.verdict}" + (f" ({res.reason})" if res.reason else "")
            + f" [{time.perf_counter() - t0:.0f} s]")
        stamp(res)
        results.append(res)
    write_report(results, out)
    return results


def _last_frame(err):
    tb = traceback.extract_tb(err.__traceback__)
    if not tb:
        return ""
    f = tb[-1]
    return f"raised at {Path(f.filename).name}:{f.lineno} ({f.name})"
