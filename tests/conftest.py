"""Shared fixtures of the shoal test suite.

Compiling one scheme specialisation (`SchemeSpec`) takes a few seconds, so
the compiled CPU backends are cached for the whole test session: every test
that asks for the same spec reuses the same `CPUBackend` (Numba compiles
each kernel once per session; the on-disk cache makes later sessions fast).

* `backend_for(options, dim)` returns the cached backend of a scheme.
* `shared_backends` makes `shoal.model.Model` take its backend from that
  cache (tests opt in with ``@pytest.mark.usefixtures("shared_backends")``).
* `fluid_block(...)` builds a Model of a block of fluid particles only,
  with no walls and no gravity unless asked.
"""

from __future__ import annotations

import os

# Numba's OpenMP threading layer (GNU libgomp) spin-waits 300k iterations at
# the end of every parallel loop. When another multi-threaded process shares
# the cores, each of the ~20 parallel loops of a time step then costs a
# scheduler time slice: measured on 2 cores next to a running shoal
# simulation, 146 ms per step of a 1640-particle tank instead of 1.4 ms.
# A short spin keeps full speed on an idle machine (the validation tests ran
# in 56 s instead of 67 s) and 3 ms per step when busy (OMP_WAIT_POLICY=
# PASSIVE: 1.3 ms busy, but 35 % slower idle). Must be set before libgomp is
# loaded (the first parallel loop); a value in the environment wins.
os.environ.setdefault("GOMP_SPINCOUNT", "3000")

# The pytest-xdist workers share one Numba cache (Numba's default, beside the
# sources): a kernel one worker compiled, the other loads. `shoal.cache_lock`
# (installed when shoal is imported) makes their writes of one cache index
# atomic; without it two workers saving two signatures of one kernel at once
# could leave an entry naming the other's machine code (a worker segfaulted in
# compute_rates that way, when each worker had to keep its own cache).

# Under Numba's CUDA simulator (child processes of the CUDA tests) shoal runs the barrier-free kernels
# in one thread and the others on a pool of threads (`shoal.backends.simulator`); the default 5 ms GIL
# switch interval is then the fastest (parity + grid modules: 27 s, 37 s at 1 ms, 45 s at 0.1 ms).
if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1" and os.environ.get("SHOAL_CUDA_KERNEL_LOG"):
    import sys  # log the kernel launches (tests/cuda_kernels.py)

    sys.path.insert(0, os.path.dirname(__file__))
    import cuda_kernels

    cuda_kernels.record(os.environ["SHOAL_CUDA_KERNEL_LOG"])

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from shoal.backends.cpu import CPUBackend  # noqa: E402
from shoal.geometry import box_fill  # noqa: E402
from shoal.model import Model  # noqa: E402
from shoal.options import SPHOptions  # noqa: E402
from shoal.physics.spec import FLUID, SchemeSpec  # noqa: E402

# Under pytest-xdist the workers share the cores: each worker's Numba kernels get
# cores / workers threads. Two workers of two threads each on 2 cores wait on each
# other at every parallel loop's barrier: a 520-particle stream (the tidal-bore
# scheme) ran 0.2 s in 7.2 s per process that way, 2.6 s with one thread each (1.5 s
# with two threads alone). Tests that must exercise several threads ask for
# `numba.config.NUMBA_NUM_THREADS` (tests/test_conservation.py).
if os.environ.get("PYTEST_XDIST_WORKER"):
    import numba

    try:
        _cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        _cores = os.cpu_count() or 1
    _workers = max(1, int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))
    numba.set_num_threads(max(1, min(numba.config.NUMBA_NUM_THREADS, _cores // _workers)))

_BACKENDS: dict[SchemeSpec, CPUBackend] = {}


def cached_backend(spec):
    """The session's CPUBackend compiled for `spec` (built on first use)."""
    backend = _BACKENDS.get(spec)
    if backend is None:
        backend = _BACKENDS[spec] = CPUBackend(spec)
    return backend


@pytest.fixture(scope="session")
def backend_for():
    """``backend_for(options, dim) -> CPUBackend``, cached per SchemeSpec."""

    def get(options, dim):
        return cached_backend(SchemeSpec.from_options(options, dim))

    return get


@pytest.fixture
def shared_backends(monkeypatch):
    """Make every Model built in the test reuse the session's CPU backends."""
    import shoal.model

    original = shoal.model.get_backend

    def get_backend(name, spec):
        if name != "cpu":
            return original(name, spec)
        return cached_backend(spec)

    monkeypatch.setattr(shoal.model, "get_backend", get_backend)


@pytest.fixture
def fluid_block(shared_backends):
    """Factory of a Model holding a block of fluid particles (no walls).

    ``fluid_block(dim, n_side, options, dp=0.01, jitter=0.0, seed=0,
    velocity_scale=0.0, rho_noise=0.0, gravity=(0, 0, 0), u_max=1.0,
    kinds=None)``: `n_side` particles per side (a tuple gives each axis),
    positions jittered uniformly by +- jitter*dp, random normal velocities
    of standard deviation `velocity_scale` [m/s] and densities
    rho0 (1 + rho_noise N(0, 1)). The model is sorted before it is returned.
    """

    def make(dim, n_side, options=None, *, dp=0.01, jitter=0.0, seed=0, velocity_scale=0.0,
             rho_noise=0.0, gravity=(0.0, 0.0, 0.0), u_max=1.0, kinds=None, surface_z=None):
        options = options or SPHOptions(precision="float64")
        sides = (n_side,) * 3 if np.isscalar(n_side) else tuple(n_side)
        if dim == 2 and len(sides) == 2:
            sides = (sides[0], 1, sides[1])
        hi = (sides[0] * dp, sides[1] * dp if dim == 3 else 0.0, sides[2] * dp)
        pos = box_fill((0.0, 0.0, 0.0), hi, dp, dim)
        rng = np.random.default_rng(seed)
        cols = [0, 1, 2] if dim == 3 else [0, 2]
        if jitter:
            pos[:, cols] += rng.uniform(-jitter * dp, jitter * dp, size=(len(pos), dim))
        vel = np.zeros_like(pos)
        if velocity_scale:
            vel[:, cols] = rng.normal(scale=velocity_scale, size=(len(pos), dim))
        kinds = np.full(len(pos), FLUID, np.int8) if kinds is None else np.asarray(kinds(pos), np.int8)
        margin = 4 * dp
        lo = (-margin, -margin if dim == 3 else 0.0, -margin)
        dom_hi = (hi[0] + margin, hi[1] + margin if dim == 3 else 0.0, hi[2] + margin)
        model = Model(pos, kinds, dp=dp, dim=dim, domain=(lo, dom_hi), options=options, gravity=gravity,
                      u_max=u_max, velocities=vel, surface_z=surface_z)
        if rho_noise:
            model.rho[:] = model.rho * (1.0 + rho_noise * rng.standard_normal(len(pos)))
        model.sort()
        return model

    return make


# pytest-xdist's `--dist loadfile` hands whole files to the workers, by default the files with the
# most tests first. The costliest files have few tests (a tidal-bore file of 3 runs took 440 s on one
# thread, 2026-12-03) and, handed out last, ran alone while the other worker idled. The files below
# go first, costliest first (the longest-processing-time rule); the rest keep their order. Order and
# seconds from a cold CI run on 2 cores (2026-12-04, file totals of the 80 slowest tests): test_cases.py
# (119 s), outside the list, could be handed out last and run alone.
_COSTLY_FILES = ("test_mpi.py", "test_tidal_bore.py", "test_still_water.py", "test_cuda_parity.py",  # 309-234 s
                 "test_scripts_smoke.py",  # 50 s warm, 200 s cold
                 "test_cases.py", "test_symmetry.py", "test_periodic_runup.py",  # 119, 116, ~100
                 "test_riemann.py", "test_dam_break.py", "test_pressure_sensors.py",  # 85, 61, 54 (one process)
                 "test_periodic.py", "test_free_surface.py", "test_wall_pressure.py",  # 61-48
                 "test_refcounts.py", "test_probes_runup.py", "test_mdbc.py",  # 35, 31, 42 (one process, loaded)
                 "test_checkpoint.py", "test_validate.py", "test_conservation.py",  # 35-28
                 "test_flow_gauge.py", "test_turbulence.py", "test_mpi_cuda.py", "test_determinism.py",  # 25-17
                 "test_filters.py", "test_cache_lock.py", "test_benchmark_script.py", "test_cuda_grid.py")


def pytest_configure(config):
    if hasattr(config.option, "loadscopereorder"):  # xdist installed
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(config, items):
    rank = {name: k for k, name in enumerate(_COSTLY_FILES)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable
