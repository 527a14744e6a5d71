"""The pieces every validation case shares: results, metrics, the case base class, figures.

A validation case is a small class with two methods:

* ``run(quick, backend, out) -> CaseResult``: run the simulations (the quick or the full
  resolutions) and keep what the comparison needs in ``result.data``;
* ``compare(result) -> (figures, passed)``: compare with the reference, record each error as a
  `Metric` (value, tolerance, pass/fail) on the result and draw the comparison plot(s) into
  ``result.out``.

`shoal.validation.run_validation` calls both for each case, catches a case that crashes (its
entry then says FAIL and why) and writes the report (`shoal.validation.report`).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

MAX_PNG_BYTES = 100_000
"""Comparison plots are kept under this size (they are committed with the report)."""


@dataclass
class Metric:
    """One compared quantity: its error, the tolerance and whether it passes.

    Parameters
    ----------
    name : str
        What is compared, e.g. "front, mean relative error vs Martin & Moyce, 0.8 <= T <= 3".
    value : float
        The measured error (in `unit`); NaN if it could not be measured.
    tolerance : float or None
        The largest error that passes (same unit); None for a figure shown for information.
    unit : str
        "%" (value and tolerance are fractions, printed as percent) or a unit name.
    passed : bool or None
        Set from `value` and `tolerance` unless given (None: not judged).
    note : str
        A short remark printed with the line (the reference value, a reason).
    lower : float or None
        With `lower`, the metric is a band: it passes when lower <= value <= tolerance (signed), e.g.
        an increase that must lie between 2 and 15 %.
    """

    name: str
    value: float
    tolerance: float | None = None
    unit: str = "%"
    passed: bool | None = None
    note: str = ""
    lower: float | None = None

    def __post_init__(self):
        if self.passed is None and self.tolerance is not None:
            if self.lower is not None:
                self.passed = bool(math.isfinite(self.value) and self.lower <= self.value <= self.tolerance)
            else:
                self.passed = bool(math.isfinite(self.value) and abs(self.value) <= self.tolerance)

    def fmt(self, v, signed=False):
        """`v` in the metric's unit, for the report."""
        if v is None or not math.isfinite(v):
            return "n/a"
        if self.unit == "%":
            return f"{100 * v:+.2f} %" if signed else f"{100 * v:.2f} %"
        return f"{v:+.4g} {self.unit}" if signed else f"{v:.4g} {self.unit}"

    @property
    def value_text(self):
        return self.fmt(self.value, signed=self.value < 0)

    @property
    def tolerance_text(self):
        if self.tolerance is not None and self.lower is not None:
            return f"in [{self.fmt(self.lower)}, {self.fmt(self.tolerance)}]"
        return "-" if self.tolerance is None else "<= " + self.fmt(self.tolerance)

    @property
    def verdict(self):
        return {True: "PASS", False: "FAIL", None: "-"}[self.passed]


@dataclass
class CaseResult:
    """What a validation case's run produced, and (after `compare`) how it compares.

    ``status`` is "run" (simulated, compared), "failed" (the run or the comparison raised:
    ``reason`` says what), "not run" (e.g. a long run whose results are not there) or
    "not yet" (the case is not built in this slice). ``shared``: some of its runs were made (and
    timed) by another case of the same session; ``run_seconds`` then counts them too.

    Where and when it was measured (written to ``results.json`` and shown in the report): ``commit``,
    the 40-hex git commit of the shoal source the run used (None where it is not known: then
    ``commit_note`` says why); ``dirty``, whether that source had changes not committed (None:
    not known, e.g. an entry backfilled from git history); ``measured``, the UTC date (ISO,
    ``YYYY-MM-DD``) the run ended; ``machine``, e.g. "2 CPU cores, Python 3.11.7". See
    `source_state`; `shoal.validation.run_validation` fills them.
    """

    case: str
    title: str = ""
    quick: bool = True
    backend: str = "cpu"
    out: Path | None = None
    setup: str = ""
    reference: str = ""
    tolerance: str = ""
    resolution: str = ""
    particles: str = ""
    run_seconds: float = 0.0
    shared: bool = False
    data: dict = field(default_factory=dict)
    metrics: list = field(default_factory=list)
    figures: list = field(default_factory=list)
    passed: bool | None = None
    status: str = "run"
    reason: str = ""
    notes: list = field(default_factory=list)
    run_notes: int | None = None
    commit: str | None = None
    measured: str | None = None
    dirty: bool | None = None
    commit_note: str = ""
    machine: str = ""

    @property
    def verdict(self):
        if self.status == "failed":
            return "FAIL"
        if self.status in ("not run", "not yet"):
            return self.status
        return {True: "PASS", False: "FAIL", None: "-"}[self.passed]


class ValidationCase:
    """Base class of a validation case (subclasses set the class attributes and the two methods).

    Attributes
    ----------
    name : str
        Command-line name (``shoal validate NAME``) and the folder ``validation/NAME/``.
    title : str
        Heading in the report.
    setup, reference, tolerance_text : str
        Markdown for the report: the set-up, the reference data (with its source) and the
        tolerance with its justification.
    cost : float
        Rough quick-mode run time on 2 cores [s] (the CI test picks the cheapest; over
        `QUICK_SET_LIMIT`, the case is left out of the default quick set).
    full_only : bool
        The case runs only with ``--full`` (its quick mode reports "not run" with the reason).
    """

    name = ""
    title = ""
    setup = ""
    reference = ""
    tolerance_text = ""
    cost = 60.0
    full_only = False

    def new_result(self, quick, backend, out):
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        return CaseResult(case=self.name, title=self.title, quick=quick, backend=backend, out=out,
                          setup=self.setup, reference=self.reference, tolerance=self.tolerance_text)

    def run(self, quick, backend, out):  # pragma: no cover - interface
        """Run the case; return a `CaseResult` holding what `compare` needs."""
        raise NotImplementedError

    def compare(self, result):  # pragma: no cover - interface
        """Compare with the reference: fill ``result.metrics``; return (figure paths, passed)."""
        raise NotImplementedError


class PendingCase(ValidationCase):
    """A case of issue 8 that is not built yet: its entry says so (no run, no verdict)."""

    def __init__(self, name, title, why):
        self.name, self.title, self.why = name, title, why
        self.cost = 0.0

    def run(self, quick, backend, out):
        res = CaseResult(case=self.name, title=self.title, quick=quick, backend=backend, out=Path(out))
        res.status, res.reason = "not yet", self.why
        return res

    def compare(self, result):
        return [], None


# ------------------------------------------------------------------ figures
def figure(width=7.5, height=3.0):
    """A matplotlib Figure on the Agg canvas (no display, no pyplot state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100)
    FigureCanvasAgg(fig)
    return fig


def save_png(fig, path, max_bytes=MAX_PNG_BYTES):
    """Write `fig` as a PNG (re-saved with a 256-colour palette if over `max_bytes`)."""
    from ..output.atomic import replace_file

    fig.tight_layout()
    return shrink_png(replace_file(path, lambda tmp: fig.savefig(tmp, format="png")), max_bytes)


def shrink_png(path, max_bytes=MAX_PNG_BYTES):
    """Re-save the PNG at `path` with a 256-colour palette if it is over `max_bytes`; returns `path`."""
    path = Path(path)
    if path.stat().st_size > max_bytes:
        from PIL import Image

        with Image.open(path) as im:
            small = im.convert("RGB").quantize(colors=256)
        small.save(path, optimize=True)
    return path


def find_validation_dir():
    """The repository's ``validation/`` folder (reference data, per-case READMEs, long-run results).

    ``$SHOAL_VALIDATION_DIR`` if set; else the ``validation/`` folder of the source checkout this
    package is imported from; else ``./validation``.
    """
    env = os.environ.get("SHOAL_VALIDATION_DIR")
    if env:
        return Path(env)
    here = Path(__file__).resolve()
    for parent in here.parents:
        cand = parent / "validation"
        if cand.is_dir() and (parent / "pyproject.toml").is_file():
            return cand
    return Path.cwd() / "validation"


REPORT_OUTPUTS = ("validation/REPORT.md", "validation/REPORT.html", "validation/results.json", "validation/figures")
"""What ``shoal validate --out validation`` rewrites: a change there does not make the source dirty."""


def source_checkout():
    """The root of the git checkout this package is imported from (``pyproject.toml`` and ``.git``
    beside ``src/``), or None for an installed copy."""
    for parent in Path(__file__).resolve().parents:
        if (parent / "pyproject.toml").is_file() and (parent / ".git").exists():
            return parent
    return None


def _git(root, *args):
    import subprocess

    return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, timeout=30,
                          check=True).stdout


def source_state(root=None):
    """The git commit of the shoal source a validation run measures: ``(commit, dirty, note)``.

    `root` is the checkout (default: `source_checkout`, the one this package is imported from).
    ``commit`` is ``git rev-parse HEAD`` there (40 hex). ``dirty`` is True when the checkout has
    changes not in that commit: a tracked file modified or staged anywhere except the report's own
    outputs (`REPORT_OUTPUTS`, which a run rewrites), or a file under ``src/`` git does not track;
    the commit is then the one those changes were made on, and the entry says so. When the source
    is not a git checkout (an installed copy) or git fails, ``commit`` and ``dirty`` are None and
    ``note`` says why; otherwise ``note`` is "".
    """
    import subprocess

    root = source_checkout() if root is None else Path(root)
    if root is None:
        from .. import __version__

        return None, None, (f"shoal {__version__} is not imported from a git checkout (an installed copy): "
                            "its commit is not known")
    try:
        commit = _git(root, "rev-parse", "--verify", "HEAD").strip()
        excluded = [f":(exclude){p}" for p in REPORT_OUTPUTS]
        changed = _git(root, "status", "--porcelain", "--untracked-files=no", "--", ".", *excluded)
        untracked = _git(root, "status", "--porcelain", "--untracked-files=all", "--", "src")
    except (OSError, subprocess.SubprocessError) as err:
        lines = (getattr(err, "stderr", "") or str(err)).strip().splitlines()
        return None, None, f"git could not give the commit of {root} ({lines[-1] if lines else type(err).__name__})"
    dirty = bool(changed.strip()) or any(line.startswith("??") for line in untracked.splitlines())
    return commit, dirty, ""


def machine_text():
    """The machine a run's time was measured on, e.g. "2 CPU cores, Python 3.11.7"."""
    import platform

    return f"{os.cpu_count()} CPU cores, Python {platform.python_version()}"


def utc_date():
    """Today's date in UTC, ISO (``YYYY-MM-DD``): a result's ``measured``."""
    import datetime

    return datetime.datetime.now(datetime.timezone.utc).date().isoformat()


def read_csv_with_comments(path):
    """(header names, float array) of a CSV whose first lines are ``#`` comments (the sources)."""
    import numpy as np

    lines = [ln for ln in Path(path).read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    header = [h.strip() for h in lines[0].split(",")]
    data = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    return header, data
