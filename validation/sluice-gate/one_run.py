"""One sluice-gate run at any dp and opening, measured as `shoal validate sluice-gate` measures its runs.

    python validation/sluice-gate/one_run.py --dp 0.0025 --opening 0.06 --out runs/sluice_a006

Runs `shoal.cases.sluice_gate.sluice_gate_2d` to t = 6 s (`shoal.validation.sluice_gate.run_sluice_gate`) and
writes ``measures.json`` in the run's folder: over the steady window 3.5-6 s the discharge q past the gate and
through the reservoir, the depths y1 and y2 (wave gauges), Cd against Henderson's Cc / sqrt(1 + Cc a / y1),
y2 / a against 0.61, and the flow gauges' wetted areas; also printed. For resolutions beyond the validation's
`--full` (dp = 5 mm): at dp = 2.5 mm a run is about an hour on one core of the project's 2-core machine.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dp", type=float, required=True, help="particle spacing [m]")
    ap.add_argument("--opening", type=float, default=0.06, help="gate opening a [m] (the validation's: 0.06, 0.09)")
    ap.add_argument("--end", type=float, default=6.0, help="end time [s] (the window analysed is 3.5-6 s)")
    ap.add_argument("--out", required=True, help="the run's folder (overwritten)")
    a = ap.parse_args(argv)

    from shoal.errors import InputError
    from shoal.validation.sluice_gate import CC, run_sluice_gate

    try:
        m, wall, n, _ = run_sluice_gate(a.out, a.dp, a.opening, end_time=a.end)
    except InputError as err:
        sys.stderr.write(f"one_run.py: error: {err}\n")
        raise SystemExit(2)
    m.update(dp=a.dp, opening=a.opening, wall_seconds=wall, fluid_at_start=n, cd_against_henderson=m["cd"] / m["cd_theory"] - 1,
             y2_against_cc=m["cc"] / CC - 1)
    Path(a.out, "measures.json").write_text(json.dumps(m, indent=1) + "\n")
    print(json.dumps(m, indent=1))


if __name__ == "__main__":
    main()
