"""The CUDA `rates` kernel's registers, spills and occupancy, as compiled and under register caps, on a machine
without a GPU (issue 34: "the register and occupancy report of the compiled kernels").

    python benchmarks/rates_registers.py                                   # both benchmark cases
    python benchmarks/rates_registers.py --case spheric-benchmark --caps 80 64 48 --json regs.json

For each case a child process runs one rate evaluation of it at a coarse dp under Numba's CUDA simulator and
logs every kernel launch with its argument types (`tests/cuda_kernels.py`, `record`); NVVM then compiles the
case's `rates` kernel to PTX for compute capability 9.0 (H100, H200) and nvJitLink assembles it to machine code
as the CUDA backend links it, without a cap (the compiler's choice) and with each of `--caps` (what
``SHOAL_CUDA_MAX_REGISTERS`` asks for, `shoal.backends.cuda.max_registers`). Printed for each: registers a
thread, spill stores and loads, stack frame, and the occupancy that the registers allow at 128 threads a block.
Whether a cap runs faster is measured on the GPU (`benchmarks/device/check.sh regs`): a cap trades occupancy for
recomputed or spilled values, which ptxas reports here.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

COARSE = {"spheric-benchmark": 0.04, "dam-break-dualsphysics": 0.03}
"""The dp each case is logged at (the argument types do not depend on it)."""
CC = (9, 0)

LOG_CHILD = """
import sys
sys.path.insert(0, {tests!r})
import cuda_kernels
cuda_kernels.record({log!r})
from shoal.cases import get_case
from shoal.runner import build_model
build_model(get_case({case!r}, dp={dp!r}), "cuda").compute_rates()
"""


def fail(message):
    print(f"rates_registers.py: error: {message}", file=sys.stderr)
    raise SystemExit(2)


def logged_rates(case, dp, log):
    """(SchemeSpec, argument descriptions) of the `rates` kernel of `case` at `dp`, logged under the simulator."""
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    env.pop("SHOAL_CUDA_MAX_REGISTERS", None)
    child = subprocess.run([sys.executable, "-c", LOG_CHILD.format(tests=str(ROOT / "tests"), log=str(log), case=case,
                                                                   dp=dp)], env=env, capture_output=True, text=True)
    if child.returncode != 0:
        fail(f"the simulator run of {case} failed: {' '.join(child.stderr.strip().splitlines()[-1:])}")
    with open(log, "rb") as f:
        for key, args in pickle.load(f):
            if key[0] == "loop" and key[2] == "rates":
                return key[1], args
    fail(f"{case} launched no rates kernel")


def report(case, dp, caps, log):
    import cuda_kernels as ck
    from numba import cuda

    from shoal.backends.cuda import cuda_device_jit, make_for_each
    from shoal.backends.loops import attach_loops

    spec, args = logged_rates(case, dp, log)
    loops = SimpleNamespace()
    attach_loops(loops, cuda_device_jit, make_for_each, spec, "cuda")
    sig = tuple(ck._numba_type(a) for a in args)
    with ck._device_cc(CC):
        t = time.perf_counter()
        ptx, _ = cuda.compile_ptx(loops.rates.kernel.py_func, sig, cc=CC)
        seconds = time.perf_counter() - t
    rows = []
    for cap in [None, *caps]:
        r = ck.resources(ptx, CC, max_registers=cap)
        r.update(cap=cap, occupancy=ck.occupancy(r["registers"]))
        rows.append(r)
    return dict(case=case, dp=dp, scheme=f"{spec.dim}D {spec.precision}, {ck._spec_flags(spec)}", cc=list(CC),
                ptx_lines=len(ptx.splitlines()), ptx_seconds=round(seconds, 2), rows=rows)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--case", action="append", choices=sorted(COARSE), help="a case (repeatable; default both)")
    p.add_argument("--caps", type=int, nargs="*", default=[96, 80, 64, 56, 48],
                   help="register caps to assemble with (16..255)")
    p.add_argument("--json", default=None, help="write the figures to this file")
    a = p.parse_args(argv)
    bad = [c for c in a.caps if not 16 <= c <= 255]
    if bad:
        fail(f"--caps {bad[0]}: a cap is a whole number of registers from 16 to 255")
    try:
        import cuda_kernels  # noqa: F401
        from cuda.core import Linker  # noqa: F401
    except Exception as exc:
        fail(f"needs the CUDA toolkit wheels of the test extra (pip install -e '.[test]'): {exc}")
    out = []
    with tempfile.TemporaryDirectory(prefix="shoal-regs-") as tmp:
        for case in a.case or sorted(COARSE):
            r = report(case, COARSE[case], a.caps, Path(tmp) / f"{case}.pkl")
            out.append(r)
            print(f"{case} rates [{r['scheme']}], sm_{CC[0]}{CC[1]}:")
            for row in r["rows"]:
                cap = "no cap" if row["cap"] is None else f"cap {row['cap']}"
                print(f"  {cap:>7}: {row['registers']:3d} registers, {row['spill_stores']} B spill stores, "
                      f"{row['spill_loads']} B spill loads, {row['stack']} B stack, occupancy {row['occupancy']:.0%}")
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
