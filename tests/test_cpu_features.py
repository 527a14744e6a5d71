"""512-bit vectors where the CPU has AVX-512 (`shoal.cpu_features`): which hosts and settings get them, and
the same rates either way."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from shoal.cpu_features import wide_vector_features

SRC = Path(__file__).resolve().parents[1] / "src"
AVX512 = "+64bit,+avx,+avx2,+avx512f,+avx512vl,+fma"
AVX2 = "+64bit,+avx,+avx2,-avx512f,-avx512fp16,+fma"


def test_a_host_with_avx512_gets_wider_vectors():
    assert wide_vector_features({}, AVX512) == AVX512 + ",-prefer-256-bit"


@pytest.mark.parametrize("features", [AVX2, "+64bit,+avx512fp16,-avx512f", ""])
def test_a_host_without_avx512f_keeps_numbas_default(features):
    assert wide_vector_features({}, features) is None


@pytest.mark.parametrize("name", ["NUMBA_CPU_FEATURES", "NUMBA_CPU_NAME"])
def test_a_users_own_target_is_left_alone(name):
    assert wide_vector_features({name: "generic"}, AVX512) is None


def _clean_env(**extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(PYTHONPATH=str(SRC), **extra)
    return env


def test_import_sets_numbas_features_before_it_compiles(tmp_path):
    code = ("import llvmlite.binding as l; l.initialize_native_target(); host = l.get_host_cpu_features().flatten()\n"
            "import shoal, numba, os\n"
            "want = host + ',-prefer-256-bit' if '+avx512f' in host.split(',') else None\n"
            "assert numba.config.CPU_FEATURES == want, numba.config.CPU_FEATURES\n"
            "assert os.environ.get('NUMBA_CPU_FEATURES') == want\n")
    subprocess.run([sys.executable, "-c", code], env=_clean_env(), cwd=tmp_path, check=True, timeout=120)
    code = "import shoal, numba; assert numba.config.CPU_FEATURES == '+avx2', numba.config.CPU_FEATURES"
    subprocess.run([sys.executable, "-c", code], env=_clean_env(NUMBA_CPU_FEATURES="+avx2"), cwd=tmp_path,
                   check=True, timeout=120)


RATES = """
import sys
import numpy as np
from shoal.cases import dam_break_2d
from shoal.runner import build_model
m = build_model(dam_break_2d(dp=0.02))  # float32, the default
m.sort()
rng = np.random.default_rng(3)
m.vel[:m.n] += (0.1 * rng.standard_normal(m.vel[:m.n].shape)).astype(m.vel.dtype)
m.rho[:m.n] *= (1 + 0.001 * rng.standard_normal(m.n)).astype(m.rho.dtype)
m.compute_rates()
np.savez(sys.argv[1], ace=m.ace[:m.n], drho=m.drho[:m.n])
"""


def test_the_rates_are_bitwise_equal_with_either_vector_width(tmp_path):
    """Each lane's arithmetic is the same whatever the vector width: the 2D dam break's perturbed rates
    (float32), compiled with the host's own features (256-bit vectors preferred) and with shoal's, agree
    bit for bit."""
    import llvmlite.binding as llvm

    llvm.initialize_native_target()
    host = llvm.get_host_cpu_features().flatten()
    script = tmp_path / "rates.py"
    script.write_text(RATES)
    out = {}
    for name, extra in (("default", {"NUMBA_CPU_FEATURES": host}), ("shoal", {})):
        env = _clean_env(NUMBA_CACHE_DIR=str(tmp_path / f"cache_{name}"), NUMBA_NUM_THREADS="1", **extra)
        subprocess.run([sys.executable, str(script), str(tmp_path / f"{name}.npz")], env=env, cwd=tmp_path,
                       check=True, timeout=600)
        out[name] = np.load(tmp_path / f"{name}.npz")
    for key in ("ace", "drho"):
        assert np.array_equal(out["default"][key], out["shoal"][key]), key
