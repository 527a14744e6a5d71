"""The undular bore of the Favre comparison with some scheme options changed.

Runs the 2D `tidal-bore` section of `shoal validate undular-bore-amplitude` (U = 0.3 m/s, d0 = 0.1 m,
dp = 0.01 m, to t = 1.3 s) with the paper's options (`shoal.cases.tidal_bore.PAPER_OPTIONS`) updated by
a JSON object, and prints the bore's celerity against the Belanger relation and the first wave's
amplitude a_max/h0 against Favre (1935) at the measured Froude number, as the validation measures them.

    python benchmarks/bore_options.py '{}'
    python benchmarks/bore_options.py '{"alpha": 0.01}'
    python benchmarks/bore_options.py '{"coef_h": 1.5, "dp": 0.005, "t_end": 1.6}'

Keys other than SPHOptions fields: "dp" [m], "t_end" [s], "U" [m/s].
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def main(argv=None):
    import shoal
    from shoal.cases import tidal_bore
    from shoal.cases.tidal_bore import PAPER_OPTIONS
    from shoal.options import SPHOptions
    from shoal.validation import runs
    from shoal.validation.bores import UndularAmplitude

    argv = sys.argv[1:] if argv is None else argv
    over = json.loads(argv[0]) if argv else {}
    dp = float(over.pop("dp", 0.01))
    t_end = float(over.pop("t_end", 1.3))
    U = float(over.pop("U", 0.3))
    opts = SPHOptions(**{**PAPER_OPTIONS, **over})
    case = tidal_bore(dp=dp, inflow_speed=U, dim=2, end_time=t_end, output_interval=t_end, options=opts)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        shoal.run_case(case, Path(tmp) / "run", plot=False, handle_signals=False)
        gauges = {}
        for name, x in runs.BORE_GAUGES:
            data = np.loadtxt(Path(tmp) / "run" / f"gauge_{name}.csv", delimiter=",", skiprows=1, ndmin=2)
            gauges[x] = (data[:, 0], data[:, 1])
    m = runs.bore_measures(dict(gauges=gauges, U=U))
    ua = UndularAmplitude()
    a_ref, _ = ua.reference_at(ua.reference_data(), m["fr"])
    out = dict(options=over, U=U, dp=dp, t_end=t_end, wall_s=round(time.perf_counter() - t0),
               celerity=m["c"], celerity_belanger=m["c_ref"], celerity_error=m["c"] / m["c_ref"] - 1,
               froude=m["fr"], a_max_over_h0=m["amax"], favre=a_ref, a_max_error=m["amax"] / a_ref - 1,
               gauge_x=m["amax_gauge"])
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    from shoal.errors import InputError

    try:
        main()
    except (InputError, json.JSONDecodeError, TypeError) as err:
        print(f"bore_options.py: {err}", file=sys.stderr)
        sys.exit(2)
