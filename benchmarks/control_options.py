"""The weir and the sluice gate of issue 33 with some scheme options changed.

Runs the quick (or, with "dp", another) resolution of `shoal validate weir` or `shoal validate sluice-gate`
(one gate opening) with the case's own options (`shoal.cases.weir.WEIR_OPTIONS`,
`shoal.cases.sluice_gate.SLUICE_OPTIONS`) updated by a JSON object, and prints what the validation measures:
C of the critical-flow relation against 0.3849 for the weir; Cd against Henderson's and the jet's depth
against 0.61 a for the sluice gate. A run that goes unstable prints where and why instead.

    python benchmarks/control_options.py weir '{}'
    python benchmarks/control_options.py weir '{"coef_h": 1.0, "dp": 0.005}'
    python benchmarks/control_options.py sluice-gate '{"coef_h": 1.2, "opening": 0.06}'

Keys other than SPHOptions fields: "dp" [m]; "opening" [m] (sluice gate, default 0.06); "end_time" [s]
(default: the end of the window the validation analyses; a shorter run runs, then stops with a one-line
error). Results of the study of 2026-12-06 (issue 33):
`benchmarks/results/issue33/control_options.json`.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path


def main(argv=None):
    from shoal.errors import InstabilityError
    from shoal.options import SPHOptions
    from shoal.validation.sluice_gate import run_timed

    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in ("weir", "sluice-gate"):
        raise ValueError("give the case: weir or sluice-gate (then a JSON object of options)")
    name = argv[0]
    over = json.loads(argv[1]) if len(argv) > 1 else {}
    dp = float(over.pop("dp", 0.01))
    opening = float(over.pop("opening", 0.06))
    end_time = over.pop("end_time", None)
    if name == "weir":
        from shoal.cases.weir import WEIR_OPTIONS, weir_2d
        from shoal.validation import weir as v

        case = weir_2d(dp=dp, upstream_depth=v.UPSTREAM_DEPTH, weir_height=v.WEIR_HEIGHT,
                       end_time=float(end_time or v.WINDOW[1]), options=SPHOptions(**{**WEIR_OPTIONS, **over}))
    else:
        from shoal.cases.sluice_gate import SLUICE_OPTIONS, sluice_gate_2d
        from shoal.validation import sluice_gate as v

        case = sluice_gate_2d(dp=dp, upstream_depth=v.UPSTREAM_DEPTH, opening=opening,
                              end_time=float(end_time or v.WINDOW[1]),
                              options=SPHOptions(**{**SLUICE_OPTIONS, **over}))
    out = dict(case=name, options=over, dp=dp)
    if name == "sluice-gate":
        out["opening"] = opening
    with tempfile.TemporaryDirectory() as tmp:
        try:
            out["wall_s"] = round(run_timed(case, Path(tmp) / "run"))
        except InstabilityError as err:
            out["unstable"] = str(err).split(" (state written")[0]
            print(json.dumps(out, indent=1))
            return out
        if case.end_time < v.WINDOW[1]:
            raise ValueError(f"the run ended at t = {case.end_time:g} s, before the end of the window analysed "
                             f"({v.WINDOW[0]:g}-{v.WINDOW[1]:g} s)")
        if name == "weir":
            m = v.steady_measures(Path(tmp) / "run")
            out.update(C=m["C"], C_error=m["C"] / v.C_IDEAL - 1, q=m["q_crest"], h1=m["h1"], head=m["head"],
                       crest_depth=m["crest_depth"])
        else:
            m = v.steady_measures(Path(tmp) / "run", opening)
            out.update(cd=m["cd"], cd_theory=m["cd_theory"], cd_error=m["cd"] / m["cd_theory"] - 1, y1=m["y1"],
                       y2=m["y2"], y2_error=m["cc"] / v.CC - 1)
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    from shoal.errors import InputError

    try:
        main()
    except (InputError, json.JSONDecodeError, TypeError, ValueError) as err:
        print(f"control_options.py: {err}", file=sys.stderr)
        sys.exit(2)
