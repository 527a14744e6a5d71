"""`shoal validate periodic-runup` quick (the Carrier & Greenspan standing wave on a 1:10 beach at
d/dp = 10, one period): half the shoreline's excursion within 10 % of A, the tolerance of the full
run (d/dp = 20, three periods; `validation/periodic-runup/README.md`)."""

from __future__ import annotations

import numpy as np

from shoal.validation import PeriodicRunup


def test_quick_run_up_and_down_the_beach(tmp_path):
    case = PeriodicRunup()
    res = case.run(quick=True, backend="cpu", out=tmp_path)
    figures, passed = case.compare(res)
    assert passed, [(m.name, m.value, m.note) for m in res.metrics]
    assert figures and figures[0].exists()
    d = res.data
    # the shoreline moved by whole amplitudes both ways, not a particle's jitter
    assert np.nanmax(d["shoreline"]) > 0.5 * d["A"] and np.nanmin(d["shoreline"]) < -0.5 * d["A"]
