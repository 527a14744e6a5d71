"""The float64 audit of compiled CUDA kernels (`cuda_kernels.float64_in_pair_loops`), on kernels
compiled here to PTX by NVVM (no GPU, no simulator: this module runs in the test process itself)."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(os.environ.get("NUMBA_ENABLE_CUDASIM") == "1",
                                reason="compiles PTX with NVVM, which the simulator replaces")


def test_the_float64_audit_finds_a_float64_literal_in_a_float32_loop():
    """`cuda_kernels.float64_in_pair_loops` on two float32 kernels with the same loop: with a Python
    float literal (float64 in Numba) the loop multiplies in double precision and is flagged; with the
    literal cast to float32 it is clean. What `_compile_check` asserts of every float32 `rates` kernel."""
    import cuda_kernels

    try:
        from numba import cuda
        from numba import types as nt
        from numba.cuda.cudadrv.nvvm import NVVM

        NVVM()
    except Exception as exc:
        pytest.skip(f"NVVM not found: {exc}")

    def make(half):
        def kernel(x, out, n):
            i = cuda.grid(1)
            s = x[0] - x[0]
            for j in range(n):
                s += x[j] * half
            out[i] = s
        return kernel

    sig = (nt.float32[::1], nt.float32[::1], nt.int64)
    with cuda_kernels._device_cc((9, 0)):
        found = {}
        for name, half in (("literal", 0.5), ("cast", np.float32(0.5))):
            ptx, _ = cuda.compile_ptx(make(half), sig, cc=(9, 0))
            found[name] = cuda_kernels.float64_in_pair_loops(ptx)
    assert found["literal"][1] >= 1 and any(k.startswith(("mul", "fma")) for k in found["literal"][0])
    assert found["cast"][0] == {} and found["cast"][1] >= 1
