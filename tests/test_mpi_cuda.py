"""One GPU per MPI rank with the CUDA backend (issue 9): the device choice, the row helpers of
the halo refresh, and a tiny dam break on 2 ranks with ``backend="cuda"`` against the
single-process CPU run.

There is no GPU in CI: the 2-rank run goes through Numba's CUDA simulator
(``NUMBA_ENABLE_CUDASIM=1`` in the ranks' environment), which runs every GPU thread as Python, so
the case is tiny (176 particles, 5 steps; about a minute on a loaded 2-core machine). The test
that starts ranks is skipped without mpi4py / mpiexec (see tests/test_mpi.py) or numba-cuda, and
fails instead under CI (the environment variable ``CI`` set, as ``.ci/run`` does; the test extra
installs all three).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

import numpy as np
import pytest
from test_mpi import HERE, _env, mpiexec, unavailable  # noqa: F401  (mpiexec: the fixture that starts 2 ranks)


def test_device_for_rank():
    """A rank uses the device numbered by its rank on the node modulo the node's visible devices;
    no device (or a bad rank) is one line."""
    from shoal.errors import InputError
    from shoal.parallel.gpu import device_for_rank

    assert [device_for_rank(r, 4) for r in range(6)] == [0, 1, 2, 3, 0, 1]  # ranks 4, 5 share devices 0, 1
    assert [device_for_rank(r, 1) for r in range(3)] == [0, 0, 0]
    assert [device_for_rank(r, 8) for r in range(4)] == [0, 1, 2, 3]  # more devices than ranks: one each
    for args, match in (((0, 0), "at least one"), ((-1, 2), "local rank"), ((1.5, 2), "local rank")):
        with pytest.raises(InputError, match=match) as err:
            device_for_rank(*args)
        assert "\n" not in str(err.value)


def test_describe_names_each_rank_and_shared_devices():
    """The run.log lines: one per rank (node, local rank, device and its name, of how many), and a
    line for a node whose ranks share a device (none when each rank has its own)."""
    from shoal.parallel.gpu import describe

    def entry(rank, host, lr, n):
        dev = lr % n
        return {"rank": rank, "host": host, "local_rank": lr, "local_size": 3, "devices": n, "device": dev,
                "name": f"GPU{dev}"}

    lines = describe([entry(0, "a", 0, 2), entry(1, "a", 1, 2), entry(2, "a", 2, 2), entry(3, "b", 0, 4)])
    assert lines[:4] == ["rank 0 (node a, local rank 0): CUDA device 0 (GPU0) of 2",
                         "rank 1 (node a, local rank 1): CUDA device 1 (GPU1) of 2",
                         "rank 2 (node a, local rank 2): CUDA device 0 (GPU0) of 2",
                         "rank 3 (node b, local rank 0): CUDA device 0 (GPU0) of 4"]
    assert len(lines) == 5 and lines[4].startswith("node a: 3 ranks share 2 CUDA device(s)")
    assert len(describe([entry(0, "a", 0, 2), entry(1, "a", 1, 2)])) == 2


def test_cpu_row_helpers_match_halo_pack():
    """The CPU backend's `pack_rows` / `unpack_rows` / `zero_rows` (what the halo refresh calls on
    every backend) give exactly `shoal.parallel.halo.pack` / `unpack` (float64, float32, int8 and
    int32 columns, exact in the float64 buffer)."""
    from shoal.backends.cpu import CPUBackend
    from shoal.parallel.halo import columns, pack, unpack

    rng = np.random.default_rng(5)
    arrays = [rng.normal(size=(40, 2)), rng.normal(size=(40, 3)).astype(np.float32),
              rng.integers(0, 5, 40).astype(np.int8), rng.integers(0, 2**31 - 1, 40).astype(np.int32)]
    rows = np.array([3, 17, 0, 39, 8, 8, 99])  # only the first k = 6 count
    out = np.full((10, columns(arrays)), np.nan)
    CPUBackend.pack_rows(arrays, rows, 6, out)
    assert np.array_equal(out[:6], pack(arrays, rows[:6])) and np.all(np.isnan(out[6:]))
    dst = [np.zeros_like(a) for a in arrays]
    ref = [np.zeros_like(a) for a in arrays]
    target = np.array([5, 6, 7, 9, 11, 12])
    CPUBackend.unpack_rows(dst, out, target, 6)
    unpack(ref, out[:6], target)
    assert all(np.array_equal(a, b) for a, b in zip(dst, ref))
    CPUBackend.zero_rows(dst, target[:3], 3)
    assert all(not np.any(a[[5, 6, 7]]) and np.array_equal(a[[9, 11, 12]], b[[9, 11, 12]]) for a, b in zip(dst, ref))


def test_two_ranks_cuda_simulator_match_one_cpu_process(mpiexec, tmp_path):  # noqa: F811
    """``shoal.run_case(..., backend="cuda")`` on 2 ranks (each its own CUDA simulator: the path of
    ``mpiexec -n 2 shoal run --backend cuda``) against the single-process CPU run: a 2D dam break
    of 176 particles (float64, symplectic, variable dt) for 5 steps from an unbalanced cut (rank 0:
    30 % of the weighted count), re-cut at the start of step 3 so particles migrate through host
    memory (54 of the 176 particles on rank 0 before, over 80 after), the halo refreshed on the device at every rate
    evaluation. Then: the same particle ids, each once (exact: mass conservation); the same step
    count and time; positions within 1e-12 m, velocities within 1e-10 m/s, densities within
    1e-8 kg/m^3 and a probe across the cut within 1e-6 (Pa, kg/m^3, m/s) of the CPU run.

    Tolerances: float64 round-off between two compilations of one physics source (the CPU's
    fast-math contractions, the simulator's plain Python arithmetic, another order of the pair
    sums on 2 ranks): measured here 0 m, 1.9e-16 m/s, 0 kg/m^3 and 6e-12 Pa; on a GPU the
    single-process parity test bounds one evaluation of the float64 rates at 1e-9 relative
    (measured 6e-15), which over 5 steps of dt ~ 2e-4 s moves a particle by far less than 1e-12 m.
    A halo fault is orders of magnitude larger: with the ghosts not refreshed on the device at the
    second stage of the step (measured by hand) the run differs by 9.3e-8 m, 3.5e-4 m/s,
    7.7e-3 kg/m^3 and 19 Pa. The ghosts' rates are checked to be zero after the run (not zeroed,
    they would enter the time step). Each rank's device arrays hold its own particles (4 spare
    rows and no margin here; 30 % and 1024 rows by default), fewer rows than the case; rank 0's are reallocated when the
    re-cut sends it particles (the run then matching the CPU run shows every reference -- model,
    grid, integrator, host copies -- followed). The run's log and resolved.json name each rank's
    device (both share the simulator's single device)."""
    try:
        import numba.cuda  # noqa: F401
    except ImportError as exc:
        unavailable(f"could not import 'numba.cuda': {exc}")
    from shoal.output import read_vtu

    out = tmp_path / "run"
    env = dict(_env(), NUMBA_ENABLE_CUDASIM="1")
    t0 = time.perf_counter()
    r = subprocess.run([*mpiexec, "-n", "2", sys.executable, str(HERE / "mpi" / "check_cuda.py"), str(out), "5"],
                       capture_output=True, text=True, timeout=900, env=env)
    wall = time.perf_counter() - t0
    line = [s for s in r.stdout.splitlines() if s.startswith("RESULTS ")]
    assert r.returncode == 0 and line, r.stdout[-2000:] + r.stderr[-3000:]
    res = json.loads(line[0][len("RESULTS "):])
    print(f"2 ranks, CUDA simulator: {wall:.1f} s; position / velocity / density / probe differences "
          f"{res['pos_err']} m, {res['vel_err']} m/s, {res['rho_err']} kg/m^3, {res['probe_err']}")
    n = res["n_particles"]
    assert n == 176 and res["n_ids"] == n and res["ids_equal"] and res["ids_unique"], res
    assert res["steps"] == [5, 5] and abs(res["time"][0] - res["time"][1]) <= 1e-12 * res["time"][1], res
    assert res["moved"] > 1e-5 and res["max_speed"] > 0.01, res  # the water moved
    (rec,) = res["rebalances"]  # one re-cut, particles migrated to rank 0
    assert rec["sort"] == 5 and rec["counts_before"] == [54, 122] and rec["counts_after"][0] > 80, rec
    assert min(res["ghosts_end"]) > 10 and res["ghost_rows"] == res["ghosts_end"], res
    # device memory follows each rank's particles (at most the case's rows) and rank 0's arrays grew: reallocated, every
    # reference re-pointed (the model's, the grid's and the integrator's)
    for cap, rows, held in zip(res["capacity"], res["array_rows"], np.add(res["owned_end"], res["ghosts_end"])):
        assert held <= cap <= n and rows == [cap, cap, cap], res
    assert res["capacity"][0] < n, res
    assert res["resizes"][0] >= 2, res  # the start's shrink, then growth at the re-cut
    assert res["pos_err"] <= 1e-12 and res["vel_err"] <= 1e-10 and res["rho_err"] <= 1e-8, res
    assert res["probe_finite"] and res["probe_err"] <= 1e-6, res
    assert res["ghost_rates_zero"] and res["owned_rates_nonzero"], res
    gpus = res["gpus"]
    assert [(g["rank"], g["local_rank"], g["device"], g["devices"]) for g in gpus] == [(0, 0, 0, 1), (1, 1, 0, 1)]
    log = (out / "run.log").read_text()
    assert "backend cuda, 2 MPI ranks" in log and "re-balanced at t " in log, log
    assert "GPU: rank 0 (node " in log and "GPU: rank 1 (node " in log and "2 ranks share 1 CUDA device" in log, log
    resolved = json.loads((out / "resolved.json").read_text())
    assert resolved["backend"] == "cuda" and len(resolved["mpi"]["gpus"]) == 2
    pts, data = read_vtu(out / "dam-break-2d_0001.pvtu")  # the final snapshot: the ranks' pieces
    assert len(pts) == n and np.array_equal(np.sort(data["id"]), np.arange(n))
    assert (out / "ckpt_000005.mpi.json").is_file()
