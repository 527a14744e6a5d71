"""The variable time step against its formula, computed here by brute force.

Monaghan & Kos (1999), as DualSPHysics uses it::

    dt = CFL min( sqrt(h / max_i |a_i|),  h / (c0 + max_i max_j |h v_ij . r_ij / (r_ij^2 + eta^2)|) )

with eta^2 = 0.01 h^2, i over the fluid particles and j over all particles within 2h of i. The
backends compare their time steps with each other (`test_cuda_parity`, the MPI halo check); this
checks the figure itself: the viscous-CFL term from an O(n^2) sum over all pairs, the force term
from the accelerations the model computed.
"""

import numpy as np
import pytest

from shoal.cases import dam_break_2d
from shoal.options import SPHOptions
from shoal.runner import build_model

A = 0.1


def _model(rng, speed):
    case = dam_break_2d(dp=A / 8, a=A, layers=2, options=SPHOptions(precision="float64"))
    m = build_model(case, "cpu")
    kind = m.host(m.kind)
    v = speed * rng.standard_normal(m.host(m.vel).shape)
    v[kind != 0] = 0.0
    m.vel[:] = v
    return m


def _brute_force(m):
    n = m.n
    pos = m.host(m.pos)[:n]
    vel = m.host(m.vel)[:n]
    kind = m.host(m.kind)[:n]
    ace = m.host(m.ace)[:n]
    h = m.h
    fluid = np.where(kind == 0)[0]
    dx = pos[fluid, None, :] - pos[None, :, :]
    dv = vel[fluid, None, :] - vel[None, :, :]
    r2 = np.sum(dx * dx, axis=2)
    term = np.abs(h * np.sum(dv * dx, axis=2) / (r2 + 0.01 * h * h))
    term[r2 >= 4 * h * h] = 0.0
    vm = term.max()
    amax = np.sqrt(np.sum(ace[fluid] ** 2, axis=1)).max()
    cfl = m.options.cfl
    return cfl * min(np.sqrt(h / amax), h / (m.c0 + vm)), vm, amax


@pytest.mark.parametrize("speed", [0.05, 2.0])
def test_time_step_is_monaghan_kos_over_all_pairs(speed):
    """Random fluid velocities of 0.05 m/s (the acoustic term h / c0 sets dt) and 2 m/s (a breaking
    jet's relative speeds: the pairs' term adds 44 % to c0 = 28 m/s and shortens dt by 30 %)."""
    m = _model(np.random.default_rng(3), speed)
    m.sort()
    m.compute_rates()
    dt = m.time_step_limit()
    ref, vm, amax = _brute_force(m)
    print(f"speed {speed}: dt {dt:.4e} s (brute force {ref:.4e}), max viscous term {vm:.3f} m/s, "
          f"max |a| {amax:.1f} m/s^2, c0 {m.c0:.2f} m/s")
    assert dt == pytest.approx(ref, rel=1e-9)
    # the viscous-CFL term, not the force term, sets dt in both (as in nearly every WCSPH step)
    assert np.sqrt(m.h / amax) > m.h / (m.c0 + vm)
    assert (vm > 0.3 * m.c0) == (speed > 1.0)


def test_a_closing_pair_shortens_the_time_step_as_the_formula_says():
    """Two fluid particles closing head-on at 4 m/s, 0.2 dp apart (pairs 0.14 dp apart in the plunging
    jet over the bar set dt in the rip-current run): h v r / (r^2 + eta^2) = h 4 m/s (0.2 dp) /
    ((0.2 dp)^2 + 0.01 h^2). The term is an absolute value (Monaghan & Kos 1999): a closing pair, whose
    v_ij . r_ij is negative, counts."""
    m = _model(np.random.default_rng(4), 0.0)
    n = m.n
    kind = m.host(m.kind)[:n]
    pos = m.host(m.pos)[:n].copy()
    fluid = np.where(kind == 0)[0]
    i = fluid[len(fluid) // 2]
    dp = A / 8
    j = np.argmin(np.where(kind == 0, np.sum((pos - (pos[i] + [dp, 0.0])) ** 2, axis=1), np.inf))
    pos[j] = pos[i] + [0.2 * dp, 0.0]
    m.pos[:n] = pos
    vel = np.zeros_like(m.host(m.vel))
    vel[i, 0], vel[j, 0] = 2.0, -2.0
    m.vel[:] = vel
    m.sort()
    m.compute_rates()
    h = m.h
    r = 0.2 * dp
    vm = h * 4.0 * r / (r * r + 0.01 * h * h)
    ref, vm_bf, _ = _brute_force(m)
    assert vm_bf == pytest.approx(vm, rel=1e-9)
    assert m.time_step_limit() == pytest.approx(ref, rel=1e-9)
    assert m.time_step_limit() == pytest.approx(m.options.cfl * h / (m.c0 + vm), rel=1e-9)


def test_time_interval_counts_without_looping():
    """A schedule finds the next output time by arithmetic (corrected for rounding), as a loop stepping
    one interval at a time did, but never loops for ever: for an interval whose times are not distinct
    numbers at t (1e-300 s at t = 1 s, issue 30) it raises instead of hanging."""
    import random
    from types import SimpleNamespace

    from shoal.errors import InputError
    from shoal.simulation.schedules import TimeInterval

    def by_loop(interval, start, count, time):
        # start + c interval grows with c, so the loop may begin a few intervals before its answer
        count = max(count, int((time - start) / interval) - 3)
        while start + count * interval <= time + 1e-9 * interval:
            count += 1
        return count

    rng = random.Random(1)
    for _ in range(20000):
        iv = rng.choice([0.001, 0.004, 0.02, 0.05, 0.1, 1 / 3, 1e-5]) * rng.choice([1.0, 1.0000001, 0.37])
        start = rng.choice([0.0, iv, 0.5])
        if rng.random() < 0.5:
            t = rng.uniform(0.0, 5.0)
        else:  # on or next to an output time, where rounding decides
            t = start + iv * rng.randint(0, 400) + rng.choice([0.0, 1e-12, -1e-12, 1e-10 * iv])
        count = rng.randint(0, 3)
        s = TimeInterval(iv, start=start)
        s.count = count
        if rng.random() < 0.5:
            s.skip_to(t)
            expect = by_loop(iv, start, 0, t)
        else:
            s.due(SimpleNamespace(time=t))
            expect = by_loop(iv, start, count, t)
        assert s.count == expect, (iv, start, count, t)
    for iv in (1e-300, 1e-17):
        with pytest.raises(InputError, match="too short to step to t = 1.0 s"):
            TimeInterval(iv).skip_to(1.0)


def test_a_step_that_no_longer_advances_the_time_stops_the_run():
    """A fixed step below the resolution of the time (1e-20 s at t = 1 s) would repeat the same t for ever:
    the step stops the run with an InstabilityError naming dt and t (the case check refuses such a step
    before a run; this guards a Model built from bare arrays)."""
    from shoal.errors import InstabilityError
    from shoal.simulation import Simulation

    model = build_model(dam_break_2d(dp=0.146 / 6, a=0.146, layers=2, options=SPHOptions(fixed_dt=1e-4)))
    model.options = SPHOptions(fixed_dt=1e-20)
    sim = Simulation(model, end_time=2.0)
    sim.run(max_steps=1)
    sim.time = 1.0
    with pytest.raises(InstabilityError, match="no longer advances t = 1 s"):
        sim.run(max_steps=1)


@pytest.mark.parametrize("precision", [np.float32, np.float64])
def test_the_check_finds_the_first_bad_particle_on_any_thread_count(precision):
    """`find_bad`, the check after every step, scans the particles on all threads: the lowest index
    whose position, velocity or density is not finite, or a fluid particle's density outside the band,
    wins, whichever thread found it; a wall particle's density is not checked."""
    import numba

    from shoal.backends.cpu import find_bad

    rng = np.random.default_rng(5)
    n = 50000
    pos, vel = rng.random((n, 3)).astype(precision), rng.random((n, 3)).astype(precision)
    rho, kind = (1000.0 + rng.random(n)).astype(precision), np.zeros(n, np.int8)
    kind[30000], rho[30000] = 1, 2000.0  # a wall particle
    before = numba.get_num_threads()
    try:
        for threads in range(1, numba.config.NUMBA_NUM_THREADS + 1):
            numba.set_num_threads(threads)
            assert find_bad(n, pos, vel, rho, kind, 700.0, 1300.0) == (-1, 0)
            rho[41000] = 650.0
            vel[45000, 2] = np.nan
            assert find_bad(n, pos, vel, rho, kind, 700.0, 1300.0) == (41000, 2)
            pos[40001, 0] = np.inf
            assert find_bad(n, pos, vel, rho, kind, 700.0, 1300.0) == (40001, 1)
            assert find_bad(40001, pos, vel, rho, kind, 700.0, 1300.0) == (-1, 0)
            rho[41000], vel[45000, 2], pos[40001, 0] = 1000.0, 0.0, 0.5
    finally:
        numba.set_num_threads(before)
