"""`ParticleStore`: growing a model's arrays mid-run changes nothing of the run.

Growth is bookkeeping: rows past ``model.n`` are never read, so a run whose
arrays are given more rows between two steps must go on bitwise as one
whose arrays were left alone (the same sort, the same sums in the same
order), and a checkpoint written after the growth must resume bitwise into a
fresh model of the case's size. The CUDA version (device arrays are
reallocated and every reference re-pointed) is in ``test_cuda_parity.py``.
"""

import numpy as np
import pytest

from shoal.cases import dam_break_2d
from shoal.options import SPHOptions
from shoal.runner import build_model
from shoal.simulation import Simulation

A = 0.146


def _case(integrator):
    return dam_break_2d(dp=A / 6, a=A, layers=2, end_time=1.0,
                        options=SPHOptions(integrator=integrator, xsph=0.5, no_slip=True, turbulence="sps"))


def _by_id(model, array):
    h = model.host(array)
    out = np.zeros_like(h)
    out[model.host(model.idp)] = h
    return out


@pytest.mark.parametrize("integrator", ["symplectic", "verlet"])
def test_growing_the_arrays_mid_run_changes_nothing(integrator):
    case = _case(integrator)
    kept, grown = build_model(case, "cpu"), build_model(case, "cpu")
    runs = [Simulation(m, case.end_time).run(max_steps=6) for m in (kept, grown)]
    n, cap = grown.n, grown.capacity
    pos_before = grown.host(grown.pos).copy()
    grown.store.resize(2 * cap + 7)
    assert grown.capacity == 2 * cap + 7 and grown.store.resizes == 1
    # every per-particle array, the integrator's and the neighbour grid's work arrays hold the new rows
    for a in grown.per_particle_arrays() + [grown.grid.cell, grown.grid.perm]:
        assert a.shape[0] == grown.capacity
    assert len(grown.extra_arrays) == (3 if integrator == "symplectic" else 2)
    assert np.array_equal(grown.host(grown.pos), pos_before) and grown.n == n
    for sim in runs:
        sim.run(max_steps=6)
    assert runs[0].step_count == runs[1].step_count == 12
    assert np.max(np.abs(_by_id(kept, kept.vel))) > 0.01  # the water moved
    for name in ("pos", "vel", "rho", "tau", "vwall"):
        assert np.array_equal(_by_id(kept, getattr(kept, name)), _by_id(grown, getattr(grown, name))), name


def test_a_checkpoint_of_grown_arrays_resumes_bitwise(tmp_path):
    """Written from a model whose arrays grew, read into a fresh model of the case's size (which grows
    to the checkpoint's rows), the run goes on as the uninterrupted one."""
    from shoal.simulation.checkpoint import capture, read_checkpoint, restore, write_checkpoint

    case = _case("symplectic")
    whole, grown = build_model(case, "cpu"), build_model(case, "cpu")
    sw = Simulation(whole, case.end_time).run(max_steps=4)
    sg = Simulation(grown, case.end_time).run(max_steps=2)
    grown.store.resize(grown.capacity + 100)
    sg.run(max_steps=2)
    path = tmp_path / "ckpt.h5"
    write_checkpoint(path, capture(sg, "# a test"))
    fresh = build_model(case, "cpu")
    sf = Simulation(fresh, case.end_time)
    restore(sf, read_checkpoint(path))
    assert fresh.capacity == grown.capacity
    sw.run(max_steps=3)
    sf.run(max_steps=3)
    for name in ("pos", "vel", "rho"):
        assert np.array_equal(_by_id(whole, getattr(whole, name)), _by_id(fresh, getattr(fresh, name))), name
