"""The CPU features Numba compiles shoal's kernels for: 512-bit vectors where the processor has AVX-512.

LLVM's tuning for Intel's server processors (Skylake-SP through Sapphire and Emerald Rapids) prefers
256-bit vectors even where 512-bit ones exist (``prefer-256-bit``), so a vectorised loop whose values
include float64 (the positions, which shoal keeps in double) runs four lanes at a time. The pair loop of
the CPU gather (`shoal.neighbours.gather`) is such a loop. Turning the preference off lets LLVM choose
eight or sixteen lanes; the rates of the DualSPHysics 3D dam break (dp = 0.0085 m, float32, 1 thread)
took 17 % less time on this project's Emerald Rapids machine (measured in
``benchmarks/results/issue34/wide_vectors/``). The arithmetic of each lane is the same, so the results
are bitwise equal.

`install` sets ``NUMBA_CPU_FEATURES`` (and Numba's config, if Numba is already imported) to the host's
features with ``-prefer-256-bit`` added, before any kernel is compiled; Numba's on-disk cache keys its
entries by these features, so kernels compiled either way never mix. A user's own ``NUMBA_CPU_FEATURES``
or ``NUMBA_CPU_NAME`` (a cache built for other machines) is left alone.
"""

from __future__ import annotations

import os
import sys


def wide_vector_features(env, host_features):
    """The value for ``NUMBA_CPU_FEATURES`` that allows 512-bit vectors, or None to leave Numba's default.

    Parameters
    ----------
    env : mapping
        The environment (``os.environ``).
    host_features : str
        The host's LLVM feature string (``llvmlite.binding.get_host_cpu_features().flatten()``), a comma
        separated list of ``+name`` / ``-name``.

    Returns
    -------
    str or None
        `host_features` with ``-prefer-256-bit`` appended where it has ``+avx512f`` and `env` names
        neither ``NUMBA_CPU_FEATURES`` nor ``NUMBA_CPU_NAME``; otherwise None.
    """
    if env.get("NUMBA_CPU_FEATURES") or env.get("NUMBA_CPU_NAME"):
        return None
    if "+avx512f" not in host_features.split(","):
        return None
    return host_features + ",-prefer-256-bit"


def install():
    """Apply `wide_vector_features` to this process (before Numba compiles anything)."""
    import llvmlite.binding as llvm

    try:
        llvm.initialize_native_target()
        host = llvm.get_host_cpu_features().flatten()
    except RuntimeError:  # a host LLVM cannot describe: Numba's default
        return
    features = wide_vector_features(os.environ, host)
    if features is None:
        return
    os.environ["NUMBA_CPU_FEATURES"] = features
    config = sys.modules.get("numba.core.config")
    if config is not None:
        config.CPU_FEATURES = features
