"""SPHERIC Test 2 (`shoal validate spheric-test2 --full`) with another scheme, to compare wall treatments.

    python benchmarks/spheric_walls.py OUT_DIR '{"wall_pressure": "dynamic", "visco_bound_factor": 1.0}'
    python benchmarks/spheric_walls.py OUT_DIR '{}' --dp 0.04
    python benchmarks/spheric_walls.py OUT_DIR '{}' --dp 0.1 --end 0.05   # a smoke test: seconds

The JSON object holds `SPHOptions` keys replacing the validation's scheme (the case defaults with the walls
of `shoal.validation.spheric_test2.WALLS`); prints the height RMSEs and the P1 peak errors, and writes the
comparison PNG and the records to OUT_DIR. About 18 minutes on one thread at dp = 0.05 m.
"""

import argparse
import json
import sys
import time
from pathlib import Path


def main(argv=None):
    from shoal.options import SPHOptions
    from shoal.validation.spheric_test2 import WALLS, SphericTest2

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("options", nargs="?", default="{}", help="JSON object of SPHOptions changes")
    ap.add_argument("--dp", type=float, default=0.05)
    ap.add_argument("--end", type=float, default=None,
                    help="end of the run and of the compared window [s] (default: the validation's, 4 s); "
                         "a short one is a smoke test, its P1 figures then meaningless")
    a = ap.parse_args(argv)
    opts = dict(WALLS, **json.loads(a.options))
    case = SphericTest2(options=SPHOptions(**opts), dp=a.dp, **({} if a.end is None else {"end_time": a.end}))
    t0 = time.perf_counter()
    res = case.run(False, "cpu", Path(a.out))
    case.compare(res)
    print(f"{opts}, dp = {a.dp:g} m, {res.particles} particles, {time.perf_counter() - t0:.0f} s")
    for m in res.metrics:
        print(f"  {m.name}: {m.value:.4g} ({m.note})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
