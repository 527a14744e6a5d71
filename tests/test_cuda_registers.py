"""The CUDA loop kernels' register cap (``SHOAL_CUDA_MAX_REGISTERS``, `shoal.backends.cuda.max_registers`) and its
report without a GPU (`benchmarks/rates_registers.py`, issue 34)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from shoal.backends import cuda as bc
from shoal.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("value,cap", [(None, None), ("", None), ("0", None), ("64", 64), (" 80 ", 80), ("255", 255)])
def test_the_cap_is_read_from_the_environment(monkeypatch, value, cap):
    if value is None:
        monkeypatch.delenv(bc.MAX_REGISTERS_ENV, raising=False)
    else:
        monkeypatch.setenv(bc.MAX_REGISTERS_ENV, value)
    assert bc.max_registers() == cap


@pytest.mark.parametrize("value", ["8", "15", "256", "64.5", "many", "-64"])
def test_a_bad_cap_is_refused_in_one_line(monkeypatch, value):
    monkeypatch.setenv(bc.MAX_REGISTERS_ENV, value)
    with pytest.raises(InputError) as err:
        bc.max_registers()
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(f"SHOAL_CUDA_MAX_REGISTERS={value!r}") and "16 to 255" in msg


def test_a_loop_kernel_is_built_with_the_cap_and_without_it_is_left_to_the_compiler(monkeypatch):
    if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1":
        pytest.skip("the simulator has no registers to cap")

    def fn(i):
        pass

    monkeypatch.setenv(bc.MAX_REGISTERS_ENV, "64")
    assert bc._build_for_each(fn).kernel.targetoptions["max_registers"] == 64
    monkeypatch.delenv(bc.MAX_REGISTERS_ENV)
    assert bc._build_for_each(fn).kernel.targetoptions.get("max_registers") is None


def test_the_report_assembles_the_rates_kernel_within_each_cap(tmp_path):
    """ptxas keeps the capped kernel within its cap; the occupancy follows the registers (25 % above 96 a thread
    at 128 threads a block, 50 % at 64)."""
    try:
        from numba.cuda.cudadrv.nvvm import NVVM

        NVVM()
    except Exception as exc:  # the toolkit wheels of numba-cuda[cu13] (the test extra) are missing
        pytest.skip(f"NVVM not found: {exc}")
    out = tmp_path / "regs.json"
    r = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "rates_registers.py"), "--case", "spheric-benchmark",
                        "--caps", "64", "--json", str(out)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    rows = {row["cap"]: row for row in json.loads(out.read_text())[0]["rows"]}
    assert rows[64]["registers"] <= 64 < rows[None]["registers"]
    assert rows[64]["occupancy"] == 0.5 and (rows[None]["occupancy"] < 0.5)
    bad = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "rates_registers.py"), "--caps", "300"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--caps 300" in bad.stderr


def test_occupancy_by_registers():
    """65,536 registers an SM, allocated 8 a thread, at most 2,048 threads: blocks of 128 threads."""
    sys.path.insert(0, str(ROOT / "tests"))
    from cuda_kernels import occupancy

    assert [occupancy(r) for r in (32, 40, 48, 64, 80, 96, 104, 128, 255)] == [
        1.0, 0.75, 0.625, 0.5, 0.375, 0.3125, 0.25, 0.25, 0.125]
