"""No reference counting inside the compiled CPU neighbour loops (`benchmarks/refcounts.py`).

Numba increments and decrements an array's reference count around each use in a function; LLVM
removes the pairs after inlining, except where Numba's pruning cannot prove them redundant. Then
every neighbour pair pays two atomic operations: an array of the pair loop read after a function
call did that once and cost 20 % of the 3D dam break's step, with identical results, so only an
inspection of the compiled code can catch it. The script compiles in a fresh Numba cache (cached
code cannot be inspected), so it runs in a subprocess.
"""

import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "refcounts.py"


def _check(*args):
    r = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=1200)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def test_the_rip_current_loops_hold_no_reference_counting():
    """The rip-current paper's scheme (Wendland, SPS, Shepard and MLS filters, probes, free surface):
    the scheme with the most loops; each scheme compiles cold, about 45 s on a shared core, so CI
    checks this one and `-m validation` the benchmark's and all the others."""
    out = _check("--default-only", "rip-current")
    assert out.count("no reference counting inside the loops") == 1, out


@pytest.mark.validation
def test_the_benchmark_loops_hold_no_reference_counting():
    """The DualSPHysics benchmark's scheme (cubic spline, tensile correction, density diffusion)."""
    out = _check("--default-only", "dam-break-dualsphysics")
    assert out.count("no reference counting inside the loops") == 1, out


def test_the_check_finds_reference_counting_in_ir():
    """The detector itself: an increment inside a loop of the control-flow graph is found, one
    before the loop is not."""
    sys.path.insert(0, str(SCRIPT.parent))
    try:
        from refcounts import increfs_in_loops
    finally:
        sys.path.pop(0)
    ir = """define i32 @f(ptr %a) {
entry:
  call void @NRT_incref(ptr %a)
  br label %loop
loop:
  call void @NRT_incref(ptr %b)
  call void @NRT_decref(ptr %b)
  br i1 %c, label %loop, label %exit
exit:
  call void @NRT_decref(ptr %a)
  ret i32 0
}
"""
    assert increfs_in_loops(ir) == {"f": ["%b"]}
    assert increfs_in_loops(ir.replace("label %loop, label %exit", "label %exit, label %exit")) == {}


@pytest.mark.validation
def test_every_builtin_scheme_holds_no_reference_counting():
    """All built-in cases and their scheme variants (about 6 min of compiling)."""
    out = _check()
    assert "reference increments inside loops" not in out, out
